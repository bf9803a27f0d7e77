"""Pictures of environments (and, later, partitions, graphs, plans and trajectories).

All plotting in solverplan lives here. Figures are built on the Agg canvas without pyplot, so no
window opens, no global figure list grows, and nothing depends on the user's matplotlib backend.

A picture is a stack of layers. Each layer is a ``draw_*`` function that takes an
:class:`~matplotlib.axes.Axes` and the data to draw and returns the artists it added, so callers
(and tests) can restyle or count them; every artist carries a ``gid`` (``edge-id-3``,
``vertex-id-0``, ``reflex-vertices``, ...) that also becomes its ``id`` in SVG output.
:func:`render_environment` composes the environment layers; later layers (``draw_partition``,
``draw_plan``, ``draw_trajectories``) take the same Axes and stack on top.

Conventions match the rest of the package: free space on the left of every directed edge; edge
``i`` goes from vertex ``i`` to the next vertex of its ring; labels are ``e3`` / ``v3`` like the
boundary-set syntax (CONTRACT.md).

>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
>>> fig = render_environment(env, edge_ids=True)
>>> len([t for t in fig.axes[0].texts if t.get_gid().startswith("edge-id-")])
8
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.figure import Figure
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath
from matplotlib.text import Annotation

from solverplan._io import atomic_write_bytes
from solverplan.bounce.partition import Partition
from solverplan.environment import Environment
from solverplan.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.bvg import SafeBVG
    from solverplan.bounce.cycles import LimitCycle
    from solverplan.plan.result import Plan
    from solverplan.simulate import Rollouts

__all__ = [
    "FigureFormat",
    "new_figure",
    "draw_free_space",
    "draw_boundary",
    "draw_edge_directions",
    "draw_edge_ids",
    "draw_vertex_ids",
    "LabelPlacer",
    "draw_reflex_vertices",
    "draw_partition",
    "draw_graph",
    "draw_safe_arcs",
    "draw_trajectories",
    "draw_cycle",
    "draw_plan",
    "plan_title",
    "draw_patrol",
    "draw_position_sets",
    "render_answer",
    "render_environment",
    "figure_format",
    "figure_bytes",
    "save_figure",
    "SavedFigure",
    "draw_heatmap",
    "render_heatmaps",
]

FigureFormat = Literal["png", "svg"]
_FORMATS: dict[str, FigureFormat] = {".png": "png", ".svg": "svg"}

# Palette: light free space, dark walls, hole interiors left white; ids in muted colours.
FREE_SPACE_COLOR = "#e8f0f8"
BOUNDARY_COLOR = "#1f2a36"
EDGE_ID_COLOR = "#1a5fa8"
VERTEX_ID_COLOR = "#5a5a5a"
REFLEX_COLOR = "#d1495b"
PARTITION_COLORS = ("#e07a1f", "#2a9d8f", "#7b5ea7")  # alternate along each ring; the third closes odd rings
INSERTED_COLOR = "#1f2a36"
GRAPH_COLOR = "#6b7b8c"  # the BVG's arcs: light grey-blue lines under everything else
SAFE_ARC_COLOR = "#2c7fb8"  # safe arcs: rays that really land, a little stronger
TRAJECTORY_COLOR = "#d95f02"  # warm, against the pale free space and the dark walls
TRAJECTORY_START_COLOR = "#1b7837"
TRAJECTORY_FLAG_COLOR = "#b2182b"
CYCLE_COLOR = "#08306b"  # a limit cycle: bold dark blue over the warm trajectories
CYCLE_POINT_COLOR = "#ffd92f"  # its contact points: yellow circles, as in the paper's Fig. 9

PNG_DPI = 150
ARROW_SIZE = 14.0  # points: the arrowheads showing edge directions


# ---------------------------------------------------------------------- figures
def new_figure(env: Environment, *, width: float | None = None, title: str | None = None) -> tuple[Figure, Axes]:
    """A fresh figure with one Axes sized to ``env``'s aspect ratio (height clamped).

    ``width`` is in inches; by default 7, growing with the number of edges and for long thin
    environments (up to 16) so that labels keep room. The figure is attached to an Agg canvas (no screen needed) and is not
    registered with pyplot.
    """
    if width is None:
        width = float(np.clip(7.0 * np.sqrt(env.n_edges / 30), 7.0, 16.0))
    xmin, ymin, xmax, ymax = env.bounds
    span_x, span_y = max(xmax - xmin, 1e-12), max(ymax - ymin, 1e-12)
    if span_x > 3 * span_y:  # long and thin (hallways): wider, so the labels fit across
        width = float(min(16.0, width * np.sqrt(span_x / (3 * span_y))))
    height = min(max(width * span_y / span_x, 3.0), width * 10 / 7)
    if span_y > span_x:  # tall environments: keep the height, narrow the figure
        width = min(max(height * span_x / span_y, 3.0), width)
    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    _style_axes(ax, title)
    return fig, ax


def _style_axes(ax: Axes, title: str | None) -> None:
    ax.set_aspect("equal", adjustable="box")
    ax.tick_params(labelsize=7, colors="#777777")
    for spine in ax.spines.values():
        spine.set_color("#cccccc")
    if title:
        ax.set_title(title, fontsize=11)


def _font_size(n_labels: int) -> float:
    """Smaller labels when there are many of them."""
    if n_labels <= 40:
        return 8.0
    if n_labels <= 120:
        return 6.5
    return 5.0


# ---------------------------------------------------------------------- geometry helpers
def _unit(v: np.ndarray) -> np.ndarray:
    norm = np.hypot(v[..., 0], v[..., 1])[..., None]
    return np.divide(v, norm, out=np.zeros_like(v), where=norm > 0)


def _left_normals(env: Environment) -> np.ndarray:
    """Unit normals of every edge pointing into the free space (the left side), shape (n, 2)."""
    d = _unit(env.edge_end - env.edge_start)
    return np.stack([-d[:, 1], d[:, 0]], axis=1)


def _free_space_angles(env: Environment) -> np.ndarray:
    """The free space's angle at every vertex, in (0, 2π) (π for a collinear vertex, > π reflex), shape (n,)."""
    verts = env.vertices
    back = verts[env.prev_vertex] - verts
    ahead = verts[env.next_vertex] - verts
    cross = ahead[:, 0] * back[:, 1] - ahead[:, 1] * back[:, 0]
    dot = np.einsum("ij,ij->i", ahead, back)
    return np.mod(np.arctan2(cross, dot), 2 * np.pi)


def _inward_at_vertices(env: Environment) -> np.ndarray:
    """Unit directions at every vertex bisecting the free-space angle (into the free space), shape (n, 2)."""
    verts = env.vertices
    ahead = _unit(verts[env.next_vertex] - verts)
    half = 0.5 * _free_space_angles(env)
    c, s = np.cos(half), np.sin(half)
    return np.stack([c * ahead[:, 0] - s * ahead[:, 1], s * ahead[:, 0] + c * ahead[:, 1]], axis=1)


