"""``fields``: composed potential fields with reflection."""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated

import typer

from solverplan.limits import MAX_SEED, MAX_TRAJECTORIES
from solverplan.cli._app import EnvArg, EnvFormatOpt, FormatOpt, OutOpt, VerboseOpt, app, check_picture, load_env
from solverplan.cli._errors import exit_codes
from solverplan.cli._options import CertificateOpt, PictureOpt, parse_xy, write_certificate_file
from solverplan.cli._output import OutputFormat, emit


class FieldScenario(StrEnum):
    CONSTRAINED = "constrained"
    UNCONSTRAINED = "unconstrained"
    REFLECTION = "reflection"
    ALL = "all"


class FieldRobot(StrEnum):
    INTEGRATOR = "integrator"
    INERTIAL = "inertial"


@app.command(name="fields")
def fields_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--from", metavar="X,Y", help="The start, a point of the free space.")],
    goal: Annotated[str, typer.Option("--to", metavar="X,Y", help="The goal, a point of the free space.")],
    scenario: Annotated[FieldScenario, typer.Option("--scenario", help="constrained (slow nominal fields), unconstrained (fast), reflection (fast, with reflection zones) or all three.")] = FieldScenario.ALL,
    model: Annotated[FieldRobot, typer.Option("--model", help="The robot: a single integrator, or inertial (acceleration cap, restitution, dead band).")] = FieldRobot.INERTIAL,
    trials: Annotated[int, typer.Option("--trials", min=1, max=10_000, metavar="N", help="Rollouts per scenario (at most 10,000).")] = 25,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the motion noise.")] = 0,
    trajectories: Annotated[int | None, typer.Option("--trajectories", min=0, max=MAX_TRAJECTORIES, metavar="K", help="Trajectories kept per scenario (at most --trials; default 0, or 5 with --picture).")] = None,
    arcs: Annotated[bool, typer.Option("--arcs", help="Arc fields in turning cells where they verify (the paper's linear/arc configuration).")] = False,
    fast: Annotated[float, typer.Option("--fast", min=1e-9, max=1e6, metavar="V", help="Speed of the unconstrained and reflection scenarios (length/s).")] = 1.5,
    slow: Annotated[float, typer.Option("--slow", min=1e-9, max=1e6, metavar="V", help="Speed of the constrained scenario (length/s).")] = 0.8,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Composed local potential fields in convex cells, with reflection (Stager and Tanner): cells, sequence, reflection cells and scenario statistics."""
    from solverplan.certify.gate import checked_answer
    from solverplan.reflection.navigation import navigate_fields

    with exit_codes(verbose):
        check_picture(picture)
        environment = load_env(env, env_format)
        names = ("constrained", "unconstrained", "reflection") if scenario is FieldScenario.ALL else (scenario.value,)
        if trajectories is None:  # a picture without runs shows empty corridors: draw a few by default
            trajectories = min(5, trials) if picture is not None else 0
        checked = checked_answer(lambda: navigate_fields(
            environment, parse_xy(start, "--from"), parse_xy(goal, "--to"), scenarios=names, model=model.value,
            trials=trials, seed=seed, trajectories=trajectories, arcs=arcs, fast=fast, slow=slow), env=environment)
        answer = checked.answer  # its cells and fields checked exactly before it leaves
        if certificate is not None:
            write_certificate_file(answer, certificate, environment, checked.certificate)
        if picture is not None:
            from solverplan.render import save_figure
            from solverplan.render.fields import render_fields

            save_figure(render_fields(answer), picture)
        emit(answer, fmt, out)
