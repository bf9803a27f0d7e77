"""The simulator: reproducible with a seed, trajectories on the boundary and inside the free space, vertex hits
flagged, known orbits and limit cycles reproduced, plans (stage policies) scored; plus the trajectory layer
of render.py and ``solverplan render --trajectories``."""

from __future__ import annotations

import json
import math
from math import pi as PI
from fractions import Fraction

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from solverplan import cli
from solverplan.interval import Interval
from solverplan.bounce.rules import Fixed, FixedInterval, MonotoneFixed, Relative, Specular
from solverplan.bounce.transitions import affine_map
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.render import draw_trajectories, render_environment
from solverplan.simulate import (
    Contacts,
    Outcome,
    RulePolicy,
    StagePolicy,
    in_boundary_set,
    simulate_policy,
    simulate_rule,
)
from tests.strategies import polygons_with_holes, simple_polygons

SQUARE = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], name="square")

RULES = st.one_of(
    st.builds(Specular, st.floats(0, 0.5)),
    st.builds(Fixed, st.floats(0.05, PI - 0.05), st.floats(0, 0.5)),
    st.builds(MonotoneFixed, st.floats(0.05, PI - 0.05)),
    st.builds(Relative, st.floats(0.05, PI - 0.05), st.just(0.0), st.sampled_from(["back", "travel"])),
)


# ---------------------------------------------------------------------- reproducibility
def test_same_seed_same_rollouts_and_the_seed_is_recorded():
    a = simulate_rule(SQUARE, Specular(0.1), "e0,e2:0:0.5", bounces=15, trials=200, seed=42)
    b = simulate_rule(SQUARE, Specular(0.1), "e0,e2:0:0.5", bounces=15, trials=200, seed=42)
    c = simulate_rule(SQUARE, Specular(0.1), "e0,e2:0:0.5", bounces=15, trials=200, seed=43)
    assert a.seed == 42 and a.to_json()["seed"] == 42
    for name in ("edge", "t", "x", "y", "heading", "status", "stop_step"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.t, c.t)


def test_without_a_seed_a_fresh_one_is_drawn_recorded_and_replays():
    a = simulate_rule(SQUARE, Specular(0.2), None, bounces=5, trials=50)
    assert isinstance(a.seed, int)
    b = simulate_rule(SQUARE, Specular(0.2), None, bounces=5, trials=50, seed=a.seed)
    np.testing.assert_array_equal(a.t, b.t)


def test_a_generator_is_used_as_given_and_its_state_recorded():
    rng = np.random.default_rng(7)
    a = simulate_rule(SQUARE, Specular(0.2), None, bounces=5, trials=50, seed=rng)
    assert a.seed is None and a.rng_state is not None
    replay = np.random.default_rng()
    replay.bit_generator.state = a.rng_state
    b = simulate_rule(SQUARE, Specular(0.2), None, bounces=5, trials=50, seed=replay)
    np.testing.assert_array_equal(a.t, b.t)


# ---------------------------------------------------------------------- trajectories are physical
def _on_boundary_and_inside(env: Environment, runs) -> None:
    polygon = env.to_shapely()
    size = max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1])
    ok = runs.edge >= 0
    rows, cols = np.nonzero(ok)
    e, t = runs.edge[rows, cols], runs.t[rows, cols]
    expected = env.points_at(e, t)
    np.testing.assert_allclose(np.stack([runs.x[rows, cols], runs.y[rows, cols]], axis=1), expected, atol=1e-9 * size)
    assert np.all((t >= 0) & (t <= 1))
    # every flight between two contacts runs through the free space: its midpoint is strictly inside
    # (a flight ending in a flagged vertex hit is recorded at the vertex itself, so it is left out)
    for k in range(runs.trials):
        path = runs.path(k)
        if runs.flagged[k]:
            path = path[:-1]
        if len(path) < 2:
            continue
        mids = 0.5 * (path[1:] + path[:-1])
        assert shapely.contains_xy(polygon, mids[:, 0], mids[:, 1]).all(), (k, path)


