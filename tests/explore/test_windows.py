"""Windows (constructed edges) of a view and their unexplored parts, exact."""

from __future__ import annotations

from fractions import Fraction

from hypothesis import given
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.explore.window import point_on_part, simplest_between, unexplored_parts, windows
from solverplan.geometry.visibility import visibility_polygon

ELL = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])


def test_the_window_of_the_l_runs_from_the_reflex_vertex():
    vp = visibility_polygon(ELL, (3, 1))
    (w,) = windows(vp, 0)
    assert w.reflex_vertex == 3 and {w.a, w.b} == {(2, 2), (0, 4)}   # the ray from (3, 1) grazes nothing until the corner (0, 4)
    assert unexplored_parts(w, [vp]) == [(0, 1)]


def test_a_second_view_explores_the_window_exactly():
    first = visibility_polygon(ELL, (3, 1))
    (w,) = windows(first, 0)
    assert unexplored_parts(w, [first, visibility_polygon(ELL, (1, 3))]) == []
    # a view from the far arm's corner covers only part of the window's unseen side
    part = unexplored_parts(w, [first, visibility_polygon(ELL, (0, 4))])
    assert part == [] or all(0 <= lo < hi <= 1 for lo, hi in part)


def test_a_collinear_window_on_the_same_side_covers_nothing():
    vp = visibility_polygon(ELL, (3, 1))
    (w,) = windows(vp, 0)
    same_line = visibility_polygon(ELL, (Fraction(7, 2), Fraction(1, 2)))   # on the line through (3, 1), (2, 2)
    assert unexplored_parts(w, [vp, same_line]) == [(0, 1)]


@given(st.fractions(-50, 50, max_denominator=60), st.fractions(Fraction(1, 60), 10, max_denominator=60))
def test_simplest_between_is_inside_and_no_smaller_denominator_is(lo, width):
    hi = lo + width
    x = simplest_between(lo, hi)
    assert lo < x < hi
    q = x.denominator
    for d in range(1, q):   # no rational with a smaller denominator lies strictly inside
        n = (lo * d).__floor__() + 1
        assert not Fraction(n, d) < hi


def test_point_on_part_lies_on_the_window_in_its_middle_third():
    (w,) = windows(visibility_polygon(ELL, (3, 1)), 0)
    p = point_on_part(w, (Fraction(0), Fraction(1)))
    lam = (p[0] - w.a[0]) / (w.b[0] - w.a[0])
    assert Fraction(1, 3) <= lam <= Fraction(2, 3)
    assert (p[1] - w.a[1]) * (w.b[0] - w.a[0]) == (p[0] - w.a[0]) * (w.b[1] - w.a[1])
