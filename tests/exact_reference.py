"""A tiny exact reference for P′, the BVG and safe headings, written from the definitions alone.

Nothing here calls solverplan's geometry: only :class:`~fractions.Fraction` arithmetic on the rings of
an environment (outer ring counter-clockwise, holes clockwise, free space on the left of every directed
edge, edges numbered ring by ring — ``docs/contract.md``). It is slow (every decision loops over every
edge) and meant for instances of a few dozen vertices.

- :func:`reference_partition` — Algorithm 1: for every reflex vertex r and every vertex v whose closed
  segment r v lies in the closed free space, the line v → r continued beyond r (when it enters the open
  free space there) stops where it first leaves the closed free space; a stop inside an edge is an
  inserted point, a stop at a vertex inserts nothing.
- :func:`reference_arcs` — Def. 5: two open segments see each other when some open segment p q between
  them lies in the open free space. Decided by exact sampling that cannot miss: the window of the target
  seen from p only opens or closes where p is collinear with two vertices, and the visible part of the
  target from a fixed p is bounded by shadows of vertices, so the midpoints of those cells suffice.
- :func:`heading_is_safe` — Def. 7 for one exact direction: from every point of the open source the ray
  first leaves the closed free space inside the open target (grazing a vertex passes it, the safe set
  being closed). The ray's first blocking edge only changes where the ray passes through a vertex, so
  the vertices' projections along the direction and the midpoints between them suffice.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations
from typing import Sequence

Point = tuple[Fraction, Fraction]


def _sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1]


def _sign(x) -> int:
    return (x > 0) - (x < 0)


def _at(p, d, s):
    return (p[0] + s * d[0], p[1] + s * d[1])


class Rings:
    """The walls of an environment as exact edges (a, b), numbered like the contract's edge ids."""

    def __init__(self, rings: Sequence[Sequence[Point]]) -> None:
        self.rings = [tuple((Fraction(x), Fraction(y)) for x, y in ring) for ring in rings]
        self.edges: list[tuple[Point, Point]] = []
        self.vertices: list[Point] = []
        self.prev: list[int] = []
        self.next: list[int] = []
        for ring in self.rings:
            base, n = len(self.vertices), len(ring)
            for k in range(n):
                self.vertices.append(ring[k])
                self.edges.append((ring[k], ring[(k + 1) % n]))
                self.prev.append(base + (k - 1) % n)
                self.next.append(base + (k + 1) % n)

    # ------------------------------------------------------------------ points
    def on_boundary(self, p: Point) -> bool:
        for a, b in self.edges:
            if _cross(_sub(b, a), _sub(p, a)) == 0 and _dot(_sub(p, a), _sub(p, b)) <= 0:
                return True
        return False

    @staticmethod
    def _inside_ring(p: Point, ring) -> bool:
        """Crossing number of the horizontal ray to +x (p not on the ring)."""
        inside = False
        n = len(ring)
        for k in range(n):
            a, b = ring[k], ring[(k + 1) % n]
            if (a[1] > p[1]) != (b[1] > p[1]):
                x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
                if p[0] < x:
                    inside = not inside
        return inside

    def classify(self, p: Point) -> int:
        """1 in the open free space, 0 on a wall, −1 outside (in an obstacle or beyond the outer ring)."""
        if self.on_boundary(p):
            return 0
        if not self._inside_ring(p, self.rings[0]):
            return -1
        return -1 if any(self._inside_ring(p, hole) for hole in self.rings[1:]) else 1

    # ------------------------------------------------------------------ lines
    def events(self, p: Point, d) -> list[Fraction]:
        """Parameters s of the points p + s d (all s) where the line meets a vertex or properly crosses an edge."""
        out = set()
        dd = _dot(d, d)
        for w in self.vertices:
            if _cross(d, _sub(w, p)) == 0:
                out.add(_dot(_sub(w, p), d) / dd)
        for a, b in self.edges:
            sa, sb = _sign(_cross(d, _sub(a, p))), _sign(_cross(d, _sub(b, p)))
            if sa * sb < 0:
                out.add(_cross(_sub(a, p), _sub(b, a)) / _cross(d, _sub(b, a)))
        return sorted(out)

    def first_block(self, p: Point, d) -> Fraction:
        """The largest s ≥ 0 such that p + σ d stays in the closed free space for σ ∈ [0, s]."""
        prev = Fraction(0)
        for s in [s for s in self.events(p, d) if s > 0] + [None]:
            mid = prev + 1 if s is None else (prev + s) / 2
            if self.classify(_at(p, d, mid)) < 0:
                return prev
            prev = s
        raise AssertionError("a ray left the bounded free space nowhere")  # pragma: no cover

    def closed_segment_free(self, p: Point, q: Point) -> bool:
        d = _sub(q, p)
        cuts = [Fraction(0)] + [s for s in self.events(p, d) if 0 < s < 1] + [Fraction(1)]
        return all(self.classify(_at(p, d, (x + y) / 2)) >= 0 for x, y in zip(cuts, cuts[1:]))

    def open_segment_interior(self, p: Point, q: Point) -> bool:
        d = _sub(q, p)
        if any(0 < s < 1 for s in self.events(p, d)):
            return False
        return self.classify(_at(p, d, Fraction(1, 2))) == 1

    def locate(self, point: Point) -> tuple[int, Fraction] | None:
        """(edge, t) of a point inside an edge (0 < t < 1), None for a vertex."""
        if point in self.vertices:
            return None
        for e, (a, b) in enumerate(self.edges):
            ab = _sub(b, a)
            if _cross(ab, _sub(point, a)) == 0:
                t = _dot(_sub(point, a), ab) / _dot(ab, ab)
                if 0 < t < 1:
                    return e, t
        raise AssertionError(f"{point} is on no edge")  # pragma: no cover

    def is_reflex(self, v: int) -> bool:
        a, b, c = self.vertices[self.prev[v]], self.vertices[v], self.vertices[self.next[v]]
        return _cross(_sub(b, a), _sub(c, b)) < 0  # a right turn: free space (on the left) wraps around


