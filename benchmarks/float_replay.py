"""Float replay of random answers: how many plans, patrols and funnels fail in plain floating-point rollouts.

Random queries on the shipped models; every answer found is executed by the simulator with ``ties="flag"``
(plain float ray casts: a ray the float caster cannot call — a vertex hit or a near-tie — stops and counts as a
failure) from uniform starts with the adversarial heading choice (interval ends). Prints one row per planner:
queries, answers found, answers with at least one failed rollout, and the worst failure rate.

    python benchmarks/float_replay.py [--queries 99] [--trials 2000] [--seed 0]
"""

from __future__ import annotations

import argparse
import random
import time
from fractions import Fraction

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.environment import load_environment
from solverplan.plan.funnels import funnel
from solverplan.plan.patrols import patrol
from solverplan.plan.search import find_plan
from solverplan.simulate import StagePolicy, simulate_plan, simulate_policy

MODELS = ["square", "triangle", "hexagon", "irregular_convex", "l_shape", "two_rooms", "one_hole", "two_holes",
          "narrow_door", "comb", "star", "spiral", "warehouse"]


def _piece(rng: random.Random, n_edges: int) -> str:
    a = rng.randrange(8)
    b = rng.randrange(a + 1, 9)
    return f"e{rng.randrange(n_edges)}:{Fraction(a, 8)}:{Fraction(b, 8)}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=99)
    parser.add_argument("--trials", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    graphs = {}
    for name in MODELS:
        env = load_environment(name)
        graphs[name] = (env, safe_bounce_visibility_graph(env))
    rows: dict[str, list[float]] = {}

    def record(kind: str, runs, expected: str) -> None:
        counts = runs.outcome_counts()
        bad = 1 - counts[expected] / runs.trials
        row = rows.setdefault(kind, [0, 0, 0, 0.0])
        row[1] += 1
        row[2] += bad > 0
        row[3] = max(row[3], bad)

    t0 = time.perf_counter()
    for _ in range(args.queries):
        name = rng.choice(MODELS)
        env, graph = graphs[name]
        # a plan of a random objective
        objective = rng.choice(["fewest", "tolerance", "sum", "constant"])
        start, goal = _piece(rng, env.n_edges), _piece(rng, env.n_edges)
        rows.setdefault(f"plan/{objective}", [0, 0, 0, 0.0])[0] += 1
        plan = find_plan(env, start, goal, objective=objective, max_bounces=4 if objective == "sum" else None,
                         graph=graph)
        if plan.found and plan.stages:
            record(f"plan/{objective}", simulate_plan(env, plan, trials=args.trials, seed=1, sampling="endpoints",
                                                      ties="flag", partition=graph.partition), "goal")
        # a patrol of 1–3 random edges, from a start set half of the time
        visit = rng.sample(range(env.n_edges), rng.randint(1, min(3, env.n_edges)))
        with_start = rng.random() < 0.5
        kind = f"patrol/{rng.choice(['contraction', 'rate'])}"
        rows.setdefault(kind, [0, 0, 0, 0.0])[0] += 1
        p = patrol(env, ",".join(f"e{e}" for e in visit), start=start if with_start else None,
                   objective=kind.split("/")[1], tolerance=0.01, graph=graph)
        if p.found:
            stages, targets, repeat = p.rollout_spec()
            first = graph.partition.segments[p.segments[0]]
            starts = start if with_start else f"e{first.edge}:{first.t0}:{first.t1}"
            runs = simulate_policy(env, StagePolicy(stages, targets, repeat_from=repeat, sampling="endpoints"), starts,
                                   bounces=len(p.entry) + 6 * len(p.cycle), trials=args.trials, seed=2, ties="flag",
                                   record="ends")
            record(kind, runs, "ok")
    for _ in range(max(1, args.queries // 5)):
        name = rng.choice(["square", "l_shape", "two_rooms", "narrow_door", "one_hole"])
        env, graph = graphs[name]
        start = _piece(rng, env.n_edges)
        centre = Fraction(rng.randint(2, 6), 8)
        goal = f"e{rng.randrange(env.n_edges)}:{centre - Fraction(1, 16)}:{centre + Fraction(1, 16)}"
        rows.setdefault("funnel", [0, 0, 0, 0.0])[0] += 1
        f = funnel(env, start, goal, graph=graph, max_bounces=12, beam=100)
        if f.found and f.stages:
            stages, targets, goal_set = f.rollout_spec()
            record("funnel", simulate_policy(env, StagePolicy(stages, targets, goal=goal_set, sampling="endpoints"),
                                             start, bounces=len(stages), trials=args.trials, seed=3, ties="flag"),
                   "goal")
    print(f"{'answers':<20} {'queries':>8} {'found':>6} {'any failure':>12} {'worst rate':>11}")
    for kind in sorted(rows):
        q, n, bad, worst = rows[kind]
        print(f"{kind:<20} {q:>8} {n:>6} {bad:>12} {worst:>11.4f}")
    print(f"({args.trials} float rollouts per answer, {time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
