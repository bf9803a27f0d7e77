"""The geometric simulator (actions and sensors) and the combinatorial one driven by the cut ordering (Prop. 7)."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.wallfollow import cut_ordering
from solverplan.wallfollow.combinatorial import OrderingWorld
from solverplan.wallfollow.world import Action, ActionNotApplicable, Touch, WallWorld

from tests.wallfollow._polygons import general_position_polygons

ROOM = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])  # vertex 3 reflex


def test_follows_stop_at_vertices_and_at_the_pebble():
    world = WallWorld(ROOM)
    assert [str(world.act(a)) for a in ["RFOLLOW", "RFOLLOW", "RFOLLOW"]] == ["convex", "convex", "reflex"]
    assert world.position == (3, 0) and world.arrived == "R"
    assert str(world.act("JUMP")) == "edge" and world.label == "r3" and world.position == (5, Fraction(11, 40))
    world.act("DROP")
    world.run(["RFOLLOW", "LFOLLOW"])  # to v0, then back: stopped by the pebble on edge 5
    assert world.position == (5, Fraction(11, 40)) and world.observe().pebble
    world.act("GRAB")
    assert world.carrying and not world.observe().pebble
    assert str(world.act("LFOLLOW")) == "convex" and world.position == (5, 0)  # a carried pebble stops nothing


def test_init_from_the_interior_drives_to_the_wall_then_counter_clockwise():
    world = WallWorld(ROOM, start=(2, 2), heading=(0, -1))
    assert world.observe().touch is Touch.INTERIOR
    assert str(world.act("INIT")) == "convex" and world.position == (1, 0) and world.arrived == "R"
    assert world.act(Action.INIT).touch is Touch.CONVEX and world.position == (1, 0)  # at a vertex: nothing


def test_a_start_on_the_wall_is_located_exactly():
    world = WallWorld(ROOM, start=("21/4", 0), carrying=False)  # the end point of the left cut of vertex 3
    assert world.label == "l3" and str(world.observe()) == "edge+pebble"
    assert str(world.act("INIT")) == "convex" and world.position == (1, 0)  # on to the next vertex, past nothing


@pytest.mark.parametrize("actions,message", [
    (["JUMP"], "JUMP needs a reflex vertex reached by following the wall; the robot is at vertex 0"),
    (["RFOLLOW", "RFOLLOW", "RFOLLOW", "DROP", "GRAB", "JUMP", "JUMP"], "the robot is on edge 5 at t = 0.275"),
    (["GRAB"], "GRAB: the robot already holds the pebble"),
    (["DROP", "RFOLLOW", "GRAB"], "GRAB needs the pebble at the robot's position; the robot is at vertex 1"),
    (["DROP", "DROP"], "DROP: the robot does not hold the pebble"),
])
def test_inapplicable_actions_say_why(actions, message):
    world = WallWorld(ROOM)
    with pytest.raises(ActionNotApplicable, match=message):
        world.run(actions)


def test_bad_starts_and_actions():
    with pytest.raises(InputError, match=r"start \(20, 1\) is outside the polygon"):
        WallWorld(ROOM, start=(20, 1))
    with pytest.raises(ActionNotApplicable, match="RFOLLOW needs the robot on the wall"):
        WallWorld(ROOM, start=(1, 1)).act("RFOLLOW")
    with pytest.raises(InputError, match="unknown action 'FLY'"):
        WallWorld(ROOM).act("FLY")


ACTIONS = list(Action)


@given(general_position_polygons(max_vertices=12), st.data())
@settings(max_examples=150)
def test_prop_7_the_cut_ordering_predicts_every_action_sequence(env, data):
    """Prop. 7: from a point of M, the combinatorial simulator on the cut ordering reports the same observations and
    the same points as the geometric one, for random action sequences (inapplicable actions refused by both)."""
    order = cut_ordering(env)
    start = data.draw(st.integers(0, env.n_vertices - 1))
    world = WallWorld(env, start=env.exact_vertices[start])
    robot = OrderingWorld(order, f"v{start}")
    for action in data.draw(st.lists(st.sampled_from(ACTIONS), min_size=1, max_size=60)):
        try:
            expected = world.act(action)
        except ActionNotApplicable:
            with pytest.raises(ActionNotApplicable):
                robot.act(action)
            continue
        assert robot.act(action) == expected
        assert robot.label == world.label and robot.carrying == world.carrying
