"""Import bugs an independent tester's SLAM maps found (#24): each a small map that reproduces it."""

from __future__ import annotations

from decimal import Decimal

import numpy as np
import shapely
import shapely.affinity

from solverplan.floorplan import import_floorplan, read_occupancy_map
from solverplan.floorplan.occupancy import cells_to_polygons
from solverplan.floorplan.outline import finish_outline

from .maps import FREE, OCCUPIED, UNKNOWN, rasterise


def _write(folder, image, *, free_thresh="0.25", negate=0, resolution=0.05):
    from PIL import Image

    Image.fromarray(image).save(folder / "m.pgm")
    path = folder / "m.yaml"
    path.write_text(f"image: m.pgm\nresolution: {resolution}\norigin: [-1.5, -2.0, 0.0]\nnegate: {negate}\n"
                    f"occupied_thresh: 0.65\nfree_thresh: {free_thresh}\n")
    return path


def _room(pixels=60):
    """A square room of free cells walled in, unknown all around (and in a patch inside)."""
    image = np.full((pixels + 20, pixels + 20), UNKNOWN, np.uint8)
    image[8:-8, 8:-8] = OCCUPIED
    image[10:-10, 10:-10] = FREE
    image[30:36, 30:36] = UNKNOWN
    return image


def test_map_savers_unknown_grey_stays_unknown_under_nav2s_free_thresh(tmp_path):
    # Nav2's map_saver writes unknown cells as grey 205 and free_thresh 0.25, which read literally makes them free
    # ((255 − 205) / 255 ≈ 0.196 < 0.25): the free space was the whole image, walls and all around it
    done = import_floorplan(_write(tmp_path, _room()))
    assert float(done.environment.area) < 60 * 60 * 0.05 ** 2  # the room only (9 m²), not the image (16 m²)
    assert len(done.environment.holes) == 1  # the unknown patch is not free
    assert any("grey 205" in w and "unknown" in w for w in done.warnings)
    negated = 255 - _room()  # negate: 1 reads dark as free; map_saver's unknown is then 50
    again = import_floorplan(_write(tmp_path, negated, negate=1))
    assert float(again.environment.area) == float(done.environment.area)
    quiet = import_floorplan(_write(tmp_path, _room(), free_thresh="0.196"))
    assert float(quiet.environment.area) == float(done.environment.area)
    assert not any("grey 205" in w for w in quiet.warnings)


def test_an_import_lies_inside_the_free_cells_where_walls_run_at_an_angle(tmp_path):
    # marching squares traces a wall at an angle as a staircase of diagonal steps through the middle of the cells'
    # edges; on the free space's reflex corners each step cut into an occupied cell, and the default (conservative)
    # simplification kept slivers of obstacles up to 1.8 cm deep (seen on racks turned 17° and on irregular blobs)
    room = shapely.box(0, 0, 9, 7)
    racks = [shapely.affinity.rotate(shapely.box(2 + 3 * k, 2, 3.2 + 3 * k, 5), 17 + 11 * k) for k in range(2)]
    blob = shapely.Polygon([(7.2, 1.1), (7.9, 1.4), (8.1, 2.2), (7.5, 2.6), (7.0, 2.0)])
    image, origin = rasterise(room.difference(shapely.union_all([*racks, blob])), 0.05, ragged=0.3, seed=4)
    source = _write(tmp_path, image, free_thresh="0.196")
    grid = read_occupancy_map(source)
    free = cells_to_polygons(grid, grid.free)
    for kwargs in ({}, {"rectilinear": 0}, {"simplify": 0, "rectilinear": 0}):
        done = import_floorplan(source, min_obstacle=0, **kwargs)  # the trace itself too: on the cells' edges
        assert done.environment.to_shapely().difference(free).area < 1e-9, kwargs


def test_obstacles_the_shrinking_leaves_touching_at_a_point_are_joined():
    # the conservative simplification grows every obstacle by the tolerance and a grid step (mitred): two obstacles
    # diagonally apart by twice that touch at a corner, which GEOS accepts and an environment does not ("hole 17
    # touches hole 18", exit 2, on a tester's 60 × 50 m map of 10 cm cells)
    outer = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    rack = np.array([[0.3, 0.3], [0.4, 0.3], [0.4, 0.4], [0.3, 0.4]])
    features: list = []
    env, dropped = finish_outline(outer, [rack, rack + 0.11], quantum=Decimal("0.001"), simplify=0.004, inside=True,
                                  features=features)
    assert dropped["touches_joined"] == 1 and [f.kind for f in features] == ["touch"]
    assert len(env.holes) == 1  # one obstacle now, joined at the corner
    traced = shapely.Polygon(outer, [rack, rack + 0.11])
    assert traced.covers(env.to_shapely())
