"""Issue #22 for the robot models: every model answers the same however the walls are written.

Each model works on the canonical walls of its environment (:class:`solverplan.geometry.walls.StraightWalls`:
collinear vertices merged exactly, each ring from its canonical vertex; the wall-following robot keeps the written
order of its corners), so for random polygons each rewriting of :mod:`solverplan.studies.rewrite` — collinear
vertices anywhere, every edge split at its midpoint, another ring start, the vertex order reversed, motions, a
mirror — must leave what the model answers unchanged:

- rooms (seed 002; rectilinear polygons, so only the rewritings that keep them rectilinear: collinear vertices,
  split edges, translation, ring start, reversal, rotation by 90°): rooms, doors, exact areas and door lengths, Φ
  of every door from each side and Ψ of every pair of rooms (exact);
- wall-following (seed 004): the cut ordering up to renaming the corners (mirror: its counts), the pursuit plan's
  status and length from the same corner (collinear vertices are never refused as a lack of general position);
- exploration (seed 001): Algorithm A's number of views, coverage and path length from the same point;
- reflection fields (seed 003): the convex cells (count, exact areas), their adjacency, and the composed policy's
  cell sequence and reflection zones between the same two points (the gains are per length unit: scaled with the
  room); every rewriting but the mirror, which reverses the order GEOS breaks Delaunay ties among cocircular
  vertices in (a strict xfail shows one).

Points (start, goal, viewpoints) move with the motions. Cost: small polygons, few examples (derandomized ``ci``
profile).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Callable

import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.explore import explore_depth_first
from solverplan.reflection.cells import decompose_free_space
from solverplan.reflection.compose import compose_fields
from solverplan.rectilinear import decompose_rooms, reachability
from solverplan.studies import rewrite as rw
from solverplan.generators import rectilinear_polygon
from solverplan.wallfollow.cut import corner_polygon, cut_ordering
from solverplan.wallfollow.pursuit import pursuit_plan
from tests.strategies import polygons_with_holes, simple_polygons

F = Fraction
Point = tuple[Fraction, Fraction]
Rewriting = Callable[[Environment], tuple[rw.Rewritten, Callable[[Point], Point]]]


def _same(p: Point) -> Point:
    return p


def _vertex_rewritings() -> dict[str, Rewriting]:
    """The rewritings of the vertex list (points stay where they are)."""

    def collinear(env: Environment):
        return rw.insert_vertices(env, [(0, F(1, 3)), (env.n_edges - 1, F(1, 2)), (env.n_edges // 2, F(3, 5))]), _same

    def ring_start(env: Environment):
        r = rw.roll_ring_start(env, 0, len(env.outer) // 2)
        for k in range(1, len(env.rings)):
            r = r.then(rw.roll_ring_start, k, 1)
        return r, _same

    return {
        "collinear_vertices": collinear,
        "edges_split": lambda env: (rw.split_edges(env, 2), _same),
        "ring_start": ring_start,
        "reversed_order": lambda env: (rw.reverse_rings(env), _same),
    }


def _translation(env: Environment):
    return rw.translate(env, F(7, 3), -5), lambda p: (p[0] + F(7, 3), p[1] - 5)


def _quarter_turn(env: Environment):
    return rw.rotate(env, 0, 1), lambda p: (-p[1], p[0])


def _motion(env: Environment):
    c, s = F(20, 29), F(21, 29)
    r = rw.rotate(env, c, s).then(rw.translate, F(7, 3), -5).then(rw.scale, F(1000, 7))
    return r, lambda p: (F(1000, 7) * (c * p[0] - s * p[1] + F(7, 3)), F(1000, 7) * (s * p[0] + c * p[1] - 5))


def _mirror(env: Environment):
    return rw.mirror(env), lambda p: (p[0], -p[1])


RECTILINEAR_REWRITINGS: dict[str, Rewriting] = {**_vertex_rewritings(), "translation": _translation,
                                                "quarter_turn": _quarter_turn}
ALL_REWRITINGS: dict[str, Rewriting] = {**RECTILINEAR_REWRITINGS, "rotation_translation_scale": _motion,
                                        "mirror": _mirror}
SCALE = {"rotation_translation_scale": F(1000, 7)}

FEW = settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.filter_too_much,
                                                                     HealthCheck.too_slow])


# ---------------------------------------------------------------------- rooms (seed 002)
def rooms_summary(env: Environment) -> tuple:
    dec = decompose_rooms(env)
    phi = sorted(tuple(sorted(door.escapability(r) for r in door.rooms)) for door in dec.doors)
    psi = sorted(reachability(dec, i, j).psi for i in range(len(dec.rooms)) for j in range(len(dec.rooms)) if i != j)
    return (len(dec.rooms), len(dec.doors), sorted(room.area for room in dec.rooms),
            sorted(door.length for door in dec.doors), phi, psi)


@pytest.mark.parametrize("name", sorted(RECTILINEAR_REWRITINGS))
@FEW
@given(cells=st.integers(2, 12), size=st.integers(1, 5), seed=st.integers(0, 2**32 - 1))
def test_rooms_invariant(name, cells, size, seed):
    env = rectilinear_polygon(cells, seed=seed, max_size=size)
    r, _ = RECTILINEAR_REWRITINGS[name](env)
    assert rooms_summary(r.env) == rooms_summary(env), r.description


def test_rooms_of_the_l_shape_with_collinear_vertices_and_any_first_vertex():
    """The L's reflex vertex ties between two walls: the same door wins however the ring is written."""
    ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    doors = {frozenset((d.a, d.b)) for d in decompose_rooms(ell).doors}
    for r in (rw.insert_vertices(ell, [(0, F(1, 2)), (5, F(1, 4))]), rw.roll_ring_start(ell, 0, 2), rw.reverse_rings(ell)):
        dec = decompose_rooms(r.env)
        assert {frozenset((d.a, d.b)) for d in dec.doors} == doors
        assert all(r.env.exact_vertices[d.vertex] == d.a for d in dec.doors)  # the user's vertex numbers


