"""`--timeout SECONDS` on plan, patrol, funnel and localize: bad values are one line and exit 2; a generous timeout
changes nothing; a timeout that expires answers (exit 0) with proved false and the timeout in its limits."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from tests.cli_runs import run

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"

COMMANDS = {
    "plan": ["plan", MODELS / "warehouse.json", "--from", "e0", "--to", "e2"],
    "pareto": ["plan", MODELS / "warehouse.json", "--from", "e0", "--to", "e2", "--pareto"],
    "patrol": ["patrol", MODELS / "warehouse.json", "--visit", "e0,e2"],
    "funnel": ["funnel", MODELS / "warehouse.json", "--from", "e0", "--to", "e2:0.4:0.6"],
    "localize": ["localize", MODELS / "warehouse.json", "--epsilon", "0.1"],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("bad", ["0", "-1", "nan", "inf", "1e400", "soon"])
def test_bad_timeouts_are_one_line_and_exit_2(command, bad):
    result = run(*COMMANDS[command], f"--timeout={bad}")
    assert result.exit_code == 2, (result.stdout, result.stderr)
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "timeout" in lines[0] and len(lines[0]) < 200


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_expired_timeout_answers_not_proved(command):
    """The warehouse's safe BVG alone takes longer than a millisecond: every search stops at once."""
    t0 = time.monotonic()
    result = run(*COMMANDS[command], "--timeout", "0.001")
    assert time.monotonic() - t0 < 60
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    opt = answer["optimality"]
    assert opt["proved"] is False and any(x.startswith("timeout 0.001 s reached after") for x in opt["limits"])
    assert answer["status"] == "not-found" and "timeout" in answer["reason"]


def test_a_generous_timeout_changes_nothing():
    args = ["plan", MODELS / "two_rooms.json", "--from", "e0", "--to", "e4", "--objective", "tolerance"]
    plain, timed = run(*args), run(*args, "--timeout", "600")
    assert plain.exit_code == timed.exit_code == 0
    a, b = json.loads(plain.stdout), json.loads(timed.stdout)
    a.pop("stats"), b.pop("stats")
    assert a == b and a["optimality"]["proved"] is True


def test_a_later_command_in_a_long_lived_process_gets_its_whole_timeout(monkeypatch):
    """The first command line of a process counts its start-up; a later one (a test run, a notebook) counts from its
    own start, not from the process's (a suite past 600 s made --timeout 600 expire at once)."""
    import time

    from solverplan.cli import _options

    monkeypatch.setattr(_options, "_STARTED", time.monotonic() - 10_000)
    monkeypatch.setattr(_options, "_COMMANDS", 1)
    timed = run("plan", MODELS / "two_rooms.json", "--from", "e0", "--to", "e4", "--objective", "tolerance",
                "--timeout", "600")
    assert timed.exit_code == 0 and json.loads(timed.stdout)["optimality"]["proved"] is True


def test_an_expired_timeout_in_text_names_the_limit():
    result = run(*COMMANDS["plan"], "--timeout", "0.001", "--format", "text")
    assert result.exit_code == 0, result.stderr
    assert "not proved" in result.stdout and "timeout 0.001 s" in result.stdout
