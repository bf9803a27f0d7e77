"""`solverplan cycle` (the cycle answer of docs/contract.md) and `solverplan render --cycle`."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from solverplan.bounce.rules import Fixed
from solverplan.environment import load_environment
from solverplan.simulate import simulate_rule
from tests.cli_runs import run

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


def test_cycle_agrees_with_a_10000_bounce_simulation():
    """Issue 4's acceptance: irregular_convex, θ inside Lemma 3, versus 10,000 simulated bounces."""
    result = run("cycle", MODELS / "irregular_convex.json", "--theta", "0.25", "--epsilon", "1e-9")
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["scope"] == "every-start" and answer["lemma3"]["inside"]
    assert answer["cycles_to_epsilon"] >= 1 and 0 < float(answer["contraction"]) < 1
    env = load_environment(MODELS / "irregular_convex.json")
    runs = simulate_rule(env, Fixed(0.25), None, bounces=10000, trials=50, seed=4, initial=[0.25], record="ends")
    assert runs.outcome_counts()["ok"] == 50
    fixed = {p["edge"]: p["t"] for p in answer["fixed_point"]}
    expected = np.array([fixed[e] for e in runs.final_edge])
    assert np.all(np.abs(runs.final_t - expected) / expected < 1e-9)


def test_cycle_outside_the_admissible_range_is_a_clear_answer():
    result = run("cycle", MODELS / "irregular_convex.json", "--theta", "1.2")
    assert result.exit_code == 0
    answer = json.loads(result.stdout)
    assert answer["status"] == "edge-order-broken" and answer["fixed_point"] == [] and answer["contraction"] is None
    assert answer["reason"].startswith("θ is outside Lemma 3's CCW range (0, 0.307046)")


def test_cycle_exact_tangent_gives_exact_numbers_and_text():
    result = run("cycle", MODELS / "square.json", "--theta", "atan:1/2", "--format", "text")
    assert result.exit_code == 0
    assert "contraction per cycle: 0.0625 (exact 0.0625)" in result.stdout
    answer = json.loads(run("cycle", MODELS / "square.json", "--theta", "tan:1/2").stdout)
    assert answer["contraction_exact"] == "0.0625" and {p["t_exact"] for p in answer["fixed_point"]} == {"1/3"}
    assert answer["theta_exact"] == "tan:0.5" and answer["theta"] == math.atan(0.5)


def test_cycle_bad_heading_is_exit_2_with_one_line():
    for bad in ("4", "0", "-1", "north", "tan:0"):
        result = run("cycle", MODELS / "square.json", "--theta", bad)
        assert result.exit_code == 2 and result.stdout == ""
        assert len(result.stderr.strip().splitlines()) == 1 and result.stderr.startswith("error: ")
    result = run("cycle", MODELS / "square.json", "--theta", "0.3", "--edges", "e0,e7")
    assert result.exit_code == 2 and "unknown edge e7" in result.stderr


def test_cycle_auto_finds_a_constant_controller_for_a_model_with_holes():
    result = run("cycle", MODELS / "two_holes.json", "--theta", "auto")
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["proved"] and answer["cycles"] and all(c["status"] == "found" for c in answer["cycles"])


def test_render_cycle_draws_the_cycle_on_top(tmp_path):
    out = tmp_path / "cycle.svg"
    result = run("render", MODELS / "one_hole.json", "--cycle", "--theta", "tan:1/3", "--trajectories", "5", "-o", out)
    assert result.exit_code == 0, result.stderr
    svg = out.read_text()
    assert 'id="limit-cycle"' in svg and 'id="limit-cycle-points"' in svg and 'id="trajectories"' in svg
    result = run("render", MODELS / "one_hole.json", "--cycle", "-o", tmp_path / "x.png")
    assert result.exit_code == 2 and "--cycle and --theta go together" in result.stderr


def test_cycle_answer_carries_the_result_protocol():
    answer = json.loads(run("cycle", MODELS / "two_holes.json", "--theta", "0.2").stdout)
    assert answer["method"] == "iterate" and answer["scope"] == "start+basin"
    assert answer["environment"]["name"] == "two_holes" and len(answer["environment"]["sha256"]) == 64
    assert answer["optimality"]["method"] == "exact-check" and answer["optimality"]["proved"] is True
    assert answer["stats"]["bounces_simulated"] >= 1
    stage = answer["entry"][0]
    assert stage["interval"] == [0.2, 0.2] and stage["nominal"] == 0.2 and set(stage["map"]) == {"alpha", "beta"}
    text = run("cycle", MODELS / "two_holes.json", "--theta", "0.2", "--format", "text").stdout
    assert "guarantee: start+basin" in text and "optimality: exact-check" in text and "entry: 5 bounces from e0:0.5" in text


def test_cycle_budget_without_a_period_is_not_found():
    result = run("cycle", MODELS / "square.json", "--theta", "tan:1/2", "--method", "iterate", "--max-bounces", "3")
    assert result.exit_code == 0
    answer = json.loads(result.stdout)
    assert answer["status"] == "not-found" and answer["optimality"]["limits"] == ["max_bounces=3"]
    assert answer["optimality"]["proved"] is False and answer["fixed_point"] == []


def test_cycle_auto_heading_margin():
    answer = json.loads(run("cycle", MODELS / "square.json", "--theta", "auto", "--heading-margin", "0.25").stdout)
    assert answer["heading_margin"] == 0.25 and answer["status"] == "found"
    assert answer["tried"][0]["theta_exact"] == "tan:0.25" and answer["tried"][0]["outcome"].startswith("skipped")
    assert 0.25 <= answer["theta"] <= math.pi - 0.25
    result = run("cycle", MODELS / "square.json", "--theta", "0.3", "--heading-margin", "0.01")
    assert result.exit_code == 2 and "--heading-margin goes with --theta auto" in result.stderr
