"""Inflections and bitangents (exact), with the paper's Props. 11, 13 and 18 as property tests."""

from __future__ import annotations

from fractions import Fraction

from hypothesis import given, settings

from solverplan.environment import Environment
from solverplan.exact import orient
from solverplan.wallfollow import cuts
from solverplan.wallfollow.bitangent import (bitangents, boundary_between, inflections, mutually_visible,
                                              reflex_chains)

from tests.wallfollow._polygons import general_position_polygons

SPIKES = Environment.from_coords([[0, 0], [20, 0], [21, 9], [14, 10], [13, 4], [12, 11], [7, 13], [6, 5], [5, 12],
                                  [0, 11]])


def test_two_spikes_have_one_bitangent_with_exact_end_points():
    (b,) = bitangents(SPIKES)
    assert (b.i, b.j) == (4, 7)
    assert b.b_ij == (1, Fraction(21, 64)) and b.point_ij == (Fraction(1301, 64), Fraction(189, 64))
    assert b.b_ji == (9, Fraction(36, 77)) and b.point_ji == (Fraction(0), Fraction(41, 7))
    pts = SPIKES.exact_vertices
    assert orient(b.point_ij, pts[4], pts[7]) == 0 and orient(pts[4], pts[7], b.point_ji) == 0
    assert mutually_visible(SPIKES, 4, 7) and not mutually_visible(SPIKES, 4, 5) and not mutually_visible(SPIKES, 3, 5)


def test_inflections_and_chains():
    room = Environment.from_coords([[0, 0], [10, 0], [11, 10], [7, 11], [6, 5], [4, 6], [3, 10], [0, 9]])
    assert reflex_chains(room) == ((4, 5),)
    assert [c.label for c in inflections(room)] == ["r4", "l5"]  # the chain's inner cuts are no inflections
    assert reflex_chains(SPIKES) == ((4,), (7,))


def _places(env):
    return {c.label: (c.edge, c.t) for c in cuts(env)}


def _v(k: int):
    return (k, Fraction(0))


SPIKY = general_position_polygons(min_vertices=8, max_vertices=18, scale=100_000, spiky=True)


@given(SPIKY)
@settings(max_examples=200)
def test_prop_11_a_bitangent_pair_is_a_candidate(env):
    """B(i, j) ⇒ v_i ∉ (r_j, ℓ_j) and v_j ∉ (r_i, ℓ_i)."""
    at = _places(env)
    for b in bitangents(env):
        for x, y in ((b.i, b.j), (b.j, b.i)):
            assert not boundary_between(at[f"r{y}"], at[f"l{y}"], _v(x), closed=False)


@given(SPIKY)
@settings(max_examples=200)
def test_prop_13_bitangent_end_points_lie_where_the_cuts_say(env):
    """For a right-handed bitangent: b_{i,j} ∈ [ℓ_i, v_i] ∩ [ℓ_j, v_i] and b_{j,i} ∈ [v_j, r_i] ∩ [v_j, r_j]."""
    at = _places(env)
    for b in bitangents(env):
        i, j = b.i, b.j
        assert boundary_between(_v(i), at[f"r{i}"], _v(j))  # right-handed
        assert boundary_between(at[f"l{i}"], _v(i), b.b_ij) and boundary_between(at[f"l{j}"], _v(i), b.b_ij)
        assert boundary_between(_v(j), at[f"r{i}"], b.b_ji) and boundary_between(_v(j), at[f"r{j}"], b.b_ji)


@given(SPIKY)
@settings(max_examples=200)
def test_prop_18_at_most_four_bitangents_between_two_reflex_chains(env):
    chain_of = {v: k for k, chain in enumerate(reflex_chains(env)) for v in chain}
    between: dict[tuple[int, int], int] = {}
    for b in bitangents(env):
        key = tuple(sorted((chain_of[b.i], chain_of[b.j])))
        between[key] = between.get(key, 0) + 1
    assert all(count <= 4 for count in between.values()), between


def test_bitangents_exist_in_random_polygons():
    """The property tests above are not vacuous: the strategy's polygons do have bitangents (Prop. 11 example)."""
    from hypothesis import given as given_, settings as settings_

    found = []

    @given_(SPIKY)
    @settings_(max_examples=60)
    def collect(env):
        found.append(len(bitangents(env)))

    collect()
    assert sum(found) >= 60 and max(found) >= 4
