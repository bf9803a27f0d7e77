"""Rewritings of the walls (studies.rewrite): the rewritten environment is the same free space (or the same room
moved), and a mapped boundary set is exactly the same boundary points — the premise of issue #22's invariance
tests (tests/plan/test_invariance.py)."""

from __future__ import annotations

from fractions import Fraction
from typing import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.exact import ExactPoint
from solverplan.studies import rewrite as rw
from tests.strategies import polygons_with_holes, simple_polygons
from tests.shapes import SQUARE

F = Fraction
HOLED = Environment.from_coords([[0, 0], [20, 0], [20, 20], [0, 20]], [[[8, 8], [8, 12], [12, 12], [12, 8]]])
ROT = (F(20, 29), F(21, 29))


def identity_point(p: ExactPoint) -> ExactPoint:
    return p


# (name, rewriting of (env, set), the map of points it applies)
REWRITINGS: list[tuple[str, Callable[[Environment, BoundarySet], rw.Rewritten], Callable[[ExactPoint], ExactPoint]]] = [
    ("identity", lambda e, s: rw.identity(e, s), identity_point),
    ("insert", lambda e, s: rw.insert_vertices(e, {0: [F(1, 3), F(1, 2)], e.n_edges - 1: ["0.9"]}, s), identity_point),
    ("split2", lambda e, s: rw.split_edges(e, 2, s), identity_point),
    ("split3", lambda e, s: rw.split_edges(e, [F(1, 7), F(2, 3)], s), identity_point),
    ("ends", lambda e, s: rw.at_set_ends(e, s), identity_point),
    ("rotate", lambda e, s: rw.rotate(e, *ROT, s), lambda p: (ROT[0] * p[0] - ROT[1] * p[1], ROT[1] * p[0] + ROT[0] * p[1])),
    ("translate", lambda e, s: rw.translate(e, F(7, 3), -5, s), lambda p: (p[0] + F(7, 3), p[1] - 5)),
    ("scale", lambda e, s: rw.scale(e, F(1000, 7), s), lambda p: (p[0] * F(1000, 7), p[1] * F(1000, 7))),
    ("roll", lambda e, s: rw.roll_ring_start(e, 0, 2, s), identity_point),
    ("roll_hole", lambda e, s: rw.roll_ring_start(e, len(e.rings) - 1, 1, s), identity_point),
    ("reverse", lambda e, s: rw.reverse_rings(e, s), identity_point),
    ("mirror", lambda e, s: rw.mirror(e, s), lambda p: (p[0], -p[1])),
    ("composed", lambda e, s: rw.at_set_ends(e, s).then(rw.mirror).then(rw.split_edges, 2).then(rw.reverse_rings),
     lambda p: (p[0], -p[1])),
]


@st.composite
def sets(draw, env: Environment) -> BoundarySet:
    t = st.fractions(F(0), F(1), max_denominator=12)
    pieces = []
    for _ in range(draw(st.integers(1, 3))):
        e = draw(st.integers(0, env.n_edges - 1))
        a, b = sorted((draw(t), draw(t)))
        if a < b:
            pieces.append(BoundaryPiece(e, a, b))
    if not pieces:
        pieces.append(BoundaryPiece(0, F(1, 4), F(1)))
    return BoundarySet(tuple(pieces))


@st.composite
def cases(draw):
    env = draw(st.one_of(simple_polygons(max_vertices=8), polygons_with_holes(max_vertices=6, max_holes=2)))
    return env, draw(sets(env))


@pytest.mark.parametrize("name, rewriting, move", REWRITINGS, ids=[r[0] for r in REWRITINGS])
@settings(max_examples=15)
@given(case=cases())
def test_mapped_sets_are_the_same_boundary_points(name, rewriting, move, case):
    """Every point of the set (ends and midpoint of each piece) lands, through map_point and through map_set, on
    the moved point; the mapped set has the same (scaled) length; the rewritten rings are the moved rings, up to
    the collinear vertices added."""
    env, bset = case
    r = rewriting(env, bset)
    assert r.source is env
    scale = float(r.length_scale)
    for piece in bset.pieces:
        for t in (piece.t0, (piece.t0 + piece.t1) / 2, piece.t1):
            e2, t2 = r.map_point(piece.edge, t)
            assert r.env.exact_point_at(e2, t2) == move(env.exact_point_at(piece.edge, t))
    (mapped,) = r.sets
    assert mapped.merged() == r.map_set(bset).merged()  # the same points (pieces in another order after flips)
    for piece in mapped.pieces:  # and back: every mapped point is a moved point of the set
        assert 0 <= piece.t0 < piece.t1 <= 1
        for t in (piece.t0, (piece.t0 + piece.t1) / 2, piece.t1):
            assert _on_set(env, bset, move, r.env.exact_point_at(piece.edge, t))

    def length(e: Environment, s: BoundarySet) -> float:
        return sum(float(p.t1 - p.t0) * float(e.edge_lengths[p.edge]) for p in s.merged().pieces)

    assert length(r.env, mapped) == pytest.approx(scale * length(env, bset), rel=1e-12)
    # the same rings, moved, with collinear vertices added: every old vertex is a new vertex
    new_vertices = set(r.env.exact_vertices)
    assert all(move(v) in new_vertices for v in env.exact_vertices)
    assert float(r.env.area) == pytest.approx(float(env.area) * scale**2, rel=1e-12)


