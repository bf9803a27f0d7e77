"""``fields``: composed potential fields with reflection."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.choices import CellKind, Reflections, RobotKind, ScenarioName, StartMode
from solverplan.limits import MAX_SEED, MAX_TRAJECTORIES
from solverplan.cli._app import EnvArg, app
from solverplan.cli._options import CommonOptions, ScenarioOrAll, common_options, parse_xy
from solverplan.cli._output import emit_string, json_text


@app.command(name="fields")
@common_options("certificate", "picture", "env_format", "fmt", "out", "verbose")
def fields_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--from", metavar="X,Y", help="The start, a point of the free space.")],
    goal: Annotated[str, typer.Option("--to", metavar="X,Y", help="The goal, a point of the free space.")],
    scenario: Annotated[ScenarioOrAll, typer.Option("--scenario", help="constrained (slow nominal fields), unconstrained (fast), reflection (fast, with reflection zones) or all three.")] = ScenarioOrAll("all"),
    model: Annotated[RobotKind, typer.Option("--model", help="The robot: a single integrator, or inertial (acceleration cap, restitution, dead band).")] = RobotKind.INERTIAL,
    trials: Annotated[int, typer.Option("--trials", min=1, max=10_000, metavar="N", help="Rollouts per scenario (at most 10,000).")] = 25,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the motion noise.")] = 0,
    trajectories: Annotated[int | None, typer.Option("--trajectories", min=0, max=MAX_TRAJECTORIES, metavar="K", help="Trajectories kept per scenario (at most --trials; default 0, or 5 with --picture).")] = None,
    arcs: Annotated[bool, typer.Option("--arcs", help="Arc fields in turning cells where they verify (the paper's linear/arc configuration).")] = False,
    fast: Annotated[float, typer.Option("--fast", min=1e-9, max=1e6, metavar="V", help="Speed of the unconstrained and reflection scenarios (length/s).")] = 1.5,
    slow: Annotated[float, typer.Option("--slow", min=1e-9, max=1e6, metavar="V", help="Speed of the constrained scenario (length/s).")] = 0.8,
    accel: Annotated[float, typer.Option("--accel", min=1e-9, max=1e9, metavar="A", help="Inertial robot: largest change of velocity per second (length/s²).")] = 2.0,
    restitution: Annotated[float, typer.Option("--restitution", min=0.0, max=1.0, metavar="E", help="Inertial robot: share of the normal speed kept (reversed) by an impact.")] = 0.8,
    control_rate: Annotated[float, typer.Option("--control-rate", min=0.1, max=10_000.0, metavar="HZ", help="Commands per second; the physics runs at 400 Hz, or at this rate if higher (it must divide it).")] = 20.0,
    gain_line: Annotated[str | None, typer.Option("--gain-line", metavar="P", help="Gain of the line fields (1/length), read exactly; default 3 in corridors as wide as the shipped serpentine's, inversely proportional to the environment's mean width 2·area/perimeter.", show_default=False)] = None,
    gain_arc: Annotated[str | None, typer.Option("--gain-arc", metavar="P", help="Gain of the arc fields (1/length), read exactly; default 1 in the serpentine, scaled like --gain-line.", show_default=False)] = None,
    goal_radius: Annotated[float | None, typer.Option("--goal-radius", metavar="R", help="A trial reaches the goal within R (length); default 0.1, less in environments narrower than the serpentine (0.1 × mean width / 0.4422).", show_default=False)] = None,
    dead_band: Annotated[float | None, typer.Option("--dead-band", metavar="V", help="Commanded speeds below V give no motion (length/s); default 1/16 of the slower speed, at most 0.05.", show_default=False)] = None,
    reflections: Annotated[Reflections, typer.Option("--reflections", help="payoff: plan a reflection only where the wall turns the robot to the exit, the robot would overshoot and rollouts predict a gain; all: every zone the geometry allows (the paper); none.")] = Reflections.PAYOFF,
    cells: Annotated[CellKind, typer.Option("--cells", help="convex: Hertel–Mehlhorn cells; corners: with the reflex corners projected along their walls, so turns get corner cells (reflection candidates).")] = CellKind.CONVEX,
    starts: Annotated[StartMode, typer.Option("--starts", help="fixed: every trial from --from; random: each trial from a uniform random point of the free space (seeded, the same in every scenario).")] = StartMode.FIXED,
    export: Annotated[Path | None, typer.Option("--export", metavar="FIELD.json", help="Also write the composed field for a controller (cells as half-planes, fields, reflection zones), atomically.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Composed local potential fields in convex cells, with reflection (Stager and Tanner): cells, sequence, reflection cells and scenario statistics."""
    from solverplan.certify.gate import checked_answer
    from solverplan.reflection.navigation import navigate_fields

    with common.loaded(env) as environment:
        names = ScenarioName.values() if scenario == "all" else (scenario.value,)
        if trajectories is None:  # a picture without runs shows empty corridors: draw a few by default
            trajectories = min(5, trials) if common.picture is not None else 0
        robot = _robot(model, accel, restitution, control_rate)
        checked = checked_answer(lambda: navigate_fields(
            environment, parse_xy(start, "--from"), parse_xy(goal, "--to"), scenarios=names, model=robot,
            trials=trials, seed=seed, trajectories=trajectories, arcs=arcs, fast=fast, slow=slow, gain_line=gain_line,
            gain_arc=gain_arc, reflections=reflections.value, starts=starts.value, cells=cells.value,
            goal_radius=goal_radius, dead_band=dead_band), env=environment)
        if export is not None:  # its cells and fields checked exactly before it leaves
            emit_string(json_text(checked.answer.plan.export(), 1) + "\n", export)
        common.emit_checked(checked, env=environment)


def _robot(model: RobotKind, accel: float, restitution: float, control_rate: float) -> Any:
    """The robot of the options: the physics at 400 Hz, or at the control rate if higher, a multiple of it."""
    from solverplan.reflection.simulate import FieldRobotDynamics

    physics = max(400.0, control_rate)
    return FieldRobotDynamics(kind=model.value, accel=accel, restitution=restitution, control_rate=control_rate,
                              physics_rate=control_rate * max(1, round(physics / control_rate)))
