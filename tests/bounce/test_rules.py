"""Bounce rules (paper §3, Def. 1–2, Fig. 2): conventions on hand-computed contacts, headings always
valid, non-deterministic sets and sampling, and one-line errors."""

from __future__ import annotations

import math
from math import pi as PI

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.interval import Interval
from solverplan.bounce.rules import (
    HEADING_MARGIN,
    BounceRule,
    Fixed,
    FixedInterval,
    MonotoneFixed,
    Relative,
    Specular,
    edge_frames,
    incoming_angles,
    parse_rule,
    rotate_clockwise_into_free,
    sample_headings,
)
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet
from tests.strategies import polygons_with_holes
from tests.shapes import SQUARE

# edges of SQUARE: e0 floor (→ +x), e1 right wall (→ +y), e2 ceiling (→ −x), e3 left wall (→ −y)


def unit(x: float, y: float) -> np.ndarray:
    return np.array([[x, y]]) / math.hypot(x, y)


def heading_vector(env: Environment, edge: int, theta: float) -> np.ndarray:
    tangent, normal = edge_frames(env, np.array([edge]))
    return math.cos(theta) * tangent[0] + math.sin(theta) * normal[0]


# ---------------------------------------------------------------------- α and the four rules by hand
@pytest.mark.parametrize(
    "edge,v,alpha",
    [
        (0, (1, -1), 3 * PI / 4),  # onto the floor moving right: back along the path is up-left
        (0, (-1, -1), PI / 4),
        (0, (0, -1), PI / 2),  # head-on
        (1, (1, 1), 3 * PI / 4),  # onto the right wall moving up: in e1's frame back is (−1, −1) → CCW 135°
        (2, (1, 1), PI / 4),  # onto the ceiling (pointing −x) moving right
    ],
)
def test_def1_incoming_angle_is_the_direction_back_along_the_path(edge, v, alpha):
    assert incoming_angles(SQUARE, [edge], unit(*v))[0] == pytest.approx(alpha, abs=1e-12)


@pytest.mark.parametrize("edge,v", [(0, (1, -1)), (0, (-3, -1)), (1, (1, 0.2)), (2, (-0.5, 1)), (3, (-1, -2))])
def test_specular_is_the_mirror_reflection_on_hand_cases(edge, v):
    b = Specular()(SQUARE, [edge], unit(*v))[0]
    out = heading_vector(SQUARE, edge, b)
    tangent, normal = edge_frames(SQUARE, np.array([edge]))
    vin = unit(*v)[0]
    mirror = vin - 2 * np.dot(vin, normal[0]) * normal[0]
    np.testing.assert_allclose(out, mirror, atol=1e-12)


@given(env=polygons_with_holes(), data=st.data())
def test_specular_reflects_on_any_edge(env, data):
    edge = data.draw(st.integers(0, env.n_edges - 1))
    alpha = data.draw(st.floats(0.01, PI - 0.01))
    tangent, normal = edge_frames(env, np.array([edge]))
    v = -(math.cos(alpha) * tangent[0] + math.sin(alpha) * normal[0])  # arrives with incoming angle α
    b = Specular()(env, [edge], v[None, :])[0]
    assert b == pytest.approx(PI - alpha, abs=1e-12)
    out = heading_vector(env, edge, b)
    np.testing.assert_allclose(out, v - 2 * np.dot(v, normal[0]) * normal[0], atol=1e-12)


def test_fixed_ignores_the_incoming_angle():
    v = np.vstack([unit(1, -1), unit(-1, -3), unit(0, -1)])
    assert Fixed(0.7)(SQUARE, [0, 0, 0], v).tolist() == [0.7, 0.7, 0.7]


@pytest.mark.parametrize(
    "theta_r,edge,v,expected",
    [
        (PI / 2, 0, (1, -1), PI / 4),  # α = 3π/4: one rotation, α − θ_r
        (PI / 6, 0, (1, -1), 7 * PI / 12),  # α − θ_r = 3π/4 − π/6
        (5 * PI / 6, 0, (-1, -1), 7 * PI / 12),  # α = π/4: π/4 − 5π/6 ≡ 17π/12 (faces the wall), again: 7π/12
        # α = π/2 head-on: α − kπ/2 = 0 (along the wall, not free), −π/2 (into it), −π ≡ π (wall), −3π/2 ≡ π/2
        (PI / 2, 0, (0, -1), PI / 2),
        (1.0, 1, (1, 1), 3 * PI / 4 - 1.0),  # on the right wall
    ],
)
def test_fig2_relative_rule_back_reference(theta_r, edge, v, expected):
    assert Relative(theta_r)(SQUARE, [edge], unit(*v))[0] == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize(
    "theta_r,v,expected",
    [
        (PI / 2, (1, -1), 3 * PI / 4),  # travelling at −45°: −135° (into the floor), −225° ≡ 135°
        (3 * PI / 4, (1, -1), PI / 4),  # −45° − 135° = −180° is along the wall, so again: −315° ≡ 45°
        (PI / 3, (0, -1), 5 * PI / 6),  # −90° → −150° → −210° ≡ 150°
    ],
)
def test_fig2_relative_rule_travel_reference(theta_r, v, expected):
    rule = Relative(theta_r, reference="travel")
    assert rule(SQUARE, [0], unit(*v))[0] == pytest.approx(expected, abs=1e-9)