# ---------------------------------------------------------------------- wall-following (seed 004)
def _corner_label(env: Environment, point: Point) -> str:
    corners = corner_polygon(env).exact_vertices
    return f"v{corners.index(point)}"


def wallfollow_summary(env: Environment, start: Point, *, mirrored: bool = False) -> tuple:
    order = cut_ordering(env)
    plan = pursuit_plan(env, start=_corner_label(env, start), max_states=20_000)
    shape = (order.n, len(order.labels)) if mirrored else order.canonical().labels
    return shape, plan.status.value, len(plan.actions)


@st.composite
def wall_following_rooms(draw) -> Environment:
    env = draw(simple_polygons(min_vertices=4, max_vertices=9, scale=1000))
    try:
        cut_ordering(env)
    except InvalidEnvironment:
        assume(False)
    return env


@pytest.mark.parametrize("name", sorted(ALL_REWRITINGS))
@FEW
@given(env=wall_following_rooms())
def test_wall_following_invariant(name, env):
    r, move = ALL_REWRITINGS[name](env)
    start = env.exact_vertices[0]
    before = wallfollow_summary(env, start, mirrored=name == "mirror")
    after = wallfollow_summary(r.env, move(start), mirrored=name == "mirror")
    assert after == before, r.description


def test_collinear_consecutive_vertices_are_no_lack_of_general_position():
    """A vertex on a straight wall is passed on an edge: merged, not refused; answers name the corners."""
    room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
    split = rw.insert_vertices(room, [(0, F(1, 3)), (0, F(2, 3)), (4, F(1, 2))]).env
    assert split.n_vertices == 9
    order = cut_ordering(split)
    assert order.labels == cut_ordering(room).labels == ('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3')
    assert order.stats.counts["collinear_vertices_merged"] == 3 and order.environment.matches(split)
    assert pursuit_plan(split).actions == pursuit_plan(room).actions


