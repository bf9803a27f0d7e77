"""Reflections only where they pay (issue #26): the reflection scenario never costs more than 1 % of the
unconstrained controller's mean time on corridors the planner has not seen, and when nothing is planned the two
scenarios are the same runs (common random numbers)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.reflection.compose import compose_fields
from solverplan.reflection.navigation import navigate_fields
from solverplan.reflection.payoff import overshoot_depth, prune_zones, stopping_distance
from solverplan.reflection.simulate import FieldRobotDynamics, default_scenarios, simulate_scenarios
from tests.reflection.corridors import corridor


def _cost(nav) -> float:
    u, r = nav.runs["unconstrained"].time_mean, nav.runs["reflection"].time_mean
    return (r - u) / u


def test_without_zones_the_reflection_scenario_is_the_unconstrained_one_run_for_run():
    env, s, g = corridor("square", 2, 0.5, seed=3)
    plan = compose_fields(env, s, g, cells="corners")
    assert plan.zones == {}  # square corners: no wall turns the robot towards the exit
    table = default_scenarios()
    runs = simulate_scenarios(plan, [table["unconstrained"], table["reflection"]], trials=6, seed=4)
    assert np.array_equal(runs["unconstrained"].times, runs["reflection"].times)
    assert np.array_equal(runs["unconstrained"].collisions, runs["reflection"].collisions)


def test_corner_cells_make_reflection_candidates_on_cut_corners():
    env, s, g = corridor("cut", 3, 0.4, seed=0)
    plain = compose_fields(env, s, g)
    corners = compose_fields(env, s, g, cells="corners")
    assert plain.zones == {} and len(corners.zones) == 3
    assert all(corners.cells[c].sides[z.side].is_wall for c, z in corners.zones.items())


def test_an_integrator_never_overshoots_so_it_plans_no_reflection():
    env, s, g = corridor("cut", 3, 0.4, seed=0)
    plan = compose_fields(env, s, g, cells="corners")
    kept, tests = prune_zones(plan, FieldRobotDynamics(kind="integrator"), 1.5)
    assert kept.zones == {} and tests == {}
    assert stopping_distance(FieldRobotDynamics(kind="integrator"), 1.5) == 0.0
    assert all(r.stage == "overshoot" for r in kept.rejected if r.cell in plan.zones and r.side is not None)
    assert all(overshoot_depth(plan, c) > 0 for c in plan.zones)


@pytest.mark.parametrize("kind,width,seed", [("cut", 0.4, 0), ("square", 0.4, 1), ("zigzag", 0.8, 1)])
def test_issue26_a_planned_reflection_costs_at_most_1_percent_against_the_unconstrained_controller(kind, width, seed):
    env, s, g = corridor(kind, 3, width, seed=seed)
    nav = navigate_fields(env, s, g, scenarios=("unconstrained", "reflection"), trials=25, seed=7, cells="corners")
    assert nav.runs["reflection"].success == 1.0
    assert _cost(nav) <= 0.01, (nav.plan.reflection_cells, [r.reason for r in nav.plan.rejected])


@pytest.mark.slow
@settings(max_examples=12)
@given(kind=st.sampled_from(["square", "cut", "zigzag"]), width=st.sampled_from([0.3, 0.5, 0.8]),
       seed=st.integers(0, 50), starts=st.sampled_from(["fixed", "random"]))
def test_payoff_reflection_never_costs_more_than_1_percent_on_random_corridors(kind, width, seed, starts):
    env, s, g = corridor(kind, 3, width, seed=seed)
    nav = navigate_fields(env, s, g, scenarios=("unconstrained", "reflection"), trials=25, seed=seed + 11,
                          cells="corners", starts=starts)
    assert _cost(nav) <= 0.01
