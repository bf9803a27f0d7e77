"""The `solverplan` command: JSON answers, text tables, exit codes, one-line errors, atomic -o.

Driven through typer's CliRunner (stdout and stderr captured separately), plus one subprocess
test of the installed console script.
"""

from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest

from solverplan.errors import SolverFailed
from tests.cli_runs import run, write, assert_one_line_error


ROOM_WITH_PILLAR = {
    "name": "room with pillar",
    "outer": [[0, 0], [10, 0], [10, 6], [6, 6], [6, 4], [0, 4]],
    "holes": [[[2, 1], [4, 1], [4, 2.5], [2, 2.5]]],  # counter-clockwise: reversed on load
}


@pytest.fixture
def pillar(tmp_path) -> Path:
    """ROOM_WITH_PILLAR written to ``pillar.json`` in the test's folder."""
    return write(tmp_path, "pillar.json", ROOM_WITH_PILLAR)


# ---------------------------------------------------------------------- info: answers
def test_info_polygon_with_hole_prints_contract_fields(pillar):
    result = run("info", pillar)
    assert result.exit_code == 0, result.stderr
    assert result.stderr == ""
    data = json.loads(result.stdout)
    assert data["name"] == "room with pillar"
    assert (data["n_vertices"], data["n_edges"], data["n_holes"]) == (10, 10, 1)
    assert data["vertices"] == [
        [[0, 0], [10, 0], [10, 6], [6, 6], [6, 4], [0, 4]],
        [[2, 1], [2, 2.5], [4, 2.5], [4, 1]],  # hole normalised to clockwise, first vertex kept
    ]
    assert data["rings"] == [
        {"index": 0, "kind": "outer", "vertices": [0, 1, 2, 3, 4, 5], "reoriented": False},
        {"index": 1, "kind": "hole", "vertices": [6, 7, 8, 9], "reoriented": True},
    ]
    assert data["notes"] == ["hole 0 was counter-clockwise: vertex order reversed"]
    assert [e["id"] for e in data["edges"]] == list(range(10))
    assert data["edges"][5] == {"id": 5, "ring": 0, "vertices": [5, 0], "a": [0, 4], "b": [0, 0], "length": 4.0}
    assert data["edges"][9] == {"id": 9, "ring": 1, "vertices": [9, 6], "a": [4, 1], "b": [2, 1], "length": 2.0}
    assert data["reflex"] == [4, 6, 7, 8, 9]  # the L's inner corner and every corner of the pillar
    assert (data["area"], data["area_exact"]) == (45.0, "45")
    assert data["perimeter"] == 39.0
    assert data["bounds"] == [0.0, 0.0, 10.0, 6.0]


def test_info_clockwise_outer_ring_says_it_was_reversed(tmp_path):
    env = write(tmp_path, "cw.json", {"outer": [[0, 0], [0, 2], [3, 2], [3, 0]]})
    result = run("info", env)
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["notes"] == ["outer ring was clockwise: vertex order reversed"]
    assert data["rings"][0]["reoriented"] is True
    assert data["vertices"] == [[[0, 0], [3, 0], [3, 2], [0, 2]]]
    assert data["name"] == "cw"  # the file's stem when the file names none


def test_info_numbers_stay_exact(tmp_path):
    env = write(tmp_path, "exact.json", '{"outer": [[0, 0], [0.1, 0], [0, "1/3"]]}')
    result = run("info", env)
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout, parse_float=Decimal)
    assert data["vertices"] == [[[0, 0], [Decimal("0.1"), 0], [0, "1/3"]]]
    assert data["area_exact"] == "1/60"


def test_info_reads_wkt_and_env_format_overrides_the_extension(tmp_path):
    wkt = write(tmp_path, "tri.wkt", "POLYGON ((0 0, 4 0, 0 3, 0 0))")
    by_extension = run("info", wkt)
    assert by_extension.exit_code == 0, by_extension.stderr
    assert json.loads(by_extension.stdout)["perimeter"] == 12.0
    odd = write(tmp_path, "tri.txt", {"outer": [[0, 0], [4, 0], [0, 3]]})
    forced = run("info", odd, "--env-format", "json")
    assert forced.exit_code == 0, forced.stderr
    assert json.loads(forced.stdout)["area_exact"] == "6"


