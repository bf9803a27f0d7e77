"""Rigorous rational enclosures of arctangents, angles and headings, for the certificate checker.

Every angle the checker decides (the headings of a stage's cones, their widths) is an arctangent of
a rational number, which is transcendental, so it is decided by enclosing it between two rationals
and refining until a comparison is decided:

- the alternating series Σ (−1)^k w^(2k+1) / (2k+1) for |w| ≤ 1/16 lies between consecutive partial
  sums (its terms decrease in size);
- the argument is reduced exactly by atan x = π/2 − atan(1/x) (x > 1) and
  atan x = atan c + atan((x − c)/(1 + c x)) with c = k/8 nearest to x; atan(k/8) and π (Machin's
  formula) are themselves enclosed by series; arguments with huge denominators are rounded outward
  to dyadic rationals (atan is increasing);
- a comparison of an angle with a rational number (:func:`compare_angle`) is refined (64, 128, …
  bits) until the enclosure excludes the number. It always terminates: the heading of a rational
  vector that is not along the positive x-axis is transcendental (Lindemann–Weierstrass), so it
  never equals a rational; differences of two headings are reduced to the heading of one rational
  vector (:func:`difference_vector`), so the same holds, and the one exact tie (angle 0, identical
  directions) is decided by a cross product.

Only the standard library and :mod:`solverplan.certify.exact2d` are used: no floats anywhere.

>>> lo, hi = atan_enclosure(Fraction(1))
>>> Fraction(7853981633974483, 10**16) < lo <= hi < Fraction(7853981633974484, 10**16)   # π/4 = 0.78539816339744830961...
True
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.exact2d import cross, dot, sign
from solverplan.certify.schema import Point, number_text, point_text

__all__ = [
    "MAX_BITS",
    "Undecided",
    "atan_enclosure",
    "pi_enclosure",
    "angle_enclosure",
    "heading_vector",
    "heading_enclosure",
    "compare_angle",
    "difference_vector",
]

MAX_BITS = 1 << 14
"""Largest precision (bits) tried when deciding an angle comparison; never reached in practice."""

_ZERO = Fraction(0)


class Undecided(ArithmeticError):
    """An angle comparison could not be decided within :data:`MAX_BITS` bits."""


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
    of d measured counter-clockwise from E (the paper's convention), exactly as a rational vector."""
    return (dot(edge_vector, d), cross(edge_vector, d))


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
        return sign(-r)
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


def difference_vector(w_from: Point, w_to: Point) -> Point:
    """A rational vector whose angle is angle(w_to) − angle(w_from), for angles in (0, π)."""
    return (dot(w_from, w_to), cross(w_from, w_to))
