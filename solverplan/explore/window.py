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

from collections import OrderedDict
from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

import numpy as np

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


class _FloatView:
    """A view's ring in floats, its exact bounding box and a length scale, made once per view: the float filter
    of :func:`unexplored_parts` (an exploration asks about the same views for every window it weighs)."""

    __slots__ = ("view", "box", "x0", "y0", "dx", "dy", "len2", "tol", "lo", "hi")

    def __init__(self, vp: VisibilityPolygon) -> None:
        self.view = vp
        self.box = _bbox(vp.ring)
        xy = np.array([(float(x), float(y)) for x, y in vp.ring])
        self.x0, self.y0 = xy[:, 0], xy[:, 1]
        nxt = np.roll(xy, -1, axis=0)
        self.dx, self.dy = nxt[:, 0] - self.x0, nxt[:, 1] - self.y0
        self.len2 = self.dx * self.dx + self.dy * self.dy
        # floats of exact coordinates err by ~1e-16 of their magnitude: 1e-9 of it is a safe margin
        self.tol = 1e-9 * max(float(np.abs(xy).max()), float(np.ptp(xy[:, 0])), float(np.ptp(xy[:, 1])), 1e-300)
        self.lo, self.hi = np.minimum(xy, nxt), np.maximum(xy, nxt)  # each side's float bounding box

    def side(self, m: ExactPoint) -> int:
        """+1 inside, -1 outside, 0 when ``m`` is within the float margin of the ring (decide exactly)."""
        mx, my = float(m[0]), float(m[1])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip(((mx - self.x0) * self.dx + (my - self.y0) * self.dy) / self.len2, 0.0, 1.0)
        t = np.where(self.len2 > 0, t, 0.0)
        gap = np.hypot(self.x0 + t * self.dx - mx, self.y0 + t * self.dy - my)
        if gap.min() <= self.tol:
            return 0
        crossing = (self.y0 > my) != (self.y0 + self.dy > my)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = self.x0 + (my - self.y0) * self.dx / self.dy
        return 1 if np.count_nonzero(crossing & (x_at > mx)) % 2 else -1


_FLOAT_VIEWS: OrderedDict[int, _FloatView] = OrderedDict()
_FLOAT_VIEWS_KEPT = 4096


def _float_view(vp: VisibilityPolygon) -> _FloatView:
    """The cached :class:`_FloatView` of ``vp`` (by identity; the cache holds the view, so an id is never reused
    while its entry lives)."""
    key = id(vp)
    entry = _FLOAT_VIEWS.get(key)
    if entry is None or entry.view is not vp:
        entry = _FloatView(vp)
        _FLOAT_VIEWS[key] = entry
        if len(_FLOAT_VIEWS) > _FLOAT_VIEWS_KEPT:
            _FLOAT_VIEWS.popitem(last=False)
    else:
        _FLOAT_VIEWS.move_to_end(key)
    return entry


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
    Floats only skip work: a view's sides whose float boxes miss the window's by more than a margin are not
    cut against it, and a midpoint farther than the margin from a view's boundary is located in floats;
    everything nearer is decided exactly.
    """
    a, b = window.a, window.b
    d = (b[0] - a[0], b[1] - a[1])
    dd = d[0] * d[0] + d[1] * d[1]
    box = _bbox([a, b])
    near = [fv for fv in map(_float_view, views) if _boxes_meet(box, fv.box)]
    cuts = {Fraction(0), Fraction(1)}
    wlo = np.array([float(box[0]), float(box[1])])
    whi = np.array([float(box[2]), float(box[3])])
    for fv in near:
        ring = fv.view.ring
        close = np.all((fv.lo <= whi + fv.tol) & (wlo - fv.tol <= fv.hi), axis=1)
        for k in np.flatnonzero(close).tolist():
            x, y = ring[k], ring[(k + 1) % len(ring)]
            hit = segment_intersection(a, b, x, y)
            if hit is not None:
                for q in hit.points:
                    cuts.add(((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / dd)
    lams = sorted(cuts)
    open_parts: list[tuple[Fraction, Fraction]] = []
    for lo, hi in zip(lams, lams[1:]):
        mid = (lo + hi) / 2
        m = (a[0] + mid * d[0], a[1] + mid * d[1])
        if not any(_covers_right(fv, m, d) for fv in near):
            if open_parts and open_parts[-1][1] == lo:
                open_parts[-1] = (open_parts[-1][0], hi)
            else:
                open_parts.append((lo, hi))
    return open_parts


def _covers_right(fv: _FloatView, m: ExactPoint, d: ExactPoint) -> bool:
    """Does the closed view contain a half-disc around m on the right of direction d?

    m is not a cut point, so the view's boundary passes through m only along a side collinear with d.
    """
    where = fv.side(m) or point_in_ring(m, fv.view.ring)
    if where > 0:
        return True
    if where < 0:
        return False
    ring = fv.view.ring
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


def point_on_part(window: Window, part: tuple[Fraction, Fraction], viewpoint: ExactPoint | None = None) -> ExactPoint:
    """The point of ``window`` at the simplest rational parameter in the middle third of a part.

    Given the ``viewpoint`` whose view the window bounds, the parameter is μ of u + μ(u − p), u the window's
    reflex vertex and p the viewpoint (u′ − u is a multiple of u − p): the point's denominators are p's times a
    small μ's, so a chain of viewpoints grows by a few digits a step. (The window's own parameter λ of
    a + λ(b − a) gives the same kind of point, but u′ is a ray's hit on a wall, whose digits roughly double
    with each viewpoint of a chain: after some dozens the coordinates have hundreds of digits.) Either
    parameter is a ratio of lengths along the window, so the point is the same wherever the room is moved,
    turned, scaled or mirrored, however its walls are written (issue #22): a rule on the coordinates (their
    simplest value) would pick another point when the room moves.
    """
    a, b = window.a, window.b
    lo, hi = part
    if viewpoint is None:
        lam = simplest_between(lo + (hi - lo) / 3, hi - (hi - lo) / 3)
        return (a[0] + lam * (b[0] - a[0]), a[1] + lam * (b[1] - a[1]))
    # u is the end nearer the viewpoint (p, u and u' are collinear with u between them)
    da = (a[0] - viewpoint[0]) ** 2 + (a[1] - viewpoint[1]) ** 2
    db = (b[0] - viewpoint[0]) ** 2 + (b[1] - viewpoint[1]) ** 2
    u, w, t_lo, t_hi = (a, b, lo, hi) if da <= db else (b, a, 1 - hi, 1 - lo)
    d = (u[0] - viewpoint[0], u[1] - viewpoint[1])
    dd = d[0] * d[0] + d[1] * d[1]
    if dd == 0:  # a viewpoint at the reflex vertex itself: no ray direction, fall back on the window's parameter
        return point_on_part(window, part)
    scale = ((w[0] - u[0]) * d[0] + (w[1] - u[1]) * d[1]) / dd  # u' = u + scale·(u − p)
    mu_lo, mu_hi = scale * t_lo, scale * t_hi
    mu = simplest_between(mu_lo + (mu_hi - mu_lo) / 3, mu_hi - (mu_hi - mu_lo) / 3)
    return (u[0] + mu * d[0], u[1] + mu * d[1])
