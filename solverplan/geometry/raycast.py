"""Ray casting: the exact scalar caster and the indexed, vectorised batch caster.

A ray is ``origin + s * direction`` for s > 0 (hits at s = 0 are ignored, so a ray leaving a
boundary point never hits its own edge there). The *first hit* is the first boundary point the
ray meets. Three casters answer the same question:

- :func:`cast_ray` — one ray, **exact**: rational origin and direction, a :class:`RayHit` with
  exact point and parameters; a ray through a vertex is reported as a vertex hit, never silently
  assigned to an edge. A float prefilter over all edges (numpy) leaves a handful of candidate
  edges to the exact arithmetic, which runs on Python integers (the ray's frame is scaled so that
  origin, direction and integer vertices are integers).
- :class:`RayCaster` — many rays at once, **floats**, with a uniform grid index over the edges and
  vectorised ray marching. It returns arrays (:class:`RayHits`) and flags as ``uncertain`` every
  ray whose answer is too close to a tie to call in floats (a vertex within the tolerance of the
  ray, two edges nearly tied, a hit right at the origin); ``exact_ties=True`` re-resolves those rays
  exactly.
- :meth:`RayCaster.cast_exact` / :func:`cast_rays_exact` — many rays, **exact**: the grid march
  gives each ray its few candidate edges (all that may meet it up to its first certain crossing),
  then the exact arithmetic of :func:`cast_ray` runs on those only. Same answers as
  :func:`cast_ray`, a few times faster per ray; the way to shoot Algorithm 1's rays.

Why the float answers can be trusted when not ``uncertain``: the float tolerance
(:data:`BATCH_TOLERANCE` × the size of the environment) is about a million times the rounding error
of the expressions it guards, so a vertex farther than the tolerance from a ray is on the same side
of it in floats and exactly, and an edge crossed away from its end points is crossed exactly too.

Conventions: free space is on the left of every directed edge; a boundary point is
``(edge, t)``, t ∈ [0, 1) along the edge; a vertex hit is reported on the edge that starts at the
vertex, with t = 0. Headings θ ∈ (0, π) are radians CCW from the directed edge (π/2 = inward normal).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> hit = cast_ray(square, (1, 1), (1, 0))
>>> hit.edge, hit.t, hit.point, hit.s, hit.vertex
(1, Fraction(1, 4), (Fraction(4, 1), Fraction(1, 1)), Fraction(3, 1), None)
>>> cast_ray(square, (1, 1), (1, 1)).vertex          # straight into the corner (4, 4)
2
>>> hits = cast_rays(square, [[1, 1], [2, 2]], [[0, 1], [-1, 0]])
>>> hits.edge.tolist(), hits.x.tolist(), hits.y.tolist()
([2, 3], [1.0, 0.0], [4.0, 2.0])
"""

from __future__ import annotations

import functools
import inspect
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, AbstractSet, Callable, Concatenate, Literal, Mapping, ParamSpec, Sequence, TypeVar

import numpy as np

from solverplan._arrays import ragged_arange, thread_map
from solverplan._arrays import workers as threads
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import ExactPoint, format_point, to_fraction

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.environment import Environment

__all__ = [
    "RayHit",
    "RayHits",
    "RayCaster",
    "cast_ray",
    "cast_rays",
    "cast_rays_exact",
    "cast_from_boundary",
    "ray_caster",
    "heading_directions",
]

# The float prefilter of the exact caster treats a float value as "maybe zero" when it is within
# _PREFILTER_REL × (scale of the inputs) of zero. Float rounding errors of those expressions are
# about 10 u ≈ 1e-15 relative, so this margin (1000×) only costs a few extra exact evaluations.
_PREFILTER_REL = 1e-12

P = ParamSpec("P")
R = TypeVar("R")


# ---------------------------------------------------------------------------------------------
# exact scalar caster
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class RayHit:
    """The exact first hit of a ray.

    Attributes
    ----------
    edge
        Global edge id. For a vertex hit: the edge that starts at the vertex (then ``t == 0``).
    t
        Boundary parameter on ``edge``, in [0, 1).
    point
        The exact hit point.
    s
        Ray parameter: ``point == origin + s * direction``, s > 0 (in units of the given direction).
    vertex
        Global vertex id when the ray hits a vertex exactly, else ``None``.
    """

    edge: int
    t: Fraction
    point: ExactPoint
    s: Fraction
    vertex: int | None


def _exact_number(value: object, where: str) -> Fraction:
    """Floats (Python or numpy) at their exact binary value; everything else via :func:`to_fraction`."""
    if isinstance(value, (float, np.floating)) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise InputError(f"{where}: coordinate is not finite ({float(value)!r})")
        return Fraction(float(value))
    return to_fraction(value, where=where)


def _exact_pair(xy: object, where: str) -> ExactPoint:
    if isinstance(xy, (str, bytes)) or not hasattr(xy, "__len__") or len(xy) != 2:
        raise InputError(f"{where}: expected a pair [x, y], got {xy!r}")
    # a sized non-string of length 2 (list, tuple, array): indexable, though hasattr cannot say so
    return (_exact_number(xy[0], where), _exact_number(xy[1], where))  # type: ignore[index]


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _wedge_side(u1x, u1y, u2x, u2y, wx, wy) -> int:
    """Where direction w points from a vertex whose outgoing edge has direction u1 and whose
    incoming edge comes from direction u2 (the free wedge runs CCW from u1 to u2):
    +1 into the free space, 0 along an incident edge, −1 into the obstacle. Exact."""
    c1 = _cross(u1x, u1y, wx, wy)  # > 0: w is CCW of u1
    c2 = _cross(wx, wy, u2x, u2y)  # > 0: u2 is CCW of w
    if (c1 == 0 and u1x * wx + u1y * wy > 0) or (c2 == 0 and u2x * wx + u2y * wy > 0):
        return 0
    turn = _cross(u1x, u1y, u2x, u2y)
    if turn > 0:  # convex corner: the free wedge is narrower than π
        inside = c1 > 0 and c2 > 0
    elif turn < 0:  # reflex corner: the obstacle wedge (CCW from u2 to u1) is the narrow one
        inside = not (_cross(u2x, u2y, wx, wy) >= 0 and _cross(wx, wy, u1x, u1y) >= 0)
    else:  # flat vertex (angle π): u2 = −u1 in direction
        inside = c1 > 0
    return 1 if inside else -1


def _lcm(a: int, b: int) -> int:
    return a // math.gcd(a, b) * b


