"""Dynamics (paper §6): Def. 11/Lemma 2 contraction, its monotonicity, Def. 12, Lemma 3's range, Theorem 1's
fixed point and Cor. 3/4 — each checked against the simulator (the ground truth) or exact ray casting."""

from __future__ import annotations

import math
from math import pi as PI
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from solverplan.bounce.dynamics import (
    ExactHeading,
    composite_contraction,
    contraction_coefficient,
    contraction_threshold,
    cycles_to_epsilon,
    distance_bound,
    interior_angles,
    is_contracting,
    lemma3_max_heading,
    lemma3_range,
    parse_heading,
    theorem1_fixed_point,
    edge_transition,
    worst_case_contraction,
)
from solverplan.bounce.rules import Fixed
from solverplan.bounce.transitions import exact_transition
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.simulate import simulate_rule
from tests.strategies import convex_polygons, polygons_with_holes
from tests.shapes import SQUARE

RECTANGLE = Environment.from_coords([[0, 0], [2, 0], [2, 1], [0, 1]], name="rectangle")
# Lemma 3's per-step contraction bound binds (at v1, where the short e0 meets the long e1), not the edge order:
CONTRACTION_BINDS = Environment.from_coords([[0, 0], [2, 0], [8, 3], [8, 6], [0, 6]], name="contraction-binds")
L_ROOM = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]], name="L")
FEW = max(10, settings.default.max_examples // 4)

thetas = st.floats(0.01, PI - 0.01)
phis = st.floats(0.01, PI - 0.01)


def _fraction_of_range(env: Environment, frac: float) -> float:
    return frac * lemma3_max_heading(env)


def _simulate(env, theta, edges, ts, bounces, **kw):
    return simulate_rule(env, Fixed(theta), (np.asarray(edges), np.asarray(ts, dtype=float)), bounces=bounces,
                         initial=[theta], ties="exact", seed=0, **kw)


# ---------------------------------------------------------------------- Def. 11, Lemma 2, monotonicity
@given(env=convex_polygons(), frac=st.floats(0.05, 0.95), t=st.floats(0.05, 0.95), u=st.floats(0.05, 0.95))
@settings(max_examples=FEW)
def test_def11_coefficient_is_the_measured_distance_ratio_at_the_corner(env, frac, t, u):
    """Two starts on e_i at distances x, y from the corner v_{i+1} land C·x and C·y from it (simulated)."""
    assume(abs(t - u) > 1e-3)
    theta = _fraction_of_range(env, frac)
    i = 0
    phi = interior_angles(env)[1]
    runs = _simulate(env, theta, [i, i], [t, u], 1)
    assert runs.outcome_counts()["ok"] == 2 and runs.edge[:, 1].tolist() == [1, 1]
    length0, length1 = env.edge_lengths[0], env.edge_lengths[1]
    before = (1 - np.array([t, u])) * length0  # distance to v1 along e0
    after = runs.t[:, 1] * length1  # distance from v1 along e1
    c = contraction_coefficient(theta, phi, "right")
    assert after == pytest.approx(c * before, rel=1e-9, abs=1e-12)
    assert edge_transition(env, 0, 1) == pytest.approx((phi, "right"))


@given(theta=thetas, phi=phis, side=st.sampled_from(["right", "left"]))
def test_lemma2_contracts_iff_past_the_threshold(theta, phi, side):
    c = contraction_coefficient(theta, phi, side)
    if math.isnan(c):  # outside the transition's domain: the ray cannot reach the target line ahead
        assert (theta + phi >= PI) if side == "right" else (theta <= phi)
        assert not is_contracting(theta, phi, side)
        return
    threshold = contraction_threshold(phi, side)
    assume(abs(theta - threshold) > 1e-9)
    assert bool(is_contracting(theta, phi, side)) == (c < 1)
    assert bool(is_contracting(theta, phi, side)) == ((theta < threshold) if side == "right" else (theta > threshold))


@given(lo=thetas, width=st.floats(0.0, 1.0), phi=phis, side=st.sampled_from(["right", "left"]))
def test_monotonicity_worst_case_is_at_the_known_endpoint(lo, width, phi, side):
    hi = min(lo + width, PI - 0.01)
    grid = np.linspace(lo, hi, 33)
    values = contraction_coefficient(grid, phi, side)
    assume(np.all(np.isfinite(values)))
    worst = worst_case_contraction((lo, hi), phi, side)
    assert worst == pytest.approx(values.max(), rel=1e-12)
    assert worst == values[-1 if side == "right" else 0]


def test_contraction_coefficient_is_vectorised_and_nan_outside_the_domain():
    out = contraction_coefficient(np.array([0.5, 2.5]), np.array([1.0, 1.0]), np.array(["right", "left"]))
    assert out.shape == (2,) and out[0] == pytest.approx(math.sin(0.5) / math.sin(1.5))
    assert out[1] == pytest.approx(math.sin(2.5) / math.sin(1.5))
    assert math.isnan(contraction_coefficient(2.5, 1.0, "right"))
    with pytest.raises(InputError, match=r"^transition side 'up' is neither 'right' nor 'left'$"):
        contraction_coefficient(0.5, 1.0, "up")


@given(env=convex_polygons(), frac=st.floats(0.05, 0.95), t=st.floats(0.1, 0.45))
@settings(max_examples=FEW)
def test_def12_measured_per_cycle_contraction_equals_the_product(env, frac, t):
    """Two starts on e0, one cycle of n bounces (simulated): the distance ratio is Π C_k (Def. 12)."""
    theta = _fraction_of_range(env, frac)
    n = env.n_edges
    phi = interior_angles(env)
    product = composite_contraction([(theta, phi[(k + 1) % n], "right") for k in range(n)])
    assume(product > 1e-8)
    runs = _simulate(env, theta, [0, 0], [t, t + 0.5], n)
    assert runs.outcome_counts()["ok"] == 2
    assert runs.edge[0].tolist() == [*range(n), 0]
    measured = abs(runs.t[0, n] - runs.t[1, n]) / 0.5
    assert measured == pytest.approx(product, rel=1e-6)


# ---------------------------------------------------------------------- Lemma 3
@given(env=convex_polygons(), frac=st.floats(0.02, 0.98), t=st.floats(0.001, 0.999), edge=st.integers(0, 30))
@settings(max_examples=FEW)
def test_lemma3_constant_heading_visits_the_edges_in_ccw_order(env, frac, t, edge):
    theta = _fraction_of_range(env, frac)
    n = env.n_edges
    e0 = edge % n
    runs = _simulate(env, theta, [e0], [t], 3 * n)
    assert runs.outcome_counts()["ok"] == 1
    assert runs.edge[0].tolist() == [(e0 + k) % n for k in range(3 * n + 1)]


def test_lemma3_range_of_a_rectangle_is_the_edge_order_bound():
    r = lemma3_range(RECTANGLE)
    assert r.bound == r.order_bound == pytest.approx(math.atan(1 / 2)) and r.contraction_bound == pytest.approx(PI / 4)
    assert lemma3_max_heading(SQUARE) == pytest.approx(PI / 4)


def test_lemma3_outside_the_range_the_edge_order_breaks_rectangle():
    """Designed example 1 (edge order binds): just above atan(1/2) a start near v0 on the long edge e0 hits e2, not e1."""
    theta = lemma3_max_heading(RECTANGLE) + 1e-3
    hit = exact_transition(RECTANGLE, 0, Fraction(1, 1000), ExactHeading.from_float(theta).direction((2, 0)))
    assert hit.edge == 2
    runs = _simulate(RECTANGLE, theta, [0], [0.001], 1)
    assert runs.edge[0, 1] == 2
    inside = lemma3_max_heading(RECTANGLE) - 1e-3
    assert exact_transition(RECTANGLE, 0, Fraction(1, 1000), ExactHeading.from_float(inside).direction((2, 0))).edge == 1


def test_lemma3_outside_the_range_a_step_expands_contraction_binds():
    """Designed example 2 (per-step contraction binds at v1): just above the bound the edge order still holds
    but the step e0 → e1 expands — measured in simulation — while the whole cycle still contracts (Def. 12:
    Lemma 3's per-step condition is sufficient, not necessary; solverplan.proofs.lemma3_convex_order)."""
    r = lemma3_range(CONTRACTION_BINDS)
    assert r.contraction_vertex == 1 and r.contraction_bound < r.order_bound
    theta = r.bound + 0.01
    phi1 = interior_angles(CONTRACTION_BINDS)[1]
    assert not is_contracting(theta, phi1) and is_contracting(r.bound - 0.01, phi1)
    runs = _simulate(CONTRACTION_BINDS, theta, [0, 0], [0.2, 0.6], 1)
    assert runs.edge[:, 1].tolist() == [1, 1]
    l0, l1 = CONTRACTION_BINDS.edge_lengths[:2]
    ratio = abs(runs.t[0, 1] - runs.t[1, 1]) * l1 / (0.4 * l0)
    assert ratio > 1 and ratio == pytest.approx(contraction_coefficient(theta, phi1))
    for t in (0.001, 0.5, 0.999):  # every start still reaches the next edge
        assert _simulate(CONTRACTION_BINDS, theta, [0], [t], 5).edge[0].tolist() == [0, 1, 2, 3, 4, 0]
    n = CONTRACTION_BINDS.n_edges
    phi = interior_angles(CONTRACTION_BINDS)
    assert composite_contraction([(theta, phi[(k + 1) % n], "right") for k in range(n)]) < 1


def test_lemma3_outside_the_range_square_breaks_both():
    """Designed example 3: in a square both bounds are π/4; just above, every step expands (C = tan θ > 1)."""
    theta = PI / 4 + 1e-3
    assert contraction_coefficient(theta, PI / 2) > 1
    runs = _simulate(SQUARE, theta, [0, 0], [0.5, 0.5 + 1e-4], 8)
    assert abs(runs.t[0, 8] - runs.t[1, 8]) > 1e-4


def test_lemma3_rejects_non_convex_environments_with_one_line():
    with pytest.raises(InputError, match=r"^Lemma 3 needs a convex polygon: vertex v3 of L is reflex$"):
        lemma3_max_heading(L_ROOM)
    holed = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], [[[4, 4], [6, 4], [6, 6], [4, 6]]], name="ring")
    with pytest.raises(InputError, match=r"^Lemma 3 needs a convex polygon without holes: ring has 1 hole\(s\)$"):
        lemma3_max_heading(holed)
    flat = Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])
    with pytest.raises(InputError, match=r"strictly convex polygon: vertex v1 is collinear"):
        lemma3_max_heading(flat)