def _on_set(env: Environment, bset: BoundarySet, move, point: ExactPoint) -> bool:
    """Is ``point`` the moved image of a point of ``bset`` (exact)?"""
    for p in bset.pieces:
        e = env.edge(p.edge)
        a, b = move(e.a), move(e.b)
        dx, dy = b[0] - a[0], b[1] - a[1]
        if dx * (point[1] - a[1]) != dy * (point[0] - a[0]):
            continue
        t = (point[0] - a[0]) / dx if dx else (point[1] - a[1]) / dy
        if p.t0 <= t <= p.t1:
            return True
    return False


def test_every_rewriting_keeps_the_orientation_convention():
    for name, rewriting, _ in REWRITINGS:
        r = rewriting(HOLED, HOLED.boundary_set("e0:0.25:0.5,e5"))
        Environment(r.env.rings)  # the constructor accepts only normalised rings (outer CCW, holes CW)


def test_reversed_rings_keep_edge_direction_one_id_on():
    """The loader reverses a ring given clockwise keeping its first vertex: the old ring started one vertex earlier."""
    r = rw.reverse_rings(HOLED, "e0:0.25:0.5,e4:0:0.5,e7")
    assert r.env.reoriented == (True, True)
    assert str(r.sets[0]) == "e1:0.25:0.5,e5:0:0.5,e4"
    assert r.env.ring(0)[1] == HOLED.ring(0)[0]


def test_mirror_reverses_edges():
    r = rw.mirror(SQUARE, "e0:0.25:0.5,e1")
    assert str(r.sets[0]) == "e3:0.5:0.75,e2"


def test_split_and_ends_map_pieces_onto_sub_edges():
    r = rw.split_edges(SQUARE, 4, "e1:0.1:0.6")
    assert str(r.sets[0]) == "e4:0.4:1,e5,e6:0:0.4"
    ends = rw.at_set_ends(SQUARE, "e1:0.1:0.6", "e1:0.6:1,e2:0:0.5")
    assert [str(s) for s in ends.sets] == ["e2", "e3,e4"] and ends.env.n_edges == 7


def test_then_composes_the_maps_and_the_scale():
    r = rw.rotate(SQUARE, F(3, 5), F(4, 5), "e0:0.25:1")
    r = r.then(rw.translate, 1, 2).then(rw.scale, 3).then(rw.split_edges, 2)
    assert str(r.sets[0]) == "e0:0.5:1,e1" and r.length_scale == 3
    assert r.map_point(0, F(1, 4)) == (0, F(1, 2))
    assert r.description == "rotate(0.6, 0.8) ∘ translate(1, 2) ∘ scale(3) ∘ split_edges(2)"


def test_map_edges_keeps_whole_edges_and_refuses_split_ones():
    r = rw.insert_vertices(SQUARE, {1: [F(1, 2)]})
    assert r.map_edges([0, 2, 3]) == (0, 3, 4)
    assert r.map_edges("e3,e0") == (4, 0)
    with pytest.raises(InputError, match=r"^edge e1 is split into e1,e2 by insert_vertices\(1 points\): a patrol "
                                         r"visit of e1 cannot be mapped to one edge$"):
        r.map_edges([1])


@pytest.mark.parametrize("call, message", [
    (lambda: rw.insert_vertices(SQUARE, {0: [0]}), r"^insert_vertices: t=0 on edge e0 is not strictly inside \(0, 1\)$"),
    (lambda: rw.insert_vertices(SQUARE, [(1, "3/2")]), r"^insert_vertices: t=1.5 on edge e1 is not strictly inside \(0, 1\)$"),
    (lambda: rw.insert_vertices(SQUARE, [(9, "1/2")]), r"^unknown edge e9: edges are e0..e3$"),
    (lambda: rw.insert_vertices(SQUARE, [(1, "x")]), r"^insert_vertices: t on edge e1: "),
    (lambda: rw.split_edges(SQUARE, 1), r"^split_edges: k=1 parts: need an integer k >= 2"),
    (lambda: rw.split_edges(SQUARE, [F(1, 2), 1]), r"^split_edges: parameter t=1 is not strictly inside \(0, 1\)$"),
    (lambda: rw.rotate(SQUARE, 1, 1), r"^rotate: \(cos, sin\) = \(1, 1\) is not an exact rotation: cos² \+ sin² = 2, "
                                      r"not 1 \(use a Pythagorean triple such as \(3/5, 4/5\)\)$"),
    (lambda: rw.scale(SQUARE, -2), r"^scale: factor -2 must be positive \(a half-turn is rotate\(-1, 0\)\)$"),
    (lambda: rw.roll_ring_start(SQUARE, 1, 1), r"^roll_ring_start: ring 1 does not exist \(rings are 0..0, 0 the outer\)$"),
    (lambda: rw.pythagorean_rotation(1, 2), r"^pythagorean_rotation: need integers m > n > 0, got m=1, n=2$"),
    (lambda: rw.identity(SQUARE).map_point(0, 2), r"^boundary parameter t=2 on edge e0 is not in \[0, 1\]$"),
])
def test_bad_input_is_one_clear_line(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_unknown_edges_in_sets_are_refused():
    with pytest.raises(InvalidBoundarySet, match=r"^unknown edge e4: edges are e0..e3$"):
        rw.at_set_ends(SQUARE, "e4")


def test_rational_rotations_are_exact_and_distinct():
    angles = set()
    for c, s in rw.RATIONAL_ROTATIONS:
        assert c * c + s * s == 1
        angles.add((c, s))
    assert len(angles) == len(rw.RATIONAL_ROTATIONS)
    assert rw.pythagorean_rotation(12, 5) == (F(119, 169), F(120, 169))
