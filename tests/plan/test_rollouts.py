"""Every found plan is checked against the simulator, the ground truth: 10⁴ rollouts, success rate 1.0.

Starts are uniform by arc length in the start set; headings uniform in each stage's interval, then
adversarial (each heading an end of its interval). A rollout succeeds when every stage lands on its
segments and the last one in the goal set; rays the float caster cannot call are re-resolved exactly.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.environment import load_environment
from solverplan.plan import find_plan, pareto_front
from solverplan.simulate import simulate_plan

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
TRIALS = 10_000

QUERIES = [
    # model, start, goal, objective, budget
    ("two_rooms", "e0:0.2:0.8", "e4:0.5:1", "fewest", None),
    ("two_rooms", "e0:0.2:0.8", "e4:0.5:1", "tolerance", None),
    ("two_rooms", "e0:0.2:0.8", "e4:0.5:1", "tolerance", 4),
    ("two_rooms", "e0:0.2:0.8", "e4:0.5:1", "sum", 4),
    ("two_rooms", "e0:0.2:0.8", "e4:0.5:1", "constant", None),
    ("two_rooms", "e5", "e0:0.6:0.8", "fewest", None),  # goal inside one segment
    ("one_hole", "e1,e5", "e3", "tolerance", None),  # belief across the outer ring and the hole
    ("two_holes", "e6:0.25:0.75", "e9:0.1:0.75,e1:0.25:0.6", "tolerance", None),
    ("degenerate", "e12:0.1:0.75,e9:0.25:1", "e1,e13:0:0.6", "fewest", None),
    ("warehouse", "e49:0.1:0.6", "e38:0.1:1", "fewest", None),
    ("spiral", "e0", "e20", "fewest", None),
]

_GRAPHS: dict[str, tuple] = {}


def _model(name: str):
    if name not in _GRAPHS:
        env = load_environment(MODELS / f"{name}.json")
        _GRAPHS[name] = (env, safe_bounce_visibility_graph(env))
    return _GRAPHS[name]


@pytest.mark.parametrize("model, start, goal, objective, budget", QUERIES,
                         ids=[f"{q[0]}-{q[3]}-{q[1]}-{q[2]}" for q in QUERIES])
def test_found_plans_succeed_in_every_rollout(model, start, goal, objective, budget):
    env, graph = _model(model)
    plan = find_plan(env, start, goal, objective=objective, max_bounces=budget, graph=graph)
    assert plan.found and plan.bounces >= 1, plan.reason
    for sampling, seed in (("uniform", 11), ("endpoints", 12)):
        runs = simulate_plan(env, plan, trials=TRIALS, seed=seed, sampling=sampling, partition=graph.partition)
        assert runs.success_rate == 1.0, (sampling, runs.outcome_counts())
        assert runs.outcome_counts()["goal"] == TRIALS and set(runs.stop_step.tolist()) == {plan.bounces}


def test_every_point_of_the_pareto_front_succeeds_in_every_rollout():
    env, graph = _model("two_rooms")
    front = pareto_front(env, "e0", "e4", graph=graph)
    assert len(front.points) >= 2
    for point in front.points:
        runs = simulate_plan(env, point.plan, trials=TRIALS, seed=point.bounces, sampling="endpoints",
                             partition=graph.partition)
        assert runs.success_rate == 1.0, (point.bounces, runs.outcome_counts())


def test_simulation_rejects_a_plan_with_a_widened_interval():
    """The simulator is a real check: widening the narrowest stage of the fewest plan makes rollouts fail."""
    from solverplan.interval import Interval

    env, graph = _model("two_rooms")
    plan = find_plan(env, "e0", "e4", graph=graph)
    k = min(range(plan.bounces), key=lambda i: plan.stages[i].width)
    stage = plan.stages[k]
    wide = stage.__class__(stage.from_segments, stage.to_segments, Interval(stage.interval.lo - 0.05, stage.interval.hi + 0.05),
                           stage.moves)
    bad = plan.with_(stages=plan.stages[:k] + (wide,) + plan.stages[k + 1:])
    runs = simulate_plan(env, bad, trials=2000, seed=3, sampling="endpoints", partition=graph.partition)
    assert runs.success_rate < 1.0 and runs.outcome_counts()["failed"] > 0
