"""Constructed edges of a visibility polygon and which parts of them are still unexplored. Exact.

A visibility polygon VP(P, p) is bounded by polygon edges, partial edges and *constructed edges* (windows)
uu′: u a reflex vertex, u′ the first boundary point beyond u on the ray from p through u (Ghosh, Burdick,
Bhattacharya and Sarkar, "Online algorithms with discrete visibility", Fig. 1). The free space behind a window
is what the view could not see. A window is *explored* once every point of it lies in the interior of the union
of the views taken so far: then nothing unseen is reachable through it. The parts that are not yet explored
are the candidates for the next viewpoint (Algorithm A, Step 5).

Everything here is exact rational arithmetic: the window is cut at every point where the boundary of a view
meets it, and each open piece between cuts is decided at its midpoint, where every view is either all around,
not at all, or on one side along a collinear side.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.exact import ExactPoint, on_segment, point_in_ring, segment_intersection
from solverplan.geometry.visibility import VisibilityPolygon

__all__ = ["Window", "windows", "unexplored_parts", "simplest_between", "point_on_part"]


@dataclass(frozen=True, slots=True)
class Window:
    """A constructed edge of a visibility polygon.

    Attributes
    ----------
    a, b
        Its end points in the visibility polygon's CCW ring order (the view lies on the left of a → b, the
        unseen free space on the right), exact coordinates in the environment's length unit.
    reflex_vertex
        Global id of the reflex vertex u (one of ``a``, ``b``).
    view
        Index of the view (in visiting order) whose polygon it bounds.
    """

    a: ExactPoint
    b: ExactPoint
    reflex_vertex: int
    view: int


def windows(vp: VisibilityPolygon, view: int) -> list[Window]:
    """The constructed edges of ``vp`` in its ring order, labelled with the view index ``view``."""
    return [Window(piece.a, piece.b, int(piece.reflex_vertex), view)
            for piece in vp.pieces if piece.kind == "constructed" and piece.reflex_vertex is not None]


def _bbox(points: Sequence[ExactPoint]) -> tuple[Fraction, Fraction, Fraction, Fraction]:
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    return min(xs), min(ys), max(xs), max(ys)


def _boxes_meet(s: tuple[Fraction, ...], t: tuple[Fraction, ...]) -> bool:
    return s[0] <= t[2] and t[0] <= s[2] and s[1] <= t[3] and t[1] <= s[3]


def unexplored_parts(window: Window, views: Sequence[VisibilityPolygon]) -> list[tuple[Fraction, Fraction]]:
    """The parts of ``window`` not in the interior of the union of ``views``, as parameter intervals.

    Parameters
    ----------
    window
        A constructed edge a → b of one of the views.
    views
        Every visibility polygon taken so far (closed regions; the window's own view may be among them).

    Returns
    -------
    list of (λ0, λ1)
        Disjoint, sorted, maximal intervals 0 ≤ λ0 < λ1 ≤ 1 of the parameter λ of a + λ(b − a) whose interior
        points are not interior to the union: the window is explored iff the list is empty.

    Notes
    -----
    The window's own view covers the left side of a → b; a point of the window is interior to the union
    iff some view covers its right (unseen) side too: it contains the point in its interior, or it has a
    side along the window with its interior on the right (a view whose window lies along the same line on
    the same side covers nothing there). Views whose bounding boxes miss the window are skipped exactly.
    """
    a, b = window.a, window.b
    d = (b[0] - a[0], b[1] - a[1])
    dd = d[0] * d[0] + d[1] * d[1]
    box = _bbox([a, b])
    near = [vp for vp in views if _boxes_meet(box, _bbox(vp.ring))]
    cuts = {Fraction(0), Fraction(1)}
    for vp in near:
        ring = vp.ring
        for k in range(len(ring)):
            x, y = ring[k], ring[(k + 1) % len(ring)]
            if not _boxes_meet(box, _bbox([x, y])):
                continue
            hit = segment_intersection(a, b, x, y)
            if hit is not None:
                for q in hit.points:
                    cuts.add(((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / dd)
    lams = sorted(cuts)
    open_parts: list[tuple[Fraction, Fraction]] = []
    for lo, hi in zip(lams, lams[1:]):
        mid = (lo + hi) / 2
        m = (a[0] + mid * d[0], a[1] + mid * d[1])
        if not any(_covers_right(vp, m, d) for vp in near):
            if open_parts and open_parts[-1][1] == lo:
                open_parts[-1] = (open_parts[-1][0], hi)
            else:
                open_parts.append((lo, hi))
    return open_parts


def _covers_right(vp: VisibilityPolygon, m: ExactPoint, d: ExactPoint) -> bool:
    """Does the closed view ``vp`` contain a half-disc around m on the right of direction d?

    m is not a cut point, so vp's boundary passes through m only along a side collinear with d.
    """
    where = point_in_ring(m, vp.ring)
    if where > 0:
        return True
    if where < 0:
        return False
    ring = vp.ring
    for k in range(len(ring)):
        x, y = ring[k], ring[(k + 1) % len(ring)]
        if on_segment(m, x, y):
            e = (y[0] - x[0], y[1] - x[1])
            # the ring is CCW: vp lies left of x → y, which is the right of d when they point opposite ways
            if e[0] * d[1] - e[1] * d[0] == 0 and e[0] * d[0] + e[1] * d[1] < 0:
                return True
    return False


def simplest_between(lo: Fraction, hi: Fraction) -> Fraction:
    """The rational with the smallest denominator (then numerator) in the open interval (lo, hi), lo < hi.

    Keeping viewpoints simple keeps exact arithmetic cheap along a chain of views, whose windows pass
    through earlier viewpoints.

    >>> simplest_between(Fraction(1, 3), Fraction(1, 2)), simplest_between(Fraction(-7, 2), Fraction(-3))
    (Fraction(2, 5), Fraction(-10, 3))
    """
    if not lo < hi:
        raise ValueError(f"empty interval ({lo}, {hi})")
    if lo < 0 < hi:
        return Fraction(0)
    if hi <= 0:
        return -simplest_between(-hi, -lo)
    fl = lo.numerator // lo.denominator
    if fl + 1 < hi:
        return Fraction(fl + 1)
    # lo and hi share the integer part fl (or hi = fl + 1): recurse on the reciprocals of the fractional parts
    rest_lo, rest_hi = lo - fl, hi - fl
    if rest_lo == 0:
        # (fl, hi) with hi ≤ fl + 1: the simplest is fl + 1/(k) for the least k with 1/k < rest_hi
        k = rest_hi.denominator // rest_hi.numerator + 1
        return fl + Fraction(1, k)
    return fl + 1 / simplest_between(1 / rest_hi, 1 / rest_lo)


def point_on_part(window: Window, part: tuple[Fraction, Fraction]) -> ExactPoint:
    """The point of ``window`` at the simplest rational parameter λ (a + λ(b − a)) in the middle third of a part.

    The parameter is the window's own (from its reflex vertex a to b), so the point is the same wherever the room
    is moved, turned, scaled or mirrored, however its walls are written (issue #22): a rule on the coordinates
    (their simplest value) would pick another point when the room moves.
    """
    a, b = window.a, window.b
    lo, hi = part
    lam = simplest_between(lo + (hi - lo) / 3, hi - (hi - lo) / 3)
    return (a[0] + lam * (b[0] - a[0]), a[1] + lam * (b[1] - a[1]))
