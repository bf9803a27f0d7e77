"""Exact 2-D predicates and constructions for the certificate checker, on rational points.

Every function takes and returns :class:`fractions.Fraction` coordinates (or ints) and decides its
answer by exact sign tests: orientations, where two lines meet, whether closed segments meet, whether
a point is inside a ring, the convex hull of a point set, the part of a segment inside a convex polygon
(the swept regions of moves), and covering of intervals by unions of intervals.

Like :mod:`solverplan.certify.check`, this module imports only the standard library (and the point
type of :mod:`solverplan.certify.schema`): the checker must not share a line of geometry with the
planner, so that a bug there cannot hide a bug here.

>>> from fractions import Fraction as F
>>> orient((F(0), F(0)), (F(1), F(0)), (F(0), F(1)))
1
>>> line_hit((F(0), F(0)), (F(1), F(1)), (F(0), F(2)), (F(1), F(0)))  # y = x meets y = 2 at s = 2, τ = 2
(Fraction(2, 1), Fraction(2, 1))
"""

from __future__ import annotations

from fractions import Fraction
from typing import Iterable, Sequence

from solverplan.certify.schema import Point

__all__ = [
    "sub",
    "cross",
    "dot",
    "along",
    "orient",
    "sign",
    "line_hit",
    "affine_coefficients",
    "convex_hull",
    "clip_segment",
    "on_closed_segment",
    "segments_meet",
    "inside_ring",
    "signed_area2",
    "uncovered",
    "union",
]

_ZERO = Fraction(0)
_ONE = Fraction(1)


# ======================================================================= vectors
def sub(u: Point, v: Point) -> Point:
    """u − v."""
    return (u[0] - v[0], u[1] - v[1])


def cross(u: Point, v: Point) -> Fraction:
    """The z-component of u × v: positive iff v is counter-clockwise of u."""
    return u[0] * v[1] - u[1] * v[0]


def dot(u: Point, v: Point) -> Fraction:
    return u[0] * v[0] + u[1] * v[1]


def along(a: Point, e: Point, t: Fraction) -> Point:
    """The point a + t·e."""
    return (a[0] + t * e[0], a[1] + t * e[1])


def orient(a: Point, b: Point, c: Point) -> int:
    """+1 if a, b, c turn counter-clockwise, −1 if clockwise, 0 if collinear."""
    return sign(cross(sub(b, a), sub(c, a)))


def sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


# ======================================================================= rays and maps
def line_hit(origin: Point, d: Point, c: Point, e: Point) -> tuple[Fraction, Fraction] | None:
    """Where the line origin + s·d meets the line c + τ·e: ``(s, τ)`` exactly, ``None`` if parallel.

    From origin + s d = c + τ e: s = cross(c − origin, e) / cross(d, e), τ = cross(origin − c, d) / cross(e, d).
    """
    den = cross(e, d)
    if den == 0:
        return None
    s = cross(sub(c, origin), e) / -den
    tau = cross(sub(origin, c), d) / den
    return (s, tau)


def affine_coefficients(a: Point, e_s: Point, c: Point, e_t: Point, d: Point) -> tuple[Fraction, Fraction]:
    """(α, β) of the exact map t ↦ α t + β from the source edge a + t·e_s to the target line c + τ·e_t
    along the direction d (the paper's transition map for a fixed heading): α = cross(e_s, d)/cross(e_t, d), β = cross(a − c, d)/cross(e_t, d)."""
    den = cross(e_t, d)
    if den == 0:
        raise ZeroDivisionError("direction parallel to the target edge")
    return (cross(e_s, d) / den, cross(sub(a, c), d) / den)


