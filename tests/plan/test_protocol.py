"""The shared result protocol (solverplan.result) on every answer of solverplan.plan: the five attributes,
statuses in their groups, optimality claims with a Method, a scope and one meaning of gap, and caps that
make a claim unproved."""

from __future__ import annotations

import importlib
import json
import math
from pathlib import Path

import pytest

from solverplan.environment import Environment, load_environment
from solverplan.plan import Funnel, Localization, ParetoFront, Patrol, Plan, find_plan, pareto_front
from solverplan.plan.funnels import funnel
from solverplan.plan.localization import localize
from solverplan.plan.patrols import patrol
from solverplan.result import EnvironmentRecord, Method, Optimality, Result, Stage, Stats, Status
from tests.shapes import SQUARE

patrol_module = importlib.import_module("solverplan.plan.patrols")
MODELS = Path(__file__).resolve().parent.parent.parent / "solverplan" / "models"
TRIANGLE = Environment.from_coords([[0, 0], [10, 0], [3, 7]], name="triangle")

BUILDERS = {
    "plan": (Plan, lambda: find_plan(SQUARE, "e0", "e2", objective="tolerance")),
    "plan-infeasible": (Plan, lambda: find_plan(SQUARE, "e0", "e2", max_bounces=1)),
    "front": (ParetoFront, lambda: pareto_front(SQUARE, "e0", "e2")),
    "patrol": (Patrol, lambda: patrol(SQUARE, "e0,e1,e2,e3", tolerance=0.05)),
    "patrol-rate": (Patrol, lambda: patrol(SQUARE, "e0,e1,e2,e3", start="e2", objective="rate", tolerance=0.05)),
    "patrol-tolerance": (Patrol, lambda: patrol(SQUARE, "e0,e1,e2,e3", objective="tolerance")),
    "funnel": (Funnel, lambda: funnel(SQUARE, "e0", "e2:0.45:0.55", tolerance=0.005)),
    "funnel-not-found": (Funnel, lambda: funnel(SQUARE, "e0", "e2:0.45:0.55", tolerance=0.005, max_bounces=1)),
    "localization": (Localization, lambda: localize(TRIANGLE, 0.05, start="e0", tolerance=0.002)),
    "localization-symmetric": (Localization, lambda: localize(SQUARE, 0.1)),
}


@pytest.fixture(scope="module", params=sorted(BUILDERS))
def answer(request):
    kind, build = BUILDERS[request.param]
    result = build()
    assert type(result) is kind
    return result


def test_every_answer_has_the_five_attributes(answer):
    assert isinstance(answer, Result)
    assert isinstance(answer.status, Status) and answer.status in Status
    assert isinstance(answer.optimality, Optimality) and isinstance(answer.optimality.method, Method)
    assert isinstance(answer.stats, Stats)
    assert isinstance(answer.environment, EnvironmentRecord)
    assert answer.environment.name in ("square", "triangle")
    assert answer.environment.matches(SQUARE if answer.environment.name == "square" else TRIANGLE)
    text = answer.to_text()
    assert isinstance(text, str) and answer.optimality.method.value in text


def test_to_json_round_trips_through_json(answer):
    data = answer.to_json()
    text = json.dumps(data, allow_nan=False)
    assert json.loads(text) == data
    assert data["status"] == answer.status.value
    assert data["optimality"]["method"] == answer.optimality.method.value
    assert data["optimality"]["scope"] == answer.optimality.scope and answer.optimality.scope
    assert data["environment"]["sha256"] == answer.environment.sha256


def test_every_answer_has_its_kind_first_and_reads_back_to_the_same_json(answer):
    from solverplan.answers import read_answer

    data = json.loads(json.dumps(answer.to_json()))
    assert list(data)[:2] == ["kind", "status"] and data["kind"] == type(answer).kind
    env = SQUARE if answer.environment.name == "square" else TRIANGLE
    back = read_answer(data, env=env)
    assert type(back) is type(answer) and json.loads(json.dumps(back.to_json())) == data


def test_proved_is_false_whenever_a_limit_was_hit(answer):
    opt = answer.optimality
    if opt.limits:
        assert not opt.proved
        assert answer.status is not Status.INFEASIBLE  # a capped search proves no absence
    if answer.status.incomplete:
        assert opt.limits and not opt.proved


