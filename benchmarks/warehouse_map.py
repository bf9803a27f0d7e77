"""SLAM-style occupancy maps of depots and warehouses (ROS ``map_server`` PGM + YAML) for the benchmarks of issue #24.

``warehouse_map(width, height, seed)`` draws, at 5 cm per cell: an outer wall (30 cm) around the floor, with the
unknown space beyond it; rows of pallet racks (1.1 m deep, 2.7 m per bay, a gap between bays, aisles of 3 m); a grid
of square building posts (40 cm) in the cross aisle; a loading dock (a notch in the wall); and then what a lidar map
looks like — every cell along a wall flipped with probability ``ragged`` (so the traced outline has a vertex every cell
or two), lost wall cells, and specks of clutter. ``write_map(folder, ...)`` saves ``NAME.pgm`` and ``NAME.yaml``.

Run it as a script to write the maps the benchmark uses: ``python benchmarks/warehouse_map.py OUT_DIR``.
This is not a test (nothing here is named ``test_*``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

RESOLUTION = 0.05
FREE, OCCUPIED, UNKNOWN = 254, 0, 205


def warehouse_map(width: float, height: float, *, seed: int = 0, rack_rows: int | None = None,
                  bays: int | None = None, posts: bool = True, ragged: float = 0.3, specks: float = 0.0005) -> np.ndarray:
    """A (rows, columns) uint8 occupancy image of a width × height metre warehouse (see the module docstring)."""
    rng = np.random.default_rng(seed)
    cells = lambda m: int(round(m / RESOLUTION))  # noqa: E731
    margin, wall = 10, cells(0.3)
    h, w = cells(height) + 2 * margin + 2 * wall, cells(width) + 2 * margin + 2 * wall
    image = np.full((h, w), UNKNOWN, np.uint8)
    image[margin:h - margin, margin:w - margin] = OCCUPIED
    lo_r, hi_r, lo_c, hi_c = margin + wall, h - margin - wall, margin + wall, w - margin - wall
    image[lo_r:hi_r, lo_c:hi_c] = FREE
    # a loading dock: a notch 4 m wide and 1.5 m deep in the bottom wall
    dock = lo_c + cells(width) // 3
    image[hi_r:hi_r + cells(1.5) - 10, dock:dock + cells(4.0)] = FREE
    # racks: double rows 2.2 m deep running along x, aisles of 3 m; a cross aisle of 4 m in the middle
    depth, aisle, bay, gap = cells(2.2), cells(3.0), cells(2.7), cells(0.5)
    cross = (lo_c + hi_c) // 2
    n_rows = rack_rows if rack_rows is not None else max(1, int((height - 6.0) // 5.2))
    top = lo_r + cells(3.0)
    for r in range(n_rows):
        r0 = top + r * (depth + aisle)
        if r0 + depth > hi_r - cells(3.0):
            break
        for side in (0, 1):  # racks left and right of the cross aisle
            c_start = lo_c + cells(3.0) if side == 0 else cross + cells(2.0)
            c_stop = cross - cells(2.0) if side == 0 else hi_c - cells(3.0)
            k, c0 = 0, c_start
            while c0 + bay <= c_stop and (bays is None or k < bays):
                image[r0:r0 + depth, c0:c0 + bay] = OCCUPIED
                c0 += bay + gap
                k += 1
    if posts:  # building posts in the cross aisle and along the walls
        post = cells(0.4)
        for r0 in range(lo_r + cells(5.0), hi_r - cells(2.0), cells(10.0)):
            for c0 in (cross - post // 2, lo_c + cells(1.2), hi_c - cells(1.2) - post):
                image[r0:r0 + post, c0:c0 + post] = OCCUPIED
    # lidar artefacts: ragged walls, clutter
    free = image == FREE
    border = (free ^ np.roll(free, 1, 0)) | (free ^ np.roll(free, -1, 0)) | (free ^ np.roll(free, 1, 1)) | (free ^ np.roll(free, -1, 1))
    flip = border & (image != UNKNOWN) & (rng.random(image.shape) < ragged)
    image[flip] = np.where(image[flip] == FREE, OCCUPIED, FREE)
    speck = (rng.random(image.shape) < specks) & (image == FREE)
    image[speck] = OCCUPIED
    return image


def write_map(folder: str | Path, name: str, image: np.ndarray) -> Path:
    """Save ``image`` as ``folder/name.pgm`` with its ``name.yaml`` (resolution 5 cm, origin 0); return the YAML."""
    from PIL import Image

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(folder / f"{name}.pgm")
    yaml = folder / f"{name}.yaml"
    yaml.write_text(f"image: {name}.pgm\nresolution: {RESOLUTION}\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                    "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    return yaml


SIZES = {  # name: (width m, height m)
    "depot": (30.0, 15.0),
    "warehouse": (30.0, 50.0),
    "warehouse_xl": (60.0, 50.0),
}


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "maps")
    for name, (width, height) in SIZES.items():
        print(write_map(out, name, warehouse_map(width, height)))
