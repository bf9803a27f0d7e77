"""--certificate on rooms, explore, wallfollow and fields, and `verify` of every model certificate (issue #23)."""

from __future__ import annotations

import json

import pytest

from tests.cli_runs import run



COMMANDS = {
    "rooms": ("rooms", "three_chambers"),
    "explore": ("explore", "two_holes", "--start", "1,1"),
    "explore-range": ("explore", "one_hole", "--start", "1,1", "--range", "4"),
    "cut-ordering": ("wallfollow", "star"),
    "learned": ("wallfollow", "star", "--learn"),
    "pursuit": ("wallfollow", "star", "--pursuit"),
    "fields": ("fields", "two_holes", "--from", "1,1", "--to", "9,9", "--trials", "1", "--scenario", "constrained"),
}
KINDS = {"rooms": "rooms", "explore": "exploration", "explore-range": "exploration", "cut-ordering": "cut-ordering",
         "learned": "cut-ordering", "pursuit": "pursuit", "fields": "fields"}
TAMPER = {  # one claim of each kind, made false
    "rooms": lambda c: c["doors"][0].update(length=c["doors"][0]["length"] + 1),
    "explore": lambda c: c.update(bound=c["bound"] - 1),
    "explore-range": lambda c: c.update(reflex=c["reflex"] + 1),
    "cut-ordering": lambda c: c["ordering"].reverse(),
    "learned": lambda c: c["cuts"][0].update(edge=c["cuts"][0]["edge"] + 1),
    "pursuit": lambda c: c.update(cleared_after=0),
    "fields": lambda c: c.update(area=str(float(c["area"]) + 1) if isinstance(c["area"], str) else c["area"] + 1),
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_certificate_of_every_model_verifies_and_a_tampered_claim_fails(name, tmp_path):
    answer, cert = tmp_path / "A.json", tmp_path / "C.json"
    made = run(*COMMANDS[name], "-o", answer, "--certificate", cert)
    assert made.exit_code == 0, made.stderr
    assert json.loads(answer.read_text())["status"] == "found"
    data = json.loads(cert.read_text())
    assert data["version"] == 4 and data["kind"] == KINDS[name]
    verified = run("verify", cert, "--format", "text")
    assert verified.exit_code == 0, verified.stderr
    assert "VALID" in verified.stdout and "scope: " in verified.stdout and "proved: " in verified.stdout
    pinned = run("verify", cert, "--env", COMMANDS[name][1])
    assert pinned.exit_code == 0 and json.loads(pinned.stdout)["valid"] is True
    TAMPER[name](data["claims"])
    cert.write_text(json.dumps(data))
    rejected = run("verify", cert)
    assert rejected.exit_code == 1 and rejected.stderr.startswith("error: certificate invalid: claims."), rejected.stderr
    assert len(rejected.stderr.splitlines()) == 1


def test_a_certificate_of_another_environment_is_refused(tmp_path):
    cert = tmp_path / "C.json"
    assert run("wallfollow", "star", "--certificate", cert).exit_code == 0
    result = run("verify", cert, "--env", "square")
    assert result.exit_code == 1 and "environment" in result.stderr


@pytest.mark.parametrize("args", [("rooms", "three_chambers", "--simulate", "--from", "0", "--to", "2"),
                                  ("wallfollow", "star", "--count")])
def test_statistics_have_no_certificate(args, tmp_path):
    cert = tmp_path / "C.json"
    result = run(*args, "--certificate", cert)
    assert result.exit_code == 2 and len(result.stderr.splitlines()) == 1 and not cert.exists(), result.stderr
