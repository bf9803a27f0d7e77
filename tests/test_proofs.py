"""Every symbolic proof in proofs/ passes (the "lemmas in CI" half of the product)."""

import pytest

from proofs import all_proofs, run_all


def test_there_are_proofs_to_run():
    assert "prop2_safe_interval" in all_proofs()


@pytest.mark.parametrize("name", sorted(all_proofs()))
def test_proof_passes(name):
    (result,) = run_all([name])
    assert result.passed, f"{name}: failed steps {[s.claim for s in result.failed_steps]}"
    assert result.to_json()["status"] == "passed"
