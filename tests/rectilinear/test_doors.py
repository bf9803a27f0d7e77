"""Virtual doors: the rooms as walls (open doors pass the robot, closed ones bounce it) and the door-control policy."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.rectilinear.decomposition import decompose_rooms
from solverplan.rectilinear.doors import DoorControl, RoomWorld


@pytest.fixture(scope="module")
def chambers():
    return decompose_rooms(load_environment("three_chambers"))


class Contacts:  # what RoomWorld.cast reads of the simulator's contacts
    def __init__(self, edge, t, rollout=None):
        self.edge = np.asarray(edge)
        self.t = np.asarray(t, dtype=float)
        self.rollout = np.arange(len(self.edge)) if rollout is None else np.asarray(rollout)


def left_wall_of_chamber_1(world):
    # room 0's ring runs (0,0) (30,0) (30,14.5) (30,15.5) (30,30) (0,30): its last side is the left wall, downwards
    wall = int(world.offsets[0]) + 5
    assert world.edge_start[wall].tolist() == [0, 30] and world.edge_end[wall].tolist() == [0, 0]
    return wall


def test_walls_number_the_sides_of_every_room_and_doors_are_twins(chambers):
    world = RoomWorld(chambers)
    assert world.n_edges == sum(len(room.ring) for room in chambers.rooms)
    doors = np.flatnonzero(world.door_of >= 0)
    assert len(doors) == 2 * len(chambers.doors)
    twin = world.twin[doors]
    assert np.array_equal(world.twin[twin], doors)                     # an involution
    assert np.array_equal(world.edge_start[twin], world.edge_end[doors])  # the same segment, the other way round
    assert np.array_equal(world.door_of[twin], world.door_of[doors])
    assert set(world.room_of[doors].tolist()) == set(range(5))
    assert np.all(world.twin[world.door_of < 0] == -1)


def test_a_ray_passes_open_doors_and_bounces_off_closed_ones(chambers):
    world = RoomWorld(chambers)
    wall = left_wall_of_chamber_1(world)
    start = Contacts([wall], [0.5])  # (0, 15), heading π/2: straight to the right, through all four doorways
    right = [math.pi / 2]
    open_all = world.cast(start, right)
    assert world.room_of[open_all.edge[0]] == 2 and (open_all.x[0], open_all.y[0]) == pytest.approx((98, 15))
    assert open_all.s[0] == pytest.approx(98) and not open_all.uncertain[0]
    closed = RoomWorld(chambers, is_open=lambda rollouts, doors: np.zeros(len(doors), dtype=bool)).cast(start, right)
    assert world.door_of[closed.edge[0]] == 0 and world.room_of[closed.edge[0]] == 0
    assert (closed.x[0], closed.y[0]) == pytest.approx((30, 15))
    only_a = RoomWorld(chambers, is_open=lambda rollouts, doors: doors == 0).cast(start, right)
    assert world.door_of[only_a.edge[0]] == 1 and world.room_of[only_a.edge[0]] == 4
    assert (only_a.x[0], only_a.y[0]) == pytest.approx((34, 15))


def test_doors_can_be_open_for_one_robot_and_closed_for_another(chambers):
    world = RoomWorld(chambers, is_open=lambda rollouts, doors: rollouts == 1)
    wall = left_wall_of_chamber_1(world)
    hits = world.cast(Contacts([wall, wall], [0.5, 0.5], rollout=[0, 1]), [math.pi / 2, math.pi / 2])
    assert hits.x.tolist() == pytest.approx([30, 98])


def test_a_ray_aimed_at_a_room_corner_is_flagged(chambers):
    world = RoomWorld(chambers)
    wall = left_wall_of_chamber_1(world)
    hits = world.cast(Contacts([wall], [0.5]), [math.pi / 2 + math.atan2(15, 30)])  # from (0, 15) to (30, 0)
    assert hits.uncertain[0] or hits.vertex[0] >= 0


def test_door_control_on_a_path_opens_the_doors_ahead_and_closes_the_one_behind(chambers):
    control = DoorControl(chambers, chambers.path(0, 2))  # rooms 0, 4, 1, 3, 2 through doors 0, 1, 2, 3
    assert [sorted(control.open_doors(k)) for k in range(5)] == [[0, 1, 2, 3], [1, 2, 3], [2, 3], [3], []]
    new, ok = control.advance(np.array([0, 0, 1, 2]), np.array([4, 1, 0, 2]))
    assert new.tolist() == [1, 2, 1, 4] and ok.tolist() == [True, True, False, True]  # back into room 0: not allowed
    assert control.is_open(np.array([1, 1]), np.array([0, 1])).tolist() == [False, True]


def test_door_control_on_a_tour_keeps_a_dead_end_open_until_the_robot_is_back(chambers):
    walk = chambers.tour(1)
    assert walk == (1, 3, 2, 3, 1, 4, 0)
    control = DoorControl(chambers, walk)
    # doors: 0 = 0|4, 1 = 4|1, 2 = 1|3, 3 = 3|2
    assert [sorted(control.open_doors(k)) for k in range(len(walk))] == [
        [2, 3],         # in 1: on to 3 and to the dead end 2 (3 repeats after it)
        [3],            # in 3: the door behind (to 1) closes
        [0, 1, 2, 3],   # in the dead end 2: its door stays open, and the way back and on to 4 and 0
        [0, 1, 2],      # back in 3: the dead end's door closes behind
        [0, 1],
        [0],
        [],
    ]


def test_door_control_needs_neighbouring_rooms(chambers):
    with pytest.raises(InputError, match=r"^rooms 0 and 1 do not share a door$"):
        DoorControl(chambers, (0, 1))
    with pytest.raises(InputError, match=r"^unknown room 7: rooms are 0\.\.4$"):
        DoorControl(chambers, (0, 7))


def test_starts_are_inside_the_room_moving_inwards(chambers):
    world = RoomWorld(chambers)
    walls, t, headings = world.starts_in(1, 200, np.random.default_rng(3))
    assert len(walls) == 200 and set(world.room_of[walls].tolist()) == {1}
    assert np.all((headings > 0) & (headings < math.pi)) and np.all((t >= 0) & (t <= 1))
    points = world.points_at(walls, t)
    assert np.all((points[:, 0] >= 34) & (points[:, 0] <= 64) & (points[:, 1] >= 0) & (points[:, 1] <= 30))


def test_room_environments_are_the_rooms_with_door_ends_as_vertices(chambers):
    envs = chambers.room_environments
    assert [env.area for env in envs] == [room.area for room in chambers.rooms]
    assert envs[0].n_vertices == 6 and chambers.rooms[0].sides == (-1, -1, 0, -1, -1, -1)
    assert envs[4].area == Fraction(4)
