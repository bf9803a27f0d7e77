"""``generate``: random valid environments."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.limits import MAX_COORDINATE, MAX_COUNT, MAX_GENERATED_VERTICES, MAX_ROOMS, MAX_SEED
from solverplan.errors import InputError
from solverplan.cli._app import FormatOpt, VerboseOpt, app
from solverplan.cli._errors import Shell, exit_codes
from solverplan.cli._output import OutputFormat, emit

logger = logging.getLogger(__name__)


generate_app = typer.Typer(
    rich_markup_mode=None,  # plain help: typer's rich help imports rich and markdown-it (≈ 0.1 s of every start)
    name="generate", cls=Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
    help="Random valid environments (seeded): prints the environment file, or writes it with -o (.json, .geojson, .wkt).",
)
app.add_typer(generate_app, name="generate")

SeedOpt = Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Random seed: the same seed gives the same environment.")]
EnvOutOpt = Annotated[
    Path | None,
    typer.Option("-o", "--output", help="Write the environment file atomically (format by extension: .json, .geojson, .wkt).", show_default=False),
]


def _emit_generated(make: Any, fmt: OutputFormat, out: Path | None, verbose: int, **params: Any) -> None:
    from solverplan.generators import GeneratedEnvironment

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
    from solverplan.generators import star_polygon

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
    from solverplan.generators import star_polygon_with_holes

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
    from solverplan.generators import rooms_and_corridors

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
    from solverplan.generators import rectilinear_floor_plan

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
    from solverplan.generators import rectilinear_polygon

    _emit_generated(rectilinear_polygon, fmt, out, verbose, n_cells=cells, max_size=max_size, seed=seed)
