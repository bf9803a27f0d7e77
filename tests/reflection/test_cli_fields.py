"""The ``fields`` command: the contract's fields answer (exact field names, defaults), the picture, bad input as one
line with exit code 2."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import solverplan as sp
from solverplan.cli import app

runner = CliRunner()
ARGS = ["fields", "serpentine", "--from", "3,2.25", "--to", "3,0.25"]


def test_fields_answers_with_the_contract_fields(tmp_path):
    picture = tmp_path / "fields.png"
    result = runner.invoke(app, [*ARGS, "--trials", "3", "--seed", "1", "--trajectories", "2", "--picture", str(picture)])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert list(answer)[:7] == ["kind", "status", "cells", "adjacency", "sequence", "reflection_cells", "scenarios"]
    assert list(answer)[-3:] == ["optimality", "stats", "environment"]
    assert all(set(c) == {"id", "polygon"} for c in answer["cells"]) and len(answer["cells"]) == 9
    assert answer["adjacency"] == [[0, 1], [0, 3], [1, 2], [2, 4], [3, 7], [5, 6], [5, 8], [6, 7]]
    assert answer["sequence"] == [4, 2, 1, 0, 3, 7, 6, 5, 8]
    # the four 45° corners pay together for the default inertial robot (rollouts); straight cells are recorded
    assert answer["reflection_cells"] == [2, 0, 7, 5] and answer["reflections"] == "payoff"
    assert {(r["cell"], r["stage"]) for r in answer["rejected_zones"]} == {(1, "candidate"), (3, "candidate"),
                                                                           (6, "candidate")}
    assert all(t["gain"] >= 0 for t in answer["rollouts"].values())
    assert list(answer["scenarios"]) == ["constrained", "unconstrained", "reflection"]  # --scenario all, the default
    for run in answer["scenarios"].values():
        assert list(run)[:6] == ["trials", "success", "time_mean", "time_var", "collisions_mean", "trajectories"]
        assert run["trials"] == 3 and run["success"] == 1.0 and len(run["trajectories"]) == 2
        assert run["trajectories"][0][0] == [3.0, 2.25]
    assert answer["model"]["kind"] == "inertial"  # --model inertial, the default
    assert answer["status"] == "found" and answer["flow_through"] is True
    assert answer["optimality"]["method"] == "exact-check" and answer["optimality"]["proved"] is True
    assert answer["environment"]["name"] == "serpentine"
    assert picture.stat().st_size > 10_000


def test_fields_matches_the_library():
    result = runner.invoke(app, [*ARGS, "--scenario", "reflection", "--model", "integrator", "--trials", "4"])
    assert result.exit_code == 0, result.output
    nav = sp.navigate_fields(sp.load_environment("serpentine"), (3, "2.25"), (3, "0.25"), scenarios=["reflection"],
                             model="integrator", trials=4)
    assert json.loads(result.stdout)["scenarios"] == nav.to_json()["scenarios"]


def test_fields_text_is_a_table_of_the_scenarios(tmp_path):
    target = tmp_path / "answer.txt"
    result = runner.invoke(app, [*ARGS, "--trials", "2", "--format", "text", "-o", str(target)])
    assert result.exit_code == 0 and result.stdout == ""
    text = target.read_text()
    assert "sequence 4 → 2 → 1 → 0 → 3 → 7 → 6 → 5 → 8" in text and "reflection cells: 2, 0, 7, 5;" in text
    assert all(name in text for name in ("constrained", "unconstrained", "reflection"))


def test_fields_with_arcs_verifies_them_by_sample():
    result = runner.invoke(app, [*ARGS, "--trials", "1", "--scenario", "constrained", "--arcs"])
    answer = json.loads(result.stdout)
    kinds = {f["cell"]: f["field"]["kind"] for f in answer["fields"]}
    assert [kinds[c] for c in (2, 0, 7, 5)] == ["arc"] * 4
    assert answer["optimality"]["method"] == "heuristic" and answer["status"] == "found"


@pytest.mark.parametrize(("args", "message"), [
    (["--from", "1,1.75", "--to", "3,0.25"], "error: start (1, 1.75) is not in the free space of serpentine"),
    (["--from", "3,2.25", "--to", "1,1"], "error: goal (1, 1) is on a wall: choose a point inside the free space"),
    (["--from", "3,2.25", "--to", "x,1"], "error: --to: 'x' is not a number"),
    (["--from", "3", "--to", "3,0.25"], "error: --from '3': expected X,Y (two numbers separated by a comma)"),
    (["--from", "3,2.25", "--to", "3,0.25", "--trials", "2", "--trajectories", "3"],
     "error: trajectories must be between 0 and the number of trials (2), got 3"),
    (["--from", "3,2.25", "--to", "3,0.25", "--picture", "f.pdf"], "error: "),
    (["--from", "3,2.25", "--to", "3,0.25", "--model", "wheeled"], "error: Invalid value for '--model'"),
    (["--from", "3,2.25", "--to", "3,0.25", "--goal-radius", "0"], "error: goal_radius must be positive, got 0.0"),
    (["--from", "3,2.25", "--to", "3,0.25", "--goal-radius", "inf"], "error: goal_radius must be finite, got inf"),
    (["--from", "3,2.25", "--to", "3,0.25", "--dead-band", "-1"], "error: dead_band must be non-negative, got -1.0"),
    (["--from", "3,2.25", "--to", "3,0.25", "--dead-band", "2"],
     "error: the fast speed must exceed the robot's dead band 2 (length/s), got 1.5"),
])
def test_fields_bad_input_is_one_line_and_exit_2(args, message):
    result = runner.invoke(app, ["fields", "serpentine", *args])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), lines
    assert result.stdout == ""


def test_issue26_robot_options_random_starts_and_the_exported_field(tmp_path):
    target = tmp_path / "field.json"
    result = runner.invoke(app, [*ARGS, "--trials", "3", "--accel", "4", "--restitution", "0.5", "--control-rate", "25",
                                 "--gain-line", "2", "--starts", "random", "--reflections", "all", "--export", str(target)])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    model = answer["model"]
    assert (model["accel"], model["restitution"], model["control_rate"], model["physics_rate"]) == (4.0, 0.5, 25.0, 400.0)
    assert answer["starts"] == "random" and answer["reflection_cells"] == [2, 0, 7, 5]
    assert answer["fields"][0]["field"]["gain_exact"] == "2"
    exported = json.loads(target.read_text())
    assert exported["sequence"] == answer["sequence"] and len(exported["cells"]) == 9
    reflecting = [c["id"] for c in exported["cells"] if c["reflection"] is not None]
    assert sorted(reflecting) == sorted(answer["reflection_cells"])
    for cell in exported["cells"]:  # the half-planes hold the cell's own vertices
        for x, y in cell["polygon"]:
            assert all(h["normal"][0] * x + h["normal"][1] * y >= h["offset"] - 1e-9 for h in cell["halfplanes"])


def test_a_control_rate_that_does_not_divide_the_physics_is_refused():
    result = runner.invoke(app, [*ARGS, "--control-rate", "33"])
    assert result.exit_code == 0  # 396 Hz physics: the nearest multiple is used


def test_fields_at_a_micro_scale_is_found_certified_and_verified(tmp_path):
    """The end-to-end reproducer (a star with a hole, coordinates ~10⁻³; not-found before the gains were relative
    to the room): found, its certificate verifies, the derived lengths are recorded; given lengths are kept."""
    from decimal import Decimal

    from tests.reflection.test_scale import F7_RINGS

    env = tmp_path / "f7.json"
    tiny = [[[float(Decimal(c).scaleb(-3)) for c in point] for point in ring] for ring in F7_RINGS]
    env.write_text(json.dumps({"outer": tiny[0], "holes": tiny[1:]}))
    answer, cert = tmp_path / "A.json", tmp_path / "C.json"
    args = ["fields", str(env), "--from", "-0.00006384,0.0000153", "--to", "-0.00061931,0.0001742", "--trials", "2",
            "--scenario", "reflection", "--seed", "74", "-o", str(answer), "--certificate", str(cert)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    data = json.loads(answer.read_text())
    assert data["status"] == "found" and data["scale"]["mean_width_exact"] == "0.0007483"
    assert data["model"]["goal_radius"] < 2e-4 and data["scenarios"]["reflection"]["time_min"] > 0
    assert runner.invoke(app, ["verify", str(cert)]).exit_code == 0
    result = runner.invoke(app, [*args, "--goal-radius", "0.00005", "--dead-band", "0.01", "--gain-line", "2000"])
    assert result.exit_code == 0, result.output
    data = json.loads(answer.read_text())
    assert (data["model"]["goal_radius"], data["model"]["dead_band"], data["gain_line_exact"]) == (5e-05, 0.01, "2000")
    assert data["scale"]["derived"] == ["gain_arc"]
