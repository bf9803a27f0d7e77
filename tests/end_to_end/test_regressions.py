"""Regressions of the end-to-end runs on hidden-like inputs (benchmarks/end_to_end.py, issue #23): each test is the
smallest input of one bug those runs found, run through the command line as a tester does (answer, certificate,
verify, tamper, report)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from solverplan import cli

runner = CliRunner()


def run(*args: object):
    return runner.invoke(cli.app, [str(a) for a in args])


def write(folder: Path, name: str, outer: list, holes: list | None = None) -> Path:
    path = folder / f"{name}.json"
    path.write_text(json.dumps({"name": name, "outer": outer, "holes": holes or []}))
    return path


def test_fields_cell_side_along_collinear_edges(tmp_path):
    """A convex cell whose side runs along a straight wall written as two edges (a vertex of angle π) is on the wall:
    the exact check refused every fields answer of such an environment (exit 1, "not on a wall")."""
    env = write(tmp_path, "split_l", [[0, 0], [2, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    cert = tmp_path / "C.json"
    done = run("fields", env, "--from", "3,1", "--to", "1,3", "--trials", "1", "--scenario", "constrained",
               "-o", tmp_path / "A.json", "--certificate", cert)
    assert done.exit_code == 0, done.stderr
    assert run("verify", cert).exit_code == 0
    data = json.loads(cert.read_text())
    cell = data["claims"]["cells"][0]
    side = next(i for i, nb in enumerate(cell["neighbours"]) if nb is None)
    cell["polygon"][side][1] = "1/1000"  # the wall side moved off the wall: no longer on a wall
    (tmp_path / "T.json").write_text(json.dumps(data))
    assert run("verify", tmp_path / "T.json").exit_code == 1


def test_not_found_strategy_says_why_no_certificate(tmp_path):
    """A patrol, funnel or localisation with nothing to certify writes no certificate and says so on stderr, as plans
    and the other models do (it was silent: a script could not tell a missing file from a forgotten option)."""
    cert = tmp_path / "C.json"
    done = run("localize", "square", "--epsilon", "0.01", "--max-bounces", "2", "-o", tmp_path / "A.json",
               "--certificate", cert)
    assert done.exit_code == 0, done.stderr
    assert json.loads((tmp_path / "A.json").read_text())["status"] != "found"
    assert not cert.exists()
    assert f"warning: no certificate written to {cert}" in done.stderr


@pytest.mark.parametrize("extra", [[], ["--range", "2"]], ids=["views", "range-views"])
def test_explore_view_side_along_collinear_edges(tmp_path, extra):
    """A view's side along a straight wall written as two edges is on the boundary: the exact check refused every
    exploration whose first view saw such a wall (exit 1, "neither on the boundary nor along a line of sight")."""
    env = write(tmp_path, "split_square", [[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])
    cert = tmp_path / "C.json"
    done = run("explore", env, "--start", "1,1", *extra, "-o", tmp_path / "A.json", "--certificate", cert)
    assert done.exit_code == 0, done.stderr
    assert run("verify", cert).exit_code == 0
    data = json.loads(cert.read_text())
    polygon = data["claims"]["views"][0]["polygon"]
    k = next(i for i, p in enumerate(polygon) if p == [0, 0])
    polygon[k] = [0, "1/100"]  # the corner lifted off the split wall: that side is no longer on the boundary
    (tmp_path / "T.json").write_text(json.dumps(data))
    assert run("verify", tmp_path / "T.json").exit_code == 1


def test_patrol_leaving_from_a_run_of_segments_names_their_ends(tmp_path):
    """A patrol stage that leaves from a run of segments of P′ (the search runs on the merged walls) is certified with
    the run's end segments named: the exact check refused it ("its end p = 22/39 of edge 9 is not accounted for"),
    so `patrol` exited 1. The input is an imported occupancy map (a room with three boxes) with split walls."""
    env = write(tmp_path, "imported_map", [[12.9, 45.05], [12.9, 47.15], [12.9, 49.25], [10.975, 49.25], [9.05, 49.25],
                                           [9.05, 48.375], [9.05, 47.5], [9.3, 47.5], [9.3, 47], [9.05, 47],
                                           [9.05, 45.05], [10.0125, 45.05]],
                [[[10.45, 46], [10.15, 46], [10.15, 46.075], [10.15, 46.3], [10.45, 46.3]],
                 [[9.75, 46], [9.6875, 46], [9.5, 46], [9.5, 46.1], [9.75, 46.1]],
                 [[12, 45.4], [11.5, 45.4], [11.5, 45.9], [12, 45.9]]])
    cert = tmp_path / "C.json"
    done = run("patrol", env, "--visit", "e10,e23", "--objective", "rate", "-o", tmp_path / "A.json",
               "--certificate", cert)
    assert done.exit_code == 0, done.stderr
    assert run("verify", cert, "--env", env).exit_code == 0
    data = json.loads(cert.read_text())
    run_stage = next(s for s in data["stages"] if "source_segment" not in s["moves"][0])
    run_stage["moves"][0]["source"][0] = "1/3"  # an end no segment, set or image accounts for
    (tmp_path / "T.json").write_text(json.dumps(data))
    assert run("verify", tmp_path / "T.json").exit_code == 1


def test_explore_with_a_range_tiny_against_the_room_gives_up_at_once(tmp_path):
    """A range so small that even Area/(πR²) views exceed the view cap answers not-found after its first view: it
    ran towards the cap of 1,000 views (no answer within 120 s on a shared machine)."""
    env = write(tmp_path, "triangle", [[0, 0], [4, 0], [0, 3]])
    cert = tmp_path / "C.json"
    done = run("explore", env, "--start", "1,1", "--range", "1e-9", "-o", tmp_path / "A.json", "--certificate", cert)
    assert done.exit_code == 0, done.stderr
    answer = json.loads((tmp_path / "A.json").read_text())
    assert answer["status"] == "not-found" and answer["views"] == 1
    assert "views are needed" in answer["optimality"]["limits"][0]
    assert not cert.exists() and "no certificate written" in done.stderr
    assert run("report", tmp_path / "A.json", "--env", env, "-o", tmp_path / "R.html").exit_code == 0
