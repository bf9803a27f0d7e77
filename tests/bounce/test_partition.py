"""Partition P′ (paper Algorithm 1, Prop. 1): exact inserted points, holes, degenerate inputs.

The reference partition at the bottom is written independently of the library's kernel and ray
casters: pure :class:`~fractions.Fraction` arithmetic, every pair (r, v), the boundary events of a
line found by looping over all edges, and "in the free space" decided by point-in-ring tests at the
midpoints between events.
"""

from __future__ import annotations

import importlib
import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from solverplan import cli
from solverplan.bounce.partitions import Partition, partition
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.exact import orient, point_in_ring, to_fraction
from solverplan.geometry.visibility import visibility_polygon
from tests.strategies import convex_polygons, polygons_with_holes, simple_polygons

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
# the module (the package re-exports the function of the same name)
partition_module = importlib.import_module("solverplan.bounce.partitions")

L_SHAPE = Environment.from_coords([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]])


def model(name: str) -> Environment:
    return load_environment(MODELS / f"{name}.json")


def inserted_set(p: Partition) -> set[tuple[int, Fraction]]:
    return {(q.edge, q.t) for q in p.inserted}


def vertex_of(env: Environment, xy) -> int:
    return env.exact_vertices.index((Fraction(xy[0]), Fraction(xy[1])))


# ---------------------------------------------------------------------------------------------
# small cases by hand
# ---------------------------------------------------------------------------------------------
def test_square_has_four_segments():
    p = partition(model("square"))
    assert len(p.segments) == 4
    assert p.inserted == ()
    assert [(s.edge, s.t0, s.t1) for s in p.segments] == [(e, 0, 1) for e in range(4)]
    assert p.ring_offsets == (0, 4)


@given(env=convex_polygons())
def test_convex_polygons_have_no_inserted_points(env):
    p = partition(env)
    assert p.inserted == ()
    assert [(s.edge, s.t0, s.t1) for s in p.segments] == [(e, 0, 1) for e in range(env.n_edges)]


def test_l_shape_inserted_points_by_hand():
    """The shipped model l_shape: the reflex vertex r = (4, 4) sees (0, 10) and (10, 0) beside its obstacle wedge.

    - extension of (10, 4) → (4, 4): hits the left wall (0,10) → (0,0) at (0, 4), t = 3/5;
    - extension of (4, 10) → (4, 4): hits the floor at (4, 0), t = 2/5;
    - from (0, 10) through r, direction (4, −6): hits the floor at (20/3, 0), t = 2/3;
    - from (10, 0) through r, direction (−6, 4): hits the left wall at (0, 20/3), t = 1/3;
    (0, 0) lies in the wedge opposite the obstacle: its ray would enter the obstacle at r.
    """
    env = model("l_shape")
    p = partition(env)
    got = {(q.edge, q.t, q.point, q.reflex_vertex, q.from_vertex) for q in p.inserted}
    F = Fraction
    assert got == {
        (0, F(2, 5), (F(4), F(0)), 3, None),
        (0, F(2, 3), (F(20, 3), F(0)), 3, 5),
        (5, F(1, 3), (F(0), F(20, 3)), 3, 1),
        (5, F(3, 5), (F(0), F(4)), 3, None),
    }
    assert len(p.segments) == 10
    assert p.vertices()[0] == (
        (0, 0), (4, 0), (F(20, 3), 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10), (0, F(20, 3)), (0, 4)
    )


