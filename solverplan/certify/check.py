"""The independent exact checker of certificates.

This module re-derives every claim of a :class:`~solverplan.certify.schema.Certificate` in rational
arithmetic. It imports only the standard library (``fractions``, ``dataclasses``, ``typing``) and
:mod:`solverplan.certify.schema`; it uses no floats, no planner, no graph builder and no geometry
kernel of solverplan, so a bug there cannot hide a bug here (``tests/certify/test_check.py`` keeps
it so with an ``ast`` test).

What is checked
---------------
1. **Environment.** Each ring has ≥ 3 vertices and no repeated consecutive vertex; the outer ring is
   counter-clockwise and every hole clockwise (exact signed areas), so the free space is on the left
   of every directed edge; no two edges meet except neighbours at their shared vertex (every pair
   of edges, exactly); every hole lies inside the outer ring and outside the other holes.
2. **Segments and sets.** Each named segment lies on its edge (``a``, ``b`` are the points of ``t0``,
   ``t1``); start, goal and position pieces are intervals of existing edges.
3. **Moves** (each stage, each move) — with source points P, Q (parameters p < q on edge e, vector E),
   cone d_lo → d_hi, target edge e′ (line L) and target range (segment or edge) τ ∈ [lo, hi]:

   - both directions leave e into the free space: cross(E, d) > 0; the cone turns counter-clockwise
     from d_lo to d_hi: cross(d_lo, d_hi) ≥ 0 (with both directions on the left of E, the turn is
     then in [0, π));
   - the four **corner rays** X + s·d (X ∈ {P, Q}, d ∈ {d_lo, d_hi}) meet L at s > 0 strictly
     inside the open target range. A source end that is a vertex of P (p = 0 or q = 1) is not a
     robot position: its rays need only s ≥ 0 and the closed range, since the positions next to it
     land next to its hit, on the inner side (the hit parameter is affine and strictly monotone in
     the source parameter). This is what admits adjacent edges (paper Cor. 1), where the shared
     vertex is its own hit (s = 0);
   - the claimed ``target`` [c, d] is either the whole target range or exactly the image
     [min τ, max τ] of the corner rays (so it holds every landing point, and says nothing more);
   - the **swept region**. All rays from [P, Q] with directions in the cone that stop at L form
     R = (PQ ⊕ cone) ∩ {the side of L facing the source}: a Minkowski sum of a segment and a
     convex cone, cut by a half-plane, hence convex, and equal to the convex hull of P, Q and the
     four corner hits. The move is sound if no boundary point other than those it must touch lies
     in R: every environment edge is clipped exactly against R (Liang–Barsky on the hull's
     half-planes) and
       * the source edge e may meet R only within [P, Q] (R ∩ line(e) = PQ, since R is on the
         left of e), the target edge e′ only within the target range (R ∩ L is the hull of the hits);
       * any other edge must miss R entirely, except that it may touch R in the single point P
         (or Q) when that end is a vertex of P — the neighbour edge of e meeting it there.
     Then the interior of R holds no boundary point; it is connected and, near the middle of PQ, on
     the free side of e, so it is free space; the sides of R from P and Q hold no boundary point
     either, so every trajectory from a robot position in [P, Q] runs through free space and first
     meets the boundary on the open target range. The check is conservative at exact grazing
     contacts (a wall parallel to a cone side through a vertex end, a corner ray through a vertex of
     P): those certificates are rejected, never wrongly accepted.
4. **Chaining.** The rule is *coverage*: the targets of stage k are covered by the union of the
   sources of stage k + 1 on the same edge (closed intervals; a stage may have more sources than the
   previous stage can reach, and one target may be covered by several sources); stage 0's sources
   cover the start set; the last stage's targets lie in the goal set (plans, funnels) or are covered
   by the first cycle stage's sources (cycles: the cycle closes). Every end of a source must be
   accounted for — an end of its edge or of a named segment, an end of a set flowing into the stage
   (the start set; the previous stage's targets; for the first cycle stage also the last stage's) or
   of another source of the stage on that edge (a split) — so a source says nothing gratuitous.
   Given the query (``expected_start``, ``expected_goal``), the start and goal sets must be exactly it.
5. **Headings.** A robot executes one heading θ measured from the edge it is on, so a stage's action
   interval is the set of headings common to its moves' cones, each measured from its own source
   edge: [max_j θ(d_lo,j), min_m θ(d_hi,m)]. It must be non-empty (exactly: the sign of a cross
   product); a claimed ``interval`` must lie inside it; ``claims.min_width`` must not exceed any
   stage's width; ``tolerance`` = min_width / 2 exactly; ``bounces`` = number of stages. Decimal
   claims must also be *tight*: within 10⁻⁹ of the exact value, and so must each move's cone be
   to the stage's common cone (a certificate claims what it proves; a loosened or a gratuitously
   widened number is as wrong as an inflated one, and tampering with any single number is caught).
6. **Positions** (funnels): the claimed positions after a stage equal the union of the exact images
   [min τ, max τ] of its moves.
7. **Cycles.** Every cycle stage has one move; the exact affine map of a direction d from source
   parameter t to target parameter τ is τ = α t + β with α = cross(E_s, d) / cross(E_t, d),
   β = cross(A − C, d) / cross(E_t, d) (A, C the first vertices, E_s, E_t the vectors of the source
   and target edges). The composed return map of the nominal directions must equal the claimed
   α, β; the fixed point must be β / (1 − α) and lie in the entry source; the claimed contraction must
   equal the worst case Π_k max(|α_k(d_lo)|, |α_k(d_hi)|) and be < 1. **Why the cone's extremes
   suffice:** every direction of the cone is a positive multiple of d(λ) = (1 − λ) d_lo + λ d_hi,
   λ ∈ [0, 1]; α is homogeneous of degree 0 in d, so α(d(λ)) is a ratio of two functions linear in
   λ; the denominator cross(E_t, d(λ)) vanishes nowhere on [0, 1] (every direction of a sound cone
   meets L) and the numerator cross(E_s, d(λ)) is positive (every direction leaves e into the free
   space). A linear-fractional function with a non-vanishing denominator is monotone on an interval,
   so |α| over the cone is largest at d_lo or d_hi — the exact, trigonometry-free form of the
   monotonicity of the contraction coefficient C(θ, φ) (Lemma 2). Choices at different
   bounces are independent and |α| of a composition is the product, so the worst case of the cycle
   is the product of the per-stage worst cases.
8. **Optimality.** The bound of a search or LP is not re-derived here (that would mean re-running the
   planner); its consistency with the checked claims is, and the report lists it as not checked.

Exactness
---------
Everything above is rational arithmetic on the certificate's numbers (``fractions.Fraction``), except
the angles of 5. Those are decided with rigorous rational enclosures of atan: the alternating series
Σ (−1)^k w^(2k+1) / (2k+1) for |w| ≤ 1/16 lies between consecutive partial sums (its terms decrease
in size), the argument is reduced exactly by atan x = π/2 − atan(1/x) (x > 1) and
atan x = atan c + atan((x − c)/(1 + c x)) with c = k/8 nearest to x; atan(k/8) and π (Machin's
formula) are themselves enclosed by series; arguments with huge denominators are rounded outward to
dyadic rationals (atan is increasing). A comparison of an angle with a rational number is refined
(64, 128, … bits) until the enclosure excludes the number. It always terminates: the heading of a
rational vector that is not along the positive x-axis is transcendental (Lindemann–Weierstrass), so
it never equals a rational; differences of two headings are reduced to the heading of one rational
vector (the "quotient" of the two), so the same holds, and the one exact tie (angle 0, identical
directions) is decided by a cross product.

>>> from solverplan.certify.schema import Certificate, EXAMPLE
>>> report = check_certificate(Certificate.from_json(EXAMPLE))
>>> report.valid, dict(report.checked)["corner_rays"]
(True, 4)
>>> lo, hi = atan_enclosure(Fraction(1))
>>> Fraction(7853981633974483, 10**16) < lo <= hi < Fraction(7853981633974484, 10**16)   # π/4 = 0.78539816339744830961...
True
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Iterable, Sequence

from solverplan.certify.schema import (
    Certificate,
    CycleClaim,
    Move,
    Piece,
    Point,
    SegmentRecord,
    Stage,
    number_text,
    point_text,
)

__all__ = [
    "Failure",
    "CheckReport",
    "check_certificate",
    "atan_enclosure",
    "pi_enclosure",
    "angle_enclosure",
    "heading_vector",
    "heading_enclosure",
    "compare_angle",
    "line_hit",
    "affine_coefficients",
    "WIDTH_SLACK",
    "MAX_BITS",
]

WIDTH_SLACK = Fraction(1, 10**9)
"""How far below the exact value a claimed width (or inside the cone a claimed interval end) may be."""

MAX_BITS = 1 << 14
"""Largest precision (bits) tried when deciding an angle comparison; never reached in practice."""

_ZERO = Fraction(0)
_ONE = Fraction(1)


class Undecided(ArithmeticError):
    """An angle comparison could not be decided within :data:`MAX_BITS` bits."""


# ======================================================================= vectors
def _sub(u: Point, v: Point) -> Point:
    return (u[0] - v[0], u[1] - v[1])


def _cross(u: Point, v: Point) -> Fraction:
    return u[0] * v[1] - u[1] * v[0]


def _dot(u: Point, v: Point) -> Fraction:
    return u[0] * v[0] + u[1] * v[1]


def _along(a: Point, e: Point, t: Fraction) -> Point:
    return (a[0] + t * e[0], a[1] + t * e[1])


def _orient(a: Point, b: Point, c: Point) -> int:
    det = _cross(_sub(b, a), _sub(c, a))
    return (det > 0) - (det < 0)


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


# ======================================================================= rigorous atan
_ATAN_CACHE: dict[tuple[str, int, int], tuple[Fraction, Fraction]] = {}


def _series(w: Fraction, bits: int) -> tuple[Fraction, Fraction]:
    """Enclosure of atan(w) for |w| ≤ 1/2 from the alternating series; width ≤ 2^-bits.

    Its terms w^(2k+1)/(2k+1) shrink in size, so atan(w) lies between consecutive partial sums
    (Leibniz); we stop once the next term is at most 2^-bits.
    """
    if w == 0:
        return (_ZERO, _ZERO)
    eps = Fraction(1, 1 << bits)
    w2 = w * w
    power = w
    total = _ZERO
    k = 0
    while True:
        term = power / (2 * k + 1)
        signed = term if k % 2 == 0 else -term
        if abs(term) <= eps:
            nxt = total + signed
            return (min(total, nxt), max(total, nxt))
        total += signed
        power *= w2
        k += 1


def _small(w: Fraction, bits: int) -> tuple[Fraction, Fraction]:
    """atan(w) for |w| ≤ 1/16; w with a large denominator is first rounded outward to a dyadic rational."""
    scale = 1 << (bits + 2)
    if w.denominator > scale:
        lo_w = Fraction((w.numerator * scale) // w.denominator, scale)
        hi_w = Fraction(-((-w.numerator * scale) // w.denominator), scale)
        return (_series(lo_w, bits + 1)[0], _series(hi_w, bits + 1)[1])
    return _series(w, bits + 1)


def pi_enclosure(bits: int = 64) -> tuple[Fraction, Fraction]:
    """lo ≤ π ≤ hi with hi − lo ≤ 2^-bits (Machin: π = 16 atan(1/5) − 4 atan(1/239)).

    >>> lo, hi = pi_enclosure(64)
    >>> lo < Fraction(355, 113) and hi - lo <= Fraction(1, 2**64)
    True
    """
    key = ("pi", 0, bits)
    if key not in _ATAN_CACHE:
        a_lo, a_hi = _series(Fraction(1, 5), bits + 6)
        b_lo, b_hi = _series(Fraction(1, 239), bits + 6)
        _ATAN_CACHE[key] = (16 * a_lo - 4 * b_hi, 16 * a_hi - 4 * b_lo)
    return _ATAN_CACHE[key]


def _atan_eighth(k: int, bits: int) -> tuple[Fraction, Fraction]:
    """atan(k/8) for k = 0..8: series for k ≤ 4, atan(1/2) + atan(2(k − 4)/(16 + k)) for 5..7, π/4 for 8."""
    key = ("eighth", k, bits)
    if key not in _ATAN_CACHE:
        if k == 0:
            value = (_ZERO, _ZERO)
        elif k <= 4:
            value = _series(Fraction(k, 8), bits + 1)
        elif k < 8:
            h_lo, h_hi = _series(Fraction(1, 2), bits + 2)
            r_lo, r_hi = _series(Fraction(2 * (k - 4), 16 + k), bits + 2)
            value = (h_lo + r_lo, h_hi + r_hi)
        else:
            p_lo, p_hi = pi_enclosure(bits + 1)
            value = (p_lo / 4, p_hi / 4)
        _ATAN_CACHE[key] = value
    return _ATAN_CACHE[key]


def atan_enclosure(x: Fraction | int, bits: int = 64) -> tuple[Fraction, Fraction]:
    """Rational lo ≤ atan(x) ≤ hi, with hi − lo ≤ 2^(2 − bits) (about 2e-19 at the default 64 bits).

    Exact argument reduction: atan is odd; atan x = π/2 − atan(1/x) for x > 1; for 0 < x ≤ 1,
    atan x = atan c + atan w with c = k/8 the nearest eighth and w = (x − c)/(1 + c x), |w| ≤ 1/16.

    >>> lo, hi = atan_enclosure(Fraction(1, 3))
    >>> Fraction(3217505543966421, 10**16) < lo <= hi < Fraction(3217505543966422, 10**16)   # 0.32175055439664219340...
    True
    >>> hi - lo < Fraction(1, 10**18)
    True
    """
    x = Fraction(x)
    if x < 0:
        lo, hi = atan_enclosure(-x, bits)
        return (-hi, -lo)
    if x == 0:
        return (_ZERO, _ZERO)
    if x > 1:
        lo, hi = atan_enclosure(1 / x, bits + 1)
        p_lo, p_hi = pi_enclosure(bits + 1)
        return (p_lo / 2 - hi, p_hi / 2 - lo)
    k = (16 * x.numerator + x.denominator) // (2 * x.denominator)  # round(8x), 0..8
    c = Fraction(k, 8)
    w = (x - c) / (1 + c * x)
    c_lo, c_hi = _atan_eighth(k, bits + 1)
    w_lo, w_hi = _small(w, bits + 1)
    return (c_lo + w_lo, c_hi + w_hi)


def angle_enclosure(v: Point, bits: int = 64) -> tuple[Fraction, Fraction]:
    """Enclosure of the angle of the non-zero vector v = (x, y), in (−π, π] (atan2(y, x)).

    For y ≠ 0: atan2(y, x) = ±π/2 − atan(x / y) (sign of y); (x, 0) gives 0 or π.

    >>> angle_enclosure((Fraction(1), Fraction(0)))
    (Fraction(0, 1), Fraction(0, 1))
    """
    x, y = Fraction(v[0]), Fraction(v[1])
    if y == 0:
        if x > 0:
            return (_ZERO, _ZERO)
        if x < 0:
            return pi_enclosure(bits)
        raise ValueError("the zero vector has no angle")
    a_lo, a_hi = atan_enclosure(x / y, bits + 1)
    p_lo, p_hi = pi_enclosure(bits + 1)
    if y > 0:
        return (p_lo / 2 - a_hi, p_hi / 2 - a_lo)
    return (-p_hi / 2 - a_hi, -p_lo / 2 - a_lo)


def heading_vector(edge_vector: Point, d: Point) -> Point:
    """The direction d in the frame of an edge: (dot(E, d), cross(E, d)); its angle is the heading θ
    of d measured counter-clockwise from E, exactly as a rational vector."""
    return (_dot(edge_vector, d), _cross(edge_vector, d))


def heading_enclosure(edge_vector: Point, d: Point, bits: int = 64) -> tuple[Fraction, Fraction]:
    """Enclosure of the heading (radians, CCW from the directed edge) of direction d."""
    return angle_enclosure(heading_vector(edge_vector, d), bits)


def compare_angle(v: Point, r: Fraction) -> int:
    """Exact sign of angle(v) − r for a non-zero rational vector v and a rational r.

    Refines the enclosure from 64 bits, doubling, until it excludes r; the only possible tie (angle 0,
    v along +x) is decided exactly. Raises :class:`Undecided` beyond :data:`MAX_BITS`.
    """
    r = Fraction(r)
    if v[1] == 0 and v[0] > 0:
        return _sign(-r)
    bits = 64
    while True:
        lo, hi = angle_enclosure(v, bits)
        if lo > r:
            return 1
        if hi < r:
            return -1
        if bits >= MAX_BITS:
            raise Undecided(f"the angle of {point_text(v)} is within 2^-{bits} of {number_text(r)}")
        bits *= 2


def _difference_vector(w_from: Point, w_to: Point) -> Point:
    """A rational vector whose angle is angle(w_to) − angle(w_from), for angles in (0, π)."""
    return (_dot(w_from, w_to), _cross(w_from, w_to))


# ======================================================================= rays and maps
def line_hit(origin: Point, d: Point, c: Point, e: Point) -> tuple[Fraction, Fraction] | None:
    """Where the line origin + s·d meets the line c + τ·e: ``(s, τ)`` exactly, ``None`` if parallel.

    From origin + s d = c + τ e: s = cross(c − origin, e) / cross(d, e), τ = cross(origin − c, d) / cross(e, d).
    """
    den = _cross(e, d)
    if den == 0:
        return None
    s = _cross(_sub(c, origin), e) / -den
    tau = _cross(_sub(origin, c), d) / den
    return (s, tau)


def affine_coefficients(a: Point, e_s: Point, c: Point, e_t: Point, d: Point) -> tuple[Fraction, Fraction]:
    """(α, β) of the exact map t ↦ α t + β from the source edge a + t·e_s to the target line c + τ·e_t
    along the direction d: α = cross(e_s, d)/cross(e_t, d), β = cross(a − c, d)/cross(e_t, d)."""
    den = _cross(e_t, d)
    if den == 0:
        raise ZeroDivisionError("direction parallel to the target edge")
    return (_cross(e_s, d) / den, _cross(_sub(a, c), d) / den)


# ======================================================================= small exact geometry
def _convex_hull(points: Iterable[Point]) -> list[Point]:
    """Counter-clockwise convex hull, collinear points dropped (Andrew's monotone chain, exact)."""
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def chain(seq: Sequence[Point]) -> list[Point]:
        out: list[Point] = []
        for p in seq:
            while len(out) >= 2 and _cross(_sub(out[-1], out[-2]), _sub(p, out[-2])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    return lower[:-1] + upper[:-1]


def _clip(a: Point, b: Point, hull: Sequence[Point]) -> tuple[Fraction, Fraction] | None:
    """Parameters [λ0, λ1] ⊂ [0, 1] of the part of the closed segment a + λ(b − a) inside the closed
    convex polygon ``hull`` (counter-clockwise), or ``None`` if they do not meet (Liang–Barsky, exact)."""
    lo, hi = _ZERO, _ONE
    m = len(hull)
    for i in range(m):
        h0, h1 = hull[i], hull[(i + 1) % m]
        edge = _sub(h1, h0)
        f0 = _cross(edge, _sub(a, h0))
        f1 = _cross(edge, _sub(b, h0))
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


def _on_closed_segment(p: Point, a: Point, b: Point) -> bool:
    return (
        _orient(a, b, p) == 0
        and min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
        and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])
    )


