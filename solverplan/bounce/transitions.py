"""Transitions (paper §3): f(s, θ), its exact version, the exact affine map of a fixed heading, and
the lifted, set-valued transition f(S, Θ) with exact end points.

A boundary point is ``(edge, t)``, t ∈ [0, 1] along the directed edge; a heading θ ∈ (0, π) is
radians CCW from the directed edge (π/2 = inward normal); an *exact direction* is a vector of
rationals (any length). The transition f(s, θ) is the first boundary point hit by the ray leaving
s at heading θ.

- :func:`transition` — floats, vectorised over many (edge, t, θ) through the batch caster.
- :func:`exact_transition` — one ray, exact rationals, a :class:`~solverplan.geometry.RayHit`.
- :func:`affine_map` — for a fixed exact direction, t ↦ α t + β onto one target edge's line, with
  rational α, β: composes into exact return maps with exact fixed points.
- :func:`transition_set` — f(S, Θ) for a boundary piece S and a heading interval Θ: the exact set of
  boundary pieces reached (see its docstring for the proof that its split points are complete).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> edge, t = transition(square, 0, 0.25, math.pi / 2)
>>> edge, round(t, 12)
(2, 0.75)
>>> hit = exact_transition(square, 0, Fraction(1, 4), (1, 1))
>>> hit.edge, hit.t
(1, Fraction(3, 4))
>>> m = affine_map(square, 0, (1, 1), 1)
>>> m.alpha, m.beta, m(Fraction(1, 4))
(Fraction(-1, 1), Fraction(1, 1), Fraction(3, 4))
>>> [str(p) for p in transition_set(square, (0, Fraction(1, 4), Fraction(1, 2)), ((1, 4), (-1, 4)))]
['e2:0.25:1']
>>> [str(p) for p in transition_set(square, (0, Fraction(1, 4), Fraction(1, 2)), ((1, 2), (-1, 2)))]
['e2', 'e3:0:0.5']
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Iterable, Sequence, Union

import numpy as np

from solverplan.interval import Interval, heading_interval
from solverplan.bounce.rules import check_edges, check_headings
from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.exact import ExactPoint, cross, format_number, format_point, orient, to_fraction
from solverplan.geometry.raycast import RayHit, cast_from_boundary, cast_ray

__all__ = [
    "transition",
    "exact_direction",
    "exact_transition",
    "AffineMap",
    "affine_map",
    "transition_set",
    "Headings",
]

Headings = Union[Interval, tuple[Sequence[object], Sequence[object]]]
"""A set of headings: an :class:`Interval` of angles, or a pair ``(d_lo, d_hi)`` of exact direction
vectors (d_lo the clockwise-most, i.e. the smaller heading) spanning the cone between them."""


# ---------------------------------------------------------------------- small exact helpers
def _exact_vector(value: object, where: str) -> ExactPoint:
    """A pair of exact numbers; floats are taken at their exact binary value (like the exact caster)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise InputError(f"{where}: expected a vector (x, y), got {value!r}")
    out = []
    # a sized non-string of length 2 (list, tuple, array): iterable, though hasattr cannot say so
    for c in value:  # type: ignore[attr-defined]
        if isinstance(c, (float, np.floating)):
            if not math.isfinite(c):
                raise InputError(f"{where}: {float(c)!r} is not finite")
            out.append(Fraction(float(c)))
        else:
            out.append(to_fraction(c, where=where))
    return (out[0], out[1])


def _edge_vector(env: Environment, edge: int) -> tuple[ExactPoint, ExactPoint]:
    e = env.edge(edge)
    return e.a, (e.b[0] - e.a[0], e.b[1] - e.a[1])


def _parameter(value: object, where: str) -> Fraction:
    t = Fraction(float(value)) if isinstance(value, (float, np.floating)) else to_fraction(value, where=where)
    if not 0 <= t <= 1:
        raise InvalidBoundarySet(f"{where} {format_number(t)} is not in [0, 1]")
    return t


