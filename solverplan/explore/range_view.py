"""Range-limited visibility: RVP(z) = VP(z) ∩ disc(z, R), with its circular arcs as arcs.

Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility", section "An Exploration
Algorithm with Range Restriction" (Fig. 12): a range sensor sees only the part of the visibility polygon within
distance R of the viewpoint. The boundary of RVP(z) is made of *segments* (what is left of the visibility
polygon's edges, partial edges and constructed edges inside the disc) and *circular arcs* of the range circle
(where the visibility polygon reaches farther than R).

Representation. The visibility polygon is exact (:func:`~solverplan.geometry.visibility.visibility_polygon`)
and the viewpoint and R are exact rationals, so every arc has an exact centre and radius and "is q in RVP(z)?"
is decided exactly (:meth:`RangeView.contains`). Where a side of the visibility polygon crosses the range
circle the crossing point is in general irrational: those end points (and the arcs' angles) are floats, and a
segment keeps its exact end points wherever they lie inside the disc. The area is computed from the pieces
(sector terms for the arcs, no polygonal approximation); :meth:`RangeView.to_shapely` gives an inscribed
polygon whose chords stay within a stated sagitta of the arcs, for unions and coverage measurement only.

Because VP(z) is star-shaped from z, the clipped region is {z + ρ·(cos θ, sin θ) : ρ ≤ min(R, ρ_VP(θ))}: walking
the visibility polygon's counter-clockwise ring, each side keeps its part inside the disc (one interval, the
disc being convex), and between a side that leaves the disc and the next one that enters it the boundary is the
arc between their angles. When no side meets the disc the view is the whole disc (one arc of 2π).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]])
>>> rv = range_visibility(square, (5, 1), 2)
>>> [piece.kind for piece in rv.pieces]
['partial', 'arc']
>>> round(rv.area, 6), rv.contains((5, 3)), rv.contains((5, 3.01))    # the disc minus the segment below y = 0
(10.109631, True, False)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal, Sequence, Union

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, exact_point, point_in_ring, to_fraction
from solverplan.geometry.visibility import VisibilityPolygon, visibility_polygon

__all__ = ["Arc", "RangeSegment", "RangeView", "range_visibility", "check_range", "DEFAULT_SAGITTA"]

FloatPoint = tuple[float, float]

DEFAULT_SAGITTA = 1e-7
"""Largest gap between an arc and its chords in :meth:`RangeView.to_shapely`, as a fraction of R."""


def check_range(range_: object) -> Fraction:
    """R as an exact rational; anything but a finite number > 0 is bad input."""
    if isinstance(range_, float) and not math.isfinite(range_):
        raise InputError(f"range R must be a finite number > 0, got {range_!r}")
    R = to_fraction(range_, where="range R")
    if R <= 0:
        raise InputError(f"range R must be a finite number > 0, got {range_!r}")
    return R


@dataclass(frozen=True, slots=True)
class Arc:
    """A counter-clockwise arc of the range circle: centre (exact), radius R (exact) and angles (radians, float).

    ``start_angle < end_angle ≤ start_angle + 2π``; a full circle has ``end_angle = start_angle + 2π``.
    """

    centre: ExactPoint
    radius: Fraction
    start_angle: float
    end_angle: float
    kind: Literal["arc"] = "arc"

    @property
    def span(self) -> float:
        """The angle swept, radians."""
        return self.end_angle - self.start_angle

    def point(self, angle: float) -> FloatPoint:
        r = float(self.radius)
        return (float(self.centre[0]) + r * math.cos(angle), float(self.centre[1]) + r * math.sin(angle))

    @property
    def start(self) -> FloatPoint:
        return self.point(self.start_angle)

    @property
    def end(self) -> FloatPoint:
        return self.point(self.end_angle)

    def chord_points(self, sagitta: float = DEFAULT_SAGITTA) -> list[FloatPoint]:
        """Points on the arc from its start to its end (both included), chords within ``sagitta``·R of it."""
        import numpy as np

        step = 2 * math.acos(1 - sagitta)  # chord of angle step has sagitta R(1 − cos(step/2))
        count = max(1, math.ceil(self.span / step))
        angles = np.linspace(self.start_angle, self.end_angle, count + 1)
        r = float(self.radius)
        xs = float(self.centre[0]) + r * np.cos(angles)
        ys = float(self.centre[1]) + r * np.sin(angles)
        return list(zip(xs.tolist(), ys.tolist()))

    def to_json(self) -> dict:
        return {"centre": [float(self.centre[0]), float(self.centre[1])], "radius": float(self.radius),
                "start_angle": self.start_angle, "end_angle": self.end_angle}


@dataclass(frozen=True, slots=True)
class RangeSegment:
    """What is left inside the disc of one side of the visibility polygon.

    ``kind``, ``edge`` and ``reflex_vertex`` are the side's (:class:`~solverplan.geometry.visibility.VisibilityPiece`).
    ``a`` and ``b`` are its end points as floats; ``a_exact`` / ``b_exact`` are the exact end points where they
    are the side's own (inside the disc) and ``None`` where the side was cut by the range circle.
    """

    kind: Literal["edge", "partial", "constructed"]
    a: FloatPoint
    b: FloatPoint
    a_exact: ExactPoint | None
    b_exact: ExactPoint | None
    edge: int | None
    reflex_vertex: int | None


Piece = Union[RangeSegment, Arc]


@dataclass(frozen=True, slots=True)
class RangeView:
    """RVP(z) = VP(z) ∩ disc(z, R): the exact visibility polygon, the range, and the boundary pieces in CCW order.

    Made by :func:`range_visibility`.

    Attributes
    ----------
    viewpoint
        z, exact (length units of the environment).
    radius
        R, exact.
    polygon
        VP(z), the exact visibility polygon (unrestricted by range).
    pieces
        The boundary of RVP(z) in CCW order: straight pieces (:attr:`segments`: walls, windows, chords) and
        circular arcs of radius R (:attr:`arcs`).
    arcs, segments
        The pieces of each kind.

    Examples
    --------
    >>> import solverplan as sp
    >>> view = sp.range_visibility(sp.load_environment("l_shape"), (2, 2), 3)
    >>> len(view.arcs), len(view.segments), view.is_unrestricted
    (2, 4, False)
    >>> round(view.area, 4), view.contains((2, 4.9)), view.contains((8, 2))   # square units; 6 units away
    (22.0794, True, False)
    """

    viewpoint: ExactPoint
    radius: Fraction
    polygon: VisibilityPolygon
    pieces: tuple[Piece, ...]

    @property
    def arcs(self) -> tuple[Arc, ...]:
        return tuple(p for p in self.pieces if isinstance(p, Arc))

    @property
    def segments(self) -> tuple[RangeSegment, ...]:
        return tuple(p for p in self.pieces if isinstance(p, RangeSegment))

    @property
    def is_unrestricted(self) -> bool:
        """True when the range cuts nothing: RVP(z) = VP(z) (Theorem 3's situation)."""
        return not self.arcs

    @property
    def area(self) -> float:
        """Area (float, square length units), from the pieces: shoelace terms for segments, sector terms for arcs."""
        total = 0.0
        cx, cy = float(self.viewpoint[0]), float(self.viewpoint[1])
        for p in self.pieces:
            if isinstance(p, Arc):
                (x0, y0), (x1, y1) = p.start, p.end
                r = float(p.radius)
                total += r * r * p.span + cx * (y1 - y0) - cy * (x1 - x0)
            else:
                total += p.a[0] * p.b[1] - p.b[0] * p.a[1]
        return total / 2

    def contains(self, q: Sequence[object]) -> bool:
        """Is q in the closed RVP(z)? Exact: in the closed visibility polygon and ``|q − z| ≤ R``."""
        q = exact_point(q, where="point")
        dx, dy = q[0] - self.viewpoint[0], q[1] - self.viewpoint[1]
        return dx * dx + dy * dy <= self.radius * self.radius and point_in_ring(q, self.polygon.ring) >= 0

    def boundary_points(self, sagitta: float = DEFAULT_SAGITTA) -> list[FloatPoint]:
        """The closed boundary as a float ring (not repeated), arcs replaced by inscribed chords."""
        out: list[FloatPoint] = []
        for p in self.pieces:
            if isinstance(p, Arc):
                out.extend(p.chord_points(sagitta)[:-1])
            else:
                out.append(p.a)
        return out

    def to_shapely(self, sagitta: float = DEFAULT_SAGITTA):
        """An inscribed :class:`shapely.Polygon` (floats): within ``sagitta``·R of the true region, inside it."""
        import shapely

        import numpy as np

        shape = shapely.Polygon(np.array(self.boundary_points(sagitta), dtype=float))
        return shape if shape.is_valid else shapely.make_valid(shape).buffer(0)

    def to_json(self) -> dict:
        return {"viewpoint": [float(self.viewpoint[0]), float(self.viewpoint[1])], "range": float(self.radius),
                "arcs": [a.to_json() for a in self.arcs],
                "segments": [{"kind": s.kind, "a": list(s.a), "b": list(s.b)} for s in self.segments]}


def _clip(a: ExactPoint, b: ExactPoint, z: ExactPoint, R2: Fraction) -> tuple[float, float, bool, bool] | None:
    """The parameter interval [t0, t1] of a + t(b − a) inside the closed disc (z, R), and whether each end is
    the segment's own end (exactly inside); ``None`` if the segment misses the open disc."""
    def d2(p: ExactPoint) -> Fraction:
        return (p[0] - z[0]) ** 2 + (p[1] - z[1]) ** 2

    a_in, b_in = d2(a) <= R2, d2(b) <= R2
    if a_in and b_in:
        return 0.0, 1.0, True, True
    d = (b[0] - a[0], b[1] - a[1])
    f = (a[0] - z[0], a[1] - z[1])
    A = d[0] * d[0] + d[1] * d[1]
    B = 2 * (f[0] * d[0] + f[1] * d[1])
    C = f[0] * f[0] + f[1] * f[1] - R2
    disc = B * B - 4 * A * C
    if disc <= 0:  # the line misses the disc or only touches it
        return None
    root = math.sqrt(float(disc))
    t0 = 0.0 if a_in else max(0.0, (-float(B) - root) / (2 * float(A)))
    t1 = 1.0 if b_in else min(1.0, (-float(B) + root) / (2 * float(A)))
    if t1 - t0 <= 1e-15:
        return None
    return t0, t1, a_in, b_in


def range_visibility(env: Environment, z: Sequence[object], range_: object) -> RangeView:
    """RVP(z) = VP(z) ∩ disc(z, R), with its arcs explicit.

    Parameters
    ----------
    env
        The free space.
    z
        The viewpoint, a point of the closed free space (length units).
    range_
        R > 0, the sensing range (length units); read exactly (``0.1`` is 1/10).

    Returns
    -------
    RangeView
        The view, its boundary as straight pieces and arcs of radius R in CCW order.

    Raises
    ------
    InputError
        If z is not in the free space or R is not a finite number > 0.

    Examples
    --------
    >>> import solverplan as sp
    >>> view = sp.range_visibility(sp.load_environment("l_shape"), (2, 2), 3)
    >>> len(view.arcs), round(view.area, 4)          # the disc of radius 3 is cut by two walls
    (2, 22.0794)
    >>> from solverplan.environment import load_environment
    >>> rv = range_visibility(load_environment("comb"), (1, 1), 1000)
    >>> rv.is_unrestricted, rv.area == float(rv.polygon.area)
    (True, True)
    """
    R = check_range(range_)
    vp = visibility_polygon(env, z)
    p = vp.viewpoint
    R2 = R * R
    kept: list[tuple[RangeSegment, bool, bool]] = []
    for side in vp.pieces:
        cut = _clip(side.a, side.b, p, R2)
        if cut is None:
            continue
        t0, t1, a_own, b_own = cut
        ax, ay, bx, by = float(side.a[0]), float(side.a[1]), float(side.b[0]), float(side.b[1])
        fa = (ax, ay) if a_own else (ax + t0 * (bx - ax), ay + t0 * (by - ay))
        fb = (bx, by) if b_own else (ax + t1 * (bx - ax), ay + t1 * (by - ay))
        kind = "partial" if side.kind == "edge" and not (a_own and b_own) else side.kind
        seg = RangeSegment(kind, fa, fb, side.a if a_own else None, side.b if b_own else None, side.edge,
                           side.reflex_vertex)
        kept.append((seg, a_own, b_own))
    cx, cy = float(p[0]), float(p[1])
    if not kept:
        return RangeView(p, R, vp, (Arc(p, R, 0.0, 2 * math.pi),))

    def angle(q: FloatPoint) -> float:
        return math.atan2(q[1] - cy, q[0] - cx)

    pieces: list[Piece] = []
    for k, (seg, _, b_own) in enumerate(kept):
        pieces.append(seg)
        nxt, nxt_a_own, _ = kept[(k + 1) % len(kept)]
        if b_own and nxt_a_own:
            continue
        start, end = angle(seg.b), angle(nxt.a)
        span = (end - start) % (2 * math.pi)
        if len(kept) == 1 and span < 1e-12:  # one side touching the circle at both ends: the rest is the arc
            span = 2 * math.pi
        if span > 1e-12:
            pieces.append(Arc(p, R, start, start + span))
    return RangeView(p, R, vp, tuple(pieces))