def _edge_label_params(env: Environment) -> np.ndarray:
    """Where along each edge its label (and arrow) goes: the midpoint, moved away from a sharp corner.

    Two edges meeting at an acute corner of the free space would have their labels meet in the
    corner's narrow wedge; sliding each label towards its edge's other end gives them room.
    """
    angles = _free_space_angles(env)
    tail, head = angles, angles[env.next_vertex]
    sharpest = np.minimum(tail, head)
    shift = 0.3 * np.clip(1.0 - sharpest / (np.pi / 2), 0.0, 1.0)
    return np.where(head < tail, 0.5 - shift, 0.5 + shift)


def _label_half_size(text: str, fontsize: float, pad: float = 2.0) -> tuple[float, float]:
    """Approximate half width and half height, in points, of a centred label with ``pad`` around it."""
    return 0.31 * fontsize * len(text) + pad, 0.5 * fontsize + pad


def _clear_distance(direction: np.ndarray, half: tuple[float, float], gap: float) -> float:
    """Distance in points from an anchor to a label's centre, so the label box clears it by ``gap``
    along ``direction`` (a unit vector) whatever the direction's slope."""
    return gap + abs(float(direction[0])) * half[0] + abs(float(direction[1])) * half[1]


def _point_clear_distance(direction: np.ndarray, half: tuple[float, float], gap: float) -> float:
    """Distance in points from an anchor to a label's centre along ``direction`` so the label box
    leaves the anchor ``gap`` points clear along one of the box's axes (whichever comes first)."""
    ux, uy = abs(float(direction[0])), abs(float(direction[1]))
    return min((half[0] + gap) / ux if ux > 1e-9 else np.inf, (half[1] + gap) / uy if uy > 1e-9 else np.inf)


_COMPASS = (np.array([0.0, 1.0]), np.array([0.0, -1.0]), np.array([1.0, 0.0]), np.array([-1.0, 0.0]))


def _rotate(v: np.ndarray, degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


class LabelPlacer:
    """Greedy placement of small labels clear of the boundary, the vertices and each other.

    Works in the Axes' current view, so create it after the limits are set (:func:`draw_free_space`
    sets them) and share one placer between the label layers of a picture. A candidate is an
    anchor (data coordinates) and an offset (points); :meth:`place` returns the first candidate
    whose label box meets no boundary edge, no vertex and no label placed before, and whose centre
    sees its anchor; failing that, the first in sight of its anchor that meets no other label;
    then the first that meets no other label; then the first candidate. Callers list candidates
    best first.
    """

    #: above this many labels, candidates are not searched (the labels are unreadable anyway)
    MAX_SEARCH = 2000

    def __init__(self, ax: Axes, env: Environment, *, vertex_clearance: float = 3.5) -> None:
        import shapely

        ax.apply_aspect()
        figure = ax.get_figure()
        width_points = ax.get_position().width * figure.get_figwidth() * 72.0
        x0, x1 = ax.get_xlim()
        self.points_per_unit = width_points / abs(x1 - x0)
        self._shapely = shapely
        self._edges = shapely.STRtree(shapely.linestrings(np.stack([env.edge_start, env.edge_end], axis=1)))
        self._search = env.n_edges <= self.MAX_SEARCH
        xmin, ymin, xmax, ymax = env.bounds
        self._cell = max(xmax - xmin, ymax - ymin) / 40 or 1.0
        self._grid: dict[tuple[int, int], list[tuple[float, float, float, float]]] = {}
        r = vertex_clearance / self.points_per_unit
        for x, y in env.vertices:
            self._add((x - r, y - r, x + r, y + r))

    def reserve(self, anchor: np.ndarray, offset: np.ndarray, half: tuple[float, float]) -> None:
        """Keep later labels off a box of half size ``half`` (points) at ``offset`` (points) from ``anchor``."""
        self._add(self._box(anchor, offset, half))

    def _cells(self, box: tuple[float, float, float, float]):
        c = self._cell
        for i in range(int(np.floor(box[0] / c)), int(np.floor(box[2] / c)) + 1):
            for j in range(int(np.floor(box[1] / c)), int(np.floor(box[3] / c)) + 1):
                yield (i, j)

    def _add(self, box: tuple[float, float, float, float]) -> None:
        for cell in self._cells(box):
            self._grid.setdefault(cell, []).append(box)

    def _clear_of_labels(self, box: tuple[float, float, float, float]) -> bool:
        for cell in self._cells(box):
            for other in self._grid.get(cell, ()):
                if box[0] < other[2] and other[0] < box[2] and box[1] < other[3] and other[1] < box[3]:
                    return False
        return True

    def _clear_of_edges(self, box: tuple[float, float, float, float]) -> bool:
        return self._edges.query(self._shapely.box(*box), predicate="intersects").size == 0

    def _box(self, anchor: np.ndarray, offset: np.ndarray, half: tuple[float, float]) -> tuple[float, float, float, float]:
        k = self.points_per_unit
        cx, cy = anchor[0] + offset[0] / k, anchor[1] + offset[1] / k
        return (cx - half[0] / k, cy - half[1] / k, cx + half[0] / k, cy + half[1] / k)

    def _sees(self, anchor: np.ndarray, offset: np.ndarray) -> bool:
        """Does the label's centre see its anchor (no boundary edge in between)?

        Keeps a label in the region of what it labels: never across a thin wall.
        """
        norm = float(np.hypot(offset[0], offset[1]))
        if norm == 0:
            return True
        k = self.points_per_unit
        start = anchor + offset * (0.5 / norm) / k  # half a point off the anchor, which lies on the boundary
        end = anchor + offset / k
        line = self._shapely.linestrings([start, end])
        return self._edges.query(line, predicate="intersects").size == 0

    def place(self, candidates: list[tuple[np.ndarray, np.ndarray]], half: tuple[float, float]) -> int:
        """Index of the candidate ``(anchor, offset)`` chosen for a label of half size ``half`` (points)."""
        chosen = 0
        if self._search:
            boxes = [self._box(anchor, offset, half) for anchor, offset in candidates]
            free_of_labels = [k for k, box in enumerate(boxes) if self._clear_of_labels(box)]
            in_sight = [k for k in free_of_labels if self._sees(*candidates[k])]
            clear = [k for k in in_sight if self._clear_of_edges(boxes[k])]
            # crowded: crossing a line is better than being far from the anchor or hiding another label
            for ranked in (clear, in_sight, free_of_labels):
                if ranked:
                    chosen = ranked[0]
                    break
        anchor, offset = candidates[chosen]
        self._add(self._box(anchor, offset, half))
        return chosen


# ---------------------------------------------------------------------- environment layers
def draw_free_space(ax: Axes, env: Environment, *, color: str = FREE_SPACE_COLOR) -> PathPatch:
    """Fill the free space (outer ring minus holes) and set the view limits to the environment."""
    vertices: list[tuple[float, float]] = []
    codes: list[int] = []
    start = 0
    for ring in env.rings:
        pts = env.vertices[start : start + len(ring)]
        start += len(ring)
        vertices.extend(map(tuple, pts))
        vertices.append(tuple(pts[0]))
        codes.extend([MplPath.MOVETO] + [MplPath.LINETO] * (len(pts) - 1) + [MplPath.CLOSEPOLY])
    patch = PathPatch(MplPath(vertices, codes), facecolor=color, edgecolor="none", zorder=0, gid="free-space")
    ax.add_patch(patch)
    xmin, ymin, xmax, ymax = env.bounds
    pad = 0.1 * max(xmax - xmin, ymax - ymin)  # room for labels outside the outer ring
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    return patch


def draw_boundary(ax: Axes, env: Environment, *, color: str = BOUNDARY_COLOR, linewidth: float = 1.6) -> LineCollection:
    """Draw every boundary edge as a line segment (one collection, in edge order)."""
    segments = np.stack([env.edge_start, env.edge_end], axis=1)
    lines = LineCollection(segments, colors=color, linewidths=linewidth, capstyle="round", zorder=2, gid="boundary")
    ax.add_collection(lines)
    return lines


def _arrow(ax: Axes, at: np.ndarray, direction: np.ndarray, *, color: str, size: float, gid: str) -> Annotation:
    tail = (-float(direction[0]) * size, -float(direction[1]) * size)
    arrow = ax.annotate(
        "",
        xy=(float(at[0]), float(at[1])),
        xytext=tail,
        textcoords="offset points",
        arrowprops=dict(
            arrowstyle="-|>,head_length=0.5,head_width=0.22",
            color=color,
            lw=0,
            shrinkA=0,
            shrinkB=0,
            mutation_scale=size,
        ),
        zorder=3,
        annotation_clip=False,
    )
    arrow.set_gid(gid)
    return arrow


def draw_edge_directions(
    ax: Axes, env: Environment, *, t: np.ndarray | None = None, color: str = EDGE_ID_COLOR, size: float | None = None
) -> list[Annotation]:
    """An arrowhead on every edge pointing along it (a → b), at boundary parameter ``t`` (default: near the middle)."""
    size = size or ARROW_SIZE
    params = _edge_label_params(env) if t is None else np.asarray(t, dtype=float)
    spots = env.points_at(np.arange(env.n_edges), params)
    dirs = _unit(env.edge_end - env.edge_start)
    return [_arrow(ax, spots[i], dirs[i], color=color, size=size, gid=f"edge-arrow-{i}") for i in range(env.n_edges)]


def _offset_label(ax: Axes, text: str, anchor, offset, *, size: float, color, gid: str, **style) -> Annotation:
    """A label centred ``offset`` points away from the data point ``anchor`` (placed by :class:`LabelPlacer`)."""
    label = ax.annotate(
        text,
        xy=(float(anchor[0]), float(anchor[1])),
        xytext=(float(offset[0]), float(offset[1])),
        textcoords="offset points",
        ha="center",
        va="center",
        fontsize=size,
        color=color,
        zorder=4,
        annotation_clip=False,
        **style,
    )
    label.set_gid(gid)
    return label


def draw_edge_ids(
    ax: Axes,
    env: Environment,
    *,
    arrows: bool = True,
    placer: LabelPlacer | None = None,
    color: str = EDGE_ID_COLOR,
    fontsize: float | None = None,
) -> list[Annotation]:
    """Label every edge ``e<i>`` beside it in the free space, with an arrowhead showing its direction.

    Each label sits near its edge's middle, moved along the edge or further from it when that
    spot is taken (by another label, a vertex or an edge). Returns the labels (gid ``edge-id-<i>``);
    the arrows (gid ``edge-arrow-<i>``) are added to the Axes beside them.
    """
    size = fontsize or _font_size(env.n_edges)
    placer = placer or LabelPlacer(ax, env)
    preferred = _edge_label_params(env)
    normals = _left_normals(env)
    dirs = _unit(env.edge_end - env.edge_start)
    labels = []
    for i in range(env.n_edges):
        text = f"e{i}"
        half = _label_half_size(text, size)
        base = _clear_distance(normals[i], half, gap=3.5)
        params = list(dict.fromkeys([float(preferred[i]), 0.5, 0.35, 0.65, 0.2, 0.8]))
        candidates = [
            (env.points_at(np.array([i]), np.array([t]))[0], normals[i] * base * stretch)
            for stretch in (1.0, 1.6, 2.4)
            for t in params
        ]
        chosen = placer.place(candidates, half)
        anchor, offset = candidates[chosen]
        label = _offset_label(ax, text, anchor, offset, size=size, color=color, gid=f"edge-id-{i}",
                              bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.8))
        labels.append(label)
        if arrows:
            _arrow(ax, anchor, dirs[i], color=color, size=ARROW_SIZE, gid=f"edge-arrow-{i}")
            head = 0.5 * ARROW_SIZE  # head_length of the arrow style, in points
            placer.reserve(anchor, -dirs[i] * head / 2, (abs(dirs[i][0]) * head / 2 + 3, abs(dirs[i][1]) * head / 2 + 3))
    return labels


