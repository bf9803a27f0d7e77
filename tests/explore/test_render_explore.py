"""The exploration picture: views (range arcs drawn as arcs), the triangulation of the explored region, the path."""

from __future__ import annotations

import math

import matplotlib.patches as mpatches

from solverplan.environment import Environment, load_environment
from solverplan.explore import explore_depth_first, explore_range_limited
from solverplan.render.explore import explored_triangles, render_exploration


def test_range_views_are_drawn_with_true_arcs_and_the_triangulation():
    env = load_environment("l_shape")
    run = explore_range_limited(env, (2, 7), 3)
    fig = render_exploration(run, env)
    ax = fig.axes[0]
    arcs = [p for p in ax.patches if isinstance(p, mpatches.Arc)]
    assert len(arcs) == sum(len(v.arcs) for v in run.views) > 0
    first = run.views[0].arcs[0]
    drawn = next(p for p in arcs if p.get_gid() == "arc-0-0")
    assert drawn.width == 2 * float(first.radius) and math.isclose(drawn.theta1, math.degrees(first.start_angle))
    gids = {c.get_gid() for c in ax.collections}
    assert {"triangulation", "boundary"} <= gids
    assert "Algorithm B" in ax.get_title()


def test_triangulation_of_a_covered_polygon_uses_its_vertices_only():
    env = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    run = explore_depth_first(env, (3, 1))
    triangles = explored_triangles(run, env)
    corners = {tuple(map(float, p)) for p in env.exact_vertices}
    assert len(triangles) == env.n_vertices - 2   # a triangulated hexagon without holes has n − 2 triangles
    assert all(tuple(c) in corners for t in triangles for c in t)
    area = sum(abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2 for a, b, c in triangles)
    assert math.isclose(area, float(env.area))