def _float_direction(dx: Fraction, dy: Fraction) -> tuple[float, float]:
    """A float vector in the direction (dx, dy), its larger component in [1, 2) (no overflow)."""
    c = _lcm(dx.denominator, dy.denominator)
    ix, iy = dx.numerator * (c // dx.denominator), dy.numerator * (c // dy.denominator)
    if ix == 0 and iy == 0:
        return (0.0, 0.0)
    k = max(abs(ix), abs(iy)).bit_length() - 1
    return (float(Fraction(ix, 1 << k)), float(Fraction(iy, 1 << k)))


class _Frame:
    """One ray's exact problem in scaled coordinates x' = q·x, q the common denominator of the
    origin, so that the origin, the direction and every integer vertex are Python ints (fast);
    rational vertices stay Fractions. ``s = s' · s_unit`` converts ray parameters back."""

    __slots__ = ("env", "q", "ox", "oy", "dx", "dy", "s_unit", "cache", "ints", "mult")

    def __init__(self, env: Environment, origin: ExactPoint, direction: ExactPoint,
                 integer_vertices: tuple[int, list] | None = None) -> None:
        (ox, oy), (dx, dy) = origin, direction
        self.env = env
        q = _lcm(ox.denominator, oy.denominator)
        self.ints = None
        if integer_vertices is not None:  # (common denominator Q of all vertices, vertices · Q as ints)
            common, self.ints = integer_vertices
            q = _lcm(q, common)
            self.mult = q // common
        self.q = q
        self.ox, self.oy = ox.numerator * (q // ox.denominator), oy.numerator * (q // oy.denominator)
        c = _lcm(dx.denominator, dy.denominator)
        ix, iy = dx.numerator * (c // dx.denominator), dy.numerator * (c // dy.denominator)
        g = math.gcd(ix, iy)
        self.dx, self.dy = ix // g, iy // g  # direction' = (c / g) · direction
        self.s_unit = Fraction(c, g * q)
        self.cache: dict[int, tuple] = {}

    def vertex(self, v: int) -> tuple:
        """Scaled vertex v (ints for integer vertices)."""
        if self.ints is not None:
            x, y = self.ints[v]
            return (x, y) if self.mult == 1 else (x * self.mult, y * self.mult)
        p = self.cache.get(v)
        if p is None:
            x, y = self.env.exact_vertices[v]
            p = self.cache[v] = (_scale(x, self.q), _scale(y, self.q))
        return p

    def side(self, v: int):
        """cross(direction', v' − origin'): > 0 if vertex v is left of the ray's line."""
        x, y = self.vertex(v)
        return _cross(self.dx, self.dy, x - self.ox, y - self.oy)

    def wedge(self, v: int, sign: int) -> int:
        """:func:`_wedge_side` of the direction (``sign`` = +1) or its reverse (−1) at vertex v."""
        env = self.env
        px, py = self.vertex(v)
        nx, ny = self.vertex(int(env.next_vertex[v]))
        qx, qy = self.vertex(int(env.prev_vertex[v]))
        return _wedge_side(nx - px, ny - py, qx - px, qy - py, sign * self.dx, sign * self.dy)

    def crossing_s(self, i: int):
        """Scaled ray parameter s' where the ray's line meets the line of edge i (not parallel)."""
        ax, ay = self.vertex(i)
        bx, by = self.vertex(int(self.env.next_vertex[i]))
        ex, ey = bx - ax, by - ay
        return Fraction(_cross(ax - self.ox, ay - self.oy, ex, ey)) / _cross(self.dx, self.dy, ex, ey)

    def vertex_s(self, v: int):
        x, y = self.vertex(v)
        return Fraction(self.dx * (x - self.ox) + self.dy * (y - self.oy), self.dx**2 + self.dy**2)


def _scale(x: Fraction, q: int):
    n, d = x.numerator * q, x.denominator
    return n // d if n % d == 0 else Fraction(n, d)


class _Contact:
    """A point where the ray meets the boundary: a proper crossing of an edge or a vertex.
    ``lo``/``hi`` bound its float position along the ray; ``s`` is the exact s' once computed."""

    __slots__ = ("lo", "hi", "vertex", "index", "s")

    def __init__(self, lo: float, hi: float, vertex: bool, index: int, s=None) -> None:
        self.lo, self.hi, self.vertex, self.index, self.s = lo, hi, vertex, index, s


def cast_ray(
    env: Environment,
    origin: Sequence[object],
    direction: Sequence[object],
    *,
    through_vertices: bool = False,
) -> RayHit:
    """The exact first hit of the ray ``origin + s * direction`` (s > 0) on the boundary of ``env``.

    Parameters
    ----------
    env
        The environment.
    origin
        A point of the closed free space: an interior point, a boundary point or a vertex. Numbers
        may be ints, :class:`~fractions.Fraction`, :class:`~decimal.Decimal`, numeric strings
        (``"1/3"``, ``"0.1"`` = 1/10), or floats, which are taken at their **exact binary value**
        (``0.1`` is 3602879701896397/36028797018963968), so a float ray cast by :class:`RayCaster`
        is exactly the ray resolved here.
    direction
        Any non-zero vector, same number types; its length only scales ``s``.
    through_vertices
        If True, a ray that only grazes a vertex (the free space continues beyond it: both incident
        edges lie on one closed side of the ray and the ray does not enter the obstacle there) goes
        on, and the next hit is returned. Algorithm 1 uses this for the first hit beyond a reflex vertex.

    Returns
    -------
    RayHit
        ``vertex`` is set when the hit point is a vertex (then ``edge`` is the edge starting there
        and ``t == 0``); otherwise the hit is a proper crossing of ``edge`` at ``t`` ∈ (0, 1).

    A ray that runs *along* a boundary edge (from a point of that edge, in the edge's direction or
    against it) is not in the interior of the free space: it is reported as hitting the first
    vertex it reaches (with ``through_vertices``: it goes on past that vertex while it stays in the
    closed free space, e.g. straight on past a reflex or flat vertex).

    Raises
    ------
    InputError
        For a zero direction, an origin outside the free space, or a ray from a boundary point
        that leaves into the obstacle.

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])  # an L
    >>> cast_ray(room, (2, 7), (2, -3)).vertex           # aimed at the reflex vertex 3 = (4, 4)
    3
    >>> hit = cast_ray(room, (2, 7), (2, -3), through_vertices=True)
    >>> hit.edge, hit.t, hit.point
    (0, Fraction(5, 6), (Fraction(20, 3), Fraction(0, 1)))
    >>> cast_ray(room, (4, 6), (1, 0))
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: ray from (4, 6) on edge 3 with direction (1, 0) points into the obstacle
    """
    origin_q = _exact_pair(origin, "ray origin")
    direction_q = _exact_pair(direction, "ray direction")
    if direction_q[0] == 0 and direction_q[1] == 0:
        raise InputError("ray direction (0, 0) is zero")
    frame = _Frame(env, origin_q, direction_q)
    nxt = env.next_vertex

    # ---------------------------------------------------------------- float prefilter
    fdx, fdy = _float_direction(*direction_q)  # the larger component in [1, 2)
    fox, foy = float(origin_q[0]), float(origin_q[1])
    n = env.n_edges
    xmin, ymin, xmax, ymax = env.bounds
    scale = max(-xmin, xmax) + max(-ymin, ymax) + abs(fox) + abs(foy)
    if not 1e-100 < scale < 1e100:  # products could underflow or overflow: no float filter at all
        return _exact_hit_among(env, origin_q, direction_q, list(range(n)), through_vertices)
    eps = _PREFILTER_REL * 4.0 * scale  # bounds the float error of sa, sb, pa, pb (|D|_1 < 4)
    # rows: a − O for every edge start, then b − O for every edge end; columns: cross(D, ·), D · (·)
    rel = np.concatenate([env.edge_start, env.edge_end]) - (fox, foy)
    cd = rel @ np.array([[-fdy, fdx], [fdx, fdy]])
    side = (cd[:, 0] > eps).astype(np.int8) - (cd[:, 0] < -eps)
    # the edges that meet the ray's line ahead of the origin, or may (then the exact test decides)
    near = np.flatnonzero((side[:n] * side[n:] <= 0) & (np.maximum(cd[:n, 1], cd[n:, 1]) > -eps))
    rows = np.concatenate([cd[near], cd[near + n], rel[near], rel[near + n]], axis=1).tolist()
    sides = np.stack([side[near], side[near + n]], axis=1).tolist()
    tol_on = eps * scale
    on_cand: list[int] = []
    co_of: dict[int, float] = {}
    spans: list[tuple[int, int, int, float, float, float]] = []
    best_hi = math.inf
    for i, (sa, pa, sb, pb, wax, way, wbx, wby), (fa, fb) in zip(near.tolist(), rows, sides):
        co = wbx * way - wby * wax  # cross(e, a − O)
        co_of[i] = co
        if abs(co) <= tol_on and wax * wbx + way * wby <= tol_on:
            on_cand.append(i)  # the origin may lie on edge i
        if fa * fb < 0:  # certainly crosses the line: bound the crossing point's position
            pc = pa + sa / (sa - sb) * (pb - pa)
            err = eps * abs(pb - pa) / abs(sa - sb) + 2 * eps
            lo, hi = pc - err, pc + err
            if lo > 0 and hi < best_hi:
                best_hi = hi
        else:
            lo, hi = min(pa, pb) - eps, max(pa, pb) + eps
        if hi > -eps:
            spans.append((i, fa, fb, pa, lo, hi))
    cand = [span for span in spans if span[4] <= best_hi]

    validated = _check_departure(frame, on_cand, origin_q, direction_q)

    # ---------------------------------------------------------------- contacts, exact where needed
    contacts: list[_Contact] = []
    for i, fa, fb, pai, loi, hii in cand:
        ea = fa or _sign(frame.side(i))
        if ea == 0:  # vertex i lies on the ray's line
            s = frame.vertex_s(i)
            if s > 0:
                contacts.append(_Contact(pai - eps, pai + eps, True, i, s))
            continue
        eb = fb or _sign(frame.side(int(nxt[i])))
        if ea * eb < 0:  # proper crossing of the ray's line (an end point on it is a vertex contact)
            contact = _Contact(loi, hii, False, i)
            if contact.lo <= 0:
                contact.s = frame.crossing_s(i)
                if contact.s <= 0:
                    continue
            contacts.append(contact)
    free_side = {i for i, co in co_of.items() if co < -tol_on}  # certainly seen from the free side
    return _walk(frame, contacts, validated, through_vertices, origin_q, direction_q, free_side)


def _check_departure(frame: _Frame, edges, origin_q: ExactPoint, direction_q: ExactPoint) -> bool:
    """If the origin lies on one of ``edges`` (exactly), check that the ray leaves into the closed
    free space (else raise) and return True; return False if the origin is on none of them."""
    nxt = frame.env.next_vertex
    for i in edges:
        j = int(nxt[i])
        (axe, aye), (bxe, bye) = frame.vertex(i), frame.vertex(j)
        wax, way, wbx, wby = axe - frame.ox, aye - frame.oy, bxe - frame.ox, bye - frame.oy
        if _cross(wax, way, wbx, wby) != 0 or wax * wbx + way * wby > 0:
            continue
        if wax == 0 and way == 0 or wbx == 0 and wby == 0:  # the origin is a vertex
            v = i if wax == 0 and way == 0 else j
            if frame.wedge(v, 1) < 0:
                raise InputError(
                    f"ray from vertex {v} at {format_point(origin_q)} with direction "
                    f"{format_point(direction_q)} points into the obstacle"
                )
        elif _cross(bxe - axe, bye - aye, frame.dx, frame.dy) < 0:
            raise InputError(
                f"ray from {format_point(origin_q)} on edge {i} with direction "
                f"{format_point(direction_q)} points into the obstacle"
            )
        return True
    return False


def _walk(frame: _Frame, contacts: list[_Contact], validated: bool, through_vertices: bool,
          origin_q: ExactPoint, direction_q: ExactPoint, free_side: AbstractSet[int] = frozenset()) -> RayHit:
    """Walk the contacts in order along the ray: the first proper crossing, or the first vertex the
    ray cannot pass. Until the origin is known to be in the free space (``validated``), the first
    contact must be reached from the free side. ``free_side``: edges known to face the origin."""
    env = frame.env
    nxt = env.next_vertex
    while contacts:
        first = _nearest(contacts, frame)
        contacts.remove(first)
        i = first.index
        if not first.vertex:  # proper crossing of edge i
            if not validated and i not in free_side:  # arrival from the free side, exactly
                (axe, aye), (bxe, bye) = frame.vertex(i), frame.vertex(int(nxt[i]))
                if _cross(bxe - axe, bye - aye, frame.ox - axe, frame.oy - aye) <= 0:
                    raise InputError(f"ray origin {format_point(origin_q)} is not in the free space")
            return _crossing_hit(frame, i, first.s)
        if not validated:
            if frame.wedge(i, -1) < 0:  # arrived from inside the obstacle
                raise InputError(f"ray origin {format_point(origin_q)} is not in the free space")
            validated = True
        if through_vertices and frame.wedge(i, 1) >= 0:
            continue
        s = first.s if first.s is not None else frame.vertex_s(i)
        return RayHit(i, Fraction(0), env.exact_vertices[i], s * frame.s_unit, i)
    if not validated:
        raise InputError(f"ray origin {format_point(origin_q)} is not in the free space")
    raise SolverFailed(  # pragma: no cover - a ray in a valid environment always hits the outer ring
        f"ray from {format_point(origin_q)} with direction {format_point(direction_q)} escaped the environment"
    )


def _exact_hit_among(env: Environment, origin_q: ExactPoint, direction_q: ExactPoint, edges: list[int],
                     through_vertices: bool, integer_vertices: tuple[int, list] | None = None) -> RayHit:
    """:func:`cast_ray` restricted to candidate ``edges`` (every edge that may meet the ray up to
    its first certain crossing, including the edges through the origin), all in exact arithmetic."""
    if direction_q[0] == 0 and direction_q[1] == 0:
        raise InputError("ray direction (0, 0) is zero")
    frame = _Frame(env, origin_q, direction_q, integer_vertices)
    nxt = env.next_vertex
    validated = _check_departure(frame, edges, origin_q, direction_q)
    contacts: list[_Contact] = []
    seen_vertices: set[int] = set()
    inf = math.inf
    for i in edges:
        j = int(nxt[i])
        ea, eb = frame.side(i), frame.side(j)
        for v, e in ((i, ea), (j, eb)):
            if e == 0 and v not in seen_vertices:
                seen_vertices.add(v)
                s = frame.vertex_s(v)
                if s > 0:
                    contacts.append(_Contact(-inf, inf, True, v, s))
        if (ea > 0 and eb < 0) or (ea < 0 and eb > 0):
            s = frame.crossing_s(i)
            if s > 0:
                contacts.append(_Contact(-inf, inf, False, i, s))
    return _walk(frame, contacts, validated, through_vertices, origin_q, direction_q)


def _sign(x) -> int:
    return (x > 0) - (x < 0)


def _nearest(contacts: list[_Contact], frame: _Frame) -> _Contact:
    """The contact nearest the origin: by float bounds when they separate it, else exactly."""
    top = min(c.hi for c in contacts)
    cluster = [c for c in contacts if c.lo <= top]
    if len(cluster) == 1:
        return cluster[0]
    for c in cluster:
        if c.s is None:
            c.s = frame.vertex_s(c.index) if c.vertex else frame.crossing_s(c.index)
    return min(cluster, key=lambda c: c.s)


def _crossing_hit(frame: _Frame, i: int, s) -> RayHit:
    env = frame.env
    j = int(env.next_vertex[i])
    ea, eb = frame.side(i), frame.side(j)
    t = Fraction(ea) / (ea - eb)
    (ax, ay), (bx, by) = env.exact_vertices[i], env.exact_vertices[j]
    if s is None:
        s = frame.crossing_s(i)
    return RayHit(i, t, (ax + t * (bx - ax), ay + t * (by - ay)), s * frame.s_unit, None)


def _coordinate_scale(env: Environment) -> float:
    """max |x| + |y| over the vertices (floats), the scale of the float tolerances."""
    v = env.vertices
    return float(np.max(np.abs(v[:, 0]) + np.abs(v[:, 1])))


# ---------------------------------------------------------------------------------------------
# vectorised batch caster
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class RayHits:
    """First hits of a batch of rays, as arrays of length m (one entry per ray).

    Attributes
    ----------
    edge
        int64 global edge id; −1 if the ray hit nothing (only possible for an ``uncertain`` ray).
        For a vertex hit: the edge starting at the vertex.
    t
        float64 boundary parameter on ``edge`` (0 for a vertex hit).
    x, y
        float64 hit point.
    s
        float64 ray parameter, ``(x, y) ≈ origin + s * direction`` in units of the given direction.
    vertex
        int64 vertex id when the hit is within the tolerance of a vertex (always ``uncertain`` in
        floats; exact after ``exact_ties``), else −1.
    uncertain
        bool: the float answer is too close to a tie to trust (a vertex within the tolerance of the
        ray before or at the hit, two edges nearly tied, a hit right at the origin). False for every
        ray re-resolved exactly.
    exact
        The exact :class:`RayHit` of every ray re-resolved by ``exact_ties`` (ray index → hit).
    """

    edge: np.ndarray
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    s: np.ndarray
    vertex: np.ndarray
    uncertain: np.ndarray
    exact: Mapping[int, RayHit] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.edge)

    @property
    def points(self) -> np.ndarray:
        """Hit points as an (m, 2) array."""
        return np.stack([self.x, self.y], axis=1)


# Tolerance of the float batch caster, relative to the size of the environment: a vertex closer
# than this to a ray, or two hits closer than this along a ray, make the ray "uncertain".
BATCH_TOLERANCE = 1e-9

# Grid cells per edge, and DDA steps per marching round.
_CELLS_PER_EDGE = 2.5
_STEPS_PER_ROUND = 1
_MAX_STEPS_PER_ROUND = 8
# Batches of at least this many rays are cast in threads, one block per core (solverplan._arrays.thread_map).
_PARALLEL_RAYS = 4096


# Polygons with at most this many edges are cast as dense (rays × edges) arrays (RayCaster._dense_block), in
# blocks of about this many (ray, edge) cells: each temporary stays in the core's cache (measured on the 20-edge
# star: 0.56 CPU s for 10⁴ × 50 bounces in blocks of 2¹⁵ cells, 1.0 s in blocks of 8,192 rays).
_DENSE_EDGES = 48  # measured crossover with the grid (CPU time, 10⁴ rollouts): 44 edges 0.30 s vs 0.35 s, 60 edges 0.37 s vs 0.32 s
_DENSE_CELLS = 1 << 15
# Rays marched together (bounds memory and keeps the arrays in cache).
_RAYS_PER_BLOCK = 8192


class RayCaster:
    """Vectorised float ray casting against one environment, with a uniform grid index.

    The index is built once: the bounding box of the environment is cut into about one square cell
    per edge, and each edge is listed in every cell its segment passes through (with a small slack).
    :meth:`cast` marches all rays through the grid together (Amanatides–Woo steps, a few cells per
    round), tests each ray only against the edges listed in the cells it crossed, and retires a ray
    as soon as its nearest hit lies inside the cells already crossed. Work is proportional to the
    cells crossed and the edges met, not to rays × edges. Polygons with few edges skip the grid.

    ``index`` chooses the grid, the brute force (every ray against every edge), or (``"auto"``)
    dense (rays × edges) arrays for polygons of at most 48 edges — the brute force's tests without its
    bookkeeping — and the grid beyond. All three give the same answers. Batches of 4,096 rays or more are
    cast in threads, one block of rays per core (each ray's answer depends on that ray alone). Use
    :func:`ray_caster` to get the cached caster of an environment.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> caster = RayCaster(square)
    >>> hits = caster.cast([[1, 1], [1, 1]], [[1, 0], [1, 1]])
    >>> hits.edge.tolist(), hits.vertex.tolist(), hits.uncertain.tolist()
    ([1, 2], [-1, 2], [False, True])
    >>> exact = caster.cast([[1, 1]], [[1, 1]], exact_ties=True)
    >>> exact.vertex.tolist(), exact.uncertain.tolist(), exact.exact[0].point
    ([2], [False], (Fraction(4, 1), Fraction(4, 1)))
    """

    def __init__(self, env: Environment, *, index: Literal["auto", "grid", "brute-force"] = "auto") -> None:
        if index not in ("auto", "grid", "brute-force"):
            raise InputError(f"index must be 'auto', 'grid' or 'brute-force', got {index!r}")
        self.env = env
        a = np.ascontiguousarray(env.edge_start, dtype=float)
        b = np.ascontiguousarray(env.edge_end, dtype=float)
        self._ax, self._ay = a[:, 0].copy(), a[:, 1].copy()
        self._bx, self._by = b[:, 0].copy(), b[:, 1].copy()
        self._next = np.asarray(env.next_vertex, dtype=np.int64)
        common = 1
        for x, y in env.exact_vertices:
            common = _lcm(_lcm(common, x.denominator), y.denominator)
        self._integer_vertices = (
            common,
            [(x.numerator * (common // x.denominator), y.numerator * (common // y.denominator)) for x, y in env.exact_vertices],
        )
        n = len(a)
        xmin, ymin, xmax, ymax = env.bounds
        size = max(xmax - xmin, ymax - ymin)
        magnitude = _coordinate_scale(env)
        # tolerance: relative to the size, but never below 1000× the rounding error of the coordinates
        self.tolerance = max(BATCH_TOLERANCE * size, 1e3 * np.finfo(float).eps * magnitude)
        pad = 1e-6 * size + self.tolerance
        self._x0, self._y0 = xmin - pad, ymin - pad
        self._x1, self._y1 = xmax + pad, ymax + pad
        # "auto": dense (rays × edges) arrays for few edges (every ray against every edge, without bookkeeping;
        # the exact caster's candidates come from the brute force there), the grid beyond
        self.dense = index == "auto" and n <= _DENSE_EDGES
        self.brute_force = index == "brute-force" or self.dense
        if self.brute_force:
            self._cell_edges = np.arange(n, dtype=np.int64)
            self._set_cells(np.array([0, n], dtype=np.int64))
            self._nx = self._ny = 1
            self._h = max(self._x1 - self._x0, self._y1 - self._y0)
        else:
            self._build_grid(n)

    # ------------------------------------------------------------------ index
    def _build_grid(self, n: int) -> None:
        width, height = self._x1 - self._x0, self._y1 - self._y0
        h = math.sqrt(width * height / max(1.0, _CELLS_PER_EDGE * n))
        nx, ny = max(1, math.ceil(width / h)), max(1, math.ceil(height / h))
        self._nx, self._ny, self._h = nx, ny, h
        slack = 1e-6  # in cells: covers float error of the marching, and the tie tolerance
        gax, gay = (self._ax - self._x0) / h, (self._ay - self._y0) / h
        gbx, gby = (self._bx - self._x0) / h, (self._by - self._y0) / h
        lox, hix = np.minimum(gax, gbx) - slack, np.maximum(gax, gbx) + slack
        c0 = np.clip(np.floor(lox), 0, nx - 1).astype(np.int64)
        c1 = np.clip(np.floor(hix), 0, nx - 1).astype(np.int64)
        ncols = c1 - c0 + 1
        edge_of = np.repeat(np.arange(n, dtype=np.int64), ncols)
        col = np.repeat(c0, ncols) + ragged_arange(ncols)
        # y-range of the edge over the column's x-range (clipped to the edge's own x-range)
        xl = np.maximum(col.astype(float), lox[edge_of])
        xr = np.minimum(col + 1.0, hix[edge_of])
        dxg = gbx[edge_of] - gax[edge_of]
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = (gby[edge_of] - gay[edge_of]) / dxg
            yl = gay[edge_of] + (xl - gax[edge_of]) * slope
            yr = gay[edge_of] + (xr - gax[edge_of]) * slope
        steep = ~np.isfinite(yl) | ~np.isfinite(yr) | (np.abs(dxg) < 1e-9)
        ylo = np.where(steep, np.minimum(gay, gby)[edge_of], np.minimum(yl, yr))
        yhi = np.where(steep, np.maximum(gay, gby)[edge_of], np.maximum(yl, yr))
        ylo = np.maximum(ylo, np.minimum(gay, gby)[edge_of]) - slack
        yhi = np.minimum(yhi, np.maximum(gay, gby)[edge_of]) + slack
        r0 = np.clip(np.floor(ylo), 0, ny - 1).astype(np.int64)
        r1 = np.clip(np.floor(yhi), 0, ny - 1).astype(np.int64)
        nrows = r1 - r0 + 1
        edge_of2 = np.repeat(edge_of, nrows)
        cell = (np.repeat(r0, nrows) + ragged_arange(nrows)) * nx + np.repeat(col, nrows)
        order = np.lexsort((edge_of2, cell))
        cell, edge_of2 = cell[order], edge_of2[order]
        self._cell_edges = edge_of2
        self._set_cells(np.searchsorted(cell, np.arange(nx * ny + 1)).astype(np.int64))

    def _set_cells(self, cell_start: np.ndarray) -> None:
        # one extra, empty cell at the end stands for "outside the grid"
        self._cell_start = np.append(cell_start, cell_start[-1])
        self._cell_count = np.diff(self._cell_start)
        self._empty_cell = len(self._cell_start) - 2

    @property
    def grid_shape(self) -> tuple[int, int]:
        """(columns, rows) of the grid index ((1, 1) for the brute-force path)."""
        return (self._nx, self._ny)

    # ------------------------------------------------------------------ casting
    def cast(
        self,
        origins: np.ndarray,
        directions: np.ndarray,
        *,
        source_edges: np.ndarray | None = None,
        exact_ties: bool = False,
        through_vertices: bool = False,
    ) -> RayHits:
        """First hits of the rays ``origins[k] + s * directions[k]``, s > 0.

        Parameters
        ----------
        origins, directions
            Float arrays of shape (m, 2); directions need not be unit vectors (``s`` is in their units).
            Origins lie in the closed free space.
        source_edges
            Optional int array (m,): the edge each origin lies on (−1 for none). That edge is
            ignored for its ray (the origin is on it). Without it, a ray from a boundary point meets
            its own edge at s ≈ 0 and is flagged ``uncertain``.
        exact_ties
            Re-resolve every ``uncertain`` ray with :func:`cast_ray`, taking the float origin and
            direction as exact binary rationals; their entries become exact (rounded to float) and
            their :class:`RayHit` is kept in ``RayHits.exact``.
        through_vertices
            Passed to :func:`cast_ray` for the re-resolved rays; implies ``exact_ties`` (floats cannot
            tell a grazed vertex from a hit one, and every ray near a vertex is ``uncertain``).

        Raises
        ------
        InputError
            Bad shapes, non-finite numbers, a zero direction, or an origin that is certainly not in
            the free space (the message names the first such ray).
        """
        origins = _as_points(origins, "origins")
        directions = _as_points(directions, "directions")
        m = len(origins)
        if len(directions) != m:
            raise InputError(f"origins and directions differ in length: {m} and {len(directions)}")
        if source_edges is None:
            src = np.full(m, -1, dtype=np.int64)
        else:
            src = np.asarray(source_edges, dtype=np.int64).reshape(-1)
            if len(src) != m:
                raise InputError(f"source_edges has length {len(src)}, expected {m}")
        norm = np.hypot(directions[:, 0], directions[:, 1])
        zero = np.flatnonzero(norm == 0)
        if len(zero):
            raise InputError(f"directions[{zero[0]}] is zero")
        outside = np.flatnonzero(
            (origins[:, 0] < self._x0) | (origins[:, 0] > self._x1)
            | (origins[:, 1] < self._y0) | (origins[:, 1] > self._y1)
        )
        if len(outside):
            k = int(outside[0])
            raise InputError(f"origins[{k}] = {format_point(origins[k].tolist())} is not in the free space")
        unit = directions / norm[:, None]
        s_unit, edge, t, vertex, uncertain, arrival = self._march(origins, unit, src)
        bad = np.flatnonzero(~uncertain & ((edge < 0) | (arrival <= 0)))
        if len(bad):
            k = int(bad[0])
            raise InputError(f"origins[{k}] = {format_point(origins[k].tolist())} is not in the free space")
        hits = self._assemble(edge, t, vertex, s_unit / norm, uncertain)
        if exact_ties or through_vertices:
            hits = self._resolve_exactly(hits, origins, directions, src, through_vertices, None)
        return hits

    def cast_from_boundary(
        self,
        edges: np.ndarray,
        t: np.ndarray,
        headings: np.ndarray,
        *,
        exact_ties: bool = False,
        through_vertices: bool = False,
    ) -> RayHits:
        """First hits of rays leaving boundary points ``(edges[k], t[k])`` at ``headings[k]``.

        Headings are radians in (0, π), CCW from the directed edge (π/2 = inward normal); the ray's
        direction is the unit vector at that heading, so ``s`` is the distance travelled. The source
        edge is ignored (the origin lies on it). With ``exact_ties``, uncertain rays are re-resolved
        by :func:`cast_ray` from the exact point at the binary rational ``t`` on the exact edge, with
        the float direction taken as an exact binary rational.

        >>> from solverplan.environment import Environment
        >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
        >>> hits = RayCaster(square).cast_from_boundary([0, 0], [0.25, 0.5], [math.pi / 2, math.pi / 4])
        >>> hits.edge.tolist(), hits.t.round(6).tolist(), hits.s.round(6).tolist()
        ([2, 1], [0.75, 0.5], [4.0, 2.828427])
        """
        edges_arr, t_arr, headings_arr = _boundary_arrays(self.env, edges, t, headings)
        origins = self.env.points_at(edges_arr, t_arr)
        directions = heading_directions(self.env, edges_arr, headings_arr)
        s_unit, edge, tt, vertex, uncertain, arrival = self._march(origins, directions, edges_arr)
        hits = self._assemble(edge, tt, vertex, s_unit, uncertain | (edge < 0) | (arrival <= 0))
        if exact_ties or through_vertices:
            hits = self._resolve_exactly(hits, origins, directions, edges_arr, through_vertices, t_arr)
        return hits

    def cast_exact(
        self,
        origins: Sequence[Sequence[object]],
        directions: Sequence[Sequence[object]],
        *,
        through_vertices: bool = False,
        skip_invalid: bool = False,
    ) -> list[RayHit | None]:
        """Exact first hits of many rays: :func:`cast_ray` for each, with the grid index in place of
        the scalar prefilter.

        The float rays are marched through the index together; each ray keeps the edges that may
        meet it up to its first certain crossing (usually one to three), and only those go through
        exact arithmetic. Numbers are read as by :func:`cast_ray` (floats at their exact binary value).

        Parameters
        ----------
        skip_invalid
            Return ``None`` for a ray that :func:`cast_ray` would reject (its origin is not in the
            free space, it leaves a boundary point into the obstacle, zero direction) instead of
            raising.

        >>> from solverplan.environment import Environment
        >>> room = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])  # an L
        >>> hits = RayCaster(room).cast_exact([(4, 4), (4, 4)], [(2, -3), (1, 1)], skip_invalid=True)
        >>> hits[0].point, hits[1]
        ((Fraction(20, 3), Fraction(0, 1)), None)
        """
        if len(origins) != len(directions):
            raise InputError(f"origins and directions differ in length: {len(origins)} and {len(directions)}")
        m = len(origins)
        o_q = [_exact_pair(p, f"origins[{k}]") for k, p in enumerate(origins)]
        d_q = [_exact_pair(d, f"directions[{k}]") for k, d in enumerate(directions)]
        results: list[RayHit | None] = [None] * m
        fo = np.array([[float(x), float(y)] for x, y in o_q], dtype=float).reshape(-1, 2)
        fd = np.array([_float_direction(dx, dy) for dx, dy in d_q], dtype=float).reshape(-1, 2)
        ok = (fd != 0).any(axis=1) & (fo[:, 0] >= self._x0) & (fo[:, 0] <= self._x1)
        ok &= (fo[:, 1] >= self._y0) & (fo[:, 1] <= self._y1)
        rays = np.flatnonzero(ok)
        fd[~ok] = (1.0, 0.0)
        unit = fd[rays] / np.hypot(fd[rays, 0], fd[rays, 1])[:, None]
        collected: list = []
        best = self._march(fo[rays], unit, np.full(len(rays), -1, dtype=np.int64), collected)[0]
        if collected:
            r = np.concatenate([c[0] for c in collected])
            e = np.concatenate([c[1] for c in collected])
            sv = np.concatenate([c[2] for c in collected])
            keep = sv <= best[r] + self.tolerance
            r, e = r[keep], e[keep]
            order = np.lexsort((e, r))
            r, e = r[order], e[order]
            fresh = np.ones(len(r), dtype=bool)
            fresh[1:] = (r[1:] != r[:-1]) | (e[1:] != e[:-1])
            r, e = r[fresh], e[fresh]
        else:
            r = e = np.zeros(0, dtype=np.int64)
        bounds = np.searchsorted(r, np.arange(len(rays) + 1))
        edge_list = e.tolist()
        for local, k in enumerate(rays.tolist()):
            try:
                results[k] = _exact_hit_among(
                    self.env, o_q[k], d_q[k], edge_list[bounds[local] : bounds[local + 1]], through_vertices,
                    self._integer_vertices,
                )
            except InputError as exc:
                if not skip_invalid:
                    raise InputError(f"ray {k}: {exc}") from None
        if not skip_invalid:
            for k in np.flatnonzero(~ok).tolist():
                cast_ray(self.env, o_q[k], d_q[k])  # raises the scalar caster's message
        return results

    # ------------------------------------------------------------------ internals
    def _assemble(self, edge, t, vertex, s, uncertain) -> RayHits:
        hit = edge >= 0
        e = np.where(hit, edge, 0)
        x = np.where(hit, self._ax[e] + t * (self._bx[e] - self._ax[e]), np.nan)
        y = np.where(hit, self._ay[e] + t * (self._by[e] - self._ay[e]), np.nan)
        on_vertex = vertex >= 0
        v = np.where(on_vertex, vertex, 0)
        x = np.where(on_vertex, self._ax[v], x)
        y = np.where(on_vertex, self._ay[v], y)
        edge = np.where(on_vertex, vertex, edge)
        t = np.where(on_vertex, 0.0, np.where(hit, t, np.nan))
        s = np.where(hit, s, np.nan)
        return RayHits(edge, t, x, y, s, vertex, uncertain)

    def _resolve_exactly(self, hits, origins, directions, src, through_vertices, t_boundary) -> RayHits:
        """Re-cast the uncertain rays with the exact caster; see :meth:`cast`."""
        edge, t, x, y, s = hits.edge.copy(), hits.t.copy(), hits.x.copy(), hits.y.copy(), hits.s.copy()
        vertex, uncertain = hits.vertex.copy(), hits.uncertain.copy()
        todo = np.flatnonzero(uncertain).tolist()
        exact_directions = [(Fraction(float(directions[k, 0])), Fraction(float(directions[k, 1]))) for k in todo]
        if t_boundary is not None:
            exact_origins = [self.env.exact_point_at(int(src[k]), Fraction(float(t_boundary[k]))) for k in todo]
        else:
            exact_origins = [(Fraction(float(origins[k, 0])), Fraction(float(origins[k, 1]))) for k in todo]
        # a ray may be rejected exactly, e.g. a heading so close to 0 or π that its float direction
        # leaves the edge into the obstacle: it keeps its float answer and stays uncertain
        resolved = self.cast_exact(exact_origins, exact_directions, through_vertices=through_vertices, skip_invalid=True)
        exact: dict[int, RayHit] = {}
        for k, hit in zip(todo, resolved):
            if hit is None:
                continue
            exact[k] = hit
            edge[k], t[k] = hit.edge, float(hit.t)
            x[k], y[k] = float(hit.point[0]), float(hit.point[1])
            s[k] = float(hit.s)
            vertex[k] = -1 if hit.vertex is None else hit.vertex
            uncertain[k] = False
        return RayHits(edge, t, x, y, s, vertex, uncertain, exact)

    def _march(self, origins: np.ndarray, unit: np.ndarray, src: np.ndarray, collect: list | None = None):
        """Float first hits of rays with unit directions. Returns per ray: distance s, edge (−1 none),
        t, vertex (−1 none), uncertain, and the winner's arrival sign (> 0: from the free side).

        With ``collect`` (a list), the "first hit" is the first *certain* proper crossing, and every
        (ray, edge, s) pair whose edge meets the ray's line within the tolerance, ahead of the origin
        or at it, is appended to ``collect`` as arrays: the candidates of the exact caster."""
        m = len(origins)
        out = [np.empty(m), np.empty(m, dtype=np.int64), np.empty(m), np.empty(m, dtype=np.int64),
               np.empty(m, dtype=bool), np.empty(m)]
        workers = threads() if collect is None and m >= _PARALLEL_RAYS else 1
        size = max(256, _DENSE_CELLS // len(self._ax)) if collect is None and self.dense else _RAYS_PER_BLOCK
        size = max(1, min(size, -(-m // workers)))
        blocks = [(lo, min(m, lo + size)) for lo in range(0, m, size)]
        if workers > 1:
            # every ray's answer depends on that ray alone, so blocks cast in threads (numpy releases the GIL in
            # its loops) give the same answers as one after the other
            parts = thread_map(lambda b: self._march_block(origins[b[0]:b[1]], unit[b[0]:b[1]], src[b[0]:b[1]], None),
                               blocks)
            for (lo, hi), part in zip(blocks, parts):
                for arr, values in zip(out, part):
                    arr[lo:hi] = values
            return tuple(out)
        for lo, hi in blocks:
            pairs: list | None = None if collect is None else []
            part = self._march_block(origins[lo:hi], unit[lo:hi], src[lo:hi], pairs)
            for arr, values in zip(out, part):
                arr[lo:hi] = values
            if collect is not None and pairs is not None:  # both or neither
                collect.extend((r + lo, e, s) for r, e, s in pairs)
        return tuple(out)

    def _march_block(self, origins: np.ndarray, unit: np.ndarray, src: np.ndarray, collect: list | None):
        m = len(origins)
        ox, oy = origins[:, 0].copy(), origins[:, 1].copy()
        dx, dy = unit[:, 0].copy(), unit[:, 1].copy()
        if collect is None and self.dense:  # (blocks sized by _march)
            return self._dense_block(ox, oy, dx, dy, src)
        st = _RayState(m, self.tolerance)
        ray = (dx, dy, dx * oy - dy * ox, dx * ox + dy * oy, src, collect)  # direction, cross(D, O), dot(D, O)
        if self.brute_force:
            n = len(self._ax)
            rows = np.arange(m, dtype=np.int64)
            self._test_pairs(st, rows, np.full(m, n, dtype=np.int64), np.tile(np.arange(n, dtype=np.int64), m), ray)
            return st.result()
        h, nx, ny = self._h, self._nx, self._ny
        gx, gy = (ox - self._x0) / h, (oy - self._y0) / h
        ix = np.clip(np.floor(gx), 0, nx - 1).astype(np.int64)
        iy = np.clip(np.floor(gy), 0, ny - 1).astype(np.int64)
        with np.errstate(divide="ignore", invalid="ignore"):
            stepx = np.sign(dx).astype(np.int64)
            stepy = np.sign(dy).astype(np.int64)
            tdx = np.where(dx != 0, h / np.abs(dx), np.inf)
            tdy = np.where(dy != 0, h / np.abs(dy), np.inf)
            tmx = np.where(dx > 0, (ix + 1 - gx) * h / dx, np.where(dx < 0, (ix - gx) * h / dx, np.inf))
            tmy = np.where(dy > 0, (iy + 1 - gy) * h / dy, np.where(dy < 0, (iy - gy) * h / dy, np.inf))
        active = np.arange(m, dtype=np.int64)
        cell_start, cell_count, cell_edges = self._cell_start, self._cell_count, self._cell_edges
        tol = self.tolerance
        steps = _STEPS_PER_ROUND
        while len(active):
            # march up to `steps` cells for every active ray, collecting the non-empty cells
            k = len(active)
            cells = np.empty((k, steps), dtype=np.int64)
            exit_s = np.full(k, np.inf)
            inside = np.ones(k, dtype=bool)
            for j in range(steps):
                cells[:, j] = np.where(inside, iy * nx + ix, self._empty_cell)
                go_x = tmx < tmy
                exit_s = np.where(inside, np.minimum(tmx, tmy), exit_s)
                ix = np.where(go_x, ix + stepx, ix)
                iy = np.where(go_x, iy, iy + stepy)
                tmx = np.where(go_x, tmx + tdx, tmx)
                tmy = np.where(go_x, tmy, tmy + tdy)
                inside &= (ix >= 0) & (ix < nx) & (iy >= 0) & (iy < ny)
            exit_s = np.where(inside, exit_s, np.inf)  # a ray that left the grid has seen everything
            flat = cells.reshape(-1)
            cnt = cell_count[flat]
            per_ray = cnt.reshape(k, steps).sum(axis=1)
            edges = cell_edges[np.repeat(cell_start[flat], cnt) + ragged_arange(cnt)]
            self._test_pairs(st, active, per_ray, edges, ray)
            keep = (st.best_s[active] + tol > exit_s) & inside
            active = active[keep]
            ix, iy, tmx, tmy = ix[keep], iy[keep], tmx[keep], tmy[keep]
            stepx, stepy, tdx, tdy = stepx[keep], stepy[keep], tdx[keep], tdy[keep]
            steps = min(_MAX_STEPS_PER_ROUND, 2 * steps)
        return st.result()

    def _dense_block(self, ox: np.ndarray, oy: np.ndarray, dx: np.ndarray, dy: np.ndarray, src: np.ndarray):
        """:meth:`_test_pairs` of every ray against every edge as (rays × edges) arrays, for polygons of few edges:
        the same formulas on the same floats, so the same answers as the brute force and the grid, without their
        ragged bookkeeping (one row per ray, reductions along it). Returns what :meth:`_RayState.result` does."""
        tol = self.tolerance
        m, n = len(ox), len(self._ax)
        ax, ay, bx, by = self._ax[None, :], self._ay[None, :], self._bx[None, :], self._by[None, :]
        rdx, rdy = dx[:, None], dy[:, None]
        co, po = (dx * oy - dy * ox)[:, None], (dx * ox + dy * oy)[:, None]
        sa = rdx * ay - rdy * ax - co  # signed distance of a from the ray's line (unit direction)
        sb = rdx * by - rdy * bx - co
        # pairs whose edge meets the ray's line (within the tolerance), the source edge left out
        meets = (np.minimum(sa, sb) <= tol) & (np.maximum(sa, sb) >= -tol) & (np.arange(n)[None, :] != src[:, None])
        d, near_a, near_b, t, nearer_a, s = _crossings(rdx, rdy, ax, ay, bx, by, po, sa, sb, tol)
        ahead = meets & (s > tol)
        suspicious = meets & (s > -tol) & (near_a | near_b | (s <= tol))
        sv = np.where(ahead, s, np.inf)
        win = np.argmin(sv, axis=1)  # the first edge of the least distance, as the pair order gives it
        rows = np.arange(m)
        best_s = sv[rows, win]
        has = best_s < np.inf
        best_e = np.where(has, win, -1)
        sv[rows, win] = np.inf  # the other edges ahead
        second = sv.min(axis=1)
        near = np.where(suspicious, np.maximum(s, 0.0), np.inf).min(axis=1)
        wa, wb, wn = near_a[rows, win], near_b[rows, win], nearer_a[rows, win]
        va, vb = win, self._next[win]
        v = np.where(wa & wb, np.where(wn, va, vb), np.where(wa, va, np.where(wb, vb, -1)))
        v = np.where(has, v, -1)
        t_win = np.where(has, t[rows, win], np.nan)
        d_win = np.where(has, d[rows, win], 0.0)
        limit = best_s + tol
        uncertain = (best_e < 0) | (v >= 0) | (near <= limit) | (second <= limit)
        return best_s, best_e, t_win, v, uncertain, d_win

    def _test_pairs(self, st, rows, counts, edges, ray) -> None:
        """Test ray rows[i] against its `counts[i]` consecutive entries of `edges`; merge into `st`."""
        if len(edges) == 0:
            return
        dx, dy, cross_o, dot_o, src, collect = ray
        tol = self.tolerance
        r = np.repeat(rows, counts)
        rdx, rdy = dx[r], dy[r]
        ax, ay, bx, by = self._ax[edges], self._ay[edges], self._bx[edges], self._by[edges]
        co = cross_o[r]
        sa = rdx * ay - rdy * ax - co  # signed distance of a from the ray's line (unit direction)
        sb = rdx * by - rdy * bx - co
        q = np.flatnonzero((np.minimum(sa, sb) <= tol) & (np.maximum(sa, sb) >= -tol))
        if len(q) == 0:
            return
        # only the pairs whose edge meets the ray's line (within the tolerance) go on
        r, e, sa, sb = r[q], edges[q], sa[q], sb[q]
        rdx, rdy, ax, ay, bx, by = rdx[q], rdy[q], ax[q], ay[q], bx[q], by[q]
        d, near_a, near_b, t, nearer, s = _crossings(rdx, rdy, ax, ay, bx, by, dot_o[r], sa, sb, tol)
        foreign = e != src[r]
        ahead = foreign & (s > tol)
        suspicious = foreign & (s > -tol) & (near_a | near_b | (s <= tol))
        if collect is not None:
            keep = s >= -tol
            collect.append((r[keep], e[keep], s[keep]))
            ahead &= ~(near_a | near_b | (np.abs(d) <= 2 * tol))  # certainly a proper crossing ahead
        # per-ray reductions over consecutive groups (r is sorted)
        starts = np.flatnonzero(np.concatenate([[True], r[1:] != r[:-1]]))
        sizes = np.diff(np.append(starts, len(r)))
        grp_rows = r[starts]
        sv = np.where(ahead, s, np.inf)
        c_s = np.minimum.reduceat(sv, starts)
        idx = np.arange(len(sv), dtype=np.int64)
        is_min = ahead & (sv == np.repeat(c_s, sizes))
        win = np.minimum.reduceat(np.where(is_min, idx, len(sv)), starts)
        has = win < len(sv)
        win = np.where(has, win, 0)
        c_e = np.where(has, e[win], -1)
        other = ahead & (e != np.repeat(c_e, sizes))
        c_second = np.minimum.reduceat(np.where(other, s, np.inf), starts)
        c_near = np.minimum.reduceat(np.where(suspicious, np.maximum(s, 0.0), np.inf), starts)
        va, vb = e[win], self._next[e[win]]
        wa, wb = near_a[win], near_b[win]
        c_v = np.where(wa & wb, np.where(nearer[win], va, vb), np.where(wa, va, np.where(wb, vb, -1)))
        c_v = np.where(has, c_v, -1)
        st.merge(grp_rows, c_s, c_e, c_second, c_near, t[win], d[win], c_v)


def _crossings(rdx, rdy, ax, ay, bx, by, po, sa, sb, tol):
    """Where rays (unit directions (rdx, rdy), ``po`` = dot(D, O)) meet edges a → b whose end points lie at signed
    distances ``sa``, ``sb`` from their lines (arrays of any matching shapes): ``d`` (> 0: crossing from the free,
    left side), whether a and b lie on the line (within ``tol``), the edge parameter ``t``, whether a is the nearer
    end ahead, and the distance ``s`` along the ray. An edge (nearly) along its ray is met at its nearer end ahead."""
    pa = rdx * ax + rdy * ay - po  # distance of a along the ray
    pb = rdx * bx + rdy * by - po
    d = sb - sa
    near_a, near_b = np.abs(sa) <= tol, np.abs(sb) <= tol
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip(-sa / d, 0.0, 1.0)
    flat = np.abs(d) <= 2 * tol
    nearer_a = (pa <= pb) & (pa > tol) | (pb <= tol)
    if flat.any():
        t = np.where(flat, np.where(nearer_a, 0.0, 1.0), t)
    return d, near_a, near_b, t, nearer_a, pa + t * (pb - pa)


class _RayState:
    """Per-ray best hit so far, the nearest other edge, and the nearest suspicious contact."""

    def __init__(self, m: int, tol: float) -> None:
        self.tol = tol
        self.best_s = np.full(m, np.inf)
        self.best_e = np.full(m, -1, dtype=np.int64)
        self.second = np.full(m, np.inf)
        self.near = np.full(m, np.inf)
        self.t = np.full(m, np.nan)
        self.d = np.zeros(m)
        self.v = np.full(m, -1, dtype=np.int64)

    def merge(self, rows, c_s, c_e, c_second, c_near, c_t, c_d, c_v) -> None:
        old_s, old_e, old_second = self.best_s[rows], self.best_e[rows], self.second[rows]
        same = c_e == old_e
        better = (c_s < old_s) & ~same
        self.second[rows] = np.where(
            same,
            np.minimum(old_second, c_second),
            np.where(better, np.minimum(c_second, old_s), np.minimum(old_second, c_s)),
        )
        self.near[rows] = np.minimum(self.near[rows], c_near)
        self.best_s[rows] = np.where(better, c_s, old_s)
        self.best_e[rows] = np.where(better, c_e, old_e)
        self.t[rows] = np.where(better, c_t, self.t[rows])
        self.d[rows] = np.where(better, c_d, self.d[rows])
        self.v[rows] = np.where(better, c_v, self.v[rows])

    def result(self):
        """(s, edge, t, vertex, uncertain, arrival) per ray."""
        limit = self.best_s + self.tol
        uncertain = (self.best_e < 0) | (self.v >= 0) | (self.near <= limit) | (self.second <= limit)
        return self.best_s, self.best_e, self.t, self.v, uncertain, self.d


def _as_points(values: object, name: str) -> np.ndarray:
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers of shape (m, 2)") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(f"{name} must have shape (m, 2), got {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if len(bad):
        raise InputError(f"{name}[{bad[0]}] is not finite")
    return arr


def _boundary_arrays(env: Environment, edges, t, headings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Validate boundary rays: edge ids, t ∈ [0, 1], headings ∈ (0, π), equal lengths."""
    try:
        edges_f = np.asarray(edges, dtype=float).reshape(-1)
        t_arr = np.asarray(t, dtype=float).reshape(-1)
        h_arr = np.asarray(headings, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError("edges, t and headings must be numbers") from None
    m = len(edges_f)
    if len(t_arr) != m or len(h_arr) != m:
        raise InputError(f"edges, t and headings differ in length: {m}, {len(t_arr)} and {len(h_arr)}")
    n = env.n_edges
    bad = np.flatnonzero(~((edges_f >= 0) & (edges_f < n) & (edges_f == np.floor(edges_f))))
    if len(bad):
        k = int(bad[0])
        raise InputError(f"edges[{k}] = {edges_f[k]:g} is not an edge: edges are e0..e{n - 1}")
    bad = np.flatnonzero(~((t_arr >= 0) & (t_arr <= 1)))
    if len(bad):
        k = int(bad[0])
        raise InputError(f"t[{k}] = {float(t_arr[k])!r} is not in [0, 1]")
    bad = np.flatnonzero(~((h_arr > 0) & (h_arr < math.pi)))
    if len(bad):
        k = int(bad[0])
        raise InputError(f"headings[{k}] = {float(h_arr[k])!r} is not in (0, π)")
    return edges_f.astype(np.int64), t_arr, h_arr


def heading_directions(env: Environment, edges: np.ndarray, headings: np.ndarray) -> np.ndarray:
    """Unit direction vectors (m, 2) of headings θ (radians, CCW from the directed edge ``edges[k]``).

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> heading_directions(square, [1], [math.pi / 2]).round(12).tolist()   # edge 1 points up: π/2 is −x
    [[-1.0, 0.0]]
    """
    edges = np.asarray(edges, dtype=np.int64).reshape(-1)
    headings = np.asarray(headings, dtype=float).reshape(-1)
    ux, uy = _unit_edges(env)
    ex, ey = ux[edges], uy[edges]
    c, s = np.cos(headings), np.sin(headings)
    out = np.empty((len(edges), 2))
    out[:, 0] = c * ex - s * ey
    out[:, 1] = s * ex + c * ey
    return out


@functools.lru_cache(maxsize=32)
def _unit_edges(env: Environment) -> tuple[np.ndarray, np.ndarray]:
    """The unit direction of every edge of ``env`` (x and y components), computed once per environment."""
    e = env.edge_end - env.edge_start
    e = e / np.hypot(e[:, 0], e[:, 1])[:, None]
    return np.ascontiguousarray(e[:, 0]), np.ascontiguousarray(e[:, 1])


@functools.lru_cache(maxsize=32)
def ray_caster(env: Environment) -> RayCaster:
    """The :class:`RayCaster` of ``env``, built once and cached (environments are immutable)."""
    return RayCaster(env)


def _with_cached_caster(method: Callable[Concatenate[RayCaster, P], R], name: str, doc: str
                        ) -> Callable[Concatenate[Environment, P], R]:
    """``method`` of :class:`RayCaster` as a function of the environment, run by its cached caster
    (:func:`ray_caster`): the parameters are the method's, written once (type checkers, :func:`help` and
    :func:`inspect.signature` see them all, after the environment)."""
    def call(env: Environment, /, *args: P.args, **kwargs: P.kwargs) -> R:
        return method(ray_caster(env), *args, **kwargs)

    own = inspect.signature(method)
    first = inspect.Parameter("env", inspect.Parameter.POSITIONAL_ONLY, annotation="Environment")
    call.__signature__ = own.replace(parameters=[first, *list(own.parameters.values())[1:]])  # type: ignore[attr-defined]
    call.__name__ = call.__qualname__ = name
    call.__doc__ = doc
    return call


cast_rays = _with_cached_caster(RayCaster.cast, "cast_rays", """Batch first hits with the cached caster of ``env``; see :meth:`RayCaster.cast`.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> cast_rays(square, [[1, 2]], [[-2, 0]]).s.tolist()      # s in units of the direction
    [0.5]
    """)

cast_rays_exact = _with_cached_caster(RayCaster.cast_exact, "cast_rays_exact", """Exact first hits of many rays with the cached caster of ``env``; see :meth:`RayCaster.cast_exact`.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> [hit.vertex for hit in cast_rays_exact(square, [(1, 1), (1, 1)], [(1, 1), (1, 0)])]
    [2, None]
    """)

cast_from_boundary = _with_cached_caster(RayCaster.cast_from_boundary, "cast_from_boundary", """Batch first hits from boundary points at headings, with the cached caster of ``env``;
    see :meth:`RayCaster.cast_from_boundary`.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> hits = cast_from_boundary(square, [0], [0.5], [3 * math.pi / 4])
    >>> hits.edge.tolist(), hits.x.tolist(), hits.y.tolist()
    ([3], [0.0], [2.0])
    """)