def test_holes_get_inserted_points_like_the_outer_ring():
    """Rays through a hole's corner land on the outer ring and on another hole; the outer ring's
    reflex vertex shoots too. Hand-computed: from the outer corner (0, 0) the ray grazes hole A's
    corner (6, 4) (it touches A only there) and hits hole B's left side x = 10 at (10, 20/3); from
    the outer reflex vertex (14, 10) the ray grazes B's corner (10, 8) and hits A's right side at (6, 6)."""
    outer = [[0, 0], [20, 0], [20, 10], [14, 10], [14, 12], [0, 12]]
    hole_a = [[4, 4], [6, 4], [6, 7], [4, 7]]
    hole_b = [[10, 2], [12, 2], [12, 8], [10, 8]]
    env = Environment.from_coords(outer, [hole_a, hole_b])
    p = partition(env)
    rings_hit = {int(env.ring_of[q.edge]) for q in p.inserted}
    assert rings_hit == {0, 1, 2}
    hit = next(q for q in p.inserted if q.point == (10, Fraction(20, 3)))
    assert (vertex_of(env, (6, 4)), vertex_of(env, (0, 0))) in hit.sources
    assert int(env.ring_of[hit.edge]) == 2
    hit = next(q for q in p.inserted if q.point == (6, 6))
    assert hit.sources == ((vertex_of(env, (10, 8)), vertex_of(env, (14, 10))),)
    assert int(env.ring_of[hit.edge]) == 1
    # hole corners are reflex for the free space and shoot: some hole corner's ray lands on the outer ring
    assert any(int(env.ring_of[r]) > 0 and int(env.ring_of[q.edge]) == 0 for q in p.inserted for r, _ in q.sources)
    # and the outer ring's reflex vertex (14, 10) extends its edges
    r = vertex_of(env, (14, 10))
    assert {v for q in p.inserted for rr, v in q.sources if rr == r} >= {None}
    assert inserted_set(p) == reference_inserted(env)
    # the shipped model one_hole: a convex hole in a convex room; all its rays land on the outer ring
    p = partition(model("one_hole"))
    assert len(p.inserted) == 14
    assert {int(p.env.ring_of[q.edge]) for q in p.inserted} == {0}
    assert {int(p.env.ring_of[q.reflex_vertex]) for q in p.inserted} == {1}


# ---------------------------------------------------------------------------------------------
# Prop. 1 on the paper's worst-case family
# ---------------------------------------------------------------------------------------------
# |P′| (segments) and inserted points of worst_case_polygon(t), n = 4t + 2, recorded with this test.
# Not smooth in t: for odd t a reflex vertex sits on the axis of symmetry and fewer rays continue.
WORST_CASE_SIZES = {2: (22, 12), 3: (42, 28), 4: (70, 52), 5: (94, 72), 6: (134, 108), 7: (182, 152), 8: (238, 204)}


def test_prop1_worst_case_family_partition_size():
    generators = pytest.importorskip("solverplan.generators")
    sizes = {}
    for t in range(2, 9):
        env = generators.worst_case_polygon(t)
        n = env.n_vertices
        p = partition(env)
        sizes[t] = (len(p.segments), len(p.inserted))
        # Prop. 1: every reflex vertex adds at most one point per other vertex: |P′| ≤ n + r (n − 1) ≤ n²
        assert len(p.segments) <= n + len(env.reflex_vertices) * (n - 1) <= n * n
        # §4.0.1: at least 2t(t − 1) + n vertices after insertion, each reflex vertex with ≥ t − 1 new points
        assert len(p.segments) >= 2 * t * (t - 1) + n
        for r in env.reflex_vertices:
            assert sum(1 for q in p.inserted if any(rr == r for rr, _ in q.sources)) >= t - 1
    assert sizes == WORST_CASE_SIZES
    counts = [sizes[t][0] for t in range(2, 9)]
    assert counts == sorted(set(counts))  # grows strictly
    # quadratic growth: |P′| / n² stays within a constant band while n grows 3.4×
    ratios = [sizes[t][0] / (4 * t + 2) ** 2 for t in range(2, 9)]
    assert 0.15 < min(ratios) and max(ratios) < 0.25


