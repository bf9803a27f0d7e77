"""Exact rational cones of floating-point heading intervals.

Planners compute heading intervals in floats (radians, counter-clockwise from the directed edge the
robot is on); exact work — certificates, exact position sets, exact return maps — needs rational world
directions instead. In the frame of an edge E a heading θ is the direction (cot θ, 1); we pick the
*simplest* rational u (smallest denominator, by continued fractions) whose heading acot(u) lies in a
small window next to the float end, and turn it back exactly: d = u·E + E⊥, with E⊥ the edge vector
turned by +90°. E and E⊥ have the same length, so the heading of d from E is exactly acot(u). Small
numbers keep exact arithmetic over long strategies cheap.

Which side of the float end the window lies on is the caller's choice (:func:`heading_cone`):

- **inside** (default): the exact cone lies inside the float interval, so a claim made of it (a
  certified width, a worst case over the cone) never exceeds what the float interval would give;
- **outside**: the exact cone contains the float interval, so every heading a robot may execute from
  the float interval is in the exact cone, and exact images of the cone hold every landing point.

The float cotangent is off by a few units in the last place; each window is shrunk by a bound on that
error (about 2·10⁻¹⁵ relative), so the inside/outside guarantee holds exactly, not just up to
rounding, whenever the window is wider than that (any margin above ~10⁻¹⁴ rad).

>>> from fractions import Fraction
>>> from solverplan.interval import Interval
>>> heading_direction((Fraction(1), Fraction(0)), 1.5, 1.6)   # straight up, the simplest direction there
(Fraction(0, 1), Fraction(1, 1))
>>> heading_cone((Fraction(10), Fraction(0)), Interval(0.5, 1.0), margin=0.01)   # headings 0.5071, 0.9995
((Fraction(9, 1), Fraction(5, 1)), (Fraction(9, 1), Fraction(14, 1)))
>>> heading_cone((Fraction(10), Fraction(0)), Interval(0.5, 1.0), margin=0.01, outside=True)   # 0.4993, 1.0041
((Fraction(11, 1), Fraction(6, 1)), (Fraction(7, 1), Fraction(11, 1)))
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Sequence

from solverplan.errors import InputError
from solverplan.exact import ExactPoint
from solverplan.interval import Interval

__all__ = ["heading_cone", "heading_direction", "DEFAULT_CONE_MARGIN"]

DEFAULT_CONE_MARGIN = 1e-13
"""Radians: the default width of the window next to each float end in which the exact end is chosen."""

_COT_REL_ERROR = 2.0**-49
"""Bound on the relative error of cos(θ)/sin(θ) in floats (a few ulps: cos, sin and the division)."""


def heading_cone(edge_vector: Sequence[Fraction | int], interval: Interval, *, margin: float = DEFAULT_CONE_MARGIN,
                 outside: bool = False) -> tuple[ExactPoint, ExactPoint]:
    """Exact world directions ``(d_lo, d_hi)`` for the two ends of a float heading interval from an edge.

    Parameters
    ----------
    edge_vector
        The directed edge's vector E (exact numbers); headings are measured counter-clockwise from it.
    interval
        The float heading interval [lo, hi] (radians), inside (0, π).
    margin
        Width (radians) of the window next to each end in which the exact end is chosen: the simplest
        rational cotangent there. Inside, it is at most a quarter of the interval's width (so the cone is
        never empty); outside, at most half the distance to 0 and π (so the cone stays inside (0, π)).
        A wider margin gives smaller numbers; a certificate's claims lose at most ``2·margin`` of width.
    outside
        ``False``: the exact ends lie in [lo, lo + margin] and [hi − margin, hi], the cone **inside** the
        interval. ``True``: they lie in [lo − margin, lo] and [hi, hi + margin], the cone **contains** it.

    Returns
    -------
    (d_lo, d_hi)
        Primitive integer vectors (as Fractions) whose headings from E are the exact cone's ends.

    Raises
    ------
    InputError
        An empty interval, or one not inside (0, π).
    """
    if interval.is_empty:
        raise InputError("heading interval is empty: it has no cone")
    lo, hi = float(interval.lo), float(interval.hi)
    if not 0.0 < lo <= hi < math.pi:
        raise InputError(f"heading interval [{lo!r}, {hi!r}] is not inside (0, π)")
    if not margin >= 0:
        raise InputError(f"cone margin {margin!r} is not a non-negative number of radians")
    if outside:
        m = min(margin, lo / 2, (math.pi - hi) / 2)
        return heading_direction(edge_vector, lo - m, lo), heading_direction(edge_vector, hi, hi + m)
    m = min(margin, (hi - lo) / 4)
    return heading_direction(edge_vector, lo, lo + m), heading_direction(edge_vector, hi - m, hi)


def heading_direction(edge_vector: Sequence[Fraction | int], lo: float, hi: float) -> ExactPoint:
    """The simplest exact direction whose heading from ``edge_vector`` lies in [lo, hi] (radians, in (0, π)).

    "Simplest" is the rational cotangent of smallest denominator in the window; the result is the
    primitive integer vector d = u·E + E⊥ (see the module docstring).
    """
    if not 0.0 < lo <= hi < math.pi:
        raise InputError(f"heading window [{lo!r}, {hi!r}] is not an interval inside (0, π)")
    # cot decreases on (0, π): headings [lo, hi] are cotangents [cot hi, cot lo]
    u_lo, u_hi = _cot(hi), _cot(lo)
    err_lo, err_hi = _cot_error(u_lo), _cot_error(u_hi)
    if u_hi - u_lo > 4 * (err_lo + err_hi):  # shrink by the float error, unless the window is narrower than it
        u_lo, u_hi = u_lo + err_lo, u_hi - err_hi
    return _turn(edge_vector, _simplest_between(u_lo, u_hi))


def _cot(theta: float) -> Fraction:
    return Fraction(math.cos(theta) / math.sin(theta))


def _cot_error(u: Fraction) -> Fraction:
    return abs(u) * Fraction(_COT_REL_ERROR)


def _turn(edge_vector: Sequence[Fraction | int], u: Fraction) -> ExactPoint:
    """u·E + E⊥, scaled to coprime integers (a positive multiple: the heading is unchanged)."""
    ex, ey = Fraction(edge_vector[0]), Fraction(edge_vector[1])
    x, y = u * ex - ey, u * ey + ex
    den = math.lcm(x.denominator, y.denominator)
    xi, yi = int(x * den), int(y * den)
    g = math.gcd(xi, yi) or 1
    return (Fraction(xi // g), Fraction(yi // g))


def _simplest_between(a: Fraction, b: Fraction) -> Fraction:
    """The rational with the smallest denominator in [a, b] (a ≤ b), by continued fractions."""
    if a <= 0 <= b:
        return Fraction(0)
    if b < 0:
        return -_simplest_between(-b, -a)
    whole = math.floor(a)
    if whole == a:
        return Fraction(whole)
    if whole + 1 <= b:
        return Fraction(whole + 1)
    return whole + 1 / _simplest_between(1 / (b - whole), 1 / (a - whole))
