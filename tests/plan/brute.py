"""Brute-force enumeration of every plan with at most K stages (the reference for the optimality tests).

Independent of :mod:`solverplan.plan`'s searches: the admissible intervals are rebuilt from the safe BVG's
arrays with the documented formula, a stage from a belief is every choice of one admissible interval per
source (a recursive product, intersecting as it goes), and every sequence of stages is enumerated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

from solverplan.bounce.bvg import SafeBVG
from solverplan.plan.margins import CORNER_CLEARANCE_FRACTION, DEFAULT_HEADING_MARGIN, DEFAULT_SAFE_MARGIN

EPS = 1e-9


def _clearance_cone(graph: SafeBVG, src, j: int, kappa: float, corner) -> tuple[float, float]:
    """Headings whose landings from every point of ``src`` (a segment or a start piece: anything with ends ``a``,
    ``b``) stay κ away from the ends of segment j (except the end j shares with ``corner``, src's segment): Prop.
    2's cone towards the target pulled in by κ, computed point by point."""
    dst = graph.partition.segments[j]
    ax, ay, bx, by = (float(v) for v in (*src.a, *src.b))
    cx, cy, dx, dy = (float(v) for v in (*dst.a, *dst.b))
    length = math.hypot(dx - cx, dy - cy)
    ux, uy = (dx - cx) / length, (dy - cy) / length
    base = math.atan2(by - ay, bx - ax)

    def heading_to(px, py, qx, qy):  # CCW angle of q − p from the source direction, in (−π, π]
        angle = math.atan2(qy - py, qx - px) - base
        return math.atan2(math.sin(angle), math.cos(angle))

    low = 0.0 if dst.a == corner.b else heading_to(bx, by, cx + kappa * ux, cy + kappa * uy)
    high = math.pi if dst.b == corner.a else heading_to(ax, ay, dx - kappa * ux, dy - kappa * uy)
    if length <= kappa * ((dst.a != corner.b) + (dst.b != corner.a)):
        return 1.0, 0.0  # empty
    return low, high


def _corner(graph: SafeBVG, a, j: int) -> tuple[int, int]:
    """(end of a, end of j) of the vertex a (a segment or a start piece) and segment j share — 1 start, 2 end —
    or (0, 0)."""
    b = graph.partition.segments[j]
    if a.b == b.a:
        return 2, 1
    if a.a == b.b:
        return 1, 2
    return 0, 0


def diameter(env) -> float:
    """The largest distance between two vertices (all pairs: independent of the planners' calipers)."""
    pts = [(float(x), float(y)) for ring in env.rings for x, y in ring]
    return max(math.dist(p, q) for p in pts for q in pts)


@dataclass(frozen=True)
class Piece:
    """A start piece: part [t0, t1] of segment ``host`` (the key of its admissible intervals)."""

    host: int
    t0: Fraction
    t1: Fraction
    a: tuple
    b: tuple


def admissible(graph: SafeBVG, delta: float = DEFAULT_HEADING_MARGIN, mu: float = DEFAULT_SAFE_MARGIN,
               kappa: float | None = None, pieces: tuple[Piece, ...] = ()):
    """The admissible intervals of every source (every segment, and every start piece in ``pieces``): safe
    intervals cut by the margin policy (δ, μ, κ), each with the corner it runs into (``dive``: the source's end,
    ``arrival``: the target's end; 0 for none). A piece's safe sets are the exact reference
    :func:`~solverplan.bounce.safe.safe_set`, towards every segment."""
    from solverplan.bounce.safe import safe_set

    size = diameter(graph.partition.env)
    kappa = CORNER_CLEARANCE_FRACTION * size if kappa is None else kappa
    end = max(mu, kappa / size)
    out: dict = {s: [] for s in range(graph.n_segments)}

    def add(key, src, j, intervals):
        # a start piece keeps the clearance exemptions of its segment at the segment's corners
        corner = graph.partition.segments[src.host] if isinstance(src, Piece) else src
        low, high = _clearance_cone(graph, src, j, kappa, corner)
        dive, arrival = _corner(graph, corner, j)
        for l0, h0 in intervals:
            lo = max(l0 + end, delta, low + mu)
            hi = min(h0 - end, math.pi - delta, high - mu)
            if hi > lo:
                out[key].append((lo, hi, j, dive, arrival))

    for k in range(graph.n_arcs):
        i, j = int(graph.source[k]), int(graph.target[k])
        rows = range(int(graph.set_offsets[k]), int(graph.set_offsets[k + 1]))
        add(i, graph.partition.segments[i], j, [(float(graph.set_lo[r]), float(graph.set_hi[r])) for r in rows])
    for piece in pieces:
        out[piece] = []
        for j, seg in enumerate(graph.partition.segments):
            if j != piece.host and seg.edge != graph.partition.segments[piece.host].edge:
                found = safe_set(graph.partition.env, (piece.a, piece.b), (seg.a, seg.b))
                add(piece, piece, j, [(iv.lo, iv.hi) for iv in found.intervals])
    return out


def start_elements(graph: SafeBVG, pieces: list[tuple[int, Fraction, Fraction]]) -> tuple[tuple, tuple[Piece, ...]]:
    """The start set as given: the segments it covers whole and the :class:`Piece` s it covers in part (pieces of
    one edge merged first)."""
    merged: dict[int, list[list[Fraction]]] = {}
    for e, a, b in sorted(pieces):
        items = merged.setdefault(e, [])
        if items and a <= items[-1][1]:
            items[-1][1] = max(items[-1][1], b)
        else:
            items.append([a, b])
    whole, parts = [], []
    for seg in graph.partition.segments:
        for a, b in merged.get(seg.edge, ()):
            lo, hi = max(a, seg.t0), min(b, seg.t1)
            if lo >= hi:
                continue
            if (lo, hi) == (seg.t0, seg.t1):
                whole.append(seg.id)
                continue
            lam0, lam1 = (lo - seg.t0) / (seg.t1 - seg.t0), (hi - seg.t0) / (seg.t1 - seg.t0)
            point = lambda lam: tuple(p + lam * (q - p) for p, q in zip(seg.a, seg.b))  # noqa: E731
            parts.append(Piece(seg.id, lo, hi, point(lam0), point(lam1)))
    return tuple(whole) + tuple(parts), tuple(parts)


def start_segments(graph: SafeBVG, pieces: list[tuple[int, Fraction, Fraction]]) -> tuple[int, ...]:
    segs = graph.partition.segments
    return tuple(sorted({s.id for s in segs for e, a, b in pieces if s.edge == e and s.t0 < b and a < s.t1}))


@dataclass
class Enumeration:
    plans: list[list[tuple[float, float]]] = field(default_factory=list)

    def fewest(self) -> int | None:
        return min((len(p) for p in self.plans), default=None)

    def best_min_width(self, k: int) -> float:
        return max((min(h - l for l, h in p) for p in self.plans if len(p) <= k), default=0.0)

    def front(self, K: int) -> list[tuple[int, float]]:
        out, best = [], 0.0
        for k in range(1, K + 1):
            w = self.best_min_width(k)
            if w > best + EPS:
                out.append((k, w))
                best = w
        return out

    def best_sum(self) -> float | None:
        return max((sum(h - l for l, h in p) for p in self.plans), default=None)

    def best_constant(self) -> float:
        best = 0.0
        for p in self.plans:
            w = min(h for _, h in p) - max(l for l, _ in p)
            best = max(best, w)
        return best


def enumerate_plans(adm, start: tuple[int, ...], goal: set[int], K: int) -> Enumeration:
    """Every plan of ≤ K stages. A belief is a set of (segment, corners): the corners (bits 1 start, 2 end) the
    robot may have just arrived near, into which no arc is taken next (no corner ping-pong)."""
    cache: dict = {}

    def stages_from(belief):
        if belief in cache:
            return cache[belief]
        found = []

        def rec(idx, lo, hi, targets):
            if idx == len(belief):
                joined: dict[int, int] = {}
                for j, tag in targets:
                    joined[j] = joined.get(j, 0) | tag
                found.append((lo, hi, tuple(sorted(joined.items()))))
                return
            segment, near = belief[idx]
            for l, h, j, dive, arrival in adm[segment]:
                if dive & near:
                    continue
                a, b = max(lo, l), min(hi, h)
                if b > a:
                    rec(idx + 1, a, b, targets + [(j, arrival)])

        rec(0, -math.inf, math.inf, [])
        cache[belief] = found
        return found

    result = Enumeration()

    def walk(belief, stages):
        if len(stages) == K:
            return
        for lo, hi, nxt in stages_from(belief):
            extended = stages + [(lo, hi)]
            if {j for j, _ in nxt} <= goal:
                result.plans.append(extended)
            walk(nxt, extended)

    walk(tuple((s, 0) for s in start), [])
    return result
