"""Negative certificates on the shipped models: how often an infeasible answer certifies, and the checker's time.

Run ``python benchmarks/bench_negative.py`` from the repository root. For every shipped model, ``--queries``
random queries ``find_plan(env, start, goal, max_bounces=K)`` (K uniform in 1..3; start one or two random
pieces, goal one random piece; ``--sets edges``: whole edges, so that the planner's segments and the
certificate's table agree; ``--sets pieces``: pieces ``eK:a:b`` with a ∈ {0, 0.1, 0.25, 0.5}, b ∈ {0.6, 0.75,
0.9, 1}). Every proved-infeasible answer is turned into an ``infeasible`` certificate (issue #22) and checked
again, timed. Printed: a markdown table per model — queries, infeasible answers, certified, not certifiable
(the exact margin-free closure reaches the goal: the answer holds only within the planner's margins or its
coarser segments), the invariant's median size, and the checker's median and worst time. Results are recorded
in ``benchmarks/README.md``.
"""

from __future__ import annotations

import argparse
import platform
import random
import statistics
import time
from pathlib import Path

from solverplan.certify import NothingToCertify, certificate, check_certificate
from solverplan.environment import load_environment
from solverplan.plan import find_plan

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


def run(n_queries: int, seed: int, sets: str) -> None:
    print(f"python {platform.python_version()}, {platform.machine()}; {n_queries} random queries per model, "
          f"seed {seed}, sets: {sets}\n")
    print("| model | edges | queries | infeasible | certified | not certifiable | beliefs (median) | check median (s) "
          "| check worst (s) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    rng = random.Random(seed)
    totals = [0, 0, 0, 0]
    for path in sorted(MODELS.glob("*.json")):
        env = load_environment(path)
        n = env.n_edges

        def piece() -> str:
            e = rng.randrange(n)
            if sets == "edges":
                return f"e{e}"
            return f"e{e}:{rng.choice([0, 0.1, 0.25, 0.5])}:{rng.choice([0.6, 0.75, 0.9, 1])}"

        queries = infeasible = certified = refused = 0
        times: list[float] = []
        sizes: list[int] = []
        for _ in range(n_queries):
            start = ",".join(piece() for _ in range(rng.choice([1, 1, 2])))
            goal, budget = piece(), rng.choice([1, 2, 3])
            try:
                plan = find_plan(env, start, goal, max_bounces=budget, timeout=20)
            except ValueError:  # a start set lying in the goal set's edge pieces, or overlapping pieces
                continue
            queries += 1
            if plan.status.value != "infeasible":
                continue
            infeasible += 1
            try:
                cert = certificate(plan, env=env)
            except NothingToCertify:
                refused += 1
                continue
            t = time.perf_counter()
            report = check_certificate(cert)
            times.append(time.perf_counter() - t)
            assert report.valid, (path.stem, start, goal, budget, [str(f) for f in report.failures[:1]])
            certified += 1
            assert cert.bound is not None
            sizes.append(len(cert.bound.beliefs))
        totals = [totals[0] + queries, totals[1] + infeasible, totals[2] + certified, totals[3] + refused]
        med = f"{statistics.median(times):.3f}" if times else "–"
        worst = f"{max(times):.3f}" if times else "–"
        beliefs = f"{statistics.median(sizes):g}" if sizes else "–"
        print(f"| {path.stem} | {n} | {queries} | {infeasible} | {certified} | {refused} | {beliefs} | {med} | {worst} |")
    print(f"| **all** | | {totals[0]} | {totals[1]} | {totals[2]} | {totals[3]} | | | |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=12)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--sets", choices=("edges", "pieces"), default="edges")
    args = parser.parse_args()
    run(args.queries, args.seed, args.sets)


if __name__ == "__main__":
    main()
