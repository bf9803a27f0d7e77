"""Interval: a real type with an empty state (an empty intersection never passes for a reversed, non-empty one)."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.interval import Interval, heading_interval
from solverplan.errors import InvalidBoundarySet

ends = st.floats(0.0, math.pi, allow_nan=False)


@st.composite
def intervals(draw):
    lo, hi = sorted((draw(ends), draw(ends)))
    return draw(st.sampled_from([Interval(lo, hi), Interval.EMPTY]))


def test_empty_intersection_is_empty_not_reversed():
    meet = Interval(1.0, 1.2) & Interval(1.5, 2.0)
    assert meet is Interval.EMPTY and meet.is_empty and meet.width == 0.0
    assert 1.3 not in meet and meet.to_json() is None


def test_reversed_interval_cannot_be_built():
    with pytest.raises(ValueError, match=r"^reversed interval \[2.0, 1.0\]: lo > hi"):
        Interval(2.0, 1.0)


def test_singleton_is_not_empty():
    point = Interval(math.pi / 2, math.pi / 2)
    assert not point.is_empty and point.width == 0.0 and math.pi / 2 in point


@given(intervals(), intervals(), st.floats(0.0, math.pi))
def test_intersection_is_the_set_intersection(a, b, x):
    assert (x in (a & b)) == (x in a and x in b)
    assert (a & b).width <= min(a.width, b.width)
    assert a.contains(a & b) and b.contains(a & b)


@given(intervals(), intervals())
def test_hull_contains_both(a, b):
    h = a.hull(b)
    assert h.contains(a) and h.contains(b)


@pytest.mark.parametrize(
    ("lo", "hi", "message"),
    [
        (0.0, 1.2, r"^heading interval \[0, 1.2\] is not inside \(0, π\): lo=0$"),
        (1.0, 3.2, r"^heading interval \[1, 3.2\] is not inside \(0, π\): hi=3.2$"),
        (1.2, 1.0, r"^heading interval \[1.2, 1\] is reversed: lo > hi$"),
        (math.nan, 1.0, r"^heading interval \[nan, 1\] is not finite$"),
    ],
)
def test_heading_interval_outside_zero_pi_is_rejected(lo, hi, message):
    with pytest.raises(InvalidBoundarySet, match=message):
        heading_interval(lo, hi)
