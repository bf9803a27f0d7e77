"""The smart rule's θ modes and the cost-aware recommendation (issue #26)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.rectilinear import decompose_rooms
from solverplan.rectilinear.rules import GUARANTEED, Smart, door_depth, room_tangents, smart_tangent
from solverplan.generators import rectilinear_polygon
from solverplan.rectilinear.simulation import NEAR_FASTEST, RULE_VARIANTS, compare_rules, recommend_from_runs


@settings(max_examples=25)
@given(cells=st.integers(3, 16), seed=st.integers(0, 10_000))
def test_paper_theta_is_at_least_twice_the_safe_one_on_every_route(cells, seed):
    """ℓ/h ≥ 2·ℓ/(2D) because the depth h across a door is a side of the room's bounding box, so h ≤ D: Eq. 1's θ
    always tilts more than the safe θ (hence fewer bounces, and no guarantee)."""
    dec = decompose_rooms(rectilinear_polygon(cells, seed=seed))
    for room in dec.rooms:
        for d in room.doors:
            x0, y0, x1, y1 = room.bounds
            assert 0 < door_depth(dec, room.id, d) <= max(x1 - x0, y1 - y0)
    if len(dec.rooms) < 2:
        return  # no door: both modes fall back to tan θ = 1/2
    walk = dec.path(0, len(dec.rooms) - 1)
    assert smart_tangent(dec, walk, "paper") >= 2 * smart_tangent(dec, walk, "safe")
    assert all(p >= 2 * s for p, s in zip(room_tangents(dec, "paper"), room_tangents(dec, "safe")))


def test_theta_modes_on_three_chambers():
    dec = decompose_rooms(load_environment("three_chambers"))
    walk = dec.path(0, 2)
    assert str(smart_tangent(dec, walk)) == "1/60" and str(smart_tangent(dec, walk, "paper")) == "1/30"
    assert Smart.for_walk(dec, walk, theta="per-room").per_room
    with pytest.raises(InputError, match="^unknown θ mode 'steep': use safe, paper, per-room$"):
        smart_tangent(dec, walk, "steep")


@settings(max_examples=6)
@given(cells=st.integers(3, 10), seed=st.integers(0, 10_000))
def test_issue26_recommended_rule_is_within_near_fastest_of_the_fastest_rule_that_always_arrived(cells, seed):
    dec = decompose_rooms(rectilinear_polygon(cells, seed=seed))
    if len(dec.rooms) < 2:
        return
    table = compare_rules(dec, 0, len(dec.rooms) - 1, rules=RULE_VARIANTS, trials=12, seed=seed, max_bounces=3000)
    advice = recommend_from_runs(table.runs)
    runs = table.runs
    arrived = [n for n, r in runs.items() if r.always_arrived]
    assert sorted(advice.always_arrived) == sorted(arrived)
    if arrived:
        fastest = min(runs[n].bounces_mean for n in arrived)
        assert advice.rule in arrived and runs[advice.rule].bounces_mean <= NEAR_FASTEST * fastest
        if advice.rule != advice.fastest:
            assert advice.rule in GUARANTEED  # only a guarantee justifies a slower pick
    data = table.to_json()
    assert data["recommended"] == advice.rule and set(data["recommendation"]["guarantees"]) == set(RULE_VARIANTS)
