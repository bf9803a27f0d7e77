"""Degenerate geometry: exact partitions, graphs and plans where floats would tie, and invariance.

Families of small exact instances — collinear runs of vertices, parallel facing walls, rays through
vertices, inserted points on vertices, reflex vertices sharing a supporting line, aligned pillars,
vertices 1e-9 apart, coordinates of 1e12 — each checked against answers computed independently here:

- P′ (inserted points with their sources, and the segments) and the BVG's arcs against
  :mod:`tests.exact_reference`, a brute force in Fractions written from the definitions;
- every exact end of every safe interval: safe at the end, safe inside, unsafe just outside
  (:func:`tests.exact_reference.heading_is_safe`), and safe sets complete at sampled exact headings;
- plans against the enumeration of :mod:`tests.plan.brute` and against values derived by hand;
- scaling by 10^k (k = −9 … 12), translation and integer/decimal spellings leave every angle answer
  unchanged; the ``solverplan`` command answers these inputs or refuses them in one line.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.bounce.bvg import SafeBVG, safe_bounce_visibility_graph
from solverplan.bounce.cycles import limit_cycle
from solverplan.bounce.partitions import Partition, partition
from solverplan.environment import Environment
from solverplan.exact import to_fraction
from solverplan.plan import find_plan
from tests.exact_reference import (Rings, frame_direction, heading_is_safe, reference_arcs, reference_partition,
                                   reference_segments, rotate)
from solverplan.plan._walls import PartitionedWalls
from tests.plan.brute import EPS, admissible, enumerate_plans, start_elements, start_segments

F = Fraction
TINY = F(1, 10**9)
runner = CliRunner()


@dataclass(frozen=True)
class Case:
    """One instance: rings as written (outer counter-clockwise, holes clockwise, so edge ids are as listed)
    and a plan query (start and goal boundary sets) for the brute-force comparison."""

    outer: list
    holes: list
    start: str
    goal: str

    def env(self, scale: Fraction = F(1), offset: tuple = (0, 0)) -> Environment:
        def move(ring):
            return [[F(x) * scale + offset[0], F(y) * scale + offset[1]] for x, y in ring]

        env = Environment.from_coords(move(self.outer), [move(h) for h in self.holes])
        assert not any(env.reoriented)  # written normalised: the edge ids of the queries hold
        return env


L_OUTER = [[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]]

CASES = {
    # collinear runs: flat vertices along walls, on the reflex vertex's lines too
    "collinear_floor": Case([[0, 0], [1, 0], [2, 0], [3, 0], [4, 0], [4, 4], [0, 4]], [], "e0,e1", "e5"),
    "collinear_l": Case([[0, 0], [5, 0], [10, 0], [10, 4], [7, 4], [4, 4], [4, 10], [0, 10], [0, 7]], [],
                        "e0:1/2:1", "e6"),
    # parallel facing walls of equal span: a single safe heading, π/2
    "corridor": Case([[0, 0], [6, 0], [6, 2], [0, 2]], [], "e3", "e1"),
    "parallel_hole": Case([[0, 0], [8, 0], [8, 4], [0, 4]], [[[2, 1], [2, 3], [6, 3], [6, 1]]], "e0", "e2"),
    # the L's two edge extensions graze a hole's vertex and go on
    "rays_through_vertices": Case(L_OUTER, [[[2, 4], [1, 6], [3, 6]], [[4, 2], [6, 3], [6, 1]]], "e0:0:1/2", "e4"),
    # the L's extension lands on a flat vertex / on a convex corner / two extensions meet at one point
    "inserted_on_vertex": Case([*L_OUTER, [0, 4]], [], "e0", "e3"),
    "ray_into_corner": Case([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [1, 10], [0, 4]], [], "e0", "e4"),
    "merged_rays": Case([[0, 0], [10, 0], [10, 10], [9, 10], [9, 8], [7, 4], [3, 4], [1, 8], [1, 10], [0, 10]], [],
                        "e0:0:1/2", "e2"),
    # four reflex vertices on the line y = 4 (two teeth hanging from the ceiling)
    "shared_support": Case([[0, 0], [12, 0], [12, 8], [10, 8], [10, 4], [8, 4], [8, 8], [4, 8], [4, 4], [2, 4],
                            [2, 8], [0, 8]], [], "e0:0:1/6", "e6"),
    # two square pillars on one row: their sides share supporting lines
    "aligned_pillars": Case([[0, 0], [7, 0], [7, 3], [0, 3]],
                            [[[2, 1], [2, 2], [3, 2], [3, 1]], [[4, 1], [4, 2], [5, 2], [5, 1]]], "e3", "e1"),
    # a slit 1e-9 wide in the floor
    "slit": Case([[0, 0], [2, 0], [2, -1], [2 + TINY, -1], [2 + TINY, 0], [4, 0], [4, 4], [0, 4]], [],
                 "e0", "e6"),
}
# the brute-force BVG costs seconds on the largest ones: those run in the slow suite
BIG = {"rays_through_vertices", "aligned_pillars"}


def slow_if_big(names):
    return [pytest.param(n, marks=pytest.mark.slow) if n in BIG else n for n in names]


_BUILT: dict = {}


def built(name: str) -> tuple[Environment, Partition, SafeBVG]:
    """The environment, P′ and safe BVG of a case (cached: every test reads them, none changes them)."""
    if name not in _BUILT:
        env = CASES[name].env()
        p = partition(env)
        _BUILT[name] = env, p, safe_bounce_visibility_graph(p)
    return _BUILT[name]


def arcs_of(graph: SafeBVG) -> set[tuple[int, int]]:
    return set(zip(graph.source.tolist(), graph.target.tolist()))


def vertex_id(env: Environment, xy) -> int:
    return env.exact_vertices.index((F(xy[0]), F(xy[1])))


# ---------------------------------------------------------------------------------------------
# P′: inserted points, their sources and the segments, exactly
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(CASES))
def test_partition_equals_the_brute_force(name):
    env, p, _ = built(name)
    expected = reference_partition(env.rings)
    got = {(q.edge, q.t): (q.point, frozenset(q.sources)) for q in p.inserted}
    assert got == expected
    for q in p.inserted:
        assert q.sources[0] == (q.reflex_vertex, q.from_vertex)
    assert [(s.edge, s.t0, s.t1, s.a, s.b) for s in p.segments] == reference_segments(env.rings, expected)
    # the JSON answer reads back to the same exact points
    doc = p.to_json()
    assert [(to_fraction(q["t"]), tuple(map(to_fraction, q["point"]))) for q in doc["inserted"]] == [
        (q.t, q.point) for q in p.inserted
    ]


def test_collinear_runs_are_vertices_like_any_other():
    """A flat vertex is a partition point and nothing else: no rays from it (it is not reflex), and the
    floor's four collinear edges get no inserted points in a convex room."""
    env, p, _ = built("collinear_floor")
    assert env.reflex_vertices == () and p.inserted == ()
    assert [(s.edge, s.t0, s.t1) for s in p.segments] == [(e, 0, 1) for e in range(7)]


