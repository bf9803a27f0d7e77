"""Certificates of planner answers, as one call: :func:`certificate` and :func:`write_certificate`.

:func:`certificate` turns an answer of the planner into a :class:`~solverplan.certify.schema.Certificate`
by its type (it reads the answers only through their public attributes, all of them in this module):

- a **plan** (:class:`~solverplan.plan.Plan`) is a ``plan`` certificate: one stage per plan stage (its
  heading interval), one move per possible source segment or piece (source → the segment it lands on). The plan's
  start and goal sets become the certificate's; its objective and optimality become the claims (the bound
  as the exact value of its float). A last stage landing on a segment the goal covers only in part claims
  the exact **images** of its moves (so that they can be checked to lie in the goal), and so does every stage of
  a plan with a later stage leaving from a piece of a segment (a landing unit between the query's set ends: the
  images must lie in the pieces); otherwise the moves claim the target segments. A plan does not carry its environment: pass ``env``;
- a **Pareto front** is the certificate of its most tolerant plan;
- a **patrol** (:class:`~solverplan.plan.patrols.Patrol`) is a ``cycle`` certificate: the entry stages
  (belief stages of the safe BVG: one move per possible segment), then the cycle's stages, one move each
  from its whole source segment; the cycle block claims the exact return map of the nominal headings, its
  fixed point, the worst-case contraction (< 1) and the visits;
- a **funnel** or a **localisation** strategy (:class:`~solverplan.plan.funnels.Funnel`,
  :class:`~solverplan.plan.localization.Localization`) is a ``funnel`` or ``localize``
  certificate: every stage moves exact position pieces with the *exact cones the planner used*, so the
  images the checker recomputes are the positions the planner tracked, and each stage claims them; a
  localisation certificate also claims the strategy's ε (the final interval is shorter than it).

Negative answers and bounds (schema version 3, :mod:`solverplan.certify.negative`):

- an **infeasible** plan or Pareto front (proved by an exhausted search) is an ``infeasible`` certificate: an
  inductive invariant over belief states proving that no plan with ≤ K stages exists (K the budget, or any
  number), over the exact, margin-free class of plans landing on segments of P′ of the straight walls refined
  at the query's set ends;
- a **fewest** plan of k bounces carries a ``bound`` block proving that no plan has ≤ k − 1 bounces; a
  **tolerance** / **constant** plan (or front) of min width W* one proving that no plan (within its budget) is
  wider than some w ≥ W*: W* + 2·end margin + 10⁻⁹ when that holds, else just above the widest margin-free plan
  the exact closure finds (the planner's margins are not the checker's: the gap w − W* is stated).

An answer with nothing to certify raises :class:`NothingToCertify`: a patrol or funnel not found, an answer
stopped by a timeout, or an infeasible answer that holds only within the planner's margins (the exact closure
reaches the goal). A bound that cannot be proved is left out (the optimality claim is then reported as not
re-derived), with a warning in the log.

:func:`write_certificate` checks a certificate with the independent exact checker first and writes it
only if every claim holds (atomically: whole or not at all); otherwise it raises
:class:`CertificateRejected`, naming the first failed claim, and writes nothing.

>>> from solverplan.environment import Environment
>>> from solverplan.plan import find_plan
>>> square = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], name="square")
>>> cert = certificate(find_plan(square, "e0", "e2"), env=square)
>>> cert.kind, cert.claims.bounces, check_certificate(cert).valid
('plan', 2, True)

Then ``write_certificate(cert, "square.cert.json")`` checks it again and writes it.
"""

from __future__ import annotations

import logging
import math
import os
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from typing import Any, Callable, Literal

from solverplan._io import atomic_write_text
from solverplan.bounce.partitions import Partition, partition as make_partition
from solverplan.certify.check import CheckReport, Failure, check_certificate
from solverplan.certify import build_models as models
from solverplan.certify.schema import (Certificate, Claims, EnvironmentRecord, ModelCertificate, Optimality as ClaimedOptimality,
                                       Piece, dumps_certificate)
