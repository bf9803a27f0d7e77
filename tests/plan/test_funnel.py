"""Funnels (paper Fig. 14): exact position sets shrunk by contraction through a doorway no safe-BVG plan passes."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.bounce.partitions import partition
from solverplan.bounce.transitions import transition_set
from solverplan.certify.check import check_certificate
from solverplan.certify.build import certificate
from solverplan.certify.schema import Certificate
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.plan import find_plan
from solverplan.plan._positions import Flat, _merged_images, _Reached, merge_pieces
from solverplan.plan.funnels import funnel, safe_plan_exists
from solverplan.simulate import StagePolicy, simulate_policy

MODELS = Path(__file__).resolve().parent.parent.parent / "solverplan" / "models"
runner = CliRunner()


@pytest.fixture(scope="module")
def door():
    env = load_environment(MODELS / "narrow_door.json")
    return env, safe_bounce_visibility_graph(partition(env))


@pytest.fixture(scope="module")
def door_funnel(door):
    env, graph = door
    return funnel(env, "e0", "e4", graph=graph)


def test_no_safe_bvg_plan_crosses_the_narrow_door(door):
    """The only safe arcs through the doorway join the two 0.2-wide strips of the far walls that line up with it
    (segments on e11 and e5, heading exactly π/2: zero width); no other segment reaches them."""
    env, graph = door
    part = graph.partition
    left_edges, right_edges = {0, 1, 9, 10, 11}, {3, 4, 5, 6, 7}
    crossing = [(int(s), int(t)) for s, t, n in zip(graph.source, graph.target, graph.n_intervals)
                if n and ((part.seg_edge[s] in left_edges) != (part.seg_edge[t] in left_edges))
                and part.seg_edge[s] in left_edges | right_edges and part.seg_edge[t] in left_edges | right_edges]
    assert crossing
    for s, t in crossing:
        interval = graph.interval(s, t)
        assert interval.width == 0 and interval.lo == pytest.approx(np.pi / 2)
    g = graph.to_networkx(safe_only=True)
    strips = {s for arc in crossing for s in arc}
    for s in part.edge_segments[0]:
        assert not (nx.descendants(g, s) & strips)
    assert not safe_plan_exists(graph, env.boundary_set("e0"), env.boundary_set("e4"))
    for objective in ("fewest", "tolerance"):
        plan = find_plan(env, "e0", "e4", objective=objective, graph=graph)
        assert plan.status == "infeasible" and plan.optimality.proved and plan.reason


def test_a_funnel_passes_the_narrow_door_and_its_certificate_verifies(door, door_funnel):
    env, _ = door
    f = door_funnel
    assert f.status == "found" and f.safe_plan is False
    widths = f.widths
    assert widths[0] == 10 and widths[-1] < 0.2
    assert min(widths) < 0.2  # shrunk below the doorway's width before passing it
    cert = certificate(f)
    report = check_certificate(cert, expected_rings=env.rings, expected_start=[(0, Fraction(0), Fraction(1))],
                               expected_goal=[(4, Fraction(0), Fraction(1))])
    assert report.valid, report.failures
    claimed = [tuple((p.edge, p.t0, p.t1) for p in s.positions) for s in cert.stages]
    assert claimed == [tuple((p.edge, p.t0, p.t1) for p in st.positions) for st in f.stages]


def test_funnel_positions_are_the_exact_images_of_the_sources(door_funnel):
    f = door_funnel
    env = f.env
    current = f.start.pieces
    for st in f.stages:
        assert st.sources == tuple(current)
        images = []
        for piece, cone in zip(st.sources, st.cones):
            images += transition_set(env, piece, cone)
        assert tuple(sorted(images, key=lambda p: (p.edge, p.t0))) == st.positions
        current = st.positions


def test_ten_thousand_rollouts_of_the_door_funnel_all_reach_the_goal(door_funnel):
    f = door_funnel
    stages, targets, goal = f.rollout_spec()
    for sampling, seed in (("uniform", 11), ("endpoints", 12)):
        runs = simulate_policy(f.env, StagePolicy(stages, targets, goal=goal, sampling=sampling), "e0",
                               bounces=len(stages), trials=10_000, seed=seed, ties="exact")
        assert runs.outcome_counts() == {"ok": 0, "goal": 10_000, "failed": 0, "vertex": 0, "tie": 0}, sampling


def test_tampered_funnel_certificates_fail(door_funnel):
    data = certificate(door_funnel).to_json()
    cases = []
    bad = json.loads(json.dumps(data))
    bad["stages"][1]["positions"][0]["t1"] = "1/2"
    cases.append(bad)
    bad = json.loads(json.dumps(data))
    move = bad["stages"][2]["moves"][0]
    move["d_lo"] = [str(Fraction(move["d_lo"][0]) * 2), move["d_lo"][1]]
    cases.append(bad)
    bad = json.loads(json.dumps(data))
    bad["stages"][2]["moves"][0]["source"][1] = "1/2"
    cases.append(bad)
    bad = json.loads(json.dumps(data))
    bad["goal"] = [{"edge": 4, "t0": 0, "t1": "1/2"}]
    cases.append(bad)
    for case in cases:
        assert not check_certificate(Certificate.from_json(case)).valid


def test_dominance_and_merging():
    assert merge_pieces([(3, 0.5, 0.7), (1, 0.1, 0.2), (3, 0.6, 0.9), (3, 0.95, 1.0)]) == (
        (1, 0.1, 0.2), (3, 0.5, 0.9), (3, 0.95, 1.0))
    reached = _Reached(4)
    reached.add(((2, 0.4, 0.5),))
    assert reached.dominated(((2, 0.3, 0.6),))  # contains an earlier state: any plan from that works
    assert reached.dominated(((1, 0.0, 0.1), (2, 0.3, 0.6)))  # one of its pieces does
    assert not reached.dominated(((2, 0.45, 0.6),))
    assert not reached.dominated(((3, 0.3, 0.6),))
    reached.add(((1, 0.1, 0.2), (3, 0.5, 0.6)))
    assert reached.dominated(((1, 0.0, 0.3), (3, 0.4, 0.7)))
    assert reached.dominated(((1, 0.0, 0.3), (3, 0.4, 0.45), (3, 0.5, 0.7)))  # several pieces on one edge
    assert not reached.dominated(((1, 0.0, 0.3), (3, 0.4, 0.55), (3, 0.57, 0.7)))  # hull fits, pieces do not
    assert not reached.dominated(((1, 0.15, 0.3), (3, 0.4, 0.7)))


def test_flat_merging_is_merge_pieces_per_candidate():
    """The vectorised state building merges each candidate's images exactly as merge_pieces does."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        n_cand = int(rng.integers(1, 6))
        rc = np.sort(rng.integers(0, n_cand, size=int(rng.integers(1, 12))))
        tgt = rng.integers(0, 3, size=len(rc))
        lo = np.round(rng.random(len(rc)), 1)  # coarse values: touching and nested pieces are common
        hi = np.minimum(lo + np.round(rng.random(len(rc)) * 0.4, 1), 1.0)
        good = rng.random(n_cand) < 0.8
        flat = _merged_images(rc, tgt, lo, hi, good)
        starts = flat.starts
        for c in range(n_cand):
            got = tuple(zip(flat.edge[starts[c]:starts[c + 1]].tolist(), flat.lo[starts[c]:starts[c + 1]].tolist(),
                            flat.hi[starts[c]:starts[c + 1]].tolist()))
            rows = np.flatnonzero(rc == c)
            expected = merge_pieces([(int(tgt[r]), float(lo[r]), float(hi[r])) for r in rows]) if good[c] else ()
            assert got == expected
    batch = Flat.of([((1, 0.1, 0.2), (1, 0.3, 0.5), (4, 0.0, 0.1)), ((2, 0.5, 0.6),)])
    owner, edge, lo, hi = batch.hulls()
    assert owner.tolist() == [0, 0, 1] and edge.tolist() == [1, 4, 2] and lo.tolist() == [0.1, 0.0, 0.5]
    assert hi.tolist() == [0.5, 0.1, 0.6] and batch.edge_counts().tolist() == [2, 1]


