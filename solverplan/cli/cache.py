"""``cache``: the disk cache of safe BVGs."""

from __future__ import annotations

from pathlib import Path

import typer

from solverplan.errors import InputError
from solverplan.cli._app import app
from solverplan.cli._errors import Shell
from solverplan.cli._options import CommonOptions, common_options


cache_app = typer.Typer(
    rich_markup_mode=None,  # plain help: typer's rich help imports rich and markdown-it (≈ 0.1 s of every start)
    name="cache", cls=Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
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
@common_options("fmt", "out", "verbose")
def cache_info_command(*, common: CommonOptions) -> None:
    """The graph cache's folder, its entries and bytes, its size cap and write threshold."""
    from solverplan.bounce import bvg

    with common.exit_codes():
        common.emit(bvg.graph_cache_report(_cache_folder()))


@cache_app.command(name="clear")
@common_options("fmt", "out", "verbose")
def cache_clear_command(*, common: CommonOptions) -> None:
    """Remove every graph of the cache (its own files only: nothing else in the folder is touched)."""
    from solverplan.bounce import bvg

    with common.exit_codes():
        common.emit(bvg.purge_graph_cache(_cache_folder()))