# ---------------------------------------------------------------------------------------------
# Algorithm 1
# ---------------------------------------------------------------------------------------------
def reference_partition(rings) -> dict[tuple[int, Fraction], tuple[Point, frozenset]]:
    """{(edge, t): (point, sources)} of every inserted point; a source is (r, v), v None for r's neighbours."""
    walls = rings if isinstance(rings, Rings) else Rings(rings)
    found: dict[tuple[int, Fraction], tuple[Point, set]] = {}
    for r, rp in enumerate(walls.vertices):
        if not walls.is_reflex(r):
            continue
        for v, vp in enumerate(walls.vertices):
            if v == r or not walls.closed_segment_free(rp, vp):
                continue
            d = _sub(rp, vp)
            s = walls.first_block(rp, d)
            if s == 0:  # the line does not go on into the open free space beyond r
                continue
            first = min(x for x in walls.events(rp, d) if x > 0)
            if walls.classify(_at(rp, d, first / 2)) != 1:  # beyond r it runs along a wall: nothing is shot
                continue
            where = walls.locate(_at(rp, d, s))
            if where is None:
                continue
            source = (r, None if v in (walls.prev[r], walls.next[r]) else v)
            found.setdefault(where, (_at(rp, d, s), set()))[1].add(source)
    return {key: (pt, frozenset(src)) for key, (pt, src) in found.items()}


def reference_segments(rings, inserted) -> list[tuple[int, Fraction, Fraction, Point, Point]]:
    """P′ as (edge, t0, t1, a, b) in boundary order, from the inserted (edge, t) keys."""
    walls = rings if isinstance(rings, Rings) else Rings(rings)
    out = []
    for e, (a, b) in enumerate(walls.edges):
        ts = [Fraction(0)] + sorted(t for edge, t in inserted if edge == e) + [Fraction(1)]
        pts = [_at(a, _sub(b, a), t) for t in ts]
        out.extend((e, ts[k], ts[k + 1], pts[k], pts[k + 1]) for k in range(len(ts) - 1))
    return out