def _segments_meet(a: Point, b: Point, c: Point, d: Point) -> bool:
    """Do the closed segments ab and cd share a point? (exact)"""
    o1, o2 = _orient(a, b, c), _orient(a, b, d)
    o3, o4 = _orient(c, d, a), _orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return (
        (o1 == 0 and _on_closed_segment(c, a, b))
        or (o2 == 0 and _on_closed_segment(d, a, b))
        or (o3 == 0 and _on_closed_segment(a, c, d))
        or (o4 == 0 and _on_closed_segment(b, c, d))
    )


def _inside_ring(p: Point, ring: Sequence[Point]) -> bool:
    """Is p strictly inside the simple ring? (p is known not to lie on it; crossing number, exact)"""
    inside = False
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if (a[1] > p[1]) != (b[1] > p[1]):
            side = _orient(a, b, p)
            if (b[1] > a[1] and side > 0) or (b[1] < a[1] and side < 0):
                inside = not inside
    return inside


def _signed_area2(ring: Sequence[Point]) -> Fraction:
    return sum((_cross(ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))), _ZERO)


def _uncovered(lo: Fraction, hi: Fraction, covers: Iterable[tuple[Fraction, Fraction]]) -> tuple[Fraction, Fraction] | None:
    """The first part of [lo, hi] not covered by the union of the closed intervals, or ``None``."""
    current = lo
    for p, q in sorted(covers):
        if current >= hi:
            return None
        if p > current:
            return (current, min(p, hi))
        current = max(current, q)
    return None if current >= hi else (current, hi)


