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
with every heading of J first meets the boundary inside one (closed) table segment t_s; the next belief is
{t_s : s ∈ B}. A stage is a *goal stage* when every t_s is a goal segment.

One source, one direction
-------------------------
For a source segment s = (a, b), E = b − a, and a direction d with cross(E, d) > 0, every point of open s
lands inside the closed segment t = (c, e), T = e − c, iff

- d enters t from its free side, cross(T, d) < 0, and the corner rays from a and b meet the line of t at
  parameters μ ≥ 0 (along d) inside the closed segment t (τ ∈ [0, 1]);
- the open region R° = {x : cross(E, x − a) > 0, cross(x − a, d) > 0, cross(d, x − b) > 0, cross(T, x − c) > 0}
  — the points strictly between s and t swept by the rays from open s — holds no boundary point: no edge of
  the environment meets it (each edge against four strict linear inequalities, exactly).

The condition is exact at every direction (no grazing exceptions): a ray from x ∈ open s runs through R°
until it meets the line of t, and every point of R° lies on such a ray. (Necessity: the corner conditions are
the limits of the landing points of positions next to a and b, which land on closed t; a boundary point in R°
lies on the path of some position's ray before it reaches t.)

Cells
-----
As the direction turns, the landing segment and the condition above can change only at *event directions*:
from a or b towards a vertex of the environment or an end of a table segment (the swept region's structure
changes only when one of its corner rays passes such a point). Between consecutive events (an open *cell*)
the condition is therefore constant; it is decided at one rational direction strictly inside the cell (the
sum of the two neighbouring event directions, in heading-vector form): its landing segment is found by an
exact ray cast from the middle of s, then the condition is tested. Consecutive cells with the same target
are merged into one closed *run* (which over-approximates the safe set at the event directions between
them: a larger successor relation only makes the invariant harder to satisfy, never unsound).

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

__all__ = ["Geometry", "TableError", "Closure", "Run"]

IPoint = tuple[int, int]
Run = tuple[IPoint, IPoint, int]
"""A merged run of one source: (heading vector of its low end, of its high end, target segment)."""

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


def _isub(u: IPoint, v: IPoint) -> IPoint:
    return (u[0] - v[0], u[1] - v[1])


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
                 table: Sequence[Sequence[tuple[int, Fraction, Fraction]]]) -> None:
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
        # the common integer grid: every vertex and every segment end, doubled (so that midpoints are integral)
        scale = 1
        for (a, b) in edges:
            for x in (*a, *b):
                scale = _lcm(scale, Fraction(x).denominator)
        for (a, b) in ends:
            for x in (*a, *b):
                scale = _lcm(scale, Fraction(x).denominator)
        scale *= 2
        self.scale = scale

        def grid(p: Point) -> IPoint:
            return (int(p[0] * scale), int(p[1] * scale))

        self.vertices: list[IPoint] = [grid(a) for a, _ in edges]
        self.edge_ends: list[tuple[int, int]] = []
        index = {v: i for i, v in enumerate(self.vertices)}
        for a, b in edges:
            self.edge_ends.append((index[grid(a)], index[grid(b)]))
        self.ends: list[tuple[IPoint, IPoint]] = [(grid(a), grid(b)) for a, b in ends]
        points = set(self.vertices)
        for a, b in self.ends:
            points.add(a)
            points.add(b)
        self.points = sorted(points)
        self.edge_params = [(_fsub(b, a)) for a, b in edges]

    def segment_of(self, edge: int, t: Fraction) -> int | None:
        """The table segment holding parameter t of ``edge`` other than at an end of a segment, else None."""
        for p in self.per_edge[edge]:
            if p.t0 < t < p.t1:
                return p.segment
            if t == p.t0:
                return None if p.first else p.segment
            if t == p.t1:
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
        a, b = g.ends[s]
        E = _isub(b, a)
        keys: dict[Fraction, IPoint] = {}
        for p in g.points:
            for o in (a, b):
                v = _isub(p, o)
                y = _icross(E, v)
                if y <= 0:
                    continue
                h = (_idot(E, v), y)
                keys.setdefault(Fraction(-h[0], h[1]), h)
        keys.setdefault(_ZERO, (0, 1))  # π/2: no cell spans [0, π]
        events: list[IPoint] = [(1, 0)] + [keys[k] for k in sorted(keys)] + [(-1, 0)]
        n = (-E[1], E[0])
        out: list[Run] = []
        for i in range(len(events) - 1):
            h0, h1 = events[i], events[i + 1]
            hx, hy = h0[0] + h1[0], h0[1] + h1[1]
            d = (hx * E[0] + hy * n[0], hx * E[1] + hy * n[1])
            self.counts["cells"] += 1
            t = self._target(s, a, b, E, d)
            if t is None:
                continue
            if out and out[-1][2] == t and out[-1][1] == h0:
                out[-1] = (out[-1][0], h1, t)
            else:
                out.append((h0, h1, t))
        return out

    def _target(self, s: int, a: IPoint, b: IPoint, E: IPoint, d: IPoint) -> int | None:
        """The segment every point of open s lands in at direction d, or None (exact)."""
        g = self.g
        m = ((a[0] + b[0]) // 2, (a[1] + b[1]) // 2)
        best_num, best_den, best_edge, best_u = 0, 0, -1, (0, 1)
        verts = g.vertices
        for e, (i, j) in enumerate(g.edge_ends):
            p, q = verts[i], verts[j]
            f = _isub(q, p)
            den = _icross(d, f)
            if den == 0:
                continue
            pm = _isub(p, m)
            num = _icross(pm, f)  # μ = num / den
            u_num = _icross(pm, d)  # u = u_num / den
            if den < 0:
                den, num, u_num = -den, -num, -u_num
            if num <= 0 or u_num < 0 or u_num > den:
                continue
            if best_edge < 0 or num * best_den < best_num * den:
                best_num, best_den, best_edge, best_u = num, den, e, (u_num, den)
        if best_edge < 0:
            return None
        t = g.segment_of(best_edge, Fraction(*best_u))
        if t is None or t == s:
            return None
        c, e_pt = g.ends[t]
        T = _isub(e_pt, c)
        ctd = _icross(T, d)
        if ctd >= 0:
            return None
        for o in (a, b):
            if _icross(_isub(c, o), T) < 0:
                return None  # behind the ray's start
            oc = _icross(_isub(o, c), d)
            if not (ctd <= oc <= 0):
                return None  # outside the closed target
        self.counts["region_tests"] += 1
        return t if self._region_empty(a, b, E, d, c, T) else None

    def _region_empty(self, a: IPoint, b: IPoint, E: IPoint, d: IPoint, c: IPoint, T: IPoint) -> bool:
        """Does no edge meet the open region R° (module docstring)?"""
        g = self.g
        vals = []
        for v in g.vertices:
            va, vb, vc = _isub(v, a), _isub(v, b), _isub(v, c)
            vals.append((_icross(E, va), _icross(va, d), _icross(d, vb), _icross(T, vc)))
        for i, j in g.edge_ends:
            fp, fq = vals[i], vals[j]
            # lower / upper bounds on the edge parameter λ as fractions num/den (den > 0), strict
            lo_n, lo_d = 0, 1
            hi_n, hi_d = 1, 1
            lo_open = hi_open = False
            ok = True
            for k in range(4):
                x, y = fp[k], fq[k]
                if x > 0 and y > 0:
                    continue
                if x <= 0 and y <= 0:
                    ok = False
                    break
                if x <= 0:  # λ > -x / (y - x)
                    n_, d_ = -x, y - x
                    if n_ * lo_d > lo_n * d_ or (n_ * lo_d == lo_n * d_):
                        lo_n, lo_d, lo_open = n_, d_, True
                else:  # λ < x / (x - y)
                    n_, d_ = x, x - y
                    if n_ * hi_d < hi_n * d_ or (n_ * hi_d == hi_n * d_):
                        hi_n, hi_d, hi_open = n_, d_, True
            if not ok:
                continue
            cmp = lo_n * hi_d - hi_n * lo_d
            if cmp < 0 or (cmp == 0 and not lo_open and not hi_open):
                return False
        return True

    # ------------------------------------------------------------------ beliefs
    def successors(self, belief: Sequence[int]) -> list[tuple[tuple[int, ...], tuple[IPoint, IPoint]]]:
        """Every successor of ``belief``: (the targets of its sources in order, the common run [lo, hi]), one per
        common cell whose admissible part is wider than w."""
        lists = [self.runs(s) for s in belief]
        if any(not runs for runs in lists):
            return []
        cells: list[tuple[IPoint, IPoint, tuple[int, ...]]] = [(lo, hi, (t,)) for lo, hi, t in lists[0]]
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
        out = []
        for lo, hi, targets in cells:
            if self.admissible(lo, hi):
                out.append((targets, (lo, hi)))
        self.counts["successors"] += len(out)
        return out
