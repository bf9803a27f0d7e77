"""The bounce visibility graph of P′ (paper §5): its arcs as a light shade, its safe arcs as landing rays.

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.bvg import safe_bounce_visibility_graph
>>> from solverplan.render import render_environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]])
>>> graph = safe_bounce_visibility_graph(env)
>>> fig = render_environment(env)
>>> (arcs,) = draw_safe_arcs(fig.axes[0], graph)
>>> arcs.get_gid(), len(arcs.get_segments()) == graph.n_safe_arcs
('safe-arcs', True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from solverplan.geometry.raycast import cast_from_boundary
from solverplan.render.figure import GRAPH_COLOR, SAFE_ARC_COLOR, _ink_alpha

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.bvg import SafeBVG
    from solverplan.environment import Environment

__all__ = ["draw_graph", "draw_safe_arcs"]


def draw_graph(ax: Axes, graph: SafeBVG, *, color: str = GRAPH_COLOR, linewidth: float = 0.5,
               alpha: float | None = None) -> list:
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
    return _shade(ax, p.env, segments, color, linewidth, alpha, ink=0.6, zorder=1.2, gid="bvg-arcs")


def draw_safe_arcs(ax: Axes, graph: SafeBVG, *, color: str = SAFE_ARC_COLOR, linewidth: float = 0.6,
                   alpha: float | None = None) -> list:
    """Draw every safe arc i → j as the ray it stands for: from the midpoint of segment i at the middle
    heading of the arc's widest safe interval, to where it lands on segment j (which it does: the
    heading is safe). Open ends at 0 or π are clipped to 0.02 rad inside, so the ray leaves the wall.

    Returns the artists: one :class:`~matplotlib.collections.LineCollection` (gid ``safe-arcs``).
    """
    p = graph.partition
    rows = np.flatnonzero(graph.safe)
    i = graph.source[rows]
    lo = np.maximum(graph.lo[rows], np.minimum(0.02, graph.hi[rows]))
    hi = np.minimum(graph.hi[rows], np.maximum(np.pi - 0.02, graph.lo[rows]))
    edges = np.asarray(p.seg_edge)[i]
    mid_t = 0.5 * (np.asarray(p.seg_t0)[i] + np.asarray(p.seg_t1)[i])
    # the heading is safe, so the first wall the ray meets is segment j; ties are settled exactly
    segments = np.empty((0, 2, 2))
    if len(rows):
        hits = cast_from_boundary(p.env, edges, mid_t, 0.5 * (lo + hi), exact_ties=True)
        ok = (hits.edge >= 0) & np.isfinite(hits.x) & np.isfinite(hits.y)
        start = p.env.points_at(edges[ok], mid_t[ok])
        segments = np.stack([start, hits.points[ok]], axis=1).reshape(-1, 2, 2)
    return _shade(ax, p.env, segments, color, linewidth, alpha, ink=0.35, zorder=1.4, gid="safe-arcs")


def _shade(ax: Axes, env: Environment, segments: np.ndarray, color: str, linewidth: float, alpha: float | None, *,
           ink: float, zorder: float, gid: str) -> list:
    """``segments`` (k × 2 × 2) as one line collection ``gid``; ``alpha`` by default falls with the total ink
    (:func:`~solverplan.render.figure._ink_alpha`, ink covering ``ink`` of the free space), so a dense graph reads as
    a shade."""
    if alpha is None:
        alpha = _ink_alpha(ax, env, segments, linewidth, ink)
    lines = LineCollection(list(segments), colors=color, linewidths=linewidth, alpha=alpha, zorder=zorder, gid=gid)
    ax.add_collection(lines)
    return [lines]
