"""Malformed and outsized input: exit 2 with one short line naming the file, the place and the reason.

Each case runs in-process through the CLI under a wall-clock bound (SIGALRM), so a regression to a hang
fails the test instead of stalling the suite; numpy warnings are turned into errors while it runs.
"""

from __future__ import annotations

import contextlib
import json
import signal
import warnings
from decimal import Decimal
from pathlib import Path

import pytest
from typer.testing import CliRunner

from solverplan import cli, limits
from solverplan.environment import json_depth, parse_environment, read_json
from solverplan.errors import InputError, MalformedFile

runner = CliRunner()

SECONDS = 10  # generous: every case answers in well under a second


@contextlib.contextmanager
def bounded(seconds: int = SECONDS):
    """Fail (instead of hanging) when the body runs longer than ``seconds``."""

    def expire(signum, frame):
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def one_line_error(*args: object) -> str:
    """Run the CLI; assert exit 2, nothing on stdout, one ``error:`` line under 200 characters; return it."""
    with bounded(), warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy RuntimeWarning would fail the case
        result = runner.invoke(cli.app, [str(a) for a in args])
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr, result.exception)
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ") and len(lines[0]) < 200, lines[0]
    assert "internal error" not in lines[0] and "Traceback" not in result.stderr
    return lines[0]


def square(side: str) -> str:
    return f'{{"outer": [[0, 0], [{side}, 0], [{side}, {side}], [0, {side}]]}}'


FILES = {
    "deep.json": ("[" * 100_000 + "]" * 100_000, "JSON nested 100000 levels deep (at most 64)"),
    "big308.json": (square("1e308"), "outer ring vertex 1: coordinate 1.00e+308 is larger than 1e100 in magnitude: rescale the file"),
    "big400.json": (square("1e400"), "outer ring vertex 1: coordinate 1.00e+400 is larger than 1e100 in magnitude: rescale the file"),
    "digits.json": ('{"outer": [[0, 0], [' + "9" * 5000 + ", 0], [1, 1]]}", "integer of 5000 digits in file (at most 1000)"),
    "xy.json": ('{"outer": [{"x": 0, "y": 0}, {"x": 1, "y": 0}, {"x": 1, "y": 1}]}',
                "outer ring vertex 0: expected a pair [x, y], got {'x': 0, 'y': 0}"),
    "tiny.json": ('{"outer": [[0, 0], [1, 0], [1, 1], [1e-999999, 1]]}',
                  "outer ring vertex 3: number '1E-999999' has decimal exponent -999999 (at most ±1000)"),
    "fine.json": ('{"outer": [[0, 0], [1, 0], [1, 1], [1e-101, 1]]}',
                  "outer ring vertex 3: coordinate 1e-101 is finer than 1e-100 (the finest step read): rescale the file"),
    "span.json": ('{"outer": [[0, 0], [1, 0], [1, 1], [1.00000000000000000000000001, 1], [0, 1]]}',
                  "outer ring edge 2 has length 0 in floats (both ends round to (1.0, 1.0)): rescale the file"),
    "long.json": ('{"outer": [[0, 0], ["' + "a" * 300 + '", 0], [1, 1]]}',
                  "outer ring vertex 1: 'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa… is not a number"),
    "longnumber.json": ('{"outer": [[0, 0], ["' + "1" * 1200 + '", 0], [1, 1]]}',
                        "outer ring vertex 1: number '" + "1" * 38 + "… is 1200 characters long (at most 1000)"),
    "longwkt.wkt": ("POLYGON ((0 0, 1 0, 1 1, " + "x" * 300 + "))", "WKT ring 0 point 3: expected 'x y', got 'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx…"),
}


@pytest.mark.parametrize("command", [["info"], ["graph"], ["plan", "--from", "e0", "--to", "e2"]], ids=lambda c: c[0])
@pytest.mark.parametrize("name", sorted(FILES))
def test_malformed_file_is_one_line_naming_file_place_and_reason(tmp_path, monkeypatch, name, command):
    text, reason = FILES[name]
    monkeypatch.chdir(tmp_path)  # a short file name, as users type it
    Path(name).write_text(text, encoding="utf-8")
    line = one_line_error(command[0], name, *command[1:])
    assert line == f"error: {name}: {reason}"


