"""Plan results: the JSON of docs/contract.md, text, reading plans back."""

from __future__ import annotations

import json
import math

import pytest

from solverplan.environment import Environment
from solverplan.errors import MalformedFile
from solverplan.plan import Plan, Status, find_plan, load_plan, parse_plan

SQUARE = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
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
                                  "algorithm": data["optimality"]["algorithm"]}


def test_text_table():
    text = find_plan(SQUARE, "e0", "e2").to_text()
    assert text.splitlines()[0] == "fewest plan in 'square' from e0 to e2"
    assert "bounces 2" in text and "proved, bound 2" in text


@pytest.mark.parametrize(
    "data, message",
    [
        ([], r"^plan: expected a JSON object \(a plan\)$"),
        ({"status": "maybe"}, r"^plan: status must be 'found' or 'infeasible', got 'maybe'$"),
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