def _single_edge(env: Environment, edge: object) -> int:
    return int(check_edges(env, [edge])[0])


# ---------------------------------------------------------------------- f(s, θ)
def transition(
    env: Environment,
    edge: int | Sequence[int] | np.ndarray,
    t: float | Sequence[float] | np.ndarray,
    theta: float | Sequence[float] | np.ndarray,
    *,
    exact_ties: bool = True,
) -> tuple[np.ndarray, np.ndarray] | tuple[int, float]:
    """The transition f((edge, t), θ) in floats: the boundary point ``(edge', t')`` the ray hits first.

    Vectorised: arrays of equal length give arrays (one batch cast); scalars give ``(int, float)``.
    With ``exact_ties`` (the default) every ray the float caster cannot call (near a vertex, two edges
    nearly tied) is re-resolved exactly; a ray through a vertex is then reported on the edge starting
    at that vertex with t' = 0 (the caster's convention). Use :func:`cast_from_boundary` directly for
    the vertex/uncertainty flags.

    Raises
    ------
    InvalidBoundarySet
        Unknown edge, t outside [0, 1], heading outside (0, π) (one line naming the value).
    """
    scalar = np.ndim(edge) == 0 and np.ndim(t) == 0 and np.ndim(theta) == 0
    edges = check_edges(env, edge)
    ts = np.asarray(t, dtype=float).reshape(-1)
    bad = np.flatnonzero(~((ts >= 0) & (ts <= 1)))
    if len(bad):
        raise InvalidBoundarySet(f"boundary parameter t = {ts[bad[0]]:g} is not in [0, 1]")
    headings = check_headings(theta)
    if not (len(edges) == len(ts) == len(headings)):
        raise InputError(f"edge, t and theta differ in length: {len(edges)}, {len(ts)} and {len(headings)}")
    hits = cast_from_boundary(env, edges, ts, headings, exact_ties=exact_ties)
    if scalar:
        return int(hits.edge[0]), float(hits.t[0])
    return hits.edge, hits.t


def exact_direction(env: Environment, edge: int, theta: float) -> ExactPoint:
    """A rational direction vector at heading θ from ``edge``: the exact edge vector rotated by the
    binary rationals cos θ and sin θ (as computed in floats), so its angle is θ to within ~1e-16 rad.

    >>> from solverplan.environment import Environment
    >>> exact_direction(Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]]), 1, math.pi / 2)[0]
    Fraction(-4, 1)
    """
    edge = _single_edge(env, edge)
    theta = float(check_headings([theta])[0])
    _, (ex, ey) = _edge_vector(env, edge)
    c, s = Fraction(math.cos(theta)), Fraction(math.sin(theta))
    return (c * ex - s * ey, s * ex + c * ey)


def _direction_from(env: Environment, edge: int, direction: object, where: str = "direction") -> ExactPoint:
    """An exact direction leaving ``edge`` into the free space (a heading number or a vector)."""
    if isinstance(direction, (int, float, np.integer, np.floating)) and not isinstance(direction, bool):
        return exact_direction(env, edge, float(direction))
    d = _exact_vector(direction, where)
    _, e = _edge_vector(env, edge)
    if cross(e, d) <= 0:
        raise InvalidBoundarySet(
            f"{where} {format_point(d)} does not point into the free space from edge e{edge}: "
            "its heading is not inside (0, π)"
        )
    return d


def exact_transition(
    env: Environment,
    edge: int,
    t: Fraction | int | str,
    direction: Sequence[object] | float,
    *,
    through_vertices: bool = False,
) -> RayHit:
    """The exact transition from boundary point ``(edge, t)`` along an exact ``direction``.

    ``t`` is exact (a :class:`Fraction`, an int, a ``"1/3"`` string; a float is taken at its exact
    binary value); ``direction`` is a vector of exact numbers pointing into the free space (or a
    float heading, made exact by :func:`exact_direction`). Returns the exact first hit
    (:func:`~solverplan.geometry.cast_ray`); a hit on a vertex has ``vertex`` set.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> hit = exact_transition(square, 0, Fraction(1, 2), (-1, 1))      # from (2, 0) to (0, 2): the middle of edge 3
    >>> hit.edge, hit.t, hit.vertex
    (3, Fraction(1, 2), None)
    >>> exact_transition(square, 0, 0, (1, 0))
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidBoundarySet: direction (1, 0) does not point into the free space from edge e0: its heading is not inside (0, π)
    """
    edge = _single_edge(env, edge)
    t_exact = _parameter(t, "boundary parameter t =")
    d = _direction_from(env, edge, direction)
    return cast_ray(env, env.exact_point_at(edge, t_exact), d, through_vertices=through_vertices)