def test_gap_is_value_minus_bound_over_the_scope(answer):
    opt = answer.optimality
    if opt.gap is None:
        return
    assert opt.gap >= 0 and opt.bound is not None
    if isinstance(answer, Plan):
        assert opt.gap == pytest.approx(abs(answer.value - opt.bound), abs=1e-12)
    elif isinstance(answer, Patrol):
        value = {"contraction": answer.contraction, "rate": answer.rate, "tolerance": answer.tolerance}[answer.objective]
        assert opt.gap == pytest.approx(abs(value - opt.bound), abs=1e-12)


def test_stages_are_the_shared_stage(answer):
    stages = []
    if isinstance(answer, ParetoFront):
        stages = [s for p in answer.points for s in p.plan.stages]
    elif isinstance(answer, Patrol):
        stages = [*answer.entry, *answer.cycle]
        assert all(s.affine is not None and len(s.from_segments) == len(s.to_segments) == 1 for s in answer.cycle)
    else:
        stages = list(answer.stages)
        if isinstance(answer, (Funnel, Localization)):
            assert all(s.positions and len(s.sources) == len(s.cones) == len(s.target_edges) for s in stages)
    assert all(type(s) is Stage for s in stages)
    assert bool(stages) == (answer.status.answered and not (isinstance(answer, Plan) and answer.bounces == 0))


def test_statuses_and_methods_of_each_kind():
    built = {name: build() for name, (_, build) in BUILDERS.items()}
    assert built["plan"].status is Status.FOUND and built["plan"].optimality.method is Method.SEARCH_EXHAUSTED
    assert built["plan-infeasible"].status is Status.INFEASIBLE and built["plan-infeasible"].optimality.proved
    assert built["patrol"].optimality.method is Method.SEARCH_EXHAUSTED  # the one-period DAG DP
    assert built["patrol-rate"].optimality.method is Method.LP_DUALITY
    assert built["patrol-tolerance"].optimality.method is Method.BISECTION
    assert built["funnel"].optimality.method is Method.HEURISTIC and not built["funnel"].optimality.proved
    assert built["funnel-not-found"].status is Status.NOT_FOUND
    assert built["funnel-not-found"].optimality.limits == ("max_bounces=1", "beam=400", "n_headings=240", "max_rows=250000",
                                                          "cut=max_bounces")
    assert built["localization"].status is Status.FOUND and built["localization"].optimality.method is Method.HEURISTIC
    sym = built["localization-symmetric"]
    assert sym.status is Status.INFEASIBLE and sym.optimality.method is Method.SYMMETRY and sym.optimality.proved


def test_patrol_reports_bounds_over_wider_classes_apart_from_the_gap():
    """With extra bounces between required visits the square's one-period contraction can be made far smaller —
    a wider class than the answer's scope: that bound is ``bound_all_classes``, and the gap stays ≈ 0."""
    p = patrol(SQUARE, "e0,e1,e2,e3", tolerance=0.05)
    assert p.bound_all_classes is not None and p.bound_all_classes < 1e-6 * p.contraction
    assert p.optimality.gap < 1e-12 and p.optimality.bound == pytest.approx(p.contraction, rel=1e-9)
    data = p.to_json()
    assert data["bound_all_classes"] == p.bound_all_classes and "optimality_scope" not in data
    assert "bound over all classes" in p.to_text()
    rate = patrol(SQUARE, "e0,e1,e2,e3", objective="rate", tolerance=0.05)
    assert rate.bound_all_classes is not None and rate.bound_all_classes <= rate.rate * (1 + 1e-9)
    assert rate.optimality.gap == pytest.approx(abs(rate.rate - rate.optimality.bound), abs=1e-12)


def test_a_capped_reachability_search_makes_the_patrol_unproved(monkeypatch):
    """With the entry search capped at one belief, the segments reachable from the start set may be incomplete:
    an answer is not proved optimal and a failure is not-found, never infeasible."""
    env = load_environment(MODELS / "narrow_door.json")
    proved = patrol(env, "e0,e10", start="e4", tolerance=0.01)
    assert proved.status is Status.INFEASIBLE and proved.optimality.proved and not proved.optimality.limits
    monkeypatch.setattr(patrol_module, "MAX_ENTRY_BELIEFS", 1)
    capped = patrol(env, "e0,e10", start="e4", tolerance=0.01)
    assert capped.status is Status.NOT_FOUND and not capped.optimality.proved
    assert capped.optimality.limits == ("max_beliefs=1",) and "not a proof" in capped.reason
    found = patrol(SQUARE, "e0,e1,e2,e3", start="e2", tolerance=0.05)
    assert found.found and not found.optimality.proved and found.optimality.limits == ("max_beliefs=1",)
    assert math.isfinite(found.contraction)
