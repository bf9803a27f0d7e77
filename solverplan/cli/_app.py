"""The ``solverplan`` app and its global options (JSON layout, graph cache, memory limit, processes)."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Iterator

import typer

from solverplan.cli._errors import Shell, exit_codes
from solverplan.limits import MAX_INDENT
from solverplan.cli._output import EnvFormat, OutputFormat, set_json_indent
from solverplan.cli._progress import command_progress

if TYPE_CHECKING:  # numpy comes with the environment: only commands that read one pay for it
    from solverplan.environment import Environment


app = typer.Typer(
    rich_markup_mode=None,  # plain help: typer's rich help imports rich and markdown-it (≈ 0.1 s of every start)
    name="solverplan",
    cls=Shell,
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


VersionOpt = Annotated[bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version and exit.")]
IndentOpt = Annotated[int | None, typer.Option("--indent", metavar="N", min=0, max=MAX_INDENT, show_default=False, help="Indent JSON answers by N spaces per level (at most 16), however large (default: 2 up to 512 KiB, then compact).")]
CompactOpt = Annotated[bool, typer.Option("--compact", help="Print JSON answers on one line, however small (fastest for large answers).")]
GraphCacheOpt = Annotated[str | None, typer.Option("--graph-cache", metavar="DIR", envvar="SOLVERPLAN_GRAPH_CACHE", show_default=False, help="Keep large safe BVGs in DIR and reuse them, integrity-checked ('off': never; default: $XDG_CACHE_HOME/solverplan/graphs).")]
GraphCacheMinArcsOpt = Annotated[int | None, typer.Option("--graph-cache-min-arcs", metavar="N", min=0, envvar="SOLVERPLAN_GRAPH_CACHE_MIN_ARCS", show_default=False, help="Write only graphs of at least N arcs to the graph cache (default 100000; 0: every graph).")]
GraphCacheSizeOpt = Annotated[str | None, typer.Option("--graph-cache-size", metavar="SIZE", envvar="SOLVERPLAN_GRAPH_CACHE_SIZE", show_default=False, help="Cap the graph cache at SIZE bytes (e.g. 500M; default 2G): least recently used graphs go first.")]
MaxMemoryOpt = Annotated[str | None, typer.Option("--max-memory", metavar="SIZE", envvar="SOLVERPLAN_MAX_MEMORY", show_default=False, help="Refuse up front a job (a safe BVG, rollouts, a patrol search) estimated to need more than SIZE bytes (e.g. 2G, 500M; default: half the memory available).")]
JobsOpt = Annotated[int | None, typer.Option("--jobs", metavar="N", min=1, max=1024, envvar="SOLVERPLAN_JOBS", show_default=False, help="Processes a large job may use at once (default: the cores available; 1: this process only). Answers do not depend on it.")]
QuietOpt = Annotated[bool, typer.Option("--quiet", help="No progress bar on stderr (jobs over 2 s show one when stderr is a terminal).")]


@app.callback()
def _root(
    ctx: typer.Context,
    show_version: VersionOpt = False,
    indent: IndentOpt = None,
    compact: CompactOpt = False,
    graph_cache: GraphCacheOpt = None,
    graph_cache_min_arcs: GraphCacheMinArcsOpt = None,
    graph_cache_size: GraphCacheSizeOpt = None,
    max_memory: MaxMemoryOpt = None,
    jobs: JobsOpt = None,
    quiet: QuietOpt = False,
) -> None:
    """Planning with proofs for minimal bouncing robots in polygonal environments."""
    from solverplan.runtime import DEFAULT_MAX_BYTES, DEFAULT_MIN_ARCS, config, default_cache_directory

    if compact and indent is not None:
        raise typer.BadParameter("give --indent or --compact, not both", param_hint="'--indent'")
    cache = default_cache_directory() if graph_cache is None else None if graph_cache in ("", "off") else Path(graph_cache)
    changes: dict[str, Any] = {
        "graph_cache": cache,
        "graph_cache_min_arcs": DEFAULT_MIN_ARCS if graph_cache_min_arcs is None else graph_cache_min_arcs,
        "graph_cache_max_bytes": DEFAULT_MAX_BYTES if graph_cache_size is None else parse_size(graph_cache_size, "--graph-cache-size"),
    }
    if max_memory is not None:
        changes["max_memory"] = parse_size(max_memory)
    if jobs is not None:
        changes["jobs"] = jobs
    # the layout, the settings and the --timeout clock belong to this one command line (tests run many in one process)
    from solverplan.cli._options import start_command_clock

    start_command_clock()
    set_json_indent(-1 if compact else indent)
    ctx.call_on_close(lambda: set_json_indent(None))
    ctx.with_resource(config(**changes))
    ctx.with_resource(command_progress(quiet))


def parse_size(text: str, option: str = "--max-memory") -> int:
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


def load_env(env: Path, env_format: EnvFormat | None, picture: Path | None = None) -> Environment:
    """The environment named on the command line (format from the extension unless given); a ``picture`` path
    (--picture) with an unknown extension is refused first."""
    from solverplan.environment import load_environment

    check_picture(picture)
    return load_environment(env, env_format.value if env_format else None)


@contextlib.contextmanager
def loaded(env: Path, env_format: EnvFormat | None, picture: Path | None = None, *,
           verbose: int = 0) -> Iterator[Environment]:
    """Run a command body on the environment named on the command line: :func:`load_env` inside
    :func:`~solverplan.cli._errors.exit_codes`, so a bad file, format or --picture path and every error of
    the body leave with one line and the exit code of docs/contract.md."""
    with exit_codes(verbose):
        yield load_env(env, env_format, picture)


def check_picture(picture: Path | None) -> None:
    """Reject a --picture path with an unknown extension before any work is done."""
    if picture is not None:
        from solverplan.render import figure_format

        figure_format(picture)
