"""The two lower-bound families of the exploration paper, as exact polygon generators.

Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility": Fig. 9 is a spiral
polygon without holes and Fig. 10 a polygon with one hole; for both the paper states that an exploration
starting from p₁ needs r + 1 views (r: reflex vertices of the free space). The paper gives pictures only, so
the shapes below are readings of those pictures that scale with a size parameter ``k``:

* :func:`spiral` — a corridor of width 1 that winds inward with ``k`` left turns; every turn puts one reflex
  vertex on the inner wall, so r = k, and p₁ is the centre of the dead-end cell at its outer end.
* :func:`one_hole` — a ring-shaped corridor between a convex (k + 2)-gon hole and the same polygon scaled by
  5/4 about its centre; the hole's vertices are the r = k + 2 reflex vertices, the outer ring is convex, and
  p₁ is the centroid of the first arm's four corners. The paper's "r + 1 views are necessary" does not hold
  for this shape: r views suffice (an exact chain over the outer corners, ``test_families.py``).

Every coordinate is an exact :class:`~fractions.Fraction`, so views and coverage are computed without
rounding. ``solverplan generate spiral --turns K`` and ``solverplan generate ring --sides K`` write them (the ring's
hole has K vertices: ``one_hole(K − 2)``).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError

__all__ = ["one_hole", "spiral"]

Point = tuple[Fraction, Fraction]

# East, north, west, south: a left turn steps to the next direction.
_DIRECTIONS = ((1, 0), (0, 1), (-1, 0), (0, -1))


def _check_size(k: int) -> None:
    if isinstance(k, bool) or not isinstance(k, int) or k < 1:
        raise InputError(f"the family size k is a positive integer, got {k!r}")


def _corridor(centre: Sequence[Point]) -> list[Point]:
    """The width-1 corridor around an axis-parallel polyline that turns left only.

    Each side is the polyline offset by 1/2; at a turn the offset corner is the centre vertex moved by half of
    each leg's left normal (so the left side gives the reflex corners, the right side the convex ones), and both
    ends are capped half a unit beyond the end vertices, which makes the end cells unit squares.

    Returns
    -------
    list of Point
        The ring: the right side forwards, then the left side backwards.
    """
    half = Fraction(1, 2)

    def direction(i: int) -> tuple[Fraction, Fraction]:
        (x0, y0), (x1, y1) = centre[i], centre[i + 1]
        length = abs(x1 - x0) + abs(y1 - y0)  # axis-parallel legs: this is the Euclidean length
        return (x1 - x0) / length, (y1 - y0) / length

    left: list[Point] = []
    right: list[Point] = []
    last = len(centre) - 1
    for i, (cx, cy) in enumerate(centre):
        if i in (0, last):
            dx, dy = direction(0 if i == 0 else last - 1)
            step = -half if i == 0 else half  # the cap lies outside the end vertex
            bx, by = cx + step * dx, cy + step * dy
            left.append((bx - half * dy, by + half * dx))
            right.append((bx + half * dy, by - half * dx))
        else:
            (ax, ay), (bx, by) = direction(i - 1), direction(i)
            nx, ny = -ay - by, ax + bx  # sum of the two left normals
            left.append((cx + half * nx, cy + half * ny))
            right.append((cx - half * nx, cy - half * ny))
    return right + left[::-1]


def spiral(k: int) -> tuple[Environment, Point]:
    """The spiral of Fig. 9 with ``k`` turns, and its start point p₁.

    The centre line starts at the origin heading east; its legs have lengths a, a, a, a − 2, a − 2, a − 4, …
    with a = 2k + 4, so that neighbouring windings keep a wall of thickness 1 between them and the shortest leg
    is at least 4 long (length units).

    Parameters
    ----------
    k
        The number of turns (≥ 1); the free space has exactly k reflex vertices.

    Returns
    -------
    Environment, Point
        The polygon (no holes) and p₁ = (0, 0), the centre of the dead-end cell at the outer end.

    >>> env, start = spiral(2)
    >>> len(env.reflex_vertices), start
    (2, (Fraction(0, 1), Fraction(0, 1)))
    """
    _check_size(k)
    a = 2 * k + 4
    centre: list[Point] = [(Fraction(0), Fraction(0))]
    for leg in range(k + 1):
        length = a if leg == 0 else a - 2 * ((leg - 1) // 2)
        dx, dy = _DIRECTIONS[leg % 4]
        x, y = centre[-1]
        centre.append((x + length * dx, y + length * dy))
    return Environment.from_coords(_corridor(centre), name=f"spiral-{k}"), centre[0]


def _circle_point(angle: float) -> Point:
    """A rational point exactly on the unit circle, near ``angle`` (radians).

    The tangent half-angle t is rounded to a multiple of 1/256 and mapped through the rational
    parametrisation ((1 − t²)/(1 + t²), 2t/(1 + t²)), so the point lies on the circle exactly.
    """
    t = Fraction(round(math.tan(angle / 2) * 256), 256)
    return (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)


def one_hole(k: int) -> tuple[Environment, Point]:
    """The one-hole polygon of Fig. 10 read as a ring corridor around a convex (k + 2)-gon, and p₁.

    The hole's vertices are points of the unit circle at angles 2π(i + 1/4)/(k + 2) (rounded to rational
    points on the circle, so the hole is convex); the outer ring is the hole scaled by 5/4 about the origin.
    The quarter-step offset keeps every angle away from π, where the rational parametrisation has no point.

    Parameters
    ----------
    k
        The size (≥ 1); the hole has k + 2 vertices, all reflex vertices of the free space, and the outer ring
        has none.

    Returns
    -------
    Environment, Point
        The polygon with its hole and p₁, the average of the four corners of the first arm (between the first
        two hole vertices and their outer copies).

    >>> env, start = one_hole(1)
    >>> len(env.holes), len(env.reflex_vertices)
    (1, 3)
    """
    _check_size(k)
    m = k + 2
    hole = [_circle_point(2 * math.pi * (i + 0.25) / m) for i in range(m)]
    scale = Fraction(5, 4)
    outer = [(scale * x, scale * y) for x, y in hole]
    corners = (hole[0], hole[1], outer[1], outer[0])
    start = (sum((c[0] for c in corners), Fraction(0)) / 4, sum((c[1] for c in corners), Fraction(0)) / 4)
    return Environment.from_coords(outer, [hole], name=f"one-hole-{k}"), start