# ---------------------------------------------------------------------- the exact affine map
@dataclass(frozen=True, slots=True)
class AffineMap:
    """t' = alpha · t + beta, exactly: boundary parameter on ``source`` → on ``target``, for rays of one
    fixed ``direction``.

    It is the map onto the *line* of the target edge: it equals the transition wherever the first
    hit of the ray is on the target edge (see :meth:`domain` for where the line is met within the
    edge; obstructions are not checked here). Compose stages with :meth:`then`; a map from an edge
    to itself has the exact fixed point β / (1 − α) and contraction |α|.
    """

    source: int
    target: int
    alpha: Fraction
    beta: Fraction
    direction: ExactPoint | None = None

    def __call__(self, t):
        """The image of t: exact for Fractions/ints, float for floats and arrays."""
        if isinstance(t, (Fraction, int)) and not isinstance(t, bool):
            return self.alpha * t + self.beta
        return float(self.alpha) * np.asarray(t, dtype=float) + float(self.beta) if np.ndim(t) else (
            float(self.alpha) * float(t) + float(self.beta)
        )

    def then(self, other: AffineMap) -> AffineMap:
        """The composition "self, then other" (other ∘ self); other must start where self ends."""
        if other.source != self.target:
            raise InputError(f"cannot compose e{self.source}→e{self.target} with e{other.source}→e{other.target}")
        return AffineMap(self.source, other.target, other.alpha * self.alpha, other.alpha * self.beta + other.beta)

    @property
    def contraction(self) -> Fraction:
        """|α|: the factor by which distances along the boundary shrink (exact)."""
        return abs(self.alpha)

    def fixed_point(self) -> Fraction | None:
        """t* = β / (1 − α) for a map of an edge to itself; ``None`` if α = 1 (no unique fixed point)."""
        if self.source != self.target:
            raise InputError(f"a map from e{self.source} to e{self.target} has no fixed point: it changes edges")
        if self.alpha == 1:
            return None
        return self.beta / (1 - self.alpha)

    def domain(self) -> tuple[Fraction, Fraction] | None:
        """The source parameters t ∈ [0, 1] whose image lies in [0, 1] (the target edge), or None."""
        lo, hi = Fraction(0), Fraction(1)
        if self.alpha == 0:
            return (lo, hi) if 0 <= self.beta <= 1 else None
        a, b = (0 - self.beta) / self.alpha, (1 - self.beta) / self.alpha
        lo, hi = max(lo, min(a, b)), min(hi, max(a, b))
        return (lo, hi) if lo <= hi else None

    def __str__(self) -> str:
        return f"e{self.source}→e{self.target}: t ↦ {format_number(self.alpha)}·t + {format_number(self.beta)}"


