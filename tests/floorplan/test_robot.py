"""Robots as they are: a disc's free space (Minkowski inflation), topology changes reported, keepout masks."""

from __future__ import annotations

import json
import warnings
from decimal import Decimal

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from solverplan.cli import app
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.floorplan import environment_from_polygon, erode_free_space, import_floorplan
from solverplan.floorplan.robot import inflation_distance

from .maps import FREE, OCCUPIED, rasterise, write_map

runner = CliRunner()

ROOMS = shapely.Polygon([(0, 0), (2, 0), (2, 0.85), (2.5, 0.85), (2.5, 0), (4.5, 0), (4.5, 2), (2.5, 2), (2.5, 1.15),
                         (2, 1.15), (2, 2), (0, 2)])  # two rooms, a 0.3 m door


@settings(max_examples=40, deadline=None)
@given(st.floats(0.05, 0.6), st.floats(0.5, 3.0), st.floats(0.1, 1.0), st.floats(-1.0, 1.0))
@example(0.17, 1.0, 0.3, 0.0)
def test_minkowski_inflation_is_conservative(radius, width, side, shift):
    """Every point of the inflated environment is at least R from every wall and obstacle (the chords of the
    rounded corners are pushed out, then the grid rounding is paid for)."""
    free = shapely.box(-3, -2, 3, 2).difference(shapely.box(shift - side / 2, -side / 2, shift + side / 2, side / 2))
    free = free.difference(shapely.box(-3, 1.5 - width / 4, -2.5, 2))  # a notch
    try:
        kept, _ = erode_free_space(free, radius, grid=1e-3)
    except InputError:
        return  # the robot fits nowhere: said
    env, _, _ = environment_from_polygon(kept, quantum=Decimal("0.001"))
    walls = free.boundary
    made = env.to_shapely()
    for ring in (made.exterior, *made.interiors):
        for x, y in ring.coords:
            assert walls.distance(shapely.Point(x, y)) >= radius - 1e-9
        mids = np.asarray(ring.coords)
        for a, b in zip(mids[:-1], mids[1:]):
            assert walls.distance(shapely.Point((a + b) / 2)) >= radius - 1e-9
    # and not much more than R: the part kept covers the free space eroded by a little more than the distance used
    deeper = free.buffer(-(inflation_distance(radius, 1e-3) + 0.002))
    assert made.buffer(1e-9).covers(max(getattr(deeper, "geoms", [deeper]), key=lambda g: g.area)) or \
        not made.intersects(deeper)


def test_a_door_narrower_than_the_robot_disconnects_the_rooms_and_says_where(tmp_path):
    kept, changes = erode_free_space(ROOMS, 0.17, grid=0.001)
    kinds = [c.kind for c in changes]
    assert kinds == ["disconnected", "passage_closed"]
    door = changes[1]
    assert door.at == pytest.approx((2.25, 1.0), abs=0.01) and door.size == pytest.approx(0.3, abs=0.01)
    assert changes[0].area == pytest.approx(kept.area, rel=0.02)  # the other room, as big
    small, changes = erode_free_space(ROOMS, 0.1, grid=0.001)  # a 0.2 m robot passes
    assert changes == [] and small.area > kept.area * 1.9


def test_obstacles_merged_by_the_inflation_are_listed():
    free = shapely.box(0, 0, 6, 4).difference(shapely.box(1, 1, 1.5, 1.5)).difference(shapely.box(1.7, 1, 2.2, 1.5))
    free = free.difference(shapely.box(4, 0.2, 4.5, 0.7))  # 0.2 m from the wall
    _, changes = erode_free_space(free, 0.17, grid=0.001)
    merged = sorted(round(c.at[0], 1) for c in changes if c.kind == "merged_obstacle")
    assert len(merged) == 3
    gaps = sorted(round(c.size, 2) for c in changes if c.kind == "passage_closed")
    assert gaps == [0.2, 0.2, 0.2]


def test_import_with_a_robot_radius_gives_exact_decimals_and_the_picture(tmp_path):
    image, origin = rasterise(ROOMS, 0.05)
    source = write_map(tmp_path, image, origin, 0.05)
    out, picture = tmp_path / "rooms.json", tmp_path / "rooms.png"
    result = runner.invoke(app, ["import", str(source), "-o", str(out), "--robot-radius", "0.17", "--picture",
                                 str(picture)])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["settings"]["robot_radius_m"] == "0.17" and summary["area"] < summary["area_before_robot"] / 1.9
    kinds = [f["kind"] for f in summary["features"]]
    assert "disconnected" in kinds and "passage_closed" in kinds
    env = load_environment(out)
    assert float(env.area) == pytest.approx(summary["area"])
    assert all(len(str(float(c))) <= 14 for p in env.exact_vertices for c in p)  # millimetre grid from the origin
    assert picture.read_bytes()[:4] == b"\x89PNG"
    bad = runner.invoke(app, ["import", str(source), "-o", str(out), "--robot-radius", "-1"])
    assert bad.exit_code == 2 and "--robot-radius must be a positive" in bad.stderr
    huge = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "h.json"), "--robot-radius", "5"])
    assert huge.exit_code == 2 and "fits nowhere" in huge.stderr and not (tmp_path / "h.json").exists()


def test_a_keepout_mask_takes_its_cells_out_of_the_free_space(tmp_path):
    room = np.full((40, 60), OCCUPIED, np.uint8)
    room[2:38, 2:58] = FREE
    source = write_map(tmp_path, room, (0.0, 0.0), 0.1, name="room")
    mask = np.full((40, 60), FREE, np.uint8)
    mask[10:20, 30:40] = OCCUPIED  # a 1 m × 1 m keepout zone
    keepout = write_map(tmp_path, mask, (0.0, 0.0), 0.1, name="keepout")
    plain = import_floorplan(source, spur_width=0)
    done = import_floorplan(source, keepout=keepout, spur_width=0)
    assert done.area == pytest.approx(plain.area - 1.0)
    assert done.holes == 1 and [f.kind for f in done.features] == ["keepout"]
    assert done.features[0].at[0] == pytest.approx(3.5, abs=0.5) and done.uninflated == plain.environment
    both = import_floorplan(source, keepout=keepout, spur_width=0, robot_radius="0.2")
    assert both.area < done.area and both.holes == 1


def test_the_import_result_names_the_environment_plainly(tmp_path):
    image, origin = rasterise(shapely.box(0, 0, 3, 2), 0.1)
    done = import_floorplan(write_map(tmp_path, image, origin, 0.1))
    assert isinstance(done.environment, Environment)
    assert done.environment_record.sha256 and done.to_json()["environment"]["sha256"] == done.environment_record.sha256
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert done.environment_value is done.environment
    assert caught and issubclass(caught[0].category, DeprecationWarning)


def test_shapely_polygons_go_in_and_out():
    polygon = shapely.Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], [[(1, 1), (2, 1), (2, 2), (1, 2)]])
    env = load_environment(polygon)
    assert float(env.area) == 11 and shapely.equals(env.to_shapely(), polygon)
    assert load_environment(shapely.MultiPolygon([polygon])) == env
    with pytest.raises(InvalidEnvironment, match="MultiPolygon of 2 parts"):
        load_environment(shapely.MultiPolygon([polygon, shapely.box(10, 10, 11, 11)]))
    with pytest.raises(InvalidEnvironment, match="expected a shapely Polygon"):
        load_environment(shapely.Point(0, 0))
    assert load_environment(env.to_shapely()) == env
