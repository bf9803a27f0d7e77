"""Explorations with discrete views (Algorithms A and B): each view as a pale translucent fill (range-limited
views bounded by true circular arcs), its constructed edges dashed and its range arcs drawn as arcs, the
triangulation of the explored region (thin grey), the robot's path (forward and backward moves) and the
numbered viewpoints.

>>> from solverplan.environment import load_environment
>>> from solverplan.explore import explore_depth_first
>>> fig = render_exploration(explore_depth_first(load_environment("comb"), (1, 1)), load_environment("comb"))
>>> sorted({a.get_gid() for a in fig.axes[0].patches})[:2], fig.axes[0].get_title().startswith("comb")
(['view-0', 'view-1'], True)
>>> "triangulation" in {c.get_gid() for c in fig.axes[0].collections}
True
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Arc as ArcPatch
from matplotlib.patches import PathPatch, Polygon
from matplotlib.path import Path

from solverplan.environment import Environment
from solverplan.explore.depth_first import Exploration
from solverplan.explore.range_limited import RangeExploration
from solverplan.explore.range_view import Arc, RangeView
from solverplan.geometry.visibility import VisibilityPolygon
from solverplan.render.environment import draw_boundary
from solverplan.render.figure import new_figure

__all__ = ["render_exploration"]

VIEW_COLORS = ("#9ecae1", "#fdae6b", "#a1d99b", "#bcbddc", "#fdd0a2", "#c7e9c0", "#dadaeb", "#fcbba1")
PATH_COLOR = "#08306b"
WINDOW_COLOR = "#636363"
ARC_COLOR = "#6a51a3"
TRIANGLE_COLOR = "#bdbdbd"


def _view_path(view: RangeView) -> Path:
    """The boundary of a range-limited view as a matplotlib path: straight sides as lines, arcs as Bézier arcs
    (matplotlib's :meth:`Path.arc`, scaled to R about the viewpoint)."""
    verts: list[tuple[float, float]] = []
    codes: list[int] = []
    cx, cy = float(view.viewpoint[0]), float(view.viewpoint[1])
    for piece in view.pieces:
        if isinstance(piece, Arc):
            unit = Path.arc(math.degrees(piece.start_angle), math.degrees(piece.end_angle))
            r = float(piece.radius)
            xy = np.asarray(unit.vertices, dtype=float) * r + np.array([cx, cy])
            unit_codes = [int(c) for c in np.asarray(unit.codes)]
            verts.extend((float(x), float(y)) for x, y in xy)
            codes.append(int(Path.MOVETO) if len(codes) == 0 else int(Path.LINETO))
            codes.extend(unit_codes[1:])
        else:
            codes.append(int(Path.MOVETO) if len(codes) == 0 else int(Path.LINETO))
            verts.append(piece.a)
    verts.append(verts[0])
    codes.append(int(Path.CLOSEPOLY))
    return Path(verts, codes)


def explored_triangles(run: Exploration | RangeExploration, env: Environment) -> list[list[tuple[float, float]]]:
    """A triangulation of the explored region (floats, for drawing): the constrained Delaunay triangulation of
    the free space when the views cover it (so it uses the polygon's vertices only, the paper's map of the free
    space), else of the union of the views (ring vertices and, for range views, arcs cut to chords of 1/20 of R)."""
    import shapely

    free = env.to_shapely()
    if run.covered_fraction > 1 - 1e-6:
        region = free
    elif isinstance(run, RangeExploration):
        sag = 2e-3
        region = shapely.union_all([v.to_shapely(sag) for v in run.views]).intersection(free)
    else:
        region = shapely.union_all([shapely.Polygon([tuple(map(float, p)) for p in vp.ring]) for vp in run.views])
        region = region.intersection(free)
    tris = shapely.constrained_delaunay_triangles(region)
    return [list(t.exterior.coords)[:3] for t in getattr(tris, "geoms", [])]


def render_exploration(run: Exploration | RangeExploration, env: Environment, *, title: str | None = None) -> Figure:
    """The views (gid ``view-<k>``), their windows (gid ``windows``), range arcs (gid ``arc-<k>-<i>``), the
    triangulation of the explored region (gid ``triangulation``), the path (gid ``path``) and the viewpoints
    p1, p2, … (gid ``viewpoints``) of ``run`` over ``env``'s walls."""
    what = f"R = {float(run.range):.3g}, " if isinstance(run, RangeExploration) else ""
    heading = title or (f"{env.name or 'exploration'}: Algorithm {run.algorithm}, {what}{run.n_views} views "
                        f"(bound {run.bound}), path {run.path_length:.3g}")
    fig, ax = new_figure(env, title=heading)
    xmin, ymin, xmax, ymax = env.bounds
    pad = 0.05 * max(xmax - xmin, ymax - ymin)
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    triangles = explored_triangles(run, env)
    if triangles:
        edges = [[t[i], t[(i + 1) % 3]] for t in triangles for i in range(3)]
        ax.add_collection(LineCollection(edges, colors=TRIANGLE_COLOR, linewidths=0.4, zorder=0.8,
                                         gid="triangulation"))
    windows = []
    views: Sequence[RangeView | VisibilityPolygon] = run.views
    for k, view in enumerate(views):
        color = VIEW_COLORS[k % len(VIEW_COLORS)]
        if isinstance(view, RangeView):
            ax.add_patch(PathPatch(_view_path(view), facecolor=color, edgecolor="none", alpha=0.35, zorder=0.5,
                                   gid=f"view-{k}"))
            cx, cy = float(view.viewpoint[0]), float(view.viewpoint[1])
            for i, arc in enumerate(view.arcs):
                d = 2 * float(arc.radius)
                ax.add_patch(ArcPatch((cx, cy), d, d, theta1=math.degrees(arc.start_angle),
                                      theta2=math.degrees(arc.end_angle), color=ARC_COLOR, linewidth=0.6,
                                      alpha=0.7, zorder=1.4, gid=f"arc-{k}-{i}"))
            windows += [[s.a, s.b] for s in view.segments if s.kind == "constructed"]
        else:
            xy = np.array([[float(x), float(y)] for x, y in view.ring])
            ax.add_patch(Polygon(xy, closed=True, facecolor=color, edgecolor="none", alpha=0.35, zorder=0.5,
                                 gid=f"view-{k}"))
            windows += [[(float(p.a[0]), float(p.a[1])), (float(p.b[0]), float(p.b[1]))]
                        for p in view.pieces if p.kind == "constructed"]
    if windows:
        ax.add_collection(LineCollection(windows, colors=WINDOW_COLOR, linewidths=0.8, linestyles="dashed", zorder=1.5,
                                         gid="windows"))
    draw_boundary(ax, env)
    path = np.array([[float(x), float(y)] for x, y in run.path])
    ax.plot(path[:, 0], path[:, 1], color=PATH_COLOR, linewidth=1.1, zorder=4, gid="path")
    points = np.array([[float(x), float(y)] for x, y in run.viewpoints])
    ax.scatter(points[:, 0], points[:, 1], s=18 if len(points) < 40 else 8, c=PATH_COLOR, zorder=5, gid="viewpoints")
    if len(points) <= 60:
        for k, (x, y) in enumerate(points):
            ax.annotate(f"p{k + 1}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8 if k < 30 else 6,
                        color=PATH_COLOR, zorder=6)
    return fig
