"""Range-limited views and Algorithm B: Theorem 3 (R reaching across P gives Algorithm A), Theorem 4 (complete
coverage), Lemma 4 (the view bound), Theorem 5 (the lower bound and the ratio), on random polygons with and
without holes."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.explore import explore_depth_first
from solverplan.explore.range_limited import covers_every_segment, explore_range_limited
from solverplan.explore.range_view import Arc, range_visibility
from solverplan.geometry.visibility import sees, visibility_polygon
from solverplan.result import Status
from tests.explore.test_depth_first import free_points
from tests.strategies import polygons_with_holes, simple_polygons

SQUARE = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]])
ELL = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])


@st.composite
def range_instances(draw, holes: bool, percent: tuple[int, int] = (25, 60)):
    """A random polygon, a start in it and R between ``percent`` of the polygon's size (exact)."""
    env = draw(polygons_with_holes(max_holes=2) if holes else simple_polygons(min_vertices=4, max_vertices=10))
    xmin, ymin, xmax, ymax = env.bounds
    size = max(xmax - xmin, ymax - ymin)
    R = Fraction(draw(st.integers(*percent)), 100) * Fraction(round(size))
    return env, draw(free_points(env)), R


def _check_chain_and_path(run, env):
    """p_i lies (exactly) in an earlier view, ε inside the free space; every leg of the path is a line of sight."""
    assert run.viewpoints[0] == run.path[0] and run.parents[0] == -1
    walls = env.to_shapely().boundary
    for k in range(1, run.n_views):
        j = run.parents[k]
        assert 0 <= j < k and run.views[j].contains(run.viewpoints[k])
        assert walls.distance(shapely.Point(*map(float, run.viewpoints[k]))) >= float(run.epsilon) / 4 * (1 - 1e-9)
    assert all(sees(env, p, q) for p, q in zip(run.path, run.path[1:]))


# ---------------------------------------------------------------------------------------- the range view
def test_a_view_in_open_space_is_the_whole_disc():
    rv = range_visibility(SQUARE, (5, 5), 2)
    (arc,) = rv.pieces
    assert isinstance(arc, Arc) and arc.centre == (5, 5) and arc.radius == 2
    assert arc.span == pytest.approx(2 * math.pi) and rv.area == pytest.approx(4 * math.pi)


def test_a_wall_cuts_the_disc_along_a_chord_with_the_exact_segment_area():
    rv = range_visibility(SQUARE, (5, 1), 2)
    assert [p.kind for p in rv.pieces] == ["partial", "arc"]
    # disc minus the circular segment below y = 0, at distance 1 from the centre
    assert rv.area == pytest.approx(4 * math.pi - (4 * math.acos(0.5) - math.sqrt(3)), rel=1e-12)
    assert rv.contains((5, 3)) and not rv.contains((5, Fraction(301, 100))) and rv.contains((5, 0))


def test_range_view_bad_range():
    for bad in (0, -1, float("nan"), float("inf"), "x"):
        with pytest.raises(InputError):
            range_visibility(SQUARE, (5, 5), bad)


@settings(max_examples=40)
@given(polygons_with_holes(), st.integers(3, 60), st.data())
def test_range_view_is_the_visibility_polygon_clipped_to_the_disc(env, radius, data):
    z = data.draw(free_points(env))
    rv = range_visibility(env, z, radius)
    vp = visibility_polygon(env, z)
    exact_vp = shapely.Polygon([tuple(map(float, p)) for p in vp.ring]).buffer(0)
    disc = shapely.Point(*map(float, z)).buffer(radius, quad_segs=2048)
    truth = exact_vp.intersection(disc).area
    assert rv.area == pytest.approx(truth, rel=1e-5, abs=1e-9)
    assert rv.area <= math.pi * radius ** 2 * (1 + 1e-12) and rv.area <= float(vp.area) * (1 + 1e-12) + 1e-12
    assert rv.to_shapely().area <= rv.area * (1 + 1e-12) + 1e-12   # inscribed: never more than the true area
    for arc in rv.arcs:   # arcs are on the range circle, centred on the viewpoint
        assert arc.centre == rv.viewpoint and arc.radius == radius and 0 < arc.span <= 2 * math.pi + 1e-12
        mid = arc.point((arc.start_angle + arc.end_angle) / 2)
        assert math.dist(mid, tuple(map(float, z))) == pytest.approx(radius)
    assert rv.is_unrestricted == (not rv.arcs)