# ---------------------------------------------------------------------------------------------
# degenerate inputs: exact ties, never epsilons
# ---------------------------------------------------------------------------------------------
def test_degenerate_collinear_vertex_at_an_inserted_point_gives_the_same_partition_points():
    """A flat vertex put exactly where the L's edge extension lands: the same points of P′, once each."""
    with_flat = Environment.from_coords([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10], [0, 4]])
    assert with_flat.n_vertices == 7 and len(with_flat.reflex_vertices) == 1
    a, b = partition(L_SHAPE), partition(with_flat)
    points_a = [pt for ring in a.vertices() for pt in ring]
    points_b = [pt for ring in b.vertices() for pt in ring]
    assert len(points_b) == len(set(points_b))
    assert set(points_a) == set(points_b)
    assert len(b.inserted) == len(a.inserted) - 1
    assert (0, 4) not in {q.point for q in b.inserted}


def test_degenerate_collinear_vertex_is_a_vertex_like_any_other():
    """A flat vertex (5, 0) splits the floor into two original edges; a robot on the ceiling sees
    the edge (5, 0) → (10, 0) vanish behind r = (4, 4) where the line from (5, 0) through r meets the
    ceiling, at (5/2, 10): that point is inserted, besides the flat vertex itself."""
    with_flat = Environment.from_coords([[0, 0], [5, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]])
    a, b = partition(L_SHAPE), partition(with_flat)
    added = {(5, 0), (Fraction(5, 2), 10)}
    assert {pt for ring in b.vertices() for pt in ring} == {pt for ring in a.vertices() for pt in ring} | added
    assert same_edge_sets(with_flat, b.segments)
    assert inserted_set(b) == reference_inserted(with_flat)


def test_degenerate_ray_landing_on_a_vertex_inserts_nothing():
    """The extension of (10, 4) → (4, 4) runs along y = 4 into the convex corner (0, 4) exactly."""
    env = Environment.from_coords([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [1, 10], [0, 4]])
    corner = vertex_of(env, (0, 4))
    assert corner not in env.reflex_vertices
    p = partition(env)
    points = [pt for ring in p.vertices() for pt in ring]
    assert points.count((0, 4)) == 1
    assert all(q.point not in env.exact_vertices for q in p.inserted)
    assert all(s.t0 < s.t1 for s in p.segments)
    assert inserted_set(p) == reference_inserted(env)


def test_degenerate_two_rays_hitting_the_same_point_are_merged():
    """A protrusion hanging from the ceiling: the extensions at its two lower corners (7, 4) and (3, 4)
    both land on the floor at (5, 0) (t = 1/2)."""
    env = Environment.from_coords(
        [[0, 0], [10, 0], [10, 10], [9, 10], [9, 8], [7, 4], [3, 4], [1, 8], [1, 10], [0, 10]]
    )
    p = partition(env)
    at = [q for q in p.inserted if q.point == (5, 0)]
    assert len(at) == 1
    assert (at[0].edge, at[0].t) == (0, Fraction(1, 2))
    assert {(vertex_of(env, (7, 4)), None), (vertex_of(env, (3, 4)), None)} <= set(at[0].sources)
    assert at[0].sources[0] == (at[0].reflex_vertex, at[0].from_vertex)
    assert sum(1 for s in p.segments if s.edge == 0 and s.t0 == Fraction(1, 2)) == 1
    assert inserted_set(p) == reference_inserted(env)


def test_degenerate_model_matches_the_reference():
    env = model("degenerate")
    assert inserted_set(partition(env)) == reference_inserted(env)


