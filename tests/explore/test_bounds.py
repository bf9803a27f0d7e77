"""The exploration cost and the paper's bounds (Theorem 1, Lemma 4, Theorem 5)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.explore.bounds import (depth_first_ratio, exploration_cost, range_ratio_bound, range_views_bound,
                                       range_views_lower_bound, views_bound)
from tests.strategies import polygons_with_holes

SQUARE = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])


def test_cost_terms():
    cost = exploration_cost(3, 4, 10.0, t_move=0.5, t_sense=2.0, speed=5.0)
    assert (cost.planning, cost.sensing, cost.driving, cost.total) == (1.5, 8.0, 2.0, 11.5)


def test_theorem_1_bound_counts_convex_corners_of_holes():
    ring = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], [[[4, 4], [4, 6], [6, 6], [6, 4]]])
    assert views_bound(ring) == 5 and depth_first_ratio(ring) == 2.5
    assert views_bound(load_environment("comb")) == 9


def test_lemma_4_and_theorem_5_on_a_square():
    assert range_views_bound(SQUARE, 2.0) == 10 + 8 + 0 + 0 + 1
    assert range_views_lower_bound(SQUARE, 2.0) == math.ceil(16 / (4 * math.pi)) == 2
    assert range_ratio_bound(SQUARE, 2.0) == pytest.approx(8 * math.pi / 3 + 2 * math.pi * 16 / 16 + 4 * math.pi / 16)


@given(polygons_with_holes(), st.floats(0.5, 200))
def test_theorem_5_lemma_4_bound_is_at_least_the_lower_bound(env, R):
    assert range_views_bound(env, R) >= range_views_lower_bound(env, R) >= 1
    # the competitive ratio bound dominates the ratio of the two counts
    assert range_views_bound(env, R) / range_views_lower_bound(env, R) <= range_ratio_bound(env, R) * (1 + 1e-12) + 1


@pytest.mark.parametrize("bad", [0.0, -1.0, float("inf"), float("nan")])
def test_bad_range_is_rejected(bad):
    with pytest.raises(InputError, match="range R must be a finite number > 0"):
        range_views_bound(SQUARE, bad)


def test_bad_cost_parameters_are_rejected():
    with pytest.raises(InputError, match="speed must be finite and > 0"):
        exploration_cost(1, 1, 1.0, speed=0)
    with pytest.raises(InputError, match="planning and sensing times"):
        exploration_cost(1, 1, 1.0, t_sense=-1)
