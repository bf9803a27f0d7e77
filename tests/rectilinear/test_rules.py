"""The rooms paper's bounce rules: billiard (β = α), random (uniform in (0, π)) and the one-bit smart rule."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.rectilinear.decomposition import decompose_rooms
from solverplan.rectilinear.doors import RoomWorld
from solverplan.rectilinear.rules import Billiard, Random, Smart, make_rule, room_tangents, smart_tangent


@pytest.fixture(scope="module")
def chambers():
    return decompose_rooms(load_environment("three_chambers"))


def floor_of_chamber_1(world):
    wall = int(world.offsets[0])  # room 0's first side: (0, 0) → (30, 0)
    assert world.edge_start[wall].tolist() == [0, 0] and world.edge_end[wall].tolist() == [30, 0]
    return wall


def test_billiard_reflects_the_incoming_direction(chambers):
    world = RoomWorld(chambers)
    floor = floor_of_chamber_1(world)
    down_right = np.array([[1.0, -1.0], [-1.0, -3.0]]) / np.array([[math.sqrt(2)], [math.sqrt(10)]])
    headings = Billiard().headings(world, np.array([floor, floor]), down_right, 1, np.random.default_rng(0))
    assert headings.tolist() == pytest.approx([math.pi / 4, math.pi - math.atan2(3, 1)])
    out = world.directions(np.array([floor, floor]), headings)
    assert np.allclose(out, down_right * [1, -1])  # the mirror image: β = α


def test_random_headings_are_uniform_in_zero_pi(chambers):
    world = RoomWorld(chambers)
    headings = Random().headings(world, np.zeros(20000, dtype=np.int64), np.zeros((20000, 2)), 1, np.random.default_rng(5))
    assert np.all((headings > 0) & (headings < math.pi))
    assert np.histogram(headings, bins=4, range=(0, math.pi))[0] == pytest.approx([5000] * 4, rel=0.05)


def test_smart_alternates_normal_and_tilted_departures(chambers):
    rule = Smart(0.25)
    headings = [rule.headings_at(step, 1)[0] for step in (1, 2, 3, 4)]
    assert headings == pytest.approx([math.pi / 2 + 0.25, math.pi / 2, math.pi / 2 + 0.25, math.pi / 2])
    world = RoomWorld(chambers)
    floor = floor_of_chamber_1(world)
    tilted = world.directions(np.array([floor]), rule.headings_at(1, 1))[0]
    assert tilted.tolist() == pytest.approx([-math.sin(0.25), math.cos(0.25)])  # leaning back along the wall


def test_smart_theta_is_half_the_door_over_the_larger_room_side(chambers):
    # rooms 0 (30 × 30, door 1), 4 (4 × 1, doors 1), 1 (30 × 30, doors 1 and 3), 3 (4 × 3, doors 3)
    assert smart_tangent(chambers, chambers.path(0, 2)) == Fraction(1, 60)
    assert smart_tangent(chambers, (1, 3, 2)) == Fraction(3, 60)
    assert room_tangents(chambers) == (Fraction(1, 60), Fraction(1, 60), Fraction(3, 60), Fraction(3, 8), Fraction(1, 8))
    assert Smart.for_walk(chambers, chambers.path(0, 2)).theta == pytest.approx(math.atan(1 / 60))
    per_room = Smart.for_walk(chambers, chambers.path(0, 2), per_room=True)
    world = RoomWorld(chambers)
    walls = np.array([int(world.offsets[3]), int(world.offsets[0])])
    assert per_room.headings(world, walls, np.zeros((2, 2)), 1, None).tolist() == pytest.approx(
        [math.pi / 2 + math.atan(3 / 8), math.pi / 2 + math.atan(1 / 60)])


def test_warehouse_smart_theta_comes_from_the_corridor():
    dec = decompose_rooms(load_environment("warehouse"))
    path = dec.path(0, 14)
    assert path == (0, 4, 7, 11, 14)
    assert smart_tangent(dec, path) == Fraction(1, 52)  # a 1-wide door out of the 26 × 3 corridor


def test_bad_rules_are_input_errors(chambers):
    with pytest.raises(InputError, match=r"^smart rule: θ = 2 must lie in \(0, π/2\)$"):
        Smart(2)
    with pytest.raises(InputError, match=r"^unknown rule 'specular': use smart, smart-paper, smart-per-room, random, billiard$"):
        make_rule("specular", chambers, (0,))