# ---------------------------------------------------------------------------------------------
# structure: segments tile the edges, inserted points lie on their edges
# ---------------------------------------------------------------------------------------------
def check_structure(p: Partition) -> None:
    env = p.env
    assert [s.id for s in p.segments] == list(range(len(p.segments)))
    edges = [s.edge for s in p.segments]
    assert edges == sorted(edges) and set(edges) == set(range(env.n_edges))
    for e in range(env.n_edges):
        segs = [s for s in p.segments if s.edge == e]
        assert segs[0].t0 == 0 and segs[-1].t1 == 1
        assert all(x.t1 == y.t0 for x, y in zip(segs, segs[1:]))
        for s in segs:
            assert 0 <= s.t0 < s.t1 <= 1
            assert s.a == env.exact_point_at(e, s.t0) and s.b == env.exact_point_at(e, s.t1)
    assert p.ring_offsets[0] == 0 and p.ring_offsets[-1] == len(p.segments)
    for k in range(len(env.rings)):
        first = p.segments[p.ring_offsets[k]]
        assert first.edge == env.ring_offsets[k] and first.t0 == 0  # starts at the ring's vertex 0
    for s in p.segments:
        assert p.segments[int(p.next_segment[s.id])].a == s.b
        assert int(p.prev_segment[int(p.next_segment[s.id])]) == s.id
    keys = [(q.edge, q.t) for q in p.inserted]
    assert keys == sorted(set(keys))  # sorted, each once
    for q in p.inserted:
        edge = env.edge(q.edge)
        assert isinstance(q.t, Fraction) and 0 < q.t < 1
        assert orient(edge.a, edge.b, q.point) == 0
        assert q.point == env.exact_point_at(q.edge, q.t)
        assert q.point not in env.exact_vertices
        assert env.is_reflex(q.reflex_vertex)
        assert q.sources[0] == (q.reflex_vertex, q.from_vertex)
    assert len(p.segments) == env.n_edges + len(p.inserted)


@pytest.mark.parametrize("name", sorted(path.stem for path in MODELS.glob("*.json")))
def test_segments_tile_every_edge_exactly(name):
    check_structure(partition(model(name)))


@given(env=polygons_with_holes())
def test_segments_tile_every_edge_exactly_with_holes(env):
    check_structure(partition(env))


# ---------------------------------------------------------------------------------------------
# agreement with the brute-force reference
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["l_shape", "two_rooms", "one_hole", "two_holes", "comb", "star", "worst_case_t4"])
def test_models_match_the_reference(name):
    env = model(name)
    assert inserted_set(partition(env)) == reference_inserted(env)


@settings(max_examples=60)
@given(env=simple_polygons(max_vertices=12))
def test_partition_matches_the_reference(env):
    assert inserted_set(partition(env)) == reference_inserted(env)


@settings(max_examples=40)
@given(env=polygons_with_holes(max_vertices=9, max_holes=2))
def test_partition_with_holes_matches_the_reference(env):
    assert inserted_set(partition(env)) == reference_inserted(env)


@st.composite
def grid_polygons(draw):
    """Star-ordered polygons on a 7 × 7 grid: many collinear vertices, rays through vertices, ties."""
    import math

    from hypothesis import assume

    from solverplan.errors import InvalidEnvironment

    n = draw(st.integers(4, 11))
    pts = draw(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=n, max_size=n, unique=True))
    cx, cy = sum(x for x, _ in pts) / n, sum(y for _, y in pts) / n
    pts.sort(key=lambda q: (math.atan2(q[1] - cy, q[0] - cx), q))
    try:
        return Environment.from_coords(pts)
    except InvalidEnvironment:
        assume(False)


@settings(max_examples=60)
@given(env=grid_polygons())
def test_degenerate_grid_polygons_match_the_reference(env):
    assert inserted_set(partition(env)) == reference_inserted(env)


@pytest.mark.parametrize("name", ["degenerate", "two_rooms", "warehouse", "star", "two_holes"])
def test_exact_fallback_agrees_with_the_float_path(name, monkeypatch):
    """With float positions made useless every pair goes through the exact scalar caster."""
    env = model(name)
    fast = partition(env)
    monkeypatch.setattr(partition_module, "_LAMBDA_REL", 1e6)
    assert partition_module._partition(env) == fast  # computed again (partition() keeps recent ones)


def test_recent_partitions_are_reused_and_equal_to_a_fresh_one():
    """partition() keeps the last partitions by environment: an equal environment gets the same answer at once."""
    env = model("two_holes")
    first = partition(env)
    again = Environment(env.rings, name="renamed")  # equal rings: the same partition, on the environment asked for
    assert partition(again) == first and partition(again).env is again
    assert partition_module._partition(env) == first


