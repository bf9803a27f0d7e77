"""``import``: floor plans in (ROS maps, DXF and SVG drawings)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from solverplan.choices import FloorplanFormat
from solverplan.cli._app import app, check_picture
from solverplan.cli._options import CommonOptions, common_options, parse_pair, save_picture
from solverplan.cli._output import emit


@app.command(name="import")
@common_options("picture", "fmt", "verbose")
def import_command(
    plan: Annotated[Path, typer.Argument(metavar="FILE", help="A ROS map (MAP.yaml with its PGM/PNG image), PLAN.dxf or PLAN.svg.", show_default=False)],
    output: Annotated[Path, typer.Option("-o", "--output", metavar="ENV", help="Environment file to write (atomically; .json, .geojson or .wkt).", show_default=False)],
    seed_point: Annotated[str | None, typer.Option("--seed-point", metavar="X,Y", help="Maps and DXF: keep the free space holding this point (metres); default the largest.", show_default=False)] = None,
    simplify: Annotated[float | None, typer.Option("--simplify", metavar="M", help="Topology-preserving simplification tolerance (metres; drawings default 0; maps default the walls' measured noise, inside the traced free space).", show_default=False)] = None,
    min_obstacle: Annotated[float | None, typer.Option("--min-obstacle", metavar="M", help="Drop obstacles whose larger side is below this (metres; maps default 0.06: a 5 cm cell, drawings 0); each is listed.", show_default=False)] = None,
    min_hole_area: Annotated[float | None, typer.Option("--min-hole-area", metavar="M2", help="Also drop holes and speckle smaller than this area (m²; default 0); each is listed.", show_default=False)] = None,
    spur_width: Annotated[float | None, typer.Option("--spur-width", metavar="M", help="Maps: cut free protrusions narrower than this (metres; default 2 cells, 0 keeps them).", show_default=False)] = None,
    rectilinear: Annotated[float | None, typer.Option("--rectilinear", metavar="DEG", help="Snap edges within DEG degrees of an axis to it (0: off; maps default 10 when 90 % of the walls are that close to an axis, drawings 0).", show_default=False)] = None,
    robot_radius: Annotated[str | None, typer.Option("--robot-radius", metavar="R", help="The robot's radius (metres): walls and obstacles inflated by it; what that closes or disconnects is listed.", show_default=False)] = None,
    keepout: Annotated[Path | None, typer.Option("--keepout", metavar="MASK.yaml", help="A Nav2 keepout mask (map YAML + image): its occupied cells are obstacles.", show_default=False)] = None,
    layer: Annotated[str | None, typer.Option("--layer", metavar="NAME", help="DXF: read only this layer (several: comma-separated).", show_default=False)] = None,
    units: Annotated[str | None, typer.Option("--units", metavar="UNIT", help="DXF: drawing unit (m, cm, mm, in, ft, ..., unitless), overriding $INSUNITS.", show_default=False)] = None,
    snap: Annotated[float | None, typer.Option("--snap", metavar="D", help="DXF: join line ends closer than D drawing units (default 1e-5 of the drawing's extent).", show_default=False)] = None,
    max_jamb: Annotated[float | None, typer.Option("--max-jamb", metavar="M", help="DXF: close wall bands left open at doors across at most M metres (default 0.5; 0: never).", show_default=False)] = None,
    scale: Annotated[str | None, typer.Option("--scale", metavar="S", help="SVG: metres per SVG user unit (default: from width/height with units, else 1).", show_default=False)] = None,
    tolerance: Annotated[float | None, typer.Option("--tolerance", metavar="M", help="DXF/SVG: largest distance between a curve and its chords (output units; default 0.01).", show_default=False)] = None,
    input_format: Annotated[FloorplanFormat | None, typer.Option("--input-format", help="ros, dxf or svg, when the extension does not say.", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Real floor plans in: a ROS occupancy map, DXF or SVG drawing to an environment file (summary on stdout)."""
    from solverplan.floorplan import import_floorplan

    with common.exit_codes():
        check_picture(common.picture)
        point = parse_pair(seed_point, "--seed-point")
        answer = import_floorplan(plan, output=output, fmt=input_format,
                                  seed_point=point, simplify=simplify, min_hole_area=min_hole_area,
                                  min_obstacle=min_obstacle, spur_width=spur_width, rectilinear=rectilinear,
                                  layer=layer, units=units, scale=scale, tolerance=tolerance, snap=snap,
                                  max_jamb=max_jamb, robot_radius=robot_radius, keepout=keepout)
        for warning in answer.warnings:
            typer.echo(f"warning: {warning}", err=True)
        save_picture(common.picture, "floorplan.render_import", answer)
        emit(answer, common.fmt, None)