# ---------------------------------------------------------------------- Theorem 1, Cor. 3, Cor. 4
@given(env=convex_polygons(), tan=st.fractions(Fraction(1, 40), Fraction(3, 2), max_denominator=40))
@example(env=SQUARE, tan=Fraction(1, 2))
@settings(max_examples=FEW)
def test_theorem1_formula_equals_the_exact_composed_return_map(env, tan):
    heading = ExactHeading.from_tangent(tan)
    assume(heading.theta < lemma3_max_heading(env))
    fp = theorem1_fixed_point(env, heading)
    assert fp.t == pytest.approx(float(fp.t_exact), rel=1e-9, abs=1e-12)
    assert fp.contraction == pytest.approx(float(fp.contraction_exact), rel=1e-9)
    assert 0 < fp.t_exact < 1


@given(env=convex_polygons(), frac=st.floats(0.05, 0.9), t=st.floats(0.01, 0.99), edge=st.integers(0, 30))
@settings(max_examples=FEW)
def test_theorem1_simulated_trajectory_converges_to_d_fp(env, frac, t, edge):
    theta = _fraction_of_range(env, frac)
    fp = theorem1_fixed_point(env, theta)
    n = env.n_edges
    e0 = edge % n
    k = cycles_to_epsilon(fp.contraction, 1.0, 1e-12 * fp.t) + 1
    assume(k * n <= 4000)
    runs = _simulate(env, theta, [e0], [t], k * n + (n - e0) % n, record="ends")
    assert runs.outcome_counts()["ok"] == 1 and runs.final_edge[0] == 0
    assert abs(runs.final_t[0] * env.edge_lengths[0] - fp.d) / fp.d < 1e-9


