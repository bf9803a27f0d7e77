"""The click command behind the ``solverplan`` typer app, for sphinx-click (the CLI reference is generated)."""

from __future__ import annotations

import typer

from solverplan.cli import app

command = typer.main.get_command(app)
