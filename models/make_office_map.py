"""Write ``office.yaml`` + ``office.pgm``: a small SLAM-style occupancy map of an office, for the README's tutorial.

Two rooms (4.6 m and 5.15 m by 6 m) side by side, split by a 25 cm wall with a 1 m door; a desk in the left room, a
table and a shelf against the wall in the right one. The map looks like one a laser SLAM run leaves: 5 cm cells,
walls 15 cm thick and ragged (cells along them flipped at random), unknown space beyond the walls and in the
shadows behind furniture the robot could not see past, stray returns (free specks inside walls and occupied specks
in the rooms), and a 10 cm-wide false corridor where a laser ray leaked through the outer wall.

Run from the repository root: ``python models/make_office_map.py`` (it writes next to itself; seeded, so the
files are the same every run).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

RESOLUTION = 0.05  # metres per cell
MARGIN = 0.5  # metres of unknown around the building
FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # the values ROS's map_saver writes
SEED = 2016


def _cells(x0: float, y0: float, x1: float, y1: float, rows: int) -> tuple[slice, slice]:
    """Image rows and columns of the world box [x0, x1] × [y0, y1] (metres; image rows grow downwards)."""
    c0, c1 = round((x0 + MARGIN) / RESOLUTION), round((x1 + MARGIN) / RESOLUTION)
    r0, r1 = rows - round((y1 + MARGIN) / RESOLUTION), rows - round((y0 + MARGIN) / RESOLUTION)
    return slice(r0, r1), slice(c0, c1)


def office_map(seed: int = SEED) -> np.ndarray:
    """The office's occupancy image (rows top first), 10 m × 6 m of rooms inside 15 cm walls."""
    rng = np.random.default_rng(seed)
    width, height, wall = 10.0, 6.0, 0.15
    rows = round((height + 2 * wall + 2 * MARGIN) / RESOLUTION)
    columns = round((width + 2 * wall + 2 * MARGIN) / RESOLUTION)
    image = np.full((rows, columns), UNKNOWN, np.uint8)
    box = lambda x0, y0, x1, y1: _cells(x0 + wall, y0 + wall, x1 + wall, y1 + wall, rows)  # noqa: E731
    image[box(-wall, -wall, width + wall, height + wall)] = OCCUPIED  # the building, walls included
    image[box(0, 0, width, height)] = FREE
    image[box(4.6, 0, 4.85, height)] = OCCUPIED  # the wall between the rooms ...
    image[box(4.6, 2.4, 4.85, 3.4)] = FREE  # ... and its door, 1 m wide
    image[box(1.2, 3.6, 2.8, 4.4)] = OCCUPIED  # a desk in the left room
    image[box(6.4, 1.4, 7.6, 2.6)] = OCCUPIED  # a table in the right room
    image[box(8.8, 4.2, 10, 6)] = OCCUPIED  # a shelf in the right room's far corner, against two walls
    image[box(2.8, 3.9, 3.2, 4.3)] = UNKNOWN  # a shadow the laser never saw behind the desk
    # ragged walls: cells next to a free/occupied border flipped with probability 0.25
    free = image == FREE
    border = free ^ np.roll(free, 1, 0) | free ^ np.roll(free, -1, 0) | free ^ np.roll(free, 1, 1) | free ^ np.roll(free, -1, 1)
    flip = border & (image != UNKNOWN) & (rng.random(image.shape) < 0.25)
    image[flip] = np.where(image[flip] == FREE, OCCUPIED, FREE)
    # stray returns: occupied specks in the rooms, free specks inside the walls
    specks = rng.random(image.shape) < 0.004
    image[specks & (image == FREE)] = OCCUPIED
    image[specks & (image == OCCUPIED)] = FREE
    # a ray that leaked through the bottom wall: a 2-cell-wide false corridor into the unknown outside
    image[box(3.0, -wall - 0.4, 3.1, 0.05)] = FREE
    return image


def main() -> None:
    here = Path(__file__).resolve().parent
    Image.fromarray(office_map()).save(here / "office.pgm")
    (here / "office.yaml").write_text(
        "image: office.pgm\n"
        f"resolution: {RESOLUTION}\n"
        f"origin: [{-MARGIN - 0.15}, {-MARGIN - 0.15}, 0.0]  # the rooms' lower-left corner is (0, 0)\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196\n"
        "mode: trinary\n"
    )


if __name__ == "__main__":
    main()