def draw_vertex_ids(
    ax: Axes,
    env: Environment,
    *,
    placer: LabelPlacer | None = None,
    color: str = VERTEX_ID_COLOR,
    fontsize: float | None = None,
) -> list[Annotation]:
    """Label every vertex ``v<i>``, preferably outside the free space (beyond the outer ring, inside holes).

    Each label goes on the bisector of the angle outside the free space, or turned from it when
    that spot is taken.

    Returns the labels (gid ``vertex-id-<i>``).
    """
    size = fontsize or _font_size(env.n_vertices)
    placer = placer or LabelPlacer(ax, env)
    outward = -_inward_at_vertices(env)
    labels = []
    for i in range(env.n_vertices):
        text = f"v{i}"
        half = _label_half_size(text, size, pad=0.5)  # no box behind vertex labels
        anchor = env.vertices[i]
        candidates = []
        for turn, stretches in ((0, (1.0, 1.6, 2.4)), (25, (1.0, 1.6)), (-25, (1.0, 1.6)), (60, (1.0,)), (-60, (1.0,)),
                                (100, (1.0,)), (-100, (1.0,)), (145, (1.0,)), (-145, (1.0,)), (180, (1.0,))):
            direction = _rotate(outward[i], turn)
            base = _point_clear_distance(direction, half, gap=4.0)
            candidates.extend((anchor, direction * base * stretch) for stretch in stretches)
        for direction in _COMPASS:  # last resorts in crowded corners: straight up, down, left, right
            base = _point_clear_distance(direction, half, gap=4.0)
            candidates.extend((anchor, direction * base * stretch) for stretch in (1.0, 2.0, 3.0))
        chosen = placer.place(candidates, half)
        _, offset = candidates[chosen]
        label = _offset_label(ax, text, anchor, offset, size=size, color=color, gid=f"vertex-id-{i}")
        labels.append(label)
    return labels


def draw_reflex_vertices(ax: Axes, env: Environment, *, color: str = REFLEX_COLOR, size: float = 22.0) -> PathCollection:
    """Mark the reflex vertices (free-space angle > π) with dots."""
    ids = list(env.reflex_vertices)
    pts = env.vertices[ids] if ids else np.empty((0, 2))
    dots = ax.scatter(pts[:, 0], pts[:, 1], s=size, c=color, zorder=5, edgecolors="white", linewidths=0.6, gid="reflex-vertices")
    return dots


