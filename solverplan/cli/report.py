"""``report``: a self-contained HTML page of an answer."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.errors import InputError
from solverplan.cli._app import EnvFormatOpt, FormatOpt, VerboseOpt, app, load_env
from solverplan.cli._errors import exit_codes, fail
from solverplan.cli._output import OutputFormat, emit


def _answer_option(kind: str, what: str) -> Any:
    return typer.Option(f"--{kind}", metavar=f"{kind.upper()}.json", help=what, show_default=False)


@app.command(name="report")
def report_command(
    out: Annotated[Path, typer.Option("-o", "--output", help="The HTML file to write (.html or .htm).", show_default=False)],
    env: Annotated[
        Path | None,
        typer.Argument(metavar="ENV", help="The environment the answer was made in (file or shipped model); none for --study.",
                       show_default=False),
    ] = None,
    plan_file: Annotated[Path | None, _answer_option("plan", "A plan or a Pareto front (from 'solverplan plan -o').")] = None,
    patrol_file: Annotated[Path | None, _answer_option("patrol", "A patrol cycle (from 'solverplan patrol -o').")] = None,
    funnel_file: Annotated[
        Path | None, _answer_option("funnel", "A funnel or localisation strategy (from 'solverplan funnel -o' or 'localize -o').")
    ] = None,
    cycle_file: Annotated[
        Path | None, _answer_option("cycle", "A limit cycle or constant controller (from 'solverplan cycle -o').")
    ] = None,
    study_file: Annotated[
        Path | None, _answer_option("study", "A study (from 'solverplan study ... -o', or the study's NAME.json); no ENV.")
    ] = None,
    certificate: Annotated[
        Path | None,
        typer.Option("--certificate", metavar="CERT.json", help="The answer's certificate: checked exactly now, its status shown.",
                     show_default=False),
    ] = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    verbose: VerboseOpt = 0,
) -> None:
    """A self-contained HTML report of an answer: the environment and the answer as SVG with hover details, the
    certificate checked exactly, the numbers, the command that reproduces it; prints {"written", "bytes", ...}."""
    from solverplan.render.html import html_report, load_answer, write_report

    with exit_codes(verbose):
        given = [(name, path) for name, path in (("plan", plan_file), ("patrol", patrol_file), ("funnel", funnel_file),
                                                 ("cycle", cycle_file), ("study", study_file)) if path is not None]
        if len(given) != 1:
            raise InputError("give exactly one answer: --plan, --patrol, --funnel, --cycle or --study")
        if out.suffix.lower() not in (".html", ".htm"):
            raise InputError(f"-o {out}: a report is an .html file: give -o REPORT.html")
        option, path = given[0]
        answer = load_answer(path, option=option)
        environment = load_env(env, env_format) if env is not None else None
        cert = None
        if certificate is not None:
            from solverplan.certify.schema import load_certificate

            cert = load_certificate(certificate)
        page = html_report(answer, environment, certificate=cert, certificate_path=str(certificate) if certificate else None,
                           env_label=str(env) if env is not None else None, output=str(out))
        saved = write_report(page, out)
        emit(saved, fmt, None)
    if page.certificate is not None and not page.certificate["valid"]:
        raise fail(f"certificate invalid: {page.certificate['failures'][0]} (the report {out} shows every failure)", 1)