def _union(intervals: Iterable[tuple[Fraction, Fraction]]) -> list[tuple[Fraction, Fraction]]:
    merged: list[tuple[Fraction, Fraction]] = []
    for p, q in sorted(intervals):
        if merged and p <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], q))
        else:
            merged.append((p, q))
    return merged


# ======================================================================= message formatting
def _approx(x: Fraction, digits: int = 6) -> str:
    """A decimal approximation of x (integer arithmetic), for messages."""
    scaled = round(Fraction(x) * 10**digits)
    sign = "-" if scaled < 0 else ""
    text = str(abs(scaled)).rjust(digits + 1, "0")
    whole, frac = text[:-digits], text[-digits:].rstrip("0")
    return f"{sign}{whole}.{frac}" if frac else f"{sign}{whole}"


def _num(x: Fraction | int) -> str:
    text = number_text(x)
    return text if len(text) <= 18 else "≈" + _approx(Fraction(x), 9)


def _pt(p: Point) -> str:
    return f"({_num(p[0])}, {_num(p[1])})"


def _heading_value(v: Point) -> Fraction:
    lo, hi = angle_enclosure(v, 40)
    return (lo + hi) / 2


def _heading(v: Point) -> str:
    """The angle of v (radians), to 6 decimals, for messages."""
    return _approx(_heading_value(v), 6)


# ======================================================================= the report
@dataclass(frozen=True, slots=True)
class Failure:
    """One claim that does not hold: ``claim`` is its path in the certificate (``stages[2].moves[0].d_hi``,
    ``claims.min_width``), ``message`` says what was found."""

    claim: str
    message: str

    def __str__(self) -> str:
        return f"{self.claim}: {self.message}"


