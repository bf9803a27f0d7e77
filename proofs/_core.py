"""The shared shape of a proof: named steps with a pass/fail each, and discovery of proof modules."""

from __future__ import annotations

import importlib
import pkgutil
import time
from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Step", "ProofResult", "all_proofs", "run_all"]


@dataclass(frozen=True, slots=True)
class Step:
    """One checked claim of a derivation: ``holds`` is the result of a sympy check, never assumed."""

    claim: str
    holds: bool
    detail: str = ""


@dataclass(frozen=True)
class ProofResult:
    """The outcome of one proof module: its result's name, the steps, and the time it took (s)."""

    result: str
    steps: tuple[Step, ...]
    seconds: float = 0.0
    module: str = ""
    errata: tuple[str, ...] = field(default=())

    @property
    def passed(self) -> bool:
        return bool(self.steps) and all(step.holds for step in self.steps)

    @property
    def failed_steps(self) -> tuple[Step, ...]:
        return tuple(step for step in self.steps if not step.holds)

    def to_json(self) -> dict:
        return {
            "result": self.result,
            "module": self.module,
            "status": "passed" if self.passed else "failed",
            "seconds": round(self.seconds, 3),
            "steps": [{"claim": s.claim, "holds": s.holds, "detail": s.detail} for s in self.steps],
            "errata": list(self.errata),
        }


def all_proofs() -> dict[str, Callable[[], ProofResult]]:
    """Every ``proofs.<module>.prove`` by module name (modules starting with ``_`` are helpers)."""
    import proofs

    found = {}
    for info in sorted(pkgutil.iter_modules(proofs.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"proofs.{info.name}")
        prove = getattr(module, "prove", None)
        if callable(prove):
            found[info.name] = prove
    return found


def run_all(names: list[str] | None = None) -> list[ProofResult]:
    """Run the named proofs (all by default), timing each."""
    results = []
    for name, prove in all_proofs().items():
        if names and name not in names:
            continue
        start = time.perf_counter()
        result = prove()
        elapsed = time.perf_counter() - start
        results.append(
            ProofResult(result.result, result.steps, elapsed, name, result.errata)
        )
    return results
