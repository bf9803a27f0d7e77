"""The ``solverplan`` command: a thin shell over the public API (docs/contract.md).

Every command parses its arguments, calls the library, and emits the answer's ``to_json()``
(default) or ``to_text()`` (``--format text``) on stdout, or writes it atomically to ``-o FILE``.
No geometry, planning or JSON shaping happens here: if a command needs some, the API lacks it.

Exit codes: 0 answered; 1 internal failure; 2 bad input — one line on stderr
(``error: <message>``), no traceback, nothing written. :func:`exit_codes` maps library errors;
the :class:`_Shell` group does the same for usage errors (unknown option, bad choice).

Adding a command::

    @app.command()
    def partition(env: EnvArg, env_format: EnvFormatOpt = None, fmt: FormatOpt = OutputFormat.JSON,
                  out: OutOpt = None, verbose: VerboseOpt = 0) -> None:
        \"\"\"The partition P′ of Algorithm 1.\"\"\"
        with exit_codes(verbose):
            emit(partition_environment(load_environment(env, env_format)), fmt, out)
"""

from __future__ import annotations

import contextlib
import gc
import json
import logging
import re
import shutil
import signal
import sys
import traceback
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any, Iterator, Protocol

import orjson
import typer
from typer.core import TyperGroup

from solverplan._io import atomic_write_bytes, atomic_write_text
from solverplan.limits import (
    MAX_BOUNCES,
    MAX_COORDINATE,
    MAX_COUNT,
    MAX_GENERATED_VERTICES,
    MAX_QUOTED_CHARS,
    MAX_ROOMS,
    MAX_SEED,
    MAX_TRAJECTORIES,
    MAX_TRIALS,
    reset_memory_limit,
    set_memory_limit,
)
from solverplan.describe import describe_environment
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, SolverplanError

__all__ = ["app", "main", "exit_codes", "emit", "OutputFormat", "EnvFormat"]

logger = logging.getLogger(__name__)


# ---------------------------------------------------------------------- answers and output
class Answer(Protocol):
    """What a command emits: every result type of the library has these two methods."""

    def to_json(self) -> dict: ...

    def to_text(self, *, width: int = ...) -> str: ...


class OutputFormat(StrEnum):
    JSON = "json"
    TEXT = "text"


class EnvFormat(StrEnum):
    JSON = "json"
    GEOJSON = "geojson"
    WKT = "wkt"


def _text_width(out: Path | None) -> int:
    if out is None and sys.stdout.isatty():
        return max(shutil.get_terminal_size().columns, 60)
    return 100


#: Answers whose compact JSON is longer than this (characters, about bytes) are printed compact
#: unless ``--indent`` asks otherwise: the standard library indents in pure Python, about five
#: times slower than its compact C encoder (≈ 0.15 s per MB of compact text on the project's
#: machine), and a reader does not page through megabytes anyway. The compact text is made first
#: in any case, so measuring it costs nothing extra.
JSON_INDENT_LIMIT = 512 * 1024

#: ``None``: choose by size (:data:`JSON_INDENT_LIMIT`); ``-1``: compact; ``n >= 0``: ``indent=n``.
#: Set by the global ``--indent``/``--compact`` options for the duration of one command.
_json_indent: int | None = None


