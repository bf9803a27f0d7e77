"""Exact numbers and the orientation family of predicates.

The lowest layer of solverplan: everything that decides a tie (collinear, parallel,
on-vertex) comes here. Coordinates are :class:`fractions.Fraction` (decimals from
files are read exactly, never through binary floats). Every predicate has a float
*filter*: a vectorised numpy version that answers when the float answer is provably
right and says "uncertain" (0) otherwise, so exact arithmetic runs only near ties.

>>> orient((0, 0), (1, 0), (0, 1))
1
>>> orient((0, 0), (1, 1), (Fraction(1, 3), Fraction(1, 3)))
0
>>> segment_intersection((0, 0), (2, 2), (2, 0), (0, 2))
SegmentIntersection(kind='point', points=((Fraction(1, 1), Fraction(1, 1)),))
>>> format_point((Fraction(1, 2), Fraction(1, 3)))
'(0.5, 1/3)'
"""

from __future__ import annotations

import math
import operator
import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from numbers import Rational
from typing import Literal, Sequence, TypeVar

import numpy as np

from solverplan.errors import InputError
from solverplan.limits import COORDINATE_RESOLUTION, MAX_COORDINATE, MAX_DECIMAL_EXPONENT, MAX_NUMBER_CHARS, quote

__all__ = [
    "cross",
    "dot",
    "signed_area2",
    "ExactPoint",
    "to_fraction",
    "exact_point",
    "exact_segment",
    "ring_without_repeats",
    "format_number",
    "json_number",
    "json_point",
    "format_point",
    "orient",
    "orient_filter",
    "SegmentIntersection",
    "segment_intersection",
    "line_intersection",
    "on_segment",
    "point_in_ring",
    "FLOAT_FILTER_REL",
]

ExactPoint = tuple[Fraction, Fraction]
"""A point with exact rational coordinates."""

_P = TypeVar("_P")

# Relative error bound of the float orientation determinant when the coordinates are
# themselves roundings of exact rationals (one rounding per coordinate, then two
# subtractions, two products and a difference): about 12 u with u = 2**-53. We use
# ten times that, so a sign the filter certifies is the exact sign.
FLOAT_FILTER_REL = 1.5e-14

_FRACTION_TEXT = re.compile(r"^\s*[+-]?\d+\s*/\s*\d+\s*$")


def to_fraction(value: object, *, where: str = "value") -> Fraction:
    """Convert a user-supplied number to an exact :class:`Fraction`.

    Integers, fractions and :class:`~decimal.Decimal` are exact. Python floats are taken
    at their shortest decimal representation (``0.1`` is 1/10, the number the user typed,
    not the binary float nearest to it). Strings may hold a decimal (``"0.25"``, ``"1e-3"``)
    or a ratio (``"1/3"``).

    Raises
    ------
    InputError
        ``where`` names the place, e.g. ``outer ring vertex 2: coordinate 'abc' is not a number``;
        NaN and infinities are rejected as non-finite.
    """
    if type(value) is Decimal and value.is_finite():  # what files hold: the common case first
        _check_decimal_size(value, where)
        return Fraction(value)
    if isinstance(value, bool):
        raise InputError(f"{where}: {value!r} is not a number")
    if isinstance(value, Fraction):
        return value
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, Rational):
        return Fraction(int(value.numerator), int(value.denominator))
    if isinstance(value, np.generic):
        return to_fraction(value.item(), where=where)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(f"{where}: coordinate is not finite ({value!r})")
        return Fraction(repr(float(value)))
    if isinstance(value, Decimal):
        if not value.is_finite():
            raise InputError(f"{where}: coordinate is not finite ({value})")
        _check_decimal_size(value, where)
        return Fraction(value)
    if isinstance(value, str):
        text = value.strip()
        if len(text) > MAX_NUMBER_CHARS:
            raise InputError(f"{where}: number {quote(text)} is {len(text)} characters long (at most {MAX_NUMBER_CHARS})")
        if _FRACTION_TEXT.match(text):
            num, den = (int(part) for part in text.split("/"))
            if den == 0:
                raise InputError(f"{where}: {quote(value)} divides by zero")
            return Fraction(num, den)
        try:
            number = Decimal(text)
        except InvalidOperation:
            raise InputError(f"{where}: {quote(value)} is not a number") from None
        return to_fraction(number, where=where)
    raise InputError(f"{where}: {quote(value)} is not a number")


