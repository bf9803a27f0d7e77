"""Occupancy maps made from known polygons: rasterised at a resolution, with sensor-like noise, written as ROS maps."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely
from PIL import Image

FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # the pixel values ROS's map_saver writes


def rasterise(polygon, resolution: float, *, wall: float = 0.3, margin: float = 1.0, speckle: float = 0.0,
              ragged: float = 0.0, unknown_margin: bool = True, seed: int = 0) -> tuple[np.ndarray, tuple[float, float]]:
    """Pixels of ``polygon``'s free space (a cell is free when its centre is inside), walls ``wall`` thick
    around it, unknown beyond (or occupied with ``unknown_margin=False``); returns (image rows top first, origin).

    Noise: ``speckle`` is the share of free cells turned occupied and of wall cells turned free (isolated
    specks); ``ragged`` the share of cells along the walls (one cell either side of the boundary) flipped.
    """
    rng = np.random.default_rng(seed)
    minx, miny, maxx, maxy = polygon.bounds
    ox, oy = minx - margin, miny - margin
    columns = int(np.ceil((maxx - minx + 2 * margin) / resolution))
    rows = int(np.ceil((maxy - miny + 2 * margin) / resolution))
    xs = ox + (np.arange(columns) + 0.5) * resolution
    ys = oy + (rows - np.arange(rows) - 0.5) * resolution  # row 0 is the top of the image
    gx, gy = np.meshgrid(xs, ys)
    inside = shapely.contains_xy(polygon, gx, gy)
    near = shapely.contains_xy(polygon.buffer(wall, join_style="mitre"), gx, gy) & ~inside
    image = np.full((rows, columns), UNKNOWN if unknown_margin else OCCUPIED, np.uint8)
    image[near] = OCCUPIED
    image[inside] = FREE
    if ragged:
        band = shapely.contains_xy(polygon.boundary.buffer(resolution), gx, gy)
        flip = band & (rng.random(image.shape) < ragged)
        image[flip & inside] = OCCUPIED
        image[flip & near] = FREE
    if speckle:
        specks = rng.random(image.shape) < speckle
        image[specks & inside] = OCCUPIED
        image[specks & near] = FREE
    return image, (ox, oy)


def write_map(folder: Path, image: np.ndarray, origin: tuple[float, float], resolution: float, *, name: str = "map",
              suffix: str = ".pgm", extra: str = "") -> Path:
    """Write ``image`` and its YAML (thresholds of map_saver); returns the YAML's path."""
    Image.fromarray(image).save(folder / f"{name}{suffix}")
    yaml = (f"image: {name}{suffix}\nresolution: {resolution!r}\norigin: [{origin[0]!r}, {origin[1]!r}, 0.0]\n"
            f"negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n{extra}")
    path = folder / f"{name}.yaml"
    path.write_text(yaml)
    return path


def office_polygon():
    """An 8 m × 6 m floor with an L-shaped notch, a rectangular pillar and a slanted cabinet (two holes)."""
    outer = [(0, 0), (8, 0), (8, 4), (6, 4), (6, 6), (0, 6)]
    pillar = [(2, 2), (3, 2), (3, 3), (2, 3)]
    cabinet = [(4.5, 1.0), (5.5, 1.6), (5.1, 2.3), (4.1, 1.7)]
    return shapely.Polygon(outer, [pillar, cabinet])
