"""Rollouts of the composed fields: global convergence from sampled starts, trajectories that never leave the free
space (collisions resolved against the real walls), reproducibility, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.reflection.cells import decompose_free_space
from solverplan.reflection.compose import compose_fields
from solverplan.reflection.simulate import FieldRobotDynamics, Scenario, default_scenarios, simulate_scenarios
from tests.strategies import polygons_with_holes

SERPENTINE = load_environment("serpentine")
PLAN = compose_fields(SERPENTINE, (3, "2.25"), (3, "0.25"))
ONE_HOLE = load_environment("one_hole")


def _sample_free(env, k: int, seed: int) -> np.ndarray:
    poly = env.to_shapely()
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = poly.bounds
    out = []
    while len(out) < k:
        p = rng.uniform([x0, y0], [x1, y1])
        if shapely.contains_xy(poly, p[0], p[1]):
            out.append(p)
    return np.array(out)


def test_global_convergence_of_the_composition_from_sampled_starts():
    """Sequential composition: from anywhere in the free space the single integrator reaches the goal (no noise),
    and with the goal in the goal cell no trajectory touches a wall (every field flows through)."""
    starts = _sample_free(SERPENTINE, 60, seed=3)
    quiet = FieldRobotDynamics(kind="integrator", heading_noise=0.0, speed_noise=0.0, goal_radius=0.02)
    runs = simulate_scenarios(PLAN, [Scenario("nominal", 1.0, False)], model=quiet, trials=60, starts=starts)
    run = runs["nominal"]
    assert run.success == 1.0
    assert run.collisions.max() == 0


def test_global_convergence_in_a_polygon_with_a_hole():
    plan = compose_fields(ONE_HOLE, (1, 1), (9, 5))
    assert plan.flow_through
    starts = _sample_free(ONE_HOLE, 40, seed=5)
    quiet = FieldRobotDynamics(kind="integrator", heading_noise=0.0, speed_noise=0.0, goal_radius=0.05)
    run = simulate_scenarios(plan, [Scenario("nominal", 2.0, False)], model=quiet, trials=40, starts=starts)["nominal"]
    assert run.success == 1.0 and run.collisions.max() == 0


@settings(max_examples=12)
@given(st.sampled_from(["integrator", "inertial"]), st.integers(0, 10_000), st.floats(0.5, 3.0),
       st.floats(0.0, 1.0), st.floats(0.0, 0.6))
def test_trajectories_never_leave_the_free_space(kind, seed, speed, restitution, noise):
    """Collisions are resolved against the real walls: the position after every physics step is strictly inside the
    free space, at any speed, restitution and noise."""
    model = FieldRobotDynamics(kind=kind, restitution=restitution, heading_noise=noise, max_time=8.0)
    runs = simulate_scenarios(PLAN, [Scenario("fast", speed, False), Scenario("reflect", speed, True)], model=model,
                              trials=4, seed=seed, keep=4, every_step=True)
    poly = SERPENTINE.to_shapely()
    for run in runs.values():
        assert run.stayed_inside
        for path in run.trajectories:
            assert shapely.contains_xy(poly, path[:, 0], path[:, 1]).all()


def test_every_scenario_reaches_the_goal_with_the_defaults():
    runs = simulate_scenarios(PLAN, list(default_scenarios().values()), trials=8, seed=11)
    for run in runs.values():
        assert run.success == 1.0 and run.time_mean is not None and run.time_var is not None
    assert runs["constrained"].collisions_mean == 0  # slow enough to follow the fields without contact
    assert runs["reflection"].collisions_mean >= len(PLAN.reflection_cells)  # the planned bounces happen


def test_scenarios_are_reproducible_and_independent_of_each_other():
    a = simulate_scenarios(PLAN, list(default_scenarios().values()), trials=5, seed=7)
    b = simulate_scenarios(PLAN, [default_scenarios()["reflection"]], trials=5, seed=7)
    assert np.array_equal(a["reflection"].times, b["reflection"].times)
    c = simulate_scenarios(PLAN, [default_scenarios()["reflection"]], trials=5, seed=8)
    assert not np.array_equal(a["reflection"].times, c["reflection"].times)


def test_integrator_gains_nothing_from_reflections():
    """Without inertia a bounce cannot turn faster than the field: the reflection scenario is slower (the benefit
    in the paper comes from momentum)."""
    model = FieldRobotDynamics(kind="integrator")
    runs = simulate_scenarios(PLAN, [default_scenarios()["unconstrained"], default_scenarios()["reflection"]],
                              model=model, trials=6, seed=2)
    assert runs["reflection"].time_mean > runs["unconstrained"].time_mean


def test_dead_band_stops_a_robot_commanded_too_slowly():
    model = FieldRobotDynamics(dead_band=0.5, max_time=3.0, heading_noise=0.0, speed_noise=0.0)
    run = simulate_scenarios(PLAN, [Scenario("crawl", 0.4, False)], model=model, trials=2, keep=1)["crawl"]
    assert run.success == 0.0 and np.allclose(run.trajectories[0], [3.0, 2.25])


@pytest.mark.parametrize("kwargs,message", [
    (dict(kind="wheeled"), "unknown robot model 'wheeled'"),
    (dict(physics_rate=30.0), "multiple of control_rate"),
    (dict(restitution=1.5), "restitution must be in"),
    (dict(accel=0.0), "accel must be positive"),
])
def test_bad_robot_models_are_input_errors(kwargs, message):
    with pytest.raises(InputError, match=message):
        FieldRobotDynamics(**kwargs)


def test_bad_starts_are_input_errors():
    with pytest.raises(InputError, match=r"starts\[0\] = \(1, 1.75\) is not in the free space"):
        simulate_scenarios(PLAN, [Scenario("x", 1.0, False)], trials=1, starts=np.array([[1.0, 1.75]]))
    with pytest.raises(InputError, match="scenario names must differ"):
        simulate_scenarios(PLAN, [Scenario("x", 1.0, False)] * 2, trials=1)


@settings(max_examples=15)
@given(polygons_with_holes(max_vertices=10, max_holes=2), st.integers(0, 1000))
def test_sequential_composition_converges_from_sampled_starts_when_every_cell_flows_through(env, seed):
    """Sequential composition: if every cell's field is verified to flow through its outlet, the single integrator
    reaches the goal from every sampled start without touching a wall."""
    dec = decompose_free_space(env)
    rng = np.random.default_rng(seed)
    start_cell, goal_cell = rng.integers(0, len(dec.cells), size=2)
    pick = lambda c: tuple(str(round(float(x), 6)) for x in dec.cells[c].centroid)  # noqa: E731
    try:
        plan = compose_fields(env, pick(start_cell), pick(goal_cell), decomposition=dec)
    except InputError:
        return  # a centroid rounded onto a wall of a sliver cell
    if not plan.flow_through:
        return
    scale = max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1])
    starts = _sample_free(env, 12, seed)
    quiet = FieldRobotDynamics(kind="integrator", heading_noise=0.0, speed_noise=0.0, goal_radius=1e-3 * scale,
                       max_time=100.0, physics_rate=2000.0)
    run = simulate_scenarios(plan, [Scenario("nominal", scale / 10, False)], model=quiet, trials=12, starts=starts)
    assert run["nominal"].success == 1.0


def test_hybrid_controller_hits_each_reflection_zone_then_follows_the_nominal_field():
    """In the reflection scenario the robot reaches the chosen wall of every reflection cell (the switching
    surface), and the run still converges; without reflection (integrator, no noise) no wall is touched."""
    quiet = FieldRobotDynamics(kind="integrator", heading_noise=0.0, speed_noise=0.0)
    runs = simulate_scenarios(PLAN, [Scenario("reflect", 1.0, True), Scenario("nominal", 1.0, False)], model=quiet,
                              trials=1, keep=1, every_step=True)
    path = runs["reflect"].trajectories[0]
    assert runs["reflect"].success == 1.0 and runs["reflect"].collisions[0] == len(PLAN.reflection_cells)
    for c in PLAN.reflection_cells:
        side = PLAN.cells[c].sides[PLAN.zones[c].side]
        wall = shapely.LineString([tuple(map(float, side.a)), tuple(map(float, side.b))])
        assert min(wall.distance(shapely.Point(p)) for p in path) < 1e-5
    assert runs["nominal"].success == 1.0 and runs["nominal"].collisions[0] == 0


def test_a_long_route_gets_a_time_limit_that_fits_it():
    # three_chambers is 100 long: at 0.8/s the route takes ~125 s, past the 60 s floor of the default limit
    import solverplan as sp

    nav = sp.navigate_fields(sp.load_environment("three_chambers"), ("4.02", "0.5"), ("96.01", "29.22"),
                             scenarios=("constrained",), trials=2, seed=0)
    run = nav.runs["constrained"]
    assert run.success == 1.0 and run.time_mean > 60
