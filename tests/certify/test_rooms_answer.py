"""The exact check of rooms answers (the rooms certificate's checker on an answer's claims): every answer of
Algorithm 1 passes, tampered ones fail naming the claim."""

from __future__ import annotations

import copy
import json
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.certify.rooms_answer import check_rooms_answer
from solverplan.errors import MalformedFile
from solverplan.rectilinear.decomposition import decompose_rooms
from solverplan.generators import rectilinear_polygon


@pytest.fixture(scope="module")
def chambers():
    env = load_environment("three_chambers")
    return env, decompose_rooms(env).to_json()


@settings(max_examples=150)
@given(st.integers(1, 24), st.integers(1, 6), st.integers(0, 2**32 - 1))
def test_every_answer_of_algorithm_1_checks(n, size, seed):
    env = rectilinear_polygon(n, seed=seed, max_size=size)
    answer = json.loads(json.dumps(decompose_rooms(env).to_json()))  # through JSON, as a file would be read
    report = check_rooms_answer(env, answer)
    assert report.valid, [str(f) for f in report.failures]
    counts = dict(report.checked)
    assert counts["rooms"] == len(answer["rooms"]) and counts.get("doors", 0) == len(answer["doors"])


@pytest.mark.parametrize("model", ["warehouse", "spiral", "comb", "hallway", "narrow_door", "l_shape", "square"])
def test_shipped_models_check(model):
    env = load_environment(model)
    assert check_rooms_answer(env, decompose_rooms(env).to_json()).valid


def tampered(answer, change):
    data = copy.deepcopy(answer)
    change(data)
    return data


def test_tampered_answers_fail_naming_the_claim(chambers):
    env, answer = chambers
    cases = {
        "area": (lambda d: d["rooms"][0].update(area_exact="901"), "claims.rooms[0].area: claims 901, the room's area is 900"),
        "sum": (lambda d: d["rooms"].pop(), "claims.doors[0].rooms: [0, 4] are not two different rooms of 0 … 3"),
        "tree": (lambda d: d["doors"].pop(), "claims.doors: 5 rooms for 3 doors"),
        "phi": (lambda d: d["doors"][2]["escapability_by_room_exact"].__setitem__(0, "1/30"),
                "claims.doors[2].escapability[0]: claims 1/30, Φ from room 1 is |door| / |wall| = 3 / 30 = 0.1"),
        "rooms": (lambda d: d["doors"][0].update(rooms=[0, 1]),
                  "claims.doors[0].rooms: claims rooms [0, 1], the door is a side of rooms [0, 4]"),
        "side": (lambda d: d["rooms"][4].update(polygon=[[30, 14.5], [34, 14.5], [34, 16.5], [30, 16.5]], area_exact="8"),
                 "claims.rooms[4].polygon: side (34, 16.5)–(30, 16.5) is neither wall nor door"),  # the doorway 2 high
        "outside": (lambda d: d["rooms"][4].update(polygon=[[30, 14.5], [34, 14.5], [34, 15.5], [31, 15.5], [31, 40], [30, 40]]),
                    "claims.rooms[4].polygon: side (31, 15.5)–(31, 40) is neither wall nor door"),
    }
    for name, (change, message) in cases.items():
        report = check_rooms_answer(env, tampered(answer, change))
        assert not report.valid, name
        assert any(message in str(failure) for failure in report.failures), (name, [str(f) for f in report.failures])


def test_a_door_must_start_at_a_reflex_vertex():
    env = load_environment("l_shape")
    answer = decompose_rooms(env).to_json()
    door = answer["doors"][0]
    door["a"], door["b"] = door["b"], door["a"]
    failures = check_rooms_answer(env, answer).failures
    assert [f.claim for f in failures] == ["claims.doors[0].a"] and "is not a reflex vertex of the polygon" in failures[0].message


def test_crossing_doors_fail(chambers):
    from solverplan.environment import Environment

    env = Environment.from_coords([(9, 4), (9, 0), (15, 0), (15, 2), (21, 2), (21, 4), (15, 4), (15, 7), (21, 7), (21, 13), (22, 13),
                                   (22, 18), (18, 18), (18, 17), (1, 17), (1, 16), (9, 16), (9, 7), (3, 7), (3, 4)])
    answer = decompose_rooms(env).to_json()
    assert check_rooms_answer(env, answer).valid
    answer["doors"].append({"a": [21, 13], "b": [21, 18], "rooms": [0, 1]})  # the dropped door of Prop. 2's counterexample
    failures = check_rooms_answer(env, answer).failures
    assert any(f.claim == f"claims.doors[{len(answer['doors']) - 1}]" and f.message.startswith("crosses or overlaps door")
               for f in failures), [str(f) for f in failures]


@pytest.mark.parametrize("answer,where", [
    ({"rooms": []}, "doors: expected a list"),
    ({"rooms": None, "doors": 3}, "doors: expected a list"),
    ({"rooms": ["a"], "doors": []}, "rooms[0]: expected an object"),
    ({"rooms": [], "doors": [{"a": [0, 0], "b": [1, 0], "rooms": [0, "x"]}]}, "doors[0]: expected an object"),
    ({"rooms": [], "doors": [{"a": [0, 0], "b": [1, 0], "rooms": [0, 1], "escapability_by_room_exact": 5}]},
     "escapability_by_room_exact: expected two numbers"),
    ({"rooms": [{"polygon": [[0, 0], [1]], "area": 1}], "doors": []}, "rooms[0].polygon: expected [x, y]"),
])
def test_a_malformed_answer_is_bad_input_naming_the_field(chambers, answer, where):
    """A file that is not a rooms answer is bad input (exit 2), not an invalid answer (#28: internal errors)."""
    env, _ = chambers
    with pytest.raises(MalformedFile, match=re.escape(where)):
        check_rooms_answer(env, answer)


def test_an_answer_states_no_lengths_or_psi_they_are_listed_not_checked(chambers):
    env, answer = chambers
    report = check_rooms_answer(env, answer)
    assert report.valid and any("Ψ" in item for item in report.not_checked)
