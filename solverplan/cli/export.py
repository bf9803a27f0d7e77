"""``export``: plans out to robots (world coordinates: waypoints, CSV, GeoJSON)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from solverplan.choices import ExportFormat
from solverplan.cli._app import app
from solverplan.cli._options import CommonOptions, common_options


@app.command(name="export")
@common_options("env_format", "verbose")
def export_command(
    plan_file: Annotated[Path, typer.Argument(metavar="PLAN.json", help="A plan written by 'solverplan plan -o PLAN.json'.", show_default=False)],
    env: Annotated[str, typer.Option("--env", metavar="ENV", help="The plan's environment (file or shipped model).")],
    export_format: Annotated[ExportFormat, typer.Option("--format", help="waypoints (JSON poses in the map frame), csv (a row per contact) or geojson.")] = ExportFormat.WAYPOINTS,
    out: Annotated[Path | None, typer.Option("-o", "--output", metavar="FILE", help="Write the export atomically instead of printing it.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """A plan in world coordinates for a robot stack: contact ranges on the walls (metres), map-frame headings."""
    from solverplan._io import atomic_write_text
    from solverplan.plan.export import export_plan
    from solverplan.plan.result import load_plan

    with common.loaded(Path(env)) as environment:
        plan = load_plan(plan_file)
        text = export_plan(plan, environment, export_format.value)
        if out is not None:
            atomic_write_text(out, text)
        else:
            typer.echo(text, nl=False)
