"""The symbolic proof of Lemma 4 and Theorem 5 passes, and fails when a formula under test is wrong."""

from __future__ import annotations

import sympy as sp

import solverplan.proofs.lemma4_range_views as lemma4
from solverplan.proofs import all_proofs


def test_the_proof_is_registered_and_passes():
    assert "lemma4_range_views" in all_proofs()
    assert lemma4.prove().passed


def test_a_wrong_grid_square_fails(monkeypatch):
    monkeypatch.setattr(lemma4, "grid_square_area", lambda R: 3 * R**2 / 4)   # diagonal √3R/2 read as a side
    failed = [s.claim for s in lemma4.prove().failed_steps]
    assert failed and all("square" in claim for claim in failed)


def test_a_wrong_ratio_bound_fails(monkeypatch):
    monkeypatch.setattr(lemma4, "ratio_bound_formula",
                        lambda A, P, R, c: 8 * sp.pi / 3 + sp.pi * R * P / A + c * R**2 / A)   # π dropped
    failed = [s.claim for s in lemma4.prove().failed_steps]
    assert any("8π/3" in claim for claim in failed) and any("library" in claim for claim in failed)