# ---------------------------------------------------------------------- exploration (seed 001)
@st.composite
def rooms_to_explore(draw) -> tuple[Environment, Point]:
    if draw(st.booleans(), label="holes"):
        env = draw(polygons_with_holes(max_vertices=8, max_holes=1, scale=40))
    else:
        env = draw(simple_polygons(min_vertices=4, max_vertices=9, scale=30))
    cells = decompose_free_space(env).cells
    cell = cells[draw(st.integers(0, len(cells) - 1), label="cell")]
    k = len(cell.vertices)
    centre = (sum((p[0] for p in cell.vertices), F(0)) / k, sum((p[1] for p in cell.vertices), F(0)) / k)
    return env, centre


@pytest.mark.parametrize("name", sorted(ALL_REWRITINGS))
@FEW
@given(query=rooms_to_explore())
def test_exploration_invariant(name, query):
    """Algorithm A from the same point (a cell's vertex average); the mirror turns the rings round, so the ``first``
    window of a view (counter-clockwise) is another: there the ``far`` rule is compared."""
    env, start = query
    r, move = ALL_REWRITINGS[name](env)
    choice = "far" if name == "mirror" else "first"
    a = explore_depth_first(env, start, choice=choice)
    b = explore_depth_first(r.env, move(start), choice=choice)
    scale = float(SCALE.get(name, 1))
    assert (b.status, b.n_views) == (a.status, a.n_views), r.description
    assert b.covered_fraction == pytest.approx(a.covered_fraction, abs=1e-9)
    assert b.path_length == pytest.approx(a.path_length * scale, rel=1e-9)


# ---------------------------------------------------------------------- reflection fields (seed 003)
def _area(vertices) -> Fraction:
    n = len(vertices)
    return sum((vertices[k][0] * vertices[(k + 1) % n][1] - vertices[(k + 1) % n][0] * vertices[k][1]
                for k in range(n)), F(0)) / 2


def fields_summary(env: Environment, start: Point, goal: Point, scale: Fraction) -> tuple:
    """The cells and the composed policy; gains are per length unit (1/length), so a room scaled by s has gains / s."""
    dec = decompose_free_space(env)
    plan = compose_fields(env, start, goal, decomposition=dec, gain_line=F(3) / scale, gain_arc=F(1) / scale)
    return (len(dec.cells), sorted(_area(cell.vertices) / scale**2 for cell in dec.cells), len(dec.adjacency),
            len(plan.sequence), len(plan.zones))


@st.composite
def field_queries(draw) -> tuple[Environment, Point, Point]:
    env, _ = draw(rooms_to_explore())
    cells = decompose_free_space(env).cells
    picks = draw(st.lists(st.integers(0, len(cells) - 1), min_size=2, max_size=2), label="cells")
    points = []
    for c in picks:
        vs = cells[c].vertices
        points.append((sum((p[0] for p in vs), F(0)) / len(vs), sum((p[1] for p in vs), F(0)) / len(vs)))
    return env, points[0], points[1]


# found by this test: a zone verified at gain 3 in the room but not in the room scaled by 1000/7 (gains are 1/length)
SCALED_ZONE = (Environment.from_coords([[10, 0], [18, 18], [0, 10], [-7, 7], [-10, 0], [-14, -14], [0, -10], [8, -8]]),
               (F(6), F(-6)), (F(28, 3), F(28, 3)))


@pytest.mark.parametrize("name", sorted(set(ALL_REWRITINGS) - {"mirror"}))
@FEW
@given(query=field_queries())
@example(query=SCALED_ZONE)
def test_reflection_fields_invariant(name, query):
    env, start, goal = query
    assume(start != goal)
    r, move = ALL_REWRITINGS[name](env)
    before = fields_summary(env, start, goal, F(1))
    after = fields_summary(r.env, move(start), move(goal), SCALE.get(name, F(1)))
    assert after == before, r.description


@pytest.mark.xfail(strict=True, reason="four cocircular vertices ((±10, 0), (0, ±10)) leave the Delaunay triangulation a "
                                       "choice, which GEOS makes by the vertex order; the canonical walls fix the order "
                                       "under motions and rewritings of the vertex list, but a mirror reverses it")
def test_reflection_cells_under_mirror_image_with_cocircular_vertices():
    env, start, goal = SCALED_ZONE
    r, move = ALL_REWRITINGS["mirror"](env)
    assert fields_summary(r.env, move(start), move(goal), F(1)) == fields_summary(env, start, goal, F(1))

