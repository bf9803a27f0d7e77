"""``rooms``: rooms and doors of a rectilinear polygon (the rooms paper), and its bounce rules simulated."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from solverplan.limits import MAX_BOUNCES, MAX_SEED, MAX_TRIALS
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, EnvFormatOpt, FormatOpt, OutOpt, VerboseOpt, app, load_env
from solverplan.cli._errors import exit_codes, invalid
from solverplan.cli._options import CertificateOpt, PictureOpt, emit_checked, save_picture
from solverplan.cli._output import OutputFormat, emit


class RoomRule(StrEnum):
    SMART = "smart"
    SMART_PAPER = "smart-paper"
    SMART_PER_ROOM = "smart-per-room"
    RANDOM = "random"
    BILLIARD = "billiard"
    ALL = "all"


class ThetaMode(StrEnum):
    SAFE = "safe"
    PAPER = "paper"
    PER_ROOM = "per-room"


class DoorMode(StrEnum):
    CONTROL = "control"
    OPEN = "open"


@app.command(name="rooms")
def rooms_command(
    env: EnvArg,
    simulate: Annotated[bool, typer.Option("--simulate", help="Simulate robots from room --from to room --to instead.")] = False,
    start: Annotated[int | None, typer.Option("--from", min=0, metavar="ROOM", help="Start room (with --simulate).", show_default=False)] = None,
    goal: Annotated[int | None, typer.Option("--to", min=0, metavar="ROOM", help="Target room (with --simulate).", show_default=False)] = None,
    rule: Annotated[RoomRule, typer.Option("--rule", help="Bounce rule: smart (θ from --theta), smart-paper, smart-per-room, random, billiard, or all side by side. Every rule is simulated with the same starts to make the recommendation.")] = RoomRule.SMART,
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="N", help="Robots per rule.")] = 100,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the starts (and of the random rule).")] = 0,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of each robot.")] = 5000,
    doors: Annotated[DoorMode, typer.Option("--doors", help="control: the door-control policy for the room sequence; open: every door open.")] = DoorMode.CONTROL,
    per_room: Annotated[bool, typer.Option("--per-room", help="Tell the smart robot the θ of the room it is in (the same as --theta per-room).")] = False,
    theta: Annotated[ThetaMode, typer.Option("--theta", help="The smart rule's θ: safe (tan θ = ℓ/2D, arrives from every start tried), paper (Eq. 1's ℓ/h: faster, some starts trapped) or per-room (the safe θ of the room it is in).")] = ThetaMode.SAFE,
    tour: Annotated[bool, typer.Option("--tour", help="Visit every room from --from (depth first) instead of going to --to.")] = False,
    check: Annotated[
        Path | None,
        typer.Option("--check", metavar="ROOMS.json", help="Check a rooms answer file against ENV exactly instead: exit 0 valid, 1 invalid.", show_default=False),
    ] = None,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Rooms and doors of a rectilinear polygon (Algorithm 1 of the rooms paper); with --simulate, the bounce rules compared."""
    from solverplan.rectilinear import decompose_rooms

    if check is not None:
        from solverplan.certify.rooms_answer import check_rooms, load_rooms_answer

        with exit_codes(verbose):
            if simulate or picture is not None or start is not None or goal is not None or tour:
                raise InputError("--check checks an answer file: drop the options of --simulate and --picture")
            report = check_rooms(load_env(env, env_format), load_rooms_answer(check))
            emit(report, fmt, out)
        if not report.valid:
            raise invalid("rooms answer", report.failures)
        return
    with exit_codes(verbose):
        if simulate and certificate is not None:
            raise InputError("--certificate certifies the rooms and doors: drop --simulate (its statistics are not claims)")
        if not simulate and (start is not None or goal is not None or tour):
            raise InputError("--from, --to and --tour choose the rooms of --simulate: add --simulate")
        if simulate and (start is None or (goal is None) == (not tour)):
            raise InputError("--simulate needs --from ROOM and either --to ROOM or --tour")
        environment = load_env(env, env_format, picture)
        if not simulate:
            from solverplan.certify.gate import checked_answer

            checked = checked_answer(lambda: decompose_rooms(environment), env=environment)  # exact check first
            emit_checked(checked, fmt, out, env=environment, certificate=certificate, picture=picture)
            return
        from solverplan.studies.rooms import RULE_VARIANTS, compare_rules

        dec = decompose_rooms(environment)

        assert start is not None
        walk = dec.tour(start) if tour else dec.path(start, dec.check_room(goal))
        names = RULE_VARIANTS if rule is RoomRule.ALL else (rule.value,) + tuple(n for n in RULE_VARIANTS if n != rule.value)
        answer = compare_rules(dec, start, walk[-1], rules=names, trials=trials, seed=seed, max_bounces=max_bounces,
                               doors=doors.value, per_room=per_room, theta=theta.value, walk=walk,
                               keep=1 if picture is not None else 0)
        if picture is not None:
            save_picture(picture, "rooms.render_rooms", dec,
                         {name: r.trajectories[0] for name, r in answer.runs.items() if r.trajectories})
        emit(answer if rule is RoomRule.ALL else answer.runs[rule.value], fmt, out)