def affine_map(env: Environment, edge: int, direction: Sequence[object] | float, target: int) -> AffineMap:
    """The exact affine map t ↦ α t + β of the rays leaving ``edge`` along ``direction`` onto ``target``.

    With p(t) = a + t (b − a) on the source edge, the ray p(t) + s d meets the line c + τ (e − c) of
    the target edge at τ = cross(p(t) − c, d) / cross(e − c, d) — affine in t, with rational
    coefficients for rational vertices and a rational direction.

    Raises
    ------
    InputError
        If the direction does not leave ``edge`` into the free space, is parallel to the target,
        meets the target from its obstacle side, or never reaches the target's line from ``edge``.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> str(affine_map(square, 0, (1, 1), 1))
    'e0→e1: t ↦ -1·t + 1'
    >>> str(affine_map(square, 0, (1, 1), 1).then(affine_map(square, 1, (-1, 1), 2)))   # two 45° bounces
    'e0→e2: t ↦ 1·t + 0'
    """
    edge = _single_edge(env, edge)
    target = _single_edge(env, target)
    d = _direction_from(env, edge, direction)
    a, e = _edge_vector(env, edge)
    c, f = _edge_vector(env, target)
    den = cross(f, d)
    if den == 0:
        raise InputError(f"direction {format_point(d)} is parallel to edge e{target}")
    if den > 0:
        raise InputError(f"direction {format_point(d)} meets edge e{target} from its obstacle side")
    # ray parameter s(t) = cross(c − p(t), f) / cross(d, f); the target line must lie ahead for some t
    ac = (c[0] - a[0], c[1] - a[1])
    s0 = cross(ac, f) / -den
    s1 = (cross(ac, f) - cross(e, f)) / -den
    if s0 <= 0 and s1 <= 0:
        raise InputError(f"edge e{target} is not ahead of the rays leaving edge e{edge} along {format_point(d)}")
    alpha = cross(e, d) / den
    beta = cross((a[0] - c[0], a[1] - c[1]), d) / den
    return AffineMap(edge, target, alpha, beta, d)


# ---------------------------------------------------------------------- f(S, Θ)
class _Frame:
    """Exact coordinates in the frame of a source edge a → b: X along e = b − a (X = t, the boundary
    parameter), Y along n = e rotated by +π/2 (the free side, same length as e). A direction u·e + n
    has heading cot⁻¹(u); u decreases as the heading grows."""

    def __init__(self, env: Environment, edge: int) -> None:
        self.a, (self.ex, self.ey) = _edge_vector(env, edge)
        self.l2 = self.ex * self.ex + self.ey * self.ey

    def coords(self, p: Sequence[Fraction]) -> tuple[Fraction, Fraction]:
        dx, dy = p[0] - self.a[0], p[1] - self.a[1]
        return ((dx * self.ex + dy * self.ey) / self.l2, (self.ex * dy - self.ey * dx) / self.l2)

    def point(self, x: Fraction, y: Fraction = Fraction(0)) -> ExactPoint:
        return (self.a[0] + x * self.ex - y * self.ey, self.a[1] + x * self.ey + y * self.ex)

    def u(self, d: Sequence[Fraction]) -> Fraction:
        return (d[0] * self.ex + d[1] * self.ey) / (self.ex * d[1] - self.ey * d[0])

    def direction(self, u: Fraction) -> ExactPoint:
        return (u * self.ex - self.ey, u * self.ey + self.ex)


def _piece_arguments(env: Environment, piece: object) -> tuple[int, Fraction, Fraction]:
    if isinstance(piece, BoundaryPiece):
        edge, t0, t1 = piece.edge, piece.t0, piece.t1
    else:
        try:
            edge, t0, t1 = piece  # type: ignore[misc]
        except (TypeError, ValueError):
            raise InputError(f"source piece must be a BoundaryPiece or (edge, t0, t1), got {piece!r}") from None
    edge = _single_edge(env, edge)
    t0 = _parameter(t0, "source piece t0 =")
    t1 = _parameter(t1, "source piece t1 =")
    if t0 > t1:
        raise InvalidBoundarySet(f"source piece e{edge}:{format_number(t0)}:{format_number(t1)} is reversed: t0 > t1")
    if t0 == t1 and t0 in (0, 1):
        raise InvalidBoundarySet(f"source point e{edge}:{format_number(t0)} is a vertex: robots never start there")
    return edge, t0, t1


