"""Commands of the bouncing robot: ``cycle``, ``patrol``, ``funnel``, ``localize``, ``plan``, ``simulate``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.choices import CycleMethod, Objective, PatrolObjective, Sampling, Ties
from solverplan.limits import MAX_BOUNCES, MAX_SEED, MAX_TRIALS
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, app
from solverplan.cli._options import (
    CommonOptions,
    CornerClearanceOpt,
    HeadingMarginOpt,
    PositionToleranceOpt,
    TimeoutOpt,
    command_stop,
    command_timeout,
    common_options,
)


ThetaOpt = Annotated[str, typer.Option(
    "--theta", metavar="THETA",
    help="The constant heading (CCW from each wall): radians, e.g. 0.3 or pi/12 (taken at the exact direction (cos θ, sin θ) "
    "of its binary floats, < 1e-15 rad away; theta_exact in the answer says which); tan:P/Q (exact rational tangent, alias "
    "atan:P/Q; negative for θ > π/2); dir:C,S (exact direction pair); or auto (search a heading that drives every start into "
    "a verified cycle, Prop. 4).")]
CycleEdgesOpt = Annotated[str | None, typer.Option("--edges", metavar="e0,e1,...", help="Ask for the cycle along this edge sequence.", show_default=False)]
CycleEpsilonOpt = Annotated[float | None, typer.Option("--epsilon", metavar="E", help="Also report the cycles needed to shrink the position set below E (Cor. 4; a length).", show_default=False)]
CycleMethodOpt = Annotated[CycleMethod, typer.Option("--method", help="theorem1 (convex polygons: the CCW cycle), iterate (follow the rule from --start), edges (--edges); auto picks.")]
CycleStartOpt = Annotated[str | None, typer.Option("--start", metavar="eK:T", help="Iterate: the start point (default e0:0.5).", show_default=False)]
CycleBouncesOpt = Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Iterate: bounce budget.")]
AutoMarginOpt = Annotated[float | None, typer.Option("--heading-margin", metavar="D", help="With --theta auto: try no heading within D radians of a wall (default 0.001; a heading given with --theta is used as asked).", show_default=False)]


@app.command(name="cycle")
@common_options("env_format", "fmt", "out", "verbose")
def cycle_command(
    env: EnvArg,
    theta: ThetaOpt,
    edges: CycleEdgesOpt = None,
    epsilon: CycleEpsilonOpt = None,
    method: CycleMethodOpt = CycleMethod.AUTO,
    cycle_start: CycleStartOpt = None,
    max_bounces: CycleBouncesOpt = 20000,
    heading_margin: AutoMarginOpt = None,
    *,
    common: CommonOptions,
) -> None:
    """The limit cycle of a constant heading (paper §6.1, Theorem 1, Proposition 4), verified in exact arithmetic:
    contact points, exact contraction, fixed points, basins; status says if and why there is none."""
    from solverplan.bounce.controller import constant_controller
    from solverplan.bounce.cycles import limit_cycle
    from solverplan.interval import DEFAULT_HEADING_MARGIN

    with common.loaded(env) as environment:
        if theta.strip().lower() == "auto":
            if edges is not None or cycle_start is not None or method is not CycleMethod.AUTO:
                raise InputError("--theta auto searches for one heading for every start: drop --edges, --start and --method")
            margin = DEFAULT_HEADING_MARGIN if heading_margin is None else heading_margin
            common.emit(constant_controller(environment, epsilon=epsilon, heading_margin=margin))
            return
        if heading_margin is not None:
            raise InputError("--heading-margin goes with --theta auto: a heading given with --theta is used as asked")
        result = limit_cycle(environment, theta, edges=edges, method=method.value, start=cycle_start, epsilon=epsilon,
                             max_bounces=max_bounces)
        common.emit(result)


SEARCH_OPTIONS = ("heading_margin", "corner_clearance", "timeout", "certificate", "picture", "env_format", "fmt", "out", "verbose")
"""The common options of the searches that answer with a strategy checked exactly: patrol, funnel, localize."""
SearchBouncesOpt = Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of the search.")]


@app.command(name="patrol")
@common_options(*SEARCH_OPTIONS)
def patrol_command(
    env: EnvArg,
    visit: Annotated[str, typer.Option("--visit", metavar="e2,e5,e9", help="The edges to visit, in this cyclic order.")],
    start: Annotated[str | None, typer.Option("--from", metavar="SET", help="Start set: the strategy first brings every point of it into the cycle.", show_default=False)] = None,
    tolerance: Annotated[float | None, typer.Option("--tolerance", metavar="E", help="Heading tolerance ε (radians): half the width of every interval (default 0.01; --objective tolerance maximises it).", show_default=False)] = None,
    objective: Annotated[PatrolObjective, typer.Option("--objective", help="contraction: least worst-case contraction per pass of the sequence; tolerance: widest intervals that still contract; rate: least contraction per bounce (minimum mean cycle, LP and Karp).")] = PatrolObjective.CONTRACTION,
    max_between: Annotated[int | None, typer.Option("--max-between", min=0, max=MAX_BOUNCES, metavar="H", help="Intermediate bounces allowed between consecutive required visits (default: the fewest that work, up to 3).", show_default=False)] = None,
    epsilon: Annotated[float | None, typer.Option("--epsilon", metavar="X", help="Also report the cycles needed to shrink the position set below the length X.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """A stable patrol cycle visiting edges in order (paper Definition 15), optimal for the objective, from a start set."""
    from solverplan.plan.patrols import patrol

    _contraction_answer(env, common, lambda environment: patrol(
        environment, visit, start=start, objective=objective.value, tolerance=tolerance, max_between=max_between,
        epsilon=epsilon, **common.search()), start=start)


@app.command(name="funnel")
@common_options(*SEARCH_OPTIONS)
def funnel_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--from", metavar="SET", help="Start set, e.g. e0 or e3:0.25:0.75,e4.")],
    goal: Annotated[str, typer.Option("--to", metavar="SET", help="Goal set: every start must end inside it.")],
    tolerance: PositionToleranceOpt = None,
    max_bounces: SearchBouncesOpt = 30,
    *,
    common: CommonOptions,
) -> None:
    """A funnel (paper Figure 14): track the exact set of possible positions and use contraction to shrink it into the goal."""
    from solverplan.plan.funnels import funnel

    _contraction_answer(env, common, lambda environment: funnel(
        environment, start, goal, tolerance=tolerance, max_bounces=max_bounces, **common.search()), start=start, goal=goal)


@app.command(name="localize")
@common_options(*SEARCH_OPTIONS)
def localize_command(
    env: EnvArg,
    epsilon: Annotated[float, typer.Option("--epsilon", metavar="X", help="Length the final position interval must be shorter than.")],
    start: Annotated[str | None, typer.Option("--from", metavar="SET", help="Start set (default: the whole boundary).", show_default=False)] = None,
    tolerance: PositionToleranceOpt = None,
    max_bounces: SearchBouncesOpt = 40,
    *,
    common: CommonOptions,
) -> None:
    """Localisation (paper §8.4): an open-loop strategy after which the possible positions lie in one interval shorter than X."""
    from solverplan.plan.localization import localize

    _contraction_answer(env, common, lambda environment: localize(
        environment, epsilon, start=start, tolerance=tolerance, max_bounces=max_bounces, **common.search()), start=start)


def _contraction_answer(env: Path, common: CommonOptions, solve: Any, *, start: str | None = None, goal: str | None = None) -> None:
    """Load the environment, ``solve`` it (patrol, funnel, localize) and check the answer exactly, write the
    --certificate (an answer not found writes none and says why on stderr) and the --picture of a found answer,
    emit the answer."""
    from solverplan.certify.gate import checked_answer

    with common.loaded(env) as environment:
        checked = checked_answer(lambda: solve(environment), env=environment, start=start, goal=goal,
                                 stop_at=command_stop(common.timeout))
        found = checked.answer.found  # a strategy not found has nothing to certify or draw
        common.emit_checked(checked, draw_picture=found)


FromSetOpt = Annotated[str, typer.Option("--from", metavar="SET", help="Start set, e.g. e0 or e3:0.25:0.75,e4 (may span edges and segments: the plan works from every point).")]
ToSetOpt = Annotated[str, typer.Option("--to", metavar="SET", help="Goal set, same syntax.")]
ObjectiveOpt = Annotated[Objective | None, typer.Option("--objective", help="fewest bounces (default); tolerance: the narrowest interval as wide as possible; sum: the sum of the widths within --max-bounces; constant: one interval at every stage (Algorithm 2).", show_default=False)]
PlanBouncesOpt = Annotated[int | None, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget (needed by --objective sum).", show_default=False)]
ParetoOpt = Annotated[bool, typer.Option("--pareto", help="Answer the Pareto front bounces ↔ tolerance instead of one plan (objective tolerance).")]
PlanMethodOpt = Annotated[str, typer.Option("--method", metavar="M", help="auto, or: fewest bfs; tolerance label|milp; sum dp|lp; constant label.")]
PlanCertificateOpt = Annotated[Path | None, typer.Option("--certificate", metavar="FILE", help="Also write the plan's certificate (checked before it is written; verify it with 'solverplan verify'). With --pareto: of the most tolerant plan.", show_default=False)]
HeadingAccuracyOpt = Annotated[float | None, typer.Option("--heading-accuracy", metavar="A", help="The robot's heading accuracy (radians): plan only with intervals at least A wide (±a turning: A = 2a); infeasible answers give the best A that works.", show_default=False)]


@app.command(name="plan")
@common_options("env_format", "fmt", "out", "verbose")
def plan_command(
    env: EnvArg,
    start: FromSetOpt,
    goal: ToSetOpt,
    objective: ObjectiveOpt = None,
    max_bounces: PlanBouncesOpt = None,
    pareto: ParetoOpt = False,
    method: PlanMethodOpt = "auto",
    certificate: PlanCertificateOpt = None,
    heading_margin: HeadingMarginOpt = 1e-3,
    corner_clearance: CornerClearanceOpt = None,
    heading_accuracy: HeadingAccuracyOpt = None,
    timeout: TimeoutOpt = None,
    *,
    common: CommonOptions,
) -> None:
    """An optimal plan from one boundary set to another (paper §7–8), or a proof that there is none (exit 0)."""
    from solverplan.certify.gate import checked_answer
    from solverplan.plan.search import find_plan, pareto_front

    with common.loaded(env) as environment:
        if pareto and (objective not in (None, Objective.TOLERANCE) or method != "auto"):
            raise InputError("--pareto answers the bounces ↔ tolerance front: drop --objective and --method")
        if pareto and heading_accuracy is not None:
            raise InputError("--heading-accuracy applies to one plan, not to --pareto")

        def solve() -> Any:
            if pareto:
                return pareto_front(environment, start, goal, max_bounces=max_bounces, heading_margin=heading_margin,
                                    corner_clearance=corner_clearance, timeout=command_timeout(timeout))
            return find_plan(environment, start, goal, objective=(objective or Objective.FEWEST).value,
                             max_bounces=max_bounces, method=method, heading_margin=heading_margin,
                             corner_clearance=corner_clearance, timeout=command_timeout(timeout),
                             min_width=heading_accuracy)

        checked = checked_answer(solve, env=environment, start=start, goal=goal,  # exact check before it leaves
                                 stop_at=command_stop(timeout))
        common.emit_checked(checked, env=environment, certificate=certificate)


@app.command(name="simulate")
@common_options("env_format", "fmt", "out", "verbose")
def simulate_command(
    env: EnvArg,
    plan_file: Annotated[Path, typer.Argument(metavar="PLAN.json", help="A plan written by 'solverplan plan -o PLAN.json'.", show_default=False)],
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="N", help="Number of rollouts.")] = 10000,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed (recorded in the answer).")] = 0,
    sampling: Annotated[Sampling, typer.Option("--sampling", help="How headings are drawn from each interval: uniform, or endpoints (adversarial: an end of the interval).")] = Sampling.UNIFORM,
    ties: Annotated[Ties, typer.Option("--ties", help="exact: re-resolve rays the float caster cannot call; flag: stop and count them.")] = Ties.EXACT,
    *,
    common: CommonOptions,
) -> None:
    """Monte Carlo rollouts of a plan: success rate (goal reached through every stage's segments) and bounce statistics."""
    from solverplan.plan import load_plan
    from solverplan.simulate import simulate_plan

    with common.loaded(env) as environment:
        plan = load_plan(plan_file)
        runs = simulate_plan(environment, plan, trials=trials, seed=seed, sampling=sampling.value, ties=ties.value)
        common.emit(runs)
