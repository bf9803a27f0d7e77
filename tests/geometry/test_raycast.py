"""Ray casting: the exact caster against a brute-force reference, the batch caster against both.

The reference below loops over every edge in Fractions and lists every contact of the ray with the
boundary (proper crossings and vertices on the ray), sorted by s; it shares no code with
:mod:`solverplan.geometry.raycast`. Whether the ray may go on past a vertex is decided the slow,
obvious way: is the midpoint to the next contact in the closed free space?
"""

from __future__ import annotations

import inspect
import math
from fractions import Fraction

import numpy as np
import pytest
import shapely
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import point_in_ring
from solverplan.geometry import RayCaster, RayHit, cast_from_boundary, cast_ray, cast_rays, cast_rays_exact, ray_caster
from tests.strategies import convex_polygons, polygons_with_holes, simple_polygons

SQUARE = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
L_ROOM = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
# outer 12×12 box with a flat vertex at (6, 0), and a square hole [4, 6]²
HOLED = Environment.from_coords(
    [[0, 0], [6, 0], [12, 0], [12, 12], [0, 12]], [[[4, 4], [6, 4], [6, 6], [4, 6]]]
)


# ------------------------------------------------------------------------------------ reference
def in_closed_free_space(env: Environment, p) -> bool:
    return point_in_ring(p, env.outer) >= 0 and all(point_in_ring(p, h) <= 0 for h in env.holes)


def in_open_free_space(env: Environment, p) -> bool:
    return point_in_ring(p, env.outer) > 0 and all(point_in_ring(p, h) < 0 for h in env.holes)


def reference_contacts(env: Environment, origin, direction):
    """Every (s, edge, t, point, vertex) where the ray (s > 0) meets the boundary, sorted by s."""
    ox, oy = map(Fraction, origin)
    dx, dy = map(Fraction, direction)
    verts = env.exact_vertices
    out = []
    for i in range(env.n_edges):
        a, b = verts[i], verts[int(env.next_vertex[i])]
        rx, ry = b[0] - a[0], b[1] - a[1]
        if dx * (a[1] - oy) - dy * (a[0] - ox) == 0:  # vertex i on the ray's line
            s = (dx * (a[0] - ox) + dy * (a[1] - oy)) / (dx * dx + dy * dy)
            if s > 0:
                out.append((s, i, Fraction(0), a, i))
        den = dx * ry - dy * rx
        if den == 0:
            continue
        s = ((a[0] - ox) * ry - (a[1] - oy) * rx) / den
        t = ((a[0] - ox) * dy - (a[1] - oy) * dx) / den
        if s > 0 and 0 < t < 1:
            out.append((s, i, t, (a[0] + t * rx, a[1] + t * ry), None))
    return sorted(out, key=lambda c: c[0])


def reference_first_hit(env: Environment, origin, direction, through_vertices: bool = False):
    contacts = reference_contacts(env, origin, direction)
    ox, oy = map(Fraction, origin)
    dx, dy = map(Fraction, direction)
    for k, (s, edge, t, point, vertex) in enumerate(contacts):
        if vertex is None or not through_vertices:
            return (edge, t, point, s, vertex)
        s_next = contacts[k + 1][0] if k + 1 < len(contacts) else s + 1
        mid = (s + s_next) / 2
        if not in_closed_free_space(env, (ox + mid * dx, oy + mid * dy)):
            return (edge, t, point, s, vertex)
    return None


def leaves_into_free_space(env: Environment, origin, direction) -> bool:
    """Is the origin in the closed free space, and the start of the ray too?"""
    contacts = reference_contacts(env, origin, direction)
    s1 = contacts[0][0] if contacts else Fraction(1)
    q = (origin[0] + s1 / 2 * direction[0], origin[1] + s1 / 2 * direction[1])
    return in_closed_free_space(env, origin) and in_closed_free_space(env, q)


def as_tuple(hit: RayHit):
    return (hit.edge, hit.t, hit.point, hit.s, hit.vertex)


# ------------------------------------------------------------------------------------ strategies
@st.composite
def interior_points(draw, env: Environment):
    """Rational points of the open free space (halves of integers)."""
    x = draw(st.integers(-130, 130))
    y = draw(st.integers(-130, 130))
    p = (Fraction(x, 2), Fraction(y, 2))
    assume(in_open_free_space(env, p))
    return p


