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
from dataclasses import dataclass, field
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Reader, Stats, Status, answer_kind
from solverplan.errors import MalformedFile
from solverplan.exact import format_number
from typing import Any
from solverplan.reflection.compose import FieldPlan, compose_fields
from solverplan.reflection.simulate import (SCENARIOS, RobotModel, ScenarioRun, default_scenarios,
                                            simulate_scenarios)

__all__ = ["FieldNavigation", "navigate_fields"]


@answer_kind("fields")
@dataclass(frozen=True)
class FieldNavigation(Answer):
    """The composed fields (``plan``), the robot ``model`` and one :class:`ScenarioRun` per scenario (``runs``).

    Made by :func:`navigate_fields`; follows the result protocol of :mod:`solverplan.result`.

    Attributes
    ----------
    plan
        The composed field policy (:func:`~solverplan.reflection.compose.compose_fields`).
    model
        The :class:`~solverplan.reflection.simulate.RobotModel` the rollouts used.
    runs
        Scenario name → its trials (success share, times in seconds, collisions, kept trajectories).
    seed
        The random seed of the rollouts.
    status, optimality
        ``found`` when every line field's flow-through is verified exactly; what that proves.
    stats, environment
        Times and counts; the :class:`~solverplan.result.EnvironmentRecord` of the environment.

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
    model: RobotModel
    runs: dict[str, ScenarioRun]
    seed: int
    status: Status
    optimality: Optimality
    stats: Stats = field(default_factory=Stats)
    environment: EnvironmentRecord | None = None

    def _fields(self) -> dict:
        plan = self.plan
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
        plan = compose_fields(env, r.exact_pair("start_exact"), r.exact_pair("goal_exact"), arcs=arcs)
        model_data = r.sub("model").data
        try:
            model = RobotModel(**model_data) if isinstance(model_data, dict) else RobotModel()
        except TypeError:
            raise MalformedFile("fields.model: unknown robot parameters") from None
        scenarios = r.sub("scenarios")
        runs = {str(name): ScenarioRun.from_json(str(name), run) for name, run in scenarios.data.items()}  # type: ignore[union-attr]
        answer = cls(plan, model, runs, r.integer("seed"), r.status(), r.optimality(), r.stats(), record)
        mine = answer._fields()
        for key in cls._PLAN_KEYS:
            if mine[key] != data.get(key):
                raise MalformedFile(f"fields.{key}: not the fields composed from this start and goal in {env.name!r}")
        return answer

    def to_text(self, *, width: int = 100) -> str:
        plan = self.plan
        lines = [f"{plan.env.name or 'environment'}: {len(plan.cells)} convex cells, sequence "
                 f"{' → '.join(map(str, plan.sequence))}",
                 f"reflection cells: {', '.join(map(str, plan.reflection_cells)) or 'none'}; flow-through "
                 f"{'verified' if plan.flow_through else 'NOT verified'} ({self.status.value}); model {self.model.kind}",
                 f"{'scenario':<14} {'trials':>6} {'success':>8} {'time mean':>10} {'time var':>10} {'collisions':>11}"]
        for name, run in self.runs.items():
            mean = "-" if run.time_mean is None else f"{run.time_mean:.3f}"
            var = "-" if run.time_var is None else f"{run.time_var:.4f}"
            lines.append(f"{name:<14} {run.trials:>6} {run.success:>8.2f} {mean:>10} {var:>10} "
                         f"{run.collisions_mean:>11.2f}")
        return "\n".join(line[:width] for line in lines) + "\n"


def navigate_fields(env: Environment, start: Sequence[object], goal: Sequence[object], *,
                    scenarios: Sequence[str] = SCENARIOS, model: str | RobotModel = "inertial", trials: int = 25,
                    seed: int = 0, trajectories: int = 0, arcs: bool = False, fast: float = 1.5,
                    slow: float = 0.8) -> FieldNavigation:
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
        ``"integrator"``, ``"inertial"`` or a :class:`~solverplan.reflection.simulate.RobotModel`.
    trials, seed
        Rollouts per scenario and the random seed.
    trajectories
        Keep this many trajectories per scenario (at most ``trials``).
    arcs
        Use arc fields in turning cells where they verify.
    fast, slow
        Commanded speeds of the unconstrained/reflection and the constrained scenarios (length/s).

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
    unknown = [s for s in scenarios if s not in SCENARIOS]
    if unknown or not scenarios:
        raise InputError(f"unknown scenario {unknown[0] if unknown else '(none)'!r}: use "
                         f"{', '.join(SCENARIOS)}")
    robot = model if isinstance(model, RobotModel) else RobotModel(kind=model)
    if not 0 <= trajectories <= trials:
        raise InputError(f"trajectories must be between 0 and the number of trials ({trials}), got {trajectories}")
    for name, value in (("fast", fast), ("slow", slow)):
        if not value > robot.dead_band:  # below it the robot never moves: every trial would run to the time limit
            raise InputError(f"the {name} speed must exceed the robot's dead band {robot.dead_band:g} "
                             f"(length/s), got {value:g}")
    plan = compose_fields(env, start, goal, arcs=arcs)
    composed = time.perf_counter()
    table = default_scenarios(fast, slow)
    runs = simulate_scenarios(plan, [table[s] for s in scenarios], model=robot, trials=trials, seed=seed,
                              keep=trajectories)
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
                          "unverified_cells": sorted(c for c, p in plan.policies.items() if not p.check.verified)})
    return FieldNavigation(plan, robot, runs, seed, Status.FOUND if plan.flow_through else Status.NOT_FOUND,
                           optimality, stats, EnvironmentRecord.of(env))
