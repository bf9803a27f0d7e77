"""Limit cycles (paper §6.1): Theorem 1 in convex polygons and Prop. 4 made constructive in polygons with holes,
compared against the simulator (the ground truth) and exact ray casting."""

from __future__ import annotations

import json
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, event, example, given, settings
from hypothesis import strategies as st

from solverplan.bounce.controller import constant_controller
from solverplan.bounce.cycles import limit_cycle
from solverplan.bounce.dynamics import ExactHeading, cycles_to_epsilon, lemma3_max_heading, theorem1_fixed_point
from solverplan.bounce.rules import Fixed
from solverplan.bounce.transitions import exact_transition
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.result import Method, Status
from solverplan.simulate import simulate_rule
from tests.strategies import convex_polygons, polygons_with_holes
from tests.shapes import SQUARE

PI = math.pi
MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
FEW = max(8, settings.default.max_examples // 5)


def _simulate(env, theta, edges, ts, bounces, **kw):
    return simulate_rule(env, Fixed(theta), (np.asarray(edges), np.asarray(ts, dtype=float)), bounces=bounces,
                         initial=[theta], ties="exact", seed=0, **kw)


def _contact_t(cycle, edge):
    return [float(p.t) for p in cycle.points if p.edge == edge]


def _verify_orbit_by_exact_casts(cycle):
    """Independent of the library's own check: cast every leg of the cycle exactly from its contact point."""
    m = len(cycle.points)
    for k, p in enumerate(cycle.points):
        nxt = cycle.points[(k + 1) % m]
        hit = exact_transition(cycle.env, p.edge, p.t, cycle.stages[k].step.direction)
        assert hit.vertex is None and (hit.edge, hit.t) == (nxt.edge, nxt.t)


# ---------------------------------------------------------------------- Theorem 1 (convex polygons)
@given(env=convex_polygons(), frac=st.floats(0.05, 0.9), t=st.floats(0.01, 0.99), edge=st.integers(0, 30))
@example(env=SQUARE, frac=0.5, t=0.25, edge=0)
@settings(max_examples=FEW)
def test_theorem1_cycle_is_where_the_simulated_trajectory_converges(env, frac, t, edge):
    theta = frac * lemma3_max_heading(env)
    cycle = limit_cycle(env, theta)
    assert cycle.status is Status.FOUND and cycle.scope == "every-start" and cycle.method == "theorem1"
    n = env.n_edges
    assert cycle.edges == tuple(range(n))
    _verify_orbit_by_exact_casts(cycle)
    # the exact fixed point agrees with Theorem 1's float closed form
    assert float(cycle.points[0].t) * env.edge_lengths[0] == pytest.approx(theorem1_fixed_point(env, theta).d, rel=1e-9)
    # the simulated trajectory visits the edges in CCW order and converges to the contact points
    k = cycles_to_epsilon(cycle.contraction, 1.0, 1e-12 * min(float(p.t) for p in cycle.points)) + 1
    assume(k * n <= 3000)
    e0 = edge % n
    runs = _simulate(env, theta, [e0], [t], k * n + 3)
    assert runs.outcome_counts()["ok"] == 1
    assert runs.edge[0].tolist() == [(e0 + j) % n for j in range(k * n + 4)]
    for col in range(k * n, k * n + 4):
        e = int(runs.edge[0, col])
        (expected,) = _contact_t(cycle, e)
        assert abs(runs.t[0, col] - expected) / expected < 1e-9


@given(env=convex_polygons(), tan=st.fractions(Fraction(1, 30), Fraction(2, 1), max_denominator=30),
       t=st.fractions(Fraction(1, 100), Fraction(99, 100), max_denominator=100))
@settings(max_examples=FEW)
def test_exact_affine_return_map_agrees_with_float_simulation(env, tan, t):
    heading = ExactHeading.from_tangent(tan)
    cycle = limit_cycle(env, heading, method="edges", edges=list(range(env.n_edges)))
    assume(cycle.stages)
    ret = cycle.stages[0]
    maps = [(s.step.alpha, s.step.beta) for s in cycle.stages]
    x = t
    for a, b in maps:
        x = a * x + b
    # where the exact composition says a start lands after one cycle, if every leg stays on its edge ...
    legs_ok = True
    y = t
    for k, (a, b) in enumerate(maps):
        hit = exact_transition(env, cycle.stages[k].step.from_edge, y, cycle.stages[k].step.direction)
        if hit.vertex is not None or hit.edge != cycle.stages[k].step.to_edge:
            legs_ok = False
            break
        assert hit.t == a * y + b  # exact cast = exact affine map, leg by leg
        y = hit.t
    assume(legs_ok)
    runs = _simulate(env, heading.theta, [ret.step.from_edge], [float(t)], env.n_edges)
    assert runs.outcome_counts()["ok"] == 1
    assert runs.t[0, -1] == pytest.approx(float(x), abs=1e-12)
    if cycle.found:
        assert float(cycle.contraction_exact) == pytest.approx(
            np.prod([s.step.contraction for s in cycle.stages]), rel=1e-9)  # Def. 12: |α| = Π C_k


def test_theorem1_on_the_square_is_exact():
    cycle = limit_cycle(SQUARE, "tan:1/2", epsilon=1e-3)
    assert cycle.contraction_exact == Fraction(1, 16) and [p.t for p in cycle.points] == [Fraction(1, 3)] * 4
    assert cycle.cycles_to_epsilon == cycles_to_epsilon(Fraction(1, 16), 4, Fraction(1, 1000)) == 3
    assert cycle.epsilon_width == 4.0


def test_theta_outside_lemma3_gets_a_clear_answer_never_a_wrong_cycle():
    square = limit_cycle(SQUARE, "tan:2")  # θ > π/4: the period-4 orbit exists but repels
    assert square.status is Status.NOT_CONTRACTING and square.contraction_exact == 16
    assert "does not attract" in square.reason and square.scope == "none"
    runs = _simulate(SQUARE, square.heading.theta, [0, 0], [float(square.points[0].t), float(square.points[0].t) + 1e-6], 8)
    assert abs(runs.t[0, 8] - runs.t[1, 8]) > 1e-5  # and indeed nearby starts drift away
    env = load_environment(MODELS / "irregular_convex.json")
    steep = limit_cycle(env, 1.2)
    assert steep.status is Status.EDGE_ORDER_BROKEN
    assert steep.reason.startswith("θ is outside Lemma 3's CCW range (0, 0.307046)") and steep.contraction is None
    near = limit_cycle(env, 0.35)  # just outside: a verified cycle, but only its basin is guaranteed
    assert near.status is Status.FOUND and near.scope == "basin" and "the CCW edge order breaks" in near.reason


def test_theorem1_clockwise_cycle_by_symmetry():
    env = load_environment(MODELS / "irregular_convex.json")
    ccw, cw = limit_cycle(env, 0.25), limit_cycle(env, PI - 0.25)
    assert cw.found and cw.scope == "every-start" and cw.edges == (0, 6, 5, 4, 3, 2, 1) and cw.lemma3.clockwise
    assert cw.contraction == pytest.approx(ccw.contraction, rel=1e-12)  # the same coefficients, mirrored
    runs = _simulate(env, PI - 0.25, [3], [0.4], 7 * 8)
    assert runs.edge[0, :8].tolist() == [3, 2, 1, 0, 6, 5, 4, 3]
    assert runs.t[0, -1] == pytest.approx(float(cw.fixed_point(3).t), rel=1e-9)


def test_theorem1_beyond_the_per_step_bound_still_attracts_every_start():
    env = Environment.from_coords([[0, 0], [2, 0], [8, 3], [8, 6], [0, 6]], name="contraction-binds")
    cycle = limit_cycle(env, 0.25)  # above π/2 − φ/2 at v1, below the edge-order bound
    assert cycle.found and cycle.scope == "every-start" and "sufficient, not necessary" in cycle.reason
    assert cycle.stages[0].step.contraction > 1 > cycle.contraction  # one step expands, the cycle contracts
    runs = _simulate(env, 0.25, np.zeros(5, dtype=int), np.linspace(0.001, 0.999, 5), 5 * 12)
    assert np.allclose(runs.t[:, -1], float(cycle.points[0].t), rtol=1e-9)


# ---------------------------------------------------------------------- Prop. 4 (any polygon)
@given(env=polygons_with_holes(), tan=st.sampled_from(["1/4", "1/3", "1/6", "-1/4", "2/3"]),
       start=st.fractions(Fraction(1, 50), Fraction(49, 50), max_denominator=50), edge=st.integers(0, 40))
@settings(max_examples=FEW)
def test_prop4_iterated_cycle_is_where_the_simulation_goes(env, tan, start, edge):
    heading = ExactHeading.from_tangent(tan)
    e0 = edge % env.n_edges
    cycle = limit_cycle(env, heading, method="iterate", start=(e0, start), max_bounces=3000)
    event(f"{cycle.status.value} {cycle.scope}")
    if cycle.status is Status.NOT_FOUND:
        return
    if not cycle.found:  # a periodic orbit that is not a stable cycle: the reason says which
        assert cycle.status in (Status.NOT_CONTRACTING, Status.NOT_REALISED, Status.VERTEX) and cycle.reason
        return
    _verify_orbit_by_exact_casts(cycle)
    assert float(cycle.contraction_exact) < 1
    if cycle.scope != "start+basin":
        return
    # entry then k cycles, in simulation, lands on the first contact point
    k = cycles_to_epsilon(cycle.contraction, 1.0, 1e-12 * float(cycle.points[0].t)) + 1 if cycle.contraction > 0 else 1
    bounces = len(cycle.entry) + k * cycle.period
    assume(bounces <= 3000)
    runs = _simulate(env, heading.theta, [e0], [float(start)], bounces)
    assume(runs.outcome_counts()["ok"] == 1)  # the float simulator may stop a ray it cannot call
    assert [s.step.from_edge for s in cycle.entry] == runs.edge[0, :len(cycle.entry)].tolist()
    assert runs.edge[0, -1] == cycle.points[0].edge
    assert runs.t[0, -1] == pytest.approx(float(cycle.points[0].t), rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("model", ["one_hole", "two_holes", "degenerate", "l_shape"])
def test_prop4_constant_controller_drives_every_simulated_start_into_a_cycle(model):
    env = load_environment(MODELS / f"{model}.json")
    ctrl = constant_controller(env)
    assert ctrl.proved and ctrl.cycles
    for c in ctrl.cycles:
        assert c.found and c.scope == "every-start"
        _verify_orbit_by_exact_casts(c)
    theta = ctrl.heading.theta
    worst = max(c.contraction for c in ctrl.cycles)
    k = cycles_to_epsilon(worst, 1.0, 1e-12) + 2
    period = max(c.period for c in ctrl.cycles)
    runs = simulate_rule(env, Fixed(theta), None, bounces=ctrl.bounces + k * period, trials=300, seed=11,
                         initial=[theta], ties="exact", record="ends")
    ok = runs.status == 0
    assert ok.mean() > 0.95  # rays the float caster cannot call are stopped, never misassigned
    contacts = {}
    for c in ctrl.cycles:
        for p in c.points:
            contacts.setdefault(p.edge, []).append(float(p.t))
    for e, t in zip(runs.final_edge[ok], runs.final_t[ok]):
        assert e in contacts, f"a start ended on e{e}, which no cycle visits"
        assert min(abs(t - x) for x in contacts[e]) < 1e-8


def test_prop4_constant_controller_reports_a_polygon_it_cannot_prove():
    corridor = Environment.from_coords([[0, 0], [50, 0], [50, 2], [0, 2]], name="corridor")
    ctrl = constant_controller(corridor, tangents=["1/4", "1/2"])  # both leave neutral period-2 orbits across the corridor
    assert not ctrl.proved and ctrl.heading is None and len(ctrl.tried) == 2
    assert all("still outside the basins" in outcome for _, outcome in ctrl.tried)
    assert constant_controller(corridor, tangents=["1/32"]).proved  # a shallow heading reaches the corners


def test_neutral_orbit_between_parallel_walls_is_not_a_limit_cycle():
    corridor = Environment.from_coords([[0, 0], [50, 0], [50, 2], [0, 2]], name="corridor")
    cycle = limit_cycle(corridor, "tan:1/2", method="iterate", start="e0:1/2")
    assert cycle.status is Status.NOT_CONTRACTING and cycle.edges == (0, 2)
    assert "neutral family" in cycle.reason and cycle.contraction_exact == 1


# ---------------------------------------------------------------------- --edges, inputs, JSON
def test_edges_mode_realises_or_explains():
    found = limit_cycle(SQUARE, "tan:1/3", edges="e0,e1,e2,e3")
    assert found.found and found.method == "edges" and found.scope == "basin"
    assert found.points[0].basin[0] < found.points[0].t < found.points[0].basin[1]
    skip = limit_cycle(SQUARE, "tan:1/3", edges=[0, 2])
    assert skip.status is Status.NOT_REALISED
    back = limit_cycle(SQUARE, "tan:1/3", edges=[0, 1, 0])
    assert back.status is Status.NOT_REALISED and back.reason


def test_bad_inputs_are_one_line_input_errors():
    with pytest.raises(InputError, match=r"^heading 3.5 is not inside \(0, π\) \(radians\)$"):
        limit_cycle(SQUARE, 3.5)
    with pytest.raises(InputError, match=r"^unknown edge e9: edges are e0..e3$"):
        limit_cycle(SQUARE, 0.3, edges="e0,e9")
    with pytest.raises(InputError, match=r"^start point e0:1 is not inside the edge"):
        limit_cycle(SQUARE, 0.3, method="iterate", start="e0:1")
    holed = load_environment(MODELS / "one_hole.json")
    with pytest.raises(InputError, match=r"^Lemma 3 needs a convex polygon without holes"):
        limit_cycle(holed, 0.3, method="theorem1")


def test_cycle_answer_has_the_contract_shape():
    env = load_environment(MODELS / "two_holes.json")
    answer = json.loads(json.dumps(limit_cycle(env, 0.2, epsilon=1e-6).to_json()))
    for key in ("status", "entry", "cycle", "contraction", "contraction_exact", "fixed_point", "cycles_to_epsilon", "optimality"):
        assert key in answer
    assert answer["status"] == "found" and answer["scope"] == "start+basin"
    stage = answer["cycle"][0]
    assert set(stage) >= {"from_segments", "to_segments", "interval"} and stage["interval"][0] == stage["interval"][1]
    assert all(set(p) >= {"edge", "t", "point"} for p in answer["fixed_point"])
    assert Fraction(answer["contraction_exact"]) < 1
    # executing entry then the cycle visits the cycle's segments (the simulator with a stage policy)
    from solverplan.simulate import StagePolicy, simulate_policy

    stages = [tuple(s["interval"]) for s in answer["entry"] + answer["cycle"]]
    targets = [[_segment(env, t) for t in s["to_segments"]] for s in answer["entry"] + answer["cycle"]]
    policy = StagePolicy(stages, targets=targets, repeat_from=len(answer["entry"]))
    runs = simulate_policy(env, policy, ([0], [0.5]), bounces=200, ties="exact", seed=0)
    assert runs.outcome_counts()["ok"] == 1


def _segment(env, seg_id):
    from solverplan.bounce.partitions import partition

    return partition(env).segments[seg_id]


# ---------------------------------------------------------------------- the result protocol
def test_a_verified_cycle_follows_the_result_protocol():
    from solverplan.result import AffineStep, EnvironmentRecord, Result, Stage

    cycle = limit_cycle(SQUARE, "tan:1/2")
    assert isinstance(cycle, Result) and cycle.status.answered
    assert cycle.optimality.method is Method.EXACT_CHECK and cycle.optimality.proved and not cycle.optimality.limits
    assert cycle.optimality.scope.startswith("every start on the boundary converges")
    assert cycle.environment == EnvironmentRecord.of(SQUARE, cycle.environment.n_segments) and cycle.environment.matches(SQUARE)
    for stage in cycle.stages:
        assert isinstance(stage, Stage) and isinstance(stage.affine, AffineStep)
        assert stage.interval.lo == stage.interval.hi == cycle.theta == stage.step.heading
    # the stages' exact maps compose to the return map whose |α| is the contraction (Def. 12)
    alpha = Fraction(1)
    for stage in cycle.stages:
        alpha *= stage.step.alpha
    assert abs(alpha) == cycle.contraction_exact == Fraction(1, 16)
    answer = cycle.to_json()
    assert answer["environment"] == {"name": "square", "sha256": cycle.environment.sha256,
                                     "n_segments": cycle.environment.n_segments}
    assert answer["method"] == "theorem1" and answer["optimality"]["method"] == "exact-check"
    assert answer["optimality"]["proved"] is True and answer["cycle"][0]["nominal"] == cycle.theta
    assert "seconds_search" in answer["stats"]
    assert "optimality: exact-check" in cycle.to_text()


def test_iterate_records_its_work_and_what_the_entry_proves():
    env = load_environment(MODELS / "two_holes.json")
    cycle = limit_cycle(env, 0.2)  # iterate from e0:1/2
    assert cycle.method == "iterate" and cycle.scope == "start+basin"
    assert cycle.optimality.proved and "the start e0:0.5" in cycle.optimality.scope
    counts = cycle.stats.counts
    assert counts["bounces_simulated"] >= 1 and counts["entry_bounces"] >= 1
    assert len(cycle.entry) >= counts["entry_bounces"]  # the proved bounces, then the walk to the first contact


def test_a_bounded_iteration_that_finds_nothing_proves_nothing():
    cycle = limit_cycle(SQUARE, "tan:1/2", method="iterate", max_bounces=3)
    assert cycle.status is Status.NOT_FOUND and cycle.status.incomplete and not cycle.points
    assert cycle.optimality.method is Method.HEURISTIC and not cycle.optimality.proved
    assert cycle.optimality.limits == ("max_bounces=3",)
    assert cycle.to_json()["status"] == "not-found" and cycle.to_json()["optimality"]["limits"] == ["max_bounces=3"]


def test_a_proved_failure_is_proven_infeasible_for_the_sequence_examined():
    repels = limit_cycle(SQUARE, "tan:2")
    assert repels.status.proven_infeasible and repels.optimality.proved
    assert repels.optimality.method is Method.EXACT_CHECK and "e0 → e1 → e2 → e3 → e0" in repels.optimality.scope
    skip = limit_cycle(SQUARE, "tan:1/3", edges=[0, 2])
    assert skip.status is Status.NOT_REALISED and skip.status.proven_infeasible and "e0 → e2 → e0" in skip.optimality.scope


def test_an_entry_cut_short_by_the_budget_is_not_proved():
    from solverplan.bounce._cycle_core import basins_grid, cycle_along, prove_entry
    from solverplan.bounce.constant_map import ConstantMap
    from solverplan.bounce.cycles import _optimality

    cmap = ConstantMap(SQUARE, ExactHeading.from_tangent("1/2"))
    core = cycle_along(SQUARE, cmap, (0, 1, 2, 3), Status.NOT_REALISED)
    basins = basins_grid(core.edges, core.orbit, core.radii)
    outside = Fraction(19, 20)  # the basin around t* = 1/3 on e0 is (0, 2/3)
    assert prove_entry(cmap, 0, outside, basins, 0).budget_hit
    entered = prove_entry(cmap, 0, outside, basins, 20)
    assert entered.steps is not None and not entered.budget_hit
    claim = _optimality(Status.FOUND, "basin", core.edges, algorithm="", start=(0, outside), limits=("max_bounces=0",))
    assert not claim.proved and claim.limits == ("max_bounces=0",) and "e0:0.95" in claim.scope


def test_a_given_heading_inside_the_margin_is_used_as_asked():
    cycle = limit_cycle(SQUARE, 0.0005)  # the user asked for it: the planners' margin does not apply
    assert cycle.found and cycle.theta == 0.0005


def test_the_constant_controller_skips_headings_inside_the_margin():
    from solverplan.interval import DEFAULT_HEADING_MARGIN

    room = Environment.from_coords([[0, 0], [12, 0], [12, 9], [0, 9]], [[[4, 3], [4, 5], [7, 6], [8, 3]]])
    ctrl = constant_controller(room, tangents=["1/10000", "-1/10000", "1/4"])
    assert ctrl.proved and ctrl.heading.spec() == "tan:0.25" and ctrl.heading_margin == DEFAULT_HEADING_MARGIN
    assert [o.startswith("skipped") for _, o in ctrl.tried] == [True, True, False]
    assert ctrl.stats.counts["headings_tried"] == 1
    with pytest.raises(InputError, match="every candidate heading is within heading_margin"):
        constant_controller(room, tangents=["1/10000"])
    for bad in (-0.1, 1.0, float("nan"), True):
        with pytest.raises(InputError, match="heading_margin must be in"):
            constant_controller(room, heading_margin=bad)


def test_a_controller_search_that_fails_is_incomplete_with_its_limits():
    corridor = Environment.from_coords([[0, 0], [50, 0], [50, 2], [0, 2]], name="corridor")
    ctrl = constant_controller(corridor, tangents=["1/4"], max_steps=50)
    assert ctrl.status is Status.NOT_FOUND and ctrl.status.incomplete and not ctrl.proved
    assert ctrl.optimality.method is Method.HEURISTIC and ctrl.optimality.limits == ("max_steps=50",)
    answer = ctrl.to_json()
    assert answer["status"] == "not-found" and answer["proved"] is False and answer["environment"]["name"] == "corridor"
    assert "limits hit: max_steps=50" in ctrl.to_text()
