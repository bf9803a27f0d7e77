"""Commands on the environment and its structures: ``info``, ``partition``, ``graph``, ``render``."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Annotated

import typer

from solverplan.choices import GraphFormat
from solverplan.limits import MAX_BOUNCES, MAX_SEED, MAX_TRAJECTORIES
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, app
from solverplan.cli._options import CommonOptions, common_options
from solverplan.cli._output import OutputFormat, emit, emit_chunks, emit_string, json_indent

logger = logging.getLogger(__name__)

@app.command()
@common_options("env_format", "fmt", "out", "verbose")
def info(env: EnvArg, *, common: CommonOptions) -> None:
    """Describe an environment: vertices, rings, edges (id, ring, end points, length), reflex vertices, area, perimeter."""
    with common.loaded(env) as environment:
        logger.info("loaded %r: %d vertices, %d holes", environment.name, environment.n_vertices, len(environment.holes))
        from solverplan.describe import describe_environment

        common.emit(describe_environment(environment))


@app.command(name="partition")
@common_options("env_format", "fmt", "out", "verbose")
def partition_command(env: EnvArg, *, common: CommonOptions) -> None:
    """The partition P′ of Algorithm 1: vertices per ring, segments (id, edge, t0, t1, a, b), inserted points."""
    from solverplan.bounce.partitions import partition as partition_boundary

    with common.loaded(env) as environment:
        common.emit(partition_boundary(environment))


GraphFormatOpt = Annotated[GraphFormat, typer.Option("--format", help="JSON (docs/contract.md), text, GraphML or Graphviz DOT.")]


@app.command(name="graph")
@common_options("env_format", "fmt", "out", "verbose", fmt=(GraphFormatOpt, GraphFormat.JSON))
def graph_command(
    env: EnvArg,
    safe: Annotated[bool, typer.Option("--safe", help="Label every arc with its exact safe headings (paper §5).")] = False,
    source: Annotated[int | None, typer.Option("--from", metavar="SEG", help="Only the arcs leaving segment SEG of P′.", show_default=False)] = None,
    heading: Annotated[float | None, typer.Option("--heading", metavar="THETA", help="Only the arcs whose safe set holds heading THETA (radians, in (0, π)); implies --safe.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """The bounce visibility graph of P′: arcs between segments that see each other; with --safe, their safe headings."""
    from solverplan.bounce.bvg import safe_bounce_visibility_graph

    out, fmt = common.out, common.fmt
    with common.loaded(env) as environment:
        graph = safe_bounce_visibility_graph(environment)
        logger.info("safe BVG: %d segments, %d arcs, %d safe (%.3f s)", graph.n_segments, graph.n_arcs, graph.n_safe_arcs,
                    graph.stats.get("seconds_total", 0.0))
        view = graph.select(source=source, heading=heading, safe=safe or heading is not None)
        if fmt is GraphFormat.GRAPHML:
            emit_string(view.to_graphml(), out)
        elif fmt is GraphFormat.DOT:
            emit_string(view.to_dot(), out)
        elif fmt is GraphFormat.JSON and json_indent() in (None, -1) and view.n_arcs > 20_000:
            # a large graph (its text well over JSON_INDENT_LIMIT) is compact JSON (json_text): the same bytes,
            # encoded and written a chunk of arcs at a time (never the whole text in memory)
            emit_chunks(view.json_chunks(end=b"\n"), out)
        else:
            emit(view, OutputFormat(fmt.value), out)


PictureOutOpt = Annotated[Path, typer.Option("-o", "--output", help="Picture file to write: .png or .svg.", show_default=False)]
EdgeIdsOpt = Annotated[bool, typer.Option("--edge-ids", help="Label edges e<i> with arrows showing their direction.")]
VertexIdsOpt = Annotated[bool, typer.Option("--vertex-ids", help="Label vertices v<i>.")]
ReflexOpt = Annotated[bool, typer.Option("--reflex/--no-reflex", help="Mark reflex vertices.")]
ShowPartitionOpt = Annotated[bool, typer.Option("--partition", help="Draw the partition P′ (Algorithm 1): numbered segments, inserted points.")]
ShowGraphOpt = Annotated[bool, typer.Option("--graph", help="Draw the bounce visibility graph lightly (a line between segments that see each other).")]
SafeArcsOpt = Annotated[bool, typer.Option("--safe-arcs", help="Draw every safe arc as a ray that lands on its target segment.")]
DrawTrajectoriesOpt = Annotated[int, typer.Option("--trajectories", min=0, max=MAX_TRAJECTORIES, metavar="N", help="Simulate N rollouts of --rule (or of --plan) and draw them.")]
DrawRuleOpt = Annotated[str, typer.Option("--rule", metavar="RULE", help="Bounce rule of the trajectories: specular, fixed:THETA, relative:THETA or monotone:THETA (radians, pi/3 allowed).")]
DrawStartOpt = Annotated[str | None, typer.Option("--from", metavar="SET", help="Start set of the trajectories, e.g. e0 or e3:0.25:0.75,e4 (default: the whole boundary).", show_default=False)]
DrawBouncesOpt = Annotated[int, typer.Option("--bounces", min=0, max=MAX_BOUNCES, metavar="K", help="Bounces per trajectory.")]
DrawSeedOpt = Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the trajectories.")]
ShowCycleOpt = Annotated[bool, typer.Option("--cycle", help="Draw the limit cycle of the constant heading --theta on top (bold; contacts as yellow circles); --trajectories then follow that constant rule (paper Fig. 9).")]
CycleThetaOpt = Annotated[str | None, typer.Option("--theta", metavar="THETA", help="The constant heading of --cycle, as in 'solverplan cycle'.", show_default=False)]
DrawPlanOpt = Annotated[Path | None, typer.Option("--plan", metavar="PLAN.json", help="Draw a plan (from 'solverplan plan -o'): its cones per stage, start and goal sets; --trajectories then follow the plan.", show_default=False)]


@app.command()
@common_options("env_format", "fmt", "verbose")
def render(
    env: EnvArg,
    out: PictureOutOpt,
    edge_ids: EdgeIdsOpt = False,
    vertex_ids: VertexIdsOpt = False,
    reflex: ReflexOpt = True,
    show_partition: ShowPartitionOpt = False,
    show_graph: ShowGraphOpt = False,
    safe_arcs: SafeArcsOpt = False,
    trajectories: DrawTrajectoriesOpt = 0,
    rule: DrawRuleOpt = "specular",
    start: DrawStartOpt = None,
    bounces: DrawBouncesOpt = 20,
    seed: DrawSeedOpt = 0,
    show_cycle: ShowCycleOpt = False,
    cycle_theta: CycleThetaOpt = None,
    plan_file: DrawPlanOpt = None,
    *,
    common: CommonOptions,
) -> None:
    """Draw an environment to a PNG or SVG file; prints {"written": FILE, ...}."""
    from solverplan.render import figure_format, save_figure, scene

    with common.exit_codes():
        figure_format(out)  # a bad extension is reported before any work
        from solverplan.bounce.rules import parse_rule

        bounce_rule = parse_rule(rule)
        if show_cycle != (cycle_theta is not None):
            raise InputError("--cycle and --theta go together: --cycle draws the limit cycle of the heading --theta")
        environment = common.load(env)
        if start is not None:
            environment.boundary_set(start)  # a bad start set is reported before drawing
        plan = None
        if plan_file is not None:
            from solverplan.plan import load_plan

            if show_cycle or start is not None:
                raise InputError("--plan draws a plan and its own trajectories: drop --cycle and --from")
            plan = load_plan(plan_file)
        figure = scene(environment, edge_ids=edge_ids, vertex_ids=vertex_ids, reflex=reflex, partition=show_partition,
                       graph=show_graph, safe_arcs=safe_arcs, plan=plan, cycle=cycle_theta, trajectories=trajectories,
                       rule=bounce_rule, start=start, bounces=bounces, seed=seed)
        emit(save_figure(figure, out), common.fmt, None)
