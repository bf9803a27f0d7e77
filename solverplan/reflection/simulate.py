"""Rollouts of the composed fields: a single integrator and an inertial robot, with noise, collisions resolved
against the real walls, and the paper's three scenarios (Stager and Tanner, §IV).

**Robots.** A point robot commanded at the control rate (20 Hz, as the paper's Vicon loop) with the unit direction of
the field at its position times the scenario's speed, a noisy heading (normal, ``heading_noise`` radians per
command) and speed (relative normal ``speed_noise``); commands below the motors' ``dead_band`` give no motion. The
*integrator* moves at the command; the *inertial* robot's velocity follows it with at most ``accel`` (length/s²) —
the limited control authority that makes it overshoot. Physics runs at ``physics_rate``.

**Collisions** are resolved against the real walls with the project's ray caster
(:class:`~solverplan.geometry.raycast.RayCaster`): a step that leaves the robot's convex cell is cast from the robot's
position (ties near vertices resolved exactly); a hit before the step's end stops the robot at the hit point and
reflects its velocity on the hit wall: normal component × −``restitution``, tangential × (1 − ``friction``); a
vertex hit reverses the velocity × ``restitution`` (its reflection is undefined). Robots keep a clearance of 10⁻⁷
of the environment's size from the walls of their cell (they are pushed off along the walls' normals), so every
position is strictly inside the free space. A step that stays in the convex cell, clear of its walls, cannot meet
a wall (the segment stays in the cell). A collision is seen by the controller at the next control tick (the
paper's detection delay).

**Scenarios** (§IV): *constrained* — the nominal fields at a low speed, meant to avoid boundary contact;
*unconstrained* — the same fields at a high constant speed; *reflection* — the high speed with the hybrid controller
of the reflection cells (aim at the reflection zone from the first entry into the cell until a wall is hit, then the
nominal field; each cell's reflection is used at most once per run, which preserves convergence).

Trials of all scenarios run together, vectorised across trials; every scenario has its own random stream (from
``seed`` and the name of its stream), so its statistics do not depend on which other scenarios run. The reflection
scenario draws from the unconstrained one's stream (common random numbers): trial k gets the same noise at every
control tick in both (one draw per trial and tick, finished or not), so without reflection zones the two are the
same runs, and their difference measures the zones, not the noise.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Sequence

import numpy as np

from solverplan.choices import RobotKind, ScenarioName
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.geometry.raycast import RayCaster
from solverplan.progress import tick
from solverplan.reflection.compose import REFERENCE_WIDTH, FieldPlan, mean_width

__all__ = ["FieldRobotDynamics", "Scenario", "SCENARIOS", "ScenarioRun", "simulate_scenarios", "default_scenarios"]

MODELS = RobotKind.values()
SCENARIOS = ScenarioName.values()


MAX_AUTO_TIME = 600.0
"""Longest default time limit (s): trials × limit × control rate bounds the work of runs that never arrive."""


def _time_limit(model: FieldRobotDynamics, plan: FieldPlan, speed: float) -> float:
    """The model's ``max_time``, or by default ten times the route at ``speed``, within [60 s, MAX_AUTO_TIME]."""
    if model.max_time is not None:
        return model.max_time
    stops = [np.array([float(plan.start[0]), float(plan.start[1])])]
    stops += [plan.cells[c].float_vertices.mean(axis=0) for c in plan.sequence]
    stops.append(np.array([float(plan.goal[0]), float(plan.goal[1])]))
    route = float(sum(np.hypot(*(b - a)) for a, b in zip(stops, stops[1:])))
    return max(60.0, min(10.0 * route / speed, MAX_AUTO_TIME))


