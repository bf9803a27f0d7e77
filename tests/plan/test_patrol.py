"""Patrolling (paper Def. 15) with optimally contracting cycles: objectives (a) contraction, (b) tolerance,
(c) rate; Theorem 1 reproduced; LP against Karp against brute force; certificates; rollouts; the CLI."""

from __future__ import annotations

import json
import math
from fractions import Fraction
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.bounce.cycles import limit_cycle
from solverplan.bounce.dynamics import contraction_coefficient, interior_angles, lemma3_max_heading
from solverplan.bounce.partitions import partition
from solverplan.certify.check import check_certificate
from solverplan.certify.build import certificate
from solverplan.certify.schema import Certificate
from solverplan.environment import load_environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.plan._choices import arc_choices
from solverplan.plan._graphs import find_negative_cycle, karp_min_mean_cycle, lp_min_mean_cycle
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN, Margins
from solverplan.plan.patrols import patrol
from solverplan.simulate import StagePolicy, simulate_policy

MODELS = Path(__file__).resolve().parent.parent.parent / "solverplan" / "models"
CONVEX = ["square", "triangle", "hexagon", "irregular_convex"]
runner = CliRunner()


def env_of(name: str):
    return load_environment(MODELS / f"{name}.json")


def all_edges(env) -> str:
    return ",".join(f"e{k}" for k in range(env.n_edges))


# ---------------------------------------------------------------------- Theorem 1 on convex models
@pytest.mark.parametrize("name", CONVEX)
@pytest.mark.parametrize("objective", ["contraction", "rate"])
def test_theorem1_patrol_over_all_edges_is_the_constant_heading_limit_cycle(name, objective):
    """Every arc e_i → e_{i+1} of a convex polygon has safe interval (0, ang(d − a)] (Cor. 1), so the best
    2ε interval is the same (μ, μ + 2ε] on every arc: a constant rule, whose cycle is Theorem 1's — exactly."""
    env = env_of(name)
    eps = 0.3 * lemma3_max_heading(env) / 2
    p = patrol(env, all_edges(env), objective=objective, tolerance=eps)
    assert p.status == "found" and p.max_between == 0 and p.periods == 1
    assert [s.step.from_edge for s in p.cycle] == list(range(env.n_edges))
    thetas = {s.step.heading for s in p.cycle}
    assert len(thetas) == 1  # one constant heading
    theta = thetas.pop()
    assert theta == pytest.approx(DEFAULT_HEADING_MARGIN + eps, abs=1e-12)  # [δ, δ + 2ε]: δ off the wall
    cycle = limit_cycle(env, theta)
    assert cycle.found and cycle.edges == tuple(range(env.n_edges))
    assert [q.t for q in cycle.points] == [q.t for q in p.points]  # the same exact fixed point orbit
    assert cycle.contraction_exact == abs(p.nominal_alpha)
    assert 0 < p.contraction < 1


@pytest.mark.parametrize("name", CONVEX)
def test_objective_rate_is_at_least_as_contracting_as_every_constant_heading(name):
    """Objective (c) against a sweep of constant headings θ, each with the same tolerance: the worst case of the
    constant cycle over [θ − ε, θ + ε] is never better per bounce, nor is its nominal contraction."""
    env = env_of(name)
    eps = 0.02
    p = patrol(env, all_edges(env), objective="rate", tolerance=eps)
    n = env.n_edges
    phi = interior_angles(env)
    corners = [phi[(k + 1) % n] for k in range(n)]  # e_k → e_{k+1} turns at v_{k+1}
    nominal_rate = float(abs(p.nominal_alpha)) ** (1 / n)
    top = lemma3_max_heading(env)
    checked = 0
    for theta in np.linspace(eps + DEFAULT_HEADING_MARGIN, top - eps, 40):
        worst = np.prod([contraction_coefficient(theta + eps, f, "right") for f in corners]) ** (1 / n)
        assert worst >= p.rate * (1 - 1e-9)
        cycle = limit_cycle(env, float(theta))
        if cycle.found:
            assert float(cycle.contraction_exact) ** (1 / n) >= nominal_rate * (1 - 1e-9)
            checked += 1
    assert checked >= 30


def test_objective_rate_lp_and_karp_agree_and_bound_every_class():
    env = env_of("two_rooms")
    p = patrol(env, "e0,e5", objective="rate", tolerance=0.01)
    assert p.found and p.optimality.method == "lp-duality" and p.optimality.proved
    assert p.solvers["lp"] == pytest.approx(p.solvers["karp"], abs=1e-6)
    assert math.log(p.rate) == pytest.approx(p.solvers["karp"], abs=1e-6)
    assert p.optimality.gap >= 0
    # more intermediate bounces can only help (the classes are nested)
    wider = patrol(env, "e0,e5", objective="rate", tolerance=0.01, max_between=p.max_between + 1)
    assert wider.rate <= p.rate * (1 + 1e-9)


