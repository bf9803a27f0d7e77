"""Exact belief-state successors over a segment table: the engine behind negative certificates and bounds.

A *bound* (``Certificate.bound``, schema version 3) proves that **no plan exists** — within a budget of K
stages, with every stage's heading interval wider than a threshold w and inside [δ, π − δ] — by an inductive
invariant over belief states (sets of segments of a *segment table*, a partition of the boundary into straight
pieces). This module decides, in exact integer arithmetic, the successor relation the invariant must be
closed under; :mod:`solverplan.certify.check` checks the invariant with it, and the planner-side builder
(:mod:`solverplan.certify.negative`) uses the same engine to compute the closure it certifies.

Like the rest of the checker it imports only the standard library and its sibling modules (no floats).

The semantics
-------------
A stage from belief B executes one closed heading interval J (radians, counter-clockwise from the wall the
robot is on) of width > w inside [δ, π − δ], such that from **every** segment s ∈ B, every point of open s
with every heading of J first meets the boundary inside one *group* (the table's groups: segments of P′ cut at
the query's set ends into pieces, the table's segments; a segment in no group is a group of its own); its
*landing unit* U_s is the shortest run of consecutive segments of that group that holds every landing of open s
over J, and the next belief is every segment of every U_s. A stage is a *goal stage* when every segment of the
next belief is a goal segment.

The planner lands on one piece or anywhere on the whole segment (its landing units): its unit holds every
landing, so it holds U_s, and its next belief holds this one. A plan from a belief works from every smaller
belief (:mod:`solverplan.proofs.piece_monotonicity`), so every plan of the planner is matched, stage by stage,
by a plan of this class whose beliefs are no larger: the class holds the planner's plans, and a goal reached
inside the goal set across a cut of the start set (a run of goal segments) is a goal stage.

One source, one direction
-------------------------
For a source segment s = (a, b), E = b − a, and a direction d with cross(E, d) > 0, every point of open s
lands inside the closed segment t = (c, e), T = e − c (or the closed span (c, e) of t's group), iff

- d enters t from its free side, cross(T, d) < 0, and the corner rays from a and b meet the line of t at
  parameters μ ≥ 0 (along d) inside the closed segment t (τ ∈ [0, 1]);
- the open region R° = {x : cross(E, x − a) > 0, cross(x − a, d) > 0, cross(d, x − b) > 0, cross(T, x − c) > 0}
  — the points strictly between s and t swept by the rays from open s — holds no boundary point: no edge of
  the environment meets it (each edge against four strict linear inequalities, exactly).

The condition is exact at every direction (no grazing exceptions): a ray from x ∈ open s runs through R°
until it meets the line of t, and every point of R° lies on such a ray. (Necessity: the corner conditions are
the limits of the landing points of positions next to a and b, which land on closed t; a boundary point in R°
lies on the path of some position's ray before it reaches t.) The landings of open s at d meet exactly the
segments of the group between the joints that lie strictly between the two corner rays (the open image holds
those joints): the cell's unit, a run of the group's segments around t.

Cells
-----
As the direction turns, the landing segment and the condition above can change only at *event directions*:
from a or b towards a vertex of the environment or an end of a table segment (the swept region's structure
changes only when one of its corner rays passes such a point). Between consecutive events (an open *cell*)
the condition, and which of a group's segments the image meets, is therefore constant; it is decided at one rational direction strictly inside the cell (the
sum of the two neighbouring event directions, in heading-vector form): its landing segment is found by an
exact ray cast from the middle of s, then the condition is tested. Consecutive cells with the same target
are merged into one closed *run* (which over-approximates the safe set at the event directions between
them: a larger successor relation only makes the invariant harder to satisfy, never unsound).

Successors
----------
The sources' runs are intersected into *common cells* (each: one unit per source). A stage interval J of the
class meets, with its interior, a stretch of contiguous common cells in which each source's units lie in one
group; J lies in the stretch's closed span, and each source's unit over J holds every unit of the stretch, so
holds their *hull* (the shortest run of the group holding them). The successors listed are therefore, for every
start cell i of a stretch, the shortest admissible stretch [i, j] (its width inside [δ, π − δ] exceeds w; the
shortest from i, as the hulls only grow with the stretch), with the hulls as units, widened on both sides to every
contiguous cell whose units lie in those hulls (same next belief, a wider interval: the planner side reports the
widths of the plans it finds). Every stage J of the class, starting in cell i, is matched by the successor from i:
its next belief is no larger, and a next belief inside the goal or holding a listed belief stays so when it
grows — the invariant's check over these successors covers the whole class. No combination of overlapping runs
is enumerated: their number stays one per common cell.

Arithmetic: integers only. The vertices sit on one integer grid (the lcm of their own denominators); segment
ends are homogeneous integer triples (X, Y, W); every test of the vertices against a line (the ray cast's sides
and positions, the four inequalities of R°, the event directions' heading vectors) is a linear functional with
integer coefficients, a positive multiple of the exact one, and a segment end's value is interpolated from its
edge's two vertices (t = n/d: ((d − n)·f(start) + n·f(end)) / d). The corner-ray conditions are sign tests.

Headings are compared across different source edges without angles: a heading θ of direction d from edge E
is the angle of the *heading vector* (E·d, E×d) (upper half-plane), and angle(h₁) < angle(h₂) iff
cross(h₁, h₂) > 0. Only the comparisons with δ and w need arctangents (:mod:`.rational_atan`, rigorous).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.certify.exact2d import union
from solverplan.certify.rational_atan import Undecided, compare_angle
from solverplan.certify.schema import Point

__all__ = ["Geometry", "TableError", "Closure", "Run", "next_belief"]

IPoint = tuple[int, int]
HPoint = tuple[int, int, int]
"""A rational point (X/W, Y/W) as the integers (X, Y, W), W > 0."""
Run = tuple[IPoint, IPoint, tuple[int, ...]]
"""A merged run of one source: (heading vector of its low end, of its high end, the segments of its landing unit:
consecutive segments of one group)."""

_ZERO = Fraction(0)
_ONE = Fraction(1)


class TableError(ValueError):
    """The segment table is not a partition of the boundary into straight pieces: ``claim`` names the place."""

    def __init__(self, claim: str, message: str) -> None:
        super().__init__(f"{claim}: {message}")
        self.claim = claim
        self.message = message


def _icross(u: IPoint, v: IPoint) -> int:
    return u[0] * v[1] - u[1] * v[0]


def _idot(u: IPoint, v: IPoint) -> int:
    return u[0] * v[0] + u[1] * v[1]


def heading_cmp(h1: IPoint, h2: IPoint) -> int:
    """Sign of angle(h1) − angle(h2) for heading vectors with angles in [0, π] (y ≥ 0, non-zero)."""
    c = _icross(h1, h2)
    if c:
        return -1 if c > 0 else 1
    if _idot(h1, h2) > 0:
        return 0
    return -1 if h1[0] > 0 else 1  # opposite: (x > 0, 0) is angle 0, (x < 0, 0) is π


def _lcm(a: int, b: int) -> int:
    x, y = a, b
    while y:
        x, y = y, x % y
    return a // x * b


def _gcd(a: int, b: int) -> int:
    while b:
        a, b = b, a % b
    return a


def _homogeneous(p: Point) -> HPoint:
    w = _lcm(Fraction(p[0]).denominator, Fraction(p[1]).denominator)
    return (int(p[0] * w), int(p[1] * w), w)


def _functional(u: IPoint, o: HPoint, grid: int) -> tuple[int, int, int]:
    """Integers (α, β, γ) with α·X + β·Y + γ = grid·W·cross(u, x − o) at the grid point x = (X, Y)/grid, for an
    integer vector u and o = (O_x, O_y)/W."""
    ox, oy, w = o
    return (-w * u[1], w * u[0], -grid * (u[0] * oy - u[1] * ox))


def _hvector(p: HPoint, q: HPoint) -> IPoint:
    """An integer positive multiple of q − p."""
    return (q[0] * p[2] - p[0] * q[2], q[1] * p[2] - p[1] * q[2])


def _side(u: IPoint, o: HPoint, p: HPoint) -> int:
    """Sign of cross(u, p − o)."""
    v = _hvector(o, p)
    c = u[0] * v[1] - u[1] * v[0]
    return (c > 0) - (c < 0)


@dataclass(frozen=True, slots=True)
class _Piece:
    t0: Fraction
    t1: Fraction
    segment: int
    first: bool  # the piece holds its segment's start
    last: bool  # the piece holds its segment's end


class Geometry:
    """The environment's edges and a segment table, validated, on a common integer grid.

    ``edges``: the (a, b) points of every edge, ``nxt[i]``: the edge after edge i on its ring; ``table``: per
    segment, its pieces ``(edge, t0, t1)``. Raises :class:`TableError` when the table is not a partition of
    every edge into consecutive, straight pieces (claims are named ``bound.table[k]``)."""

    def __init__(self, edges: Sequence[tuple[Point, Point]], nxt: Sequence[int],
                 table: Sequence[Sequence[tuple[int, Fraction, Fraction]]],
                 groups: Sequence[Sequence[int]] = ()) -> None:
        n = len(edges)
        self.n_edges = n
        if not table:
            raise TableError("bound.table", "the table has no segments")
        per_edge: list[list[_Piece]] = [[] for _ in range(n)]
        ends: list[tuple[Point, Point]] = []
        for k, pieces in enumerate(table):
            where = f"bound.table[{k}]"
            if not pieces:
                raise TableError(where, "a segment has at least one piece")
            for i, (edge, t0, t1) in enumerate(pieces):
                if not 0 <= edge < n:
                    raise TableError(f"{where}[{i}]", f"edge {edge} does not exist (edges 0..{n - 1})")
                if not _ZERO <= t0 < t1 <= _ONE:
                    raise TableError(f"{where}[{i}]", f"[t0, t1] = [{t0}, {t1}] is not an interval 0 ≤ t0 < t1 ≤ 1")
                if i > 0:
                    prev_edge, _, prev_t1 = pieces[i - 1]
                    if not (prev_t1 == _ONE and t0 == _ZERO and nxt[prev_edge] == edge):
                        raise TableError(f"{where}[{i}]", f"does not continue piece {i - 1} (edge {prev_edge} up to t = "
                                                          f"{prev_t1}) at the next edge's start: a segment is contiguous")
                    u = _fsub(edges[prev_edge][1], edges[prev_edge][0])
                    v = _fsub(edges[edge][1], edges[edge][0])
                    if u[0] * v[1] - u[1] * v[0] != 0 or u[0] * v[0] + u[1] * v[1] <= 0:
                        raise TableError(f"{where}[{i}]", f"edges {prev_edge} and {edge} turn at their shared vertex: a "
                                                          "segment is straight")
                per_edge[edge].append(_Piece(t0, t1, k, i == 0, i == len(pieces) - 1))
            e0, s0, _ = pieces[0]
            e1, _, s1 = pieces[-1]
            ends.append((_fpoint(edges[e0], s0), _fpoint(edges[e1], s1)))
        for e, items in enumerate(per_edge):
            items.sort(key=lambda p: (p.t0, p.t1))
            at = _ZERO
            for p in items:
                if p.t0 != at:
                    what = "overlaps" if p.t0 < at else "leaves a gap before"
                    raise TableError("bound.table", f"segment {p.segment} {what} t = {p.t0} of edge {e}: the table must "
                                                    "cover every edge exactly once")
                at = p.t1
            if at != _ONE:
                raise TableError("bound.table", f"edge {e} is covered only up to t = {at}: the table must cover every "
                                                "edge exactly once")
        self.per_edge = per_edge
        self.table = [tuple(p) for p in table]
        # The vertices on one integer grid (the lcm of their denominators: small, the environment's own numbers).
        # Segment ends keep their exact rationals (their denominators differ; a common grid of all of them would
        # hold integers of thousands of digits): every test against the vertices is a linear functional with
        # integer coefficients, a positive multiple of the exact one (:func:`_functional`).
        grid = 1
        for (a, b) in edges:
            for x in (*a, *b):
                grid = _lcm(grid, Fraction(x).denominator)
        self.grid = grid
        self.vertices: list[IPoint] = [(int(a[0] * grid), int(a[1] * grid)) for a, _ in edges]
        self.edge_ends: list[tuple[int, int]] = [(i, nxt[i]) for i in range(n)]
        self.ends: list[tuple[Point, Point]] = ends
        self.hends: list[tuple[HPoint, HPoint]] = [(_homogeneous(a), _homogeneous(b)) for a, b in ends]
        # the event points: every vertex and every segment end, each as (edge, n, d): the point t = n/d of the edge
        # (a value of a linear functional there is ((d − n)·f(start) + n·f(end)) / d, from the vertices' values)
        params: dict[Point, tuple[int, int, int]] = {}
        for i, (a, _) in enumerate(edges):
            params[(Fraction(a[0]), Fraction(a[1]))] = (i, 0, 1)
        for k, pieces in enumerate(table):
            for (edge, t), point in (((pieces[0][0], pieces[0][1]), ends[k][0]), ((pieces[-1][0], pieces[-1][2]), ends[k][1])):
                params.setdefault(point, (edge, Fraction(t).numerator, Fraction(t).denominator))
        self.points: list[tuple[int, int, int]] = list(params.values())
        self.groups: list[tuple[int, ...]] = []
        self.group_of: dict[int, tuple[int, int]] = {}
        for gi, group in enumerate(groups):
            self._add_group(gi, tuple(group), edges, nxt, per_edge)

    def _add_group(self, gi: int, group: tuple[int, ...], edges, nxt, per_edge) -> None:
        """Validate group ``gi`` (consecutive table segments along the boundary, on one straight line, each in one
        group) and record it."""
        where = f"bound.groups[{gi}]"
        if len(group) < 2:
            raise TableError(where, "a group joins at least two segments")
        for pos, k in enumerate(group):
            if not 0 <= k < len(self.table):
                raise TableError(where, f"segment {k} is not in the table (segments 0..{len(self.table) - 1})")
            if k in self.group_of:
                raise TableError(where, f"segment {k} is already in group {self.group_of[k][0]}: groups are disjoint")
            self.group_of[k] = (gi, pos)
        for k, k2 in zip(group, group[1:]):
            edge, _, t1 = self.table[k][-1]
            edge2, t0, _ = self.table[k2][0]
            if not ((edge2 == edge and t0 == t1) or (t1 == _ONE and t0 == _ZERO and nxt[edge] == edge2)):
                raise TableError(where, f"segment {k2} does not follow segment {k} along the boundary: a group is a run "
                                        "of consecutive segments")
            u = _fsub(self.ends[k][1], self.ends[k][0])
            v = _fsub(self.ends[k2][1], self.ends[k2][0])
            if u[0] * v[1] - u[1] * v[0] != 0 or u[0] * v[0] + u[1] * v[1] <= 0:
                raise TableError(where, f"segments {k} and {k2} turn where they meet: a group is straight")
        self.groups.append(group)

    def members(self, t: int) -> tuple[tuple[int, ...], int]:
        """The group of table segment t (t alone if it is in none) and t's position in it."""
        found = self.group_of.get(t)
        return (self.groups[found[0]], found[1]) if found is not None else ((t,), 0)

    def segment_of(self, edge: int, t: Fraction) -> int | None:
        """The table segment holding parameter t of ``edge`` other than at an end of a segment, else None."""
        return self._segment_at(edge, t.numerator, t.denominator)

    def _segment_at(self, edge: int, num: int, den: int, *, joints: bool = False) -> int | None:
        """:meth:`segment_of` at t = num/den (den > 0), in integers; with ``joints``, a point where two segments of one
        group meet belongs to the later one."""
        for p in self.per_edge[edge]:
            lo = num * p.t0.denominator - p.t0.numerator * den
            if lo == 0:
                if p.first and joints and self.group_of.get(p.segment, (0, 0))[1] > 0:
                    return p.segment
                return None if p.first else p.segment
            hi = num * p.t1.denominator - p.t1.numerator * den
            if lo > 0 and hi < 0:
                return p.segment
            if hi == 0:
                if p.last and joints:  # the joint with the next segment of its group belongs to that segment
                    found = self.group_of.get(p.segment)
                    if found is not None and found[1] + 1 < len(self.groups[found[0]]):
                        return self.groups[found[0]][found[1] + 1]
                return None if p.last else p.segment
        return None

    def pieces_of(self, segments: Sequence[int]) -> dict[int, list[tuple[Fraction, Fraction]]]:
        """The union of some segments as merged intervals per edge."""
        out: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for k in segments:
            for edge, t0, t1 in self.table[k]:
                out.setdefault(edge, []).append((t0, t1))
        return {e: union(v) for e, v in out.items()}

    def overlapping(self, pieces: Sequence[tuple[int, Fraction, Fraction]]) -> frozenset[int]:
        """The segments that share a piece of positive length with the given pieces."""
        out = set()
        for edge, lo, hi in pieces:
            if not 0 <= edge < self.n_edges:
                continue
            for p in self.per_edge[edge]:
                if p.t0 < hi and lo < p.t1:
                    out.add(p.segment)
        return frozenset(out)


