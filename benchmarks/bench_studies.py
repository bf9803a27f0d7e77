"""Study speed: time per polygon against n, and the paper's full grid on 1 and 2 workers.

Run ``python benchmarks/bench_studies.py`` from the repository root (package installed). It prints
markdown tables, recorded in ``benchmarks/README.md`` ("Studies"):

1. **Per polygon against n**: star polygons (irregularity 0.25, spikiness 0.3, 10 seeds per n), the
   median time of each stage of a reachability row: generate, partition (Algorithm 1), safe BVG,
   the metrics (reachability + connectivity), and the whole row (``run_task``).
2. **The paper's grid** (5 × 5 cells × 10 star polygons, n = 20) for ``reachability`` and
   ``connectivity``, and the same grid at n = 40 (rows ~4× dearer): wall time of :func:`run_study` from a cold start (the pool is created inside
   the timing), with 1 worker (in process) and with 2 worker processes, best of ``--repeat``; the
   speed-up is t(1) / t(2); "first row" is when the first row arrived (the pool's start-up). The target: the full grid in under 60 s on 2 cores.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.bounce.partitions import partition
from solverplan.studies import ReachabilityMetric, build_study, run_study
from solverplan.generators import star_polygon
from solverplan.studies.metrics import component_counts, unreachable_fraction
from solverplan.studies.study import PAPER_GRID, Task, run_task


def per_polygon(ns: list[int], seeds: int) -> list[dict]:
    rows = []
    for n in ns:
        stages: dict[str, list[float]] = {k: [] for k in ("generate", "partition", "safe BVG", "metrics", "row")}
        segments, arcs = [], []
        for seed in range(seeds):
            t0 = time.perf_counter()
            env = star_polygon(n, 0.25, 0.3, seed=seed)
            t1 = time.perf_counter()
            p = partition(env)
            t2 = time.perf_counter()
            g = safe_bounce_visibility_graph(p)
            t3 = time.perf_counter()
            lengths = np.hypot(*(np.asarray(p.seg_end) - np.asarray(p.seg_start)).T)
            src, dst = g.source[g.safe], g.target[g.safe]
            unreachable_fraction(lengths, src, dst)
            component_counts(g.n_segments, src, dst, lengths)
            t4 = time.perf_counter()
            task = Task(0, 0, seed, "star", (("n", n), ("irregularity", 0.25), ("spikiness", 0.3)), (), ReachabilityMetric())
            t5 = time.perf_counter()
            run_task(task)
            t6 = time.perf_counter()
            for key, dt in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t6 - t5)):
                stages[key].append(dt)
            segments.append(g.n_segments)
            arcs.append(g.n_arcs)
        rows.append({"n": n, "segments": statistics.median(segments), "arcs": statistics.median(arcs),
                     **{k: statistics.median(v) for k, v in stages.items()}})
    return rows


def grid_times(repeat: int) -> list[dict]:
    out = []
    for name, n in (("reachability", 20), ("connectivity", 20), ("reachability", 40)):
        study = build_study(name, grid=[f"n={n}"])
        assert dict(study.grid)["irregularity"] == dict(PAPER_GRID)["irregularity"] and study.per_cell == 10
        times, first = {}, {}
        for workers in (1, 2):
            best = float("inf")
            for _ in range(repeat):
                t0 = time.perf_counter()
                started: list[float] = []

                def progress(done: int, total: int) -> None:
                    if done == 1:
                        started.append(time.perf_counter() - t0)

                result = run_study(study, None, workers=workers, progress=progress)
                elapsed = time.perf_counter() - t0
                assert len(result.table.rows) == 250
                if elapsed < best:
                    best, first[workers] = elapsed, started[0]
            times[workers] = best
        out.append({"study": name, "n": n, "rows": 250, "t1": times[1], "t2": times[2], "first2": first[2],
                    "speedup": times[1] / times[2]})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ns", default="10,20,40,80,160", help="polygon sizes for the per-polygon table")
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    rows = per_polygon([int(n) for n in args.ns.split(",")], args.seeds)
    print("| n | segments | arcs | generate (ms) | partition (ms) | safe BVG (ms) | metrics (ms) | whole row (ms) |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['n']} | {r['segments']:.0f} | {r['arcs']:.0f} | {1e3 * r['generate']:.1f} | {1e3 * r['partition']:.1f} | "
              f"{1e3 * r['safe BVG']:.1f} | {1e3 * r['metrics']:.1f} | {1e3 * r['row']:.1f} |")
    print()
    print("| study | n | rows | 1 worker (s) | 2 workers (s) | first row, 2 workers (s) | speed-up |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for r in grid_times(args.repeat):
        print(f"| {r['study']} | {r['n']} | {r['rows']} | {r['t1']:.2f} | {r['t2']:.2f} | {r['first2']:.2f} | {r['speedup']:.2f}× |")


if __name__ == "__main__":  # the process pool (forkserver) re-imports this module in its workers
    main()
