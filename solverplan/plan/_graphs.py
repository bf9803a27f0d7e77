"""Graph algorithms behind the patrol objectives (private): minimum mean cycles by Karp's algorithm and by
linear programming (cvxpy), negative-cycle detection (Bellman–Ford), strongly connected components.

Graphs are given as arrays: ``n`` nodes ``0..n-1`` and arcs ``src[k] → dst[k]`` with float weights ``w[k]``.
Cycles are returned as lists of arc indices in travel order.

Minimum mean cycle. λ* = min over cycles C of w(C)/|C|.

- **Karp** (1978): with D_k(v) the least weight of a walk of exactly k arcs ending at v (starting anywhere,
  D_0 = 0), λ* = min_v max_{0≤k<n} (D_n(v) − D_k(v)) / (n − k), over the v with D_n(v) finite.
- **LP**: maximise λ subject to π_v − π_u ≤ w_uv − λ for every arc. Its dual is the minimum-cost circulation
  of unit total flow, a convex combination of cycles; the support of an optimal dual holds a minimum mean
  cycle, and duality makes the LP value a proof of optimality (no cycle has a smaller mean).

>>> import numpy as np
>>> src, dst, w = np.array([0, 1, 1, 2]), np.array([1, 0, 2, 1]), np.array([1.0, 3.0, -1.0, 0.0])
>>> lam, cycle = karp_min_mean_cycle(3, src, dst, w)
>>> round(lam, 12), sorted(cycle)
(-0.5, [2, 3])
>>> round(lp_min_mean_cycle(3, src, dst, w)[0], 6)
-0.5
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from solverplan.errors import SolverFailed

__all__ = [
    "strong_components",
    "cycle_arcs_only",
    "karp_min_mean_cycle",
    "lp_min_mean_cycle",
    "find_negative_cycle",
    "KARP_MAX_NODES",
]

KARP_MAX_NODES = 6000
"""Karp keeps an (n + 1) × n table of walk weights; above this many nodes it is skipped (the LP remains)."""


def strong_components(n: int, src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Label of the strongly connected component of every node."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    if n == 0:
        return np.zeros(0, dtype=np.int64)
    graph = coo_matrix((np.ones(len(src)), (src, dst)), shape=(n, n)).tocsr()
    _, labels = connected_components(graph, directed=True, connection="strong")
    return labels.astype(np.int64)


def cycle_arcs_only(n: int, src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Mask of the arcs that lie on some cycle (both ends in one strongly connected component)."""
    if len(src) == 0:
        return np.zeros(0, dtype=bool)
    labels = strong_components(n, src, dst)
    return labels[src] == labels[dst]


def _grouped_min(values: np.ndarray, order: np.ndarray, starts: np.ndarray, nodes: np.ndarray, n: int):
    """Per node (arcs sorted by destination), the minimum of ``values`` and the arc achieving it."""
    out = np.full(n, np.inf)
    arg = np.full(n, -1, dtype=np.int64)
    if len(order) == 0:
        return out, arg
    v = values[order]
    mins = np.minimum.reduceat(v, starts)
    out[nodes] = mins
    # the first arc of each group achieving the minimum
    group = np.repeat(np.arange(len(starts)), np.diff(np.append(starts, len(order))))
    hit = v == mins[group]
    first = np.full(len(starts), -1, dtype=np.int64)
    idx = np.flatnonzero(hit)
    # reverse so that the first index wins in the assignment
    first[group[idx[::-1]]] = order[idx[::-1]]
    arg[nodes] = first
    return out, arg


def _by_destination(dst: np.ndarray):
    order = np.argsort(dst, kind="stable")
    d = dst[order]
    if len(d) == 0:
        return order, np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    starts = np.flatnonzero(np.concatenate([[True], d[1:] != d[:-1]]))
    return order, starts, d[starts]


