"""Plan results: the JSON of docs/contract.md, text, reading plans back."""

from __future__ import annotations

import json
import math

import pytest

from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.plan import Plan, find_plan, load_plan, parse_plan
from solverplan.result import EnvironmentRecord, Method, Optimality, Status
from tests.shapes import SQUARE

ELL = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]], name="ell")


def test_plan_json_round_trips():
    plan = find_plan(ELL, "e2,e4:0:0.5", "e1", objective="tolerance")
    assert plan.found and len(plan.stages[0].from_segments) == 2
    data = json.loads(json.dumps(plan.to_json()))
    back = parse_plan(data)
    assert back.stages == plan.stages and back.status is Status.FOUND
    assert back.optimality == plan.optimality and back.start == plan.start and back.goal == plan.goal
    assert back.min_width == plan.min_width and back.environment == plan.environment


def test_contract_fields_and_numbers():
    plan = find_plan(SQUARE, "e0", "e1", objective="tolerance")
    data = plan.to_json()
    assert data["bounces"] == 1 and data["tolerance"] == data["min_width"] / 2
    assert data["stages"][0]["interval"][0] > 0 and data["stages"][0]["interval"][1] < math.pi
    assert data["optimality"] == {"method": "search-exhausted", "proved": True, "bound": data["min_width"],
                                  "scope": data["optimality"]["scope"], "gap": 0.0,
                                  "algorithm": data["optimality"]["algorithm"]}
    scope = data["optimality"]["scope"]
    assert scope.startswith("plans whose first stage works from every point of the start set as given")
    assert "straight walls (collinear vertices merged)" in scope and "admissible intervals" in scope
    assert all(stage["width"] == stage["interval"][1] - stage["interval"][0] for stage in data["stages"])


def test_text_table():
    text = find_plan(SQUARE, "e0", "e2").to_text()
    assert text.splitlines()[0] == "fewest plan in 'square' from e0 to e2"
    assert "bounces 2" in text and "proved, bound 2" in text


@pytest.mark.parametrize(
    "data, message",
    [
        ([], r"^plan: expected a JSON object \(a plan\)$"),
        ({"status": "maybe"}, r"^plan: status must be 'found', 'infeasible' or 'not-found', got 'maybe'$"),
        ({"status": "found", "stages": [{"from_segments": [0], "to_segments": [1], "interval": [1.0]}]},
         r"^plan: stages\[0\].interval: expected \[lo, hi\]$"),
        ({"status": "found", "stages": [{"from_segments": [0], "to_segments": [1], "interval": [1.0, 0.5]}]},
         r"^plan: stages\[0\].interval \[1.0, 0.5\] is not inside \(0, π\)$"),
        ({"status": "found", "stages": [{"from_segments": [0], "to_segments": [1], "interval": [0.5, 1.0]},
                                        {"from_segments": [2], "to_segments": [1], "interval": [0.5, 1.0]}]},
         r"^plan: stages\[1\].from_segments must be stages\[0\].to_segments$"),
        ({"status": "found", "stages": [{"from_segments": [0, 1], "to_segments": [2, 3], "interval": [0.5, 1.0]}]},
         r"^plan: stages\[0\]: several sources and targets need 'moves'"),
    ],
)
def test_malformed_plans_are_rejected_with_the_place(data, message):
    with pytest.raises(MalformedFile, match=message):
        parse_plan(data)


def test_load_plan_reports_unreadable_files(tmp_path):
    bad = tmp_path / "plan.json"
    bad.write_text("{")
    with pytest.raises(MalformedFile, match="not valid JSON"):
        load_plan(bad)


def test_infeasible_plan_json_has_a_reason_and_no_numbers():
    plan = find_plan(SQUARE, "e0", "e2", max_bounces=1)
    data = plan.to_json()
    assert data["status"] == "infeasible" and data["reason"].startswith("exhausted all plans with ≤ 1 bounces")
    assert data["bounces"] is None and data["min_width"] is None and data["tolerance"] is None
    assert isinstance(plan, Plan) and not plan.found


def test_old_plan_files_still_load():
    """A plan written before the shared result protocol: no scope or gap, an old method spelling, the
    environment as a plain record; it loads, with the method mapped and the record read."""
    plan = find_plan(SQUARE, "e0", "e2")
    data = json.loads(json.dumps(plan.to_json()))
    old = {key: data[key] for key in ("status", "objective", "bounces", "min_width", "tolerance", "start", "goal")}
    old["stages"] = [{k: s[k] for k in ("from_segments", "to_segments", "interval")} for s in data["stages"]]
    old["optimality"] = {"method": "dag-exhausted", "proved": True, "bound": 2}
    old["environment"] = {"name": "square", "sha256": data["environment"]["sha256"]}
    back = parse_plan(old)
    assert back.optimality.method is Method.SEARCH_EXHAUSTED and back.optimality.proved
    assert back.optimality.scope == "" and back.optimality.gap is None
    assert back.environment == EnvironmentRecord("square", data["environment"]["sha256"])
    assert back.intervals == plan.intervals
    back.check_environment(SQUARE, 4)  # the same rings: no error
    unknown = parse_plan({**old, "optimality": {"method": "oracle", "proved": True, "bound": 2}})
    assert unknown.optimality.method is Method.NONE and not unknown.optimality.proved
    search = parse_plan({**old, "optimality": {"method": "search", "proved": False, "bound": None}})
    assert search.optimality.method is Method.HEURISTIC


def test_a_plan_made_elsewhere_is_refused():
    plan = find_plan(SQUARE, "e0", "e2")
    other = Environment.from_coords([[0, 0], [5, 0], [5, 5], [0, 5]], name="big")
    with pytest.raises(InputError, match="made in another environment"):
        plan.check_environment(other, 4)


def test_constructing_is_strict_about_methods():
    with pytest.raises(ValueError, match="unknown optimality method 'dag-exhausted'"):
        Plan.infeasible("fewest", "none", Optimality("dag-exhausted", True, None))
    with pytest.raises(MalformedFile, match="optimality.limits: expected a list of strings"):
        parse_plan({"status": "infeasible", "optimality": {"method": "milp", "proved": False, "bound": None,
                                                             "limits": 3}})
