"""Algorithm A (depth-first exploration with discrete views): coverage, the r + 1 bound, the chain, the path."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.exact import point_in_ring
from solverplan.explore import CHOICES, explore_depth_first, unexplored_parts, windows
from solverplan.geometry.visibility import sees, visibility_polygon
from solverplan.result import Status
from tests.strategies import polygons_with_holes, simple_polygons

ELL = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])


@st.composite
def free_points(draw, env: Environment):
    """A point of the closed free space on a quarter-unit grid inside the bounding box."""
    xmin, ymin, xmax, ymax = env.bounds
    for _ in range(50):
        p = (Fraction(draw(st.integers(int(4 * xmin), int(4 * xmax))), 4),
             Fraction(draw(st.integers(int(4 * ymin), int(4 * ymax))), 4))
        if point_in_ring(p, env.outer) >= 0 and all(point_in_ring(p, h) <= 0 for h in env.holes):
            return p
    return env.exact_vertices[0]  # a vertex is always in the closed free space


@st.composite
def instances(draw, holes: bool):
    env = draw(polygons_with_holes() if holes else simple_polygons(min_vertices=4))
    return env, draw(free_points(env)), draw(st.sampled_from(CHOICES)), draw(st.integers(0, 1000))


def _explore(env, start, choice, seed):
    return explore_depth_first(env, start, choice=choice, seed=seed if choice == "random" else None)


def _check_theorem_1(run, env):
    assert run.status is Status.FOUND
    assert run.n_views <= len(env.reflex_vertices) + 1 == run.bound
    assert 1 - run.covered_fraction < 1e-9
    # Lemma 2's termination condition: every window of every view leads into known space
    for k, vp in enumerate(run.views):
        assert all(not unexplored_parts(w, run.views) for w in windows(vp, k))


@settings(max_examples=60)
@given(instances(holes=False))
def test_theorem_1_simple_polygons_covered_with_at_most_r_plus_1_views(case):
    env, start, choice, seed = case
    _check_theorem_1(_explore(env, start, choice, seed), env)


@settings(max_examples=60)
@given(instances(holes=True))
def test_theorem_1_polygons_with_holes_covered_with_at_most_r_plus_1_views(case):
    env, start, choice, seed = case
    _check_theorem_1(_explore(env, start, choice, seed), env)


@settings(max_examples=30)
@given(instances(holes=True))
def test_viewpoints_are_chained_and_the_path_stays_in_the_free_space(case):
    env, start, choice, seed = case
    run = _explore(env, start, choice, seed)
    assert run.viewpoints[0] == start and run.parents[0] == -1
    for k in range(1, run.n_views):  # constraint 2): p_i lies in an earlier view
        assert 0 <= run.parents[k] < k
        assert run.views[run.parents[k]].contains(run.viewpoints[k])
    assert run.path[0] == start
    assert all(sees(env, p, q) for p, q in zip(run.path, run.path[1:]))
    visited = [q for q in run.path if q in run.viewpoints]
    assert sorted(set(visited)) == sorted(set(run.viewpoints))


def test_convex_polygon_needs_one_view():
    square = Environment.from_coords([[0, 0], [3, 0], [3, 3], [0, 3]])
    run = explore_depth_first(square, (1, 1))
    assert run.n_views == 1 and run.moves == 0 and run.path_length == 0 and run.bound == 1


def test_the_l_polygon_from_the_dark_arm():
    run = explore_depth_first(ELL, (3, 1))
    assert run.n_views == 2 and run.viewpoints[1] == (1, 3)   # the simplest point of the window's middle third
    assert run.moves == 1 and run.path_length == pytest.approx(8 ** 0.5)
    assert visibility_polygon(ELL, (3, 1)).area + Fraction(0) < ELL.area


def test_comb_takes_one_view_per_tooth_at_most():
    comb = load_environment("comb")
    for choice in CHOICES:
        run = explore_depth_first(comb, (1, 1), choice=choice, seed=3 if choice == "random" else None)
        assert run.n_views <= run.bound == 9 and 1 - run.covered_fraction < 1e-9


def test_random_rule_is_reproducible_and_seeded():
    env = load_environment("comb")
    a = explore_depth_first(env, (9, 1), choice="random", seed=5)
    b = explore_depth_first(env, (9, 1), choice="random", seed=5)
    assert a.viewpoints == b.viewpoints and a.to_json()["seed"] == 5


def test_answer_json_follows_the_contract():
    out = explore_depth_first(ELL, (3, 1), choice="far").to_json()
    assert {"viewpoints", "views", "reflex", "bound", "path_length", "covered_fraction"} <= set(out)
    assert out["viewpoints"][0] == [3.0, 1.0] and out["views"] == len(out["viewpoints"]) == 2
    assert out["reflex"] == 1 and out["bound"] == 2 and out["status"] == "found"
    assert out["cost"]["total"] == pytest.approx(out["moves"] + out["views"] + out["path_length"])


def test_view_limit_gives_an_incomplete_answer():
    run = explore_depth_first(load_environment("comb"), (1, 1), max_views=2)
    assert run.status is Status.NOT_FOUND and run.n_views == 2
    assert run.optimality.limits == ("max_views=2",) and run.covered_fraction < 1


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"start": (5, 5)}, "start (5, 5) is not in the free space"),
    ({"start": (1, 1), "choice": "near"}, "unknown z-choice rule 'near'"),
    ({"start": (1, 1), "choice": "far", "seed": 2}, "--seed only applies to the random"),
    ({"start": (1, 1), "max_views": 0}, "max_views must be >= 1"),
])
def test_bad_input_is_one_clear_line(kwargs, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        explore_depth_first(ELL, **kwargs)