def karp_min_mean_cycle(n: int, src: np.ndarray, dst: np.ndarray, w: np.ndarray) -> tuple[float, list[int]]:
    """λ* and a cycle of mean λ* (Karp's theorem for the value; the cycle is then a negative cycle of
    w − λ* − δ for a tiny δ, found by :func:`find_negative_cycle`). Raises :class:`SolverFailed` if the
    graph has no cycle or more than :data:`KARP_MAX_NODES` nodes."""
    src, dst, w = np.asarray(src, dtype=np.int64), np.asarray(dst, dtype=np.int64), np.asarray(w, dtype=float)
    if n > KARP_MAX_NODES:
        raise SolverFailed(f"Karp's algorithm needs an (n+1)×n table: n = {n} > {KARP_MAX_NODES}")
    order, starts, nodes = _by_destination(dst)
    D = np.full((n + 1, n), np.inf)
    D[0] = 0.0
    for k in range(1, n + 1):
        D[k], _ = _grouped_min(D[k - 1][src] + w, order, starts, nodes, n)
    finite = np.isfinite(D[n])
    if not finite.any():
        raise SolverFailed("the graph has no cycle: no minimum mean cycle")
    ks = np.arange(n)
    with np.errstate(invalid="ignore"):
        ratios = (D[n][None, :] - D[:n]) / (n - ks)[:, None]
    ratios = np.where(np.isfinite(D[:n]), ratios, -np.inf)
    worst = ratios.max(axis=0)
    lam = float(np.min(worst[finite]))
    scale = 1.0 + float(np.max(np.abs(w))) if len(w) else 1.0
    for delta in (1e-10, 1e-8, 1e-6):
        cycle = find_negative_cycle(n, src, dst, w - lam - delta * scale)
        if cycle is not None:
            return lam, cycle
    raise SolverFailed(f"Karp's value λ* = {lam!r} but no cycle of that mean was found")  # pragma: no cover


def lp_min_mean_cycle(n: int, src: np.ndarray, dst: np.ndarray, w: np.ndarray, *,
                      solver: str | None = None) -> tuple[float, list[int], str]:
    """λ* by the LP of the minimum mean cycle in cvxpy, a cycle from the support of the optimal dual, and the solver name.

    Raises :class:`SolverFailed` when the solver does not report an optimal solution.
    """
    import cvxpy as cp
    from scipy.sparse import coo_matrix

    src, dst, w = np.asarray(src, dtype=np.int64), np.asarray(dst, dtype=np.int64), np.asarray(w, dtype=float)
    m = len(src)
    if m == 0:
        raise SolverFailed("the graph has no arcs: no minimum mean cycle")
    rows = np.concatenate([np.arange(m), np.arange(m)])
    cols = np.concatenate([dst, src])
    vals = np.concatenate([np.ones(m), -np.ones(m)])
    incidence = coo_matrix((vals, (rows, cols)), shape=(m, n)).tocsr()
    pi = cp.Variable(n)
    lam = cp.Variable()
    constraint = incidence @ pi + lam <= w
    problem = cp.Problem(cp.Maximize(lam), [constraint])
    chosen = solver or ("CLARABEL" if "CLARABEL" in cp.installed_solvers() else None)
    try:
        problem.solve(solver=chosen)
    except cp.error.SolverError as exc:
        raise SolverFailed(f"{chosen or 'cvxpy'} failed on the minimum-mean-cycle LP: {exc}; installed solvers: "
                           f"{', '.join(cp.installed_solvers())}") from None
    if problem.status != cp.OPTIMAL:
        raise SolverFailed(f"{problem.solver_stats.solver_name} returned {problem.status!r} for the minimum-mean-cycle LP "
                           f"(unbounded means the graph has no cycle); installed solvers: {', '.join(cp.installed_solvers())}")
    value = float(np.asarray(lam.value))  # solved: the variable has a value
    flow = np.asarray(constraint.dual_value, dtype=float).reshape(-1)
    cycle = _cycle_in_support(n, src, dst, flow)
    if cycle is None:  # pragma: no cover - the dual of an optimal LP always holds a cycle
        scale = 1.0 + float(np.max(np.abs(w)))
        cycle = find_negative_cycle(n, src, dst, w - value - 1e-7 * scale)
    if cycle is None:  # pragma: no cover
        raise SolverFailed("the LP's optimal dual holds no cycle")
    return value, cycle, problem.solver_stats.solver_name


