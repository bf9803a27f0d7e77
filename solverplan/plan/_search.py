"""Label-setting searches over the belief-state graph (private backends of :mod:`.search`).

Every search returns paths as lists of :class:`~._problem.Option` (the last one a goal option) and
counts what it explored, so that an empty answer is a proof: the search space was exhausted.
Optimality arguments are in the docstrings; :mod:`.search` states them in each plan's ``optimality``.

Every search takes a ``deadline`` (:class:`~._deadline.Deadline`, default never), asked once per expansion.
When it expires the search stops and says so (``timed_out`` in its statistics or its :class:`Front`), with the
bound it has proved so far and, where it has one, its best plan so far: then nothing is exhausted.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field
from typing import Callable

from solverplan.plan._deadline import NEVER, Deadline
from solverplan.plan._problem import Belief, Option, Problem

__all__ = ["Path", "Front", "WIDTH_EPS", "bfs", "reachable", "fewest_stages", "bottleneck", "layered_front", "max_sum",
           "widest_constant", "walk"]

INF = math.inf
Path = list[Option]

WIDTH_EPS = 1e-12
"""Widths closer than this (radians) count as equal: hi − lo of intervals with equal exact widths can
differ in the last float digit, and a longer plan must not win a tie by rounding noise."""


@dataclass
class Front:
    """Result of :func:`layered_front`: points (bounces, min width, path), strictly improving."""

    points: list[tuple[int, float, Path]] = field(default_factory=list)
    beliefs: int = 0
    layers: int = 0
    exhausted: bool = True  # True: no label could change any more (the whole space was searched)
    budget_pruned: bool = False  # some belief was dropped because it cannot reach the goal within the budget
    timed_out: bool = False  # the deadline stopped the search (then ``exhausted`` is False)
    scanned: int = 0  # layers whose goal options were all looked at: no plan has fewer stages than the first point
    bound: float | None = None  # on a timeout: an upper bound on the min width of every plan within the budget


def _widest_per_next(options: list[Option], threshold: float = 0.0) -> dict[Belief, Option]:
    best: dict[Belief, Option] = {}
    for o in options:
        w = o.hi - o.lo
        if w < threshold:
            continue
        cur = best.get(o.next)
        if cur is None or w > cur.hi - cur.lo:
            best[o.next] = o
    return best


def _widest(options: list[Option], threshold: float = 0.0) -> Option | None:
    best = None
    for o in options:
        w = o.hi - o.lo
        if w >= threshold and (best is None or w > best.hi - best.lo):
            best = o
    return best


# ---------------------------------------------------------------------- fewest bounces (BFS)
def bfs(problem: Problem, *, threshold: float = 0.0, max_bounces: int | None = None,
        accept: Callable[[Belief], bool] | None = None, deadline: Deadline = NEVER) -> tuple[Path | None, dict]:
    """Breadth-first search over beliefs using only options of width ≥ ``threshold``; with ``accept``, only
    goal options whose next belief it accepts end a plan (patrol entries must end on one known segment).

    Returns a plan with the fewest stages (the widest last stage among the goal options of the
    first belief found at that depth), or None once every belief reachable within ``max_bounces``
    − 1 stages has been expanded. *Optimality*: BFS visits beliefs in order of depth, and a plan with
    k stages is a path of k − 1 options followed by a goal option from a belief of depth ≤ k − 1;
    the first depth d at which some belief has a goal option gives k = d + 1, and none is shorter.
    On a timeout: None with ``timed_out`` (no plan has ≤ ``depth`` stages).
    """
    start = problem.start_belief
    parent: dict[Belief, tuple[Belief, Option] | None] = {start: None}
    level = [start]
    depth = 0
    while level:
        if max_bounces is not None and depth + 1 > max_bounces:
            return None, {"beliefs": len(parent), "depth": depth, "cut_by_budget": True}
        best: tuple[float, Belief, Option] | None = None
        for b in level:
            if deadline.expired():
                return None, {"beliefs": len(parent), "depth": depth, "cut_by_budget": False, "timed_out": True}
            goals = problem.goal_options(b)
            if accept is not None:
                goals = [o for o in goals if accept(o.next)]
            g = _widest(goals, threshold)
            if g is not None and (best is None or g.hi - g.lo > best[0]):
                best = (g.hi - g.lo, b, g)
        if best is not None:
            _, b, g = best
            path = [g]
            while parent[b] is not None:
                b, o = parent[b]  # type: ignore[misc]
                path.append(o)
            path.reverse()
            return path, {"beliefs": len(parent), "depth": depth}
        nxt = []
        bounded = len(start) > 1
        # options of width ≥ threshold are exactly those wider than the float just below it
        below = math.nextafter(threshold, 0.0) if threshold > 0.0 else 0.0
        for b in level:
            if deadline.expired():
                return None, {"beliefs": len(parent), "depth": depth + 1, "cut_by_budget": False, "timed_out": True}
            for o in _options_wider(problem, b, below):
                if o.hi - o.lo < threshold or o.next in parent:
                    continue
                if bounded:
                    d_n, h_n = problem.belief_bounds(o.next)
                    if h_n < threshold or d_n == INF or any((s,) in parent for s in o.next if len(o.next) > 1):
                        continue
                parent[o.next] = (b, o)
                nxt.append(o.next)
        level = nxt
        depth += 1
    return None, {"beliefs": len(parent), "depth": depth, "cut_by_budget": False}


def reachable(problem: Problem, *, threshold: float = 0.0, max_beliefs: int | None = None,
              deadline: Deadline = NEVER) -> tuple[dict[Belief, int], bool]:
    """Every belief reachable from the start belief with options of width ≥ ``threshold``, with its depth
    (fewest stages), by breadth-first search. Returns ``(depth, exhausted)``: ``exhausted`` is False when the
    search stopped at ``max_beliefs`` beliefs or at the deadline (then the set is a subset and proves nothing
    about the rest)."""
    depth: dict[Belief, int] = {problem.start_belief: 0}
    level = [problem.start_belief]
    while level:
        nxt = []
        for b in level:
            if deadline.expired():
                return depth, False
            for o in problem.options(b):
                if o.hi - o.lo < threshold or o.next in depth:
                    continue
                if max_beliefs is not None and len(depth) >= max_beliefs:
                    return depth, False
                depth[o.next] = depth[b] + 1
                nxt.append(o.next)
        level = nxt
    return depth, True


def fewest_stages(problem: Problem, max_bounces: int | None = None, *,
                  deadline: Deadline = NEVER) -> tuple[int | None, dict]:
    """The fewest stages of any plan, by A* over beliefs with h(b) = max_{s∈b} d(s) (the fewest stages
    from each segment alone, :attr:`Problem.singleton_bounds`). h is admissible (a plan from b is a plan
    from each {s}) and consistent (an option b → b′ takes each s ∈ b to some j ∈ b′, so d(s) ≤ 1 + d(j)
    ≤ 1 + h(b′)), so beliefs are expanded at most once, in order of f = depth + h, and the first belief
    with a goal option at f = depth + 1 gives the optimum. A belief is not queued when one of its segments
    alone was already reached with no more stages (subsumption). None when the queue empties (no plan) or
    when f exceeds the budget; None with ``timed_out`` on a timeout, and ``bound``: the smallest f queued, a
    lower bound on the stages of every plan.
    """
    start = problem.start_belief

    def h(b: Belief) -> float:
        return problem.belief_bounds(b)[0]

    depth: dict[Belief, int] = {start: 0}
    heap = [(h(start), 0, start)]
    expanded = 0
    while heap:
        if deadline.expired():
            return None, {"beliefs": len(depth), "expanded": expanded, "cut_by_budget": False, "timed_out": True,
                          "bound": heap[0][0]}
        f, g, b = heapq.heappop(heap)
        if f == INF:
            break
        if g > depth[b]:
            continue
        if max_bounces is not None and f > max_bounces:
            return None, {"beliefs": len(depth), "expanded": expanded, "cut_by_budget": True}
        expanded += 1
        if problem.goal_options(b):
            return g + 1, {"beliefs": len(depth), "expanded": expanded}
        for o in problem.options(b):
            nb = o.next
            if g + 1 < depth.get(nb, INF):
                if len(nb) > 1 and any(depth.get((s,), INF) <= g + 1 for s in nb):
                    continue  # subsumed: one of its segments alone was reached as early (a plan from nb is one from it)
                depth[nb] = g + 1
                f2 = g + 1 + h(nb)
                if f2 < INF:
                    heapq.heappush(heap, (f2, g + 1, nb))
    return None, {"beliefs": len(depth), "expanded": expanded, "cut_by_budget": False}


# ---------------------------------------------------------------------- bottleneck (max-min) paths
def bottleneck(problem: Problem, *, deadline: Deadline = NEVER) -> tuple[float, dict]:
    """The largest min width W* of any plan (no bounce budget), 0.0 if there is no plan.

    Dijkstra with max-min labels: a belief is settled with the largest bottleneck of any path to it
    (widths are non-negative and min is monotone, so the usual exchange argument holds: when the
    belief with the largest tentative label is taken from the queue, no other path can give it more).
    W* = max over settled beliefs b of min(label(b), widest goal option of b). Beliefs whose label
    cannot exceed the current W* are not expanded (they cannot lead to a better plan).

    With a start of several segments the queue is ordered by f(b) = min(label(b), h(b)) where h(b) =
    min over s ∈ b of the best min width from {s} alone (an upper bound on every completion, see
    :attr:`Problem.singleton_bounds`), a best-first branch and bound: as long as the best plan found is
    below W*, some belief of an optimal plan waits in the queue with f ≥ W*, so the search stops (when the
    largest f left is ≤ the best found) only at W*. Beliefs are re-expanded if their label improves. The
    best found starts at the width of a greedy plan (:func:`_greedy_plan`, a plan's width is ≤ W*), so
    that options no wider than it are never built.

    Each label keeps the option it came by; ``incumbent`` in the statistics is the plan of the best value (its
    options' widths are ≥ the labels along it, which never decrease towards the start, so it attains the value;
    the pointers form a tree: a label only changes with its pointer, and strictly grows), or the greedy plan
    while nothing beat it. On a timeout the statistics say ``timed_out`` and ``bound`` = max(best, largest f
    queued) ≥ W*.
    """
    start = problem.start_belief
    bounded = len(start) > 1
    bounds: dict[Belief, float] = {}  # h(b), once per belief (the same belief is offered by many options)

    def bound(b: Belief) -> float:
        if not bounded:
            return INF
        h = bounds.get(b)
        if h is None:
            h = bounds[b] = problem.belief_bounds(b)[1]
        return h

    label: dict[Belief, float] = {start: INF}
    parent: dict[Belief, tuple[Belief, Option]] = {}
    heap = [(-bound(start), INF, start)]
    best, greedy = _greedy_plan(problem, bound, deadline) if bounded else (0.0, None)
    best_at: tuple[Belief, Option] | None = None
    expanded = 0
    timed_out = False
    while heap:
        if deadline.expired():
            timed_out = True
            break
        neg_f, w_b, b = heapq.heappop(heap)
        if -neg_f <= best:
            break
        if w_b < label[b]:
            continue  # a stale entry: the label improved since
        expanded += 1
        g = _widest(problem.goal_options(b))
        if g is not None and min(w_b, g.hi - g.lo) > best:
            best, best_at = min(w_b, g.hi - g.lo), (b, g)
        for o in _options_wider(problem, b, best):
            w = min(w_b, o.hi - o.lo)
            if w <= best or w <= label.get(o.next, 0.0):
                continue
            f = min(w, bound(o.next))
            if f <= best or (bounded and _subsumed(label, o.next, w)):
                continue
            label[o.next] = w
            parent[o.next] = (b, o)
            heapq.heappush(heap, (-f, w, o.next))
    stats: dict = {"beliefs": len(label), "expanded": expanded}
    if best_at is not None:
        stats["incumbent"] = _pointer_path(parent, *best_at)
    elif greedy is not None:
        stats["incumbent"] = greedy
    if timed_out:
        stats.update(timed_out=True, bound=max(best, -heap[0][0]) if heap else best)
    return best, stats


def _pointer_path(parent: dict[Belief, tuple[Belief, Option]], belief: Belief, last: Option) -> Path:
    """The options from the start to ``belief`` by its label pointers, then ``last``."""
    path = [last]
    while belief in parent:
        belief, o = parent[belief]
        path.append(o)
        assert len(path) <= len(parent) + 1, "label pointers form a cycle"
    path.reverse()
    return path


def _greedy_plan(problem: Problem, bound: Callable[[Belief], float], deadline: Deadline = NEVER,
                 beam: int = 8) -> tuple[float, Path | None]:
    """The min width of one plan found by a small beam search and the plan ((0.0, None) if it finds none): a
    lower bound on W* that
    lets :func:`bottleneck` prune from its first expansion. From the start, layer by layer, keep the ``beam``
    unvisited beliefs with the smallest stage bound d(belief) (then the largest min(width so far, h)); stop
    at the first layer with a goal option (or after a few times the start's stage bound). The options it builds
    are cached by the problem, so the search reuses them."""
    start = problem.start_belief
    d0, _ = problem.belief_bounds(start)
    if d0 == INF:
        return 0.0, None
    layer: list[tuple[float, Belief, Path]] = [(INF, start, [])]
    seen = {start}
    for _ in range(4 * int(d0) + 8):
        if deadline.expired():
            return 0.0, None
        found, found_path = 0.0, None
        for w_b, b, path in layer:
            g = _widest(problem.goal_options(b))
            if g is not None and min(w_b, g.hi - g.lo) > found:
                found, found_path = min(w_b, g.hi - g.lo), [*path, g]
        if found_path is not None:
            return found, found_path
        children: dict[Belief, tuple[float, Path]] = {}
        for w_b, b, path in layer:
            for o in problem.options(b):
                w = min(w_b, o.hi - o.lo)
                if o.next in seen or w <= children.get(o.next, (0.0, []))[0]:
                    continue
                if min(w, bound(o.next)) > 0.0 and problem.belief_bounds(o.next)[0] < INF:
                    children[o.next] = (w, [*path, o])
        if not children:
            return 0.0, None
        # closest to the goal first (the stage bound d), then the widest
        ranked = sorted(children.items(), key=lambda item: (problem.belief_bounds(item[0])[0],
                                                            -min(item[1][0], bound(item[0]))))[:beam]
        layer = [(w, nb, path) for nb, (w, path) in ranked]
        seen.update(nb for _, nb, _ in layer)
    return 0.0, None


def _options_wider(problem: Problem, belief: Belief, threshold: float) -> list[Option]:
    """The options of ``belief`` wider than ``threshold`` (all of them, cached, when it is 0). An option's
    interval is the intersection of one admissible interval per element, so an element's intervals no wider
    than the threshold cannot contribute: they are dropped before the intersection is folded, which is where a
    search with a lower bound spends its time."""
    if threshold <= 0.0 or len(belief) == 1:
        return problem.options(belief)
    lists = []
    for s in belief:
        los, his, tgts = problem.intervals(s)
        keep = [k for k in range(len(los)) if his[k] - los[k] > threshold]
        lists.append(([los[k] for k in keep], [his[k] for k in keep], [tgts[k] for k in keep]))
    return [o for o in problem._combine(belief, lists, problem._merged, problem._finer) if o.hi - o.lo > threshold]


# ---------------------------------------------------------------------- the Pareto front bounces ↔ min width
def layered_front(problem: Problem, max_bounces: int | None, *, stop_at_first: bool = False,
                  deadline: Deadline = NEVER) -> Front:
    """The Pareto front (bounces, min width) by label setting in order of bounces.

    Each belief keeps the largest min width of any path of ≤ k options to it (its label after layer
    k); a new label (k, w) is dominated — and dropped — when the belief already has a label (k′ ≤ k,
    w′ ≥ w), or when w cannot beat the best plan found so far (a longer plan is on the front only if it
    is strictly more tolerant). Only beliefs whose label changed in layer k − 1 are relaxed in layer k
    (the others' candidates were already tried with fewer bounces). The front's point for k stages is
    max over beliefs b changed at layer k − 1 of min(label(b), widest goal option of b), kept when it
    beats the previous point. *Proof of optimality*: by induction on k the labels equal the best
    bottleneck of ≤ k-option paths (a best path's prefix is a best-or-dominated path: replacing it by
    a dominating prefix never lowers the bottleneck). The loop ends when no label changes (every
    further layer would repeat the last one: the front is complete) or at the budget.
    ``stop_at_first``: stop at the first point (fewest bounces, most tolerant among them).

    With a start of several segments, beliefs are also dropped when their bounds from single segments
    (:attr:`Problem.singleton_bounds`) show that no completion can beat the front or fit the budget
    (min(w, h(b′)) ≤ best, or k + d(b′) > K): both are upper/lower bounds on every completion.

    On a timeout the front found so far is returned with ``timed_out`` and ``bound`` = max(best, the largest
    label changed in the last finished layer, capped by h), an upper bound on every plan within the budget: a
    plan of minimal length among the best has a prefix of k − 1 options ending on such a belief (else a
    shorter prefix dominates it), and its min width is at most that belief's label.
    """
    start = problem.start_belief
    hist: dict[Belief, list[tuple[int, float, Belief | None, Option | None]]] = {start: [(0, INF, None, None)]}
    label: dict[Belief, float] = {start: INF}
    changed = [start]
    front = Front()
    best_total = 0.0
    bounded = len(start) > 1
    k = 0
    while changed:
        k += 1
        if max_bounces is not None and k > max_bounces:
            front.exhausted = False
            break
        if _front_timed_out(deadline, front, problem, changed, label, best_total, bounded):
            break
        cand: tuple[float, Belief, Option] | None = None
        for b in changed:
            w_b = label[b]
            g = _widest(problem.goal_options(b))
            if g is None:
                continue
            w = min(w_b, g.hi - g.lo)
            if w > best_total + WIDTH_EPS and (cand is None or w > cand[0]):
                cand = (w, b, g)
        front.scanned = k
        if cand is not None:
            best_total = cand[0]
            front.points.append((k, cand[0], _backtrack(hist, cand[1], k - 1) + [cand[2]]))
            if stop_at_first:
                front.exhausted = False
                break
        if max_bounces is not None and k == max_bounces:
            front.exhausted = False
            break
        improved: dict[Belief, tuple[float, Belief, Option]] = {}
        for b in changed:
            if _front_timed_out(deadline, front, problem, changed, label, best_total, bounded):
                break
            w_b = label[b]
            for o in problem.options(b):
                w = min(w_b, o.hi - o.lo)
                if w <= best_total + WIDTH_EPS or w <= label.get(o.next, 0.0):
                    continue
                if bounded:
                    d_n, h_n = problem.belief_bounds(o.next)
                    if min(w, h_n) <= best_total + WIDTH_EPS or d_n == INF:
                        continue
                    if max_bounces is not None and k + d_n > max_bounces:
                        front.budget_pruned = True
                        continue
                    if _subsumed(label, o.next, w):
                        continue
                cur = improved.get(o.next)
                if cur is None or w > cur[0]:
                    improved[o.next] = (w, b, o)
        if front.timed_out:
            break
        for nb, (w, b, o) in improved.items():
            label[nb] = w
            hist.setdefault(nb, []).append((k, w, b, o))
        changed = list(improved)
    front.beliefs = len(label)
    front.layers = k
    return front


def _front_timed_out(deadline: Deadline, front: Front, problem: Problem, changed: list[Belief],
                     label: dict[Belief, float], best: float, bounded: bool) -> bool:
    """On an expired deadline, mark ``front`` as cut and give it its bound (:func:`layered_front`)."""
    if not deadline.expired():
        return False
    top = best
    for b in changed:
        w = label[b]
        if bounded:
            w = min(w, problem.belief_bounds(b)[1])
        top = max(top, w)
    front.timed_out, front.exhausted, front.bound = True, False, min(top, math.pi)
    return True


def _subsumed(label: dict[Belief, float], belief: Belief, w: float) -> bool:
    """Is the label (belief, w) dominated by a label (s, w′ ≥ w) of one of its segments alone?

    A plan from a belief works from each of its subsets, so a belief is never better than a subset
    reached with a label at least as good (conformant planning's subsumption; only singletons are
    looked up, which is cheap). Labels are only ever pushed or improved, so the dominating singleton
    is itself searched from.
    """
    if len(belief) == 1:
        return False
    for s in belief:
        if label.get((s,), 0.0) >= w:
            return True
    return False


def _backtrack(hist, belief: Belief, layer: int) -> Path:
    """The path of ≤ ``layer`` options whose bottleneck is ``belief``'s label after that layer."""
    path: Path = []
    b, ell = belief, layer
    while True:
        entries = hist[b]
        entry = None
        for e in entries:
            if e[0] <= ell:
                entry = e
            else:
                break
        assert entry is not None
        k, _, parent, option = entry
        if parent is None:
            break
        path.append(option)
        b, ell = parent, k - 1
    path.reverse()
    return path


# ---------------------------------------------------------------------- sum of widths (DP over (belief, bounces))
def max_sum(problem: Problem, max_bounces: int, *, deadline: Deadline = NEVER) -> tuple[float | None, Path | None, dict]:
    """The plan with ≤ ``max_bounces`` stages maximising the sum of its widths.

    S_k(b) = the largest sum of widths of a walk of exactly k options from the start to b (walks may
    revisit beliefs: the sum rewards extra stages); S_0(start) = 0 and S_k(b′) = max over options
    b → b′ of S_{k−1}(b) + width (only the widest option per (b, b′) can be best). A plan with k
    stages scores S_{k−1}(b) + widest goal option of b. This is exact dynamic programming over the
    (belief, bounces) layers (Bellman's principle: the best k-walk to b′ extends a best (k−1)-walk).
    Ties go to fewer stages. On a timeout the best plan so far, with ``timed_out`` and ``bound`` = max(best,
    max_b S_{k−1}(b) + (K − k + 1)(π − 2δ)): no stage is wider than π − 2δ.
    """
    start = problem.start_belief
    layer: dict[Belief, float] = {start: 0.0}
    timed_out = False
    widest = math.pi - 2 * problem.heading_margin
    parents: list[dict[Belief, tuple[Belief, Option]]] = []
    best: tuple[float, int, Belief, Option] | None = None
    states = 1
    for k in range(1, max_bounces + 1):
        if deadline.expired():
            timed_out = True
            break
        for b, s in layer.items():
            g = _widest(problem.goal_options(b))
            if g is not None:
                total = s + (g.hi - g.lo)
                if best is None or total > best[0] + WIDTH_EPS:
                    best = (total, k, b, g)
        if k == max_bounces:
            break
        nxt: dict[Belief, float] = {}
        par: dict[Belief, tuple[Belief, Option]] = {}
        for b, s in layer.items():
            if deadline.expired():
                break
            for nb, o in _widest_per_next(problem.options(b)).items():
                v = s + (o.hi - o.lo)
                if v > nxt.get(nb, -1.0):
                    nxt[nb] = v
                    par[nb] = (b, o)
        if deadline.expired():
            timed_out = True
            break
        if not nxt:
            break
        parents.append(par)
        layer = nxt
        states += len(nxt)
    stats: dict = {"states": states}
    if timed_out:
        top = max(layer.values()) + (max_bounces - k + 1) * widest
        stats.update(timed_out=True, bound=top if best is None else max(best[0], top))
    if best is None:
        return None, None, stats
    total, k, b, g = best
    path = [g]
    for depth in range(k - 1, 0, -1):
        pb, o = parents[depth - 1][b]
        path.append(o)
        b = pb
    path.reverse()
    return total, path, stats


# ---------------------------------------------------------------------- constant strategies (Algorithm 2)
@dataclass
class _Label:
    belief: Belief
    lo: float
    hi: float
    depth: int
    parent: "_Label | None"
    option: Option | None


def widest_constant(problem: Problem, max_bounces: int | None, *,
                    deadline: Deadline = NEVER) -> tuple[tuple[float, float] | None, Path | None, dict]:
    """The widest constant interval (paper Algorithm 2, optimised): one interval I used at every stage.

    Labels are (belief, I) with I the running intersection of the options' intervals, starting from
    the whole admissible range [δ, π − δ]; a label (b, I) is dropped when b already holds a label
    (b, J) with J ⊇ I found with no more stages (every continuation of (b, I) is available to (b, J)
    with an interval at least as wide and no more stages), or when |I| cannot beat the best constant
    plan found so far (intersections only shrink; with several start segments also when the bound h(b)
    from single segments cannot beat it, or d(b) cannot fit the budget). Labels are expanded in order of
    stages, so the
    first plan of the largest width has the fewest stages. The interval ends are ends of admissible
    intervals, so there are finitely many labels and the search ends; when it ends with no plan, no
    constant interval survives (within the budget, if any). On a timeout the best plan so far, with
    ``timed_out`` and ``bound`` = max(best, widest running intersection of the frontier): intersections only
    shrink.
    """
    start = problem.start_belief
    d = problem.heading_margin
    root = _Label(start, d, math.pi - d, 0, None, None)
    bounded = len(start) > 1
    store: dict[Belief, list[_Label]] = {start: [root]}
    frontier = [root]
    best: tuple[float, _Label, Option, float, float] | None = None
    labels = 1
    depth = 0
    cut = False
    timed_out = False
    while frontier:
        if deadline.expired():
            timed_out = True
            break
        depth += 1
        if max_bounces is not None and depth > max_bounces:
            cut = True
            break
        best_w = best[0] if best else 0.0
        for lab in frontier:
            for g in problem.goal_options(lab.belief):
                lo, hi = max(lab.lo, g.lo), min(lab.hi, g.hi)
                if hi - lo > best_w + WIDTH_EPS:
                    best_w = hi - lo
                    best = (best_w, lab, g, lo, hi)
        if max_bounces is not None and depth == max_bounces:
            cut = bool(frontier)
            break
        best_w = best[0] if best else 0.0
        nxt: list[_Label] = []
        for lab in frontier:
            if deadline.expired():
                timed_out = True
                break
            for o in problem.options(lab.belief):
                lo, hi = max(lab.lo, o.lo), min(lab.hi, o.hi)
                if not hi - lo > best_w + WIDTH_EPS:
                    continue
                if bounded:
                    d_n, h_n = problem.belief_bounds(o.next)
                    if h_n <= best_w + WIDTH_EPS or d_n == INF or (max_bounces is not None and depth + d_n > max_bounces):
                        continue
                held = store.setdefault(o.next, [])
                if any(h.lo <= lo and hi <= h.hi for h in held):
                    continue
                if bounded and len(o.next) > 1 and any(
                    h.lo <= lo and hi <= h.hi for s in o.next for h in store.get((s,), ())
                ):
                    continue
                new = _Label(o.next, lo, hi, depth, lab, o)
                held.append(new)
                nxt.append(new)
                labels += 1
        if timed_out:
            break
        frontier = nxt
    stats: dict = {"labels": labels, "beliefs": len(store), "depth": depth, "cut_by_budget": cut}
    if timed_out:
        top = max((lab.hi - lab.lo for lab in frontier), default=0.0)
        stats.update(timed_out=True, bound=max(best[0] if best else 0.0, top))
    if best is None:
        return None, None, stats
    _, lab, g, lo, hi = best
    path = [g]
    node: _Label | None = lab
    while node is not None and node.option is not None:
        path.append(node.option)
        node = node.parent
    path.reverse()
    return (lo, hi), path, stats


def walk(problem: Problem, path: Path) -> list[tuple[Belief, Option]]:
    """Pair each option of a path with the belief it leaves (for building stages)."""
    out = []
    b = problem.start_belief
    for o in path:
        out.append((b, o))
        b = o.next
    return out
