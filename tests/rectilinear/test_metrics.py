"""Escapability Φ, reachability Ψ, the reachability graph and the rule recommendation (the paper's §VII)."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.rectilinear.decomposition import decompose_rooms
from solverplan.rectilinear.metrics import (SMART_THRESHOLD, escapability, reachability, reachability_along, reachability_graph,
                                            recommend_rule)
from solverplan.generators import rectilinear_polygon
from tests.rectilinear.test_decomposition import chambers


def test_the_shipped_chambers_model_is_fig_5():
    assert load_environment("three_chambers") == chambers(4)


def test_fig_5_escapability_and_reachability():
    dec = decompose_rooms(load_environment("three_chambers"))
    one, two, three = 0, 1, 2  # the chambers, numbered by their lowest vertex
    x, y = 4, 3                # the doorways: x (1 wide) between chambers 1 and 2, y (3 wide) between 2 and 3
    assert dec.path(one, three) == (one, x, two, y, three)
    assert escapability(dec, one, x) == Fraction(1, 30)   # door a: 1 of chamber 1's 30-long wall
    assert escapability(dec, x, two) == 1                 # door b covers the doorway's whole end
    assert escapability(dec, two, y) == Fraction(1, 10)   # door c: 3 of 30
    assert escapability(dec, y, three) == 1
    reach = reachability(dec, one, three)
    assert reach.factors == (Fraction(1, 30), 1, Fraction(1, 10), 1)
    assert reach.psi == Fraction(1, 300)                  # the paper's Ψ(1, 3) ≈ 0.003
    assert reachability(dec, three, one).psi == Fraction(1, 300)  # 3/30 and 1/30 from the other side too
    assert reachability(dec, two, two).psi == 1 and reachability(dec, two, two).rooms == (two,)


def test_fig_5_reachability_graph_is_directed_and_weighted():
    dec = decompose_rooms(load_environment("three_chambers"))
    graph = reachability_graph(dec)
    assert sorted(graph.nodes) == [0, 1, 2, 3, 4] and graph.number_of_edges() == 2 * len(dec.doors)
    assert graph[0][4]["escapability"] == Fraction(1, 30) and graph[4][0]["escapability"] == 1
    assert graph[1][3]["weight"] == pytest.approx(0.1) and graph[3][1]["escapability"] == 1
    assert graph.nodes[0]["area"] == 900


def test_recommendation_smart_below_the_threshold_random_above():
    dec = decompose_rooms(load_environment("three_chambers"))
    assert SMART_THRESHOLD == Fraction(1, 10)
    far = recommend_rule(dec, 0, 2)
    assert far.rule == "smart" and far.reachability.psi == Fraction(1, 300)
    assert "1/300 < 0.1" in far.reason
    near = recommend_rule(dec, 4, 1)  # the doorway into chamber 2: Φ = 1
    assert near.rule == "random" and near.to_json()["reachability"] == 1.0
    assert recommend_rule(dec, 1, 3).rule == "random"                       # Ψ = 1/10 is not below 1/10
    assert recommend_rule(dec, 1, 3, threshold=Fraction(1, 5)).rule == "smart"


def test_metrics_of_rooms_that_share_no_door_are_input_errors():
    dec = decompose_rooms(load_environment("three_chambers"))
    with pytest.raises(InputError, match=r"^rooms 0 and 1 do not share a door$"):
        escapability(dec, 0, 1)


@settings(max_examples=100)
@given(st.integers(2, 24), st.integers(0, 2**32 - 1))
def test_reachability_is_the_product_along_the_tree_path_and_at_most_each_factor(n, seed):
    dec = decompose_rooms(rectilinear_polygon(n, seed=seed))
    graph = reachability_graph(dec)
    last = len(dec.rooms) - 1
    reach = reachability(dec, 0, last)
    product = Fraction(1)
    for i, j in zip(reach.rooms, reach.rooms[1:]):
        product *= graph[i][j]["escapability"]
    assert reach.psi == product and 0 < reach.psi <= min(reach.factors, default=1) <= 1


def test_reachability_along_a_tour_multiplies_every_door_crossed():
    dec = decompose_rooms(load_environment("three_chambers"))
    tour = dec.tour(1)  # 1, 3, 2, 3, 1, 4, 0
    reach = reachability_along(dec, tour)
    assert reach.factors == (Fraction(1, 10), 1, Fraction(1, 10), 1, Fraction(1, 30), 1)
    assert reach.psi == Fraction(1, 3000)
    assert recommend_rule(dec, 1, 0, rooms=tour).reachability.psi == Fraction(1, 3000)