# ======================================================================= polygons
def convex_hull(points: Iterable[Point]) -> list[Point]:
    """Counter-clockwise convex hull, collinear points dropped, from the lexicographically least point
    (gift wrapping, exact).

    The least point (smallest x, then smallest y) is a corner of the hull. From a corner p the next corner is
    the point q with no point strictly to the right of the line p → q, the farthest from p among those collinear
    with it (so points inside a hull edge are skipped); the walk ends back at the first corner. Points all on one
    line give the two ends of their segment, fewer than three distinct points themselves.

    >>> convex_hull([(0, 0), (2, 0), (1, 0), (2, 2), (1, 1), (0, 2)])
    [(0, 0), (2, 0), (2, 2), (0, 2)]
    """
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts
    hull = [pts[0]]
    while True:
        p = hull[-1]
        q = pts[0] if p != pts[0] else pts[1]
        for r in pts:
            turn = orient(p, q, r)
            if turn < 0 or (turn == 0 and dot(sub(r, p), sub(r, p)) > dot(sub(q, p), sub(q, p))):
                q = r
        if q == hull[0]:
            return hull
        hull.append(q)


def clip_segment(a: Point, b: Point, hull: Sequence[Point]) -> tuple[Fraction, Fraction] | None:
    """Parameters [λ0, λ1] ⊂ [0, 1] of the part of the closed segment a + λ(b − a) inside the closed
    convex polygon ``hull`` (counter-clockwise), or ``None`` if they do not meet (Liang–Barsky, exact)."""
    lo, hi = _ZERO, _ONE
    m = len(hull)
    for i in range(m):
        h0, h1 = hull[i], hull[(i + 1) % m]
        edge = sub(h1, h0)
        f0 = cross(edge, sub(a, h0))
        f1 = cross(edge, sub(b, h0))
        if f0 < 0 and f1 < 0:
            return None
        if f0 >= 0 and f1 >= 0:
            continue
        lam = f0 / (f0 - f1)
        if f0 < 0:
            lo = max(lo, lam)
        else:
            hi = min(hi, lam)
        if lo > hi:
            return None
    return (lo, hi)


def on_closed_segment(p: Point, a: Point, b: Point) -> bool:
    """Does p lie on the closed segment ab?"""
    return (
        orient(a, b, p) == 0
        and min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
        and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])
    )


def segments_meet(a: Point, b: Point, c: Point, d: Point) -> bool:
    """Do the closed segments ab and cd share a point?"""
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return (
        (o1 == 0 and on_closed_segment(c, a, b))
        or (o2 == 0 and on_closed_segment(d, a, b))
        or (o3 == 0 and on_closed_segment(a, c, d))
        or (o4 == 0 and on_closed_segment(b, c, d))
    )


def inside_ring(p: Point, ring: Sequence[Point]) -> bool:
    """Is p strictly inside the simple ring? (p must not lie on it; crossing number.)"""
    inside = False
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if (a[1] > p[1]) != (b[1] > p[1]):
            side = orient(a, b, p)
            if (b[1] > a[1] and side > 0) or (b[1] < a[1] and side < 0):
                inside = not inside
    return inside


def signed_area2(ring: Sequence[Point]) -> Fraction:
    """Twice the signed area of the ring: positive iff it is counter-clockwise."""
    return sum((cross(ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))), _ZERO)


# ======================================================================= intervals
def uncovered(lo: Fraction, hi: Fraction, covers: Iterable[tuple[Fraction, Fraction]]) -> tuple[Fraction, Fraction] | None:
    """The first part of [lo, hi] not covered by the union of the closed intervals, or ``None``."""
    current = lo
    for p, q in sorted(covers):
        if current >= hi:
            return None
        if p > current:
            return (current, min(p, hi))
        current = max(current, q)
    return None if current >= hi else (current, hi)


def union(intervals: Iterable[tuple[Fraction, Fraction]]) -> list[tuple[Fraction, Fraction]]:
    """The union of closed intervals as sorted, disjoint closed intervals (touching ones merged)."""
    merged: list[tuple[Fraction, Fraction]] = []
    for p, q in sorted(intervals):
        if merged and p <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], q))
        else:
            merged.append((p, q))
    return merged