def test_offset_and_scaled_coordinates_give_the_same_parameters():
    """An affine change of coordinates keeps every boundary parameter; far from the origin and small,
    many float signs become uncertain and are decided exactly."""
    env = model("two_rooms")
    moved = Environment.from_coords([[x / 1000 + 10**6, y / 1000 - 10**6] for x, y in env.outer])
    assert [(q.edge, q.t) for q in partition(env).inserted] == [(q.edge, q.t) for q in partition(moved).inserted]


# ---------------------------------------------------------------------------------------------
# the paper's claim: two points of one segment see the same set of original edges
# ---------------------------------------------------------------------------------------------
def seen_edges(env: Environment, p) -> frozenset[int]:
    """Edges with a part of positive length in the (exact) visibility polygon of p."""
    vp = visibility_polygon(env, p)
    return frozenset(piece.edge for piece in vp.pieces if piece.kind in ("edge", "partial") and piece.a != piece.b)


def same_edge_sets(env: Environment, segments) -> bool:
    for s in segments:
        samples = [env.exact_point_at(s.edge, s.t0 + (s.t1 - s.t0) * Fraction(k, 4)) for k in (1, 2, 3)]
        if len({seen_edges(env, x) for x in samples}) != 1:
            return False
    return True


@pytest.mark.parametrize("name", ["l_shape", "one_hole", "two_holes", "two_rooms", "degenerate", "worst_case_t4"])
def test_points_of_a_segment_see_the_same_original_edges(name):
    env = model(name)
    assert same_edge_sets(env, partition(env).segments)


def test_points_of_an_unpartitioned_edge_do_not_see_the_same_edges():
    """Control: the claim fails for the original edges, so the test above can fail."""
    floor = partition(L_SHAPE).segments[0]
    whole_floor = type(floor)(0, 0, Fraction(0), Fraction(1), L_SHAPE.exact_vertices[0], L_SHAPE.exact_vertices[1])
    assert not same_edge_sets(L_SHAPE, [whole_floor])
    assert same_edge_sets(L_SHAPE, [floor])


@settings(max_examples=8)
@given(env=simple_polygons(max_vertices=9))
def test_points_of_a_segment_see_the_same_original_edges_random(env):
    assert same_edge_sets(env, partition(env).segments)


# ---------------------------------------------------------------------------------------------
# lookup
# ---------------------------------------------------------------------------------------------
def test_segment_at_puts_partition_points_in_the_segment_starting_there():
    p = partition(L_SHAPE)  # edge 0 is cut at 2/5 and 2/3: segments 0, 1, 2
    assert p.segment_at(0, 0) == 0
    assert p.segment_at(0, Fraction(2, 5)) == 1
    assert p.segment_at(0, Fraction(1, 2)) == 1
    assert p.segment_at(0, Fraction(2, 3)) == 2
    assert p.segment_at(0, 1) == 3  # the end vertex starts the next edge's first segment
    last = len(p.segments) - 1
    assert p.segment_at(5, 1) == 0 and p.segment_at(5, Fraction(9, 10)) == last
    got = p.segments_at([0, 0, 0, 0, 0, 5, 5], [0.0, 0.4, 0.5, 2 / 3 + 1e-12, 1.0, 1.0, 0.9])
    assert got.tolist() == [0, 1, 1, 2, 3, 0, last]


def test_segments_at_agrees_with_segment_at():
    p = partition(model("two_holes"))
    rng = np.random.default_rng(3)
    edges = rng.integers(0, p.env.n_edges, 500)
    t = rng.random(500)
    t[:50] = p.seg_t0[rng.integers(0, len(p.segments), 50)]  # exactly on partition points (as floats)
    edges[:50] = p.seg_edge[rng.integers(0, len(p.segments), 50)]
    fast = p.segments_at(edges, t)
    exact = [p.segment_at(int(e), Fraction(float(x))) for e, x in zip(edges, t)]
    # a float t rounded from an inserted point's parameter may fall on either side of it
    assert np.mean(fast == np.array(exact)) > 0.9
    for k in range(50, 500):
        s = p.segments[fast[k]]
        assert s.edge == edges[k] and float(s.t0) <= t[k] <= float(s.t1)