def _fsub(u: Point, v: Point) -> Point:
    return (u[0] - v[0], u[1] - v[1])


def _fpoint(edge: tuple[Point, Point], t: Fraction) -> Point:
    a, b = edge
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))


class Closure:
    """The exact successor relation over beliefs of one :class:`Geometry`, with heading margin δ and width
    threshold w (rationals: δ ∈ [0, π/4), w ≥ 0). Per-source runs and angle decisions are cached."""

    def __init__(self, geometry: Geometry, heading_margin: Fraction, threshold: Fraction) -> None:
        self.g = geometry
        self.delta = Fraction(heading_margin)
        self.w = Fraction(threshold)
        self._runs: dict[int, list[Run]] = {}
        self._angle_cache: dict[tuple[IPoint, Fraction], bool] = {}
        self.counts = {"sources": 0, "cells": 0, "region_tests": 0, "angle_decisions": 0, "successors": 0}
        # π − 2δ > w, once
        self.room = self._angle_gt((-1, 0), 2 * self.delta + self.w)

    # ------------------------------------------------------------------ angles
    def _angle_gt(self, v: IPoint, r: Fraction) -> bool:
        """angle(v) > r for v in the closed upper half-plane (angle in [0, π]), exactly."""
        x, y = v
        if r < 0:
            return True
        if y == 0:
            if x > 0:
                return False  # angle 0 > r ≥ 0 never
            if r < 3:
                return True  # π > 3 > r
        elif r <= 1 and x > 0:
            if y <= r * x:
                return False  # tan θ = y/x ≤ r, so θ ≤ atan r < r (r > 0) or θ = 0 (r = 0)
            if y >= 2 * r * x:
                return True  # tan θ ≥ 2r > tan r (0 < r ≤ 1)
        elif x <= 0 and r < Fraction(3, 2):
            return True  # θ ≥ π/2 > 3/2
        key = (v, r)
        hit = self._angle_cache.get(key)
        if hit is None:
            self.counts["angle_decisions"] += 1
            try:
                hit = compare_angle((Fraction(x), Fraction(y)), r) > 0
            except Undecided:  # pragma: no cover - transcendental: always decided
                hit = True  # over-approximate: admit the interval (never unsound for a negative certificate)
            self._angle_cache[key] = hit
        return hit

    def admissible(self, lo: IPoint, hi: IPoint) -> bool:
        """Does the closed heading interval [lo, hi] ∩ [δ, π − δ] have width > w?"""
        if heading_cmp(lo, hi) >= 0 or not self.room:
            return False
        d, w = self.delta, self.w
        if not self._angle_gt(hi, d + w):
            return False
        if not self._angle_gt((-lo[0], lo[1]), d + w):  # π − angle(lo) > δ + w
            return False
        if w > 0:
            diff = (_idot(lo, hi), _icross(lo, hi))  # angle(hi) − angle(lo)
            if not self._angle_gt(diff, w):
                return False
        return True

    # ------------------------------------------------------------------ one source
    def runs(self, s: int) -> list[Run]:
        """The merged runs of source segment s: sorted, disjoint up to shared ends, each with its target."""
        cached = self._runs.get(s)
        if cached is None:
            cached = self._runs[s] = self._compute_runs(s)
        return cached

    def _compute_runs(self, s: int) -> list[Run]:
        g = self.g
        self.counts["sources"] += 1
        a, b = g.hends[s]
        E = _hvector(a, b)
        n = (-E[1], E[0])
        keys: set[Fraction] = set()
        verts = g.vertices
        for o in (a, b):
            # heading vectors of x − o in the frame of E, both coordinates scaled alike: (dot(E, ·), cross(E, ·))
            fy = _functional(E, o, g.grid)
            fx = _functional(n, o, g.grid)  # cross(n, v) = −dot(E, v) for the left normal n
            ys = [fy[0] * x + fy[1] * y + fy[2] for x, y in verts]
            xs = [-(fx[0] * x + fx[1] * y + fx[2]) for x, y in verts]
            for edge, num, den in g.points:
                i, j = g.edge_ends[edge]
                y = (den - num) * ys[i] + num * ys[j]
                if y <= 0:
                    continue
                keys.add(Fraction(-((den - num) * xs[i] + num * xs[j]), y))
        keys.discard(_ZERO)
        ordered = sorted(keys)
        events: list[IPoint] = [(1, 0)] + [(-k.numerator, k.denominator) for k in ordered if k < 0]
        events += [(0, 1)] + [(-k.numerator, k.denominator) for k in ordered if k > 0] + [(-1, 0)]  # π/2 always: no cell spans [0, π]
        f1 = self._values(_functional(E, a, g.grid))
        out: list[Run] = []
        for i in range(len(events) - 1):
            h0, h1 = events[i], events[i + 1]
            hx, hy = h0[0] + h1[0], h0[1] + h1[1]
            dx, dy = hx * E[0] + hy * n[0], hx * E[1] + hy * n[1]
            k = _gcd(abs(dx), abs(dy)) or 1
            self.counts["cells"] += 1
            t = self._target(s, a, b, (dx // k, dy // k), f1)
            if t is None:
                continue
            if out and out[-1][2] == t and out[-1][1] == h0:
                out[-1] = (out[-1][0], h1, t)
            else:
                out.append((h0, h1, t))
        return out

    def _values(self, f: tuple[int, int, int]) -> list[int]:
        al, be, ga = f
        return [al * x + be * y + ga for x, y in self.g.vertices]

    def _target(self, s: int, a: HPoint, b: HPoint, d: IPoint, f1: list[int]) -> tuple[int, ...] | None:
        """The landing unit of open s at direction d — the run of consecutive segments of one group that the landings
        meet (one segment when they cross no joint) — or None when they do not all land inside one group (exact)."""
        g = self.g
        m = (a[0] * b[2] + b[0] * a[2], a[1] * b[2] + b[1] * a[2], 2 * a[2] * b[2])
        phi = self._values(_functional(d, m, g.grid))  # side of the ray's line
        psi = self._values(_functional((d[1], -d[0]), m, g.grid))  # a positive multiple of dot(d, x − m)
        best_num, best_den, best_edge, best_u = 0, 0, -1, (0, 1)
        for e, (i, j) in enumerate(g.edge_ends):
            fp, fq = phi[i], phi[j]
            if (fp > 0 and fq > 0) or (fp < 0 and fq < 0) or fp == fq:
                continue  # the edge does not cross the ray's line (or lies on it)
            den = fp - fq
            num = fp * psi[j] - fq * psi[i]
            u_num = fp
            if den < 0:
                den, num, u_num = -den, -num, -u_num
            if num <= 0:
                continue  # behind the start of the ray
            if best_edge < 0 or num * best_den < best_num * den:
                best_num, best_den, best_edge, best_u = num, den, e, (u_num, den)
        if best_edge < 0:
            return None
        t = g._segment_at(best_edge, *best_u, joints=True)
        if t is None or t == s:
            return None
        group, pos = g.members(t)
        c, e_pt = g.hends[group[0]][0], g.hends[group[-1]][1]
        T = _hvector(c, e_pt)
        if T[0] * d[1] - T[1] * d[0] >= 0:
            return None  # d does not enter t from its free side
        for o in (a, b):
            if _side(T, o, c) > 0:  # o on the wall's side of the line of t: its ray meets the line behind o
                return None
            if _side(d, o, c) * _side(d, o, e_pt) > 0:
                return None  # c and e on one side of the corner ray: it lands outside the closed group
        self.counts["region_tests"] += 1
        if not self._region_empty(a, b, d, c, T, f1):
            return None
        # t, and its neighbours in the group as long as the joint between lies strictly between the two corner rays
        # (the open image holds the joint): the minimal run of the group's segments the image meets
        lo = hi = pos
        while lo > 0 and _side(d, a, g.hends[group[lo]][0]) * _side(d, b, g.hends[group[lo]][0]) < 0:
            lo -= 1
        while hi < len(group) - 1 and _side(d, a, g.hends[group[hi]][1]) * _side(d, b, g.hends[group[hi]][1]) < 0:
            hi += 1
        return group[lo:hi + 1]

    def _region_empty(self, a: HPoint, b: HPoint, d: IPoint, c: HPoint, T: IPoint, f1: list[int]) -> bool:
        """Does no edge meet the open region R° (module docstring)?"""
        grid = self.g.grid
        vals = (f1, self._values(_functional((-d[0], -d[1]), a, grid)), self._values(_functional(d, b, grid)),
                self._values(_functional(T, c, grid)))
        for i, j in self.g.edge_ends:
            # strict bounds on the edge parameter λ ∈ [0, 1] as fractions num/den (den > 0)
            lo_n, lo_d, hi_n, hi_d = 0, 1, 1, 1
            for f in vals:
                x, y = f[i], f[j]
                if x > 0 and y > 0:
                    continue
                if x <= 0 and y <= 0:
                    break
                if x <= 0:  # λ > −x / (y − x)
                    if -x * lo_d > lo_n * (y - x):
                        lo_n, lo_d = -x, y - x
                elif x * hi_d < hi_n * (x - y):  # λ < x / (x − y)
                    hi_n, hi_d = x, x - y
            else:
                if lo_n * hi_d < hi_n * lo_d:
                    return False  # the open interval of λ is not empty: the edge meets R°
        return True

    # ------------------------------------------------------------------ beliefs
    def successors(self, belief: Sequence[int]) -> list[tuple[tuple[tuple[int, ...], ...], tuple[IPoint, IPoint]]]:
        """Every successor of ``belief`` up to smaller next beliefs: (the landing unit of each of its sources in order,
        the heading interval [lo, hi]). See *Successors* in the module docstring: one per start cell of the common
        cells, the shortest admissible stretch of cells from it (each source's unit: the minimal run of its group
        covering its units there), widened to every neighbouring cell whose units lie in those runs. The next belief is
        every segment of the units (:func:`next_belief`)."""
        lists = [self.runs(s) for s in belief]
        if any(not runs for runs in lists):
            return []
        cells: list[tuple[IPoint, IPoint, tuple[tuple[int, ...], ...]]] = [(lo, hi, (t,)) for lo, hi, t in lists[0]]
        for runs in lists[1:]:
            merged = []
            i = j = 0
            while i < len(cells) and j < len(runs):
                c_lo, c_hi, c_t = cells[i]
                r_lo, r_hi, r_t = runs[j]
                lo = c_lo if heading_cmp(c_lo, r_lo) >= 0 else r_lo
                hi = c_hi if heading_cmp(c_hi, r_hi) <= 0 else r_hi
                if heading_cmp(lo, hi) < 0:
                    merged.append((lo, hi, c_t + (r_t,)))
                if heading_cmp(c_hi, r_hi) < 0:
                    i += 1
                else:
                    j += 1
            cells = merged
            if not cells:
                return []
        # each cell's unit of each source as (its group, first and last position in it)
        places = [tuple(self._place(t) for t in targets) for _, _, targets in cells]
        out: list[tuple[tuple[tuple[int, ...], ...], tuple[IPoint, IPoint]]] = []
        start = 0
        for k in range(1, len(cells) + 1):
            if k < len(cells) and heading_cmp(cells[k - 1][1], cells[k][0]) == 0 and all(
                    p[0] == q[0] for p, q in zip(places[k - 1], places[k])):
                continue  # the stretch of contiguous cells, each source's units in one group, goes on
            self._stretch(cells, places, start, k, out)
            start = k
        self.counts["successors"] += len(out)
        return out

    def _place(self, unit: tuple[int, ...]) -> tuple[tuple[int, ...], int, int]:
        group, pos = self.g.members(unit[0])
        return group, pos, pos + len(unit) - 1

    def _stretch(self, cells: list, places: list, start: int, end: int, out: list) -> None:
        """The successors of the contiguous cells ``cells[start:end]`` (module docstring, *Successors*)."""
        seen: set[tuple[int, int]] = set()
        j = start
        for i in range(start, end):
            j = max(j, i)
            while j < end and not self.admissible(cells[i][0], cells[j][1]):
                j += 1  # the shortest admissible stretch from i ends at j (never before the one from i − 1)
            if j == end:
                return
            hull = [[pl[1], pl[2]] for pl in places[i]]
            for k in range(i + 1, j + 1):
                for h, pl in zip(hull, places[k]):
                    h[0], h[1] = min(h[0], pl[1]), max(h[1], pl[2])
            lo, hi = i, j
            while lo > start and all(h[0] <= pl[1] and pl[2] <= h[1] for h, pl in zip(hull, places[lo - 1])):
                lo -= 1
            while hi < end - 1 and all(h[0] <= pl[1] and pl[2] <= h[1] for h, pl in zip(hull, places[hi + 1])):
                hi += 1
            if (lo, hi) in seen:
                continue
            seen.add((lo, hi))
            targets = tuple(pl[0][h[0]:h[1] + 1] for h, pl in zip(hull, places[i]))
            out.append((targets, (cells[lo][0], cells[hi][1])))


def next_belief(targets: Sequence[Sequence[int]]) -> frozenset[int]:
    """The belief after a stage whose sources land on the units ``targets``: every segment of every unit."""
    return frozenset(k for run in targets for k in run)
