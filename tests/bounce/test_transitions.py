"""Transitions: float vs exact, the exact affine map vs exact ray casting, and the lifted
transition f(S, Θ) vs sampled and exact rays (sound: every ray lands in a reported piece; tight: points
just inside every reported end point are reached, checked with exact point-to-point visibility)."""

from __future__ import annotations

import math
from math import pi as PI
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from solverplan.interval import Interval
from solverplan.bounce.transitions import (
    AffineMap,
    affine_map,
    exact_direction,
    exact_transition,
    transition,
    transition_set,
)
from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.geometry.raycast import cast_from_boundary, cast_ray
from solverplan.geometry.visibility import sees
from tests.strategies import polygons_with_holes, simple_polygons
from tests.shapes import SQUARE

ROOM_WITH_PILLAR = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], [[[4, 4], [6, 4], [6, 6], [4, 6]]])
L_ROOM = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
FEWER = max(10, settings.default.max_examples // 4)  # the costlier exact properties (scaled by the profile)


def cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


@st.composite
def boundary_rays(draw, envs=polygons_with_holes()):
    """An environment, an edge, an exact t ∈ (0, 1) and an integer direction into the free space."""
    env = draw(envs)
    edge = draw(st.integers(0, env.n_edges - 1))
    t = draw(st.fractions(0, 1, max_denominator=64).filter(lambda f: 0 < f < 1))
    e = env.edge(edge)
    ev = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    d = draw(st.tuples(st.integers(-20, 20), st.integers(-20, 20)).filter(lambda d: cross(ev, d) > 0))
    return env, edge, t, d


# ---------------------------------------------------------------------- f(s, θ): float vs exact
@given(boundary_rays())
@example((SQUARE, 0, Fraction(1, 2), (1, 1)))
def test_float_transition_agrees_with_exact_transition(case):
    env, edge, t, d = case
    hit = exact_transition(env, edge, t, d)
    e = env.edge(edge)
    ev = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    theta = math.atan2(float(cross(ev, d)), float(ev[0] * d[0] + ev[1] * d[1]))
    f_edge, f_t = transition(env, edge, float(t), theta)
    size = max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1])
    point = np.array([float(hit.point[0]), float(hit.point[1])])
    near_vertex = np.min(np.hypot(*(env.vertices - point).T)) < 1e-7 * size
    assume(not near_vertex)  # the float heading is not the exact direction: near a vertex the two may differ
    assert f_edge == hit.edge
    assert f_t == pytest.approx(float(hit.t), abs=1e-9)


def test_transition_is_vectorised_and_matches_scalars():
    edges, ts = transition(SQUARE, [0, 0, 1], [0.25, 0.5, 0.5], [PI / 2, PI / 4, PI / 2])
    assert edges.tolist() == [2, 1, 3]
    np.testing.assert_allclose(ts, [0.75, 0.5, 0.5], atol=1e-12)
    assert transition(SQUARE, 1, 0.5, PI / 2) == (3, pytest.approx(0.5))


# ---------------------------------------------------------------------- the exact affine map
@given(boundary_rays())
@example((SQUARE, 0, Fraction(1, 3), (1, 1)))
@example((ROOM_WITH_PILLAR, 0, Fraction(1, 2), (1, 3)))
def test_dsgn6_fixed_heading_transition_is_affine_with_rational_coefficients(case):
    env, edge, t, d = case
    hit = exact_transition(env, edge, t, d)
    assume(hit.vertex is None)
    m = affine_map(env, edge, d, hit.edge)
    assert isinstance(m.alpha, Fraction) and isinstance(m.beta, Fraction)
    assert m(t) == hit.t  # exact equality
    lo, hi = m.domain()
    assert lo <= t <= hi
    # the same map at another exact parameter whose ray also lands on that edge agrees with the caster too
    other = (t + Fraction(1, 997)) if t < Fraction(1, 2) else (t - Fraction(1, 997))
    hit2 = exact_transition(env, edge, other, d)
    if hit2.edge == hit.edge and hit2.vertex is None:
        assert m(other) == hit2.t


