"""The certificate writer (solverplan/certify/writer.py): float plans in, exactly verified certificates out."""

from __future__ import annotations

import math
import os
from fractions import Fraction

import pytest
from hypothesis import assume, example, given
from hypothesis import strategies as st

from solverplan.interval import Interval
from solverplan.bounce.partitions import partition
from solverplan.certify.check import check_certificate
from solverplan.certify.rational_atan import compare_angle, heading_vector
from solverplan.certify.schema import load_certificate
from solverplan.bounce.cones import heading_direction
from solverplan.certify.build import write_certificate
from solverplan.certify.writer import CycleSpec, MoveSpec, StageSpec, build_certificate
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from tests.certify.cases import MODELS
from tests.strategies import convex_polygons

SQUARE = load_environment(MODELS / "square.json")
SQUARE_P = partition(SQUARE)


def edge_vector(env: Environment, edge: int):
    e = env.edge(edge)
    return (e.b[0] - e.a[0], e.b[1] - e.a[1])


def assert_valid(cert, **kwargs):
    report = check_certificate(cert, **kwargs)
    assert report.valid, [str(f) for f in report.failures]
    return report


# ---------------------------------------------------------------------- directions
@pytest.mark.parametrize("theta", [1e-6, 0.1, 1.0, math.pi / 2, 2.5, math.pi - 1e-6])
@pytest.mark.parametrize("edge", [(Fraction(1), Fraction(0)), (Fraction(-3), Fraction(7, 2)), (Fraction(0), Fraction(-10))])
def test_heading_direction_has_the_heading_asked_for(theta, edge):
    d = heading_direction(edge, theta - 1e-10, theta + 1e-10)
    assert all(x.denominator == 1 for x in d) and math.gcd(int(d[0]), int(d[1])) == 1  # primitive integers
    w = heading_vector(edge, d)
    assert compare_angle(w, Fraction(theta) - Fraction(1, 10**10) - Fraction(1, 10**15)) == 1
    assert compare_angle(w, Fraction(theta) + Fraction(1, 10**10) + Fraction(1, 10**15)) == -1


def test_directions_lie_strictly_inside_the_interval_and_claims_are_recomputed():
    interval = Interval(0.1, 0.7)
    cert = build_certificate(SQUARE, SQUARE_P, [StageSpec(interval, (MoveSpec(source=0, target=1),))], start="e0", goal="e1")
    move = cert.stages[0].moves[0]
    w_lo, w_hi = heading_vector(edge_vector(SQUARE, 0), move.d_lo), heading_vector(edge_vector(SQUARE, 0), move.d_hi)
    assert compare_angle(w_lo, Fraction(0.1)) == 1 and compare_angle(w_hi, Fraction(0.7)) == -1  # strictly inside
    assert compare_angle(w_lo, Fraction(0.1) + Fraction(2, 10**9)) == -1  # ... by no more than the margin
    lo, hi = cert.stages[0].interval
    assert compare_angle(w_lo, lo) <= 0 and compare_angle(w_hi, hi) >= 0  # the claimed interval is inside the cone
    assert cert.claims.min_width == hi - lo and cert.claims.tolerance == (hi - lo) / 2
    assert abs(float(cert.claims.min_width) - 0.6) < 4e-9  # never more than was checked, and not much less
    assert cert.claims.bounces == 1 and cert.claims.sum_width == cert.claims.min_width
    assert move.target == (Fraction(0), Fraction(1)) and move.target_segment == 1 and move.source_segment == 0
    assert_valid(cert, expected_rings=SQUARE.rings, expected_start=[(0, 0, 1)], expected_goal=[(1, 0, 1)])


def test_belief_stage_gets_one_cone_per_source_edge():
    """Start on the bottom or the left edge: the same relative interval is a different world cone on each."""
    stages = [
        StageSpec(Interval(0.1, 0.7), (MoveSpec(0, 1), MoveSpec(3, 0))),
        StageSpec(Interval(0.1, 0.7), (MoveSpec(1, 2), MoveSpec(0, 1))),
    ]
    cert = build_certificate(SQUARE, SQUARE_P, stages, start="e0,e3", goal=[1, 2])
    m0, m1 = cert.stages[0].moves
    assert m0.d_lo != m1.d_lo
    assert (m1.d_lo[0], m1.d_lo[1]) == (m0.d_lo[1], -m0.d_lo[0])  # the left edge's frame is the bottom's turned by −90°
    assert_valid(cert)


