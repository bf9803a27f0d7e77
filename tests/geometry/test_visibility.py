"""Visibility: point–point, open segment–open segment, entire visibility, visibility polygons.

Every property is checked against a brute-force reference written here, independent of the code
under test: a segment is cut at *all* its exact intersections with *every* edge and the midpoint of
each piece is located with the exact crossing-number test (``point_in_ring``).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError
from solverplan.exact import on_segment, orient, point_in_ring, segment_intersection
from solverplan.geometry import (
    VisibilityPolygon,
    is_entirely_visible,
    segments_see_each_other,
    sees,
    visibility_polygon,
)
from solverplan.geometry.visibility import (
    _left_part,
    _resolve_segment,
    _ShadowFilter,
    _visible_point,
    _weak_visibility_witness,
)
from tests.strategies import convex_polygons, polygons_with_holes, simple_polygons
from tests.shapes import SQUARE

F = Fraction
ELL = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], name="L")
# Three holes whose tips (-2, 0) [below], (2, 0) [above], (4, 0) [below] leave exactly one line,
# y = 0, through the open walls x = ±6: it grazes all three tips, no line near it is free.
GRAZE_ONLY = Environment.from_coords(
    [[-6, -6], [6, -6], [6, 6], [-6, 6]],
    [[[-2, 0], [-4, -4], [0, -4]], [[2, 0], [4, 4], [0, 4]], [[4, 0], [3, -4], [5, -4]]],
    name="graze-only",
)
LEFT_WALL = ((-6, 1), (-6, -1))
RIGHT_WALL = ((6, -1), (6, 1))


# ---------------------------------------------------------------------------------------------
# brute-force references
# ---------------------------------------------------------------------------------------------
def ref_location(env: Environment, x) -> int:
    """+1 in the open free space, 0 on its boundary, −1 outside (exact crossing numbers)."""
    where = [point_in_ring(x, env.outer)] + [-point_in_ring(x, hole) for hole in env.holes]
    if min(where) < 0:
        return -1
    return 0 if min(where) == 0 else 1


def ref_cuts(env: Environment, p, q) -> list[Fraction]:
    """Parameters λ ∈ [0, 1] of every point where pq meets an edge, plus 0 and 1."""
    d = (q[0] - p[0], q[1] - p[1])
    dd = d[0] * d[0] + d[1] * d[1]
    cuts = {F(0), F(1)}
    for e in env.edges:
        hit = segment_intersection(p, q, e.a, e.b)
        if hit is not None:
            for x in hit.points:
                cuts.add(((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / dd)
    return sorted(cuts)


def ref_sees(env: Environment, p, q, strict: bool = False) -> bool:
    p, q = tuple(map(F, p)), tuple(map(F, q))
    if p == q:
        return ref_location(env, p) >= 0
    cuts = ref_cuts(env, p, q)
    if ref_location(env, p) < 0 or ref_location(env, q) < 0:
        return False
    if strict and len(cuts) > 2:
        return False  # a boundary point strictly between p and q
    for lo, hi in zip(cuts, cuts[1:]):
        lam = (lo + hi) / 2
        m = (p[0] + lam * (q[0] - p[0]), p[1] + lam * (q[1] - p[1]))
        if ref_location(env, m) < (1 if strict else 0):
            return False
    return True


def lerp(a, b, t):
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))


def ref_entirely_visible(env: Environment, a, b) -> bool:
    """Def. 6 via the hull criterion, written independently: open b strictly left of a's edge line
    and vice versa, and no edge has a point strictly inside conv(a ∪ b)."""
    (a0, a1, ea), (b0, b1, eb) = a, b
    la, lb = env.edge(ea), env.edge(eb)
    for x in (b0, b1):
        if orient(la.a, la.b, x) < 0:
            return False
    for x in (a0, a1):
        if orient(lb.a, lb.b, x) < 0:
            return False
    if orient(la.a, la.b, b0) == 0 and orient(la.a, la.b, b1) == 0:
        return False
    if orient(lb.a, lb.b, a0) == 0 and orient(lb.a, lb.b, a1) == 0:
        return False
    corners = [a0, a1, b0, b1]

    def strictly_inside(x):
        sides = [(corners[k], corners[(k + 1) % 4]) for k in range(4) if corners[k] != corners[(k + 1) % 4]]
        return all(orient(c, d, x) > 0 for c, d in sides)

    for e in env.edges:
        if strictly_inside(e.a):
            return False
        cuts = {F(0), F(1)}
        for k in range(4):
            c, d = corners[k], corners[(k + 1) % 4]
            if c == d:
                continue
            hit = segment_intersection(e.a, e.b, c, d)
            if hit is not None:
                for x in hit.points:
                    dx, dy = e.b[0] - e.a[0], e.b[1] - e.a[1]
                    cuts.add(((x[0] - e.a[0]) * dx + (x[1] - e.a[1]) * dy) / (dx * dx + dy * dy))
        cuts = sorted(cuts)
        if any(strictly_inside(lerp(e.a, e.b, (lo + hi) / 2)) for lo, hi in zip(cuts, cuts[1:])):
            return False
    return True


# ---------------------------------------------------------------------------------------------
# strategies for points
# ---------------------------------------------------------------------------------------------
T_VALUES = st.sampled_from([F(1, 2), F(1, 3), F(1, 4), F(3, 4), F(2, 5), F(7, 9)])


@st.composite
def points_of(draw, env: Environment):
    """Vertices, boundary points and lattice points (inside or outside): where ties live."""
    kind = draw(st.sampled_from(["vertex", "boundary", "lattice", "lattice"]))
    if kind == "vertex":
        return env.exact_vertices[draw(st.integers(0, env.n_vertices - 1))]
    if kind == "boundary":
        return env.exact_point_at(draw(st.integers(0, env.n_edges - 1)), draw(T_VALUES))
    xmin, ymin, xmax, ymax = (int(v) for v in env.bounds)
    return (F(draw(st.integers(xmin, xmax))), F(draw(st.integers(ymin, ymax))))


@st.composite
def env_and_viewpoint(draw, envs):
    env = draw(envs)
    p = draw(points_of(env))
    assume(ref_location(env, p) >= 0)
    return env, p


def random_points(env: Environment, count: int, seed: int) -> list:
    """Exact rational points of the bounding box with a large prime denominator (never on a line
    through two lattice points by accident)."""
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, ymax = env.bounds
    den = 1_000_003
    out = []
    for _ in range(count):
        x = F(int(rng.integers(int(xmin * den), int(xmax * den) + 1)), den)
        y = F(int(rng.integers(int(ymin * den), int(ymax * den) + 1)), den)
        out.append((x, y))
    return out


# ---------------------------------------------------------------------------------------------
# sees
# ---------------------------------------------------------------------------------------------
@given(data=st.data(), env=st.one_of(simple_polygons(), polygons_with_holes()))
def test_sees_matches_brute_force_on_exact_ties(data, env):
    for _ in range(6):
        p, q = data.draw(points_of(env)), data.draw(points_of(env))
        assert sees(env, p, q) == ref_sees(env, p, q), (p, q)
        assert sees(env, p, q, strict=True) == ref_sees(env, p, q, strict=True), (p, q)


def test_sees_grazing_and_running_along_edges():
    assert sees(ELL, (4, 0), (0, 4))  # touches the reflex vertex (2, 2) from the free side
    assert not sees(ELL, (4, 0), (0, 4), strict=True)
    assert sees(ELL, (4, 2), (0, 2))  # runs along edge 2 then through the free space
    assert not sees(ELL, (4, 2), (0, 2), strict=True)
    assert not sees(ELL, (3, 1), (1, 3 + F(1, 100)))  # cuts the corner
    assert sees(ELL, (3, 1), (1, 3 - F(1, 100)), strict=True)
    assert sees(SQUARE, (0, 0), (4, 4), strict=True)  # a diagonal: end points on the boundary
    assert not sees(SQUARE, (0, 0), (4, 0), strict=True)
    assert not sees(SQUARE, (5, 5), (5, 5))
    assert sees(SQUARE, (4, 4), (4, 4))


def test_sees_through_collinear_hole_vertices():
    # three vertices of holes on the line y = 0: closed visibility passes, strict does not
    assert sees(GRAZE_ONLY, (-6, 0), (6, 0))
    assert not sees(GRAZE_ONLY, (-6, 0), (6, 0), strict=True)
    assert not sees(GRAZE_ONLY, (-6, F(-1, 10)), (6, F(1, 10)))
    assert not sees(GRAZE_ONLY, (-3, -3), (-1, -3))  # through the inside of hole 0


def test_sees_rejects_malformed_points():
    with pytest.raises(InputError, match=r"^point q: expected a pair \[x, y\], got 3$"):
        sees(SQUARE, (1, 1), 3)


# ---------------------------------------------------------------------------------------------
# visibility polygon
# ---------------------------------------------------------------------------------------------
def check_visibility_polygon(env: Environment, p, vp: VisibilityPolygon, seed: int = 0) -> None:
    """Structural and semantic checks of a visibility polygon against the references."""
    p = tuple(map(F, p))
    n = len(vp.pieces)
    assert n == len(vp.ring) >= 3
    assert vp.area > 0 and vp.area <= env.area
    assert vp.contains(p)
    verts = env.exact_vertices
    for k, piece in enumerate(vp.pieces):
        assert piece.a == vp.ring[k] and piece.b == vp.ring[(k + 1) % n] and piece.a != piece.b
        assert ref_sees(env, p, piece.a)  # every corner of the polygon is seen
        if piece.kind in ("edge", "partial"):
            e = env.edge(piece.edge)
            assert piece.reflex_vertex is None
            assert on_segment(piece.a, e.a, e.b) and on_segment(piece.b, e.a, e.b)
            same_way = (piece.b[0] - piece.a[0]) * (e.b[0] - e.a[0]) + (piece.b[1] - piece.a[1]) * (e.b[1] - e.a[1])
            assert same_way > 0  # traversed in the edge's direction: free space on the left
            assert (piece.kind == "edge") == ((piece.a, piece.b) == (e.a, e.b))
        else:
            u = piece.reflex_vertex
            assert piece.edge is None and u in env.reflex_vertices
            near, far = (piece.a, piece.b) if piece.a == verts[u] else (piece.b, piece.a)
            assert near == verts[u]
            assert orient(p, near, far) == 0  # on the ray from p through u, beyond u
            assert (near[0] - p[0]) * (far[0] - near[0]) + (near[1] - p[1]) * (far[1] - near[1]) > 0
            assert ref_location(env, far) == 0  # u′ is on the boundary ...
            assert ref_cuts(env, near, far) == [0, 1]  # ... and the first boundary point beyond u
            assert ref_sees(env, p, far)
    for q in random_points(env, 25, seed):
        if ref_location(env, q) < 0:
            assert not vp.contains(q)
        else:
            assert vp.contains(q) == ref_sees(env, p, q), q


@given(case=env_and_viewpoint(st.one_of(simple_polygons(), polygons_with_holes())))
def test_visibility_polygon_is_what_the_viewpoint_sees(case):
    env, p = case
    check_visibility_polygon(env, p, visibility_polygon(env, p))


@given(env=convex_polygons(), k=st.integers(0, 24), t=T_VALUES)
def test_visibility_polygon_of_convex_polygon_is_the_polygon(env, k, t):
    verts = env.exact_vertices
    k %= env.n_vertices
    inside = ((verts[0][0] + verts[1][0] + verts[2][0]) / 3, (verts[0][1] + verts[1][1] + verts[2][1]) / 3)
    vp = visibility_polygon(env, inside)
    assert vp.area == env.area
    assert sorted(vp.ring) == sorted(verts)
    assert all(piece.kind == "edge" for piece in vp.pieces)
    on_edge = env.exact_point_at(k, t)
    vp = visibility_polygon(env, on_edge)
    assert vp.area == env.area
    assert [piece.kind for piece in vp.pieces] == ["partial"] + ["edge"] * (env.n_edges - 1) + ["partial"]
    assert vp.ring[0] == on_edge
    vp = visibility_polygon(env, verts[k])
    assert vp.area == env.area and all(piece.kind == "edge" for piece in vp.pieces)


def test_visibility_polygon_of_the_L_has_one_window():
    vp = visibility_polygon(ELL, (1, 3))
    assert vp.area == 10
    windows = [piece for piece in vp.pieces if piece.kind == "constructed"]
    assert [(w.a, w.b, w.reflex_vertex) for w in windows] == [((4, 0), (2, 2), 3)]
    assert visibility_polygon(ELL, (2, 2)).area == ELL.area  # from the reflex vertex itself
    check_visibility_polygon(ELL, (3, 2), visibility_polygon(ELL, (3, 2)))  # on the reflex edge


def test_visibility_polygon_cuts_windows_at_collinear_vertices():
    # from (-6, 0) the ray y = 0 grazes the tips (-2, 0), (2, 0), (4, 0): windows run between them
    p = (-6, 0)
    vp = visibility_polygon(GRAZE_ONLY, p)
    check_visibility_polygon(GRAZE_ONLY, p, vp)
    windows = {(w.a, w.b, w.reflex_vertex) for w in vp.pieces if w.kind == "constructed"}
    tip = {GRAZE_ONLY.exact_vertices[v]: v for v in GRAZE_ONLY.reflex_vertices}
    assert ((-2, 0), (2, 0), tip[(-2, 0)]) in windows or ((2, 0), (-2, 0), tip[(-2, 0)]) in windows
    # p on a hole edge, and p at a hole vertex
    for q in [(-3, -2), (-2, 0), (F(7, 2), -2)]:
        check_visibility_polygon(GRAZE_ONLY, q, visibility_polygon(GRAZE_ONLY, q), seed=1)


def test_visibility_polygon_rejects_points_outside():
    with pytest.raises(InputError, match=r"^viewpoint \(3, 3\) is not in the free space$"):
        visibility_polygon(ELL, (3, 3))


# ---------------------------------------------------------------------------------------------
# weak visibility of open segments
# ---------------------------------------------------------------------------------------------
@st.composite
def env_and_two_segments(draw, envs):
    env = draw(envs)
    i = draw(st.integers(0, env.n_edges - 1))
    j = draw(st.integers(0, env.n_edges - 1).filter(lambda j: j != i))
    cuts = st.sampled_from([F(0), F(1, 3), F(1, 2), F(1)])

    def piece(edge):
        t0, t1 = sorted((draw(cuts), draw(cuts)))
        if t0 == t1:
            t0, t1 = F(0), F(1)
        return BoundaryPiece(edge, t0, t1)

    return env, piece(i), piece(j)


def sample_pairs(env, a: BoundaryPiece, b: BoundaryPiece, k: int = 7):
    ts = [F(m, k + 1) for m in range(1, k + 1)]
    for s in ts:
        for t in ts:
            yield (
                env.exact_point_at(a.edge, a.t0 + s * (a.t1 - a.t0)),
                env.exact_point_at(b.edge, b.t0 + t * (b.t1 - b.t0)),
            )


def on_open_piece(env, x, piece: BoundaryPiece) -> bool:
    e = env.edge(piece.edge)
    lo, hi = env.exact_point_at(piece.edge, piece.t0), env.exact_point_at(piece.edge, piece.t1)
    return on_segment(x, lo, hi) and x not in (lo, hi) and on_segment(x, e.a, e.b)


@given(case=env_and_two_segments(st.one_of(simple_polygons(max_vertices=12), polygons_with_holes(max_vertices=10))))
def test_segment_visibility_agrees_with_sampling_and_has_a_witness(case):
    env, a, b = case
    witness = _weak_visibility_witness(env, a, b)
    assert segments_see_each_other(env, a, b) == (witness is not None)
    if any(ref_sees(env, p, q, strict=True) for p, q in sample_pairs(env, a, b)):
        assert witness is not None
    if witness is not None:
        p, q = witness
        assert on_open_piece(env, p, a) and on_open_piece(env, q, b)
        assert ref_sees(env, p, q, strict=True)
    assert segments_see_each_other(env, b, a) == (witness is not None)  # symmetric


@given(case=env_and_two_segments(st.one_of(simple_polygons(max_vertices=10), polygons_with_holes(max_vertices=8, max_holes=2))))
def test_exhaustive_critical_sweep_agrees_with_the_fast_path(case):
    """The sweep alone (reflex separating tangents, float-certified tests) and the sweep over every
    vertex pair with exact tests only give the same answer as the full function."""
    env, a, b = case
    fast = _weak_visibility_witness(env, a, b) is not None
    swept = _weak_visibility_witness(env, a, b, sample=False)
    every_pair = _weak_visibility_witness(env, a, b, sample=False, reduce_critical=False, float_filter=False)
    assert (swept is not None) == fast == (every_pair is not None)
    for witness in (swept, every_pair):
        if witness is not None:
            assert on_open_piece(env, witness[0], a) and on_open_piece(env, witness[1], b)
            assert ref_sees(env, *witness, strict=True)


@given(case=env_and_two_segments(st.one_of(simple_polygons(max_vertices=12), polygons_with_holes(max_vertices=10))),
       s=st.fractions(0, 1).filter(lambda s: 0 < s < 1))
def test_float_shadow_filter_never_blocks_a_visible_position(case, s):
    env, a, b = case
    verts, nxt = env.exact_vertices, env.next_vertex
    a0, a1, ea = _resolve_segment(env, a, "a")
    b0, b1, eb = _resolve_segment(env, b, "b")
    la, lb = (verts[ea], verts[int(nxt[ea])]), (verts[eb], verts[int(nxt[eb])])
    part_a, part_b = _left_part(a0, a1, *lb), _left_part(b0, b1, *la)
    assume(part_a is not None and part_b is not None)
    (a0, a1), (b0, b1) = part_a, part_b
    blockers = [i for i in range(env.n_edges) if i not in (ea, eb)]
    p = lerp(a0, a1, s)
    if _ShadowFilter(env, blockers, b0, b1, la).certainly_blocked(p):
        assert _visible_point(env, p, b0, b1, blockers, [(verts[i], verts[int(nxt[i])]) for i in blockers]) is None
        ts = [F(k, 50) for k in range(1, 50)]
        assert not any(ref_sees(env, p, lerp(b0, b1, t), strict=True) for t in ts)


def test_grazing_lines_do_not_make_segments_visible():
    # L: the right side of the lower arm and the top of the upper arm meet only the diagonal
    # through the closed ends (4, 0), (2, 2), (0, 4)
    assert sees(ELL, (4, 0), (0, 4))
    assert not segments_see_each_other(ELL, ((4, 0), (4, 2)), ((2, 4), (0, 4)))
    assert not segments_see_each_other(ELL, BoundaryPiece(1, F(0), F(1)), BoundaryPiece(4, F(0), F(1)))
    # three collinear tips: the line y = 0 passes through the open walls, but only by grazing
    assert sees(GRAZE_ONLY, (-6, 0), (6, 0))
    assert not segments_see_each_other(GRAZE_ONLY, LEFT_WALL, RIGHT_WALL)
    assert _weak_visibility_witness(GRAZE_ONLY, LEFT_WALL, RIGHT_WALL, sample=False, reduce_critical=False) is None


def test_narrow_window_is_found_by_the_exact_sweep():
    # lower the third tip by 1/1000: now lines with tiny negative slope pass (y(-2) > 0 > y(2), y(4) > -1/1000)
    narrow = Environment.from_coords(
        [[-6, -6], [6, -6], [6, 6], [-6, 6]],
        [[[-2, 0], [-4, -4], [0, -4]], [[2, 0], [4, 4], [0, 4]], [["4", "-0.001"], [3, -4], [5, -4]]],
    )
    witness = _weak_visibility_witness(narrow, LEFT_WALL, RIGHT_WALL)
    assert witness is not None and ref_sees(narrow, *witness, strict=True)
    assert not any(ref_sees(narrow, p, q, strict=True) for p, q in sample_pairs(narrow, *(
        BoundaryPiece(narrow.locate(LEFT_WALL[0])[0], *sorted((narrow.locate(x)[1] for x in LEFT_WALL))),
        BoundaryPiece(narrow.locate(RIGHT_WALL[0])[0], *sorted((narrow.locate(x)[1] for x in RIGHT_WALL))),
    )))  # too narrow for a 7 × 7 sample: only the exact sweep finds it
    assert segments_see_each_other(narrow, LEFT_WALL, RIGHT_WALL)


def test_segments_on_one_line_or_behind_each_other_do_not_see_each_other():
    assert not segments_see_each_other(SQUARE, ((0, 0), (1, 0)), ((2, 0), (4, 0)))  # one edge
    assert not segments_see_each_other(ELL, ((4, 2), (3, 2)), ((2, 2), (2, 4)))  # around the reflex corner
    assert segments_see_each_other(ELL, ((4, 2), (2, 2)), ((0, 4), (0, 0)))
    assert segments_see_each_other(SQUARE, ((0, 0), (4, 0)), ((4, 0), (4, 4)))  # adjacent, convex corner


def test_segment_must_lie_on_one_edge():
    with pytest.raises(InputError, match=r"^segment b \(1, 1\)-\(2, 2\) does not lie on one boundary edge$"):
        segments_see_each_other(SQUARE, ((0, 0), (4, 0)), ((1, 1), (2, 2)))
    with pytest.raises(InputError, match=r"^segment a has zero length: both end points are \(1, 0\)$"):
        is_entirely_visible(SQUARE, ((1, 0), (1, 0)), ((0, 4), (4, 4)))


# ---------------------------------------------------------------------------------------------
# entire visibility
# ---------------------------------------------------------------------------------------------
def test_square_sides_are_entirely_visible():
    sides = [SQUARE.edge(i) for i in range(4)]
    for i in range(4):
        for j in range(4):
            expected = i != j
            assert is_entirely_visible(SQUARE, (sides[i].a, sides[i].b), (sides[j].a, sides[j].b)) == expected
    assert not is_entirely_visible(SQUARE, ((0, 0), (1, 0)), ((1, 0), (4, 0)))  # same edge


def test_L_sides_around_the_reflex_corner_are_not_entirely_visible():
    e = [(ELL.edge(i).a, ELL.edge(i).b) for i in range(6)]
    assert not is_entirely_visible(ELL, e[2], e[3])  # share the reflex vertex (2, 2)
    assert not is_entirely_visible(ELL, e[1], e[4])  # only the grazing diagonal
    assert not is_entirely_visible(ELL, e[0], e[4])  # (2, 2) lies inside their hull ...
    assert segments_see_each_other(ELL, e[0], e[4])  # ... though they see each other weakly
    assert is_entirely_visible(ELL, e[0], e[5])  # convex corner; (2, 2) is on the hull's side
    assert is_entirely_visible(ELL, e[1], e[2])
    assert not is_entirely_visible(ELL, e[0], ((2, F(5, 2)), (2, 4)))  # the bottom reaches right of edge 3's line
    assert is_entirely_visible(ELL, e[0], ((4, 2), (3, 2)))  # both in the convex lower arm


@given(case=env_and_two_segments(st.one_of(simple_polygons(max_vertices=12), polygons_with_holes(max_vertices=10))))
def test_entire_visibility_matches_the_hull_criterion_and_sampling(case):
    env, a, b = case
    ends = [(env.exact_point_at(s.edge, s.t0), env.exact_point_at(s.edge, s.t1), s.edge) for s in (a, b)]
    entire = is_entirely_visible(env, a, b)
    assert entire == ref_entirely_visible(env, *ends)
    assert entire == is_entirely_visible(env, b, a)
    if entire:
        assert all(ref_sees(env, p, q, strict=True) for p, q in sample_pairs(env, a, b, k=4))
        assert segments_see_each_other(env, a, b)