def test_thm1_square_return_map_is_exact_and_its_fixed_point_is_one_third():
    """Fixed heading atan(1/2) in a square: d' = (ℓ − d) tan θ per bounce, fixed point tan θ/(1 + tan θ) = 1/3."""
    directions = [(2, 1), (-1, 2), (-2, -1), (1, -2)]  # heading atan(1/2) from edges 0, 1, 2, 3
    cycle = affine_map(SQUARE, 0, directions[0], 1)
    for k in (1, 2, 3):
        cycle = cycle.then(affine_map(SQUARE, k, directions[k], (k + 1) % 4))
    assert (cycle.source, cycle.target) == (0, 0)
    assert cycle.contraction == Fraction(1, 16)
    assert cycle.fixed_point() == Fraction(1, 3)
    one = affine_map(SQUARE, 0, directions[0], 1)
    assert (one.alpha, one.beta) == (Fraction(-1, 2), Fraction(1, 2))  # t' = (1 − t)/2


def test_affine_map_errors_are_one_line():
    with pytest.raises(InputError, match=r"^direction \(-1, 0\) is parallel to edge e2$"):
        affine_map(SQUARE, 1, (-1, 0), 2)
    with pytest.raises(InputError, match=r"^direction \(0, 1\) is parallel to edge e1$"):
        affine_map(SQUARE, 0, (0, 1), 1)
    with pytest.raises(InputError, match=r"^direction \(1, 1\) meets edge e3 from its obstacle side$"):
        affine_map(SQUARE, 0, (1, 1), 3)
    with pytest.raises(InputError, match=r"^cannot compose e0→e1 with e2→e3$"):
        AffineMap(0, 1, Fraction(1), Fraction(0)).then(AffineMap(2, 3, Fraction(1), Fraction(0)))
    with pytest.raises(InputError, match=r"^a map from e0 to e1 has no fixed point: it changes edges$"):
        AffineMap(0, 1, Fraction(1), Fraction(0)).fixed_point()


# ---------------------------------------------------------------------- f(S, Θ) by hand
def strs(pieces):
    return [str(p) for p in pieces]


def test_lifted_transition_fast_path_is_spanned_by_the_four_corners():
    # x ∈ [1, 2] on the floor, directions (±1, 4): the ceiling between x = 0 and x = 3, i.e. t ∈ [1/4, 1]
    assert strs(transition_set(SQUARE, (0, Fraction(1, 4), Fraction(1, 2)), ((1, 4), (-1, 4)))) == ["e2:0.25:1"]


def test_lifted_transition_splits_at_the_corner_of_the_room():
    # directions (±1, 2) reach past the ceiling's end: the left wall below y = 4 is hit from x = 1..2 at slope 2
    assert strs(transition_set(SQUARE, (0, Fraction(1, 4), Fraction(1, 2)), ((1, 2), (-1, 2)))) == ["e2", "e3:0:0.5"]


def test_lifted_transition_shadow_of_a_pillar_is_exact():
    # straight up from x ∈ [2, 8]: the pillar [4, 6]² hides the ceiling over x ∈ (4, 6) and is hit from below
    pieces = transition_set(ROOM_WITH_PILLAR, (0, Fraction(1, 5), Fraction(4, 5)), ((0, 1), (0, 1)))
    bottom = next(e.id for e in ROOM_WITH_PILLAR.edges if e.ring == 1 and e.a[1] == e.b[1] == 4)
    assert pieces == sorted(
        [BoundaryPiece(2, Fraction(1, 5), Fraction(2, 5)), BoundaryPiece(2, Fraction(3, 5), Fraction(4, 5)),
         BoundaryPiece(bottom, Fraction(0), Fraction(1))],
        key=lambda p: (p.edge, p.t0),
    )


