"""`solverplan verify CERT.json`: exit 0 valid, 1 invalid (first failing claim on one stderr line, all
failures in the report on stdout), 2 malformed (one line, nothing on stdout)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from solverplan.certify.schema import EXAMPLE
from tests.certify import cases
from tests.certify.cases import MODELS, tampered
from tests.cli_runs import run, write, assert_one_line_error



# ---------------------------------------------------------------------- valid
def test_valid_certificate_exits_0_with_a_json_report(tmp_path):
    result = run("verify", write(tmp_path, "c.json", cases.square_adjacent()))
    assert result.exit_code == 0, result.stderr
    assert result.stderr == ""
    report = json.loads(result.stdout)
    assert report["valid"] is True and report["failures"] == [] and report["kind"] == "plan"
    assert report["checked"]["corner_rays"] == 8 and report["checked"]["edge_tests"] == 8


def test_valid_certificate_text_report(tmp_path):
    result = run("verify", write(tmp_path, "c.json", cases.l_shape_plan()), "--format", "text")
    assert result.exit_code == 0
    assert result.stdout.splitlines()[0] == "certificate (plan): VALID"


def test_the_schema_example_verifies(tmp_path):
    assert run("verify", write(tmp_path, "example.json", EXAMPLE)).exit_code == 0


def test_report_to_a_file(tmp_path):
    out = tmp_path / "report.json"
    result = run("verify", write(tmp_path, "c.json", cases.square_cycle()), "-o", out)
    assert result.exit_code == 0 and result.stdout == ""
    assert json.loads(out.read_text())["kind"] == "cycle"


def test_environment_and_query_checks(tmp_path):
    cert = write(tmp_path, "c.json", cases.square_up())
    square, ell = MODELS / "square.json", MODELS / "l_shape.json"
    assert run("verify", cert, "--env", square, "--from", "e0:0.1:0.9", "--to", "e2").exit_code == 0
    line = assert_one_line_error(run("verify", cert, "--env", ell), 1, "certificate invalid: environment.rings[0]", stdout_empty=False)
    assert "the given environment's ring has 6" in line
    assert_one_line_error(run("verify", cert, "--env", square, "--from", "e0"), 1, "start: is e0:[0.1, 0.9], but the query's start set is e0:[0, 1]", stdout_empty=False)
    assert_one_line_error(run("verify", cert, "--from", "e0"), 2, "give it with --env")
    assert_one_line_error(run("verify", cert, "--env", square, "--to", "e9"), 2, "unknown edge e9")


# ---------------------------------------------------------------------- invalid: exit 1
def test_invalid_certificate_exits_1_naming_the_first_failing_claim(tmp_path):
    data = tampered(cases.square_up(), "stages.0.moves.0.d_hi", [-1, 2])
    result = run("verify", write(tmp_path, "bad.json", data))
    line = assert_one_line_error(result, 1, "certificate invalid: stages[0].moves[0].d_hi: corner ray from (1, 0)", stdout_empty=False)
    report = json.loads(result.stdout)
    assert report["valid"] is False
    assert report["failures"][0]["claim"] == "stages[0].moves[0].d_hi"
    more = len(report["failures"]) - 1
    assert more >= 1 and line.endswith(f"(and {more} more failure{'s' if more > 1 else ''} in the report)")


def test_swept_region_through_the_hole_exits_1(tmp_path):
    result = run("verify", write(tmp_path, "hole.json", cases.one_hole_through_the_hole()))
    assert_one_line_error(result, 1, "stages[0].moves[0].swept: edge 4 runs through the swept region", stdout_empty=False)


def test_single_failure_has_no_more_suffix(tmp_path):
    data = tampered(cases.square_cycle(), "cycle.fixed_point", "1/12")
    line = assert_one_line_error(run("verify", write(tmp_path, "c.json", data)), 1, "cycle.fixed_point: claims 1/12", stdout_empty=False)
    assert "more failure" not in line


# ---------------------------------------------------------------------- malformed: exit 2
@pytest.mark.parametrize(
    "mutate,fragment",
    [
        (lambda d: d.update(schema="something-else"), "not a solverplan certificate: schema is 'something-else'"),
        (lambda d: d.update(version=5), "certificate version 5 is not supported (this solverplan reads versions 1 to 4)"),
        (lambda d: d["claims"].update(min_width="abc"), "claims.min_width: 'abc' is not a number"),
        (lambda d: d["claims"].update(tolerance="1/0"), "claims.tolerance: '1/0' divides by zero"),
        (lambda d: d["stages"][0]["moves"][0].update(d_lo=[1]), "stages[0].moves[0].d_lo: expected a pair [x, y], got [1]"),
        (lambda d: d["stages"][0]["moves"][0].pop("target"), "stages[0].moves[0]: missing field 'target'"),
        (lambda d: d["stages"][0]["moves"][0].update(colour="red"), "stages[0].moves[0]: unknown field 'colour'"),
        (lambda d: d.update(kind="tour"), "kind: 'tour' is not one of plan, cycle, funnel, localize"),
        (lambda d: d.update(kind="localize", stages=[]), "stages: a localize certificate has at least one stage"),
        (lambda d: d.update(kind="funnel"), "stages[0].positions: a funnel certificate claims the positions after every stage"),
    ],
)
def test_malformed_certificate_exits_2_with_one_line(tmp_path, mutate, fragment):
    data = cases.square_up()
    mutate(data)
    assert_one_line_error(run("verify", write(tmp_path, "m.json", data)), 2, fragment)


def test_not_json_and_missing_file_exit_2(tmp_path):
    assert_one_line_error(run("verify", write(tmp_path, "t.json", '{"schema": ')), 2, "not valid JSON")
    assert_one_line_error(run("verify", tmp_path / "none.json"), 2, "none.json: no such file")
    assert_one_line_error(run("verify", write(tmp_path, "n.json", '{"x": NaN}')), 2, "non-finite number NaN")


def test_json_decimals_are_read_exactly_not_as_binary_floats(tmp_path):
    text = json.dumps(cases.square_up()).replace('"0.1"', "0.1")  # a JSON number: read as the decimal 1/10
    assert '"t0": 0.1' in text
    assert run("verify", write(tmp_path, "d.json", text)).exit_code == 0


def test_installed_script_verifies(tmp_path):
    """One end-to-end run of the real console script (the exit codes of docs/contract.md)."""
    script = Path(sys.executable).with_name("solverplan")
    if not script.exists():
        pytest.skip("console script not installed in this environment")
    ok = subprocess.run([str(script), "verify", str(write(tmp_path, "c.json", cases.one_hole_plan()))], capture_output=True, text=True)
    assert ok.returncode == 0 and json.loads(ok.stdout)["valid"] is True
    bad = subprocess.run([str(script), "verify", str(write(tmp_path, "b.json", cases.l_shape_around_the_corner()))], capture_output=True, text=True)
    assert bad.returncode == 1 and bad.stderr.count("\n") == 1 and "stages[0].moves[0].swept" in bad.stderr


# ---------------------------------------------------------------------- --certificate of the planning commands
def test_plan_certificate_that_fails_the_check_exits_1_and_writes_nothing(tmp_path, monkeypatch):
    """The check before the answer leaves (solverplan.certify.gate): a plan whose certificate the exact checker
    refuses, even when computed again with fresh graphs, is neither printed nor written (exit 1, one line)."""
    from dataclasses import replace

    from solverplan.certify import build

    real = build.certificate

    def inflated(answer, **kwargs):
        cert = real(answer, **kwargs)
        return replace(cert, claims=replace(cert.claims, bounces=cert.claims.bounces + 1))

    monkeypatch.setattr(build, "certificate", inflated)
    cert = tmp_path / "plan.cert.json"
    result = run("plan", MODELS / "two_rooms.json", "--from", "e0", "--to", "e4", "--certificate", cert)
    assert_one_line_error(result, 1, "error: the plan failed its exact check, even with freshly built graphs: claims.bounces: claims ")
    assert not cert.exists() and list(tmp_path.iterdir()) == []


def test_plan_certificate_is_written_and_verifies_against_the_query(tmp_path):
    cert = tmp_path / "plan.cert.json"
    model = MODELS / "two_rooms.json"
    result = run("plan", model, "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "--objective", "tolerance", "--certificate", cert)
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["status"] == "found"
    checked = run("verify", cert, "--env", model, "--from", "e0:0.2:0.8", "--to", "e4:0.5:1")
    assert checked.exit_code == 0 and json.loads(checked.stdout)["valid"] is True


def test_pareto_certificate_is_of_the_most_tolerant_plan(tmp_path):
    cert = tmp_path / "front.cert.json"
    result = run("plan", MODELS / "two_rooms.json", "--from", "e0", "--to", "e4", "--pareto", "--certificate", cert)
    assert result.exit_code == 0, result.stderr
    front = json.loads(result.stdout)
    widest = max(point["min_width"] for point in front["points"])
    report = json.loads(run("verify", cert).stdout)
    assert report["valid"] and report["kind"] == "plan"
    written = json.loads(cert.read_text())
    assert abs(float(written["claims"]["min_width"]) - widest) < 1e-9


# ---------------------------------------------------------------------- what was certified
def test_a_cut_start_set_stays_valid_and_the_report_shows_the_small_set(tmp_path):
    """A certificate whose start set was cut to a tenth is a true statement about a smaller query: valid,
    and the report names the smaller set (so an unpinned verify does not hide it); pinned, it fails."""
    ell = MODELS / "l_shape.json"
    cert = tmp_path / "plan.cert.json"
    made = run("plan", ell, "--from", "e0", "--to", "e3", "--certificate", cert)
    assert made.exit_code == 0, made.stderr
    full = json.loads(run("verify", cert).stdout)
    assert full["start"] == {"set": "e0", "length": "10", "length_exact": True}
    data = json.loads(cert.read_text())
    assert data["start"] == [{"edge": 0, "t0": 0, "t1": 1}]
    data["start"] = [{"edge": 0, "t0": "0.45", "t1": "0.55"}]  # a tenth of edge 0
    assert "bound" in data  # its fewest-bounces bound is about the whole start set: with a cut start it fails
    assert_one_line_error(run("verify", write(tmp_path, "cut_bound.json", data)), 1,
                          "bound.beliefs[0].segments: the start belief's segments make up e0:[0, 1], but the start set "
                          "is e0:[0.45, 0.55]", stdout_empty=False)
    del data["bound"]
    cut = write(tmp_path, "cut.json", data)
    result = run("verify", cut)
    assert result.exit_code == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["valid"] is True
    assert report["start"] == {"set": "e0:0.45:0.55", "length": "1", "length_exact": True}
    assert report["goal"]["set"] == "e3" and report["environment"]["name"] == "l_shape"
    text = run("verify", cut, "--format", "text").stdout.splitlines()
    assert text[0] == "certificate (plan): VALID" and "start: e0:0.45:0.55 (length 1)" in text
    assert_one_line_error(run("verify", cut, "--env", ell, "--from", "e0", "--to", "e3"), 1,
                          "start: is e0:[0.45, 0.55], but the query's start set is e0:[0, 1]", stdout_empty=False)


def test_the_report_names_the_environment_by_the_hash_of_the_answers(tmp_path):
    ell = MODELS / "l_shape.json"
    cert = tmp_path / "plan.cert.json"
    answer = json.loads(run("plan", ell, "--from", "e0", "--to", "e3", "--certificate", cert).stdout)
    env = json.loads(run("verify", cert).stdout)["environment"]
    assert env == {"name": "l_shape", "sha256": answer["environment"]["sha256"], "vertices": 6, "edges": 6, "holes": 0}
    line = run("verify", cert, "--format", "text").stdout.splitlines()[1]
    assert line == f"environment: 'l_shape', sha256 {env['sha256']}, 6 vertices, 6 edges, 0 holes"


def test_cycle_claims_are_printed(tmp_path):
    result = run("verify", write(tmp_path, "c.json", cases.square_cycle()), "--format", "text")
    lines = result.stdout.splitlines()
    assert "goal: none (a cycle: the cycle is the goal)" in lines
    cycle = next(line for line in lines if line.startswith("cycle: "))
    assert "fixed point 1/11" in cycle and "contraction 0.0081 < 1" in cycle and "visits [0, 1, 2, 3]" in cycle


def test_a_certificate_with_a_number_of_too_many_digits_is_bad_input(tmp_path):
    """Certificates may carry integers past Python's 4,300-digit guard (exact products along long cycles), up to
    200,000 digits; longer is a malformed file (exit 2, one line), and a long but readable version is refused as a
    version."""
    from typer.testing import CliRunner

    from solverplan.cli import app

    path = tmp_path / "long.json"
    path.write_text('{"schema": "solverplan-certificate", "version": ' + "1" * 200_002 + "}")
    result = CliRunner().invoke(app, ["verify", str(path)])
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr == f"error: {path}: certificate: an integer of 200,002 digits (at most 200,000 are read)\n"
    path.write_text('{"schema": "solverplan-certificate", "version": ' + "1" * 5000 + "}")
    result = CliRunner().invoke(app, ["verify", str(path)])
    # the line's length without the path, which depends on where pytest puts tmp_path (longer under xdist)
    assert result.exit_code == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert len(result.stderr.replace(str(path), "")) < 160, result.stderr


# ---------------------------------------------------------------------- negative answers (issue #22)
def test_issue_22_an_infeasible_plan_writes_a_certificate_that_verify_proves(tmp_path):
    cert = tmp_path / "none.cert.json"
    made = run("plan", "comb", "--from", "e3:0.15:1,e4:0:0.25", "--to", "e3:0.4:1,e4:0:0.05", "--pareto",
               "--max-bounces", "4", "--certificate", cert)
    assert made.exit_code == 0 and made.stderr == "", made.stderr
    assert json.loads(made.stdout)["status"] == "infeasible"
    data = json.loads(cert.read_text())
    assert data["version"] == 4 and data["kind"] == "infeasible" and data["stages"] == []
    assert data["bound"]["budget"] == 4 and data["bound"]["heading_margin"] == "0.001"
    report = json.loads(run("verify", cert).stdout)
    assert report["valid"] is True and report["kind"] == "infeasible"
    assert report["proved"][0].startswith("no plan with at most 4 stages takes the start set to the goal set")
    text = run("verify", cert, "--format", "text")
    assert text.exit_code == 0
    lines = text.stdout.splitlines()
    assert lines[0] == "certificate (infeasible): VALID"
    assert any(line.startswith("bound: no plan with at most 4 stages, every interval wider than 0 rad") for line in lines)
    assert any(line.startswith("proved: no plan with at most 4 stages") for line in lines)
    data["bound"]["beliefs"] = data["bound"]["beliefs"][:1]  # the start belief alone is not closed
    assert_one_line_error(run("verify", write(tmp_path, "cut.json", data)), 1, "the invariant is not closed",
                          stdout_empty=False)


def test_issue_22_a_fewest_plan_certificate_proves_no_plan_has_fewer_bounces(tmp_path):
    cert = tmp_path / "plan.cert.json"
    made = run("plan", "two_rooms", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "--certificate", cert)
    assert made.exit_code == 0, made.stderr
    bounces = json.loads(made.stdout)["bounces"]
    report = json.loads(run("verify", cert).stdout)
    assert report["valid"] and report["proved"][-1] == (f"hence every such plan has at least {bounces} bounces: this "
                                                        f"plan's {bounces} is the fewest")
    assert not any("not re-derived" in item for item in report["not_checked"])


def test_issue_22_an_infeasible_answer_that_holds_only_within_the_margins_writes_nothing(tmp_path):
    cert = tmp_path / "none.cert.json"
    made = run("plan", "square", "--from", "e3:0.5:0.75", "--to", "e0:0.1:0.6", "--max-bounces", "2",
               "--certificate", cert)
    assert made.exit_code == 0
    if json.loads(made.stdout)["status"] == "infeasible":  # the planner's start segment is the whole edge e3
        assert made.stderr.startswith(f"warning: no certificate written to {cert}: infeasible within 2 bounces only "
                                      "within the planner's corner clearance")
        assert not cert.exists()
