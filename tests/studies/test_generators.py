"""Generators: always valid, reproducible by seed, the sizes asked for, the paper's worst case as described."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest

from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.exact import orient, orient_filter, point_in_ring, segment_intersection
from solverplan.generators import star_polygon, star_polygon_with_holes, worst_case_polygon

ORIGIN = (Fraction(0), Fraction(0))


# ---------------------------------------------------------------------- brute-force exact references
def sees(env: Environment, p, q) -> bool:
    """Exact, brute force: does the open segment pq lie in the interior of the free space?

    For p, q vertices (or interior points): no edge may meet the closed segment pq except at
    p or q themselves (grazing a vertex or running along an edge blocks), and then the whole
    open segment is on one side of the boundary, decided by its midpoint.
    """
    # float filter (exact.orient_filter) drops the edges certainly apart from pq; the rest are decided exactly
    a, b = env.edge_start, env.edge_end
    fp, fq = np.array([float(p[0]), float(p[1])]), np.array([float(q[0]), float(q[1])])
    apart = (orient_filter(fp, fq, a) * orient_filter(fp, fq, b) > 0) | (
        orient_filter(a, b, fp) * orient_filter(a, b, fq) > 0
    )
    for index in np.flatnonzero(~apart):
        edge = env.edge(int(index))
        hit = segment_intersection(p, q, edge.a, edge.b)
        if hit is None:
            continue
        if hit.kind == "overlap" or hit.points[0] not in (p, q):
            return False
    mid = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)
    return point_in_ring(mid, env.outer) > 0 and all(point_in_ring(mid, hole) < 0 for hole in env.holes)


def continues_inside(env: Environment, v, r_index: int) -> bool:
    """Exact: does the ray from v through the reflex vertex r continue into the free space beyond r?

    At a reflex vertex the outside is the convex cone spanned by the directions to its two
    neighbours; the ray continues inside iff its direction r − v is strictly outside that
    closed cone (a direction along an edge is a tie, not counted).
    """
    verts = env.exact_vertices
    r = verts[r_index]
    p, q = verts[int(env.prev_vertex[r_index])], verts[int(env.next_vertex[r_index])]
    u = (p[0] - r[0], p[1] - r[1])
    w = (q[0] - r[0], q[1] - r[1])
    d = (r[0] - v[0], r[1] - v[1])

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    det = cross(u, w)
    assert det != 0, "a reflex vertex has non-collinear edges"
    a, b = cross(d, w) / det, cross(u, d) / det  # d = a·u + b·w
    return not (a >= 0 and b >= 0)


def is_six_decimal(env: Environment) -> bool:
    return all((x * 10**6).denominator == 1 for x, y in env.exact_vertices for x in (x, y))


L_SHAPE = Environment.from_coords([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


def P(x, y):
    return (Fraction(x), Fraction(y))


def test_reference_visibility_blocks_grazing_and_outside_segments():
    assert sees(L_SHAPE, P(0, 0), P(2, 1))
    assert not sees(L_SHAPE, P(2, 0), P(0, 2))  # grazes the reflex vertex (1, 1)
    assert not sees(L_SHAPE, P(2, 1), P(1, 2))  # runs outside, touching the boundary only at its ends
    assert not sees(L_SHAPE, P(0, 0), P(2, 0))  # along an edge


def test_reference_ray_continuation_at_a_reflex_vertex():
    reflex = L_SHAPE.reflex_vertices[0]
    assert L_SHAPE.exact_vertices[reflex] == P(1, 1)
    assert continues_inside(L_SHAPE, P(2, 0), reflex)  # on towards (0, 2)
    assert not continues_inside(L_SHAPE, P(0, 0), reflex)  # out into the missing quadrant
    assert not continues_inside(L_SHAPE, P(0, 1), reflex)  # along the edge to (2, 1): a tie, not counted


# ---------------------------------------------------------------------- star_polygon
SHAPES = [(0.0, 0.0), (0.3, 0.3), (0.4, 0.5), (1.0, 0.0), (1.0, 0.5)]


@pytest.mark.parametrize("n", [3, 4, 5, 8, 20, 60])
@pytest.mark.parametrize("irregularity,spikiness", SHAPES)
def test_star_polygon_is_valid_with_n_vertices_for_many_seeds(n, irregularity, spikiness):
    for seed in range(8):
        env = star_polygon(n, irregularity, spikiness, radius=10, seed=seed)
        assert isinstance(env, Environment)
        assert env.n_vertices == n and env.holes == ()
        assert is_six_decimal(env)
        # a valid Environment re-validates from its own coordinates
        assert Environment.from_coords(env.outer) == env


@pytest.mark.parametrize("n", [3, 4, 6])
def test_star_polygon_is_valid_at_full_spikiness_for_small_n(n):
    # spikiness 1 clips a radius to 0 with probability 0.16: fine for a few vertices, hopeless for many
    for seed in range(8):
        assert star_polygon(n, 0.5, 1.0, seed=seed).n_vertices == n


def test_star_polygon_large_sizes_are_valid():
    for n, spikiness in [(1000, 0.2), (3000, 0.1)]:
        env = star_polygon(n, 0.5, spikiness, seed=1)
        assert env.n_vertices == n


def test_star_polygon_is_reproducible_by_seed():
    a = star_polygon(20, 0.3, 0.3, seed=42)
    assert a == star_polygon(20, 0.3, 0.3, seed=42)
    assert a.name == star_polygon(20, 0.3, 0.3, seed=42).name
    assert a != star_polygon(20, 0.3, 0.3, seed=43)
    assert star_polygon(20, 0.3, 0.3, seed=np.random.default_rng(42)) == a  # a Generator seeded alike


def test_star_polygon_name_records_parameters_and_seed():
    assert star_polygon(6, 0.1, 0.2, radius=2, seed=5).name == (
        "star_polygon(n=6, irregularity=0.1, spikiness=0.2, radius=2, seed=5)"
    )


def test_irregularity_is_scaled_so_angles_increase():
    """With the irregularity scaled by the mean step, the angle steps are positive: the polygon winds
    once around the origin, every edge turning left about it (star-shaped), even at irregularity 1."""
    for seed in range(20):
        env = star_polygon(12, 1.0, 0.2, seed=seed)
        ring = env.outer
        turns = [orient(ORIGIN, ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))]
        assert min(turns) >= 0, f"seed {seed}: an edge turns clockwise about the centre"
        assert not env.reoriented[0]


def test_star_polygon_spikiness_zero_puts_vertices_on_the_circle():
    env = star_polygon(10, 0.5, 0.0, radius=3, seed=0)
    assert np.allclose(np.hypot(*env.vertices.T), 3, atol=1e-6)


def test_star_polygon_irregularity_zero_gives_equal_angle_steps():
    env = star_polygon(9, 0.0, 0.3, seed=0)
    angles = np.unwrap(np.arctan2(env.vertices[:, 1], env.vertices[:, 0]))
    assert np.allclose(np.diff(angles), 2 * math.pi / 9, atol=1e-5)


@pytest.mark.parametrize(
    "kwargs,message",
    [
        (dict(n=2, irregularity=0.3, spikiness=0.3), r"^expected n >= 3, got n=2$"),
        (dict(n=5.0, irregularity=0.3, spikiness=0.3), r"^expected an integer n, got n=5\.0 \(type=float\)$"),
        (dict(n=5, irregularity=1.5, spikiness=0.3), r"^expected irregularity in \[0, 1\], got irregularity=1\.5$"),
        (dict(n=5, irregularity=0.3, spikiness=-0.1), r"^expected spikiness in \[0, 1\], got spikiness=-0\.1$"),
        (dict(n=5, irregularity=0.3, spikiness=0.3, radius=0), r"^expected a finite radius > 0, got radius=0$"),
    ],
)
def test_star_polygon_bad_arguments_are_named(kwargs, message):
    with pytest.raises(InputError, match=message):
        star_polygon(**kwargs, seed=0)


def test_star_polygon_gives_up_with_a_clear_error():
    # n = 1000 at spikiness 1: dozens of radii clip to 0, so every candidate has vertices at the centre
    with pytest.raises(InvalidEnvironment, match=r"^no valid star polygon with n=1000, .* in 3 attempts \(last: "):
        star_polygon(1000, 0.3, 1.0, seed=0, max_attempts=3)


# ---------------------------------------------------------------------- star_polygon_with_holes
@pytest.mark.parametrize(
    "n,n_holes,kind,hole_vertices",
    [(10, 0, "convex", 6), (10, 1, "convex", 4), (20, 5, "convex", 6), (100, 20, "convex", 8),
     (50, 10, "star", 7), (8, 3, "star", 12)],
)
def test_star_polygon_with_holes_is_valid_with_the_sizes_asked(n, n_holes, kind, hole_vertices):
    for seed in range(5):
        env = star_polygon_with_holes(n, n_holes, seed=seed, hole_kind=kind, hole_vertices=hole_vertices)
        assert len(env.outer) == n and len(env.holes) == n_holes
        assert all(len(hole) == hole_vertices for hole in env.holes)
        assert env.n_edges == n + n_holes * hole_vertices
        assert is_six_decimal(env)
        if kind == "convex":  # a convex hole: every corner is reflex for the free space
            hole_vertex_ids = range(len(env.outer), env.n_vertices)
            assert all(env.is_reflex(v) for v in hole_vertex_ids)


def test_star_polygon_with_holes_keeps_holes_strictly_inside_and_apart():
    env = star_polygon_with_holes(40, 12, seed=3)
    outer, holes = env.to_shapely().exterior, [h for h in env.to_shapely().interiors]
    assert min(outer.distance(h) for h in holes) > 0
    assert min(a.distance(b) for a, b in itertools.combinations(holes, 2)) > 0


def test_star_polygon_with_holes_is_reproducible_by_seed():
    a = star_polygon_with_holes(30, 4, seed=9, hole_kind="star")
    assert a == star_polygon_with_holes(30, 4, seed=9, hole_kind="star")
    assert a != star_polygon_with_holes(30, 4, seed=10, hole_kind="star")


def test_star_polygon_with_holes_at_one_thousand_edges():
    env = star_polygon_with_holes(800, 20, hole_vertices=10, seed=0)
    assert env.n_edges == 1000


@pytest.mark.slow
def test_star_polygon_with_holes_at_ten_thousand_edges():
    env = star_polygon_with_holes(9000, 10, hole_vertices=100, seed=0)
    assert env.n_edges == 10_000 and len(env.holes) == 10


def test_star_polygon_with_holes_gives_up_with_a_clear_error():
    with pytest.raises(InvalidEnvironment, match=r"^no valid star polygon with n=8 and n_holes=50 .*could not place 50 holes"):
        star_polygon_with_holes(8, 50, hole_radius=0.3, seed=0, max_attempts=2)


def test_star_polygon_with_holes_bad_hole_kind_is_named():
    with pytest.raises(InputError, match=r"^expected hole_kind 'convex' or 'star', got hole_kind='round'$"):
        star_polygon_with_holes(10, 1, seed=0, hole_kind="round")


# ---------------------------------------------------------------------- worst_case_polygon
@pytest.mark.parametrize("t", range(1, 21))
def test_worst_case_has_4t_plus_2_vertices_and_2t_reflex(t):
    env = worst_case_polygon(t)
    assert env.n_vertices == 4 * t + 2 and env.holes == ()
    assert len(env.reflex_vertices) == 2 * t
    assert env.name == f"worst_case_t{t}"
    assert is_six_decimal(env)


@pytest.mark.parametrize("t", range(1, 21))
def test_worst_case_is_symmetric_about_the_x_axis(t):
    env = worst_case_polygon(t)
    verts = env.exact_vertices
    assert set(verts) == {(x, -y) for x, y in verts}
    # and the mirror image of a reflex vertex is reflex
    reflex = {verts[i] for i in env.reflex_vertices}
    assert reflex == {(x, -y) for x, y in reflex}


@pytest.mark.parametrize("t", range(1, 21))
def test_worst_case_reflex_vertices_lie_uniformly_on_one_circle(t):
    env = worst_case_polygon(t)
    refl = env.vertices[list(env.reflex_vertices)]
    assert np.allclose(np.hypot(*refl.T), 10, atol=1e-5)
    top = np.sort(np.arctan2(refl[:, 1], refl[:, 0])[refl[:, 1] > 0])
    assert len(top) == t
    assert np.allclose(np.diff(top), math.pi / (2 * t), atol=1e-6)
    convex = np.delete(env.vertices, list(env.reflex_vertices), axis=0)
    assert np.all(np.hypot(*convex.T) > 10 + 1)  # convex vertices outside the circle


@pytest.mark.parametrize("t", [1, 2, 3, 4, 5, 8, 13, 20])
def test_worst_case_reflex_vertices_see_each_other(t):
    env = worst_case_polygon(t)
    verts = env.exact_vertices
    for i, j in itertools.combinations(env.reflex_vertices, 2):
        assert sees(env, verts[i], verts[j]), f"t={t}: reflex vertices {i} and {j} do not see each other"


@pytest.mark.parametrize("t", [1, 2, 3, 4, 5, 8, 13, 20])
def test_worst_case_each_reflex_vertex_gets_t_minus_1_new_vertices(t):
    """Paper §4.0.1: the ray from every other top reflex vertex through a top reflex vertex continues
    inside, so Algorithm 1 inserts at least t − 1 new vertices per reflex vertex (bottom half by symmetry)."""
    env = worst_case_polygon(t)
    verts = env.exact_vertices
    for r in env.reflex_vertices:
        same_half = [v for v in env.reflex_vertices if v != r and (verts[v][1] > 0) == (verts[r][1] > 0)]
        assert len(same_half) == t - 1
        assert all(continues_inside(env, verts[v], r) for v in same_half), f"t={t}, reflex vertex {r}"


@pytest.mark.parametrize("t", [1, 2, 3, 4, 6, 10])
def test_worst_case_is_in_general_position(t):
    """No three vertices collinear: in particular no line through an edge passes through another vertex."""
    verts = worst_case_polygon(t).exact_vertices
    for a, b, c in itertools.combinations(verts, 3):
        assert orient(a, b, c) != 0, f"t={t}: {a}, {b}, {c} are collinear"


def test_worst_case_rejects_t_below_one():
    with pytest.raises(InputError, match=r"^expected t >= 1, got t=0$"):
        worst_case_polygon(0)


# ---------------------------------------------------------------------- rooms joined by corridors
from solverplan.generators import generate, rectilinear_floor_plan, rooms_and_corridors  # noqa: E402


@pytest.mark.parametrize("n_rooms, loops", [(1, 0), (2, 0), (5, 0), (4, 1), (8, 2), (16, 4)])
def test_rooms_and_corridors_are_valid_with_one_hole_per_loop(n_rooms, loops):
    for seed in range(6):
        env = rooms_and_corridors(n_rooms, loops=loops, seed=seed)  # validated by Environment.from_coords
        assert len(env.holes) == loops
        assert env.to_shapely().is_valid
        # one convex room per cell: the free space has about n_rooms "blobs" (area well above the corridors')
        rooms_area = n_rooms * math.pi * (0.85 * 2) ** 2 * 0.5
        assert float(env.area) > rooms_area * 0.8


def test_rooms_and_corridors_reproducible_and_named():
    a, b = rooms_and_corridors(6, loops=1, seed=4), rooms_and_corridors(6, loops=1, seed=4)
    assert a == b and a != rooms_and_corridors(6, loops=1, seed=5)
    assert a.name == "rooms_and_corridors(n_rooms=6, loops=1, room_size=4, spacing=10, corridor_width=1, seed=4)"
    assert all((x * 1000).denominator == 1 for p in a.exact_vertices for x in p)  # exact 3-place decimals


@pytest.mark.parametrize(
    "kwargs, message",
    [({"n_rooms": 0}, r"^expected n_rooms >= 1, got n_rooms=0$"),
     ({"n_rooms": 5, "loops": 2}, r"^expected loops <= n_rooms // 2 - 1 = 1 \(a loop needs a ring of rooms\), got loops=2$"),
     ({"n_rooms": 3, "spacing": 5}, r"^expected spacing >= 1\.6 \* room_size = 6\.4, got spacing=5$"),
     ({"n_rooms": 3, "corridor_width": 2}, r"^expected corridor_width < room_size / 3 = 1\.33333, got corridor_width=2$"),
     ({"n_rooms": 3, "room_vertices": (2, 5)}, r"^expected 3 <= lo <= hi in room_vertices, got room_vertices=\(2, 5\)$")],
)
def test_rooms_and_corridors_bad_arguments_are_named(kwargs, message):
    with pytest.raises(InputError, match=message):
        rooms_and_corridors(seed=0, **kwargs)


# ---------------------------------------------------------------------- rectilinear floor plans
@pytest.mark.parametrize("n_rooms, pillars", [(1, 0), (2, 1), (4, 0), (6, 3), (12, 2)])
def test_rectilinear_floor_plans_are_valid_rectilinear_and_integer(n_rooms, pillars):
    for seed in range(6):
        env = rectilinear_floor_plan(n_rooms, pillars=pillars, seed=seed)
        assert len(env.holes) == pillars
        for k in range(env.n_edges):
            e = env.edge(k)
            assert e.a[0] == e.b[0] or e.a[1] == e.b[1], f"edge {k} is not axis-parallel"
            assert all(c.denominator == 1 for c in (*e.a, *e.b))
        width = height = math.ceil(2.5 * 4 * math.sqrt(n_rooms)) + 1
        xs = [p[0] for p in env.outer]
        ys = [p[1] for p in env.outer]
        assert (min(xs), max(xs), min(ys), max(ys)) == (0, width, 0, height)
        # n_rooms − 1 walls, 1 thick, across rooms at least 4 wide, each with one door 2 wide; unit pillars
        assert env.area <= width * height - pillars - 2 * (n_rooms - 1)
        assert (env.area == width * height) == (n_rooms == 1 and pillars == 0)


def test_rectilinear_floor_plan_gives_up_with_a_clear_error():
    with pytest.raises(InvalidEnvironment, match=r"^no rectilinear floor plan with n_rooms=9 in a 9 x 9 building in 3 attempts "
                                                 r"\(last: a 9 x 9 building holds only \d rooms of width >= 4\)"):
        rectilinear_floor_plan(9, width=9, height=9, seed=0, max_attempts=3)
    with pytest.raises(InputError, match=r"^expected min_room >= 4, got min_room=3$"):
        rectilinear_floor_plan(3, seed=0, min_room=3)


def test_generate_dispatches_by_name():
    assert generate("rectilinear", n_rooms=3, seed=2) == rectilinear_floor_plan(3, seed=2)
    assert generate("holes", n=10, n_holes=1, seed=2) == star_polygon_with_holes(10, 1, seed=2)
    with pytest.raises(InputError, match=r"^generator 'star': got an unexpected keyword argument 'rooms'$"):
        generate("star", n=10, irregularity=0.1, spikiness=0.1, rooms=3, seed=0)