from solverplan.certify.writer import CycleSpec, MoveSpec, StageSpec, build_certificate
from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError, SolverplanError
from solverplan.plan._results import PositionStrategy
from solverplan.plan.localization import Localization
from solverplan.plan.patrols import Patrol
from solverplan.plan.result import ParetoFront, Plan
from solverplan.explore.depth_first import Exploration
from solverplan.explore.range_limited import RangeExploration
from solverplan.rectilinear.decomposition import Decomposition as RoomsDecomposition
from solverplan.reflection.compose import FieldPlan
from solverplan.reflection.navigation import FieldNavigation
from solverplan.result import Status
from solverplan.wallfollow.ordering import CutOrdering
from solverplan.wallfollow.pursuit import PursuitPlan

__all__ = ["certificate", "write_certificate", "NothingToCertify", "CertificateRejected"]

logger = logging.getLogger(__name__)

_PLAN_MARGIN = 2e-10
"""Radians: the window next to each end of a plan interval in which its exact end is chosen (inside the
interval). The planner's intervals already lie 10⁻⁹ rad inside the exact safe sets, so a tiny margin
suffices; it is kept small so that a proved optimality bound stays within the checker's 10⁻⁹ of the
certified width (the certified width is the plan's minus at most 2·margin, plus the 10⁻¹⁶ of rounding)."""

_PROVED_SLACK = 3e-10
"""A plan claims proved optimality in its certificate only if its bound exceeds its value by at most this
much per stage: the checker allows 10⁻⁹ (per stage for sums) between a proved bound and the certified
value, and the certified widths are up to 4·10⁻¹⁰ below the plan's."""


class NothingToCertify(InputError):
    """The answer has nothing a certificate could claim: a plan without stages, an answer stopped by a timeout,
    an infeasible answer that holds only within the planner's margins, a patrol or funnel that was not found.
    ``why`` is the reason in a few words, for warnings (``"the answer has status 'not-found', not a proved
    infeasible"``)."""

    def __init__(self, message: str, *, why: str) -> None:
        super().__init__(message)
        self.why = why


class CertificateRejected(SolverplanError):
    """The exact checker refused a certificate that was about to be written: ``failure`` is the first
    claim that does not hold, ``report`` the whole verdict. Nothing was written."""

    def __init__(self, cert: Certificate | ModelCertificate, report: CheckReport) -> None:
        self.report = report
        self.failure: Failure = report.failures[0]
        super().__init__(f"the {cert.kind}'s certificate does not verify: {self.failure}")


# ---------------------------------------------------------------------- the two calls
def certificate(result: Any, *, env: Environment | None = None,
                partition: Partition | None = None) -> Certificate | ModelCertificate:
    """The certificate of a planner's answer (see the module docstring for what each kind claims).

    Its claims are exact (rational numbers, the exact safe-set ends); :func:`check_certificate` re-derives them
    with the standard library alone.

    Parameters
    ----------
    result
        A :class:`~solverplan.plan.Plan`, :class:`~solverplan.plan.ParetoFront` (its most tolerant plan),
        :class:`~solverplan.plan.patrols.Patrol` or :class:`~solverplan.plan.funnels.Funnel` (funnels and
        localisation strategies).
    env
        The environment of a plan (plans record only its name and hash; required for plans and fronts).
        Answers that carry their environment need none; if given, it must have the same rings.
    partition
        The partition P′ of ``env`` the answer's segment ids refer to (default: the answer's own, or
        :func:`~solverplan.bounce.partitions.partition` of ``env``).

    Returns
    -------
    Certificate
        The answer's claims, stated exactly (its JSON is ``docs/contract.md``'s certificate); write it with
        :func:`write_certificate`.

    Raises
    ------
    NothingToCertify
        The answer is not found (or infeasible without a proof the checker can re-derive).
    InputError
        ``env`` is not the answer's environment.
    TypeError
        ``result`` is not an answer that has certificates, or a plan without ``env``.

    Examples
    --------
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> cert = sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env)
    >>> cert.kind, len(cert.stages), [(p.edge, p.t0, p.t1) for p in cert.goal]   # the goal as exact pieces
    ('plan', 1, [(0, Fraction(0, 1), Fraction(3, 10))])
    >>> sp.check_certificate(cert).valid
    True
    """
    for cls in type(result).__mro__:
        build = _BUILDERS.get(cls)
        if build is not None:
            return build(result, env, partition)
    raise TypeError(f"cannot certify a {type(result).__name__}: certificates are made of plans, Pareto fronts, "
                    f"patrols, funnels, localisation strategies, rooms, explorations, cut orderings, pursuit plans "
                    f"and composed fields")