def _reserve_labels(placer: LabelPlacer, ax: Axes) -> None:
    """Keep new labels off the labels already on ``ax`` (annotations placed with an offset in points)."""
    for text in ax.texts:
        if not isinstance(text, Annotation) or text.anncoords != "offset points":
            continue
        anchor, offset = np.asarray(text.xy, dtype=float), np.asarray(text.xyann, dtype=float)
        label = text.get_text()
        if label:
            placer.reserve(anchor, offset, _label_half_size(label, float(text.get_fontsize())))
        else:  # an arrow drawn from `offset` to its anchor: keep its shaft and head clear
            placer.reserve(anchor, offset / 2, (abs(offset[0]) / 2 + 3, abs(offset[1]) / 2 + 3))


def draw_partition(
    ax: Axes,
    partition: Partition,
    *,
    segment_ids: bool = True,
    placer: LabelPlacer | None = None,
    colors: tuple[str, ...] = PARTITION_COLORS,
    fontsize: float | None = None,
) -> list:
    """Draw the partition P′ (paper Algorithm 1, as in the paper's Figs. 3 and 4).

    Segments are drawn over the boundary in colours alternating along each ring (a third colour
    closes a ring with an odd number of segments, so neighbours always differ); inserted points are
    white dots ringed in dark; with ``segment_ids`` each segment is labelled with its id beside its
    middle, in the free space, in the segment's colour.

    Returns the artists added: the segments' :class:`~matplotlib.collections.LineCollection` (gid
    ``partition-segments``), the inserted points' ``PathCollection`` (gid ``partition-inserted``),
    then the labels (gid ``segment-id-<k>``).
    """
    env = partition.env
    m = partition.n_segments
    colour_of = []
    for k in range(len(partition.ring_offsets) - 1):
        count = partition.ring_offsets[k + 1] - partition.ring_offsets[k]
        ring_colours = [colors[j % 2] for j in range(count)]
        if count % 2 and count > 1:
            ring_colours[-1] = colors[2 % len(colors)]
        colour_of.extend(ring_colours)
    starts, ends = partition.seg_start, partition.seg_end
    lines = LineCollection(
        np.stack([starts, ends], axis=1), colors=colour_of, linewidths=3.2, capstyle="butt", zorder=2.5,
        gid="partition-segments",
    )
    ax.add_collection(lines)
    pts = np.array([[float(q.point[0]), float(q.point[1])] for q in partition.inserted]).reshape(-1, 2)
    dots = ax.scatter(
        pts[:, 0], pts[:, 1], s=16, c="white", edgecolors=INSERTED_COLOR, linewidths=0.9, zorder=5.5,
        gid="partition-inserted",
    )
    artists: list = [lines, dots]
    if not segment_ids:
        return artists
    size = fontsize or _font_size(m)
    if placer is None:
        placer = LabelPlacer(ax, env)
        _reserve_labels(placer, ax)
    normals = _left_normals(env)
    for k in range(m):
        text = str(k)
        half = _label_half_size(text, size, pad=1.0)
        normal = normals[int(partition.seg_edge[k])]
        base = _clear_distance(normal, half, gap=3.0)
        candidates = [
            (starts[k] + f * (ends[k] - starts[k]), normal * base * stretch)
            for stretch in (1.0, 1.7, 2.5, 3.5)
            for f in (0.5, 0.35, 0.65, 0.2, 0.8)
        ]
        anchor, offset = candidates[placer.place(candidates, half)]
        label = _offset_label(ax, text, anchor, offset, size=size, color=colour_of[k], gid=f"segment-id-{k}",
                              fontweight="bold")
        artists.append(label)
    return artists


def _ink_alpha(ax: Axes, env: Environment, segments: np.ndarray, linewidth: float, coverage_goal: float) -> float:
    """Opacity so that the ink of all lines, spread evenly, would cover ``coverage_goal`` of the free space."""
    if len(segments) == 0:
        return 0.8
    ax.apply_aspect()
    x0, x1 = ax.get_xlim()
    width_points = ax.get_position().width * ax.get_figure().get_figwidth() * 72.0
    line_width = linewidth / (width_points / abs(x1 - x0))  # in data units
    ink = float(np.hypot(*(segments[:, 1] - segments[:, 0]).T).sum()) * line_width
    coverage = ink / max(float(env.area), 1e-300)
    return float(np.clip(coverage_goal / max(coverage, 1e-12), 0.01, 0.6))


def draw_graph(
    ax: Axes,
    graph: SafeBVG,
    *,
    color: str = GRAPH_COLOR,
    linewidth: float = 0.5,
    alpha: float | None = None,
) -> list:
    """Draw the bounce visibility graph lightly: one thin line between the midpoints of every two
    segments of P′ that see each other (arcs come in both directions; each pair is drawn once).

    The line joins midpoints, so it may cross an obstacle when the segments see each other only in
    part; :func:`draw_safe_arcs` draws lines that are real trajectories. ``alpha`` defaults to a value
    that falls with the total ink, so a dense graph reads as a shade. Draw after :func:`draw_free_space`.

    Returns the artists: one :class:`~matplotlib.collections.LineCollection` (gid ``bvg-arcs``).
    """
    p = graph.partition
    mid = 0.5 * (np.asarray(p.seg_start) + np.asarray(p.seg_end))
    once = graph.source < graph.target
    segments = np.stack([mid[graph.source[once]], mid[graph.target[once]]], axis=1).reshape(-1, 2, 2)
    if alpha is None:
        alpha = _ink_alpha(ax, p.env, segments, linewidth, 0.6)
    lines = LineCollection(segments, colors=color, linewidths=linewidth, alpha=alpha, zorder=1.2, gid="bvg-arcs")
    ax.add_collection(lines)
    return [lines]


def draw_safe_arcs(
    ax: Axes,
    graph: SafeBVG,
    *,
    color: str = SAFE_ARC_COLOR,
    linewidth: float = 0.6,
    alpha: float | None = None,
) -> list:
    """Draw every safe arc i → j as the ray it stands for: from the midpoint of segment i at the middle
    heading of the arc's widest safe interval, to where it lands on segment j (which it does: the
    heading is safe). Open ends at 0 or π are clipped to 0.02 rad inside, so the ray leaves the wall.

    Returns the artists: one :class:`~matplotlib.collections.LineCollection` (gid ``safe-arcs``).
    """
    p = graph.partition
    rows = np.flatnonzero(graph.safe)
    i, j = graph.source[rows], graph.target[rows]
    start, end = np.asarray(p.seg_start), np.asarray(p.seg_end)
    m = 0.5 * (start[i] + end[i])
    e = end[i] - start[i]
    e = e / np.hypot(e[:, 0], e[:, 1])[:, None]
    lo = np.maximum(graph.lo[rows], np.minimum(0.02, graph.hi[rows]))
    hi = np.minimum(graph.hi[rows], np.maximum(np.pi - 0.02, graph.lo[rows]))
    theta = 0.5 * (lo + hi)
    c, s = np.cos(theta), np.sin(theta)
    u = np.stack([c * e[:, 0] - s * e[:, 1], s * e[:, 0] + c * e[:, 1]], axis=1)
    q, d = start[j], end[j] - start[j]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((q[:, 0] - m[:, 0]) * d[:, 1] - (q[:, 1] - m[:, 1]) * d[:, 0]) / (u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0])
    ok = np.isfinite(t) & (t > 0)
    segments = np.stack([m[ok], m[ok] + t[ok, None] * u[ok]], axis=1).reshape(-1, 2, 2)
    if alpha is None:
        alpha = _ink_alpha(ax, p.env, segments, linewidth, 0.35)
    lines = LineCollection(segments, colors=color, linewidths=linewidth, alpha=alpha, zorder=1.4, gid="safe-arcs")
    ax.add_collection(lines)
    return [lines]


