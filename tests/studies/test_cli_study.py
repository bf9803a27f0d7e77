"""`solverplan generate ...` and `solverplan study ...`: outputs, exit codes, one-line errors, kill and resume."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from solverplan.environment import load_environment, parse_environment
from solverplan.generators import rooms_and_corridors, star_polygon
from tests.cli_runs import run, assert_one_line_error


SMALL = ["--grid", "n=10", "--grid", "irregularity=0.1,0.4", "--grid", "spikiness=0.2,0.5"]


# ---------------------------------------------------------------------- generate
def test_generate_star_prints_the_environment_file():
    result = run("generate", "star", "--n", 12, "--irregularity", 0.2, "--spikiness", 0.4, "--seed", 7)
    assert result.exit_code == 0 and result.stderr == ""
    env = parse_environment(result.stdout, "json")
    assert env == star_polygon(12, 0.2, 0.4, seed=7)
    assert env.name == "star_polygon(n=12, irregularity=0.2, spikiness=0.4, radius=1, seed=7)"


@pytest.mark.parametrize("suffix", [".json", ".geojson", ".wkt"])
def test_generate_rooms_writes_the_file_atomically(tmp_path, suffix):
    path = tmp_path / f"rooms{suffix}"
    result = run("generate", "rooms", "--rooms", 5, "--loops", 1, "--seed", 3, "-o", path)
    assert result.exit_code == 0 and result.stdout == "" and result.stderr == ""
    assert load_environment(path).rings == rooms_and_corridors(5, loops=1, seed=3).rings
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary file left


def test_generate_rectilinear_and_holes():
    rect = parse_environment(run("generate", "rectilinear", "--rooms", 3, "--pillars", 2, "--seed", 1).stdout, "json")
    assert len(rect.holes) == 2 and all(c.denominator == 1 for p in rect.exact_vertices for c in p)
    holes = parse_environment(run("generate", "holes", "--n", 10, "--holes", 3, "--seed", 1).stdout, "json")
    assert len(holes.holes) == 3 and holes.n_edges == 10 + 3 * 6


@pytest.mark.parametrize(
    "args, fragment",
    [(["star", "--n", 2], "Invalid value for '--n'"),
     (["star", "--spikiness", 1.5], "Invalid value for '--spikiness'"),
     (["rooms", "--rooms", 3, "--loops", 2], "expected loops <= n_rooms // 2 - 1 = 0"),
     (["rooms", "--corridor-width", 3], "expected corridor_width < room_size / 3"),
     (["rectilinear", "--rooms", 3, "--pillars", 4], "expected pillars <= n_rooms = 3, got pillars=4"),
     (["holes", "--hole-kind", "round"], "expected hole_kind 'convex' or 'star', got hole_kind='round'"),
     (["blob"], "No such command 'blob'")],
)
def test_generate_bad_parameters_exit_2_with_one_line(args, fragment):
    assert_one_line_error(run("generate", *args), 2, fragment)


# ---------------------------------------------------------------------- study
def test_study_reachability_writes_tables_and_heatmap_and_resumes(tmp_path):
    result = run("study", "reachability", *SMALL, "--per-cell", 2, "--workers", 1, "--out-dir", tmp_path)
    assert result.exit_code == 0, result.stderr
    assert result.stderr == ""  # no progress bar when stderr is not a terminal
    summary = json.loads(result.stdout)
    assert (summary["rows"], summary["computed"], summary["reused"]) == (8, 8, 0)
    assert set(summary["files"]) == {"rows", "csv", "json", "figure"}
    for path in summary["files"].values():
        assert Path(path).parent == tmp_path and Path(path).stat().st_size > 0
    assert Path(summary["files"]["figure"]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [c["rows"] for c in summary["cells"]] == [2, 2, 2, 2]
    again = json.loads(run("study", "reachability", *SMALL, "--per-cell", 2, "--out-dir", tmp_path, "-q").stdout)
    assert (again["computed"], again["reused"]) == (0, 8)
    assert again["means"] == summary["means"] | {"seconds": again["means"]["seconds"]}


def test_study_connectivity_text_and_output_file(tmp_path):
    out = tmp_path / "summary.txt"
    result = run("study", "connectivity", *SMALL, "--per-cell", 1, "--workers", 1, "--out-dir", tmp_path / "c",
                 "--no-figure", "--format", "text", "-o", out)
    assert result.exit_code == 0 and result.stdout == ""
    text = out.read_text()
    assert text.startswith("study connectivity: star polygons, 4 cells x 1 seeds = 4 rows (4 computed, 0 reused)")
    assert "irregularity  spikiness" in text and not (tmp_path / "c" / "connectivity.png").exists()


def test_study_rules_has_one_row_per_family(tmp_path):
    result = run("study", "rules", *SMALL, "--per-cell", 1, "--workers", 1, "--out-dir", tmp_path, "--rules", "any,fixed:pi/4",
                 "--trials", 10, "--bounces", 6)
    assert result.exit_code == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["rows"] == 8 and set(summary["means_by"]["rule"]) == {"any", "fixed:pi/4"}
    assert summary["means_by"]["rule"]["fixed:pi/4"]["unreachable"] >= summary["means_by"]["rule"]["any"]["unreachable"]


@pytest.mark.parametrize(
    "args, fragment",
    [(["--grid", "irregularity=1.5"], "expected irregularity in [0, 1], got irregularity=1.5"),
     (["--grid", "rooms=3"], "generator 'star' has no parameter 'rooms'"),
     (["--grid", "spikiness"], "grid axis 'spikiness': expected NAME=VALUES"),
     (["--grid", "spikiness=0.1:0.5"], "spikiness: expected VALUE, V1,V2,... or START:STOP:COUNT"),
     (["--generator", "rooms", "--grid", "n=3"], "generator 'rooms' has no parameter 'n'"),
     (["--generator", "dodecahedron"], "Invalid value for '--generator'"),
     (["--per-cell", 0], "Invalid value for '--per-cell'"),
     (["--workers", 0], "Invalid value for '--workers'")],
)
def test_study_bad_parameters_exit_2_with_one_line(tmp_path, args, fragment):
    assert_one_line_error(run("study", "reachability", *args, "--out-dir", tmp_path), 2, fragment)
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_study_bad_rule_family_and_command_exit_2(tmp_path):
    assert_one_line_error(run("study", "rules", "--rules", "fixed,bogus", "--out-dir", tmp_path), 2, "unknown rule family 'bogus'")
    assert_one_line_error(run("study", "bounces"), 2, "No such command 'bounces'")


def test_study_output_folder_of_another_study_exits_2(tmp_path):
    assert run("study", "reachability", *SMALL, "--per-cell", 1, "--workers", 1, "--out-dir", tmp_path, "--no-figure").exit_code == 0
    result = run("study", "reachability", *SMALL, "--per-cell", 1, "--workers", 1, "--out-dir", tmp_path, "--seed", 4)
    assert_one_line_error(result, 2, "holds rows of another study (seed: 0 there, 4 here); use --fresh")
    assert run("study", "reachability", *SMALL, "--per-cell", 1, "--workers", 1, "--out-dir", tmp_path, "--seed", 4,
               "--fresh", "--no-figure").exit_code == 0


# ---------------------------------------------------------------------- kill half-way, run again
def _console_script() -> list[str]:
    script = Path(sys.executable).parent / "solverplan"
    return [str(script)] if script.exists() else [sys.executable, "-m", "solverplan.cli"]


@pytest.mark.parametrize("sig, workers", [(signal.SIGTERM, 2), (signal.SIGINT, 1)], ids=["sigterm-pool", "sigint-serial"])
def test_killed_study_finishes_only_the_rest_when_run_again(tmp_path, sig, workers):
    # n = 30: ~20 ms a row, so the 90 rows after the 10th outlast the lag of reading stderr in 8 KB chunks (with
    # n = 12 a loaded machine let the study finish before the signal arrived: exit 0, seen in a clean-clone run)
    args = ["study", "reachability", "--grid", "n=30", "--per-cell", "4", "--out-dir", str(tmp_path / "run"), "--no-figure"]
    # the child starts with SIGINT at its default whatever the test process inherited (an inherited SIG_IGN would
    # make Python install no KeyboardInterrupt handler, as for a background job, and the study would run to the end)
    proc = subprocess.Popen([*_console_script(), *args, "--workers", str(workers), "-vv"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert proc.stderr is not None
    for line in proc.stderr:  # blocks until the study reports its 10th row (no sleeping, no timing)
        if line.startswith("DEBUG solverplan.studies.execute: row 10 of 100"):
            break
    else:  # pragma: no cover - the study ended without reporting rows
        pytest.fail(f"no progress lines; exit {proc.wait()}")
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    last = err.strip().splitlines()[-1]
    assert last.startswith("error: study reachability interrupted after ") and last.endswith(": run it again to finish")
    saved = len((tmp_path / "run" / "reachability.jsonl").read_text().splitlines()) - 1
    assert 10 <= saved < 100
    assert f"interrupted after {saved} of 100 rows" in last
    # run again: only the rest is computed, and the table equals an uninterrupted run's
    again = run(*args, "--workers", 1)
    summary = json.loads(again.stdout)
    assert (summary["computed"], summary["reused"]) == (100 - saved, saved)
    whole = json.loads(run(*args[:-3], "--out-dir", tmp_path / "whole", "--no-figure", "--workers", 1).stdout)
    table = json.loads((tmp_path / "run" / "reachability.json").read_text())["rows"]
    reference = json.loads((tmp_path / "whole" / "reachability.json").read_text())["rows"]
    strip = lambda rows: [{k: v for k, v in r.items() if k != "seconds"} for r in rows]  # noqa: E731
    assert strip(table) == strip(reference) and whole["computed"] == 100


def test_progress_bar_goes_to_a_terminal_on_stderr_never_to_stdout(tmp_path):
    """stderr on a pseudo-terminal: the rich bar is drawn there; stdout (a pipe) stays pure JSON."""
    import pty
    import select

    master, slave = pty.openpty()
    args = ["study", "reachability", *SMALL, "--per-cell", "1", "--workers", "1", "--out-dir", str(tmp_path), "--no-figure"]
    proc = subprocess.Popen([*_console_script(), *args], stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    seen = b""
    while True:  # drain the terminal until the child closes it
        ready, _, _ = select.select([master], [], [], 60)
        if not ready:
            break
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
    out, _ = proc.communicate(timeout=60)
    os.close(master)
    assert proc.returncode == 0
    assert json.loads(out)["rows"] == 4
    assert b"study reachability" in seen and b"4/4" in seen
    quiet = subprocess.run([*_console_script(), *args, "-q"], capture_output=True, text=True)
    assert quiet.returncode == 0 and quiet.stderr == ""