def test_rays_through_vertices_graze_and_go_on():
    """The extension of (10, 4) → (4, 4) grazes the hole vertex (2, 4) and lands on the left wall at (0, 4);
    the extension of (4, 10) → (4, 4) grazes (4, 2) and lands on the floor at (4, 0)."""
    env, p, _ = built("rays_through_vertices")
    r = vertex_id(env, (4, 4))
    at = {q.point: q for q in p.inserted}
    assert (r, None) in at[(4, 0)].sources and (at[(4, 0)].edge, at[(4, 0)].t) == (0, F(2, 5))
    assert (r, None) in at[(0, 4)].sources and (at[(0, 4)].edge, at[(0, 4)].t) == (5, F(3, 5))
    # the grazed vertices are partition points already: never inserted again
    assert {(2, 4), (4, 2)}.isdisjoint(at)


def test_a_ray_landing_on_a_vertex_inserts_nothing():
    """The extension of (10, 4) → (4, 4) runs along y = 4 into (0, 4): a flat vertex of the left wall in one
    case, a convex corner in the other. (0, 4) stays one partition point, and nothing is inserted there."""
    for name in ("inserted_on_vertex", "ray_into_corner"):
        env, p, _ = built(name)
        corner = (F(0), F(4))
        assert [pt for ring in p.vertices() for pt in ring].count(corner) == 1
        assert corner not in {q.point for q in p.inserted}
        assert all(q.point not in env.exact_vertices for q in p.inserted)
        assert (F(4), F(0)) in {q.point for q in p.inserted}  # the other extension still cuts the floor


def test_two_extensions_meeting_at_one_point_are_one_inserted_point():
    env, p, _ = built("merged_rays")
    (mid,) = [q for q in p.inserted if q.point == (5, 0)]
    assert (mid.edge, mid.t) == (0, F(1, 2))
    assert {(vertex_id(env, (7, 4)), None), (vertex_id(env, (3, 4)), None)} <= set(mid.sources)
    assert sum(s.edge == 0 and s.t0 == F(1, 2) for s in p.segments) == 1


