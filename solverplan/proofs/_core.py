"""The shared shape of a proof: named steps with a pass/fail each, discovery of proof modules, the report.

:func:`prove_all` is what ``solverplan prove`` answers: a :class:`ProofReport` with ``to_json()``
(``{"proofs": [...], "passed": bool}``) and ``to_text(width=)`` (a table: proof, result, status, steps,
seconds; then any failed steps and the errata the proofs recorded).
"""

from __future__ import annotations

import importlib
import io
import pkgutil
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

__all__ = ["Step", "ProofResult", "ProofReport", "all_proofs", "run_all", "prove_all"]


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
    """Every ``solverplan.proofs.<module>.prove`` by module name (modules starting with ``_`` are helpers)."""
    import solverplan.proofs as package

    found = {}
    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{package.__name__}.{info.name}")
        prove = getattr(module, "prove", None)
        if callable(prove):
            found[info.name] = prove
    return found


def run_all(names: Sequence[str] | None = None) -> list[ProofResult]:
    """Run the named proofs (all by default), timing each.

    A proof that raises does not stop the others: it is reported as failed, with one step naming
    the exception.
    """
    results = []
    for name, prove in all_proofs().items():
        if names and name not in names:
            continue
        start = time.perf_counter()
        try:
            result = prove()
        except Exception as exc:  # a crashing proof is a failing proof, not a crashing command
            result = ProofResult(name, (Step("prove() ran to the end", False, f"{type(exc).__name__}: {exc}"),))
        elapsed = time.perf_counter() - start
        results.append(
            ProofResult(result.result, result.steps, elapsed, name, result.errata)
        )
    return results


@dataclass(frozen=True)
class ProofReport:
    """The outcome of a run of proofs: what ``solverplan prove`` prints."""

    proofs: tuple[ProofResult, ...]

    @property
    def passed(self) -> bool:
        """True iff there was at least one proof and every proof passed."""
        return bool(self.proofs) and all(p.passed for p in self.proofs)

    @property
    def seconds(self) -> float:
        return sum(p.seconds for p in self.proofs)

    def to_json(self) -> dict:
        return {"proofs": [p.to_json() for p in self.proofs], "passed": self.passed}

    def to_text(self, *, width: int = 100) -> str:
        """A table (proof, result, status, steps, seconds), then failed steps and recorded errata."""
        from rich import box
        from rich.console import Console
        from rich.table import Table

        buffer = io.StringIO()
        console = Console(file=buffer, width=width, color_system=None, force_terminal=False, highlight=False)
        table = Table(box=box.SIMPLE)
        table.add_column("proof")
        table.add_column("result")
        table.add_column("status")
        table.add_column("steps", justify="right")
        table.add_column("seconds", justify="right")
        for p in self.proofs:
            held = sum(step.holds for step in p.steps)
            table.add_row(p.module, p.result, "passed" if p.passed else "FAILED", f"{held}/{len(p.steps)}", f"{p.seconds:.2f}")
        console.print(table)
        failed = [p for p in self.proofs if not p.passed]
        verdict = "all passed" if self.passed else f"{len(failed)} failed"
        console.print(f"{len(self.proofs)} proofs, {verdict}, {self.seconds:.2f} s")
        for p in failed:
            console.print(f"\n{p.module}: failed steps")
            console.print(_bullets([s.claim + (f" [{s.detail}]" if s.detail else "") for s in p.failed_steps] or ["(no steps)"]))
        errata = [f"{p.module}: {e}" for p in self.proofs for e in p.errata]
        if errata:
            console.print("\nerrata recorded by the proofs (the paper's text vs what the proof yields)")
            console.print(_bullets(errata))
        return "".join(line.rstrip() + "\n" for line in buffer.getvalue().splitlines())


def _bullets(lines: list[str]):
    """A borderless two-column grid so that wrapped lines keep their indent."""
    from rich.table import Table
    from rich.text import Text

    grid = Table.grid(padding=(0, 1))
    grid.add_column(no_wrap=True)
    grid.add_column()
    for line in lines:
        grid.add_row("  -", Text(line))
    return grid


def prove_all(names: Sequence[str] | None = None) -> ProofReport:
    """Run the named proofs (all by default) into a :class:`ProofReport`.

    Raises :class:`solverplan.errors.InputError` naming an unknown proof.
    """
    if names:
        known = all_proofs()
        unknown = [name for name in names if name not in known]
        if unknown:
            import difflib

            from solverplan.errors import InputError
            from solverplan.limits import quote

            # The full list of names would make a line too long to read: name the closest one, or where to look.
            names_known = list(known)
            # Users type the lemma's short name ('lemma2'): match it against each module's first word too.
            first_words = {name.split("_")[0]: name for name in names_known}
            close = difflib.get_close_matches(str(unknown[0]), names_known, n=1) or [
                first_words[word] for word in difflib.get_close_matches(str(unknown[0]), list(first_words), n=1)]
            hint = (f"did you mean {close[0]}?" if close else
                    f"{len(names_known)} proofs, e.g. {names_known[0]}; 'solverplan prove' runs and lists them all")
            raise InputError(f"unknown proof {quote(str(unknown[0]))}: {hint}")
    return ProofReport(tuple(run_all(names)))
