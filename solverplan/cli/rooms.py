"""``rooms``: rooms and doors of a rectilinear polygon (the rooms paper), and its bounce rules simulated."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.choices import DoorPolicy, ThetaMode
from solverplan.limits import MAX_BOUNCES, MAX_SEED, MAX_TRIALS
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, app
from solverplan.cli._errors import invalid
from solverplan.cli._options import CommonOptions, RoomRuleOrAll, common_options, save_picture


@app.command(name="rooms")
@common_options("certificate", "picture", "env_format", "fmt", "out", "verbose")
def rooms_command(
    env: EnvArg,
    simulate: Annotated[bool, typer.Option("--simulate", help="Simulate robots from room --from to room --to instead.")] = False,
    start: Annotated[int | None, typer.Option("--from", min=0, metavar="ROOM", help="Start room (with --simulate).", show_default=False)] = None,
    goal: Annotated[int | None, typer.Option("--to", min=0, metavar="ROOM", help="Target room (with --simulate).", show_default=False)] = None,
    rule: Annotated[RoomRuleOrAll, typer.Option("--rule", help="Bounce rule: smart (θ from --theta), smart-paper, smart-per-room, random, billiard, or all side by side. Every rule is simulated with the same starts to make the recommendation.")] = RoomRuleOrAll("smart"),
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="N", help="Robots per rule.")] = 100,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the starts (and of the random rule).")] = 0,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of each robot.")] = 5000,
    doors: Annotated[DoorPolicy, typer.Option("--doors", help="control: the door-control policy for the room sequence; open: every door open.")] = DoorPolicy.CONTROL,
    per_room: Annotated[bool, typer.Option("--per-room", help="Tell the smart robot the θ of the room it is in (the same as --theta per-room).")] = False,
    theta: Annotated[ThetaMode, typer.Option("--theta", help="The smart rule's θ: safe (tan θ = ℓ/2D, arrives from every start tried), paper (Eq. 1's ℓ/h: faster, some starts trapped) or per-room (the safe θ of the room it is in).")] = ThetaMode.SAFE,
    tour: Annotated[bool, typer.Option("--tour", help="Visit every room from --from (depth first) instead of going to --to.")] = False,
    check: Annotated[Path | None, typer.Option("--check", metavar="ROOMS.json", help="Check a rooms answer file against ENV exactly instead: exit 0 valid, 1 invalid.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Rooms and doors of a rectilinear polygon (Algorithm 1 of the rooms paper); with --simulate, the bounce rules compared."""
    if check is not None:
        if simulate or common.picture is not None or start is not None or goal is not None or tour:
            with common.exit_codes():
                raise InputError("--check checks an answer file: drop the options of --simulate and --picture")
        return _check_answer(env, check, common)
    with common.exit_codes():
        if simulate and common.certificate is not None:
            raise InputError("--certificate certifies the rooms and doors: drop --simulate (its statistics are not claims)")
        if not simulate and (start is not None or goal is not None or tour):
            raise InputError("--from, --to and --tour choose the rooms of --simulate: add --simulate")
        if simulate and (start is None or (goal is None) == (not tour)):
            raise InputError("--simulate needs --from ROOM and either --to ROOM or --tour")
        environment = common.load(env)
        if not simulate:
            return _decompose(environment, common)
        assert start is not None
        _simulate(environment, start, goal, tour, rule, common, trials=trials, seed=seed,
                  max_bounces=max_bounces, doors=doors.value, per_room=per_room, theta=theta.value)


def _simulate(environment: Any, start: int, goal: int | None, tour: bool, rule: Any, common: CommonOptions,
              **options: Any) -> None:
    """--simulate: every rule through the same rooms from the same starts (the one asked for first), and its runs
    (or all of them, with --rule all)."""
    from solverplan.rectilinear import decompose_rooms
    from solverplan.rectilinear.simulation import RULE_VARIANTS, compare_rules

    dec = decompose_rooms(environment)
    walk = dec.tour(start) if tour else dec.path(start, dec.check_room(goal))
    names = RULE_VARIANTS if rule == "all" else (rule.value,) + tuple(n for n in RULE_VARIANTS if n != rule.value)
    answer = compare_rules(dec, start, walk[-1], rules=names, walk=walk, keep=1 if common.picture else 0, **options)
    if common.picture is not None:
        save_picture(common.picture, "rooms.render_rooms", dec,
                     {name: r.trajectories[0] for name, r in answer.runs.items() if r.trajectories})
    common.emit(answer if rule == "all" else answer.runs[rule.value])


def _check_answer(env: Path, check: Path, common: CommonOptions) -> None:
    """--check: a rooms answer file checked against ENV exactly (exit 0 valid, 1 invalid)."""
    from solverplan.certify.rooms_answer import check_rooms_answer, load_rooms_answer

    with common.exit_codes():
        report = check_rooms_answer(common.load(env), load_rooms_answer(check))
        common.emit(report)
    if not report.valid:
        raise invalid("rooms answer", report.failures)


def _decompose(environment: Any, common: CommonOptions) -> None:
    """The rooms and doors, checked exactly before they leave, with the --certificate and --picture."""
    from solverplan.certify.gate import checked_answer
    from solverplan.rectilinear import decompose_rooms

    checked = checked_answer(lambda: decompose_rooms(environment), env=environment)
    common.emit_checked(checked, env=environment)
