"""The answer of ``solverplan fields``: the composed fields from a start to a goal and the scenarios' statistics.

:func:`navigate_fields` composes the fields (:func:`~solverplan.reflection.compose.compose_fields`) and runs the
scenarios (:func:`~solverplan.reflection.simulate.simulate_scenarios`); :class:`FieldNavigation` follows the result
protocol (``status``, ``optimality``, ``stats``, ``environment``, ``to_json``, ``to_text``).

Status. ``found`` when every cell's nominal field was verified to flow through its outlet (the composition
converges from every point of the free space that can reach the goal); ``not-found`` otherwise (the candidate fields
of some cell all failed the verifier: a bounded search that proves nothing). The optimality record says how the
convergence was established — ``exact-check`` when every verdict is exact (line and goal fields), ``heuristic`` when
an arc field was verified by a dense sample — and claims no optimality of the time to goal, which is measured.
"""

from __future__ import annotations

import time
from dataclasses import field, replace
from typing import Sequence

from solverplan.choices import Reflections, ScenarioName, StartMode
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Reader, Stats, Status, answer_dataclass
from solverplan.errors import MalformedFile
from solverplan.exact import format_number
from solverplan.reflection.zones import RejectedZone
from fractions import Fraction
from typing import Any

import numpy as np

from solverplan.reflection.compose import FieldPlan, compose_fields, mean_width, resolve_gains
from solverplan.reflection.payoff import ROLLOUT_TRIALS, ZoneTest, prune_zones
from solverplan.reflection.simulate import (SCENARIOS, FieldRobotDynamics, ScenarioRun, default_scenarios,
                                            simulate_scenarios)

__all__ = ["FieldNavigation", "navigate_fields", "random_starts", "ROLLOUT_SEED"]


def _without_flow(value: Any) -> Any:
    """A composed plan's JSON without the cells' ``flow`` verdicts: they follow from the fields compared beside them,
    and answers written before the one verdict shape (``verified`` in place of ``valid``) still read back."""
    if isinstance(value, list):
        return [_without_flow(v) for v in value]
    if isinstance(value, dict):
        return {k: _without_flow(v) for k, v in value.items() if k != "flow"}
    return value