# ---------------------------------------------------------------------------------------------
# Def. 5
# ---------------------------------------------------------------------------------------------
def _cells(ts: set[Fraction]) -> list[Fraction]:
    cuts = sorted({Fraction(0), Fraction(1)} | {t for t in ts if 0 < t < 1})
    return [(x + y) / 2 for x, y in zip(cuts, cuts[1:])]


def segments_see(walls: Rings, src: tuple[Point, Point], dst: tuple[Point, Point]) -> bool:
    """Whether some open segment between the open ``src`` and the open ``dst`` lies in the open free space."""
    (a, b), (c, d) = src, dst
    ab, cd = _sub(b, a), _sub(d, c)
    # necessary: each target has a point strictly on the free side of the other's line
    if max(_cross(ab, _sub(c, a)), _cross(ab, _sub(d, a))) <= 0:
        return False
    if max(_cross(cd, _sub(a, c)), _cross(cd, _sub(b, c))) <= 0:
        return False
    feats = set(walls.vertices) | {a, b, c, d}
    critical = set()
    for u, w in combinations(feats, 2):
        den = _cross(ab, _sub(w, u))
        if den != 0:
            critical.add(_cross(_sub(u, a), _sub(w, u)) / den)
    for lam in _cells(critical):
        p = _at(a, ab, lam)
        shadows = set()
        for u in feats:
            den = _cross(cd, _sub(u, p))
            if den != 0:
                shadows.add(_cross(_sub(p, c), _sub(u, p)) / den)
        for mu in _cells(shadows):
            if walls.open_segment_interior(p, _at(c, cd, mu)):
                return True
    return False


def reference_arcs(rings, segments) -> set[tuple[int, int]]:
    """Every ordered pair (i, j) of P′ segments (given as (a, b) pairs) whose open segments see each other."""
    walls = rings if isinstance(rings, Rings) else Rings(rings)
    arcs = set()
    for i, j in combinations(range(len(segments)), 2):
        if segments_see(walls, segments[i], segments[j]):
            arcs |= {(i, j), (j, i)}
    return arcs


# ---------------------------------------------------------------------------------------------
# Def. 7
# ---------------------------------------------------------------------------------------------
def heading_is_safe(rings, src: tuple[Point, Point], dst: tuple[Point, Point], u) -> bool:
    """Whether every point of the open ``src`` reaches the open ``dst`` along the exact direction ``u``."""
    walls = rings if isinstance(rings, Rings) else Rings(rings)
    (a, b), (c, d) = src, dst
    ab, cd = _sub(b, a), _sub(d, c)
    if _cross(ab, u) <= 0 or _cross(cd, u) >= 0:  # not into the room, or not into the target's wall
        return False
    den = _cross(ab, u)
    proj = {_cross(_sub(w, a), u) / den for w in set(walls.vertices) | {c, d}}
    samples = _cells(proj) + [t for t in proj if 0 < t < 1]
    for lam in samples:
        p = _at(a, ab, lam)
        s = walls.first_block(p, u)
        q = _at(p, u, s)
        if _cross(cd, _sub(q, c)) != 0:
            return False
        mu = _dot(_sub(q, c), cd) / _dot(cd, cd)
        if not 0 < mu < 1:
            return False
    return True


def rotate(u, eps: Fraction, *, clockwise: bool):
    """u turned by about eps radians (exact rational), clockwise or counter-clockwise."""
    if clockwise:
        return (u[0] + eps * u[1], u[1] - eps * u[0])
    return (u[0] - eps * u[1], u[1] + eps * u[0])


def frame_direction(src: tuple[Point, Point], tan_half: Fraction):
    """The exact direction of heading θ = 2·atan(tan_half) counter-clockwise from the source's direction."""
    a, b = src
    e = _sub(b, a)
    n = (-e[1], e[0])
    x, y = 1 - tan_half**2, 2 * tan_half
    return (x * e[0] + y * n[0], x * e[1] + y * n[1])
