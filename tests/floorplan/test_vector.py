"""DXF and SVG drawings written here read back exactly; curves are flattened within the tolerance."""

from __future__ import annotations

import math
from decimal import Decimal
from fractions import Fraction

import ezdxf
import pytest

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, MalformedFile
from solverplan.floorplan import import_floorplan, read_dxf_rings, read_svg_rings

F = Fraction


def _expected(outer, holes=()) -> Environment:
    return Environment.from_coords(outer, holes)


def _canonical(ring):
    """A ring from its least vertex (the same ring, whatever vertex a reader starts at)."""
    start = ring.index(min(ring))
    return ring[start:] + ring[:start]


def test_dxf_polylines_and_chained_lines_read_back_exactly_in_metres(tmp_path):
    doc = ezdxf.new(units=4)  # millimetres
    space = doc.modelspace()
    space.add_lwpolyline([(0, 0), (12500, 0), (12500, 8250), (0, 8250)], close=True, dxfattribs={"layer": "WALLS"})
    space.add_polyline2d([(1000, 1000), (2000, 1000), (2000, 1750), (1000, 1750)], close=True, dxfattribs={"layer": "WALLS"})
    # a column drawn as four loose lines, in scrambled order and direction
    for a, b in [((5000, 5000), (5500, 5000)), ((5000, 5500), (5000, 5000)), ((5500, 5500), (5000, 5500)),
                 ((5500, 5000), (5500, 5500))]:
        space.add_line(a, b, dxfattribs={"layer": "WALLS"})
    space.add_line((100, 100), (200, 300), dxfattribs={"layer": "WALLS"})  # dangling: no loop
    space.add_lwpolyline([(0, 0), (99999, 0), (99999, 99999)], close=True, dxfattribs={"layer": "FURNITURE"})
    space.add_circle((7000, 3000), 300, dxfattribs={"layer": "WALLS"})
    space.add_lwpolyline([(2000, 1750), (2000, 1000), (1000, 1000), (1000, 1750)], close=True,
                         dxfattribs={"layer": "WALLS"})  # the first hole drawn again, backwards
    file = tmp_path / "plan.dxf"
    doc.saveas(file)
    done = import_floorplan(file, layer="walls", output=tmp_path / "plan.json")
    want = _expected([("0", "0"), ("12.5", "0"), ("12.5", "8.25"), ("0", "8.25")],
                     [[("1", "1"), ("2", "1"), ("2", "1.75"), ("1", "1.75")],
                      [("5", "5"), ("5.5", "5"), ("5.5", "5.5"), ("5", "5.5")]])
    got = done.environment
    assert _canonical(got.outer) == _canonical(want.outer)
    squares = [h for h in got.holes if len(h) == 4]
    assert sorted(map(_canonical, squares)) == sorted(map(_canonical, want.holes))
    # the CIRCLE is a column: a regular polygon around it, within the tolerance (1 cm)
    column = [h for h in got.holes if len(h) > 4]
    assert len(column) == 1
    radii = [math.hypot(float(x) - 7, float(y) - 3) for x, y in column[0]]
    assert all(0.3 <= r <= 0.3 + 0.01 for r in radii)
    assert load_environment(tmp_path / "plan.json") == got
    column_area = float(Environment.from_coords(column[0]).area)
    assert math.pi * 0.09 <= column_area <= math.pi * 0.31 ** 2
    assert done.units == "m" and done.area == pytest.approx(12.5 * 8.25 - 0.75 - 0.25 - column_area, abs=1e-9)
    assert done.dropped["other_layers"] == 1 and done.dropped["unsupported"] == {}
    dangling = [f for f in done.features if f.kind == "dangling_line"]
    assert len(dangling) == 1 and dangling[0].at == pytest.approx((0.15, 0.2)) and dangling[0].size == pytest.approx(
        math.hypot(0.1, 0.2))
    assert done.warnings == ()


def test_dxf_units_come_from_the_header_and_units_overrides_them(tmp_path):
    doc = ezdxf.new(units=1)  # inches
    doc.modelspace().add_lwpolyline([(0, 0), (100, 0), (100, 50), (0, 50)], close=True)
    file = tmp_path / "inches.dxf"
    doc.saveas(file)
    inches = import_floorplan(file).environment
    assert inches.area == F(254, 100) * F(127, 100)  # 2.54 m × 1.27 m, exactly
    unitless = import_floorplan(file, units="unitless")
    assert unitless.units == "unitless" and unitless.environment.area == 5000
    with pytest.raises(InputError, match="--units 'parsec'"):
        import_floorplan(file, units="parsec")


def test_dxf_bulges_are_flattened_within_the_tolerance(tmp_path):
    doc = ezdxf.new(units=6)
    # a 4 × 2 room whose right wall is a half circle of radius 1 (bulge 1 = 180°)
    doc.modelspace().add_lwpolyline([(0, 0, 0), (4, 0, 1), (4, 2, 0), (0, 2, 0)], format="xyb", close=True)
    file = tmp_path / "apse.dxf"
    doc.saveas(file)
    rings, _ = read_dxf_rings(file, tolerance=0.001)
    arc = [(float(x), float(y)) for x, y in rings[0] if float(x) > 4]
    assert len(arc) > 10
    assert all(abs(math.hypot(x - 4, y - 1) - 1) <= 0.001 + 1e-9 for x, y in arc)


