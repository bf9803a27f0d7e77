"""The shipped models: every file loads, by path and by name, the README table is right, each model has the
properties it is for."""

from __future__ import annotations

import itertools
import json
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from solverplan import models
from solverplan.cli import app
from solverplan.environment import Environment, load_environment, save_environment
from solverplan.errors import InputError, MalformedFile
from solverplan.exact import orient
from solverplan.generators import star_polygon, worst_case_polygon

MODELS = Path(models.__file__).resolve().parent
FILES = sorted(MODELS.glob("*.json"))


def model(stem: str) -> Environment:
    return load_environment(MODELS / f"{stem}.json")


def edge_vectors(ring):
    return [(b[0] - a[0], b[1] - a[1]) for a, b in zip(ring, (*ring[1:], ring[0]))]


def cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def is_rectilinear(env: Environment) -> bool:
    return all(dx == 0 or dy == 0 for ring in env.rings for dx, dy in edge_vectors(ring))


def pieces_after_erosion(env: Environment, distance: float) -> list:
    """The parts of the free space at distance > ``distance`` from the boundary (float, shapely)."""
    eroded = env.to_shapely().buffer(-distance)
    return list(getattr(eroded, "geoms", [eroded]))


# ---------------------------------------------------------------------- every file
def test_at_least_fourteen_models():
    assert len(FILES) >= 14


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_model_loads_normalised_with_its_name_and_exact_short_coordinates(path):
    env = load_environment(path)
    data = json.loads(path.read_text(), parse_float=Decimal)
    assert data["name"] == path.stem == env.name
    assert not any(env.reoriented), "files are stored normalised: outer ring CCW, holes CW"
    numbers = [x for ring in [data["outer"], *data.get("holes", [])] for point in ring for x in point]
    assert all(isinstance(x, (int, Decimal)) for x in numbers), "coordinates are JSON numbers, not strings"
    assert all((Fraction(x) * 10**6).denominator == 1 for x in numbers), "at most 6 decimals"


def test_readme_table_matches_the_files():
    from solverplan.models import make_table

    readme = (MODELS / "README.md").read_text(encoding="utf-8")
    assert make_table.embedded_table(readme) == make_table.table(), "run: python -m solverplan.models.make_table --write"
    assert set(make_table.PURPOSES) == {path.stem for path in FILES}


# ---------------------------------------------------------------------- models by name
def test_names_are_the_file_stems_and_path_and_load_agree():
    assert models.names() == sorted(path.stem for path in FILES)
    assert {"square", "two_rooms", "one_hole"} <= set(models.names())
    assert models.path("two_rooms") == models.path("two_rooms.json") == MODELS / "two_rooms.json"
    assert models.load("one_hole") == load_environment(MODELS / "one_hole.json")
    assert models.load("one_hole").name == "one_hole"


@pytest.mark.parametrize("name", ["two_room", "", "solverplan/models/square.json", "../models/square"])
def test_an_unknown_model_name_is_one_line_listing_the_known_names(name):
    with pytest.raises(InputError) as info:
        models.path(name)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"unknown model {name!r}")
    assert message.endswith(", ".join(models.names()))


