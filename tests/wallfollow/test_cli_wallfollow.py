"""`solverplan wallfollow`: the cut ordering, Strategy 1, the counting filter, pictures, errors."""

from __future__ import annotations

import json

import pytest

from solverplan.environment import load_environment
from solverplan.wallfollow import cut_ordering
from tests.cli_runs import run



def answer(*args: object) -> dict:
    result = run(*args)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


def one_line_error(result, fragment: str) -> None:
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr)
    assert result.stdout == "" and len(result.stderr.splitlines()) == 1
    assert result.stderr.startswith("error: ") and fragment in result.stderr, result.stderr


def test_cut_ordering_is_the_default_and_matches_the_contract():
    data = answer("wallfollow", "l_shape", "--cut-ordering")
    assert data["cut_ordering"] == ["v0", "l3", "v1", "v2", "v3", "v4", "v5", "r3"]
    assert data == answer("wallfollow", "l_shape")
    assert data["status"] == "found" and data["optimality"]["proved"] is True


@pytest.mark.parametrize("model", ["star", "worst_case_t4", "l_shape"])
def test_learn_on_shipped_models_matches_geometry(model):
    data = answer("wallfollow", model, "--learn", "--comparisons", "sort")
    assert data["matches_geometry"] is True and data["pebble_vertex"] == 0
    assert data["cut_ordering"] == list(cut_ordering(load_environment(model)).labels)
    assert data["actions"] == data["counts"]["count"] + data["counts"]["locate"] + data["counts"]["order"]
    assert data["memory"] == data["n"] + 4 * len(data["reflex"]) + 2


def test_learn_from_an_interior_start_with_transcript(tmp_path):
    picture = tmp_path / "cuts.svg"
    data = answer("wallfollow", "l_shape", "--learn", "--start", "1,1", "--heading", "0,-1", "--transcript",
                  "--picture", picture)
    assert data["matches_geometry"] is True and len(data["transcript"]) == data["actions"]
    assert data["transcript"][0]["action"] == "INIT"
    assert picture.read_bytes().startswith(b"<?xml") and b"chord-l" in picture.read_bytes()


def test_count_reports_n_winding_and_ground_truth():
    data = answer("wallfollow", "worst_case_t4", "--count", "--steps", "5000", "--seed", "2")
    assert data["status"] == "found" and data["n"] == data["true_n"] == 18
    assert data["winding"] == data["true_winding"] and data["known_after"] <= 5000
    short = answer("wallfollow", "worst_case_t4", "--count", "--steps", "3")
    assert short["status"] == "not-found" and short["n"] is None and short["winding"] == 0


def test_text_output():
    result = run("wallfollow", "star", "--learn", "--format", "text")
    assert result.exit_code == 0 and "renamed, the ordering equals the geometric one" in result.stdout


@pytest.mark.parametrize("args,fragment", [
    (["comb"], "the right cut of reflex vertex 5 runs into vertex 8 at (12, 3): vertices 4, 5 and 8 are collinear"),
    (["one_hole"], "needs a polygon without holes: one_hole has 1 hole"),
    (["l_shape", "--learn", "--count"], "choose one of --cut-ordering, --learn, --count and --pursuit"),
    (["l_shape", "--transcript"], "--comparisons and --transcript belong to --learn"),
    (["l_shape", "--learn", "--start", "1"], "--start must be two numbers X,Y"),
    (["l_shape", "--learn", "--start", "100,100"], "start (100, 100) is outside the polygon"),
    (["l_shape", "--learn", "--heading", "0,0", "--start", "1,1"], "heading (0, 0) is zero"),
    (["l_shape", "--start", "1,1"], "--start and --heading place the robot of --learn or --count"),
    (["l_shape", "--learn", "--seed", "3"], "--steps and --seed belong to --count"),
])
def test_bad_input_is_one_line(args, fragment):
    one_line_error(run("wallfollow", *args), fragment)
