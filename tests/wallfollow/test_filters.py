"""Vertex counting and winding number (§IV): the corrected filter against ground truth, and the printed one failing."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.wallfollow.filters import (CountingFilter, count_walk, printed_vertex_count, printed_winding,
                                           step_value)
from solverplan.wallfollow.world import WallWorld

from tests.wallfollow._polygons import general_position_polygons


def _walk(env: Environment, pebble: int, start: int, steps: list[str]):
    """Actions and observations of a walk with the pebble at vertex ``pebble``, and the ground truth: the lifted
    vertex position (unwrapped, so consecutive positions differ by ±1) from the simulator's exact positions."""
    world = WallWorld(env, start=env.exact_vertices[pebble])
    world.act("DROP")
    while world.position != (start, 0):
        world.act("RFOLLOW")
    initial = world.observe()
    n = env.n_vertices
    lift = [start]
    observations = []
    for action in steps:
        observations.append(world.act(action))
        assert world.position is not None and world.position[1] == 0  # a pebble at a vertex: every stop a vertex
        d = (world.position[0] - lift[-1]) % n
        lift.append(lift[-1] + (1 if d == 1 else -1))
    return initial, observations, lift


def _true_counts(lift: list[int], pebble: int, n: int):
    """Ground truth at the end: displacement since the first visit of the pebble, and the net number of times the
    pebble was passed (counter-clockwise positive), counted on the lifted path."""
    first = next((i for i, x in enumerate(lift) if (x - pebble) % n == 0), None)
    if first is None:
        return None, None
    disp = lift[-1] - lift[first]
    turns = abs(disp) // n
    return disp, turns if disp >= 0 else -turns


@given(general_position_polygons(max_vertices=9), st.data())
@settings(max_examples=200)
def test_corrected_filter_counts_vertices_and_winding_on_random_walks(env, data):
    n = env.n_vertices
    pebble, start = data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, n - 1))
    steps = data.draw(st.lists(st.sampled_from(["RFOLLOW", "LFOLLOW"]), max_size=80))
    initial, observations, lift = _walk(env, pebble, start, steps)
    f = count_walk(steps, observations, initial)
    disp, winding = _true_counts(lift, pebble, n)
    assert f.displacement == disp and f.winding == winding
    visits = [x for x in lift if (x - pebble) % n == 0]  # lifted positions at the pebble, in order
    went_round = any(x != visits[0] for x in visits)
    assert f.n == (n if went_round else None)  # known exactly when the robot came back after a whole turn


def test_the_filter_needs_a_whole_turn():
    f = CountingFilter()
    f.start(True)
    for action, pebble in [("RFOLLOW", False), ("LFOLLOW", True), ("LFOLLOW", False), ("RFOLLOW", True)]:
        f.update(action, pebble)
    assert (f.n, f.winding, f.displacement, f.stages) == (None, 0, 0, 4)
    assert CountingFilter().winding is None and step_value("INIT") == 0


def test_printed_props_1_and_2_fail_on_a_step_back_through_the_pebble():
    """From the pebble: one step counter-clockwise, back to the pebble, one step clockwise. The robot never went
    round, yet Prop. 2's κ₈ says n = 2 and Eq. 10 says the winding is ±1. The corrected filter knows no n and
    says winding 0."""
    actions = ["RFOLLOW", "LFOLLOW", "LFOLLOW"]
    pebbles = [True, False, True, False]  # stages 1..4
    assert printed_vertex_count(actions, pebbles) == 2  # in any polygon: n ≥ 3
    assert printed_winding(actions, pebbles) == 1
    f = count_walk(actions, pebbles[1:], pebbles[0])
    assert (f.n, f.winding) == (None, 0)


def test_printed_winding_misses_the_arrival_and_has_the_wrong_sign():
    """A counter-clockwise turn from the pebble back to it: the winding number is +1 (counter-clockwise). Eq. 10
    gives 0 at the arrival (its sum stops at stage k − 1) and −1 one step later (LFOLLOW counted +1)."""
    n = 6
    around = ["RFOLLOW"] * n
    pebbles = [True] + [False] * (n - 1) + [True]
    assert printed_winding(around, pebbles) == 0
    assert printed_winding(around + ["RFOLLOW"], pebbles + [False]) == -1
    f = count_walk(around, pebbles[1:], True)
    assert (f.n, f.winding) == (n, 1)


def test_walk_lengths_must_match():
    with pytest.raises(InputError, match="2 actions but 1 observations"):
        count_walk(["RFOLLOW", "LFOLLOW"], [True])


def test_random_walk_count_agrees_with_ground_truth():
    from tests.wallfollow._polygons import comb
    from solverplan.wallfollow.filters import count_random_walk

    for seed in range(5):
        walk = count_random_walk(comb(2), steps=400, seed=seed)
        assert walk.winding == walk.true_winding
        assert walk.n in (None, walk.true_n) and (walk.n is None) == (walk.known_after is None)
    with pytest.raises(InputError, match="steps must be a non-negative integer"):
        count_random_walk(comb(1), steps=-1)