def test_large_and_small_coordinates_inside_the_limits_answer_without_warnings(tmp_path):
    for side in ("1e99", "1e-99"):
        path = tmp_path / "ok.json"
        path.write_text(square(side))
        with bounded(), warnings.catch_warnings():
            warnings.simplefilter("error")
            result = runner.invoke(cli.app, ["graph", str(path)])
        assert result.exit_code == 0, (side, result.stderr)
        assert json.loads(result.stdout)["n_segments"] == 4


@pytest.mark.parametrize(
    "args,message",
    [
        (["render", "two_rooms", "-o", "{tmp}/x.png", "--trajectories", "18446744073709551616"],
         "error: Invalid value for '--trajectories': Input should be less than or equal to 100000 (see 'solverplan render --help')"),
        (["generate", "star", "--n", "18446744073709551616"],
         "error: Invalid value for '--n': Input should be less than or equal to 10000 (see 'solverplan generate star --help')"),
        (["generate", "rooms", "--rooms", "18446744073709551616"],
         "error: Invalid value for '--rooms': Input should be less than or equal to 1000 (see 'solverplan generate rooms --help')"),
        (["generate", "rectilinear", "--rooms", "18446744073709551616"],
         "error: Invalid value for '--rooms': Input should be less than or equal to 1000 (see 'solverplan generate rectilinear --help')"),
        (["generate", "holes", "--holes", "18446744073709551616"],
         "error: Invalid value for '--holes': Input should be less than or equal to 1000 (see 'solverplan generate holes --help')"),
        (["generate", "star", "--seed", "18446744073709551616"],
         "error: Invalid value for '--seed': Input should be less than or equal to 18446744073709551615 (see 'solverplan generate star --help')"),
        (["generate", "star", "--radius", "1e300"], "error: --radius 1e+300 is larger than 1e100 in magnitude"),
        (["cycle", "two_rooms", "--theta", "1e-300"], "error: heading 1e-300 is within 1e-09 rad of the wall: floats cannot follow it"),
        (["cycle", "two_rooms", "--theta", "tan:1e-300"],
         "error: exact heading (1, 1e-300) is within 1e-09 rad of the wall: floats cannot follow it"),
        (["cycle", "two_rooms", "--theta", "dir:-1e400,1"],
         "error: exact heading (-1000000000000000000…, 1) is within 1e-09 rad of the wall: floats cannot follow it"),
        (["cycle", "two_rooms", "--theta", "0.5", "--method", "iterate", "--max-bounces", "18446744073709551616"],
         "error: Invalid value for '--max-bounces': Input should be less than or equal to 10000000 (see 'solverplan cycle --help')"),
    ],
    ids=lambda v: v[1] if isinstance(v, list) and len(v) > 1 else None,
)
def test_option_out_of_range_is_one_line(tmp_path, args, message):
    assert one_line_error(*(a.replace("{tmp}", str(tmp_path)) for a in args)) == message


def test_json_depth_skips_brackets_inside_strings():
    assert json_depth('{"a": ["[[[[", {"b": "]]"}]}') == 3
    assert json_depth('"\\"[[["') == 0
    assert json_depth("") == 0


def test_read_json_refuses_before_the_parser_recurses():
    with pytest.raises(MalformedFile, match=r"^JSON nested 65 levels deep \(at most 64\)$"):
        read_json("[" * 65 + "]" * 65)
    assert read_json("[" * 64 + "]" * 64) is not None


def test_a_file_over_the_size_limit_is_refused_before_it_is_read(tmp_path, monkeypatch):
    monkeypatch.setattr("solverplan.environment.MAX_FILE_BYTES", 10)
    path = tmp_path / "big.json"
    path.write_text(square("1"))
    assert one_line_error("info", path) == f"error: {path}: file is {path.stat().st_size} bytes (at most 10)"