def _cycle_in_support(n: int, src: np.ndarray, dst: np.ndarray, flow: np.ndarray) -> list[int] | None:
    """A cycle among the arcs carrying the largest flows of a circulation (greedy walk, heaviest arc first)."""
    if not np.all(np.isfinite(flow)) or flow.max() <= 0:
        return None
    threshold = 1e-6 * flow.max()
    out: dict[int, int] = {}
    for k in np.argsort(-flow):
        if flow[k] < threshold:
            break
        u = int(src[k])
        if u not in out:
            out[u] = int(k)
    start = int(src[int(np.argmax(flow))])
    seen: dict[int, int] = {}
    path: list[int] = []
    u = start
    while u not in seen:
        if u not in out:
            return None
        seen[u] = len(path)
        k = out[u]
        path.append(k)
        u = int(dst[k])
    return path[seen[u]:]


def find_negative_cycle(n: int, src: Sequence[int] | np.ndarray, dst: Sequence[int] | np.ndarray,
                        w: Sequence[float] | np.ndarray, *, max_rounds: int | None = None) -> list[int] | None:
    """A cycle of negative total weight (its arcs in order), or ``None`` if there is none.

    Bellman–Ford from a virtual source joined to every node by a 0-weight arc, vectorised over the arcs;
    after every round the parent pointers are checked for a cycle (pointer doubling). A cycle of parent
    pointers of a label-correcting algorithm always has negative weight (Tarjan), and if a negative cycle
    exists the labels never settle, so within n rounds one appears (or the labels are still changing in
    round n, and walking n parents back from a changed node lands on one).
    """
    src = np.asarray(src, dtype=np.int64)
    dst = np.asarray(dst, dtype=np.int64)
    w = np.asarray(w, dtype=float)
    if len(src) == 0:
        return None
    order, starts, nodes = _by_destination(dst)
    dist = np.zeros(n)
    parent = np.full(n, -1, dtype=np.int64)  # arc index
    rounds = n + 1 if max_rounds is None else max_rounds
    for r in range(rounds):
        best, arg = _grouped_min(dist[src] + w, order, starts, nodes, n)
        scale = np.maximum(1.0, np.abs(dist))
        better = best < dist - 1e-12 * scale
        if not better.any():
            return None
        dist = np.where(better, best, dist)
        parent = np.where(better, arg, parent)
        cycle = _parent_cycle(n, src, dst, w, parent)
        if cycle is not None:
            return cycle
    return None  # pragma: no cover - a negative cycle shows up in the parents within n rounds


def _parent_cycle(n: int, src: np.ndarray, dst: np.ndarray, w: np.ndarray, parent: np.ndarray) -> list[int] | None:
    """A cycle of the parent-pointer graph (node → node of its parent arc) with negative weight, if any."""
    has = parent >= 0
    nxt = np.where(has, src[np.maximum(parent, 0)], -1)
    # pointer doubling: after ⌈log2 n⌉ + 1 doublings every node that reaches a cycle sits on it
    jump = nxt.copy()
    for _ in range(max(1, math.ceil(math.log2(max(n, 2)))) + 1):
        ok = jump >= 0
        jump = np.where(ok, jump[np.maximum(jump, 0)], -1)
    candidates = np.unique(jump[jump >= 0])
    for v in candidates.tolist():
        # walk from v along parents until it repeats
        seen: dict[int, int] = {}
        path: list[int] = []
        u = v
        while u >= 0 and u not in seen:
            seen[u] = len(path)
            k = int(parent[u])
            if k < 0:
                break
            path.append(k)
            u = int(src[k])
        if u < 0 or u not in seen:
            continue
        arcs = path[seen[u]:]
        arcs.reverse()  # parents were walked backwards
        if float(np.sum(w[arcs])) < 0:
            return arcs
    return None