def _trajectory_alpha(ax: Axes, env: Environment, segments: np.ndarray, linewidth: float) -> float:
    """Opacity so that the ink of all paths, if spread evenly, would cover the free space about half
    over: few short paths stay clearly visible, dense ones do not saturate, and where many paths
    agree (a limit cycle) the picture still darkens."""
    if len(segments) == 0:
        return 0.8
    ax.apply_aspect()
    x0, x1 = ax.get_xlim()
    width_points = ax.get_position().width * ax.get_figure().get_figwidth() * 72.0
    line_width = linewidth / (width_points / abs(x1 - x0))  # in data units
    ink = float(np.hypot(*(segments[:, 1] - segments[:, 0]).T).sum()) * line_width
    coverage = ink / max(float(env.area), 1e-300)
    return float(np.clip(0.5 / max(coverage, 1e-12), 0.04, 0.8))


def draw_trajectories(
    ax: Axes,
    rollouts: Rollouts,
    *,
    max_paths: int | None = None,
    color: str = TRAJECTORY_COLOR,
    linewidth: float = 0.6,
    alpha: float | None = None,
    starts: bool = True,
    flags: bool = True,
) -> list:
    """Draw simulated trajectories: thin, semi-transparent polylines through the contacts, start points
    marked (green dots), rollouts stopped at a vertex or a near-tie marked where they stopped (red ×).

    ``max_paths`` limits the drawing to the first rollouts (all by default). ``alpha`` defaults to a
    value that falls with the total ink of the paths (see :func:`_trajectory_alpha`), so that dense
    pictures do not saturate and where many paths agree (a limit cycle) the picture darkens. Draw
    after :func:`draw_free_space` (which sets the view). Needs rollouts recorded with ``record="all"``.

    Returns the artists: the paths' :class:`~matplotlib.collections.LineCollection` (gid
    ``trajectories``), then the start dots (gid ``trajectory-starts``) and the flags
    (gid ``trajectory-flags``) when drawn.
    """
    if rollouts.record != "all":
        raise InputError("these rollouts kept only their end points: simulate with record='all' to draw trajectories")
    count = rollouts.trials if max_paths is None else max(0, min(int(max_paths), rollouts.trials))
    x, y = rollouts.x[:count], rollouts.y[:count]
    a = np.stack([x[:, :-1], y[:, :-1]], axis=-1)
    b = np.stack([x[:, 1:], y[:, 1:]], axis=-1)
    valid = np.isfinite(a).all(axis=-1) & np.isfinite(b).all(axis=-1)
    segments = np.stack([a[valid], b[valid]], axis=1)
    if alpha is None:
        alpha = _trajectory_alpha(ax, rollouts.env, segments, linewidth)
    lines = LineCollection(
        segments, colors=color, linewidths=linewidth, alpha=alpha, capstyle="round", zorder=1.5, gid="trajectories"
    )
    ax.add_collection(lines)
    artists: list = [lines]
    if starts and count:
        dots = ax.scatter(
            x[:, 0], y[:, 0], s=9, c=TRAJECTORY_START_COLOR, edgecolors="white", linewidths=0.4, zorder=5.2,
            alpha=min(1.0, 2 * alpha + 0.2), gid="trajectory-starts",
        )
        artists.append(dots)
    if flags and count:
        flagged = np.flatnonzero(rollouts.flagged[:count])
        ends = rollouts.final_points[flagged]
        ends = ends[np.isfinite(ends).all(axis=1)]
        if len(ends):
            marks = ax.scatter(
                ends[:, 0], ends[:, 1], s=28, marker="x", c=TRAJECTORY_FLAG_COLOR, linewidths=1.2, zorder=5.4,
                gid="trajectory-flags",
            )
            artists.append(marks)
    return artists


def draw_cycle(
    ax: Axes,
    cycle: LimitCycle,
    *,
    color: str = CYCLE_COLOR,
    point_color: str = CYCLE_POINT_COLOR,
    linewidth: float = 2.2,
) -> list:
    """Draw a limit cycle (:class:`~solverplan.bounce.cycles.LimitCycle`) on top of everything: a bold
    closed polyline through its contact points with an arrowhead on every leg (the direction of travel)
    and yellow circles at the contacts (the paper's Fig. 9). A periodic orbit that is not a stable cycle
    (status other than ``found``, e.g. ``not-contracting``) is drawn dashed and grey; a cycle without
    contact points draws nothing.

    Returns the artists: the polyline (gid ``limit-cycle``), the arrowheads (``limit-cycle-arrow-k``) and
    the contact points (``limit-cycle-points``).
    """
    from matplotlib import patheffects

    pts = np.array([[float(p.point[0]), float(p.point[1])] for p in cycle.points], dtype=float).reshape(-1, 2)
    if len(pts) == 0:
        return []
    stable = cycle.found
    ink = color if stable else "#6b6b6b"
    closed = np.vstack([pts, pts[:1]])
    halo = [patheffects.Stroke(linewidth=linewidth + 2.2, foreground="white", alpha=0.85), patheffects.Normal()]
    (line,) = ax.plot(
        closed[:, 0], closed[:, 1], color=ink, linewidth=linewidth, linestyle="-" if stable else (0, (4, 2.5)),
        solid_capstyle="round", solid_joinstyle="round", zorder=6, path_effects=halo, gid="limit-cycle",
    )
    artists: list = [line]
    for k in range(len(pts)):
        a, b = closed[k], closed[k + 1]
        direction = b - a
        norm = float(np.hypot(*direction))
        if norm == 0:
            continue
        arrow = _arrow(ax, a + 0.55 * direction, direction / norm, color=ink, size=ARROW_SIZE * 0.9,
                       gid=f"limit-cycle-arrow-{k}")
        arrow.set_zorder(6.2)
        artists.append(arrow)
    dots = ax.scatter(
        pts[:, 0], pts[:, 1], s=70, c=point_color if stable else "white", edgecolors=ink, linewidths=1.4, zorder=6.6,
        gid="limit-cycle-points",
    )
    artists.append(dots)
    return artists


PLAN_STAGE_COLORS = ("#1b9e77", "#d95f02", "#7570b3", "#1f78b4", "#66a61e", "#e6ab02", "#a6761d", "#17becf")
PLAN_START_COLOR = "#1b7837"  # the start set: green, like the trajectories' start dots
PLAN_GOAL_COLOR = "#c51b7d"  # the goal set: magenta, distinct from every stage colour


def _plan_cone(p: Partition, source: int, target: int, lo: float, hi: float) -> np.ndarray | None:
    """The region swept by one move (floats): the hull of the source segment and its four corner landings."""
    a, b = np.asarray(p.seg_start[source]), np.asarray(p.seg_end[source])
    c, d = np.asarray(p.seg_start[target]), np.asarray(p.seg_end[target])
    e = (b - a) / float(np.hypot(*(b - a)))
    f = d - c
    hits = []
    for theta in (lo, hi):
        u = np.array([np.cos(theta) * e[0] - np.sin(theta) * e[1], np.sin(theta) * e[0] + np.cos(theta) * e[1]])
        den = u[0] * f[1] - u[1] * f[0]
        if abs(den) < 1e-15:
            return None
        for x in (a, b):
            s = ((c[0] - x[0]) * f[1] - (c[1] - x[1]) * f[0]) / den
            hits.append(x + max(s, 0.0) * u)
    pts = np.array([a, b, *hits])
    centre = pts.mean(axis=0)
    order = np.argsort(np.arctan2(pts[:, 1] - centre[1], pts[:, 0] - centre[0]))
    return pts[order]


