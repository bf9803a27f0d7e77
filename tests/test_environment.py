"""Environment: normalisation, numbering, boundary coordinates, file formats, validation messages."""

from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.environment import (
    BoundaryPiece,
    Environment,
    format_environment,
    load_environment,
    parse_environment,
    save_environment,
)
from solverplan.environment import _candidate_pairs, _edge_pair_problem
from solverplan.exact import ExactPoint
from solverplan.errors import InputError, InvalidBoundarySet, InvalidEnvironment, MalformedFile
from tests.strategies import polygons_with_holes

SQUARE_WITH_HOLE = Environment.from_coords(
    [[0, 0], [10, 0], [10, 10], [0, 10]], [[[2, 2], [4, 2], [4, 4], [2, 4]]], name="sq-hole"
)


def test_orientation_is_normalised_outer_ccw_holes_cw():
    env = Environment.from_coords([[0, 0], [0, 10], [10, 10], [10, 0]], [[[2, 2], [4, 2], [4, 4], [2, 4]]])
    assert env.reoriented == (True, True)
    assert env.outer == ((0, 0), (10, 0), (10, 10), (0, 10))
    assert env.holes[0] == ((2, 2), (2, 4), (4, 4), (4, 2))


def test_edge_numbering_continues_over_holes():
    env = SQUARE_WITH_HOLE
    assert env.n_edges == 8 and env.ring_offsets == (0, 4, 8)
    assert env.edge(3).a == (0, 10) and env.edge(3).b == (0, 0)  # outer ring wraps
    assert env.edge(4).ring == 1 and env.edge(7).b == env.edge(4).a  # hole ring wraps to its own start
    assert list(env.next_vertex) == [1, 2, 3, 0, 5, 6, 7, 4]
    assert list(env.prev_vertex[env.next_vertex]) == list(range(8))


def test_reflex_vertices_include_convex_corners_of_holes():
    assert SQUARE_WITH_HOLE.reflex_vertices == (4, 5, 6, 7)
    l_shape = Environment.from_coords([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])
    assert l_shape.reflex_vertices == (3,)


def test_collinear_consecutive_vertices_are_kept_and_not_reflex():
    env = Environment.from_coords([[0, 0], [1, 0], [2, 0], [2, 2], [0, 2]])
    assert env.n_vertices == 5 and env.reflex_vertices == ()


def test_area_is_exact_and_decimals_are_read_exactly():
    env = Environment.from_coords([[0, 0], ["0.1", 0], ["0.1", "0.3"]])
    assert env.area == Fraction(3, 200)
    env_float = Environment.from_coords([[0, 0], [0.1, 0], [0.1, 0.3]])
    assert env_float.area == Fraction(3, 200)  # floats taken at their shortest decimal


def test_boundary_coordinates_round_trip_through_arc_length():
    env = SQUARE_WITH_HOLE
    edges = np.array([0, 3, 4, 7, 5])
    t = np.array([0.0, 0.5, 0.25, 0.999, 0.5])
    s = env.arc_length(edges, t)
    back_edges, back_t = env.from_arc_length(s)
    assert list(back_edges) == list(edges) and np.allclose(back_t, t)
    assert env.arc_length(4, 0) == 40.0
    assert env.perimeter == 48.0


def test_locate_exact_points_and_vertices():
    env = SQUARE_WITH_HOLE
    assert env.locate((10, "2.5")) == (1, Fraction(1, 4))
    assert env.locate((10, 10)) == (2, 0)  # a vertex is reported on the edge it starts
    assert env.exact_point_at(1, Fraction(1, 4)) == (10, Fraction(5, 2))
    with pytest.raises(InvalidBoundarySet, match=r"^point \(5, 5\) is not on the boundary$"):
        env.locate((5, 5))


def test_boundary_sets_parse_pieces_and_reject_bad_ones():
    env = SQUARE_WITH_HOLE
    parsed = env.boundary_set("e3:0.5:1, e4")
    assert parsed.pieces == (BoundaryPiece(3, Fraction(1, 2), Fraction(1)), BoundaryPiece(4, Fraction(0), Fraction(1)))
    assert str(parsed) == "e3:0.5:1,e4"
    assert parsed.edges == (3, 4)
    with pytest.raises(InvalidBoundarySet, match=r"^unknown edge e8: edges are e0\.\.e7$"):
        env.boundary_set("e8")
    with pytest.raises(InvalidBoundarySet, match=r"need 0 <= t0 < t1 <= 1, got t0=0.75, t1=0.25$"):
        env.boundary_set("e1:0.75:0.25")
    with pytest.raises(InvalidBoundarySet, match=r"^boundary set piece 'x3' is malformed"):
        env.boundary_set("x3")
    with pytest.raises(InvalidBoundarySet, match=r"is not a number$"):
        env.boundary_set("e1:a:0.5")


