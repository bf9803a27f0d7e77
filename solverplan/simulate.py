"""Monte Carlo rollouts of bounce rules and plans: the ground truth that property tests compare against.

Many robots ("rollouts", one per trial) run side by side: at every stage each one asks its
*policy* for a heading at its current boundary point, all rays are cast in **one batch** (the
vectorised caster), and each robot lands on the boundary point its ray hits first. A rollout stops
when its policy says so (goal reached, or failed — e.g. landed outside a plan stage's targets), when
its bounce budget is spent, or when the float caster cannot call its ray: a hit within the caster's
tolerance of a vertex (**vertex**; the paper's model has no trajectories through vertices) or a
near-tie (**tie**: the ray grazes a vertex on the way, or two edges are nearly tied). Flagged
rollouts are stopped and counted, never silently assigned to an edge; ``ties="exact"`` instead
re-resolves every such ray in exact arithmetic and flags only exact vertex hits.

Randomness comes from one :class:`numpy.random.Generator`; the seed is recorded in the result
(a fresh seed is drawn and recorded when none is given), so every run can be replayed.

Policies (:class:`Policy`) map the current contacts to headings and test for termination:

- :class:`RulePolicy` — a bounce rule (:mod:`solverplan.bounce.rules`) after an initial heading;
- :class:`StagePolicy` — an open-loop sequence of heading intervals (a plan), with the
  allowed landing set of each stage, a goal set, and an optional repeating tail (limit cycles,
  patrols, funnels).

A policy may bring its own :class:`PolicyWalls` (attribute ``walls``): then contacts are numbered on those
walls, and the walls cast the rays — e.g. rooms whose doors are open (the robot passes) or closed (it
bounces off them) for each rollout, as the policy decides.

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
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, Iterable, Literal, Protocol, Sequence, runtime_checkable

import numpy as np

from solverplan.choices import Sampling, Ties
from solverplan.interval import Interval, heading_interval
from solverplan.bounce.rules import (
    HEADING_MARGIN,
    SAMPLINGS,
    BounceRule,
    check_edges,
    sample_headings,
)
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.geometry.raycast import RayHits, cast_from_boundary, heading_directions
from solverplan.limits import MAX_BOUNCES, MAX_TRIALS, quote, refuse_beyond_memory
from solverplan.progress import tick
from solverplan.result import answer_kind

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


class Outcome(IntEnum):
    """How a rollout ended (``RUNNING`` is what a policy's check returns to carry on)."""

    RUNNING = -1
    OK = 0  #: the bounce budget was spent with nothing to report
    GOAL = 1  #: the policy's goal test succeeded
    FAILED = 2  #: the policy's check failed (e.g. a plan stage landed outside its targets)
    VERTEX = 3  #: the ray hit within the caster's tolerance of a vertex (flagged, stopped there)
    TIE = 4  #: the float caster could not call the ray (grazes a vertex, near-tied edges); flagged, stopped

    @property
    def label(self) -> str:
        return self.name.lower()


_LABELS = tuple(o.label for o in Outcome if o is not Outcome.RUNNING)

Starts = BoundarySet | str | tuple[Sequence[int] | np.ndarray, Sequence[float] | np.ndarray] | None
"""Where rollouts start: a boundary set (or its text, ``"e3:0.25:0.75,e4"``), sampled uniformly by arc
length; explicit ``(edges, t)`` arrays (one start per trial, or one start repeated); or ``None`` for
the whole boundary."""


# ---------------------------------------------------------------------- contacts and policies
@dataclass(frozen=True, slots=True)
class Contacts:
    """The current contacts of the rollouts still running, as arrays (one entry per running rollout).

    Attributes
    ----------
    env
        The environment.
    step
        Bounces made so far (0 at the start; the same for every running rollout).
    rollout
        Index of each running rollout among all trials.
    edge, t
        Boundary coordinates of the contacts (on the policy's own :class:`PolicyWalls` when it has them).
    point
        Contact points, shape (m, 2).
    incoming
        Unit travel directions on arrival, shape (m, 2); NaN at step 0 (no arrival yet).
    """

    env: Environment
    step: int
    rollout: np.ndarray
    edge: np.ndarray
    t: np.ndarray
    point: np.ndarray
    incoming: np.ndarray

    def __len__(self) -> int:
        return len(self.rollout)


@runtime_checkable
class Policy(Protocol):
    """What the simulator asks of a policy at every stage."""

    def headings(self, contacts: Contacts, rng: np.random.Generator) -> np.ndarray:
        """The heading (radians, in (0, π), CCW from the contact's edge) each running rollout executes."""
        ...

    def check(self, contacts: Contacts) -> np.ndarray:
        """Per contact, :data:`Outcome.RUNNING` to carry on or the outcome to stop with (int array)."""
        ...


@runtime_checkable
class PolicyWalls(Protocol):
    """PolicyWalls of a policy's own (its attribute ``walls``), in place of the environment's edges.

    Contacts are then ``(edge, t)`` on these walls (ids ``0 .. n_edges − 1``, t ∈ [0, 1] along each), starts
    must be explicit ``(edges, t)`` arrays, and every batch of rays is cast by :meth:`cast`, which may depend
    on the rollout (``contacts.rollout``): walls that open and close. Headings are radians in (0, π), CCW
    from the wall the robot is on, as everywhere.
    """

    @property
    def n_edges(self) -> int: ...

    def points_at(self, edges: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Points (m, 2) of wall coordinates."""
        ...

    def directions(self, edges: np.ndarray, headings: np.ndarray) -> np.ndarray:
        """Unit world directions (m, 2) of headings leaving the walls ``edges``."""
        ...

    def cast(self, contacts: Contacts, headings: np.ndarray, *, exact_ties: bool) -> RayHits:
        """The first wall each contact's ray hits (edges numbered on these walls), as the ray caster reports it."""
        ...


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
    sampling = Sampling.parse(sampling, "sampling").value


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


def in_boundary_set(pieces: BoundarySet | Iterable[Any], edges: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Vectorised membership of boundary points (edges, t) in a set of pieces, closed at both ends.

    ``pieces`` is a :class:`BoundarySet` or any iterable of objects with ``edge``, ``t0`` and ``t1``
    (boundary pieces, partition segments). Floats are compared with the pieces' ends rounded to float.
    """
    items = pieces.pieces if isinstance(pieces, BoundarySet) else tuple(pieces)
    edges = np.asarray(edges)
    t = np.asarray(t, dtype=float)
    inside = np.zeros(edges.shape, dtype=bool)
    for p in items:
        inside |= (edges == p.edge) & (t >= float(p.t0)) & (t <= float(p.t1))
    return inside


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


# ---------------------------------------------------------------------- starts and seeds
def sample_boundary(env: Environment, pieces: BoundarySet, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``n`` boundary points drawn uniformly by arc length from ``pieces``: arrays (edges, t)."""
    edges = np.array([p.edge for p in pieces.pieces], dtype=np.int64)
    t0 = np.array([float(p.t0) for p in pieces.pieces])
    t1 = np.array([float(p.t1) for p in pieces.pieces])
    weights = (t1 - t0) * env.edge_lengths[edges]
    total = weights.sum()
    if not total > 0:
        raise InvalidBoundarySet(f"start set {pieces} has zero length")
    cumulative = np.cumsum(weights)
    s = rng.random(n) * total
    k = np.minimum(np.searchsorted(cumulative, s, side="right"), len(weights) - 1)
    before = cumulative[k] - weights[k]
    frac = np.clip((s - before) / weights[k], 0.0, 1.0)
    return edges[k], t0[k] + frac * (t1[k] - t0[k])


def _whole_boundary(env: Environment) -> BoundarySet:
    from fractions import Fraction

    return BoundarySet(tuple(BoundaryPiece(e, Fraction(0), Fraction(1)) for e in range(env.n_edges)))


def _starts(env: Environment, starts: Starts, trials: int | None, rng: np.random.Generator):
    if starts is None or isinstance(starts, (str, BoundarySet)):
        pieces = _whole_boundary(env) if starts is None else (
            env.boundary_set(starts) if isinstance(starts, str) else starts
        )
        if trials is None:
            raise InputError("trials is needed to sample starts from a boundary set")
        return sample_boundary(env, pieces, trials, rng)
    try:
        edges, t = starts
    except (TypeError, ValueError):
        raise InputError(f"starts must be a boundary set or (edges, t) arrays, got {starts!r}") from None
    edges = check_edges(env, edges)
    t = np.asarray(t, dtype=float).reshape(-1)
    if len(t) != len(edges):
        raise InputError(f"start edges and t differ in length: {len(edges)} and {len(t)}")
    bad = np.flatnonzero(~((t >= 0) & (t <= 1)))
    if len(bad):
        raise InvalidBoundarySet(f"start t = {t[bad[0]]:g} is not in [0, 1]")
    if trials is not None and trials != len(edges):
        if len(edges) != 1:
            raise InputError(f"{len(edges)} explicit starts for trials={trials}")
        edges, t = np.repeat(edges, trials), np.repeat(t, trials)
    return edges, t


def _wall_starts(walls: PolicyWalls, starts: Starts, trials: int | None):
    """Explicit ``(edges, t)`` starts on a policy's own walls (boundary sets name the environment's edges)."""
    if starts is None or isinstance(starts, (str, BoundarySet)):
        raise InputError("a policy with walls of its own needs explicit (edges, t) starts on those walls")
    try:
        edges, t = starts
    except (TypeError, ValueError):
        raise InputError(f"starts must be (edges, t) arrays, got {starts!r}") from None
    edges = np.asarray(edges, dtype=np.int64).reshape(-1)
    t = np.asarray(t, dtype=float).reshape(-1)
    if len(t) != len(edges):
        raise InputError(f"start edges and t differ in length: {len(edges)} and {len(t)}")
    bad = np.flatnonzero((edges < 0) | (edges >= walls.n_edges) | ~((t >= 0) & (t <= 1)))
    if len(bad):
        raise InvalidBoundarySet(f"start {bad[0]} (wall {edges[bad[0]]}, t = {t[bad[0]]:g}) is not on the walls")
    if trials is not None and trials != len(edges):
        raise InputError(f"{len(edges)} explicit starts for trials={trials}")
    return edges, t


def _generator(seed: int | np.random.Generator | None):
    """(rng, recorded seed, recorded generator state)."""
    if isinstance(seed, np.random.Generator):
        return seed, None, seed.bit_generator.state
    if seed is None:
        entropy = np.random.SeedSequence().entropy  # fresh, and recorded so the run can be replayed
        assert isinstance(entropy, int)  # drawn from the OS when none is given: one integer
        seed = entropy
    elif isinstance(seed, (bool, float)) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer or a numpy Generator, got {seed!r}")
    rng = np.random.default_rng(int(seed))
    return rng, int(seed), None


# ---------------------------------------------------------------------- results
@answer_kind("simulation")
@dataclass(frozen=True, eq=False)
class Rollouts:
    """The result of a simulation: trajectories, per-rollout outcomes, and how to replay it.

    Trajectory arrays have shape (trials, columns). With ``record="all"`` column k is the k-th contact
    (k = 0 the start, up to ``bounces``); with ``record="ends"`` there are two columns, the start and
    the contact where the rollout stopped. After a rollout stops, its later entries are −1 (edge) or
    NaN. ``heading[:, k]`` is the heading executed at contact k (NaN at the last contact).

    Attributes
    ----------
    seed
        The integer seed of the run (drawn fresh and recorded when none was given); ``None`` when a
        Generator was passed, whose state at the start is then in ``rng_state``.
    status
        int8 :class:`Outcome` per rollout; ``stop_step`` the number of bounces it made.
    """

    env: Environment
    policy: str
    bounces: int
    record: Literal["all", "ends"]
    seed: int | None
    rng_state: dict | None
    edge: np.ndarray
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    heading: np.ndarray
    status: np.ndarray
    stop_step: np.ndarray
    ties: str = "flag"
    extra: dict = field(default_factory=dict)

    @property
    def trials(self) -> int:
        return len(self.status)

    def _final_column(self) -> np.ndarray:
        return self.stop_step if self.record == "all" else np.ones(self.trials, dtype=np.int64)

    @property
    def final_edge(self) -> np.ndarray:
        """Edge of the contact where each rollout stopped."""
        return self.edge[np.arange(self.trials), self._final_column()]

    @property
    def final_t(self) -> np.ndarray:
        return self.t[np.arange(self.trials), self._final_column()]

    @property
    def final_points(self) -> np.ndarray:
        k = self._final_column()
        rows = np.arange(self.trials)
        return np.stack([self.x[rows, k], self.y[rows, k]], axis=1)

    def path(self, rollout: int) -> np.ndarray:
        """The recorded contact points of one rollout, shape (contacts, 2)."""
        last = int(self._final_column()[rollout])
        return np.stack([self.x[rollout, : last + 1], self.y[rollout, : last + 1]], axis=1)

    def segments(self, partition: Any) -> np.ndarray:
        """The P′ segment id of every recorded contact (−1 where there is none), shaped like ``edge``.

        ``partition`` is a :class:`~solverplan.bounce.partition.Partition` (its ``segments_at``; a float
        t within rounding of an inserted point may land on either side of it).
        """
        out = np.full(self.edge.shape, -1, dtype=np.int64)
        ok = self.edge >= 0
        if ok.any():
            out[ok] = partition.segments_at(self.edge[ok], self.t[ok])
        return out

    def outcome_counts(self) -> dict[str, int]:
        counts = np.bincount(self.status.astype(np.int64), minlength=len(_LABELS))
        return {label: int(counts[k]) for k, label in enumerate(_LABELS)}

    @property
    def success_rate(self) -> float:
        """Fraction of rollouts that reached the goal."""
        return float(np.mean(self.status == Outcome.GOAL)) if self.trials else 0.0

    @property
    def flagged(self) -> np.ndarray:
        """Rollouts stopped by a vertex hit or a near-tie."""
        return (self.status == Outcome.VERTEX) | (self.status == Outcome.TIE)

    def summary(self) -> dict:
        """Counts by outcome, success rate, and bounce statistics (overall and of goal-reaching rollouts)."""
        goal = self.status == Outcome.GOAL
        steps = self.stop_step

        def stats(values: np.ndarray) -> dict | None:
            if len(values) == 0:
                return None
            return {"mean": float(np.mean(values)), "median": float(np.median(values)),
                    "min": int(np.min(values)), "max": int(np.max(values))}

        return {
            "trials": self.trials,
            "outcomes": self.outcome_counts(),
            "success_rate": self.success_rate,
            "flagged_rate": float(np.mean(self.flagged)) if self.trials else 0.0,
            "bounces": stats(steps),
            "bounces_to_goal": stats(steps[goal]),
        }

    def to_json(self) -> dict:
        """The run's parameters and :meth:`summary` (not the trajectories)."""
        return {
            "kind": "simulation",
            "environment": self.env.name,
            "policy": self.policy,
            "bounces": self.bounces,
            "seed": self.seed,
            "ties": self.ties,
            **self.summary(),
        }

    def to_text(self, *, width: int = 100) -> str:
        s = self.summary()
        outcomes = ", ".join(f"{k} {v}" for k, v in s["outcomes"].items() if v)
        lines = [
            f"{self.trials} rollouts of {self.policy} in {self.env.name or 'environment'}, "
            f"up to {self.bounces} bounces, seed {self.seed}",
            f"outcomes: {outcomes}",
            f"success rate: {s['success_rate']:.4f}",
        ]
        if s["bounces_to_goal"]:
            b = s["bounces_to_goal"]
            lines.append(f"bounces to goal: mean {b['mean']:.2f}, median {b['median']:g}, max {b['max']}")
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- the simulator
def simulate_policy(
    env: Environment,
    policy: Policy,
    starts: Starts = None,
    *,
    bounces: int,
    trials: int | None = None,
    seed: int | np.random.Generator | None = None,
    ties: Literal["flag", "exact"] = "flag",
    record: Literal["all", "ends"] = "all",
) -> Rollouts:
    """Run ``trials`` rollouts of ``policy`` for up to ``bounces`` bounces each, vectorised over trials.

    Parameters
    ----------
    env
        The environment.
    policy
        A :class:`Policy` (e.g. :class:`RulePolicy`, :class:`StagePolicy`).
    starts
        See :data:`Starts` (default: the whole boundary, uniformly by arc length).
    bounces
        The bounce budget (≥ 0).
    trials
        Number of rollouts (needed when starts are sampled; defaults to the number of explicit starts).
    seed
        An integer, a :class:`numpy.random.Generator`, or None for a fresh seed; recorded in the result.
    ties
        ``"flag"``: stop and flag every ray the float caster cannot call (outcome ``vertex`` when its hit
        is within the tolerance of a vertex, else ``tie``). ``"exact"``: re-resolve those rays exactly
        and flag only exact vertex hits.
    record
        ``"all"`` keeps every contact; ``"ends"`` only the start and the last contact (long runs).

    One batch cast per bounce; the work is O(trials × bounces) casts.
    """
    if isinstance(bounces, bool) or not isinstance(bounces, (int, np.integer)) or not 0 <= bounces <= MAX_BOUNCES:
        raise InputError(f"bounces must be an integer in [0, {MAX_BOUNCES:,}], got {quote(bounces)}")
    if trials is not None and (isinstance(trials, bool) or not isinstance(trials, (int, np.integer))
                               or not 1 <= trials <= MAX_TRIALS):
        raise InputError(f"trials must be an integer in [1, {MAX_TRIALS:,}], got {quote(trials)}")
    ties = Ties.parse(ties, "ties").value
    if record not in ("all", "ends"):
        raise InputError(f"record must be 'all' or 'ends', got {record!r}")
    if not isinstance(policy, Policy):
        raise InputError(f"{policy!r} is not a policy: it needs headings(contacts, rng) and check(contacts)")
    bounces = int(bounces)
    if trials is not None:
        # Measured peak ≈ 400 bytes per rollout of a 2-bounce plan with record="ends" (10⁷ rollouts: 4 GB), plus
        # 16 bytes per recorded contact: refuse up front rather than end in MemoryError minutes later.
        kept = bounces + 1 if record == "all" else 2
        refuse_beyond_memory(trials * (400 + 16 * kept), f"{trials:,} rollouts of {bounces:,} bounces")
    rng, seed_used, state = _generator(seed)
    walls: PolicyWalls | None = getattr(policy, "walls", None)
    if walls is not None and not isinstance(walls, PolicyWalls):
        raise InputError(f"{policy!r} has walls that are not PolicyWalls: they need n_edges, points_at, directions and cast")
    start_edges, start_t = _starts(env, starts, trials, rng) if walls is None else _wall_starts(walls, starts, trials)
    m = len(start_edges)
    columns = bounces + 1 if record == "all" else 2
    edge = np.full((m, columns), -1, dtype=np.int64)
    t_arr = np.full((m, columns), np.nan)
    x_arr = np.full((m, columns), np.nan)
    y_arr = np.full((m, columns), np.nan)
    heading = np.full((m, columns), np.nan)
    status = np.full(m, Outcome.RUNNING, dtype=np.int8)
    stop_step = np.zeros(m, dtype=np.int64)

    active = np.arange(m)
    cur_e, cur_t = start_edges.astype(np.int64), start_t.astype(float)
    incoming = np.full((m, 2), np.nan)
    points = env.points_at(cur_e, cur_t) if walls is None else walls.points_at(cur_e, cur_t)

    def store(column: int, rows, e, t, p) -> None:
        edge[rows, column], t_arr[rows, column] = e, t
        x_arr[rows, column], y_arr[rows, column] = p[:, 0], p[:, 1]

    store(0, active, cur_e, cur_t, points)
    if record == "ends":
        store(1, active, cur_e, cur_t, points)  # the last contact so far: a rollout stopped at once ends where it starts
    tolerance_ties = ties == "exact"
    for step in range(bounces + 1):
        if len(active) == 0:
            break
        tick("rollouts: bounces", step, bounces)  # the progress bar of long simulations
        contacts = Contacts(env, step, active, cur_e, cur_t, points, incoming)
        verdict = np.asarray(policy.check(contacts), dtype=np.int8)
        if len(verdict) != len(active):
            raise InputError(f"policy check returned {len(verdict)} outcomes for {len(active)} contacts")
        done = verdict != Outcome.RUNNING
        if done.any():
            status[active[done]] = verdict[done]
            stop_step[active[done]] = step
            keep = ~done
            active, cur_e, cur_t, points, incoming = active[keep], cur_e[keep], cur_t[keep], points[keep], incoming[keep]
            contacts = Contacts(env, step, active, cur_e, cur_t, points, incoming)
        if step == bounces or len(active) == 0:
            break
        h = np.asarray(policy.headings(contacts, rng), dtype=float).reshape(-1)
        if len(h) != len(active):
            raise InputError(f"policy returned {len(h)} headings for {len(active)} contacts")
        hcol = step if record == "all" else 0
        if record == "all" or step == 0:
            heading[active, hcol] = h
        if walls is None:
            hits = cast_from_boundary(env, cur_e, cur_t, h, exact_ties=tolerance_ties)
        else:
            hits = walls.cast(contacts, h, exact_ties=tolerance_ties)
        on_vertex = hits.vertex >= 0
        tie = hits.uncertain & ~on_vertex
        flagged = on_vertex | tie
        column = step + 1 if record == "all" else 1
        landed = np.stack([hits.x, hits.y], axis=1)
        store(column, active, hits.edge, hits.t, landed)
        if flagged.any():
            rows = active[flagged]
            status[rows] = np.where(on_vertex[flagged], Outcome.VERTEX, Outcome.TIE)
            stop_step[rows] = step + 1
        keep = ~flagged
        incoming = (heading_directions(env, cur_e[keep], h[keep]) if walls is None
                    else walls.directions(cur_e[keep], h[keep]))
        active, cur_e, cur_t = active[keep], hits.edge[keep], hits.t[keep]
        points = landed[keep]
    status[status == Outcome.RUNNING] = Outcome.OK
    stop_step[active] = bounces
    return Rollouts(
        env=env,
        policy=str(policy),
        bounces=bounces,
        record=record,
        seed=seed_used,
        rng_state=state,
        edge=edge,
        t=t_arr,
        x=x_arr,
        y=y_arr,
        heading=heading,
        status=status,
        stop_step=stop_step,
        ties=ties,
    )


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
    starts
        Where the rollouts start (:data:`Starts`: a boundary set sampled uniformly by arc length, explicit
        ``(edges, t)`` arrays with t ∈ [0, 1], or ``None`` for the whole boundary).
    bounces
        How many bounces each rollout makes at most (≥ 0).
    trials
        Number of rollouts (needed when starts are sampled; defaults to the number of explicit starts).
    seed
        An integer, a :class:`numpy.random.Generator`, or None for a fresh seed; recorded in the result.
    initial
        The first heading (radians, CCW from the start's wall): an :class:`~solverplan.interval.Interval`, an
        array (one per trial, or one for all), or ``None`` for all of (0, π).
    sampling, initial_sampling
        How headings are drawn from the rule's sets and from ``initial`` (``uniform``, ``endpoints``
        (adversarial), ``lo``, ``hi``, ``mid``).
    ties
        ``"flag"`` (default): stop and flag every ray the float caster cannot call; ``"exact"``: re-resolve
        those rays exactly and flag only exact vertex hits.
    record
        ``"all"`` keeps every contact; ``"ends"`` only the start and the last contact.

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
    from solverplan.bounce.partition import partition as make_partition
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
    seed
        An integer, a :class:`numpy.random.Generator`, or None for a fresh seed; recorded in the result.
    sampling
        ``uniform``, or ``endpoints``: each heading at an end of its interval, the adversarial choice (also
        ``lo``, ``hi``, ``mid``).
    ties
        ``"exact"`` (default): re-resolve the rays the float caster cannot call, so only exact vertex hits are
        flagged; ``"flag"``: flag every such ray.
    record
        ``"ends"`` (default) keeps the start and the last contact; ``"all"`` every contact.
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
