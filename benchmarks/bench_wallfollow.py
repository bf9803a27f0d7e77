"""Strategy 1's cost: actions against n, and the fitted exponent (the paper's Prop. 5 claims O(n²)).

Run ``python benchmarks/bench_wallfollow.py`` from the repository root. Two families, made here:

- ``random``: star-shaped polygons (integer vertices, radius 10⁶, random radii in [R/4, R], angular jitter), in
  general position (others are redrawn); few cut end points share an edge;
- ``comb``: a floor under a ceiling with t spikes hanging down; both cuts of every spike land on the floor, so one
  edge receives 2t = Θ(n) end points — the case where comparisons dominate.

For each, Strategy 1 runs with pairwise comparisons (the paper) and with a merge sort; the table gives the mean
actions over the polygons of each n and the least-squares slope of log(actions) against log(n).
Results are recorded in ``benchmarks/README.md``.
"""

from __future__ import annotations

import argparse
import math
import random
import time

import numpy as np

from solverplan.environment import Environment
from solverplan.generators import spiked_comb
from solverplan.wallfollow import cuts
from solverplan.wallfollow.learning import learn_cut_ordering
from tests.wallfollow._polygons import in_general_position


def random_polygon(n: int, seed: int, radius: int = 1_000_000) -> Environment:
    rng = random.Random(seed)
    while True:
        ring = []
        for k in range(n):
            r = rng.randint(radius // 4, radius)
            a = 2 * math.pi * (k + rng.uniform(-0.4, 0.4)) / n
            ring.append((round(r * math.cos(a)), round(r * math.sin(a))))
        env = in_general_position(ring)
        if env is not None:
            return env


def slope(ns: list[int], values: list[float]) -> float:
    return float(np.polyfit(np.log(ns), np.log(values), 1)[0])


def run(family: str, sizes: list[int], per_size: int) -> None:
    print(f"\n### {family}\n")
    print("| n | m | max end points on an edge | actions (pairwise) | comparisons | actions (sort) | comparisons | seconds |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    ns, pair, merged = [], [], []
    for size in sizes:
        rows = []
        for s in range(per_size):
            env = random_polygon(size, s) if family == "random" else spiked_comb((size - 5) // 2, s)
            ends = [c.edge for c in cuts(env)]
            crowd = max([ends.count(e) for e in set(ends)] or [0])
            t0 = time.perf_counter()
            a = learn_cut_ordering(env, comparisons="pairwise")
            b = learn_cut_ordering(env, comparisons="sort")
            assert a.matches_geometry and b.matches_geometry
            rows.append((env.n_vertices, len(env.reflex_vertices), crowd, a.actions, a.counts["comparisons"],
                         b.actions, b.counts["comparisons"], time.perf_counter() - t0))
        mean = [sum(r[i] for r in rows) / len(rows) for i in range(8)]
        ns.append(mean[0])
        pair.append(mean[3])
        merged.append(mean[5])
        print(f"| {mean[0]:.0f} | {mean[1]:.1f} | {mean[2]:.1f} | {mean[3]:,.0f} | {mean[4]:,.0f} | {mean[5]:,.0f} | "
              f"{mean[6]:,.0f} | {mean[7]:.2f} |")
    print(f"\nfitted exponent (actions ∝ n^k): pairwise k = {slope(ns, pair):.2f}, sort k = {slope(ns, merged):.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-size", type=int, default=5)
    args = parser.parse_args()
    run("random", [8, 16, 32, 64, 128], args.per_size)
    run("comb", [9, 17, 33, 65, 129], 1)


if __name__ == "__main__":
    main()
