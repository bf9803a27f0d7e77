"""Funnels (paper Fig. 14, §7.1): plans that track the exact set of possible positions and use contraction to
shrink it until it fits through a gap that no plan over whole segments passes.

A safe-BVG plan (Def. 14, :func:`solverplan.plan.find_plan`) needs every stage to carry *every point of a whole
segment of P′* onto one segment; a funnel only needs it for the positions the robot can actually be at. Those
are tracked exactly: the set after a stage is the lifted transition f(S, Θ) of the set before it
(:func:`~solverplan.bounce.transitions.transition_set`), and contraction (Def. 11–12: small headings into a
corner shrink distances to the corner by C < 1 per bounce) makes it as small as needed — e.g. circling a room
until the position set is narrow enough to be aimed through a doorway. The paper shows such a strategy
(Fig. 14) and notes its planner cannot find it.

The search (:mod:`solverplan.plan._positions`) is over (position set, bounces) states with dominance (a state
whose positions contain an earlier state's is dropped) and a beam; every heading interval is 2ε wide (ε the
tolerance). What it returns is exact — replayed in rational arithmetic, with the exact positions after every
stage — and certifiable (:func:`solverplan.certify.contraction.funnel_certificate`); its fewest-bounces claim is
heuristic (``optimality.proved`` is false).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> f = funnel(square, "e0", "e2:0.45:0.55", tolerance=0.005)
>>> f.status, len(f.stages) > 1, f.stages[-1].positions[0].edge
('found', True, 2)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from solverplan.bounce.bvg import SafeBVG, safe_bounce_visibility_graph
from solverplan.bounce.partition import Partition, partition
from solverplan.environment import BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.plan._positions import search_positions
from solverplan.plan._results import PositionStage, piece_json
from solverplan.plan.result import Optimality, environment_record

__all__ = ["Funnel", "funnel", "DEFAULT_FUNNEL_TOLERANCE", "safe_plan_exists"]

DEFAULT_FUNNEL_TOLERANCE = 0.005
"""Radians: the half-width of every heading interval of a funnel when none is given."""


@dataclass(frozen=True)
class Funnel:
    """A funnel or localisation strategy (docs/contract.md: a plan whose stages carry ``positions``), or why there is none.

    ``stages`` are :class:`~solverplan.plan._results.PositionStage` s: interval, exact source pieces and cones,
    exact positions after the stage. ``widths``: arc length of the position set before the first stage and after
    each stage. ``safe_plan``: whether a plan over whole segments (the safe BVG, any tolerance) exists at all,
    for comparison. ``kind``: ``funnel`` or ``localize``.
    """

    env: Environment
    status: str
    reason: str
    start: BoundarySet
    goal: BoundarySet | None
    tolerance: float
    stages: tuple[PositionStage, ...] = ()
    kind: str = "funnel"
    epsilon: float | None = None
    safe_plan: bool | None = None
    optimality: Optimality = field(default_factory=lambda: Optimality("none", False, None))
    stats: dict = field(default_factory=dict)
    partition: Partition | None = field(default=None, repr=False)

    @property
    def found(self) -> bool:
        return self.status == "found"

    @property
    def widths(self) -> list[float]:
        lengths = self.env.edge_lengths
        out = [sum(float(p.t1 - p.t0) * float(lengths[p.edge]) for p in self.start.pieces)]
        out += [sum(float(p.t1 - p.t0) * float(lengths[p.edge]) for p in st.positions) for st in self.stages]
        return out

    @property
    def intervals(self):
        return tuple(st.interval for st in self.stages)

    def rollout_spec(self):
        """``(stages, targets, goal)`` for :class:`solverplan.simulate.StagePolicy`: each stage must land in its
        exact positions; after the last one the robot must be in the goal (the final positions for localisation)."""
        targets = tuple(st.positions for st in self.stages)
        goal = self.goal if self.goal is not None else BoundarySet(self.stages[-1].positions)
        return self.intervals, targets, goal

    def to_json(self) -> dict:
        widths = self.widths
        out: dict = {
            "status": self.status,
            "reason": self.reason,
            "environment": environment_record(self.env),
            "kind": self.kind,
            "start": str(self.start),
            "goal": None if self.goal is None else str(self.goal),
            "tolerance": self.tolerance,
            "objective": "fewest",
            "bounces": len(self.stages),
            "min_width": 2 * self.tolerance if self.stages else None,
            "stages": [st.to_json() for st in self.stages],
            "position_widths": widths,
            "final_positions": [piece_json(p) for p in (self.stages[-1].positions if self.stages else ())],
            "safe_plan_exists": self.safe_plan,
            "optimality": self.optimality.to_json(),
            "stats": self.stats,
        }
        if self.epsilon is not None:
            out["epsilon"] = self.epsilon
        return out

    def to_text(self, *, width: int = 100) -> str:
        head = f"{self.kind} in {self.env.name or 'the environment'} from {self.start}"
        if self.kind == "localize":
            head += f" to one interval shorter than {self.epsilon:g}"
        else:
            head += f" to {self.goal}"
        lines = [f"{head}: {self.status}"]
        if self.reason:
            lines.append(f"reason: {self.reason}")
        if self.safe_plan is not None:
            lines.append(f"plan over whole segments (safe BVG): {'exists' if self.safe_plan else 'none'}")
        widths = self.widths
        lines.append(f"start: {self.start} (length {widths[0]:.6g})")
        for k, st in enumerate(self.stages):
            where = ", ".join(f"e{p.edge}:[{float(p.t0):.6g}, {float(p.t1):.6g}]" for p in st.positions)
            lines.append(f"  {k}: θ ∈ [{st.interval.lo:.6f}, {st.interval.hi:.6f}] → {where}  (length {widths[k + 1]:.3g})")
        return "\n".join(lines) + "\n"


def _pieces_of(env: Environment, value, what: str) -> BoundarySet:
    if isinstance(value, BoundarySet):
        return value
    if isinstance(value, str):
        return env.boundary_set(value)
    raise InputError(f"{what} set {value!r}: expected a boundary set such as 'e3:0.25:0.75,e4'")


def safe_plan_exists(graph: SafeBVG, start: BoundarySet, goal: BoundarySet) -> bool:
    """Is there a plan over whole segments (safe-BVG arcs, any positive or zero width) from every segment the
    start set overlaps to segments inside the goal? Reachability of beliefs' members is necessary for a
    belief plan, so ``False`` proves no safe-BVG plan exists (``True`` is only necessary)."""
    part = graph.partition
    import networkx as nx

    g = graph.to_networkx(safe_only=True)

    def overlapping(bs: BoundarySet, inside: bool):
        out = set()
        for p in bs.pieces:
            for s in part.edge_segments[p.edge]:
                seg = part.segments[s]
                if inside and p.t0 <= seg.t0 and seg.t1 <= p.t1:
                    out.add(s)
                elif not inside and min(seg.t1, p.t1) > max(seg.t0, p.t0):
                    out.add(s)
        return out

    starts, goals = overlapping(start, False), overlapping(goal, True)
    if not goals:
        return False
    for s in starts:
        reach = nx.descendants(g, s) | {s}
        if not reach & goals:
            return False
    return True


def funnel(
    env: Environment,
    start: str | BoundarySet,
    goal: str | BoundarySet,
    *,
    tolerance: float | None = None,
    max_bounces: int = 30,
    n_headings: int = 240,
    beam: int = 400,
    graph: SafeBVG | None = None,
) -> Funnel:
    """A funnel from ``start`` to ``goal``: fixed-width heading intervals whose exact position sets shrink by
    contraction until they fit the goal (module docstring).

    Parameters
    ----------
    env
        The environment.
    start, goal
        Boundary sets (``"e0"``, ``"e3:0.25:0.75,e4"``); every point of ``start`` must end inside ``goal``.
    tolerance
        ε, radians: every interval is [θ − ε, θ + ε] (default :data:`DEFAULT_FUNNEL_TOLERANCE`).
    max_bounces, n_headings, beam
        The search's bounds: bounces, headings tried per stage (a uniform grid, plus aims at the goal), states
        kept per bounce.
    graph
        A precomputed safe BVG (for the comparison with plans over whole segments).

    Returns
    -------
    Funnel
        ``found`` with exact stages, or ``not-found`` with the search's bounds (the search is heuristic: not
        finding is not a proof).
    """
    start_set = _pieces_of(env, start, "start")
    goal_set = _pieces_of(env, goal, "goal")
    eps = DEFAULT_FUNNEL_TOLERANCE if tolerance is None else float(tolerance)
    if not (0 < eps < math.pi / 2):
        raise InputError(f"tolerance {tolerance!r} must be a heading half-width in (0, π/2) radians")
    if isinstance(max_bounces, bool) or not isinstance(max_bounces, int) or max_bounces < 1:
        raise InputError(f"max_bounces must be a positive integer, got {max_bounces!r}")
    g = graph if graph is not None else safe_bounce_visibility_graph(partition(env))
    part = g.partition
    goal_f = [(p.edge, float(p.t0), float(p.t1)) for p in goal_set.pieces]

    def inside(pieces) -> bool:
        return all(any(e == E and A + 1e-12 <= a and b <= B - 1e-12 for E, A, B in goal_f) for e, a, b in pieces)

    def inside_exact(pieces) -> bool:
        return all(any(p.edge == q.edge and q.t0 <= p.t0 and p.t1 <= q.t1 for q in goal_set.pieces) for p in pieces)

    points = []
    for p in goal_set.pieces:
        for s in np.linspace(0.1, 0.9, 5):
            points.append(env.point_at(p.edge, float(p.t0) + s * float(p.t1 - p.t0)))
    outcome = search_positions(env, part, start_set.pieces, inside, inside_exact, tolerance=eps, max_bounces=max_bounces,
                               goal_points=np.array(points), n_headings=n_headings, beam=beam)
    safe = safe_plan_exists(g, start_set, goal_set)
    stats = {"expanded": outcome.expanded, "bounces_searched": outcome.layers, "replay_failures": outcome.replay_failures}
    if outcome.stages is None:
        return Funnel(env, "not-found", outcome.reason, start_set, goal_set, eps, safe_plan=safe, stats=stats,
                      optimality=Optimality("search", False, None, algorithm="beam search over position sets"),
                      partition=part)
    return Funnel(env, "found", "", start_set, goal_set, eps, outcome.stages, safe_plan=safe, stats=stats,
                  optimality=Optimality("search", False, None,
                                        algorithm=f"breadth-first beam search over position sets ({n_headings} headings, "
                                                  f"beam {beam}): fewest bounces not proved"),
                  partition=part)
