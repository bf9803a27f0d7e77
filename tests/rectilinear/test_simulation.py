"""Bouncing through rooms, driven through the simulator: Prop. 3 (with door control the smart robot visits every
room of the sequence), the billiard trap of Fig. 3a, and the rules side by side (Table I)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.rectilinear.decomposition import decompose_rooms
from solverplan.rectilinear.doors import RoomWorld
from solverplan.rectilinear.rules import Billiard, Smart
from solverplan.simulate import Outcome, simulate_policy
from solverplan.generators import rectilinear_polygon
from solverplan.rectilinear.simulation import RoomPolicy, compare_rules, periodic_orbit, simulate_rooms


@pytest.fixture(scope="module")
def chambers():
    return decompose_rooms(load_environment("three_chambers"))


# ---------------------------------------------------------------------- Prop. 3
@settings(max_examples=300)  # 1,000 took 19 s once rooms compared every rule
@given(st.integers(1, 16), st.integers(1, 4), st.integers(0, 2**32 - 1), st.integers(0, 100))
def test_prop_3_with_door_control_the_smart_robot_visits_every_room(n, size, seed, start):
    dec = decompose_rooms(rectilinear_polygon(n, seed=seed, max_size=size))
    start %= len(dec.rooms)
    tour = dec.tour(start)
    assert set(tour) == set(range(len(dec.rooms)))
    runs = simulate_rooms(dec, start, tour[-1], rule="smart", trials=1, seed=seed, max_bounces=50_000, walk=tour)
    # every robot reaches the end of the tour (so it entered every room, in the sequence's order), unless the
    # float caster stopped it at a room corner (outside the model: a ray through a vertex)
    assert runs.outcomes["goal"] + runs.outcomes["vertex"] + runs.outcomes["tie"] == 1, runs.to_json()
    assert runs.outcomes["failed"] == 0 and runs.trapped == 0


def test_prop_3_on_the_shipped_models_every_robot_arrives(chambers):
    warehouse = decompose_rooms(load_environment("warehouse"))
    for dec, start, goal in ((chambers, 0, 2), (chambers, 2, 0), (warehouse, 0, 14), (warehouse, 3, 12)):
        runs = simulate_rooms(dec, start, goal, rule="smart", trials=15, seed=1, max_bounces=20_000)
        assert runs.success == 1.0 and runs.trapped == 0, (dec.env.name, start, goal, runs.outcomes)
    tour = simulate_rooms(warehouse, 0, warehouse.tour(0)[-1], rule="smart", trials=4, seed=2,
                          max_bounces=50_000, walk=warehouse.tour(0))
    assert tour.success == 1.0


def test_without_door_control_the_robot_may_wander_but_still_counts_rooms(chambers):
    runs = simulate_rooms(chambers, 0, 2, rule="random", trials=30, seed=4, max_bounces=20_000, doors="open")
    assert runs.outcomes["failed"] == 0 and runs.success > 0.5
    assert runs.doors == "open" and runs.trapped is None


# ---------------------------------------------------------------------- the billiard trap (Fig. 3a)
def test_billiard_trap_a_six_bounce_periodic_orbit_in_a_square_chamber(chambers):
    # from (0, 5) on chamber 1's left wall along (1, 2): (12.5, 30), (27.5, 0), (30, 5), (17.5, 30), (2.5, 0),
    # (0, 5) — six bounces (Fig. 3a), the right wall only at y = 5, never the door at y ∈ [14.5, 15.5]
    world = RoomWorld(chambers)
    left = int(world.offsets[0]) + 5
    walk = chambers.path(0, 2)
    assert periodic_orbit(chambers, Billiard(), walk, left, (0, 5), (1, 2), max_bounces=50) == 6
    # the float simulator agrees: the robot never reaches room 2
    heading = math.atan2(1, -2)  # (1, 2) measured from the left wall, which points down (0, −1): π − arctan(1/2)
    assert world.directions(np.array([left]), np.array([heading]))[0].tolist() == pytest.approx([1 / math.sqrt(5), 2 / math.sqrt(5)])
    policy = RoomPolicy(chambers, Billiard(), walk, np.array([heading]))
    runs = simulate_policy(chambers.env, policy, (np.array([left]), np.array([5 / 6])), bounces=600, trials=1, seed=0)
    assert runs.status[0] == Outcome.OK and set(policy.walls.room_of[runs.edge[0, 1:]].tolist()) == {0}
    points = runs.path(0)[1:7]
    assert np.allclose(points, [[12.5, 30], [27.5, 0], [30, 5], [17.5, 30], [2.5, 0], [0, 5]])
    # a slope that is not rational reaches the door: no periodic orbit, the billiard robot escapes
    assert periodic_orbit(chambers, Billiard(), walk, left, (0, 5), (1, Fraction(2) + Fraction(1, 997)), max_bounces=50) is None


def test_the_smart_robot_escapes_where_the_billiard_robot_is_trapped(chambers):
    # near the trapped start (an exact start on the orbit makes the smart robot's rational sweep run into a
    # corner): the smart robot leaves along the normal and sweeps the walls in steps of half a door
    world = RoomWorld(chambers)
    left = int(world.offsets[0]) + 5
    walk = chambers.path(0, 2)
    smart = Smart.for_walk(chambers, walk)
    heading, t = math.atan2(1, -2) + 0.001, 5 / 6 + 0.0007
    policy = RoomPolicy(chambers, smart, walk, np.array([heading]))
    runs = simulate_policy(chambers.env, policy, (np.array([left]), np.array([t])), bounces=20_000, trials=1, seed=0,
                           record="ends")
    assert runs.status[0] == Outcome.GOAL
    billiard = RoomPolicy(chambers, Billiard(), walk, np.array([math.atan2(1, -2)]))
    stuck = simulate_policy(chambers.env, billiard, (np.array([left]), np.array([5 / 6])), bounces=int(runs.stop_step[0]),
                            trials=1, seed=0, record="ends")
    assert stuck.status[0] == Outcome.OK  # as many bounces, still in chamber 1


def test_periodic_orbits_are_for_deterministic_rules(chambers):
    from solverplan.rectilinear.rules import Random

    with pytest.raises(InputError, match=r"^the random rule is not deterministic"):
        periodic_orbit(chambers, Random(), (0,), 5, (0, 5), (1, 2), max_bounces=5)


# ---------------------------------------------------------------------- Table I
def test_rules_side_by_side_like_table_1(chambers):
    table = compare_rules(chambers, 0, 2, trials=12, seed=7, max_bounces=4000)
    data = table.to_json()
    assert set(data["rules"]) == {"smart", "random", "billiard"}
    for name, row in data["rules"].items():
        assert {"rule", "trials", "success", "bounces_mean", "bounces_median", "trapped"} <= set(row)
        assert row["rule"] == name and row["trials"] == 12
    assert data["rules"]["smart"]["success"] == 1.0 and data["rules"]["smart"]["trapped"] == 0
    assert data["rules"]["random"]["trapped"] is None
    assert data["reachability_exact"] == "1/300" and data["paper_recommendation"] == "smart"
    advice = table.runs["smart"].advice
    assert advice is not None and data["recommended"] == advice.rule
    arrived = [name for name, row in data["rules"].items() if row["success"] == 1.0 and not row["trapped"]]
    best = min(data["rules"][name]["bounces_mean"] for name in arrived)
    assert data["rules"][advice.rule]["bounces_mean"] <= 1.2 * best  # NEAR_FASTEST
    assert data["rules"]["smart"]["theta_tangent_exact"] == "1/60"
    text = table.to_text()
    assert "smart" in text and "random" in text and "billiard" in text and "Ψ = 1/300" in text
    # the same seed gives the same starts for every rule, and the same answer again
    assert compare_rules(chambers, 0, 2, trials=12, seed=7, max_bounces=4000).to_json() == data


def test_runs_keep_trajectories_for_pictures(chambers):
    runs = simulate_rooms(chambers, 0, 2, rule="smart", trials=3, seed=1, max_bounces=5000, keep=2)
    assert len(runs.trajectories) == 2
    path = runs.trajectories[0]
    assert path.shape[1] == 2 and len(path) == runs.bounces[0] + 1


def test_bad_simulation_requests_are_input_errors(chambers):
    with pytest.raises(InputError, match=r"^trials must be an integer >= 1, got 0$"):
        simulate_rooms(chambers, 0, 2, trials=0)
    with pytest.raises(InputError, match=r"^the room sequence must go from room 0 to room 2$"):
        simulate_rooms(chambers, 0, 2, walk=(0, 4, 1))
    with pytest.raises(InputError, match=r"^unknown door policy 'shut': use control, open$"):
        simulate_rooms(chambers, 0, 2, doors="shut")  # type: ignore[arg-type]


def test_the_literal_theta_of_eq_1_traps_the_smart_robot_in_a_flat_room_and_ours_does_not():
    # a 13 × 2 room with a 1-wide door in its ceiling at x ∈ [7.5, 8.5] (into a 1 × 1 alcove): the paper's
    # θ = arctan(ℓ/h), h = 2 the distance from the door to the opposite wall, and even half of it, let the tilted
    # crossings of the short side walls leap along them, and the robot settles into a periodic orbit that never
    # meets the door; tan θ = ℓ / (2·13) (the larger side) sweeps every wall and finds it
    from solverplan.environment import Environment

    a = Fraction(15, 2)
    env = Environment.from_coords([(0, 0), (13, 0), (13, 2), (a + 1, 2), (a + 1, 3), (a, 3), (a, 2), (0, 2)])
    dec = decompose_rooms(env)
    assert [room.area for room in dec.rooms] == [26, 1] and len(dec.doors) == 1
    walk = dec.path(0, 1)
    world = RoomWorld(dec)
    floor = int(world.offsets[0])
    start, direction = (Fraction(3, 10), 0), (-1, 2)
    assert periodic_orbit(dec, Smart.with_tangent(Fraction(1, 2)), walk, floor, start, direction, max_bounces=1000) == 14
    assert periodic_orbit(dec, Smart.with_tangent(Fraction(1, 4)), walk, floor, start, direction, max_bounces=1000) == 20
    ours = Smart.for_walk(dec, walk)
    assert ours.tangent == Fraction(1, 26)
    assert periodic_orbit(dec, ours, walk, floor, start, direction, max_bounces=100_000) is None
    policy = RoomPolicy(dec, ours, walk, np.array([math.atan2(2, -1)]))
    runs = simulate_policy(env, policy, (np.array([floor]), np.array([0.3 / 13])), bounces=20_000, trials=1, seed=0,
                           record="ends")
    assert runs.status[0] == Outcome.GOAL


def test_prop_3_has_exceptional_starts_even_for_the_documented_reading():
    # the failing case: a 12 × 2 room, door [3, 4] in the ceiling; from (10.48, 0) along (1, 1) the smart robot
    # (tan θ = 1/24) runs into a periodic orbit of 40 bounces that never meets the door. It is isolated: moving
    # the start by 1e-7 (or the direction by 1e-6) the robot arrives — which is why 2,000 random starts never
    # showed it. So Prop. 3 holds for almost every start, not for every one.
    from solverplan.environment import Environment

    env = Environment.from_coords([(0, 0), (12, 0), (12, 2), (4, 2), (4, 3), (3, 3), (3, 2), (0, 2)])
    dec = decompose_rooms(env)
    walk = dec.path(0, 1)
    world = RoomWorld(dec)
    floor = int(world.offsets[0])
    smart = Smart.for_walk(dec, walk)
    assert smart.tangent == Fraction(1, 24)
    start = Fraction(262, 25)
    assert periodic_orbit(dec, smart, walk, floor, (start, 0), (1, 1), max_bounces=1000) == 40
    for moved, direction in (((start + Fraction(1, 10**7), 0), (1, 1)), ((start, 0), (1, 1 + Fraction(1, 10**6)))):
        assert periodic_orbit(dec, smart, walk, floor, moved, direction, max_bounces=20_000) is None
    policy = RoomPolicy(dec, smart, walk, np.array([math.pi / 4]))
    runs = simulate_policy(env, policy, (np.array([floor]), np.array([10.48 / 12 + 1e-7])), bounces=20_000, trials=1,
                           seed=0, record="ends")
    assert runs.status[0] == Outcome.GOAL


def test_the_simulator_hook_for_walls_of_a_policys_own(chambers):
    from solverplan.errors import InvalidBoundarySet

    policy = RoomPolicy(chambers, Smart(0.1), chambers.path(0, 2), np.array([1.0]))
    with pytest.raises(InputError, match=r"^a policy with walls of its own needs explicit \(edges, t\) starts on those walls$"):
        simulate_policy(chambers.env, policy, "e0", bounces=3, trials=1)
    with pytest.raises(InvalidBoundarySet, match=r"^start 0 \(wall 999, t = 0.5\) is not on the walls$"):
        simulate_policy(chambers.env, policy, (np.array([999]), np.array([0.5])), bounces=3)

    class Broken:
        walls = object()

        def headings(self, contacts, rng):
            return np.ones(len(contacts))

        def check(self, contacts):
            return np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)

    with pytest.raises(InputError, match=r"has walls that are not PolicyWalls"):
        simulate_policy(chambers.env, Broken(), (np.array([0]), np.array([0.5])), bounces=3)