def test_info_format_text_prints_tables(pillar):
    result = run("info", pillar, "--format", "text")
    assert result.exit_code == 0, result.stderr
    text = result.stdout
    assert text.startswith("environment 'room with pillar'")
    assert "hole 0 was counter-clockwise: vertex order reversed" in text
    for heading in ("rings", "vertices", "edges"):
        assert f"\n{heading}" in text
    assert "4, 6, 7, 8, 9" in text  # reflex vertices
    assert "(4, 2.5)" in text  # an exact end point in the edge table
    with pytest.raises(json.JSONDecodeError):
        json.loads(text)


# ---------------------------------------------------------------------- info: -o
def test_info_output_file_is_written_instead_of_stdout(tmp_path, pillar):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / "info.json"
    out.write_text("old answer")
    result = run("info", pillar, "-o", out)
    assert result.exit_code == 0, result.stderr
    assert result.stdout == ""
    assert json.loads(out.read_text()) == json.loads(run("info", pillar).stdout)
    assert sorted(os.listdir(out_dir)) == ["info.json"]  # no temporary file left behind


def test_info_text_to_output_file(tmp_path, pillar):
    out = tmp_path / "info.txt"
    result = run("info", pillar, "--format", "text", "-o", out)
    assert result.exit_code == 0, result.stderr
    assert result.stdout == ""
    assert out.read_text().startswith("environment 'room with pillar'")


