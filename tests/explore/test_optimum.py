"""The chained cover MILP: the offline optimum that measures Algorithm A's competitive ratio."""

from __future__ import annotations

from solverplan.environment import Environment, load_environment
from solverplan.explore.depth_first import explore_depth_first
from solverplan.explore.optimum import chained_optimum
from solverplan.geometry.visibility import sees


def test_convex_needs_one_view_and_the_l_two():
    square = Environment.from_coords([[0, 0], [3, 0], [3, 3], [0, 3]])
    assert chained_optimum(square, (1, 1)).views == 1
    ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    assert chained_optimum(ell, (3, 1)).views == 2


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
