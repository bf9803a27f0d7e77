"""`solverplan prove`: runs the symbolic proofs of solverplan.proofs, JSON or a text table, exit 1 if any fails.

The full run happens once (module fixture); the other tests select proofs with ``--only`` or replace
the discovered proofs with fakes (``solverplan.proofs._core.all_proofs``) to see a failure reach the exit code.
"""

from __future__ import annotations

import json

import pytest

import solverplan.proofs as proofs
import solverplan.proofs._core
from solverplan.proofs import ProofResult, Step
from tests.cli_runs import run



def _failing() -> ProofResult:
    return ProofResult("a fake result", (Step("true", True), Step("an identity that does not hold", False, "x ≠ 0")))


def _crashing() -> ProofResult:
    raise ZeroDivisionError("division by zero in a derivation")


@pytest.fixture(scope="module")
def full_run():
    return run("prove")


def test_prove_runs_every_proof_and_exits_0(full_run):
    assert full_run.exit_code == 0, full_run.stdout + full_run.stderr
    data = json.loads(full_run.stdout)
    assert set(data) == {"proofs", "passed"}
    assert data["passed"] is True
    assert [p["module"] for p in data["proofs"]] == sorted(proofs.all_proofs())
    assert {"lemma2_contraction", "theorem1_fixed_point", "cor3_cor4_uncertainty"} <= {p["module"] for p in data["proofs"]}
    for entry in data["proofs"]:
        assert set(entry) == {"result", "module", "status", "seconds", "steps", "errata"}
        assert entry["status"] == "passed"
        assert entry["seconds"] >= 0
        assert entry["steps"] and all(set(s) == {"claim", "holds", "detail"} and s["holds"] is True for s in entry["steps"])
        assert all(isinstance(e, str) and e for e in entry["errata"])


def test_prove_reports_the_errata_found(full_run):
    data = json.loads(full_run.stdout)
    errata = {p["module"]: p["errata"] for p in data["proofs"]}
    assert any("⌈log(ε/w)/log C⌉" in e for e in errata["cor3_cor4_uncertainty"])


def test_prove_only_selects_proofs_and_text_prints_a_table():
    result = run("prove", "--only", "prop2_safe_interval", "--only", "lemma2_contraction", "--format", "text")
    assert result.exit_code == 0, result.stdout + result.stderr
    out = result.stdout
    assert "proof" in out and "status" in out and "seconds" in out
    assert "prop2_safe_interval" in out and "lemma2_contraction" in out
    assert "theorem1_fixed_point" not in out
    assert "2 proofs, all passed" in out
    assert all(line == line.rstrip() for line in out.splitlines())


def test_prove_writes_json_to_a_file(tmp_path):
    target = tmp_path / "proofs.json"
    result = run("prove", "--only", "prop2_safe_interval", "-o", target)
    assert result.exit_code == 0, result.stderr
    assert result.stdout == ""
    data = json.loads(target.read_text(encoding="utf-8"))
    assert data["passed"] is True and [p["module"] for p in data["proofs"]] == ["prop2_safe_interval"]


def test_prove_unknown_name_is_bad_input():
    result = run("prove", "--only", "lemma99")
    assert result.exit_code == 2
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and len(lines[0]) < 200
    assert lines[0].startswith("error: unknown proof 'lemma99': did you mean lemma")
    other = run("prove", "--only", "0").stderr.splitlines()
    assert len(other) == 1 and other[0].startswith(f"error: unknown proof '0': {len(proofs.all_proofs())} proofs, e.g. ")


def test_prove_a_failing_proof_exits_1(monkeypatch):
    real = proofs._core.all_proofs()
    monkeypatch.setattr(
        proofs._core, "all_proofs", lambda: {"fake_failing": _failing, "prop2_safe_interval": real["prop2_safe_interval"]}
    )
    result = run("prove")
    assert result.exit_code == 1, result.stdout + result.stderr
    data = json.loads(result.stdout)
    assert data["passed"] is False
    status = {p["module"]: p["status"] for p in data["proofs"]}
    assert status == {"fake_failing": "failed", "prop2_safe_interval": "passed"}
    text = run("prove", "--format", "text")
    assert text.exit_code == 1
    assert "FAILED" in text.stdout and "1 failed" in text.stdout
    assert "an identity that does not hold [x ≠ 0]" in text.stdout


def test_prove_a_crashing_proof_is_a_failed_proof(monkeypatch):
    monkeypatch.setattr(proofs._core, "all_proofs", lambda: {"fake_crashing": _crashing})
    result = run("prove")
    assert result.exit_code == 1
    assert result.stderr == ""
    (entry,) = json.loads(result.stdout)["proofs"]
    assert entry["status"] == "failed"
    assert entry["steps"] == [
        {"claim": "prove() ran to the end", "holds": False, "detail": "ZeroDivisionError: division by zero in a derivation"}
    ]


def test_prove_with_no_proofs_does_not_pass(monkeypatch):
    monkeypatch.setattr(proofs._core, "all_proofs", lambda: {})
    result = run("prove")
    assert result.exit_code == 1
    assert json.loads(result.stdout) == {"proofs": [], "passed": False}
