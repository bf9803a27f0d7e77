"""Visibility in the free space, exact: point–point, open segment–open segment, visibility polygons.

Notation: F is the **closed** free space (outer ring with its boundary, minus the open holes),
int F its interior and ∂F the boundary. Three notions of "p sees q" are used, and every function
says which one it answers:

- *closed visibility* — the closed segment pq lies in F. Grazing a vertex and running along an
  edge are allowed. :func:`sees` (the default) and membership in a visibility polygon's rays.
- *strict visibility* — the open segment pq lies in int F (its end points may be on ∂F). No
  grazing, no running along edges. ``sees(..., strict=True)``, and the two segment predicates.
- *weak (segment) visibility* — open segments a and b see each other if **some** p in a and q in b
  see each other strictly (paper Def. 5, the arcs of the bounce visibility graph); *entire*
  visibility if **every** such pair does (paper Def. 6, the premise of Prop. 2).

Everything is decided in exact rational arithmetic (:class:`fractions.Fraction`); numpy float
filters (:func:`solverplan.exact.orient_filter`, whose nonzero answers are certified exact signs)
only discard edges that certainly do not matter and find witnesses quickly, never decide a tie.

>>> from solverplan.environment import Environment
>>> ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])   # an L
>>> sees(ell, (4, 0), (0, 4))                  # grazes the reflex vertex (2, 2)
True
>>> sees(ell, (4, 0), (0, 4), strict=True)
False
>>> segments_see_each_other(ell, ((4, 0), (4, 2)), ((2, 4), (0, 4)))   # only a grazing line
False
>>> is_entirely_visible(ell, ((0, 0), (4, 0)), ((0, 4), (0, 0)))
True
>>> vp = visibility_polygon(ell, (1, 3))
>>> vp.area, [piece.kind for piece in vp.pieces].count("constructed")
(Fraction(10, 1), 1)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import cmp_to_key
from typing import Literal, Sequence, Union

import numpy as np

from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import (
    ExactPoint,
    cross,
    dot,
    exact_point,
    exact_segment,
    ring_without_repeats,
    format_point,
    line_intersection,
    on_segment,
    orient_filter,
    point_in_ring,
    segment_intersection,
)
from solverplan.geometry.raycast import cast_ray

__all__ = [
    "Segment",
    "VisibilityPiece",
    "VisibilityPolygon",
    "sees",
    "segments_see_each_other",
    "is_entirely_visible",
    "visibility_polygon",
]

Segment = Union[tuple[Sequence[object], Sequence[object]], BoundaryPiece]
"""A piece of the boundary: two end points lying on one edge, or a :class:`BoundaryPiece`."""

_INSIDE, _ON_BOUNDARY, _OUTSIDE = 1, 0, -1
_Feature = tuple[str, int]  # ("v", vertex id) or ("e", edge id): where a boundary point lies

# Samples per segment of the float witness search in :func:`segments_see_each_other`.
_WITNESS_SAMPLES = 8


# ---------------------------------------------------------------------------------------------
# small exact vector helpers
# ---------------------------------------------------------------------------------------------
def _sub(a: Sequence[Fraction], b: Sequence[Fraction]) -> ExactPoint:
    return (a[0] - b[0], a[1] - b[1])


def _add(a: Sequence[Fraction], b: Sequence[Fraction]) -> ExactPoint:
    return (a[0] + b[0], a[1] + b[1])


def _lerp(a: ExactPoint, b: ExactPoint, t: Fraction) -> ExactPoint:
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))


def _mid(a: ExactPoint, b: ExactPoint) -> ExactPoint:
    return ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)


def _det(a: Sequence[Fraction], b: Sequence[Fraction], c: Sequence[Fraction]) -> Fraction:
    """Twice the signed area of abc: > 0 iff c is left of the directed line a → b."""
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def _same_direction(u: Sequence[Fraction], v: Sequence[Fraction]) -> bool:
    return cross(u, v) == 0 and dot(u, v) > 0


def _angle_cmp(ref: Sequence[Fraction], u: Sequence[Fraction], v: Sequence[Fraction]) -> int:
    """Compare the CCW angles in [0, 2π) of directions u and v measured from direction ``ref``."""

    def half(w: Sequence[Fraction]) -> int:
        c = cross(ref, w)
        return 0 if c > 0 or (c == 0 and dot(ref, w) > 0) else 1

    hu, hv = half(u), half(v)
    if hu != hv:
        return hu - hv
    return -_sign(cross(u, v))


def _floats(points: Sequence[Sequence[Fraction]]) -> np.ndarray:
    return np.array([[float(x), float(y)] for x, y in points], dtype=float).reshape(-1, 2)


# ---------------------------------------------------------------------------------------------
# boundary structure along a segment
# ---------------------------------------------------------------------------------------------
def _locate(env: Environment, p: ExactPoint) -> tuple[str, int]:
    """Exactly where p is: ("v", vertex), ("e", edge) for the open edge, ("in", -1) or ("out", -1)."""
    fp = _floats([p])[0]
    e0, e1 = env.edge_start, env.edge_end
    maybe = (
        (orient_filter(e0, e1, fp) == 0)
        & (np.minimum(e0[:, 0], e1[:, 0]) <= fp[0])
        & (fp[0] <= np.maximum(e0[:, 0], e1[:, 0]))
        & (np.minimum(e0[:, 1], e1[:, 1]) <= fp[1])
        & (fp[1] <= np.maximum(e0[:, 1], e1[:, 1]))
    )  # rounding is monotone: an exact point of a closed edge passes this float test
    verts, nxt = env.exact_vertices, env.next_vertex
    for i in np.flatnonzero(maybe).tolist():
        a, b = verts[i], verts[int(nxt[i])]
        if on_segment(p, a, b):
            if p == a:
                return ("v", i)
            if p == b:
                return ("v", int(nxt[i]))
            return ("e", i)
    inside = point_in_ring(p, env.outer) > 0 and all(point_in_ring(p, hole) < 0 for hole in env.holes)
    return ("in", -1) if inside else ("out", -1)


def _boundary_events(env: Environment, p: ExactPoint, q: ExactPoint) -> list[tuple[Fraction, ExactPoint, _Feature]]:
    """Every point where the closed segment pq (p ≠ q) meets ∂F, once each, sorted along pq.

    Returns (λ, point, feature) with point = p + λ (q − p), λ ∈ [0, 1]; an edge lying along pq
    contributes the two ends of the overlap. Float filter: an edge whose end points are certainly
    on one side of the line pq, or which certainly has p and q on one side of its line, is skipped.
    """
    fp, fq = _floats([p, q])
    e0, e1 = env.edge_start, env.edge_end
    apart = (orient_filter(fp, fq, e0) * orient_filter(fp, fq, e1) > 0) | (
        orient_filter(e0, e1, fp) * orient_filter(e0, e1, fq) > 0
    )
    verts, nxt = env.exact_vertices, env.next_vertex
    d = _sub(q, p)
    dd = dot(d, d)
    found: dict[Fraction, tuple[Fraction, ExactPoint, _Feature]] = {}
    for i in np.flatnonzero(~apart).tolist():
        a, b = verts[i], verts[int(nxt[i])]
        hit = segment_intersection(p, q, a, b)
        if hit is None:
            continue
        for x in hit.points:
            lam = dot(_sub(x, p), d) / dd
            if lam in found:
                continue
            feature: _Feature = ("v", i) if x == a else ("v", int(nxt[i])) if x == b else ("e", i)
            found[lam] = (lam, x, feature)
    return [found[lam] for lam in sorted(found)]


def _local_status(env: Environment, feature: _Feature, d: Sequence[Fraction]) -> int:
    """Where the open segment leaving the boundary point ``feature`` in direction d starts:
    ``_INSIDE`` (int F), ``_ON_BOUNDARY`` (along an edge) or ``_OUTSIDE``."""
    kind, i = feature
    verts = env.exact_vertices
    if kind == "e":
        a, b = verts[i], verts[int(env.next_vertex[i])]
        return _sign(cross(_sub(b, a), d))  # free space is on the left of the edge
    v = verts[i]
    out = _sub(verts[int(env.next_vertex[i])], v)  # along the outgoing edge
    back = _sub(verts[int(env.prev_vertex[i])], v)  # back along the incoming edge
    if _same_direction(d, out) or _same_direction(d, back):
        return _ON_BOUNDARY
    # the free wedge at v runs CCW from `out` to `back`
    return _INSIDE if _angle_cmp(out, d, back) < 0 else _OUTSIDE


def _piece_statuses(env: Environment, p: ExactPoint, q: ExactPoint):
    """The boundary events of pq and the status of each open piece between consecutive events
    (pieces cover [0, 1]; the first and last may be half-open at p and q when those are not events)."""
    events = _boundary_events(env, p, q)
    d = _sub(q, p)
    back = (-d[0], -d[1])
    if not events:
        where = _locate(env, p)[0]
        return events, [_INSIDE if where == "in" else _OUTSIDE]
    lams = [e[0] for e in events]
    cuts = ([Fraction(0)] if lams[0] > 0 else []) + lams + ([Fraction(1)] if lams[-1] < 1 else [])
    by_lam = {e[0]: e for e in events}
    statuses = []
    for lo, hi in zip(cuts, cuts[1:]):
        if lo in by_lam:
            statuses.append(_local_status(env, by_lam[lo][2], d))
        else:  # only the first piece, from p (not on the boundary) to the first event
            statuses.append(_local_status(env, by_lam[hi][2], back))
    return events, statuses


def sees(env: Environment, p: Sequence[object], q: Sequence[object], *, strict: bool = False) -> bool:
    """Does point p see point q? Exact; p and q may be interior points, boundary points or vertices.

    Default (*closed visibility*): the closed segment pq lies in the closed free space F. Grazing
    a vertex and running along an edge are allowed, so two points of one edge see each other and a
    segment through a reflex vertex that touches it from outside the obstacle sees through it.
    With ``strict=True``: the open segment pq lies in the interior of F — no point strictly between
    p and q may touch the boundary (p and q themselves may lie on it). Points outside F see nothing.
    For p == q both notions reduce to "p ∈ F".

    Algorithm: the boundary points of pq (float-filtered edges, exact intersections) cut pq into
    open pieces; each piece lies in int F, along ∂F or outside F, decided exactly from the local
    picture at one of its ends (the side of an edge, the free wedge of a vertex). O(n) numpy work,
    plus exact work per edge that nearly meets pq.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [2, 0], [2, 2], [0, 2]])
    >>> sees(square, (0, 0), (2, 0)), sees(square, (0, 0), (2, 0), strict=True)   # along an edge
    (True, False)
    >>> sees(square, (0, 1), (2, 1), strict=True), sees(square, (1, 1), (3, 1))
    (True, False)
    """
    p = exact_point(p, where="point p")
    q = exact_point(q, where="point q")
    if p == q:
        return _locate(env, p)[0] != "out"
    events, statuses = _piece_statuses(env, p, q)
    if strict:
        return not any(0 < lam < 1 for lam, _, _ in events) and statuses == [_INSIDE]
    return _OUTSIDE not in statuses


# ---------------------------------------------------------------------------------------------
# boundary segments
# ---------------------------------------------------------------------------------------------
def _resolve_segment(env: Environment, seg: Segment, name: str) -> tuple[ExactPoint, ExactPoint, int]:
    """End points (ordered along the edge's direction) and edge id of a boundary segment."""
    if isinstance(seg, BoundaryPiece):
        edge = env.edge(seg.edge)  # unknown edge: InvalidBoundarySet
        t0, t1 = Fraction(seg.t0), Fraction(seg.t1)
        if not 0 <= t0 < t1 <= 1:
            raise InputError(f"{name} {seg}: need 0 <= t0 < t1 <= 1")
        return _lerp(edge.a, edge.b, t0), _lerp(edge.a, edge.b, t1), seg.edge
    p0, p1 = exact_segment(seg, where=name)
    f0, f1 = _floats([p0, p1])
    e0, e1 = env.edge_start, env.edge_end
    maybe = (orient_filter(e0, e1, f0) == 0) & (orient_filter(e0, e1, f1) == 0)
    verts, nxt = env.exact_vertices, env.next_vertex
    for i in np.flatnonzero(maybe).tolist():
        a, b = verts[i], verts[int(nxt[i])]
        if on_segment(p0, a, b) and on_segment(p1, a, b):
            if dot(_sub(p1, p0), _sub(b, a)) < 0:
                p0, p1 = p1, p0
            return p0, p1, i
    raise InputError(f"{name} {format_point(p0)}-{format_point(p1)} does not lie on one boundary edge")


def _left_part(x0: ExactPoint, x1: ExactPoint, la: ExactPoint, lb: ExactPoint) -> tuple[ExactPoint, ExactPoint] | None:
    """End points of the part of the open segment x0x1 strictly left of the line la → lb, or None."""
    d0, d1 = _det(la, lb, x0), _det(la, lb, x1)
    if d0 <= 0 and d1 <= 0:
        return None
    if d0 >= 0 and d1 >= 0:
        return x0, x1
    cut = _lerp(x0, x1, d0 / (d0 - d1))
    return (cut, x1) if d0 < 0 else (x0, cut)


def _edges_near_convex(env: Environment, ring: Sequence[ExactPoint], skip: Sequence[int] = ()) -> list[int]:
    """Edges not certainly disjoint from the closed convex CCW polygon ``ring`` (float filter:
    an edge goes if both its ends are certainly strictly right of one side)."""
    fr = _floats(ring)
    e0, e1 = env.edge_start, env.edge_end
    outside = np.zeros(env.n_edges, dtype=bool)
    for k in range(len(fr)):
        c, d = fr[k], fr[(k + 1) % len(fr)]
        outside |= (orient_filter(c, d, e0) < 0) & (orient_filter(c, d, e1) < 0)
    outside[list(skip)] = True
    return np.flatnonzero(~outside).tolist()


def _clip_to_convex(ring: Sequence[ExactPoint], u: ExactPoint, w: ExactPoint) -> tuple[ExactPoint, ExactPoint] | None:
    """The closed segment uw clipped to the closed convex CCW polygon ``ring`` (exact Liang–Barsky)."""
    t0, t1 = Fraction(0), Fraction(1)
    for k in range(len(ring)):
        c, d = ring[k], ring[(k + 1) % len(ring)]
        fu, fw = _det(c, d, u), _det(c, d, w)
        if fu < 0 and fw < 0:
            return None
        if fu < 0:
            t0 = max(t0, fu / (fu - fw))
        elif fw < 0:
            t1 = min(t1, fu / (fu - fw))
        if t0 > t1:
            return None
    return _lerp(u, w, t0), _lerp(u, w, t1)


def _meets_open_convex(ring: Sequence[ExactPoint], u: ExactPoint, w: ExactPoint) -> bool:
    """Does the closed segment uw meet the interior of the convex CCW polygon ``ring``?

    The clipped part of uw is a chord of the polygon; a chord that is not a single point and does
    not lie on a side's line has its relative interior inside the polygon's interior.
    """
    clipped = _clip_to_convex(ring, u, w)
    if clipped is None or clipped[0] == clipped[1]:
        return False
    m = _mid(*clipped)
    return all(_det(ring[k], ring[(k + 1) % len(ring)], m) > 0 for k in range(len(ring)))


def is_entirely_visible(env: Environment, seg_a: Segment, seg_b: Segment) -> bool:
    """Are two boundary segments entirely visible (paper Def. 6)? Exact.

    True iff **every** p of the open segment a and **every** q of the open segment b see each other
    strictly (the open segment pq lies in the interior of the free space). Segments are pieces of
    one edge each: a pair of end points or a :class:`~solverplan.environment.BoundaryPiece`; their
    orientation does not matter.

    Criterion (proved below): with A, B the edges of a and b,

    1. the open segment b lies strictly left of the line of A (the free side) and the open a
       strictly left of the line of B — then Q = conv(a ∪ b) is the convex polygon
       (a0, a1, b0, b1), CCW with a and b among its sides (a triangle if they share an end point);
    2. no boundary edge meets the interior of Q.

    Proof. (⇒) If some q ∈ b is on or right of the line of A, then pq leaves p ∈ a (an interior
    point of edge A) along A or into the obstacle, for every p. And every x ∈ int Q lies on some
    open pq with p ∈ a, q ∈ b: seen from x, the sides of Q subtend arcs A, C, B, D (C, D the
    connecting sides, possibly empty) summing to 2π with C < π and D < π, so the arc antipodal to
    a's arc meets b's arc; all such pq lie in int F, hence int Q ⊂ int F and no edge meets int Q.
    (⇐) For p, q in the relative interiors of two different sides of the convex polygon Q, the open
    segment pq lies in int Q (its line is not a supporting line); int Q is connected, misses ∂F and
    contains points just left of a (in F), so int Q ⊂ int F.
    The same argument shows that demanding only *closed* visibility for every pair gives the same
    answer: an edge point inside int Q would have obstacle points right next to it inside Q.
    Sharing a reflex or flat vertex fails condition 1; sharing a convex vertex passes it (Cor. 1).

    O(n) numpy filtering plus exact clipping of the edges near Q.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [2, 0], [2, 2], [0, 2]])
    >>> is_entirely_visible(square, ((0, 0), (2, 0)), ((2, 2), (0, 2)))      # opposite sides
    True
    >>> is_entirely_visible(square, ((0, 0), (1, 0)), ((1, 0), (2, 0)))      # one line
    False
    """
    a0, a1, ea = _resolve_segment(env, seg_a, "segment a")
    b0, b1, eb = _resolve_segment(env, seg_b, "segment b")
    if ea == eb:
        return False
    verts, nxt = env.exact_vertices, env.next_vertex
    la, lb = (verts[ea], verts[int(nxt[ea])]), (verts[eb], verts[int(nxt[eb])])
    if _left_part(b0, b1, *la) != (b0, b1) or _left_part(a0, a1, *lb) != (a0, a1):
        return False  # some point of the open b is not strictly on A's free side, or vice versa
    ring = ring_without_repeats([a0, a1, b0, b1])
    for i in _edges_near_convex(env, ring, skip=(ea, eb)):
        if _meets_open_convex(ring, verts[i], verts[int(nxt[i])]):
            return False
    return True


# ---------------------------------------------------------------------------------------------
# weak visibility of open boundary segments
# ---------------------------------------------------------------------------------------------
def segments_see_each_other(env: Environment, seg_a: Segment, seg_b: Segment) -> bool:
    """Do two open boundary segments see each other (paper Def. 5, the bounce visibility graph)? Exact.

    True iff there are p in the open segment a and q in the open segment b such that the open
    segment pq lies in the interior of the free space. Lines that only graze a vertex or run along
    an edge do not count (exact predicates decide every tie; no epsilon): the end points of a and b themselves are never
    used. Segments are pieces of one edge each (end point pairs or
    :class:`~solverplan.environment.BoundaryPiece`); orientation does not matter.

    Algorithm (m = number of edges near the segments):

    1. *Clip.* pq must leave p into A's free side and q into B's: keep a' = the part of a strictly
       left of B's line and b' = the part of b strictly left of A's line (exact). Every candidate
       pq lies in Q = conv(a' ∪ b'), so only the m edges meeting Q can block; edges A and B never do.
    2. *Float witness.* An 8 × 8 grid of exact rational pairs (p, q) is tested against those edges
       with the certified float orientation filter; a pair cleared for every edge is an exact
       witness (pq misses ∂F, leaves p into F): answer True. This settles most visible pairs.
    3. *Exact sweep over critical positions.* For fixed p, the visible part W(p) of b' is b' minus
       the angular shadows of the edges clipped to the triangle (p, b0', b1'). As p moves along a',
       the shadows' ends move continuously, so a gap of W(p) can open or close only where its two
       ends meet. A gap end is b0', b1' or a vertex u whose two edges both lie on the far side of
       the ray p→u while the free space continues just beside the ray: u is reflex. So the
       critical positions are where a' meets the lines through a reflex vertex and b0' or b1',
       and the lines through two reflex vertices u, w that separate their edges (u's edges on
       one closed side of the line uw, w's on the other) — O(r²) positions for the r reflex
       vertices near the segments, filtered in floats and computed exactly. W(p) is then tested
       at one exact p strictly between each consecutive pair of positions (and the ends of a');
       the set of visible pairs is open, so a visible pair anywhere shows up at one of them.
       Each test is first tried as a certified float computation (shadow ends are vertices or
       the cone's sides, coverage is decided by orientation signs only, numpy over all edges);
       any tie falls back to the exact sweep of the shadows, O(m log m) in rationals.
       Worst case O(r² · m²) numpy work and O(r² · m log m) exact work; it runs only when step 2
       finds nothing — typically when the segments do not see each other.

    Every True answer comes with an exact witness pair, re-checked with ``sees(strict=True)``.

    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    >>> segments_see_each_other(ell, ((0, 0), (4, 0)), ((2, 4), (0, 4)))   # bottom and top of the L
    True
    >>> segments_see_each_other(ell, ((4, 0), (4, 2)), ((2, 4), (0, 4)))   # only the grazing diagonal
    False
    """
    return _weak_visibility_witness(env, seg_a, seg_b) is not None


def _weak_visibility_witness(
    env: Environment,
    seg_a: Segment,
    seg_b: Segment,
    *,
    sample: bool = True,
    reduce_critical: bool = True,
    float_filter: bool = True,
) -> tuple[ExactPoint, ExactPoint] | None:
    """A pair (p, q), p in open a, q in open b, seeing each other strictly; None if there is none.

    For tests of the exhaustive step: ``sample=False`` skips the float witness search;
    ``reduce_critical=False`` uses the lines through *every* pair of vertices near the segments
    (not only separating tangents through reflex vertices); ``float_filter=False`` decides every
    test position with the exact sweep.
    """
    a0, a1, ea = _resolve_segment(env, seg_a, "segment a")
    b0, b1, eb = _resolve_segment(env, seg_b, "segment b")
    if ea == eb:
        return None
    verts, nxt, prv = env.exact_vertices, env.next_vertex, env.prev_vertex
    la, lb = (verts[ea], verts[int(nxt[ea])]), (verts[eb], verts[int(nxt[eb])])
    part_a, part_b = _left_part(a0, a1, *lb), _left_part(b0, b1, *la)
    if part_a is None or part_b is None:
        return None
    (a0, a1), (b0, b1) = part_a, part_b
    quad = ring_without_repeats([a0, a1, b0, b1])
    blockers = _edges_near_convex(env, quad, skip=(ea, eb))
    edges = [(verts[i], verts[int(nxt[i])]) for i in blockers]

    def checked(p: ExactPoint, q: ExactPoint) -> tuple[ExactPoint, ExactPoint]:
        if not sees(env, p, q, strict=True):  # pragma: no cover - a bug, not an input problem
            raise SolverFailed(f"segment visibility witness {format_point(p)}-{format_point(q)} is not visible")
        return p, q

    if sample:
        ts = [Fraction(k, _WITNESS_SAMPLES + 1) for k in range(1, _WITNESS_SAMPLES + 1)]
        ps = [_lerp(a0, a1, t) for t in ts]
        qs = [_lerp(b0, b1, t) for t in ts]
        fp, fq = _floats(ps)[:, None, None, :], _floats(qs)[None, :, None, :]
        fe0 = env.edge_start[blockers][None, None, :, :]
        fe1 = env.edge_end[blockers][None, None, :, :]
        clear = (orient_filter(fp, fq, fe0) * orient_filter(fp, fq, fe1) > 0) | (
            orient_filter(fe0, fe1, fp) * orient_filter(fe0, fe1, fq) > 0
        )
        ok = np.argwhere(clear.all(axis=2))
        if len(ok):
            i, j = ok[len(ok) // 2].tolist()
            return checked(ps[i], qs[j])

    # critical positions along a' (parameter s ∈ (0, 1) from a0 to a1)
    da = _sub(a1, a0)
    daa = dot(da, da)

    def relevant(v: int) -> bool:
        x = verts[v]
        return (
            (env.is_reflex(v) or not reduce_critical)
            and _det(*la, x) > 0
            and _det(*lb, x) > 0
            and all(_det(quad[k], quad[(k + 1) % len(quad)], x) >= 0 for k in range(len(quad)))
        )

    ids = sorted({v for i in blockers for v in (i, int(nxt[i]))})
    us = [v for v in ids if relevant(v)]
    critical: set[Fraction] = set()

    def add_line(x: ExactPoint, y: ExactPoint) -> None:
        hit = line_intersection(x, y, a0, a1)
        if hit is not None:
            s = dot(_sub(hit, a0), da) / daa
            if 0 < s < 1:
                critical.add(s)

    for u in us:
        add_line(verts[u], b0)
        add_line(verts[u], b1)
    if len(us) > 1:
        ua = np.array(us, dtype=np.int64)
        ii, jj = np.triu_indices(len(us), 1)
        ui, uj = ua[ii], ua[jj]
        fv = env.vertices

        def side(n: np.ndarray) -> np.ndarray:
            """Exact sign of det(u_i, u_j, vertex n) per pair: float filter, exact where it is unsure."""
            sgn = orient_filter(fv[ui], fv[uj], fv[n]).astype(np.int64)
            for t in np.flatnonzero(sgn == 0).tolist():
                sgn[t] = _sign(_det(verts[int(ui[t])], verts[int(uj[t])], verts[int(n[t])]))
            return sgn

        # the line u_i u_j must cross the open a' (certainly or maybe)
        cross_a = orient_filter(fv[ui], fv[uj], _floats([a0])[0]) * orient_filter(fv[ui], fv[uj], _floats([a1])[0])
        keep = cross_a <= 0
        ui, uj = ui[keep], uj[keep]
        if reduce_critical and len(ui):
            # separating tangents only: u's edges on one closed side of the line, w's on the other
            s1, s2 = side(np.asarray(prv)[ui]), side(np.asarray(nxt)[ui])
            t1, t2 = side(np.asarray(prv)[uj]), side(np.asarray(nxt)[uj])
            sep = (s1 * s2 >= 0) & (t1 * t2 >= 0) & (s1 * t1 <= 0) & (s1 * t2 <= 0) & (s2 * t1 <= 0) & (s2 * t2 <= 0)
            ui, uj = ui[sep], uj[sep]
        for u, w in zip(ui.tolist(), uj.tolist()):
            add_line(verts[u], verts[w])
    cuts = [Fraction(0), *sorted(critical), Fraction(1)]
    shadows = _ShadowFilter(env, blockers, b0, b1, la) if float_filter else None
    for lo, hi in zip(cuts, cuts[1:]):
        p = _lerp(a0, a1, (lo + hi) / 2)
        if shadows is not None and shadows.certainly_blocked(p):
            continue
        q = _visible_point(env, p, b0, b1, blockers, edges)
        if q is not None:
            return checked(p, q)
    return None


class _ShadowFilter:
    """Certified float test "p sees no point of the open segment b0b1" for many p (see
    :func:`_visible_point` for the exact version).

    Every shadow end is one of: an edge's end point (a vertex, exact), b0 or b1 (where the edge
    leaves the cone through its side: the same direction), or — only for the rare edges crossing
    the line of b — an exactly clipped point. All decisions are orientations of exact points,
    certified by :func:`~solverplan.exact.orient_filter`; any uncertain one (a tie) gives up and
    leaves the position to the exact sweep. Coverage of the open cone by closed intervals is
    checked without sorting: every right end r (and b0) that is not the cone's end must have an
    interval with lo ≤ r < hi.
    """

    def __init__(
        self, env: Environment, blockers: list[int], b0: ExactPoint, b1: ExactPoint, la: tuple[ExactPoint, ExactPoint]
    ) -> None:
        verts, nxt = env.exact_vertices, env.next_vertex
        # edges on the line of a (through every p) shadow no direction of the open cone
        blockers = [i for i in blockers if _det(*la, verts[i]) != 0 or _det(*la, verts[int(nxt[i])]) != 0]
        self.b0, self.b1 = b0, b1
        self.fb0, self.fb1 = _floats([b0, b1])
        u_ids = np.array(blockers, dtype=np.int64)
        w_ids = np.asarray(nxt, dtype=np.int64)[u_ids] if len(blockers) else u_ids
        sides = {}  # exact side of b's line (independent of p): > 0 in front (p's side)
        for v in set(u_ids.tolist()) | set(w_ids.tolist()):
            sides[v] = _sign(_det(b0, b1, verts[v]))
        su = np.array([sides[v] for v in u_ids.tolist()], dtype=np.int8)
        sw = np.array([sides[v] for v in w_ids.tolist()], dtype=np.int8)
        crossing = su * sw < 0
        keep = ~crossing & ((su > 0) | (sw > 0))  # edges on or behind b's line cast no shadow
        self.crossing = [(int(u), int(w)) for u, w in zip(u_ids[crossing], w_ids[crossing])]
        self.verts = verts

        def ident(ids: np.ndarray) -> np.ndarray:
            out = ids.copy()
            for k, v in enumerate(ids.tolist()):
                if verts[v] == b0:
                    out[k] = -1
                elif verts[v] == b1:
                    out[k] = -2
            return out

        self.u_id, self.w_id = ident(u_ids[keep]), ident(w_ids[keep])
        self.fu, self.fw = env.vertices[u_ids[keep]], env.vertices[w_ids[keep]]
        # exact zeros the float filter cannot see: p, a vertex on a's line and b0 (or b1) on it too
        on_a = {v: _det(*la, verts[v]) == 0 for v in set(u_ids.tolist()) | set(w_ids.tolist())}
        b0_on_a, b1_on_a = _det(*la, b0) == 0, _det(*la, b1) == 0
        self.zu = np.array([on_a[v] for v in u_ids[keep].tolist()], dtype=bool)
        self.zw = np.array([on_a[v] for v in w_ids[keep].tolist()], dtype=bool)
        self.b0_on_a, self.b1_on_a = b0_on_a, b1_on_a

    def certainly_blocked(self, p: ExactPoint) -> bool:
        fp = _floats([p])[0]
        fb0, fb1 = self.fb0, self.fb1
        fu, fw, uid, wid, zu, zw = self.fu, self.fw, self.u_id, self.w_id, self.zu, self.zw
        if self.crossing:  # clip the few edges crossing b's line exactly
            points, ids_list = [], []
            for u, w in self.crossing:
                clipped = _clip_to_convex([p, self.b0, self.b1], self.verts[u], self.verts[w])
                if clipped is not None:
                    for x in clipped:
                        points.append(x)
                        # an end point keeps its vertex id; a point on a side of the cone is that side
                        if x == self.verts[u] or x == self.verts[w]:
                            ids_list.append(u if x == self.verts[u] else w)
                        elif _det(p, self.b0, x) == 0:
                            ids_list.append(-1)
                        elif _det(p, self.b1, x) == 0:
                            ids_list.append(-2)
                        else:
                            ids_list.append(-3 - len(points))
            if points:
                pts = _floats(points)
                ids = np.array(ids_list, dtype=np.int64)
                pts[ids == -1] = fb0
                pts[ids == -2] = fb1
                fu, fw = np.concatenate([fu, pts[0::2]]), np.concatenate([fw, pts[1::2]])
                uid, wid = np.concatenate([uid, ids[0::2]]), np.concatenate([wid, ids[1::2]])
                no = np.zeros(len(points) // 2, dtype=bool)
                zu, zw = np.concatenate([zu, no]), np.concatenate([zw, no])

        def classify(f: np.ndarray, ids: np.ndarray, on_a: np.ndarray):
            """Cone class of each point: orientation against the rays p→b0 (s0) and p→b1 (s1).
            Inside: s0 ≥ 0 ≥ s1; before the cone or behind p: s0 < 0; after it: s0 > 0 and s1 > 0
            (s0 < 0 < s1 is behind p, in the cone's opposite)."""
            z0 = (ids == -1) | (on_a & self.b0_on_a)  # exactly on the line p b0
            z1 = (ids == -2) | (on_a & self.b1_on_a)
            s0 = np.where(z0, 0, orient_filter(fp, fb0, f))
            s1 = np.where(z1, 0, orient_filter(fp, fb1, f))
            s1 = np.where(ids == -1, -1, s1)
            s0 = np.where(ids == -2, 1, s0)
            unsure = ((s0 == 0) & ~z0) | ((s1 == 0) & ~z1)
            inside = (s0 >= 0) & (s1 <= 0)
            at0, at1 = inside & z0, inside & z1  # in the direction of b0 (b1): the same point for angles
            ids = np.where(at0, -1, np.where(at1, -2, ids))
            f = np.where(at0[:, None], fb0, np.where(at1[:, None], fb1, f))
            return unsure, inside, s0 < 0, (s0 > 0) & (s1 > 0), f, ids

        o = orient_filter(fp, fu, fw)
        if np.any(o == 0):
            return False  # an edge's line passes (nearly) through p: let the exact sweep decide
        swap = o < 0  # order every edge so that its first end comes first CCW around p
        first = np.where(swap[:, None], fw, fu)
        second = np.where(swap[:, None], fu, fw)
        un1, in1, bx1, _, first, first_id = classify(
            first, np.where(swap, wid, uid), np.where(swap, zw, zu)
        )
        un2, in2, _, ax2, second, second_id = classify(
            second, np.where(swap, uid, wid), np.where(swap, zu, zw)
        )
        if np.any(un1 | un2):
            return False
        # an edge spans less than π seen from p, so it shadows the cone iff it starts inside it,
        # or starts before it (or behind p) and ends inside or after it
        shadow = in1 | (bx1 & (in2 | ax2))
        lo = np.where(in1[:, None], first, fb0)[shadow]
        lo_id = np.where(in1, first_id, -1)[shadow]
        hi = np.where(in2[:, None], second, fb1)[shadow]
        hi_id = np.where(in2, second_id, -2)[shadow]
        if len(lo) == 0:
            return False
        # right ends r that are not the cone's end: b0, and every hi strictly before b1
        before_end = orient_filter(fp, hi, fb1)
        if np.any((before_end == 0) & (hi_id != -2)):
            return False
        open_end = (before_end > 0) & (hi_id != -2)
        r = np.concatenate([fb0[None, :], hi[open_end]])
        r_id = np.concatenate([[-1], hi_id[open_end]])
        m1 = orient_filter(fp, lo[None, :, :], r[:, None, :])  # lo_j ≤ r  ⇔  m1 ≥ 0
        m2 = orient_filter(fp, r[:, None, :], hi[None, :, :])  # r < hi_j  ⇔  m2 > 0
        same_lo = lo_id[None, :] == r_id[:, None]
        same_hi = hi_id[None, :] == r_id[:, None]
        if np.any((m1 == 0) & ~same_lo) or np.any((m2 == 0) & ~same_hi):
            return False
        covered = ((m1 > 0) | same_lo) & (m2 > 0) & ~same_hi
        return bool(covered.any(axis=1).all())


def _visible_point(
    env: Environment,
    p: ExactPoint,
    b0: ExactPoint,
    b1: ExactPoint,
    blockers: list[int],
    edges: list[tuple[ExactPoint, ExactPoint]],
) -> ExactPoint | None:
    """A point q of the open segment b0b1 that p sees strictly, or None (exact).

    p lies on an open edge with b0b1 strictly on its free side, and p strictly left of b0 → b1;
    ``edges`` are all edges that may meet the triangle (p, b0, b1), none containing p. Each edge
    clipped to the closed triangle shadows a closed angular interval of the open cone (b0, b1)
    seen from p; sweep the intervals in angular order and return a point in the first gap.
    """
    tri = [p, b0, b1]
    if edges:
        keep = _edges_near_convex_subset(tri, env, blockers)
        edges = [edges[k] for k in keep]
    shadows = []
    for u, w in edges:
        clipped = _clip_to_convex(tri, u, w)
        if clipped is None:
            continue
        x, y = clipped
        if _det(p, x, y) < 0:
            x, y = y, x
        shadows.append((x, y))
    # angular order around p inside the cone (less than π wide): x before y iff det(p, x, y) > 0
    def around_p(s: tuple[ExactPoint, ExactPoint], t: tuple[ExactPoint, ExactPoint]) -> int:
        return -_sign(_det(p, s[0], t[0]))

    shadows.sort(key=cmp_to_key(around_p))
    cur = b0
    for x, y in shadows:
        if _det(p, cur, x) > 0:
            return _ray_to_segment(p, cur, x, b0, b1)
        if _det(p, cur, y) > 0:
            cur = y
    if _det(p, cur, b1) > 0:
        return _ray_to_segment(p, cur, b1, b0, b1)
    return None


def _edges_near_convex_subset(ring: Sequence[ExactPoint], env: Environment, ids: list[int]) -> list[int]:
    """Positions k in ``ids`` of the edges not certainly disjoint from the closed convex ``ring``."""
    fr = _floats(ring)
    e0, e1 = env.edge_start[ids], env.edge_end[ids]
    outside = np.zeros(len(ids), dtype=bool)
    for k in range(len(fr)):
        c, d = fr[k], fr[(k + 1) % len(fr)]
        outside |= (orient_filter(c, d, e0) < 0) & (orient_filter(c, d, e1) < 0)
    return np.flatnonzero(~outside).tolist()


def _ray_to_segment(p: ExactPoint, x: ExactPoint, y: ExactPoint, b0: ExactPoint, b1: ExactPoint) -> ExactPoint:
    """The point of line b0b1 on the ray from p strictly between the directions of x and y (< π apart)."""
    direction = _add(_sub(x, p), _sub(y, p))
    hit = line_intersection(p, _add(p, direction), b0, b1)
    assert hit is not None
    return hit


# ---------------------------------------------------------------------------------------------
# visibility polygon
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class VisibilityPiece:
    """One side of a visibility polygon, from ``a`` to ``b`` in the polygon's CCW order.

    kind
        ``"edge"`` — a whole polygon edge ``edge``; ``"partial"`` — part of edge ``edge``;
        ``"constructed"`` — a window (Ghosh et al., "Online algorithms with discrete visibility"): it lies on the ray from the viewpoint through the
        reflex vertex ``reflex_vertex`` = u, which is one end of the piece, and runs from u to the
        first boundary point u′ beyond u on that ray. Ring order may run u → u′ (going outward) or
        u′ → u (coming back); ``reflex_vertex`` says which end is u.
    edge
        Global edge id for ``"edge"`` and ``"partial"`` pieces (traversed in the edge's direction),
        else None.
    reflex_vertex
        Global vertex id of u for ``"constructed"`` pieces, else None.
    """

    kind: Literal["edge", "partial", "constructed"]
    a: ExactPoint
    b: ExactPoint
    edge: int | None
    reflex_vertex: int | None


@dataclass(frozen=True, slots=True)
class VisibilityPolygon:
    """The visibility polygon of ``viewpoint``: an exact CCW ring and its labelled sides.

    ``pieces[k]`` runs from ``ring[k]`` to ``ring[k + 1]`` (cyclically). The region is the closure
    of the points the viewpoint sees strictly; see :func:`visibility_polygon`.
    """

    viewpoint: ExactPoint
    ring: tuple[ExactPoint, ...]
    pieces: tuple[VisibilityPiece, ...]

    @property
    def area(self) -> Fraction:
        """Exact area (shoelace)."""
        ring = self.ring
        total = Fraction(0)
        for k in range(len(ring)):
            (x0, y0), (x1, y1) = ring[k], ring[(k + 1) % len(ring)]
            total += x0 * y1 - x1 * y0
        return total / 2

    def contains(self, q: Sequence[object]) -> bool:
        """Is q in the closed visibility polygon (boundary included)? Exact."""
        return point_in_ring(exact_point(q, where="point"), self.ring) >= 0


def visibility_polygon(env: Environment, p: Sequence[object]) -> VisibilityPolygon:
    """The visibility polygon of the point p: interior point, boundary point or vertex. Exact.

    The region is the closure of {q : p sees q strictly}, i.e. the classical visibility polygon
    without its zero-width "antennas": where the rays from p pass exactly between two obstacles
    (grazing a vertex of each from opposite sides) the segment beyond is seen by :func:`sees` but is
    not part of the region. It is star-shaped from p, given as a CCW ring with one labelled piece
    per side: whole edges, partial edges and constructed edges (windows u → u′). Rays
    through several vertices are cut at each of them, so a window always runs from a reflex vertex
    to the first boundary point beyond it. When p is on the boundary the ring passes through p and
    the two sides at p are (parts of) the edges at p.

    Algorithm: sort the directions from p to all vertices exactly (within the free wedge at p when p
    is on the boundary); in every open wedge between consecutive directions no vertex is seen, so
    one ray cast (exact, :func:`~solverplan.geometry.raycast.cast_ray`) in a direction strictly
    inside it finds the single edge seen there. The polygon alternates those edge pieces (their
    ends are the intersections of the wedge's bounding rays with the edge's line) with radial
    pieces along the critical rays, cut at the vertices on them. O(n log n) for sorting plus
    n exact ray casts of O(n) numpy work each: O(n²) overall.

    Raises
    ------
    InputError
        If p is not in the closed free space.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [2, 0], [2, 2], [0, 2]])
    >>> vp = visibility_polygon(square, (1, 0))                  # on the bottom edge
    >>> [piece.kind for piece in vp.pieces], vp.area
    (['partial', 'edge', 'edge', 'edge', 'partial'], Fraction(4, 1))
    >>> vp.contains((2, 2)), vp.contains((3, 1))
    (True, False)
    """
    if isinstance(p, tuple) and len(p) == 2 and type(p[0]) is Fraction and type(p[1]) is Fraction:
        # an exact point the library computed (a viewpoint chained from window to window) may need a longer
        # denominator than input may have: only input text and floats are held to the documented resolution
        p = (p[0], p[1])
    else:
        p = exact_point(p, where="viewpoint")
    kind, idx = _locate(env, p)
    if kind == "out":
        raise InputError(f"viewpoint {format_point(p)} is not in the free space")
    verts, nxt, prv = env.exact_vertices, env.next_vertex, env.prev_vertex
    span: tuple[ExactPoint, ExactPoint] | None = None
    apex_edges: tuple[int, ...] = ()
    apex_vertex: int | None = None
    if kind == "e":
        e = env.edge(idx)
        span = (_sub(e.b, e.a), _sub(e.a, e.b))
        apex_edges = (idx,)
    elif kind == "v":
        span = (_sub(verts[int(nxt[idx])], p), _sub(verts[int(prv[idx])], p))
        apex_edges = (idx, int(prv[idx]))
        apex_vertex = idx

    # directions to every vertex, grouped exactly (key: direction scaled to max-norm 1)
    groups: dict[ExactPoint, list[tuple[Fraction, int]]] = {}
    for v, x in enumerate(verts):
        if x == p:
            continue
        d = _sub(x, p)
        m = max(abs(d[0]), abs(d[1]))
        groups.setdefault((d[0] / m, d[1] / m), []).append((m, v))
    keys = list(groups)
    if span is not None:
        keys = [k for k in keys if _angle_cmp(span[0], k, span[1]) <= 0]
    ref = span[0] if span is not None else keys[0]
    def from_ref(u: ExactPoint, w: ExactPoint) -> int:
        return _angle_cmp(ref, u, w)

    keys.sort(key=cmp_to_key(from_ref))
    for key in keys:
        groups[key].sort()
    n_keys = len(keys)
    if span is not None and not (_same_direction(keys[0], span[0]) and _same_direction(keys[-1], span[1])):
        raise SolverFailed(f"visibility polygon of {format_point(p)}: the free wedge is not bounded by vertices")

    def along(k: int, x: ExactPoint) -> Fraction:
        """Position of x on ray k, in the units of the group keys (max-norm distance)."""
        key = keys[k]
        c = 0 if abs(key[0]) == 1 else 1
        return (x[c] - p[c]) / key[c]

    # the edge seen in each open wedge between consecutive directions
    n_wedges = n_keys if span is None else n_keys - 1
    seen: list[int] = []
    for k in range(n_wedges):
        u, w = keys[k], keys[(k + 1) % n_keys]
        mid = _add(u, w) if cross(u, w) > 0 else (-u[1], u[0])
        hit = cast_ray(env, p, mid)
        if hit.vertex is not None:  # pragma: no cover - no vertex lies strictly inside a wedge
            raise SolverFailed(f"visibility polygon of {format_point(p)}: wedge ray hit vertex {hit.vertex}")
        seen.append(hit.edge)

    def on_ray(k: int, edge: int) -> ExactPoint:
        a, b = verts[edge], verts[int(nxt[edge])]
        x = line_intersection(p, _add(p, keys[k]), a, b)
        if x is None:  # pragma: no cover - an edge seen in a wedge is not parallel to its rays
            raise SolverFailed(f"visibility polygon of {format_point(p)}: edge {edge} is parallel to a wedge ray")
        return x

    raw: list[list] = []  # [a, b, kind, edge, reflex_vertex]

    def radial(k: int, x_start: ExactPoint, x_end: ExactPoint) -> None:
        """Pieces along ray k from x_start to x_end (ring order), cut at the vertices on the ray."""
        if x_start == x_end:
            return
        m0, m1 = along(k, x_start), along(k, x_end)
        lo, hi = min(m0, m1), max(m0, m1)
        on = groups[keys[k]]
        ident = {m: v for m, v in on}
        inner = [(m, v) for m, v in on if lo < m < hi]
        if m0 > m1:
            inner.reverse()

        def vertex_at(x: ExactPoint, m: Fraction) -> int | None:
            return apex_vertex if x == p else ident.get(m)

        stops = [(x_start, m0, vertex_at(x_start, m0))]
        stops += [(verts[v], m, v) for m, v in inner]
        stops.append((x_end, m1, vertex_at(x_end, m1)))
        for (x, mx, vx), (y, my, vy) in zip(stops, stops[1:]):
            candidates = set(apex_edges)
            for v in (vx, vy):
                if v is not None:
                    candidates |= {v, int(prv[v])}
            centre = _mid(x, y)
            edge = next((i for i in sorted(candidates) if on_segment(centre, verts[i], verts[int(nxt[i])])), None)
            if edge is not None:
                raw.append([x, y, "edge", edge, None])
                continue
            near = vx if mx < my else vy
            if near is None or (near == apex_vertex):  # pragma: no cover - windows start at vertices
                raise SolverFailed(f"visibility polygon of {format_point(p)}: window without a reflex vertex")
            raw.append([x, y, "constructed", None, near])

    def wedge_edge(k: int) -> None:
        edge = seen[k]
        x, y = on_ray(k, edge), on_ray((k + 1) % n_keys, edge)
        if x != y:
            raw.append([x, y, "edge", edge, None])

    if span is None:
        for k in range(n_keys):
            radial(k, on_ray(k, seen[k - 1]), on_ray(k, seen[k]))
            wedge_edge(k)
    else:
        radial(0, p, on_ray(0, seen[0]))
        for k in range(n_wedges):
            if k:
                radial(k, on_ray(k, seen[k - 1]), on_ray(k, seen[k]))
            wedge_edge(k)
        radial(n_keys - 1, on_ray(n_keys - 1, seen[-1]), p)

    # merge consecutive pieces of one edge (a hidden vertex direction splits nothing)
    merged: list[list] = []
    for piece in raw:
        last = merged[-1] if merged else None
        if last and last[2] == piece[2] == "edge" and last[3] == piece[3] and last[1] == piece[0]:
            last[1] = piece[1]
        else:
            merged.append(piece)
    if span is None and len(merged) > 1:
        first, last = merged[0], merged[-1]
        if first[2] == last[2] == "edge" and first[3] == last[3] and last[1] == first[0]:
            first[0] = last[0]
            merged.pop()
    pieces = []
    for k, (a, b, kind_, edge, reflex) in enumerate(merged):
        if b != merged[(k + 1) % len(merged)][0]:  # pragma: no cover - internal consistency
            raise SolverFailed(f"visibility polygon of {format_point(p)}: ring is not closed at {format_point(b)}")
        if kind_ == "edge" and not (a == verts[edge] and b == verts[int(nxt[edge])]):
            kind_ = "partial"
        pieces.append(VisibilityPiece(kind_, a, b, edge, reflex))
    return VisibilityPolygon(p, tuple(piece.a for piece in pieces), tuple(pieces))
