"""Algorithm A's competitive ratio against the chained-cover MILP optimum, and Algorithm B against its bounds.

Run ``python benchmarks/bench_explore.py`` from the repository root (``--polygons N`` per family, default 30).
Two families from :mod:`solverplan.generators`: star polygons without holes (n = 8 … 12 vertices,
irregularity 0.5, spikiness 0.6) and star polygons with one hole (n = 7 … 10 outer vertices, a triangle or
quadrilateral hole). The start is a random point of the free space (seeded), on a grid of 1/1000.

For every polygon Algorithm A runs with each z-choice rule (``first``, ``random`` seed 0, ``far``); the optimum
is :func:`~solverplan.explore.optimum.chained_optimum` over the start, the polygon's vertices and every viewpoint
of the three runs. That optimum is over a finite candidate set, so it is an upper bound on the true optimum and
the ratio A / OPT is a lower estimate of the true ratio on that instance; Theorem 2's (r + 1)/2 is printed next
to it. Algorithm B then runs with R = 0.5 (the polygons have radius about 1) and is compared with Lemma 4's bound
and Theorem 5's lower bound ⌈Area/(πR²)⌉. Results are recorded in ``benchmarks/README.md``.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import os
import random
import statistics
import sys
import time
from fractions import Fraction

from solverplan.environment import Environment
from solverplan.exact import point_in_ring
from solverplan.explore import CHOICES, explore_depth_first, explore_range_limited
from solverplan.explore.optimum import chained_optimum
from solverplan.generators import star_polygon, star_polygon_with_holes


@contextlib.contextmanager
def _quiet():
    """Silence the MILP solver's banner, which HiGHS writes to the process's stdout (file descriptor 1)."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            sys.stdout.flush()
            os.dup2(saved, 1)
            os.close(saved)


def random_start(env: Environment, rng: random.Random) -> tuple[Fraction, Fraction]:
    xmin, ymin, xmax, ymax = env.bounds
    while True:
        p = (Fraction(round(rng.uniform(xmin, xmax) * 1000), 1000), Fraction(round(rng.uniform(ymin, ymax) * 1000), 1000))
        if point_in_ring(p, env.outer) > 0 and all(point_in_ring(p, h) < 0 for h in env.holes):
            return p


def polygons(count: int) -> list[tuple[str, Environment]]:
    out = []
    for i in range(count):
        out.append(("simple", star_polygon(8 + i % 5, 0.5, 0.6, seed=1000 + i, decimals=3)))
    for i in range(count):
        out.append(("one hole", star_polygon_with_holes(7 + i % 4, 1, seed=2000 + i, hole_vertices=3 + i % 2,
                                                        hole_radius=0.2, decimals=3)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--polygons", type=int, default=30, help="polygons per family")
    args = parser.parse_args()
    rng = random.Random(7)
    rows: dict[str, list] = collections.defaultdict(list)
    opt_counts: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    b_rows: dict[str, list] = collections.defaultdict(list)
    t0 = time.process_time()
    for family, env in polygons(args.polygons):
        start = random_start(env, rng)
        runs = {c: explore_depth_first(env, start, choice=c, seed=0 if c == "random" else None) for c in CHOICES}
        assert all(r.n_views <= r.bound and 1 - r.covered_fraction < 1e-9 for r in runs.values())
        candidates = [p for r in runs.values() for p in r.viewpoints]
        with _quiet():
            opt = chained_optimum(env, start, candidates)
        assert opt.views <= min(r.n_views for r in runs.values())
        opt_counts[family][opt.views] += 1
        for c, r in runs.items():
            rows[family, c].append((r.n_views, opt.views, r.bound, len(env.reflex_vertices)))
        b = explore_range_limited(env, start, Fraction(1, 2))
        assert b.status.value == "found" and b.n_views <= b.bound and 1 - b.covered_fraction < 1e-6
        b_rows[family].append((b.n_views, b.bound, b.lower_bound, b.ratio, b.ratio_bound))
    seconds = time.process_time() - t0

    print("| family | z-choice | polygons | mean r | mean views | mean OPT | mean A/OPT | max A/OPT | "
          "max A/OPT over (r+1)/2 | A = OPT |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (family, c), data in rows.items():
        ratios = [v / o for v, o, _, _ in data]
        thm2 = [(v / o) / (b / 2) for v, o, b, _ in data if o >= 2]
        print(f"| {family} | {c} | {len(data)} | {statistics.mean(r for *_, r in data):.2f} | "
              f"{statistics.mean(v for v, *_ in data):.2f} | {statistics.mean(o for _, o, *_ in data):.2f} | "
              f"{statistics.mean(ratios):.3f} | {max(ratios):.3f} | {max(thm2) if thm2 else float('nan'):.3f} | "
              f"{sum(v == o for v, o, *_ in data)} |")
    print()
    print("| family | OPT distribution (views: polygons) |")
    print("|---|---|")
    for family, counter in opt_counts.items():
        print(f"| {family} | " + ", ".join(f"{k}: {counter[k]}" for k in sorted(counter)) + " |")
    print()
    print("| family (R = 0.5) | polygons | mean views | max views / Lemma 4 | mean lower bound | mean views / lower bound "
          "| max views / lower bound | mean Theorem 5 bound |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for family, data in b_rows.items():
        print(f"| {family} | {len(data)} | {statistics.mean(d[0] for d in data):.1f} | "
              f"{max(d[0] / d[1] for d in data):.3f} | {statistics.mean(d[2] for d in data):.2f} | "
              f"{statistics.mean(d[3] for d in data):.2f} | {max(d[3] for d in data):.2f} | "
              f"{statistics.mean(d[4] for d in data):.1f} |")
    print(f"\nCPU time {seconds:.1f} s")


if __name__ == "__main__":
    main()
