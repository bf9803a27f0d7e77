"""Reflection candidates (α ≤ π/2, exact) and zones (corrected Eq. 4 with the tie-break)."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.reflection.cells import decompose_free_space
from solverplan.reflection.compose import compose_fields
from solverplan.reflection.zones import (alpha, is_reflection_candidate, rank_zones, select_zone, zone_cost,
                                         zone_cost_printed)


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


def test_square_tie_is_broken_by_the_smallest_n_in_dot_v_in():
    square = _cell([(0, 0), (1, 0), (1, 1), (0, 1)])  # inlet bottom (0), outlet right (1); walls top (2), left (3)
    assert zone_cost(square, 0, 1, 2) == zone_cost(square, 0, 1, 3) == Fraction(1, 2)
    assert rank_zones(square, 0, 1) == [3, 2]  # the left wall is entered obliquely (n_in·v_in = 1/√2 < 1)
    zone = select_zone(square, 0, 1, (Fraction(3),))
    assert zone is not None and zone.side == 3 and zone.point == (0, Fraction(1, 2))


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
                assert is_reflection_candidate(cell, inlet, outlet) and zone.check.verified


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