def test_reflex_vertices_on_one_supporting_line():
    """Four reflex vertices on y = 4: the horizontal line runs along both teeth's bottoms and lands once on
    each side wall, with every reflex vertex of the line among its sources; the vertical extensions cut the
    floor at x = 2, 4, 8, 10."""
    env, p, _ = built("shared_support")
    reflex = [vertex_id(env, xy) for xy in [(10, 4), (8, 4), (4, 4), (2, 4)]]
    assert sorted(env.reflex_vertices) == sorted(reflex)
    at = {q.point: q for q in p.inserted}
    assert {t for e, t in ((q.edge, q.t) for q in p.inserted) if e == 0} >= {F(1, 6), F(1, 3), F(2, 3), F(5, 6)}
    left, right = at[(0, 4)], at[(12, 4)]
    assert (left.edge, left.t, right.edge, right.t) == (11, F(1, 2), 1, F(1, 2))
    assert {r for r, _ in left.sources} >= {vertex_id(env, (2, 4))}
    assert {r for r, _ in right.sources} >= {vertex_id(env, (10, 4))}


def test_vertices_a_billionth_apart_are_kept_apart_exactly():
    """The slit's walls x = 2 and x = 2 + δ (δ = 1e-9) extend to the ceiling at x = 2 and 2 + δ; the lines
    from each bottom corner through the opposite top corner reach it at 2 − 4δ and 2 + 5δ (slope 1/δ):
    four distinct inserted points within 1e-8 of each other, exact."""
    env, p, _ = built("slit")
    assert p.segments[p.segment_at(2, F(1, 2))].b[0] - p.segments[p.segment_at(2, F(1, 2))].a[0] == TINY
    ceiling = {q.point[0]: q for q in p.inserted if q.edge == 6}
    assert sorted(ceiling) == [2 - 4 * TINY, F(2), 2 + TINY, 2 + 5 * TINY]
    assert ceiling[2 - 4 * TINY].sources == ((vertex_id(env, (2, 0)), vertex_id(env, (2 + TINY, -1))),)
    assert ceiling[F(2)].sources == ((vertex_id(env, (2, 0)), None),)


# ---------------------------------------------------------------------------------------------
# the BVG: arcs, and the exact ends of every safe interval
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", slow_if_big(sorted(CASES)))
def test_graph_arcs_equal_the_brute_force(name):
    env, p, g = built(name)
    assert arcs_of(g) == reference_arcs(env.rings, [(s.a, s.b) for s in p.segments])
    # never between two segments on one line (a collinear run, or the two sides of a reflex vertex's cut)
    for i, j in arcs_of(g):
        a, b = p.segments[i], p.segments[j]
        along = (a.b[0] - a.a[0], a.b[1] - a.a[1])
        sides = [along[0] * (q[1] - a.a[1]) - along[1] * (q[0] - a.a[0]) for q in (b.a, b.b)]
        assert sides != [0, 0], (i, j)


OUT = F(1, 10**6)  # how far outside an end the heading must already be unsafe (radians, about)


def check_safe_ends(env: Environment, p: Partition, g: SafeBVG) -> int:
    """Every exact end is safe, a heading between the ends is safe, one just outside is not. Returns the
    number of intervals checked."""
    walls = Rings(env.rings)
    checked = 0
    for k in range(g.n_arcs):
        i, j = int(g.source[k]), int(g.target[k])
        si, sj = p.segments[i], p.segments[j]
        src, dst = (si.a, si.b), (sj.a, sj.b)
        e = (si.b[0] - si.a[0], si.b[1] - si.a[1])
        for piece in g.safe_set(i, j).intervals:
            checked += 1
            open_lo, open_hi = piece.lo == 0.0, piece.hi == math.pi  # Cor. 1: open at the wall
            lo, hi = piece.lo_direction, piece.hi_direction  # ±e at an open end
            nl, nh = abs(lo[0]) + abs(lo[1]), abs(hi[0]) + abs(hi[1])
            mid = (lo[0] / nl + hi[0] / nh, lo[1] / nl + hi[1] / nh)  # strictly between the ends
            where = (i, j, piece.interval)
            assert heading_is_safe(walls, src, dst, mid), where
            assert open_lo or heading_is_safe(walls, src, dst, lo), where
            assert open_hi or heading_is_safe(walls, src, dst, hi), where
            if not open_lo:
                assert not heading_is_safe(walls, src, dst, rotate(lo, OUT, clockwise=True)), where
            if not open_hi:
                assert not heading_is_safe(walls, src, dst, rotate(hi, OUT, clockwise=False)), where
    return checked