@pytest.mark.parametrize(
    ("outer", "holes", "message"),
    [
        ([[0, 0], [2, 2], [2, 0], [0, 2]], [], r"^outer ring self-intersects: edge 0 crosses edge 2 at \(1, 1\)$"),
        ([[0, 0], [1, 0]], [], r"^outer ring has fewer than 3 distinct vertices \(2\)$"),
        ([[0, 0], [1, 0], [1, 0], [0, 1]], [], r"^outer ring repeats vertex 1 at \(1, 0\) as vertex 2$"),
        ([[0, 0], [1, 0], [2, 0]], [], r"^outer ring has zero area \(all its vertices are collinear\)$"),
        ([[0, 0], [float("nan"), 0], [0, 1]], [], r"^outer ring vertex 1: coordinate is not finite \(nan\)$"),
        ([[0, 0], [float("inf"), 0], [0, 1]], [], r"^outer ring vertex 1: coordinate is not finite \(inf\)$"),
        ([[0, 0], ["abc", 0], [0, 1]], [], r"^outer ring vertex 1: 'abc' is not a number$"),
        ([[0, 0], [1], [0, 1]], [], r"^outer ring vertex 1: expected a pair \[x, y\], got \[1\]$"),
        ([[0, 0], [4, 0], [4, 4], [2, 0], [0, 4]], [], r"^outer ring self-intersects: edge 0 touches edge 2 at \(2, 0\)$"),
        ([[0, 0], [4, 0], [4, 4], [4, 2], [0, 4]], [], r"^outer ring self-intersects: edge 1 overlaps edge 2 from \(4, 2\) to \(4, 4\)$"),
        (
            [[0, 0], [10, 0], [10, 10], [0, 10]],
            [[[20, 20], [21, 20], [21, 21]]],
            r"^hole 0 lies outside the outer ring$",
        ),
        (
            [[0, 0], [10, 0], [10, 10], [0, 10]],
            [[[0, 5], [2, 5], [2, 6]]],
            r"^hole 0 touches the outer ring at \(0, 5\) \(hole edge 2, outer edge 3\)$",
        ),
        (
            [[0, 0], [10, 0], [10, 10], [0, 10]],
            [[[1, 1], [5, 1], [5, 5]], [[3, 1], [3, 0.5], [6, 0.5]]],
            r"^hole 0 touches hole 1 at \(3, 1\)",
        ),
        (
            [[0, 0], [10, 0], [10, 10], [0, 10]],
            [[[1, 1], [8, 1], [8, 8], [1, 8]], [[3, 3], [4, 3], [4, 4]]],
            r"^hole 1 lies inside hole 0$",
        ),
    ],
    ids=[
        "bowtie",
        "two-vertices",
        "repeated-vertex",
        "collinear",
        "nan",
        "inf",
        "non-numeric",
        "not-a-pair",
        "ring-touches-itself",
        "spike-overlap",
        "hole-outside",
        "hole-touches-outer",
        "holes-touch",
        "hole-in-hole",
    ],
)
def test_invalid_environments_get_one_clear_message(outer, holes, message):
    with pytest.raises(InvalidEnvironment, match=message) as info:
        Environment.from_coords(outer, holes)
    assert "\n" not in str(info.value)
    assert isinstance(info.value, ValueError)  # callers may catch the builtin


def test_self_intersection_is_reported_in_input_numbering_even_when_reversed():
    # clockwise figure: reversing it must not renumber the edges named in the message
    with pytest.raises(InvalidEnvironment, match=r"^outer ring self-intersects: edge 0 crosses edge 3 at \(2.4, 1.2\)$"):
        Environment.from_coords([[0, 2], [6, 0], [4, 0], [4, 2], [0, 0]])  # clockwise


def test_constructor_rejects_wrong_orientation():
    with pytest.raises(InvalidEnvironment, match=r"^outer ring is clockwise"):
        Environment((((0, 0), (0, 1), (1, 0)),))


@pytest.mark.parametrize("fmt", ["json", "geojson", "wkt"])
@given(env=polygons_with_holes(max_holes=2))
def test_every_file_format_round_trips_exactly(fmt, env):
    text = format_environment(env, fmt)
    back = parse_environment(text, fmt)
    assert back == env
    assert back.reoriented == (False,) * len(env.rings)  # written normalised


