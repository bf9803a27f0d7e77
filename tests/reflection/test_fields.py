"""The line and arc fields: the properties the composition relies on, numerically (the sympy proofs are in
solverplan.proofs.line_field), and the flow-through verifier (exact for line fields, dense sample otherwise)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import solverplan.proofs.line_field as line_proof
from solverplan.environment import Environment, load_environment
from solverplan.reflection.cells import decompose_free_space
from solverplan.reflection.fields import (ArcField, GoalField, LineField, dense_flows_through, line_flows_through,
                                          line_inward_sign)

coords = st.integers(-20, 20)
points = st.tuples(coords, coords)
gains = st.fractions(Fraction(1, 10), Fraction(5), max_denominator=20)


def _field(origin, target, gain) -> LineField:
    return LineField(tuple(map(Fraction, origin)), tuple(map(Fraction, target)), gain)


# line fields between two distinct integer points, with a gain in [1/10, 5]
line_fields = st.builds(lambda ends, gain: _field(*ends, gain),
                        st.tuples(points, points).filter(lambda ends: ends[0] != ends[1]), gains)


@settings(max_examples=60)
@given(line_fields, st.lists(points, min_size=1, max_size=8))
def test_line_field_along_track_rate_is_one(f, qs):
    """Eq. 2: d·v = 1 everywhere."""
    v = f.velocity(np.array(qs, dtype=float))
    assert np.allclose(v @ f.direction, 1.0, atol=1e-9)


@settings(max_examples=30)
@given(line_fields, points)
def test_line_field_cross_track_error_decays_exponentially(f, q):
    """Eq. 2: e(t) = e₀ e^{−pt} along trajectories (RK4 integration against the closed form)."""
    origin = np.array(f.origin, dtype=float)
    d = f.direction
    normal = np.array([-d[1], d[0]])
    x = np.array([q], dtype=float)
    e0 = float((x[0] - origin) @ normal)
    h, steps = 0.01, 200
    for _ in range(steps):
        k1 = f.velocity(x)
        k2 = f.velocity(x + h / 2 * k1)
        k3 = f.velocity(x + h / 2 * k2)
        k4 = f.velocity(x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    e = float((x[0] - origin) @ normal)
    assert e == pytest.approx(e0 * math.exp(-float(f.gain) * h * steps), abs=1e-7 * (1 + abs(e0)))


@settings(max_examples=40)
@given(line_fields, points)
def test_line_field_is_the_negative_gradient_of_its_potential(f, q):
    """Eq. 2: v = −∇φ (central differences of φ)."""
    x = np.array(q, dtype=float)
    eps = 1e-5
    grad = np.array([(f.potential(np.array([x + eps * u])) - f.potential(np.array([x - eps * u])))[0] / (2 * eps)
                     for u in np.eye(2)])
    assert np.allclose(-grad, f.velocity(np.array([x]))[0], atol=1e-5 * (1 + np.abs(x).max()))


@settings(max_examples=30)
@given(points, st.floats(0.5, 10), st.fractions(Fraction(1, 10), Fraction(3), max_denominator=10), st.booleans(),
       st.floats(0.1, 12), st.floats(0, 2 * math.pi))
def test_arc_field_radial_error_decays_exponentially(centre, radius, gain, clockwise, rho0, theta):
    """Our Eq. 3: ρ̇ = p(r − ρ) and unit tangential speed, at every point."""
    f = ArcField(tuple(map(Fraction, centre)), radius, gain, clockwise)
    q = np.array(centre, dtype=float) + rho0 * np.array([math.cos(theta), math.sin(theta)])
    v = f.velocity(q[None])[0]
    r_hat = np.array([math.cos(theta), math.sin(theta)])
    t_cw = np.array([r_hat[1], -r_hat[0]])
    assert v @ r_hat == pytest.approx(float(gain) * (radius - rho0), abs=1e-9)
    assert v @ t_cw == pytest.approx(1.0 if clockwise else -1.0, abs=1e-9)


def test_goal_field_is_unit_towards_the_goal():
    f = GoalField((Fraction(1), Fraction(1)))
    v = f.velocity(np.array([[4.0, 5.0]]))[0]
    assert np.allclose(v, [-0.6, -0.8])


# ---------------------------------------------------------------------- the exact sign and the verifier
@settings(max_examples=200)
@given(line_fields, st.tuples(coords, coords), points)
@example(_field((0, 0), (1, 1), Fraction(1)), (1, 0), (2, 0))  # n·w √L = −B exactly would need L a square: no tie
def test_exact_inward_sign_agrees_with_floats_away_from_zero(f, normal, q):
    n = tuple(map(Fraction, normal))
    value = float(np.array(normal, dtype=float) @ f.velocity(np.array([q], dtype=float))[0])
    sign = line_inward_sign(f, n, tuple(map(Fraction, q)))
    if abs(value) > 1e-9:
        assert sign == (1 if value > 0 else -1)


def test_exact_inward_sign_decides_an_exact_zero():
    # d = (3, 4)/5 (|w| rational); n = (−4, 3) ⊥ d; q on the line: n·v = 0 exactly
    f = LineField((Fraction(0), Fraction(0)), (Fraction(3), Fraction(4)), Fraction(1))
    assert line_inward_sign(f, (Fraction(-4), Fraction(3)), (Fraction(6), Fraction(8))) == 0
    assert line_inward_sign(f, (Fraction(3), Fraction(4)), (Fraction(6), Fraction(8))) == 1


def _box(w: int, h: int) -> Environment:
    return Environment.from_coords([(0, 0), (w, 0), (w, h), (0, h)], name="box")


@settings(max_examples=40)
@given(st.integers(1, 6), st.integers(1, 6), gains, st.integers(0, 3), st.integers(0, 3),
       st.tuples(st.fractions(0, 1, max_denominator=8), st.fractions(0, 1, max_denominator=8)))
def test_exact_flow_through_verdict_is_confirmed_by_the_dense_sample(w, h, gain, inlet, outlet, origin_t):
    """The exact (analytic) verifier's 'flows through' is never contradicted by sampled trajectories."""
    cell = decompose_free_space(_box(w, h)).cells[0]
    if inlet == outlet:
        return
    a, b = cell.sides[inlet].a, cell.sides[inlet].b
    origin = (a[0] + origin_t[0] * (b[0] - a[0]), a[1] + origin_t[0] * (b[1] - a[1]))
    target = cell.sides[outlet].midpoint
    if origin == target:
        return
    f = LineField(origin, target, gain)
    exact = line_flows_through(f, cell, {outlet})
    if exact.valid:
        assert dense_flows_through(f, cell, {outlet}, grid=10, per_side=10).valid