@answer_dataclass("fields")
class FieldNavigation(Answer):
    """The composed fields (``plan``), the robot ``model`` and one :class:`ScenarioRun` per scenario (``runs``).

    Made by :func:`navigate_fields`; follows the result protocol of :mod:`solverplan.result`.

    Attributes
    ----------
    plan
        The composed field policy (:func:`~solverplan.reflection.compose.compose_fields`).
    model
        The :class:`~solverplan.reflection.simulate.FieldRobotDynamics` the rollouts used.
    runs
        Scenario name → its trials (success share, times in seconds, collisions, kept trajectories).
    seed
        The random seed of the rollouts.
    status, optimality
        ``found`` when every line field's flow-through is verified exactly; what that proves.
    stats, environment
        Times and counts; the :class:`~solverplan.result.EnvironmentRecord` of the environment.
    gains
        The line and arc gains used (1/length, exact).
    derived
        The parameters not given, derived from the environment's scale (``gain_line``, ``gain_arc``,
        ``goal_radius``) or the speeds (``dead_band``); written under ``scale`` beside the mean width.

    Examples
    --------
    >>> import solverplan as sp
    >>> nav = sp.navigate_fields(sp.load_environment("l_shape"), (5, 2), (2, 5), scenarios=("reflection",),
    ...                          model="integrator", trials=2, seed=1)
    >>> run = nav.runs["reflection"]
    >>> nav.status.value, nav.plan.sequence, run.success, run.collisions.tolist()
    ('found', (0, 1), 1.0, [0, 0])
    """

    plan: FieldPlan
    model: FieldRobotDynamics
    runs: dict[str, ScenarioRun]
    seed: int
    status: Status
    optimality: Optimality
    stats: Stats = field(default_factory=Stats)
    environment: EnvironmentRecord | None = None
    reflections: str = "payoff"
    starts: str = "fixed"
    rollouts: dict[int, ZoneTest] = field(default_factory=dict)
    cells: str = "convex"
    gains: tuple[Fraction, Fraction] = (Fraction(3), Fraction(1))
    derived: tuple[str, ...] = ()

    def _fields(self) -> dict:
        plan = self.plan
        width = mean_width(plan.env)
        out: dict = {
            "cells": [c.to_json() for c in plan.cells],
            "adjacency": [list(pair) for pair in plan.decomposition.adjacency],
            "sequence": list(plan.sequence),
            "reflection_cells": list(plan.reflection_cells),
            "scenarios": {name: run.to_json() for name, run in self.runs.items()},
            "start": [float(c) for c in plan.start],
            "goal": [float(c) for c in plan.goal],
            "flow_through": plan.flow_through,
            "fields": [plan.policies[c].to_json() for c in sorted(plan.policies)],
            "reflection_zones": [plan.zones[c].to_json() for c in plan.reflection_cells],
            "rejected_zones": [r.to_json() for r in plan.rejected],
            "reflections": self.reflections,
            "starts": self.starts,
            "decomposition": self.cells,
            "gain_line_exact": format_number(self.gains[0]),
            "gain_arc_exact": format_number(self.gains[1]),
            "scale": {"mean_width": float(width), "mean_width_exact": format_number(width),
                      "derived": list(self.derived)},
            "rollouts": {str(c): {"time_without": t.without, "time_with": t.with_zone, "gain": t.gain}
                         for c, t in self.rollouts.items()},
            "model": self.model.to_json(),
            "seed": self.seed,
            "start_exact": [format_number(c) for c in plan.start],
            "goal_exact": [format_number(c) for c in plan.goal],
        }
        return out

    _PLAN_KEYS = ("cells", "adjacency", "sequence", "reflection_cells", "flow_through", "fields", "reflection_zones")

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> FieldNavigation:
        """Read a fields answer back in ``env`` (required). The composed fields are a function of the environment,
        the exact start and goal and whether arc fields were allowed: they are composed again and must be the
        answer's (cells, fields, verdicts, zones — else :class:`~solverplan.errors.MalformedFile`); the trials are
        read from the file."""
        r = Reader(data, "fields")
        env, record = r.in_environment(env, 'fields')
        arcs = any(f.sub("field").string("kind", "") == "arc" for f in r.items("fields"))
        cells = r.string("decomposition", "convex")
        reflections = r.string("reflections", "all")
        gains = (r.exact("gain_line_exact") if r.has("gain_line_exact") else Fraction(3),
                 r.exact("gain_arc_exact") if r.has("gain_arc_exact") else Fraction(1))
        try:
            plan = compose_fields(env, r.exact_pair("start_exact"), r.exact_pair("goal_exact"), arcs=arcs, cells=cells,
                                  gain_line=gains[0], gain_arc=gains[1], reflection=reflections != "none")
        except InputError as exc:
            raise MalformedFile(f"fields: {exc}") from None
        # the zones the payoff tests kept are the answer's (rollouts are not repeated); the others are recorded
        kept = set(r.ints("reflection_cells"))
        dropped = [RejectedZone(z.integer("cell"), z.get("side", None), z.string("stage"), z.string("reason"))  # type: ignore[arg-type]
                   for z in r.items("rejected_zones") if z.string("stage", "") in ("overshoot", "rollout")] \
            if r.has("rejected_zones") else []
        plan = plan.without_zones([c for c in plan.zones if c not in kept], dropped)
        model_data = r.sub("model").data
        try:
            model = FieldRobotDynamics(**model_data) if isinstance(model_data, dict) else FieldRobotDynamics()
        except TypeError:
            raise MalformedFile("fields.model: unknown robot parameters") from None
        scenarios = r.sub("scenarios")
        runs = {str(name): ScenarioRun.from_json(str(name), run) for name, run in scenarios.data.items()}  # type: ignore[union-attr]
        recorded = r.get("rollouts", {})
        try:
            rollouts = {int(c): ZoneTest(float(t["time_without"]), float(t["time_with"]))
                        for c, t in recorded.items()} if isinstance(recorded, dict) else {}
        except (KeyError, TypeError, ValueError):
            raise MalformedFile("fields.rollouts: expected {cell: {time_without, time_with, gain}}") from None
        derived = r.sub("scale").get("derived", []) if r.has("scale") else []
        if not isinstance(derived, list) or not all(isinstance(d, str) for d in derived):
            raise MalformedFile("fields.scale.derived: expected a list of parameter names")
        answer = cls(plan, model, runs, r.integer("seed"), r.status(), r.optimality(), r.stats(), record, reflections,
                     r.string("starts", "fixed"), rollouts, cells, gains, tuple(derived))
        mine = answer._fields()
        for key in cls._PLAN_KEYS:
            if _without_flow(mine[key]) != _without_flow(data.get(key)):
                raise MalformedFile(f"fields.{key}: not the fields composed from this start and goal in {env.name!r}")
        return answer

    def to_text(self, *, width: int = 100) -> str:
        plan = self.plan
        lines = [f"{plan.env.name or 'environment'}: {len(plan.cells)} convex cells, sequence "
                 f"{' → '.join(map(str, plan.sequence))}",
                 f"reflection cells: {', '.join(map(str, plan.reflection_cells)) or 'none'}; flow-through "
                 f"{'verified' if plan.flow_through else 'NOT verified'} ({self.status.value}); model {self.model.kind}",
                 f"gains {float(self.gains[0]):.4g} (line), {float(self.gains[1]):.4g} (arc); goal radius "
                 f"{self.model.goal_radius or float('nan'):.4g}; dead band {self.model.dead_band or 0.0:.4g}"]
        if self.derived:
            lines.append(f"defaults (from the mean width {float(mean_width(plan.env)):g} and the speeds): "
                         f"{', '.join(self.derived)}")
        for c in sorted(plan.policies):  # the cells' verdicts that are not exact proofs, in the verdicts' words
            check = plan.policies[c].check
            lines.extend(f"cell {c}: FAIL {failure}" for failure in check.failures)
            lines.extend(f"cell {c}: not checked: {item}" for item in check.not_checked)
        lines += [f"{'scenario':<14} {'trials':>6} {'success':>8} {'time mean':>10} {'time var':>10} {'collisions':>11}"]
        for name, run in self.runs.items():
            mean = "-" if run.time_mean is None else f"{run.time_mean:.3f}"
            var = "-" if run.time_var is None else f"{run.time_var:.4f}"
            lines.append(f"{name:<14} {run.trials:>6} {run.success:>8.2f} {mean:>10} {var:>10} "
                         f"{run.collisions_mean:>11.2f}")
        return "\n".join(line[:width] for line in lines) + "\n"