def test_funnel_into_a_short_goal_of_the_square_uses_contraction():
    square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
    f = funnel(square, "e0", "e2:0.45:0.55", tolerance=0.005)
    assert f.found and f.safe_plan is False and f.widths[-1] < 0.4
    assert check_certificate(certificate(f)).valid


def test_funnel_not_found_is_an_answer_and_bad_input_raises(door):
    env, graph = door
    f = funnel(env, "e0", "e4", max_bounces=2, graph=graph)
    assert f.status == "not-found" and "heuristic" in f.reason and not f.optimality.proved
    assert f.status.incomplete and f.optimality.method == "heuristic"
    assert f.optimality.limits == ("max_bounces=2", "beam=400", "n_headings=240", "max_rows=250000", "cut=max_bounces")
    with pytest.raises(InputError, match="unknown edge e99"):
        funnel(env, "e0", "e99")
    with pytest.raises(InputError, match="tolerance"):
        funnel(env, "e0", "e4", tolerance=0)
    with pytest.raises(InputError, match="there is no strategy to certify"):
        certificate(f)


def test_cli_funnel_writes_a_certificate_that_verifies(tmp_path):
    cert = tmp_path / "funnel.cert.json"
    picture = tmp_path / "funnel.svg"
    model = MODELS / "narrow_door.json"
    result = runner.invoke(cli.app, ["funnel", str(model), "--from", "e0", "--to", "e4", "--certificate", str(cert),
                                     "--picture", str(picture)])
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["safe_plan_exists"] is False
    assert all("positions" in s and s["positions"] for s in answer["stages"])
    assert answer["bounces"] == len(answer["stages"]) and answer["min_width"] == pytest.approx(0.01)
    verify = runner.invoke(cli.app, ["verify", str(cert), "--env", str(model), "--from", "e0", "--to", "e4"])
    assert verify.exit_code == 0, verify.stderr
    assert "funnel-positions-0" in picture.read_text()