def float_end_errors(p: Partition, g: SafeBVG) -> list[tuple[int, int, float]]:
    """(source, target, error) of every float end farther than 1e-12 rad from its exact direction's angle."""
    out = []
    for i, j in sorted(arcs_of(g)):
        si = p.segments[i]
        e = (si.b[0] - si.a[0], si.b[1] - si.a[1])
        for piece in g.safe_set(i, j).intervals:
            for angle, d in [(piece.lo, piece.lo_direction), (piece.hi, piece.hi_direction)]:
                exact = math.atan2(float(e[0] * d[1] - e[1] * d[0]), float(e[0] * d[0] + e[1] * d[1]))
                if abs(angle - exact) > 1e-12:
                    out.append((i, j, abs(angle - exact)))
    return out


@pytest.mark.parametrize("name", slow_if_big(sorted(CASES)))
def test_safe_interval_ends_are_exact(name):
    assert check_safe_ends(*built(name)) > 0


@pytest.mark.parametrize("name", sorted(CASES))
def test_float_safe_ends_are_the_angles_of_the_exact_directions(name):
    _, p, g = built(name)
    assert float_end_errors(p, g) == []


# headings 2·atan(t): exact rational directions spread over (0, π)
SAMPLES = [F(1, 16), F(1, 5), F(1, 3), F(1, 2), F(3, 4), F(1), F(4, 3), F(2), F(3), F(5), F(16)]


@pytest.mark.parametrize("name", ["collinear_floor", "corridor", "inserted_on_vertex", "slit",
                                  pytest.param("collinear_l", marks=pytest.mark.slow),
                                  pytest.param("merged_rays", marks=pytest.mark.slow)])
def test_safe_sets_hold_exactly_the_safe_sampled_headings(name):
    """No safe heading is missing from the safe sets, and none listed is unsafe (at exact sampled headings)."""
    env, p, g = built(name)
    walls = Rings(env.rings)
    for k in range(g.n_arcs):
        i, j = int(g.source[k]), int(g.target[k])
        si, sj = p.segments[i], p.segments[j]
        pieces = g.safe_set(i, j).intervals
        for t in SAMPLES:
            theta = 2 * math.atan(float(t))
            if any(abs(theta - end) < 1e-9 for piece in pieces for end in (piece.lo, piece.hi)):
                continue
            listed = any(piece.lo <= theta <= piece.hi for piece in pieces)
            assert heading_is_safe(walls, (si.a, si.b), (sj.a, sj.b), frame_direction((si.a, si.b), t)) == listed, \
                (i, j, theta)


def test_parallel_facing_walls_of_equal_span_have_one_safe_heading():
    """Left wall to right wall of a 6 × 2 corridor: only straight across, [π/2, π/2], with the exact
    direction (1, 0) at both ends; bottom to top likewise; bottom to the right wall is Cor. 1's (0, atan(1/3)]."""
    env, p, g = built("corridor")
    for i, j, across in [(3, 1, (1, 0)), (0, 2, (0, 1)), (1, 3, (-1, 0))]:
        (piece,) = g.safe_set(i, j).intervals
        assert piece.lo == piece.hi == math.pi / 2
        for d in (piece.lo_direction, piece.hi_direction):
            assert d[0] * across[1] - d[1] * across[0] == 0 and d[0] * across[0] + d[1] * across[1] > 0
    (corner,) = g.safe_set(0, 1).intervals
    assert corner.lo == 0.0 and corner.hi == pytest.approx(math.atan(1 / 3), abs=1e-15)
    assert corner.hi_direction[0] * 2 - corner.hi_direction[1] * 6 == 0


def test_a_single_safe_heading_gives_no_plan_and_a_proof():
    """With the margins no interval of positive width fits a single heading: one bounce is impossible across
    the corridor's equal walls, and the planner proves it and goes round in three (down, up, across)."""
    env, _, g = built("corridor")
    one = find_plan(env, "e3", "e1", objective="fewest", max_bounces=1, graph=g)
    assert not one.found and one.optimality.proved
    best = find_plan(env, "e3", "e1", objective="fewest", graph=g)
    start, parts = start_elements(g, [(3, F(0), F(1))])
    brute = enumerate_plans(admissible(g, pieces=parts), start, {1}, 3)
    assert best.found and best.bounces == brute.fewest()


# ---------------------------------------------------------------------------------------------
# plans: the optimum of brute force, and values derived by hand
# ---------------------------------------------------------------------------------------------
def _pieces(env: Environment, spec: str):
    return [(piece.edge, piece.t0, piece.t1) for piece in env.boundary_set(spec).pieces]


