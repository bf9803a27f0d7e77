"""Every symbolic proof in solverplan.proofs passes (the "lemmas in CI" half of the product)."""

import pytest
import sympy as sp

import solverplan.proofs.cor3_cor4_uncertainty as cor34
import solverplan.proofs.lemma2_contraction as lemma2
import solverplan.proofs.theorem1_fixed_point as theorem1
from solverplan.proofs import all_proofs, run_all


def test_there_are_proofs_to_run():
    assert "prop2_safe_interval" in all_proofs()


@pytest.mark.parametrize("name", sorted(all_proofs()))
def test_proof_passes(name):
    (result,) = run_all([name])
    assert result.passed, f"{name}: failed steps {[s.claim for s in result.failed_steps]}"
    assert result.to_json()["status"] == "passed"


# ---------------------------------------------------------------------- the proofs can fail
# Each formula under test is replaced by a plausible wrong one (a sign, a factor, an index): the proof
# that checks it must then fail. A proof that still passes would be checking nothing.


def test_lemma2_fails_for_a_swapped_coefficient(monkeypatch):
    def swapped(kind, theta, phi):  # right and left exchanged
        return sp.sin(theta) / sp.sin(theta - phi if kind == "right" else theta + phi)

    monkeypatch.setattr(lemma2, "design_coefficient", swapped)
    assert not lemma2.prove().passed


def test_lemma2_fails_for_a_wrong_threshold(monkeypatch):
    monkeypatch.setattr(lemma2, "design_threshold", lambda kind, phi: sp.pi / 2 - phi if kind == "right" else sp.pi / 2 + phi)
    result = lemma2.prove()
    assert not result.passed
    assert all("threshold" in s.claim or "C(θ*, φ) = 1" in s.claim for s in result.failed_steps)


def test_theorem1_fails_for_a_wrong_sign_exponent(monkeypatch):
    def wrong(cs, ells):  # (−1)^{n−j} instead of (−1)^{n−1−j}
        n = len(cs)
        return sp.Add(*[(-1) ** (n - j) * ells[j] * sp.Mul(*cs[j:]) for j in range(n)])

    monkeypatch.setattr(theorem1, "design_constant", wrong)
    failed = {s.claim for s in theorem1.prove().failed_steps}
    assert any(c.startswith("n = 3..8: composing") for c in failed)


def test_cor4_example_fails_for_the_unclamped_tight_count(monkeypatch):
    monkeypatch.setattr(cor34, "cycles_tight", lambda c, w, e: sp.ceiling(sp.log(e / w) / sp.log(c)))
    failed = [s.claim for s in cor34.prove().failed_steps]
    assert failed and all("ε = 100ℓ" in c for c in failed)
