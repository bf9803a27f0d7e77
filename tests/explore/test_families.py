"""Algorithm A on the paper's lower-bound families: the spiral (Fig. 9) and the one-hole polygon (Fig. 10).

The paper states that both families need r + 1 views from p₁, which with Theorem 1 (at most r + 1) means
Algorithm A uses exactly r + 1 there. The spiral meets it: its corridor ends in a dead end, and each of the k
windings needs its own view after p₁'s.

The ring corridor read from Fig. 10 does not, and no construction of this shape can: the claim is false for it,
by the exact argument of :func:`test_one_hole_r_views_suffice_for_any_exploration` (P is the union of m convex
trapezoids, and a chain of m viewpoints on the outer corners sees them all; m = r). Algorithm A finds such a
chain by itself: it goes round the hole in one direction, and the window that p₁'s view opens in the other
direction is covered by the last view of the round, so that hole vertex never needs a view of its own — the ring
closes on itself where the spiral has a dead end. The measured count (r) is asserted; the chained-cover MILP over
the vertices and A's viewpoints also finds r, for k = 1..6.
"""

from __future__ import annotations

import doctest
import math
from fractions import Fraction

import pytest

from solverplan.explore import CHOICES, explore_depth_first, unexplored_parts, windows
from solverplan.exact import point_in_ring
from solverplan.geometry.visibility import visibility_polygon
from solverplan.result import Status
from tests.explore import families
from tests.explore.families import one_hole, spiral

SIZES = range(1, 7)


def _explore(env, start, choice):
    return explore_depth_first(env, start, choice=choice, seed=1 if choice == "random" else None)


def _check_covered(run):
    assert run.status is Status.FOUND
    assert 1 - run.covered_fraction < 1e-9
    # Algorithm A's stopping rule: no window of any view still leads out of the explored region
    for i, vp in enumerate(run.views):
        assert all(not unexplored_parts(w, run.views) for w in windows(vp, i))


@pytest.mark.parametrize("choice", CHOICES)
@pytest.mark.parametrize("k", SIZES)
def test_spiral_takes_exactly_r_plus_1_views_and_covers_it(k, choice):
    env, start = spiral(k)
    assert not env.holes and len(env.reflex_vertices) == k
    run = _explore(env, start, choice)
    _check_covered(run)
    assert run.n_views == k + 1 == run.bound
    # one view per winding: each viewpoint lies on a window of the one before (no backtracking needed)
    assert run.parents == (-1, *range(k))


@pytest.mark.parametrize("k", SIZES)
def test_one_hole_is_covered_with_r_views(k):
    env, start = one_hole(k)
    assert len(env.holes) == 1 and len(env.reflex_vertices) == k + 2
    assert all(v >= len(env.outer) for v in env.reflex_vertices)  # every reflex vertex is on the hole
    for choice in CHOICES:
        run = _explore(env, start, choice)
        _check_covered(run)
        assert run.n_views == k + 2  # measured: r, one below the bound


@pytest.mark.parametrize("k", SIZES)
def test_one_hole_r_views_suffice_for_any_exploration(k):
    """Exact refutation of "r + 1 views are necessary" for the ring corridor.

    The hole H has vertices h_0 … h_{m−1} (m = k + 2, all reflex, r = m) and the outer ring is o_i = (5/4)·h_i, so
    the free space is the union of the m trapezoids T_i = h_i h_{i+1} o_{i+1} o_i (indices mod m; the rays from
    the centre through the h_i cut the annulus into them). Each T_i is convex and lies in P, so every point of
    T_i sees all of T_i. The chain p₁, o_1, o_2, …, o_{m−1} is admissible (p₁ ∈ T_0 sees T_0 ∋ o_1, and
    o_{i+1} ∈ T_i ⊂ VP(o_i)) and covers P (o_i sees T_{i−1} ∪ T_i): m = r views. Checked exactly below: the
    corners of each trapezoid lie in the exact visibility polygon of its viewpoint, and the trapezoids' exact
    areas add up to the area of P.
    """
    env, start = one_hole(k)
    m = len(env.holes[0])
    outer, hole = list(env.outer), list(env.holes[0])
    # rings are normalised (outer CCW, hole CW): pair each hole vertex with its outer copy exactly
    copy = {h: next(o for o in outer if o == (Fraction(5, 4) * h[0], Fraction(5, 4) * h[1])) for h in hole}
    ccw = sorted(hole, key=lambda h: math.atan2(float(h[1]), float(h[0])))
    trapezoids = [(ccw[i], ccw[(i + 1) % m], copy[ccw[(i + 1) % m]], copy[ccw[i]]) for i in range(m)]
    first = next(i for i, t in enumerate(trapezoids) if point_in_ring(start, t) > 0)  # T_0 holds p₁
    ccw = ccw[first:] + ccw[:first]
    trapezoids = trapezoids[first:] + trapezoids[:first]
    area = sum((_area(t) for t in trapezoids), Fraction(0))
    assert area == env.area and len(env.reflex_vertices) == m
    chain = [start] + [copy[ccw[i]] for i in range(1, m)]
    seen = [{0}] + [{i - 1, i} for i in range(1, m)]
    for j, (p, covers) in enumerate(zip(chain, seen)):
        vp = visibility_polygon(env, p)
        assert all(vp.contains(c) for i in covers for c in trapezoids[i])  # convex: the corners suffice
        if j:
            assert visibility_polygon(env, chain[j - 1]).contains(p)  # the chain constraint
    assert set().union(*seen) == set(range(m)) and len(chain) == m == len(env.reflex_vertices)


def _area(quad) -> Fraction:
    return abs(sum((quad[i][0] * quad[(i + 1) % 4][1] - quad[(i + 1) % 4][0] * quad[i][1] for i in range(4)),
                   Fraction(0))) / 2


@pytest.mark.parametrize("family", [spiral, one_hole])
@pytest.mark.parametrize("k", [0, -1, 1.5, True])
def test_family_size_must_be_a_positive_integer(family, k):
    with pytest.raises(ValueError, match="positive integer"):
        family(k)


def test_families_doctests():
    import solverplan.explore.families as library_families

    result = doctest.testmod(library_families)
    assert result.attempted > 0 and result.failed == 0