def test_relative_rotation_closed_form_matches_stepwise_rotation():
    rng = np.random.default_rng(3)
    start = rng.uniform(-2 * PI, 4 * PI, 2000)
    theta = rng.uniform(0.05, PI - 0.05, 2000)
    fast = np.array([rotate_clockwise_into_free(np.array([s]), th)[0] for s, th in zip(start, theta)])
    for s, th, got in zip(start, theta, fast):
        h = s
        for _ in range(200):
            h = (h - th) % (2 * PI)
            if 0 < h < PI:
                break
        assert got == pytest.approx(h, abs=1e-9)


@pytest.mark.parametrize(
    "edge,v,expected",
    [
        (0, (1, -1), PI / 3),  # floor, moving right: θ_m leans right (+x)
        (0, (-1, -1), 2 * PI / 3),  # floor, moving left: π − θ_m
        (2, (1, 1), 2 * PI / 3),  # ceiling points −x: θ_m would lean left, so π − θ_m keeps +x
        (2, (-1, 1), PI / 3),
        (1, (1, 1), PI / 3),  # a wall perpendicular to x: no choice keeps +x, tie keeps θ_m
        (0, (0, -1), PI / 3),  # arriving straight down: σ = +1 (v·x = 0)
    ],
)
def test_fig2_monotone_fixed_keeps_travel_monotone_in_x(edge, v, expected):
    assert MonotoneFixed(PI / 3)(SQUARE, [edge], unit(*v))[0] == pytest.approx(expected, abs=1e-12)


@given(env=polygons_with_holes(), data=st.data())
def test_monotone_fixed_never_reverses_x_travel_when_it_can_avoid_it(env, data):
    edge = data.draw(st.integers(0, env.n_edges - 1))
    theta = data.draw(st.floats(0.05, PI - 0.05))
    alpha = data.draw(st.floats(0.01, PI - 0.01))
    tangent, normal = edge_frames(env, np.array([edge]))
    v = -(math.cos(alpha) * tangent[0] + math.sin(alpha) * normal[0])
    b = MonotoneFixed(theta)(env, [edge], v[None, :])[0]
    assert b in (theta, PI - theta)
    sense = 1.0 if v[0] >= 0 else -1.0
    chosen = sense * heading_vector(env, edge, b)[0]
    other = sense * heading_vector(env, edge, PI - b)[0]
    assert chosen >= other - 1e-12


# ---------------------------------------------------------------------- headings always valid
RULES = st.one_of(
    st.builds(Specular, st.floats(0, 1.0)),
    st.builds(Fixed, st.floats(0.001, PI - 0.001), st.floats(0, 1.0)),
    st.builds(MonotoneFixed, st.floats(0.001, PI - 0.001), st.floats(0, 1.0)),
    st.builds(Relative, st.floats(0.001, PI - 0.001), st.floats(0, 1.0), st.sampled_from(["back", "travel"])),
)


@given(env=polygons_with_holes(), rule=RULES, data=st.data())
def test_outgoing_headings_always_inside_open_0_pi(env, rule, data):
    m = 50
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    edges = rng.integers(0, env.n_edges, m)
    alpha = rng.uniform(0, PI, m)
    alpha[:3] = [0.0, PI, 1e-17]  # grazing arrivals
    tangent, normal = edge_frames(env, edges)
    v = -(np.cos(alpha)[:, None] * tangent + np.sin(alpha)[:, None] * normal)
    assert isinstance(rule, BounceRule)
    lo, hi = rule.bounds(env, edges, v)
    nominal = rule.nominal(env, edges, v)
    assert np.all((0 < lo) & (lo <= nominal) & (nominal <= hi) & (hi < PI))
    assert np.all(hi - lo <= 2 * rule.epsilon + 1e-12)
    for sampling in ("uniform", "endpoints", "lo", "hi", "mid"):
        h = rule.headings(env, edges, v, rng, sampling=sampling)
        assert np.all((lo <= h) & (h <= hi) & (h > 0) & (h < PI))


def test_endpoint_sampling_is_adversarial_uniform_fills_the_interval():
    rule = Specular(0.2)
    v = np.repeat(unit(1, -1), 4000, axis=0)
    rng = np.random.default_rng(0)
    ends = rule.headings(SQUARE, np.zeros(4000, dtype=int), v, rng, sampling="endpoints")
    assert set(np.round(ends, 12).tolist()) == {round(PI / 4 - 0.2, 12), round(PI / 4 + 0.2, 12)}
    uniform = rule.headings(SQUARE, np.zeros(4000, dtype=int), v, rng)
    assert PI / 4 - 0.2 <= uniform.min() < PI / 4 - 0.19 and PI / 4 + 0.19 < uniform.max() <= PI / 4 + 0.2


