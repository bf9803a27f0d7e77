"""``import``: floor plans in (ROS maps, DXF and SVG drawings)."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from solverplan.cli._app import FormatOpt, VerboseOpt, app
from solverplan.cli._errors import exit_codes
from solverplan.cli._options import parse_pair
from solverplan.cli._output import OutputFormat, emit


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
        point = parse_pair(seed_point, "--seed-point")
        answer = import_floorplan(plan, output=output, fmt=input_format.value if input_format else None,
                                  seed_point=point, simplify=simplify, min_hole_area=min_hole_area,
                                  spur_width=spur_width, rectilinear=rectilinear, layer=layer, units=units,
                                  scale=scale, tolerance=tolerance)
        emit(answer, fmt, None)