def _check_decimal_size(value: Decimal, where: str) -> None:
    """Refuse a decimal whose exact value would be huge to compute with (``1e-999999``, 5,000 digits)."""
    sign_digits_exponent = value.as_tuple()
    digits = len(sign_digits_exponent.digits)
    exponent = sign_digits_exponent.exponent
    assert isinstance(exponent, int)  # finite decimals only reach here
    if digits > MAX_NUMBER_CHARS:
        raise InputError(f"{where}: number has {digits} digits (at most {MAX_NUMBER_CHARS})")
    if abs(exponent) > MAX_DECIMAL_EXPONENT or abs(value.adjusted()) > MAX_DECIMAL_EXPONENT:
        raise InputError(
            f"{where}: number {quote(str(value))} has decimal exponent {value.adjusted()} (at most ±{MAX_DECIMAL_EXPONENT})"
        )


def exact_point(xy: Sequence[object], *, where: str = "point") -> ExactPoint:
    """Convert a pair of numbers to an exact point; see :func:`to_fraction`."""
    if isinstance(xy, (str, bytes)) or not hasattr(xy, "__len__") or len(xy) != 2:
        raise InputError(f"{where}: expected a pair [x, y], got {quote(xy)}")
    point = (to_fraction(xy[0], where=where), to_fraction(xy[1], where=where))
    for c in point:
        check_coordinate(c, where)
    return point


def exact_segment(seg: object, *, where: str = "segment") -> tuple[ExactPoint, ExactPoint]:
    """The exact end points of a segment given as two points; one line naming ``where`` for anything else, or for a
    segment of zero length.

    >>> exact_segment(((0, 0), ("1/2", 1)))
    ((Fraction(0, 1), Fraction(0, 1)), (Fraction(1, 2), Fraction(1, 1)))
    >>> exact_segment(((1, 1), (1, 1)), where="src")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: src has zero length: both end points are (1, 1)
    """
    first: Sequence[object]
    second: Sequence[object]
    try:
        first, second = seg  # type: ignore[misc]
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected two end points ((x0, y0), (x1, y1)), got {quote(seg)}") from None
    a, b = exact_point(first, where=where), exact_point(second, where=where)
    if a == b:
        raise InputError(f"{where} has zero length: both end points are {format_point(a)}")
    return a, b


def ring_without_repeats(points: Sequence[_P]) -> list[_P]:
    """The closed ring through ``points`` without repeated consecutive points (the last one included, against the
    first).

    >>> ring_without_repeats([(0, 0), (1, 0), (1, 0), (1, 1), (0, 0)])
    [(0, 0), (1, 0), (1, 1)]
    """
    ring: list[_P] = []
    for p in points:
        if not ring or ring[-1] != p:
            ring.append(p)
    while len(ring) > 1 and ring[0] == ring[-1]:
        ring.pop()
    return ring


def check_coordinate(c: Fraction, where: str) -> None:
    """Refuse a coordinate (or length) past the documented magnitude 1e100 or resolution 1e-100.

    Past them floats overflow (``1e309``) or vanish (``1e-309``) where the exact value still means something,
    so a float step later would divide by zero or overflow: refused here in one line instead.

    >>> check_coordinate(Fraction(1, 10**309), "--range")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: --range: 1e-309 is finer than 1e-100 (the finest step read)
    """
    if abs(c.numerator) > MAX_COORDINATE * c.denominator:  # |c| > MAX_COORDINATE, in integers
        raise InputError(f"{where}: {_magnitude(c)} is larger than 1e100 in magnitude")
    if c.denominator > COORDINATE_RESOLUTION:
        raise InputError(f"{where}: {_magnitude(c)} is finer than 1e-100 (the finest step read)")


def _magnitude(c: Fraction) -> str:
    """``c`` in a few characters (``1e-309``, ``-3.2e+400``): its exact text can have hundreds of digits."""
    text = f"{Decimal(c.numerator) / Decimal(c.denominator):.2g}"
    return text.replace("E", "e")


def format_number(value: Fraction | int | float) -> str:
    """Shortest faithful text for a number: ``3``, ``0.25``, ``1/3`` (exact), floats as ``repr``."""
    if isinstance(value, float):
        return repr(value)
    value = Fraction(value)
    if value.denominator == 1:
        return _long_int_text(value.numerator)
    den = value.denominator
    twos = fives = 0
    while den % 2 == 0:
        den //= 2
        twos += 1
    while den % 5 == 0:
        den //= 5
        fives += 1
    if den == 1:  # terminating decimal: print it exactly
        digits = max(twos, fives)
        scaled = value * 10**digits
        sign = "-" if scaled < 0 else ""
        text = _long_int_text(abs(scaled.numerator)).rjust(digits + 1, "0")
        return f"{sign}{text[:-digits]}.{text[-digits:]}"
    return _long_int_text(value.numerator) + "/" + _long_int_text(value.denominator)