@dataclass(frozen=True)
class CheckReport:
    """The verdict of :func:`check_certificate`.

    ``valid`` is true iff there are no ``failures``; ``checked`` counts what was re-derived exactly
    (stages, moves, corner rays, edge-against-region tests, chaining links, angle decisions);
    ``not_checked`` lists claims taken on trust (the optimality bound of a search, for instance).
    """

    valid: bool
    failures: tuple[Failure, ...]
    checked: tuple[tuple[str, int], ...]
    not_checked: tuple[str, ...]
    kind: str

    def to_json(self) -> dict:
        return {
            "valid": self.valid,
            "kind": self.kind,
            "failures": [{"claim": f.claim, "message": f.message} for f in self.failures],
            "checked": dict(self.checked),
            "not_checked": list(self.not_checked),
        }

    def to_text(self, *, width: int = 100) -> str:
        counts = ", ".join(f"{value} {name.replace('_', ' ')}" for name, value in self.checked)
        lines = [f"certificate ({self.kind}): {'VALID' if self.valid else 'INVALID'}", f"checked exactly: {counts}"]
        for failure in self.failures:
            lines.append(f"FAIL {failure}")
        for item in self.not_checked:
            lines.append(f"not checked: {item}")
        return "\n".join(lines) + "\n"


@dataclass
class _Edge:
    id: int
    ring: int
    a: Point
    b: Point

    @property
    def vector(self) -> Point:
        return _sub(self.b, self.a)


@dataclass
class _MoveResult:
    """What the move checks learnt, for the stage, chaining, position and cycle checks."""

    move: Move
    edge_vector: Point
    w_lo: Point  # d_lo in the source edge's frame (its angle is the heading)
    w_hi: Point
    image: tuple[Fraction, Fraction] | None = None  # [min τ, max τ] on the target edge, when sound
    sound: bool = False


# ======================================================================= the checker
Query = Sequence[tuple[int, Fraction, Fraction]]
"""A start or goal set as (edge, t0, t1) pieces, to compare a certificate's own with."""


def check_certificate(
    cert: Certificate,
    *,
    expected_rings: Sequence[Sequence[Point]] | None = None,
    expected_start: Query | None = None,
    expected_goal: Query | None = None,
) -> CheckReport:
    """Check every claim of ``cert`` in exact arithmetic; see the module docstring for what and how.

    Parameters
    ----------
    cert
        A parsed certificate.
    expected_rings
        If given, the certificate's environment must have exactly these (normalised) rings, e.g.
        ``load_environment(path).rings``: the certificate then speaks about that environment.
    expected_start, expected_goal
        If given, the query the certificate must answer: its start (goal) set must be this union of
        pieces, exactly. Without them, a certificate with a smaller start or a larger goal than asked
        for is a true statement about another query, and valid.

    Returns
    -------
    CheckReport
        ``valid`` with no failures, or every failure found, each naming its claim.
    """
    checker = _Checker(cert)
    checker.run(expected_rings)
    if expected_start is not None:
        checker.check_query("start", cert.start, expected_start)
    if expected_goal is not None:
        checker.check_query("goal", cert.goal or (), expected_goal)
    return checker.report()


