"""The picture of a floor-plan import: what was kept, and everything left out, where it was.

Drawn on the environment made (free space and walls): the free space before the robot's inflation (dashed), the
keepout areas (orange), and every dropped feature of :class:`~solverplan.floorplan.importer.FloorplanImport`
(``features``) as a marker at its position, sized by the feature, coloured by kind, with a legend that counts them.
"""

from __future__ import annotations

from typing import Any

from matplotlib.figure import Figure
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath

from solverplan.render.environment import draw_boundary, draw_free_space
from solverplan.render.figure import new_figure

__all__ = ["render_import", "FEATURE_STYLES"]

FEATURE_STYLES: dict[str, tuple[str, str]] = {
    "speckle": ("x", "#d62728"),
    "small_hole": ("x", "#d62728"),
    "component": ("o", "#1f77b4"),
    "spur": ("^", "#9467bd"),
    "face": ("s", "#1f77b4"),
    "dangling_line": ("|", "#8c564b"),
    "cut_off": ("o", "#17becf"),
    "touch": ("+", "#7f7f7f"),
    "disconnected": ("D", "#e377c2"),
    "passage_closed": ("*", "#c51b7d"),
    "merged_obstacle": ("P", "#ff7f0e"),
    "keepout": ("h", "#ff7f0e"),
    "door_swing": ("d", "#2ca02c"),
}
"""Marker and colour of each kind of dropped feature."""


def _shape_patch(geometry: Any, **style: Any) -> PathPatch | None:
    vertices: list[tuple[float, float]] = []
    codes: list[int] = []
    for polygon in getattr(geometry, "geoms", [geometry]):
        if polygon.geom_type != "Polygon" or polygon.is_empty:
            continue
        for ring in (polygon.exterior, *polygon.interiors):
            points = list(ring.coords)
            vertices.extend(points)
            codes.extend(int(c) for c in [MplPath.MOVETO] + [MplPath.LINETO] * (len(points) - 2) + [MplPath.CLOSEPOLY])
    if not vertices:
        return None
    return PathPatch(MplPath(vertices, codes), **style)


def render_import(result: Any, *, title: str | None = None) -> Figure:
    """Draw an import: the environment, the free space before inflation, keepout areas, every dropped feature.

    >>> import shapely
    >>> from solverplan.environment import Environment
    >>> from solverplan.floorplan.drawing import DroppedFeature
    >>> from solverplan.floorplan.importer import FloorplanImport
    >>> from solverplan.result import Status
    >>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="room")
    >>> done = FloorplanImport(Status.FOUND, env, None, {}, "room.yaml", "ros", "m",
    ...                        features=(DroppedFeature("speckle", (1.0, 1.0), 0.02, 0.0004),))
    >>> fig = render_import(done)
    >>> [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    ['speckle (1)']
    """
    env = result.environment
    name = title if title is not None else f"{env.name}: {len(result.features)} features left out"
    fig, ax = new_figure(env, title=name)
    draw_free_space(ax, env)
    draw_boundary(ax, env)
    if result.uninflated is not None:
        before = result.uninflated.to_shapely()
        patch = _shape_patch(before, facecolor="none", edgecolor="#6b7b8c", linestyle="--", linewidth=0.8, zorder=1,
                             gid="free-space-before-robot")
        if patch is not None:
            ax.add_patch(patch)
        xmin, ymin, xmax, ymax = before.bounds
        pad = 0.05 * max(xmax - xmin, ymax - ymin)
        ax.set_xlim(xmin - pad, xmax + pad)
        ax.set_ylim(ymin - pad, ymax + pad)
    if result.keepout is not None and not result.keepout.is_empty:
        patch = _shape_patch(result.keepout, facecolor="#ff7f0e", alpha=0.35, edgecolor="#ff7f0e", zorder=1,
                             gid="keepout")
        if patch is not None:
            ax.add_patch(patch)
    by_kind: dict[str, list] = {}
    for feature in result.features:
        by_kind.setdefault(feature.kind, []).append(feature)
    for kind, items in sorted(by_kind.items()):
        marker, color = FEATURE_STYLES.get(kind, ("o", "#333333"))
        xs = [f.at[0] for f in items]
        ys = [f.at[1] for f in items]
        noise = kind in ("spur", "component", "dangling_line", "face")  # many and small: kept in the background
        ax.scatter(xs, ys, marker=marker, c=color, s=8 if noise else 36, alpha=0.5 if noise else 1.0, linewidths=1.2,
                   zorder=3 if noise else 4, label=f"{kind} ({len(items)})", gid=f"dropped-{kind}")
    if by_kind:
        ax.legend(fontsize=7, loc="upper right", framealpha=0.85)
    return fig
