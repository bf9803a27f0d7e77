"""Searches over position sets and beliefs: ``localize`` on every shipped model, the narrow-door funnel, and
belief-state tolerance queries from two edges of a 100-vertex star.

Run ``python benchmarks/bench_positions.py`` from the repository root (package importable). Three tables:

1. ``solverplan --compact localize MODEL --epsilon 0.1`` for every model of ``solverplan/models`` (whole
   process, from the whole boundary): status, stages, what cut a search that found nothing
   (``optimality.limits``), the best wall time of ``--repeat`` runs and that run's CPU time (user + system:
   on a shared machine the wall time also counts waiting for a core);
2. ``solverplan --compact funnel narrow_door --from e0 --to e4`` the same way;
3. ``--queries`` random belief-state queries ``find_plan(env, "eA,eB", "eC", objective="tolerance")`` on
   ``star_polygon(100, 0.2, 0.3, seed=1)`` with the safe BVG built once (in process: median and worst query
   time), then the worst query again as a whole process (``solverplan generate star ...`` written once, then
   ``solverplan plan STAR --from eA,eB --to eC --objective tolerance``, which also builds the graph).

Each command runs once untimed first (bytecode cache warm, kept outside the tree, as for an installed package).
``--wait-load L`` waits until the 1-minute load average is below L. The recorded results are in
``benchmarks/README.md``, "Localisation, funnels and belief queries". Not a test (pytest collects ``tests/``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_cli import child_environment, cpu_model, run_measured, solverplan_command, wait_for_load  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
MODELS = sorted(p.stem for p in (ROOT / "solverplan" / "models").glob("*.json"))


def timed(args: list[str], env: dict[str, str]) -> tuple[float, float, dict]:
    """(wall seconds, CPU seconds of the child, parsed JSON answer) of one run of ``args``."""
    wall, cpu, _, out = run_measured(args, env)
    return wall, cpu, json.loads(out)


def best_of(args: list[str], env: dict[str, str], repeat: int) -> tuple[float, float, dict]:
    timed(args, env)  # warm the bytecode cache
    runs = [timed(args, env) for _ in range(repeat)]
    return min(runs, key=lambda r: r[0])


def belief_queries(n_queries: int, seed: int) -> list[tuple[float, str, str, str]]:
    """(seconds, start, goal, status) of random two-edge tolerance queries on the 100-vertex star, slowest first."""
    from solverplan.bounce.bvg import safe_bounce_visibility_graph
    from solverplan.plan import find_plan
    from solverplan.generators import star_polygon

    env = star_polygon(100, 0.2, 0.3, seed=1)
    graph = safe_bounce_visibility_graph(env)
    rng = random.Random(seed)
    out = []
    for _ in range(n_queries):
        a, goal, b = rng.sample(range(env.n_edges), 3)
        start = f"e{a},e{b}"
        t0 = time.perf_counter()
        plan = find_plan(env, start, f"e{goal}", objective="tolerance", graph=graph)
        out.append((time.perf_counter() - t0, start, f"e{goal}", plan.status.value))
    return sorted(out, reverse=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per command (the best is reported)")
    parser.add_argument("--queries", type=int, default=12, help="random belief queries")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--wait-load", type=float, default=None)
    parser.add_argument("--max-wait", type=float, default=600.0)
    opts = parser.parse_args()
    cli = solverplan_command()
    print(f"python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores, {cpu_model()}\n")
    with tempfile.TemporaryDirectory() as tmp:
        env = child_environment(Path(tmp) / "pycache")
        print("| model | status | stages | cut | wall (s) | CPU (s) | load |")
        print("|---|---|---:|---|---:|---:|---:|")
        for name in MODELS:
            wait_for_load(opts.wait_load, opts.max_wait)
            load = os.getloadavg()[0]
            wall, cpu, answer = best_of([*cli, "--compact", "localize", name, "--epsilon", "0.1"], env, opts.repeat)
            limits = (answer.get("optimality") or {}).get("limits") or []
            cut = next((x[4:] for x in limits if x.startswith("cut=")), "–")
            print(f"| {name} | {answer['status']} | {len(answer.get('stages') or [])} | {cut} | {wall:.2f} | "
                  f"{cpu:.2f} | {load:.1f} |")
        wait_for_load(opts.wait_load, opts.max_wait)
        load = os.getloadavg()[0]
        wall, cpu, answer = best_of([*cli, "--compact", "funnel", "narrow_door", "--from", "e0", "--to", "e4"], env,
                                    opts.repeat)
        print(f"\nfunnel narrow_door e0 → e4: {answer['status']}, {len(answer['stages'])} stages, "
              f"wall {wall:.2f} s, CPU {cpu:.2f} s (load {load:.1f})\n")
        wait_for_load(opts.wait_load, opts.max_wait)
        load = os.getloadavg()[0]
        queries = belief_queries(opts.queries, opts.seed)
        times = [q[0] for q in queries]
        print(f"belief tolerance queries (star n = 100, two-edge starts, {len(queries)} queries, in process, load "
              f"{load:.1f}): median {statistics.median(times):.2f} s, worst {times[0]:.2f} s "
              f"({queries[0][1]} → {queries[0][2]}, {queries[0][3]})")
        star = Path(tmp) / "star100.json"
        subprocess.run([*cli, "generate", "star", "--n", "100", "--irregularity", "0.2", "--spikiness", "0.3",
                        "--radius", "1", "--seed", "1", "-o", str(star)], env=env, check=True)
        wall, cpu, answer = best_of([*cli, "--compact", "plan", str(star), "--from", queries[0][1], "--to",
                                     queries[0][2], "--objective", "tolerance"], env, opts.repeat)
        print(f"the worst as a process (graph built too): {answer['status']}, wall {wall:.2f} s, CPU {cpu:.2f} s")


if __name__ == "__main__":
    main()