def _long_int_text(n: int) -> str:
    """``str(n)`` for integers of any length: products along long cycles exceed Python's 4,300-digit guard,
    which protects parsers of untrusted text, not the printing of numbers we computed. Past it the digits come
    from :class:`~decimal.Decimal`, exact for integers and outside the guard, so the guard (a setting of the whole
    process, which other threads rely on) is never lifted."""
    return str(n) if n.bit_length() < 14_000 else str(Decimal(n))


def json_number(value: Fraction | int) -> int | float | str:
    """An exact number as JSON: integers as integers, decimals whose shortest float text is exact as
    numbers, anything else as an exact string (``"1/3"``, or a long decimal) that :func:`to_fraction` reads back.

    >>> json_number(Fraction(5, 2)), json_number(Fraction(1, 3)), json_number(7)
    (2.5, '1/3', 7)
    """
    if type(value) is not Fraction:
        value = Fraction(value)
    num, den = value.numerator, value.denominator
    if den == 1 and num.bit_length() < 13_000:
        return int(num)
    if den != 1 and abs(num) < den << 53:  # a float past 2**53 is an integer
        number = num / den  # correctly rounded
        # the shortest text of the float is exact when its decimal value is the value itself
        if Decimal(repr(number)).as_integer_ratio() == (num, den):
            return number
    return format_number(value)  # also integers past Python's digit guard: JSON encoders refuse to print them


def json_point(p: Sequence[Fraction | int]) -> list[int | float | str]:
    """An exact point as JSON: ``[x, y]`` with :func:`json_number` coordinates.

    >>> json_point((Fraction(1, 3), Fraction(5, 2)))
    ['1/3', 2.5]
    """
    return [json_number(p[0]), json_number(p[1])]


def format_point(p: Sequence[Fraction | int | float]) -> str:
    """``(x, y)`` with :func:`format_number` coordinates, for messages; a coordinate whose exact text is longer
    than 24 characters is written ``≈`` its float (messages stay one short line).

    >>> format_point((Fraction(1, 3), 2)), format_point((Fraction(10**30 + 1, 3 * 10**29), 0))
    ('(1/3, 2)', '(≈3.33333333333, 0)')
    """
    def text(x: Fraction | int | float) -> str:
        exact = format_number(x)
        return exact if len(exact) <= 24 else f"≈{float(x):.12g}"

    return f"({text(p[0])}, {text(p[1])})"


def cross(u: Sequence[Fraction | int], v: Sequence[Fraction | int]) -> Fraction:
    """The cross product u × v = u_x v_y − u_y v_x, exact: > 0 when v is counter-clockwise of u.

    >>> cross((1, 0), (0, 1)), cross((Fraction(1, 2), 1), (1, 2))
    (1, Fraction(0, 1))
    """
    return u[0] * v[1] - u[1] * v[0]  # type: ignore[return-value]


def dot(u: Sequence[Fraction | int], v: Sequence[Fraction | int]) -> Fraction:
    """The dot product u · v, exact.

    >>> dot((1, 2), (3, Fraction(1, 2)))
    Fraction(4, 1)
    """
    return u[0] * v[0] + u[1] * v[1]  # type: ignore[return-value]