@pytest.mark.parametrize("name", ["two_rooms", "two_rooms.json"])
def test_load_environment_takes_a_model_name_with_or_without_the_extension(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no such file here: the name means the shipped model
    env = load_environment(name)
    assert env == models.load("two_rooms") and env.name == "two_rooms"
    # a format given for a file does not apply to the model (shipped models are JSON); a bad one is still an error
    assert load_environment(name, "wkt") == env
    with pytest.raises(MalformedFile, match="unknown format 'svg'"):
        load_environment(name, "svg")


def test_an_existing_file_wins_over_a_model_of_the_same_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    save_environment(Environment.from_coords([[0, 0], [3, 0], [0, 4]], name="mine"), tmp_path / "square.json")
    assert load_environment("square.json").name == "mine"
    assert load_environment("square").n_vertices == 4  # no file "square" (no extension): the model
    (tmp_path / "square").write_text((tmp_path / "square.json").read_text())
    assert load_environment("square", "json").name == "mine"


def test_neither_a_file_nor_a_model_is_one_line_no_such_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(MalformedFile) as bare:
        load_environment("two_roms")
    assert str(bare.value) == "two_roms: no such file, nor a shipped model (did you mean two_rooms or two_holes?)"
    with pytest.raises(MalformedFile) as nested:
        load_environment(Path("data") / "two_rooms.json")  # a directory part: a file, never a model
    assert str(nested.value) == "data/two_rooms.json: no such file, nor a shipped model"


def test_every_environment_argument_of_the_cli_takes_a_model_name(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    info = runner.invoke(app, ["info", "two_rooms"])
    assert info.exit_code == 0 and json.loads(info.stdout)["name"] == "two_rooms"
    plan = runner.invoke(
        app, ["plan", "two_rooms", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "-o", "plan.json", "--certificate", "cert.json"]
    )
    assert plan.exit_code == 0, plan.output
    verify = runner.invoke(app, ["verify", "cert.json", "--env", "two_rooms.json", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1"])
    assert verify.exit_code == 0 and json.loads(verify.stdout)["valid"] is True
    missing = runner.invoke(app, ["info", "two_roms"])
    assert missing.exit_code == 2
    assert missing.stderr.strip().splitlines() == [
        "error: two_roms: no such file, nor a shipped model (did you mean two_rooms or two_holes?)"
    ]


# ---------------------------------------------------------------------- each model's purpose
def test_square_is_a_square():
    env = model("square")
    assert env.n_vertices == 4 and is_rectilinear(env)
    assert {abs(dx) + abs(dy) for dx, dy in edge_vectors(env.outer)} == {10}


def test_triangle_is_acute_and_scalene():
    ring = model("triangle").outer
    assert len(ring) == 3
    sides = edge_vectors(ring)
    squared = {dx * dx + dy * dy for dx, dy in sides}
    assert len(squared) == 3
    for u, v in zip(sides, sides[1:] + sides[:1]):  # angle at each vertex < 90°: −u·v > 0
        assert -(u[0] * v[0] + u[1] * v[1]) > 0


def test_hexagon_is_close_to_regular_with_exactly_parallel_opposite_edges():
    env = model("hexagon")
    assert env.n_vertices == 6 and env.reflex_vertices == ()
    sides = edge_vectors(env.outer)
    assert all(cross(sides[i], sides[i + 3]) == 0 for i in range(3))
    assert np.ptp(env.edge_lengths) < 1e-7
    angles = np.arctan2(env.vertices[:, 1], env.vertices[:, 0])
    regular = 10 * np.column_stack([np.cos(angles), np.sin(angles)])
    assert np.allclose(np.hypot(*env.vertices.T), 10, atol=1e-7)
    assert np.allclose(np.diff(np.unwrap(angles)), np.pi / 3, atol=1e-7) and np.allclose(env.vertices, regular)


def test_irregular_convex_is_strictly_convex_without_parallel_edges():
    env = model("irregular_convex")
    ring = env.outer
    assert len(ring) == 7 and env.reflex_vertices == ()
    assert all(orient(ring[i - 1], ring[i], ring[(i + 1) % 7]) > 0 for i in range(7))
    sides = edge_vectors(ring)
    assert all(cross(u, v) != 0 for u, v in itertools.combinations(sides, 2))


def test_l_shape_has_one_reflex_vertex():
    env = model("l_shape")
    assert env.n_vertices == 6 and len(env.reflex_vertices) == 1 and is_rectilinear(env)


def test_two_rooms_are_joined_by_a_corridor_with_non_parallel_sides():
    env = model("two_rooms")
    assert 12 <= env.n_vertices <= 20 and env.holes == ()
    slanted = [v for v in edge_vectors(env.outer) if v[0] != 0 and v[1] != 0]
    assert len(slanted) == 2 and cross(*slanted) != 0  # the corridor's sides, and only they, are slanted
    rooms = pieces_after_erosion(env, 1.1)  # the corridor is 2 wide at its narrow end
    assert len(rooms) == 2 and min(room.area for room in rooms) > 20
    assert len(pieces_after_erosion(env, 0.9)) == 1


def test_comb_has_five_teeth():
    env = model("comb")
    assert is_rectilinear(env) and env.holes == ()
    assert len(env.reflex_vertices) == 2 * (5 - 1)  # two reflex corners between neighbouring teeth


def test_spiral_is_rectilinear_with_a_single_reflex_chain():
    env = model("spiral")
    assert is_rectilinear(env) and env.holes == ()
    reflex = set(env.reflex_vertices)
    assert len(reflex) >= 8
    starts = [v for v in reflex if (v - 1) % env.n_vertices not in reflex]
    assert len(starts) == 1, "the reflex vertices are consecutive along the boundary"


def test_star_is_the_generator_output_with_its_seed():
    env = model("star")
    generated = star_polygon(20, 0.3, 0.3, radius=10, seed=7)
    assert env == generated, "numpy's Generator stream changed, or the generator did: regenerate solverplan/models/star.json"
    origin = (Fraction(0), Fraction(0))
    ring = env.outer
    assert all(orient(origin, ring[i], ring[(i + 1) % 20]) > 0 for i in range(20))  # star-shaped about 0


@pytest.mark.parametrize("stem,holes", [("one_hole", 1), ("two_holes", 2), ("degenerate", 1)])
def test_models_with_holes(stem, holes):
    assert len(model(stem).holes) == holes


def test_warehouse_is_rectilinear_with_at_least_six_rooms_behind_narrow_doors():
    env = model("warehouse")
    assert is_rectilinear(env) and env.holes == ()
    pieces = pieces_after_erosion(env, 0.6)  # doors are 1 wide: eroding by 0.6 closes every door
    assert len(pieces) >= 7  # ≥ 6 rooms and the corridor
    assert sum(piece.area > 40 for piece in pieces) >= 6
    assert len(pieces_after_erosion(env, 0.4)) == 1


def test_hallway_is_long_and_narrow():
    env = model("hallway")
    xmin, ymin, xmax, ymax = env.bounds
    assert is_rectilinear(env) and (xmax - xmin) >= 10 * (ymax - ymin)


def test_narrow_door_joins_two_rooms_through_a_narrow_doorway():
    env = model("narrow_door")
    rooms = pieces_after_erosion(env, 0.11)  # the doorway is 0.2 wide
    assert len(rooms) == 2 and min(room.area for room in rooms) > 50
    assert len(pieces_after_erosion(env, 0.09)) == 1


def test_worst_case_t4_is_the_generator_output():
    env = model("worst_case_t4")
    assert env == worst_case_polygon(4)
    assert env.n_vertices == 18 and len(env.reflex_vertices) == 8


def test_degenerate_has_collinear_vertices_parallel_edges_and_aligned_hole_vertices():
    env = model("degenerate")
    outer, hole = env.outer, env.holes[0]
    n = len(outer)
    assert any(orient(outer[i - 1], outer[i], outer[(i + 1) % n]) == 0 for i in range(n))
    sides = edge_vectors(outer)
    assert any(cross(u, v) == 0 for u, v in itertools.combinations(sides, 2))
    outer_edges = list(zip(outer, (*outer[1:], outer[0])))
    # a hole vertex on the supporting line of an outer edge (off the edge itself: holes never touch)
    assert any(orient(a, b, h) == 0 for a, b in outer_edges for h in hole)
    # a hole vertex on the line through two outer vertices that are not an edge
    assert any(
        orient(p, q, h) == 0
        for p, q in itertools.combinations(outer, 2)
        if (p, q) not in outer_edges and (q, p) not in outer_edges
        for h in hole
    )


def test_chambers_are_three_big_rooms_joined_by_doorways_one_and_three_wide():
    env = model("three_chambers")
    assert is_rectilinear(env) and env.holes == () and env.area == 3 * 900 + 4 * 1 + 4 * 3
    assert len(pieces_after_erosion(env, 0.6)) == 2  # the 1-wide doorway closes: chamber 1 | chambers 2, 3
    assert len(pieces_after_erosion(env, 1.6)) == 3  # the 3-wide one too


def test_serpentine_is_a_half_metre_corridor_with_four_turns_cut_at_45_degrees():
    env = model("serpentine")
    # the stretches are 0.5 wide, the cut corners √2/4 ≈ 0.354 (reflex vertex to the 45° wall)
    assert len(pieces_after_erosion(env, 0.17)) == 1 and len(pieces_after_erosion(env, 0.18)) == 5
    assert all(piece.is_empty for piece in pieces_after_erosion(env, 0.26))
    diagonal = [e for e in env.edges if abs(e.a[0] - e.b[0]) == abs(e.a[1] - e.b[1]) != 0]
    assert len(diagonal) == 4 and all(abs(e.a[0] - e.b[0]) == Fraction(1, 2) for e in diagonal)
    assert len(env.reflex_vertices) == 4