def test_l_shape_plan_on_partition_segments():
    env = load_environment(MODELS / "l_shape.json")
    part = partition(env)
    stages = [
        StageSpec(Interval(1.55, 1.59), (MoveSpec((0, Fraction(1, 20), Fraction(7, 20)), 6),)),
        StageSpec(Interval(2.3, 3.0), (MoveSpec(6, 5),)),
    ]
    cert = build_certificate(env, part, stages, start="e0:0.05:0.35", goal="e3", objective="fewest")
    assert cert.stages[0].moves[0].source_segment == 0  # the sub-interval lies in segment 0
    assert [s.id for s in cert.segments] == [0, 5, 6]
    assert_valid(cert)


def test_obstructed_float_plan_gives_a_certificate_that_fails():
    """The writer does not judge: a float plan through the hole becomes a certificate that says so."""
    env = load_environment(MODELS / "one_hole.json")
    part = partition(env)
    cert = build_certificate(env, part, [StageSpec(Interval(1.5, 1.64), (MoveSpec(1, target_edge=2),))], start=[1], goal="e2")
    report = check_certificate(cert)
    assert not report.valid and report.failures[0].claim == "stages[0].moves[0].swept"


def test_exact_directions_for_a_singleton_interval():
    """Prop. 2's parallel case: bottom x ∈ [1, 9] → top only straight up; exact directions given."""
    spec = MoveSpec((0, "0.1", "0.9"), 2, directions=((0, 5), (0, 1)))
    cert = build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval(math.pi / 2, math.pi / 2), (spec,))], start="e0:0.1:0.9", goal="e2")
    assert cert.stages[0].moves[0].d_lo == (0, 1) and cert.claims.min_width == 0
    assert_valid(cert)


def test_funnel_positions_are_exact_images():
    spec = MoveSpec((0, "0.1", "0.9"), target_edge=2)
    cert = build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval(1.5, 1.64), (spec,))], start="e0:0.1:0.9", goal="e2", kind="funnel")
    move = cert.stages[0].moves[0]
    assert move.target_segment is None and 0 < move.target[0] < move.target[1] < 1
    assert cert.stages[0].positions[0].edge == 2 and (cert.stages[0].positions[0].t0, cert.stages[0].positions[0].t1) == move.target
    assert_valid(cert)


def test_square_limit_cycle_fixed_point_and_contraction():
    """Theorem 1 in the square: period 4, per bounce t ↦ (1 − t)·tan θ, fixed point tan θ / (1 + tan θ)."""
    stages = [StageSpec(Interval(0.1, 0.25), (MoveSpec(k, (k + 1) % 4),)) for k in range(4)]
    cert = build_certificate(SQUARE, SQUARE_P, stages, start="e0", kind="cycle", cycle=CycleSpec(0, headings=(0.2,) * 4, visits=(0, 2)))
    cycle = cert.cycle
    c = Fraction(cycle.nominal[0][1], cycle.nominal[0][0])  # tan θ of the nominal direction on edge 0
    assert cycle.alpha == c**4 and cycle.fixed_point == c / (1 + c)
    assert abs(float(c) - math.tan(0.2)) < 1e-11
    d_hi = cert.stages[0].moves[0].d_hi
    assert cycle.contraction == Fraction(d_hi[1], d_hi[0]) ** 4  # worst case: the steepest heading, tan θ_hi
    assert cycle.contraction < 1
    assert_valid(cert)


def test_write_certificate_is_atomic_and_round_trips(tmp_path):
    cert = build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval(0.1, 0.7), (MoveSpec(0, 1),))], start="e0", goal="e1")
    path = tmp_path / "plan.cert.json"
    write_certificate(cert, path)
    assert load_certificate(path) == cert
    assert os.listdir(tmp_path) == ["plan.cert.json"]
    assert "0.1" not in path.read_text().split('"rings"')[0]  # exact numbers only: ints and strings
    with pytest.raises(FileNotFoundError):
        write_certificate(cert, tmp_path / "missing" / "x.json")
    assert os.listdir(tmp_path) == ["plan.cert.json"]