@settings(max_examples=max(10, settings.default.max_examples // 2))
@given(env=st.one_of(polygons_with_holes(), simple_polygons()), rule=RULES, seed=st.integers(0, 2**31))
def test_trajectories_stay_on_the_boundary_and_fly_through_free_space(env, rule, seed):
    runs = simulate_rule(env, rule, None, bounces=12, trials=40, seed=seed)
    _on_boundary_and_inside(env, runs)
    running = runs.status == Outcome.OK
    assert np.all(runs.stop_step[running] == 12)
    assert np.all(runs.edge[running] >= 0)
    # each executed heading is a valid action of the edge it left
    h = runs.heading[:, :-1]
    assert np.all(np.isnan(h) | ((h > 0) & (h < PI)))


def test_vertex_hits_are_flagged_not_assigned():
    # from (5, 0) aimed at the corner (10, 10): the float ray comes within rounding of vertex 2
    theta = math.atan2(10, 5)
    runs = simulate_rule(SQUARE, Specular(), ([0], [0.5]), bounces=5, initial=[theta], seed=0)
    assert runs.status.tolist() == [Outcome.VERTEX] and runs.stop_step.tolist() == [1]
    assert runs.flagged.tolist() == [True]
    assert runs.path(0)[-1] == pytest.approx([10.0, 10.0], abs=1e-9)
    assert runs.outcome_counts()["vertex"] == 1 and runs.summary()["flagged_rate"] == 1.0
    # the same ray resolved exactly: this float direction passes just beside the corner, and goes on
    exact = simulate_rule(SQUARE, Specular(), ([0], [0.5]), bounces=5, initial=[theta], seed=0, ties="exact")
    assert exact.status.tolist() in ([Outcome.OK], [Outcome.VERTEX])


def test_rays_along_a_wall_are_flagged():
    runs = simulate_rule(SQUARE, Fixed(1e-13), ([0], [0.5]), bounces=3, initial=[1e-13], seed=0)
    assert runs.flagged.tolist() == [True]


# ---------------------------------------------------------------------- known dynamics
def test_specular_square_period_four_billiard_orbit():
    """At 45° a billiard in a square closes after four bounces from any start: t, 1 − t, t, 1 − t."""
    starts = np.array([0.1, 0.25, 0.4, 0.7])
    runs = simulate_rule(SQUARE, Specular(), (np.zeros(4, dtype=int), starts), bounces=8, initial=[PI / 4], seed=0)
    assert np.all(runs.status == Outcome.OK)
    assert runs.edge.tolist() == [[0, 1, 2, 3, 0, 1, 2, 3, 0]] * 4
    expected = np.stack([starts, 1 - starts] * 4 + [starts], axis=1)
    np.testing.assert_allclose(runs.t, expected, atol=1e-12)


def test_thm1_fixed_rule_in_a_square_converges_to_the_period_four_limit_cycle():
    """Hand-derived: d' = (ℓ − d) tan θ (Lemma 2 with φ = π/2), so t* = tan θ / (1 + tan θ) on every edge."""
    theta = 0.5
    fixed_point = math.tan(theta) / (1 + math.tan(theta))
    runs = simulate_rule(SQUARE, Fixed(theta), "e0", bounces=120, trials=300, seed=5, initial=Interval(0.2, 0.7))
    assert np.all(runs.status == Outcome.OK)
    assert np.all(np.diff(runs.edge, axis=1) % 4 == 1)  # counter-clockwise, one edge per bounce
    np.testing.assert_allclose(runs.t[:, -8:], fixed_point, atol=1e-12)
    # the error contracts by tan θ per bounce
    err = np.abs(runs.t[:, 1:30] - fixed_point)
    ratio = err[:, 1:] / err[:, :-1]
    np.testing.assert_allclose(ratio[err[:, :-1] > 1e-9], math.tan(theta), rtol=1e-6)


def test_thm1_exact_fixed_point_matches_simulation():
    """tan θ = 1/2: the exact affine return map has fixed point 1/3; the simulated cycle lands there."""
    directions = [(2, 1), (-1, 2), (-2, -1), (1, -2)]
    cycle = affine_map(SQUARE, 0, directions[0], 1)
    for k in (1, 2, 3):
        cycle = cycle.then(affine_map(SQUARE, k, directions[k], (k + 1) % 4))
    assert cycle.fixed_point() == Fraction(1, 3)
    runs = simulate_rule(SQUARE, Fixed(math.atan(0.5)), ([0], [0.9]), bounces=80, initial=[math.atan(0.5)], seed=0)
    assert runs.final_edge.tolist() == [0]
    assert runs.final_t[0] == pytest.approx(1 / 3, abs=1e-12)


def test_monotone_rule_travels_monotonically_along_a_hallway():
    hallway = Environment.from_coords([[0, 0], [40, 0], [40, 2], [0, 2]])
    runs = simulate_rule(hallway, MonotoneFixed(PI / 3), "e0:0:0.1", bounces=20, trials=50, seed=2,
                         initial=Interval(0.3, 1.2))
    for k in range(runs.trials):
        path = runs.path(k)
        stop = np.flatnonzero(np.isclose(path[:, 0], 40))  # until the far wall turns it round
        xs = path[: stop[0] + 1, 0] if len(stop) else path[:, 0]
        assert np.all(np.diff(xs) > 0)


# ---------------------------------------------------------------------- plans (stage policies)
def test_stage_policy_scores_a_safe_plan_and_a_wrong_goal():
    # from the floor's middle straight up ±0.1 lands on the ceiling's middle; the goal is there
    plan = StagePolicy([Interval(PI / 2 - 0.1, PI / 2 + 0.1)], targets=[SQUARE.boundary_set("e2")],
                       goal=SQUARE.boundary_set("e2:0.25:0.75"), sampling="endpoints")
    runs = simulate_policy(SQUARE, plan, "e0:0.4:0.6", bounces=3, trials=2000, seed=0)
    assert runs.success_rate == 1.0 and np.all(runs.stop_step == 1)
    assert runs.summary()["bounces_to_goal"] == {"mean": 1.0, "median": 1.0, "min": 1, "max": 1}
    wrong = StagePolicy([Interval(PI / 2 - 0.1, PI / 2 + 0.1)], goal=SQUARE.boundary_set("e1"))
    runs = simulate_policy(SQUARE, wrong, "e0:0.4:0.6", bounces=3, trials=100, seed=0)
    assert runs.outcome_counts()["failed"] == 100 and runs.success_rate == 0.0


def test_stage_policy_fails_rollouts_that_miss_a_stage_target():
    # from the floor at 0.3..1.2 rad: the right wall from x > 10 − 10/tan θ, else the ceiling (a failure)
    plan = StagePolicy([Interval(0.3, 1.2), Interval(1.4, 1.7)], targets=[SQUARE.boundary_set("e1"), None])
    runs = simulate_policy(SQUARE, plan, "e0", bounces=5, trials=500, seed=1)
    counts = runs.outcome_counts()
    assert counts["failed"] > 0 and counts["ok"] > 0 and counts["failed"] + counts["ok"] + counts["vertex"] + counts["tie"] == 500
    failed = runs.status == Outcome.FAILED
    assert np.all(runs.stop_step[failed] == 1) and np.all(runs.final_edge[failed] != 1)


def test_stage_policy_repeats_a_cycle_until_the_budget():
    cycle = StagePolicy([Interval(0.5, 0.5)], repeat_from=0)
    runs = simulate_policy(SQUARE, cycle, ([0], [0.9]), bounces=60, seed=0)
    assert runs.status.tolist() == [Outcome.OK] and runs.stop_step.tolist() == [60]
    assert runs.final_t[0] == pytest.approx(math.tan(0.5) / (1 + math.tan(0.5)), abs=1e-9)
    early = StagePolicy([Interval(0.5, 0.5)], repeat_from=0, goal=SQUARE.boundary_set("e2"), stop_at_goal=True)
    runs = simulate_policy(SQUARE, early, ([0], [0.9]), bounces=60, seed=0)
    assert runs.status.tolist() == [Outcome.GOAL] and runs.stop_step.tolist() == [2]


def test_custom_policies_see_the_contacts():
    seen = []

    class Straight:
        def headings(self, contacts: Contacts, rng):
            seen.append((contacts.step, len(contacts), bool(np.isnan(contacts.incoming).all())))
            return np.full(len(contacts), PI / 2)

        def check(self, contacts: Contacts):
            return np.where(contacts.step >= 2, Outcome.GOAL, Outcome.RUNNING).astype(np.int8) * np.ones(len(contacts), dtype=np.int8)

    runs = simulate_policy(SQUARE, Straight(), "e0:0.2:0.8", bounces=10, trials=7, seed=0)
    assert seen == [(0, 7, True), (1, 7, False)]
    assert runs.success_rate == 1.0 and runs.edge[:, 2].tolist() == [0] * 7


def test_rule_policy_samples_adversarially_at_the_interval_ends():
    policy = RulePolicy(FixedInterval(0.4, 0.6), initial=Interval(1.0, 2.0), sampling="endpoints", initial_sampling="mid")
    runs = simulate_policy(SQUARE, policy, "e0", bounces=8, trials=200, seed=0)
    assert np.all(runs.heading[:, 0] == 1.5)
    later = runs.heading[:, 1:-1][np.isfinite(runs.heading[:, 1:-1])]
    assert set(later.tolist()) == {0.4, 0.6}


def test_record_ends_keeps_the_start_and_the_final_contact():
    full = simulate_rule(SQUARE, Specular(0.1), "e0", bounces=30, trials=100, seed=9)
    ends = simulate_rule(SQUARE, Specular(0.1), "e0", bounces=30, trials=100, seed=9, record="ends")
    assert ends.t.shape == (100, 2)
    np.testing.assert_array_equal(ends.t[:, 0], full.t[:, 0])
    np.testing.assert_array_equal(ends.final_t, full.final_t)
    np.testing.assert_array_equal(ends.status, full.status)


def test_rollouts_report_their_partition_segments(models_dir):
    from solverplan.bounce.partitions import partition

    env = load_environment(models_dir / "l_shape.json")
    p = partition(env)
    runs = simulate_rule(env, Specular(), None, bounces=6, trials=300, seed=4)
    seg = runs.segments(p)
    assert seg.shape == runs.edge.shape and np.all((seg >= 0) == (runs.edge >= 0))
    ok = seg >= 0
    assert np.all(p.seg_edge[seg[ok]] == runs.edge[ok])
    assert np.all((p.seg_t0[seg[ok]] <= runs.t[ok] + 1e-12) & (runs.t[ok] <= p.seg_t1[seg[ok]] + 1e-12))
    # partition segments serve as a plan stage's targets directly
    plan = StagePolicy([Interval(1.0, 2.0)], targets=[[p.segments[k] for k in range(len(p))]])
    assert simulate_policy(env, plan, "e0", bounces=1, trials=50, seed=0).outcome_counts()["failed"] == 0


def test_starts_are_uniform_by_arc_length():
    env = Environment.from_coords([[0, 0], [30, 0], [30, 10], [0, 10]])  # e0 is three times e1
    runs = simulate_rule(env, Specular(), "e0,e1", bounces=0, trials=20000, seed=3)
    share = np.mean(runs.edge[:, 0] == 0)
    assert share == pytest.approx(0.75, abs=0.02)
    assert in_boundary_set(env.boundary_set("e0,e1"), runs.edge[:, 0], runs.t[:, 0]).all()


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "call,error,message",
    [
        (lambda: simulate_rule(SQUARE, Specular(), "e9", bounces=3, trials=5), InvalidBoundarySet,
         r"^unknown edge e9: edges are e0..e3$"),
        (lambda: simulate_rule(SQUARE, Specular(), ([7], [0.5]), bounces=3), InvalidBoundarySet,
         r"^unknown edge e7: edges are e0..e3$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=3, trials=5, initial=Interval(0.0, 1.0)),
         InvalidBoundarySet, r"^heading interval \[0, 1\] is not inside \(0, π\): lo=0$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=3, trials=5, initial=[4.0]), InvalidBoundarySet,
         r"^initial heading 4 is not inside \(0, π\)$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=-1, trials=5), InputError,
         r"^bounces must be an integer in \[0, 10,000,000\], got -1$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=2, trials=0), InputError,
         r"^trials must be an integer in \[1, 100,000,000\], got 0$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=2, trials=3, seed=-4), InputError,
         r"^seed must be a non-negative integer or a numpy Generator, got -4$"),
        (lambda: simulate_rule(SQUARE, Specular(), "e0", bounces=2), InputError,
         r"^trials is needed to sample starts from a boundary set$"),
        (lambda: simulate_rule(SQUARE, Specular(), ([0, 1], [0.5, 2.0]), bounces=2), InvalidBoundarySet,
         r"^start t = 2 is not in \[0, 1\]$"),
        (lambda: StagePolicy([Interval(0.5, 3.5)]), InvalidBoundarySet,
         r"^stage 0: heading interval \[0.5, 3.5\] is not inside \(0, π\): hi=3.5$"),
        (lambda: simulate_policy(SQUARE, object(), "e0", bounces=2, trials=2), InputError, r"is not a policy"),
    ],
)
def test_bad_input_is_one_line(call, error, message):
    with pytest.raises(error, match=message):
        call()


# ---------------------------------------------------------------------- pictures
def test_draw_trajectories_layer():
    runs = simulate_rule(SQUARE, Fixed(0.5), "e0", bounces=10, trials=30, seed=0)
    fig = render_environment(SQUARE)
    ax = fig.axes[0]
    artists = draw_trajectories(ax, runs, max_paths=12)
    lines, starts = artists[0], artists[1]
    assert lines.get_gid() == "trajectories" and starts.get_gid() == "trajectory-starts"
    assert len(lines.get_segments()) == 12 * 10
    assert 0.04 <= lines.get_alpha() <= 0.8
    assert len(starts.get_offsets()) == 12
    flagged = simulate_rule(SQUARE, Specular(), ([0], [0.5]), bounces=5, initial=[math.atan2(10, 5)], seed=0)
    artists = draw_trajectories(render_environment(SQUARE).axes[0], flagged)
    assert artists[-1].get_gid() == "trajectory-flags"
    with pytest.raises(InputError, match=r"record='all'"):
        draw_trajectories(ax, simulate_rule(SQUARE, Specular(), "e0", bounces=2, trials=2, seed=0, record="ends"))


runner = CliRunner()


def run_cli(*args):
    return runner.invoke(cli.app, [str(a) for a in args])


def test_cli_render_trajectories_png_and_svg(tmp_path, models_dir):
    png = tmp_path / "square.png"
    result = run_cli("render", models_dir / "square.json", "--trajectories", 20, "--rule", "fixed:0.5",
                     "--from", "e0", "--bounces", 12, "--seed", 3, "-o", png)
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["written"] == str(png) and png.read_bytes()[:4] == b"\x89PNG"
    svg = tmp_path / "rooms.svg"
    result = run_cli("render", models_dir / "two_rooms.json", "--trajectories", 5, "-o", svg)
    assert result.exit_code == 0, result.stderr
    assert 'id="trajectories"' in svg.read_text() and 'id="trajectory-starts"' in svg.read_text()


@pytest.mark.parametrize(
    "args,fragment",
    [
        (["--rule", "fixed:4"], "fixed rule: heading interval [4, 4] is not inside (0, π): hi=4"),
        (["--rule", "bouncy"], "unknown bounce rule 'bouncy'"),
        (["--from", "e99"], "unknown edge e99: edges are e0..e3"),
        (["--bounces", "-2"], "--bounces"),
    ],
)
def test_cli_render_trajectories_bad_input_exits_2(tmp_path, models_dir, args, fragment):
    out = tmp_path / "x.png"
    result = run_cli("render", models_dir / "square.json", "--trajectories", 5, *args, "-o", out)
    assert result.exit_code == 2
    assert result.stdout == "" and not out.exists()
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0]


def test_models_two_rooms_specular_runs_clean(models_dir):
    env = load_environment(models_dir / "two_rooms.json")
    runs = simulate_rule(env, Specular(), None, bounces=50, trials=2000, seed=11)
    assert runs.outcome_counts()["ok"] + runs.outcome_counts()["vertex"] + runs.outcome_counts()["tie"] == 2000
    assert runs.summary()["flagged_rate"] < 0.01
    _on_boundary_and_inside(env, simulate_rule(env, Specular(), None, bounces=20, trials=200, seed=11))
