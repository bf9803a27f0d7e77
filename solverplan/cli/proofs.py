"""Commands that check: ``prove`` (the symbolic proofs) and ``verify`` (a certificate, exactly)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.errors import InputError
from solverplan.cli._app import app
from solverplan.cli._errors import invalid
from solverplan.cli._options import CommonOptions, common_options


@app.command(name="prove")
@common_options("fmt", "out", "verbose")
def prove_command(
    only: Annotated[list[str] | None, typer.Option("--only", metavar="NAME", help="Run only this proof module (repeatable), e.g. lemma2_contraction.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Run the symbolic proofs of solverplan.proofs (sympy): a table of results (proof, status, seconds); exit 1 if any fails."""
    with common.exit_codes():
        from solverplan.proofs import prove_all  # sympy-heavy: imported only by this command

        report = prove_all(only or None)
        common.emit(report)
    if not report.passed:
        raise typer.Exit(1)


@app.command(name="verify")
@common_options("env_format", "fmt", "out", "verbose")
def verify_command(
    cert: Annotated[Path, typer.Argument(metavar="CERT.json", help="The certificate file to check.", show_default=False)],
    env: Annotated[Path | None, typer.Option("--env", metavar="ENV", help="Also require the certificate's environment to be exactly this environment file (or shipped model).", show_default=False)] = None,
    start: Annotated[str | None, typer.Option("--from", metavar="SET", help="Also require the certificate's start set to be exactly SET (needs --env).", show_default=False)] = None,
    goal: Annotated[str | None, typer.Option("--to", metavar="SET", help="Also require the certificate's goal set to be exactly SET (needs --env).", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Check a certificate in exact rational arithmetic: exit 0 valid, 1 invalid (the first failing claim on stderr), 2 malformed."""
    from solverplan.certify.check import check_certificate
    from solverplan.certify.schema import MODEL_KINDS, load_certificate

    with common.exit_codes():
        if (start is not None or goal is not None) and env is None:
            raise InputError("--from and --to name edges of an environment: give it with --env")
        certificate = load_certificate(cert)
        if (start is not None or goal is not None) and certificate.kind in MODEL_KINDS:
            raise InputError(f"--from and --to pin a plan's start and goal sets: this {certificate.kind} certificate has none")
        environment = common.load(env) if env is not None else None
        query: dict[str, Any] = {}
        if environment is not None:
            query["expected_rings"] = environment.rings
            for key, text in (("expected_start", start), ("expected_goal", goal)):
                if text is not None:
                    query[key] = [(p.edge, p.t0, p.t1) for p in environment.boundary_set(text).pieces]
        report = check_certificate(certificate, **query)
        common.emit(report)
    if not report.valid:
        raise invalid("certificate", report.failures)
