"""ROS occupancy maps: known polygons rasterised with noise come back within resolution-based bounds."""

from __future__ import annotations

import json
import math
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.floorplan import import_floorplan, read_occupancy_map, snap_rectilinear

from .maps import FREE, OCCUPIED, UNKNOWN, office_polygon, rasterise, write_map

NOISE = {
    "clean": {},
    "speckle": {"speckle": 0.01},
    "ragged": {"ragged": 0.25},
    "ragged+speckle": {"ragged": 0.2, "speckle": 0.01},
    "occupied margin": {"unknown_margin": False},
}


def _hausdorff(environment, polygon) -> float:
    return shapely.hausdorff_distance(environment.to_shapely().boundary, polygon.boundary, densify=0.05)


@pytest.mark.parametrize("resolution", [0.05, 0.1, 0.2])
@pytest.mark.parametrize("noise", list(NOISE))
def test_a_rasterised_polygon_imports_back_within_a_resolution_bound(tmp_path, resolution, noise):
    truth = office_polygon()
    image, origin = rasterise(truth, resolution, seed=7, **NOISE[noise])
    source = write_map(tmp_path, image, origin, resolution)
    specks = "speckle" in NOISE[noise]
    # sensor specks are single cells: keep them out by size (each is listed where it was), obstacles stay
    done = import_floorplan(source, output=tmp_path / "env.json", min_obstacle=4 * resolution if specks else None)
    environment = done.environment
    noisy = noise not in ("clean", "occupied margin")
    # the traced boundary lies on cell edges (± half a cell on slanted walls), simplification adds its tolerance
    # (half a cell) and ragged walls one more cell; the default simplification (the walls' measured noise) keeps the
    # outline inside the traced free space: walls move in by up to twice its tolerance
    shrink = 2 * done.settings["simplify_m"]
    assert done.settings["inside_traced"] and done.settings["simplify_m"] <= 3 * resolution
    bound = (2.0 if noisy else 1.0) * resolution + resolution / 2 + shrink
    assert _hausdorff(environment, truth) <= bound
    assert abs(float(environment.area) - truth.area) <= truth.length * (resolution * (0.5 if noisy else 0.25) + shrink)
    traced = import_floorplan(source, simplify=0, rectilinear=0, min_obstacle=4 * resolution if specks else None)
    assert traced.environment.to_shapely().covers(environment.to_shapely())
    assert len(environment.holes) == 2
    assert done.to_json()["holes"] == 2 and done.to_json()["outer_vertices"] == len(environment.outer)
    from solverplan.answers import read_answer

    summary = json.loads(json.dumps(done.to_json()))
    assert read_answer(summary).to_json() == summary  # an import summary reads back
    if specks:
        assert done.dropped["speckle"] > 0 or done.dropped["components"] > 0
        listed = [f for f in done.features if f.kind == "speckle"]
        assert len(listed) == done.dropped["speckle"]
        minx, miny, maxx, maxy = truth.bounds
        assert all(minx - 1 <= f.at[0] <= maxx + 1 and miny - 1 <= f.at[1] <= maxy + 1 for f in listed)
        assert all(f.size < 4 * resolution for f in listed)
    # the file written reads back as the very same environment (short exact decimals)
    assert load_environment(tmp_path / "env.json") == environment
    assert all(len(json.dumps(float(c))) <= 12 for p in environment.exact_vertices for c in p)


def test_the_seed_point_picks_its_component_and_the_largest_is_the_default(tmp_path):
    big = shapely.box(0, 0, 4, 3)
    small = shapely.box(5, 0, 6.5, 1.5)
    image, origin = rasterise(shapely.MultiPolygon([big, small]), 0.1, wall=0.2)
    source = write_map(tmp_path, image, origin, 0.1)
    largest = import_floorplan(source)
    assert float(largest.environment.area) == pytest.approx(12, abs=0.2)
    assert largest.dropped["components"] == 1 and largest.dropped["component_area"] == pytest.approx(2.25, abs=0.2)
    chosen = import_floorplan(source, seed_point=("5.5", "0.5"))
    assert float(chosen.environment.area) == pytest.approx(2.25, abs=0.1)


def test_world_coordinates_put_the_origin_at_the_lower_left_pixel_corner(tmp_path):
    image = np.full((4, 6), OCCUPIED, np.uint8)
    image[1:3, 1:5] = FREE  # rows 1-2 from the top: the second and third rows from the bottom
    source = write_map(tmp_path, image, (10.0, -5.0), 0.5)
    environment = import_floorplan(source, simplify=0, spur_width=0).environment
    xs = sorted({float(x) for x, _ in environment.outer})
    ys = sorted({float(y) for _, y in environment.outer})
    assert xs == [10.5, 12.5] and ys == [-4.5, -3.5]


