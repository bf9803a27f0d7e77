"""Whole-process cost of checking every answer before it leaves (issue #27), and of the graph cache's reads.

Run ``python benchmarks/bench_gate.py`` from the repository root; ``--before DIR`` also times another source tree
(e.g. ``git archive <commit> | tar -x -C DIR``) on the same commands, runs interleaved so that both see the same
load. Each command is a subprocess ``python -c 'from solverplan.cli import main; main()' ...`` with ``PYTHONPATH``
set to the tree; it runs once untimed (warm bytecode), then ``--repeat`` times. The table gives, per tree and
command, the median wall time, the median user+system CPU time and the peak resident memory (all from ``/usr/bin/time``), and the 1-minute load average when the runs started. The recorded results are in
``benchmarks/README.md``, "Checking answers before they leave". Not a test (nothing here is named ``test_*``).

Commands:

- ``plan two_rooms --from e0:0.2:0.8 --to e4:0.5:1 --objective tolerance`` and the same with ``--pareto``, with the
  disk cache off (the graph is built: 980 arcs);
- the same two with a warm disk cache written with ``--graph-cache-min-arcs 0`` (after: the graph is read back,
  digest checked, and the answer still checked exactly).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

QUERY = ["plan", "two_rooms", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1"]
COMMANDS = {
    "tolerance": [*QUERY, "--objective", "tolerance"],
    "pareto": [*QUERY, "--pareto"],
}
CODE = "import sys; from solverplan.cli import main; sys.argv[0] = 'solverplan'; main()"


def run(tree: Path, args: list[str]) -> tuple[float, float, int]:
    """Wall seconds, CPU seconds (user + system) and peak RSS (KiB) of one subprocess, as /usr/bin/time reports them."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    with tempfile.NamedTemporaryFile("r") as report:
        # cwd=tree: ``python -c`` puts the working folder before PYTHONPATH on sys.path
        subprocess.run(["/usr/bin/time", "-f", "%e %U %S %M", "-o", report.name, sys.executable, "-c", CODE, *args],
                       env=env, cwd=tree, stdout=subprocess.DEVNULL, check=True)
        wall, user, system, rss = report.read().split()[-4:]
    return float(wall), float(user) + float(system), int(rss)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, help="another source tree to time on the same commands")
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args()
    trees = {"after": Path.cwd()}
    if args.before is not None:
        trees = {"before": args.before.resolve(), **trees}
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for name, command in COMMANDS.items():
            for cache in ("off", "warm"):
                per: dict[str, list[tuple[float, float, int]]] = {t: [] for t in trees}
                options = {}
                for tree_name, tree in trees.items():
                    where = Path(folder) / f"{tree_name}-{name}"
                    options[tree_name] = (["--graph-cache", "off"] if cache == "off" else
                                          ["--graph-cache", str(where), *(["--graph-cache-min-arcs", "0"] if tree_name == "after" else [])])
                    if cache == "warm" and tree_name == "before":
                        # the old tree writes graphs that took over a second only: write this one from the library
                        subprocess.run([sys.executable, "-c",
                                        "import sys; from solverplan.bounce import bvg; from solverplan.environment import "
                                        "load_environment as L; bvg.set_graph_cache(sys.argv[1], min_seconds=0.0); "
                                        "bvg.safe_bounce_visibility_graph(L('two_rooms'))", str(where)],
                                       env={**os.environ, "PYTHONPATH": str(tree)}, cwd=tree, check=True)
                    run(tree, [*options[tree_name], *command])  # warm-up (and cache fill)
                load = os.getloadavg()[0]
                for _ in range(args.repeat):
                    for tree_name, tree in trees.items():
                        per[tree_name].append(run(tree, [*options[tree_name], *command]))
                for tree_name, runs in per.items():
                    rows.append((name, cache, tree_name, statistics.median(r[0] for r in runs),
                                 statistics.median(r[1] for r in runs), max(r[2] for r in runs), load))
    print("| command | disk cache | tree | wall (s, median) | CPU (s, median) | peak RSS (MiB) | load |")
    print("|---|---|---|---|---|---|---|")
    for name, cache, tree_name, wall, cpu, rss, load in rows:
        print(f"| {name} | {cache} | {tree_name} | {wall:.3f} | {cpu:.3f} | {rss / 1024:.0f} | {load:.1f} |")
    print(f"\n{os.cpu_count()} cores, Python {sys.version.split()[0]}, {args.repeat} runs each")


if __name__ == "__main__":
    main()