@st.composite
def boundary_points(draw, env: Environment):
    """(edge, exact point) with t strictly inside the edge."""
    edge = draw(st.integers(0, env.n_edges - 1))
    t = draw(st.fractions(0, 1, max_denominator=12).filter(lambda f: 0 < f < 1))
    return edge, env.exact_point_at(edge, t)


small_directions = st.tuples(st.integers(-6, 6), st.integers(-6, 6)).filter(lambda d: d != (0, 0))


# ------------------------------------------------------------------------------------ exact caster
@given(env=polygons_with_holes(), data=st.data())
def test_cast_ray_matches_brute_force_from_interior_points(env, data):
    origin = data.draw(interior_points(env))
    direction = data.draw(small_directions)
    assert as_tuple(cast_ray(env, origin, direction)) == reference_first_hit(env, origin, direction)


@given(env=polygons_with_holes(), data=st.data())
def test_cast_ray_matches_brute_force_from_boundary_points(env, data):
    edge, origin = data.draw(boundary_points(env))
    direction = data.draw(small_directions)
    if not leaves_into_free_space(env, origin, direction):
        with pytest.raises(InputError, match=rf"^ray from .* on edge {edge} with direction .* points into the obstacle$"):
            cast_ray(env, origin, direction)
        return
    hit = cast_ray(env, origin, direction)
    assert as_tuple(hit) == reference_first_hit(env, origin, direction)
    assert hit.s > 0 and (hit.edge != edge or hit.vertex is not None)


def ray_origins(env):
    """Exact ray origins in ``env``: an interior point, a point of the boundary, or a vertex."""
    return st.one_of(interior_points(env), boundary_points(env).map(lambda hit: hit[1]),
                     st.integers(0, env.n_edges - 1).map(lambda k: env.exact_vertices[k]))


@given(env=polygons_with_holes(), data=st.data())
def test_cast_ray_reports_a_vertex_it_is_aimed_at_as_a_vertex_hit(env, data):
    """Integer vertices, rational origins: exact ties. A ray through a vertex is never an edge hit."""
    origin = data.draw(ray_origins(env))
    target = data.draw(st.integers(0, env.n_edges - 1))
    v = env.exact_vertices[target]
    direction = (v[0] - origin[0], v[1] - origin[1])
    assume(direction != (0, 0))
    through = data.draw(st.booleans())
    if not leaves_into_free_space(env, origin, direction):
        with pytest.raises(InputError, match=r"^ray from .* points into the obstacle$"):
            cast_ray(env, origin, direction, through_vertices=through)
        return
    hit = cast_ray(env, origin, direction, through_vertices=through)
    assert as_tuple(hit) == reference_first_hit(env, origin, direction, through)
    if hit.vertex is not None:
        assert hit.edge == hit.vertex and hit.t == 0 and hit.point == env.exact_vertices[hit.vertex]
    if not through and hit.s == 1:  # the ray reached its target first: reported as that vertex
        assert hit.vertex == target


def aimed_at_a_vertex(data, env):
    """An interior point of ``env``, a vertex, and the direction from the point to the vertex (exact, drawn)."""
    origin = data.draw(interior_points(env))
    v = env.exact_vertices[data.draw(st.integers(0, env.n_edges - 1))]
    direction = (v[0] - origin[0], v[1] - origin[1])
    assume(direction != (0, 0))
    return origin, v, direction


@given(env=polygons_with_holes(), data=st.data())
def test_cast_ray_through_vertices_matches_the_walk_of_the_reference(env, data):
    origin, v, direction = aimed_at_a_vertex(data, env)
    hit = cast_ray(env, origin, direction, through_vertices=True)
    assert as_tuple(hit) == reference_first_hit(env, origin, direction, through_vertices=True)


@given(env=simple_polygons(), data=st.data())
def test_cast_ray_from_a_vertex_into_its_free_wedge_matches_brute_force(env, data):
    vertex = data.draw(st.integers(0, env.n_edges - 1))
    origin = env.exact_vertices[vertex]
    direction = data.draw(small_directions)
    if not leaves_into_free_space(env, origin, direction):
        with pytest.raises(InputError, match=rf"^ray from vertex {vertex} at .* points into the obstacle$"):
            cast_ray(env, origin, direction)
        return
    assert as_tuple(cast_ray(env, origin, direction)) == reference_first_hit(env, origin, direction)