def random_starts(plan: FieldPlan, trials: int, seed: int) -> np.ndarray:
    """``trials`` start points drawn uniformly from the cells that reach the goal (area-weighted cell, then a
    uniform point of the convex cell by rejection from its bounding box), length units; seeded."""
    rng = np.random.default_rng([seed, 7919])
    cells = [plan.cells[c] for c in sorted(plan.policies)]
    areas = np.array([abs(float(_area2(c.float_vertices))) for c in cells])
    normals, offsets = plan.decomposition.halfplanes
    out = np.empty((trials, 2))
    picks = rng.choice(len(cells), size=trials, p=areas / areas.sum())
    for k, i in enumerate(picks.tolist()):
        cell = cells[i]
        lo, hi = cell.float_vertices.min(axis=0), cell.float_vertices.max(axis=0)
        while True:
            q = lo + (hi - lo) * rng.random(2)
            values = normals[cell.id] @ q - offsets[cell.id]
            if np.all(values[: len(cell.sides)] > 1e-9 * float(np.max(hi - lo))):
                out[k] = q
                break
    return out


def _area2(v: np.ndarray) -> float:
    return float(np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(v[:, 1], np.roll(v[:, 0], -1)))


ROLLOUT_SEED = 1_000_003
"""Added to the caller's seed for the rollouts that decide which reflections pay (independent of the runs
reported)."""


