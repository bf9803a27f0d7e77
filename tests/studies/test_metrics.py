"""Study metrics: the paper's reachability and connectivity on the safe BVG, and §8.2's rule systems."""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest

from solverplan.bounce.rules import Fixed, MonotoneFixed
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.simulate import simulate_rule
from solverplan.studies import ConnectivityMetric, ReachabilityMetric, RuleReachability
from solverplan.generators import star_polygon
from solverplan.generators import rectilinear_floor_plan, rooms_and_corridors
from solverplan.studies.metrics import component_counts, safe_graph_summary, unreachable_fraction
from solverplan.studies.rule_systems import FamilyPolicy, guaranteed_arcs, parse_family

SQUARE = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])

ENVIRONMENTS = [
    star_polygon(20, 0.4, 0.5, seed=0),
    star_polygon(20, 0.25, 0.3, seed=3),
    star_polygon(20, 0.4, 0.5, seed=3),
    rooms_and_corridors(4, loops=1, seed=1),
    rectilinear_floor_plan(3, pillars=1, seed=2),
]


def test_square_is_fully_reachable_and_strongly_connected():
    assert ReachabilityMetric()(SQUARE)["unreachable"] == 0.0
    assert ConnectivityMetric()(SQUARE) == {"segments": 4, "arcs": 12, "safe_arcs": 12, "scc": 1, "wcc": 1, "largest_scc": 1.0}


def test_unreachable_fraction_and_components_on_small_graphs():
    lengths = np.array([1.0, 1.0, 2.0, 4.0])
    assert unreachable_fraction(lengths, np.array([0, 1, 2]), np.array([1, 2, 2])) == (2, 0.625)  # a self-loop is no way in
    assert component_counts(4, np.array([0, 1, 2]), np.array([1, 0, 3]), lengths) == {"scc": 3, "wcc": 2, "largest_scc": 0.5}
    assert component_counts(0, np.array([]), np.array([])) == {"scc": 0, "wcc": 0, "largest_scc": 0.0}


@pytest.mark.parametrize("env", ENVIRONMENTS, ids=lambda e: e.name[:40])
def test_metrics_agree_with_networkx_on_the_safe_bvg(env):
    """The array computations against the documented networkx view of the safe BVG (paper §7.3–7.4)."""
    summary = safe_graph_summary(env)
    g = summary.graph.to_networkx(safe_only=True)
    no_incoming = [v for v in g.nodes if g.in_degree(v) == 0]
    expected = sum(summary.lengths[v] for v in no_incoming) / summary.lengths.sum()
    reach = ReachabilityMetric()(env)
    assert reach["unreachable_segments"] == len(no_incoming)
    assert reach["unreachable"] == pytest.approx(expected, abs=1e-15)
    assert reach["unreachable"] <= reach["unreachable_nonadjacent"]
    conn = ConnectivityMetric()(env)
    assert conn["scc"] == nx.number_strongly_connected_components(g)
    assert conn["wcc"] == nx.number_weakly_connected_components(g)
    assert abs(summary.lengths.sum() - env.perimeter) < 1e-9 * env.perimeter


# ---------------------------------------------------------------------- rule families
def test_families_parse():
    assert [round(r.theta, 6) for r in parse_family("relative", family_size=2).members] == [1.047198, 2.094395]
    assert parse_family(" Any ").is_free and len(parse_family("specular").members) == 1
    with pytest.raises(InputError, match=r"^rule family 'specular:1': specular takes no angle$"):
        parse_family("specular:1")
    with pytest.raises(InputError, match=r"^expected family_size >= 1, got family_size=0$"):
        parse_family("fixed", family_size=0)
    with pytest.raises(InputError, match=r"^unknown rule family 'billiard'"):
        RuleReachability(("any", "billiard"))