# ---------------------------------------------------------------------- the solvers against brute force
@pytest.mark.parametrize("seed", range(6))
def test_karp_and_lp_find_the_minimum_mean_cycle_of_random_graphs(seed):
    rng = np.random.default_rng(seed)
    n, m = 7, 16
    src, dst = rng.integers(0, n, m), rng.integers(0, n, m)
    w = rng.normal(size=m)
    g = nx.MultiDiGraph()
    for k, (u, v) in enumerate(zip(src.tolist(), dst.tolist())):
        g.add_edge(u, v, key=k)
    best = math.inf
    simple = nx.DiGraph()
    for k in np.argsort(w):  # the cheapest of parallel arcs is the one on an optimal cycle
        if not simple.has_edge(int(src[k]), int(dst[k])):
            simple.add_edge(int(src[k]), int(dst[k]), w=float(w[k]))
    for cyc in nx.simple_cycles(simple):
        arcs = list(zip(cyc, cyc[1:] + cyc[:1]))
        best = min(best, sum(simple[u][v]["w"] for u, v in arcs) / len(arcs))
    if best == math.inf:
        return
    lam, cycle = karp_min_mean_cycle(n, src, dst, w)
    assert lam == pytest.approx(best, abs=1e-9)
    assert np.mean(w[cycle]) == pytest.approx(best, abs=1e-7)
    assert all(dst[a] == src[b] for a, b in zip(cycle, cycle[1:] + cycle[:1]))
    lp, lp_cycle, _ = lp_min_mean_cycle(n, src, dst, w)
    assert lp == pytest.approx(best, abs=1e-6)
    assert np.mean(w[lp_cycle]) == pytest.approx(best, abs=1e-6)


def test_negative_cycle_detection():
    src, dst = np.array([0, 1, 2, 2]), np.array([1, 2, 0, 3])
    assert find_negative_cycle(4, src, dst, np.array([1.0, 1.0, -1.0, -5.0])) is None
    cycle = find_negative_cycle(4, src, dst, np.array([1.0, 1.0, -2.5, -5.0]))
    assert sorted(cycle) == [0, 1, 2]


def test_objective_contraction_is_the_best_one_period_walk_by_brute_force():
    """(a) by dynamic programming against every one-period walk of the class, enumerated."""
    env = env_of("l_shape")
    visit = (0, 2, 4)
    eps = 0.02
    p = patrol(env, "e0,e2,e4", objective="contraction", tolerance=eps, max_between=1)
    assert p.found and p.optimality.method == "search-exhausted" and p.optimality.proved
    assert "one-period" in p.optimality.scope and p.optimality.gap == pytest.approx(0.0, abs=1e-12)
    ch = arc_choices(safe_bounce_visibility_graph(partition(env)), eps, Margins.for_environment(env))
    part = partition(env)
    out: dict[int, list[tuple[int, float]]] = {}
    for s, t, w in zip(ch.source.tolist(), ch.target.tolist(), ch.weight.tolist()):
        out.setdefault(s, []).append((t, w))
    best = math.inf

    def walk(anchor, seg, q, h, total):  # q: required visits made after the anchor
        nonlocal best
        for t, w in out.get(seg, ()):
            edge = int(part.seg_edge[t])
            if edge == visit[(q + 1) % 3]:
                if q + 1 == 3:
                    if t == anchor:
                        best = min(best, total + w)
                    continue
                walk(anchor, t, q + 1, 0, total + w)
            elif h < 1:
                walk(anchor, t, q, h + 1, total + w)

    for anchor in part.edge_segments[0]:
        walk(anchor, anchor, 0, 0, 0.0)
    assert math.log(p.contraction) == pytest.approx(best, abs=1e-6)


def test_objective_tolerance_finds_the_widest_contracting_intervals_of_the_square():
    """Square: arcs e_i → e_{i+1} have safe interval (0, π/4] and C(θ) = tan θ; the widest interval that still
    contracts is all of it that the margins leave, [δ, π/4 − max(μ, κ/D)], so ε* is half of that."""
    env = env_of("square")
    p = patrol(env, "e0,e1,e2,e3", objective="tolerance")
    assert p.found and p.optimality.method == "bisection"
    lo, hi = p.solvers["bracket"]
    assert hi - lo < 1e-8
    margins = Margins.for_environment(env)
    assert p.tolerance == pytest.approx((math.pi / 4 - margins.end_margin - margins.heading_margin) / 2, abs=1e-8)
    assert p.contraction < 1
    check = patrol(env, "e0,e1,e2,e3", objective="contraction", tolerance=hi + 1e-6)
    assert check.status == "infeasible"


