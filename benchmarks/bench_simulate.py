"""Monte Carlo rollout speed: :func:`solverplan.simulate.simulate_rule`, 10⁴ rollouts × 50 bounces.

Run ``python benchmarks/bench_simulate.py`` from the repository root (package installed): it prints a
markdown table (model, edges, rule, rollouts, bounces, CPU seconds and bounces per CPU-second, wall seconds
and bounces per wall-second, share of the wall time spent in the batch caster, threads of the caster) for
shipped models and a generated 1,000-edge star polygon, and the load average. ``--threads 1`` casts in one
thread (the default: one per core, at most 4). Results are recorded in ``benchmarks/README.md``. The target
(issue #24): ≥ 10⁶ specular bounces per wall-second on the shipped 20-edge star.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from solverplan.bounce.rules import Fixed, Relative, Specular
from solverplan.environment import load_environment
from solverplan import _arrays
from solverplan.geometry import raycast
from solverplan.simulate import simulate_rule
from solverplan.generators import star_polygon

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


def timed_run(env, rule, trials: int, bounces: int, repeat: int) -> tuple[float, float, float, dict]:
    """Best-of-``repeat`` wall and CPU times, the caster's share of the wall time, and the outcome counts."""
    inner = raycast.RayCaster.cast_from_boundary
    spent = [0.0]

    def counting(self, *args, **kwargs):
        t0 = time.perf_counter()
        try:
            return inner(self, *args, **kwargs)
        finally:
            spent[0] += time.perf_counter() - t0

    best, cpu, share, counts = np.inf, np.inf, 0.0, {}
    raycast.RayCaster.cast_from_boundary = counting
    try:
        simulate_rule(env, rule, None, bounces=2, trials=100, seed=0)  # warm the caster's cache
        for _ in range(repeat):
            spent[0] = 0.0
            t0, c0 = time.perf_counter(), time.process_time()
            runs = simulate_rule(env, rule, None, bounces=bounces, trials=trials, seed=0)
            elapsed, used = time.perf_counter() - t0, time.process_time() - c0
            cpu = min(cpu, used)
            if elapsed < best:
                best, share, counts = elapsed, spent[0] / elapsed, runs.outcome_counts()
    finally:
        raycast.RayCaster.cast_from_boundary = inner
    return best, cpu, share, counts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=10_000)
    parser.add_argument("--bounces", type=int, default=50)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=None, help="threads of the caster (default: one per core, at most 4)")
    args = parser.parse_args()
    if args.threads is not None:
        raycast.threads = lambda: max(1, args.threads)
    cases = [
        (load_environment(MODELS / "star.json"), Specular()),
        (load_environment(MODELS / "star.json"), Fixed(1.0)),
        (load_environment(MODELS / "star.json"), Relative(1.0, 0.1)),
        (load_environment(MODELS / "two_rooms.json"), Specular()),
        (load_environment(MODELS / "warehouse.json"), Specular()),
        (star_polygon(1000, 0.2, 0.3, radius=100, seed=1), Specular()),
    ]
    print(f"load average at the start: {os.getloadavg()[0]:.1f}; caster threads: {raycast.threads()} "
          f"(cores {_arrays.workers()})\n")
    print("| model | edges | rule | rollouts | bounces | CPU s | bounces/CPU-s | wall s | bounces/wall-s | in caster | flagged |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for env, rule in cases:
        seconds, cpu, share, counts = timed_run(env, rule, args.trials, args.bounces, args.repeat)
        flagged = counts.get("vertex", 0) + counts.get("tie", 0)
        total = args.trials * args.bounces
        print(f"| {env.name} | {env.n_edges} | {rule} | {args.trials:,} | {args.bounces} | {cpu:.3f} | {total / cpu:,.0f} | "
              f"{seconds:.3f} | {total / seconds:,.0f} | {share:.0%} | {flagged} |")
    print(f"\nload average at the end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
