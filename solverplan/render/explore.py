"""Explorations with discrete views (Algorithm A): each view's visibility polygon as a pale translucent fill with
its constructed edges dashed, the robot's path (forward and backward moves) and the numbered viewpoints.

>>> from solverplan.environment import load_environment
>>> from solverplan.explore import explore_depth_first
>>> fig = render_exploration(explore_depth_first(load_environment("comb"), (1, 1)), load_environment("comb"))
>>> sorted({a.get_gid() for a in fig.axes[0].patches})[:2], fig.axes[0].get_title().startswith("comb")
(['view-0', 'view-1'], True)
"""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from solverplan.environment import Environment
from solverplan.explore.depth_first import Exploration
from solverplan.render.environment import draw_boundary
from solverplan.render.figure import new_figure

__all__ = ["render_exploration"]

VIEW_COLORS = ("#9ecae1", "#fdae6b", "#a1d99b", "#bcbddc", "#fdd0a2", "#c7e9c0", "#dadaeb", "#fcbba1")
PATH_COLOR = "#08306b"
WINDOW_COLOR = "#636363"


def render_exploration(run: Exploration, env: Environment, *, title: str | None = None) -> Figure:
    """The views (gid ``view-<k>``), their windows (gid ``windows``), the path (gid ``path``) and the
    viewpoints p1, p2, … (gid ``viewpoints``) of ``run`` over ``env``'s walls."""
    heading = title or (f"{env.name or 'exploration'}: {run.n_views} views (bound {run.bound}), "
                        f"path {run.path_length:.3g}")
    fig, ax = new_figure(env, title=heading)
    xmin, ymin, xmax, ymax = env.bounds
    pad = 0.05 * max(xmax - xmin, ymax - ymin)
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    windows = []
    for k, vp in enumerate(run.views):
        xy = np.array([[float(x), float(y)] for x, y in vp.ring])
        ax.add_patch(Polygon(xy, closed=True, facecolor=VIEW_COLORS[k % len(VIEW_COLORS)], edgecolor="none",
                             alpha=0.35, zorder=0.5, gid=f"view-{k}"))
        windows += [[(float(p.a[0]), float(p.a[1])), (float(p.b[0]), float(p.b[1]))]
                    for p in vp.pieces if p.kind == "constructed"]
    if windows:
        ax.add_collection(LineCollection(windows, colors=WINDOW_COLOR, linewidths=0.8, linestyles="dashed", zorder=1.5,
                                         gid="windows"))
    draw_boundary(ax, env)
    path = np.array([[float(x), float(y)] for x, y in run.path])
    ax.plot(path[:, 0], path[:, 1], color=PATH_COLOR, linewidth=1.1, zorder=4, gid="path")
    points = np.array([[float(x), float(y)] for x, y in run.viewpoints])
    ax.scatter(points[:, 0], points[:, 1], s=18, c=PATH_COLOR, zorder=5, gid="viewpoints")
    for k, (x, y) in enumerate(points):
        ax.annotate(f"p{k + 1}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8, color=PATH_COLOR,
                    zorder=6)
    return fig