@given(env=convex_polygons(), data=st.data())
def test_cast_ray_in_a_convex_polygon_never_grazes(env, data):
    """Every vertex of a strictly convex polygon is convex: through_vertices changes nothing."""
    origin, v, direction = aimed_at_a_vertex(data, env)
    plain = cast_ray(env, origin, direction)
    assert plain.point == v and plain.vertex is not None
    assert cast_ray(env, origin, direction, through_vertices=True) == plain


def test_through_vertices_passes_a_reflex_vertex_and_stops_at_a_convex_one():
    # aimed at the reflex corner (4, 4) of the L: stops there, or goes on to the floor
    assert cast_ray(L_ROOM, (2, 7), (2, -3)).vertex == 3
    beyond = cast_ray(L_ROOM, (2, 7), (2, -3), through_vertices=True)
    assert as_tuple(beyond) == (0, Fraction(5, 6), (Fraction(20, 3), Fraction(0)), Fraction(7, 3), None)
    # aimed at the convex corner (8, 0): stops there either way
    for through in (False, True):
        assert cast_ray(L_ROOM, (2, 2), (3, -1), through_vertices=through).vertex == 1


def test_through_vertices_grazes_a_hole_corner_and_hits_the_far_wall():
    # the line y = x − 2 touches the hole [4, 6]² only at its corner (6, 4)
    hit = cast_ray(HOLED, (3, 1), (1, 1))
    assert hit.vertex is not None and hit.point == (6, 4)
    beyond = cast_ray(HOLED, (3, 1), (1, 1), through_vertices=True)
    assert beyond.vertex is None and beyond.point == (12, 10) and beyond.edge == 2


def test_ray_along_an_edge_reports_the_first_vertex_it_reaches():
    # from the middle of edge 0 of the square, along it and against it
    forward = cast_ray(SQUARE, (2, 0), (1, 0))
    assert (forward.vertex, forward.edge, forward.t, forward.s) == (1, 1, 0, 2)
    backward = cast_ray(SQUARE, (2, 0), (-3, 0))
    assert (backward.vertex, backward.s) == (0, Fraction(2, 3))


def test_ray_along_an_edge_goes_past_a_flat_vertex_only_with_through_vertices():
    assert cast_ray(HOLED, (1, 0), (1, 0)).vertex == 1  # the flat vertex (6, 0)
    assert cast_ray(HOLED, (1, 0), (1, 0), through_vertices=True).vertex == 2  # the corner (12, 0)


def test_cast_ray_ignores_the_hit_at_the_origin_on_a_boundary_point():
    hit = cast_ray(SQUARE, (1, 0), (0, 1))
    assert (hit.edge, hit.t, hit.s) == (2, Fraction(3, 4), 4)


def test_cast_ray_takes_floats_at_their_exact_binary_value():
    hit = cast_ray(SQUARE, (0.1, 1.0), (-1.0, 0.0))
    assert hit.s == Fraction(0.1) and hit.s != Fraction(1, 10)
    assert cast_ray(SQUARE, ("0.1", 1), (-1, 0)).s == Fraction(1, 10)


@pytest.mark.parametrize(
    "origin, direction, message",
    [
        ((1, 1), (0, 0), r"^ray direction \(0, 0\) is zero$"),
        ((5, 1), (1, 0), r"^ray origin \(5, 1\) is not in the free space$"),
        ((-1, 2), (1, 0), r"^ray origin \(-1, 2\) is not in the free space$"),
        ((9, 9), (-1, 0), r"^ray origin \(9, 9\) is not in the free space$"),
        ((2, 0), (1, -1), r"^ray from \(2, 0\) on edge 0 with direction \(1, -1\) points into the obstacle$"),
        ((4, 4), (1, 0), r"^ray from vertex 2 at \(4, 4\) with direction \(1, 0\) points into the obstacle$"),
        ("ab", (1, 0), r"^ray origin: expected a pair \[x, y\], got 'ab'$"),
        ((1, "x"), (1, 0), r"^ray origin: 'x' is not a number$"),
        ((1, 1), (float("nan"), 0), r"^ray direction: coordinate is not finite \(nan\)$"),
    ],
)
def test_cast_ray_rejects_bad_input_with_one_clear_line(origin, direction, message):
    with pytest.raises(InputError, match=message):
        cast_ray(SQUARE, origin, direction)


