"""`solverplan plan`, `solverplan simulate`, `solverplan render --plan`: answers, exit codes, files."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from solverplan.certify.check import check_certificate
from solverplan.certify.schema import load_certificate
from tests.cli_runs import run, assert_one_line_error

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
TWO_ROOMS = MODELS / "two_rooms.json"

# the contract's plan fields, in the one key order of every answer: kind, status, the plan's fields, ... optimality
CONTRACT_KEYS = ["kind", "status", "objective", "bounces", "min_width", "tolerance", "stages"]


def test_plan_prints_the_contract_plan_and_writes_a_verified_certificate(tmp_path):
    cert = tmp_path / "cert.json"
    result = run("plan", TWO_ROOMS, "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "--objective", "tolerance",
                 "--certificate", cert)
    assert result.exit_code == 0, result.stderr
    plan = json.loads(result.stdout)
    assert list(plan)[: len(CONTRACT_KEYS)] == CONTRACT_KEYS and "reason" not in plan and plan["kind"] == "plan"
    assert list(plan)[-3:] == ["optimality", "stats", "environment"]
    assert plan["status"] == "found" and plan["tolerance"] == pytest.approx(plan["min_width"] / 2)
    assert set(plan["stages"][0]) >= {"from_segments", "to_segments", "interval"}
    assert plan["optimality"]["method"] == "search-exhausted" and plan["optimality"]["proved"] is True
    assert plan["start"] == "e0:0.2:0.8" and plan["goal"] == "e4:0.5:1"
    verified = run("verify", cert, "--env", TWO_ROOMS, "--from", "e0:0.2:0.8", "--to", "e4:0.5:1")
    assert verified.exit_code == 0, verified.stderr
    certificate = load_certificate(cert)
    assert check_certificate(certificate).valid and certificate.claims.objective == "tolerance"


def test_plan_infeasible_is_an_answer_with_exit_0(tmp_path):
    cert = tmp_path / "cert.json"
    result = run("plan", TWO_ROOMS, "--from", "e17,e0", "--to", "e4:0.25:1", "--objective", "constant", "--certificate", cert)
    assert result.exit_code == 0, result.stderr
    plan = json.loads(result.stdout)
    assert plan["status"] == "infeasible" and plan["reason"].startswith("no constant interval survives")
    assert plan["bounces"] is None and plan["stages"] == [] and plan["optimality"]["proved"] is True
    assert not cert.exists()  # certificates certify plans; a warning says so on stderr
    assert "no certificate written" in result.stderr


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--from", "e0", "--to", "e99"], "unknown edge e99: edges are e0..e17"),
        (["--from", "e0:0.5:0.2", "--to", "e4"], "need 0 <= t0 < t1 <= 1"),
        (["--from", "e0", "--to", "e4", "--objective", "sum"], "objective 'sum' needs max_bounces"),
        (["--from", "e0", "--to", "e4", "--method", "simplex"], "unknown method 'simplex' for objective 'fewest'"),
        (["--from", "e0", "--to", "e4", "--pareto", "--objective", "sum"], "--pareto answers the bounces ↔ tolerance front"),
        (["--from", "e0", "--to", "e4", "--objective", "fastest"], "fastest"),
    ],
)
def test_plan_bad_input_exits_2_with_one_line(args, fragment):
    assert_one_line_error(run("plan", TWO_ROOMS, *args), 2, fragment)


def test_plan_pareto_and_text_output(tmp_path):
    result = run("plan", TWO_ROOMS, "--from", "e0", "--to", "e4", "--pareto", "--max-bounces", "6")
    assert result.exit_code == 0, result.stderr
    front = json.loads(result.stdout)
    bounces = [p["bounces"] for p in front["front"]]
    widths = [p["min_width"] for p in front["front"]]
    assert bounces == sorted(bounces) and widths == sorted(widths) and max(bounces) <= 6 and len(bounces) >= 2
    text = run("plan", TWO_ROOMS, "--from", "e0", "--to", "e4", "--format", "text")
    assert text.exit_code == 0 and "fewest plan in 'two_rooms' from e0 to e4" in text.stdout
    assert "stage" in text.stdout and "interval (rad)" in text.stdout


def test_simulate_a_written_plan(tmp_path):
    plan_file = tmp_path / "plan.json"
    assert run("plan", TWO_ROOMS, "--from", "e0", "--to", "e4", "-o", plan_file).exit_code == 0
    result = run("simulate", TWO_ROOMS, plan_file, "--trials", "10000", "--seed", "4", "--sampling", "endpoints")
    assert result.exit_code == 0, result.stderr
    runs = json.loads(result.stdout)
    assert runs["success_rate"] == 1.0 and runs["trials"] == 10000 and runs["seed"] == 4
    assert runs["bounces_to_goal"]["min"] == runs["bounces_to_goal"]["max"] == json.loads(plan_file.read_text())["bounces"]


def test_simulate_rejects_bad_plans(tmp_path):
    plan_file = tmp_path / "plan.json"
    assert run("plan", TWO_ROOMS, "--from", "e0", "--to", "e4", "-o", plan_file).exit_code == 0
    assert_one_line_error(run("simulate", MODELS / "square.json", plan_file), 2, "the plan was made in another environment")
    broken = tmp_path / "broken.json"
    broken.write_text('{"status": "found", "stages": [{"from_segments": [0], "to_segments": [1], "interval": [0, 1]}]}')
    assert_one_line_error(run("simulate", TWO_ROOMS, broken), 2, "is not inside (0, π)")
    infeasible = tmp_path / "infeasible.json"
    assert run("plan", TWO_ROOMS, "--from", "e0", "--to", "e4", "--max-bounces", "2", "-o", infeasible).exit_code == 0
    assert_one_line_error(run("simulate", TWO_ROOMS, infeasible), 2, "the plan is infeasible")
    assert_one_line_error(run("simulate", TWO_ROOMS, tmp_path / "missing.json"), 2, "no such file")


def test_render_a_plan_with_trajectories(tmp_path):
    plan_file = tmp_path / "plan.json"
    picture = tmp_path / "plan.svg"
    assert run("plan", TWO_ROOMS, "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "-o", plan_file).exit_code == 0
    result = run("render", TWO_ROOMS, "--plan", plan_file, "--trajectories", "20", "-o", picture)
    assert result.exit_code == 0, result.stderr
    svg = picture.read_text()
    stages = json.loads(plan_file.read_text())["stages"]
    for k, stage in enumerate(stages):  # one cone per stage and possible source, and the stage's label
        for source, _ in stage["moves"]:
            assert f'id="plan-cone-{k}-{source}"' in svg
        assert f'id="plan-stage-label-{k}"' in svg
    assert 'id="trajectories"' in svg and 'id="plan-start"' in svg and 'id="plan-goal"' in svg
    assert_one_line_error(run("render", TWO_ROOMS, "--plan", plan_file, "--from", "e0", "-o", picture), 2,
                          "--plan draws a plan and its own trajectories")
