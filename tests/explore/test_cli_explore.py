"""The ``explore`` command: the contract's exploration answer, the picture, bad input as one line (exit 2)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import solverplan as sp
from solverplan.cli import app

runner = CliRunner()


def test_explore_answers_with_the_contract_fields(tmp_path):
    picture = tmp_path / "views.png"
    result = runner.invoke(app, ["explore", "comb", "--start", "1,1", "--picture", str(picture)])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["viewpoints"][0] == [1.0, 1.0]
    assert answer["views"] == len(answer["viewpoints"]) <= answer["bound"] == answer["reflex"] + 1 == 9
    assert answer["covered_fraction"] > 1 - 1e-9 and answer["path_length"] > 0
    assert picture.stat().st_size > 1000


def test_explore_random_rule_with_a_seed_matches_the_library():
    result = runner.invoke(app, ["explore", "comb", "--start", "9,1", "--choice", "random", "--seed", "4"])
    assert result.exit_code == 0, result.output
    run = sp.explore_depth_first(sp.load_environment("comb"), (9, 1), choice="random", seed=4)
    assert json.loads(result.stdout)["viewpoints"] == [[float(x), float(y)] for x, y in run.viewpoints]


def test_explore_text_lists_the_viewpoints():
    result = runner.invoke(app, ["explore", "comb", "--start", "1,1", "--choice", "far", "--format", "text"])
    assert result.exit_code == 0 and "p1 = (1, 1)" in result.stdout and "bound 9" in result.stdout


@pytest.mark.parametrize(("args", "message"), [
    (["--start", "50,1"], "start (50, 1) is not in the free space of comb"),
    (["--start", "1"], "--start '1': expected X,Y"),
    (["--start", "1,1", "--seed", "2"], "--seed only applies to the random z-choice rule"),
])
def test_explore_bad_input_is_one_line_exit_2(args, message):
    result = runner.invoke(app, ["explore", "comb", *args])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0]