def _boundary_set_lines(env: Environment, spec: str) -> np.ndarray:
    pieces = env.boundary_set(spec).pieces
    a = env.points_at(np.array([q.edge for q in pieces]), np.array([float(q.t0) for q in pieces]))
    b = env.points_at(np.array([q.edge for q in pieces]), np.array([float(q.t1) for q in pieces]))
    return np.stack([a, b], axis=1)


def draw_plan(
    ax: Axes,
    partition: Partition,
    plan: Plan,
    *,
    colors: tuple[str, ...] = PLAN_STAGE_COLORS,
    alpha: float = 0.3,
    legend: bool = True,
) -> list:
    """Draw a plan (:class:`~solverplan.plan.Plan`) as the paper's Figs. 12–13: for every stage and every
    possible source segment, the **cone** the robot may sweep — the region between the source segment
    and the four landing points of its corner rays at the two ends of the stage's interval — filled in
    the stage's colour; the segments a stage lands on drawn bold in that colour and numbered with the
    stage; the start set (green) and the goal set (magenta) drawn along the walls; and a legend with each
    stage's interval and width. Draw after :func:`draw_free_space`; draw trajectories on top
    (:func:`draw_trajectories` with rollouts of :func:`solverplan.simulate.simulate_plan`).

    Returns the artists: the cones (gid ``plan-cone-<stage>-<source>``, filled, under the trajectories, and
    ``plan-cone-outline-<stage>-<source>``, their outlines above them), the landing segments
    (``plan-targets-<stage>``), their stage numbers (``plan-stage-label-<stage>``), the start and goal
    sets (``plan-start``, ``plan-goal``) and the legend (``plan-legend``).
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon

    env = partition.env
    artists: list = []
    handles = []
    normals = _left_normals(env)
    for k, stage in enumerate(plan.stages):
        colour = colors[k % len(colors)]
        lo, hi = stage.interval.lo, stage.interval.hi
        for i, j in stage.moves:
            cone = _plan_cone(partition, i, j, lo, hi)
            if cone is None:
                continue
            patch = Polygon(cone, closed=True, facecolor=colour, edgecolor="none", alpha=alpha, zorder=1.3,
                            gid=f"plan-cone-{k}-{i}")
            outline = Polygon(cone, closed=True, fill=False, edgecolor=colour, alpha=0.9, linewidth=0.9, zorder=1.7,
                              gid=f"plan-cone-outline-{k}-{i}")
            ax.add_patch(patch)
            ax.add_patch(outline)
            artists.extend([patch, outline])
        segs = np.stack([partition.seg_start[list(stage.to_segments)], partition.seg_end[list(stage.to_segments)]], axis=1)
        lines = LineCollection(segs, colors=colour, linewidths=4.0, capstyle="butt", zorder=3.2, gid=f"plan-targets-{k}")
        ax.add_collection(lines)
        artists.append(lines)
        for s in stage.to_segments[:1]:
            mid = 0.5 * (np.asarray(partition.seg_start[s]) + np.asarray(partition.seg_end[s]))
            normal = normals[int(partition.seg_edge[s])]
            label = ax.annotate(
                str(k + 1), xy=(float(mid[0]), float(mid[1])), xytext=(float(-normal[0] * 9), float(-normal[1] * 9)),
                textcoords="offset points", ha="center", va="center", fontsize=8, fontweight="bold", color="white",
                bbox=dict(boxstyle="circle,pad=0.18", facecolor=colour, edgecolor="none"), zorder=6.8,
                annotation_clip=False,
            )
            label.set_gid(f"plan-stage-label-{k}")
            artists.append(label)
        handles.append(Line2D([], [], color=colour, linewidth=6, alpha=0.6,
                              label=f"{k + 1}: [{lo:.4f}, {hi:.4f}]  width {hi - lo:.4f}"))
    for spec, colour, gid, name in ((plan.start, PLAN_START_COLOR, "plan-start", "start"),
                                   (plan.goal, PLAN_GOAL_COLOR, "plan-goal", "goal")):
        if not spec:
            continue
        lines = LineCollection(_boundary_set_lines(env, spec), colors=colour, linewidths=7.0, alpha=0.55,
                               capstyle="butt", zorder=2.9, gid=gid)
        ax.add_collection(lines)
        artists.append(lines)
        handles.append(Line2D([], [], color=colour, linewidth=6, alpha=0.55, label=f"{name} {spec}"))
    if legend and handles:
        box = ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5, frameon=False,
                        title="stage: heading interval (rad)", title_fontsize=8, handlelength=1.6, borderaxespad=0.0)
        box.set_gid("plan-legend")
        box._legend_box.align = "left"
        artists.append(box)
    return artists


def plan_title(plan: Plan) -> str:
    """A one-line description of a plan for a figure title."""
    env = plan.environment.name if plan.environment is not None else ""
    head = f"{env}: " if env else ""
    if not plan.found:
        return f"{head}{plan.objective} plan from {plan.start} to {plan.goal}: infeasible"
    tol = plan.tolerance or 0.0
    return (f"{head}{plan.objective} plan {plan.start} → {plan.goal}: {plan.bounces} bounce"
            f"{'s' if plan.bounces != 1 else ''}, tolerance ±{tol:.4f} rad (±{np.degrees(tol):.2f}°)")


def render_environment(
    env: Environment,
    *,
    ax: Axes | None = None,
    edge_ids: bool = False,
    vertex_ids: bool = False,
    reflex: bool = True,
    title: str | None = None,
) -> Figure:
    """Draw ``env``: free space, boundary, and on request edge ids (with direction arrows) and vertex ids.

    Parameters
    ----------
    env
        The environment (normalised: free space on the left of every edge).
    ax
        Draw into this Axes; by default a new figure sized to the environment (:func:`new_figure`).
    edge_ids
        Label edges ``e<i>`` near their midpoints, inside the free space, with an arrowhead showing direction.
    vertex_ids
        Label vertices ``v<i>``, outside the free space.
    reflex
        Mark reflex vertices (red dots).
    title
        Axes title; defaults to the environment's name when drawing a new figure.

    Returns
    -------
    Figure
        The figure holding the Axes (``fig.axes[0]`` for a new figure); write it with :func:`save_figure`.
    """
    if ax is None:
        fig, ax = new_figure(env, title=title if title is not None else env.name)
    else:
        fig = ax.get_figure()
        if title:
            ax.set_title(title, fontsize=11)
    draw_free_space(ax, env)
    draw_boundary(ax, env)
    if reflex:
        draw_reflex_vertices(ax, env)
    if edge_ids or vertex_ids:
        placer = LabelPlacer(ax, env)  # one placer, so edge and vertex labels keep clear of each other
        if edge_ids:
            draw_edge_ids(ax, env, placer=placer)
        if vertex_ids:
            draw_vertex_ids(ax, env, placer=placer)
    return fig  # type: ignore[return-value]


# ---------------------------------------------------------------------- output
def figure_format(path: str | os.PathLike[str]) -> FigureFormat:
    """The picture format for ``path``, from its extension (``.png`` or ``.svg``).

    >>> figure_format("plan.SVG")
    'svg'
    >>> figure_format("plan.pdf")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: plan.pdf: unknown picture format '.pdf': use a .png or .svg file name
    """
    suffix = Path(path).suffix.lower()
    try:
        return _FORMATS[suffix]
    except KeyError:
        shown = repr(suffix) if suffix else "(no extension)"
        raise InputError(f"{path}: unknown picture format {shown}: use a .png or .svg file name") from None


def figure_bytes(fig: Figure, fmt: FigureFormat) -> bytes:
    """Render ``fig`` in memory as PNG or SVG bytes (reproducible: no dates or random ids in SVG)."""
    from matplotlib import rc_context

    buffer = io.BytesIO()
    metadata = {"Date": None} if fmt == "svg" else {"Software": None}
    with rc_context({"svg.hashsalt": "solverplan", "svg.fonttype": "none"}):
        fig.savefig(buffer, format=fmt, dpi=PNG_DPI, bbox_inches="tight", pad_inches=0.1, metadata=metadata)
    return buffer.getvalue()


@dataclass(frozen=True, slots=True)
class SavedFigure:
    """What :func:`save_figure` wrote: the file, its format and its size in bytes."""

    path: Path
    format: FigureFormat
    size: int

    def to_json(self) -> dict:
        return {"written": str(self.path), "format": self.format, "bytes": self.size}

    def to_text(self, *, width: int = 100) -> str:
        return f"wrote {self.path} ({self.format.upper()}, {self.size} bytes)\n"


def save_figure(fig: Figure, path: str | os.PathLike[str]) -> SavedFigure:
    """Write ``fig`` to ``path`` atomically, as PNG or SVG by the extension.

    The picture is rendered in memory first, so a failure leaves no partial file behind.

    Raises
    ------
    InputError
        For an extension other than ``.png`` / ``.svg``, or a path that cannot be written
        (missing folder, no permission); nothing is written.
    """
    fmt = figure_format(path)
    data = figure_bytes(fig, fmt)
    try:
        atomic_write_bytes(path, data)
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
    return SavedFigure(Path(path), fmt, len(data))


# ---------------------------------------------------------------------- study heatmaps
HEATMAP_CMAP = "viridis"


def draw_heatmap(
    ax: Axes,
    heatmap,
    *,
    cmap: str = HEATMAP_CMAP,
    vmin: float | None = None,
    vmax: float | None = None,
    annotate: bool = True,
):
    """Draw one study heatmap (paper Figs. 15–16): a cell per (x, y) coloured by its mean, annotated.

    ``heatmap`` is a :class:`solverplan.studies.study.Heatmap` (any object with ``title``, ``x_name``,
    ``x_values``, ``y_name``, ``y_values``, ``mean`` (rows = y, columns = x, NaN = no rows) and
    ``count``). y grows upwards. Returns the :class:`~matplotlib.image.AxesImage` (gid ``heatmap``).
    """
    mean = np.asarray(heatmap.mean, dtype=float)
    finite = mean[np.isfinite(mean)]
    lo = vmin if vmin is not None else (float(finite.min()) if finite.size else 0.0)
    hi = vmax if vmax is not None else (float(finite.max()) if finite.size else 1.0)
    if hi <= lo:
        hi = lo + (abs(lo) * 0.01 or 1.0)
    image = ax.imshow(mean, origin="lower", cmap=cmap, vmin=lo, vmax=hi, aspect="auto", interpolation="nearest")
    image.set_gid("heatmap")
    ax.set_xticks(range(len(heatmap.x_values)), [f"{v:g}" if isinstance(v, float) else str(v) for v in heatmap.x_values])
    ax.set_yticks(range(len(heatmap.y_values)), [f"{v:g}" if isinstance(v, float) else str(v) for v in heatmap.y_values])
    ax.set_xlabel(heatmap.x_name, fontsize=9)
    ax.set_ylabel(heatmap.y_name, fontsize=9)
    ax.tick_params(labelsize=8)
    ax.set_title(heatmap.title, fontsize=10)
    if annotate:
        from matplotlib import colormaps

        colours = colormaps[cmap]
        size = 8 if mean.size <= 36 else 6
        for i in range(mean.shape[0]):
            for j in range(mean.shape[1]):
                value = mean[i, j]
                if not np.isfinite(value):
                    continue
                level = (value - lo) / (hi - lo)
                r, g, b, _ = colours(float(np.clip(level, 0, 1)))
                ink = "white" if 0.299 * r + 0.587 * g + 0.114 * b < 0.5 else "black"
                text = f"{value:.3g}" if abs(value) >= 0.01 or value == 0 else f"{value:.1e}"
                ax.text(j, i, text, ha="center", va="center", fontsize=size, color=ink, gid=f"heatmap-value-{i}-{j}")
    return image


def render_heatmaps(heatmaps, *, title: str | None = None, columns: int | None = None, cmap: str = HEATMAP_CMAP) -> Figure:
    """A figure of study heatmaps in a grid (``columns`` per row; default: all in one row up to 5).

    Panels showing the same ``value`` share one colour scale (so families or options compare
    directly); each scale has a colour bar beside the last panel using it.
    """
    panels = list(heatmaps)
    if not panels:
        raise InputError("no heatmap to draw")
    ncols = columns or min(len(panels), 5)
    nrows = -(-len(panels) // ncols)
    fig = Figure(figsize=(3.9 * ncols + 0.6, 3.4 * nrows + (0.5 if title else 0.1)))
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    scales: dict[str, tuple[float, float]] = {}
    for h in panels:
        finite = np.asarray(h.mean, dtype=float)[np.isfinite(h.mean)]
        if finite.size:
            lo, hi = scales.get(h.value, (float("inf"), float("-inf")))
            scales[h.value] = (min(lo, float(finite.min())), max(hi, float(finite.max())))
    last = {h.value: k for k, h in enumerate(panels)}
    for k, h in enumerate(panels):
        ax = axes[k // ncols][k % ncols]
        lo, hi = scales.get(h.value, (0.0, 1.0))
        image = draw_heatmap(ax, h, cmap=cmap, vmin=lo, vmax=hi)
        if last[h.value] == k:
            fig.colorbar(image, ax=ax, fraction=0.046, pad=0.03).ax.tick_params(labelsize=7)
    for k in range(len(panels), nrows * ncols):
        axes[k // ncols][k % ncols].set_visible(False)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig  # type: ignore[return-value]


# ---------------------------------------------------------------------- contraction answers (issue 6)
PATROL_EDGE_COLOR = "#7b3294"  # the edges a patrol must visit
CONE_COLOR = "#2c7fb8"  # the heading interval of a stage, as a fan of rays
FUNNEL_START_COLOR = "#1b7837"
FUNNEL_GOAL_COLOR = "#b2182b"


def _piece_xy(env: Environment, edge: int, t0: float, t1: float) -> np.ndarray:
    return env.points_at(np.array([edge, edge]), np.array([float(t0), float(t1)]))


def draw_patrol(ax: Axes, patrol, *, linewidth: float = 2.2) -> list:
    """Draw a patrol (:class:`~solverplan.plan.patrol.Patrol`): the required edges (thick, purple), each cycle
    stage's heading interval as a shaded fan of rays from its nominal contact point, and the nominal limit
    cycle (bold, contact points as yellow circles). Returns the artists (gids ``patrol-edges``,
    ``patrol-cone-k``, ``patrol-cycle``, ``patrol-points``)."""
    from matplotlib.patches import Polygon

    from solverplan.geometry.raycast import cast_from_boundary

    env = patrol.env
    artists: list = []
    segs = [env.points_at(np.array([e, e]), np.array([0.0, 1.0])) for e in dict.fromkeys(patrol.visit)]
    if segs:
        lines = LineCollection(segs, colors=PATROL_EDGE_COLOR, linewidths=5.0, alpha=0.55, zorder=3.5,
                               gid="patrol-edges", capstyle="butt")
        ax.add_collection(lines)
        artists.append(lines)
    if not patrol.points:
        return artists
    for k, (st, p) in enumerate(zip(patrol.cycle, patrol.points)):
        hits = cast_from_boundary(env, np.array([st.affine.from_edge] * 2), np.array([float(p.t)] * 2),
                                  np.array([st.interval.lo, st.interval.hi]))
        origin = [float(p.point[0]), float(p.point[1])]
        fan = Polygon([origin, [hits.x[0], hits.y[0]], [hits.x[1], hits.y[1]]], closed=True, facecolor=CONE_COLOR,
                      edgecolor=CONE_COLOR, alpha=0.18, linewidth=0.6, zorder=4, gid=f"patrol-cone-{k}")
        ax.add_patch(fan)
        artists.append(fan)
    pts = np.array([[float(p.point[0]), float(p.point[1])] for p in patrol.points])
    closed = np.vstack([pts, pts[:1]])
    (line,) = ax.plot(closed[:, 0], closed[:, 1], color=CYCLE_COLOR if patrol.found else "#6b6b6b", linewidth=linewidth,
                      zorder=6, gid="patrol-cycle")
    artists.append(line)
    artists.append(ax.scatter(pts[:, 0], pts[:, 1], s=60, c=CYCLE_POINT_COLOR, edgecolors=CYCLE_COLOR, linewidths=1.2,
                              zorder=6.5, gid="patrol-points"))
    return artists


def draw_position_sets(ax: Axes, answer, *, cmap: str = "viridis") -> list:
    """Draw a funnel or localisation strategy: the start set (green), the goal (red), and for every stage the
    region its rays sweep (the hull of the source pieces and their corner hits, shaded) and the exact set of
    positions after it (thick, coloured from the first stage to the last) — the shrinking position sets.
    Returns the artists (gids ``funnel-start``, ``funnel-goal``, ``funnel-swept-k``, ``funnel-positions-k``)."""
    from matplotlib import colormaps
    from matplotlib.patches import Polygon

    env = answer.env
    artists: list = []
    colours = colormaps[cmap]
    n = max(len(answer.stages), 1)

    def pieces(items, colour, width, gid, z):
        segs = [_piece_xy(env, p.edge, p.t0, p.t1) for p in items]
        if not segs:
            return
        lc = LineCollection(segs, colors=colour, linewidths=width, zorder=z, gid=gid, capstyle="round")
        ax.add_collection(lc)
        artists.append(lc)

    pieces(answer.start.pieces, FUNNEL_START_COLOR, 6.0, "funnel-start", 3.6)
    if answer.goal is not None:
        pieces(answer.goal.pieces, FUNNEL_GOAL_COLOR, 6.0, "funnel-goal", 3.6)
    for k, st in enumerate(answer.stages):
        colour = colours(0.1 + 0.8 * k / max(n - 1, 1))
        for src, (d_lo, d_hi) in zip(st.sources, st.cones):
            a = _piece_xy(env, src.edge, src.t0, src.t1)
            corner = []
            for origin in a:
                for d in (d_lo, d_hi):
                    corner.append(_ray_to_boundary(env, origin, np.array([float(d[0]), float(d[1])])))
            hull = _hull(np.vstack([a, np.array(corner)]))
            patch = Polygon(hull, closed=True, facecolor=colour, edgecolor=colour, alpha=0.3, linewidth=0.8, zorder=4,
                            gid=f"funnel-swept-{k}")
            ax.add_patch(patch)
            artists.append(patch)
        pieces(st.positions, colour, 4.5, f"funnel-positions-{k}", 5.5)
        p = st.positions[0]
        x, y = _piece_xy(env, p.edge, p.t0, p.t1).mean(axis=0)
        label = ax.annotate(str(k + 1), (x, y), xytext=(6, 6), textcoords="offset points", fontsize=8, color="black",
                            zorder=7, gid=f"funnel-label-{k}",
                            bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": colour, "alpha": 0.85})
        artists.append(label)
    return artists


def _ray_to_boundary(env: Environment, origin: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The first boundary point along origin + s d, s > 0 (floats; for drawing only)."""
    a, b = env.edge_start, env.edge_end
    e = b - a
    den = d[0] * e[:, 1] - d[1] * e[:, 0]
    rel = a - origin
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (rel[:, 0] * e[:, 1] - rel[:, 1] * e[:, 0]) / den
        u = (rel[:, 0] * d[1] - rel[:, 1] * d[0]) / den
    scale = float(np.hypot(*d))
    ok = np.isfinite(s) & (s * scale > 1e-9 * (1 + np.abs(origin).max())) & (u >= -1e-12) & (u <= 1 + 1e-12)
    if not ok.any():
        return origin
    return origin + s[ok].min() * d


