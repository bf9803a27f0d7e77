"""The ``import`` command: the contract's summary, the environment file, bad input as one line (exit 2)."""

from __future__ import annotations

import json

import ezdxf
import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan.cli import app
from solverplan.environment import load_environment

from .maps import FREE, OCCUPIED, office_polygon, rasterise, write_map

runner = CliRunner()


@pytest.fixture
def office_map(tmp_path):
    image, origin = rasterise(office_polygon(), 0.1, ragged=0.1, speckle=0.005, seed=1)
    return write_map(tmp_path, image, origin, 0.1)


def test_import_prints_the_summary_and_writes_the_environment(tmp_path, office_map):
    out = tmp_path / "office.json"
    result = runner.invoke(app, ["import", str(office_map), "-o", str(out), "--simplify", "0.1", "--rectilinear", "2",
                                 "--min-obstacle", "0.25"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    specks = [f for f in summary["features"] if f["kind"] == "speckle"]
    assert len(specks) == summary["dropped"]["speckle"] > 0 and all(f["size"] < 0.25 for f in specks)
    assert summary["settings"]["min_obstacle_m"] == 0.25 and summary["warnings"] == []
    assert list(summary)[:7] == ["kind", "status", "written", "outer_vertices", "holes", "dropped", "area"]
    assert summary["written"] == str(out) and summary["holes"] == 2 and summary["format"] == "ros"
    environment = load_environment(out)
    assert summary["outer_vertices"] == len(environment.outer)
    assert summary["area"] == pytest.approx(float(environment.area)) == pytest.approx(office_polygon().area, rel=0.03)
    assert summary["environment"]["sha256"] and summary["resolution"] == "0.1"


def test_import_text_report(tmp_path, office_map):
    result = runner.invoke(app, ["import", str(office_map), "-o", str(tmp_path / "o.wkt"), "--format", "text",
                                 "--min-obstacle", "0.25"])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith(f"import {office_map} (ros): found\n") and "2 holes" in result.stdout
    assert (tmp_path / "o.wkt").read_text().startswith("POLYGON ((")


def _map(tmp_path, yaml: str, image: np.ndarray | None = None):
    if image is not None:
        from PIL import Image

        Image.fromarray(image).save(tmp_path / "m.pgm")
    (tmp_path / "m.yaml").write_text(yaml)
    return tmp_path / "m.yaml"


GOOD = "image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\n"
ROOM = np.full((20, 20), OCCUPIED, np.uint8)
ROOM[2:18, 2:18] = FREE


@pytest.mark.parametrize("yaml,image,message", [
    ("image: nothere.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n", None, "image .*nothere.pgm does not exist"),
    (GOOD + "occupied_thresh: 0.2\nfree_thresh: 0.6\n", ROOM, "thresholds out of order"),
    ("- image: m.pgm\n- resolution: 0.1\n", ROOM, "not a ROS map: expected a YAML mapping"),
    ("", ROOM, "not a ROS map: expected a YAML mapping with image, resolution and origin, got empty"),
    ("image: m.pgm\norigin: [0, 0, 0]\n", ROOM, "missing 'resolution'"),
    ("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n", ROOM, "resolution must be positive"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0]\nmode: fancy\n", ROOM, "unknown mode 'fancy'"),
    ("image: [m.pgm\n", ROOM, "not valid YAML"),
    (GOOD, np.full((5, 5), OCCUPIED, np.uint8), "the map has no free space"),
])
def test_malformed_maps_exit_2_with_one_line(tmp_path, yaml, image, message):
    source = _map(tmp_path, yaml, image)
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: ")
    assert __import__("re").search(message, result.stderr), result.stderr
    assert not (tmp_path / "e.json").exists()


def test_a_corrupt_image_exits_2(tmp_path):
    source = _map(tmp_path, GOOD)
    (tmp_path / "m.pgm").write_bytes(b"P5\n20 20\n255\n" + b"\x00" * 17)  # truncated
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and "cannot read the image" in result.stderr and result.stderr.count("\n") == 1


@pytest.mark.parametrize("point,message", [("0.05,0.05", "no free space at the seed point (0.05, 0.05): its cell is occupied"),
                                           ("50,50", "--seed-point (50, 50) is outside the map"),
                                           ("1,x", "--seed-point")])
def test_a_seed_point_off_the_free_space_exits_2(tmp_path, point, message):
    source = _map(tmp_path, GOOD, ROOM)
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json"), "--seed-point", point])
    assert result.exit_code == 2 and message in result.stderr and result.stderr.count("\n") == 1, result.stderr


@pytest.mark.parametrize("options,message", [(["--layer", "A"], "--layer, --units, --snap and --max-jamb apply to DXF"),
                                             (["--scale", "2"], "--scale applies to SVG"),
                                             (["--tolerance", "0.1"], "--tolerance applies to DXF and SVG"),
                                             (["--simplify", "-1"], "--simplify must be a non-negative"),
                                             (["--rectilinear", "50"], "--rectilinear must be below 45")])
def test_options_that_do_not_fit_exit_2(tmp_path, options, message):
    source = _map(tmp_path, GOOD, ROOM)
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json"), *options])
    assert result.exit_code == 2 and message in result.stderr, result.stderr


def test_an_empty_dxf_and_an_unknown_extension_exit_2(tmp_path):
    empty = tmp_path / "empty.dxf"
    ezdxf.new().saveas(empty)
    result = runner.invoke(app, ["import", str(empty), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and "no closed outline found" in result.stderr
    other = tmp_path / "plan.pdf"
    other.write_text("%PDF")
    result = runner.invoke(app, ["import", str(other), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and "use .yaml (ROS map), .dxf or .svg" in result.stderr
    result = runner.invoke(app, ["import", str(tmp_path / "none.yaml"), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and "no such file" in result.stderr


@pytest.mark.parametrize("yaml,message", [
    ("image: m.pgm\nresolution: 1e300\norigin: [0, 0, 0]\n", "resolution must be between 1e-9 and 1e+6 metres per cell, got 1e+300"),
    ("image: m.pgm\nresolution: 0.1\norigin: [1e99, 0, 0]\n", "origin must be three numbers [x, y, yaw] of magnitude at most 1e+12"),
    ("image: m.pgm\nresolution: .nan\norigin: [0, 0, 0]\n", "resolution must be a number, got 'nan'"),
])
def test_numbers_out_of_range_exit_2(tmp_path, yaml, message):
    source = _map(tmp_path, yaml, ROOM)
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and message in result.stderr, result.stderr


def test_numbers_yaml_1_1_reads_as_strings_are_numbers(tmp_path):
    source = _map(tmp_path, "image: m.pgm\nresolution: 1e-1\norigin: ['0.5', 2e0, 0]\n", ROOM)
    result = runner.invoke(app, ["import", str(source), "-o", str(tmp_path / "e.json"), "--spur-width", "0"])
    assert result.exit_code == 0, result.output
    environment = load_environment(tmp_path / "e.json")
    assert min(float(x) for x, _ in environment.outer) == 0.7 and float(environment.area) == pytest.approx(2.56)


def test_input_format_names_the_kind_when_the_extension_does_not(tmp_path):
    source = _map(tmp_path, GOOD, ROOM)
    renamed = tmp_path / "map.conf"
    renamed.write_text(source.read_text())
    result = runner.invoke(app, ["import", str(renamed), "-o", str(tmp_path / "e.json"), "--input-format", "ros"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["format"] == "ros"
    result = runner.invoke(app, ["import", str(renamed), "-o", str(tmp_path / "e.json")])
    assert result.exit_code == 2 and "cannot tell the floor plan's format" in result.stderr
