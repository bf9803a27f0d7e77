"""Simulated trajectories (:mod:`solverplan.simulate` rollouts): thin paths, start dots, flagged stops.

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.rules import Specular
>>> from solverplan.render import render_environment
>>> from solverplan.simulate import simulate_rule
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]])
>>> runs = simulate_rule(env, Specular(), "e0", bounces=5, trials=3, seed=1)
>>> fig = render_environment(env)
>>> [a.get_gid() for a in draw_trajectories(fig.axes[0], runs)]
['trajectories', 'trajectory-starts']
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from solverplan.errors import InputError
from solverplan.render.figure import TRAJECTORY_COLOR, TRAJECTORY_FLAG_COLOR, TRAJECTORY_START_COLOR, _ink_alpha

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.simulate import Rollouts

__all__ = ["draw_trajectories"]


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
    value that falls with the total ink of the paths (half the free space covered, spread evenly), so that dense
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
        alpha = _ink_alpha(ax, rollouts.env, segments, linewidth, 0.5, lo=0.04, hi=0.8)
    lines = LineCollection(
        list(segments), colors=color, linewidths=linewidth, alpha=alpha, capstyle="round", zorder=1.5, gid="trajectories"
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
