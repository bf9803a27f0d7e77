"""The pebble-visibility sensor, Strategy 4 (learning the bitangents) and Strategy 5 (pursuit on them)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.geometry.visibility import sees
from solverplan.models import load
from solverplan.result import Status
from solverplan.wallfollow import bitangents, cut_ordering
from solverplan.wallfollow.pebble import PebbleWorld, bitangent_candidates, learn_bitangents
from solverplan.wallfollow.pursuit import pursuit_plan

from tests.wallfollow._polygons import bent_arms, general_position_polygons
from tests.wallfollow.test_bitangents import SPIKES
from tests.wallfollow.test_pursuit import assert_found_exactly_when_strategy2_finds

ROOM = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])  # one reflex vertex, 3


def _geometric(env):
    return [(b.i, b.j, b.after_ij, b.after_ji) for b in bitangents(env)]


def _learned(learned):
    return [(b.i, b.j, b.after_ij, b.after_ji) for b in learned.bitangents]


# ---------------------------------------------------------------------- the sensor
def test_pebble_sensor_reads_closed_visibility_and_counts_its_queries():
    world = PebbleWorld(ROOM)
    with pytest.raises(InputError, match="holds the pebble"):
        world.pebble_visible()
    with pytest.raises(InputError, match="straight last motion"):
        world.pebble_trace()
    world.run(["RFOLLOW", "DROP"])             # the pebble at v1 = (9, 0)
    traces = []
    for _ in range(5):
        world.act("RFOLLOW")
        traces.append(world.pebble_trace())
    # v1→v2 along the edge; v2→v3 (reflex) all seen; v3→v4 lost after the corner; v4→v5 found again; v5→v0 seen
    assert traces == [(1,), (1,), (1, 0), (0, 1), (1,)]
    assert world.visibility_queries == 5


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(general_position_polygons(min_vertices=4, max_vertices=10, spiky=True), st.data())
def test_pebble_trace_starts_and_ends_with_the_readings_at_the_ends_of_the_motion(env, data):
    """The trace along a follow or a JUMP begins with h_p at the start and ends with h_p at the end (exact
    closed visibility, :func:`sees`), and never repeats a value."""
    n = env.n_vertices
    world = PebbleWorld(env)
    for _ in range(data.draw(st.integers(0, n - 1))):
        world.act("RFOLLOW")
    world.act("DROP")
    for action in data.draw(st.lists(st.sampled_from(["RFOLLOW", "LFOLLOW", "JUMP"]), min_size=1, max_size=8)):
        p0 = world.point
        try:
            world.act(action)
        except InputError:
            continue
        trace = world.pebble_trace()
        q = world.env.exact_point_at(*world.pebble)
        assert trace[0] == sees(env, p0, q) and trace[-1] == sees(env, world.point, q)
        assert all(a != b for a, b in zip(trace, trace[1:]))


# ---------------------------------------------------------------------- Strategy 4
@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(general_position_polygons(min_vertices=4, max_vertices=13, spiky=True))
def test_prop11_every_bitangent_is_a_candidate_of_the_cut_ordering(env):
    """Prop. 11: B(i, j) ⇒ C(i, j); the candidates are read off the cut ordering alone."""
    candidates = set(bitangent_candidates(cut_ordering(env)))
    assert {(b.i, b.j) for b in bitangents(env)} <= candidates


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(general_position_polygons(min_vertices=4, max_vertices=13, spiky=True))
@example(bent_arms(0))
@example(SPIKES)
def test_prop12_strategy4_learns_exactly_the_geometric_bitangents(env):
    """Prop. 12 (Strategy 4 is correct): from actions and the pebble sensors only, the robot finds every
    bitangent and places both end points in the cut ordering exactly as the exact geometry does."""
    learned = learn_bitangents(env)
    assert _learned(learned) == _geometric(env)
    assert learned.actions == len(learned.transcript)
    assert learned.candidates == len(bitangent_candidates(cut_ordering(env)))


@pytest.mark.parametrize("name", ["star", "worst_case_t4", "three_arms", "l_shape"])
def test_strategy4_on_the_shipped_models(name):
    env = load(name)
    learned = learn_bitangents(env)
    assert _learned(learned) == _geometric(env)
    # every action the robot did is one WallWorld accepted; learning ends holding the pebble
    assert set(learned.transcript) <= {"RFOLLOW", "LFOLLOW", "JUMP", "GRAB", "DROP"}
    assert learned.transcript.count("DROP") == learned.transcript.count("GRAB")


# ---------------------------------------------------------------------- Strategy 5
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(general_position_polygons(min_vertices=5, max_vertices=11, spiky=True), st.integers(0, 30))
def test_strategy5_finds_a_plan_exactly_when_strategy2_does(env, start_at):
    """Strategy 5 is complete like Strategy 3 (the paper's claim after Prop. 12): on the bitangents Strategy 4
    learned, the search succeeds exactly when Strategy 2's does, with a plan of the same length, and the
    ground-truth checker verifies every plan."""
    pebble = assert_found_exactly_when_strategy2_finds(env, start_at, "pebble")
    if pebble.status is Status.FOUND:
        assert pebble.optimality.proved and pebble.optimality.algorithm == "Strategy 5 (BFS)"


@pytest.mark.parametrize("name", ["star", "worst_case_t4", "three_arms"])
def test_strategy5_on_the_shipped_models_matches_strategy3(name):
    env = load(name)
    pebble = pursuit_plan(env, sensor="pebble")
    bitangent = pursuit_plan(env, sensor="bitangent", check=False)
    assert pebble.status is Status.FOUND and pebble.verified is True
    assert pebble.actions == bitangent.actions
    assert pebble.learning is not None and pebble.learning.actions > 0
    assert "Strategy 4 learned" in pebble.to_text()


def test_cli_pursuit_with_the_pebble_sensor():
    from tests.wallfollow.test_cli_wallfollow import answer

    data = answer("wallfollow", "three_arms", "--pursuit", "--sensor", "pebble")
    assert data["status"] == "found" and data["verified"] is True and data["sensor"] == "pebble"
    assert data["plan"] == ["RFOLLOW", "JUMP", "LFOLLOW", "RFOLLOW", "RFOLLOW"]
    assert data["optimality"]["algorithm"] == "Strategy 5 (BFS)" and data["optimality"]["proved"] is True
    assert data["learning_actions"] == 256 and data["visibility_queries"] == 39
    assert data["bitangents"] == [["v0", "v11", "l0", "l11"], ["v1", "v5", "l1", "l5"], ["v6", "v10", "l6", "l10"]]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(general_position_polygons(min_vertices=6, max_vertices=13, spiky=True))
@example(bent_arms(0))
def test_learned_places_decide_which_jumps_cross_each_bitangent_ray(env):
    """What Strategy 4 learns is enough to tell which JUMPs cross which bitangent rays (as Prop. 4 does for two
    cuts): a cut and a bitangent ray, both chords of the polygon, cross iff their end points alternate along the
    boundary — with each bitangent end point placed just after the point of the ordering Strategy 4 found."""
    from solverplan.exact import segment_intersection
    from solverplan.wallfollow import cuts

    order = cut_ordering(env)
    size = len(order.labels)
    pts = env.exact_vertices
    learned = learn_bitangents(env)

    def key(label, after=False):
        return 2 * order.index(label) + (1 if after else 0)

    def inside(a, b, x):  # x strictly inside the counter-clockwise interval (a, b)
        return 0 < (x - a) % (2 * size) < (b - a) % (2 * size)

    for b, ray in zip(learned.bitangents, bitangents(env)):
        for near, after, end in ((b.i, b.after_ij, ray.point_ij), (b.j, b.after_ji, ray.point_ji)):
            r0, r1 = key(f"v{near}"), key(after, after=True)
            for c in cuts(env):
                if c.vertex == near:
                    continue  # they share the vertex: no crossing inside
                c0, c1 = key(f"v{c.vertex}"), key(c.label)
                alternate = inside(r0, r1, c0) != inside(r0, r1, c1)
                meet = segment_intersection(pts[near], end, pts[c.vertex], c.point)
                assert alternate == (meet is not None), (near, after, c.label)
