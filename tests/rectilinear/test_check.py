"""The independent exact check of rooms answers: every answer of Algorithm 1 passes, tampered ones fail naming
the claim."""

from __future__ import annotations

import copy
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.rectilinear.check import check_rooms
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
    report = check_rooms(env, answer)
    assert report.valid, report.failures
    assert report.checked >= len(answer["doors"]) + len(answer["rooms"])


@pytest.mark.parametrize("model", ["warehouse", "spiral", "comb", "hallway", "narrow_door", "l_shape", "square"])
def test_shipped_models_check(model):
    env = load_environment(model)
    assert check_rooms(env, decompose_rooms(env).to_json()).valid


def tampered(answer, change):
    data = copy.deepcopy(answer)
    change(data)
    return data


def test_tampered_answers_fail_naming_the_claim(chambers):
    env, answer = chambers
    cases = {
        "area": (lambda d: d["rooms"][0].update(area_exact="901"), "room 0: area 901 claimed, 900 exactly"),
        "sum": (lambda d: d["rooms"].pop(), "the room areas add up to 2712"),
        "tree": (lambda d: d["doors"].pop(), "5 rooms for 3 doors"),
        "phi": (lambda d: d["doors"][2]["escapability_by_room_exact"].__setitem__(0, "1/30"), "door 2: escapability from room 1 claimed 1/30, 0.1 exactly"),
        "rooms": (lambda d: d["doors"][0].update(rooms=[0, 1]), "door 0 lies on a side of rooms [0, 4]; the answer says it joins rooms [0, 1]"),
        "side": (lambda d: d["rooms"][4].update(polygon=[[30, 14.5], [34, 14.5], [34, 16.5], [30, 16.5]], area_exact="8"),
                 "room 4: its side (34, 16.5)–(30, 16.5) is neither wall nor door"),  # the doorway made 2 high
        "outside": (lambda d: d["rooms"][4].update(polygon=[[30, 14.5], [34, 14.5], [34, 15.5], [31, 15.5], [31, 40], [30, 40]]),
                    "room 4: a vertex lies outside the polygon"),
    }
    for name, (change, message) in cases.items():
        report = check_rooms(env, tampered(answer, change))
        assert not report.valid, name
        assert any(message in failure for failure in report.failures), (name, report.failures)


def test_a_door_must_start_at_a_reflex_vertex():
    env = load_environment("l_shape")
    answer = decompose_rooms(env).to_json()
    door = answer["doors"][0]
    door["a"], door["b"] = door["b"], door["a"]
    failures = check_rooms(env, answer).failures
    assert len(failures) == 1 and "a is not a reflex vertex of the polygon" in failures[0]


def test_crossing_doors_fail(chambers):
    from solverplan.environment import Environment

    env = Environment.from_coords([(9, 4), (9, 0), (15, 0), (15, 2), (21, 2), (21, 4), (15, 4), (15, 7), (21, 7), (21, 13), (22, 13),
                                   (22, 18), (18, 18), (18, 17), (1, 17), (1, 16), (9, 16), (9, 7), (3, 7), (3, 4)])
    answer = decompose_rooms(env).to_json()
    assert check_rooms(env, answer).valid
    answer["doors"].append({"a": [21, 13], "b": [21, 18], "rooms": [0, 1]})  # the dropped door of Prop. 2's counterexample
    failures = check_rooms(env, answer).failures
    assert any(f.startswith(f"doors ") and f.endswith(f"and {len(answer['doors']) - 1} cross") for f in failures), failures


def test_a_malformed_answer_is_one_failure(chambers):
    env, _ = chambers
    report = check_rooms(env, {"rooms": []})
    assert not report.valid and report.failures[0].startswith("malformed answer")
    assert report.to_json() == {"valid": False, "checked": 0, "failures": list(report.failures)}
