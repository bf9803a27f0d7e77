"""Plans become certificates that the independent exact checker accepts, with their
optimality claims; a certificate of a plan whose interval was widened past the safe set is rejected."""

from __future__ import annotations

from pathlib import Path

from dataclasses import replace
from fractions import Fraction

import pytest

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.interval import Interval
from solverplan.certify.check import check_certificate
from solverplan.certify.build import certificate
from solverplan.environment import load_environment
from solverplan.plan import find_plan, pareto_front

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"


@pytest.fixture(scope="module")
def two_rooms():
    env = load_environment(MODELS / "two_rooms.json")
    return env, safe_bounce_visibility_graph(env)


def _expected(env, spec):
    return [(p.edge, p.t0, p.t1) for p in env.boundary_set(spec).pieces]


@pytest.mark.parametrize("objective, budget", [("fewest", None), ("tolerance", None), ("tolerance", 5), ("sum", 4),
                                               ("constant", None)])
def test_two_rooms_plans_have_valid_certificates(two_rooms, objective, budget):
    env, graph = two_rooms
    start, goal = "e0:0.2:0.8", "e4:0.5:1"
    plan = find_plan(env, start, goal, objective=objective, max_bounces=budget, graph=graph)
    cert = certificate(plan, env=env, partition=graph.partition)
    report = check_certificate(cert, expected_rings=env.rings, expected_start=_expected(env, start),
                               expected_goal=_expected(env, goal))
    assert report.valid, [str(f) for f in report.failures]
    claims = cert.claims
    assert claims.bounces == plan.bounces and claims.objective == objective
    assert abs(float(claims.min_width) - plan.min_width) < 1e-9  # the certified width is the plan's, to 1e-9
    assert claims.optimality.proved and claims.optimality.bound == Fraction(plan.optimality.bound)
    assert len(cert.stages[0].moves) == len(plan.stages[0].from_segments) == 4  # one move per possible source


def test_goal_inside_a_segment_is_certified_with_exact_images(two_rooms):
    env, graph = two_rooms
    plan = find_plan(env, "e5", "e0:0.6:0.8", graph=graph)
    cert = certificate(plan, env=env, partition=graph.partition)
    (move,) = cert.stages[-1].moves
    assert Fraction(6, 10) < move.target[0] < move.target[1] < Fraction(8, 10)  # the image, inside the goal piece
    assert check_certificate(cert).valid


def test_every_pareto_point_is_certified(two_rooms):
    env, graph = two_rooms
    for point in pareto_front(env, "e0", "e4", graph=graph).points:
        report = check_certificate(certificate(point.plan, env=env, partition=graph.partition))
        assert report.valid, (point.bounces, [str(f) for f in report.failures])


def test_plans_on_holes_and_degenerate_models_are_certified():
    for model, start, goal in [("one_hole", "e1,e5", "e3"), ("two_holes", "e6:0.25:0.75", "e9:0.1:0.75,e1:0.25:0.6"),
                               ("degenerate", "e12:0.1:0.75,e9:0.25:1", "e1,e13:0:0.6")]:
        env = load_environment(MODELS / f"{model}.json")
        for objective in ("fewest", "tolerance"):
            plan = find_plan(env, start, goal, objective=objective)
            report = check_certificate(certificate(plan, env=env))
            assert report.valid, (model, objective, [str(f) for f in report.failures])


def test_a_widened_interval_is_caught_by_the_checker(two_rooms):
    env, graph = two_rooms
    plan = find_plan(env, "e0", "e4", graph=graph)
    k = min(range(plan.bounces), key=lambda i: plan.stages[i].width)
    stage = plan.stages[k]
    wide = replace(stage, interval=Interval(stage.interval.lo - 0.05, stage.interval.hi + 0.05))
    bad = plan.with_(stages=plan.stages[:k] + (wide,) + plan.stages[k + 1:])
    report = check_certificate(certificate(bad, env=env, partition=graph.partition))
    assert not report.valid and any(f"stages[{k}]" in str(f) for f in report.failures)


def test_infeasible_plans_and_plans_of_no_stages_certify(two_rooms):
    env, graph = two_rooms
    infeasible = find_plan(env, "e0", "e4", max_bounces=2, graph=graph)  # certified since issue #22
    assert certificate(infeasible, env=env).kind == "infeasible"
    empty = find_plan(env, "e0:0.1:0.2", "e0", graph=graph)
    cert = certificate(empty, env=env)  # its start set lies in its goal set: checked exactly (session 9)
    assert cert.stages == () and cert.claims.bounces == 0 and check_certificate(cert).valid