@given(env=convex_polygons(), frac=st.floats(0.05, 0.9), exponent=st.floats(1.0, 7.0))
@settings(max_examples=FEW)
def test_cor4_count_is_an_upper_bound_within_one_of_the_observed(env, frac, exponent):
    """Starts spread over all of e0; the observed cycles until their spread is ≤ ε versus the tight Cor. 4 count
    for the whole edge (and the paper's factor-2 count, which is never smaller)."""
    theta = _fraction_of_range(env, frac)
    fp = theorem1_fixed_point(env, theta)
    n, length = env.n_edges, float(env.edge_lengths[0])
    epsilon = length * 10.0 ** (-exponent)
    predicted = cycles_to_epsilon(fp.contraction, length, epsilon)
    assume(predicted * n <= 3000)
    starts = np.linspace(1e-7, 1 - 1e-7, 9)
    runs = _simulate(env, theta, np.zeros(9, dtype=int), starts, (predicted + 1) * n)
    assert runs.outcome_counts()["ok"] == 9
    spreads = [np.ptp(runs.t[:, c * n]) * length for c in range(predicted + 2)]
    observed = next(c for c, s in enumerate(spreads) if s <= epsilon)
    assert observed <= predicted <= observed + 1
    design = max(0, math.ceil(math.log(epsilon / (2 * length)) / math.log(fp.contraction)))
    assert design >= predicted