def test_info_error_writes_nothing_and_keeps_the_old_file(tmp_path):
    bowtie = write(tmp_path, "bowtie.json", {"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]})
    fresh, old = tmp_path / "fresh.json", tmp_path / "old.json"
    old.write_text("old answer")
    assert_one_line_error(run("info", bowtie, "-o", fresh), 2, "crosses")
    assert_one_line_error(run("info", bowtie, "-o", old), 2, "crosses")
    assert not fresh.exists()
    assert old.read_text() == "old answer"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bowtie.json", "old.json"]


def test_info_unwritable_output_is_bad_input(tmp_path, pillar):
    assert_one_line_error(run("info", pillar, "-o", tmp_path / "missing" / "info.json"), 2, "cannot write")


# ---------------------------------------------------------------------- bad input: exit 2, one line
def test_bowtie_is_rejected_naming_the_crossing(tmp_path):
    env = write(tmp_path, "bowtie.json", {"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]})
    line = assert_one_line_error(run("info", env), 2, "edge 0 crosses edge 2 at (1, 1)")
    assert line == f"error: {env}: outer ring self-intersects: edge 0 crosses edge 2 at (1, 1)"


def test_hole_outside_the_outer_ring(tmp_path):
    env = write(tmp_path, "outside.json", {"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], "holes": [[[5, 5], [6, 5], [6, 6]]]})
    assert_one_line_error(run("info", env), 2, "hole 0 lies outside the outer ring")


def test_nan_coordinate(tmp_path):
    env = write(tmp_path, "nan.json", '{"outer": [[0, 0], [1, NaN], [2, 0]]}')
    assert_one_line_error(run("info", env), 2, "NaN")


def test_truncated_json(tmp_path):
    env = write(tmp_path, "truncated.json", '{"outer": [[0, 0], [1,')
    assert_one_line_error(run("info", env), 2, "not valid JSON")


def test_missing_file(tmp_path):
    assert_one_line_error(run("info", tmp_path / "nowhere.json"), 2, "no such file")


def test_unknown_extension(tmp_path):
    env = write(tmp_path, "room.txt", {"outer": [[0, 0], [1, 0], [0, 1]]})
    assert_one_line_error(run("info", env), 2, "cannot tell the format from the extension '.txt'")


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["info", "{env}", "--format", "yaml"], "'yaml' is not one of 'json', 'text'"),
        (["info", "{env}", "--env-format", "shp"], "--env-format"),
        (["info", "{env}", "--no-such-option"], "--no-such-option"),
        (["info"], "Missing argument 'ENV'"),
        (["render", "{env}"], "-o"),
        (["frobnicate"], "frobnicate"),
    ],
)
def test_usage_errors_exit_2_with_one_line(args, fragment, pillar):
    result = run(*(str(a).format(env=pillar) for a in args))
    line = assert_one_line_error(result, 2, fragment)
    assert "--help" in line  # where to look next


# ---------------------------------------------------------------------- failures: exit 1
def test_library_failure_exits_1_with_one_line(monkeypatch, pillar):
    def fail(env):
        raise SolverFailed("the tolerance LP returned 'inaccurate'")

    monkeypatch.setattr("solverplan.describe.describe_environment", fail)  # imported by info when it runs
    line = assert_one_line_error(run("info", pillar), 1, "inaccurate")
    assert line == "error: the tolerance LP returned 'inaccurate'"


def test_unexpected_exception_exits_1_traceback_only_with_verbose(monkeypatch, pillar):
    def crash(env):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr("solverplan.describe.describe_environment", crash)
    line = assert_one_line_error(run("info", pillar), 1, "internal error: ZeroDivisionError: boom")
    assert "-v" in line
    verbose = run("info", pillar, "-v")
    assert verbose.exit_code == 1
    assert "Traceback (most recent call last)" in verbose.stderr
    assert verbose.stderr.splitlines()[-1] == "error: internal error: ZeroDivisionError: boom"


def test_verbose_logs_to_stderr_and_keeps_stdout_json(pillar):
    result = run("info", pillar, "-v")
    assert result.exit_code == 0
    assert "loaded 'room with pillar': 10 vertices, 1 holes" in result.stderr
    assert json.loads(result.stdout)["n_edges"] == 10


# ---------------------------------------------------------------------- render
def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_render_png(tmp_path, pillar):
    out = tmp_path / "pillar.png"
    result = run("render", pillar, "--edge-ids", "--vertex-ids", "-o", out)
    assert result.exit_code == 0, result.stderr
    assert result.stderr == ""
    data = out.read_bytes()
    assert json.loads(result.stdout) == {"written": str(out), "format": "png", "bytes": len(data)}
    width, height = png_size(data)
    assert width > 400 and height > 200


def test_render_svg_carries_edge_ids(tmp_path, pillar):
    out = tmp_path / "pillar.svg"
    result = run("render", pillar, "--edge-ids", "-o", out, "--format", "text")
    assert result.exit_code == 0, result.stderr
    assert result.stdout.startswith(f"wrote {out} (SVG, ")
    svg = out.read_text()
    assert svg.startswith("<?xml") and "<svg" in svg
    assert all(f'id="edge-id-{i}"' in svg for i in range(10))
    assert 'id="vertex-id-0"' not in svg  # vertex ids only on request


def test_render_unknown_picture_format_writes_nothing(tmp_path, pillar):
    out = tmp_path / "pillar.pdf"
    assert_one_line_error(run("render", pillar, "-o", out), 2, "unknown picture format '.pdf'")
    assert not out.exists()


def test_render_bad_environment_writes_nothing(tmp_path):
    env = write(tmp_path, "bowtie.json", {"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]})
    out = tmp_path / "bowtie.png"
    assert_one_line_error(run("render", env, "-o", out), 2, "edge 0 crosses edge 2 at (1, 1)")
    assert not out.exists()


# ---------------------------------------------------------------------- the installed command
def installed_command() -> str:
    beside = Path(sys.executable).with_name("solverplan")
    found = str(beside) if beside.exists() else shutil.which("solverplan")
    if found is None:
        pytest.skip("the solverplan console script is not installed (pip install -e .)")
    return found


def test_installed_command_runs_info_and_reports_bad_input(tmp_path, pillar):
    command = installed_command()
    ok = subprocess.run([command, "info", str(pillar)], capture_output=True, text=True, check=False)
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["reflex"] == [4, 6, 7, 8, 9]
    bowtie = write(tmp_path, "bowtie.json", {"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]})
    bad = subprocess.run([command, "info", str(bowtie)], capture_output=True, text=True, check=False)
    assert bad.returncode == 2
    assert bad.stdout == ""
    assert bad.stderr.splitlines() == [f"error: {bowtie}: outer ring self-intersects: edge 0 crosses edge 2 at (1, 1)"]
    usage = subprocess.run([command, "info", str(pillar), "--format", "yaml"], capture_output=True, text=True, check=False)
    assert usage.returncode == 2
    assert len(usage.stderr.splitlines()) == 1
