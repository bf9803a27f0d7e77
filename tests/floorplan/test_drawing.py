"""Drawings as architects draw them: walls as line pairs, touching partitions, columns, doors as gaps, hatches.

Each drawing is made here with ezdxf from a known free space (shapely), and the import must give that free space
back: its area within 2 % (in practice within the columns' chord tolerance), its obstacles as holes, nothing silent.
"""

from __future__ import annotations

import math

import ezdxf
import pytest
import shapely
from shapely.geometry import Point, box

from solverplan.errors import MalformedFile
from solverplan.floorplan import import_floorplan

W, H, T, P = 12000, 8000, 200, 100  # millimetres: interior, outer wall, partition
COLUMNS = ((2500, 2500), (2500, 5500), (7500, 4000))
COLUMN_R = 150


def _plan(path, *, jambs: bool = True, gap: float = 0.0, blocks: bool = False, text: bool = True) -> float:
    """Write the CAD-style plan; returns the true free area (m²).

    Outer walls: two loops of LINEs (outer face and inner face, 200 mm apart). A partition (100 mm) at x = 5000
    touches the outer wall top and bottom and has a 900 mm door; its lines stop *on* the inner wall line (the inner
    line is not broken there, as drafters leave it). A second partition stub hangs from the top wall (an open
    polyline). Three columns are CIRCLEs (or INSERTs of a block holding one). ``gap`` moves every line's end that
    much: ends that do not quite meet.
    """
    doc = ezdxf.new(units=4)
    space = doc.modelspace()

    def loop(points):
        for a, b in zip(points, points[1:] + points[:1]):
            space.add_line(a, (b[0] + gap, b[1] + gap), dxfattribs={"layer": "WALLS"})

    loop([(-T, -T), (W + T, -T), (W + T, H + T), (-T, H + T)])
    loop([(0, 0), (W, 0), (W, H), (0, H)])
    x0, x1 = 5000, 5000 + P
    for ya, yb in ((0, 3000), (3900, H)):
        space.add_line((x0, ya), (x0, yb), dxfattribs={"layer": "WALLS"})
        space.add_line((x1, ya), (x1, yb), dxfattribs={"layer": "WALLS"})
        if jambs:
            for y in (ya, yb):
                if y not in (0, H):
                    space.add_line((x0, y), (x1, y), dxfattribs={"layer": "WALLS"})
    space.add_lwpolyline([(9000, H), (9000, 5000), (9100, 5000), (9100, H)], dxfattribs={"layer": "WALLS"})
    if blocks:
        block = doc.blocks.new("COLUMN")
        block.add_circle((0, 0), COLUMN_R)
        for c in COLUMNS:
            space.add_blockref("COLUMN", c, dxfattribs={"layer": "COLUMNS"})
    else:
        for c in COLUMNS:
            space.add_circle(c, COLUMN_R, dxfattribs={"layer": "COLUMNS"})
    if text:
        space.add_text("Office", dxfattribs={"layer": "TEXT"}).set_placement((1000, 1000))
    doc.saveas(path)
    free = box(0, 0, W, H).difference(box(x0, 0, x1, 3000)).difference(box(x0, 3900, x1, H))
    free = free.difference(box(9000, 5000, 9100, H))
    for c in COLUMNS:
        free = free.difference(Point(c).buffer(COLUMN_R, quad_segs=256))
    return free.area / 1e6


@pytest.mark.parametrize("variant", [{}, {"jambs": False}, {"gap": 1e-6}, {"blocks": True}])
def test_a_cad_plan_imports_within_two_percent_with_its_columns_and_partitions(tmp_path, variant):
    truth = _plan(tmp_path / "plan.dxf", **variant)
    done = import_floorplan(tmp_path / "plan.dxf", output=tmp_path / "plan.json")
    assert done.area == pytest.approx(truth, rel=0.02)
    assert done.area == pytest.approx(truth, rel=2e-3)  # the columns' polygons are within 1 cm of their circles
    assert done.area <= truth  # columns are polygons around their circles: never thinner
    assert done.holes == 3 and done.units == "m" and done.warnings == ()
    # the partitions are walls: the outer ring goes around them, through the door
    ring = shapely.Polygon([(float(x), float(y)) for x, y in done.environment.outer])
    assert not ring.contains(Point(5.05, 1.5)) and ring.contains(Point(5.05, 3.45))  # wall, door
    assert not ring.contains(Point(9.05, 7.0))
    assert done.dropped["unsupported"] == {"TEXT": 1}
    if variant.get("jambs") is False:
        assert done.dropped["jambs_closed"] == 2
    if variant.get("gap"):
        assert done.dropped["ends_joined"] > 0


def test_only_the_walls_layer_leaves_the_columns_out_and_says_so(tmp_path):
    _plan(tmp_path / "plan.dxf")
    walls = import_floorplan(tmp_path / "plan.dxf", layer="WALLS")
    both = import_floorplan(tmp_path / "plan.dxf", layer="walls,columns")
    assert walls.holes == 0 and both.holes == 3
    assert walls.dropped["other_layers"] == 4  # three circles and the text
    assert walls.area == pytest.approx(both.area + 3 * math.pi * 0.15 ** 2, rel=1e-3)


