"""Strategy 1: the cut ordering learned from sensing alone equals the geometric one."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.wallfollow import cut_ordering
from solverplan.wallfollow.combinatorial import OrderingWorld
from solverplan.wallfollow.learning import learn_cut_ordering, strategy1
from solverplan.wallfollow.world import Action, WallWorld

from tests.wallfollow._polygons import comb, general_position_polygons


@given(general_position_polygons(max_vertices=14), st.data())
@settings(max_examples=500)
def test_prop_5_strategy_1_learns_exactly_the_geometric_cut_ordering(env, data):
    """500 random simple polygons in general position, the robot started at a random vertex: the ordering it
    learns, renamed by the vertex where it dropped the pebble, is exactly the geometric one."""
    start = data.draw(st.integers(0, env.n_vertices - 1))
    learned = learn_cut_ordering(env, start=env.exact_vertices[start])
    assert learned.pebble_vertex == start
    assert learned.matches_geometry
    assert learned.ordering.relabel(start).labels == cut_ordering(env).labels
    assert learned.memory == env.n_vertices + 4 * len(env.reflex_vertices) + 2


@pytest.mark.parametrize("comparisons", ["pairwise", "sort"])
@pytest.mark.parametrize("teeth", [2, 5])
def test_many_end_points_on_one_edge_are_ordered_by_comparisons(teeth, comparisons):
    env = comb(teeth)
    learned = learn_cut_ordering(env, start=(3, 1), heading=(0, -1), comparisons=comparisons)
    assert learned.matches_geometry
    k = 2 * teeth  # end points on the floor
    if comparisons == "pairwise":  # every pair on the floor, as the paper does
        assert learned.counts["comparisons"] == k * (k - 1) // 2
    else:  # a merge sort: at most k·⌈log₂ k⌉
        assert 0 < learned.counts["comparisons"] <= k * (k - 1).bit_length()
    assert learned.actions == sum(learned.counts[a.value] for a in Action if a.value in learned.counts)


def test_the_strategy_sees_only_observations():
    """Driven through the combinatorial simulator (no geometry at all), Strategy 1 learns the same ordering."""
    env = comb(3)
    truth = cut_ordering(env)
    learned = strategy1(OrderingWorld(truth, "v4"))
    assert learned.ordering.relabel(4).labels == truth.labels


def test_transcript_replays_in_the_geometric_simulator():
    env = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
    learned = learn_cut_ordering(env, transcript=True)
    assert learned.transcript is not None and len(learned.transcript) == learned.actions
    world = WallWorld(env)
    assert [world.act(a) for a, _ in learned.transcript] == [o for _, o in learned.transcript]
    answer = learned.to_json()
    assert answer["transcript"][0] == {"action": "INIT", "touch": "convex", "pebble": False}
    assert answer["matches_geometry"] is True and answer["actions"] == learned.actions
    assert "equals the geometric one" in learned.to_text()


def test_unknown_comparison_mode():
    with pytest.raises(InputError, match="unknown comparisons"):
        strategy1(WallWorld(comb(1)), comparisons="bubble")  # type: ignore[arg-type]


def test_the_action_budget_stops_a_runaway_strategy():
    with pytest.raises(InputError, match="Strategy 1 stopped after max_actions = 100 actions"):
        learn_cut_ordering(comb(5), max_actions=100)