def _json_text(value: Any, indent: int | None = None) -> str:
    """``value`` as JSON text (no trailing newline): indented by two spaces when small, compact otherwise.

    ``indent`` is ``None`` to choose by the size of the compact text, ``-1`` for compact, or the
    number of spaces per level. Answers up to :data:`JSON_INDENT_LIMIT` go through the standard
    encoder, which refuses NaN and infinities (``ValueError``), as strict JSON readers do: results
    carry exact or non-finite numbers as strings or null. Larger answers (graphs of 10⁵ arcs) are
    encoded by orjson, ten times faster — the encoder was most of a big answer's time; it writes the
    same text but does not re-check finiteness (the answers' own ``to_json`` map non-finite floats to
    null).
    """
    try:
        fast = orjson.dumps(value)
    except orjson.JSONEncodeError:  # e.g. an exact integer beyond 64 bits: the standard encoder writes it
        fast = b""
    if len(fast) > JSON_INDENT_LIMIT:
        if indent is None or indent < 0:
            return fast.decode()
        if indent == 2:
            return orjson.dumps(value, option=orjson.OPT_INDENT_2).decode()
        return json.dumps(value, ensure_ascii=False, allow_nan=False, indent=indent)
    if indent is not None and indent < 0:
        return json.dumps(value, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    return json.dumps(value, ensure_ascii=False, allow_nan=False, indent=2 if indent is None else indent)


def emit(answer: Answer, fmt: OutputFormat, out: Path | None) -> None:
    """Print ``answer`` as JSON or text on stdout, or write it atomically to ``out``.

    JSON is indented for small answers and compact for large ones (:data:`JSON_INDENT_LIMIT`),
    unless the global ``--indent N`` or ``--compact`` option says which.
    """
    if fmt is OutputFormat.JSON:
        # A large answer is hundreds of thousands of fresh dicts and lists, none of them in a
        # reference cycle: without the collector pausing, its repeated full scans of the growing
        # heap made building a 250,000-arc graph answer ≈ 4× slower.
        collecting = gc.isenabled()
        gc.disable()
        try:
            text = _json_text(answer.to_json(), _json_indent) + "\n"
        finally:
            if collecting:
                gc.enable()
    else:
        text = answer.to_text(width=_text_width(out))
        if not text.endswith("\n"):  # a report is whole lines: the shell prompt must not follow on the last one
            text += "\n"
    if out is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    try:
        atomic_write_text(out, text)
    except OSError as exc:
        raise InputError(f"{out}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
    logger.info("wrote %s", out)


# ---------------------------------------------------------------------- errors and logging
def _one_line(message: str, limit: int | None = None) -> str:
    """A message on one line. With a ``limit`` (the framework's usage messages, which quote the input whole), the
    quotes of the input are cut like ours (``limits.quote``) and the line to ``limit`` characters."""
    text = " ".join(part.strip() for part in message.splitlines() if part.strip())
    if limit is None or len(text) <= limit:
        return text
    # a quote opens before a non-space and closes before a non-word character: the framework's repr of the input
    text = re.sub(r"(?<!\w)'([^'\s][^']{%d,}?)'(?!\w)" % (MAX_QUOTED_CHARS - 1),
                  lambda m: f"'{m.group(1)[:MAX_QUOTED_CHARS - 3]}…'", text)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _fail(message: str, code: int) -> typer.Exit:
    sys.stderr.write(f"error: {_one_line(message)}\n")
    sys.stderr.flush()
    return typer.Exit(code)


@contextlib.contextmanager
def _stderr_logging(verbose: int) -> Iterator[None]:
    """Log solverplan's messages to stderr while a command runs: -v info, -vv debug."""
    if verbose <= 0:
        yield
        return
    root = logging.getLogger("solverplan")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    old_level = root.level
    root.addHandler(handler)
    root.setLevel(logging.DEBUG if verbose > 1 else logging.INFO)
    try:
        yield
    finally:
        root.removeHandler(handler)
        root.setLevel(old_level)


@contextlib.contextmanager
def exit_codes(verbose: int = 0) -> Iterator[None]:
    """Run a command body, mapping errors to the exit codes of docs/contract.md with one line on stderr.

    :class:`InputError` → 2; any other :class:`SolverplanError` → 1; anything unexpected → 1 with
    ``internal error: ...`` (and the traceback before it when ``verbose``). Also sets up ``-v`` logging.
    """
    with _stderr_logging(verbose):
        try:
            yield
        except (typer.Exit, typer.Abort, BrokenPipeError):
            raise
        except InputError as exc:
            raise _fail(str(exc) or type(exc).__name__, 2) from None
        except SolverplanError as exc:
            raise _fail(str(exc) or type(exc).__name__, 1) from None
        except Exception as exc:  # a bug: say so in one line, the traceback only on request
            if verbose:
                traceback.print_exc(file=sys.stderr)
                hint = ""
            else:
                hint = " (run with -v for the traceback)"
            raise _fail(f"internal error: {type(exc).__name__}: {exc}{hint}", 1) from None


class _Shell(TyperGroup):
    """The command group, reporting usage errors (bad option, bad choice) as one ``error:`` line, exit 2."""

    def main(  # type: ignore[override]
        self,
        args: Any = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        try:
            result = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except typer.TyperException as exc:  # the framework's usage errors (vendored click)
            ctx = getattr(exc, "ctx", None)
            if type(exc).__name__ == "NoArgsIsHelpError":  # bare `solverplan`: show the help
                sys.stderr.write(exc.format_message() + "\n")
            else:
                hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
                sys.stderr.write(f"error: {_one_line(exc.format_message(), limit=150)}{hint}\n")
            sys.stderr.flush()
            sys.exit(getattr(exc, "exit_code", 2))
        except typer.Abort:
            sys.stderr.write("error: aborted\n")
            sys.exit(1)
        # non-standalone mode returns the code of a typer.Exit (commands themselves return None)
        sys.exit(result if isinstance(result, int) else 0)


# ---------------------------------------------------------------------- the app
app = typer.Typer(
    name="solverplan",
    cls=_Shell,
    help="Planning with proofs for minimal bouncing robots. Answers are JSON on stdout (see docs/contract.md).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

EnvArg = Annotated[
    Path,
    typer.Argument(
        metavar="ENV",
        help="Environment file: .json, .geojson or .wkt (or say which with --env-format), or a shipped model's name (two_rooms, square, ...).",
        show_default=False,
    ),
]
EnvFormatOpt = Annotated[
    EnvFormat | None,
    typer.Option("--env-format", help="Format of the environment file, when its extension does not say.", show_default=False),
]
FormatOpt = Annotated[OutputFormat, typer.Option("--format", help="Answer as JSON (for scripts) or text tables (for people).")]
OutOpt = Annotated[
    Path | None,
    typer.Option("-o", "--output", help="Write the answer to this file (atomically) instead of stdout.", show_default=False),
]
VerboseOpt = Annotated[
    int, typer.Option("-v", "--verbose", count=True, show_default=False, help="Log progress to stderr (-vv: debug).")
]


def _version(value: bool) -> None:
    if value:
        from importlib.metadata import PackageNotFoundError, version

        try:
            number = version("solverplan")
        except PackageNotFoundError:  # running from a source tree that is not installed
            number = "unknown"
        sys.stdout.write(f"solverplan {number}\n")
        raise typer.Exit(0)


def _reset_json_layout() -> None:
    global _json_indent
    from solverplan.bounce import bvg

    _json_indent = None
    bvg.set_graph_cache(None)
    reset_memory_limit()


@app.callback()
def _root(
    ctx: typer.Context,
    show_version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version and exit.")
    ] = False,
    indent: Annotated[
        int | None,
        typer.Option("--indent", metavar="N", min=0, show_default=False,
                     help="Indent JSON answers by N spaces per level, however large (default: 2 up to 512 KiB, then compact)."),
    ] = None,
    compact: Annotated[
        bool, typer.Option("--compact", help="Print JSON answers on one line, however small (fastest for large answers).")
    ] = False,
    graph_cache: Annotated[
        str | None,
        typer.Option("--graph-cache", metavar="DIR", envvar="SOLVERPLAN_GRAPH_CACHE", show_default=False,
                     help="Keep large safe BVGs in DIR and reuse them, integrity-checked ('off': never; default: $XDG_CACHE_HOME/solverplan/graphs)."),
    ] = None,
    graph_cache_min_arcs: Annotated[
        int | None,
        typer.Option("--graph-cache-min-arcs", metavar="N", min=0, envvar="SOLVERPLAN_GRAPH_CACHE_MIN_ARCS", show_default=False,
                     help="Write only graphs of at least N arcs to the graph cache (default 100000; 0: every graph)."),
    ] = None,
    graph_cache_size: Annotated[
        str | None,
        typer.Option("--graph-cache-size", metavar="SIZE", envvar="SOLVERPLAN_GRAPH_CACHE_SIZE", show_default=False,
                     help="Cap the graph cache at SIZE bytes (e.g. 500M; default 2G): least recently used graphs go first."),
    ] = None,
    max_memory: Annotated[
        str | None,
        typer.Option("--max-memory", metavar="SIZE", envvar="SOLVERPLAN_MAX_MEMORY", show_default=False,
                     help="Refuse up front a job (a safe BVG, rollouts, a patrol search) estimated to need more than SIZE bytes (e.g. 2G, 500M; default: the memory available)."),
    ] = None,
) -> None:
    """Planning with proofs for minimal bouncing robots in polygonal environments."""
    global _json_indent
    from solverplan.bounce import bvg

    if compact and indent is not None:
        raise typer.BadParameter("give --indent or --compact, not both", param_hint="'--indent'")
    _json_indent = -1 if compact else indent
    cache = bvg.default_cache_directory() if graph_cache is None else None if graph_cache in ("", "off") else Path(graph_cache)
    limit = _parse_size(max_memory) if max_memory is not None else None
    cap = _parse_size(graph_cache_size, "--graph-cache-size") if graph_cache_size is not None else bvg.DEFAULT_MAX_BYTES
    bvg.set_graph_cache(cache, min_arcs=bvg.DEFAULT_MIN_ARCS if graph_cache_min_arcs is None else graph_cache_min_arcs,
                        max_bytes=cap)
    if limit is not None:
        set_memory_limit(limit)
    # the layout, cache and limit belong to this one command line (tests run many in one process)
    ctx.call_on_close(_reset_json_layout)


def _parse_size(text: str, option: str = "--max-memory") -> int:
    """``SIZE`` of --max-memory (or ``option``): bytes, or a number with K, M, G or T (powers of 1024)."""
    units = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}
    t = text.strip().upper().removesuffix("B")
    unit = t[-1:] if t[-1:] in units and t[-1:] else ""
    try:
        value = float(t[: len(t) - len(unit)])
    except ValueError:
        value = float("nan")
    if not (1 <= value * units[unit] < 2**62):
        raise typer.BadParameter(f"expected a size such as 2G, 500M or 1000000 bytes, got {text[:40]!r}", param_hint=f"'{option}'")
    return int(value * units[unit])


def _load(env: Path, env_format: EnvFormat | None) -> Environment:
    """The environment named on the command line (format from the extension unless given)."""
    return load_environment(env, env_format.value if env_format else None)


def _check_picture(picture: Path | None) -> None:
    """Reject a --picture path with an unknown extension before any work is done."""
    if picture is not None:
        from solverplan.render import figure_format

        figure_format(picture)


@app.command()
def info(
    env: EnvArg,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Describe an environment: vertices, rings, edges (id, ring, end points, length), reflex vertices, area, perimeter."""
    with exit_codes(verbose):
        environment = _load(env, env_format)
        logger.info("loaded %r: %d vertices, %d holes", environment.name, environment.n_vertices, len(environment.holes))
        emit(describe_environment(environment), fmt, out)


@app.command(name="partition")
def partition_command(
    env: EnvArg,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """The partition P′ of Algorithm 1: vertices per ring, segments (id, edge, t0, t1, a, b), inserted points."""
    from solverplan.bounce.partition import partition as partition_boundary

    with exit_codes(verbose):
        environment = _load(env, env_format)
        emit(partition_boundary(environment), fmt, out)


class GraphFormat(StrEnum):
    JSON = "json"
    TEXT = "text"
    GRAPHML = "graphml"
    DOT = "dot"


def _emit_string(text: str, out: Path | None) -> None:
    """Write ready-made text (GraphML, DOT) to stdout or atomically to ``out``."""
    if out is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    try:
        atomic_write_text(out, text)
    except OSError as exc:
        raise InputError(f"{out}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
    logger.info("wrote %s", out)


@app.command(name="graph")
def graph_command(
    env: EnvArg,
    safe: Annotated[bool, typer.Option("--safe", help="Label every arc with its exact safe headings (paper §5).")] = False,
    source: Annotated[
        int | None, typer.Option("--from", metavar="SEG", help="Only the arcs leaving segment SEG of P′.", show_default=False)
    ] = None,
    heading: Annotated[
        float | None,
        typer.Option("--heading", metavar="THETA", help="Only the arcs whose safe set holds heading THETA (radians, in (0, π)); implies --safe.", show_default=False),
    ] = None,
    env_format: EnvFormatOpt = None,
    fmt: Annotated[GraphFormat, typer.Option("--format", help="JSON (docs/contract.md), text, GraphML or Graphviz DOT.")] = GraphFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """The bounce visibility graph of P′: arcs between segments that see each other; with --safe, their safe headings."""
    from solverplan.bounce.bvg import safe_bounce_visibility_graph

    with exit_codes(verbose):
        environment = _load(env, env_format)
        graph = safe_bounce_visibility_graph(environment)
        logger.info("safe BVG: %d segments, %d arcs, %d safe (%.3f s)", graph.n_segments, graph.n_arcs, graph.n_safe_arcs,
                    graph.stats.get("seconds_total", 0.0))
        view = graph.select(source=source, heading=heading, safe=safe or heading is not None)
        if fmt is GraphFormat.GRAPHML:
            _emit_string(view.to_graphml(), out)
        elif fmt is GraphFormat.DOT:
            _emit_string(view.to_dot(), out)
        elif fmt is GraphFormat.JSON and _json_indent in (None, -1) and view.n_arcs > 20_000:
            # a large graph is compact JSON (_json_text): the same bytes, encoded a chunk at a time
            data = view.json_bytes(end=b"\n")
            if len(data) <= JSON_INDENT_LIMIT:
                emit(view, OutputFormat.JSON, out)
            elif out is None:
                sys.stdout.buffer.write(data)
                sys.stdout.flush()
            else:
                try:
                    atomic_write_bytes(out, data)  # type: ignore[arg-type]  # any bytes-like object
                except OSError as exc:
                    raise InputError(f"{out}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
                logger.info("wrote %s", out)
        else:
            emit(view, OutputFormat(fmt.value), out)


@app.command()
def render(
    env: EnvArg,
    out: Annotated[Path, typer.Option("-o", "--output", help="Picture file to write: .png or .svg.", show_default=False)],
    edge_ids: Annotated[bool, typer.Option("--edge-ids", help="Label edges e<i> with arrows showing their direction.")] = False,
    vertex_ids: Annotated[bool, typer.Option("--vertex-ids", help="Label vertices v<i>.")] = False,
    reflex: Annotated[bool, typer.Option("--reflex/--no-reflex", help="Mark reflex vertices.")] = True,
    show_partition: Annotated[
        bool, typer.Option("--partition", help="Draw the partition P′ (Algorithm 1): numbered segments, inserted points.")
    ] = False,
    show_graph: Annotated[
        bool, typer.Option("--graph", help="Draw the bounce visibility graph lightly (a line between segments that see each other).")
    ] = False,
    safe_arcs: Annotated[
        bool, typer.Option("--safe-arcs", help="Draw every safe arc as a ray that lands on its target segment.")
    ] = False,
    trajectories: Annotated[
        int, typer.Option("--trajectories", min=0, max=MAX_TRAJECTORIES, metavar="N", help="Simulate N rollouts of --rule (or of --plan) and draw them.")
    ] = 0,
    rule: Annotated[
        str,
        typer.Option(
            "--rule", metavar="RULE",
            help="Bounce rule of the trajectories: specular, fixed:THETA, relative:THETA or monotone:THETA (radians, pi/3 allowed).",
        ),
    ] = "specular",
    start: Annotated[
        str | None,
        typer.Option("--from", metavar="SET", help="Start set of the trajectories, e.g. e0 or e3:0.25:0.75,e4 (default: the whole boundary).", show_default=False),
    ] = None,
    bounces: Annotated[int, typer.Option("--bounces", min=0, max=MAX_BOUNCES, metavar="K", help="Bounces per trajectory.")] = 20,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the trajectories.")] = 0,
    show_cycle: Annotated[
        bool,
        typer.Option("--cycle", help="Draw the limit cycle of the constant heading --theta on top (bold; contacts as yellow "
                     "circles); --trajectories then follow that constant rule (paper Fig. 9)."),
    ] = False,
    cycle_theta: Annotated[
        str | None,
        typer.Option("--theta", metavar="THETA", help="The constant heading of --cycle, as in 'solverplan cycle'.", show_default=False),
    ] = None,
    plan_file: Annotated[
        Path | None,
        typer.Option("--plan", metavar="PLAN.json", help="Draw a plan (from 'solverplan plan -o'): its cones per stage, start and goal "
                     "sets; --trajectories then follow the plan.", show_default=False),
    ] = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    verbose: VerboseOpt = 0,
) -> None:
    """Draw an environment to a PNG or SVG file; prints {"written": FILE, ...}."""
    from solverplan.render import figure_format, save_figure, scene

    with exit_codes(verbose):
        figure_format(out)  # a bad extension is reported before any work
        from solverplan.bounce.rules import parse_rule

        bounce_rule = parse_rule(rule)
        if show_cycle != (cycle_theta is not None):
            raise InputError("--cycle and --theta go together: --cycle draws the limit cycle of the heading --theta")
        environment = _load(env, env_format)
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
        emit(save_figure(figure, out), fmt, None)


class CycleMethod(StrEnum):
    AUTO = "auto"
    THEOREM1 = "theorem1"
    ITERATE = "iterate"
    EDGES = "edges"


@app.command(name="cycle")
def cycle_command(
    env: EnvArg,
    theta: Annotated[
        str,
        typer.Option(
            "--theta", metavar="THETA",
            help="The constant heading (CCW from each wall): radians, e.g. 0.3 or pi/12 (taken at the exact direction "
            "(cos θ, sin θ) of its binary floats, < 1e-15 rad away; theta_exact in the answer says which); tan:P/Q "
            "(exact rational tangent, alias atan:P/Q; negative for θ > π/2); dir:C,S (exact direction pair); or auto "
            "(search a heading that drives every start into a verified cycle, Prop. 4).",
        ),
    ],
    edges: Annotated[
        str | None,
        typer.Option("--edges", metavar="e0,e1,...", help="Ask for the cycle along this edge sequence.", show_default=False),
    ] = None,
    epsilon: Annotated[
        float | None,
        typer.Option("--epsilon", metavar="E", help="Also report the cycles needed to shrink the position set below E (Cor. 4; a length).", show_default=False),
    ] = None,
    method: Annotated[
        CycleMethod,
        typer.Option("--method", help="theorem1 (convex polygons: the CCW cycle), iterate (follow the rule from --start), "
                     "edges (--edges); auto picks."),
    ] = CycleMethod.AUTO,
    cycle_start: Annotated[
        str | None,
        typer.Option("--start", metavar="eK:T", help="Iterate: the start point (default e0:0.5).", show_default=False),
    ] = None,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Iterate: bounce budget.")] = 20000,
    heading_margin: Annotated[
        float | None,
        typer.Option("--heading-margin", metavar="D", help="With --theta auto: try no heading within D radians of a wall "
                     "(default 0.001; a heading given with --theta is used as asked).", show_default=False),
    ] = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """The limit cycle of a constant heading (paper §6.1, Theorem 1, Prop. 4), verified in exact arithmetic:
    contact points, exact contraction, fixed points, basins; status says if and why there is none."""
    from solverplan.bounce.controller import constant_controller
    from solverplan.bounce.cycles import limit_cycle
    from solverplan.interval import DEFAULT_HEADING_MARGIN

    with exit_codes(verbose):
        environment = _load(env, env_format)
        if theta.strip().lower() == "auto":
            if edges is not None or cycle_start is not None or method is not CycleMethod.AUTO:
                raise InputError("--theta auto searches for one heading for every start: drop --edges, --start and --method")
            margin = DEFAULT_HEADING_MARGIN if heading_margin is None else heading_margin
            emit(constant_controller(environment, epsilon=epsilon, heading_margin=margin), fmt, out)
            return
        if heading_margin is not None:
            raise InputError("--heading-margin goes with --theta auto: a heading given with --theta is used as asked")
        result = limit_cycle(environment, theta, edges=edges, method=method.value, start=cycle_start, epsilon=epsilon,
                             max_bounces=max_bounces)
        emit(result, fmt, out)


class PatrolObjective(StrEnum):
    CONTRACTION = "contraction"
    TOLERANCE = "tolerance"
    RATE = "rate"


CertificateOpt = Annotated[
    Path | None,
    typer.Option("--certificate", metavar="FILE", help="Also write a certificate of the answer (check it with 'solverplan verify').", show_default=False),
]
PictureOpt = Annotated[
    Path | None,
    typer.Option("--picture", metavar="FIG", help="Also draw the answer to a .png or .svg file.", show_default=False),
]
PositionToleranceOpt = Annotated[
    float | None,
    typer.Option("--tolerance", metavar="E", help="Heading tolerance ε (radians): every interval is 2ε wide (default 0.005).", show_default=False),
]
HeadingMarginOpt = Annotated[
    float, typer.Option("--heading-margin", metavar="D", help="Keep every heading this far (radians) from the walls (0 and π).")
]
TimeoutOpt = Annotated[
    float | None,
    typer.Option("--timeout", metavar="SECONDS", help="Stop searching after this many seconds (the graph build counts, "
                 "uninterrupted) and answer the best found so far, not proved optimal, with the bound proved so far.",
                 show_default=False),
]
CornerClearanceOpt = Annotated[
    float | None,
    typer.Option("--corner-clearance", metavar="K", help="Keep every landing point this far (a length) from segment ends, "
                 "but the corner a stage's segments share (default: 1e-4 of the environment's diameter).", show_default=False),
]


@app.command(name="patrol")
def patrol_command(
    env: EnvArg,
    visit: Annotated[str, typer.Option("--visit", metavar="e2,e5,e9", help="The edges to visit, in this cyclic order.")],
    start: Annotated[
        str | None,
        typer.Option("--from", metavar="SET", help="Start set: the strategy first brings every point of it into the cycle.", show_default=False),
    ] = None,
    tolerance: Annotated[
        float | None,
        typer.Option("--tolerance", metavar="E", help="Heading tolerance ε (radians): half the width of every interval (default 0.01; --objective tolerance maximises it).", show_default=False),
    ] = None,
    objective: Annotated[
        PatrolObjective,
        typer.Option("--objective", help="contraction: least worst-case contraction per pass of the sequence; tolerance: widest "
                     "intervals that still contract; rate: least contraction per bounce (minimum mean cycle, LP and Karp)."),
    ] = PatrolObjective.CONTRACTION,
    max_between: Annotated[
        int | None,
        typer.Option("--max-between", min=0, max=MAX_BOUNCES, metavar="H", help="Intermediate bounces allowed between consecutive required visits (default: the fewest that work, up to 3).", show_default=False),
    ] = None,
    epsilon: Annotated[
        float | None,
        typer.Option("--epsilon", metavar="X", help="Also report the cycles needed to shrink the position set below the length X.", show_default=False),
    ] = None,
    heading_margin: HeadingMarginOpt = 1e-3,
    corner_clearance: CornerClearanceOpt = None,
    timeout: TimeoutOpt = None,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A stable patrol cycle visiting edges in order (paper Def. 15), optimal for the objective, from a start set."""
    from solverplan.plan.patrol import patrol

    _contraction_answer(env, env_format, lambda environment: patrol(
        environment, visit, start=start, objective=objective.value, tolerance=tolerance, max_between=max_between,
        epsilon=epsilon, heading_margin=heading_margin, corner_clearance=corner_clearance, timeout=timeout),
        certificate, picture, fmt, out, verbose, start=start)


@app.command(name="funnel")
def funnel_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--from", metavar="SET", help="Start set, e.g. e0 or e3:0.25:0.75,e4.")],
    goal: Annotated[str, typer.Option("--to", metavar="SET", help="Goal set: every start must end inside it.")],
    tolerance: PositionToleranceOpt = None,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of the search.")] = 30,
    heading_margin: HeadingMarginOpt = 1e-3,
    corner_clearance: CornerClearanceOpt = None,
    timeout: TimeoutOpt = None,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A funnel (paper Fig. 14): track the exact set of possible positions and use contraction to shrink it into the goal."""
    from solverplan.plan.funnel import funnel

    _contraction_answer(env, env_format, lambda environment: funnel(
        environment, start, goal, tolerance=tolerance, max_bounces=max_bounces, heading_margin=heading_margin,
        corner_clearance=corner_clearance, timeout=timeout), certificate, picture, fmt, out, verbose, start=start, goal=goal)


@app.command(name="localize")
def localize_command(
    env: EnvArg,
    epsilon: Annotated[float, typer.Option("--epsilon", metavar="X", help="Length the final position interval must be shorter than.")],
    start: Annotated[
        str | None,
        typer.Option("--from", metavar="SET", help="Start set (default: the whole boundary).", show_default=False),
    ] = None,
    tolerance: PositionToleranceOpt = None,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of the search.")] = 40,
    heading_margin: HeadingMarginOpt = 1e-3,
    corner_clearance: CornerClearanceOpt = None,
    timeout: TimeoutOpt = None,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Localisation (paper §8.4): an open-loop strategy after which the possible positions lie in one interval shorter than X."""
    from solverplan.plan.localize import localize

    _contraction_answer(env, env_format, lambda environment: localize(
        environment, epsilon, start=start, tolerance=tolerance, max_bounces=max_bounces,
        heading_margin=heading_margin, corner_clearance=corner_clearance, timeout=timeout), certificate, picture, fmt,
        out, verbose, start=start)


def _contraction_answer(env: Path, env_format: EnvFormat | None, solve: Any, certificate: Path | None,
                        picture: Path | None, fmt: OutputFormat, out: Path | None, verbose: int, *,
                        start: str | None = None, goal: str | None = None) -> None:
    """Load the environment, ``solve`` it (patrol, funnel, localize) and check the answer exactly, write the
    --certificate and --picture of a found answer, emit the answer."""
    from solverplan.certify.gate import checked_answer

    with exit_codes(verbose):
        _check_picture(picture)
        environment = _load(env, env_format)
        checked = checked_answer(lambda: solve(environment), env=environment, start=start, goal=goal)
        result = checked.answer
        if result.found:
            _write_extras(result, certificate, picture, checked.certificate)
        emit(result, fmt, out)


def _write_extras(result: Any, certificate: Path | None, picture: Path | None, checked: Any = None) -> None:
    """The --certificate and --picture files of a contraction answer (patrol, funnel, localize)."""
    if certificate is not None:
        _write_certificate_file(result, certificate, checked=checked)
    if picture is not None:
        from solverplan.render import render_answer, save_figure

        save_figure(render_answer(result), picture)


def _write_certificate_file(answer: Any, path: Path, env: Any = None, checked: Any = None) -> None:
    """--certificate: the answer's certificate, checked exactly, then written (a warning, and no file, for an
    answer with nothing to certify; exit 1 if the check fails). ``checked``: the certificate, already checked."""
    from solverplan.certify.build import NothingToCertify, certificate, write_certificate

    try:
        cert = checked if checked is not None else certificate(answer, env=env)
    except NothingToCertify as exc:
        sys.stderr.write(f"warning: no certificate written to {path}: {exc.why}\n")
        return
    try:
        write_certificate(cert, path, check=checked is None)
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
    logger.info("wrote certificate %s (verified)", path)


class PlanObjective(StrEnum):
    FEWEST = "fewest"
    TOLERANCE = "tolerance"
    SUM = "sum"
    CONSTANT = "constant"


class PlanSampling(StrEnum):
    UNIFORM = "uniform"
    ENDPOINTS = "endpoints"
    LO = "lo"
    HI = "hi"
    MID = "mid"


class TieMode(StrEnum):
    EXACT = "exact"
    FLAG = "flag"


@app.command(name="plan")
def plan_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--from", metavar="SET", help="Start set, e.g. e0 or e3:0.25:0.75,e4 (may span edges and segments: the plan works from every point).")],
    goal: Annotated[str, typer.Option("--to", metavar="SET", help="Goal set, same syntax.")],
    objective: Annotated[
        PlanObjective | None,
        typer.Option("--objective", help="fewest bounces (default); tolerance: the narrowest interval as wide as possible; sum: "
                     "the sum of the widths within --max-bounces; constant: one interval at every stage (Algorithm 2).", show_default=False),
    ] = None,
    max_bounces: Annotated[
        int | None, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget (needed by --objective sum).", show_default=False)
    ] = None,
    pareto: Annotated[
        bool, typer.Option("--pareto", help="Answer the Pareto front bounces ↔ tolerance instead of one plan (objective tolerance).")
    ] = False,
    method: Annotated[
        str, typer.Option("--method", metavar="M", help="auto, or: fewest bfs; tolerance label|milp; sum dp|lp; constant label.")
    ] = "auto",
    certificate: Annotated[
        Path | None,
        typer.Option("--certificate", metavar="FILE", help="Also write the plan's certificate (checked before it is written; "
                     "verify it with 'solverplan verify'). With --pareto: of the most tolerant plan.", show_default=False),
    ] = None,
    heading_margin: HeadingMarginOpt = 1e-3,
    corner_clearance: CornerClearanceOpt = None,
    timeout: TimeoutOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """An optimal plan from one boundary set to another (paper §7–8), or a proof that there is none (exit 0)."""
    from solverplan.certify.gate import checked_answer
    from solverplan.plan.search import find_plan, pareto_front

    with exit_codes(verbose):
        environment = _load(env, env_format)
        if pareto and (objective not in (None, PlanObjective.TOLERANCE) or method != "auto"):
            raise InputError("--pareto answers the bounces ↔ tolerance front: drop --objective and --method")

        def solve() -> Any:
            if pareto:
                return pareto_front(environment, start, goal, max_bounces=max_bounces, heading_margin=heading_margin,
                                    corner_clearance=corner_clearance, timeout=timeout)
            return find_plan(environment, start, goal, objective=(objective or PlanObjective.FEWEST).value,
                             max_bounces=max_bounces, method=method, heading_margin=heading_margin,
                             corner_clearance=corner_clearance, timeout=timeout)

        checked = checked_answer(solve, env=environment, start=start, goal=goal)  # exact check before it leaves
        answer = checked.answer
        if certificate is not None:
            _write_certificate_file(answer, certificate, environment, checked.certificate)
        emit(answer, fmt, out)


@app.command(name="simulate")
def simulate_command(
    env: EnvArg,
    plan_file: Annotated[Path, typer.Argument(metavar="PLAN.json", help="A plan written by 'solverplan plan -o PLAN.json'.", show_default=False)],
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="N", help="Number of rollouts.")] = 10000,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed (recorded in the answer).")] = 0,
    sampling: Annotated[
        PlanSampling,
        typer.Option("--sampling", help="How headings are drawn from each interval: uniform, or endpoints (adversarial: an end of the interval)."),
    ] = PlanSampling.UNIFORM,
    ties: Annotated[
        TieMode, typer.Option("--ties", help="exact: re-resolve rays the float caster cannot call; flag: stop and count them.")
    ] = TieMode.EXACT,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Monte Carlo rollouts of a plan: success rate (goal reached through every stage's segments) and bounce statistics."""
    from solverplan.plan import load_plan
    from solverplan.simulate import simulate_plan

    with exit_codes(verbose):
        environment = _load(env, env_format)
        plan = load_plan(plan_file)
        runs = simulate_plan(environment, plan, trials=trials, seed=seed, sampling=sampling.value, ties=ties.value)
        emit(runs, fmt, out)


@app.command(name="prove")
def prove_command(
    only: Annotated[
        list[str] | None,
        typer.Option("--only", metavar="NAME", help="Run only this proof module (repeatable), e.g. lemma2_contraction.", show_default=False),
    ] = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Run the symbolic proofs of solverplan.proofs (sympy): a table of results (proof, status, seconds); exit 1 if any fails."""
    with exit_codes(verbose):
        from solverplan.proofs import prove_all  # sympy-heavy: imported only by this command

        report = prove_all(only or None)
        emit(report, fmt, out)
    if not report.passed:
        raise typer.Exit(1)



@app.command(name="verify")
def verify_command(
    cert: Annotated[Path, typer.Argument(metavar="CERT.json", help="The certificate file to check.", show_default=False)],
    env: Annotated[
        Path | None,
        typer.Option("--env", metavar="ENV", help="Also require the certificate's environment to be exactly this environment file (or shipped model).", show_default=False),
    ] = None,
    start: Annotated[
        str | None,
        typer.Option("--from", metavar="SET", help="Also require the certificate's start set to be exactly SET (needs --env).", show_default=False),
    ] = None,
    goal: Annotated[
        str | None,
        typer.Option("--to", metavar="SET", help="Also require the certificate's goal set to be exactly SET (needs --env).", show_default=False),
    ] = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Check a certificate in exact rational arithmetic: exit 0 valid, 1 invalid (the first failing claim on stderr), 2 malformed."""
    from solverplan.certify.check import check_certificate
    from solverplan.certify.schema import load_certificate

    with exit_codes(verbose):
        if (start is not None or goal is not None) and env is None:
            raise InputError("--from and --to name edges of an environment: give it with --env")
        certificate = load_certificate(cert)
        environment = _load(env, env_format) if env is not None else None
        query: dict[str, Any] = {}
        if environment is not None:
            query["expected_rings"] = environment.rings
            for key, text in (("expected_start", start), ("expected_goal", goal)):
                if text is not None:
                    query[key] = [(p.edge, p.t0, p.t1) for p in environment.boundary_set(text).pieces]
        report = check_certificate(certificate, **query)
        emit(report, fmt, out)
    if not report.valid:
        more = len(report.failures) - 1
        suffix = f" (and {more} more failure{'s' if more > 1 else ''} in the report)" if more else ""
        raise _fail(f"certificate invalid: {report.failures[0]}{suffix}", 1)


# ---------------------------------------------------------------------- rooms and doors (rectilinear polygons)
class RoomRule(StrEnum):
    SMART = "smart"
    RANDOM = "random"
    BILLIARD = "billiard"
    ALL = "all"


class DoorMode(StrEnum):
    CONTROL = "control"
    OPEN = "open"


@app.command(name="rooms")
def rooms_command(
    env: EnvArg,
    simulate: Annotated[bool, typer.Option("--simulate", help="Simulate robots from room --from to room --to instead.")] = False,
    start: Annotated[int | None, typer.Option("--from", min=0, metavar="ROOM", help="Start room (with --simulate).", show_default=False)] = None,
    goal: Annotated[int | None, typer.Option("--to", min=0, metavar="ROOM", help="Target room (with --simulate).", show_default=False)] = None,
    rule: Annotated[RoomRule, typer.Option("--rule", help="Bounce rule: smart, random, billiard, or all three side by side.")] = RoomRule.SMART,
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="N", help="Robots per rule.")] = 100,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed of the starts (and of the random rule).")] = 0,
    max_bounces: Annotated[int, typer.Option("--max-bounces", min=1, max=MAX_BOUNCES, metavar="K", help="Bounce budget of each robot.")] = 5000,
    doors: Annotated[DoorMode, typer.Option("--doors", help="control: the door-control policy for the room sequence; open: every door open.")] = DoorMode.CONTROL,
    per_room: Annotated[bool, typer.Option("--per-room", help="Tell the smart robot the θ of the room it is in.")] = False,
    tour: Annotated[bool, typer.Option("--tour", help="Visit every room from --from (depth first) instead of going to --to.")] = False,
    check: Annotated[
        Path | None,
        typer.Option("--check", metavar="ROOMS.json", help="Check a rooms answer file against ENV exactly instead: exit 0 valid, 1 invalid.", show_default=False),
    ] = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Rooms and doors of a rectilinear polygon (Algorithm 1 of the rooms paper); with --simulate, the bounce rules compared."""
    from solverplan.rectilinear import decompose_rooms
    from solverplan.render import save_figure
    from solverplan.render.rooms import render_rooms

    if check is not None:
        from solverplan.rectilinear.check import check_rooms, load_rooms_answer

        with exit_codes(verbose):
            if simulate or picture is not None or start is not None or goal is not None or tour:
                raise InputError("--check checks an answer file: drop the options of --simulate and --picture")
            report = check_rooms(_load(env, env_format), load_rooms_answer(check))
            emit(report, fmt, out)
        if not report.valid:
            more = len(report.failures) - 1
            suffix = f" (and {more} more failure{'s' if more > 1 else ''} in the report)" if more else ""
            raise _fail(f"rooms answer invalid: {report.failures[0]}{suffix}", 1)
        return
    with exit_codes(verbose):
        _check_picture(picture)
        if not simulate and (start is not None or goal is not None or tour):
            raise InputError("--from, --to and --tour choose the rooms of --simulate: add --simulate")
        if simulate and (start is None or (goal is None) == (not tour)):
            raise InputError("--simulate needs --from ROOM and either --to ROOM or --tour")
        dec = decompose_rooms(_load(env, env_format))
        if not simulate:
            if picture is not None:
                save_figure(render_rooms(dec), picture)
            emit(dec, fmt, out)
            return
        from solverplan.studies.rooms import RULES, compare_rules

        assert start is not None
        walk = dec.tour(start) if tour else dec.path(start, dec.check_room(goal))
        names = RULES if rule is RoomRule.ALL else (rule.value,)
        answer = compare_rules(dec, start, walk[-1], rules=names, trials=trials, seed=seed, max_bounces=max_bounces,
                               doors=doors.value, per_room=per_room, walk=walk, keep=1 if picture is not None else 0)
        if picture is not None:
            save_figure(render_rooms(dec, {name: r.trajectories[0] for name, r in answer.runs.items() if r.trajectories}), picture)
        emit(answer if rule is RoomRule.ALL else answer.runs[rule.value], fmt, out)


# ---------------------------------------------------------------------- online exploration with discrete views
class ZChoice(StrEnum):
    FIRST = "first"
    RANDOM = "random"
    FAR = "far"


def _xy(text: str, option: str) -> tuple:
    """``X,Y`` as an exact point; bad text is one line naming the option."""
    from solverplan.exact import to_fraction

    parts = text.split(",")
    if len(parts) != 2:
        raise InputError(f"{option} {text!r}: expected X,Y (two numbers separated by a comma)")
    return tuple(to_fraction(part.strip(), where=option) for part in parts)


@app.command(name="explore")
def explore_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--start", metavar="X,Y", help="The robot's start p1, a point of the free space.")],
    choice: Annotated[ZChoice, typer.Option("--choice", help="Which unexplored constructed edge the next view is taken on: first, random (with --seed) or far.")] = ZChoice.FIRST,
    seed: Annotated[int | None, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Seed of --choice random (default 0).", show_default=False)] = None,
    range_: Annotated[str | None, typer.Option("--range", metavar="R", help="Sensing range R > 0: range-limited views and Algorithm B (Algorithm A when R reaches across the polygon).", show_default=False)] = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Explore an unknown polygon with discrete views (Ghosh et al.): Algorithm A (at most r + 1 views), or with
    --range R Algorithm B (at most Lemma 4's bound)."""
    from solverplan.explore import Exploration, RangeExploration, explore_depth_first, explore_range_limited

    with exit_codes(verbose):
        _check_picture(picture)
        environment = _load(env, env_format)
        run: Exploration | RangeExploration
        if range_ is None:
            run = explore_depth_first(environment, _xy(start, "--start"), choice=choice.value, seed=seed)
        else:
            run = explore_range_limited(environment, _xy(start, "--start"), range_, choice=choice.value, seed=seed)
        if picture is not None:
            from solverplan.render import save_figure
            from solverplan.render.explore import render_exploration

            save_figure(render_exploration(run, environment), picture)
        emit(run, fmt, out)


# ---------------------------------------------------------------------- the wall-following robot
class Comparisons(StrEnum):
    PAIRWISE = "pairwise"
    SORT = "sort"


class PursuitSensor(StrEnum):
    GAP = "gap"
    BITANGENT = "bitangent"
    PEBBLE = "pebble"
    CONTACT = "contact"


def _pair(text: str | None, name: str) -> tuple[str, str] | None:
    """``"X,Y"`` → two number strings (read exactly by the library), or ``None``."""
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise InputError(f"{name} must be two numbers X,Y, got {text!r}")
    return parts[0].strip(), parts[1].strip()


@app.command(name="wallfollow")
def wallfollow_command(
    env: EnvArg,
    cut_ordering: Annotated[bool, typer.Option("--cut-ordering", help="The exact geometric cut ordering (the default).")] = False,
    learn: Annotated[bool, typer.Option("--learn", help="The cut ordering learned by Strategy 1 from sensing alone, with its action and memory counts.")] = False,
    count: Annotated[bool, typer.Option("--count", help="n and the winding number by the counting filter, from a seeded random walk.")] = False,
    start: Annotated[str | None, typer.Option("--start", metavar="X,Y", help="The robot's start point (default vertex 0).", show_default=False)] = None,
    heading: Annotated[str | None, typer.Option("--heading", metavar="DX,DY", help="Direction INIT drives in from an interior start (default 1,0).", show_default=False)] = None,
    comparisons: Annotated[Comparisons, typer.Option("--comparisons", help="With --learn: compare every pair of end points on an edge (the paper) or merge-sort them.")] = Comparisons.PAIRWISE,
    transcript: Annotated[bool, typer.Option("--transcript", help="With --learn: include every action and observation.")] = False,
    steps: Annotated[int, typer.Option("--steps", min=0, max=10_000_000, metavar="K", help="With --count: follows of the random walk (at most 10,000,000).")] = 1000,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="With --count: seed of the random walk.")] = 0,
    pursuit: Annotated[bool, typer.Option("--pursuit", help="A shortest pursuit-evasion plan, replayed by the geometric ground-truth checker.")] = False,
    sensor: Annotated[PursuitSensor, typer.Option("--sensor", help="With --pursuit: the pursuer's extra sensor (gap: Strategy 2; bitangent: Strategy 3; pebble: Strategies 4–5, pebble visibility; contact: Strategy 6, touch and pebble only).")] = PursuitSensor.GAP,
    origin: Annotated[str, typer.Option("--from", metavar="POINT", help="With --pursuit: the pursuer's start, a point of the cut ordering (v0, r3).")] = "v0",
    max_states: Annotated[int, typer.Option("--max-states", min=1, max=10_000_000, metavar="N", help="With --pursuit: cap on the derived I-states searched.")] = 200_000,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """The wall-following robot (Yershova et al.): cut ordering, Strategy 1, vertex counting, pursuit-evasion."""
    from solverplan.wallfollow.cuts import cut_ordering as exact_cut_ordering
    from solverplan.wallfollow.filters import count_random_walk
    from solverplan.wallfollow.learning import learn_cut_ordering

    with exit_codes(verbose):
        if cut_ordering + learn + count + pursuit > 1:
            raise InputError("choose one of --cut-ordering, --learn, --count and --pursuit")
        if not pursuit and (sensor is not PursuitSensor.GAP or origin != "v0" or max_states != 200_000):
            raise InputError("--sensor, --from and --max-states belong to --pursuit")
        if not learn and (transcript or comparisons is not Comparisons.PAIRWISE):
            raise InputError("--comparisons and --transcript belong to --learn")
        if not (learn or count) and (start is not None or heading is not None):
            raise InputError("--start and --heading place the robot of --learn or --count")
        if not count and (steps != 1000 or seed != 0):
            raise InputError("--steps and --seed belong to --count")
        _check_picture(picture)
        environment = _load(env, env_format)
        where, towards = _pair(start, "--start"), _pair(heading or "1,0", "--heading")
        assert towards is not None
        if learn:
            answer: Any = learn_cut_ordering(environment, where, towards, comparisons=comparisons.value,
                                             transcript=transcript)
        elif count:
            answer = count_random_walk(environment, steps, seed, where, towards)
        elif pursuit:
            from solverplan.wallfollow.pursuit import pursuit_plan

            answer = pursuit_plan(environment, sensor=sensor.value, start=origin, max_states=max_states)
        else:
            answer = exact_cut_ordering(environment)
        if picture is not None:
            from solverplan.render import save_figure
            from solverplan.render.wallfollow import render_cuts, render_pursuit

            save_figure(render_pursuit(environment, answer) if pursuit else
                        render_cuts(environment, answer.ordering.relabel(answer.pebble_vertex) if learn else None),
                        picture)
        emit(answer, fmt, out)


# ---------------------------------------------------------------------- floor plans in
class PlanInputFormat(StrEnum):
    ROS = "ros"
    DXF = "dxf"
    SVG = "svg"


@app.command(name="import")
def import_command(
    plan: Annotated[Path, typer.Argument(metavar="FILE", help="A ROS map (MAP.yaml with its PGM/PNG image), PLAN.dxf or PLAN.svg.", show_default=False)],
    output: Annotated[Path, typer.Option("-o", "--output", metavar="ENV", help="Environment file to write (atomically; .json, .geojson or .wkt).", show_default=False)],
    seed_point: Annotated[str | None, typer.Option("--seed-point", metavar="X,Y", help="Maps: keep the free-space component holding this world point (metres); default the largest.", show_default=False)] = None,
    simplify: Annotated[float | None, typer.Option("--simplify", metavar="M", help="Topology-preserving simplification tolerance (metres; maps default half a cell, drawings 0).", show_default=False)] = None,
    min_hole_area: Annotated[float | None, typer.Option("--min-hole-area", metavar="M2", help="Drop holes and speckle smaller than this (m²; maps default 9 cells, drawings 0).", show_default=False)] = None,
    spur_width: Annotated[float | None, typer.Option("--spur-width", metavar="M", help="Maps: cut free protrusions narrower than this (metres; default 2 cells, 0 keeps them).", show_default=False)] = None,
    rectilinear: Annotated[float, typer.Option("--rectilinear", metavar="DEG", help="Snap edges within DEG degrees of an axis to it (0: off).")] = 0.0,
    layer: Annotated[str | None, typer.Option("--layer", metavar="NAME", help="DXF: read only this layer.", show_default=False)] = None,
    units: Annotated[str | None, typer.Option("--units", metavar="UNIT", help="DXF: drawing unit (m, cm, mm, in, ft, ..., unitless), overriding $INSUNITS.", show_default=False)] = None,
    scale: Annotated[str, typer.Option("--scale", metavar="S", help="SVG: metres per SVG user unit.")] = "1",
    tolerance: Annotated[float | None, typer.Option("--tolerance", metavar="M", help="DXF/SVG: largest distance between a curve and its chords (output units; default 0.01).", show_default=False)] = None,
    input_format: Annotated[PlanInputFormat | None, typer.Option("--input-format", help="ros, dxf or svg, when the extension does not say.", show_default=False)] = None,
    fmt: FormatOpt = OutputFormat.JSON,
    verbose: VerboseOpt = 0,
) -> None:
    """Real floor plans in: a ROS occupancy map, DXF or SVG drawing to an environment file (summary on stdout)."""
    from solverplan.floorplan import import_floorplan

    with exit_codes(verbose):
        point = _pair(seed_point, "--seed-point")
        answer = import_floorplan(plan, output=output, fmt=input_format.value if input_format else None,
                                  seed_point=point, simplify=simplify, min_hole_area=min_hole_area,
                                  spur_width=spur_width, rectilinear=rectilinear, layer=layer, units=units,
                                  scale=scale, tolerance=tolerance)
        emit(answer, fmt, None)


# ---------------------------------------------------------------------- generate (random environments)
generate_app = typer.Typer(
    name="generate", cls=_Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
    help="Random valid environments (seeded): prints the environment file, or writes it with -o (.json, .geojson, .wkt).",
)
app.add_typer(generate_app, name="generate")

SeedOpt = Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed: the same seed gives the same environment.")]
EnvOutOpt = Annotated[
    Path | None,
    typer.Option("-o", "--output", help="Write the environment file atomically (format by extension: .json, .geojson, .wkt).", show_default=False),
]


def _emit_generated(make: Any, fmt: OutputFormat, out: Path | None, verbose: int, **params: Any) -> None:
    from solverplan.studies.generators import GeneratedEnvironment

    with exit_codes(verbose):
        for key, value in params.items():  # lengths: the coordinates they make must stay readable
            if isinstance(value, float) and abs(value) > MAX_COORDINATE:
                raise InputError(f"--{key.replace('_', '-')} {value:g} is larger than 1e100 in magnitude")
        answer = GeneratedEnvironment(make(**params))
        if out is not None:
            answer.save(out)
            logger.info("wrote %s", out)
        else:
            emit(answer, fmt, None)


@generate_app.command("star")
def generate_star(
    n: Annotated[int, typer.Option("--n", min=3, max=MAX_GENERATED_VERTICES, help="Number of vertices.")] = 20,
    irregularity: Annotated[float, typer.Option("--irregularity", min=0.0, max=1.0, help="Spread of the angle steps (fraction of 2π/n).")] = 0.3,
    spikiness: Annotated[float, typer.Option("--spikiness", min=0.0, max=1.0, help="Spread of the radii (fraction of the radius).")] = 0.3,
    radius: Annotated[float, typer.Option("--radius", help="Mean distance of the vertices from the origin.")] = 1.0,
    seed: SeedOpt = 0,
    fmt: FormatOpt = OutputFormat.JSON,
    out: EnvOutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A random star polygon (the paper's §7.3 family, irregularity scaled)."""
    from solverplan.studies.generators import star_polygon

    _emit_generated(star_polygon, fmt, out, verbose, n=n, irregularity=irregularity, spikiness=spikiness, radius=radius, seed=seed)


@generate_app.command("holes")
def generate_holes(
    n: Annotated[int, typer.Option("--n", min=3, max=MAX_GENERATED_VERTICES, help="Vertices of the outer ring.")] = 20,
    holes: Annotated[int, typer.Option("--holes", min=0, max=MAX_ROOMS, help="Number of holes.")] = 2,
    hole_vertices: Annotated[int, typer.Option("--hole-vertices", min=3, max=MAX_GENERATED_VERTICES, help="Vertices per hole.")] = 6,
    hole_kind: Annotated[str, typer.Option("--hole-kind", help="convex or star.")] = "convex",
    irregularity: Annotated[float, typer.Option("--irregularity", min=0.0, max=1.0)] = 0.2,
    spikiness: Annotated[float, typer.Option("--spikiness", min=0.0, max=1.0)] = 0.15,
    seed: SeedOpt = 0,
    fmt: FormatOpt = OutputFormat.JSON,
    out: EnvOutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A random star polygon with small holes strictly inside."""
    from solverplan.studies.generators import star_polygon_with_holes

    _emit_generated(star_polygon_with_holes, fmt, out, verbose, n=n, n_holes=holes, hole_vertices=hole_vertices,
                    hole_kind=hole_kind, irregularity=irregularity, spikiness=spikiness, seed=seed)


@generate_app.command("rooms")
def generate_rooms(
    rooms: Annotated[int, typer.Option("--rooms", min=1, max=MAX_ROOMS, help="Number of rooms.")] = 5,
    loops: Annotated[int, typer.Option("--loops", min=0, max=MAX_ROOMS, help="Extra corridors closing loops (one hole each).")] = 0,
    room_size: Annotated[float, typer.Option("--room-size", help="Room diameter.")] = 4.0,
    spacing: Annotated[float, typer.Option("--spacing", help="Distance between neighbouring rooms (>= 1.6 room size).")] = 10.0,
    corridor_width: Annotated[float, typer.Option("--corridor-width", help="Corridor width (< room size / 3).")] = 1.0,
    seed: SeedOpt = 0,
    fmt: FormatOpt = OutputFormat.JSON,
    out: EnvOutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Convex rooms on a jittered grid joined by straight corridors (an office-like environment)."""
    from solverplan.studies.generators import rooms_and_corridors

    _emit_generated(rooms_and_corridors, fmt, out, verbose, n_rooms=rooms, loops=loops, room_size=room_size,
                    spacing=spacing, corridor_width=corridor_width, seed=seed)


@generate_app.command("rectilinear")
def generate_rectilinear(
    rooms: Annotated[int, typer.Option("--rooms", min=1, max=MAX_ROOMS, help="Number of rooms.")] = 4,
    width: Annotated[int | None, typer.Option("--width", min=1, max=MAX_GENERATED_VERTICES, help="Building width (default grows with the rooms).", show_default=False)] = None,
    height: Annotated[int | None, typer.Option("--height", min=1, max=MAX_GENERATED_VERTICES, help="Building height.", show_default=False)] = None,
    wall: Annotated[int, typer.Option("--wall", min=1, max=MAX_COUNT, help="Wall thickness.")] = 1,
    door: Annotated[int, typer.Option("--door", min=1, max=MAX_COUNT, help="Door width.")] = 2,
    min_room: Annotated[int, typer.Option("--min-room", min=1, max=MAX_COUNT, help="Smallest room width (>= door + 2).")] = 4,
    pillars: Annotated[int, typer.Option("--pillars", min=0, max=MAX_ROOMS, help="Square pillars (holes), one per room at most.")] = 0,
    seed: SeedOpt = 0,
    fmt: FormatOpt = OutputFormat.JSON,
    out: EnvOutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A rectangular building split into rooms by walls with doors (integer coordinates)."""
    from solverplan.studies.generators import rectilinear_floor_plan

    _emit_generated(rectilinear_floor_plan, fmt, out, verbose, n_rooms=rooms, width=width, height=height, wall=wall,
                    door=door, min_room=min_room, pillars=pillars, seed=seed)


@generate_app.command("polyomino")
def generate_polyomino(
    cells: Annotated[int, typer.Option("--cells", min=1, max=MAX_ROOMS, help="Number of grid cells (1,000 take seconds).")] = 12,
    max_size: Annotated[int, typer.Option("--max-size", min=1, max=MAX_COUNT, help="Largest cell width or height.")] = 6,
    seed: SeedOpt = 0,
    fmt: FormatOpt = OutputFormat.JSON,
    out: EnvOutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """A random simple rectilinear polygon without holes (grid cells of random sizes; integer coordinates)."""
    from solverplan.studies.generators import rectilinear_polygon

    _emit_generated(rectilinear_polygon, fmt, out, verbose, n_cells=cells, max_size=max_size, seed=seed)


# ---------------------------------------------------------------------- study (batch experiments)
study_app = typer.Typer(
    name="study", cls=_Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
    help="Batch studies over random environments (paper §7.3-7.4, §8.2): tables (CSV, JSON) and heatmaps; resumable.",
)
app.add_typer(study_app, name="study")


class GeneratorName(StrEnum):
    STAR = "star"
    HOLES = "holes"
    ROOMS = "rooms"
    RECTILINEAR = "rectilinear"


GeneratorOpt = Annotated[GeneratorName, typer.Option("--generator", help="The random environments.")]
GridOpt = Annotated[
    list[str] | None,
    typer.Option("--grid", metavar="NAME=VALUES", show_default=False,
                 help="A generator parameter: one value (20), a list (0.1,0.3) or START:STOP:COUNT (0.1:0.4:5); repeatable. "
                      "Default for star: the paper's n=20, irregularity=0.1:0.4:5, spikiness=0.1:0.5:5."),
]
PerCellOpt = Annotated[int, typer.Option("--per-cell", min=1, max=MAX_COUNT, metavar="N", help="Environments per grid cell.")]
StudySeedOpt = Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Base seed (each row's seed derives from it).")]
OutDirOpt = Annotated[
    Path | None,
    typer.Option("--out-dir", metavar="DIR", show_default=False,
                 help="Folder of NAME.jsonl (rows, written as they finish), NAME.csv, NAME.json, NAME.png (default ./NAME-study)."),
]
WorkersOpt = Annotated[
    int | None, typer.Option("--workers", min=1, max=MAX_COUNT, metavar="N", show_default=False, help="Local worker processes (default: the CPU count).")
]
SchedulerOpt = Annotated[
    str | None, typer.Option("--scheduler", metavar="ADDRESS", show_default=False, help="Run on this Dask scheduler (tcp://host:8786).")
]
FreshOpt = Annotated[bool, typer.Option("--fresh", help="Start over instead of resuming the rows already in --out-dir.")]
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar (there is none when stderr is not a terminal).")]
FigureOpt = Annotated[bool, typer.Option("--figure/--no-figure", help="Draw the heatmaps to DIR/NAME.png.")]


@contextlib.contextmanager
def _progress_bar(description: str, quiet: bool) -> Iterator[Any]:
    """A rich progress bar on stderr (never stdout), or None when quiet or stderr is not a terminal."""
    if quiet or not sys.stderr.isatty():
        yield None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True)) as bar:
        task = bar.add_task(description, total=None)
        yield lambda done, total: bar.update(task, completed=done, total=total)


def _study(name: str, generator: GeneratorName, grid: list[str] | None, per_cell: int, seed: int, out_dir: Path | None,
           workers: int | None, scheduler: str | None, fresh: bool, quiet: bool, figure: bool, fmt: OutputFormat,
           out: Path | None, verbose: int, **options: Any) -> None:
    from solverplan.studies import StudyInterrupted, build_study, run_study
    from solverplan.studies.execute import output_paths

    with exit_codes(verbose):
        study = build_study(name, generator=generator.value, grid=grid or (), per_cell=per_cell, seed=seed, **options)
        folder = out_dir if out_dir is not None else Path(f"{study.name}-study")
        try:
            with _progress_bar(f"study {study.name}", quiet) as progress:
                result = run_study(study, folder, workers=workers, scheduler=scheduler, resume=not fresh, progress=progress)
        except StudyInterrupted as exc:
            raise _fail(str(exc), 130) from None
        if figure:
            from solverplan.render import render_heatmaps, save_figure

            path = output_paths(study, folder)["figure"]
            save_figure(render_heatmaps(result.table.heatmaps(), title=result.figure_title(),
                                        columns=result.table.panel_columns()), path)
            result = result.with_file("figure", path)
        emit(result, fmt, out)


@study_app.command("reachability")
def study_reachability(
    generator: GeneratorOpt = GeneratorName.STAR, grid: GridOpt = None, per_cell: PerCellOpt = 10, seed: StudySeedOpt = 0,
    out_dir: OutDirOpt = None, workers: WorkersOpt = None, scheduler: SchedulerOpt = None, fresh: FreshOpt = False,
    quiet: QuietOpt = False, figure: FigureOpt = True, fmt: FormatOpt = OutputFormat.JSON, out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Share of the boundary no safe action reaches (safe-BVG nodes without incoming arcs; paper Fig. 15)."""
    _study("reachability", generator, grid, per_cell, seed, out_dir, workers, scheduler, fresh, quiet, figure, fmt, out, verbose)


@study_app.command("connectivity")
def study_connectivity(
    generator: GeneratorOpt = GeneratorName.STAR, grid: GridOpt = None, per_cell: PerCellOpt = 10, seed: StudySeedOpt = 0,
    out_dir: OutDirOpt = None, workers: WorkersOpt = None, scheduler: SchedulerOpt = None, fresh: FreshOpt = False,
    quiet: QuietOpt = False, figure: FigureOpt = True, fmt: FormatOpt = OutputFormat.JSON, out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Strongly and weakly connected components of the safe BVG (paper Fig. 16)."""
    _study("connectivity", generator, grid, per_cell, seed, out_dir, workers, scheduler, fresh, quiet, figure, fmt, out, verbose)


@study_app.command("rules")
def study_rules(
    rules: Annotated[
        str, typer.Option("--rules", metavar="F1,F2,...", help="Rule families: any, fixed, monotone, relative, specular, or one rule "
                          "such as fixed:pi/4.")
    ] = "any,fixed,monotone,relative,specular",
    family_size: Annotated[int, typer.Option("--family-size", min=1, max=MAX_COUNT, metavar="M", help="Parameters per family: θ = kπ/(M+1).")] = 5,
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="K", help="Simulated robots per environment and family.")] = 200,
    bounces: Annotated[int, typer.Option("--bounces", min=2, max=MAX_BOUNCES, metavar="B", help="Bounces per simulated robot.")] = 50,
    generator: GeneratorOpt = GeneratorName.STAR, grid: GridOpt = None, per_cell: PerCellOpt = 10, seed: StudySeedOpt = 0,
    out_dir: OutDirOpt = None, workers: WorkersOpt = None, scheduler: SchedulerOpt = None, fresh: FreshOpt = False,
    quiet: QuietOpt = False, figure: FigureOpt = True, fmt: FormatOpt = OutputFormat.JSON, out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Compare bounce-rule families by the reachability of the systems they induce (paper §8.2; see rule_systems)."""
    families = [f for f in (part.strip() for part in rules.split(",")) if f]
    _study("rules", generator, grid, per_cell, seed, out_dir, workers, scheduler, fresh, quiet, figure, fmt, out, verbose,
           families=families, family_size=family_size, trials=trials, bounces=bounces)


# ---------------------------------------------------------------------- report (a self-contained HTML page of an answer)
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
    from solverplan.render.report import html_report, load_answer, write_report

    with exit_codes(verbose):
        given = [(name, path) for name, path in (("plan", plan_file), ("patrol", patrol_file), ("funnel", funnel_file),
                                                 ("cycle", cycle_file), ("study", study_file)) if path is not None]
        if len(given) != 1:
            raise InputError("give exactly one answer: --plan, --patrol, --funnel, --cycle or --study")
        if out.suffix.lower() not in (".html", ".htm"):
            raise InputError(f"-o {out}: a report is an .html file: give -o REPORT.html")
        option, path = given[0]
        answer = load_answer(path, option=option)
        environment = _load(env, env_format) if env is not None else None
        cert = None
        if certificate is not None:
            from solverplan.certify.schema import load_certificate

            cert = load_certificate(certificate)
        page = html_report(answer, environment, certificate=cert, certificate_path=str(certificate) if certificate else None,
                           env_label=str(env) if env is not None else None, output=str(out))
        saved = write_report(page, out)
        emit(saved, fmt, None)
    if page.certificate is not None and not page.certificate["valid"]:
        raise _fail(f"certificate invalid: {page.certificate['failures'][0]} (the report {out} shows every failure)", 1)


# ---------------------------------------------------------------------- composed potential fields with reflection
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
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """Composed local potential fields in convex cells, with reflection (Stager and Tanner): cells, sequence, reflection cells and scenario statistics."""
    from solverplan.reflection.navigation import navigate_fields

    with exit_codes(verbose):
        _check_picture(picture)
        environment = _load(env, env_format)
        names = ("constrained", "unconstrained", "reflection") if scenario is FieldScenario.ALL else (scenario.value,)
        if trajectories is None:  # a picture without runs shows empty corridors: draw a few by default
            trajectories = min(5, trials) if picture is not None else 0
        answer = navigate_fields(environment, _xy(start, "--from"), _xy(goal, "--to"), scenarios=names,
                                 model=model.value, trials=trials, seed=seed, trajectories=trajectories, arcs=arcs,
                                 fast=fast, slow=slow)
        if picture is not None:
            from solverplan.render import save_figure
            from solverplan.render.fields import render_fields

            save_figure(render_fields(answer), picture)
        emit(answer, fmt, out)


def _terminate(signum: int, frame: Any) -> None:
    """SIGTERM unwinds like SIGINT, so output files half-written are removed (exit 128 + 15)."""
    raise SystemExit(128 + signum)


# ---------------------------------------------------------------------- cache (the safe-BVG disk cache)
cache_app = typer.Typer(
    name="cache", cls=_Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
    help="The disk cache of safe BVGs (the folder of the global --graph-cache option): its size, or empty it.",
)
app.add_typer(cache_app, name="cache")


def _cache_folder() -> Path:
    from solverplan.bounce import bvg

    folder = bvg.graph_cache_directory()
    if folder is None:
        raise InputError("the graph cache is off (--graph-cache off or SOLVERPLAN_GRAPH_CACHE=off): "
                         "name its folder, e.g. 'solverplan --graph-cache DIR cache clear'")
    return folder


@cache_app.command(name="info")
def cache_info_command(fmt: FormatOpt = OutputFormat.JSON, out: OutOpt = None, verbose: VerboseOpt = 0) -> None:
    """The graph cache's folder, its entries and bytes, its size cap and write threshold."""
    from solverplan.bounce import bvg

    with exit_codes(verbose):
        emit(bvg.graph_cache_report(_cache_folder()), fmt, out)


@cache_app.command(name="clear")
def cache_clear_command(fmt: FormatOpt = OutputFormat.JSON, out: OutOpt = None, verbose: VerboseOpt = 0) -> None:
    """Remove every graph of the cache (its own files only: nothing else in the folder is touched)."""
    from solverplan.bounce import bvg

    with exit_codes(verbose):
        emit(bvg.purge_graph_cache(_cache_folder()), fmt, out)


def main() -> None:
    """Console-script entry point (``solverplan = "solverplan.cli:main"``)."""
    signal.signal(signal.SIGTERM, _terminate)
    # A command builds large acyclic structures (10⁵–10⁶ arcs, their answers) and exits: with the default
    # thresholds the cyclic collector rescans the growing heap again and again (≈ 40 % of a big graph's build).
    # Collect young objects rarely; the structures have no cycles, and the process is short-lived.
    gc.freeze()
    gc.set_threshold(200_000, 50, 50)
    app()
