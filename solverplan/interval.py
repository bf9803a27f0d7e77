"""Closed intervals of headings (radians), with an explicit empty state.

Safe actions, bounce rules and plans are intervals of headings θ ∈ (0, π) measured CCW from the
directed source edge. An :class:`Interval` is never reversed: a constructor call with lo > hi
raises, and an empty intersection is :data:`Interval.EMPTY`, whose width is 0 and which contains
nothing (a reversed interval whose width is taken with abs() would pass for a non-empty one).

>>> a, b = Interval(0.5, 1.5), Interval(1.0, 2.0)
>>> a & b
Interval(lo=1.0, hi=1.5)
>>> (a & Interval(1.6, 2.0)).is_empty
True
>>> Interval(0.5, 1.5).width, Interval.EMPTY.width
(1.0, 0.0)
>>> 1.2 in a, 1.2 in Interval.EMPTY
(True, False)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Iterable

from solverplan.errors import InvalidBoundarySet

__all__ = ["Interval", "heading_interval", "DEFAULT_HEADING_MARGIN"]

DEFAULT_HEADING_MARGIN = 1e-3
"""Radians: no strategy leaves within this of a wall (every planned interval lies in [δ, π − δ]): a robot
cannot execute a grazing heading, and a ray nearly along a wall ends next to a vertex."""


@dataclass(frozen=True, slots=True)
class Interval:
    """The closed interval [lo, hi] (radians), or the empty interval :data:`Interval.EMPTY`.

    ``lo == hi`` is a legal singleton (e.g. the parallel case of paper Prop. 2). Headings are measured CCW from
    the wall the robot is on, so the intervals of strategies lie inside (0, π).

    Parameters
    ----------
    lo, hi
        The ends (radians), ``lo ≤ hi``; a reversed pair raises :class:`ValueError` (the empty interval is
        :data:`Interval.EMPTY`, whose ends are NaN).

    Examples
    --------
    >>> import solverplan as sp
    >>> a = sp.Interval(0.5, 1.5)
    >>> a & sp.Interval(1.0, 2.0), a.width, a.midpoint, 1.2 in a
    (Interval(lo=1.0, hi=1.5), 1.0, 1.0, True)
    >>> (a & sp.Interval(1.6, 2.0)) is sp.Interval.EMPTY
    True
    """

    lo: float
    hi: float
    EMPTY: ClassVar["Interval"]

    def __post_init__(self) -> None:
        if math.isnan(self.lo) or math.isnan(self.hi):
            if not (math.isnan(self.lo) and math.isnan(self.hi)):
                raise ValueError(f"interval end is NaN: [{self.lo}, {self.hi}]")
        elif self.lo > self.hi:
            raise ValueError(f"reversed interval [{self.lo}, {self.hi}]: lo > hi (use Interval.EMPTY for none)")

    @property
    def is_empty(self) -> bool:
        """True only for :data:`Interval.EMPTY`."""
        return math.isnan(self.lo)

    @property
    def width(self) -> float:
        """hi − lo, and 0 for the empty interval."""
        return 0.0 if self.is_empty else self.hi - self.lo

    @property
    def midpoint(self) -> float:
        if self.is_empty:
            raise ValueError("the empty interval has no midpoint")
        return (self.lo + self.hi) / 2

    def __contains__(self, value: float) -> bool:
        return not self.is_empty and self.lo <= value <= self.hi

    def contains(self, other: Interval) -> bool:
        """Is ``other`` a subset of this interval? (The empty set is a subset of everything.)"""
        return other.is_empty or (not self.is_empty and self.lo <= other.lo and other.hi <= self.hi)

    def intersection(self, other: Interval) -> Interval:
        """The common part, :data:`Interval.EMPTY` if none."""
        if self.is_empty or other.is_empty:
            return Interval.EMPTY
        lo, hi = max(self.lo, other.lo), min(self.hi, other.hi)
        return Interval(lo, hi) if lo <= hi else Interval.EMPTY

    __and__ = intersection

    def hull(self, other: Interval) -> Interval:
        """The smallest interval containing both."""
        if self.is_empty:
            return other
        if other.is_empty:
            return self
        return Interval(min(self.lo, other.lo), max(self.hi, other.hi))

    def shrink(self, margin: float) -> Interval:
        """The interval with ``margin`` removed at both ends (empty if nothing is left)."""
        if self.is_empty:
            return self
        lo, hi = self.lo + margin, self.hi - margin
        return Interval(lo, hi) if lo <= hi else Interval.EMPTY

    @classmethod
    def intersect_all(cls, intervals: Iterable[Interval]) -> Interval:
        """Intersection of many intervals; the full heading range (0, π) closure if none given."""
        result = cls(0.0, math.pi)
        for interval in intervals:
            result = result & interval
        return result

    def to_json(self) -> list[float] | None:
        """``[lo, hi]``, or ``None`` for the empty interval (``safe: [lo, hi] or null`` in docs/contract.md)."""
        return None if self.is_empty else [self.lo, self.hi]

    def __repr__(self) -> str:
        return "Interval.EMPTY" if self.is_empty else f"Interval(lo={self.lo!r}, hi={self.hi!r})"


Interval.EMPTY = Interval(math.nan, math.nan)


def heading_interval(lo: float, hi: float) -> Interval:
    """A user-given heading interval: must satisfy 0 < lo ≤ hi < π (radians), else a one-line error.

    >>> heading_interval(0.0, 1.2)
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidBoundarySet: heading interval [0, 1.2] is not inside (0, π): lo=0
    """
    def text(x: float) -> str:
        return f"{x:g}"

    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InvalidBoundarySet(f"heading interval [{text(lo)}, {text(hi)}] is not finite")
    if lo > hi:
        raise InvalidBoundarySet(f"heading interval [{text(lo)}, {text(hi)}] is reversed: lo > hi")
    if lo <= 0:
        raise InvalidBoundarySet(f"heading interval [{text(lo)}, {text(hi)}] is not inside (0, π): lo={text(lo)}")
    if hi >= math.pi:
        raise InvalidBoundarySet(f"heading interval [{text(lo)}, {text(hi)}] is not inside (0, π): hi={text(hi)}")
    return Interval(lo, hi)