def signed_area2(ring: Sequence[ExactPoint]) -> Fraction:
    """Twice the signed area (shoelace), exact: positive for a CCW ring.

    Decimal coordinates share small denominators: over their common denominator the sum is one of
    integers (fast); a ring whose common denominator is huge is summed in fractions.

    >>> signed_area2([(Fraction(0), Fraction(0)), (Fraction(2), Fraction(0)), (Fraction(0), Fraction(1))])
    Fraction(2, 1)
    """
    xs = [p[0] for p in ring]
    ys = [p[1] for p in ring]
    common = math.lcm(*(x.denominator for x in xs), *(y.denominator for y in ys))
    if common.bit_length() > 512:
        total = Fraction(0)
        n = len(ring)
        for i in range(n):
            (x0, y0), (x1, y1) = ring[i], ring[(i + 1) % n]
            total += x0 * y1 - x1 * y0
        return total
    X = [x.numerator * (common // x.denominator) for x in xs]
    Y = [y.numerator * (common // y.denominator) for y in ys]
    X1, Y1 = X[1:] + X[:1], Y[1:] + Y[:1]
    return Fraction(sum(map(operator.mul, X, Y1)) - sum(map(operator.mul, X1, Y)), common * common)


def orient(a: Sequence[Fraction | int], b: Sequence[Fraction | int], c: Sequence[Fraction | int]) -> int:
    """Exact sign of the turn a → b → c: +1 left (CCW), −1 right (CW), 0 collinear."""
    det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (det > 0) - (det < 0)


def orient_filter(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Vectorised float filter for :func:`orient`.

    ``a``, ``b``, ``c`` are float arrays of shape (..., 2), roundings of exact points.
    Returns int8 signs: +1 / −1 where the float determinant is provably of that exact
    sign, 0 where it is too close to call (then use :func:`orient`).
    """
    with np.errstate(over="ignore", invalid="ignore"):  # overflow → inf/nan → "uncertain" below
        det = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
        # bound in terms of the coordinates' magnitudes (covers the rounding of the inputs too)
        mag = (np.abs(a[..., 0]) + np.abs(b[..., 0]) + np.abs(c[..., 0])) * (
            np.abs(a[..., 1]) + np.abs(b[..., 1]) + np.abs(c[..., 1])
        )
        bound = FLOAT_FILTER_REL * mag
    sign = np.zeros(det.shape, dtype=np.int8)
    finite = np.isfinite(det) & np.isfinite(bound)
    sign[finite & (det > bound)] = 1
    sign[finite & (det < -bound)] = -1
    return sign


@dataclass(frozen=True, slots=True)
class SegmentIntersection:
    """How two closed segments meet: at one ``point``, or along an ``overlap`` (two end points)."""

    kind: Literal["point", "overlap"]
    points: tuple[ExactPoint, ...]


def _between(p: Sequence[Fraction], a: Sequence[Fraction], b: Sequence[Fraction]) -> bool:
    """For p collinear with a, b: is p on the closed segment ab?"""
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def on_segment(p: Sequence[Fraction], a: Sequence[Fraction], b: Sequence[Fraction]) -> bool:
    """Exactly: does p lie on the closed segment ab?"""
    return orient(a, b, p) == 0 and _between(p, a, b)


def line_intersection(
    a: Sequence[Fraction], b: Sequence[Fraction], c: Sequence[Fraction], d: Sequence[Fraction]
) -> ExactPoint | None:
    """Exact intersection of the lines ab and cd, or ``None`` if they are parallel (or equal)."""
    rx, ry = b[0] - a[0], b[1] - a[1]
    sx, sy = d[0] - c[0], d[1] - c[1]
    den = rx * sy - ry * sx
    if den == 0:
        return None
    lam = Fraction((c[0] - a[0]) * sy - (c[1] - a[1]) * sx) / den
    return (a[0] + lam * rx, a[1] + lam * ry)


def segment_intersection(
    a: Sequence[Fraction], b: Sequence[Fraction], c: Sequence[Fraction], d: Sequence[Fraction]
) -> SegmentIntersection | None:
    """Exact intersection of the closed segments ab and cd (``None`` if disjoint).

    Touching counts: an end point on the other segment is a ``point`` intersection.
    Collinear segments sharing more than a point give an ``overlap`` with its two ends.
    """
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    if o1 == o2 == 0:  # collinear (or degenerate): overlap of 1-D intervals, ordered lexicographically
        lo1, hi1 = sorted((tuple(a), tuple(b)))
        lo2, hi2 = sorted((tuple(c), tuple(d)))
        lo, hi = max(lo1, lo2), min(hi1, hi2)
        if lo > hi:
            return None
        lo = (Fraction(lo[0]), Fraction(lo[1]))
        hi = (Fraction(hi[0]), Fraction(hi[1]))
        if lo == hi:
            return SegmentIntersection("point", (lo,))
        return SegmentIntersection("overlap", (lo, hi))
    if o1 * o2 > 0 or o3 * o4 > 0:
        return None
    if o1 == 0:
        return SegmentIntersection("point", ((Fraction(c[0]), Fraction(c[1])),))
    if o2 == 0:
        return SegmentIntersection("point", ((Fraction(d[0]), Fraction(d[1])),))
    if o3 == 0:
        return SegmentIntersection("point", ((Fraction(a[0]), Fraction(a[1])),))
    if o4 == 0:
        return SegmentIntersection("point", ((Fraction(b[0]), Fraction(b[1])),))
    point = line_intersection(a, b, c, d)
    assert point is not None  # proper crossing: lines are not parallel
    return SegmentIntersection("point", (point,))


def point_in_ring(p: Sequence[Fraction], ring: Sequence[Sequence[Fraction]]) -> int:
    """Exact location of p relative to a simple closed ring: +1 inside, 0 on the boundary, −1 outside.

    Crossing-number test with half-open edge rule; orientation-independent.
    """
    inside = False
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if on_segment(p, a, b):
            return 0
        if (a[1] > p[1]) != (b[1] > p[1]):
            # x of the edge at height p.y, compared exactly without division
            side = orient(a, b, p)
            if (b[1] > a[1] and side > 0) or (b[1] < a[1] and side < 0):
                inside = not inside
    return 1 if inside else -1