def test_lookup_errors_are_input_errors():
    p = partition(L_SHAPE)
    with pytest.raises(InputError, match=r"^unknown edge e6: edges are e0\.\.e5$"):
        p.segment_at(6, 0)
    with pytest.raises(InputError, match=r"^boundary parameter t=1\.5 on edge 0 is not in \[0, 1\]$"):
        p.segment_at(0, Fraction(3, 2))
    with pytest.raises(InputError, match=r"^t\[1\] = -0\.1 is not in \[0, 1\]$"):
        p.segments_at([0, 1], [0.5, -0.1])


def test_float_views_are_read_only_and_consistent():
    p = partition(model("one_hole"))
    assert p.seg_start.shape == (len(p), 2) and not p.seg_start.flags.writeable
    assert np.allclose(p.seg_end, p.seg_start[p.next_segment])
    assert p.seg_edge.tolist() == [s.edge for s in p.segments]
    assert [len(ring) for ring in p.vertices()] == [p.ring_offsets[k + 1] - p.ring_offsets[k] for k in range(2)]


# ---------------------------------------------------------------------------------------------
# output: JSON, text, CLI, picture
# ---------------------------------------------------------------------------------------------
def test_to_json_is_exact_and_follows_the_contract():
    p = partition(L_SHAPE)
    data = json.loads(json.dumps(p.to_json()))
    assert {"vertices", "segments", "inserted"} <= set(data)
    assert data["segments"][1] == {"id": 1, "edge": 0, "t0": 0.4, "t1": "2/3", "a": [4, 0], "b": ["20/3", 0]}
    assert data["vertices"][0][2] == ["20/3", 0]
    for seg, exact in zip(data["segments"], p.segments):
        assert to_fraction(seg["t0"]) == exact.t0 and to_fraction(seg["t1"]) == exact.t1
        assert tuple(to_fraction(x) for x in seg["b"]) == exact.b
    assert data["inserted"][1] == {
        "point": ["20/3", 0], "edge": 0, "t": "2/3", "reflex_vertex": 3, "from_vertex": 5, "sources": [[3, 5]]
    }


def test_to_text_is_a_readable_table():
    text = partition(L_SHAPE).to_text(width=100)
    assert "inserted points" in text and "segments" in text
    assert "(20/3, 0)*" in text and "r3 v5" in text and "r3 ext" in text
    assert max(len(line) for line in text.splitlines()) <= 100


runner = CliRunner()


def test_cli_partition_prints_json(tmp_path):
    result = runner.invoke(cli.app, ["partition", str(MODELS / "l_shape.json")])
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert len(data["segments"]) == 10 and len(data["inserted"]) == 4
    assert data == json.loads(json.dumps(partition(model("l_shape")).to_json()))
    out = tmp_path / "p.txt"
    result = runner.invoke(cli.app, ["partition", str(MODELS / "one_hole.json"), "--format", "text", "-o", str(out)])
    assert result.exit_code == 0 and result.stdout == ""
    assert "segments 18..21" in out.read_text()  # the hole's segments


