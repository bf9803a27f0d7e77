"""Algorithm B: exploration with range-limited views, boundary by boundary (Bug1-like).

Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility", section "An Exploration
Algorithm with Range Restriction". The robot sees only RVP(z) = VP(z) ∩ disc(z, R)
(:func:`~solverplan.explore.range_view.range_visibility`). CP is the union of the views so far. The procedure:

* **Steps 2 and 6 (open space)** — while no wall is in sight the robot goes straight on (along
  :data:`HEADING`), each next viewpoint on the arc of the last view, until a wall comes in sight (Bug1 heads for
  the boundary); when every wall in sight is explored but CP does not cover P yet, the next viewpoint is taken
  on CP's frontier (its arcs and constructed edges), at the point farthest from every viewpoint so far, so views
  spread out like the grid of Lemma 4's proof.
* **Steps 3–5 (a boundary, hole by hole)** — as soon as part of a boundary ring (a hole or the outer ring) is in
  sight, the robot follows that ring: the next viewpoint is where the explored part of the ring ends going
  forward (free space on the left) — the start of a circular arc or a constructed edge of CP — and an edge is
  *marked* once it lies wholly in CP. The ring is done when all its edges are marked; then the next partially
  seen ring is taken, and so on.
* **Step 8** — stop when CP covers the free space: no uncovered region is left (Theorem 4).

Viewpoints ε inside the free space. The paper takes viewpoints "arbitrarily close to the boundary rather than on
the polygonal edges to avoid collision". Here a viewpoint for a boundary point s is s + ε·b (b the inward
bisector of the free angle at a vertex, the inward normal on an edge), with a clearance of at least ε/4 from
every wall, a rational point on a grid of ε/16, and exactly inside an earlier view (the chain). ε is
min(R, the polygon's minimum clearance)/100 unless given: small against R, so a view from there still sees about
R along the wall, and small against the narrowest passage, so the point exists on the free side of the wall.

Floats decide, exact arithmetic checks: the union CP and the uncovered region are shapely geometry (arcs as
chords within 10⁻⁷·R, inscribed, so CP is never over-estimated). An uncovered piece smaller than 10⁻⁹·min(R²,
Area) may be a chord sliver or float rounding; it is dismissed only when exact arithmetic agrees (no vertex of P
in it lies outside every view, and its representative point is outside the free space or inside a view), and
``found`` needs every vertex of P in some view, exactly — a needle 10⁻⁸ wide is never reported explored. When no
viewpoint can be placed to see what is left, the answer is ``not-found`` with the uncovered pieces (each with an
exact witness point in no view) and the unseen vertices listed; every viewpoint is checked exactly to lie in the earlier view it is
taken from (exact visibility polygon and exact |z − p|² ≤ R²) and every move is an exact straight line of sight.

When R is at least the largest distance between two vertices, every segment inside P is shorter than R (P lies
in the hull of its vertices), so RVP = VP and Algorithm A is used (Theorem 3).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Sequence

from solverplan.choices import ViewChoice
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import (ExactPoint, exact_point, format_number, format_point, orient, point_in_ring,
                              to_fraction)
from solverplan.explore.bounds import range_ratio_bound, range_views_bound, range_views_lower_bound
from solverplan.explore.depth_first import ViewpointRun, explore_depth_first
from solverplan.explore.range_view import DEFAULT_SAGITTA, RangeView, check_range, range_visibility
from solverplan.geometry.visibility import sees
from solverplan.geometry.walls import StraightWalls
from solverplan.result import EnvironmentRecord, Method, Optimality, Stats, Status, answer_dataclass
from typing import Any

__all__ = ["RangeExploration", "UncoveredPiece", "explore_range_limited", "covers_every_segment", "range_covered_fraction"]

HEADING = (1.0, 0.0)
"""The direction the robot keeps while no wall is in sight (Step 2): any fixed one will do."""

MAX_VIEWS = 1000
"""The default cap on the views of one run (about a minute of CPU): a range tiny against the polygon answers
``not-found`` instead of running for hours; ``max_views`` lifts it."""

PHASES = ("start", "open", "boundary", "frontier")
"""Why each viewpoint was taken: ``start`` p₁; ``open`` on an arc with no unexplored wall in sight (Steps 2, 6);
``boundary`` following a ring (Steps 3–5); ``frontier`` any other part of CP's frontier (constructed edges)."""


