"""The rollout engine below the robot models: many robots bounce side by side, one batch of rays per bounce.

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

The engine knows no robot model: a :class:`Policy` maps the current contacts to headings and tests for
termination. The bounce rules' and plans' policies are in :mod:`solverplan.simulate`; the rooms model's (doors
that open and close) in :mod:`solverplan.rectilinear.simulation`. A policy may bring its own
:class:`PolicyWalls` (attribute ``walls``): then contacts are numbered on those walls, and the walls cast the
rays — e.g. rooms whose doors are open (the robot passes) or closed (it bounces off them) for each rollout, as
the policy decides.

>>> import numpy as np
>>> from solverplan.environment import Environment
>>> class Straight:                      # always leave perpendicular to the wall
...     def headings(self, contacts, rng):
...         return np.full(len(contacts), np.pi / 2)
...     def check(self, contacts):
...         return np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> runs = simulate_policy(square, Straight(), ([0], [0.25]), bounces=3, seed=1)
>>> runs.edge.tolist(), runs.outcome_counts()["ok"]
([[0, 2, 0, 2]], 1)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, Iterable, Literal, Protocol, Sequence, runtime_checkable

import numpy as np

from solverplan.choices import Ties
from solverplan.environment import BoundaryPiece, BoundarySet, Environment, check_edges
from solverplan._docstrings import fill_doc
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.geometry.raycast import RayHits, cast_from_boundary, heading_directions
from solverplan.limits import MAX_BOUNCES, MAX_TRIALS, quote, refuse_beyond_memory
from solverplan.progress import tick
from solverplan.result import answer_dataclass

__all__ = [
    "Outcome",
    "Contacts",
    "Policy",
    "PolicyWalls",
    "Rollouts",
    "simulate_policy",
    "sample_boundary",
    "in_boundary_set",
    "Starts",
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
@answer_dataclass("simulation", eq=False)
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

        ``partition`` is a :class:`~solverplan.bounce.partitions.Partition` (its ``segments_at``; a float
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
ROLLOUT_DOCS = {
    "runs": """
starts
    Where the rollouts start (:data:`~solverplan.rollout.Starts`: a boundary set sampled uniformly by arc length,
    explicit ``(edges, t)`` arrays with t ∈ [0, 1], or ``None`` for the whole boundary).
bounces
    How many bounces each rollout makes at most (≥ 0).
trials
    Number of rollouts (needed when starts are sampled; defaults to the number of explicit starts).""",
    "seed": """
seed
    An integer, a :class:`numpy.random.Generator`, or None for a fresh seed; recorded in the result.""",
    "rays": """
ties
    ``"flag"``: stop and flag every ray the float caster cannot call (outcome ``vertex`` when its hit is within
    the tolerance of a vertex, else ``tie``); ``"exact"``: re-resolve those rays exactly and flag only exact
    vertex hits.
record
    ``"all"`` keeps every contact; ``"ends"`` only the start and the last contact (for long runs).""",
}
"""The parameters every simulator describes alike (:func:`~solverplan._docstrings.fill_doc` fragments)."""


@fill_doc(**ROLLOUT_DOCS)
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
    %(runs)s
    %(seed)s
    %(rays)s

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


