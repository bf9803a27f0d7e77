"""The exact gate under a caller's time limit: a check that cannot finish in time stops and says so."""

from __future__ import annotations

import json
import time

import pytest

import solverplan as sp
from solverplan.certify.check import CheckStopped, check_certificate
from solverplan.certify.gate import STOPPED, checked_answer
from tests.cli_runs import run


def test_a_check_past_its_stop_time_gives_no_verdict():
    env = sp.load_environment("l_shape")
    cert = sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env)
    with pytest.raises(CheckStopped):
        check_certificate(cert, expected_rings=env.rings, stop=lambda: True)
    assert check_certificate(cert, expected_rings=env.rings, stop=lambda: False).valid


def test_an_answer_whose_check_is_stopped_leaves_not_proved_without_a_certificate():
    env = sp.load_environment("two_rooms")
    checked = checked_answer(lambda: sp.find_plan(env, "e0", "e4", objective="tolerance"), env=env, start="e0",
                             goal="e4", stop_at=time.monotonic() - 1)
    assert checked.stopped and checked.certificate is None and checked.unchecked == STOPPED
    assert checked.answer.found and not checked.answer.optimality.proved
    assert STOPPED in checked.answer.optimality.limits
    whole = checked_answer(lambda: sp.find_plan(env, "e0", "e4", objective="tolerance"), env=env, start="e0", goal="e4")
    assert not whole.stopped and whole.certificate is not None and whole.answer.optimality.proved


def test_the_command_line_stops_the_check_at_its_timeout(tmp_path, monkeypatch):
    """--timeout covers the exact check: here the check is made to stop at once (stop time already past)."""
    import solverplan.cli.bounce as bounce

    monkeypatch.setattr(bounce, "command_stop", lambda timeout: None if timeout is None else time.monotonic() - 1)
    cert = tmp_path / "c.json"
    result = run("plan", "two_rooms", "--from", "e0", "--to", "e4", "--objective", "tolerance", "--timeout", "60",
                 "--certificate", cert)
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["optimality"]["proved"] is False
    assert any("stopped by the time limit" in limit for limit in answer["optimality"]["limits"])
    assert not cert.exists()


def test_an_answer_that_found_nothing_is_not_marked_stopped():
    """A search cut by its timeout before any plan claims nothing: no 'check stopped' limit is added to it."""
    env = sp.load_environment("two_rooms")
    checked = checked_answer(lambda: sp.find_plan(env, "e0", "e4", objective="tolerance", timeout=1e-9), env=env,
                             start="e0", goal="e4", stop_at=time.monotonic() - 1)
    assert not checked.answer.found and not checked.stopped
    assert STOPPED not in checked.answer.optimality.limits
