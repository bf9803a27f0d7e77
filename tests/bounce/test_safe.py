"""Safe actions (paper §5): Prop. 2, Lemma 1, Cor. 1, Def. 8, and the exact safe set of any pair.

The references here are independent of the library's sweeps: the closed forms of Prop. 2 / Cor. 1
written out with Python floats, the exact predicate :func:`~solverplan.geometry.visibility.is_entirely_visible`,
and rays cast from sampled points (:func:`~solverplan.geometry.raycast.cast_from_boundary`).
"""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import solverplan.proofs.safe_set_structure as structure
from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.interval import Interval
from solverplan.bounce.partitions import partition
from solverplan.bounce.safe import (
    SafeSet,
    heading_is_safe,
    safe_action,
    safe_interval,
    safe_set,
    transition_angle,
    transition_side,
)
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.geometry.raycast import cast_from_boundary, cast_ray
from solverplan.geometry.visibility import is_entirely_visible
from solverplan.generators import star_polygon_with_holes
from tests.strategies import convex_polygons, polygons_with_holes, simple_polygons

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
SQUARE = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]], name="square")
# a wide room with a small hole right above the middle of the floor piece (−1, 0)–(1, 0)
HOLE_ROOM = Environment.from_coords(
    [[-12, 0], [12, 0], [12, 8], [-12, 8]], [[[-0.5, 2], [0.5, 2], [0.5, 3], [-0.5, 3]]], name="room with a hole"
)