def write_certificate(cert: Certificate | ModelCertificate, path: str | os.PathLike[str], *, check: bool = True) -> None:
    """Write ``cert`` as JSON to ``path`` — after checking it exactly, unless ``check=False``.

    The file is written atomically (whole or not at all; a previous file at ``path`` stays intact on failure).

    Parameters
    ----------
    cert
        The certificate (:func:`certificate`).
    path
        The file to write (``docs/contract.md`` describes its JSON).
    check
        Check every claim in exact arithmetic first (:func:`~solverplan.certify.check.check_certificate`).

    Raises
    ------
    CertificateRejected
        ``check`` and a claim of ``cert`` does not hold (the message names the first); nothing is written.
    OSError
        The file cannot be written.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> cert = sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "certificate.json"
    >>> sp.write_certificate(cert, path)                  # checked, then written
    >>> sp.load_certificate(path) == cert
    True
    """
    if check:
        report = check_certificate(cert)
        if not report.valid:
            raise CertificateRejected(cert, report)
    atomic_write_text(Path(path), dumps_certificate(cert))


# ---------------------------------------------------------------------- plans
def _plan(plan: Plan, env: Environment | None, part: Partition | None, budget: Any = "plan") -> Certificate:
    if env is None:
        raise TypeError("a plan does not carry its environment: call certificate(plan, env=...)")
    if not plan.found:
        return _infeasible(plan.status, plan.objective, plan.start, plan.goal, plan.max_bounces, plan.optimality,
                           plan.reason, env, plan.margins)
    part = part if part is not None else make_partition(env)
    plan.check_environment(env, len(part.segments))
    stages = [StageSpec(stage.interval, _plan_moves(part, stage.moves, stage.sources)) for stage in plan.stages]
    partial = set(plan.stats.counts.get("partial_goal_segments", ())) if plan.stats else set()
    if not plan.stats and plan.goal:
        partial = _partial_goal_segments(env, part, plan.goal)
    on_walls = any(spec.target is None for st in stages for spec in st.moves)
    # a stage that leaves from a piece of a segment (a landing unit between the query's set ends) is covered by the
    # exact images of the stage before it, not by whole target segments
    from_pieces = any(stage.sources for stage in plan.stages[1:])
    targets: Literal["image", "segment"] = ("image" if on_walls or from_pieces or (plan.stages and set(plan.stages[-1].to_segments) & partial)
                                            else "segment")
    opt = plan.optimality
    proved = opt.proved
    value = {"tolerance": plan.min_width, "constant": plan.min_width, "sum": plan.sum_width}.get(plan.objective)
    if proved and opt.bound is not None and value is not None and opt.bound - value > _PROVED_SLACK * len(plan.stages):
        proved = False  # an LP/MILP bound with a visible gap: claim the bound, not optimality
    claimed = ClaimedOptimality(method=str(opt.method), proved=proved, bound=None if opt.bound is None else Fraction(opt.bound))
    if not plan.stages and not (plan.start and plan.goal):
        raise NothingToCertify("the plan has no stages and records no start and goal sets: there is nothing to certify",
                               why="a plan of no stages without its start and goal sets")
    start = plan.start if plan.start else list(plan.stages[0].from_segments)
    goal = plan.goal if plan.goal else list(plan.stages[-1].to_segments)
    cert = build_certificate(env, part, stages, start=start, goal=goal, kind="plan", objective=plan.objective,
                             optimality=claimed, targets=targets, margin=_PLAN_MARGIN)
    return _with_bound(cert, plan, env, plan.max_bounces if budget == "plan" else budget)