# ---------------------------------------------------------------------- start sets, certificates, rollouts
@pytest.mark.parametrize("name,visit,start,objective", [
    ("square", "e0,e1,e2,e3", "e2", "contraction"),
    ("irregular_convex", "e0,e2,e4", None, "rate"),
    ("two_rooms", "e0,e5", "e0", "rate"),
    ("l_shape", "e0,e2,e4", "e1:0.2:0.8", "tolerance"),
])
def test_patrol_certificates_verify_and_tampered_ones_fail(name, visit, start, objective):
    env = env_of(name)
    p = patrol(env, visit, start=start, objective=objective, tolerance=0.02)
    assert p.found
    cert = certificate(p)
    report = check_certificate(cert, expected_rings=env.rings)
    assert report.valid, report.failures
    assert cert.cycle.contraction < 1 and cert.cycle.visits == p.visit
    assert float(cert.cycle.contraction) == pytest.approx(p.contraction, rel=1e-6)
    data = cert.to_json()
    for path, value in [(("cycle", "contraction"), "1/1000000000000"), (("cycle", "fixed_point"), "1/3"),
                        (("cycle", "alpha"), "1/2"), (("cycle", "visits"), list(reversed(p.visit)) + [p.visit[0]])]:
        bad = json.loads(json.dumps(data))
        bad[path[0]][path[1]] = value
        assert not check_certificate(Certificate.from_json(bad)).valid, path
    bad = json.loads(json.dumps(data))
    move = bad["stages"][-1]["moves"][0]
    move["d_hi"] = [str(Fraction(move["d_hi"][0]) * 3), move["d_hi"][1]]  # widen a cone
    assert not check_certificate(Certificate.from_json(bad)).valid


def test_ten_thousand_rollouts_enter_and_follow_the_patrol_cycle():
    env = env_of("two_rooms")
    p = patrol(env, "e0,e5", start="e0", objective="rate", tolerance=0.01, epsilon=0.05)
    stages, targets, repeat = p.rollout_spec()
    bounces = len(p.entry) + 12 * len(p.cycle)
    runs = simulate_policy(env, StagePolicy(stages, targets, repeat_from=repeat), "e0", bounces=bounces,
                           trials=10_000, seed=6, ties="exact", record="ends")
    assert runs.outcome_counts() == {"ok": 10_000, "goal": 0, "failed": 0, "vertex": 0, "tie": 0}
    # after whole cycles every robot is on the first cycle segment, inside the attractor around the fixed point
    first = p.points[0]
    assert np.all(runs.final_edge == first.edge)
    spread = (runs.final_t.max() - runs.final_t.min()) * float(env.edge_lengths[first.edge])
    assert spread <= p.attractor + 1e-9
    assert p.cycles_to_epsilon is not None


def test_patrol_from_a_start_set_only_uses_reachable_cycles_and_says_infeasible_otherwise():
    env = env_of("narrow_door")
    p = patrol(env, "e0,e4", tolerance=0.01)  # one edge in each room: no safe arc crosses the doorway
    assert p.status == "infeasible" and "e0, e4" in p.reason and p.optimality.proved
    q = patrol(env, "e0,e10", start="e4", tolerance=0.01)
    assert q.status == "infeasible"


def test_patrol_rejects_bad_input():
    env = env_of("square")
    with pytest.raises(InputError, match="unknown patrol objective 'fast'"):
        patrol(env, "e0,e1", objective="fast")
    with pytest.raises(InvalidBoundarySet, match="unknown edge e9"):
        patrol(env, "e0,e9")
    with pytest.raises(InvalidBoundarySet, match="whole edges"):
        patrol(env, "e0:0:0.5,e1")
    with pytest.raises(InputError, match="tolerance"):
        patrol(env, "e0,e1", tolerance=2.0)


# ---------------------------------------------------------------------- the CLI
def test_cli_patrol_answers_with_a_verified_certificate(tmp_path):
    cert = tmp_path / "patrol.cert.json"
    picture = tmp_path / "patrol.png"
    result = runner.invoke(cli.app, ["patrol", str(MODELS / "irregular_convex.json"), "--visit", "e0,e1,e2,e3,e4,e5,e6",
                                     "--objective", "rate", "--tolerance", "0.02", "--epsilon", "0.5",
                                     "--certificate", str(cert), "--picture", str(picture)])
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["objective"] == "rate"
    assert len(answer["cycle"]) == 7 and answer["entry"] == []
    assert 0 < answer["contraction"] < 1 and answer["contraction_exact"]
    assert {"edge", "t", "point"} <= set(answer["fixed_point"][0])
    assert answer["optimality"]["method"] == "lp-duality" and answer["optimality"]["proved"]
    assert answer["cycles_to_epsilon"] is not None
    verify = runner.invoke(cli.app, ["verify", str(cert)])
    assert verify.exit_code == 0, verify.stderr
    assert picture.stat().st_size > 1000


def test_cli_patrol_infeasible_is_an_answer_and_bad_input_exits_2():
    result = runner.invoke(cli.app, ["patrol", str(MODELS / "narrow_door.json"), "--visit", "e0,e4"])
    assert result.exit_code == 0 and json.loads(result.stdout)["status"] == "infeasible"
    bad = runner.invoke(cli.app, ["patrol", str(MODELS / "square.json"), "--visit", "e0,e7"])
    assert bad.exit_code == 2 and bad.stderr.strip() == "error: unknown edge e7: edges are e0..e3"
