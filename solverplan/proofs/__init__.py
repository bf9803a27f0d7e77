"""Symbolic proofs (sympy) of the results solverplan relies on: one module per result.

The results are those of the paper the library implements, Nilles et al., "Visibility-based
planning for bouncing robots" (its lemmas, corollaries and theorems are cited by number). Each module
defines ``prove() -> ProofResult``: the formula under test is *derived* (from the geometry, not
retyped) and compared by simplification; each step says what it checks and whether it held. An
erratum (where the paper's text disagrees with what the proof yields) goes in the module docstring. ``solverplan prove`` runs them all; the test suite runs them too.
"""

from solverplan.proofs._core import ProofReport, ProofResult, Step, all_proofs, prove_all, run_all

__all__ = ["ProofReport", "ProofResult", "Step", "all_proofs", "prove_all", "run_all"]