def test_cli_partition_bad_input_is_one_line_exit_2(tmp_path):
    bad = tmp_path / "bowtie.json"
    bad.write_text(json.dumps({"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]}))
    result = runner.invoke(cli.app, ["partition", str(bad)])
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and "edge 0 crosses edge 2 at (1, 1)" in result.stderr


def test_render_partition_layer_and_cli_flag(tmp_path):
    from solverplan.render import draw_partition, render_environment

    p = partition(model("two_rooms"))
    fig = render_environment(p.env)
    artists = draw_partition(fig.axes[0], p)
    assert artists[0].get_gid() == "partition-segments" and len(artists[0].get_segments()) == len(p)
    assert artists[1].get_gid() == "partition-inserted" and len(artists[1].get_offsets()) == len(p.inserted)
    labels = [a for a in artists[2:] if a.get_gid().startswith("segment-id-")]
    assert [a.get_text() for a in labels] == [str(k) for k in range(len(p))]
    colours = artists[0].get_colors()
    for s in p.segments:  # neighbours along a ring never share a colour
        assert tuple(colours[s.id]) != tuple(colours[int(p.next_segment[s.id])])
    out = tmp_path / "p.png"
    result = runner.invoke(cli.app, ["render", str(MODELS / "one_hole.json"), "--partition", "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------------------------
# the reference partition: pure Fractions, all pairs, every edge
# ---------------------------------------------------------------------------------------------
def _in_free(env: Environment, p, *, closed: bool) -> bool:
    outer = point_in_ring(p, env.outer)
    holes = [point_in_ring(p, h) for h in env.holes]
    if closed:
        return outer >= 0 and all(h <= 0 for h in holes)
    return outer > 0 and all(h < 0 for h in holes)


def _events(env: Environment, o, d):
    """(s, kind, edge, t) for s > 0 where the line o + s d meets the boundary, sorted; kind 'v' for a
    vertex (edge = the vertex), 'e' for a proper crossing of edge's interior at t."""
    verts, nxt = env.exact_vertices, env.next_vertex
    dd = d[0] * d[0] + d[1] * d[1]
    out = []
    for i in range(env.n_edges):
        a, b = verts[i], verts[int(nxt[i])]
        ca = d[0] * (a[1] - o[1]) - d[1] * (a[0] - o[0])
        cb = d[0] * (b[1] - o[1]) - d[1] * (b[0] - o[0])
        if ca == 0:
            out.append((Fraction((a[0] - o[0]) * d[0] + (a[1] - o[1]) * d[1]) / dd, "v", i, Fraction(0)))
        if (ca > 0) != (cb > 0) and ca != 0 and cb != 0:
            t = Fraction(ca) / (ca - cb)
            x = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            out.append((Fraction((x[0] - o[0]) * d[0] + (x[1] - o[1]) * d[1]) / dd, "e", i, t))
    return sorted(e for e in out if e[0] > 0)


def _at(o, d, s):
    return (o[0] + s * d[0], o[1] + s * d[1])


def _closed_visible(env: Environment, p, q) -> bool:
    d = (q[0] - p[0], q[1] - p[1])
    cuts = sorted({Fraction(0), Fraction(1), *(s for s, *_ in _events(env, p, d) if s < 1)})
    return all(_in_free(env, _at(p, d, (x + y) / 2), closed=True) for x, y in zip(cuts, cuts[1:]))


def reference_inserted(env: Environment) -> set[tuple[int, Fraction]]:
    """Algorithm 1 by brute force: every reflex r, every v whose closed segment to r is free, the ray
    beyond r when it starts into the open free space; its first blocking point, if an edge interior."""
    verts = env.exact_vertices
    found = set()
    for r in env.reflex_vertices:
        for v in range(env.n_vertices):
            if v == r or not _closed_visible(env, verts[v], verts[r]):
                continue
            o = verts[r]
            d = (o[0] - verts[v][0], o[1] - verts[v][1])
            events = _events(env, o, d)
            if not events or not _in_free(env, _at(o, d, events[0][0] / 2), closed=False):
                continue
            stops = sorted({s for s, *_ in events})
            for k, s in enumerate(stops):
                after = (s + stops[k + 1]) / 2 if k + 1 < len(stops) else s + 1
                if not _in_free(env, _at(o, d, after), closed=True):
                    here = [e for e in events if e[0] == s]
                    if all(kind == "e" for _, kind, _, _ in here):
                        found.add((here[0][2], here[0][3]))
                    break
    return found
