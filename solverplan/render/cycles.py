"""Limit cycles of a constant heading (paper §6.1, Fig. 9): a bold closed path with arrows and contact points.

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.cycles import limit_cycle
>>> from solverplan.render import render_environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]])
>>> fig = render_environment(env)
>>> [a.get_gid() for a in draw_cycle(fig.axes[0], limit_cycle(env, "tan:1/3"))][::4]
['limit-cycle', 'limit-cycle-arrow-3']
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

from solverplan.render.figure import ARROW_SIZE, CYCLE_COLOR, CYCLE_POINT_COLOR, _arrow

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.cycles import LimitCycle

__all__ = ["draw_cycle"]


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