def test_writer_rejects_bad_input():
    with pytest.raises(InputError, match="unknown segment 9"):
        build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval(0.1, 0.7), (MoveSpec(9, 1),))], start="e0", goal="e1")
    with pytest.raises(InputError, match="empty"):
        build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval.EMPTY, (MoveSpec(0, 1),))], start="e0", goal="e1")
    with pytest.raises(InputError, match="not inside"):
        build_certificate(SQUARE, SQUARE_P, [StageSpec(Interval(0.0, 0.7), (MoveSpec(0, 1),))], start="e0", goal="e1")


# ---------------------------------------------------------------------- Prop. 2 on convex polygons
def _ang(v, base) -> float:
    """Heading of v CCW from base, in [0, 2π) (floats: the planner's side)."""
    a = math.atan2(base[0] * v[1] - base[1] * v[0], base[0] * v[0] + base[1] * v[1])
    return a if a >= 0 else a + 2 * math.pi


def prop2_interval(env: Environment, i: int, j: int) -> tuple[float, float]:
    """Prop. 2 / Cor. 1: θ_lo = ang(c − b), θ_hi = ang(d − a) for source (a, b) and target (c, d)."""
    a, b = (float(x) for x in env.edge(i).a), (float(x) for x in env.edge(i).b)
    a, b = tuple(a), tuple(b)
    c, d = (tuple(float(x) for x in p) for p in (env.edge(j).a, env.edge(j).b))
    base = (b[0] - a[0], b[1] - a[1])
    lo = 0.0 if c == b else _ang((c[0] - b[0], c[1] - b[1]), base)
    hi = math.pi if d == a else _ang((d[0] - a[0], d[1] - a[1]), base)
    return lo, hi


SQUARE_INTEGER = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])


@given(
    env=convex_polygons(),
    pick=st.tuples(st.integers(0, 10**6), st.integers(1, 10**6)),
    cut=st.tuples(st.floats(0.0, 0.45), st.floats(0.0, 0.45)),
    grow=st.floats(1e-3, 0.3),
)
@example(env=SQUARE_INTEGER, pick=(0, 1), cut=(0.1, 0.1), grow=0.1)  # adjacent, Cor. 1
@example(env=SQUARE_INTEGER, pick=(1, 3), cut=(0.0, 0.2), grow=0.05)  # towards e_{i−1}
def test_prop2_safe_interval_certificates_verify_and_wider_ones_fail(env, pick, cut, grow):
    n = env.n_edges
    i = pick[0] % n
    j = (i + 1 + pick[1] % (n - 1)) % n
    lo, hi = prop2_interval(env, i, j)
    assume(hi - lo > 1e-6)
    width = hi - lo
    inner = Interval(lo + cut[0] * width + 1e-9, hi - cut[1] * width - 1e-9)
    part = partition(env)
    assert len(part) == n  # convex: P′ is the polygon's own edges
    stage = StageSpec(inner, (MoveSpec(i, j),))
    cert = build_certificate(env, part, [stage], start=f"e{i}", goal=f"e{j}")
    assert_valid(cert, expected_rings=env.rings)
    assert float(cert.claims.min_width) <= inner.width and float(cert.claims.min_width) >= inner.width - 4e-9

    # widened beyond Prop. 2 on a side that is not 0 or π: a corner ray leaves the target
    if lo - grow > 1e-6:
        wide = Interval(lo - grow, hi - cut[1] * width - 1e-9)
    elif hi + grow < math.pi - 1e-6:
        wide = Interval(lo + cut[0] * width + 1e-9, hi + grow)
    else:
        return
    bad = build_certificate(env, part, [StageSpec(wide, (MoveSpec(i, j),))], start=f"e{i}", goal=f"e{j}")
    report = check_certificate(bad)
    assert not report.valid
    assert report.failures[0].claim in ("stages[0].moves[0].d_lo", "stages[0].moves[0].d_hi")