@pytest.mark.parametrize("name", slow_if_big(sorted(CASES)))
def test_plans_equal_the_brute_force(name):
    """Brute force on the straight walls (collinear vertices merged, the sets mapped onto them: what the planners
    search) against the planners on the environment as written."""
    env, p, g = built(name)
    case = CASES[name]
    walls = PartitionedWalls(env)
    g = safe_bounce_visibility_graph(walls.merged)

    def merged(spec: str):
        return [(q.edge, q.t0, q.t1) for q in walls.to_merged(env.boundary_set(spec)).pieces]

    start, parts = start_elements(g, merged(case.start))
    goal = set(start_segments(g, merged(case.goal)))
    K = 3
    brute = enumerate_plans(admissible(g, pieces=parts), start, goal, K)
    fewest = find_plan(env, case.start, case.goal, objective="fewest")
    if brute.fewest() is None:
        assert not fewest.found or fewest.bounces > K
    else:
        assert fewest.found and fewest.optimality.proved and fewest.bounces == brute.fewest()
        assert abs(fewest.min_width - brute.best_min_width(brute.fewest())) <= EPS
    tolerance = find_plan(env, case.start, case.goal, objective="tolerance", max_bounces=K)
    front = brute.front(K)
    if front:
        assert (tolerance.bounces, tolerance.min_width) == (front[-1][0], pytest.approx(front[-1][1], abs=EPS))
    else:
        assert not tolerance.found and tolerance.optimality.proved


def test_half_floor_to_ceiling_of_a_square_by_hand():
    """A square whose floor has a flat vertex at its middle: from the left half e0 to the ceiling e3 in one
    bounce. Prop. 2's interval is [ang(c − b), ang(d − a)] = [atan 2, π/2], width atan(1/2) (exact ends
    (2, 4) and (0, 4)); the plan is that interval pulled in by the margins (the corner clearance, 1e-4 of
    the diagonal, at both ends: neither corner is shared with the source)."""
    env = Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])
    g = safe_bounce_visibility_graph(env)
    (piece,) = g.safe_set(0, 3).intervals
    assert (piece.lo, piece.hi) == (pytest.approx(math.atan(2), abs=1e-15), math.pi / 2)
    assert piece.lo_direction[0] * 4 == piece.lo_direction[1] * 2 and piece.hi_direction[0] == 0
    plan = find_plan(env, "e0", "e3", objective="tolerance", max_bounces=1, graph=g)
    (stage,) = plan.stages
    assert plan.bounces == 1 and plan.optimality.proved and stage.to_segments == (3,)
    assert math.atan(2) < stage.interval.lo < math.atan(2) + 1e-3
    assert math.pi / 2 - 1e-3 < stage.interval.hi < math.pi / 2
    assert math.atan(0.5) - 2e-3 < plan.min_width < math.atan(0.5)


# ---------------------------------------------------------------------------------------------
# collinear runs: what must already hold, and what the collinear branch fixes
# ---------------------------------------------------------------------------------------------
def midpoint_split(ring):
    out = []
    for k, a in enumerate(ring):
        b = ring[(k + 1) % len(ring)]
        out += [a, [F(a[0] + b[0], 2), F(a[1] + b[1], 2)]]
    return out


def test_midpoint_split_polygon_partition_and_graph_are_exact_and_sound():
    """Splitting every edge of the L at its midpoint: P′ and the arcs are those of the brute force, every
    plan found there still holds exactly (certificate), and the inserted points of the L are still cut."""
    from solverplan.certify.build import certificate
    from solverplan.certify.check import check_certificate

    env = Environment.from_coords(midpoint_split(L_OUTER))
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    expected = reference_partition(env.rings)
    assert {(q.edge, q.t): (q.point, frozenset(q.sources)) for q in p.inserted} == expected
    assert {(4, 0), (0, 4)} <= {pt for ring in p.vertices() for pt in ring}
    assert arcs_of(g) == reference_arcs(env.rings, [(s.a, s.b) for s in p.segments])
    plan = find_plan(env, "e0,e1", "e6,e7", objective="fewest", graph=g)
    assert plan.found and check_certificate(certificate(plan, env=env)).valid


@pytest.mark.parametrize("objective", ["fewest", "tolerance"])
def test_collinear_runs_never_change_plan_answers(objective):
    """The L and the L with every edge split at its midpoint are the same free space: the same optimum
    (fewest from the floor to the left wall: 2 bounces on the L, 3 found on the split one)."""
    plain, split = Environment.from_coords(L_OUTER), Environment.from_coords(midpoint_split(L_OUTER))
    budget = None if objective == "fewest" else 4
    for s, t in [(0, 3), (0, 4)]:
        a = find_plan(plain, f"e{s}", f"e{t}", objective=objective, max_bounces=budget)
        b = find_plan(split, f"e{2 * s},e{2 * s + 1}", f"e{2 * t},e{2 * t + 1}", objective=objective,
                      max_bounces=budget)
        assert (b.bounces, b.min_width) == (a.bounces, pytest.approx(a.min_width, rel=1e-9))