def test_negate_mode_and_thresholds_are_honoured(tmp_path):
    image = np.full((10, 10), 0, np.uint8)
    image[2:8, 2:8] = 255  # white free ...
    image[4:6, 2:8] = 100  # ... and a grey band: occupancy 0.61 (unknown), or 0.39 with negate (unknown too)
    plain = write_map(tmp_path, image, (0.0, 0.0), 1.0, name="plain")
    grid = read_occupancy_map(plain)
    assert grid.free.sum() == 24 and grid.occupied.sum() == 64
    flipped = write_map(tmp_path, 255 - image, (0.0, 0.0), 1.0, name="flipped", extra="")
    negated = write_map(tmp_path, image, (0.0, 0.0), 1.0, name="negated", extra="")
    text = negated.read_text().replace("negate: 0", "negate: 1")
    negated.write_text(text)
    assert read_occupancy_map(negated).free.tolist() == read_occupancy_map(flipped).free.tolist()
    raw = write_map(tmp_path, np.array([[0, 100, 255, 10]], np.uint8), (0.0, 0.0), 1.0, name="raw", extra="mode: raw\n")
    grid = read_occupancy_map(raw)
    assert grid.free.tolist() == [[True, False, False, True]]  # 10 % < 19.6 %: free
    assert grid.occupied.tolist() == [[False, True, False, False]]  # 255 is unknown, not occupied


def test_unknown_cells_are_not_free(tmp_path):
    image = np.full((10, 10), UNKNOWN, np.uint8)
    image[2:8, 2:5] = FREE
    source = write_map(tmp_path, image, (0.0, 0.0), 1.0)
    assert float(import_floorplan(source, spur_width=0).environment.area) == 18


def test_png_with_transparency_reads_transparent_cells_as_unknown(tmp_path):
    from PIL import Image

    rgba = np.zeros((6, 6, 4), np.uint8)
    rgba[..., 3] = 255
    rgba[1:5, 1:5, :3] = 255
    rgba[1:5, 3:5, 3] = 0  # transparent: unknown
    Image.fromarray(rgba, "RGBA").save(tmp_path / "m.png")
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 1\norigin: [0, 0, 0]\n")
    assert read_occupancy_map(tmp_path / "m.yaml").free.sum() == 8


def test_spurs_and_speckle_are_removed_and_counted(tmp_path):
    image = np.full((40, 40), OCCUPIED, np.uint8)
    image[5:35, 5:35] = FREE
    image[20, 35:39] = FREE  # a one-cell spur into the wall
    image[12, 12] = OCCUPIED  # a speck
    image[25:29, 25:29] = OCCUPIED  # a real obstacle, 16 cells
    source = write_map(tmp_path, image, (0.0, 0.0), 0.1)
    kept = import_floorplan(source)  # by default a 10 cm speck is an obstacle (a post): kept
    assert kept.dropped["spurs"] == 1 and kept.dropped["speckle"] == 0 and len(kept.environment.holes) == 2
    done = import_floorplan(source, min_obstacle=0.15)
    assert done.dropped["spurs"] == 1 and done.dropped["speckle"] == 1
    assert len(done.environment.holes) == 1
    speck = [f for f in done.features if f.kind == "speckle"]
    assert len(speck) == 1 and speck[0].at == pytest.approx((1.25, 2.75)) and speck[0].size == pytest.approx(0.1)
    spur = [f for f in done.features if f.kind == "spur"]
    assert len(spur) == 1 and spur[0].at[0] > 3.5 and spur[0].area == pytest.approx(0.04)
    assert "speckle at (1.25, 2.75)" in done.to_text()
    by_area = import_floorplan(source, min_hole_area=0.05)  # the old area rule still works
    assert by_area.dropped["speckle"] == 1
    bare = import_floorplan(source, spur_width=0)
    assert bare.dropped["spurs"] == 0 and len(bare.environment.holes) == 2


def test_rectilinear_snapping_straightens_a_slightly_turned_map(tmp_path):
    truth = shapely.affinity.rotate(office_polygon(), 1.0, origin=(0, 0))
    image, origin = rasterise(truth, 0.05, ragged=0.2, seed=3)
    source = write_map(tmp_path, image, origin, 0.05)
    done = import_floorplan(source, simplify=0.1, rectilinear=3, min_obstacle=0.06)  # one-cell specks out
    environment = done.environment
    outer = environment.outer
    axis = [a[0] == b[0] or a[1] == b[1] for a, b in zip(outer, outer[1:] + outer[:1])]
    assert all(axis) and len(outer) == 6
    assert done.rectilinear_edges >= 6 + 4
    assert _hausdorff(environment, truth) <= 0.25  # a 1° turn over 8 m moves a wall's end by 7 cm


def test_snap_rectilinear_leaves_oblique_edges_oblique():
    ring = np.array([[0, 0], [4, 0.02], [4, 3], [2, 4], [0, 3]], float)
    snapped, count = snap_rectilinear(ring, 2.0)
    assert count == 3
    assert snapped[0, 1] == snapped[1, 1] and snapped[1, 0] == snapped[2, 0]
    assert snapped[3].tolist() == [2.0, 4.0]