def test_interval_view_of_one_contact_and_clipping_near_the_wall():
    assert Fixed(1.0, 0.25).interval(SQUARE, 0, [1, -1]) == Interval(0.75, 1.25)
    near_wall = Fixed(0.1, 0.5).interval(SQUARE, 0, [1, -1])
    assert near_wall == Interval(HEADING_MARGIN, 0.6)
    assert Specular().interval(SQUARE, 0, unit(1, -1)[0]).width == 0.0


def test_fixed_interval_rule_keeps_its_ends_exactly():
    rule = FixedInterval.of(Interval(0.3, 0.9000000000000001))
    lo, hi = rule.bounds(SQUARE, [0, 1], np.vstack([unit(1, -1), unit(1, 1)]))
    assert lo.tolist() == [0.3, 0.3] and hi.tolist() == [0.9000000000000001] * 2
    assert rule.headings(SQUARE, [0], unit(1, -1), sampling="hi").tolist() == [0.9000000000000001]


def test_rule_names_round_trip_through_parse_rule():
    for rule in (Specular(), Fixed(1.25), MonotoneFixed(0.5), Relative(2.0), Relative(2.0, reference="travel")):
        assert parse_rule(str(rule)) == rule
    assert parse_rule("relative:pi/2") == Relative(PI / 2)
    assert parse_rule("fixed:2pi/5") == Fixed(2 * PI / 5)


# ---------------------------------------------------------------------- bad input: one line
@pytest.mark.parametrize(
    "build,message",
    [
        (lambda: Fixed(3.5), r"^fixed rule: heading interval \[3.5, 3.5\] is not inside \(0, π\): hi=3.5$"),
        (lambda: Fixed(0.0), r"^fixed rule: heading interval \[0, 0\] is not inside \(0, π\): lo=0$"),
        (lambda: Relative(PI), r"^relative rule: heading interval \[3.14159, 3.14159\] is not inside \(0, π\): hi=3.14159$"),
        (lambda: MonotoneFixed(-1), r"^monotone rule: heading interval \[-1, -1\] is not inside \(0, π\): lo=-1$"),
        (lambda: FixedInterval(0.5, 4.0), r"^fixed rule: heading interval \[0.5, 4\] is not inside \(0, π\): hi=4$"),
        (lambda: parse_rule("fixed:4"), r"^fixed rule: heading interval \[4, 4\] is not inside \(0, π\): hi=4$"),
    ],
)
def test_headings_outside_0_pi_are_rejected_in_one_line(build, message):
    with pytest.raises(InvalidBoundarySet, match=message):
        build()


@pytest.mark.parametrize(
    "build,message",
    [
        (lambda: Specular(-0.1), r"^specular rule: epsilon -0.1 must lie in \[0, π\)$"),
        (lambda: Relative(1.0, reference="sideways"), r"^relative rule: reference 'sideways' must be 'back' or 'travel'$"),
        (lambda: MonotoneFixed(1.0, axis=(0, 0)), r"^monotone rule: axis \(0, 0\) is zero or not finite$"),
        (lambda: parse_rule("bouncy"), r"^unknown bounce rule 'bouncy': use specular, fixed:THETA"),
        (lambda: parse_rule("fixed"), r"^bounce rule 'fixed': fixed needs an angle, e.g. fixed:1.2$"),
        (lambda: parse_rule("fixed:abc"), r"^bounce rule 'fixed:abc': 'abc' is not an angle in radians$"),
        (lambda: parse_rule("specular:1"), r"^bounce rule 'specular:1': specular takes no angle$"),
    ],
)
def test_bad_rule_parameters_are_input_errors(build, message):
    with pytest.raises(InputError, match=message):
        build()


def test_unknown_edge_and_bad_incoming_directions_are_one_line_errors():
    with pytest.raises(InvalidBoundarySet, match=r"^unknown edge e7: edges are e0..e3$"):
        Specular()(SQUARE, [7], unit(1, -1))
    with pytest.raises(InputError, match=r"^incoming direction \(0.707107, 0.707107\) leaves edge e0 instead of arriving at it$"):
        Specular()(SQUARE, [0], unit(1, 1))
    with pytest.raises(InputError, match=r"^incoming direction 0 is zero or not finite$"):
        Specular()(SQUARE, [0], np.array([[0.0, 0.0]]))
    with pytest.raises(InputError, match=r"^edges and incoming directions differ in length: 2 and 1$"):
        Specular()(SQUARE, [0, 1], unit(1, -1))
    with pytest.raises(InputError, match=r"^uniform sampling of a non-deterministic rule needs an rng$"):
        Specular(0.1)(SQUARE, [0], unit(1, -1))
    with pytest.raises(InputError, match=r"^unknown sampling 'worst'"):
        sample_headings(np.array([1.0]), np.array([1.0]), None, "worst")  # type: ignore[arg-type]