@given(env=convex_polygons(), frac=st.floats(0.05, 0.9), t=st.floats(0.0, 1.0), k=st.integers(0, 4))
@settings(max_examples=FEW)
def test_cor3_distance_to_the_fixed_point_after_k_cycles(env, frac, t, k):
    theta = _fraction_of_range(env, frac)
    fp = theorem1_fixed_point(env, theta)
    n, length = env.n_edges, float(env.edge_lengths[0])
    t = min(max(t, 1e-6), 1 - 1e-6)
    runs = _simulate(env, theta, [0], [t], k * n)
    gap = abs(runs.t[0, k * n] * length - fp.d)
    assert gap <= distance_bound(k, fp.contraction, length) * (1 + 1e-9) + 1e-12
    assert gap == pytest.approx(fp.contraction**k * abs(t * length - fp.d), rel=1e-6, abs=1e-11)


def test_cor4_tight_count_exact_and_edge_cases():
    assert cycles_to_epsilon(Fraction(9, 10), 1, Fraction(1, 1000)) == 66  # the paper's factor 2 gives 73
    assert cycles_to_epsilon(Fraction(1, 2), 1, Fraction(1, 4)) == 2  # an exact power: not rounded up to 3
    assert cycles_to_epsilon(0.5, 1.0, 0.25) == 2
    assert cycles_to_epsilon(0.9, 1.0, 100.0) == 0  # the paper's formula is negative here (−37 for ε = 100ℓ)
    with pytest.raises(InputError, match=r"^contraction 1 is not < 1: the position set never shrinks$"):
        cycles_to_epsilon(1, 1, Fraction(1, 2))
    with pytest.raises(InputError, match=r"^epsilon -1.0 must be positive$"):
        cycles_to_epsilon(0.5, 1.0, -1.0)
    assert distance_bound(2, 0.5, 4.0) == 1.0


# ---------------------------------------------------------------------- exact headings
def test_exact_headings_parse_and_rotate_every_edge_by_the_same_angle():
    assert parse_heading("tan:1/3") == ExactHeading(3, 1) == parse_heading("atan:2/6") == parse_heading((Fraction(3, 2), "1/2"))
    assert parse_heading("tan:-1/2") == ExactHeading(-2, 1) and parse_heading("dir:0,5").theta == PI / 2
    assert parse_heading("pi/8") == PI / 8 and parse_heading(0.3) == 0.3
    with pytest.raises(InputError, match=r"^heading 0 is not inside \(0, π\) \(radians\)$"):
        parse_heading("0")
    with pytest.raises(InputError, match=r"^heading tangent 0 is not inside \(0, π\)"):
        parse_heading("tan:0")
    h = ExactHeading.from_float(0.7)
    assert abs(h.theta - 0.7) < 1e-15
    for edge in range(L_ROOM.n_edges):
        e = L_ROOM.edge(edge)
        v = (e.b[0] - e.a[0], e.b[1] - e.a[1])
        d = h.direction(v)
        angle = math.atan2(float(v[0] * d[1] - v[1] * d[0]), float(v[0] * d[0] + v[1] * d[1]))
        assert angle == pytest.approx(h.theta, abs=1e-15)


@given(env=polygons_with_holes(), edge=st.integers(0, 60), target=st.integers(0, 60))
@settings(max_examples=FEW)
def test_transition_angle_agrees_with_the_affine_map_slope(env, edge, target):
    """In arc length the affine map's slope is ±C (solverplan.proofs.affine_transition): |α|·ℓ_j/ℓ_i = C(θ, φ)."""
    from solverplan.bounce.transitions import affine_map

    i, j = edge % env.n_edges, target % env.n_edges
    assume(i != j)
    try:
        phi, side = edge_transition(env, i, j)
    except InputError:
        return
    theta = 1.0 if side == "right" else 2.0
    c = contraction_coefficient(theta, phi, side)
    assume(np.isfinite(c))
    try:
        m = affine_map(env, i, ExactHeading.from_float(theta).direction(
            (env.edge(i).b[0] - env.edge(i).a[0], env.edge(i).b[1] - env.edge(i).a[1])), j)
    except InputError:
        return
    assert float(abs(m.alpha)) * env.edge_lengths[j] / env.edge_lengths[i] == pytest.approx(c, rel=1e-9)