def _infeasible(status: Status, objective: str, start: str | None, goal: str | None, budget: int | None,
                optimality: Any, reason: str | None, env: Environment, margins: dict | None) -> Certificate:
    """The ``infeasible`` certificate of an exhausted search (module docstring)."""
    from solverplan.certify.negative import NoBound, bound_claim, heading_margin_of

    if status != Status.INFEASIBLE or not optimality.proved:
        raise NothingToCertify(f"the answer has status {status.value!r} ({reason}): not a proof that there is no plan",
                               why=f"the answer has status {status.value!r}, not a proved infeasible")
    if start is None or goal is None:
        raise NothingToCertify("the answer does not record its start and goal sets", why="no start and goal sets recorded")
    start_set, goal_set = env.boundary_set(start), env.boundary_set(goal)
    try:
        bound = bound_claim(env, start_set, goal_set, budget=budget,
                            heading_margin=heading_margin_of(margins, getattr(optimality, "scope", None)))
    except NoBound as exc:
        within = "" if budget is None else f" within {budget} bounces"
        if objective == "constant":
            why = f"no constant plan exists{within}, but plans with changing intervals do ({exc.why})"
        else:
            why = (f"infeasible{within} only within the planner's corner clearance, safe margin, corner rule or landing "
                   f"units: {exc.why}")
        raise NothingToCertify(f"no infeasibility certificate: {why}", why=why) from None
    return Certificate(
        kind="infeasible",
        environment=EnvironmentRecord(env.rings, env.name),
        segments=(),
        start=tuple(Piece(p.edge, p.t0, p.t1) for p in start_set.merged().pieces),
        goal=tuple(Piece(p.edge, p.t0, p.t1) for p in goal_set.merged().pieces),
        stages=(),
        claims=Claims(bounces=0, min_width=Fraction(0), tolerance=Fraction(0), objective=objective),
        producer="solverplan",
        bound=bound,
    )


def _with_bound(cert: Certificate, plan: Plan, env: Environment, budget: int | None) -> Certificate:
    """``cert`` with the bound block proving its optimality claim, when the exact closure proves one."""
    from solverplan.certify.negative import NoBound, bound_claim, heading_margin_of, tolerance_bound

    opt = plan.optimality
    if not plan.stages:
        return cert  # 0 bounces and no heading constraint: optimal for every objective, nothing to bound
    if not opt.proved or plan.start is None or plan.goal is None or plan.objective not in ("fewest", "tolerance", "constant"):
        return cert
    delta = heading_margin_of(plan.margins, opt.scope)
    start_set, goal_set = env.boundary_set(plan.start), env.boundary_set(plan.goal)
    try:
        if plan.objective == "fewest":
            bound = bound_claim(env, start_set, goal_set, budget=len(plan.stages) - 1, heading_margin=delta)
        else:
            bound = tolerance_bound(env, start_set, goal_set, width=plan.min_width or 0.0, floor=cert.claims.min_width,
                                    margins=plan.margins, budget=budget, heading_margin=delta)
    except NoBound as exc:
        logger.warning("no bound block for the %s plan's optimality: %s", plan.objective, exc.why)
        return cert
    return replace(cert, bound=bound)


