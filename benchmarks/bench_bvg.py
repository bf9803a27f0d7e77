"""Partition + safe bounce visibility graph build time against n and against the number of arcs.

Run ``python benchmarks/bench_bvg.py`` from the repository root (package installed). It prints a
markdown table (family, n, segments of P′, BVG arcs, safe arcs, seconds for the partition, seconds
for the safe BVG, total) for

- random star polygons ``star_polygon(n, 0.2, 0.3, seed=1)`` (the paper's §7.3 family at the
  paper's parameters), n = 10, 20, 40, 80, 160, 320, 640, 1000 — stopping early when one size takes
  longer than ``--budget`` seconds;
- the paper's worst case ``worst_case_polygon(t)`` (n = 4t + 2, §4.0.1), t = 2, 4, 8, 16, 24, 32;

then the growth exponents fitted with ``numpy.polyfit`` on logs: time against n, time against the
number of arcs (time ∝ output size means an exponent near 1), and arcs against n. Times are the
best of ``--repeat`` runs (1 for the large sizes). Results are recorded in ``benchmarks/README.md``.

Issue 3's targets on this 2-core machine class: star n = 80 (about 650 segments, 80,000 arcs) under
0.5 s; star n = 320 under 10 s; worst case t = 16 (n = 66) under 2 s — partition and safe BVG together.
"""

from __future__ import annotations

import argparse
import gc
import platform
import time
import warnings
from typing import Iterable

import numpy as np

from solverplan.bounce.bvg import clear_graph_cache, safe_bounce_visibility_graph
from solverplan.bounce.partitions import partition
from solverplan.environment import Environment
from solverplan.generators import star_polygon, worst_case_polygon

STAR_SIZES = [10, 20, 40, 80, 160, 320, 640, 1000]
WORST_CASE_T = [2, 4, 8, 16, 24, 32]


def measure(env, repeat: int) -> dict:
    best_p = best_g = float("inf")
    for _ in range(repeat):
        clear_graph_cache()  # a build each time, not the graph kept from the previous run
        gc.collect()
        t0 = time.perf_counter()
        p = partition(env)
        t1 = time.perf_counter()
        g = safe_bounce_visibility_graph(p)
        t2 = time.perf_counter()
        best_p, best_g = min(best_p, t1 - t0), min(best_g, t2 - t1)
    return {
        "n": env.n_vertices,
        "segments": len(p),
        "arcs": g.n_arcs,
        "safe": g.n_safe_arcs,
        "partition": best_p,
        "bvg": best_g,
        "total": best_p + best_g,
    }


def fit(rows: list[dict], x: str, y: str) -> float:
    xs = np.log([r[x] for r in rows if r[y] > 0.01 or y != "total"])
    ys = np.log([r[y] for r in rows if r[y] > 0.01 or y != "total"])
    if len(xs) < 2:
        return float("nan")
    return float(np.polyfit(xs, ys, 1)[0])


def table(title: str, rows: list[dict], label: str) -> str:
    lines = [f"**{title}**", "", f"| {label} | n | segments | arcs | safe arcs | s partition | s safe BVG | s total |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['label']} | {r['n']} | {r['segments']:,} | {r['arcs']:,} | {r['safe']:,} | "
                     f"{r['partition']:.3f} | {r['bvg']:.3f} | {r['total']:.3f} |")
    big = [r for r in rows if r["total"] >= 0.05]  # tiny sizes are dominated by fixed costs
    lines += ["", f"fitted exponents (sizes with total ≥ 0.05 s: {', '.join(str(r['n']) for r in big)}): "
              f"time ∝ n^{fit(big, 'n', 'total'):.2f}, time ∝ arcs^{fit(big, 'arcs', 'total'):.2f}; "
              f"over all sizes arcs ∝ n^{fit(rows, 'n', 'arcs'):.2f}, segments ∝ n^{fit(rows, 'n', 'segments'):.2f}", ""]
    return "\n".join(lines)


def sweep(family: Iterable[tuple[str, str, Environment]], args: argparse.Namespace) -> list[dict]:
    """Measure each environment of ``family`` (label, name shown, environment; made as it is reached) in turn, the
    best of ``--repeat`` runs when one takes under 2 s, until one takes over ``--budget`` seconds."""
    rows = []
    for label, shown, env in family:
        row = measure(env, 1)
        if row["total"] < 2.0 and args.repeat > 1:
            row = measure(env, args.repeat)
        rows.append({**row, "label": label})
        print(f"  {shown}: {row['segments']} segments, {row['arcs']} arcs, {row['total']:.3f} s", flush=True)
        if row["total"] > args.budget:
            break
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=60.0, help="stop a family after a size slower than this (s)")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many runs for sizes under 2 s")
    parser.add_argument("--max-n", type=int, default=1000, help="largest star polygon")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, numpy {np.__version__}\n")
    stars = sweep(((f"star n={n}", f"star n={n}", star_polygon(n, 0.2, 0.3, seed=1))
                   for n in STAR_SIZES if n <= args.max_n), args)
    worst = sweep(((f"t={t}", f"worst case t={t}", worst_case_polygon(t)) for t in WORST_CASE_T), args)
    print()
    print(table("Random star polygons (irregularity 0.2, spikiness 0.3, seed 1)", stars, "polygon"))
    print(table("The paper's worst case, n = 4t + 2", worst, "t"))


if __name__ == "__main__":
    main()
