"""The environment layers: free space, walls, edge directions, reflex vertices, and their composition.

A picture is a stack of layers. Each layer is a ``draw_*`` function that takes an
:class:`~matplotlib.axes.Axes` and the data to draw and returns the artists it added, so callers
(and tests) can restyle or count them; every artist carries a ``gid`` (``edge-id-3``,
``vertex-id-0``, ``reflex-vertices``, ...) that also becomes its ``id`` in SVG output.
:func:`render_environment` composes the environment layers; later layers (``draw_partition``,
``draw_plan``, ``draw_trajectories``) take the same Axes and stack on top.

Conventions match the rest of the package: free space on the left of every directed edge; edge
``i`` goes from vertex ``i`` to the next vertex of its ring; labels are ``e3`` / ``v3`` like the
boundary-set syntax (``docs/contract.md``).

>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
>>> fig = render_environment(env, edge_ids=True)
>>> len([t for t in fig.axes[0].texts if t.get_gid().startswith("edge-id-")])
8
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.figure import Figure
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath
from matplotlib.text import Annotation

from solverplan.environment import Environment
from solverplan.render.figure import ARROW_SIZE, BOUNDARY_COLOR, EDGE_ID_COLOR, FREE_SPACE_COLOR, REFLEX_COLOR, _arrow, _figure_of, new_figure
from solverplan.render.labels import LabelPlacer, _edge_label_params, _unit, draw_edge_ids, draw_vertex_ids

__all__ = ["draw_free_space", "draw_boundary", "draw_edge_directions", "draw_reflex_vertices", "render_environment"]


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
        codes.extend(int(c) for c in [MplPath.MOVETO] + [MplPath.LINETO] * (len(pts) - 1) + [MplPath.CLOSEPOLY])
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
    lines = LineCollection(list(segments), colors=color, linewidths=linewidth, capstyle="round", zorder=2, gid="boundary")
    ax.add_collection(lines)
    return lines


def draw_edge_directions(
    ax: Axes, env: Environment, *, t: np.ndarray | None = None, color: str = EDGE_ID_COLOR, size: float | None = None
) -> list[Annotation]:
    """An arrowhead on every edge pointing along it (a → b), at boundary parameter ``t`` (default: near the middle)."""
    size = size or ARROW_SIZE
    params = _edge_label_params(env) if t is None else np.asarray(t, dtype=float)
    spots = env.points_at(np.arange(env.n_edges), params)
    dirs = _unit(env.edge_end - env.edge_start)
    return [_arrow(ax, spots[i], dirs[i], color=color, size=size, gid=f"edge-arrow-{i}") for i in range(env.n_edges)]


def draw_reflex_vertices(ax: Axes, env: Environment, *, color: str = REFLEX_COLOR, size: float = 22.0) -> PathCollection:
    """Mark the reflex vertices (free-space angle > π) with dots."""
    ids = list(env.reflex_vertices)
    pts = env.vertices[ids] if ids else np.empty((0, 2))
    dots = ax.scatter(pts[:, 0], pts[:, 1], s=size, c=color, zorder=5, edgecolors="white", linewidths=0.6, gid="reflex-vertices")
    return dots


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
        fig = _figure_of(ax)
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
    return fig