class _Checker:
    def __init__(self, cert: Certificate) -> None:
        self.cert = cert
        self.failures: list[Failure] = []
        self.not_checked: list[str] = []
        self.counts = {
            "stages": 0,
            "moves": 0,
            "corner_rays": 0,
            "edge_tests": 0,
            "links": 0,
            "angle_decisions": 0,
        }
        self.edges: list[_Edge] = []
        self.segments: dict[int, SegmentRecord] = {}

    def fail(self, claim: str, message: str) -> None:
        self.failures.append(Failure(claim, message))

    def report(self) -> CheckReport:
        return CheckReport(
            valid=not self.failures,
            failures=tuple(self.failures),
            checked=tuple(self.counts.items()),
            not_checked=tuple(self.not_checked),
            kind=self.cert.kind,
        )

    # ------------------------------------------------------------------ the run
    def run(self, expected_rings: Sequence[Sequence[Point]] | None) -> None:
        cert = self.cert
        if expected_rings is not None:
            self.check_expected(expected_rings)
        if not self.check_environment():
            return  # nothing else means anything on an invalid environment
        self.check_segments()
        self.check_pieces(cert.start, "start")
        if cert.goal is not None:
            self.check_pieces(cert.goal, "goal")
        results: list[list[_MoveResult | None]] = []
        for k, stage in enumerate(cert.stages):
            self.counts["stages"] += 1
            results.append([self.check_move(f"stages[{k}].moves[{m}]", move) for m, move in enumerate(stage.moves)])
        widths = [self.check_stage_headings(k, stage, results[k]) for k, stage in enumerate(cert.stages)]
        self.check_chaining(results)
        self.check_source_ends()
        for k, stage in enumerate(cert.stages):
            if stage.positions is not None:
                self.check_positions(k, stage, results[k])
        self.check_claims(widths)
        if cert.cycle is not None:
            self.check_cycle(cert.cycle, results)

    # ------------------------------------------------------------------ environment
    def check_expected(self, expected: Sequence[Sequence[Point]]) -> None:
        rings = self.cert.environment.rings
        if len(rings) != len(expected):
            self.fail("environment", f"has {len(rings)} rings, the given environment has {len(expected)}")
            return
        for r, (mine, theirs) in enumerate(zip(rings, expected)):
            if len(mine) != len(theirs):
                self.fail(f"environment.rings[{r}]", f"has {len(mine)} vertices, the given environment's ring has {len(theirs)}")
                return
            for i, (p, q) in enumerate(zip(mine, theirs)):
                if (Fraction(p[0]), Fraction(p[1])) != (Fraction(q[0]), Fraction(q[1])):
                    self.fail(f"environment.rings[{r}][{i}]", f"is {_pt(p)}, the given environment has {_pt(q)}")
                    return

    def check_query(self, where: str, mine: Sequence[Piece], expected: Query) -> None:
        def union(pieces: Iterable[tuple[int, Fraction, Fraction]]) -> dict[int, list[tuple[Fraction, Fraction]]]:
            by_edge: dict[int, list[tuple[Fraction, Fraction]]] = {}
            for edge, a, b in pieces:
                by_edge.setdefault(int(edge), []).append((Fraction(a), Fraction(b)))
            return {e: _union(v) for e, v in by_edge.items()}

        have = union((p.edge, p.t0, p.t1) for p in mine)
        want = union(expected)
        if have != want:
            self.fail(where, f"is {self._pieces_text(have)}, but the query's {where} set is {self._pieces_text(want)}")

    def check_environment(self) -> bool:
        rings = self.cert.environment.rings
        before = len(self.failures)
        for r, ring in enumerate(rings):
            where = f"environment.rings[{r}]"
            if len(ring) < 3:
                self.fail(where, f"has {len(ring)} vertices; a ring needs at least 3")
                continue
            for i in range(len(ring)):
                if ring[i] == ring[(i + 1) % len(ring)]:
                    self.fail(where, f"repeats vertex {i} {_pt(ring[i])}")
                    break
            else:
                area2 = _signed_area2(ring)
                if r == 0 and area2 <= 0:
                    self.fail(where, f"the outer ring must be counter-clockwise (free space on the left); its signed area is {_num(area2 / 2)}")
                elif r > 0 and area2 >= 0:
                    self.fail(where, f"a hole must be clockwise (free space on the left); its signed area is {_num(area2 / 2)}")
        if len(self.failures) > before:
            return False
        edges: list[_Edge] = []
        nxt: list[int] = []
        for r, ring in enumerate(rings):
            first = len(edges)
            for i in range(len(ring)):
                edges.append(_Edge(len(edges), r, ring[i], ring[(i + 1) % len(ring)]))
                nxt.append(first + (i + 1) % len(ring))
        # every pair of edges, pruned exactly by x-extent
        order = sorted(range(len(edges)), key=lambda i: min(edges[i].a[0], edges[i].b[0]))
        for pos, i in enumerate(order):
            ei = edges[i]
            x_max = max(ei.a[0], ei.b[0])
            y_lo, y_hi = min(ei.a[1], ei.b[1]), max(ei.a[1], ei.b[1])
            for j in order[pos + 1 :]:
                ej = edges[j]
                if min(ej.a[0], ej.b[0]) > x_max:
                    break
                if max(ej.a[1], ej.b[1]) < y_lo or min(ej.a[1], ej.b[1]) > y_hi:
                    continue
                if nxt[i] == j or nxt[j] == i:
                    first, second = (ei, ej) if nxt[i] == j else (ej, ei)
                    v = first.b  # the shared vertex: they may meet only there
                    if _orient(first.a, v, second.b) == 0 and _dot(_sub(first.a, v), _sub(second.b, v)) > 0:
                        self.fail("environment", f"edges {first.id} and {second.id} fold back onto each other at {_pt(v)}")
                        return False
                    continue
                if _segments_meet(ei.a, ei.b, ej.a, ej.b):
                    lo, hi = sorted((i, j))
                    self.fail("environment", f"edge {lo} meets edge {hi}: the boundary is not simple")
                    return False
        for h in range(1, len(rings)):
            if not _inside_ring(rings[h][0], rings[0]):
                self.fail(f"environment.rings[{h}]", "the hole lies outside the outer ring")
                return False
            for g in range(1, len(rings)):
                if g != h and _inside_ring(rings[h][0], rings[g]):
                    self.fail(f"environment.rings[{h}]", f"the hole lies inside hole ring {g}")
                    return False
        self.edges = edges
        return True

    # ------------------------------------------------------------------ records
    def point_at(self, edge: int, t: Fraction) -> Point:
        e = self.edges[edge]
        return _along(e.a, e.vector, t)

    def check_segments(self) -> None:
        n = len(self.edges)
        for i, seg in enumerate(self.cert.segments):
            where = f"segments[{i}]"
            if seg.id in self.segments:
                self.fail(f"{where}.id", f"segment id {seg.id} appears twice")
                continue
            if not 0 <= seg.edge < n:
                self.fail(f"{where}.edge", f"edge {seg.edge} does not exist (edges 0..{n - 1})")
                continue
            if not 0 <= seg.t0 < seg.t1 <= 1:
                self.fail(where, f"[t0, t1] = [{_num(seg.t0)}, {_num(seg.t1)}] is not an interval 0 ≤ t0 < t1 ≤ 1")
                continue
            if seg.a != self.point_at(seg.edge, seg.t0):
                self.fail(f"{where}.a", f"{_pt(seg.a)} is not the point t0 = {_num(seg.t0)} of edge {seg.edge}, {_pt(self.point_at(seg.edge, seg.t0))}")
                continue
            if seg.b != self.point_at(seg.edge, seg.t1):
                self.fail(f"{where}.b", f"{_pt(seg.b)} is not the point t1 = {_num(seg.t1)} of edge {seg.edge}, {_pt(self.point_at(seg.edge, seg.t1))}")
                continue
            self.segments[seg.id] = seg

    def check_pieces(self, pieces: Sequence[Piece], where: str) -> None:
        n = len(self.edges)
        for i, piece in enumerate(pieces):
            if not 0 <= piece.edge < n:
                self.fail(f"{where}[{i}].edge", f"edge {piece.edge} does not exist (edges 0..{n - 1})")
            elif not 0 <= piece.t0 < piece.t1 <= 1:
                self.fail(f"{where}[{i}]", f"[t0, t1] = [{_num(piece.t0)}, {_num(piece.t1)}] is not an interval 0 ≤ t0 < t1 ≤ 1")

    # ------------------------------------------------------------------ one move
    def check_move(self, path: str, move: Move) -> _MoveResult | None:
        self.counts["moves"] += 1
        n = len(self.edges)
        if not 0 <= move.edge < n:
            self.fail(f"{path}.edge", f"edge {move.edge} does not exist (edges 0..{n - 1})")
            return None
        if not 0 <= move.target_edge < n:
            self.fail(f"{path}.target_edge", f"edge {move.target_edge} does not exist (edges 0..{n - 1})")
            return None
        if move.target_edge == move.edge:
            self.fail(f"{path}.target_edge", f"edge {move.edge} is the source edge: no ray leaving an edge into the free space comes back to its line")
            return None
        p, q = move.source
        if not 0 <= p < q <= 1:
            self.fail(f"{path}.source", f"[{_num(p)}, {_num(q)}] is not an interval 0 ≤ p < q ≤ 1 of edge {move.edge}")
            return None
        sound = True
        if move.source_segment is not None:
            seg = self.segments.get(move.source_segment)
            if seg is None:
                self.fail(f"{path}.source_segment", f"segment {move.source_segment} is not among the certificate's (valid) segments")
                sound = False
            elif seg.edge != move.edge:
                self.fail(f"{path}.source_segment", f"segment {seg.id} lies on edge {seg.edge}, not on the source edge {move.edge}")
                sound = False
            elif not (seg.t0 <= p and q <= seg.t1):
                self.fail(f"{path}.source", f"[{_num(p)}, {_num(q)}] is not within segment {seg.id} ([{_num(seg.t0)}, {_num(seg.t1)}] of edge {seg.edge})")
                sound = False
        t_lo, t_hi, label = _ZERO, _ONE, f"edge {move.target_edge}"
        if move.target_segment is not None:
            seg = self.segments.get(move.target_segment)
            if seg is None:
                self.fail(f"{path}.target_segment", f"segment {move.target_segment} is not among the certificate's (valid) segments")
                return None
            if seg.edge != move.target_edge:
                self.fail(f"{path}.target_segment", f"segment {seg.id} lies on edge {seg.edge}, not on the target edge {move.target_edge}")
                return None
            t_lo, t_hi, label = seg.t0, seg.t1, f"segment {seg.id}"
        c, d = move.target
        if not t_lo <= c <= d <= t_hi:
            self.fail(f"{path}.target", f"[{_num(c)}, {_num(d)}] is not within {label} (t in [{_num(t_lo)}, {_num(t_hi)}] of edge {move.target_edge})")
            sound = False

        # ---- directions and the cone
        src = self.edges[move.edge]
        e_vec = src.vector
        directions = (("d_lo", move.d_lo), ("d_hi", move.d_hi))
        cone_ok = True
        for name, vec in directions:
            if vec[0] == 0 and vec[1] == 0:
                self.fail(f"{path}.{name}", "is the zero vector, not a direction")
                cone_ok = False
            elif _cross(e_vec, vec) <= 0:
                self.fail(
                    f"{path}.{name}",
                    f"{_pt(vec)} points into the wall: it does not leave edge {move.edge} (along {_pt(e_vec)}) into the "
                    f"free space on its left (cross(edge, d) = {_num(_cross(e_vec, vec))} ≤ 0)",
                )
                cone_ok = False
        if not cone_ok:
            return None
        if _cross(move.d_lo, move.d_hi) < 0:
            self.fail(f"{path}.d_hi", f"{_pt(move.d_hi)} lies clockwise of d_lo {_pt(move.d_lo)}: the cone must turn counter-clockwise from d_lo to d_hi")
            return None
        result = _MoveResult(move, e_vec, heading_vector(e_vec, move.d_lo), heading_vector(e_vec, move.d_hi))

        # ---- corner rays
        tgt = self.edges[move.target_edge]
        c_pt, t_vec = tgt.a, tgt.vector
        ends = (("p", p, self.point_at(move.edge, p)), ("q", q, self.point_at(move.edge, q)))
        taus: list[Fraction] = []
        hits: list[Point] = []
        corners_ok = True
        for end, t, origin in ends:
            vertex = t == 0 or t == 1
            for name, vec in directions:
                self.counts["corner_rays"] += 1
                where = f"corner ray from {_pt(origin)} (t = {_num(t)} of edge {move.edge}) along {_pt(vec)}"
                hit = line_hit(origin, vec, c_pt, t_vec)
                if hit is None:
                    self.fail(f"{path}.{name}", f"{where} runs parallel to edge {move.target_edge} and never reaches it")
                    corners_ok = False
                    continue
                s, tau = hit
                point = _along(c_pt, t_vec, tau)
                if s < 0 or (s == 0 and not vertex):
                    self.fail(f"{path}.{name}", f"{where} meets the line of edge {move.target_edge} behind its start, at {_pt(point)}")
                    corners_ok = False
                    continue
                inside = (t_lo <= tau <= t_hi) if vertex else (t_lo < tau < t_hi)
                if not inside:
                    self.fail(
                        f"{path}.{name}",
                        f"{where} hits the line of edge {move.target_edge} at {_pt(point)} (t = {_num(tau)}), "
                        f"outside {label} (t in {'[' if vertex else '('}{_num(t_lo)}, {_num(t_hi)}{']' if vertex else ')'})",
                    )
                    corners_ok = False
                    continue
                if not c <= tau <= d:
                    self.fail(f"{path}.target", f"{where} lands at t = {_num(tau)} of edge {move.target_edge}, outside the claimed target [{_num(c)}, {_num(d)}]")
                    sound = False
                taus.append(tau)
                hits.append(point)
        if not corners_ok:
            return result
        result.image = (min(taus), max(taus))
        if sound and (c, d) not in ((t_lo, t_hi), result.image):
            self.fail(
                f"{path}.target",
                f"claims [{_num(c)}, {_num(d)}], neither all of {label} ([{_num(t_lo)}, {_num(t_hi)}]) nor the exact image "
                f"[{_num(result.image[0])}, {_num(result.image[1])}] of the move",
            )
            sound = False

        # ---- the swept region
        allowed = {origin for _, t, origin in ends if t == 0 or t == 1}
        swept_ok = self.check_swept(path, move, (ends[0][2], ends[1][2], *hits), allowed, (t_lo, t_hi))
        result.sound = sound and swept_ok
        return result

    def check_swept(self, path: str, move: Move, points: Sequence[Point], allowed: set[Point], target_range: tuple[Fraction, Fraction]) -> bool:
        hull = _convex_hull(points)
        if len(hull) < 3:
            self.fail(f"{path}.swept", "the swept region is degenerate (its corners are collinear)")
            return False
        xs = [h[0] for h in hull]
        ys = [h[1] for h in hull]
        x_lo, x_hi, y_lo, y_hi = min(xs), max(xs), min(ys), max(ys)
        p, q = move.source
        for edge in self.edges:
            self.counts["edge_tests"] += 1
            a, b = edge.a, edge.b
            if max(a[0], b[0]) < x_lo or min(a[0], b[0]) > x_hi or max(a[1], b[1]) < y_lo or min(a[1], b[1]) > y_hi:
                continue  # bounding boxes apart (exact)
            clip = _clip(a, b, hull)
            if clip is None:
                continue
            l0, l1 = clip
            if edge.id == move.edge:
                if p <= l0 and l1 <= q:
                    continue
            elif edge.id == move.target_edge:
                if target_range[0] <= l0 and l1 <= target_range[1]:
                    continue
            elif l0 == l1 and _along(a, edge.vector, l0) in allowed:
                continue  # a neighbour of the source edge touching it at a vertex end of the source
            x0, x1 = _along(a, edge.vector, l0), _along(a, edge.vector, l1)
            if l0 == l1:
                what = f"vertex {_pt(x0)} of edge {edge.id}" if l0 in (0, 1) else f"edge {edge.id} at {_pt(x0)}"
                self.fail(f"{path}.swept", f"{what} lies in the swept region (the hull of the source and the corner hits)")
            else:
                self.fail(f"{path}.swept", f"edge {edge.id} runs through the swept region from {_pt(x0)} to {_pt(x1)}")
            return False
        return True

    # ------------------------------------------------------------------ headings of a stage
    def _compare(self, v: Point, r: Fraction, claim: str) -> int | None:
        self.counts["angle_decisions"] += 1
        try:
            return compare_angle(v, r)
        except Undecided as exc:
            self.fail(claim, f"cannot decide a heading comparison: {exc}")
            return None

    def check_stage_headings(self, k: int, stage: Stage, results: Sequence[_MoveResult | None]) -> list[Point] | None:
        """Checks of 5. for one stage; returns the vectors whose angles are the stage's pairwise widths
        (angle(d_hi of m) − angle(d_lo of j), for all m, j), or ``None`` if the cones are unusable."""
        if any(r is None for r in results):
            return None
        moves = [r for r in results if r is not None]
        diffs: list[Point] = []
        for m, rm in enumerate(moves):
            for j, rj in enumerate(moves):
                v = _difference_vector(rj.w_lo, rm.w_hi)
                if v[1] < 0:
                    self.fail(
                        f"stages[{k}]",
                        f"the moves' cones share no heading: moves[{m}] ends (d_hi) at heading {_heading(rm.w_hi)} before "
                        f"moves[{j}] starts (d_lo) at {_heading(rj.w_lo)} (each measured from its source edge)",
                    )
                    return None
                diffs.append(v)
        for m, rm in enumerate(moves):
            for j, rj in enumerate(moves):
                if j == m:
                    continue
                if self._compare(_difference_vector(rj.w_lo, rm.w_lo), -WIDTH_SLACK, f"stages[{k}].moves[{m}].d_lo") == -1:
                    self.fail(
                        f"stages[{k}].moves[{m}].d_lo",
                        f"the cone starts at heading {_heading(rm.w_lo)}, more than 1e-9 before the stage's common cone "
                        f"(moves[{j}] starts at {_heading(rj.w_lo)}): a move's cone must be the stage's action interval",
                    )
                    break
                if self._compare(_difference_vector(rj.w_hi, rm.w_hi), WIDTH_SLACK, f"stages[{k}].moves[{m}].d_hi") == 1:
                    self.fail(
                        f"stages[{k}].moves[{m}].d_hi",
                        f"the cone ends at heading {_heading(rm.w_hi)}, more than 1e-9 after the stage's common cone "
                        f"(moves[{j}] ends at {_heading(rj.w_hi)}): a move's cone must be the stage's action interval",
                    )
                    break
        if stage.interval is not None:
            lo, hi = stage.interval
            if lo > hi:
                self.fail(f"stages[{k}].interval", f"[{_num(lo)}, {_num(hi)}] is reversed")
                return None
            for j, r in enumerate(moves):
                if self._compare(r.w_lo, lo, f"stages[{k}].interval.lo") == 1:
                    self.fail(f"stages[{k}].interval.lo", f"claims {_num(lo)}, but the cone of moves[{j}] starts at heading {_heading(r.w_lo)} (d_lo {_pt(r.move.d_lo)} from edge {r.move.edge})")
                    return None
                if self._compare(r.w_hi, hi, f"stages[{k}].interval.hi") == -1:
                    self.fail(f"stages[{k}].interval.hi", f"claims {_num(hi)}, but the cone of moves[{j}] ends at heading {_heading(r.w_hi)} (d_hi {_pt(r.move.d_hi)} from edge {r.move.edge})")
                    return None
            if not any(self._compare(r.w_lo, lo - WIDTH_SLACK, f"stages[{k}].interval.lo") in (1, None) for r in moves):
                self.fail(f"stages[{k}].interval.lo", f"claims {_num(lo)}, more than 1e-9 inside the common cone, which starts at heading {_approx(max(_heading_value(r.w_lo) for r in moves), 6)}")
            if not any(self._compare(r.w_hi, hi + WIDTH_SLACK, f"stages[{k}].interval.hi") in (-1, None) for r in moves):
                self.fail(f"stages[{k}].interval.hi", f"claims {_num(hi)}, more than 1e-9 inside the common cone, which ends at heading {_approx(min(_heading_value(r.w_hi) for r in moves), 6)}")
        return diffs

    # ------------------------------------------------------------------ chaining
    def check_chaining(self, results: Sequence[Sequence[_MoveResult | None]]) -> None:
        cert = self.cert
        stages = cert.stages
        # start: covered by the sources of stage 0
        sources0 = self._sources(stages[0])
        for i, piece in enumerate(cert.start):
            if not (0 <= piece.edge < len(self.edges) and piece.t0 < piece.t1):
                continue
            self.counts["links"] += 1
            gap = _uncovered(piece.t0, piece.t1, sources0.get(piece.edge, []))
            if gap is not None:
                self.fail("stages[0].moves", f"no move leaves t in ({_num(gap[0])}, {_num(gap[1])}) of edge {piece.edge}, part of start[{i}]")
        links = [(k, k + 1) for k in range(len(stages) - 1)]
        if cert.cycle is not None and 0 <= cert.cycle.stages[0] < len(stages):
            links.append((len(stages) - 1, cert.cycle.stages[0]))
        for k_from, k_to in links:
            sources = self._sources(stages[k_to])
            for m, move in enumerate(stages[k_from].moves):
                self.counts["links"] += 1
                c, d = move.target
                gap = _uncovered(c, d, sources.get(move.target_edge, []))
                if gap is not None:
                    wrap = " (the cycle returns to its first stage)" if k_to <= k_from else ""
                    self.fail(
                        f"stages[{k_to}].moves",
                        f"no move leaves t in ({_num(gap[0])}, {_num(gap[1])}) of edge {move.target_edge}, where "
                        f"stages[{k_from}].moves[{m}] may land (its target is [{_num(c)}, {_num(d)}]){wrap}",
                    )
        if cert.goal is not None:
            goal: dict[int, list[tuple[Fraction, Fraction]]] = {}
            for piece in cert.goal:
                goal.setdefault(piece.edge, []).append((piece.t0, piece.t1))
            last = len(stages) - 1
            for m, move in enumerate(stages[last].moves):
                self.counts["links"] += 1
                c, d = move.target
                gap = _uncovered(c, d, goal.get(move.target_edge, []))
                if gap is not None:
                    self.fail(
                        f"stages[{last}].moves[{m}].target",
                        f"[{_num(c)}, {_num(d)}] of edge {move.target_edge} is not within the goal set: "
                        f"t in ({_num(gap[0])}, {_num(gap[1])}) is outside it",
                    )

    def check_source_ends(self) -> None:
        """Every end of a source is accounted for: an end of the edge or of a named segment, an end of a
        set flowing into the stage (the start set, or the previous stage's targets), or an end of another
        source of the same stage on that edge (a split). A certificate claims nothing gratuitous."""
        cert = self.cert
        stages = cert.stages
        n = len(stages)
        segment_ends: dict[int, set[Fraction]] = {}
        for seg in self.segments.values():
            segment_ends.setdefault(seg.edge, set()).update((seg.t0, seg.t1))
        for k, stage in enumerate(stages):
            inflow: dict[int, set[Fraction]] = {}
            feeding: list[tuple[int, Fraction, Fraction]] = []
            if k == 0:
                feeding += [(piece.edge, piece.t0, piece.t1) for piece in cert.start]
            else:
                feeding += [(m.target_edge, *m.target) for m in stages[k - 1].moves]
            if cert.cycle is not None and k == cert.cycle.stages[0]:
                feeding += [(m.target_edge, *m.target) for m in stages[n - 1].moves]
            for edge, a, b in feeding:
                inflow.setdefault(edge, set()).update((a, b))
            for m, move in enumerate(stage.moves):
                others = {t for j, o in enumerate(stage.moves) if j != m and o.edge == move.edge for t in o.source}
                known = {_ZERO, _ONE} | segment_ends.get(move.edge, set()) | inflow.get(move.edge, set()) | others
                for name, t in zip(("p", "q"), move.source):
                    if t not in known:
                        flowing = "the start set" if k == 0 else f"stages[{k - 1}]'s targets"
                        self.fail(
                            f"stages[{k}].moves[{m}].source",
                            f"its end {name} = {_num(t)} of edge {move.edge} is not accounted for: not an end of the edge, of a "
                            f"named segment, of {flowing} or of another source of the stage",
                        )
                        break

    @staticmethod
    def _sources(stage: Stage) -> dict[int, list[tuple[Fraction, Fraction]]]:
        out: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for move in stage.moves:
            out.setdefault(move.edge, []).append(move.source)
        return out

    # ------------------------------------------------------------------ positions
    def check_positions(self, k: int, stage: Stage, results: Sequence[_MoveResult | None]) -> None:
        assert stage.positions is not None
        where = f"stages[{k}].positions"
        before = len(self.failures)
        self.check_pieces(stage.positions, where)
        if len(self.failures) > before or any(r is None or r.image is None for r in results):
            return
        exact: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for r in results:
            assert r is not None and r.image is not None
            exact.setdefault(r.move.target_edge, []).append(r.image)
        claimed: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for piece in stage.positions:
            claimed.setdefault(piece.edge, []).append((piece.t0, piece.t1))
        exact_u = {e: _union(v) for e, v in exact.items()}
        claimed_u = {e: _union(v) for e, v in claimed.items()}
        if exact_u != claimed_u:
            self.fail(where, f"claims {self._pieces_text(claimed_u)}, but the exact image of the stage is {self._pieces_text(exact_u)}")

    @staticmethod
    def _pieces_text(pieces: dict[int, list[tuple[Fraction, Fraction]]]) -> str:
        parts = [f"e{e}:[{_num(a)}, {_num(b)}]" for e in sorted(pieces) for a, b in pieces[e]]
        return ", ".join(parts) if parts else "nothing"

    # ------------------------------------------------------------------ claims
    def check_claims(self, widths: Sequence[list[Point] | None]) -> None:
        cert = self.cert
        claims = cert.claims
        if claims.bounces != len(cert.stages):
            self.fail("claims.bounces", f"claims {claims.bounces}, the certificate has {len(cert.stages)} stages")
        if claims.tolerance * 2 != claims.min_width:
            self.fail("claims.tolerance", f"claims {_num(claims.tolerance)}, but min_width / 2 = {_num(claims.min_width / 2)}")
        usable = all(w is not None for w in widths)
        if claims.min_width < 0:
            self.fail("claims.min_width", f"claims {_num(claims.min_width)} < 0")
        elif usable:
            self.check_min_width(claims.min_width, widths)  # type: ignore[arg-type]
        if claims.sum_width is not None and usable:
            self.check_sum_width(claims.sum_width, widths)  # type: ignore[arg-type]
        self.check_optimality()

    def check_min_width(self, claimed: Fraction, widths: Sequence[list[Point]]) -> None:
        for k, diffs in enumerate(widths):
            interval = self.cert.stages[k].interval
            if interval is not None and claimed > interval[1] - interval[0]:
                self.fail("claims.min_width", f"claims {_num(claimed)}, more than the width {_num(interval[1] - interval[0])} of stages[{k}].interval")
                return
            for v in diffs:
                if self._compare(v, claimed, "claims.min_width") == -1:
                    self.fail("claims.min_width", f"claims {_num(claimed)}, but stages[{k}] is only {_heading(v)} wide (its common cone, measured exactly)")
                    return
        tight = any(self._compare(v, claimed + WIDTH_SLACK, "claims.min_width") in (-1, 0, None) for diffs in widths for v in diffs)
        if not tight:
            narrowest = _approx(min(_heading_value(v) for diffs in widths for v in diffs), 9)
            self.fail("claims.min_width", f"claims {_num(claimed)}, more than 1e-9 below the narrowest stage's width {narrowest}: claims must be tight")

    def check_sum_width(self, claimed: Fraction, widths: Sequence[list[Point]]) -> None:
        slack = WIDTH_SLACK * len(widths)
        bits = 64
        while True:
            lo_sum = hi_sum = _ZERO
            for diffs in widths:
                enclosures = [angle_enclosure(v, bits) for v in diffs]
                lo_sum += min(e[0] for e in enclosures)
                hi_sum += min(e[1] for e in enclosures)
            self.counts["angle_decisions"] += 1
            if hi_sum < claimed:
                self.fail("claims.sum_width", f"claims {_num(claimed)}, but the stages' widths add up to {_approx(hi_sum, 9)}")
                return
            if lo_sum > claimed + slack:
                self.fail("claims.sum_width", f"claims {_num(claimed)}, more than {_num(slack)} below the sum of the widths {_approx(lo_sum, 9)}: claims must be tight")
                return
            if lo_sum >= claimed and hi_sum <= claimed + slack:
                return
            if bits >= MAX_BITS:
                self.fail("claims.sum_width", f"cannot decide {_num(claimed)} against the sum of the widths within 2^-{bits}")
                return
            bits *= 2

    def check_optimality(self) -> None:
        claims = self.cert.claims
        opt = claims.optimality
        if opt is None:
            return
        self.not_checked.append(
            f"claims.optimality: the bound of method {opt.method!r} is not re-derived (only its consistency with the checked claims)"
        )
        if opt.proved and opt.bound is None:
            self.fail("claims.optimality.bound", "a proved optimality claim must state its bound")
            return
        if opt.bound is None:
            return
        bound = opt.bound
        objective = claims.objective
        if objective == "fewest":
            if bound > claims.bounces:
                self.fail("claims.optimality.bound", f"a lower bound of {_num(bound)} bounces exceeds this plan's {claims.bounces}")
            elif opt.proved and bound != claims.bounces:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} differs from the {claims.bounces} bounces")
        elif objective in ("tolerance", "constant"):
            if bound < claims.min_width:
                self.fail("claims.optimality.bound", f"an upper bound {_num(bound)} below the certified min_width {_num(claims.min_width)}")
            elif opt.proved and bound - claims.min_width > WIDTH_SLACK:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} exceeds min_width {_num(claims.min_width)} by more than 1e-9")
        elif objective == "sum":
            if claims.sum_width is None:
                self.fail("claims.sum_width", "the objective is the sum of widths: claim it")
            elif bound < claims.sum_width:
                self.fail("claims.optimality.bound", f"an upper bound {_num(bound)} below the certified sum_width {_num(claims.sum_width)}")
            elif opt.proved and bound - claims.sum_width > WIDTH_SLACK * len(self.cert.stages):
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} exceeds sum_width {_num(claims.sum_width)}")
        elif objective == "contraction" and self.cert.cycle is not None:
            contraction = self.cert.cycle.contraction
            if bound > contraction:
                self.fail("claims.optimality.bound", f"a lower bound {_num(bound)} above the certified contraction {_num(contraction)}")
            elif opt.proved and contraction - bound > WIDTH_SLACK:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} is below the contraction {_num(contraction)}")

    # ------------------------------------------------------------------ cycles
    def check_cycle(self, cycle: CycleClaim, results: Sequence[Sequence[_MoveResult | None]]) -> None:
        stages = self.cert.stages
        n = len(stages)
        first = cycle.stages[0]
        if list(cycle.stages) != list(range(first, n)) or not 0 <= first < n:
            self.fail("cycle.stages", f"{list(cycle.stages)} must be the last stages in order ({first}..{n - 1}): the cycle repeats the tail of the stage list")
            return
        if len(cycle.nominal) != len(cycle.stages):
            self.fail("cycle.nominal", f"gives {len(cycle.nominal)} directions for {len(cycle.stages)} cycle stages")
            return
        for i in cycle.stages:
            if len(stages[i].moves) != 1:
                self.fail(f"stages[{i}].moves", f"a cycle stage has exactly one move (found {len(stages[i].moves)}): its return map is one affine map")
                return
        moves = [results[i][0] for i in cycle.stages]
        if any(r is None or not r.sound or r.image is None for r in moves):
            return  # the move's own failures are reported already
        for idx, i in enumerate(cycle.stages):
            nxt = cycle.stages[(idx + 1) % len(cycle.stages)]
            here, there = stages[i].moves[0], stages[nxt].moves[0]
            if here.target_edge != there.edge:
                self.fail("cycle.stages", f"stages[{i}] lands on edge {here.target_edge} but stages[{nxt}] leaves from edge {there.edge}")
                return
        alpha, beta, worst = _ONE, _ZERO, _ONE
        for idx, i in enumerate(cycle.stages):
            move = stages[i].moves[0]
            src, tgt = self.edges[move.edge], self.edges[move.target_edge]
            d = cycle.nominal[idx]
            if not (_cross(src.vector, d) > 0 and _cross(move.d_lo, d) >= 0 and _cross(d, move.d_hi) >= 0):
                self.fail(f"cycle.nominal[{idx}]", f"{_pt(d)} is not inside the cone {_pt(move.d_lo)} → {_pt(move.d_hi)} of stages[{i}].moves[0]")
                return
            a_k, b_k = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, d)
            alpha, beta = a_k * alpha, a_k * beta + b_k
            a_lo = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, move.d_lo)[0]
            a_hi = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, move.d_hi)[0]
            worst *= max(abs(a_lo), abs(a_hi))
        entry = stages[first].moves[0]
        if cycle.alpha != alpha:
            self.fail("cycle.alpha", f"claims {_num(cycle.alpha)}, the return map of the nominal directions on edge {entry.edge} has α = {_num(alpha)}")
        if cycle.beta != beta:
            self.fail("cycle.beta", f"claims {_num(cycle.beta)}, the return map of the nominal directions on edge {entry.edge} has β = {_num(beta)}")
        if alpha == 1:
            self.fail("cycle.fixed_point", "the return map has α = 1: no unique fixed point")
        else:
            fixed = beta / (1 - alpha)
            if cycle.fixed_point != fixed:
                self.fail("cycle.fixed_point", f"claims {_num(cycle.fixed_point)}, but β / (1 − α) = {_num(fixed)}")
            elif not entry.source[0] <= fixed <= entry.source[1]:
                self.fail("cycle.fixed_point", f"t* = {_num(fixed)} lies outside the entry source [{_num(entry.source[0])}, {_num(entry.source[1])}] of edge {entry.edge}")
        if cycle.contraction != worst:
            self.fail("cycle.contraction", f"claims {_num(cycle.contraction)}, but the worst case of |α| over the cones is {_num(worst)}")
        elif worst >= 1:
            self.fail("cycle.contraction", f"the cycle does not contract: the worst case of |α| over the cones is {_num(worst)} ≥ 1")
        if cycle.visits is not None:
            visited = [stages[i].moves[0].edge for i in cycle.stages]
            if not any(_is_subsequence(cycle.visits, visited[s:] + visited[:s]) for s in range(len(visited))):
                self.fail("cycle.visits", f"the cycle bounces on edges {visited} (cyclically), which does not visit {list(cycle.visits)} in that order")


def _is_subsequence(needle: Sequence[int], haystack: Sequence[int]) -> bool:
    it = iter(haystack)
    return all(any(x == y for y in it) for x in needle)