def test_a_yaw_turns_the_map_about_its_origin(tmp_path):
    image = np.full((6, 8), OCCUPIED, np.uint8)
    image[1:5, 1:7] = FREE
    source = write_map(tmp_path, image, (0.0, 0.0), 1.0)
    source.write_text(source.read_text().replace("0.0]", f"{math.pi / 2!r}]"))
    environment = import_floorplan(source, simplify=0, spur_width=0).environment
    xs = sorted({round(float(x), 6) for x, _ in environment.outer})
    ys = sorted({round(float(y), 6) for _, y in environment.outer})
    assert xs == [-5.0, -1.0] and ys == [1.0, 7.0]


def test_the_grid_of_the_coordinates_is_a_short_decimal():
    from solverplan.floorplan import grid_quantum

    assert grid_quantum(Decimal("0.025")) == Decimal("0.001")
    assert grid_quantum(Decimal("0.5")) == Decimal("0.01")


def test_sixteen_bit_and_colour_images_read_like_their_grey_versions(tmp_path):
    from PIL import Image

    grey = np.full((8, 10), OCCUPIED, np.uint8)
    grey[2:6, 2:8] = FREE
    grey[3, 4] = UNKNOWN
    plain = read_occupancy_map(write_map(tmp_path, grey, (0.0, 0.0), 1.0, name="grey"))
    Image.fromarray(grey.astype(np.uint16) * 257).save(tmp_path / "deep.png")  # 16 bits, full scale 65535
    (tmp_path / "deep.yaml").write_text("image: deep.png\nresolution: 1\norigin: [0, 0, 0]\n")
    deep = read_occupancy_map(tmp_path / "deep.yaml")
    Image.fromarray(np.stack([grey] * 3, axis=2)).save(tmp_path / "colour.png")
    (tmp_path / "colour.yaml").write_text("image: colour.png\nresolution: 1\norigin: [0, 0, 0]\n")
    colour = read_occupancy_map(tmp_path / "colour.yaml")
    for other in (deep, colour):
        assert np.array_equal(other.free, plain.free) and np.array_equal(other.occupied, plain.occupied)
    assert plain.free.sum() == 23


@settings(max_examples=40)
@given(st.integers(1, 12), st.integers(0, 2**32 - 1))
def test_the_square_opening_equals_scipys_binary_opening(side, seed):
    from scipy import ndimage

    from solverplan.floorplan.occupancy import _open_square

    mask = np.random.default_rng(seed).random((23, 31)) < 0.8
    assert (_open_square(mask, side) == ndimage.binary_opening(mask, structure=np.ones((side, side), bool))).all()


def test_a_spur_width_wider_than_the_map_is_one_clear_error(tmp_path):
    # found by fuzzing: --spur-width 16 on the office map ran scipy out of memory (a 321-cell structure)
    office = Path(__file__).resolve().parents[2] / "models" / "office.yaml"
    for width in (16, 1e300):
        with pytest.raises(InputError, match="narrower than --spur-width"):
            import_floorplan(office, output=tmp_path / "o.json", spur_width=width)


def test_snapping_survives_posts_near_the_walls(tmp_path):
    """A depot hall: ragged walls, 10–15 cm posts (some 10 cm from a wall) and a 20 × 40 cm box. The posts and the box
    are kept by default, and snapping the walls to the axes does not give up on the walls because of them."""
    hall = shapely.box(0, 0, 12, 6)
    posts = [shapely.box(x, y, x + s, y + s) for x, y, s in ((2, 2, 0.1), (4, 2, 0.15), (6, 4, 0.1), (0.2, 3, 0.1),
                                                              (11.7, 1, 0.15), (8, 5.7, 0.1))]
    box = shapely.box(9, 2, 9.4, 2.2)
    free = hall.difference(shapely.union_all([*posts, box]))
    image, origin = rasterise(free, 0.05, ragged=0.1, seed=5)
    source = write_map(tmp_path, image, origin, 0.05)
    done = import_floorplan(source, simplify=0.1, rectilinear=10)
    assert done.holes >= 4  # posts in the open; those 10 cm from a wall may join it (the gap is a spur, listed)
    assert done.dropped["rectilinear_skipped"] < done.holes and done.dropped["speckle"] == 0  # walls snapped
    outer = done.environment.outer
    assert all(a[0] == b[0] or a[1] == b[1] for a, b in zip(outer, outer[1:] + outer[:1]))
    assert done.area == pytest.approx(free.area, rel=0.02)
    kept = shapely.Polygon([(float(x), float(y)) for x, y in outer])
    for post in (*posts, box):  # every post and the box: a hole, or outside the outer ring (joined to a wall)
        centre = post.centroid
        in_hole = any(shapely.Polygon([(float(x), float(y)) for x, y in h]).buffer(0.05).contains(centre)
                      for h in done.environment.holes)
        assert in_hole or not kept.buffer(-0.01).contains(centre)