def test_lifted_transition_penumbra_of_a_pillar():
    # x ∈ [2, 8], directions from (1, 10) to (−1, 10). The outermost rays reach the ceiling (y = 10) at
    # x = 1 (from 2 along (−1, 10)) and x = 9 (from 8 along (1, 10)). Over the pillar the ceiling is lit up
    # to where the rays along the cone's ends graze the pillar's top corners: along (1, 10) through (4, 6)
    # it reaches x = 4.4, along (−1, 10) through (6, 6) x = 5.6. The ceiling runs from x = 10 (t = 0) to 0.
    pieces = transition_set(ROOM_WITH_PILLAR, (0, Fraction(1, 5), Fraction(4, 5)), ((1, 10), (-1, 10)))
    ceiling = [p for p in pieces if p.edge == 2]
    assert [(p.t0, p.t1) for p in ceiling] == [(Fraction(1, 10), Fraction(11, 25)), (Fraction(14, 25), Fraction(9, 10))]


def test_lifted_transition_grazing_the_reflex_corner_of_an_l():
    # from x ∈ [0, 2] up-right at 45°: x = 0 runs into the reflex corner (4, 4); the rest land on e2
    assert strs(transition_set(L_ROOM, (0, 0, Fraction(1, 4)), ((1, 1), (1, 1)))) == ["e2:0.5:1"]
    # a wide cone from the whole floor's left half sees past the corner into the upper arm
    assert strs(transition_set(L_ROOM, (0, 0, Fraction(1, 2)), ((1, 1), (-1, 1)))) == ["e2", "e3", "e4", "e5"]


def test_lifted_transition_from_one_point_with_a_cone():
    # from (2, 0) between 45° and 135°: the right wall above y = 2, the whole ceiling, the left wall above y = 2
    exact = transition_set(SQUARE, (0, Fraction(1, 2), Fraction(1, 2)), ((1, 1), (-1, 1)))
    assert strs(exact) == ["e1:0.5:1", "e2", "e3:0:0.5"]
    # float headings are made exact within ~1e-16 rad: the same pieces, their ends within 1e-15
    approx = transition_set(SQUARE, (0, Fraction(1, 2), Fraction(1, 2)), Interval(PI / 4, 3 * PI / 4))
    assert [p.edge for p in approx] == [1, 2, 3]
    for a, b in zip(approx, exact):
        assert abs(a.t0 - b.t0) < 1e-15 and abs(a.t1 - b.t1) < 1e-15


# ---------------------------------------------------------------------- f(S, Θ): sound and tight
def window(env, edge, t0, t1, d_lo, d_hi, q):
    """Exact origins t ∈ [t0, t1] on ``edge`` whose ray towards q lies in the cone [d_lo, d_hi] (or None)."""
    e = env.edge(edge)
    ev = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    lo, hi = Fraction(t0), Fraction(t1)
    for d, sign in ((d_lo, 1), (d_hi, -1)):
        # sign·cross(d, q − a − t·ev) ≥ 0, linear in t
        c0 = sign * cross(d, (q[0] - e.a[0], q[1] - e.a[1]))
        c1 = -sign * cross(d, ev)
        if c1 == 0:
            if c0 < 0:
                return None
        elif c1 > 0:
            lo = max(lo, -c0 / c1)
        else:
            hi = min(hi, -c0 / c1)
    return (lo, hi) if lo <= hi else None