# ---------------------------------------------------------------------------------------- Theorem 3
@settings(max_examples=25)
@given(polygons_with_holes(), st.data())
def test_theorem_3_range_reaching_across_p_is_algorithm_a(env, data):
    start = data.draw(free_points(env))
    verts = env.vertices
    diameter = max(math.dist(p, q) for p in verts for q in verts)
    R = Fraction(math.ceil(diameter))
    assert covers_every_segment(env, R)
    run = explore_range_limited(env, start, R)
    plain = explore_depth_first(env, start)
    assert run.algorithm == "A" and run.viewpoints == plain.viewpoints and run.status is Status.FOUND
    assert all(v.is_unrestricted and v.polygon == w for v, w in zip(run.views, plain.views))
    assert run.n_views <= len(env.reflex_vertices) + 1 <= run.bound


def test_theorem_3_does_not_apply_below_the_diameter():
    assert covers_every_segment(ELL, 6) and not covers_every_segment(ELL, 5)


# ---------------------------------------------------------------------------------------- Theorem 4 and Lemma 4
def _check_theorem_4_lemma_4(run, env):
    assert run.algorithm == "B" and run.status is Status.FOUND, run.optimality.limits
    assert 1 - run.covered_fraction < 1e-6                          # Theorem 4 (shapely, inscribed arcs)
    assert run.n_views <= run.bound                                 # Lemma 4
    assert run.lower_bound <= run.n_views                           # Theorem 5's premise
    assert run.ratio <= run.ratio_bound * (1 + 1e-12)               # Theorem 5
    _check_chain_and_path(run, env)


@settings(max_examples=20, deadline=None)
@given(range_instances(holes=False))
def test_theorem_4_lemma_4_simple_polygons(case):
    env, start, R = case
    _check_theorem_4_lemma_4(explore_range_limited(env, start, R), env)


@settings(max_examples=20, deadline=None)
@given(range_instances(holes=True))
def test_theorem_4_lemma_4_polygons_with_holes(case):
    env, start, R = case
    _check_theorem_4_lemma_4(explore_range_limited(env, start, R), env)


@settings(max_examples=30)
@given(polygons_with_holes(), st.floats(0.5, 200))
def test_theorem_5_ratio_bound_dominates_lemma_4_over_the_lower_bound(env, R):
    from solverplan.explore.bounds import range_ratio_bound, range_views_bound, range_views_lower_bound

    assert range_views_bound(env, R) / range_views_lower_bound(env, R) <= range_ratio_bound(env, R) * (1 + 1e-12)


def test_square_open_space_then_the_wall():
    run = explore_range_limited(SQUARE, (5, 5), 2)
    _check_theorem_4_lemma_4(run, SQUARE)
    assert run.phases[0] == "start" and run.phases[1] == "open"   # Step 2: no wall in sight from p1
    assert "boundary" in run.phases


def test_two_holes_are_followed_one_by_one():
    env = load_environment("two_holes")
    run = explore_range_limited(env, (5, Fraction(13, 2)), 3)
    _check_theorem_4_lemma_4(run, env)
    followed = [k for k, phase in zip(run.rings, run.phases) if phase == "boundary"]
    assert set(followed) == {0, 1, 2}
    # hole by hole: once the robot leaves a ring it has every edge of it marked and does not come back
    blocks = [k for i, k in enumerate(followed) if i == 0 or followed[i - 1] != k]
    assert len(blocks) == len(set(blocks))


def test_answer_json_has_the_range_fields():
    out = explore_range_limited(ELL, (3, 1), 1).to_json()
    assert out["algorithm"] == "B" and out["range"] == 1.0 and out["views"] == len(out["viewpoints"])
    assert out["bound"] >= out["views"] >= out["lower_bound"] and out["ratio"] == out["views"] / out["lower_bound"]
    assert len(out["arcs"]) == out["views"] and all("radius" in a for arcs in out["arcs"] for a in arcs)


def test_view_limit_gives_not_found():
    run = explore_range_limited(SQUARE, (5, 5), 1, max_views=3)
    assert run.status is Status.NOT_FOUND and run.n_views == 3 and run.optimality.limits == ("max_views=3",)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"start": (50, 5), "range_": 2}, "start (50, 5) is not in the free space"),
    ({"start": (5, 5), "range_": 0}, "range R must be a finite number > 0"),
    ({"start": (5, 5), "range_": 2, "epsilon": 0}, "epsilon must be > 0"),
    ({"start": (5, 5), "range_": 2, "max_views": 0}, "max_views must be >= 1"),
])
def test_bad_input_is_one_clear_line(kwargs, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        explore_range_limited(SQUARE, **kwargs)
