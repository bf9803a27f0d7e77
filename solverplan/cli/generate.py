"""``generate``: random valid environments."""

from __future__ import annotations

import functools
import logging
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Callable

import typer

from solverplan.limits import MAX_COORDINATE, MAX_COUNT, MAX_GENERATED_VERTICES, MAX_ROOMS, MAX_SEED
from solverplan.errors import InputError
from solverplan.cli._app import app
from solverplan.cli._errors import Shell
from solverplan.cli._options import CommonOptions, common_options

if TYPE_CHECKING:
    from solverplan.environment import Environment

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


def _generator(command: Callable[..., Environment]) -> Callable[..., None]:
    """A ``generate`` command: ``command`` makes the environment from its own options, and this prints it or writes
    it with -o (:func:`~solverplan.cli._options.common_options` adds --format, -o and -v). Its lengths are checked
    first: the coordinates they make must stay readable."""

    @functools.wraps(command)
    def run(*, common: CommonOptions, **params: Any) -> None:
        from solverplan.generators import GeneratedEnvironment

        with common.exit_codes():
            for key, value in params.items():
                if isinstance(value, float) and abs(value) > MAX_COORDINATE:
                    raise InputError(f"--{key.replace('_', '-')} {value:g} is larger than 1e100 in magnitude")
            answer = GeneratedEnvironment(command(**params))
            if common.out is not None:
                answer.save(common.out)
                logger.info("wrote %s", common.out)
            else:
                common.emit(answer)

    return common_options("fmt", "out", "verbose", out=(EnvOutOpt, None))(run)


@generate_app.command("star")
@_generator
def generate_star(
    n: Annotated[int, typer.Option("--n", min=3, max=MAX_GENERATED_VERTICES, help="Number of vertices.")] = 20,
    irregularity: Annotated[float, typer.Option("--irregularity", min=0.0, max=1.0, help="Spread of the angle steps (fraction of 2π/n).")] = 0.3,
    spikiness: Annotated[float, typer.Option("--spikiness", min=0.0, max=1.0, help="Spread of the radii (fraction of the radius).")] = 0.3,
    radius: Annotated[float, typer.Option("--radius", help="Mean distance of the vertices from the origin.")] = 1.0,
    seed: SeedOpt = 0,
) -> Environment:
    """A random star polygon (the paper's §7.3 family, irregularity scaled)."""
    from solverplan.generators import star_polygon

    return star_polygon(n=n, irregularity=irregularity, spikiness=spikiness, radius=radius, seed=seed)


@generate_app.command("holes")
@_generator
def generate_holes(
    n: Annotated[int, typer.Option("--n", min=3, max=MAX_GENERATED_VERTICES, help="Vertices of the outer ring.")] = 20,
    holes: Annotated[int, typer.Option("--holes", min=0, max=MAX_ROOMS, help="Number of holes.")] = 2,
    hole_vertices: Annotated[int, typer.Option("--hole-vertices", min=3, max=MAX_GENERATED_VERTICES, help="Vertices per hole.")] = 6,
    hole_kind: Annotated[str, typer.Option("--hole-kind", help="convex or star.")] = "convex",
    irregularity: Annotated[float, typer.Option("--irregularity", min=0.0, max=1.0)] = 0.2,
    spikiness: Annotated[float, typer.Option("--spikiness", min=0.0, max=1.0)] = 0.15,
    seed: SeedOpt = 0,
) -> Environment:
    """A random star polygon with small holes strictly inside."""
    from solverplan.generators import star_polygon_with_holes

    return star_polygon_with_holes(n=n, n_holes=holes, hole_vertices=hole_vertices,
                                   hole_kind=hole_kind,  # type: ignore[arg-type]  # the library checks the text
                                   irregularity=irregularity, spikiness=spikiness, seed=seed)


