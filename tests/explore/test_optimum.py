"""The chained cover MILP: the offline optimum that measures Algorithm A's competitive ratio."""

from __future__ import annotations

import pytest

from solverplan.environment import Environment, load_environment
from solverplan.explore.depth_first import explore_depth_first
from solverplan.explore.optimum import chained_optimum
from solverplan.geometry.visibility import sees


def test_convex_needs_one_view_and_the_l_two():
    square = Environment.from_coords([[0, 0], [3, 0], [3, 3], [0, 3]])
    assert chained_optimum(square, (1, 1)).views == 1
    ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    assert chained_optimum(ell, (3, 1)).views == 2


@pytest.mark.slow  # the optimum over every arrangement cell of the comb takes about a minute
def test_theorem_2_online_views_within_r_plus_1_over_2_of_the_optimum_on_the_comb():
    comb = load_environment("comb")
    run = explore_depth_first(comb, (1, 1))
    opt = chained_optimum(comb, (1, 1), run.viewpoints)
    assert opt.views <= run.n_views <= run.bound
    if opt.views >= 2:
        assert run.n_views / opt.views <= run.bound / 2
    chosen = opt.viewpoints
    assert chosen[0] == (1, 1)
    reached = {chosen[0]}   # the chosen set is chained: connected by visibility from the start
    grew = True
    while grew:
        grew = False
        for q in chosen:
            if q not in reached and any(sees(comb, p, q) for p in reached):
                reached.add(q)
                grew = True
    assert reached == set(chosen)


def test_issue26_lower_bound_is_below_the_optimum_and_witnesses_are_pairwise_invisible():
    from solverplan.geometry.visibility import visibility_polygon
    import shapely

    for env, start in [(load_environment("comb"), (1, 1)), (load_environment("l_shape"), (8, 2)),
                       (Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]]), (3, 1))]:
        opt = chained_optimum(env, start)
        assert 1 <= opt.lower_bound <= opt.views and opt.gap == opt.views - opt.lower_bound
        views = [shapely.Polygon([tuple(map(float, x)) for x in visibility_polygon(env, w).ring]) for w in opt.witnesses]
        for i in range(len(views)):
            for j in range(i + 1, len(views)):
                assert views[i].intersection(views[j]).area == 0.0  # no point sees two witnesses
        assert opt.to_json()["gap"] == opt.gap


def test_issue26_cell_points_find_two_chained_views_where_vertices_need_three():
    # a plus-shaped room: from its centre one view sees all four arms' mouths but not their ends; the start in
    # one arm and one point in the middle suffice only if the middle point is offered (not a vertex)
    plus = Environment.from_coords([[2, 0], [4, 0], [4, 2], [6, 2], [6, 4], [4, 4], [4, 6], [2, 6], [2, 4], [0, 4],
                                    [0, 2], [2, 2]])
    coarse = chained_optimum(plus, (3, 1), refine=False)
    fine = chained_optimum(plus, (3, 1))
    assert fine.views <= coarse.views and fine.candidates > coarse.candidates
    assert fine.lower_bound <= fine.views