# ---------------------------------------------------------------------------------------------
# invariance: scale, translation, integer and decimal spellings
# ---------------------------------------------------------------------------------------------
INVARIANT = Case(L_OUTER, [[[2, 4], [1, 6], [3, 6]]], "e0:0:1/2", "e4")


def angle_answers(env: Environment) -> dict:
    """Every angle answer of an environment: P′'s parameters, the arcs with their float and exact safe ends,
    φ, two plans (tolerance within 3 bounces, fewest) and a limit cycle's exact contraction."""
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    tol = find_plan(env, INVARIANT.start, INVARIANT.goal, objective="tolerance", max_bounces=3, graph=g)
    few = find_plan(env, "e0", "e3", objective="fewest", graph=g)
    cycle = limit_cycle(env, "tan:1/3")

    def unit(d):  # exact directions up to positive scale
        m = max(abs(d[0]), abs(d[1]))
        return (d[0] / m, d[1] / m)

    ends = [tuple(unit(d) for piece in g.safe_set(i, j).intervals for d in (piece.lo_direction, piece.hi_direction))
            for i, j in zip(g.source.tolist(), g.target.tolist())]
    return {
        "exact": ([(q.edge, q.t, q.sources) for q in p.inserted], [(s.edge, s.t0, s.t1) for s in p.segments],
                  sorted(arcs_of(g)), ends, g.transition.tolist(), tol.bounces, few.bounces,
                  [s.to_segments for s in tol.stages + few.stages],
                  (cycle.status, cycle.edges, cycle.contraction_exact)),
        "float": np.concatenate([g.set_lo, g.set_hi, g.phi, [tol.min_width, few.min_width],
                                 [x for s in tol.stages + few.stages for x in (s.interval.lo, s.interval.hi)]]),
    }


def assert_same_angles(got: dict, want: dict, rel: float = 1e-12) -> None:
    assert got["exact"] == want["exact"]
    assert got["float"].shape == want["float"].shape
    np.testing.assert_allclose(got["float"], want["float"], rtol=rel, atol=0)


@pytest.fixture(scope="module")
def base_answers() -> dict:
    return angle_answers(INVARIANT.env())


@pytest.mark.parametrize("k", range(-9, 13))
def test_scaling_by_powers_of_ten_keeps_every_angle_answer(k, base_answers):
    assert_same_angles(angle_answers(INVARIANT.env(scale=F(10) ** k)), base_answers)


@pytest.mark.parametrize("k, offset", [(0, (10**6, -(10**6))), (3, (-(10**12), 10**12)), (12, (10**12, 10**12)),
                                       (-9, (F(7, 3), -5))])
def test_translation_keeps_the_exact_answers(k, offset, base_answers):
    moved = angle_answers(INVARIANT.env(scale=F(10) ** k, offset=offset))
    assert moved["exact"] == base_answers["exact"]


def test_translation_keeps_the_exact_safe_directions():
    """An L whose points of P′ are all integers, moved by 1e12 (still exact floats): the same arcs and the same
    exact end directions of every safe interval."""
    env = Environment.from_coords(L_OUTER)
    far = Environment.from_coords([[x + 10**12, y - 10**12] for x, y in L_OUTER])
    a, b = safe_bounce_visibility_graph(env), safe_bounce_visibility_graph(far)
    assert arcs_of(a) == arcs_of(b)
    for i, j in arcs_of(a):
        ends = [[(piece.lo_direction, piece.hi_direction) for piece in g.safe_set(i, j).intervals] for g in (a, b)]
        assert ends[0] == ends[1]


def test_translated_float_ends_are_the_angles_of_the_exact_directions():
    far = Environment.from_coords([[x + 10**12, y - 10**12] for x, y in L_OUTER])
    p = partition(far)
    assert float_end_errors(p, safe_bounce_visibility_graph(p)) == []


def test_translation_keeps_the_float_angles(base_answers):
    assert_same_angles(angle_answers(INVARIANT.env(offset=(10**12, -(10**12)))), base_answers)


def test_translation_never_changes_the_arcs():
    env = INVARIANT.env(scale=F(1, 10**4), offset=(10**12, -(10**12)))
    assert arcs_of(safe_bounce_visibility_graph(env)) == arcs_of(safe_bounce_visibility_graph(INVARIANT.env()))


def _write_env(folder: Path, name: str, outer, holes) -> Path:
    path = folder / f"{name}.json"
    path.write_text(f'{{"name": "{name}", "outer": {outer}, "holes": {holes}}}', encoding="utf-8")
    return path


