"""Monte Carlo rollouts of bounce rules and plans: the ground truth that property tests compare against.

The rollouts run on the engine of :mod:`solverplan.rollout` (one batch of rays per bounce, vertex hits and
near-ties flagged or re-resolved exactly, the seed recorded); this module gives it the bouncing robot's
policies (:class:`Policy`):

- :class:`RulePolicy` — a bounce rule (:mod:`solverplan.bounce.rules`) after an initial heading;
- :class:`StagePolicy` — an open-loop sequence of heading intervals (a plan), with the
  allowed landing set of each stage, a goal set, and an optional repeating tail (limit cycles,
  patrols, funnels).

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.rules import Fixed
>>> square = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]])
>>> runs = simulate_rule(square, Fixed(0.5), "e0", bounces=40, trials=100, seed=1, initial=[0.5])
>>> runs.outcome_counts(), runs.seed
({'ok': 100, 'goal': 0, 'failed': 0, 'vertex': 0, 'tie': 0}, 1)
>>> fixed_point = math.tan(0.5) / (1 + math.tan(0.5))     # the period-4 limit cycle (Thm. 1)
>>> bool(np.all(np.abs(runs.final_t - fixed_point) < 1e-9)), sorted(set(runs.final_edge.tolist()))
(True, [0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, Sequence

import numpy as np

from solverplan.choices import Sampling
from solverplan.interval import Interval, heading_interval
from solverplan.bounce.rules import HEADING_MARGIN, BounceRule, sample_headings
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan._docstrings import fill_doc
from solverplan.rollout import (ROLLOUT_DOCS, Contacts, Outcome, Policy, PolicyWalls, Rollouts, Starts, in_boundary_set,
                                sample_boundary, simulate_policy)

__all__ = [
    "Outcome",
    "Contacts",
    "Policy",
    "PolicyWalls",
    "RulePolicy",
    "StagePolicy",
    "Rollouts",
    "simulate_policy",
    "simulate_rule",
    "sample_boundary",
    "in_boundary_set",
    "Starts",
    "plan_policy",
    "simulate_plan",
]


def _initial_bounds(initial: Interval | np.ndarray | Sequence[float] | None, contacts: Contacts):
    if initial is None:
        lo = np.full(len(contacts), HEADING_MARGIN)
        return lo, np.full(len(contacts), math.pi - HEADING_MARGIN)
    if isinstance(initial, Interval):
        return np.full(len(contacts), initial.lo), np.full(len(contacts), initial.hi)
    values = np.asarray(initial, dtype=float).reshape(-1)
    if len(values) == 1:
        chosen = np.full(len(contacts), values[0])
    elif len(contacts) and int(contacts.rollout.max()) >= len(values):
        raise InputError(f"{len(values)} initial headings for more trials ({int(contacts.rollout.max()) + 1})")
    else:
        chosen = values[contacts.rollout]
    return chosen, chosen


@dataclass(frozen=True)
class RulePolicy:
    """Execute a bounce rule at every contact after the first; the first heading comes from ``initial``.

    Parameters
    ----------
    rule
        Any :class:`~solverplan.bounce.rules.BounceRule`.
    initial
        The starting headings: an :class:`Interval` sampled by ``initial_sampling``, an array (one per
        trial, or one for all), or ``None`` for all of (0, π).
    sampling, initial_sampling
        How headings are drawn from the rule's non-deterministic sets and from ``initial``
        (:class:`~solverplan.choices.Sampling`: uniform, endpoints (adversarial), lo, hi, mid).
    """

    rule: BounceRule
    initial: Interval | np.ndarray | Sequence[float] | None = None  # a sequence is stored as a float array
    sampling: Sampling | str = "uniform"
    initial_sampling: Sampling | str = "uniform"

    def __post_init__(self) -> None:
        _check_sampling(self.sampling)
        _check_sampling(self.initial_sampling)
        object.__setattr__(self, "initial", _check_initial(self.initial))

    def headings(self, contacts: Contacts, rng: np.random.Generator) -> np.ndarray:
        if contacts.step == 0:
            lo, hi = _initial_bounds(self.initial, contacts)
            return sample_headings(lo, hi, rng, self.initial_sampling)
        return self.rule.headings(contacts.env, contacts.edge, contacts.incoming, rng, sampling=self.sampling)

    def check(self, contacts: Contacts) -> np.ndarray:
        return np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)

    def __str__(self) -> str:
        return str(self.rule)


def _check_sampling(sampling: str) -> None:
    Sampling.parse(sampling, "sampling")


def _check_initial(initial):
    if initial is None or isinstance(initial, Interval):
        if isinstance(initial, Interval):
            if initial.is_empty:
                raise InvalidBoundarySet("initial heading interval is empty")
            heading_interval(initial.lo, initial.hi)
        return initial
    values = np.asarray(initial, dtype=float).reshape(-1)
    if len(values) == 0:
        raise InputError("initial headings are empty")
    bad = np.flatnonzero(~((values > 0) & (values < math.pi)))
    if len(bad):
        raise InvalidBoundarySet(f"initial heading {values[bad[0]]:g} is not inside (0, π)")
    return values




@dataclass(frozen=True)
class StagePolicy:
    """An open-loop sequence of heading intervals: stage k's interval is executed at the k-th contact.

    Parameters
    ----------
    stages
        Heading intervals ⊂ (0, π), one per stage (a plan's ``interval`` list).
    targets
        Optional, one per stage: where stage k must land (a :class:`BoundarySet` or pieces/segments
        with ``edge, t0, t1``; ``None`` for no check). Landing elsewhere ends the rollout as ``failed``.
    goal
        Optional goal set, tested after the last stage: ``goal`` if inside, else ``failed``. Without a
        goal, finishing the stages ends the rollout as ``ok``.
    repeat_from
        If given, after the last stage the stages from this index on repeat forever (an entry followed
        by a cycle); then the rollout only ends by failing a target, by ``stop_at_goal``, or when the
        bounce budget is spent.
    stop_at_goal
        End a rollout as ``goal`` as soon as it lands in ``goal`` (at any stage).
    sampling
        How a heading is drawn from each interval (uniform, endpoints (adversarial), lo, hi, mid).
    """

    stages: tuple[Interval, ...]
    targets: tuple[Any, ...] | None = None
    goal: Any = None
    repeat_from: int | None = None
    stop_at_goal: bool = False
    sampling: Sampling | str = "uniform"

    def __post_init__(self) -> None:
        stages = tuple(self.stages)
        if not stages:
            raise InputError("a stage policy needs at least one stage")
        for k, interval in enumerate(stages):
            if not isinstance(interval, Interval):
                try:
                    lo, hi = interval
                except (TypeError, ValueError):
                    raise InputError(f"stage {k}: expected a heading interval [lo, hi], got {interval!r}") from None
                interval = Interval(float(lo), float(hi)) if float(lo) <= float(hi) else Interval.EMPTY
            if interval.is_empty:
                raise InvalidBoundarySet(f"stage {k}: the heading interval is empty")
            try:
                heading_interval(interval.lo, interval.hi)
            except InvalidBoundarySet as exc:
                raise InvalidBoundarySet(f"stage {k}: {exc}") from None
        object.__setattr__(self, "stages", tuple(
            s if isinstance(s, Interval) else Interval(float(s[0]), float(s[1])) for s in stages
        ))
        if self.targets is not None:
            targets = tuple(self.targets)
            if len(targets) != len(stages):
                raise InputError(f"{len(targets)} target sets for {len(stages)} stages")
            object.__setattr__(self, "targets", targets)
        if self.repeat_from is not None and not (0 <= self.repeat_from < len(stages)):
            raise InputError(f"repeat_from={self.repeat_from} is not a stage index (0..{len(stages) - 1})")
        if self.stop_at_goal and self.goal is None:
            raise InputError("stop_at_goal needs a goal set")
        _check_sampling(self.sampling)

    def stage_index(self, step: int) -> int | None:
        """Which stage is executed at contact ``step`` (None once a non-repeating plan is done)."""
        n = len(self.stages)
        if step < n:
            return step
        if self.repeat_from is None:
            return None
        period = n - self.repeat_from
        return self.repeat_from + (step - self.repeat_from) % period

    def headings(self, contacts: Contacts, rng: np.random.Generator) -> np.ndarray:
        k = self.stage_index(contacts.step)
        if k is None:  # pragma: no cover - check() ends every rollout first
            raise InputError(f"stage policy has no stage {contacts.step}")
        interval = self.stages[k]
        m = len(contacts)
        return sample_headings(np.full(m, interval.lo), np.full(m, interval.hi), rng, self.sampling)

    def check(self, contacts: Contacts) -> np.ndarray:
        out = np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)
        step = contacts.step
        if step == 0:
            return out
        done = self.stage_index(step - 1)
        if self.targets is not None and done is not None and self.targets[done] is not None:
            out[~in_boundary_set(self.targets[done], contacts.edge, contacts.t)] = Outcome.FAILED
        in_goal = None
        if self.goal is not None:
            in_goal = in_boundary_set(self.goal, contacts.edge, contacts.t)
            if self.stop_at_goal:
                out[(out == Outcome.RUNNING) & in_goal] = Outcome.GOAL
        if self.stage_index(step) is None:
            running = out == Outcome.RUNNING
            if in_goal is None:
                out[running] = Outcome.OK
            else:
                out[running & in_goal] = Outcome.GOAL
                out[running & ~in_goal] = Outcome.FAILED
        return out

    def __str__(self) -> str:
        text = ", ".join(f"[{s.lo:.6g}, {s.hi:.6g}]" for s in self.stages)
        tail = f", repeating from stage {self.repeat_from}" if self.repeat_from is not None else ""
        return f"stages {text}{tail}"




@fill_doc(**ROLLOUT_DOCS)
def simulate_rule(
    env: Environment,
    rule: BounceRule,
    starts: Starts = None,
    *,
    bounces: int,
    trials: int | None = None,
    seed: int | np.random.Generator | None = None,
    initial: Interval | np.ndarray | Sequence[float] | None = None,
    sampling: Sampling | str = "uniform",
    initial_sampling: Sampling | str = "uniform",
    ties: Literal["flag", "exact"] = "flag",
    record: Literal["all", "ends"] = "all",
) -> Rollouts:
    """Rollouts of a bounce rule: start at ``starts`` with a heading from ``initial``, then bounce by ``rule``.

    Parameters
    ----------
    env
        The environment.
    rule
        Any :class:`~solverplan.bounce.rules.BounceRule` (specular, constant heading, a heading interval, ...).
    %(runs)s
    %(seed)s
    initial
        The first heading (radians, CCW from the start's wall): an :class:`~solverplan.interval.Interval`, an
        array (one per trial, or one for all), or ``None`` for all of (0, π).
    sampling, initial_sampling
        How headings are drawn from the rule's sets and from ``initial`` (``uniform``, ``endpoints``
        (adversarial), ``lo``, ``hi``, ``mid``).
    %(rays)s

    Returns
    -------
    Rollouts
        The trajectories (edge, t, x, y and heading per contact), each rollout's outcome, and the seed.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> from solverplan.bounce.rules import Specular
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> runs = simulate_rule(square, Specular(), ([0], [0.25]), bounces=4, initial=[math.pi / 4])
    >>> runs.edge[0].tolist(), runs.t[0].round(12).tolist()      # a period-4 billiard orbit
    ([0, 1, 2, 3, 0], [0.25, 0.75, 0.25, 0.75, 0.25])
    """
    policy = RulePolicy(rule, initial=initial, sampling=sampling, initial_sampling=initial_sampling)
    return simulate_policy(env, policy, starts, bounces=bounces, trials=trials, seed=seed, ties=ties, record=record)


# ---------------------------------------------------------------------- plans
def plan_policy(env: Environment, plan: Any, *, sampling: Sampling | str = "uniform", partition: Any = None) -> tuple[StagePolicy, BoundarySet]:
    """The :class:`StagePolicy` that executes a :class:`~solverplan.plan.Plan`, and its start set.

    Stage k's interval is executed at the k-th contact; landing outside stage k's ``to_segments`` fails
    the rollout; after the last stage the robot must be in the plan's goal set (its ``goal`` boundary
    set; the last stage's segments if the plan does not name it). Starts are the plan's ``start`` set
    (the first stage's segments if it does not name it). The plan must have been made in ``env``
    (same exact rings; its segment ids refer to ``env``'s partition P′).

    Raises :class:`InputError` for an infeasible plan, a plan without stages, or a plan made in
    another environment.
    """
    from solverplan.bounce.partitions import partition as make_partition
    from solverplan.plan.result import Plan

    if not isinstance(plan, Plan):
        raise InputError(f"expected a Plan, got {type(plan).__name__}")
    if not plan.found:
        raise InputError(f"the plan is infeasible ({plan.reason}): there is nothing to execute")
    if not plan.stages:
        raise InputError("the plan has no stages (its start set lies in its goal set): there is nothing to execute")
    part = partition if partition is not None else make_partition(env)
    plan.check_environment(env, part.n_segments)

    def pieces(segments) -> BoundarySet:
        return BoundarySet(tuple(BoundaryPiece(part.segments[s].edge, part.segments[s].t0, part.segments[s].t1)
                                 for s in sorted(segments)))

    targets = tuple(tuple(part.segments[s] for s in stage.to_segments) for stage in plan.stages)
    goal = env.boundary_set(plan.goal) if plan.goal else pieces(plan.stages[-1].to_segments)
    start = env.boundary_set(plan.start) if plan.start else pieces(plan.stages[0].from_segments)
    policy = StagePolicy(plan.intervals, targets=targets, goal=goal, sampling=sampling)
    return policy, start


@fill_doc(seed=ROLLOUT_DOCS["seed"], rays=ROLLOUT_DOCS["rays"])
def simulate_plan(
    env: Environment,
    plan: Any,
    *,
    trials: int,
    seed: int | np.random.Generator | None = None,
    sampling: Sampling | str = "uniform",
    ties: Literal["flag", "exact"] = "exact",
    record: Literal["all", "ends"] = "ends",
    partition: Any = None,
) -> Rollouts:
    """Monte Carlo rollouts of a plan: the ground truth its certificate is about.

    Starts are uniform by arc length in the plan's start set; headings are drawn from each stage's interval
    (:func:`plan_policy`). A rollout succeeds (outcome ``goal``) when every stage lands on its segments and the
    last one in the goal set.

    Parameters
    ----------
    env
        The environment the plan was made in (same exact rings).
    plan
        A found :class:`~solverplan.plan.Plan`, or any strategy with plan-like stages.
    trials
        Number of rollouts.
    %(seed)s
    sampling
        ``uniform``, or ``endpoints``: each heading at an end of its interval, the adversarial choice (also
        ``lo``, ``hi``, ``mid``).
    %(rays)s
    partition
        The partition P′ of ``env``, when already built (the plan's segment ids refer to it).

    Returns
    -------
    Rollouts
        Per rollout its outcome (``runs.success_rate``, ``runs.outcome_counts()``) and trajectory.

    Raises
    ------
    InputError
        An infeasible plan, a plan without stages, a plan made in another environment, bad ``trials``.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> from solverplan.plan import find_plan
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> runs = simulate_plan(square, find_plan(square, "e0", "e2"), trials=1000, seed=3, sampling="endpoints")
    >>> runs.success_rate, runs.outcome_counts()["goal"]
    (1.0, 1000)
    """
    policy, start = plan_policy(env, plan, sampling=sampling, partition=partition)
    return simulate_policy(env, policy, start, bounces=len(plan.stages), trials=trials, seed=seed, ties=ties, record=record)