@pytest.mark.parametrize("env", ENVIRONMENTS, ids=lambda e: e.name[:40])
def test_guaranteed_systems_nest_inside_the_safe_bvg(env):
    summary = safe_graph_summary(env)
    safe = summary.graph.safe
    assert np.array_equal(guaranteed_arcs(summary, parse_family("any")), safe)
    fixed = guaranteed_arcs(summary, parse_family("fixed"))
    assert not np.any(fixed & ~safe) and np.count_nonzero(fixed) > 0
    for spec in ("specular", "relative"):
        assert not guaranteed_arcs(summary, parse_family(spec)).any()
    third = guaranteed_arcs(summary, parse_family("fixed:pi/3"))  # θ = π/3 is the 2nd of the 5 family members
    assert not np.any(third & ~fixed)


@pytest.mark.parametrize("env", [ENVIRONMENTS[1], ENVIRONMENTS[4]], ids=lambda e: e.name[:40])
@pytest.mark.parametrize("spec", ["fixed", "monotone"])
def test_guaranteed_arcs_are_guaranteed_by_simulation(env, spec):
    """Ground truth: every robot on segment i that executes a heading the rule may pick lands on j."""
    summary = safe_graph_summary(env)
    graph, p = summary.graph, summary.graph.partition
    family = parse_family(spec)
    rng = np.random.default_rng(0)
    checked = 0
    for rule in family.members:
        keep = guaranteed_arcs(summary, type(family)(spec, (rule,)))
        for k in np.flatnonzero(keep)[::7]:
            i, j = int(graph.source[k]), int(graph.target[k])
            seg = p.segments[i]
            t = float(seg.t0) + (float(seg.t1) - float(seg.t0)) * rng.uniform(0.01, 0.99, size=20)
            edges = np.full(20, seg.edge)
            headings = [rule.theta] if isinstance(rule, Fixed) else [rule.theta, math.pi - rule.theta]
            tangent = np.asarray(env.edge_end[seg.edge] - env.edge_start[seg.edge], dtype=float)
            if isinstance(rule, MonotoneFixed) and tangent[0] == 0:
                headings = [rule.theta]
            for theta in headings:
                runs = simulate_rule(env, Fixed(theta), (edges, t), bounces=1, initial=[theta], seed=1)
                landed = runs.segments(p)[:, 1]
                assert np.all(landed == j), (i, j, theta, landed)
                checked += 1
    assert checked > 0


def test_family_policy_runs_member_k_mod_m_on_robot_k():
    from solverplan.simulate import Contacts

    family = parse_family("fixed", family_size=3)
    contacts = Contacts(SQUARE, 1, np.arange(6), np.zeros(6, dtype=np.int64), np.full(6, 0.5),
                        np.tile([2.0, 0.0], (6, 1)), np.tile([0.0, -1.0], (6, 1)))
    headings = FamilyPolicy(family).headings(contacts, np.random.default_rng(0))
    assert headings.tolist() == pytest.approx([r.theta for r in family.members] * 2)


def test_rule_reachability_is_reproducible_and_in_range():
    env = ENVIRONMENTS[1]
    metric = RuleReachability(trials=40, bounces=20)
    rows = {spec: metric(env, seed=11, rule=spec) for spec in metric.families}
    assert rows["fixed"] == metric(env, seed=11, rule="fixed")
    assert rows["any"]["guaranteed_arcs"] == rows["any"]["safe_arcs"]
    assert rows["any"]["unreachable"] == pytest.approx(ReachabilityMetric()(env)["unreachable"])
    assert rows["specular"]["unreachable"] == 1.0 and rows["specular"]["scc"] == rows["specular"]["segments"]
    for row in rows.values():
        assert set(row) == set(RuleReachability.columns)
        assert 0 <= row["recurrent"] <= row["coverage"] <= row["visited"] <= 1 + 1e-12
        assert 0 <= row["flagged"] <= 1
    assert rows["fixed"]["unreachable"] >= rows["any"]["unreachable"]
