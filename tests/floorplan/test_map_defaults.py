"""The defaults of a map import on a raw SLAM-style map: a plannable outline inside the traced free space (#24)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import shapely.affinity

from solverplan.floorplan import import_floorplan

from .maps import rasterise, write_map


def _store(rows: int = 2, bays: int = 3):
    """A 12 × 9 m store room: racks 2 m × 1 m in rows, a post, an outer wall with a notch."""
    outer = [(0, 0), (12, 0), (12, 9), (5, 9), (5, 8), (0, 8)]
    holes = [[(1.5 + 3 * b, 1.5 + 3 * r), (3.5 + 3 * b, 1.5 + 3 * r), (3.5 + 3 * b, 2.5 + 3 * r), (1.5 + 3 * b, 2.5 + 3 * r)]
             for r in range(rows) for b in range(bays)]
    holes.append([(10.5, 4), (10.9, 4), (10.9, 4.4), (10.5, 4.4)])
    return shapely.Polygon(outer, holes)


@pytest.fixture(scope="module")
def raw_store(tmp_path_factory):
    """The store as a lidar map at 5 cm: ragged walls (a quarter of the cells along them flipped), one-cell specks."""
    folder = tmp_path_factory.mktemp("store")
    image, origin = rasterise(_store(), 0.05, ragged=0.25, speckle=0.002, seed=3)
    return write_map(folder, image, origin, 0.05)


def test_a_raw_map_imports_with_defaults_inside_its_traced_free_space_with_a_few_vertices(raw_store):
    done = import_floorplan(raw_store)
    traced = import_floorplan(raw_store, simplify=0, rectilinear=0)
    env = done.environment
    # what the defaults chose, and why, is said
    assert done.settings["inside_traced"] is True and done.settings["rectilinear_deg"] == 10.0
    assert 0.025 <= done.settings["simplify_m"] <= 0.15
    assert done.settings["measured"]["wall_noise_m"] > 0 and done.settings["measured"]["axis_parallel_share"] >= 0.9
    assert any("inside the traced free space" in w for w in done.warnings)
    assert any("snapped" in w for w in done.warnings)
    # a plan valid on the outline is valid on the map: the outline lies inside the free space as traced
    assert traced.environment.to_shapely().covers(env.to_shapely())
    assert float(env.area) > 0.85 * float(traced.environment.area)  # walls in by ~2 tolerances, racks boxed
    # the racks and the post are boxes, the walls straight: a few vertices where the trace had thousands
    assert len(env.holes) == 7 and all(len(h) == 4 for h in env.holes)
    assert len(env.outer) <= 8 and traced.environment.n_vertices > 15 * env.n_vertices  # 6 corners, a chamfer left
    # the specks are gone, each listed, and the import says so
    specks = [f for f in done.features if f.kind == "speckle"]
    assert specks and len(specks) == done.dropped["speckle"]
    assert any("lidar specks" in w and "--min-obstacle 0" in w for w in done.warnings)


def test_explicit_options_keep_their_meaning(raw_store):
    done = import_floorplan(raw_store, simplify=0.025, rectilinear=0, min_obstacle=0)
    assert done.settings["inside_traced"] is False and done.settings["rectilinear_deg"] == 0
    assert done.dropped["speckle"] == 0 and done.rectilinear_edges == 0
    assert not any("lidar specks" in w or "snapped" in w for w in done.warnings)


def test_a_turned_map_is_snapped_to_its_own_axes_and_stays_inside(tmp_path):
    turned = shapely.affinity.rotate(_store(rows=1, bays=2), 30, origin=(0, 0))
    image, origin = rasterise(turned, 0.05, ragged=0.25, seed=5)
    source = write_map(tmp_path, image, origin, 0.05)
    done = import_floorplan(source)
    traced = import_floorplan(source, simplify=0, rectilinear=0)
    assert done.settings["rectilinear_deg"] == 10 and done.settings["rectilinear_axes_deg"] == pytest.approx(30, abs=1)
    assert done.settings["measured"]["axis_parallel_share"] >= 0.9 and any("turned" in w for w in done.warnings)
    assert traced.environment.to_shapely().covers(done.environment.to_shapely())
    assert len(done.environment.holes) == 3 and all(len(h) == 4 for h in done.environment.holes)
    assert traced.environment.n_vertices > 10 * done.environment.n_vertices
    plain = import_floorplan(source, rectilinear=0)  # not snapped: inside all the same, more vertices
    assert traced.environment.to_shapely().covers(plain.environment.to_shapely())
    assert plain.environment.n_vertices > done.environment.n_vertices


def test_a_clean_map_of_straight_walls_is_kept_exactly(tmp_path):
    image, origin = rasterise(shapely.box(0, 0, 4, 3).difference(shapely.box(1, 1, 2, 2)), 0.1)
    source = write_map(tmp_path, image, origin, 0.1)
    done = import_floorplan(source)
    assert done.settings["simplify_m"] == 0 and done.settings["measured"]["wall_noise_m"] == 0
    assert float(done.environment.area) == pytest.approx(11.0) and done.environment.n_vertices == 8
    assert not any("inside the traced" in w for w in done.warnings)


def test_what_the_shrinking_closes_is_listed_and_the_seed_points_room_is_kept(tmp_path):
    rooms = shapely.union_all([shapely.box(0, 0, 4, 3), shapely.box(4, 1.45, 4.6, 1.55), shapely.box(4.6, 0, 6.6, 3)])
    image, origin = rasterise(rooms, 0.05, ragged=0.25, seed=2)
    source = write_map(tmp_path, image, origin, 0.05)
    done = import_floorplan(source, seed_point=("5.6", "1.5"), spur_width=0)  # the raster keeps the passage
    assert done.settings["simplify_m"] > 0.02
    closed = [f for f in done.features if f.kind == "passage_closed"]
    assert closed and all(f.size < 0.3 for f in closed)  # each listed where it was, with its width
    assert float(done.environment.area) < 6.5  # the small room only (2 × 3 m less its shrunk walls)
    assert done.environment.to_shapely().contains(shapely.Point(5.6, 1.5))