def attained(env, edge, t0, t1, d_lo, d_hi, q) -> bool:
    """Is boundary point q seen strictly, inside the cone, from some origin of the piece? (exact)"""
    w = window(env, edge, t0, t1, d_lo, d_hi, q)
    if w is None:
        return False
    e = env.edge(edge)
    ev = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    lo, hi = w
    cuts = {lo, hi}
    for v in env.exact_vertices:  # where the line q v meets the source line: visibility can change there
        den = cross((v[0] - q[0], v[1] - q[1]), ev)
        if den != 0:
            s = cross((e.a[0] - q[0], e.a[1] - q[1]), ev) / den
            point = (q[0] + s * (v[0] - q[0]), q[1] + s * (v[1] - q[1]))
            tt = ((point[0] - e.a[0]) * ev[0] + (point[1] - e.a[1]) * ev[1]) / (ev[0] ** 2 + ev[1] ** 2)
            if lo < tt < hi:
                cuts.add(tt)
    cuts = sorted(cuts)
    probes = cuts if len(cuts) == 1 else [(a + b) / 2 for a, b in zip(cuts, cuts[1:])]
    return any(sees(env, env.exact_point_at(edge, tt), q, strict=True) for tt in probes)


@st.composite
def lifted_cases(draw):
    env = draw(st.one_of(polygons_with_holes(max_vertices=10, max_holes=2), simple_polygons(max_vertices=10)))
    edge = draw(st.integers(0, env.n_edges - 1))
    t0, t1 = sorted(draw(st.lists(st.fractions(0, 1, max_denominator=12), min_size=2, max_size=2, unique=True)))
    e = env.edge(edge)
    ev = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    into = st.tuples(st.integers(-12, 12), st.integers(-12, 12)).filter(lambda d: cross(ev, d) > 0)
    d1, d2 = draw(into), draw(into)
    d_lo, d_hi = (d1, d2) if cross(d1, d2) >= 0 else (d2, d1)
    return env, edge, t0, t1, d_lo, d_hi


@settings(max_examples=FEWER)
@given(lifted_cases())
@example((ROOM_WITH_PILLAR, 0, Fraction(1, 5), Fraction(4, 5), (1, 10), (-1, 10)))
@example((L_ROOM, 0, Fraction(0), Fraction(1, 2), (1, 1), (-1, 1)))
def test_lifted_transition_is_sound_and_tight(case):
    env, edge, t0, t1, d_lo, d_hi = case
    pieces = transition_set(env, (edge, t0, t1), (d_lo, d_hi))
    assert pieces == sorted(pieces, key=lambda p: (p.edge, p.t0))
    assert all(p.t0 < p.t1 for p in pieces)
    # sound, floats: sampled rays that the caster is sure of land inside the reported pieces
    rng = np.random.default_rng(0)
    m = 1500
    e = env.edge(edge)
    ev = np.array([float(e.b[0] - e.a[0]), float(e.b[1] - e.a[1])])
    ang = lambda d: math.atan2(ev[0] * d[1] - ev[1] * d[0], ev[0] * d[0] + ev[1] * d[1])  # noqa: E731
    lo, hi = ang(d_lo), ang(d_hi)
    ts = rng.uniform(float(t0), float(t1), m)
    hs = rng.uniform(lo, hi, m)
    ts[:4], hs[:4] = [float(t0), float(t0), float(t1), float(t1)], [lo, hi, lo, hi]
    ok = (ts > 0) & (ts < 1)  # rays leave vertices only as limits
    hits = cast_from_boundary(env, np.full(m, edge), ts, hs)
    sure = ok & ~hits.uncertain
    for j, tj in zip(hits.edge[sure].tolist(), hits.t[sure].tolist()):
        assert any(p.edge == j and float(p.t0) - 1e-9 <= tj <= float(p.t1) + 1e-9 for p in pieces), (j, tj, strs(pieces))
    # sound, exact: a few exact rays of the family (rational origin, rational direction in the cone)
    for k in range(6):
        tt = t0 + (t1 - t0) * Fraction(k + 1, 8)
        lam = Fraction(k, 5)
        d = ((1 - lam) * d_lo[0] + lam * d_hi[0], (1 - lam) * d_lo[1] + lam * d_hi[1])
        if not 0 < tt < 1:
            continue
        hit = cast_ray(env, env.exact_point_at(edge, tt), d)
        if hit.vertex is None:
            assert any(p.edge == hit.edge and p.t0 <= hit.t <= p.t1 for p in pieces), (hit, strs(pieces))
    # tight: just inside each end point the boundary is reached (exact point-to-point visibility)
    for p in pieces:
        delta = (p.t1 - p.t0) / 1000
        for inner in (p.t0 + delta, p.t1 - delta):
            q = env.exact_point_at(p.edge, inner)
            assert attained(env, edge, t0, t1, d_lo, d_hi, q), (str(p), inner)


