"""Plan a reflection only where it pays: the robot would overshoot the turn, and short rollouts predict a gain.

Stager and Tanner plan a reflection in every cell where the path turns by at least 90°. A reflection is a
gamble: aim at a wall, bounce, and let the wall turn the robot towards the exit. It pays only when the robot
could not turn in time anyway — an inertial robot at speed v with at most ``accel`` a (length/s²) needs v²/(2a)
to stop its motion along the entry direction, and when that is more than the cell leaves beyond the outlet's
middle it hits the far wall with the nominal field too. Elsewhere the reflection adds a detour. And a wall helps
only if its normal turns the robot towards the exit (:func:`~solverplan.reflection.zones.turns_towards_exit`,
checked when the zones are chosen). Independent reviews measured reflection slower than the plain controller
on 5 of 5 unseen corridors (issue #26); here a zone survives three tests, in order:

1. **turn** (geometry, exact, in :func:`~solverplan.reflection.zones.select_zone_recorded`);
2. **overshoot** (the robot model): v²/(2a) ≥ the depth of the cell beyond the outlet's midpoint along the entry
   direction; an integrator (a = ∞) never overshoots, so it never gets a zone;
3. **rollout**: ``trials`` simulated runs (their own seed, independent of the runs reported), the same noise
   for every plan compared (common random numbers: a difference is the zones'). If all the zones that passed
   save at least :data:`MIN_GAIN` of the mean time together, each is then dropped if the others do at least as
   well without it; otherwise they are added one at a time, in sequence order, each kept only if it saves
   :data:`MIN_GAIN` on its own. Last, the kept set must save :data:`CONFIRM_GAIN` on a fresh batch of runs,
   else every zone is dropped.

When nothing pays the reflection scenario *is* the unconstrained controller — the same runs (its noise is the
unconstrained scenario's), so it never costs time. Each zone dropped is recorded with its stage and the numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import logging

import numpy as np

from solverplan.reflection.compose import FieldPlan
from solverplan.reflection.simulate import FieldRobotDynamics, Scenario, simulate_scenarios
from solverplan.reflection.zones import RejectedZone

logger = logging.getLogger(__name__)

__all__ = ["MIN_GAIN", "CONFIRM_GAIN", "ROLLOUT_TRIALS", "ZoneTest", "overshoot_depth", "stopping_distance", "prune_zones"]

MIN_GAIN = 0.02
"""A zone must save at least this share of the mean time in rollouts (2 %: the acceptance allows reflection to
cost at most 1 % on unseen runs, so a predicted gain needs a margin above the rollouts' noise)."""

CONFIRM_GAIN = 0.01
"""The zones kept must still save this share of the mean time on a second, fresh batch of runs."""

ROLLOUT_TRIALS = 24
"""Runs per rollout comparison."""


def stopping_distance(model: FieldRobotDynamics, speed: float) -> float:
    """v²/(2a): how far the robot goes while killing a speed ``speed`` (length/s) at ``accel`` (length); 0 for an
    integrator (it turns at once)."""
    return 0.0 if model.kind == "integrator" else speed * speed / (2.0 * model.accel)


def overshoot_depth(plan: FieldPlan, cell: int) -> float:
    """How deep the cell is beyond its outlet's midpoint along the entry direction (the inlet's inward normal),
    length units: the room the robot has to turn in before it meets the far wall."""
    zone = plan.zones[cell]
    c = plan.cells[cell]
    n_in = c.sides[zone.inlet].unit_normal()
    mid = c.sides[zone.outlet].float_midpoint()
    return float(((c.float_vertices - mid) @ n_in).max())


@dataclass(frozen=True, slots=True)
class ZoneTest:
    """One rollout comparison: mean times (s) without and with the zone(s), and the relative gain."""

    without: float
    with_zone: float

    @property
    def gain(self) -> float:
        return (self.without - self.with_zone) / self.without if self.without > 0 else 0.0


def _mean_time(plan: FieldPlan, model: FieldRobotDynamics, speed: float, trials: int, seed: int,
               starts: np.ndarray | None) -> float:
    """Mean time (s) of the reflection controller with the plan's zones, on the rollouts' own noise stream (the
    same noise for every plan compared: common random numbers). A failed run counts as twice the slowest
    arrival: a zone that makes runs fail must not look fast."""
    scenario = Scenario("rollout", speed, True)
    logger.info("payoff test: %d rollouts with %d reflection zone(s)", trials, len(plan.zones))
    times = simulate_scenarios(plan, [scenario], model=model, trials=trials, seed=seed, starts=starts)["rollout"].times
    worst = 2.0 * float(np.nanmax(times)) if np.isfinite(times).any() else 1e9
    return float(np.mean(np.where(np.isfinite(times), times, worst)))


def _change(gain: float) -> str:
    return f"saves {100 * gain:.1f} %" if gain >= 0 else f"costs {-100 * gain:.1f} %"


def prune_zones(plan: FieldPlan, model: FieldRobotDynamics, speed: float, *, trials: int = ROLLOUT_TRIALS, seed: int = 0,
                starts: np.ndarray | None = None) -> tuple[FieldPlan, dict[int, ZoneTest]]:
    """Keep only the reflection zones that pay (module docstring); the dropped ones join ``plan.rejected``.

    Parameters
    ----------
    plan
        Composed fields with their candidate zones (:func:`~solverplan.reflection.compose.compose_fields`).
    model, speed
        The robot and its commanded speed (length/s) in the reflection scenario.
    trials, seed
        Runs per rollout comparison and their seed (use one the final runs do not use).
    starts
        Optional (trials, 2) start points of the rollouts (random starts), else the plan's start.

    Returns
    -------
    (FieldPlan, dict)
        The plan with the zones that pay, and the rollout comparison of each zone tried (by cell).

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.compose_fields(sp.load_environment("serpentine"), (3, "2.25"), (3, "0.25"))
    >>> kept, tests = prune_zones(plan, FieldRobotDynamics(kind="integrator"), 1.5)
    >>> kept.reflection_cells, {r.stage for r in kept.rejected if r.side is not None and r.cell in plan.zones}
    ((), {'overshoot'})
    """
    if not plan.zones:
        return plan, {}
    v_stop = stopping_distance(model, speed)
    rejected: list[RejectedZone] = []
    candidates = []
    for c in plan.reflection_cells:
        depth = overshoot_depth(plan, c)
        if v_stop < depth:
            rejected.append(RejectedZone(c, plan.zones[c].side, "overshoot",
                                         f"the robot turns in time: stopping distance v²/2a = {v_stop:.3g} < depth "
                                         f"{depth:.3g} beyond the outlet"))
        else:
            candidates.append(c)
    kept: list[int] = []
    tests: dict[int, ZoneTest] = {}

    def time_with(zones: list[int], runs_seed: int = seed) -> float:
        return _mean_time(plan.without_zones([z for z in plan.zones if z not in zones]), model, speed, trials,
                          runs_seed, starts)

    if candidates:
        # every plan is tried on the same runs (common random numbers): differences are the zones'
        base = time_with([])
        together = time_with(candidates)
        if ZoneTest(base, together).gain >= MIN_GAIN:
            # all together pay: drop one at a time those whose removal is not slower
            kept, current = list(candidates), together
            for c in candidates:
                rest = [z for z in kept if z != c]
                without = time_with(rest)
                tests[c] = ZoneTest(without, current)
                if without <= current:
                    kept, current = rest, without
                    rejected.append(RejectedZone(c, plan.zones[c].side, "rollout",
                                                 f"the others do better without it: {current:.3f} s without it, "
                                                 f"{tests[c].with_zone:.3f} s with it"))
        else:
            # together they do not pay: add one at a time those that pay on their own
            current = base
            for c in candidates:
                with_zone = time_with(kept + [c])
                tests[c] = ZoneTest(current, with_zone)
                if tests[c].gain >= MIN_GAIN:
                    kept.append(c)
                    current = with_zone
                else:
                    rejected.append(RejectedZone(c, plan.zones[c].side, "rollout",
                                                 f"rollouts predict no gain: {with_zone:.3f} s with it, {current:.3f} s "
                                                 f"without ({_change(tests[c].gain)})"))
    if kept:  # the kept set as a whole, on fresh runs
        without, with_zones = time_with([], seed + 1), time_with(kept, seed + 1)
        if ZoneTest(without, with_zones).gain < CONFIRM_GAIN:
            rejected.extend(RejectedZone(c, plan.zones[c].side, "rollout",
                                         f"together the kept zones predict too little gain on fresh runs: "
                                         f"{with_zones:.3f} s with them, {without:.3f} s without "
                                         f"({_change(ZoneTest(without, with_zones).gain)})") for c in kept)
            kept = []
    return plan.without_zones([z for z in plan.zones if z not in kept], rejected), tests
