"""cli/_options.py: the options commands end with are written once (``_COMMON``) and given to a command as one value."""

from __future__ import annotations

from typing import Annotated

import pytest
import typer
import typer.main
from typer.testing import CliRunner

from solverplan.cli import app
from solverplan.cli._options import _COMMON, CommonOptions, common_options
from solverplan.cli._output import OutputFormat


def _toy_app() -> tuple[typer.Typer, list[CommonOptions]]:
    seen: list[CommonOptions] = []
    toy = typer.Typer(add_completion=False)

    @toy.command()
    @common_options("verbose", "fmt", "out")  # listed in any order: --help follows _COMMON's
    def toy_command(
        name: Annotated[str, typer.Argument(help="A name.")],
        times: Annotated[int, typer.Option("--times", help="How often.")] = 1,
        *,
        common: CommonOptions,
    ) -> None:
        """A toy command."""
        seen.append(common)
        typer.echo(f"{name} {times}")

    return toy, seen


def test_a_command_takes_its_own_options_then_the_common_ones_in_table_order():
    toy, seen = _toy_app()
    command = typer.main.get_command(toy)
    assert [p.name for p in command.params] == ["name", "times", "fmt", "out", "verbose"]
    result = CliRunner().invoke(toy, ["ada", "--times", "2", "--format", "text", "-vv"])
    assert result.exit_code == 0 and result.output == "ada 2\n"
    assert seen == [CommonOptions(fmt=OutputFormat.TEXT, out=None, verbose=2)]


def test_an_unknown_common_option_is_refused_where_it_is_written():
    with pytest.raises(ValueError, match="common options"):
        common_options("fmt", "colour")
    with pytest.raises(ValueError, match="own types"):
        common_options("fmt", out=(int, 0))


def _commands(group, path=(), *, groups=False):
    for name, command in sorted(group.commands.items()):
        if hasattr(command, "commands"):
            if groups:
                yield (*path, name), command
            yield from _commands(command, (*path, name), groups=groups)
        else:
            yield (*path, name), command


@pytest.mark.parametrize("path,command", list(_commands(typer.main.get_command(app))), ids=lambda v: " ".join(v) if isinstance(v, tuple) else "")
def test_every_command_ends_with_its_common_options_in_one_order(path, command):
    """What users read in every --help: -v last, --format before -o, --env-format before them (_COMMON's order)."""
    names = [p.name for p in command.params]
    common = [name for name in names if name in _COMMON and name not in ("out", "certificate")]  # own -o/--certificate: report, render, plan, export
    assert common == sorted(common, key=list(_COMMON).index), f"{' '.join(path)}: {names}"
    assert names[-1] == "verbose", f"{' '.join(path)}: -v is not last"


@pytest.mark.parametrize("path,command", list(_commands(typer.main.get_command(app), groups=True)),
                         ids=lambda v: " ".join(v) if isinstance(v, tuple) else "")
def test_no_summary_in_a_command_list_is_cut_inside_parentheses(path, command):
    """click ends a command's summary at its first word ending in a period: 'A funnel (paper Fig.' was all
    ``solverplan --help`` showed of funnel. Summaries spell such references out ('Figure 14')."""
    summary = command.get_short_help_str(limit=10_000)
    assert summary.count("(") == summary.count(")"), f"{' '.join(path)}: {summary!r}"
