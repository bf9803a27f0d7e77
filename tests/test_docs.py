"""docs/contract.md covers the command line: every command, and every option of every command, is described."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import typer.main
from typer.core import TyperArgument, TyperGroup

from solverplan.cli import app

CONTRACT = (Path(__file__).resolve().parent.parent / "docs" / "contract.md").read_text(encoding="utf-8")


def _commands(group=None, path=()):
    group = group or typer.main.get_command(app)
    for name, command in sorted(group.commands.items()):
        if isinstance(command, TyperGroup):
            yield from _commands(command, (*path, name))
        else:
            yield (*path, name), command


COMMANDS = list(_commands())


@pytest.mark.parametrize("path,command", COMMANDS, ids=lambda v: " ".join(v) if isinstance(v, tuple) else "")
def test_every_command_and_option_is_in_the_contract(path, command):
    *group, name = path
    if group:  # `generate star|holes|...`: the group's section names its commands
        assert re.search(rf"`{' '.join(group)} [^`]*\b{name}\b", CONTRACT), f"{' '.join(path)} is not in docs/contract.md"
    else:
        assert f"`{name} " in CONTRACT or f"solverplan {name}" in CONTRACT, f"{name} is not in docs/contract.md"
    for param in command.params:
        if isinstance(param, TyperArgument) or param.name == "help":
            continue
        names = [*param.opts, *getattr(param, "secondary_opts", ())]
        assert any(f"`{o}" in CONTRACT or f" {o}" in CONTRACT for o in names), f"{' '.join(path)} {names[0]} is undocumented"


def test_the_contract_is_self_contained():
    for pattern in (r"\.\./shared", r"CONTRACT\.md", r"DESIGN", r"\bissue \d", r"note 000", r"\bseed 00\d"):
        assert not re.search(pattern, CONTRACT), pattern
    assert "## Statuses, optimality and stages" in CONTRACT and "## Exit codes" in CONTRACT