def examples(k: int) -> int:
    """k examples in the default profile, 10 k in the thorough one."""
    return max(k, settings.default.max_examples * k // 100)


def ang(a, b, w) -> float:
    """CCW angle of vector w from direction b − a (floats), in (−π, π]."""
    ex, ey = float(b[0] - a[0]), float(b[1] - a[1])
    wx, wy = float(w[0]), float(w[1])
    return math.atan2(ex * wy - ey * wx, ex * wx + ey * wy)


def sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def edges_of(env: Environment):
    return [(e.a, e.b) for e in env.edges]


def same_sets(got: SafeSet, want: SafeSet) -> bool:
    """Equal up to float rounding of the ends (the sweeps compute headings from float coordinates,
    the reference from exact ones: the same exact ends may differ in the last bit)."""
    return len(got) == len(want) and all(
        abs(x.lo - y.lo) <= 1e-12 and abs(x.hi - y.hi) <= 1e-12 for x, y in zip(got.intervals, want.intervals)
    )


def same_interval(got: Interval, want: Interval) -> bool:
    if got.is_empty or want.is_empty:
        return got.is_empty and want.is_empty
    return abs(got.lo - want.lo) <= 1e-12 and abs(got.hi - want.hi) <= 1e-12


# ---------------------------------------------------------------------------------------------
# Prop. 2 and Cor. 1 in closed form
# ---------------------------------------------------------------------------------------------
def test_prop2_case1_interval_between_floor_and_ceiling():
    src, dst = ((0, 0), (2, 0)), ((4, 2), (0, 2))
    got = safe_interval(src, dst)
    assert got == Interval(ang((0, 0), (2, 0), (2, 2)), ang((0, 0), (2, 0), (0, 2)))
    action = safe_action(src, dst)
    assert action.lo_direction == (2, 2) and action.hi_direction == (0, 2)  # c − b and d − a, exact


def test_prop2_case2_lines_meet_above_is_empty():
    assert safe_interval(((0, 0), (2, 0)), ((1, 2), (0, 2))) is Interval.EMPTY


def test_prop2_case3_parallel_corner_rays_give_a_singleton():
    # c − b = (1, 2) ∥ d − a = (1, 2): exactly one heading, and its two float ends are the same number
    got = safe_interval(((0, 0), (2, 0)), ((3, 2), (1, 2)))
    assert got.lo == got.hi == math.atan2(2, 1)
    # a near-parallel pair a hair wider is a (tiny) interval, a hair narrower is empty: decided exactly
    eps = Fraction(1, 10**30)
    assert not safe_interval(((0, 0), (2, 0)), ((3 + eps, 2), (1, 2))).is_empty
    assert safe_interval(((0, 0), (2, 0)), ((3 - eps, 2), (1, 2))).is_empty


@given(env=convex_polygons())
@settings(max_examples=examples(40))
@example(env=SQUARE)
def test_prop2_closed_form_on_convex_polygons(env):
    """In a convex polygon every two edges are entirely visible: the safe set is Prop. 2's interval."""
    edges = edges_of(env)
    n = len(edges)
    for i in range(n):
        a, b = edges[i]
        for j in range(n):
            if i == j:
                continue
            c, d = edges[j]
            got = safe_set(env, edges[i], edges[j])
            assert len(got) <= 1
            assert got.interval == safe_interval(edges[i], edges[j])
            if j == (i + 1) % n:  # Cor. 1: (0, ang(d − a)]
                assert got.interval == Interval(0.0, ang(a, b, sub(d, a)))
            elif j == (i - 1) % n:  # Cor. 1: [ang(c − b), π)
                assert got.interval == Interval(ang(a, b, sub(c, b)), math.pi)
            else:
                lo, hi = ang(a, b, sub(c, b)), ang(a, b, sub(d, a))
                cross = (c[0] - b[0]) * (d[1] - a[1]) - (c[1] - b[1]) * (d[0] - a[0])
                if cross > 0:
                    assert got.interval.lo == pytest.approx(lo, abs=1e-12) and got.interval.hi == pytest.approx(hi, abs=1e-12)
                elif cross == 0:
                    assert got.interval.lo == got.interval.hi == pytest.approx(lo, abs=1e-12)
                else:
                    assert got.is_empty


def test_cor1_adjacent_segments_have_safe_intervals_both_ways():
    """Cor. 1: a plain square has safe arcs between all adjacent sides, in both directions."""
    edges = edges_of(SQUARE)
    for i in range(4):
        nxt, prv = edges[(i + 1) % 4], edges[(i - 1) % 4]
        assert safe_set(SQUARE, edges[i], nxt).interval == Interval(0.0, math.pi / 4)
        assert safe_set(SQUARE, edges[i], prv).interval == Interval(3 * math.pi / 4, math.pi)
    g = safe_bounce_visibility_graph(SQUARE)
    assert g.n_segments == 4 and g.n_arcs == g.n_safe_arcs == 12
    for i in range(4):
        assert g.interval(i, (i + 1) % 4) == Interval(0.0, math.pi / 4)
        assert g.interval(i, (i - 1) % 4) == Interval(3 * math.pi / 4, math.pi)
        assert g.interval(i, (i + 2) % 4) == Interval(math.pi / 2, math.pi / 2)  # opposite sides: case 3


def test_cor1_needs_a_convex_corner():
    ell = load_environment(MODELS / "l_shape.json")
    reflex = ell.reflex_vertices[0]
    before, after = ell.edge(int(ell.prev_vertex[reflex])), ell.edge(reflex)
    assert safe_interval(before, after).is_empty and safe_interval(after, before).is_empty
    assert safe_interval(((0, 0), (1, 0)), ((1, 0), (2, 0))).is_empty  # collinear: no ray between them


# ---------------------------------------------------------------------------------------------
# Lemma 1, and Prop. 2 = the exact safe set for entirely visible pairs
# ---------------------------------------------------------------------------------------------
@given(env=st.one_of(simple_polygons(max_vertices=10), polygons_with_holes(max_vertices=8, max_holes=2)))
@settings(max_examples=examples(12))
def test_lemma1_and_prop2_on_entirely_visible_segments(env):
    """For entirely visible segments of P′ (checked exactly), the exact safe set is Prop. 2's interval,
    and a safe action exists in at least one direction (Lemma 1), in both when the corner rays are parallel."""
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    segs = p.segments
    seen = 0
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            si, sj = (segs[i].a, segs[i].b), (segs[j].a, segs[j].b)
            if not is_entirely_visible(env, si, sj):
                continue
            seen += 1
            for x, y, sx, sy in ((i, j, si, sj), (j, i, sj, si)):
                got = g.safe_set(x, y)
                assert len(got) <= 1
                assert same_interval(got.interval, safe_interval(sx, sy))
            assert g.n_intervals[g.arc_index(i, j)] or g.n_intervals[g.arc_index(j, i)]
            (a, b), (c, d) = si, sj
            if (c[0] - b[0]) * (d[1] - a[1]) - (c[1] - b[1]) * (d[0] - a[0]) == 0 and b != c and a != d:
                assert g.safe_set(i, j).interval.width == 0 and g.safe_set(j, i).interval.width == 0
    assert seen > 0


# ---------------------------------------------------------------------------------------------
# Def. 8: transitions and φ
# ---------------------------------------------------------------------------------------------
def test_def8_transition_sides_in_a_square():
    bottom, right, top, left = edges_of(SQUARE)
    assert transition_side(bottom, right) == "right" and transition_side(bottom, left) == "left"
    assert transition_side(bottom, top) == "parallel" and transition_angle(bottom, top) == 0.0
    assert transition_angle(bottom, right) == pytest.approx(math.pi / 2)


@given(env=convex_polygons())
@settings(max_examples=examples(30))
def test_def8_phi_of_adjacent_segments_is_the_interior_angle(env):
    edges = edges_of(env)
    n = len(edges)
    for i in range(n):
        (a, b), (_, d) = edges[i], edges[(i + 1) % n]
        interior = math.pi - ang(a, b, sub(d, b))  # interior angle of the convex polygon at b
        assert transition_side(edges[i], edges[(i + 1) % n]) == "right"
        assert transition_angle(edges[i], edges[(i + 1) % n]) == pytest.approx(interior, abs=1e-12)
        assert transition_side(edges[(i + 1) % n], edges[i]) == "left"
        assert transition_angle(edges[(i + 1) % n], edges[i]) == pytest.approx(interior, abs=1e-12)


# ---------------------------------------------------------------------------------------------
# the exact safe set beyond Prop. 2
# ---------------------------------------------------------------------------------------------
def test_safe_set_with_a_hole_is_two_intervals():
    """A counterexample: with holes the safe set is not an interval (the paper's statement holds without holes only)."""
    floor, ceiling = ((-1, 0), (1, 0)), ((12, 8), (-12, 8))
    found = safe_set(HOLE_ROOM, floor, ceiling)
    assert len(found) == 2
    assert math.pi / 4 in found and 3 * math.pi / 4 in found and math.pi / 2 not in found
    assert heading_is_safe(HOLE_ROOM, floor, ceiling, (1, 1)) and heading_is_safe(HOLE_ROOM, floor, ceiling, (-1, 1))
    assert not heading_is_safe(HOLE_ROOM, floor, ceiling, (0, 1))
    # the ends are exact directions: Θ₀'s c − b and d − a, and the hole's corners seen from a and b
    (first, second) = found.intervals
    assert first.lo_direction == (11, 8) and first.hi_direction == (Fraction(3, 2), 2)
    assert second.lo_direction == (Fraction(-3, 2), 2) and second.hi_direction == (-11, 8)
    assert found.interval == max((first.interval, second.interval), key=lambda i: i.width)
    assert found.to_json() == [[first.lo, first.hi], [second.lo, second.hi]]
    # each piece is an Interval of headings itself, whose ends are the headings of its exact directions
    assert isinstance(first, Interval) and math.pi / 4 in first and first.interval == Interval(first.lo, first.hi)
    for piece in (first, second):
        assert piece.lo == pytest.approx(math.atan2(*reversed(piece.lo_direction)), abs=1e-15)
        assert piece.hi == pytest.approx(math.atan2(*reversed(piece.hi_direction)), abs=1e-15)


def test_safe_set_with_a_hole_agrees_with_the_bvg():
    assert_safe_bvg_is_the_exact_reference(HOLE_ROOM)


def test_segments_of_p_prime_can_have_several_safe_intervals():
    """Through P′ too: in this seeded polygon with star-shaped holes a pair of segments has two safe
    intervals (the partition's lines do not always separate the two landing zones), confirmed by the
    exact reference."""
    env = star_polygon_with_holes(12, 4, hole_kind="star", hole_vertices=6, hole_radius=0.06, seed=3)
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    k = int(np.argmax(g.n_intervals))
    assert g.n_intervals[k] == 2
    i, j = int(g.source[k]), int(g.target[k])
    got = g.safe_set(i, j)
    assert same_sets(got, safe_set(env, (p.segments[i].a, p.segments[i].b), (p.segments[j].a, p.segments[j].b)))
    arc = g.to_json()["arcs"][k]
    assert arc["safe_set"] == got.to_json() and len(arc["safe_set"]) == 2
    widest = max(got.intervals, key=lambda piece: piece.width)
    assert arc["safe"] == [widest.lo, widest.hi] == [g.lo[k], g.hi[k]]
    assert got.intervals[0].hi < got.intervals[1].lo  # disjoint, sorted


@given(env=simple_polygons(max_vertices=12))
@settings(max_examples=examples(25))
def test_safe_set_without_holes_is_one_interval(env):
    g = safe_bounce_visibility_graph(env)
    assert g.n_arcs == 0 or int(np.max(g.n_intervals)) <= 1


def assert_safe_bvg_is_the_exact_reference(env):
    """The safe BVG's safe set of every ordered pair of segments of P′ is the exact reference's (``safe_set``)."""
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    segs = p.segments
    for i in range(len(segs)):
        for j in range(len(segs)):
            if i != j:
                assert same_sets(g.safe_set(i, j), safe_set(env, (segs[i].a, segs[i].b), (segs[j].a, segs[j].b))), (i, j)


@given(env=polygons_with_holes(max_vertices=7, max_holes=2))
@settings(max_examples=examples(8))
def test_safe_bvg_equals_the_exact_reference_on_every_pair(env):
    assert_safe_bvg_is_the_exact_reference(env)


@pytest.mark.parametrize("name", ["degenerate", "comb", "two_holes"])
def test_safe_bvg_equals_the_exact_reference_on_models(name):
    """The degenerate model (collinear vertices, parallel edges, hole vertices on lines through outer
    edges: exact ties) and two others, every pair against the exact reference."""
    env = load_environment(MODELS / f"{name}.json")
    assert_safe_bvg_is_the_exact_reference(env)


# ---------------------------------------------------------------------------------------------
# Prop. 2 against rays: soundness and maximality of every safe set
# ---------------------------------------------------------------------------------------------
def _land(env, p, edge, t, heading):
    hits = cast_from_boundary(env, edge, t, heading, exact_ties=True)
    seg = p.segments_at(np.where(hits.edge < 0, 0, hits.edge), np.clip(np.nan_to_num(hits.t), 0, 1))
    return seg, hits


def _source_params(p, i, fractions):
    s = p.segments[i]
    return float(s.t0) + fractions * float(s.t1 - s.t0)


def _turn(u, eta: Fraction):
    """u turned by about eta radians (counter-clockwise for eta > 0), exactly rational."""
    return (u[0] - eta * u[1], u[1] + eta * u[0])


def _witness(env, src, dst, u) -> bool:
    """Is there a point of the open src whose exact ray with direction u misses the open dst?

    The points whose ray misses form an open subset of src whose ends are src's ends or the points
    from which the ray passes through a vertex; the candidates are points right next to those.
    """
    (a, b), (c, d) = src, dst
    e = (b[0] - a[0], b[1] - a[1])
    den = e[0] * u[1] - e[1] * u[0]
    tiny = Fraction(1, 10**12)
    mus = {tiny, 1 - tiny}
    for v in env.exact_vertices:
        mu = ((v[0] - a[0]) * u[1] - (v[1] - a[1]) * u[0]) / den
        for m in (mu - tiny, mu + tiny):
            if 0 < m < 1:
                mus.add(m)
    for mu in sorted(mus):
        s = (a[0] + mu * e[0], a[1] + mu * e[1])
        hit = cast_ray(env, s, u)
        if hit.vertex is not None:
            return True
        edge = env.edge(hit.edge)
        if not (on_segment_open(hit.point, c, d) and on_segment_open(hit.point, edge.a, edge.b)):
            return True
    return False


def on_segment_open(q, c, d) -> bool:
    cross = (d[0] - c[0]) * (q[1] - c[1]) - (d[1] - c[1]) * (q[0] - c[0])
    dot = (q[0] - c[0]) * (d[0] - c[0]) + (q[1] - c[1]) * (d[1] - c[1])
    return cross == 0 and 0 < dot < (d[0] - c[0]) ** 2 + (d[1] - c[1]) ** 2


def check_rays(env, max_arcs: int = 100, seed: int = 0) -> tuple[int, int]:
    """Prop. 2 for (a sample of) the safe arcs of ``env``: *soundness* — float rays from points spread
    over the source, at headings inside each safe interval, all land on the target; *maximality* —
    just outside each end (other than 0 and π) some point's exact ray misses it. Returns the counts."""
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    rows = np.flatnonzero(g.safe)
    rng = np.random.default_rng(seed)
    if len(rows) > max_arcs:
        rows = np.sort(rng.choice(rows, max_arcs, replace=False))
    fr = np.linspace(0.01, 0.99, 13)
    sound = maximal = 0
    for k in rows.tolist():
        i, j = int(g.source[k]), int(g.target[k])
        si, sj = p.segments[i], p.segments[j]
        found = g.safe_set(i, j)
        for piece in found.intervals:
            lo, hi = piece.lo, piece.hi
            inner = [lo + (hi - lo) * f for f in (1e-6, 0.5, 1 - 1e-6)] if hi - lo > 1e-6 else [(lo + hi) / 2]
            t = np.tile(_source_params(p, i, fr), len(inner))
            h = np.repeat(inner, len(fr))
            h = np.clip(h, 1e-9, math.pi - 1e-9)
            seg, _ = _land(env, p, np.full(len(t), si.edge), t, h)
            assert np.all(seg == j), (i, j, piece, seg.tolist())
            sound += len(t)
            eta = Fraction(1, 10**9)
            for end, direction, step in ((lo, piece.lo_direction, -eta), (hi, piece.hi_direction, eta)):
                if end == 0.0 or end == math.pi:
                    continue
                outside = _turn(direction, step)
                assert _witness(env, (si.a, si.b), (sj.a, sj.b), outside), (i, j, end, step)
                maximal += 1
    return sound, maximal


@pytest.mark.parametrize("name", ["two_rooms", "one_hole", "degenerate", "star"])
def test_prop2_soundness_and_maximality_on_models(name):
    sound, maximal = check_rays(load_environment(MODELS / f"{name}.json"))
    assert sound > 0 and maximal > 0


def test_prop2_soundness_and_maximality_with_several_intervals():
    sound, maximal = check_rays(HOLE_ROOM, max_arcs=400)
    assert sound > 0 and maximal > 0


@given(env=st.one_of(simple_polygons(max_vertices=12), polygons_with_holes(max_vertices=8, max_holes=2)))
@settings(max_examples=examples(10))
def test_prop2_soundness_and_maximality_on_random_polygons(env):
    check_rays(env, max_arcs=30)


# ---------------------------------------------------------------------------------------------
# the proof module, and input errors
# ---------------------------------------------------------------------------------------------
def test_safe_set_structure_proof_passes():
    result = structure.prove()
    assert result.passed, [s.claim for s in result.failed_steps]
    assert "holes" in result.errata[0]


def test_safe_set_structure_proof_fails_for_a_reversed_blocked_interval(monkeypatch):
    monkeypatch.setattr(structure, "blocked_interval", lambda alpha, beta: (beta, alpha))
    assert not structure.prove().passed


def test_zero_length_segment_is_rejected():
    with pytest.raises(InputError, match=r"^src has zero length: both end points are \(1, 1\)$"):
        safe_interval(((1, 1), (1, 1)), ((0, 1), (0, 0)))
    with pytest.raises(InputError, match=r"^dst: expected two end points"):
        safe_interval(((0, 0), (1, 0)), 3)


def test_heading_of_a_zero_vector_is_rejected():
    with pytest.raises(InputError, match=r"^direction \(0, 0\) is zero: it has no heading$"):
        heading_is_safe(SQUARE, edges_of(SQUARE)[0], edges_of(SQUARE)[2], (0, 0))
