"""Whole-process costs on SLAM-style warehouse maps (issue #24): import, a tolerance plan, the star n = 1,000 graph.

Run ``python benchmarks/bench_maps.py [--sizes depot,warehouse] [--timeout 60]`` from the repository root (the
package importable: installed or ``PYTHONPATH=.``). For each map of ``benchmarks/warehouse_map.py`` it writes the
PGM + YAML to a temporary folder and runs, each as a subprocess (wall time, CPU time and peak resident memory of
the process from ``wait4``):

1. ``solverplan import MAP.yaml -o ENV.json`` with the defaults (vertices and holes of the environment), and with
   ``--simplify 0 --rectilinear 0`` for the traced vertices;
2. ``solverplan --quiet --graph-cache off plan ENV.json --from e0 --to eK --objective tolerance --timeout T`` (K: the edge half-way
   round the outer ring; status, arcs the query built against the segments of P′, the sources it reached);
3. ``solverplan graph star_1000.json --safe -o G.json`` on the 1,000-vertex star of the other benchmarks;
4. start-up: ``solverplan --help`` and ``solverplan info square``.

The machine is shared: every figure is one run (``--repeat`` for more); read them with the load printed at the top.
This script is not a test (nothing here is named ``test_*``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from warehouse_map import SIZES, warehouse_map, write_map  # noqa: E402

CLI = [sys.executable, "-m", "solverplan.cli"]


def run(args: list[str], timeout: float = 900.0) -> tuple[float, float, float, subprocess.CompletedProcess]:
    """(wall s, CPU s, peak RSS MB, the finished process) of one command."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
    wall = time.perf_counter() - t0
    import resource

    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.CompletedProcess(args, proc.returncode, out, err)
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, done


def child(args: list[str], timeout: float = 900.0) -> tuple[float, float, float, subprocess.CompletedProcess]:
    """:func:`run` in a fresh helper process, so the CPU time and peak memory are this command's alone."""
    code = ("import json, sys; sys.path.insert(0, %r); from bench_maps import run; "
            "w, c, m, p = run(%r, %r); print(json.dumps([w, c, m, p.returncode, p.stdout[-200000:], p.stderr[-2000:]]))"
            % (str(Path(__file__).resolve().parent), args, timeout))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    w, c, m, rc, so, se = json.loads(out)
    return w, c, m, subprocess.CompletedProcess(args, rc, so, se)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="depot,warehouse")
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--skip-star", action="store_true")
    options = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores\n")
    folder = Path(tempfile.mkdtemp())
    print("| map | size (m) | traced vertices | vertices | holes | import s | plan status | plan s (wall / CPU) | peak MB | "
          "segments of P′ | arcs built | sources reached |")
    print("|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|")
    for name in options.sizes.split(","):
        width, height = SIZES[name]
        yaml = write_map(folder, name, warehouse_map(width, height))
        env_file = folder / f"{name}.json"
        w_imp, _, _, p = child(CLI + ["import", str(yaml), "-o", str(env_file)])
        info = json.loads(p.stdout)
        _, _, _, raw = child(CLI + ["import", str(yaml), "-o", str(folder / f"{name}_raw.json"), "--simplify", "0",
                                    "--rectilinear", "0"])
        traced = json.loads(raw.stdout)["vertices"]
        from solverplan.environment import load_environment

        environment = load_environment(env_file)
        goal = f"e{len(environment.rings[0]) // 2}"
        w, c, m, p = child(CLI + ["--quiet", "--graph-cache", "off", "plan", str(env_file), "--from", "e0", "--to", goal, "--objective",
                                  "tolerance", "--timeout", str(options.timeout)], timeout=options.timeout * 3)
        try:
            answer = json.loads(p.stdout)
            status, stats = answer["status"], answer.get("stats", {})
            if answer.get("optimality", {}).get("limits"):
                status += " (timeout)"
        except json.JSONDecodeError:
            status, stats = f"exit {p.returncode}: {p.stderr.strip()[-120:]}", {}
        print(f"| {name} | {width:g} × {height:g} | {traced:,} | {environment.n_vertices:,} | "
              f"{info.get('holes')} | {w_imp:.1f} | {status} | {w:.1f} / {c:.1f} | {m:.0f} | "
              f"{stats.get('graph_segments', '–')} | {stats.get('graph_arcs', '–')} | "
              f"{stats.get('graph_reachable_sources', 'all' if 'graph_arcs' in stats else '–')} |")
    if not options.skip_star:
        from solverplan.generators import star_polygon

        star = folder / "star_1000.json"
        star.write_text(json.dumps(star_polygon(1000, 0.2, 0.3, seed=1).to_dict()))
        w, c, m, p = child(CLI + ["--graph-cache", "off", "graph", str(star), "--safe", "-o", str(folder / "g.json")])
        print(f"\nstar n = 1,000, `graph --safe -o G.json` (cache off): {w:.1f} s wall, {c:.1f} s CPU, {m:.0f} MB peak, "
              f"exit {p.returncode}")
    for args in (["--help"], ["info", "square"]):
        w, c, m, p = child(CLI + args)
        print(f"`solverplan {' '.join(args)}`: {w:.2f} s wall, {c:.2f} s CPU, {m:.0f} MB")


if __name__ == "__main__":
    main()
