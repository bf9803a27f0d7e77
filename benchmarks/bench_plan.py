"""Planning queries on large safe BVGs (target: queries on a 1,000-node safe BVG answer in well under a second).

Run ``python benchmarks/bench_plan.py`` from the repository root (package installed). For random star
polygons ``star_polygon(n, 0.2, 0.3, seed=1)`` (the paper's §7.3 family) of growing size, the safe BVG is
built once (not timed here: ``bench_bvg.py`` measures it), then ``--queries`` random queries per objective
are answered with that graph: start and goal are random single edges, and for the belief-state rows a start
of two random edges (the robot does not know which one it is on). Printed: a markdown table with the
segments (nodes) and safe arcs of the graph, and per objective the median and the worst query time, the
number of feasible answers, and the median bounces of the feasible plans. Results are recorded in
``benchmarks/README.md``.
"""

from __future__ import annotations

import argparse
import platform
import random
import statistics
import time

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.plan import find_plan, pareto_front
from solverplan.generators import star_polygon

QUERIES = [
    ("fewest", None, "single"),
    ("tolerance", None, "single"),
    ("tolerance", 8, "single"),
    ("constant", 8, "single"),
    ("sum", 6, "single"),
    ("pareto", 10, "single"),
    ("fewest", None, "two edges"),
    ("tolerance", None, "two edges"),
]


def run(sizes: list[int], n_queries: int, seed: int) -> None:
    print(f"python {platform.python_version()}, {platform.machine()}; {n_queries} random queries per row, seed {seed}\n")
    print("| n | segments | safe arcs | objective | K | start | median (s) | worst (s) | feasible | median bounces |")
    print("|---:|---:|---:|---|---:|---|---:|---:|---:|---:|")
    for n in sizes:
        env = star_polygon(n, 0.2, 0.3, seed=1)
        graph = safe_bounce_visibility_graph(env)
        rng = random.Random(seed)
        for objective, k, kind in QUERIES:
            times, bounces, feasible = [], [], 0
            for _ in range(n_queries):
                edges = rng.sample(range(env.n_edges), 3)
                start = f"e{edges[0]}" if kind == "single" else f"e{edges[0]},e{edges[2]}"
                goal = f"e{edges[1]}"
                t0 = time.perf_counter()
                if objective == "pareto":
                    front = pareto_front(env, start, goal, max_bounces=k, graph=graph)
                    ok, b = bool(front.points), (front.points[-1].bounces if front.points else None)
                else:
                    plan = find_plan(env, start, goal, objective=objective, max_bounces=k, graph=graph)
                    ok, b = plan.found, plan.bounces
                times.append(time.perf_counter() - t0)
                if ok:
                    feasible += 1
                    bounces.append(b)
            med_b = f"{statistics.median(bounces):g}" if bounces else "–"
            print(f"| {n} | {graph.n_segments} | {graph.n_safe_arcs} | {objective} | {k or '–'} | {kind} | "
                  f"{statistics.median(times):.4f} | {max(times):.4f} | {feasible}/{n_queries} | {med_b} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[20, 80, 140])
    parser.add_argument("--queries", type=int, default=20)
    parser.add_argument("--seed", type=int, default=5)
    args = parser.parse_args()
    run(args.sizes, args.queries, args.seed)


if __name__ == "__main__":
    main()
