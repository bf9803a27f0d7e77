"""Reflection candidates (α ≤ π/2, exact) and zones (corrected Eq. 4 with the tie-break)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.reflection.cells import decompose_free_space
from solverplan.reflection.compose import compose_fields
from solverplan.reflection.zones import (alpha, is_reflection_candidate, rank_zones, select_zone,
                                         select_zone_recorded, turns_towards_exit, zone_cost, zone_cost_printed)


def _cell(coords):
    return decompose_free_space(Environment.from_coords(coords, name="cell")).cells[0]


def test_isosceles_right_triangle_corrected_eq4_is_zero_printed_is_two():
    """The paper's example (§III-B): legs as inlet and outlet, the hypotenuse's midpoint, cost 0 (printed: 2)."""
    cell = _cell([(0, 0), (2, 0), (0, 2)])
    legs = [i for i, s in enumerate(cell.sides) if s.a[0] == s.b[0] or s.a[1] == s.b[1]]
    hyp = next(i for i in range(3) if i not in legs)
    inlet, outlet = legs
    assert is_reflection_candidate(cell, inlet, outlet) and alpha(cell, inlet, outlet) == pytest.approx(1.5707963)
    assert zone_cost(cell, inlet, outlet, hyp) == 0
    assert zone_cost_printed(cell, inlet, outlet, hyp) == 2


def test_alpha_half_pi_is_a_candidate_exactly_and_straight_cells_are_not():
    square = _cell([(0, 0), (1, 0), (1, 1), (0, 1)])
    assert is_reflection_candidate(square, 0, 1)  # α = π/2 exactly: n_in·n_out = 0
    assert not is_reflection_candidate(square, 0, 2)  # α = π
    kite = _cell([(0, 0), (4, 0), (5, 3), (0, 1)])
    assert all(is_reflection_candidate(kite, i, j) == (alpha(kite, i, j) <= 1.5707963267948966) for i in range(4) for j in range(4) if i != j)


def test_issue26_square_tie_goes_to_the_wall_ahead_not_the_wall_opposite_the_exit():
    square = _cell([(0, 0), (1, 0), (1, 1), (0, 1)])  # inlet bottom (0), outlet right (1); walls top (2), left (3)
    assert zone_cost(square, 0, 1, 2) == zone_cost(square, 0, 1, 3) == Fraction(1, 2)
    assert rank_zones(square, 0, 1) == [2, 3]  # the top wall is the one a robot going up runs into
    # and in a square corner no wall turns the robot towards the exit: no zone, both walls recorded
    zone, rejected = select_zone_recorded(square, 0, 1, (Fraction(3),))
    assert zone is None and [(r.side, r.stage) for r in rejected] == [(2, "turn"), (3, "turn")]


def test_a_45_degree_cut_is_a_zone_that_turns_the_robot_to_the_exit():
    cut = _cell([(0, 0), (2, 0), (2, 1), (1, 2), (0, 2)])  # in at the bottom (0), out on the left (4)
    zone, rejected = select_zone_recorded(cut, 0, 4, (Fraction(3),))
    assert zone is not None and zone.side == 2 and turns_towards_exit(cut, 0, 4, 2)
    assert all(r.stage == "turn" for r in rejected)


@given(st.integers(1, 6), st.integers(1, 6), st.integers(1, 5))
def test_turns_towards_exit_matches_a_mirrored_unit_velocity(w, h, c):
    """A wall passes the turn test iff a robot moving along n_in that hits it leaves with more velocity along the
    exit direction than it had and less along the entry (a float mirror of the velocity, the simulator's bounce)."""
    c = min(c, w - 1, h - 1) if min(w, h) > 1 else 0
    ring = [(0, 0), (w, 0), (w, h - c), (w - c, h), (0, h)] if c else [(0, 0), (w, 0), (w, h), (0, h)]
    cell = _cell(ring)
    outlet = len(cell.sides) - 1  # the left side
    for side in range(1, len(cell.sides) - 1):
        n = cell.sides[side].unit_normal()
        v = np.array([0.0, 1.0])
        if v @ n >= 0:
            assert not turns_towards_exit(cell, 0, outlet, side)  # never met going up
            continue
        bounced = v - 2 * (v @ n) * n
        helps = bounced @ np.array([-1.0, 0.0]) > 1e-12
        assert turns_towards_exit(cell, 0, outlet, side) == helps


@settings(max_examples=40)
@given(st.lists(st.tuples(st.integers(0, 12), st.integers(0, 12)), min_size=5, max_size=12, unique=True))
def test_zone_is_a_wall_minimising_the_corrected_eq4(points):
    from tests.strategies import convex_hull

    hull = convex_hull(points)
    if len(hull) < 4:
        return
    try:
        cell = _cell(hull)
    except Exception:
        return
    m = len(cell.sides)
    for inlet in range(m):
        for outlet in range(m):
            if inlet == outlet:
                continue
            ranked = rank_zones(cell, inlet, outlet)
            costs = [zone_cost(cell, inlet, outlet, i) for i in ranked]
            assert costs == sorted(costs) and all(0 <= c <= 2 for c in costs)
            zone = select_zone(cell, inlet, outlet, (Fraction(1), Fraction(4)))
            if zone is not None:
                assert cell.sides[zone.side].is_wall and zone.side not in (inlet, outlet)
                assert is_reflection_candidate(cell, inlet, outlet) and zone.check.valid


def test_serpentine_reflection_cells_are_the_four_cut_corners():
    """Each corner is the paper's isosceles right triangle: the zone is the 45° wall, at cost 0."""
    plan = compose_fields(load_environment("serpentine"), (3, "2.25"), (3, "0.25"))
    assert plan.reflection_cells == (2, 0, 7, 5)
    for c in plan.reflection_cells:
        zone = plan.zones[c]
        side = plan.cells[c].sides[zone.side]
        assert zone.alpha == pytest.approx(1.5707963267948966) and zone.cost == 0
        assert side.is_wall and abs(side.b[0] - side.a[0]) == abs(side.b[1] - side.a[1])
    assert plan.flow_through and plan.proved