def _ring_text(ring, spell) -> str:
    return "[" + ", ".join(f"[{spell(x)}, {spell(y)}]" for x, y in ring) + "]"


def run(*args):
    result = runner.invoke(cli.app, [str(a) for a in args])
    assert "Traceback" not in result.stderr
    return result


def answer(*args) -> dict:
    result = run(*args)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


COORDINATE_FIELDS = {"a", "b", "point", "vertices", "bounds", "area", "area_exact", "perimeter", "length",
                     "corner_clearance", "sha256", "name", "stats", "seconds", "reoriented", "notes",
                     "size", "scope"}  # a plan's scope quotes the corner clearance, a length; size is one


def without(doc, fields=COORDINATE_FIELDS):
    if isinstance(doc, dict):
        return {k: without(v, fields) for k, v in doc.items() if k not in fields}
    if isinstance(doc, list):
        return [without(v, fields) for v in doc]
    return doc


def assert_same_json(got, want, path="") -> None:
    """Equal structure and exact values; floats within 1e-12 relative (1e-15 absolute near 0)."""
    if isinstance(want, float) and isinstance(got, (int, float)):
        assert got == pytest.approx(want, rel=1e-12, abs=1e-15), path
    elif isinstance(want, dict):
        assert isinstance(got, dict) and got.keys() == want.keys(), path
        for k in want:
            assert_same_json(got[k], want[k], f"{path}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), path
        for k, (x, y) in enumerate(zip(got, want)):
            assert_same_json(x, y, f"{path}[{k}]")
    else:
        assert got == want, path


COMMANDS = [("info",), ("partition",), ("graph", "--safe"),
            ("plan", "--from", INVARIANT.start, "--to", INVARIANT.goal, "--objective", "tolerance",
             "--max-bounces", "3")]


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
def test_integer_and_decimal_spellings_give_the_same_answers(command, tmp_path):
    """The same polygon written with integers, with decimals ("10.0"), and divided by 10 as decimals
    ("1.0", "0.4"): the same JSON answers; divided by 10, the same apart from coordinates and lengths."""
    rings = [INVARIANT.outer, *INVARIANT.holes]
    spellings = {
        "ints": str,
        "decimals": lambda x: f"{x}.0",
        "tenths": lambda x: str(Decimal(x) / 10),
    }
    docs = {}
    for label, spell in spellings.items():
        holes = "[" + ", ".join(_ring_text(h, spell) for h in rings[1:]) + "]"
        path = _write_env(tmp_path, label, _ring_text(rings[0], spell), holes)
        docs[label] = answer(command[0], path, *command[1:])
    same_value = {"stats", "seconds", "name"}
    assert without(docs["ints"], same_value) == without(docs["decimals"], same_value)  # the same numbers
    # a tenth of the coordinates: floats of different binary roundings, the same within 1e-12
    assert_same_json(without(docs["tenths"]), without(docs["ints"]))
    if command[0] == "partition":  # coordinates divided by 10, exactly
        tenth = [[tuple(to_fraction(c) / 10 for c in pt) for pt in ring] for ring in docs["ints"]["vertices"]]
        assert tenth == [[tuple(map(to_fraction, pt)) for pt in ring] for ring in docs["tenths"]["vertices"]]


# ---------------------------------------------------------------------------------------------
# the command line on these inputs: an answer or one line, never a traceback
# ---------------------------------------------------------------------------------------------
def _env_file(folder: Path, name: str, env: Environment) -> Path:
    def num(c: Fraction) -> str:
        return str(c.numerator) if c.denominator == 1 else json.dumps(str(c))

    rings = [_ring_text(ring, num) for ring in env.rings]
    return _write_env(folder, name, rings[0], "[" + ", ".join(rings[1:]) + "]")


@pytest.mark.parametrize("name", ["collinear_l", "corridor", "slit", "shared_support", "merged_rays"])
def test_cli_round_trips(name, tmp_path):
    env, p, g = built(name)
    case = CASES[name]
    path = _env_file(tmp_path, name, env)
    info = answer("info", path)
    assert info["n_vertices"] == env.n_vertices and sorted(info["reflex"]) == sorted(env.reflex_vertices)
    part = answer("partition", path)
    assert part["n_segments"] == len(p.segments)
    assert [(s["edge"], to_fraction(s["t0"]), to_fraction(s["t1"])) for s in part["segments"]] == [
        (s.edge, s.t0, s.t1) for s in p.segments]
    graph = answer("graph", path, "--safe")
    assert {(a["from"], a["to"]) for a in graph["arcs"]} == arcs_of(g)
    assert graph["n_safe_arcs"] == g.n_safe_arcs
    plan = answer("plan", path, "--from", case.start, "--to", case.goal)
    direct = find_plan(env, case.start, case.goal, graph=g)
    assert (plan["status"], plan["bounces"]) == (direct.status.value, direct.bounces)
    if direct.found:
        assert [s["interval"] for s in plan["stages"]] == [[s.interval.lo, s.interval.hi] for s in direct.stages]


EXTREME = [  # (outer ring, what the message must say; None: an answer)
    ([[0, 0], [1, 0], ["1e-400", 0], [1, 1]], "finer than 1e-100"),
    ([[0, 0], [1, 0], [1, 1], [0, 1], [0, "0.5"], [0, "0.5000000000000000000000000000001"]], "length 0 in floats"),
    ([[0, 0], [2, 0], [1, 0], [1, 1]], "overlaps"),                   # a collinear run folding back on itself
    ([[0, 0], ["1e12", 0], ["1e12", "1e-9"], [0, "1e-9"]], None),      # a 1e-9 sliver 1e12 long
]


@pytest.mark.parametrize("outer, refusal", EXTREME)
@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
def test_cli_on_extreme_inputs_answers_or_refuses_in_one_line(outer, refusal, command, tmp_path):
    path = _write_env(tmp_path, "extreme", json.dumps(outer), "[]")
    args = ["plan", path, "--from", "e0", "--to", "e2"] if command[0] == "plan" else [command[0], path, *command[1:]]
    result = run(*args)
    if refusal is not None:
        lines = result.stderr.splitlines()
        assert result.exit_code == 2 and result.stdout == "" and len(lines) == 1
        assert lines[0].startswith("error: ") and refusal in lines[0] and len(lines[0]) < 200
    else:
        assert result.exit_code == 0, result.stderr
        doc = json.loads(result.stdout)
        if command[0] == "plan":
            # floor to ceiling of the sliver: one heading straight across (no width), and the side walls
            # are 1e-21 rad wide from the long walls: proven infeasible, not a float accident
            assert doc["status"] == "infeasible" and doc["optimality"]["proved"] is True


# ---------------------------------------------------------------------------------------------
# exact numbers of every kind from Python, and big grids of pillars (slow)
# ---------------------------------------------------------------------------------------------
def test_ints_fractions_decimals_and_strings_are_the_same_environment():
    spellings = [int, lambda x: F(2 * x, 2), lambda x: Decimal(x), lambda x: f"{x}.00", lambda x: f"{x}e0"]
    def written(spell, ring):
        return [[spell(x), spell(y)] for x, y in ring]

    envs = [Environment.from_coords(written(spell, INVARIANT.outer), [written(spell, h) for h in INVARIANT.holes])
            for spell in spellings]
    docs = [json.dumps(safe_bounce_visibility_graph(env).to_json()) for env in envs]
    assert all(env == envs[0] for env in envs) and len(set(docs)) == 1


def pillar_grid(n: int, pitch: int = 3) -> Case:
    """A square room with n × n unit pillars on a grid: rows and columns share every supporting line."""
    side = pitch * n + 1
    holes = [[[x, y], [x, y + 1], [x + 1, y + 1], [x + 1, y]]
             for x in range(2, side - 1, pitch) for y in range(2, side - 1, pitch)]
    return Case([[0, 0], [side, 0], [side, side], [0, side]], holes[: n * n], "e3", "e1")


@pytest.mark.slow
@pytest.mark.parametrize("n", [2, 3])
def test_grids_of_aligned_pillars(n):
    case = pillar_grid(n)
    env = case.env()
    p = partition(env)
    expected = reference_partition(env.rings)
    assert {(q.edge, q.t): (q.point, frozenset(q.sources)) for q in p.inserted} == expected
    g = safe_bounce_visibility_graph(p)
    if n == 2:  # the brute-force BVG and safe ends cost minutes beyond that
        assert arcs_of(g) == reference_arcs(env.rings, [(s.a, s.b) for s in p.segments])
        assert check_safe_ends(env, p, g) > 0
    start, parts = start_elements(g, _pieces(env, case.start))
    goal = set(start_segments(g, _pieces(env, case.goal)))
    brute = enumerate_plans(admissible(g, pieces=parts), start, goal, 2)
    plan = find_plan(env, case.start, case.goal, objective="tolerance", max_bounces=2, graph=g)
    front = brute.front(2)
    if front:
        assert (plan.bounces, plan.min_width) == (front[-1][0], pytest.approx(front[-1][1], abs=EPS))
    else:
        assert not plan.found and plan.optimality.proved