@dataclass(frozen=True)
class UncoveredPiece:
    """A piece of the free space no view covers: its outline (floats, length units), area, and a point of it in
    no view and in the free space (exact; ``None`` when the piece is thinner than floats can sample)."""

    polygon: tuple[tuple[float, float], ...]
    area: float
    witness: ExactPoint | None

    def to_json(self) -> dict:
        return {"polygon": [list(p) for p in self.polygon], "area": self.area,
                "witness": None if self.witness is None else [float(c) for c in self.witness],
                "witness_exact": None if self.witness is None else [format_number(c) for c in self.witness]}


@answer_dataclass("range-exploration", kw_only=True)
class RangeExploration(ViewpointRun):
    """An exploration with range-limited views (Algorithm B, or Algorithm A when Theorem 3 applies).

    Attributes
    ----------
    status
        ``found`` when the views cover the free space; ``not-found`` when the view limit was hit first.
    viewpoints, parents, path
        As in :class:`~solverplan.explore.depth_first.Exploration`: exact viewpoints in visiting order, the
        index of the earlier view each lies in (−1 for p₁), and the robot's straight legs.
    views
        RVP of every viewpoint, arcs explicit.
    phases
        For each viewpoint, why it was taken (:data:`PHASES`).
    rings
        For each viewpoint, the boundary ring it was placed on (0 the outer ring, k the k-th hole), or −1.
    reflex, holes
        r and h of the free space.
    bound
        Lemma 4: ⌊8·Area/(3R²)⌋ + ⌊Perimeter/R⌋ + r + h + 1.
    lower_bound
        Theorem 5's premise ⌈Area/(πR²)⌉: no exploration takes fewer views.
    ratio_bound
        Theorem 5: 8π/3 + πR·Perimeter/Area + (r + h + 1)·πR²/Area.
    covered_fraction
        Area of the union of the (inscribed) views over the free space's area (floats).
    range, epsilon
        R and ε (length units).
    uncovered
        With ``not-found``: the pieces of the free space the views do not cover (floats, each with an exact
        witness point in no view when one was found); empty with ``found``.
    unseen_vertices
        Vertices of P in no view (exact test); empty with ``found``.
    algorithm
        ``"B"``, or ``"A"`` when R reaches across P (Theorem 3).

    Examples
    --------
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> run = sp.explore_range_limited(env, (8, 2), 3)           # views reach 3 units
    >>> run.algorithm, run.status.value, run.n_views, (run.lower_bound, run.bound), run.covered_fraction
    ('B', 'found', 10, (3, 33), 1.0)
    >>> sp.explore_range_limited(env, (8, 2), 20).algorithm      # R reaches across the room: Theorem 3
    'A'
    """

    views: tuple[RangeView, ...]
    phases: tuple[str, ...]
    rings: tuple[int, ...]
    holes: int
    lower_bound: int
    ratio_bound: float
    range: Fraction
    epsilon: Fraction
    algorithm: str = "B"
    choice: str = "first"
    uncovered: tuple[UncoveredPiece, ...] = ()
    unseen_vertices: tuple[int, ...] = ()

    @property
    def ratio(self) -> float:
        """Views over Theorem 5's lower bound: an upper estimate of the competitive ratio on this instance."""
        return self.n_views / self.lower_bound

    def _fields(self) -> dict:
        """The exploration answer of ``docs/contract.md`` with the range fields."""
        out = self._answer_json()
        out.update({
            "range": float(self.range),
            "holes": self.holes,
            "lower_bound": self.lower_bound,
            "ratio": self.ratio,
            "ratio_bound": self.ratio_bound,
            "epsilon": float(self.epsilon),
            "phases": list(self.phases),
            "arcs": [[a.to_json() for a in v.arcs] for v in self.views],
            "rings": list(self.rings),
            "range_exact": format_number(self.range),
            "epsilon_exact": format_number(self.epsilon),
            "uncovered": [piece.to_json() for piece in self.uncovered],
            "unseen_vertices": list(self.unseen_vertices),
        })
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> RangeExploration:
        """Read a range-limited exploration back in ``env`` (required): the exact viewpoints, path, R and ε; the views
        recomputed exactly (RVP of each viewpoint)."""
        r, env, fields = cls._read_run(data, env)
        R = r.exact("range_exact")
        views = tuple(range_visibility(env, p, R) for p in fields["viewpoints"])
        uncovered = []
        for piece in (r.items("uncovered") if r.has("uncovered") else []):
            outline = [piece.at("polygon", q) for q in piece.array("polygon")]
            witness = piece.exact_pair("witness_exact") if piece.has("witness_exact") else None
            uncovered.append(UncoveredPiece(tuple((q.number(0), q.number(1)) for q in outline), piece.number("area"),
                                            witness))
        unseen = tuple(r.ints("unseen_vertices")) if r.has("unseen_vertices") else ()
        return cls(views=views, phases=tuple(r.texts("phases")), rings=tuple(r.ints("rings")), holes=r.integer("holes"),
                   lower_bound=r.integer("lower_bound"), ratio_bound=r.number("ratio_bound"), range=R,
                   epsilon=r.exact("epsilon_exact"), uncovered=tuple(uncovered), unseen_vertices=unseen, **fields)

    def to_text(self, *, width: int = 100) -> str:
        return self._text(f"exploration (Algorithm {self.algorithm}, range R = {float(self.range):.6g}): "
                          f"{self.status.value}",
                          f"views {self.n_views} (Lemma 4 bound {self.bound}, Theorem 5 lower bound "
                          f"{self.lower_bound}, ratio {self.ratio:.3g} <= {self.ratio_bound:.3g}), r = {self.reflex}, "
                          f"h = {self.holes}",
                          lambda k: "" if self.parents[k] < 0 else
                          f"  (in the view of p{self.parents[k] + 1}, {self.phases[k]})", width)