def test_the_seed_point_chooses_the_face(tmp_path):
    _plan(tmp_path / "plan.dxf")
    band = import_floorplan(tmp_path / "plan.dxf", seed_point=("-0.1", "4"))  # inside the outer wall
    assert band.area == pytest.approx(12.4 * 8.4 - 12 * 8, rel=0.01)
    assert band.warnings  # a wall is no free space: said, not silent


def test_walls_drawn_as_a_hatch_are_solid(tmp_path):
    doc = ezdxf.new(units=6)  # metres
    space = doc.modelspace()
    hatch = space.add_hatch()
    hatch.paths.add_polyline_path([(-0.2, -0.2), (6.2, -0.2), (6.2, 4.2), (-0.2, 4.2)], is_closed=True)
    hatch.paths.add_polyline_path([(0, 0), (6, 0), (6, 4), (0, 4)], is_closed=True)
    space.add_lwpolyline([(2, 2), (3, 2), (3, 3), (2, 3)], close=True)  # a table
    file = tmp_path / "hatch.dxf"
    doc.saveas(file)
    done = import_floorplan(file)
    assert done.area == pytest.approx(24 - 1) and done.holes == 1
    assert done.settings["read"]["hatches"] == 1


def test_an_implausible_free_space_is_a_warning_never_a_silent_found(tmp_path):
    doc = ezdxf.new(units=4)
    space = doc.modelspace()
    # a title frame of 40 x 30 m, and walls drawn as single lines that do not close: only a 1.2 x 0.8 m table closes
    space.add_lwpolyline([(0, 0), (40000, 0), (40000, 30000), (0, 30000)], close=False)
    space.add_lwpolyline([(10000, 10000), (11200, 10000), (11200, 10800), (10000, 10800)], close=True)
    file = tmp_path / "table.dxf"
    doc.saveas(file)
    done = import_floorplan(file)
    assert done.area == pytest.approx(0.96)
    assert any("bounding box" in w for w in done.warnings)
    assert any(f.kind == "dangling_line" for f in done.features)


def test_a_drawing_that_encloses_nothing_is_a_clear_error(tmp_path):
    doc = ezdxf.new(units=4)
    doc.modelspace().add_line((0, 0), (1000, 0))
    doc.saveas(tmp_path / "line.dxf")
    with pytest.raises(MalformedFile, match="no closed outline found"):
        import_floorplan(tmp_path / "line.dxf")


def test_svg_user_units_follow_the_viewbox_and_width_units(tmp_path):
    # an Inkscape drawing in millimetres: 1 user unit = 1 mm, whatever CSS pixels are
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="4000mm" height="3000mm" viewBox="0 0 4000 3000">'
            '<rect width="4000" height="3000"/><rect x="1000" y="1000" width="500" height="500"/></svg>')
    (tmp_path / "mm.svg").write_text(text)
    done = import_floorplan(tmp_path / "mm.svg")
    assert done.units == "m" and done.area == pytest.approx(12 - 0.25) and done.settings["scale_m_per_user_unit"] == "0.001"
    given = import_floorplan(tmp_path / "mm.svg", scale="0.01")  # --scale: metres per user unit, not per pixel
    assert given.area == pytest.approx((12 - 0.25) * 100)
    (tmp_path / "px.svg").write_text(text.replace('width="4000mm" height="3000mm"', 'width="400" height="300"'))
    bare = import_floorplan(tmp_path / "px.svg")  # no physical size: user units as they are
    assert bare.units == "user units" and bare.area == pytest.approx(12e6 - 0.25e6)


def test_thick_polylines_and_multilines_are_walls(tmp_path):
    doc = ezdxf.new(units=6)
    space = doc.modelspace()
    # the outer walls as one closed polyline 0.2 m wide along the walls' centre line
    space.add_lwpolyline([(-0.1, -0.1), (6.1, -0.1), (6.1, 4.1), (-0.1, 4.1)], close=True,
                         dxfattribs={"const_width": 0.2})
    file = tmp_path / "thick.dxf"
    doc.saveas(file)
    done = import_floorplan(file)
    assert done.area == pytest.approx(24.0, rel=1e-6) and done.holes == 0
    doc = ezdxf.new(units=6)
    doc.modelspace().add_mline([(0, 0), (6, 0), (6, 4), (0, 4)], close=True)
    doc.saveas(tmp_path / "mline.dxf")
    lines = import_floorplan(tmp_path / "mline.dxf")
    assert lines.area > 20 and lines.dropped["unsupported"] == {}


def test_door_swings_leave_the_doorway_open(tmp_path):
    truth = _plan(tmp_path / "plan.dxf")
    doc = ezdxf.readfile(tmp_path / "plan.dxf")
    space = doc.modelspace()
    # the door in the partition (x 5000–5100, y 3000–3900): hinge at (5100, 3000), leaf open at 90°, swing arc
    space.add_line((5100, 3000), (6000, 3000))
    space.add_arc((5100, 3000), 900, 0, 90)
    doc.saveas(tmp_path / "door.dxf")
    done = import_floorplan(tmp_path / "door.dxf")
    assert done.area == pytest.approx(truth, rel=2e-3)
    assert done.dropped["door_swings"] == 1 and done.dropped["door_leaves"] == 1
    swing = [f for f in done.features if f.kind == "door_swing"]
    assert len(swing) == 1 and swing[0].at == pytest.approx((5.1, 3.0)) and swing[0].size == pytest.approx(0.9)
