"""Certificates of plans (:class:`solverplan.plan.Plan`) — the glue between the planner and the writer.

:func:`plan_certificate` turns a found plan into the stages and moves of
:func:`~solverplan.certify.writer.build_certificate`: one :class:`~solverplan.certify.writer.StageSpec` per
stage (its heading interval), one :class:`~solverplan.certify.writer.MoveSpec` per possible source segment
(source → the segment it lands on). The plan's start and goal sets become the certificate's; its
objective and :class:`~solverplan.plan.Optimality` become the claims (the bound as the exact value of its
float). A last stage that lands on the part of a segment the goal set covers claims the exact
**images** of its moves (so that they can be checked to lie in the goal), every other plan the target
segments.

The writer shrinks each interval by ``margin`` before making its ends rational. The planner's
intervals already lie μ = 10⁻⁹ rad inside the exact safe sets, so a tiny margin suffices; it is kept
at 2·10⁻¹⁰ so that a proved optimality bound stays within the checker's 10⁻⁹ of the certified width
(the certified width is the plan's width minus about 2 × (margin + rounding)).

Written by the planner's side (issue 5, items 1–2) for ``solverplan plan --certificate``; the writer and the
checker are untouched.
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.bounce.partition import Partition, partition as make_partition
from solverplan.certify.schema import Certificate, Optimality as ClaimedOptimality
from solverplan.certify.writer import MoveSpec, StageSpec, build_certificate
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.plan.result import Plan

__all__ = ["plan_certificate", "PLAN_MARGIN"]

PLAN_MARGIN = 2e-10
"""Radians the writer cuts off each end of a plan interval before making it rational."""

_PROVED_SLACK = 3e-10
"""A plan claims proved optimality in its certificate only if its bound exceeds its value by at most this
much per stage: the checker allows 10⁻⁹ (per stage for sums) between a proved bound and the certified
value, and the certified widths are about 6·10⁻¹⁰ below the plan's."""


def plan_certificate(env: Environment, plan: Plan, *, partition: Partition | None = None,
                     margin: float = PLAN_MARGIN) -> Certificate:
    """The certificate of a found plan with at least one stage.

    Raises :class:`InputError` for an infeasible plan or a plan without stages (nothing to certify: the
    checker certifies plans, not proofs of infeasibility).
    """
    if not plan.found:
        raise InputError(f"the plan is infeasible ({plan.reason}): the checker certifies plans, not infeasibility")
    if not plan.stages:
        raise InputError("the plan has no stages (its start set lies in its goal set): there is nothing to certify")
    part = partition if partition is not None else make_partition(env)
    stages = [StageSpec(stage.interval, tuple(MoveSpec(source=i, target=j) for i, j in stage.moves))
              for stage in plan.stages]
    partial = set(plan.stats.counts.get("partial_goal_segments", ())) if plan.stats else set()
    if not plan.stats and plan.goal:
        partial = _partial_goal_segments(env, part, plan.goal)
    targets = "image" if set(plan.stages[-1].to_segments) & partial else "segment"
    opt = plan.optimality
    proved = opt.proved
    value = {"tolerance": plan.min_width, "constant": plan.min_width, "sum": plan.sum_width}.get(plan.objective)
    if proved and opt.bound is not None and value is not None and opt.bound - value > _PROVED_SLACK * len(plan.stages):
        proved = False  # an LP/MILP bound with a visible gap: claim the bound, not optimality
    claimed = ClaimedOptimality(
        method=opt.method,
        proved=proved,
        bound=None if opt.bound is None else Fraction(opt.bound),
    )
    start = plan.start if plan.start else list(plan.stages[0].from_segments)
    goal = plan.goal if plan.goal else list(plan.stages[-1].to_segments)
    return build_certificate(env, part, stages, start=start, goal=goal, kind="plan", objective=plan.objective,
                             optimality=claimed, targets=targets, margin=margin)


def _partial_goal_segments(env: Environment, part: Partition, goal: str) -> set[int]:
    """Segments the goal set covers only in part (for plans read back without their stats)."""
    out = set()
    for edge, merged in env.boundary_set(goal).by_edge().items():
        for k in part.edge_segments[edge]:
            s = part.segments[k]
            if not any(lo <= s.t0 and s.t1 <= hi for lo, hi in merged) and any(s.t0 < hi and lo < s.t1 for lo, hi in merged):
                out.add(k)
    return out