def test_json_keeps_exact_decimals_and_ratios(tmp_path):
    env = Environment.from_coords([[0, 0], ["0.1", 0], ["1/3", "2.75"]], name="exact")
    path = tmp_path / "exact.json"
    save_environment(env, path)
    assert json.loads(path.read_text())["outer"][2] == ["1/3", 2.75]
    assert load_environment(path) == env and load_environment(path).name == "exact"


def test_geojson_feature_collection_and_wkt_files_load(tmp_path):
    collection = {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "properties": {"name": "tri"},
                "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 1], [0, 0]]]},
            }
        ],
    }
    (tmp_path / "a.geojson").write_text(json.dumps(collection))
    assert load_environment(tmp_path / "a.geojson").name == "tri"
    (tmp_path / "b.wkt").write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (2 2, 2 4, 4 4, 4 2, 2 2))")
    env = load_environment(tmp_path / "b.wkt")
    assert env.name == "b" and env.n_edges == 8


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("trunc.json", '{"outer": [[0, 0], [1, 0], [0, 1]', r"trunc\.json: not valid JSON \(Expecting ',' delimiter"),
        ("nan.json", '{"outer": [[0, 0], [NaN, 0], [0, 1]]}', r"nan\.json: non-finite number NaN in file$"),
        ("list.json", "[1, 2]", r'list\.json: expected a JSON object'),
        ("noouter.json", '{"holes": []}', r'noouter\.json: missing "outer"'),
        ("two.geojson", '{"type": "FeatureCollection", "features": []}', r"exactly one feature, found 0$"),
        ("line.geojson", '{"type": "LineString", "coordinates": []}', r"must be a Polygon, got LineString$"),
        ("pt.wkt", "POINT (1 2)", r"pt\.wkt: WKT must be a POLYGON, got 'POINT'$"),
        ("empty.wkt", "POLYGON EMPTY", r"WKT polygon is EMPTY$"),
        ("trunc.wkt", "POLYGON ((0 0, 1 0", r"unbalanced parentheses$"),
        ("bad.wkt", "POLYGON ((0 0, 1, 0 1))", r"WKT ring 0 point 1: expected 'x y', got '1'$"),
        ("shape.txt", "{}", r"cannot tell the format from the extension '\.txt'"),
    ],
)
def test_malformed_files_get_one_clear_message(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(MalformedFile, match=message) as info:
        load_environment(path)
    assert "\n" not in str(info.value)


def test_missing_file_is_input_error(tmp_path):
    with pytest.raises(InputError, match=r"nothere\.json: no such file, nor a shipped model$"):
        load_environment(tmp_path / "nothere.json")


def test_invalid_polygon_in_file_names_the_file(tmp_path):
    path = tmp_path / "bowtie.json"
    path.write_text('{"outer": [[0, 0], [2, 2], [2, 0], [0, 2]]}')
    with pytest.raises(InvalidEnvironment, match=r"bowtie\.json: outer ring self-intersects: edge 0 crosses edge 2"):
        load_environment(path)


def test_save_is_atomic_and_leaves_no_temporary_files(tmp_path):
    path = tmp_path / "out.json"
    save_environment(SQUARE_WITH_HOLE, path)
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


@given(env=polygons_with_holes(), data=st.data())
def test_point_at_lies_on_its_edge_and_locate_inverts_exact_point_at(env, data):
    edge = data.draw(st.integers(0, env.n_edges - 1))
    t = data.draw(st.fractions(0, 1, max_denominator=50).filter(lambda f: f < 1))
    point = env.exact_point_at(edge, t)
    assert env.locate(point) == (edge, t) or t == 0
    assert np.allclose(env.point_at(edge, float(t)), [float(point[0]), float(point[1])])


# ---------------------------------------------------------------------- validation at scale
def _star(n: int) -> list[list[float]]:
    """A radial star: vertices alternating at radius 1000 and 1300, six decimals (long thin edges)."""
    return [[round(r * math.cos(a), 6), round(r * math.sin(a), 6)]
            for k in range(n) for r, a in [(1000 if k % 2 == 0 else 1300, 2 * math.pi * k / n)]]


def _comb(teeth: int, bowtie: int | None = None) -> list[list[int]]:
    """Teeth 1 wide and 10 tall, 1 apart, on a base (clockwise); tooth ``bowtie`` has its top two vertices
    swapped, so that exactly two edges cross, edge 4·bowtie and edge 4·bowtie + 2, at (2·bowtie + 0.5, 5)."""
    ring = []
    for k in range(teeth):
        a = 2 * k
        corners = [[a, 0], [a, 10], [a + 1, 10], [a + 1, 0]]
        if k == bowtie:
            corners[1], corners[2] = corners[2], corners[1]
        ring += corners
    return ring + [[2 * teeth - 1, -5], [0, -5]]


def _first_illegal_pair(ring: list[ExactPoint]) -> str | None:
    """Reference: every pair of edges of one ring whose exact bounding boxes meet, exactly, in order."""
    n = len(ring)
    boxes = [(min(p[0], q[0]), max(p[0], q[0]), min(p[1], q[1]), max(p[1], q[1]))
             for p, q in zip(ring, ring[1:] + ring[:1])]
    for i in range(n):
        for j in range(i + 1, n):
            a, b = boxes[i], boxes[j]
            if a[1] < b[0] or b[1] < a[0] or a[3] < b[2] or b[3] < a[2]:
                continue
            problem = _edge_pair_problem(ring, n, i, j)
            if problem:
                return problem
    return None


@pytest.mark.parametrize("seed", range(60))
def test_the_sweep_finds_exactly_the_rings_the_all_pairs_reference_rejects(seed):
    # 65-200 vertices (beyond the pair-by-pair size) on coarse grids, so that touches, vertices on edges,
    # shared points, collinear runs and overlaps, and vertical edges are common; about 40 % are valid
    rng = np.random.default_rng(seed)
    n = int(rng.integers(65, 200))
    angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    r0 = rng.choice([30, 100, 400])
    scale = int(rng.choice([1, 3, 7]))
    ring = [(Fraction(round(r * math.cos(a)), scale), Fraction(round(r * math.sin(a)), scale))
            for r, a in zip(rng.uniform(r0, 2 * r0, n), angles)]
    for _ in range(int(rng.integers(0, 4)) * (rng.random() < 0.5)):  # a vertex onto or next to another
        i, j = rng.integers(0, n, 2)
        ring[i] = (ring[j][0] + int(rng.integers(-1, 2)), ring[j][1] + int(rng.integers(-1, 2)))
    if rng.random() < 0.15:  # two neighbours swapped
        i = int(rng.integers(0, n - 1))
        ring[i], ring[i + 1] = ring[i + 1], ring[i]
    ring = [p for k, p in enumerate(ring) if p != ring[k - 1]]  # the ring-shape check refuses repeats first
    n = len(ring)
    assert n > 64
    expected = _first_illegal_pair(ring)
    starts = np.array([[float(x), float(y)] for x, y in ring])
    pairs = _candidate_pairs(starts, np.roll(np.arange(n), -1), ring)
    found = next((p for p in (_edge_pair_problem(ring, n, i, j) for i, j in pairs) if p), None)
    assert (found is None) == (expected is None), (expected, found)


def test_a_crossing_hidden_among_10_000_vertices_is_found_in_input_numbering():
    with pytest.raises(InvalidEnvironment, match=r"^outer ring self-intersects: edge 6000 crosses edge 6002 at \(3000.5, 5\)$"):
        Environment.from_coords(_comb(2_499, bowtie=1_500))
    assert Environment.from_coords(_comb(2_499)).n_vertices == 9_998


def test_a_10_000_vertex_star_is_valid_and_a_hole_touching_it_is_named():
    outer = _star(10_000)
    env = Environment.from_coords(outer)
    assert env.n_vertices == 10_000 and len(env.reflex_vertices) == 5_000
    # a thin triangle in the first spike, one corner exactly on the middle of edge 0
    a, b = env.exact_vertices[0], env.exact_vertices[1]
    middle = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    axis = 2 * math.pi / 10_000
    hole = [middle, [1100 * math.cos(axis), 1100 * math.sin(axis)], [900 * math.cos(axis), 900 * math.sin(axis)]]
    with pytest.raises(InvalidEnvironment, match=r"^hole 0 touches the outer ring at \(.+\) \(hole edge [02], outer edge 0\)$"):
        Environment.from_coords(outer, [hole])
    with pytest.raises(InvalidEnvironment, match=r"^hole 0 touches the outer ring at \(1000, 0\)"):
        Environment.from_coords(outer, [[outer[0], [500, 10], [500, -10]]])  # a hole corner on vertex 0


@pytest.mark.slow
def test_a_crossing_hidden_among_100_000_vertices_is_found():
    with pytest.raises(InvalidEnvironment, match=r"^outer ring self-intersects: edge 80000 crosses edge 80002 at \(40000.5, 5\)$"):
        Environment.from_coords(_comb(24_999, bowtie=20_000))
    assert Environment.from_coords(_star(100_000)).n_vertices == 100_000
    outer = _star(99_996)  # with a triangular hole: 99,999 vertices, inside the limit
    with pytest.raises(InvalidEnvironment, match=r"^hole 0 touches the outer ring at \(1000, 0\)"):
        Environment.from_coords(outer, [[outer[0], [500, 10], [500, -10]]])