def test_a_dxf_without_outline_or_not_dxf_is_a_malformed_file(tmp_path):
    empty = tmp_path / "empty.dxf"
    ezdxf.new().saveas(empty)
    with pytest.raises(MalformedFile, match="no closed outline found"):
        import_floorplan(empty)
    junk = tmp_path / "junk.dxf"
    junk.write_text("this is not a drawing\n")
    with pytest.raises(MalformedFile, match="not a valid DXF file|cannot read"):
        import_floorplan(junk)


SVG = """<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 200 100">
  <path d="M 0 0 L 200 0 L 200 100 L 0 100 Z M 20 20 L 40 20 L 40 50 Z"/>
  <g transform="translate(100 10)"><rect x="0" y="0" width="30" height="15"/></g>
  <circle cx="150" cy="60" r="10"/>
  <path d="M 1 1 L 5 5"/>
  <rect x="300" y="300" width="5" height="5"/>
</svg>"""


def test_svg_closed_paths_read_back_exactly_with_y_flipped_and_scaled(tmp_path):
    file = tmp_path / "plan.svg"
    file.write_text(SVG)
    done = import_floorplan(file, scale="0.05", output=tmp_path / "plan.json")
    got = done.environment
    assert _canonical(got.outer) == _canonical(_expected([("0", "0"), ("10", "0"), ("10", "5"), ("0", "5")]).outer)
    holes = [_canonical(h) for h in got.holes]
    triangle = _expected([("0", "0"), ("10", "0"), ("10", "5"), ("0", "5")], [[("1", "4"), ("2", "4"), ("2", "2.5")]])
    assert _canonical(triangle.holes[0]) in holes
    box = _expected([("0", "0"), ("10", "0"), ("10", "5"), ("0", "5")], [[("5", "4.5"), ("6.5", "4.5"), ("6.5", "3.75"), ("5", "3.75")]])
    assert _canonical(box.holes[0]) in holes
    assert len(got.holes) == 3  # with the circle
    assert done.dropped["open_paths"] == 1 and done.dropped["outside"] == 1
    assert load_environment(tmp_path / "plan.json") == got


def test_svg_curves_are_flattened_within_the_tolerance(tmp_path):
    file = tmp_path / "plan.svg"
    file.write_text(SVG)
    rings, _ = read_svg_rings(file, scale=Decimal("0.05"), tolerance=0.002)
    circle = [r for r in rings if len(r) > 8]
    assert len(circle) == 1
    cx, cy, radius = 7.5, 2.0, 0.5
    points = [(float(x), float(y)) for x, y in circle[0]]
    assert all(abs(math.hypot(x - cx, y - cy) - radius) <= 1e-3 for x, y in points)
    # chords stay within the tolerance: the sagitta of each chord of a circle is r (1 − cos(θ/2))
    for (x0, y0), (x1, y1) in zip(points, points[1:] + points[:1]):
        chord = math.hypot(x1 - x0, y1 - y0)
        assert radius - math.sqrt(max(radius**2 - chord**2 / 4, 0)) <= 0.002 + 1e-4


def test_not_svg_is_a_malformed_file(tmp_path):
    file = tmp_path / "bad.svg"
    file.write_text("<svg><path d=")
    with pytest.raises(MalformedFile):
        import_floorplan(file)


def test_a_skewed_drawing_is_snapped_and_simplified_on_request(tmp_path):
    doc = ezdxf.new(units=6)
    # a 6 × 4 room drawn a little off square, with a wobble on the floor
    doc.modelspace().add_lwpolyline([(0, 0), (3, 0.004), (6, 0.02), (6.03, 4), (0, 4.01)], close=True)
    file = tmp_path / "skewed.dxf"
    doc.saveas(file)
    exact = import_floorplan(file).environment
    assert len(exact.outer) == 5 and exact.outer[1] == (F(3), F(4, 1000))
    done = import_floorplan(file, simplify=0.01, rectilinear=2)
    outer = done.environment.outer
    assert len(outer) == 4 and done.dropped["simplified_vertices"] == 1
    assert all(a[0] == b[0] or a[1] == b[1] for a, b in zip(outer, outer[1:] + outer[:1]))


@pytest.mark.parametrize("output,message", [("-", "-o - is not available"), ("env.txt", "use .json, .geojson or .wkt")])
def test_the_output_must_be_an_environment_file(tmp_path, output, message):
    file = tmp_path / "plan.svg"
    file.write_text(SVG)
    with pytest.raises((InputError, MalformedFile), match=message):
        import_floorplan(file, output=tmp_path / output if output != "-" else output)


def test_dxf_block_references_are_expanded_on_their_layer(tmp_path):
    doc = ezdxf.new(units=6)
    column = doc.blocks.new(name="COLUMN")
    column.add_lwpolyline([(0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5)], close=True)  # layer 0: takes the INSERT's
    space = doc.modelspace()
    space.add_lwpolyline([(0, 0), (10, 0), (10, 6), (0, 6)], close=True, dxfattribs={"layer": "WALLS"})
    space.add_blockref("COLUMN", (2, 2), dxfattribs={"layer": "WALLS"})
    space.add_blockref("COLUMN", (7, 3), dxfattribs={"layer": "WALLS"})
    space.add_blockref("COLUMN", (4, 4), dxfattribs={"layer": "FURNITURE"})
    file = tmp_path / "columns.dxf"
    doc.saveas(file)
    done = import_floorplan(file, layer="WALLS")
    holes = sorted(_canonical(h) for h in done.environment.holes)
    assert [h[0] for h in holes] == [(F(2), F(2)), (F(7), F(3))]
    assert done.area == 60 - 2 * 0.25 and done.dropped["other_layers"] == 1