def _cone(env: Environment, edge: int, headings: object) -> tuple[ExactPoint, ExactPoint]:
    if isinstance(headings, Interval):
        if headings.is_empty:
            raise InvalidBoundarySet("heading interval is empty")
        interval = heading_interval(headings.lo, headings.hi)
        return exact_direction(env, edge, interval.lo), exact_direction(env, edge, interval.hi)
    given_lo: object
    given_hi: object
    try:
        given_lo, given_hi = headings  # type: ignore[misc]  # any pair; a non-pair is reported just below
    except (TypeError, ValueError):
        raise InputError(f"headings must be an Interval or a pair of direction vectors, got {headings!r}") from None
    d_lo = _direction_from(env, edge, given_lo, "direction d_lo")
    d_hi = _direction_from(env, edge, given_hi, "direction d_hi")
    if cross(d_lo, d_hi) < 0:
        raise InvalidBoundarySet(
            f"direction cone {format_point(d_lo)} .. {format_point(d_hi)} is reversed: d_lo must be clockwise of d_hi"
        )
    return d_lo, d_hi


def _convex_hull(points: Sequence[ExactPoint]) -> list[ExactPoint]:
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def chain(seq: Iterable[ExactPoint]) -> list[ExactPoint]:
        out: list[ExactPoint] = []
        for p in seq:
            while len(out) >= 2 and orient(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(reversed(pts))
    return lower[:-1] + upper[:-1]


def _meets_open_polygon(ring: Sequence[ExactPoint], u: ExactPoint, w: ExactPoint) -> bool:
    """Does the closed segment uw meet the interior of the convex CCW polygon ``ring``? (exact)"""
    lo, hi = Fraction(0), Fraction(1)
    lo_open = hi_open = False
    dw = (w[0] - u[0], w[1] - u[1])
    n = len(ring)
    for k in range(n):
        p, q = ring[k], ring[(k + 1) % n]
        side = (q[0] - p[0], q[1] - p[1])
        const = cross(side, (u[0] - p[0], u[1] - p[1]))  # > 0: u strictly inside this half-plane
        slope = cross(side, dw)
        if slope == 0:
            if const <= 0:
                return False
            continue
        root = -const / slope
        if slope > 0 and root >= lo:
            lo, lo_open = root, True
        elif slope < 0 and root <= hi:
            hi, hi_open = root, True
    return lo < hi or (lo == hi and not lo_open and not hi_open)


def _clean_fast_path(env, frame, edge, t0, t1, d_lo, d_hi) -> list[BoundaryPiece] | None:
    """The common case: every corner ray lands inside one edge j and the convex hull
    of the source piece and the corner hits holds no vertex and meets no other edge in its interior.
    Then the swept region is that hull, every ray of the family lands on j, and the image is the
    interval spanned by the corner images. Returns None when the case does not apply."""
    origins = list(dict.fromkeys([frame.point(t0), frame.point(t1)]))
    directions = list(dict.fromkeys([d_lo, d_hi]))
    hits: list[RayHit] = []
    for o in origins:
        for d in directions:
            try:
                hit = cast_ray(env, o, d)
            except InputError:  # leaves a vertex of the piece into the obstacle
                return None
            if hit.vertex is not None:
                return None
            hits.append(hit)
    target = hits[0].edge
    if any(h.edge != target for h in hits):
        return None
    hull = _convex_hull([*origins, *(h.point for h in hits)])
    if len(hull) < 3:
        return None
    for v in env.exact_vertices:
        if all(orient(hull[k], hull[(k + 1) % len(hull)], v) > 0 for k in range(len(hull))):
            return None
    nxt = env.next_vertex
    verts = env.exact_vertices
    for k in range(env.n_edges):
        if k in (edge, target):
            continue
        if _meets_open_polygon(hull, verts[k], verts[int(nxt[k])]):
            return None
    ts = [h.t for h in hits]
    return [BoundaryPiece(target, min(ts), max(ts))]


_INF = float("inf")
_Origin = Fraction | float  # an exact origin parameter on the source line, or ±inf (a shadow without an end)


class _Sweep:
    """The exact machinery of the general case of :func:`transition_set` (see its docstring)."""

    def __init__(self, env: Environment, frame: _Frame, edge: int, t0: Fraction, t1: Fraction,
                 u_min: Fraction, u_max: Fraction) -> None:
        self.env, self.frame, self.edge = env, frame, edge
        self.t0, self.t1, self.u_min, self.u_max = t0, t1, u_min, u_max
        self.coords = [frame.coords(p) for p in env.exact_vertices]
        self.next = [int(j) for j in env.next_vertex]

    def window(self, x: Fraction, y: Fraction) -> tuple[Fraction, Fraction]:
        """W(m): the origins t ∈ [t0, t1] whose cone contains the direction to m = (x, y), y > 0."""
        return max(self.t0, x - y * self.u_max), min(self.t1, x - y * self.u_min)

    def shadows(self, x: Fraction, y: Fraction, skip: set[int]) -> list[tuple[_Origin, _Origin]]:
        """For each edge k ∉ skip, the origins t on the source line whose segment to m = (x, y) meets
        edge k: the central projection from m of edge k ∩ {0 < Y < y}, as [lo, hi] (±inf allowed)."""
        out: list[tuple[_Origin, _Origin]] = []
        coords, nxt = self.coords, self.next
        for k in range(len(coords)):
            if k in skip:
                continue
            (xp, yp), (xq, yq) = coords[k], coords[nxt[k]]
            if (yp <= 0 and yq <= 0) or (yp >= y and yq >= y):
                continue
            dy = yq - yp
            lam0, lam1 = Fraction(0), Fraction(1)
            if dy != 0:
                a, b = -yp / dy, (y - yp) / dy
                lam0, lam1 = max(lam0, min(a, b)), min(lam1, max(a, b))
                if lam0 >= lam1:
                    continue
            ends: list[_Origin] = []
            for lam in (lam0, lam1):
                px, py = xp + lam * (xq - xp), yp + lam * dy
                if py == y:
                    if px == x:  # pragma: no cover - only an edge through m, which is skipped
                        break
                    ends.append(_INF if px > x else -_INF)
                else:
                    ends.append(x + (px - x) * y / (y - py))
            else:
                lo, hi = (ends[0], ends[1]) if ends[0] <= ends[1] else (ends[1], ends[0])
                out.append((lo, hi))
        return out

    def reached(self, x: Fraction, y: Fraction, skip: set[int]) -> bool:
        """Is m = (x, y) first-hit, without touching a vertex, by a positive-measure set of rays
        (or, for a degenerate window, by its one ray)? Strict visibility minus closed shadows."""
        if y <= 0:
            return False
        lo, hi = self.window(x, y)
        if lo > hi:
            return False
        shadows = self.shadows(x, y, skip)
        if lo == hi:
            return not any(a <= lo <= b for a, b in shadows)
        cur: _Origin = lo
        for a, b in sorted(shadows, key=lambda ab: ab[0]):
            if b <= cur:
                continue
            if a > cur:
                return True
            cur = b
            if cur >= hi:
                return False
        return cur < hi

    def maybe_reached(self, v: int) -> bool:
        """A superset test for "vertex v lies in the closed swept region": False only if every admissible
        origin's segment to v properly crosses the interior of some edge (open shadows cover W(v))."""
        x, y = self.coords[v]
        if y <= 0:
            return False
        lo, hi = self.window(x, y)
        if lo > hi:
            return False
        prev = [k for k, j in enumerate(self.next) if j == v]
        shadows = self.shadows(x, y, {v, *prev})
        cur: _Origin = lo
        while True:
            best = max((b for a, b in shadows if a < cur), default=None)
            if best is None or best <= cur:
                return True
            if best > hi:
                return False
            cur = best

    def critical_rays(self) -> list[tuple[Fraction, Fraction]]:
        """(origin t, u) of the corner rays and of every ray from the piece, inside the cone, through a
        possibly reached vertex from an end of the piece, along an extreme direction, or through a
        second such vertex."""
        t0, t1, u_min, u_max = self.t0, self.t1, self.u_min, self.u_max
        rays = {(t, u) for t in (t0, t1) for u in (u_min, u_max)}
        live = [v for v in range(len(self.coords)) if self.maybe_reached(v)]
        for v in live:
            x, y = self.coords[v]
            for t in (t0, t1):
                u = (x - t) / y
                if u_min <= u <= u_max:
                    rays.add((t, u))
            for u in (u_min, u_max):
                t = x - y * u
                if t0 <= t <= t1:
                    rays.add((t, u))
        for i, v in enumerate(live):
            xv, yv = self.coords[v]
            for w in live[i + 1:]:
                xw, yw = self.coords[w]
                if yw == yv:
                    continue
                u = (xw - xv) / (yw - yv)
                t = xv - yv * u
                if u_min <= u <= u_max and t0 <= t <= t1:
                    rays.add((t, u))
        return sorted(rays)

    def pieces(self) -> list[BoundaryPiece]:
        env, frame = self.env, self.frame
        split: dict[int, set[Fraction]] = {}
        for t, u in self.critical_rays():
            try:
                hit = cast_ray(env, frame.point(t), frame.direction(u), through_vertices=True)
            except InputError:  # from a vertex end of the piece, straight into the obstacle: its limit is that vertex
                continue
            if hit.vertex is None:
                split.setdefault(hit.edge, set()).add(hit.t)
        out: list[BoundaryPiece] = []
        for j in range(env.n_edges):
            if j == self.edge or not self._may_land(j):
                continue
            cuts = sorted({Fraction(0), Fraction(1), *split.get(j, ())})
            run: list[Fraction] | None = None
            for a, b in zip(cuts, cuts[1:]):
                x, y = frame.coords(env.exact_point_at(j, (a + b) / 2))
                if self.reached(x, y, {self.edge, j}):
                    run = [run[0], b] if run is not None else [a, b]
                else:
                    if run is not None:
                        out.append(BoundaryPiece(j, run[0], run[1]))
                    run = None
            if run is not None:
                out.append(BoundaryPiece(j, run[0], run[1]))
        return out

    def _may_land(self, j: int) -> bool:
        """False when edge j lies wholly outside the unobstructed sweep {y > 0, x − y·u_max ≤ t1, x − y·u_min ≥ t0}."""
        (xa, ya), (xb, yb) = self.coords[j], self.coords[self.next[j]]
        if ya <= 0 and yb <= 0:
            return False
        if xa - ya * self.u_max > self.t1 and xb - yb * self.u_max > self.t1:
            return False
        return not (xa - ya * self.u_min < self.t0 and xb - yb * self.u_min < self.t0)


def transition_set(env: Environment, piece: BoundaryPiece | tuple, headings: Headings) -> list[BoundaryPiece]:
    """The lifted transition f(S, Θ): the boundary pieces reached from every point of ``piece`` at every
    heading of ``headings``, with exact end points.

    Parameters
    ----------
    piece
        A :class:`BoundaryPiece` or ``(edge, t0, t1)`` with exact t0 ≤ t1 (a single point t0 = t1 must
        not be a vertex).
    headings
        An :class:`Interval` ⊂ (0, π) of headings — each end made exact by :func:`exact_direction`
        (within ~1e-16 rad of the float) — or a pair ``(d_lo, d_hi)`` of exact direction vectors,
        d_lo the clockwise-most. Not both the piece and the cone may be degenerate (a single ray:
        use :func:`exact_transition`).

    Returns
    -------
    list[BoundaryPiece]
        Sorted by edge then t, maximal on each edge, each of positive length: the closure of the set
        of first hits of the rays of the family that touch no vertex (the paper ignores trajectories
        through vertices). Pieces on consecutive edges meeting at a vertex are listed per edge.

    **Fast path**. If the four corner rays (piece ends × cone ends) hit one edge j away
    from vertices and the convex hull H of the piece and the four hits contains no vertex and meets no
    other edge in its interior, the answer is the interval of j spanned by the four corner hits. Proof:
    in the source frame (x = t along the edge, y along the inward normal of the same length, a direction
    written u·e + n with u = cot θ), the hit on the line of j is τ = (α₁x + α₂u + α₃)/(n_x u + n_y), whose
    denominator has one sign on the cone because it has at the two cone ends; so τ is monotone in x
    and in u, every ray of the family meets line j between the corner hits, and its segment lies in H
    (it joins a point of the piece to a point of H ∩ line j). H's interior is connected, meets no
    boundary, and contains free points next to the piece, so it lies in the open free space; rays on
    ∂H are corner rays, which were cast. So every ray reaches j first, and continuity gives the whole
    interval.

    **General case: the split points are exactly the hits of the critical rays.** Let q run over the
    relative interior of an edge j ≠ source. In the frame above, q = (X, Y) with Y > 0 is reached by the
    origins A(q) = W(q) ∖ ∪ₖ Shₖ(q), where W(q) = [max(t0, X − Y·u_max), min(t1, X − Y·u_min)] are the
    origins whose cone contains the direction to q, and Shₖ(q) is the set of origins whose open segment
    to q meets edge k: the central projection from q onto the source line of edge k ∩ {0 < y < Y}, an
    interval whose ends are projections of vertices of P, points where edge k meets the source line
    (fixed; inside [0, 1] only t = 0 or 1, the source edge's own end points, as edges do not cross), or
    ±∞. q is in the image iff A(q) has positive length (or,
    for a degenerate window — one heading, or one origin — contains its point); strict visibility from
    an interior origin keeps the segment in the open free space, so these are exactly the rays that
    touch no vertex. As q moves, the ends of W and of the Shₖ move continuously, and whether the
    complement of the shadows in W is empty can only change where two of these ends coincide (a gap
    opens or closes, or W itself shrinks to a point). A coincidence puts q on a *critical line*:
    (piece end, cone end) — a corner ray; (piece end, projected vertex w) — the ray from t0 or t1
    through w; (cone end, projected w) — the ray along d_lo or d_hi through w; (projected w, projected
    w′) — the ray through w and w′; the fixed ends t ∈ {0, 1} only matter when they are piece ends.
    Moreover at a boundary point q* of the image there are reached points converging to it, so a limit
    segment [s*, q*] of strictly free segments lies in the closed free space: q* is where the critical
    ray from s* first leaves the closed free space — the first hit of that ray *continued through the
    vertices it grazes* (``cast_ray(..., through_vertices=True)``), and w, w′ lie on [s*, q*], hence
    in the closed swept region (vertices certainly outside it are pruned soundly: every admissible
    segment to them properly crosses an edge). So every end point of the image on j is a vertex of j or
    the continued hit of a critical ray; between two consecutive such points the image status is
    constant, and one exact test at the midpoint decides it. The computed split points can be a
    superset (extra rays, blocked before their vertex); adjacent pieces are merged, so the reported end
    points are exactly the boundary points of the image on each edge (plus the edge's own end points
    where the image turns a corner onto the next edge).

    Cost: one exact cast per critical ray (O(V) rays, plus the collinear vertex pairs of the swept
    region) and O(n) exact work per elementary piece, so it is meant for stage-sized problems.

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])   # an L
    >>> [str(p) for p in transition_set(room, (0, 0, Fraction(1, 4)), ((1, 1), (1, 1)))]  # x ∈ [0, 2], up-right
    ['e2:0.5:1']
    """
    edge, t0, t1 = _piece_arguments(env, piece)
    d_lo, d_hi = _cone(env, edge, headings)
    if t0 == t1 and cross(d_lo, d_hi) == 0:
        raise InvalidBoundarySet(
            f"a single point with a single heading is one ray, not a set: use exact_transition for e{edge}:{format_number(t0)}"
        )
    frame = _Frame(env, edge)
    fast = _clean_fast_path(env, frame, edge, t0, t1, d_lo, d_hi)
    if fast is not None:
        return fast
    sweep = _Sweep(env, frame, edge, t0, t1, frame.u(d_hi), frame.u(d_lo))
    return sweep.pieces()
