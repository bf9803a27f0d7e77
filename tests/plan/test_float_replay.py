"""The margin policy: every answer replays in plain floating point as well as in exact arithmetic.

Random queries on the shipped models for every planner (plans of each objective, patrols, funnels); each
answer found is executed by the simulator with ``ties="flag"`` — plain float ray casts, no exact
re-resolution — from starts uniform in the start set with the adversarial heading choice (each heading at an
end of its interval), and must succeed in every rollout: no landing outside a stage's segments, no ray the
float caster cannot call (a vertex hit or a near-tie). Without the corner clearance and the heading margin
such answers drive robots to within 10⁻⁹ of a corner or off a wall at 10⁻⁶ rad, and without the rule against
two consecutive arcs into one corner (the corner ping-pong) they converge into the vertex: float rollouts fail.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.environment import load_environment
from solverplan.plan import find_plan
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN
from solverplan.simulate import StagePolicy, simulate_plan, simulate_policy

NAMES = ["square", "triangle", "hexagon", "irregular_convex", "l_shape", "two_rooms", "one_hole", "narrow_door"]
TRIALS = 2000

_CACHE: dict[str, tuple] = {}


def _model(name: str):
    if name not in _CACHE:
        env = load_environment(name)  # a shipped model
        _CACHE[name] = (env, safe_bounce_visibility_graph(env))
    return _CACHE[name]


@st.composite
def pieces(draw, n_edges: int) -> str:
    edge = draw(st.integers(0, n_edges - 1))
    a = draw(st.integers(0, 7))
    b = draw(st.integers(a + 1, 8))
    return f"e{edge}:{Fraction(a, 8)}:{Fraction(b, 8)}"


@st.composite
def queries(draw):
    name = draw(st.sampled_from(NAMES))
    env, graph = _model(name)
    return name, env, graph, draw(pieces(env.n_edges)), draw(pieces(env.n_edges))


def _assert_every_rollout_succeeds(runs, expected: str = "goal") -> None:
    counts = runs.outcome_counts()
    assert counts[expected] == runs.trials, counts


def _assert_margins(intervals) -> None:
    for iv in intervals:
        assert DEFAULT_HEADING_MARGIN - 1e-15 <= iv.lo <= iv.hi <= math.pi - DEFAULT_HEADING_MARGIN + 1e-15


@settings(max_examples=40)
@given(queries(), st.sampled_from(["fewest", "tolerance", "sum", "constant"]))
def test_plans_replay_in_float_rollouts_without_a_failure(query, objective):
    name, env, graph, start, goal = query
    plan = find_plan(env, start, goal, objective=objective, max_bounces=4 if objective == "sum" else None, graph=graph)
    if not plan.found or not plan.stages:
        return
    _assert_margins(plan.intervals)
    runs = simulate_plan(env, plan, trials=TRIALS, seed=5, sampling="endpoints", ties="flag",
                         partition=graph.partition)
    _assert_every_rollout_succeeds(runs)


@settings(max_examples=30)
@given(queries(), st.sampled_from(["contraction", "rate"]), st.booleans(), st.data())
def test_patrols_replay_in_float_rollouts_without_a_failure(query, objective, with_start, data):
    from solverplan.plan.patrols import patrol

    name, env, graph, start, _ = query
    visit = data.draw(st.lists(st.integers(0, env.n_edges - 1), min_size=1, max_size=3, unique=True))
    p = patrol(env, ",".join(f"e{e}" for e in visit), start=start if with_start else None, objective=objective,
               tolerance=0.01, graph=graph)
    if not p.found:
        return
    stages, targets, repeat = p.rollout_spec()
    _assert_margins(stages)
    first = graph.partition.segments[p.segments[0]] if not with_start else None
    starts = start if with_start else f"e{first.edge}:{first.t0}:{first.t1}"
    bounces = len(p.entry) + 6 * len(p.cycle)
    runs = simulate_policy(env, StagePolicy(stages, targets, repeat_from=repeat, sampling="endpoints"), starts,
                           bounces=bounces, trials=TRIALS, seed=6, ties="flag", record="ends")
    _assert_every_rollout_succeeds(runs, expected="ok")


@settings(max_examples=12)
@given(st.sampled_from(["square", "l_shape", "two_rooms", "narrow_door"]), st.data())
def test_funnels_replay_in_float_rollouts_without_a_failure(name, data):
    from solverplan.plan.funnels import funnel

    env, graph = _model(name)
    start = data.draw(pieces(env.n_edges))
    edge = data.draw(st.integers(0, env.n_edges - 1))
    centre = data.draw(st.sampled_from([Fraction(1, 4), Fraction(1, 2), Fraction(3, 4)]))
    goal = f"e{edge}:{centre - Fraction(1, 16)}:{centre + Fraction(1, 16)}"
    f = funnel(env, start, goal, graph=graph, max_bounces=12, beam=100)
    if not f.found or not f.stages:
        return
    stages, targets, goal_set = f.rollout_spec()
    _assert_margins(stages)
    for sampling in ("uniform", "endpoints"):
        runs = simulate_policy(env, StagePolicy(stages, targets, goal=goal_set, sampling=sampling), start,
                               bounces=len(stages), trials=TRIALS, seed=7, ties="flag")
        _assert_every_rollout_succeeds(runs)


def test_the_convex_room_patrol_keeps_the_heading_margin():
    """The contraction-optimal patrol of a convex room sits at the contracting end of each arc's safe interval —
    at the wall itself without a margin; with it, every heading is at least δ from 0 and π."""
    from solverplan.plan.patrols import patrol

    env, graph = _model("square")
    p = patrol(env, "e0,e1,e2,e3", objective="contraction", tolerance=0.01, graph=graph)
    assert p.found
    lows = np.array([s.interval.lo for s in p.cycle])
    assert np.all(lows >= DEFAULT_HEADING_MARGIN) and np.allclose(lows, DEFAULT_HEADING_MARGIN)
