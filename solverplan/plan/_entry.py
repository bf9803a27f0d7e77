"""Safe-BVG plans over belief states (private): fewest stages from a set of possible segments to a goal.

A *belief* is the set of segments of P′ the robot may be on. One stage is one heading interval executed
whatever the segment: it is usable from belief B when, for every heading in it, every segment of B has a safe
arc to some target (then every point of every segment of B lands inside one known segment), and the next
belief is the set of those targets ("fewest bounces … over sets of possible segments"). For a belief
the candidate intervals come from one sweep over the ends of its segments' safe intervals: between two
consecutive ends the map segment → target is constant; maximal runs with the same map that cover every segment
are the candidates, kept when at least 2ε wide. Breadth-first search over beliefs gives the fewest stages.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Callable, Iterable

import numpy as np

from solverplan.bounce.bvg import SafeBVG
from solverplan.interval import Interval
from solverplan.plan._results import SAFE_END_MARGIN

__all__ = ["BeliefStage", "belief_successors", "belief_search"]


@dataclass(frozen=True, slots=True)
class BeliefStage:
    """One stage from a belief: the interval and the move (source segment → target segment) of every source."""

    interval: Interval
    moves: tuple[tuple[int, int], ...]

    @property
    def sources(self) -> frozenset[int]:
        return frozenset(s for s, _ in self.moves)

    @property
    def targets(self) -> frozenset[int]:
        return frozenset(t for _, t in self.moves)


class _Arcs:
    """Safe pieces per source segment: (lo, hi, target), margins applied at 0 and π."""

    def __init__(self, g: SafeBVG) -> None:
        counts = np.asarray(g.n_intervals, dtype=np.int64)
        arc_of = np.repeat(np.arange(g.n_arcs), counts)
        lo = np.asarray(g.set_lo, dtype=float) + SAFE_END_MARGIN
        hi = np.asarray(g.set_hi, dtype=float) - SAFE_END_MARGIN
        src = np.asarray(g.source, dtype=np.int64)[arc_of]
        tgt = np.asarray(g.target, dtype=np.int64)[arc_of]
        self.by_source: dict[int, list[tuple[float, float, int]]] = {}
        for s, t, a, b in zip(src.tolist(), tgt.tolist(), lo.tolist(), hi.tolist()):
            if b > a:
                self.by_source.setdefault(s, []).append((a, b, t))


def belief_successors(arcs: _Arcs, belief: frozenset[int], tolerance: float) -> list[BeliefStage]:
    """Every maximal candidate stage from ``belief`` at least 2·tolerance wide (one per distinct next belief,
    the widest)."""
    items = [(s, a, b, t) for s in belief for a, b, t in arcs.by_source.get(s, ())]
    if not items:
        return []
    ends = sorted({x for _, a, b, _ in items for x in (a, b)})
    best: dict[frozenset[int], BeliefStage] = {}
    run_lo = None
    run_map: tuple | None = None
    need = 2 * tolerance

    def close(lo: float, hi: float, mapping: tuple) -> None:
        if mapping is None or hi - lo < need:
            return
        stage = BeliefStage(Interval(lo, hi), mapping)
        key = stage.targets
        if key not in best or best[key].interval.width < stage.interval.width:
            best[key] = stage

    for x0, x1 in zip(ends[:-1], ends[1:]):
        mid = (x0 + x1) / 2
        mapping: dict[int, int] = {}
        for s, a, b, t in items:
            if a <= mid <= b:
                mapping[s] = t
        m = tuple(sorted(mapping.items())) if len(mapping) == len(belief) else None
        if m != run_map:
            if run_map is not None:
                close(run_lo, x0, run_map)
            run_map, run_lo = m, x0
    if run_map is not None:
        close(run_lo, ends[-1], run_map)
    return list(best.values())


def belief_search(g: SafeBVG, start: Iterable[int], tolerance: float, *,
                  goal: Callable[[frozenset[int]], bool] | None = None,
                  max_stages: int = 16, max_beliefs: int = 20000):
    """Breadth-first search over beliefs from ``start``.

    Returns ``(plan, reached)``: ``plan`` the fewest-stage list of :class:`BeliefStage` to a belief
    satisfying ``goal`` (``None`` without a goal or if none was found), ``reached`` every belief reached
    (within ``max_stages`` stages and ``max_beliefs`` beliefs), each with its depth.
    """
    arcs = _Arcs(g)
    first = frozenset(int(s) for s in start)
    parent: dict[frozenset[int], tuple[frozenset[int], BeliefStage] | None] = {first: None}
    depth = {first: 0}
    queue = deque([first])

    def path_to(b: frozenset[int]) -> list[BeliefStage]:
        out = []
        while parent[b] is not None:
            prev, stage = parent[b]  # type: ignore[misc]
            out.append(stage)
            b = prev
        return out[::-1]

    if goal is not None and goal(first):
        return [], depth
    while queue:
        b = queue.popleft()
        if depth[b] >= max_stages:
            continue
        for stage in belief_successors(arcs, b, tolerance):
            nb = stage.targets
            if nb in parent:
                continue
            parent[nb] = (b, stage)
            depth[nb] = depth[b] + 1
            if goal is not None and goal(nb):
                return path_to(nb), depth
            if len(parent) >= max_beliefs:
                return None, depth
            queue.append(nb)
    return None, depth