def _plan_moves(part: Partition, moves: tuple[tuple[int, int], ...],
                sources: tuple[BoundaryPiece, ...] = ()) -> tuple[MoveSpec, ...]:
    """One certificate move per source of a plan stage: a segment, or the exact part of one that a stage leaves from
    (``sources``, aligned with ``moves``: a start set that ends inside a segment). A source with several targets
    lands on a run of consecutive collinear segments (one straight wall: the planner merges collinear vertices):
    its move names the target edge of the run's first segment and no segment, and claims its exact image on the
    wall."""
    targets: dict[int | BoundaryPiece, list[int]] = {}
    for k, (i, j) in enumerate(moves):
        targets.setdefault(sources[k] if sources else i, []).append(j)
    out = []
    for source, js in targets.items():
        if len(js) == 1:
            out.append(MoveSpec(source=source, target=js[0]))
            continue
        ends = {part.segments[j].b for j in js}
        first = [j for j in js if part.segments[j].a not in ends]
        if len(first) != 1:
            raise InputError(f"plan move from {source}: its targets {sorted(js)} are not one run of consecutive segments")
        out.append(MoveSpec(source=source, target_edge=part.segments[first[0]].edge))
    return tuple(out)


def _pareto(front: ParetoFront, env: Environment | None, part: Partition | None) -> Certificate:
    best = front.best()
    if best is None:
        if env is None:
            raise TypeError("a Pareto front does not carry its environment: call certificate(front, env=...)")
        status = Status.INFEASIBLE if front.optimality.proved and not front.optimality.limits else Status.NOT_FOUND
        return _infeasible(status, "tolerance", front.start, front.goal, front.max_bounces, front.optimality,
                           front.reason, env, None)
    return _plan(best.plan, env, part, budget=front.max_bounces)


def _partial_goal_segments(env: Environment, part: Partition, goal: str) -> set[int]:
    """Segments the goal set covers only in part (for plans read back without their stats)."""
    out = set()
    for edge, merged in env.boundary_set(goal).by_edge().items():
        for k in part.edge_segments[edge]:
            s = part.segments[k]
            if not any(lo <= s.t0 and s.t1 <= hi for lo, hi in merged) and any(s.t0 < hi and lo < s.t1 for lo, hi in merged):
                out.add(k)
    return out


# ---------------------------------------------------------------------- contraction answers
def _patrol(result: Patrol, env: Environment | None, part: Partition | None) -> Certificate:
    env, part = _found_in_own_environment(result, env, part, "the patrol", "cycle")
    stages: list[StageSpec] = []
    for st in result.entry:
        stages.append(StageSpec(st.interval, _plan_moves(part, st.moves, st.sources)))
    for cs in result.cycle:
        stages.append(StageSpec(cs.interval, (_cycle_move(env, part, cs),)))
    start = result.start if result.start is not None else [result.cycle[0].from_segment]
    return build_certificate(
        env, part, stages, start=start, kind="cycle",
        cycle=CycleSpec(len(result.entry), headings=tuple(cs.step.heading for cs in result.cycle), visits=result.visit),
        objective=f"patrol-{result.objective}", optimality=_contraction_optimality(result.optimality),
    )


