"""Safe actions between boundary segments (paper §5: Def. 6–8, Prop. 2, Lemma 1, Cor. 1), exact.

A robot on the open source segment e_i = (a, b) leaves at heading θ ∈ (0, π), radians measured
counter-clockwise from the direction b − a (θ = π/2 is the inward normal). θ is **safe** towards the
target segment e_j = (c, d) when the ray from *every* point of the open e_i first meets the boundary
in the open e_j (paper Def. 7). Both segments are oriented with the free space on their left, as
every edge and every segment of P′ is.

What this module computes
-------------------------
- :func:`safe_interval` — the heading set that is safe **if nothing is in the way** (call it Θ₀):
  for entirely visible segments (Def. 6) it is the exact safe set, paper Prop. 2:
  ``[ang(c − b), ang(d − a)]``, a singleton when c − b ∥ d − a, empty when ang(c − b) > ang(d − a);
  for adjacent segments at a convex corner it is Cor. 1's ``(0, ang(d − a)]`` (e_j follows e_i at b)
  or ``[ang(c − b), π)`` (e_j precedes e_i at a). Here ang(w) is the CCW angle of w from b − a.
- :func:`safe_set` — the exact safe set of **any** pair in an environment, entirely visible or not,
  as sorted disjoint closed intervals (:class:`SafeSet`). An exact, O(n)-per-pair reference; the
  bounce visibility graph (:mod:`solverplan.bounce.bvg`) computes the same sets for all pairs at once.
- :func:`heading_is_safe` — exact membership of one rational direction.
- :func:`transition_side` and :func:`transition_angle` — Def. 8 (left/right) and φ_ij.

End points are decided exactly: every end point of a safe interval is the direction of a vector
between two exact points (c − b, d − a, p − a, p − b for a vertex p), or the boundary heading 0 or
π (excluded: headings live in the open (0, π)); end points are compared with exact cross products,
and the float angle is only for reporting. An interval whose two ends are exactly equal is the
singleton of Prop. 2, case 3. The exact end directions are kept for certificates.

The structure of the exact safe set (proof)
-------------------------------------------
Notation: ê = b − a; H = the open half-plane of directions u with cross(ê, u) > 0 (headings in
(0, π)); δ = d − c. For a heading u put R(u) = the region swept by the rays from the open e_i up to
the line of e_j: R(u) = {s + t·u : s ∈ (a, b), 0 < t, s + t·u strictly left of c → d}, an open
trapezoid with corners a, b, L_b(u), L_a(u), where L_x(u) is where the ray from x meets the line cd.

**(1) Characterisation.** u is safe ⇔ (i) L_a(u), L_b(u) ∈ [c, d] with the rays crossing the line cd
from its free (left) side, and (ii) R(u) contains no boundary point.
*Proof.* The landing point s ↦ L_s(u) is affine in s, so every s of the open e_i lands in the open
e_j iff the two limit landings L_a, L_b lie in the closed [c, d]; every point of R(u) lies on the
open segment from some s to L_s, so a boundary point in R(u) stops that ray first, and conversely a
first hit before the line cd lies in R(u). The landing points themselves are points of the open
e_j, which no other edge touches (edges meet only at vertices). □
Condition (i) is the *unobstructed* set Θ₀ computed by :func:`safe_interval`: for x ∈ {a, b}
strictly left of the line cd, L_x(u) ∈ [c, d] ⇔ u lies in the closed cone from c − x to d − x
(narrower than π); for x on the line, L_x = x, so x must be c or d, and the condition is that u
crosses from the left (cross(δ, u) < 0); a point right of the line, or both on it, makes Θ₀ empty.
For c, d strictly above the line of e_i and a, b strictly left of cd, a point c seen from b has a
larger heading than seen from a (cross(c − a, c − b) = |ê|·height(c) > 0), so the intersection of
the two cones is [ang(c − b), ang(d − a)]: Prop. 2. With b = c it is (0, ang(d − a)] and with
a = d it is [ang(c − b), π): Cor. 1.

**(2) Which headings a boundary point blocks.** Let Open = {p : p strictly left of a → b and of
c → d}. For u ∈ Θ₀, R(u) = Open ∩ {strictly right of the line a + t·u} ∩ {strictly left of the line
b + t·u}. For p strictly above the line of e_i, cross(u, p − a) = |p − a|·sin(ang(p − a) − θ), so p
is right of the a-line iff ang(p − a) < θ, and left of the b-line iff θ < ang(p − b). Hence p ∈ R(u)
⇔ p ∈ Open and ang(p − a) < θ < ang(p − b): **a point p ∈ Open blocks exactly the open interval
(ang(p − a), ang(p − b))** (non-empty: seen from b, p has the larger heading).

**(3) Whole edges.** Along a segment not through a, the heading of p − a is monotone (d/dλ of the
angle of p₀ + λv has the sign of cross(p₀, v), a constant), so for an edge E the union of the
blocked intervals of its points in Open — a connected union of open intervals — is the open interval
(min ang(q − a), max ang(q − b)) over the two ends q of the closure of E ∩ Open (an edge through a
has the constant heading of its direction, and β → π at a; symmetrically at b). So

    safe set  =  Θ₀  minus  ⋃_E (α_E, β_E),

a closed subset of (0, π) (Θ₀'s ends inside (0, π) are closed; only 0 and π are open), i.e. a finite
union of closed intervals, some possibly single points. This is :func:`safe_set`.

**(4) One interval without holes, several with holes.** Let A_x(j) (x ∈ {a, b}) be the headings u
such that the ray from x + ε(b − a) (resp. b − ε(b − a)) lands in the open e_j for all small ε > 0.
Then the safe set is A_a(j) ∩ A_b(j) minus, for every hole H lying strictly in Open, the open
interval (max_{v∈H} ang(v − a), min_{v∈H} ang(v − b)) (the headings whose R(u) contains all of H).
*Proof.* ⊆ is clear. ⊇: if a boundary point lies in R(u), its ring either lies entirely in R(u) —
then it is a hole and u is in its interval — or it reaches ∂R(u); it cannot cross the open sides
on e_i or e_j (open pieces of edges), so it enters R(u) from a point z of a closed corner side
[a, L_a] or [b, L_b]; the edge leaving z into R(u) is then met by the rays from the points of e_i
next to a (resp. b), so u ∉ A_a(j) (resp. A_b(j)). □
From a point x the headings whose first hit lies in the open e_j form an interval when P has no
holes: if two headings reach p₁, p₂ ∈ e_j, a boundary point hit in between lies in the triangle
x p₁ p₂, and its ring cannot leave that triangle (its sides are free, or open pieces of e_j, or the
point x on the open e_i), so it is a hole. Hence **without holes A_a(j) ∩ A_b(j) is one interval**
and so is the safe set; with holes it can be several: a hole strictly above the middle of e_i
blocks the heading π/2 but not π/4 or 3π/4 (``solverplan.proofs.safe_set_structure`` and the tests build
this room). The statement "the exact set of safe headings is an interval" holds for polygons without
holes only; :class:`SafeSet` keeps every interval and :attr:`SafeSet.interval` the widest.

>>> square = ((0, 0), (4, 0)), ((4, 4), (0, 4))      # floor → ceiling of a 4 × 4 room
>>> safe_interval(*square)                             # Prop. 2: [ang(c − b), ang(d − a)]
Interval(lo=1.5707963267948966, hi=1.5707963267948966)
>>> safe_action(*square).lo_direction                  # c − b, exact
(Fraction(0, 1), Fraction(4, 1))
>>> right = ((4, 0), (4, 4))                           # the next side, sharing b = (4, 0): Cor. 1
>>> round(safe_interval(square[0], right).hi, 6), transition_side(square[0], right), round(transition_angle(square[0], right), 6)
(0.785398, 'right', 1.570796)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Literal, Sequence

import numpy as np

from solverplan.interval import Interval
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, cross, dot, exact_point, exact_segment

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.environment import Environment

__all__ = [
    "Direction",
    "Transition",
    "SafeInterval",
    "SafeSet",
    "SafeAction",
    "heading_angle",
    "safe_interval",
    "safe_action",
    "safe_set",
    "heading_is_safe",
    "transition_side",
    "transition_angle",
]

Direction = tuple[Fraction, Fraction]
"""An exact direction vector (its length does not matter)."""

Transition = Literal["left", "right", "parallel"]
"""Paper Def. 8: where the supporting lines of e_i and e_j meet, seen in the frame of e_i."""

_Seg = tuple[ExactPoint, ExactPoint]


# ---------------------------------------------------------------------------------------------
# exact vector helpers
# ---------------------------------------------------------------------------------------------
def _sub(p: Sequence[Fraction], q: Sequence[Fraction]) -> Direction:
    return (p[0] - q[0], p[1] - q[1])


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def _neg(u: Direction) -> Direction:
    return (-u[0], -u[1])


def _segment(seg: object, name: str) -> _Seg:
    """Exact end points (a, b) of a segment given as a point pair or an object with ``.a`` and ``.b``."""
    return exact_segment((seg.a, seg.b) if hasattr(seg, "a") and hasattr(seg, "b") else seg, where=name)


def heading_angle(src: object, w: Sequence[object]) -> float:
    """The heading (radians, CCW from the direction of ``src``) of the vector ``w``, in (−π, π].

    >>> heading_angle(((0, 0), (1, 0)), (0, 1)), heading_angle(((0, 0), (1, 0)), (-1, 0))
    (1.5707963267948966, 3.141592653589793)
    """
    a, b = _segment(src, "src")
    e = _sub(b, a)
    w = exact_point(w, where="w")
    return _angle(e, w)


def _angle(e: Direction, w: Direction) -> float:
    return math.atan2(float(cross(e, w)), float(dot(e, w)))


# ---------------------------------------------------------------------------------------------
# headings as exact directions in the closed upper half-plane of ê
# ---------------------------------------------------------------------------------------------
def _hclass(e: Direction, u: Direction) -> int:
    """0: heading 0 (along ê); 1: heading in (0, π); 2: heading π; −1: below (not a heading)."""
    c = cross(e, u)
    if c > 0:
        return 1
    if c < 0:
        return -1
    return 0 if dot(e, u) > 0 else 2


def _hcmp(e: Direction, u: Direction, v: Direction) -> int:
    """Exact comparison of the headings of u and v (both in the closed upper half-plane of e)."""
    cu, cv = _hclass(e, u), _hclass(e, v)
    if cu != cv:
        return -1 if cu < cv else 1
    if cu != 1:
        return 0
    return -_sign(cross(u, v))


@dataclass(frozen=True, slots=True)
class _Bound:
    """An end of a heading set: an exact direction and whether the end belongs to the set."""

    direction: Direction
    closed: bool


def _lower_max(e: Direction, bounds: list[_Bound]) -> _Bound:
    best = bounds[0]
    for bound in bounds[1:]:
        c = _hcmp(e, bound.direction, best.direction)
        if c > 0 or (c == 0 and not bound.closed):
            best = bound
    return best


def _upper_min(e: Direction, bounds: list[_Bound]) -> _Bound:
    best = bounds[0]
    for bound in bounds[1:]:
        c = _hcmp(e, bound.direction, best.direction)
        if c < 0 or (c == 0 and not bound.closed):
            best = bound
    return best


def _theta0(src: _Seg, dst: _Seg) -> tuple[_Bound, _Bound] | None:
    """Θ₀: the headings whose landing points from a and b both lie on [c, d] (see the module proof, (1))."""
    a, b = src
    c, d = dst
    e = _sub(b, a)
    delta = _sub(d, c)
    lower = [_Bound(e, False)]
    upper = [_Bound(_neg(e), False)]
    sides = [_sign(cross(delta, _sub(x, c))) for x in (a, b)]  # > 0: strictly left of c → d
    if min(sides) < 0 or max(sides) == 0:
        return None
    for x, side in zip((a, b), sides):
        if side > 0:  # the closed cone from c − x to d − x, intersected with the upper half-plane
            cx, dx = _sub(c, x), _sub(d, x)
            sc, sd = _sign(cross(e, cx)), _sign(cross(e, dx))
            if sc <= 0 and sd <= 0:
                return None
            if sc > 0:
                lower.append(_Bound(cx, True))
            if sd > 0:
                upper.append(_Bound(dx, True))
        else:  # x on the line of e_j: it must be c or d, and the ray must cross from the free side
            if x != c and x != d:
                return None
            s = _sign(cross(e, delta))
            if s < 0:
                lower.append(_Bound(_neg(delta), False))
            elif s > 0:
                upper.append(_Bound(delta, False))
            elif dot(e, delta) > 0:
                return None  # along ê: the open half-plane right of δ misses every heading
    lo, hi = _lower_max(e, lower), _upper_min(e, upper)
    order = _hcmp(e, lo.direction, hi.direction)
    if order > 0 or (order == 0 and not (lo.closed and hi.closed)):
        return None
    return lo, hi


# ---------------------------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------------------------
def _interval(e: Direction, lo: Direction, hi: Direction) -> SafeInterval:
    """The safe interval between two exact end directions (lo ≤ hi exactly), with float ends; ties share one float."""
    flo, fhi = _angle(e, lo), _angle(e, hi)
    if _hclass(e, lo) == 0:
        flo = 0.0
    if _hclass(e, hi) == 2:
        fhi = math.pi
    if _hcmp(e, lo, hi) == 0 or fhi < flo:  # exact ties (or a difference below float resolution) share one value
        fhi = flo
    return SafeInterval(flo, fhi, lo, hi)


@dataclass(frozen=True, slots=True)
class SafeInterval(Interval):
    """One interval of safe headings (an :class:`~solverplan.interval.Interval`, radians) with its exact end
    directions.

    An end at 0 or π means "open there" (headings are in (0, π)), and its direction is then ±(b − a).
    ``lo_direction``/``hi_direction`` are exact vectors whose headings are the ends (e.g. c − b and d − a for
    Prop. 2).
    """

    lo_direction: Direction
    hi_direction: Direction

    @property
    def interval(self) -> Interval:
        """The plain interval [lo, hi], without the directions."""
        return Interval(self.lo, self.hi)


@dataclass(frozen=True, slots=True)
class SafeSet:
    """The exact set of safe headings from one segment to another: sorted, disjoint closed intervals.

    Without holes this is at most one interval; with holes it can be several (module docstring, (4)).
    :attr:`interval` is the widest one (``safe`` in the graph answer), :meth:`to_json` lists them all.
    """

    intervals: tuple[SafeInterval, ...] = ()

    @property
    def is_empty(self) -> bool:
        return not self.intervals

    @property
    def widest(self) -> SafeInterval | None:
        """The widest interval (the first of equal widths), ``None`` if there is none."""
        if not self.intervals:
            return None
        return max(self.intervals, key=lambda piece: piece.width)

    @property
    def interval(self) -> Interval:
        """The widest interval, :data:`Interval.EMPTY` if there is none."""
        widest = self.widest
        return Interval.EMPTY if widest is None else widest.interval

    def __contains__(self, theta: float) -> bool:
        return any(theta in piece for piece in self.intervals)

    def __len__(self) -> int:
        return len(self.intervals)

    def to_json(self) -> list[list[float]]:
        """``[[lo, hi], ...]`` in radians (``safe_set`` in the graph answer)."""
        return [[piece.lo, piece.hi] for piece in self.intervals]


@dataclass(frozen=True, slots=True)
class SafeAction:
    """Prop. 2 / Cor. 1 for one ordered pair: the unobstructed safe interval, exact ends, Def. 8 and φ."""

    interval: Interval
    lo_direction: Direction | None
    hi_direction: Direction | None
    transition: Transition
    phi: float


# ---------------------------------------------------------------------------------------------
# Prop. 2, Cor. 1, Def. 8
# ---------------------------------------------------------------------------------------------
def safe_interval(src: object, dst: object) -> Interval:
    """The safe headings from ``src`` = (a, b) to ``dst`` = (c, d) when nothing is in the way (paper Prop. 2).

    Both segments are oriented with the free space on their left; headings are radians CCW from
    b − a. For entirely visible segments (Def. 6) this is the exact safe set:

    - ``[ang(c − b), ang(d − a)]`` (Prop. 2; a singleton when c − b ∥ d − a, case 3),
    - ``(0, ang(d − a)]`` when dst follows src at a convex corner b = c, and ``[ang(c − b), π)`` when
      it precedes it at a = d (Cor. 1; the open end is reported as 0 or π),
    - :data:`Interval.EMPTY` when ang(c − b) > ang(d − a) (case 2), and whenever some point of the
      source cannot reach the target's line from its free side (reflex or flat shared corner, a
      target behind the source's line, ...).

    The ends are decided exactly (cross products of the exact end points); the floats are for
    reporting. For segments that are *not* entirely visible the result is only an upper bound: use
    :func:`safe_set`, which subtracts what is in the way.

    Parameters
    ----------
    src, dst
        Two end points each (numbers as in :func:`solverplan.exact.to_fraction`), or objects with
        ``.a`` and ``.b`` (a :class:`~solverplan.bounce.partitions.PartitionSegment`, an
        :class:`~solverplan.environment.Edge`).

    >>> safe_interval(((0, 0), (2, 0)), ((4, 2), (0, 2)))          # lines meet below e_i: case 1
    Interval(lo=0.7853981633974483, hi=1.5707963267948966)
    >>> safe_interval(((0, 0), (2, 0)), ((3, 2), (1, 2)))          # parallel: case 3, a singleton
    Interval(lo=1.1071487177940904, hi=1.1071487177940904)
    >>> safe_interval(((0, 0), (2, 0)), ((1, 2), (0, 2)))          # meet above: case 2
    Interval.EMPTY
    """
    return safe_action(src, dst).interval


def safe_action(src: object, dst: object) -> SafeAction:
    """:func:`safe_interval` with the exact end directions, the transition side (Def. 8) and φ_ij.

    ``lo_direction``/``hi_direction`` are exact vectors whose headings are the ends (c − b and d − a
    for Prop. 2; ±(b − a) for an open end at 0 or π), ``None`` for an empty interval.
    """
    s, t = _segment(src, "src"), _segment(dst, "dst")
    e = _sub(s[1], s[0])
    bounds = _theta0(s, t)
    side = _transition(s, t)
    phi = _phi(s, t, side)
    if bounds is None:
        return SafeAction(Interval.EMPTY, None, None, side, phi)
    lo, hi = bounds
    return SafeAction(_interval(e, lo.direction, hi.direction).interval, lo.direction, hi.direction, side, phi)


def _transition(src: _Seg, dst: _Seg) -> Transition:
    e = _sub(src[1], src[0])
    s = _sign(cross(e, _sub(dst[1], dst[0])))
    return "right" if s > 0 else "left" if s < 0 else "parallel"


def _phi(src: _Seg, dst: _Seg, side: Transition) -> float:
    e = _sub(src[1], src[0])
    delta = _sub(dst[1], dst[0])
    if side == "right":
        return math.pi - _angle(e, delta)
    if side == "left":
        return _angle(e, _neg(delta))
    return 0.0


def transition_side(src: object, dst: object) -> Transition:
    """Paper Def. 8: ``"right"`` if the supporting lines of src and dst meet beyond b (to the right
    of src in its own frame), ``"left"`` if before a, ``"parallel"`` if they do not meet.

    Decided exactly by the sign of cross(b − a, d − c): for every pair with a non-empty safe set
    (both a and b on or left of the line c → d) the lines meet beyond b exactly when that sign is
    positive. Adjacent segments: the next one (sharing b) is a right transition, the previous one
    (sharing a) a left one.

    >>> bottom = ((0, 0), (1, 0))
    >>> transition_side(bottom, ((1, 0), (1, 1))), transition_side(bottom, ((0, 1), (0, 0))), transition_side(bottom, ((1, 1), (0, 1)))
    ('right', 'left', 'parallel')
    """
    return _transition(_segment(src, "src"), _segment(dst, "dst"))


def transition_angle(src: object, dst: object) -> float:
    """φ_ij (radians, in [0, π)): the interior angle at the meeting point X of the supporting lines,
    between the ray from X towards src and the ray from X towards dst (the part of dst's line above
    src's line). For adjacent segments it is the interior angle of P′ at the shared vertex; 0 for
    parallel lines. With it the contraction coefficient of Lemma 2 is sin θ / sin(θ + φ) for a right
    transition and sin θ / sin(θ − φ) for a left one.

    >>> round(transition_angle(((0, 0), (4, 0)), ((4, 0), (1, 3))), 12) == round(math.pi / 4, 12)
    True
    """
    s, t = _segment(src, "src"), _segment(dst, "dst")
    return _phi(s, t, _transition(s, t))


# ---------------------------------------------------------------------------------------------
# the exact safe set of any pair (the reference)
# ---------------------------------------------------------------------------------------------
def _clip_open(p0: ExactPoint, p1: ExactPoint, planes: list[tuple[ExactPoint, Direction]]) -> tuple[Fraction, Fraction] | None:
    """Parameters [λ0, λ1] of the closure of {p0 + λ(p1 − p0) : λ ∈ [0, 1], strictly left of every
    line (point, direction)}, or None if that set is empty."""
    lo, hi = Fraction(0), Fraction(1)
    v = _sub(p1, p0)
    for point, direction in planes:
        f0 = cross(direction, _sub(p0, point))
        f1 = f0 + cross(direction, v)
        if f0 <= 0 and f1 <= 0:
            return None
        if f0 > 0 and f1 > 0:
            continue
        cut = f0 / (f0 - f1)
        if f0 > 0:
            hi = min(hi, cut)
        else:
            lo = max(lo, cut)
    return (lo, hi) if lo < hi else None


def _lerp(p0: ExactPoint, p1: ExactPoint, lam: Fraction) -> ExactPoint:
    return (p0[0] + lam * (p1[0] - p0[0]), p0[1] + lam * (p1[1] - p0[1]))


def _edge_blocks(src: _Seg, dst: _Seg, p0: ExactPoint, p1: ExactPoint) -> tuple[Direction, Direction] | None:
    """The open heading interval blocked by the closed edge p0p1 (module proof, (3)), or None."""
    a, b = src
    c, d = dst
    e = _sub(b, a)
    clipped = _clip_open(p0, p1, [(a, e), (c, _sub(d, c))])
    if clipped is None:
        return None
    q0, q1 = _lerp(p0, p1, clipped[0]), _lerp(p0, p1, clipped[1])

    def toward(x: ExactPoint, q: ExactPoint, other: ExactPoint) -> Direction:
        return _sub(other, x) if q == x else _sub(q, x)

    alphas = [toward(a, q0, q1), toward(a, q1, q0)]
    betas = [toward(b, q0, q1), toward(b, q1, q0)]
    alpha = alphas[0] if _hcmp(e, alphas[0], alphas[1]) <= 0 else alphas[1]
    beta = betas[0] if _hcmp(e, betas[0], betas[1]) >= 0 else betas[1]
    if _hcmp(e, alpha, beta) >= 0:
        return None
    return alpha, beta


def _subtract(e: Direction, lo: _Bound, hi: _Bound, blocked: list[tuple[Direction, Direction]]) -> list[tuple[_Bound, _Bound]]:
    """[lo, hi] minus a union of open intervals; closed pieces (open only where lo/hi were)."""
    from functools import cmp_to_key

    def by_start(x: tuple[Direction, Direction], y: tuple[Direction, Direction]) -> int:
        return _hcmp(e, x[0], y[0])

    blocked = sorted(blocked, key=cmp_to_key(by_start))
    pieces: list[tuple[_Bound, _Bound]] = []
    cur = lo
    for blo, bhi in blocked:
        if _hcmp(e, bhi, cur.direction) <= 0:
            continue  # ends before (or at) the current start: the start point stays
        if _hcmp(e, blo, hi.direction) >= 0:
            break
        if _hcmp(e, blo, cur.direction) >= 0:
            pieces.append((cur, _Bound(blo, True)))
        cur = _Bound(bhi, True) if _hcmp(e, bhi, cur.direction) > 0 else cur
    pieces.append((cur, hi))
    out = []
    for p_lo, p_hi in pieces:
        c = _hcmp(e, p_lo.direction, p_hi.direction)
        if c < 0 or (c == 0 and p_lo.closed and p_hi.closed):
            out.append((p_lo, p_hi))
    return out


def _safe_set(env: Environment, src: _Seg, dst: _Seg) -> SafeSet:
    e = _sub(src[1], src[0])
    bounds = _theta0(src, dst)
    if bounds is None:
        return SafeSet()
    verts, nxt = env.exact_vertices, env.next_vertex
    candidates = _edges_meeting_hull(env, src, dst)
    blocked = []
    for i in candidates:
        found = _edge_blocks(src, dst, verts[i], verts[int(nxt[i])])
        if found is not None:
            blocked.append(found)
    pieces = _subtract(e, bounds[0], bounds[1], blocked)
    return SafeSet(tuple(_interval(e, p.direction, q.direction) for p, q in pieces))


def _edges_meeting_hull(env: Environment, src: _Seg, dst: _Seg) -> list[int]:
    """Edges that may meet conv(a, b, c, d) (a float superset: bounding boxes with a margin).

    Every blocked heading comes from a point of Open inside some R(u) ⊂ conv(a, b, c, d), so edges
    whose boxes miss the hull's box cannot block.
    """
    pts = np.array([[float(x), float(y)] for x, y in (*src, *dst)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    margin = 1e-9 * (1.0 + float(np.abs(pts).max()))
    s, t = env.edge_start, env.edge_end
    emin, emax = np.minimum(s, t), np.maximum(s, t)
    keep = np.all((emax >= lo - margin) & (emin <= hi + margin), axis=1)
    return np.flatnonzero(keep).tolist()


def safe_set(env: Environment, src: object, dst: object) -> SafeSet:
    """The exact set of safe headings from ``src`` to ``dst`` in ``env`` (paper Def. 7), for any pair.

    ``src`` = (a, b) and ``dst`` = (c, d) are pieces of boundary edges, oriented with the free space
    on the left (segments of P′, edges, or point pairs). A heading θ is safe when the ray from every
    point of the open src first meets the boundary in the open dst. The result is Θ₀
    (:func:`safe_interval`) minus the open heading interval each boundary edge blocks (module
    docstring, (1)–(3)): sorted disjoint closed intervals, at most one for environments without holes,
    possibly several with holes. Exact (rational arithmetic); O(n) per pair — the reference that
    :func:`~solverplan.bounce.bvg.safe_bounce_visibility_graph` is tested against.

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[-12, 0], [12, 0], [12, 8], [-12, 8]], [[[-0.5, 2], [0.5, 2], [0.5, 3], [-0.5, 3]]])
    >>> found = safe_set(room, ((-1, 0), (1, 0)), ((12, 8), (-12, 8)))     # floor under the hole → ceiling
    >>> len(found), 1.5 in found, 0.8 in found, 2.3 in found
    (2, False, True, True)
    """
    return _safe_set(env, _segment(src, "src"), _segment(dst, "dst"))


def heading_is_safe(env: Environment, src: object, dst: object, direction: Sequence[object]) -> bool:
    """Exactly: is the heading of the vector ``direction`` safe from ``src`` to ``dst``? (Def. 7)

    ``direction`` is any non-zero vector, read exactly like coordinates (:func:`~solverplan.exact.to_fraction`:
    a Python float is its shortest decimal; pass Fractions for other values). True iff its heading
    lies in :func:`safe_set`.

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[-12, 0], [12, 0], [12, 8], [-12, 8]], [[[-0.5, 2], [0.5, 2], [0.5, 3], [-0.5, 3]]])
    >>> floor, ceiling = ((-1, 0), (1, 0)), ((12, 8), (-12, 8))
    >>> heading_is_safe(room, floor, ceiling, (1, 1)), heading_is_safe(room, floor, ceiling, (0, 1))
    (True, False)
    """
    s, t = _segment(src, "src"), _segment(dst, "dst")
    u = exact_point(direction, where="direction")
    if u[0] == u[1] == 0:
        raise InputError("direction (0, 0) is zero: it has no heading")
    return _heading_safe(env, s, t, u)


def _heading_safe(env: Environment, s: _Seg, t: _Seg, u: Direction) -> bool:
    e = _sub(s[1], s[0])
    if _hclass(e, u) != 1:
        return False
    bounds = _theta0(s, t)
    if bounds is None:
        return False
    lo, hi = bounds
    c_lo, c_hi = _hcmp(e, u, lo.direction), _hcmp(e, u, hi.direction)
    if c_lo < 0 or (c_lo == 0 and not lo.closed) or c_hi > 0 or (c_hi == 0 and not hi.closed):
        return False
    verts, nxt = env.exact_vertices, env.next_vertex
    for i in _edges_meeting_hull(env, s, t):
        found = _edge_blocks(s, t, verts[i], verts[int(nxt[i])])
        if found is not None and _hcmp(e, found[0], u) < 0 < _hcmp(e, found[1], u):
            return False
    return True