def test_cast_ray_rejects_an_origin_inside_a_hole():
    with pytest.raises(InputError, match=r"^ray origin \(5, 5\) is not in the free space$"):
        cast_ray(HOLED, (5, 5), (1, 2))


# ------------------------------------------------------------------------------------ batch caster
def star_with_holes(n: int = 160, holes: int = 3, seed: int = 7) -> Environment:
    """A star polygon (integer vertices) with a row-by-row grid of small square holes: > 24 edges."""
    rng = np.random.default_rng(seed)
    outer = []
    for k in range(n):
        angle = 2 * math.pi * k / n
        r = 1000 * ((1.0 if k % 2 == 0 else 0.8) + 0.05 * rng.uniform(-1, 1))
        outer.append((round(r * math.cos(angle)), round(r * math.sin(angle))))
    hole_rings = []
    for i in range(holes):
        for j in range(holes):
            x0, y0 = -450 + 300 * i, -450 + 300 * j
            hole_rings.append([(x0, y0), (x0, y0 + 100), (x0 + 100, y0 + 100), (x0 + 100, y0)])
    return Environment.from_coords(outer, hole_rings)


STAR = star_with_holes()


def random_interior_rays(env: Environment, m: int, seed: int):
    """Float origins uniformly in the free space (rejection sampling), random unit directions."""
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, ymax = env.bounds
    shape = env.to_shapely()
    points = np.empty((0, 2))
    while len(points) < m:
        cand = rng.uniform((xmin, ymin), (xmax, ymax), size=(4 * m, 2))
        points = np.concatenate([points, cand[shapely.contains_xy(shape, cand[:, 0], cand[:, 1])]])
    angles = rng.uniform(0, 2 * math.pi, m)
    return points[:m], np.stack([np.cos(angles), np.sin(angles)], axis=1)


def exact_of(origins, directions, k):
    return (
        (Fraction(float(origins[k, 0])), Fraction(float(origins[k, 1]))),
        (Fraction(float(directions[k, 0])), Fraction(float(directions[k, 1]))),
    )


@pytest.mark.parametrize("index", ["grid", "brute-force"])
def test_batch_caster_agrees_with_the_exact_caster_away_from_ties(index):
    origins, directions = random_interior_rays(STAR, 400, seed=1)
    hits = RayCaster(STAR, index=index).cast(origins, directions)
    assert hits.edge.dtype == np.int64 and hits.uncertain.dtype == bool and len(hits) == 400
    for k in range(400):
        exact = cast_ray(STAR, *exact_of(origins, directions, k))
        if hits.uncertain[k]:
            continue
        assert (hits.edge[k], hits.vertex[k]) == (exact.edge, -1) and exact.vertex is None
        assert hits.t[k] == pytest.approx(float(exact.t), abs=1e-9)
        assert (hits.x[k], hits.y[k]) == pytest.approx(tuple(map(float, exact.point)), abs=1e-6)
        assert hits.s[k] == pytest.approx(float(exact.s), rel=1e-9)


