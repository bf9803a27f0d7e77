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


@pytest.mark.parametrize(("args", "fragments"), [
    (["comb", "--start", "1,1", "--choice", "far"], ["p1 = (1, 1)", "bound 9"]),  # the viewpoints, the bound
    (["l_shape", "--start", "2,7", "--range", "3"], ["Algorithm B, range R = 3", "Lemma 4 bound"]),
])
def test_explore_text(args, fragments):
    result = runner.invoke(app, ["explore", *args, "--format", "text"])
    assert result.exit_code == 0 and all(fragment in result.stdout for fragment in fragments), result.output


@pytest.mark.parametrize(("args", "message"), [
    (["--start", "50,1"], "start (50, 1) is not in the free space of comb"),
    (["--start", "1"], "--start '1': expected X,Y"),
    (["--start", "1,1", "--seed", "2"], "--seed only applies to the random z-choice rule"),
    (["--start", "1,1", "--range", "0"], "range R must be a finite number > 0"),
    (["--start", "1,1", "--range", "abc"], "'abc' is not a number"),
    (["--start", "1,1", "--range", "nan"], "not finite"),
    (["--start", "1,1", "--range", "2", "--seed", "1"], "--seed only applies to the random z-choice rule"),
])
def test_explore_bad_input_is_one_line_exit_2(args, message):
    result = runner.invoke(app, ["explore", "comb", *args])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], lines


def test_explore_with_a_range_is_algorithm_b_within_lemma_4(tmp_path):
    picture = tmp_path / "range.png"
    result = runner.invoke(app, ["explore", "two_holes", "--start", "1,1", "--range", "3", "--picture", str(picture)])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert answer["algorithm"] == "B" and answer["status"] == "found" and answer["range"] == 3.0
    assert answer["lower_bound"] <= answer["views"] <= answer["bound"]
    env = sp.load_environment("two_holes")
    assert answer["bound"] == sp.explore.range_views_bound(env, 3.0) and answer["holes"] == 2
    assert answer["ratio"] == answer["views"] / answer["lower_bound"] <= answer["ratio_bound"]
    assert 1 - answer["covered_fraction"] < 1e-6 and len(answer["arcs"]) == answer["views"]
    assert picture.stat().st_size > 1000


def test_explore_with_a_range_across_the_polygon_is_algorithm_a():
    result = runner.invoke(app, ["explore", "comb", "--start", "1,1", "--range", "100", "--choice", "far"])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    run = sp.explore_depth_first(sp.load_environment("comb"), (1, 1), choice="far")
    assert answer["algorithm"] == "A" and answer["views"] == run.n_views and answer["arcs"] == [[]] * run.n_views


def test_issue26_generate_spiral_and_ring_write_the_papers_families(tmp_path):
    from typer.testing import CliRunner

    from solverplan.cli import app
    from solverplan.environment import load_environment
    from solverplan.explore.families import one_hole, spiral

    runner = CliRunner()
    target = tmp_path / "spiral.json"
    assert runner.invoke(app, ["generate", "spiral", "--turns", "3", "-o", str(target)]).exit_code == 0
    assert load_environment(target) == spiral(3)[0] and len(load_environment(target).reflex_vertices) == 3
    ring = tmp_path / "ring.json"
    assert runner.invoke(app, ["generate", "ring", "--sides", "5", "-o", str(ring)]).exit_code == 0
    env = load_environment(ring)
    assert env == one_hole(3)[0] and len(env.holes[0]) == 5 and len(env.reflex_vertices) == 5
    bad = runner.invoke(app, ["generate", "ring", "--sides", "2"])
    assert bad.exit_code == 2
