"""Cuts, general position and the geometric cut ordering."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.exact import orient, segment_intersection
from solverplan.wallfollow import CutOrdering, cut_ordering, cuts

from tests.wallfollow._polygons import general_position_polygons

ROOM = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])


def test_cut_end_points_are_exact():
    left, right = cuts(ROOM)
    assert (left.label, left.edge, left.t, left.point) == ("l3", 0, Fraction(7, 12), (Fraction(21, 4), Fraction(0)))
    assert (right.label, right.edge, right.t) == ("r3", 5, Fraction(11, 40))
    assert cut_ordering(ROOM).labels == ("v0", "l3", "v1", "v2", "v3", "v4", "v5", "r3")


def test_cut_ordering_answer():
    answer = cut_ordering(ROOM).to_json()
    assert answer["cut_ordering"][:2] == ["v0", "l3"] and answer["n"] == 6 and answer["reflex"] == [3]
    assert answer["status"] == "found" and answer["optimality"]["method"] == "exact-check"
    assert answer["environment"]["sha256"]
    assert "v0, l3, v1" in cut_ordering(ROOM).to_text()


@pytest.mark.parametrize("ring,message", [
    ([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]],
     "vertices 1, 3 and 5 are collinear ((8, 0), (4, 4), (0, 8)): the wall-following model needs general position"),
    ([[-10, 0], [10, 0], [11, 10], [5, 11], [3, 6], [2, 4], [-2, 4], [-3, 6], [-5, 11], [-10, 9]],
     "cut end points r5 and l6 (of reflex vertices 5 and 6) coincide at (0, 0): the cut ordering needs distinct "
     "end points"),
])
def test_general_position_errors_name_the_vertices(ring, message):
    env = Environment.from_coords(ring)
    with pytest.raises(InvalidEnvironment) as err:
        cuts(env)
    assert str(err.value) == message


def test_a_cut_into_a_vertex_names_the_cut():
    # the right cut of vertex 3 = (4, 5) continues (9, 4) → (4, 5) and runs into vertex 5 = (-1, 6)
    env = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [-1, 6]])
    with pytest.raises(InvalidEnvironment, match=r"^the right cut of reflex vertex 3 runs into vertex 5 at \(-1, 6\): "
                                                 r"vertices 2, 3 and 5 are collinear"):
        cuts(env)


def test_holes_are_refused():
    env = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], holes=[[[4, 4], [6, 4], [5, 6]]])
    with pytest.raises(InvalidEnvironment, match="without holes: .* has 1 hole$"):
        cuts(env)


@given(general_position_polygons())
@settings(max_examples=150)
def test_cuts_continue_their_edge_to_a_visible_boundary_point(env):
    pts = env.exact_vertices
    n = len(pts)
    for cut in cuts(env):
        v = pts[cut.vertex]
        w = pts[(cut.vertex - 1) % n] if cut.side == "r" else pts[(cut.vertex + 1) % n]
        assert orient(w, v, cut.point) == 0  # on the edge's line ...
        assert (cut.point[0] - v[0]) * (v[0] - w[0]) + (cut.point[1] - v[1]) * (v[1] - w[1]) > 0  # ... beyond v
        assert 0 < cut.t < 1
        for e in range(n):  # the open cut meets no edge: the end point is visible from the vertex
            if e in (cut.edge, cut.vertex, (cut.vertex - 1) % n):
                continue
            assert segment_intersection(v, cut.point, pts[e], pts[(e + 1) % n]) is None


@given(general_position_polygons())
@settings(max_examples=150)
def test_prop_4_cuts_cross_iff_their_end_points_alternate(env):
    order = cut_ordering(env)
    pts = env.exact_vertices
    all_cuts = cuts(env)
    for a in all_cuts:
        for b in all_cuts:
            if a.vertex == b.vertex:
                continue
            meet = segment_intersection(pts[a.vertex], a.point, pts[b.vertex], b.point)
            assert order.cuts_cross(a.label, b.label) == (meet is not None), (a.label, b.label)


@given(general_position_polygons())
@settings(max_examples=100)
def test_a_reflex_chain_cut_never_lands_between_vertices_of_its_chain(env):
    order = cut_ordering(env)
    n, reflex = env.n_vertices, set(env.reflex_vertices)
    for cut in cuts(env):
        lo = hi = cut.vertex  # the maximal chain of consecutive reflex vertices around the cut's vertex
        while (lo - 1) % n in reflex and (lo - 1) % n != cut.vertex:
            lo -= 1
        while (hi + 1) % n in reflex and (hi + 1) % n != lo % n:
            hi += 1
        if hi > lo:
            assert not order.between(f"v{lo % n}", f"v{hi % n}", cut.label)


@given(general_position_polygons(), st.integers(0, 50))
@settings(max_examples=100)
def test_renumbering_the_polygon_gives_an_equivalent_ordering(env, shift):
    ring = list(env.outer)
    k = shift % len(ring)
    renumbered = Environment.from_coords(ring[k:] + ring[:k])
    a, b = cut_ordering(env), cut_ordering(renumbered)
    assert a.equivalent(b) and a.canonical().labels == b.canonical().labels
    assert b.labels == a.relabel(-k).labels


def test_canonical_form_separates_distinct_orderings():
    a = CutOrdering.from_labels(["v0", "v1", "v2", "l4", "r1", "v3", "v4", "v5", "l1", "r4"])
    b = CutOrdering.from_labels(["v0", "v1", "v2", "r1", "l4", "v3", "v4", "v5", "l1", "r4"])
    assert not a.equivalent(b)
    assert a.canonical() == a.relabel(3).canonical()


@pytest.mark.parametrize("labels,message", [
    (["v0", "v1", "x2"], "'x2' is not a point name"),
    (["v0", "v1", "v1", "v2"], "v1 appears more than once"),
    (["v0", "v2", "v1"], "must appear as v0, v1, v2"),
    (["v0", "v1"], "at least 3 needed"),
    (["v0", "l1", "v1", "v2"], "l1 without r1"),
    (["v0", "l7", "r7", "v1", "v2"], "names vertex 7, but there are 3 vertices"),
])
def test_malformed_orderings_are_refused(labels, message):
    with pytest.raises(InputError, match=message):
        CutOrdering.from_labels(labels)


def test_from_labels_rotates_to_v0():
    assert CutOrdering.from_labels(["r3", "v0", "l3", "v1", "v2", "v3", "v4", "v5"]).labels[:2] == ("v0", "l3")


def _brute_force_triple(env):
    from itertools import combinations

    pts = env.exact_vertices
    return next((t for t in combinations(range(len(pts)), 3) if orient(*(pts[k] for k in t)) == 0), None)


@given(st.lists(st.tuples(st.integers(-6, 6), st.integers(-6, 6)), min_size=3, max_size=12, unique=True))
@settings(max_examples=300)
def test_collinear_triple_agrees_with_brute_force(points):
    """The sorted-angle filter finds exactly the collinear triples (small grids make them common)."""
    from types import SimpleNamespace

    import numpy as np

    from solverplan.wallfollow.cut import collinear_triple

    exact = tuple((Fraction(x), Fraction(y)) for x, y in points)
    fake = SimpleNamespace(exact_vertices=exact, vertices=np.array(points, dtype=float))
    assert collinear_triple(fake) == _brute_force_triple(fake)  # type: ignore[arg-type]
