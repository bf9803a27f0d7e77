"""``report``: a self-contained HTML page of an answer."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.errors import InputError
from solverplan.cli._app import app
from solverplan.cli._errors import fail
from solverplan.cli._options import CommonOptions, common_options
from solverplan.cli._output import emit


def _answer_option(kind: str, what: str) -> Any:
    return typer.Option(f"--{kind}", metavar=f"{kind.upper()}.json", help=what, show_default=False)


@app.command(name="report")
@common_options("env_format", "fmt", "verbose")
def report_command(
    file: Annotated[Path | None, typer.Argument(metavar="ANSWER.json", help="The answer (any command's -o file); in the older form 'report ENV --plan P.json', the environment.", show_default=False)] = None,
    out: Annotated[Path | None, typer.Option("-o", "--output", help="The HTML file to write (.html or .htm; default: the answer's name with .html).", show_default=False)] = None,
    env: Annotated[Path | None, typer.Option("--env", metavar="ENV", help="The environment the answer was made in (default: the certificate's, or the shipped model the answer names).", show_default=False)] = None,
    plan_file: Annotated[Path | None, _answer_option("plan", "Older form: a plan or a Pareto front, with ENV as the argument.")] = None,
    patrol_file: Annotated[Path | None, _answer_option("patrol", "Older form: a patrol cycle.")] = None,
    funnel_file: Annotated[Path | None, _answer_option("funnel", "Older form: a funnel or localisation strategy.")] = None,
    cycle_file: Annotated[Path | None, _answer_option("cycle", "Older form: a limit cycle or constant controller.")] = None,
    study_file: Annotated[Path | None, _answer_option("study", "Older form: a study (no ENV).")] = None,
    certificate: Annotated[Path | None, typer.Option("--certificate", metavar="CERT.json", help="The answer's certificate: checked exactly now, its status shown.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """A self-contained HTML report of an answer of any kind: the answer drawn as SVG (zoom, pan, hover details), its
    certificate checked exactly, the numbers, the command that reproduces it; prints {"written", "kind", "bytes", ...}."""
    from solverplan.render.report import make_report

    with common.exit_codes():
        given = [(name, path) for name, path in (("plan", plan_file), ("patrol", patrol_file), ("funnel", funnel_file),
                                                 ("cycle", cycle_file), ("study", study_file)) if path is not None]
        if len(given) > 1:
            raise InputError("give one answer: ANSWER.json, or one of --plan, --patrol, --funnel, --cycle, --study")
        option, answer = given[0] if given else (None, file)
        env_path = file if given else env
        if answer is None:
            raise InputError("give the answer: solverplan report ANSWER.json [--certificate C.json] -o REPORT.html")
        if given and env is not None:
            raise InputError("the older form names the environment as its argument: drop --env")
        out = out if out is not None else answer.with_suffix(".html")
        environment = common.load(env_path) if env_path is not None else None
        saved = make_report(answer, out, env=environment, env_label=str(env_path) if env_path is not None else None,
                            certificate_path=certificate, option=option)
        emit(saved, common.fmt, None)
    verdict = saved.report.certificate
    if verdict is not None and not verdict["valid"]:
        first = verdict["failures"][0]
        raise fail(f"certificate invalid: {first['claim']}: {first['message']} (the report {out} shows every failure)", 1)