@dataclass(frozen=True, slots=True)
class FieldRobotDynamics:
    """The fields robot's dynamics and controller, as :func:`simulate_scenarios` drives them.

    Lengths are in the environment's units, times in seconds.

    Attributes
    ----------
    kind
        ``"inertial"`` (a mass with bounded acceleration that bounces off walls) or ``"integrator"`` (the
        velocity is the command).
    control_rate, physics_rate
        Commands per second, and integration steps per second (Hz; a multiple of the control rate).
    accel
        Inertial: the largest change of velocity per second (length/s²).
    restitution, friction
        Inertial: the normal speed kept (reversed) by an impact, and the share of the tangential speed lost.
    dead_band
        Commanded speeds below this give no motion (length/s). ``None`` (default): :meth:`resolved` makes it
        1/16 of the slowest commanded speed, at most 0.05 length/s (0.05 at the default speeds).
    heading_noise, speed_noise
        Standard deviation of the commanded heading (radians), and relative standard deviation of the speed.
    goal_radius
        The goal is reached within this distance (length). ``None`` (default): :meth:`resolved` makes it 0.1
        length units, or less in an environment narrower than the shipped ``serpentine``: 0.1 × w/0.4422 with w
        its mean width (:func:`~solverplan.reflection.compose.mean_width`) — never a radius that holds the whole
        room.
    max_time
        A trial that has not reached the goal by then failed (s); ``None``: ten times the time the scenario's
        speed takes along the cell sequence's centres, at least 60 s and at most 600 s.

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.FieldRobotDynamics(kind="integrator", heading_noise=0.3).to_json()["heading_noise"]
    0.3
    >>> sp.FieldRobotDynamics(control_rate=30)
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: physics_rate must be a positive multiple of control_rate
    """

    kind: str = "inertial"
    control_rate: float = 20.0  #: commands per second (Hz)
    physics_rate: float = 400.0  #: integration steps per second (a multiple of the control rate)
    accel: float = 2.0  #: inertial: the largest change of velocity per second (length/s²)
    restitution: float = 0.8  #: inertial: normal speed kept (reversed) by an impact
    friction: float = 0.1  #: inertial: share of the tangential speed lost in an impact
    dead_band: float | None = None  #: commanded speeds below this give no motion (length/s); None: see resolved()
    heading_noise: float = 0.15  #: standard deviation of the commanded heading (radians)
    speed_noise: float = 0.05  #: relative standard deviation of the commanded speed
    goal_radius: float | None = None  #: the goal is reached within this distance (length); None: see resolved()
    #: a trial that has not reached the goal by then failed (s); None: ten times the time the scenario's speed takes
    #: along the cell sequence's centres, at least 60 s and at most 600 s (a 100 m route at 0.8 m/s takes 125 s)
    max_time: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", RobotKind.parse(self.kind, "robot model").value)
        substeps = self.physics_rate / self.control_rate
        if self.control_rate <= 0 or substeps < 1 or abs(substeps - round(substeps)) > 1e-9:
            raise InputError("physics_rate must be a positive multiple of control_rate")
        for name in ("accel", "goal_radius", "max_time"):
            if getattr(self, name) is not None and not getattr(self, name) > 0:
                raise InputError(f"{name} must be positive, got {getattr(self, name)}")
        for name in ("goal_radius", "dead_band"):
            if getattr(self, name) is not None and not math.isfinite(getattr(self, name)):
                raise InputError(f"{name} must be finite, got {getattr(self, name)}")
        for name in ("restitution", "friction"):
            if not 0 <= getattr(self, name) <= 1:
                raise InputError(f"{name} must be in [0, 1], got {getattr(self, name)}")
        for name in ("dead_band", "heading_noise", "speed_noise"):
            if getattr(self, name) is not None and not getattr(self, name) >= 0:
                raise InputError(f"{name} must be non-negative, got {getattr(self, name)}")

    def to_json(self) -> dict:
        return {name: getattr(self, name) for name in self.__slots__}

    @property
    def unset(self) -> tuple[str, ...]:
        """The lengths left to :meth:`resolved` (``goal_radius``, ``dead_band``)."""
        return tuple(name for name in ("goal_radius", "dead_band") if getattr(self, name) is None)

    def resolved(self, env: Environment, speed: float) -> FieldRobotDynamics:
        """The robot with its unset lengths made relative to the environment and the commanded speeds.

        ``goal_radius``: 0.1 length units, or 0.1 × w/w₀ when the environment's mean width w
        (:func:`~solverplan.reflection.compose.mean_width`) is below w₀ = 0.4422, the shipped ``serpentine``'s
        (the goal then holds the same share of the corridor as there): in a room a millimetre wide the goal is not
        the whole room, while every shipped model, at least as wide, keeps 0.1. ``dead_band``: 1/16 of
        ``speed`` (the slowest commanded speed), at most 0.05 length/s: a robot commanded at micro speeds still
        moves, and the default speeds keep 0.05. Values given are kept.

        Examples
        --------
        >>> import solverplan as sp
        >>> robot = sp.FieldRobotDynamics()
        >>> tiny = sp.Environment.from_coords([(0, 0), ("0.002", 0), ("0.002", "0.001"), (0, "0.001")])
        >>> r = robot.resolved(tiny, 0.8)
        >>> round(r.goal_radius, 8), r.dead_band, robot.unset, r.unset
        (0.00015077, 0.05, ('goal_radius', 'dead_band'), ())
        >>> slow = robot.resolved(sp.load_environment("serpentine"), 0.008)     # micro speeds, serpentine's width
        >>> slow.goal_radius, slow.dead_band
        (0.1, 0.0005)
        """
        if not self.unset:
            return self
        radius = 0.1 * float(min(Fraction(1), mean_width(env) / REFERENCE_WIDTH))
        return replace(self, goal_radius=radius if self.goal_radius is None else self.goal_radius,
                       dead_band=min(0.05, speed / 16) if self.dead_band is None else self.dead_band)


