"""LP and MILP formulations of the budgeted objectives (private backends of :mod:`.search`), via cvxpy.

Both work on the **time-expanded network** of the belief-state graph: a node (b, k) for every
belief b reachable by a walk of exactly k options (k = 0 .. K − 1), an arc (b, k) → (b′, k + 1) for
the widest option b → b′ (only the widest can be optimal), and an arc (b, k) → T for the widest goal
option of b. A plan with ≤ K stages is exactly a path from (start, 0) to T.

- ``sum`` as an **LP** (clarabel): maximise Σ wₐ xₐ over unit flows x ≥ 0 from (start, 0) to T. The
  network is acyclic, so the flow polytope's vertices are the paths (the node–arc incidence matrix is
  totally unimodular) and the LP optimum is the best path. The dual is min y_s − y_T subject to
  y_u − y_v ≥ w_uv; we report as ``bound`` the dual value of the solver's duals corrected by their
  largest infeasibility times K (any path has ≤ K arcs, so it is a valid upper bound even for
  slightly infeasible duals), and the path read off the primal support (by complementary slackness
  every arc carrying flow is tight, so every support path is optimal) with its exact value. The gap is
  bound − value.
- ``tolerance`` as a **MILP** (HiGHS through cvxpy): binary xₐ, maximise z subject to the flow constraints and
  z ≤ wₐ + π (1 − xₐ) (π bounds every width, so the constraint binds exactly on the arcs used). The
  solver's dual bound and gap are reported. A bottleneck path is not an LP (min over the path is not
  linear in the flow), hence the integrality.

These are cross-checks for small instances (the network has K × beliefs nodes); the label-setting
searches of :mod:`._search` are the default methods.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
from typing import Iterator

import numpy as np

from solverplan.errors import SolverFailed
from solverplan.plan._problem import Belief, Option, Problem
from solverplan.plan._search import Path, _widest, _widest_per_next

__all__ = ["sum_lp", "tolerance_milp"]


class _Network:
    def __init__(self, problem: Problem, max_bounces: int) -> None:
        self.nodes: dict[tuple[Belief, int], int] = {}
        self.tails: list[int] = []
        self.heads: list[int] = []
        self.weights: list[float] = []
        self.options: list[Option] = []
        start = problem.start_belief
        self.source = self._node((start, 0))
        self.sink = -1
        layer = [start]
        pending_goal: list[tuple[int, Option]] = []
        for k in range(max_bounces):
            nxt: dict[Belief, None] = {}
            for b in layer:
                u = self.nodes[(b, k)]
                g = _widest(problem.goal_options(b))
                if g is not None:
                    pending_goal.append((u, g))
                if k + 1 >= max_bounces:
                    continue
                for nb, o in _widest_per_next(problem.options(b)).items():
                    v = self._node((nb, k + 1))
                    self._arc(u, v, o)
                    nxt[nb] = None
            layer = list(nxt)
        self.sink = len(self.nodes)
        for u, g in pending_goal:
            self._arc(u, self.sink, g)
        self.n_nodes = len(self.nodes) + 1

    def _node(self, key: tuple[Belief, int]) -> int:
        if key not in self.nodes:
            self.nodes[key] = len(self.nodes)
        return self.nodes[key]

    def _arc(self, u: int, v: int, o: Option) -> None:
        self.tails.append(u)
        self.heads.append(v)
        self.weights.append(o.hi - o.lo)
        self.options.append(o)

    def incidence(self):
        import scipy.sparse as sp

        m = len(self.tails)
        rows = np.concatenate([self.tails, self.heads])
        cols = np.concatenate([np.arange(m), np.arange(m)])
        vals = np.concatenate([np.ones(m), -np.ones(m)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(self.n_nodes, m))

    def rhs(self) -> np.ndarray:
        b = np.zeros(self.n_nodes)
        b[self.source] = 1.0
        b[self.sink] = -1.0
        return b

    def path_from(self, flow: np.ndarray) -> Path:
        """Follow the arc of largest flow from the source to T."""
        out: dict[int, list[int]] = {}
        for a, u in enumerate(self.tails):
            out.setdefault(u, []).append(a)
        path: Path = []
        u = self.source
        for _ in range(self.n_nodes):
            if u == self.sink:
                return path
            arcs = out.get(u, [])
            if not arcs:
                break
            a = max(arcs, key=lambda k: flow[k])
            if flow[a] < 1e-6:
                break
            path.append(self.options[a])
            u = self.heads[a]
        raise SolverFailed("the LP's flow does not form a path from the start to the goal")


def _flow_network(problem: Problem, max_bounces: int, status_key: str) -> tuple[_Network, dict, tuple | None]:
    """The time-expanded network of the query, its size (``stats``) and its flow arrays (incidence matrix, right-hand
    side, arc widths); no arrays when no arc enters the goal (``stats[status_key]`` says so)."""
    net = _Network(problem, max_bounces)
    stats: dict = {"nodes": net.n_nodes, "arcs": len(net.tails)}
    if not any(h == net.sink for h in net.heads):
        return net, {**stats, status_key: "no arc into the goal"}, None
    return net, stats, (net.incidence(), net.rhs(), np.asarray(net.weights))


def sum_lp(problem: Problem, max_bounces: int) -> tuple[float | None, Path | None, dict]:
    """The sum-of-widths plan by LP over path flows (clarabel); see the module docstring."""
    import cvxpy as cp

    net, stats, arrays = _flow_network(problem, max_bounces, "lp_status")
    if arrays is None:
        return None, None, stats
    A, b, w = arrays
    x = cp.Variable(len(w), nonneg=True)
    balance = A @ x == b
    problem_lp = cp.Problem(cp.Maximize(w @ x), [balance])
    try:
        problem_lp.solve(solver=cp.CLARABEL, tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12, tol_ktratio=1e-10)
    except cp.error.SolverError as exc:
        raise SolverFailed(f"CLARABEL failed on the sum-of-widths LP: {exc}; installed solvers: "
                           f"{', '.join(cp.installed_solvers())}") from None
    if problem_lp.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):  # inaccurate: the gap below says how far
        raise SolverFailed(f"CLARABEL returned {problem_lp.status!r} for the sum-of-widths LP "
                           f"({net.n_nodes} nodes, {len(w)} arcs)")
    flow = np.asarray(x.value, dtype=float)
    path = net.path_from(flow)
    value = float(sum(o.hi - o.lo for o in path))
    y = np.asarray(balance.dual_value, dtype=float)
    bound = math.inf
    for sign in (1.0, -1.0):  # the dual's sign convention: take the one that is (nearly) dual feasible
        ys = sign * y
        violation = float(np.max(w - A.T @ ys, initial=0.0))
        candidate = float(b @ ys) + max(violation, 0.0) * max_bounces
        bound = min(bound, candidate) if violation < 1e-6 else bound
    if not math.isfinite(bound):
        raise SolverFailed("the sum-of-widths LP's duals are not dual feasible: no bound")
    bound = max(bound, value)
    return value, path, {**stats, "lp_status": problem_lp.status, "lp_value": float(problem_lp.value),
                         "bound": bound, "gap": bound - value, "solver": "CLARABEL"}


@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """Discard what native code writes to file descriptor 1 meanwhile (HiGHS prints a banner when it
    starts): stdout belongs to the CLI's JSON answers. The solver's status is checked instead."""
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError):  # no real stdout (embedded interpreters): nothing to protect
        yield
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def tolerance_milp(problem: Problem, max_bounces: int) -> tuple[float | None, Path | None, dict]:
    """The most tolerant plan with ≤ K stages by MILP (HiGHS through cvxpy); see the module docstring."""
    import cvxpy as cp

    if "HIGHS" not in cp.installed_solvers():
        raise SolverFailed(f"the tolerance MILP needs HiGHS; installed solvers: {', '.join(cp.installed_solvers())}")
    net, stats, arrays = _flow_network(problem, max_bounces, "milp_status")
    if arrays is None:
        return None, None, stats
    A, b, w = arrays
    x = cp.Variable(len(w), boolean=True)
    z = cp.Variable(nonneg=True)  # bounded by the arcs used: z ≤ wₐ where xₐ = 1
    big = math.pi
    milp = cp.Problem(cp.Maximize(z), [A @ x == b, z <= w + big * (1 - x)])
    try:
        with _quiet_stdout():
            milp.solve(solver=cp.HIGHS, mip_rel_gap=0.0, mip_abs_gap=1e-12)
    except cp.error.SolverError as exc:
        raise SolverFailed(f"HiGHS failed on the tolerance MILP: {exc}") from None
    if milp.status == cp.INFEASIBLE:
        return None, None, {**stats, "milp_status": milp.status}
    if milp.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
        raise SolverFailed(f"HiGHS returned {milp.status!r} for the tolerance MILP ({net.n_nodes} nodes, {len(w)} arcs)")
    path = net.path_from(np.round(np.asarray(x.value, dtype=float)))
    value = min(o.hi - o.lo for o in path)
    info = milp.solver_stats.extra_stats
    dual = getattr(info, "mip_dual_bound", None)
    bound = float(dual) if dual is not None and math.isfinite(float(dual)) else float(milp.value)
    bound = max(bound, value)
    return value, path, {**stats, "milp_status": milp.status, "milp_value": float(milp.value), "bound": bound,
                         "gap": bound - value, "solver": "HIGHS"}