@generate_app.command("rooms")
@_generator
def generate_rooms(
    rooms: Annotated[int, typer.Option("--rooms", min=1, max=MAX_ROOMS, help="Number of rooms.")] = 5,
    loops: Annotated[int, typer.Option("--loops", min=0, max=MAX_ROOMS, help="Extra corridors closing loops (one hole each).")] = 0,
    room_size: Annotated[float, typer.Option("--room-size", help="Room diameter.")] = 4.0,
    spacing: Annotated[float, typer.Option("--spacing", help="Distance between neighbouring rooms (>= 1.6 room size).")] = 10.0,
    corridor_width: Annotated[float, typer.Option("--corridor-width", help="Corridor width (< room size / 3).")] = 1.0,
    seed: SeedOpt = 0,
) -> Environment:
    """Convex rooms on a jittered grid joined by straight corridors (an office-like environment)."""
    from solverplan.generators import rooms_and_corridors

    return rooms_and_corridors(n_rooms=rooms, loops=loops, room_size=room_size,
                               spacing=spacing, corridor_width=corridor_width, seed=seed)


@generate_app.command("rectilinear")
@_generator
def generate_rectilinear(
    rooms: Annotated[int, typer.Option("--rooms", min=1, max=MAX_ROOMS, help="Number of rooms.")] = 4,
    width: Annotated[int | None, typer.Option("--width", min=1, max=MAX_GENERATED_VERTICES, help="Building width (default grows with the rooms).", show_default=False)] = None,
    height: Annotated[int | None, typer.Option("--height", min=1, max=MAX_GENERATED_VERTICES, help="Building height.", show_default=False)] = None,
    wall: Annotated[int, typer.Option("--wall", min=1, max=MAX_COUNT, help="Wall thickness.")] = 1,
    door: Annotated[int, typer.Option("--door", min=1, max=MAX_COUNT, help="Door width.")] = 2,
    min_room: Annotated[int, typer.Option("--min-room", min=1, max=MAX_COUNT, help="Smallest room width (>= door + 2).")] = 4,
    pillars: Annotated[int, typer.Option("--pillars", min=0, max=MAX_ROOMS, help="Square pillars (holes), one per room at most.")] = 0,
    seed: SeedOpt = 0,
) -> Environment:
    """A rectangular building split into rooms by walls with doors (integer coordinates)."""
    from solverplan.generators import rectilinear_floor_plan

    return rectilinear_floor_plan(n_rooms=rooms, width=width, height=height, wall=wall,
                                  door=door, min_room=min_room, pillars=pillars, seed=seed)


@generate_app.command("polyomino")
@_generator
def generate_polyomino(
    cells: Annotated[int, typer.Option("--cells", min=1, max=MAX_ROOMS, help="Number of grid cells (1,000 take seconds).")] = 12,
    max_size: Annotated[int, typer.Option("--max-size", min=1, max=MAX_COUNT, help="Largest cell width or height.")] = 6,
    seed: SeedOpt = 0,
) -> Environment:
    """A random simple rectilinear polygon without holes (grid cells of random sizes; integer coordinates)."""
    from solverplan.generators import rectilinear_polygon

    return rectilinear_polygon(n_cells=cells, max_size=max_size, seed=seed)


@generate_app.command("spiral")
@_generator
def generate_spiral(
    turns: Annotated[int, typer.Option("--turns", min=1, max=500, help="Left turns of the width-1 corridor (its reflex vertices).")] = 4,
) -> Environment:
    """The exploration paper's spiral (Figure 9): a width-1 corridor winding inward, r = turns; start at (0, 0)."""
    from solverplan.explore.families import spiral

    return spiral(turns)[0]


@generate_app.command("ring")
@_generator
def generate_ring(
    sides: Annotated[int, typer.Option("--sides", min=3, max=500, help="Vertices of the convex hole (all reflex).")] = 5,
) -> Environment:
    """The exploration paper's one-hole polygon (Figure 10): a ring corridor round a convex hole of --sides vertices."""
    from solverplan.explore.families import one_hole

    return one_hole(sides - 2)[0]