@dataclass(frozen=True, slots=True)
class Scenario:
    """A scenario: its ``name``, the commanded ``speed`` (length/s) and whether the reflection zones are used."""

    name: str
    speed: float
    reflect: bool
    stream: str | None = None  #: the name of the random stream (default ``name``): common random numbers

    def to_json(self) -> dict:
        return {"speed": self.speed, "reflect": self.reflect, "stream": self.stream or self.name}


def default_scenarios(fast: float = 1.5, slow: float = 0.8) -> dict[str, Scenario]:
    """The paper's three scenarios: constrained at ``slow``, unconstrained and reflection at ``fast`` (length/s)."""
    return {"constrained": Scenario("constrained", slow, False),
            "unconstrained": Scenario("unconstrained", fast, False),
            "reflection": Scenario("reflection", fast, True, stream="unconstrained")}


@dataclass(frozen=True)
class ScenarioRun:
    """The trials of one scenario: per-trial ``times`` (s; NaN when the goal was not reached), ``collisions``
    (impacts) and the first ``K`` ``trajectories`` (positions at every control tick, start first)."""

    scenario: Scenario
    times: np.ndarray
    collisions: np.ndarray
    trajectories: tuple[np.ndarray, ...] = field(default=())
    stayed_inside: bool = True

    @property
    def trials(self) -> int:
        return len(self.times)

    @property
    def reached(self) -> np.ndarray:
        return np.isfinite(self.times)

    @property
    def success(self) -> float:
        """Share of the trials that reached the goal."""
        return float(self.reached.mean()) if self.trials else 0.0

    @property
    def time_mean(self) -> float | None:
        t = self.times[self.reached]
        return float(t.mean()) if len(t) else None

    @property
    def time_var(self) -> float | None:
        """Sample variance (n − 1) of the times of the trials that reached the goal."""
        t = self.times[self.reached]
        return float(t.var(ddof=1)) if len(t) > 1 else (0.0 if len(t) == 1 else None)

    @property
    def collisions_mean(self) -> float:
        return float(self.collisions.mean()) if self.trials else 0.0

    def to_json(self) -> dict:
        return {"trials": self.trials, "success": self.success, "time_mean": self.time_mean,
                "time_var": self.time_var, "collisions_mean": self.collisions_mean,
                "trajectories": [np.round(t, 5).tolist() for t in self.trajectories],
                "speed": self.scenario.speed, "reflect": self.scenario.reflect,
                "time_min": float(self.times[self.reached].min()) if self.reached.any() else None,
                "time_max": float(self.times[self.reached].max()) if self.reached.any() else None,
                # every trial (null: the goal was not reached), so that the answer reads back whole
                "times": [float(t) if np.isfinite(t) else None for t in self.times],
                "collisions": [int(c) for c in self.collisions], "stayed_inside": bool(self.stayed_inside)}

    @classmethod
    def from_json(cls, name: str, data: dict) -> ScenarioRun:
        """Read :meth:`to_json` back (``name``: the scenario's); raises :class:`~solverplan.errors.InputError` if
        malformed."""
        try:
            times = np.array([np.nan if t is None else float(t) for t in data["times"]], dtype=float)
            collisions = np.array([int(c) for c in data["collisions"]], dtype=np.int64)
            trajectories = tuple(np.array(t, dtype=float).reshape(-1, 2) for t in data.get("trajectories") or [])
            scenario = Scenario(name, float(data["speed"]), bool(data["reflect"]))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"scenarios.{name}: expected the trials' times, collisions, speed and reflect") from None
        return cls(scenario, times, collisions, trajectories, bool(data.get("stayed_inside", True)))