def _in_free_space(env: Environment, q: ExactPoint) -> bool:
    """Is the exact point q in the closed free space (inside or on the outer ring, not strictly inside a hole)?"""
    return point_in_ring(q, env.outer) >= 0 and all(point_in_ring(q, hole) <= 0 for hole in env.holes)


def covers_every_segment(env: Environment, range_: object) -> bool:
    """Is R at least the largest distance between two vertices (exact)? Then every segment inside P is at most
    R long (P lies in the convex hull of its vertices, whose diameter is attained at vertices) and RVP = VP."""
    R = check_range(range_)
    verts = env.exact_vertices
    R2 = R * R
    return all((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 <= R2 for i, p in enumerate(verts) for q in verts[i + 1:])


def range_covered_fraction(env: Environment, views: Sequence[RangeView], sagitta: float = DEFAULT_SAGITTA,
                           shapes: Sequence | None = None) -> float:
    """Area of the union of the inscribed views over the free space's area (floats, shapely): a lower estimate,
    within a relative 2·sagitta of the true union's. ``shapes``: the views' polygons, when already made."""
    import shapely

    free = env.to_shapely()
    union = shapely.union_all(shapes if shapes is not None else [v.to_shapely(sagitta) for v in views])
    return float(union.intersection(free).area / free.area)


def _default_epsilon(env: Environment, R: Fraction) -> Fraction:
    import shapely

    clearance = float(shapely.minimum_clearance(env.to_shapely()))
    raw = min(float(R), clearance if math.isfinite(clearance) and clearance > 0 else float(R)) / 100
    return Fraction(f"{raw:.2g}")


class _Explorer:
    """The state of one run of Algorithm B (floats decide, exact checks)."""

    def __init__(self, env: Environment, R: Fraction, eps: Fraction, limit: int):
        import shapely

        self.env, self.R, self.eps, self.limit = env, R, eps, limit
        self.free = env.to_shapely()
        self.walls = self.free.boundary
        xmin, ymin, xmax, ymax = env.bounds
        self.scale = max(xmax - xmin, ymax - ymin, float(R))
        self.tol = 1e-9 * self.scale
        self.area_tol = 1e-9 * min(float(R) ** 2, self.free.area)
        self.grid = eps / 16
        self.views: list[RangeView] = []
        self.shapes: list = []
        self._covered = shapely.Polygon()
        self._covered_views = 0  # how many views the cached union holds
        self.viewpoints: list[ExactPoint] = []
        self.parents: list[int] = []
        self.phases: list[str] = []
        self.rings: list[int] = []
        self.path: list[ExactPoint] = []
        self.blocked: set[tuple[float, float]] = set()
        # ring structure: for each ring its global edge ids in order
        offsets = env.ring_offsets
        self.ring_edges = [list(range(offsets[k], offsets[k + 1])) for k in range(len(env.rings))]
        self.edge_ring = {e: k for k, es in enumerate(self.ring_edges) for e in es}
        verts, nxt = env.exact_vertices, env.next_vertex
        self.edge_lines = [shapely.LineString([tuple(map(float, verts[e])), tuple(map(float, verts[int(nxt[e])]))])
                           for e in range(env.n_edges)]
        self.edge_left = list(self.edge_lines)  # the part of each edge not yet in CP (shapely lines)
        self._unseen: list[int] = []
        self._unseen_at = -1  # how many views the list of unseen vertices was computed with (-1: never)

    # ------------------------------------------------------------------ views
    def add_view(self, z: ExactPoint, parent: int, phase: str, ring: int) -> None:
        import shapely

        rv = range_visibility(self.env, z, self.R)
        shape = rv.to_shapely()
        self.views.append(rv)
        self.shapes.append(shape)
        self.gained = self._gain(shape, z)
        grown = shape.buffer(10 * self.tol, quad_segs=1)
        for e, left in enumerate(self.edge_left):
            if not left.is_empty and grown.intersects(left):
                self.edge_left[e] = left.difference(grown)
        if self.path:
            self.path.extend(self._route(self.path[-1], z, parent))
        self.path.append(z)
        self.viewpoints.append(z)
        self.parents.append(parent)
        self.phases.append(phase)
        self.rings.append(ring)

    def _route(self, here: ExactPoint, z: ExactPoint, parent: int) -> list[ExactPoint]:
        """Intermediate positions from ``here`` to ``z``: straight if ``here`` sees z, else through the chain
        tree (up from here to the common ancestor with z's parent, down to it): every leg was a forward move."""
        if sees(self.env, here, z):
            return []
        k_here = self.viewpoints.index(here)
        k_to = parent
        up = [k_here]
        while self.parents[up[-1]] >= 0:
            up.append(self.parents[up[-1]])
        down = [k_to]
        while down[-1] not in up:
            down.append(self.parents[down[-1]])
        meet = down[-1]
        legs = up[1:up.index(meet) + 1] + down[::-1][1:]
        return [self.viewpoints[k] for k in legs]

    @property
    def covered(self):
        """CP, the union of the views' shapes (computed when asked: most steps need only the new view)."""
        import shapely

        if self._covered_views < len(self.shapes):
            self._covered = shapely.union_all([self._covered, *self.shapes[self._covered_views:]])
            self._covered_views = len(self.shapes)
        return self._covered

    def _gain(self, shape, z: ExactPoint) -> float:
        """The area the new view (``shape``, last in ``shapes``, from z) adds to CP: its difference with the
        earlier views whose viewpoints lie within 2R of z (no other view can overlap it)."""
        import numpy as np
        import shapely

        if not self.viewpoints:
            return float(shape.area)
        centres = np.array([[float(x), float(y)] for x, y in self.viewpoints])
        d = np.hypot(centres[:, 0] - float(z[0]), centres[:, 1] - float(z[1]))
        near = np.flatnonzero(d <= 2 * float(self.R) * (1 + 1e-9)).tolist()
        if not near:
            return float(shape.area)
        return float(shape.difference(shapely.union_all([self.shapes[k] for k in near])).area)

    # ------------------------------------------------------------------ what is left
    def uncovered(self) -> list:
        """The pieces of P − CP that are not proved to be float artefacts.

        A piece above the area tolerance is kept. A smaller one (a chord sliver between an arc and its chords, or
        float rounding along a wall) is dismissed only when exact arithmetic agrees: no vertex of P in it or on its
        boundary is outside every view, and its representative point is outside the free space or inside some
        view (both exact). A needle 10⁻⁸ wide has a tip no view holds: it stays, however small its area.
        """
        rest = self.free.difference(self.covered)
        pieces = [g for g in getattr(rest, "geoms", [rest]) if g.geom_type == "Polygon" and not g.is_empty]
        unseen = self.unseen_vertices()
        out = []
        for g in pieces:
            if g.area > self.area_tol or self._holds_unseen(g, unseen) or not self._witness_seen(g):
                out.append(g)
        return out

    def uncovered_pieces(self) -> tuple[UncoveredPiece, ...]:
        """:meth:`uncovered` as records, each with an exact witness point when its representative point is one."""
        out = []
        for g in self.uncovered():
            c = g.representative_point()
            q: ExactPoint = (Fraction(c.x), Fraction(c.y))
            witness = None if not _in_free_space(self.env, q) or self._seen_exactly(q) else q
            out.append(UncoveredPiece(tuple((float(x), float(y)) for x, y in g.exterior.coords[:-1]), float(g.area),
                                      witness))
        return tuple(out)

    def _seen_exactly(self, q: ExactPoint) -> bool:
        """Is the exact point q in the closed RVP of some view (a float prefilter on the distance, then exact)?"""
        R = float(self.R)
        for view in self.views:
            z = view.viewpoint
            if math.hypot(float(q[0] - z[0]), float(q[1] - z[1])) <= R * (1 + 1e-9) + 1e-12 and view.contains(q):
                return True
        return False

    def unseen_vertices(self) -> list[int]:
        """The vertices of P in no view, decided exactly (cached per number of views: views only grow)."""
        if self._unseen_at != len(self.views):
            candidates = self._unseen if self._unseen_at >= 0 else range(self.env.n_vertices)
            verts = self.env.exact_vertices
            self._unseen = [v for v in candidates if not self._seen_exactly(verts[v])]
            self._unseen_at = len(self.views)
        return list(self._unseen)

    def _holds_unseen(self, piece, unseen: Sequence[int]) -> bool:
        import shapely

        verts = self.env.vertices
        return any(piece.distance(shapely.Point(verts[v])) <= 10 * self.tol for v in unseen)

    def _witness_seen(self, piece) -> bool:
        """Exact test of a small piece's representative point: True when it is outside the free space or in a
        view (the piece is an artefact of the floats), False when it is a free point no view holds."""
        c = piece.representative_point()
        q = (Fraction(c.x), Fraction(c.y))
        if not _in_free_space(self.env, q):
            return True
        return self._seen_exactly(q)

    def unseen_runs(self) -> dict[int, list[tuple[int, float, float]]]:
        """For each ring, its unseen intervals (edge, t0, t1) in ring order; an edge with none is marked."""
        import shapely

        out: dict[int, list[tuple[int, float, float]]] = {}
        for k, edges in enumerate(self.ring_edges):
            runs = []
            for e in edges:
                line, left = self.edge_lines[e], self.edge_left[e]
                L = line.length
                for g in getattr(left, "geoms", [left]):
                    if g.is_empty or g.length <= 10 * self.tol:
                        continue
                    ts = sorted(line.project(shapely.Point(c)) / L for c in g.coords)
                    runs.append((e, ts[0], ts[-1]))
            out[k] = sorted(runs, key=lambda r: (edges.index(r[0]), r[1]))
        return out

    def ring_seen(self, k: int) -> bool:
        """Is some part of ring k in CP?"""
        return any(self.edge_left[e].length < self.edge_lines[e].length - 10 * self.tol for e in self.ring_edges[k])

    # ------------------------------------------------------------------ placing a viewpoint
    def _inward(self, edge: int, t: float) -> list[tuple[float, float]]:
        """Directions into the free space at the boundary point (edge, t), best first: at a vertex (within ε/4
        of it: the chords of CP end a little short of corners) the free angle's bisector, then the two edges'
        inward normals; on an edge its inward (left) normal."""
        env = self.env
        verts, nxt, prv = env.exact_vertices, env.next_vertex, env.prev_vertex
        a, b = verts[edge], verts[int(nxt[edge])]
        L = math.dist(tuple(map(float, a)), tuple(map(float, b)))
        snap = float(self.eps) / 4
        v = edge if t * L <= snap else (int(nxt[edge]) if (1 - t) * L <= snap else None)
        if v is None:
            return [(-float(b[1] - a[1]) / L, float(b[0] - a[0]) / L)]
        p, x, n = verts[int(prv[v])], verts[v], verts[int(nxt[v])]

        def unit(d: tuple[float, float]) -> tuple[float, float]:
            norm = math.hypot(*d)
            return d[0] / norm, d[1] / norm

        u1 = unit((float(p[0] - x[0]), float(p[1] - x[1])))
        u2 = unit((float(n[0] - x[0]), float(n[1] - x[1])))
        normals = [(-u2[1], u2[0]), (u1[1], -u1[0])]  # left normals of the edge out of v and the edge into v
        turn = orient(p, x, n)
        if turn == 0:
            return normals[:1]
        s = 1.0 if turn > 0 else -1.0  # convex: the bisector u1 + u2 points into the free angle; reflex: away
        return [unit((s * (u1[0] + u2[0]), s * (u1[1] + u2[1]))), *normals]

    def _grid_point(self, x: float, y: float) -> ExactPoint:
        g = self.grid
        return (round(Fraction(x) / g) * g, round(Fraction(y) / g) * g)

    def _clear(self, z: ExactPoint) -> bool:
        import shapely

        q = shapely.Point(float(z[0]), float(z[1]))
        return self.free.contains(q) and self.walls.distance(q) >= float(self.eps) / 4

    def _parents_of(self, s: tuple[float, float]) -> list[int]:
        import shapely

        import numpy as np

        q = shapely.Point(s)
        centres = np.array([[float(x), float(y)] for x, y in self.viewpoints])
        reach = np.flatnonzero(np.hypot(centres[:, 0] - s[0], centres[:, 1] - s[1]) <= float(self.R) + 1e-6 * self.scale)
        # s may lie up to the marking buffer (10·tol) outside the view it was seen from: 1e-6·scale covers that
        near = [k for k in reach.tolist() if self.shapes[k].distance(q) <= 1e-6 * self.scale]
        return near[::-1]  # the most recent view first: shorter moves

    def place(self, s: tuple[float, float], directions: Sequence[tuple[float, float]]) -> tuple[ExactPoint, int] | None:
        """A viewpoint near the point s of CP's boundary: ε inside the free space along one of ``directions`` (or
        pulled back towards the view that sees s), exactly inside an earlier view. ``None`` if none passes."""
        eps = float(self.eps)
        for j in self._parents_of(s):
            pj = tuple(map(float, self.viewpoints[j]))
            candidates: list[tuple[float, float]] = []
            for direction in directions:
                for k in (1, 2, 4, 8):
                    c = (s[0] + k * eps * direction[0], s[1] + k * eps * direction[1])
                    candidates.append(c)
                    # the same, pulled back towards p_j when the range would be exceeded
                    d = math.dist(c, pj)
                    if d > 0:
                        back = min(1.0, 4 * k * eps / d)
                        candidates.append((c[0] + back * (pj[0] - c[0]), c[1] + back * (pj[1] - c[1])))
            d = math.dist(s, pj)
            for k in (1, 2, 4, 8, 16, 64):
                lam = max(0.0, 1 - k * eps / d) if d > 0 else 0.0
                candidates.append((pj[0] + lam * (s[0] - pj[0]), pj[1] + lam * (s[1] - pj[1])))
            for c in candidates:
                z = self._grid_point(*c)
                if z in self.viewpoints or not self._clear(z):
                    continue
                if self.views[j].contains(z):
                    return z, j
        return None

    # ------------------------------------------------------------------ the next target
    def next_viewpoint(self, state: dict) -> tuple[ExactPoint, int, str, int, tuple[float, float]] | None:
        """Steps 3–5 first (the ring being followed, then any partially seen ring), else Steps 2/6 (an arc)."""
        import shapely

        runs = self.unseen_runs()
        env = self.env
        verts, nxt = env.exact_vertices, env.next_vertex
        here = tuple(map(float, self.path[-1]))

        def point_of(e: int, t: float) -> tuple[float, float]:
            a, b = verts[e], verts[int(nxt[e])]
            return (float(a[0]) + t * float(b[0] - a[0]), float(a[1]) + t * float(b[1] - a[1]))

        def run_starts(k: int) -> list[tuple[int, float]]:
            """Starts of the unseen runs of ring k (edge, t): unseen intervals not continuing an unseen one."""
            rs = runs[k]
            edges = self.ring_edges[k]
            starts = []
            for i, (e, t0, _) in enumerate(rs):
                pe, _, p1 = rs[i - 1]  # the interval before, cyclically
                prev_edge = edges[(edges.index(e) - 1) % len(edges)]
                continues = (len(rs) > 1 or len(edges) == 1) and (
                    (t0 <= 1e-9 and pe == prev_edge and p1 >= 1 - 1e-9) or (pe == e and abs(p1 - t0) < 1e-9))
                if not continues:
                    starts.append((e, t0))
            return starts

        order: list[int] = []
        if state.get("ring") is not None and runs[state["ring"]]:
            order.append(state["ring"])
        others = [k for k in runs if runs[k] and k not in order and self.ring_seen(k)]
        others.sort(key=lambda k: min(math.dist(point_of(e, t), here) for e, t, _ in runs[k]))
        order += others
        for k in order:
            starts = [st for st in run_starts(k) if point_of(*st) not in self.blocked]
            if not starts:
                continue
            if k == state.get("ring") and state.get("position") is not None:
                edges = self.ring_edges[k]
                total = len(edges)
                pos = state["position"]
                starts.sort(key=lambda st: ((edges.index(st[0]) + st[1]) - pos) % total)
            else:
                starts.sort(key=lambda st: math.dist(point_of(*st), here))
            for e, t in starts:
                s = point_of(e, t)
                placed = self.place(s, self._inward(e, t))
                if placed is None:
                    self.blocked.add(s)
                    continue
                state["ring"], state["position"] = k, self.ring_edges[k].index(e) + t
                return placed[0], placed[1], "boundary", k, s
        state["ring"] = state["position"] = None
        import numpy as np

        if not any(self.ring_seen(k) for k in runs):
            # Step 2, no wall in sight yet: straight on (Bug1 heads for the boundary), along the heading HEADING,
            # from the arc of the last view that reaches farthest that way
            last = self.views[-1]
            ring = np.array(last.boundary_points(1e-4))
            found = self._first_placed(ring, -(ring @ np.array(HEADING)), 16, "open")
            if found is not None:
                return found
        # Steps 2 and 6: a point of CP's frontier (arcs, constructed edges) farthest from every viewpoint
        pieces = self.uncovered()
        if not pieces:
            return None

        frontier = shapely.union_all([g.boundary for g in pieces]).difference(self.walls.buffer(10 * self.tol))
        coords = shapely.get_coordinates(frontier)  # (every part's, in order: vectorised, not point by point)
        if not len(coords):
            coords = shapely.get_coordinates([g.exterior for g in pieces])
        if len(coords) > 2000:  # the chords of the arcs are dense: an even subsample is enough to aim at
            coords = coords[np.linspace(0, len(coords) - 1, 2000).astype(int)]
        seen_from = np.array([[float(x), float(y)] for x, y in self.viewpoints])
        spread = np.min(np.linalg.norm(coords[:, None, :] - seen_from[None, :, :], axis=2), axis=1)
        arc_phase = "open" if all(not runs[k] for k in runs if self.ring_seen(k)) else "frontier"
        return self._first_placed(coords, -spread, 64, arc_phase)

    def _first_placed(self, coords: Any, rank: Any, tries: int, phase: str) -> Any:
        """The first of the ``tries`` best-ranked points (lowest ``rank``) not blocked where a viewpoint can be placed:
        (viewpoint, view, phase, -1, aim), or ``None``; the points that fail are blocked."""
        import numpy as np

        for i in np.argsort(rank, kind="stable")[:tries].tolist():
            s = (float(coords[i][0]), float(coords[i][1]))
            if s in self.blocked:
                continue
            placed = self.place(s, ())
            if placed is not None:
                return placed[0], placed[1], phase, -1, s
            self.blocked.add(s)
        return None


def explore_range_limited(env: Environment, start: Sequence[object], range_: object, *,
                          epsilon: object | None = None, max_views: int | None = None, choice: str = "first",
                          seed: int | None = None) -> RangeExploration:
    """Explore ``env`` from ``start`` with views of range R (Algorithm B; Algorithm A when Theorem 3 applies).

    Parameters
    ----------
    env
        The free space (outer ring and holes).
    start
        p₁, a point of the closed free space (length units).
    range_
        R > 0, the sensing range (length units), read exactly.
    epsilon
        ε > 0, how far inside the free space boundary viewpoints sit (length units); default min(R, minimum
        clearance of P)/100, rounded to two significant digits.
    max_views
        Stop after this many views (default 2·(Lemma 4's bound) + 10, at most :data:`MAX_VIEWS`); hitting it
        gives ``not-found``. With the default, a range so small that Area/(πR²) views exceed the cap answers
        ``not-found`` after the first view.
    choice, seed
        Algorithm A's z-choice rule and its seed, used when Theorem 3 hands over to Algorithm A (Algorithm B
        itself has no choice to make).

    Returns
    -------
    RangeExploration
        Status ``found`` when CP covers the free space (Theorem 4), with the views and the bounds.

    Raises
    ------
    InputError
        If ``start`` is not in the free space, or R, ε or ``max_views`` is out of range.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [8, 0], [8, 8], [0, 8]])
    >>> run = explore_range_limited(square, (4, 4), 3)
    >>> run.algorithm, run.status.value, run.lower_bound <= run.n_views <= run.bound, run.covered_fraction > 1 - 1e-6
    ('B', 'found', True, True)
    """
    R = check_range(range_)
    walls = StraightWalls(env)
    if not walls.identity:  # the canonical walls, as for Algorithm A (explore.depth_first)
        canonical = explore_range_limited(walls.merged, start, R, epsilon=epsilon, max_views=max_views, choice=choice,
                                          seed=seed)
        return replace(canonical, environment=EnvironmentRecord.of(env),
                       unseen_vertices=tuple(sorted(walls.user_vertex(v) for v in canonical.unseen_vertices)),
                       stats=canonical.stats.with_(collinear_vertices_merged=walls.n_merged_vertices))
    bound = range_views_bound(env, float(R))
    lower = range_views_lower_bound(env, float(R))
    ratio_bound = range_ratio_bound(env, float(R))
    limit = min(2 * bound + 10, MAX_VIEWS) if max_views is None else max_views
    if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
        raise InputError(f"max_views must be >= 1, got {max_views}")
    p = exact_point(start, where="start")
    t0 = time.perf_counter()
    if covers_every_segment(env, R):  # Theorem 3: every view is a whole visibility polygon
        run = explore_depth_first(env, p, max_views=limit, choice=choice, seed=seed)
        views = tuple(range_visibility(env, q, R) for q in run.viewpoints)
        eps = Fraction(0) if epsilon is None else to_fraction(epsilon, where="epsilon")
        optimality = Optimality(Method.NONE, False, None, scope="chained viewpoint sets covering the free space",
                                algorithm="Algorithm A (Theorem 3: R reaches across P, RVP = VP)",
                                limits=run.optimality.limits)
        return RangeExploration(status=run.status, viewpoints=run.viewpoints, views=views, parents=run.parents,
                                path=run.path, phases=("start",) + ("frontier",) * (run.n_views - 1),
                                rings=(-1,) * run.n_views, reflex=run.reflex, holes=len(env.holes), bound=bound,
                                lower_bound=lower, ratio_bound=ratio_bound, covered_fraction=run.covered_fraction,
                                range=R, epsilon=eps, optimality=optimality,
                                stats=Stats(seconds_search=time.perf_counter() - t0, counts=dict(run.stats.counts)),
                                environment=EnvironmentRecord.of(env), algorithm="A", choice=run.choice)
    choice = ViewChoice.parse(choice, "z-choice rule").value
    if seed is not None and choice != "random":
        raise InputError(f"--seed only applies to the random z-choice rule, not to {choice!r}")
    eps = _default_epsilon(env, R) if epsilon is None else to_fraction(epsilon, where="epsilon")
    if eps <= 0:
        raise InputError(f"epsilon must be > 0, got {epsilon!r}")
    try:
        range_visibility(env, p, R)
    except InputError:
        raise InputError(f"start {format_point(p)} is not in the free space of {env.name or 'the environment'}") from None
    ex = _Explorer(env, R, eps, limit)
    ex.add_view(p, -1, "start", -1)
    state: dict = {"ring": None, "position": None}
    # Theorem 5's premise: every exploration takes at least Area/(πR²) views; past the default cap, do not run
    # towards it (minutes of views for a range tiny against the room); a max_views asked for is run to
    hopeless = max_views is None and lower > limit
    hit_limit = hopeless
    stuck = False
    while not hit_limit:
        nxt = ex.next_viewpoint(state)  # None when nothing is left to aim at: CP covers P, or no viewpoint fits
        if nxt is None:
            # Step 8's test, exact where it matters: a piece left over (however thin) or a vertex in no view
            stuck = bool(ex.uncovered()) or bool(ex.unseen_vertices())
            break
        if len(ex.viewpoints) >= limit:
            hit_limit = True
            break
        z, parent, phase, ring, target = nxt
        ex.add_view(z, parent, phase, ring)
        if ex.gained <= ex.area_tol:  # the view added nothing: never aim there again
            ex.blocked.add(target)
    seconds = time.perf_counter() - t0
    found = not hit_limit and not stuck
    limits = ((f"max_views={limit}" + (f" (at least Area/(πR²) = {lower} views are needed)" if hopeless else ""),)
              if hit_limit else (("no admissible viewpoint",) if stuck else ()))
    optimality = Optimality(Method.NONE, False, None, scope="chained viewpoint sets covering the free space",
                            algorithm="Algorithm B (range-limited views, boundary by boundary)", limits=limits)
    covered = range_covered_fraction(env, ex.views, shapes=ex.shapes)
    left = () if found else ex.uncovered_pieces()
    unseen = () if found else tuple(ex.unseen_vertices())
    if stuck:
        limits = (f"no admissible viewpoint: {len(left)} uncovered piece(s), {len(unseen)} vertex(es) in no view",)
        optimality = Optimality(Method.NONE, False, None, scope="chained viewpoint sets covering the free space",
                                algorithm="Algorithm B (range-limited views, boundary by boundary)", limits=limits)
    return RangeExploration(status=Status.FOUND if found else Status.NOT_FOUND, viewpoints=tuple(ex.viewpoints),
                            views=tuple(ex.views), parents=tuple(ex.parents), path=tuple(ex.path),
                            phases=tuple(ex.phases), rings=tuple(ex.rings), reflex=len(env.reflex_vertices),
                            holes=len(env.holes), bound=bound, lower_bound=lower, ratio_bound=ratio_bound,
                            covered_fraction=covered, range=R, epsilon=eps, optimality=optimality,
                            stats=Stats(seconds_search=seconds, counts={"blocked_targets": len(ex.blocked)}),
                            environment=EnvironmentRecord.of(env), uncovered=left, unseen_vertices=unseen)
