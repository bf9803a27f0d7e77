"""Whole-process time and memory of loading (reading and validating) large environment files.

Run ``python benchmarks/bench_environment.py`` from the repository root (package installed in that
Python's environment). It writes three families of floor plans to a temporary folder, at 1,000,
10,000 and 100,000 vertices (the documented limit):

- ``star``: a radial star, vertices alternating at radius 1000 and 1300 around the circle, six
  decimals: long thin edges whose bounding boxes overlap thousands of others;
- ``room``: a rectilinear room, its floor wall a row of small steps, with square pillars (holes)
  on a grid (1,000 of them at 100,000 vertices): many equal coordinates and collinear edges;
- ``slam``: a scanned room outline, a rounded rectangle with millimetre noise, four decimals.

For each file it times, as subprocesses (``/usr/bin/time -v`` when present): ``load``, a Python
process that imports solverplan and calls ``load_environment`` (the validation of every ring, every
crossing and the nesting of holes, exactly), and ``info``, the command ``solverplan info FILE -o
OUT`` (load, then describe every vertex and edge in JSON). The table gives the best wall time of
``--repeat`` runs, the peak resident memory of that run, and the 1-minute load average. This
script is not a test (pytest collects only ``tests/``, ``solverplan/`` and ``proofs/``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LOAD = "import sys; from solverplan.environment import load_environment; load_environment(sys.argv[1])"


def star(n: int) -> dict:
    """A radial star of ``n`` vertices (n even)."""
    outer = [[round(r * math.cos(a), 6), round(r * math.sin(a), 6)]
             for k in range(n) for r, a in [(1000 if k % 2 == 0 else 1300, 2 * math.pi * k / n)]]
    return {"name": f"star{n}", "outer": outer}


def room(n: int) -> dict:
    """A rectilinear room of about ``n`` vertices: n/100 square pillars, the rest steps of its floor wall."""
    side = max(1, round(math.sqrt(n / 100)))
    holes = []
    for i in range(side):
        for j in range(side):
            x, y = 10 + 20 * i, 10 + 20 * j
            holes.append([[x, y], [x + 5, y], [x + 5, y + 5], [x, y + 5]])
    width, height = 20 * side + 10, 20 * side + 10
    steps = max(1, (n - 4 * len(holes) - 4) // 4)
    floor = []
    for k in range(steps):
        x0 = width * k / steps
        x1, x2 = width * (k + 0.5) / steps, width * (k + 0.75) / steps
        floor += [[round(x0, 6), 0], [round(x1, 6), 0], [round(x1, 6), -1], [round(x2, 6), -1]]
    outer = floor + [[width, 0], [width, height], [0, height], [0, 0.5]]
    return {"name": f"room{n}", "outer": outer, "holes": holes}


def slam(n: int, seed: int = 1) -> dict:
    """A scanned outline: a rounded rectangle (superellipse, 10 m) with ±2 cm radial noise, four decimals."""
    rnd = random.Random(seed)
    outer = []
    for k in range(n):
        a = 2 * math.pi * k / n
        c, s = math.cos(a), math.sin(a)
        r = 5000 / (abs(c) ** 8 + abs(s) ** 8) ** (1 / 8) + rnd.uniform(-20, 20)
        outer.append([round(r * c, 4), round(r * s, 4)])
    return {"name": f"slam{n}", "outer": outer}


def timed(command: list[str]) -> tuple[float, float | None]:
    """Wall seconds and peak resident MB of one run of ``command`` (MB from ``/usr/bin/time -v``)."""
    gnu_time = Path("/usr/bin/time")
    wrapped = [str(gnu_time), "-v", *command] if gnu_time.exists() else command
    start = time.perf_counter()
    done = subprocess.run(wrapped, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed: {done.stderr.strip().splitlines()[-1]}")
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)
    return wall, (int(peak.group(1)) / 1024 if peak else None)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000", help="vertex counts, comma-separated")
    parser.add_argument("--repeat", type=int, default=3, help="runs per command (best is reported)")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    script = Path(sys.executable).with_name("solverplan")
    cli = [str(script)] if script.exists() else [sys.executable, "-c", "from solverplan.cli import main; main()"]
    print(f"{os.cpu_count()} cores, Python {sys.version.split()[0]}")
    print("| family | vertices | holes | load (s) | load (MB) | info (s) | info (MB) | load average |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for family in (star, room, slam):
            for n in sizes:
                data = family(n)
                path = Path(folder) / f"{data['name']}.json"
                path.write_text(json.dumps(data))
                vertices = len(data["outer"]) + sum(map(len, data.get("holes", [])))
                runs = {}
                for label, command in [("load", [sys.executable, "-c", LOAD, str(path)]),
                                       ("info", [*cli, "info", str(path), "-o", str(path.with_suffix(".out"))])]:
                    runs[label] = min((timed(command) for _ in range(args.repeat)), key=lambda run: run[0])
                load_average = os.getloadavg()[0]
                (load_s, load_mb), (info_s, info_mb) = runs["load"], runs["info"]
                print(f"| {family.__name__} | {vertices:,} | {len(data.get('holes', []))} | {load_s:.2f} | "
                      f"{load_mb or float('nan'):.0f} | {info_s:.2f} | {info_mb or float('nan'):.0f} | {load_average:.1f} |",
                      flush=True)


if __name__ == "__main__":
    main()