def test_vertex_and_hole_counts_are_bounded(monkeypatch):
    monkeypatch.setattr("solverplan.environment.MAX_VERTICES", 3)
    with pytest.raises(InputError, match=r"^input: outer ring has 4 vertices \(at most 3\)$"):
        parse_environment(square("1"), "json")
    monkeypatch.setattr("solverplan.environment.MAX_VERTICES", 5)
    with pytest.raises(InputError, match=r"^input: environment has 7 vertices \(at most 5\)$"):
        parse_environment('{"outer": [[0,0],[9,0],[9,9],[0,9]], "holes": [[[1,1],[2,1],[2,2]]]}', "json")
    monkeypatch.setattr("solverplan.environment.MAX_HOLES", 0)
    with pytest.raises(InputError, match=r"^input: environment has 1 holes \(at most 0\)$"):
        parse_environment('{"outer": [[0,0],[9,0],[9,9],[0,9]], "holes": [[[1,1],[2,1],[2,2]]]}', "json")


def test_quote_cuts_long_runs():
    assert limits.quote("ab") == "'ab'"
    assert limits.quote("x" * 100) == "'" + "x" * 38 + "…"
    assert len(limits.quote("x" * 100)) == limits.MAX_QUOTED_CHARS


@pytest.mark.parametrize(
    "spec,message",
    [
        ("e0:1e-999999:0.5", "boundary set piece 'e0:1e-999999:0.5': number '1E-999999' has decimal exponent -999999 (at most ±1000)"),
        ("e0:0:1e-300", "boundary set piece 'e0:0:1e-300': the piece is narrower than floats carry (t0=0, t1=1e-300)"),
        ("e0:0.5:0.50000000000000000001",
         "boundary set piece 'e0:0.5:0.50000000000000000001': the piece is narrower than floats carry (t0=0.5, t1=0.50000000000000000001)"),
        ("e" + "1" * 5000, "unknown edge e11111111111111111111…: edges are e0..e17"),
        ("x" * 300, "boundary set piece '" + "x" * 38 + "… is malformed: expected 'eK' or 'eK:T0:T1' with 0 <= T0 < T1 <= 1"),
    ],
    ids=["exponent", "fine", "float-width", "edge-digits", "long"],
)
def test_malformed_boundary_set_is_one_short_line(spec, message):
    assert one_line_error("plan", "two_rooms", "--from", spec, "--to", "e2") == f"error: {message}"


@pytest.mark.parametrize("name", ["deep.json", "digits.json"])
def test_plan_files_are_read_within_the_same_limits(tmp_path, monkeypatch, name):
    text, reason = FILES[name]
    monkeypatch.chdir(tmp_path)
    Path(name).write_text(text)
    assert one_line_error("simulate", "two_rooms", name) == f"error: {name}: {reason}"


def test_answers_at_the_magnitude_limits_match_the_unit_scale(tmp_path):
    """Inside the limits, a scaled copy gets the same angles (no overflow, no underflow, no warnings)."""
    shape = [[0, 0], [1, 0], [1, 1], [0.5, 0.2], [0, 1]]
    tolerances = []
    for scale in ("1", "1e99", "1e-90"):
        path = tmp_path / "scaled.json"
        path.write_text(json.dumps({"outer": [[str(Decimal(str(x)) * Decimal(scale)) for x in p] for p in shape]}))
        with bounded(), warnings.catch_warnings():
            warnings.simplefilter("error")
            result = runner.invoke(cli.app, ["plan", str(path), "--from", "e0", "--to", "e2", "--objective", "tolerance"])
        assert result.exit_code == 0, (scale, result.stderr)
        answer = json.loads(result.stdout)
        tolerances.append((answer["bounces"], answer["tolerance"]))
    assert tolerances[0] == tolerances[1] == tolerances[2]


def test_rollouts_beyond_memory_are_refused_up_front(monkeypatch, tmp_path):
    import json

    import solverplan as sp
    import solverplan.limits as limits
    from solverplan.cli import app
    from typer.testing import CliRunner

    assert limits.available_memory() is None or limits.available_memory() > 0
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(sp.find_plan(sp.load_environment("square"), "e0", "e2").to_json()))
    monkeypatch.setattr(limits, "available_memory", lambda: 2**31)  # 2 GiB left: the default limit is half of it
    result = CliRunner().invoke(app, ["simulate", "square", str(plan), "--trials", "10000000"])
    assert result.exit_code == 2, result.stderr
    assert result.stderr.splitlines() == [
        "error: 10,000,000 rollouts of 2 bounces would need about 4.0 GiB of memory, more than half the memory available (1.0 GiB; see --max-memory)"]
