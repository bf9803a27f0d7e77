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


def _clearance_cone(graph: SafeBVG, i: int, j: int, kappa: float) -> tuple[float, float]:
    """Headings whose landings from every point of segment i stay κ away from the ends of segment j (except the
    end j shares with i): Prop. 2's cone towards the target pulled in by κ, computed point by point."""
    src, dst = graph.partition.segments[i], graph.partition.segments[j]
    ax, ay, bx, by = (float(v) for v in (*src.a, *src.b))
    cx, cy, dx, dy = (float(v) for v in (*dst.a, *dst.b))
    length = math.hypot(dx - cx, dy - cy)
    ux, uy = (dx - cx) / length, (dy - cy) / length
    base = math.atan2(by - ay, bx - ax)

    def heading_to(px, py, qx, qy):  # CCW angle of q − p from the source direction, in (−π, π]
        angle = math.atan2(qy - py, qx - px) - base
        return math.atan2(math.sin(angle), math.cos(angle))

    low = 0.0 if dst.a == src.b else heading_to(bx, by, cx + kappa * ux, cy + kappa * uy)
    high = math.pi if dst.b == src.a else heading_to(ax, ay, dx - kappa * ux, dy - kappa * uy)
    if length <= kappa * ((dst.a != src.b) + (dst.b != src.a)):
        return 1.0, 0.0  # empty
    return low, high


def _corner(graph: SafeBVG, i: int, j: int) -> tuple[int, int]:
    """(end of i, end of j) of the vertex segments i and j share — 1 start, 2 end — or (0, 0)."""
    a, b = graph.partition.segments[i], graph.partition.segments[j]
    if a.b == b.a:
        return 2, 1
    if a.a == b.b:
        return 1, 2
    return 0, 0


def admissible(graph: SafeBVG, delta: float = DEFAULT_HEADING_MARGIN, mu: float = DEFAULT_SAFE_MARGIN,
               kappa: float | None = None):
    """The admissible intervals of every source: safe intervals cut by the margin policy (δ, μ, κ), each with
    the corner it runs into (``dive``: the source's end, ``arrival``: the target's end; 0 for none)."""
    xmin, ymin, xmax, ymax = graph.partition.env.bounds
    diagonal = math.hypot(xmax - xmin, ymax - ymin)
    kappa = CORNER_CLEARANCE_FRACTION * diagonal if kappa is None else kappa
    end = max(mu, kappa / diagonal)
    out: dict[int, list[tuple[float, float, int]]] = {s: [] for s in range(graph.n_segments)}
    for k in range(graph.n_arcs):
        i, j = int(graph.source[k]), int(graph.target[k])
        low, high = _clearance_cone(graph, i, j, kappa)
        dive, arrival = _corner(graph, i, j)
        for r in range(int(graph.set_offsets[k]), int(graph.set_offsets[k + 1])):
            lo = max(float(graph.set_lo[r]) + end, delta, low + mu)
            hi = min(float(graph.set_hi[r]) - end, math.pi - delta, high - mu)
            if hi > lo:
                out[i].append((lo, hi, j, dive, arrival))
    return out


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
