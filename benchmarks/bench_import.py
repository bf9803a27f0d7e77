"""Whole-process time of ``solverplan import`` on a large SLAM-style occupancy map (the 5 s target at 2,000²).

Run ``python benchmarks/bench_import.py`` from the repository root (package importable by that Python:
installed, or ``PYTHONPATH=.``). It writes, to a temporary folder, a ROS map of N × N cells at 5 cm (N = 2,000 by
default: a 100 m × 100 m floor) — a grid of 10 m rooms behind 20 cm walls with 1 m doors, a column and a desk in
every room, ragged walls (a quarter of the cells along them flipped), specks (0.2 % of the cells), unknown space
beyond the building — and runs ``solverplan import MAP.yaml -o ENV.json [OPTIONS]`` as a subprocess ``--repeat``
times (after one untimed run that warms the bytecode cache), for the default options and for a coarser
simplification. The table gives the median wall time, the CPU time (user + system) and the peak resident memory of
the process, and the size of the environment written; the recorded results are in ``benchmarks/README.md``,
"Importing occupancy maps".

This script is not a test (nothing here is named ``test_*``); tests never time anything.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_cli import run_measured  # noqa: E402

RESOLUTION = 0.05
FREE, OCCUPIED, UNKNOWN = 254, 0, 205


def building_map(cells: int, seed: int = 0) -> np.ndarray:
    """A cells × cells occupancy image: rooms of 200 cells (10 m) with doors, a column and a desk in each, noise."""
    rng = np.random.default_rng(seed)
    image = np.full((cells, cells), UNKNOWN, np.uint8)
    margin, room, wall, door = 20, 200, 4, 20
    inner = slice(margin, cells - margin)
    image[inner, inner] = OCCUPIED
    lo, hi = margin + wall, cells - margin - wall
    image[lo:hi, lo:hi] = FREE
    for k in range(lo + room, hi - wall, room):  # interior walls, every room joined to the next by a door
        image[lo:hi, k:k + wall] = OCCUPIED
        image[k:k + wall, lo:hi] = OCCUPIED
        for j in range(lo, hi - room // 2, room):
            image[j + room // 2:j + room // 2 + door, k:k + wall] = FREE
            image[k:k + wall, j + room // 2:j + room // 2 + door] = FREE
    for i in range(lo, hi - room + 1, room):  # furniture: a column and a desk per room
        for j in range(lo, hi - room + 1, room):
            image[i + 40:i + 52, j + 40:j + 52] = OCCUPIED
            image[i + 120:i + 136, j + 90:j + 150] = OCCUPIED
    free = image == FREE
    border = free ^ np.roll(free, 1, 0) | free ^ np.roll(free, -1, 0) | free ^ np.roll(free, 1, 1) | free ^ np.roll(free, -1, 1)
    flip = border & (image != UNKNOWN) & (rng.random(image.shape) < 0.25)
    image[flip] = np.where(image[flip] == FREE, OCCUPIED, FREE)
    specks = (rng.random(image.shape) < 0.002) & (image != UNKNOWN)
    image[specks] = np.where(image[specks] == FREE, OCCUPIED, FREE)
    return image


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=2000, help="map side in cells (default 2000)")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per row (default 3)")
    args = parser.parse_args()
    command = [sys.executable, "-c", "import sys; from solverplan.cli import main; sys.argv[0] = 'solverplan'; main()"]
    with tempfile.TemporaryDirectory() as folder:
        base = Path(folder)
        Image.fromarray(building_map(args.cells)).save(base / "big.pgm")
        (base / "big.yaml").write_text(f"image: big.pgm\nresolution: {RESOLUTION}\norigin: [0.0, 0.0, 0.0]\n"
                                       "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
        print(f"map {args.cells} × {args.cells} cells at {RESOLUTION} m; machine: {os.cpu_count()} cores, "
              f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
              f"load {os.getloadavg()[0]:.2f}\n")
        print("| options | wall (s, median) | CPU (s, median) | peak RSS (MiB) | outer vertices | holes | vertices |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for options in ([], ["--simplify", "0.15", "--rectilinear", "10"]):
            run = [*command, "import", str(base / "big.yaml"), "-o", str(base / "big.json"), *options]
            run_measured(run)  # warm the bytecode cache
            results = [run_measured(run) for _ in range(args.repeat)]
            summary = json.loads(results[-1][3])
            print(f"| {' '.join(options) or '(defaults)'} | {statistics.median(r[0] for r in results):.2f} | "
                  f"{statistics.median(r[1] for r in results):.2f} | {max(r[2] for r in results)} | "
                  f"{summary['outer_vertices']:,} | {summary['holes']:,} | {summary['vertices']:,} |")


if __name__ == "__main__":
    main()