def test_flow_through_of_the_paper_field_in_a_straight_cell_and_its_failure_sideways():
    cell = decompose_free_space(load_environment("square")).cells[0]
    f = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, Fraction(3, 10))
    assert line_flows_through(f, cell, {2}).valid
    turn = LineField(cell.sides[0].midpoint, cell.sides[1].midpoint, Fraction(3, 10))
    check = line_flows_through(turn, cell, {1})
    assert not check.valid and check.failing_side == 0  # p·L = 3: the far end of the inlet is pulled back out
    assert not dense_flows_through(turn, cell, {1}, per_side=200).valid  # fails on the last 3 % of the inlet only


def test_arc_field_flows_through_a_corner_square_only_by_sample():
    from solverplan.reflection.fields import arc_turn

    cell = decompose_free_space(_box(1, 1)).cells[0]
    arc = arc_turn(cell, 0, 1, Fraction(4))
    assert arc is not None and arc.clockwise is True and arc.radius == pytest.approx(0.5)
    assert dense_flows_through(arc, cell, {1}).valid
    with pytest.raises(TypeError, match="use dense_flows_through"):
        line_flows_through(arc, cell, {1})  # type: ignore[arg-type]
    assert arc_turn(cell, 0, 2, Fraction(1)) is None  # opposite sides do not meet


# ---------------------------------------------------------------------- the symbolic proof can fail
@pytest.mark.slow  # sympy takes about 2 minutes to give up on the false identities
def test_line_field_proof_fails_for_a_wrong_sign(monkeypatch):
    real = line_proof.line_field_velocity

    def wrong(q, q0, d, p):  # cross-track term pushing away from the line
        return real(q, q0, d, -p)

    monkeypatch.setattr(line_proof, "line_field", wrong)
    failed = [s.claim for s in line_proof.prove().failed_steps]
    assert any("ė = −p e" in c for c in failed) and any("−∇φ" in c for c in failed)


def test_line_field_proof_fails_for_the_printed_eq4(monkeypatch):
    monkeypatch.setattr(line_proof, "zone_cost_corrected", line_proof.zone_cost_printed)
    failed = [s.claim for s in line_proof.prove().failed_steps]
    assert failed and all("Eq. 4" in c for c in failed)



@settings(max_examples=25)
@given(st.lists(st.tuples(st.integers(0, 20), st.integers(0, 20)), min_size=5, max_size=10, unique=True),
       st.integers(0, 9))
def test_fitted_line_field_flows_through_exactly_and_by_sample(points, outlet_pick):
    """fit_line_field's answer is verified exactly, and sampled trajectories agree."""
    from solverplan.reflection.fields import fit_line_field
    from tests.strategies import convex_hull

    hull = convex_hull(points)
    if len(hull) < 3:
        return
    cell = decompose_free_space(Environment.from_coords(hull, name="cell")).cells[0]
    outlet = outlet_pick % len(cell.sides)
    fitted = fit_line_field(cell, {outlet})
    if fitted is None:
        return
    field, check = fitted
    assert check.valid and check.method == "exact"
    assert dense_flows_through(field, cell, {outlet}, grid=8, per_side=8).valid


def test_fitted_line_field_rescues_a_cell_the_paper_fields_cannot_cross():
    from solverplan.reflection.compose import compose_fields

    plan = compose_fields(load_environment("hallway"), ("0.5", "1"), ("49.5", "1"))
    assert plan.flow_through and plan.proved