def _cycle_move(env: Environment, part: Partition, stage: Any) -> MoveSpec:
    """The one move of a patrol's cycle stage. Patrols search the straight walls (collinear vertices merged), so a
    stage may leave from a run of user segments over collinear vertices and land on one: such a source is the run's
    span on the line of the edge where the run begins (the stage's ``from_edge``; t beyond [0, 1] runs on over the
    collinear neighbours), and such a target is the straight wall through the edge where the target run begins
    (its ``to_edge``), claiming the exact image."""
    src, dst = stage.from_segments, stage.to_segments
    source: int | tuple[int, Fraction, Fraction] = src[0]
    if len(src) > 1:
        edge = stage.step.from_edge
        a, b = env.edge(edge).a, env.edge(edge).b
        ex, ey = b[0] - a[0], b[1] - a[1]
        norm = ex * ex + ey * ey
        ts = [Fraction((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / norm
              for k in src for x in (part.segments[k].a, part.segments[k].b)]
        source = (edge, min(ts), max(ts))
    if len(dst) > 1:
        return MoveSpec(source=source, target_edge=stage.step.to_edge)
    return MoveSpec(source=source, target=dst[0])


def _funnel(result: PositionStrategy, env: Environment | None, part: Partition | None) -> Certificate:
    """Funnels and localisation strategies: each stage's moves leave the exact position pieces with the
    planner's exact cones."""
    env, part = _found_in_own_environment(result, env, part, f"the {result.kind}", "strategy")
    stages: list[StageSpec] = []
    for st in result.stages:
        if st.sources is None or st.cones is None:
            raise InputError("a funnel stage without exact sources and cones cannot be certified")
        moves = tuple(MoveSpec(source=BoundaryPiece(piece.edge, piece.t0, piece.t1), target_edge=target, directions=cone)
                      for piece, cone, target in zip(st.sources, st.cones, st.target_edges))
        stages.append(StageSpec(st.interval, moves))
    epsilon = result.epsilon if isinstance(result, Localization) else None
    return build_certificate(env, part, stages, start=result.start, goal=result.goal,
                             kind="localize" if epsilon is not None else "funnel", epsilon=epsilon,
                             objective=f"{result.kind}-fewest", optimality=_contraction_optimality(result.optimality))


def _found_in_own_environment(result: Any, env: Environment | None, part: Partition | None, answer: str,
                              certified: str) -> tuple[Environment, Partition]:
    """:func:`_own_environment` of a found contraction answer; for any other, :class:`NothingToCertify` saying
    that ``answer`` (its name in words) has no ``certified`` thing to certify."""
    if not result.found:
        status = f"{answer} has status {result.status.value!r}"
        raise NothingToCertify(f"{status}: there is no {certified} to certify", why=status)
    return _own_environment(result, env, part)


def _own_environment(result: Any, env: Environment | None, part: Partition | None) -> tuple[Environment, Partition]:
    """The environment and partition an answer carries (``env``, if given, must be the same)."""
    own = result.env
    if env is not None and env.rings != own.rings:
        raise InputError(f"the answer was made in another environment ({own.name!r}), not in {env.name!r}")
    if part is None:
        part = result.partition if result.partition is not None else make_partition(own)
    return own, part


def _contraction_optimality(opt: Any) -> ClaimedOptimality | None:
    if opt is None or opt.method == "none" or opt.bound is None or not math.isfinite(opt.bound):
        return None
    return ClaimedOptimality(str(opt.method), bool(opt.proved), Fraction(opt.bound))


def _model(make: Callable[[Any, Environment | None], ModelCertificate]) -> Callable[..., ModelCertificate]:
    """A model certificate's builder (:mod:`solverplan.certify.build_models`) as a :data:`_BUILDERS` entry."""
    return lambda result, env, _partition: make(result, env)


_BUILDERS: dict[type, Callable[[Any, Environment | None, Partition | None], Certificate | ModelCertificate]] = {
    Plan: _plan,
    ParetoFront: _pareto,
    Patrol: _patrol,
    PositionStrategy: _funnel,  # funnels and localisation strategies (both track exact position sets)
    RoomsDecomposition: _model(models.rooms_certificate),
    Exploration: _model(models.exploration_certificate),
    RangeExploration: _model(models.exploration_certificate),
    CutOrdering: _model(models.cut_ordering_certificate),
    PursuitPlan: _model(models.pursuit_certificate),
    FieldNavigation: _model(models.fields_certificate),
    FieldPlan: _model(models.fields_certificate),
}
"""How each type of answer becomes a certificate; :func:`certificate` looks the answer's classes up in order."""
