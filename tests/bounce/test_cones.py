"""Exact cones of float heading intervals (solverplan/bounce/cones.py): inside lies inside, outside contains,
the directions are exact with the headings claimed, and their numbers are small. Headings are compared with
the certificate checker's rigorous arithmetic, which shares no code with the module under test."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.bounce import cones, heading_cone as exported
from solverplan.bounce.cones import heading_cone, heading_direction
from solverplan.certify.rational_atan import compare_angle, heading_vector
from solverplan.errors import InputError
from solverplan.interval import Interval

EDGES = [(Fraction(1), Fraction(0)), (Fraction(-3), Fraction(7, 2)), (Fraction(0), Fraction(-10)), (Fraction(5, 3), Fraction(5, 7))]


def within(edge, d, lo: Fraction, hi: Fraction) -> bool:
    """Is the exact heading of d from edge in [lo, hi]?"""
    w = heading_vector(edge, d)
    return compare_angle(w, lo) >= 0 and compare_angle(w, hi) <= 0


intervals = st.tuples(st.floats(1e-4, math.pi - 1e-4), st.floats(0, 1.0)).map(
    lambda p: (p[0], min(p[0] + p[1], math.pi - 1e-4)))
margins = st.sampled_from([1e-13, 1e-10, 1e-6, 1e-2])


@given(intervals, margins, st.sampled_from(EDGES))
def test_inside_cone_lies_inside_the_float_interval_within_the_margin(bounds, margin, edge):
    lo, hi = bounds
    d_lo, d_hi = heading_cone(edge, Interval(lo, hi), margin=margin)
    m = Fraction(min(margin, (hi - lo) / 4))
    flo, fhi = Fraction(lo), Fraction(hi)
    if m > Fraction(1, 10**14):  # the guarantee is exact once the window exceeds float rounding
        assert within(edge, d_lo, flo, flo + m) and within(edge, d_hi, fhi - m, fhi)
    else:  # a (near-)singleton interval: its ends, to float rounding
        tiny = Fraction(1, 10**14)
        assert within(edge, d_lo, flo - tiny, flo + m + tiny) and within(edge, d_hi, fhi - m - tiny, fhi + tiny)


@given(intervals, margins, st.sampled_from(EDGES))
def test_outside_cone_contains_the_float_interval_within_the_margin(bounds, margin, edge):
    lo, hi = bounds
    d_lo, d_hi = heading_cone(edge, Interval(lo, hi), margin=margin, outside=True)
    m = Fraction(min(margin, lo / 2, (math.pi - hi) / 2))
    flo, fhi = Fraction(lo), Fraction(hi)
    assert within(edge, d_lo, flo - m, flo) and within(edge, d_hi, fhi, fhi + m)
    # strictly outside: every float heading of the interval is in the exact cone
    assert compare_angle(heading_vector(edge, d_lo), flo) == -1 and compare_angle(heading_vector(edge, d_hi), fhi) == 1


@pytest.mark.parametrize("edge", EDGES)
def test_directions_are_primitive_integer_vectors_with_a_rational_cotangent(edge):
    for d in heading_cone(edge, Interval(0.3, 2.9), margin=1e-9):
        assert all(x.denominator == 1 for x in d) and math.gcd(int(d[0]), int(d[1])) == 1
        w = heading_vector(edge, d)  # (dot(E, d), cross(E, d)) = |E|²·(u, 1) up to scale: the heading is acot(u)
        assert w[1] > 0
        u = w[0] / w[1]
        assert abs(float(u) - 1 / math.tan(math.atan2(float(w[1]), float(w[0])))) < 1e-9
    # the same heading from a longer edge along the same line is the same world direction
    longer = (edge[0] * 7, edge[1] * 7)
    assert heading_cone(longer, Interval(0.3, 2.9), margin=1e-9) == heading_cone(edge, Interval(0.3, 2.9), margin=1e-9)


def test_numbers_are_small():
    """The simplest cotangent in a window of width w has denominator at most about 1/w."""
    x_axis = (Fraction(1), Fraction(0))
    for theta in (0.1, 0.7, 1.2, 2.0, 3.0):
        for margin in (1e-13, 1e-9, 1e-4):
            d = heading_direction(x_axis, theta, theta + margin)  # d = (u, 1) scaled: u = d[0] / d[1]
            window = 1 / math.tan(theta) - 1 / math.tan(theta + margin)
            assert 0 < d[1] <= 1 / window + 1, (theta, margin, d)
    assert heading_direction(x_axis, 1.5, 1.6) == (0, 1)  # straight up: u = 0
    assert heading_direction(x_axis, 0.78, 0.79) == (1, 1)  # π/4: u = 1
    assert heading_cone(x_axis, Interval(0.5, 1.0), margin=0.01) == ((9, 5), (9, 14))


@given(st.fractions(-20, 20, max_denominator=50), st.fractions(0, 3, max_denominator=50))
def test_simplest_between_has_the_smallest_denominator(a, width):
    b = a + width
    u = cones._simplest_between(a, b)
    assert a <= u <= b
    for q in range(1, u.denominator):  # no fraction with a smaller denominator in [a, b]
        assert math.ceil(a * q) > math.floor(b * q), (a, b, q)


def test_bad_intervals_are_refused():
    x_axis = (Fraction(1), Fraction(0))
    with pytest.raises(InputError, match=r"not inside \(0, π\)"):
        heading_cone(x_axis, Interval(0.0, 1.0))
    with pytest.raises(InputError, match=r"not inside \(0, π\)"):
        heading_cone(x_axis, Interval(1.0, 3.5))
    with pytest.raises(InputError, match="margin"):
        heading_cone(x_axis, Interval(1.0, 2.0), margin=-1e-9)
    with pytest.raises(InputError, match="window"):
        heading_direction(x_axis, 2.0, 1.0)


def test_one_function_for_every_layer():
    from solverplan.plan import _results

    assert _results.heading_cone is heading_cone is exported
