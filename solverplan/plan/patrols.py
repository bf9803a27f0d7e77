"""Patrolling (paper Def. 15, §7.2) with optimally contracting cycles (§8.3): a strategy that brings the robot
from any point of a start set S into a **stable** cycle visiting a required sequence of edges E = (e_1 … e_k) in
order, forever.

**The search space.** Stages are arcs of the safe bounce visibility graph (every point of the source segment
lands inside the target segment for every heading of the stage's interval), with the interval of each arc
chosen for the required tolerance ε (the half-width of every heading interval) at the *contracting end* of its
safe interval (:mod:`solverplan.plan._choices`: the worst case of C over the interval is a closed form). The
sequence automaton is multiplied in: a product node (s, q, h) says the robot is on segment s, its last required
visit was e_q, and it has made h bounces since (h ≤ H, the allowed *intermediate bounces* between consecutive
required visits, ``max_between``). Landing on e_{q+1} advances q and resets h. Every cycle of this product is a
patrol cycle (h cannot return without an advance, so a cycle visits all of E, in order, a whole number of
times), and every patrol cycle with at most H intermediate bounces between required visits is a cycle of it.
Without ``max_between`` the smallest H that admits a cycle is used (H = 0: the robot bounces only on the listed
edges).

**Objectives** (weights w = log of the worst-case contraction coefficient of the arc, Def. 11–12):

- ``contraction`` (a): for a required tolerance ε, the cycle through E *once* (one period) with the smallest
  worst-case contraction Π C_k. With h in the state the one-period product is a DAG, so dynamic programming over
  it is exact: the answer is optimal among all one-period patrols of the class (``search-exhausted``, gap
  ``|value − bound|`` ≈ 0 over that class). A second DP without the bound on h (H = number of segments, enough
  when no within-layer cycle contracts: shortest walks are then simple) bounds all classes; if a cycle between
  two required visits contracts, repeating it drives the per-period contraction to 0 and the bound is 0 —
  reported as ``bound_all_classes`` (a wider class than the claim's scope, so not a gap).
- ``tolerance`` (b): the largest ε for which some patrol cycle contracts (worst case < 1): a negative cycle of
  w(ε). w is increasing in ε and arcs only disappear as ε grows, so feasibility is monotone and bisection
  with negative-cycle detection (Bellman–Ford) brackets ε* (``bisection``: the bracket's upper end is the
  bound, its width the gap).
- ``rate`` (c): the smallest worst-case contraction *per bounce*, exp of the minimum mean cycle of the product —
  solved both as the LP max λ s.t. π_v − π_u ≤ w_uv − λ (cvxpy; duality proves it) and by Karp's algorithm, and
  the two must agree. The min mean cycle of the product *without* the bound on h (cycles between two required
  visits allowed) is a lower bound over every class, reported as ``bound_all_classes``.

A start set S restricts the cycle to the segments a safe plan from S reaches with certainty, found by a
belief search with caps; when a cap is hit, nothing the answer says is proved (``proved`` false, the caps in
``optimality.limits``; an answer without a cycle is then ``not-found``, not ``infeasible``). A ``timeout``
(seconds) is such a cap too: the reachability sweep, the classes H and the bisection stop at the deadline and
answer the best cycle found so far (for ``tolerance``, the bracket reached) or ``not-found``, with the timeout in
``optimality.limits``. The safe BVG and each class's product and solve are not interrupted.

Every answer reports the cycle's stages and intervals, its worst-case contraction (exact, from rational
directions inside the intervals), the exact affine return map of the nominal headings (interval midpoints,
exact directions :class:`~solverplan.bounce.dynamics.ExactHeading`), its fixed point and orbit, and the cycles
needed to shrink the position set below a length ε (Cor. 4 for the nominal heading; and for the set-valued map
of the whole intervals, whose positions converge to an attractor of positive width).

The problem is NP-hard in general (the paper reduces it to TSP); here it is polynomial *per class H*, and H is
the stated bound of every claim.

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> p = patrol(square, "e0,e1,e2,e3", tolerance=0.05, objective="contraction")
>>> p.status.value, [s.step.from_edge for s in p.cycle], p.max_between
('found', [0, 1, 2, 3], 0)
>>> round(p.contraction, 6) == round(math.tan(0.001 + 0.1) ** 4, 6)    # tan(δ + 2ε) per bounce (right angles)
True
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Sequence

import numpy as np

from solverplan.choices import PatrolObjective
from solverplan._docstrings import fill_doc
from solverplan.bounce.bvg import SafeBVG, safe_bounce_visibility_graph
from solverplan.bounce.dynamics import ExactHeading, cycles_to_epsilon
from solverplan.interval import Interval
from solverplan.bounce.partitions import Partition, partition
from solverplan.bounce.transitions import affine_map
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError, InvalidBoundarySet, SolverFailed
from solverplan.exact import ExactPoint, format_number
from solverplan.limits import refuse_beyond_memory
from solverplan.plan import _search
from solverplan.plan._choices import ArcChoices, arc_choices, max_tolerance
from solverplan.plan._deadline import NEVER, Deadline, deadline_of
from solverplan.plan._problem import Problem
from solverplan.plan._walls import PartitionedWalls, cut_partition
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN, DEFAULT_SAFE_MARGIN, MARGIN_DOCS, Margins
from solverplan.plan._graphs import (
    KARP_MAX_NODES,
    cycle_arcs_only,
    find_negative_cycle,
    karp_min_mean_cycle,
    lp_min_mean_cycle,
)
from solverplan.plan._results import OnPartition, heading_cone
from solverplan.plan.search import straight_walls_graph
from solverplan.result import AffineStep, Answer, EnvironmentRecord, Method, Optimality, Reader, Stage, Stats, Status, answer_dataclass

__all__ = ["DEFAULT_TOLERANCE", "PatrolPoint", "Patrol", "patrol", "parse_visit"]

logger = logging.getLogger(__name__)

OBJECTIVES = PatrolObjective.values()

DEFAULT_TOLERANCE = 0.01
"""Radians: the heading tolerance ε (half-width of every interval) used by objectives ``contraction`` and
``rate`` when none is given."""

MAX_ENTRY_BELIEFS = 200_000
"""The reachability sweep from a start set stops after this many beliefs (and says so: the answer is then not
proved); the sweep is exhaustive below it."""

MAX_BETWEEN_SEARCHED = 3
"""Without ``max_between``, the classes H = 0, 1, … up to this many intermediate bounces are tried in turn."""

_EPS_FLOOR = 1e-7  # smallest tolerance bisection considers (radians)
_AGREE = 1e-6  # LP and Karp values must agree to this (absolute, in log C per bounce)


# ---------------------------------------------------------------------- results
@dataclass(frozen=True, slots=True)
class PatrolPoint:
    """A contact point of the nominal cycle: edge, exact t and point."""

    edge: int
    segment: int
    t: Fraction
    point: ExactPoint

    def to_json(self) -> dict:
        return {"edge": self.edge, "segment": self.segment, "t": float(self.t), "t_exact": format_number(self.t),
                "point": [float(self.point[0]), float(self.point[1])]}


@answer_dataclass("patrol", kw_only=True)
class Patrol(OnPartition, Answer):
    """A patrol strategy (``docs/contract.md``: cycle answer) or the reason there is none.

    Attributes
    ----------
    status, reason
        A :class:`~solverplan.result.Status`: ``found``; ``not-contracting`` (the best cycle of the class
        exists but does not contract: proved); ``infeasible`` (no patrol cycle of the class: proved); or
        ``not-found`` when the search for the segments reachable from the start set hit a cap (its caps are
        in ``optimality.limits``: nothing is proved) — and why.
    optimality
        How the objective's optimum is established (:class:`~solverplan.result.Optimality`): its method,
        bound and ``scope`` (the class of patrols it holds for: at most ``max_between`` intermediate bounces
        between required visits; for ``contraction`` one period), with ``gap`` = ``|value − bound|`` over that
        same scope (the bisection bracket's width for ``tolerance``).
    bound_all_classes, bound_all_classes_note
        A bound over a *wider* class (any number of intermediate bounces) for ``contraction`` (one-period
        contraction) and ``rate`` (contraction per bounce), and what it says; ``None`` when none was computed.
        Not a gap: the answer is optimal only within ``optimality.scope``.
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of the environment.
    visit, objective, tolerance, max_between
        The query: required edges in order, objective, heading tolerance ε (radians, half-width; for
        ``tolerance`` the best found) and the class H of intermediate bounces.
    entry, cycle
        Stages (:class:`~solverplan.result.Stage`) from the start set into the cycle (a safe-BVG plan over
        beliefs), and the cycle's stages, each with one source and one target segment and its exact affine
        map ``affine`` (:class:`~solverplan.result.AffineStep`: edges, nominal heading — the interval's
        midpoint — and its exact direction, the map t ↦ α t + β, the worst-case coefficient C over the
        interval, the transition and corner angle φ).
    contraction, contraction_exact
        Worst case of Π C_k over the cycle's intervals (rational directions inside them), float and exact.
    rate
        contraction ** (1 / len(cycle)): the worst-case contraction per bounce.
    periods
        How many times the cycle passes through E.
    nominal_alpha, nominal_beta, points
        The exact return map t ↦ α t + β of the nominal headings on the first stage's edge, and the orbit of
        its fixed point t* = β / (1 − α) (one contact point per stage).
    attractor
        Width (arc length) of the set of positions on the first segment the whole intervals converge to.
    epsilon, cycles_to_epsilon, cycles_to_epsilon_nominal
        With a length ``epsilon``: cycles until the position set (the whole first segment at the start) is at
        most ε wide — for the set-valued map of the intervals (None if its attractor is wider), and by
        Cor. 4 for the nominal heading.
    solvers
        Values of the different solvers (LP, Karp, DP, bisection bracket) for the record.
    stats
        Times (recorded, never asserted).
    partition
        The partition P′ (not serialised): for rollouts and certificates; ``env`` is its environment.

    Examples
    --------
    >>> import solverplan as sp
    >>> guard = sp.patrol(sp.load_environment("l_shape"), "e0,e4")      # visit edge 0, then edge 4, forever
    >>> guard.status.value, guard.max_between, len(guard.cycle), guard.periods
    ('found', 1, 4, 1)
    >>> [(stage.from_segment, stage.to_segment) for stage in guard.cycle]   # segments of P′
    [(0, 9), (9, 6), (6, 7), (7, 0)]
    >>> round(guard.rate, 4), guard.optimality.proved                     # worst-case contraction per bounce
    (0.021, True)
    """

    status: Status
    optimality: Optimality
    environment: EnvironmentRecord
    partition: Partition = field(repr=False, compare=False)
    reason: str
    visit: tuple[int, ...]
    objective: str
    tolerance: float | None
    max_between: int | None
    start: BoundarySet | None = None
    entry: tuple[Stage, ...] = ()
    cycle: tuple[Stage, ...] = ()
    contraction: float | None = None
    contraction_exact: Fraction | None = None
    rate: float | None = None
    periods: int = 0
    nominal_alpha: Fraction | None = None
    nominal_beta: Fraction | None = None
    points: tuple[PatrolPoint, ...] = ()
    attractor: float | None = None
    epsilon: float | None = None
    cycles_to_epsilon: int | None = None
    cycles_to_epsilon_nominal: int | None = None
    bound_all_classes: float | None = None
    bound_all_classes_note: str = ""
    solvers: dict = field(default_factory=dict)
    stats: Stats = field(default_factory=Stats, compare=False)


    @property
    def segments(self) -> tuple[int, ...]:
        """The cycle's segments in order (the source of each stage)."""
        return tuple(s.from_segment for s in self.cycle)

    @property
    def fixed_point(self) -> PatrolPoint:
        return self.points[0]

    def rollout_spec(self):
        """``(stages, targets, repeat_from)`` for :class:`solverplan.simulate.StagePolicy`: every heading
        interval in order (entry, then the cycle, which repeats), and the segments each stage must land on."""
        part = self.partition
        intervals = [s.interval for s in self.entry] + [s.interval for s in self.cycle]
        targets = [tuple(part.segments[t] for t in s.to_segments) for s in (*self.entry, *self.cycle)]
        return tuple(intervals), tuple(targets), len(self.entry)

    def _fields(self) -> dict:
        out: dict = {
            "reason": self.reason,
            "visit": [f"e{e}" for e in self.visit],
            "objective": self.objective,
            "tolerance": self.tolerance,
            "max_between": self.max_between,
            "start": None if self.start is None else str(self.start),
            "entry": [s.to_json() for s in self.entry],
            "cycle": [s.to_json() for s in self.cycle],
            "bounces": len(self.cycle),
            "periods": self.periods,
            "contraction": self.contraction,
            "contraction_exact": None if self.contraction_exact is None else format_number(self.contraction_exact),
            "rate": self.rate,
            "return_map": None if self.nominal_alpha is None else {
                "edge": self.cycle[0].step.from_edge,
                "alpha": format_number(self.nominal_alpha),
                "beta": format_number(self.nominal_beta if self.nominal_beta is not None else 0),
                "nominal_contraction": float(abs(self.nominal_alpha)),
            },
            "fixed_point": [p.to_json() for p in self.points],
            "attractor_width": self.attractor,
            "bound_all_classes": self.bound_all_classes,
            "bound_all_classes_note": self.bound_all_classes_note,
            "solvers": self.solvers,
        }
        if self.epsilon is not None:
            out.update(epsilon=self.epsilon, cycles_to_epsilon=self.cycles_to_epsilon, cycles_to_epsilon_nominal=self.cycles_to_epsilon_nominal)
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> Patrol:
        """Read a patrol answer back in ``env`` (required: its stages name segments of P′ of ``env``)."""
        r = Reader(data, "patrol")
        env, record = r.in_environment(env, 'patrol')
        ret = r.sub("return_map") if r.has("return_map") else None
        start = r.string("start", None)
        exact = r.get("contraction_exact", None)
        points = tuple(PatrolPoint(p.integer("edge"), p.integer("segment"), p.exact("t_exact"),
                                   env.exact_point_at(p.integer("edge"), p.exact("t_exact")))
                       for p in r.items("fixed_point"))
        tolerance, between = r.get("tolerance", None), r.get("max_between", None)
        return cls(status=r.status(), optimality=r.optimality(), environment=record or EnvironmentRecord.of(env),
                   partition=partition(env), reason=r.string("reason", ""),
                   visit=tuple(parse_visit(env, ",".join(r.texts("visit")))) if r.array("visit") else (),
                   objective=r.string("objective"), tolerance=None if tolerance is None else r.number("tolerance"),
                   max_between=None if between is None else r.integer("max_between"),
                   start=None if start is None else env.boundary_set(start),
                   entry=tuple(Stage.from_json(st.data, st.where) for st in r.items("entry")),
                   cycle=tuple(Stage.from_json(st.data, st.where) for st in r.items("cycle")),
                   contraction=r.number("contraction", None),
                   contraction_exact=None if exact is None else r.exact("contraction_exact"),
                   rate=r.number("rate", None), periods=r.integer("periods", 0),
                   nominal_alpha=None if ret is None else ret.exact("alpha"),
                   nominal_beta=None if ret is None else ret.exact("beta"), points=points,
                   attractor=r.number("attractor_width", None), epsilon=r.number("epsilon", None),
                   cycles_to_epsilon=r.integer("cycles_to_epsilon", None),
                   cycles_to_epsilon_nominal=r.integer("cycles_to_epsilon_nominal", None),
                   bound_all_classes=r.number("bound_all_classes", None),
                   bound_all_classes_note=r.string("bound_all_classes_note", ""),
                   solvers=dict(r.sub("solvers").data) if r.has("solvers") else {}, stats=r.stats())

    def to_text(self, *, width: int = 100) -> str:
        seq = " → ".join(f"e{e}" for e in self.visit)
        lines = [f"patrol of {seq} in {self.environment.name or 'the environment'} (objective {self.objective}): "
                 f"{self.status.value}"]
        if self.reason:
            lines.append(f"reason: {self.reason}")
        if self.tolerance is not None:
            lines.append(f"tolerance ε = {self.tolerance:.6g} rad; intermediate bounces ≤ {self.max_between}")
        for k, s in enumerate(self.entry):
            lines.append(f"  entry {k}: {list(s.from_segments)} → {list(s.to_segments)}  θ ∈ [{s.interval.lo:.6f}, {s.interval.hi:.6f}]")
        for k, s in enumerate(self.cycle):
            a = s.step
            lines.append(f"  cycle {k}: seg {s.from_segment} (e{a.from_edge}) → seg {s.to_segment} (e{a.to_edge})  "
                         f"θ ∈ [{s.interval.lo:.6f}, {s.interval.hi:.6f}]  C ≤ {a.contraction:.4g}")
        if self.contraction is not None:
            lines.append(f"worst-case contraction per cycle {self.contraction:.6g}, per bounce {self.rate:.6g} "
                         f"({len(self.cycle)} bounces, {self.periods} pass(es) of the sequence)")
        for p in self.points:
            lines.append(f"  fixed point e{p.edge}: t = {float(p.t):.12g} at ({float(p.point[0]):.9g}, {float(p.point[1]):.9g})")
        if self.attractor is not None:
            lines.append(f"positions converge to a set {self.attractor:.3g} wide (intervals' spread)")
        if self.epsilon is not None:
            lines.append(f"cycles to ε = {self.epsilon:g}: {self.cycles_to_epsilon} (intervals), "
                         f"{self.cycles_to_epsilon_nominal} (nominal heading, Cor. 4)")
        lines.append(f"optimality: {self.optimality.to_text()}")
        if self.bound_all_classes is not None or self.bound_all_classes_note:
            bound = "" if self.bound_all_classes is None else f" {self.bound_all_classes:.6g}"
            note = f" ({self.bound_all_classes_note})" if self.bound_all_classes_note else ""
            lines.append(f"bound over all classes:{bound}{note}")
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- input
def parse_visit(env: Environment, visit: str | Sequence[int]) -> tuple[int, ...]:
    """The required edge sequence: ``"e2,e5,e9"`` or edge ids. Whole edges only."""
    if isinstance(visit, str):
        pieces = env.boundary_set(visit).pieces
        for p in pieces:
            if p.t0 != 0 or p.t1 != 1:
                raise InvalidBoundarySet(f"patrol edges are whole edges: {p} is part of an edge")
        edges = tuple(p.edge for p in pieces)
    else:
        ids: list[int] = []
        for e in visit:
            if isinstance(e, bool) or not isinstance(e, (int, np.integer)):
                raise InputError(f"patrol edge {e!r} is not an edge id")
            env._check_edge_id(int(e))
            ids.append(int(e))
        edges = tuple(ids)
    if not edges:
        raise InputError("a patrol needs at least one edge to visit")
    return edges


def _start_set(env: Environment, start) -> BoundarySet | None:
    if start is None:
        return None
    if isinstance(start, str):
        return env.boundary_set(start)
    if isinstance(start, BoundarySet):
        return start
    raise InputError(f"start set {start!r}: expected a boundary set such as 'e3:0.25:0.75,e4'")


class _Entry:
    """Entry plans from the start set into a patrol cycle, by the planners' own engine: the belief-state problem
    of the safe BVG (:class:`~solverplan.plan._problem.Problem`, under the query's margins) and its exhaustive
    breadth-first searches. An entry stage is one option of the problem at least 2ε wide; an entry ends on *one*
    known segment of the cycle (the cycle's stages depend on the segment)."""

    def __init__(self, graph: SafeBVG, start: BoundarySet, margins: Margins, deadline: Deadline = NEVER,
                 walls: PartitionedWalls | None = None) -> None:
        self.graph, self.start, self.margins, self.deadline, self.walls = graph, start, margins, deadline, walls
        # entries land on whole segments (an entry ends on one known segment of the cycle): landing units only for
        # the start set's pieces
        self.problem = Problem(graph, start, None, margins=margins, walls=walls, landing_units=False)
        self.start_belief = self.problem.start_belief
        self._singletons: dict[float, tuple[frozenset[int], tuple[str, ...]]] = {}

    def singletons(self, eps: float) -> tuple[frozenset[int], tuple[str, ...]]:
        """The segments some entry reaches with certainty (singleton beliefs), every belief reachable with
        stages ≥ 2ε wide searched (beliefs never grow, so the sweep is finite), and the cap it hit if it stopped
        at :data:`MAX_ENTRY_BELIEFS` beliefs (then the set may miss segments: nothing is proved)."""
        if eps not in self._singletons:
            depth, exhausted = _search.reachable(self.problem, threshold=2 * eps, max_beliefs=MAX_ENTRY_BELIEFS,
                                                 deadline=self.deadline)
            found = frozenset(self.problem.segment(b[0]) for b in depth if len(b) == 1)
            cap = (self.deadline.limit(f"{len(depth)} beliefs of the reachability sweep") if self.deadline.hit
                   else f"max_beliefs={MAX_ENTRY_BELIEFS}")
            self._singletons[eps] = (found, () if exhausted else (cap,))
        return self._singletons[eps]

    def plan(self, targets: dict[int, int], eps: float) -> tuple[tuple[Stage, ...], int] | None:
        """The fewest-stage entry onto one segment of ``targets`` with stages ≥ 2ε wide (in the user's numbering:
        :meth:`Problem.user_stage`), and that segment (of the search). ``targets`` maps each cycle segment to the
        corner the cycle's arc from it runs into (0 for none): an entry that arrives near that corner is not
        accepted (no corner ping-pong across the junction)."""
        if len(self.start_belief) == 1 and self.start_belief[0] in targets:
            return (), self.start_belief[0]
        part = self.graph.partition
        goal = BoundarySet(tuple(BoundaryPiece(part.segments[s].edge, part.segments[s].t0, part.segments[s].t1)
                                 for s in sorted(targets)))
        if self.walls is not None:  # the problem takes its sets in the user's numbering
            goal = self.walls.to_user_set(goal)
        problem = Problem(self.graph, self.start, goal, margins=self.margins, walls=self.walls, landing_units=False)
        n = problem.n_segments

        def accept(belief) -> bool:
            if len(belief) != 1:
                return False
            tag = belief[0] // n
            return not tag & targets.get(belief[0] % n, 0)

        path, _ = _search.bfs(problem, threshold=2 * eps, accept=accept, deadline=self.deadline)
        if path is None:
            return None
        stages = tuple(problem.user_stage(belief, o, Interval(o.lo, o.hi)) for belief, o in _search.walk(problem, path))
        return stages, problem.segment(path[-1].next[0])


# ---------------------------------------------------------------------- the product graph
Visits = tuple[np.ndarray, ...]
"""For every required visit in order, a boolean mask over the searched segments: the segments landing on which is
that visit (the segments of the visited edge's part of its straight wall)."""


def _visit_targets(part: Partition, walls: PartitionedWalls, edges: tuple[int, ...]) -> Visits:
    """The segments of the searched partition (of the straight walls, cut where the visited edges end: every
    segment lies inside or outside each visited edge) that lie on each visited user edge."""
    out = []
    for k in edges:
        m, s0, s1 = walls.edge_map[k]
        rows = [i for i in part.edge_segments[m] if s0 <= part.segments[i].t0 and part.segments[i].t1 <= s1]
        mask = np.zeros(len(part.segments), dtype=bool)
        mask[rows] = True
        out.append(mask)
    return tuple(out)


@dataclass(frozen=True)
class _Product:
    """Arcs of the product of the safe BVG (at one tolerance) with the sequence automaton."""

    n_nodes: int
    src: np.ndarray
    dst: np.ndarray
    w: np.ndarray
    choice: np.ndarray  # row of ArcChoices
    advance: np.ndarray  # bool: lands on the next required edge


def _tagged(choices: ArcChoices, rows: np.ndarray, N: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arcs ``rows`` between tagged segments c = s + N·k (k: the corner of s the robot arrived near, 0 for
    none): (source code, target code, row), without an arc into the corner the robot just arrived at (the
    corner ping-pong of :mod:`solverplan.plan.margins`)."""
    src, dst, out = [], [], []
    s, t = choices.source[rows], choices.target[rows]
    land = t + N * choices.arrival[rows]
    for k in range(4):  # bits of k: arrived near the start (1) / end (2) corner
        ok = (choices.dive[rows] & k) == 0
        src.append(s[ok] + N * k)
        dst.append(land[ok])
        out.append(rows[ok])
    return np.concatenate(src), np.concatenate(dst), np.concatenate(out)


def _product(part: Partition, choices: ArcChoices, visit: Visits, H: int | None,
             allowed: frozenset[int] | None) -> _Product:
    """Nodes (c, q, h) over tagged segments c (:func:`_tagged`), h ∈ 0..H; ``H=None``: no h, within-layer cycles
    allowed: node (c, q). ``visit``: for each required visit, which segments it lands on (:func:`_visit_targets`)."""
    N, k = len(part.segments), len(visit)
    rows = np.arange(len(choices.arc))
    if allowed is not None:
        mask = np.isin(choices.source, list(allowed)) & np.isin(choices.target, list(allowed))
        rows = rows[mask]
    s, t, rows = _tagged(choices, rows, N)
    M = 4 * N
    # four int64/bool arrays (25 bytes) per product arc: one copy of the tagged arcs per (q, h)
    refuse_beyond_memory(25 * len(s) * k * (1 if H is None else H + 1),
                         f"the patrol product graph with max_between = {H or 0:,}")
    hs = [0] if H is None else list(range(H + 1))
    nh = len(hs)
    src, dst, ch, adv = [], [], [], []
    for q in range(k):
        nxt = (q + 1) % k
        lands = visit[nxt][t % N]
        for h in hs:
            here = (q * nh + h) * M + s
            # advancing arcs
            src.append(here[lands])
            dst.append((nxt * nh + 0) * M + t[lands])
            ch.append(rows[lands])
            adv.append(np.ones(int(lands.sum()), dtype=bool))
            stay = ~lands
            if H is None:
                src.append(here[stay])
                dst.append((q * nh + 0) * M + t[stay])
            elif h < H:
                src.append(here[stay])
                dst.append((q * nh + h + 1) * M + t[stay])
            else:
                continue
            ch.append(rows[stay])
            adv.append(np.zeros(int(stay.sum()), dtype=bool))
    src_a = np.concatenate(src) if src else np.zeros(0, dtype=np.int64)
    dst_a = np.concatenate(dst) if dst else np.zeros(0, dtype=np.int64)
    ch_a = np.concatenate(ch) if ch else np.zeros(0, dtype=np.int64)
    adv_a = np.concatenate(adv) if adv else np.zeros(0, dtype=bool)
    n = k * nh * M
    keep = cycle_arcs_only(n, src_a, dst_a)
    return _Product(n, src_a[keep], dst_a[keep], choices.weight[ch_a[keep]], ch_a[keep], adv_a[keep])


def _compact(prod: _Product) -> tuple[int, np.ndarray, np.ndarray]:
    """Renumber the nodes that carry arcs: (n, src, dst)."""
    used, inverse = np.unique(np.concatenate([prod.src, prod.dst]), return_inverse=True)
    m = len(prod.src)
    return len(used), inverse[:m], inverse[m:]


# ---------------------------------------------------------------------- one-period DP (objective a)
def _period_dp(part: Partition, choices: ArcChoices, visit: Visits, H: int,
               allowed: frozenset[int] | None) -> tuple[float, list[int]] | None:
    """Minimum total weight of a walk from a segment of e_1 through e_2, …, e_k back to the same segment with at
    most H intermediate bounces between required visits: (weight, rows of ``choices`` in order), or None."""
    N, k = len(part.segments), len(visit)
    rows = np.arange(len(choices.arc))
    if allowed is not None:
        rows = rows[np.isin(choices.source, list(allowed)) & np.isin(choices.target, list(allowed))]
    if len(rows) == 0:
        return None
    # tagged segments (the corner the robot arrived near: no arc into it next); a period starts and ends at
    # the same tagged anchor, so that it can be repeated
    s, t, rows = _tagged(choices, rows, N)
    w = choices.weight[rows]
    M = 4 * N
    anchors = [a + N * tag for a in np.flatnonzero(visit[0]).tolist() if allowed is None or a in allowed
               for tag in range(4)]
    if not anchors:
        return None
    A = len(anchors)
    layers = (k + 1) * (H + 1)
    # distances (8 bytes) and predecessors (16 bytes) per (layer, anchor, tagged segment)
    refuse_beyond_memory(24 * layers * A * M, f"the one-period patrol search with max_between = {H:,}")
    dist = np.full((layers, A, M), np.inf)
    pred = np.full((layers, A, M, 2), -1, dtype=np.int64)  # (previous layer, tagged arc)
    for i, a in enumerate(anchors):
        dist[0, i, a] = 0.0
    for j in range(k):
        lands = visit[(j + 1) % k][t % N]
        for h in range(H + 1):
            L = j * (H + 1) + h
            cand = dist[L][:, s] + w[None, :]  # (A, arcs)
            targets = []
            if lands.any():
                targets.append(((j + 1) * (H + 1), lands))
            if h < H and (~lands).any():
                targets.append((L + 1, ~lands))
            for L2, m in targets:
                c = cand[:, m]
                tt = t[m]
                rr = np.flatnonzero(m)  # index into the tagged arcs (its source code and row)
                for i in range(A):
                    order = np.lexsort((c[i], tt))
                    tt_o, c_o = tt[order], c[i][order]
                    first = np.concatenate([[True], tt_o[1:] != tt_o[:-1]])
                    nodes, best, arc_rows = tt_o[first], c_o[first], rr[order][first]
                    better = best < dist[L2, i, nodes]
                    dist[L2, i, nodes[better]] = best[better]
                    pred[L2, i, nodes[better], 0] = L
                    pred[L2, i, nodes[better], 1] = arc_rows[better]
    end = k * (H + 1)
    best_val, best_i = math.inf, -1
    for i, a in enumerate(anchors):
        if dist[end, i, a] < best_val:
            best_val, best_i = float(dist[end, i, a]), i
    if best_i < 0:
        return None
    path = []
    L, node = end, anchors[best_i]
    while L != 0:
        L_prev, p = (int(x) for x in pred[L, best_i, node])
        if p < 0:  # pragma: no cover - every finite label has a predecessor
            raise SolverFailed("broken predecessor chain in the one-period dynamic programme")
        path.append(int(rows[p]))
        node = int(s[p])
        L = L_prev
    path.reverse()
    return best_val, path


# ---------------------------------------------------------------------- the solver
@fill_doc(margins=MARGIN_DOCS["margins"])
def patrol(
    env: Environment,
    visit: str | Sequence[int],
    *,
    start: str | BoundarySet | None = None,
    objective: PatrolObjective | str = "contraction",
    tolerance: float | None = None,
    max_between: int | None = None,
    epsilon: float | None = None,
    solver: str | None = None,
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    safe_margin: float = DEFAULT_SAFE_MARGIN,
    corner_clearance: float | None = None,
    timeout: float | Deadline | None = None,
) -> Patrol:
    """A patrol cycle visiting ``visit`` in order, optimal for ``objective`` (module docstring).

    Parameters
    ----------
    env
        The environment.
    visit
        The required edges in order (``"e2,e5,e9"`` or ids), visited cyclically.
    start
        Start set S (``"e3:0.25:0.75,e4"``); the strategy then first brings every point of S into the cycle
        (a safe-BVG plan over beliefs with intervals at least 2ε wide). None: the cycle alone.
    objective
        ``contraction`` (a), ``tolerance`` (b) or ``rate`` (c).
    tolerance
        ε, radians: half the width of every heading interval (default :data:`DEFAULT_TOLERANCE`; ignored by
        ``tolerance``, which maximises it).
    max_between
        H: intermediate bounces allowed between consecutive required visits (default: the smallest H ≤
        :data:`MAX_BETWEEN_SEARCHED` with a patrol cycle).
    epsilon
        A length: also report the cycles needed to shrink the position set below it.
    solver
        cvxpy solver for the LP of ``rate`` (default Clarabel).
    graph
        A precomputed safe BVG of ``env`` (saves its construction).
    %(margins)s
    timeout
        Seconds of wall time (positive, finite; None: no limit), the graph build included (it is not
        interrupted). At the deadline the search answers the best cycle found so far or ``not-found``, not
        proved, with the timeout in ``optimality.limits`` (module docstring).

    Returns
    -------
    Patrol
        ``found`` with the entry and the cycle, ``not-contracting`` or ``infeasible`` (proved for the class of
        cycles with at most ``max_between`` intermediate bounces), or ``not-found`` when a cap or the timeout
        stopped the search.

    Raises
    ------
    InputError
        Unknown edges, a bad start set, tolerance outside (0, π/2), negative max_between, unknown objective,
        a timeout that is not a positive finite number.
    SolverFailed
        The LP and Karp disagree, or a solver breaks down.

    Examples
    --------
    >>> import solverplan as sp
    >>> guard = sp.patrol(sp.load_environment("square"), "e0,e2", objective="tolerance")
    >>> guard.status.value, len(guard.cycle), round(guard.tolerance, 4)      # ± radians on every bounce
    ('found', 4, 0.3921)
    >>> sp.patrol(sp.load_environment("hexagon"), "e0,e3").max_between    # one bounce between visits is not enough
    2
    """
    objective = PatrolObjective.parse(objective, "patrol objective").value
    edges = parse_visit(env, visit)
    start_set = _start_set(env, start)
    if tolerance is not None and not (isinstance(tolerance, (int, float)) and 0 < float(tolerance) < math.pi / 2):
        raise InputError(f"tolerance {tolerance!r} must be a heading half-width in (0, π/2) radians")
    if max_between is not None and (isinstance(max_between, bool) or not isinstance(max_between, int) or max_between < 0):
        raise InputError(f"max_between must be a non-negative integer, got {max_between!r}")
    if epsilon is not None and not (isinstance(epsilon, (int, float)) and math.isfinite(epsilon) and epsilon > 0):
        raise InputError(f"epsilon {epsilon!r} must be a positive length")
    deadline = deadline_of(timeout)
    t0 = time.perf_counter()
    # Collinear vertices are no corners: search the straight walls (the same free space with them merged, each ring
    # from its canonical vertex: plan._walls), cut again only where a visited edge ends inside a wall (a visit of
    # user edge k means landing on k's part of its wall), and answer in the user's edges
    walls = PartitionedWalls(env)
    if graph is not None and graph.partition.env not in (env, walls.merged):
        raise InputError("the safe BVG given was built for another environment")
    cuts = walls.visit_cuts(edges)
    if cuts:
        base = graph.partition if graph is not None and graph.partition.env == walls.merged else partition(walls.merged)
        g = safe_bounce_visibility_graph(cut_partition(base, cuts))
    else:
        g = straight_walls_graph(walls, graph)
    t1 = time.perf_counter()
    margins = Margins.for_environment(walls.merged, heading_margin=heading_margin, safe_margin=safe_margin,
                                      corner_clearance=corner_clearance)
    result = _solve(walls, g, edges, objective, tolerance, max_between, start_set, epsilon, solver, margins, deadline)
    stats = Stats(seconds_setup=round(t1 - t0, 6), seconds_search=round(time.perf_counter() - t1, 6))
    logger.info("patrol (%s): %s in %.3f s", objective, result.status.value, time.perf_counter() - t1)
    return replace(result, stats=stats)


def _scope(H: int, eps: float | None, start_set: BoundarySet | None, *, one_period: bool) -> str:
    """The class of patrols an answer's optimality claim is about."""
    what = "one-period patrol cycles" if one_period else "patrol cycles"
    width = "" if eps is None else f", intervals {2 * eps:g} rad wide at the contracting end of each admissible interval"
    reach = "" if start_set is None else f", on segments a safe plan from {start_set} reaches with certainty"
    return (f"{what} with at most {H} intermediate bounces between consecutive required visits{width}{reach}, "
            "every stage an arc of the safe BVG between segments of P′ of the straight walls (collinear vertices "
            "merged; cut where a visited edge ends inside a wall) (within the margin policy: no two consecutive arcs "
            "into one corner)")


def _claim(method: Method, bound: float | None, scope: str, algorithm: str, limits: tuple[str, ...],
           gap: float | None = None) -> Optimality:
    """An optimality claim of the class searched: proved unless the reachability search hit a cap."""
    return Optimality(method, not limits, bound, scope=scope, gap=gap, algorithm=algorithm, limits=limits)


def _solve(walls: PartitionedWalls, g: SafeBVG, edges, objective, tolerance, max_between, start_set, epsilon, solver,
           margins: Margins, deadline: Deadline = NEVER) -> Patrol:
    """The patrol of ``edges`` (user edges) searched on ``g`` (the safe BVG of the straight walls of
    ``walls``); the answer in the user's numbering (:func:`_to_user`)."""
    part = g.partition
    env = part.env
    visits = _visit_targets(part, walls, edges)
    eps = float(tolerance) if tolerance is not None else DEFAULT_TOLERANCE
    entry = _Entry(g, start_set, margins, deadline, walls) if start_set is not None else None
    classes = [max_between] if max_between is not None else list(range(MAX_BETWEEN_SEARCHED + 1))
    user_part = walls.user_partition if not walls.identity else part
    base = dict(environment=EnvironmentRecord.of(walls.env, user_part.n_segments), partition=user_part, visit=edges,
                objective=objective, start=start_set)

    if objective == "tolerance":
        answer = _objective_tolerance(env, part, g, visits, classes, entry, margins, epsilon, base, deadline)
    else:
        answer = _objective_cycle(env, part, g, visits, objective, eps, classes, entry, epsilon, solver, margins,
                                  base, deadline)
    return _to_user(walls, part, answer)


def _objective_cycle(env, part, g, visits: Visits, objective, eps, classes, entry, epsilon, solver, margins, base,
                     deadline: Deadline) -> Patrol:
    """(a) and (c): the best cycle of each class H in turn; the first class with a cycle answers."""
    start_set, edges = base["start"], base["visit"]

    choices = arc_choices(g, eps, margins)
    allowed, limits = _allowed(choices, entry, eps)
    if allowed is not None and not allowed:
        status, capped = (Status.NOT_FOUND, _capped(limits)) if limits else (Status.INFEASIBLE, "")
        return Patrol(status=status, tolerance=eps, max_between=classes[-1],
                      reason=f"no safe plan with tolerance {eps:g} leaves the start set {start_set} at all{capped}",
                      optimality=_claim(Method.SEARCH_EXHAUSTED, None, f"safe belief plans from {start_set} with "
                                        f"intervals {2 * eps:g} rad wide", "breadth-first search over beliefs", limits),
                      **base)
    one_period = objective == "contraction"
    for H in classes:
        if deadline.expired():
            limits = (*limits, deadline.limit(_classes_done(classes, H)))
            break
        scope = _scope(H, eps, start_set, one_period=one_period)
        if one_period:
            found = _period_dp(part, choices, visits, H, allowed)
            if found is None:
                continue
            value, rows = found
            wider, note = _period_bound(part, choices, visits, allowed, value)
            opt = _claim(Method.SEARCH_EXHAUSTED, math.exp(value), scope,
                         f"dynamic programming over the one-period product DAG, H = {H}", limits)
            solvers = {"dp_log_contraction": value}
            periods = 1
        else:
            prod = _product(part, choices, visits, H, allowed)
            if len(prod.src) == 0:
                continue
            value, cyc, solvers = _min_mean(prod, solver)
            rows = [int(prod.choice[a]) for a in cyc]
            periods = int(prod.advance[cyc].sum()) // len(edges)
            loose = _product(part, choices, visits, None, allowed)
            lb = _min_mean(loose, solver, karp=False)[0] if len(loose.src) else value
            wider = math.exp(lb)
            note = (f"over all patrol cycles (any number of intermediate bounces) the per-bounce contraction is "
                    f"≥ {wider:.6g} (minimum mean cycle LP)")
            opt = _claim(Method.LP_DUALITY, math.exp(value), scope,
                         f"minimum mean cycle: LP (duality) and Karp's algorithm agree, H = {H}", limits)
        return _answer(env, part, g, choices, rows, eps, H, entry, epsilon, opt, solvers, base, periods,
                       bound_all_classes=(wider, note), visits=visits)
    where = "" if entry is None else f", among the segments reachable from {start_set}"
    status = Status.NOT_FOUND if limits else Status.INFEASIBLE
    return Patrol(status=status, tolerance=eps, max_between=classes[-1],
                  reason=(f"no patrol cycle visits {', '.join(f'e{e}' for e in edges)} in order with intervals "
                          f"{2 * eps:g} rad wide and at most {classes[-1]} intermediate bounces between required visits "
                          f"(every such walk of the safe BVG was searched){where}{_capped(limits)}")
                  if not _timed_out(limits) else _timed_out(limits),
                  optimality=_claim(Method.SEARCH_EXHAUSTED, None, _scope(classes[-1], eps, start_set,
                                                                          one_period=one_period),
                                    "search of the product of the safe BVG with the sequence automaton", limits),
                  **base)


def _classes_done(classes: list[int], H: int) -> str:
    """How far a search over the classes got before class ``H`` (for a timeout's limit entry)."""
    if H == classes[0]:
        return "building the safe BVG and the arc choices"
    return f"the classes H = {classes[0]}..{H - 1}" if H - 1 > classes[0] else f"the class H = {classes[0]}"


def _timed_out(limits: tuple[str, ...]) -> str:
    """The reason of an answer the timeout stopped before a cycle was found ("" when it did not)."""
    hit = [x for x in limits if x.startswith("timeout")]
    return f"{hit[0]} before a patrol cycle was found: not a proof" if hit else ""


def _capped(limits: tuple[str, ...]) -> str:
    if not limits:
        return ""
    return (f"; the search for the segments reachable from the start set stopped at its caps ({', '.join(limits)}): "
            "not a proof")


def _allowed(choices: ArcChoices, entry: _Entry | None, eps: float) -> tuple[frozenset[int] | None, tuple[str, ...]]:
    """Segments a safe plan from the start set can reach with certainty (singleton beliefs, then arcs), and the
    caps of the belief search that were hit (then the set may miss reachable segments)."""
    if entry is None:
        return None, ()
    singletons, limits = entry.singletons(eps)
    seeds = set(singletons)
    out = set(seeds)
    adj: dict[int, list[int]] = {}
    for s, t in zip(choices.source.tolist(), choices.target.tolist()):
        adj.setdefault(s, []).append(t)
    stack = list(seeds)
    while stack:
        u = stack.pop()
        for v in adj.get(u, ()):
            if v not in out:
                out.add(v)
                stack.append(v)
    return frozenset(out), limits


def _period_bound(part, choices, visits: Visits, allowed, value) -> tuple[float | None, str]:
    """Lower bound on the one-period contraction over every class (any number of intermediate bounces)."""
    loose = _product(part, choices, visits, None, allowed)
    within = ~loose.advance
    if within.any():
        n, src, dst = loose.n_nodes, loose.src[within], loose.dst[within]
        if find_negative_cycle(n, src, dst, loose.w[within]) is not None:
            return 0.0, ("a contracting cycle between two required visits exists, so with more intermediate bounces "
                         "the per-period contraction can be made arbitrarily small")
    N = len(part.segments)
    if N * len(visits) * N > 200000:
        return None, "no bound over larger classes computed (too many segments)"
    deep = _period_dp(part, choices, visits, N, allowed)
    if deep is None:  # pragma: no cover - the deeper class contains the found walk
        return None, ""
    return math.exp(deep[0]), (f"over every class (any number of intermediate bounces) the optimum is "
                               f"{math.exp(deep[0]):.6g}")


def _min_mean(prod: _Product, solver: str | None, *, karp: bool = True) -> tuple[float, list[int], dict]:
    n, src, dst = _compact(prod)
    lp_value, lp_cycle, lp_solver = lp_min_mean_cycle(n, src, dst, prod.w, solver=solver)
    solvers: dict = {"lp": lp_value, "lp_solver": lp_solver}
    value, cycle = lp_value, lp_cycle
    if karp and n <= KARP_MAX_NODES:
        k_value, k_cycle = karp_min_mean_cycle(n, src, dst, prod.w)
        solvers["karp"] = k_value
        if abs(k_value - lp_value) > _AGREE * (1 + abs(k_value)):
            raise SolverFailed(f"the minimum-mean-cycle LP ({lp_solver}: {lp_value!r}) and Karp's algorithm "
                               f"({k_value!r}) disagree")
        value, cycle = k_value, k_cycle  # Karp's value is exact up to rounding; its cycle is tight
    elif karp:
        solvers["karp"] = None
        solvers["karp_skipped"] = f"{n} nodes > {KARP_MAX_NODES}"
    # the cycle's own mean (the reported value is the cycle's, never better than the solvers')
    mean = float(np.mean(prod.w[cycle]))
    solvers["cycle_mean"] = mean
    return mean, cycle, solvers


def _objective_tolerance(env, part, g, visits: Visits, classes, entry, margins, epsilon, base,
                         deadline: Deadline = NEVER) -> Patrol:
    """(b): bisection on ε with negative-cycle detection; at the deadline, the bracket reached (not proved)."""
    edges = base["visit"]
    top = max_tolerance(g, margins)
    hit_limits: set[str] = set()  # caps the reachability search hit at any ε tried

    def feasible(eps: float, H: int):
        ch = arc_choices(g, eps, margins)
        allowed, limits = _allowed(ch, entry, eps)
        hit_limits.update(limits)
        if allowed is not None and not allowed:
            return None
        prod = _product(part, ch, visits, H, allowed)
        if len(prod.src) == 0:
            return None
        cyc = find_negative_cycle(prod.n_nodes, prod.src, prod.dst, prod.w)
        if cyc is None:
            return None
        return ch, [int(prod.choice[a]) for a in cyc], int(prod.advance[cyc].sum()) // len(edges)

    start_set = base["start"]
    for H in classes:
        if deadline.expired():
            hit_limits.add(deadline.limit(_classes_done(classes, H)))
            break
        lo_hit = feasible(_EPS_FLOOR, H)
        if lo_hit is None:
            continue
        lo, hi = _EPS_FLOOR, top
        best = lo_hit
        if feasible(hi, H) is not None:  # pragma: no cover - only with a whole-interval contracting cycle
            lo, best = hi, feasible(hi, H)
        else:
            for step in range(60):
                if hi - lo <= 1e-9 * max(1.0, hi):
                    break
                if deadline.expired():
                    hit_limits.add(deadline.limit(f"{step} bisection steps (H = {H})"))
                    break
                mid = (lo + hi) / 2
                hit = feasible(mid, H)
                if hit is None:
                    hi = mid
                else:
                    lo, best = mid, hit
        ch, rows, periods = best
        scope = (f"{_scope(H, None, start_set, one_period=False)}, each arc's interval at the contracting end of its "
                 f"safe interval: the largest tolerance ε with a contracting cycle, ε* ∈ [{lo:.12g}, {hi:.12g}]")
        opt = _claim(Method.BISECTION, hi, scope, f"bisection with Bellman-Ford negative-cycle detection, H = {H}",
                     tuple(sorted(hit_limits)))
        return _answer(env, part, g, ch, rows, lo, H, entry, epsilon, opt, {"bracket": [lo, hi]}, base, periods,
                       visits=visits)
    limits = tuple(sorted(hit_limits))
    return Patrol(status=Status.NOT_FOUND if limits else Status.INFEASIBLE, tolerance=None, max_between=classes[-1],
                  reason=(f"no contracting patrol cycle visits {', '.join(f'e{e}' for e in edges)} in order with at most "
                          f"{classes[-1]} intermediate bounces between required visits, even with tolerance "
                          f"{_EPS_FLOOR:g}{_capped(limits)}") if not _timed_out(limits) else _timed_out(limits),
                  optimality=_claim(Method.BISECTION, None, _scope(classes[-1], _EPS_FLOOR, start_set, one_period=False),
                                    "Bellman-Ford negative-cycle detection at the smallest tolerance", limits),
                  **base)


# ---------------------------------------------------------------------- building the answer
def _answer(env, part, g, choices: ArcChoices, rows: list[int], eps: float, H: int, entry: _Entry | None, epsilon,
            opt: Optimality, solvers: dict, base: dict, periods: int = 1,
            bound_all_classes: tuple[float | None, str] = (None, ""), *, visits: Visits) -> Patrol:
    """The answer of a cycle (``rows`` of ``choices``) found on ``part`` (the searched partition): the cycle in the
    searched numbering, the entry in the user's (:func:`_to_user` maps the cycle)."""
    segs = [int(choices.source[r]) for r in rows]
    # entry: a belief plan from the start set to some segment of the cycle; rotate the cycle to begin there
    entry_stages: tuple[Stage, ...] = ()
    rotate = 0
    if entry is not None:
        found = entry.plan({int(choices.source[r]): int(choices.dive[r]) for r in reversed(rows)}, eps)  # first visit wins
        if found is None and entry.deadline.hit:
            limit = entry.deadline.limit("the search for an entry plan")
            return Patrol(status=Status.NOT_FOUND, tolerance=eps, max_between=H,
                          reason=f"a patrol cycle was found, but {limit} before a plan into it from the start set: "
                                 "not a proof", optimality=replace(opt, proved=False, limits=(*opt.limits, limit)),
                          **base)
        if found is None:  # pragma: no cover - the cycle was chosen among reachable segments
            raise SolverFailed("the patrol cycle lies among reachable segments, yet no entry plan was found")
        entry_stages, landing = found
        rotate = segs.index(landing)
    else:
        # begin with a bounce leaving a segment of the first required edge when there is one
        for k, s in enumerate(segs):
            if visits[0][s]:
                rotate = k
                break
    rows = rows[rotate:] + rows[:rotate]
    stages = [_stage(env, part, g, choices, r) for r in rows]
    worst_exact = Fraction(1)
    alpha, beta = Fraction(1), Fraction(0)
    for st in stages:
        worst_exact *= _worst_exact(env, st)
        alpha, beta = st.step.alpha * alpha, st.step.alpha * beta + st.step.beta
    if alpha == 1:  # pragma: no cover - a contracting cycle has |α| < 1
        raise SolverFailed("the nominal return map has slope 1: no fixed point")
    t_star = beta / (1 - alpha)
    points = []
    t = t_star
    for st in stages:
        points.append(PatrolPoint(st.step.from_edge, st.from_segment, t, env.exact_point_at(st.step.from_edge, t)))
        t = st.step.alpha * t + st.step.beta
    contraction = float(worst_exact)
    rate = contraction ** (1 / len(stages)) if contraction > 0 else 0.0
    status = Status.FOUND if contraction < 1 else Status.NOT_CONTRACTING
    reason = ("" if status is Status.FOUND else
              "the best patrol cycle of the class does not contract in the worst case: it is not stable")
    # gap: the answer's own value (exact worst case; for tolerance the bracket's feasible end) against the bound
    value = {"contraction": contraction, "rate": rate, "tolerance": eps}[base["objective"]]
    if opt.bound is not None:
        opt = replace(opt, gap=abs(value - opt.bound))
    first = part.segments[stages[0].from_segment]
    seg_len = float(first.t1 - first.t0) * float(env.edge_lengths[first.edge])
    attractor, counts = _set_valued(env, stages, first, epsilon)
    nominal_cycles = None
    if epsilon is not None and 0 < abs(alpha) < 1:
        nominal_cycles = cycles_to_epsilon(abs(alpha), Fraction(seg_len), Fraction(epsilon))
    return Patrol(
        status=status, reason=reason, tolerance=eps, max_between=H, entry=entry_stages, cycle=tuple(stages),
        contraction=contraction, contraction_exact=worst_exact, rate=rate,
        periods=max(periods, 1), nominal_alpha=alpha, nominal_beta=beta, points=tuple(points),
        attractor=attractor, epsilon=epsilon, cycles_to_epsilon=counts, cycles_to_epsilon_nominal=nominal_cycles,
        optimality=opt, bound_all_classes=bound_all_classes[0], bound_all_classes_note=bound_all_classes[1],
        solvers=solvers, **base)


def _to_user(walls: PartitionedWalls, part: Partition, answer: Patrol) -> Patrol:
    """A patrol found on ``part`` (P′ of the straight walls, maybe cut where visits end) in the user's numbering:
    each cycle stage leaves from the run of user segments its segment is made of and lands on a run; its exact
    map is stated between the user edges where the two runs begin (the edges' lines are the walls' lines, so the
    map runs on over the collinear neighbours: t < 0 or t > 1 there), and so is the return map; the orbit's points
    lie on the user edges that hold them (t in [0, 1]). Entry stages are in the user's numbering already."""
    if walls.identity or not answer.cycle:
        return answer
    user = walls.user_partition
    runs = walls.runs(part)
    env = walls.env
    stages = []
    alpha, beta = Fraction(1), Fraction(0)
    for st in answer.cycle:
        a = st.step
        src, dst = runs[st.from_segment], runs[st.to_segment]
        fe, te = user.segments[src[0]].edge, user.segments[dst[0]].edge
        m = affine_map(env, fe, a.direction, te)
        affine = replace(a, from_edge=fe, to_edge=te, alpha=m.alpha, beta=m.beta)
        alpha, beta = m.alpha * alpha, m.alpha * beta + m.beta
        stages.append(Stage(src, tuple(sorted(dst)), st.interval, moves=tuple((u, v) for u in src for v in dst),
                            affine=affine))
    points = []
    for p in answer.points:
        edge, t = walls.user_point(p.edge, p.t)
        points.append(PatrolPoint(edge, user.segment_at(edge, t), t, p.point))
    return replace(answer, cycle=tuple(stages), nominal_alpha=alpha, nominal_beta=beta, points=tuple(points))


def _stage(env: Environment, part: Partition, g: SafeBVG, choices: ArcChoices, r: int) -> Stage:
    a = int(choices.arc[r])
    s, t = int(choices.source[r]), int(choices.target[r])
    e_from, e_to = int(part.seg_edge[s]), int(part.seg_edge[t])
    interval = Interval(float(choices.lo[r]), float(choices.hi[r]))
    nominal = interval.midpoint
    edge = env.edge(e_from)
    vec = (edge.b[0] - edge.a[0], edge.b[1] - edge.a[1])
    direction = ExactHeading.from_float(nominal).direction(vec)
    m = affine_map(env, e_from, direction, e_to)
    side = int(g.transition[a])
    affine = AffineStep(e_from, e_to, nominal, direction, m.alpha, m.beta, float(choices.worst[r]),
                        transition="right" if side > 0 else "left" if side < 0 else "parallel", phi=float(g.phi[a]))
    return Stage((s,), (t,), interval, moves=((s, t),), affine=affine)


def _worst_exact(env: Environment, st: Stage) -> Fraction:
    """max |α| over the exact cone inside the stage's interval (the end directions: the checker's argument)."""
    a = st.step
    edge = env.edge(a.from_edge)
    vec = (edge.b[0] - edge.a[0], edge.b[1] - edge.a[1])
    d_lo, d_hi = heading_cone(vec, st.interval)
    return max(abs(affine_map(env, a.from_edge, d, a.to_edge).alpha) for d in (d_lo, d_hi))


def _set_valued(env: Environment, stages: Sequence[Stage], first, epsilon: float | None,
                max_cycles: int = 100000) -> tuple[float, int | None]:
    """Iterate the set of positions on the first segment through the cycle with the whole intervals (floats):
    the image of [a, b] is spanned by the four corner maps (monotone in t and in the heading). Returns the
    attractor's width (arc length) and the cycles until the set is at most ``epsilon`` wide (None if never)."""
    maps = []
    for st in stages:
        edge = env.edge(st.step.from_edge)
        vec = (edge.b[0] - edge.a[0], edge.b[1] - edge.a[1])
        ends = []
        for theta in (st.interval.lo, st.interval.hi):
            d = ExactHeading.from_float(theta).direction(vec)
            m = affine_map(env, st.step.from_edge, d, st.step.to_edge)
            ends.append((float(m.alpha), float(m.beta)))
        maps.append(ends)
    length = float(env.edge_lengths[first.edge])
    a, b = float(first.t0), float(first.t1)
    count = None
    widths = []
    for cycle in range(max_cycles):
        w = (b - a) * length
        widths.append(w)
        if epsilon is not None and count is None and w <= epsilon:
            count = cycle
        if cycle > 2 and abs(widths[-1] - widths[-2]) <= 1e-15 * max(1.0, length) and (epsilon is None or count is not None or w > epsilon):
            break
        for ends in maps:
            vals = [al * x + be for al, be in ends for x in (a, b)]
            a, b = min(vals), max(vals)
    return widths[-1], count
