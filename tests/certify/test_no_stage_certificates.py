"""Plans and funnels whose start set lies in their goal set: a certificate of no stages, checked exactly.

A plan of 0 bounces is an answer like any other: ``--certificate`` writes it and ``verify`` checks the one claim it
makes (every start piece lies inside the goal set, exactly), whatever way the walls and sets are written."""

from __future__ import annotations

import json

import pytest

import solverplan as sp
from solverplan.certify.check import check_certificate
from solverplan.certify.schema import Certificate
from tests.cli_runs import run, write

SQUARE = {"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}
# the same square, its bottom wall written as two collinear edges and the ring started elsewhere
SQUARE_SPLIT = {"outer": [[4, 4], [0, 4], [0, 0], [1, 0], [4, 0]]}


@pytest.mark.parametrize("command,extra", [
    ("plan", []), ("plan", ["--objective", "tolerance"]), ("plan", ["--pareto"]),
    ("plan", ["--objective", "constant"]), ("funnel", []),
])
@pytest.mark.parametrize("env,start,goal", [
    (SQUARE, "e0:0.1:0.2", "e0"),
    (SQUARE, "e0:0.1:0.2", "e0:0:0.15,e0:0.15:1"),  # the goal written as two touching pieces
    (SQUARE_SPLIT, "e2:0.5:0.9", "e2,e3"),           # the start and goal across the split wall's pieces
])
def test_a_start_inside_the_goal_certifies_with_no_stages(tmp_path, command, extra, env, start, goal):
    env_path = write(tmp_path, "env.json", env)
    answer, cert = tmp_path / "A.json", tmp_path / "C.json"
    result = run(command, env_path, "--from", start, "--to", goal, *extra, "-o", answer, "--certificate", cert)
    assert result.exit_code == 0, result.stderr
    assert "no certificate" not in result.stderr
    data = json.loads(cert.read_text())
    assert data["stages"] == [] and data["claims"]["bounces"] == 0
    verified = run("verify", cert, "--env", env_path, "--from", start, "--to", goal)
    assert verified.exit_code == 0, verified.stderr
    assert "no bounce" in verified.stdout


def _stageless(start: list[dict], goal: list[dict], **claims: object) -> dict:
    data = {
        "schema": "solverplan-certificate", "version": 4, "kind": "plan", "producer": "test",
        "environment": {"name": "square", "rings": SQUARE["outer"] and [SQUARE["outer"]]},
        "segments": [], "start": start, "goal": goal, "stages": [],
        "claims": {"bounces": 0, "min_width": "3", "tolerance": "3/2", "objective": "fewest", **claims},
    }
    return data


@pytest.mark.parametrize("start,goal,claims,fragment", [
    ([{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 0, "t0": 0, "t1": "3/20"}], {}, "is not in the goal set"),
    ([{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 1, "t0": 0, "t1": 1}], {}, "is not in the goal set"),
    ([{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 0, "t0": 0, "t1": 1}], {"bounces": 1}, "claims.bounces"),
    ([{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 0, "t0": 0, "t1": 1}],
     {"min_width": "355/113", "tolerance": "355/226"}, "outside [0, π)"),  # 355/113 > π
    ([{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 0, "t0": 0, "t1": 1}], {"sum_width": "1"}, "no stages to add up"),
])
def test_a_false_stageless_certificate_is_rejected(start, goal, claims, fragment):
    report = check_certificate(Certificate.from_json(_stageless(start, goal, **claims)))
    assert not report.valid
    assert any(fragment in str(f) for f in report.failures), report.failures


def test_a_true_stageless_certificate_states_its_claim():
    report = check_certificate(Certificate.from_json(_stageless(
        [{"edge": 0, "t0": "1/10", "t1": "1/5"}], [{"edge": 0, "t0": 0, "t1": "3/20"}, {"edge": 0, "t0": "3/20", "t1": 1}])))
    assert report.valid, report.failures
    assert report.proved == ("the start set lies in the goal set: the robot is there with no bounce (a plan of 0 stages)",)


@pytest.mark.parametrize("kind", ["cycle", "localize"])
def test_other_kinds_of_no_stages_are_malformed(kind):
    data = _stageless([{"edge": 0, "t0": 0, "t1": 1}], [{"edge": 0, "t0": 0, "t1": 1}])
    data["kind"] = kind
    with pytest.raises(sp.InputError, match=f"a {kind} certificate has at least one stage"):
        Certificate.from_json(data)