def test_grid_index_finds_exactly_what_brute_force_finds():
    origins, directions = random_interior_rays(STAR, 5000, seed=2)
    grid = RayCaster(STAR, index="grid")
    assert grid.grid_shape[0] * grid.grid_shape[1] > 100
    a = grid.cast(origins, directions)
    b = RayCaster(STAR, index="brute-force").cast(origins, directions)
    for name in ("edge", "t", "s", "vertex", "uncertain"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


@settings(max_examples=25, deadline=None)
@given(env=polygons_with_holes(), data=st.data())
def test_dense_arrays_and_threads_find_what_the_grid_and_the_brute_force_find(env, data):
    """"auto" casts polygons of few edges as dense (rays × edges) arrays, and batches of 4,096 rays or more in
    threads: the same answers, array for array, as the grid and the brute force, from the boundary (ends of edges
    and vertices aimed at included) and from inside."""
    from solverplan.geometry import raycast

    assume(env.n_edges <= raycast._DENSE_EDGES)
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    m = 5000
    edges, t = rng.integers(0, env.n_edges, m), rng.random(m)
    t[: m // 5] = rng.choice([0.0, 0.5, 1.0], m // 5)
    headings = np.clip(rng.random(m) * math.pi, 1e-9, math.pi - 1e-9)
    auto = RayCaster(env)
    assert auto.dense
    want = RayCaster(env, index="grid").cast_from_boundary(edges, t, headings)
    for got in (auto.cast_from_boundary(edges, t, headings), RayCaster(env, index="brute-force").cast_from_boundary(edges, t, headings)):
        for name in ("edge", "t", "x", "y", "s", "vertex", "uncertain"):
            np.testing.assert_array_equal(getattr(got, name), getattr(want, name), err_msg=name)
    inside = ~want.uncertain
    origins = (auto.env.points_at(edges, t) + 0.5 * want.s[:, None] * raycast.heading_directions(env, edges, headings))[inside]
    directions = raycast.heading_directions(env, edges, headings)[inside] * 3.0
    a, b = auto.cast(origins, directions), RayCaster(env, index="grid").cast(origins, directions)
    for name in ("edge", "t", "s", "vertex", "uncertain"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


@given(env=polygons_with_holes(), data=st.data())
@example(env=L_ROOM, data=None)
def test_batch_caster_flags_rays_aimed_at_vertices_and_exact_ties_resolves_them(env, data):
    rng = np.random.default_rng(0 if data is None else data.draw(st.integers(0, 2**32 - 1)))
    origins, _ = random_interior_rays(env, 30, seed=int(rng.integers(2**32)))
    origins = np.round(origins * 4) / 4  # quarter-integers: exact in floats
    keep = [k for k in range(30) if in_open_free_space(env, tuple(map(Fraction, origins[k])))]
    assume(keep)
    origins = origins[keep]
    targets = rng.integers(0, env.n_edges, len(origins))
    directions = env.vertices[targets] - origins  # exact in floats: aimed exactly at the vertices
    for index in ("grid", "brute-force"):
        caster = RayCaster(env, index=index)
        floats = caster.cast(origins, directions)
        resolved = caster.cast(origins, directions, exact_ties=True)
        assert not resolved.uncertain.any()
        for k in range(len(origins)):
            exact = cast_ray(env, *exact_of(origins, directions, k))
            if exact.vertex is not None:
                assert floats.uncertain[k], "a ray through a vertex must be uncertain in floats"
            assert (resolved.edge[k], resolved.vertex[k]) == (exact.edge, -1 if exact.vertex is None else exact.vertex)
            if floats.uncertain[k]:
                assert resolved.exact[k] == exact
                assert (resolved.x[k], resolved.y[k], resolved.s[k]) == tuple(map(float, (*exact.point, exact.s)))
            else:
                assert floats.edge[k] == exact.edge and k not in resolved.exact


@given(env=polygons_with_holes(), data=st.data())
def test_cast_exact_gives_what_cast_ray_gives_ray_by_ray(env, data):
    """The batch exact caster (grid candidates) against the scalar one (its own prefilter)."""
    origins, directions = [], []
    for _ in range(data.draw(st.integers(1, 8))):
        origin = data.draw(ray_origins(env))
        if data.draw(st.booleans()):
            v = env.exact_vertices[data.draw(st.integers(0, env.n_edges - 1))]
            direction = (v[0] - origin[0], v[1] - origin[1])
        else:
            direction = data.draw(small_directions)
        origins.append(origin)
        directions.append(direction)
    through = data.draw(st.booleans())
    expected = []
    for origin, direction in zip(origins, directions):
        try:
            expected.append(cast_ray(env, origin, direction, through_vertices=through))
        except InputError:
            expected.append(None)
    for index in ("grid", "brute-force"):
        caster = RayCaster(env, index=index)
        assert caster.cast_exact(origins, directions, through_vertices=through, skip_invalid=True) == expected


def test_cast_exact_shoots_through_every_reflex_vertex_like_algorithm_1():
    """From every reflex vertex r, away from every other vertex v: the first hit beyond r."""
    env = STAR
    origins, directions = [], []
    for r in env.reflex_vertices[::4]:
        for v in range(0, env.n_vertices, 7):
            if v != r:
                (rx, ry), (vx, vy) = env.exact_vertices[r], env.exact_vertices[v]
                origins.append((rx, ry))
                directions.append((rx - vx, ry - vy))
    hits = ray_caster(env).cast_exact(origins, directions, through_vertices=True, skip_invalid=True)
    assert sum(hit is not None for hit in hits) > 100
    for origin, direction, hit in zip(origins, directions, hits):
        try:
            expected = cast_ray(env, origin, direction, through_vertices=True)
        except InputError:
            expected = None
        assert hit == expected


def test_cast_exact_names_the_ray_it_rejects():
    with pytest.raises(InputError, match=r"^ray 1: ray origin \(5, 5\) is not in the free space$"):
        ray_caster(HOLED).cast_exact([(1, 1), (5, 5)], [(1, 0), (1, 0)])
    with pytest.raises(InputError, match=r"^ray origin \(20, 5\) is not in the free space$"):
        ray_caster(HOLED).cast_exact([(20, 5)], [(1, 0)])
    assert ray_caster(HOLED).cast_exact([(20, 5), (1, 1)], [(1, 0), (0, 0)], skip_invalid=True) == [None, None]


def test_batch_through_vertices_resolves_grazing_rays_exactly():
    origins = np.array([[2.0, 7.0], [3.0, 1.0]])
    directions = np.array([[2.0, -3.0], [1.0, 1.0]])
    hits = cast_rays(L_ROOM, origins[:1], directions[:1], through_vertices=True)
    assert hits.edge.tolist() == [0] and hits.vertex.tolist() == [-1] and hits.exact[0].t == Fraction(5, 6)
    hits = cast_rays(HOLED, origins[1:], directions[1:], through_vertices=True)
    assert hits.exact[0].point == (12, 10) and not hits.uncertain.any()


@given(env=polygons_with_holes(), seed=st.integers(0, 2**32 - 1))
def test_cast_from_boundary_never_returns_its_source_edge(env, seed):
    rng = np.random.default_rng(seed)
    m = 200
    edges = rng.integers(0, env.n_edges, m)
    t = rng.uniform(0, 1, m)
    t[:10] = 0.0  # some rays start exactly at vertices
    headings = rng.uniform(1e-6, math.pi - 1e-6, m)
    hits = cast_from_boundary(env, edges, t, headings)
    certain = ~hits.uncertain
    assert (hits.edge[certain] != edges[certain]).all()
    assert (hits.s[certain] > 0).all()
    resolved = cast_from_boundary(env, edges, t, headings, exact_ties=True)
    for k in np.flatnonzero(~resolved.uncertain):
        assert resolved.s[k] > 0
        if resolved.vertex[k] < 0:
            assert resolved.edge[k] != edges[k]


@pytest.mark.parametrize("env", [SQUARE, L_ROOM, HOLED, STAR], ids=["square", "L", "holed", "star"])
def test_cast_from_boundary_agrees_with_the_exact_caster_from_the_exact_boundary_point(env):
    rng = np.random.default_rng(3)
    m = 300
    edges = rng.integers(0, env.n_edges, m)
    t = rng.uniform(0, 1, m)
    headings = rng.uniform(0.01, math.pi - 0.01, m)
    hits = ray_caster(env).cast_from_boundary(edges, t, headings)
    resolved = ray_caster(env).cast_from_boundary(edges, t, headings, exact_ties=True)
    edge_dirs = env.edge_end[edges] - env.edge_start[edges]
    edge_dirs /= np.hypot(edge_dirs[:, 0], edge_dirs[:, 1])[:, None]
    for k in range(m):
        c, s = math.cos(headings[k]), math.sin(headings[k])
        direction = (c * edge_dirs[k, 0] - s * edge_dirs[k, 1], s * edge_dirs[k, 0] + c * edge_dirs[k, 1])
        exact = cast_ray(env, env.exact_point_at(int(edges[k]), Fraction(float(t[k]))), direction)
        assert (resolved.edge[k], resolved.vertex[k]) == (exact.edge, -1 if exact.vertex is None else exact.vertex)
        if not hits.uncertain[k]:
            assert hits.edge[k] == exact.edge
            assert hits.t[k] == pytest.approx(float(exact.t), abs=1e-9)
            assert hits.s[k] == pytest.approx(float(exact.s), rel=1e-9, abs=1e-9)


def test_batch_caster_marks_rays_from_a_boundary_point_without_source_edge_uncertain():
    hits = cast_rays(SQUARE, [[1.0, 0.0]], [[0.0, 1.0]])
    assert hits.uncertain.tolist() == [True] and hits.edge.tolist() == [2]
    hits = cast_rays(SQUARE, [[1.0, 0.0]], [[0.0, 1.0]], source_edges=[0])
    assert hits.uncertain.tolist() == [False] and hits.t.tolist() == [0.75]


def test_batch_caster_returns_arrays_of_the_right_shapes_for_no_rays():
    hits = cast_rays(STAR, np.zeros((0, 2)), np.zeros((0, 2)))
    assert len(hits) == 0 and hits.points.shape == (0, 2)


@pytest.mark.parametrize(
    "origins, directions, message",
    [
        ([[1, 1]], [[0, 0]], r"^directions\[0\] is zero$"),
        ([[1, 1], [2, 2]], [[1, 0]], r"^origins and directions differ in length: 2 and 1$"),
        ([1, 1], [[1, 0]], r"^origins must have shape \(m, 2\), got \(2,\)$"),
        ([[1, 1], [1, np.inf]], [[1, 0], [1, 0]], r"^origins\[1\] is not finite$"),
        ([[1, 1], [9, 9]], [[1, 0], [1, 0]], r"^origins\[1\] = \(9.0, 9.0\) is not in the free space$"),
    ],
)
def test_batch_caster_rejects_bad_input_with_one_clear_line(origins, directions, message):
    with pytest.raises(InputError, match=message):
        cast_rays(SQUARE, origins, directions)


def test_batch_caster_rejects_an_origin_inside_a_hole():
    with pytest.raises(InputError, match=r"^origins\[1\] = \(5.0, 5.0\) is not in the free space$"):
        cast_rays(HOLED, [[1, 1], [5, 5]], [[1, 0.5], [1, 0.5]])


@pytest.mark.parametrize(
    "edges, t, headings, message",
    [
        ([7], [0.5], [1.0], r"^edges\[0\] = 7 is not an edge: edges are e0..e3$"),
        ([0, 1.5], [0.5, 0.5], [1.0, 1.0], r"^edges\[1\] = 1.5 is not an edge: edges are e0..e3$"),
        ([0], [1.5], [1.0], r"^t\[0\] = 1.5 is not in \[0, 1\]$"),
        ([0], [0.5], [0.0], r"^headings\[0\] = 0.0 is not in \(0, π\)$"),
        ([0], [0.5], [4.0], r"^headings\[0\] = 4.0 is not in \(0, π\)$"),
        ([0, 1], [0.5], [1.0], r"^edges, t and headings differ in length: 2, 1 and 1$"),
    ],
)
def test_cast_from_boundary_rejects_bad_input_with_one_clear_line(edges, t, headings, message):
    with pytest.raises(InputError, match=message):
        cast_from_boundary(SQUARE, edges, t, headings)


def test_ray_caster_is_cached_per_environment():
    same = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    assert ray_caster(SQUARE) is ray_caster(same)
    with pytest.raises(InputError, match=r"^index must be 'auto', 'grid' or 'brute-force', got 'kd'$"):
        RayCaster(SQUARE, index="kd")


@pytest.mark.parametrize("function, method", [(cast_rays, RayCaster.cast), (cast_rays_exact, RayCaster.cast_exact),
                                              (cast_from_boundary, RayCaster.cast_from_boundary)])
def test_the_function_forms_take_the_environment_and_the_methods_parameters(function, method):
    params = list(inspect.signature(function).parameters.values())
    assert params[0].name == "env" and params[0].kind is inspect.Parameter.POSITIONAL_ONLY
    assert params[1:] == list(inspect.signature(method).parameters.values())[1:]
    hits = function(SQUARE, [[1, 2]], [[-2, 0]]) if function is not cast_from_boundary else function(SQUARE, [0], [0.5], [1.0])
    assert len(hits) == 1
