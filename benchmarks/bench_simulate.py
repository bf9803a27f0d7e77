"""Monte Carlo rollout speed: :func:`solverplan.simulate.simulate_rule`, 10⁴ rollouts × 50 bounces.

Run ``python benchmarks/bench_simulate.py`` from the repository root (package installed): it prints a
markdown table (model, edges, rule, rollouts, bounces, seconds, bounces/s, share of the time spent in
the batch caster) for shipped models and a generated 1,000-edge star polygon. Results are recorded in
``benchmarks/README.md``. The target: 10⁴ rollouts × 50 bounces on a 20-vertex polygon well
under a second.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from solverplan.bounce.rules import Fixed, Relative, Specular
from solverplan.environment import load_environment
from solverplan.geometry import raycast
from solverplan.simulate import simulate_rule
from solverplan.generators import star_polygon

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


def timed_run(env, rule, trials: int, bounces: int, repeat: int) -> tuple[float, float, dict]:
    """Best-of-``repeat`` wall time, the caster's share of it, and the outcome counts."""
    inner = raycast.RayCaster.cast_from_boundary
    spent = [0.0]

    def counting(self, *args, **kwargs):
        t0 = time.perf_counter()
        try:
            return inner(self, *args, **kwargs)
        finally:
            spent[0] += time.perf_counter() - t0

    best, share, counts = np.inf, 0.0, {}
    raycast.RayCaster.cast_from_boundary = counting
    try:
        simulate_rule(env, rule, None, bounces=2, trials=100, seed=0)  # warm the caster's cache
        for _ in range(repeat):
            spent[0] = 0.0
            t0 = time.perf_counter()
            runs = simulate_rule(env, rule, None, bounces=bounces, trials=trials, seed=0)
            elapsed = time.perf_counter() - t0
            if elapsed < best:
                best, share, counts = elapsed, spent[0] / elapsed, runs.outcome_counts()
    finally:
        raycast.RayCaster.cast_from_boundary = inner
    return best, share, counts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=10_000)
    parser.add_argument("--bounces", type=int, default=50)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    cases = [
        (load_environment(MODELS / "star.json"), Specular()),
        (load_environment(MODELS / "star.json"), Fixed(1.0)),
        (load_environment(MODELS / "star.json"), Relative(1.0, 0.1)),
        (load_environment(MODELS / "two_rooms.json"), Specular()),
        (load_environment(MODELS / "warehouse.json"), Specular()),
        (star_polygon(1000, 0.2, 0.3, radius=100, seed=1), Specular()),
    ]
    print("| model | edges | rule | rollouts | bounces | seconds | bounces/s | in caster | flagged |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for env, rule in cases:
        seconds, share, counts = timed_run(env, rule, args.trials, args.bounces, args.repeat)
        flagged = counts.get("vertex", 0) + counts.get("tie", 0)
        rate = args.trials * args.bounces / seconds
        print(f"| {env.name} | {env.n_edges} | {rule} | {args.trials:,} | {args.bounces} | {seconds:.3f} | "
              f"{rate:,.0f} | {share:.0%} | {flagged} |")


if __name__ == "__main__":
    main()