@settings(max_examples=FEWER)
@given(lifted_cases())
def test_lifted_transition_misses_what_no_ray_reaches(case):
    """Between and beside the reported pieces, exact visibility finds no ray of the family."""
    env, edge, t0, t1, d_lo, d_hi = case
    pieces = transition_set(env, (edge, t0, t1), (d_lo, d_hi))
    for j in range(env.n_edges):
        if j == edge:
            continue
        own = sorted((p.t0, p.t1) for p in pieces if p.edge == j)
        gaps, cur = [], Fraction(0)
        for a, b in own:
            if a > cur:
                gaps.append((cur, a))
            cur = max(cur, b)
        if cur < 1:
            gaps.append((cur, Fraction(1)))
        for a, b in gaps:
            q = env.exact_point_at(j, (a + b) / 2)
            assert not attained(env, edge, t0, t1, d_lo, d_hi, q), (j, (a + b) / 2, strs(pieces))


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "call,error,message",
    [
        (lambda: transition(SQUARE, 0, 0.5, 3.5), InvalidBoundarySet, r"^heading 3.5 is not inside \(0, π\)$"),
        (lambda: transition(SQUARE, 9, 0.5, 1.0), InvalidBoundarySet, r"^unknown edge e9: edges are e0..e3$"),
        (lambda: transition(SQUARE, 0, 1.5, 1.0), InvalidBoundarySet, r"^boundary parameter t = 1.5 is not in \[0, 1\]$"),
        (lambda: exact_transition(SQUARE, 0, Fraction(1, 2), (1, -1)), InvalidBoundarySet,
         r"^direction \(1, -1\) does not point into the free space from edge e0: its heading is not inside \(0, π\)$"),
        (lambda: exact_transition(SQUARE, 0, "3/2", (0, 1)), InvalidBoundarySet, r"^boundary parameter t = 1.5 is not in \[0, 1\]$"),
        (lambda: exact_direction(SQUARE, 0, 0.0), InvalidBoundarySet, r"^heading 0 is not inside \(0, π\)$"),
        (lambda: transition_set(SQUARE, (0, 0, 1), Interval(0.5, 3.5)), InvalidBoundarySet,
         r"^heading interval \[0.5, 3.5\] is not inside \(0, π\): hi=3.5$"),
        (lambda: transition_set(SQUARE, (0, 0, 1), ((-1, 1), (1, 1))), InvalidBoundarySet,
         r"^direction cone \(-1, 1\) .. \(1, 1\) is reversed: d_lo must be clockwise of d_hi$"),
        (lambda: transition_set(SQUARE, (0, Fraction(3, 4), Fraction(1, 4)), Interval(1, 2)), InvalidBoundarySet,
         r"^source piece e0:0.75:0.25 is reversed: t0 > t1$"),
        (lambda: transition_set(SQUARE, (0, Fraction(1, 2), Fraction(1, 2)), Interval(1, 1)), InvalidBoundarySet,
         r"^a single point with a single heading is one ray, not a set: use exact_transition for e0:0.5$"),
        (lambda: transition_set(SQUARE, (5, 0, 1), Interval(1, 2)), InvalidBoundarySet, r"^unknown edge e5: edges are e0..e3$"),
    ],
)
def test_bad_input_is_one_line(call, error, message):
    with pytest.raises(error, match=message):
        call()