class _Fields:
    """Every cell's nominal and reflection field, evaluated for groups of robots."""

    def __init__(self, plan: FieldPlan) -> None:
        self.plan = plan
        self.n_cells = len(plan.cells)

    def directions(self, q: np.ndarray, cells: np.ndarray, reflecting: np.ndarray) -> np.ndarray:
        out = np.zeros_like(q)
        for c in np.unique(cells):
            for refl in (False, True):
                rows = np.flatnonzero((cells == c) & (reflecting == refl))
                if not len(rows):
                    continue
                if refl:
                    f = self.plan.zones[int(c)].field
                else:
                    policy = self.plan.policies.get(int(c))
                    if policy is None:
                        raise InputError(f"cell {int(c)} cannot reach the goal: no field drives a robot out of it")
                    f = policy.field  # type: ignore[assignment]
                out[rows] = f.velocity(q[rows])
        norm = np.hypot(out[:, 0], out[:, 1])
        return out / np.maximum(norm, 1e-12)[:, None]


def simulate_scenarios(plan: FieldPlan, scenarios: Sequence[Scenario], *, model: FieldRobotDynamics | None = None,
                       trials: int = 25, seed: int = 0, keep: int = 0,
                       starts: np.ndarray | None = None, every_step: bool = False) -> dict[str, ScenarioRun]:
    """Run ``trials`` rollouts of each scenario from the plan's start to its goal.

    Parameters
    ----------
    plan
        The composed fields (:func:`~solverplan.reflection.compose.compose_fields`).
    scenarios
        The scenarios to run (:func:`default_scenarios`).
    model
        The robot (:class:`FieldRobotDynamics`; inertial by default).
    trials
        Rollouts per scenario.
    seed
        The random seed; each scenario draws from its own stream of it.
    keep
        Keep the trajectories of the first ``keep`` trials of each scenario.
    starts
        Optional (trials, 2) float array: trial k of every scenario starts there instead of at the plan's start
        (points of the free space; the composition drives every cell that reaches the goal).
    every_step
        Record the kept trajectories at every physics step instead of every control tick.

    Returns
    -------
    dict
        Scenario name → :class:`ScenarioRun`, in the order given.

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.compose_fields(sp.load_environment("l_shape"), (5, 2), (2, 5))
    >>> robot = sp.FieldRobotDynamics(physics_rate=100)          # 5 integration steps per command: coarse, quick
    >>> runs = simulate_scenarios(plan, list(default_scenarios().values()), model=robot, trials=4, seed=1)
    >>> [(name, r.success, round(float(r.times.mean()))) for name, r in runs.items()]   # seconds to the goal
    [('constrained', 1.0, 8), ('unconstrained', 1.0, 5), ('reflection', 1.0, 5)]
    """
    model = model or FieldRobotDynamics()
    if trials < 1:
        raise InputError(f"trials must be at least 1, got {trials}")
    scen = list(scenarios)
    names = [s.name for s in scen]
    if len(set(names)) != len(names):
        raise InputError(f"scenario names must differ: {names}")
    for s in scen:
        if not s.speed > 0:
            raise InputError(f"scenario {s.name}: speed must be positive, got {s.speed}")
    env = plan.env
    model = model.resolved(env, min((s.speed for s in scen), default=1.0))
    goal_radius, dead_band = float(model.goal_radius or 0.0), float(model.dead_band or 0.0)  # resolved: set
    dec = plan.decomposition
    caster = RayCaster(env)
    fields = _Fields(plan)
    n = trials * len(scen)
    block = np.repeat(np.arange(len(scen)), trials)
    speed = np.array([s.speed for s in scen])[block]
    reflect_on = np.array([s.reflect for s in scen])[block]
    rngs = [np.random.default_rng([seed, zlib.crc32((s.stream or s.name).encode())]) for s in scen]
    start = np.array([float(plan.start[0]), float(plan.start[1])])
    goal = np.array([float(plan.goal[0]), float(plan.goal[1])])
    start_cell = plan.sequence[0]

    normals_all, offsets_all = dec.halfplanes
    reflection_cells = np.zeros(len(plan.cells), dtype=bool)
    reflection_cells[list(plan.zones)] = True
    edge_dir = env.edge_end - env.edge_start
    edge_normal = np.stack([-edge_dir[:, 1], edge_dir[:, 0]], axis=1)
    edge_normal /= np.hypot(edge_normal[:, 0], edge_normal[:, 1])[:, None]
    scale = float(max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1]))

    # Robots keep a clearance from the walls (a 10⁻⁷ of the environment's size): far above float rounding, so a
    # position is strictly inside the free space, and far below any length that matters to the dynamics.
    clearance = 1e-7 * scale
    locate_tolerance = 1e-9 * scale
    n_sides = normals_all.shape[1]
    wall_mask = np.zeros((len(plan.cells), n_sides), dtype=bool)
    for c in plan.cells:
        for i, side in enumerate(c.sides):
            wall_mask[c.id, i] = side.is_wall
    test_margin = np.where(wall_mask, 0.5 * clearance, 0.0)

    def _clear_of_walls(points: np.ndarray, cells_of: np.ndarray) -> np.ndarray:
        """Push points off the walls of their (convex) cells to the clearance, along the walls' normals."""
        out = points.copy()
        for _ in range(3):
            values = np.einsum("kmj,kj->km", normals_all[cells_of], out) - offsets_all[cells_of]
            deficit = np.where(wall_mask[cells_of], np.clip(clearance - values, 0.0, None), 0.0)
            if not deficit.any():
                break
            out += np.einsum("km,kmj->kj", deficit, normals_all[cells_of])
        return out

    if starts is None:
        q = np.tile(start, (n, 1))
        cell = np.full(n, start_cell)
    else:
        points = np.asarray(starts, dtype=float)
        if points.shape != (trials, 2) or not np.all(np.isfinite(points)):
            raise InputError(f"starts must be a finite ({trials}, 2) array, got shape {points.shape}")
        where = dec.inside(points)
        if not where.any(axis=1).all():
            k = int(np.flatnonzero(~where.any(axis=1))[0])
            raise InputError(f"starts[{k}] = ({points[k, 0]:g}, {points[k, 1]:g}) is not in the free space")
        q = np.tile(points, (len(scen), 1))
        cell = np.tile(np.argmax(where, axis=1), len(scen))
    q = _clear_of_walls(q, cell)
    vel = np.zeros((n, 2))
    done = np.zeros(n, dtype=bool)
    times = np.full(n, np.nan)
    collisions = np.zeros(n, dtype=np.int64)
    in_contact = np.zeros(n, dtype=bool)
    hit_since_tick = np.zeros(n, dtype=bool)
    used = np.zeros((n, len(plan.cells)), dtype=bool)
    reflecting = reflect_on & reflection_cells[cell]
    used[np.arange(n), cell] = reflecting
    kept = np.concatenate([np.arange(k * trials, k * trials + min(keep, trials)) for k in range(len(scen))]) \
        if keep > 0 else np.zeros(0, dtype=np.int64)
    paths: list[list[np.ndarray]] = [[q[r].copy()] for r in kept]
    inside_everywhere = True
    polygon = env.to_shapely()

    at_goal = np.hypot(q[:, 0] - goal[0], q[:, 1] - goal[1]) <= goal_radius
    times[at_goal] = 0.0  # started within reach of the goal
    done |= at_goal
    substeps = int(round(model.physics_rate / model.control_rate))
    dt = 1.0 / model.physics_rate
    ticks = int(np.ceil(_time_limit(model, plan, min(s.speed for s in scen)) * model.control_rate))
    step_count = 0
    ticks_per_second = max(1, round(model.control_rate))
    for k_tick in range(ticks):
        if k_tick % ticks_per_second == 0:  # once a simulated second: the progress bar of long runs
            tick("fields rollouts: simulated seconds", k_tick / model.control_rate, ticks / model.control_rate)
        active = np.flatnonzero(~done)
        if not len(active):
            break
        active_set = set(active.tolist())
        # the controller: a collision seen since the last tick ends the reflection mode
        reflecting[active] &= ~hit_since_tick[active]
        hit_since_tick[active] = False
        direction = fields.directions(q[active], cell[active], reflecting[active])
        heading_error = np.empty(len(active))
        speed_factor = np.empty(len(active))
        for k, rng in enumerate(rngs):  # one draw per trial and tick, so that trial k's noise is its own
            rows = block[active] == k
            local = active[rows] - k * trials
            heading = rng.normal(0.0, model.heading_noise, trials) if model.heading_noise else np.zeros(trials)
            factor = rng.normal(0.0, model.speed_noise, trials) if model.speed_noise else np.zeros(trials)
            heading_error[rows] = heading[local]
            speed_factor[rows] = 1.0 + factor[local]
        cos, sin = np.cos(heading_error), np.sin(heading_error)
        rotated = np.stack([cos * direction[:, 0] - sin * direction[:, 1],
                            sin * direction[:, 0] + cos * direction[:, 1]], axis=1)
        magnitude = np.clip(speed[active] * speed_factor, 0.0, None)
        magnitude[magnitude < dead_band] = 0.0
        command = rotated * magnitude[:, None]
        for _sub in range(substeps):
            step_count += 1
            t = step_count * dt  # not a running sum: times stay multiples of dt
            rows = active[~done[active]]
            if not len(rows):
                break
            cmd = command[np.searchsorted(active, rows)]
            if model.kind == "integrator":
                vel[rows] = cmd
            else:
                change = cmd - vel[rows]
                size = np.hypot(change[:, 0], change[:, 1])
                limit = model.accel * dt
                factor = np.where(size > limit, limit / np.maximum(size, 1e-300), 1.0)
                vel[rows] += change * factor[:, None]
            step = vel[rows] * dt
            moving = np.hypot(step[:, 0], step[:, 1]) > 1e-12 * scale
            new = q[rows] + step
            own = np.einsum("kmj,kj->km", normals_all[cell[rows]], new) - offsets_all[cell[rows]]
            leaves = moving & np.any(own < test_margin[cell[rows]], axis=1)
            touching = np.zeros(len(rows), dtype=bool)
            q[rows[~leaves]] = new[~leaves]  # within the convex cell, clear of its walls: no wall in between
            if leaves.any():
                idx = np.flatnonzero(leaves)
                r_idx = rows[idx]
                with np.errstate(over="ignore", divide="ignore"):  # the grid walk of nearly axis-parallel steps
                    hits = caster.cast(q[r_idx], step[idx], exact_ties=True)
                certain = (hits.edge >= 0) & (hits.vertex < 0) & ~hits.uncertain
                hit = certain & (hits.s <= 1.0)
                bad = ~certain  # a vertex, or a hit the floats cannot place: stay, and bounce back
                target = new[idx].copy()
                target[hit] = q[r_idx[hit]] + np.clip(hits.s[hit], 0.0, 1.0)[:, None] * step[idx[hit]]
                target[bad] = q[r_idx[bad]]
                where = dec.inside(target, tolerance=locate_tolerance)
                lost = ~where.any(axis=1)  # floats place the point in no cell: stay
                bad |= lost
                hit &= ~lost
                target[lost] = q[r_idx[lost]]
                stays = where[np.arange(len(idx)), cell[r_idx]] | lost
                new_cell = np.where(stays, cell[r_idx], np.argmax(where, axis=1))
                q[r_idx] = _clear_of_walls(target, new_cell)
                if hit.any():  # reflect the velocities on the hit walls (only the parts going into them)
                    rh = r_idx[hit]
                    nrm = edge_normal[hits.edge[hit]]
                    vn = np.einsum("kj,kj->k", vel[rh], nrm)
                    tangential = vel[rh] - vn[:, None] * nrm
                    if model.kind == "inertial":
                        bounced = (1.0 - model.friction) * tangential - model.restitution * vn[:, None] * nrm
                    else:
                        bounced = tangential
                    into = vn < 0
                    vel[rh[into]] = bounced[into]
                back = r_idx[bad]
                vel[back] = -model.restitution * vel[back] if model.kind == "inertial" else 0.0 * vel[back]
                touching[idx] = hit | bad
                changed = new_cell != cell[r_idx]
                if changed.any():
                    rc = r_idx[changed]
                    nc = new_cell[changed]
                    cell[rc] = nc
                    arm = reflect_on[rc] & reflection_cells[nc] & ~used[rc, nc]
                    reflecting[rc] = arm
                    used[rc, nc] |= arm
            new_impacts = touching & ~in_contact[rows]
            collisions[rows[new_impacts]] += 1
            hit_since_tick[rows[touching]] = True
            in_contact[rows] = touching
            if every_step:
                for k, r in enumerate(kept):
                    if not done[r] and r in active_set:
                        paths[k].append(q[r].copy())
            arrived = np.hypot(q[rows, 0] - goal[0], q[rows, 1] - goal[1]) <= goal_radius
            if arrived.any():
                times[rows[arrived]] = t
                done[rows[arrived]] = True
        for k, r in enumerate(kept):
            if r in active_set and not every_step:
                paths[k].append(q[r].copy())
    import shapely

    trajectories = [np.array(p) for p in paths]
    if trajectories:
        everything = np.vstack(trajectories)
        inside_everywhere = bool(np.all(shapely.contains_xy(polygon, everything[:, 0], everything[:, 1])))
    runs: dict[str, ScenarioRun] = {}
    for k, s in enumerate(scen):
        sl = slice(k * trials, (k + 1) * trials)
        mine = tuple(trajectories[i] for i, r in enumerate(kept) if block[r] == k)
        runs[s.name] = ScenarioRun(s, times[sl].copy(), collisions[sl].copy(), mine, inside_everywhere)
    return runs