def navigate_fields(env: Environment, start: Sequence[object], goal: Sequence[object], *,
                    scenarios: Sequence[str] = SCENARIOS, model: str | FieldRobotDynamics = "inertial", trials: int = 25,
                    seed: int = 0, trajectories: int = 0, arcs: bool = False, fast: float = 1.5,
                    slow: float = 0.8, gain_line: object = None, gain_arc: object = None, reflections: str = "payoff",
                    starts: str = "fixed", cells: str = "convex", goal_radius: float | None = None,
                    dead_band: float | None = None) -> FieldNavigation:
    """Compose the fields from ``start`` to ``goal`` and run ``trials`` rollouts of each scenario.

    Parameters
    ----------
    env
        The environment.
    start, goal
        Points of the open free space (read exactly).
    scenarios
        Names among ``constrained``, ``unconstrained``, ``reflection`` (in the order wanted).
    model
        ``"integrator"``, ``"inertial"`` or a :class:`~solverplan.reflection.simulate.FieldRobotDynamics`.
    trials, seed
        Rollouts per scenario and the random seed.
    trajectories
        Keep this many trajectories per scenario (at most ``trials``).
    arcs
        Use arc fields in turning cells where they verify.
    fast, slow
        Commanded speeds of the unconstrained/reflection and the constrained scenarios (length/s).
    gain_line, gain_arc
        Gains p of the line and arc fields (1/length, read exactly); ``None`` (default): relative to the
        environment's mean width (:func:`~solverplan.reflection.compose.default_gains`: 3 and 1 in the shipped
        ``serpentine``), so that the answer does not depend on the scale of the coordinates.
    goal_radius, dead_band
        The distance within which the goal is reached (length) and the commanded speed below which the robot does
        not move (length/s); they replace the ``model``'s. ``None`` (default, and unset in the model): relative
        to the environment and the speeds (:meth:`~solverplan.reflection.simulate.FieldRobotDynamics.resolved`:
        0.1 and 0.05 in rooms at least as wide as the shipped ``serpentine``, at the default speeds). The answer
        records the values used (``model``) and which were derived (``scale.derived``).
    reflections
        ``payoff`` (default): plan only the zones that pay for this robot (:mod:`~solverplan.reflection.payoff`:
        turn, overshoot, rollouts); ``all``: every zone the geometry allows (the paper); ``none``.
    cells
        The decomposition: ``convex`` or ``corners`` (corner cells at the turns, where reflections can help).
    starts
        ``fixed``: every trial from ``start``; ``random``: trial k from a uniform random point of the free space
        that reaches the goal (:func:`random_starts`, seeded), the same points in every scenario.

    Returns
    -------
    FieldNavigation
        The composed fields, the model, and per scenario the trials' success, times (seconds) and collisions.

    Raises
    ------
    InputError
        An unknown scenario or model, bad counts or speeds, or points :func:`compose_fields` refuses.

    Examples
    --------
    >>> import solverplan as sp
    >>> nav = navigate_fields(sp.load_environment("l_shape"), (5, 2), (2, 5), model="integrator", trials=2)
    >>> nav.status.value, nav.to_json()["sequence"], {name: run.success for name, run in nav.runs.items()}
    ('found', [0, 1], {'constrained': 1.0, 'unconstrained': 1.0, 'reflection': 1.0})
    """
    began = time.perf_counter()
    if not scenarios:
        raise InputError(f"no scenario: use one or more of {', '.join(SCENARIOS)}")
    scenarios = [ScenarioName.parse(s, "scenario").value for s in scenarios]
    robot = model if isinstance(model, FieldRobotDynamics) else FieldRobotDynamics(kind=model)
    robot = replace(robot, goal_radius=robot.goal_radius if goal_radius is None else goal_radius,
                    dead_band=robot.dead_band if dead_band is None else dead_band)
    derived = robot.unset + tuple(name for name, g in (("gain_line", gain_line), ("gain_arc", gain_arc)) if g is None)
    robot = robot.resolved(env, min(fast, slow))
    if not 0 <= trajectories <= trials:
        raise InputError(f"trajectories must be between 0 and the number of trials ({trials}), got {trajectories}")
    for name, value in (("fast", fast), ("slow", slow)):
        if not value > (robot.dead_band or 0.0):  # below it the robot never moves: every trial runs to the limit
            raise InputError(f"the {name} speed must exceed the robot's dead band {robot.dead_band:g} "
                             f"(length/s), got {value:g}")
    reflections = Reflections.parse(reflections, "reflections").value
    starts = StartMode.parse(starts, "starts").value
    gains = resolve_gains(env, gain_line, gain_arc)
    plan = compose_fields(env, start, goal, arcs=arcs, gain_line=gains[0], gain_arc=gains[1],
                          reflection=reflections != "none", cells=cells)
    points = random_starts(plan, trials, seed) if starts == "random" else None
    tests: dict = {}
    if reflections == "payoff" and plan.zones and "reflection" in scenarios:
        probe = random_starts(plan, ROLLOUT_TRIALS, seed + ROLLOUT_SEED) if starts == "random" else None
        plan, tests = prune_zones(plan, robot, fast, trials=ROLLOUT_TRIALS, seed=seed + ROLLOUT_SEED, starts=probe)
    composed = time.perf_counter()
    table = default_scenarios(fast, slow)
    runs = simulate_scenarios(plan, [table[s] for s in scenarios], model=robot, trials=trials, seed=seed,
                              keep=trajectories, starts=points)
    finished = time.perf_counter()
    if plan.proved:
        optimality = Optimality(Method.EXACT_CHECK, True, None,
                                scope="convergence of the composed fields: every cell's nominal field flows through its "
                                      "outlet (exact); the time to goal is measured, not optimised",
                                algorithm="exact flow-through test of line fields")
    else:
        optimality = Optimality(Method.HEURISTIC, False, None,
                                scope="convergence of the composed fields (arc fields checked by a dense sample)"
                                      if plan.flow_through else
                                      "some cell has no field verified to flow through its outlet",
                                algorithm="flow-through tests (exact for line fields, dense sample otherwise)")
    stats = Stats(seconds_setup=composed - began, seconds_search=finished - composed,
                  counts={"cells": len(plan.cells), "trials": trials * len(scenarios),
                          "unverified_cells": sorted(c for c, p in plan.policies.items() if not p.check.valid)})
    return FieldNavigation(plan, robot, runs, seed, Status.FOUND if plan.flow_through else Status.NOT_FOUND,
                           optimality, stats, EnvironmentRecord.of(env), reflections, starts, tests, cells, gains,
                           tuple(sorted(derived)))