def _hull(points: np.ndarray) -> np.ndarray:
    pts = sorted(set(map(tuple, np.round(points, 12).tolist())))
    if len(pts) < 3:
        return np.array(pts)

    def chain(seq):
        out: list = []
        for p in seq:
            while len(out) >= 2 and (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1]) - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0]) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def render_answer(answer, *, edge_ids: bool = True) -> Figure:
    """A picture of a patrol, funnel or localisation answer over its environment, with a two-line title."""
    env = answer.env
    name = env.name or "environment"
    if hasattr(answer, "cycle"):
        seq = "→".join(f"e{e}" for e in answer.visit)
        sub = (f"worst-case contraction {answer.contraction:.3g} per cycle, {answer.rate:.3g} per bounce"
               if answer.found else answer.status)
        fig = render_environment(env, edge_ids=edge_ids, title=f"{name}: patrol {seq} ({answer.objective})\n{sub}")
        draw_patrol(fig.axes[0], answer)
        return fig
    widths = answer.widths
    sub = (f"{len(answer.stages)} bounces; position set {widths[0]:.3g} → {widths[-1]:.3g} long" if answer.stages
           else answer.status)
    target = f"< {answer.epsilon:g}" if answer.kind == "localize" else str(answer.goal)
    fig = render_environment(env, edge_ids=edge_ids, title=f"{name}: {answer.kind} {answer.start} → {target}\n{sub}")
    draw_position_sets(fig.axes[0], answer)
    return fig
