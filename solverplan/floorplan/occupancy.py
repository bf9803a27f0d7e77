"""ROS ``map_server`` occupancy maps: the YAML description, the image, and the free space traced out of them.

A map is a YAML mapping (``image``, ``resolution``, ``origin``, ``negate``, ``occupied_thresh``,
``free_thresh``, ``mode``) next to a PGM or PNG image. A pixel of value v (0–255; colour pixels are the
mean of their channels) has occupancy p = (255 − v) / 255, or v / 255 with ``negate: 1``; it is **free**
when p < ``free_thresh``, occupied when p > ``occupied_thresh`` and unknown in between — and unknown is
never free. ``mode: raw`` reads v itself as the occupancy in percent (0 free, 100 occupied, above 100
unknown), free when v < 100 · ``free_thresh``. A (partly) transparent pixel is unknown, and so is a pixel of
map_saver's unknown grey (:data:`SAVER_UNKNOWN`) even when ``free_thresh`` is above its occupancy (with a warning).

World coordinates are metres: the lower-left corner of the lower-left pixel is at ``origin`` (x, y), the
image is turned by the origin's yaw about that corner (radians, counter-clockwise), x grows to the right
and y **up** (image rows grow down).

The free space is traced with SciPy's connected components (4-connected free cells, so two cells meeting at
a corner are not a passage) and morphological opening against spurs, then scikit-image's marching squares
(``skimage.measure.find_contours``) at the level halfway between free and not free, which puts every
axis-parallel wall on the cell edges; its diagonal steps (walls at an angle, traced as staircases) are put back on
the cell edges too, so the traced outline is the boundary of the free cells exactly.
"""

from __future__ import annotations

import io
import math
import struct
import zlib
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from solverplan._io import read_input_bytes, read_input_text, shown_path
from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.floorplan.drawing import DroppedFeature
from solverplan.floorplan.outline import finish_outline, grid_quantum
from solverplan.limits import BYTES_PER_PIXEL, MAX_PIXELS, quote, refuse_beyond_memory

__all__ = ["OccupancyMap", "read_occupancy_map", "trace_free_space", "DEFAULT_FREE_THRESH",
           "DEFAULT_OCCUPIED_THRESH", "DEFAULT_MIN_OBSTACLE", "AUTO_RECTILINEAR", "AXIS_PARALLEL_SHARE", "cell_to_world",
           "read_keepout_mask", "cells_to_polygons", "auto_simplification", "SAVER_UNKNOWN"]

DEFAULT_MIN_OBSTACLE = 0.06
"""The smallest obstacle a map import keeps by default (metres, the larger side of its bounding box): on the usual
5 cm maps a lone occupied cell is gone (a lidar speck — a SLAM map of a warehouse has hundreds, each a hole of four
reflex corners for the planner), two cells (a post of 10 cm) stay; on coarser maps every obstacle stays. Each one
dropped is listed where it was, and the import warns how many (``--min-obstacle 0`` keeps them)."""

AUTO_RECTILINEAR = 10.0
"""The snapping angle (degrees) a map import uses when ``rectilinear`` is not given and its walls are
overwhelmingly axis-parallel (:data:`AXIS_PARALLEL_SHARE` of their length within it)."""

AXIS_PARALLEL_SHARE = 0.9
"""The share of the walls' length (simplified within 3 cells) within :data:`AUTO_RECTILINEAR` of an axis above which a
map's walls are snapped by default."""

DEFAULT_OCCUPIED_THRESH = 0.65
"""``occupied_thresh`` when the YAML gives none (the value of ROS's map_saver)."""

DEFAULT_FREE_THRESH = 0.196
"""``free_thresh`` when the YAML gives none (the value of ROS's map_saver)."""

_MODES = ("trinary", "scale", "raw")

SAVER_UNKNOWN = 205
"""The grey level ROS's and Nav2's ``map_saver`` write for an unknown cell (occupancy (255 − 205) / 255 ≈ 0.196).
Nav2's saver writes ``free_thresh: 0.25`` by default, above that occupancy, so the YAML taken literally makes every
unknown cell free (Nav2's own map server then plans through unexplored space); in trinary and scale modes a pixel of
exactly this grey (50 with ``negate: 1``) is read as unknown whatever ``free_thresh`` says, and the import warns."""

MIN_RESOLUTION = Decimal("1e-9")
"""Finest map cell read (metres): a nanometre; finer cells make coordinates past the environment's resolution."""

MAX_RESOLUTION = Decimal("1e6")
"""Coarsest map cell read (metres): 1,000 km, so that a map's coordinates stay far inside the coordinate bound."""

MAX_ORIGIN = Decimal("1e12")
"""Largest origin coordinate (and yaw) read: a billion kilometres, far beyond any map."""


@dataclass(frozen=True)
class OccupancyMap:
    """An occupancy grid read from a ROS map.

    Attributes
    ----------
    free
        Boolean array, rows top to bottom as in the image: the free cells.
    occupied
        Boolean array: the occupied cells (neither free nor occupied is unknown).
    resolution
        Metres per cell, exact as written in the YAML.
    origin
        World coordinates (metres, exact) of the lower-left corner of the lower-left cell.
    yaw
        Rotation of the image about ``origin`` (radians, counter-clockwise).
    source
        The YAML file.
    image
        The image file.
    notes
        What reading the map decided that a user should know, one line each (e.g. :data:`SAVER_UNKNOWN` grey read
        as unknown against the YAML's ``free_thresh``); the import repeats them as warnings.
    """

    free: np.ndarray
    occupied: np.ndarray
    resolution: Decimal
    origin: tuple[Fraction, Fraction]
    yaw: float
    source: Path
    image: Path
    notes: tuple[str, ...] = ()

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, columns) of the grid."""
        return self.free.shape

    def cell_of(self, point: tuple[Fraction, Fraction]) -> tuple[int, int] | None:
        """The (row, column) of the cell holding a world point (metres), or ``None`` outside the image."""
        dx, dy = float(point[0] - self.origin[0]), float(point[1] - self.origin[1])
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        u, v = c * dx + s * dy, -s * dx + c * dy  # undo the yaw
        res = float(self.resolution)
        column, up = math.floor(u / res), math.floor(v / res)
        rows, columns = self.shape
        if not (0 <= column < columns and 0 <= up < rows):
            return None
        return rows - 1 - up, column


def _yaml_number(value: object) -> Decimal | None:
    """A YAML scalar as an exact decimal, or None if it is not a finite number.

    PyYAML follows YAML 1.1, which reads ``1e-3`` (no dot) as a string where ROS's yaml-cpp reads a number:
    numeric strings are numbers here too. Floats are taken at their shortest repr (the text written).
    """
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return Decimal(value)
    if isinstance(value, float):
        return Decimal(repr(value)) if math.isfinite(value) else None
    if isinstance(value, str) and len(value) <= 100:
        try:
            number = Decimal(value.strip())
        except InvalidOperation:
            return None
        return number if number.is_finite() else None
    return None


def _number(data: dict, key: str, source: Path, default: float | None = None) -> Decimal:
    value = data.get(key, default)
    if value is None:
        raise MalformedFile(f"{source}: missing {key!r} (a ROS map YAML has image, resolution and origin)")
    number = _yaml_number(value)
    if number is None:
        raise MalformedFile(f"{source}: {key} must be a number, got {quote(str(value))}")
    return number


MAX_MAP_YAML_BYTES = 1024 * 1024
"""Largest ROS map YAML read (bytes): the file is a handful of lines (image, resolution, origin, thresholds)."""

MAX_YAML_DEPTH = 32
"""Deepest nesting of lists and mappings in a ROS map YAML (it needs 2)."""


def _map_loader() -> type:
    """PyYAML's safe loader without aliases and with bounded nesting.

    A ROS map YAML never needs an alias (``*name``); refusing them keeps a "billion laughs" file (each
    alias repeating the one before nine times) from becoming 10⁹ nodes when the value is walked or
    printed, and a bounded depth keeps a nested file from exhausting the composer's recursion.
    """
    import yaml

    class MapLoader(yaml.SafeLoader):
        depth = 0

        def compose_node(self, parent: Any, index: Any) -> Any:
            if self.check_event(yaml.AliasEvent):
                mark = self.peek_event().start_mark
                raise MalformedFile(f"a YAML alias at line {mark.line + 1}: a ROS map file has none")
            self.depth += 1
            try:
                if self.depth > MAX_YAML_DEPTH:
                    raise MalformedFile(f"YAML nested more than {MAX_YAML_DEPTH} deep")
                return super().compose_node(parent, index)
            finally:
                self.depth -= 1

    return MapLoader


def _read_yaml(source: Path) -> dict:
    import yaml

    name = shown_path(source)
    text = read_input_text(source, limit=MAX_MAP_YAML_BYTES, what="the map YAML")
    try:
        data = yaml.load(text, Loader=_map_loader())  # noqa: S506 (a safe loader: the subclass above)
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        at = f" at line {where.line + 1}" if where is not None else ""
        raise MalformedFile(f"{name}: not valid YAML{at}") from None
    except MalformedFile as exc:
        raise MalformedFile(f"{name}: {exc}") from None
    except (RecursionError, ValueError, TypeError, OverflowError) as exc:  # a scalar PyYAML cannot construct
        raise MalformedFile(f"{name}: not valid YAML ({exc.__class__.__name__})") from None
    if not isinstance(data, dict):
        kind = "empty" if data is None else type(data).__name__
        raise MalformedFile(f"{name}: not a ROS map: expected a YAML mapping with image, resolution and origin, "
                            f"got {kind}")
    return data


def _grey_levels(image: Any) -> tuple[np.ndarray, np.ndarray]:
    """(grey level 0–255 as float32, opaque mask) of a loaded image, channel by channel.

    float32 holds every level of 8- and 16-bit images exactly enough for the thresholds, and averaging the
    colour channels one at a time keeps the peak at a few bytes per pixel (not the 24 of a float64 copy of
    three channels): the working arrays of :data:`~solverplan.limits.MAX_PIXELS` pixels stay near 1 GB.
    """
    mode = image.mode
    if mode in ("I;16", "I;16B", "I;16L", "I"):
        values = np.asarray(image).astype(np.float32)
        values *= np.float32(255.0 / 65535.0)  # 16-bit PGM: full scale 65535
        return values, np.ones(values.shape, bool)
    has_alpha = mode in ("LA", "RGBA", "PA") or (mode == "P" and "transparency" in image.info)
    if mode in ("L", "1") and not has_alpha:
        grey = np.asarray(image.convert("L") if mode == "1" else image)
        return grey.astype(np.float32), np.ones(grey.shape, bool)
    converted = image.convert("RGBA" if has_alpha else "RGB")
    pixels = np.asarray(converted)
    del converted
    values = pixels[..., 0].astype(np.float32)
    values += pixels[..., 1]
    values += pixels[..., 2]
    values /= np.float32(3.0)
    opaque = pixels[..., 3] == 255 if has_alpha else np.ones(values.shape, bool)
    return values, opaque


def _read_image(path: Path, source: Path) -> tuple[np.ndarray, np.ndarray]:
    """(value 0–255 as floats, opaque mask) of the image; colour averaged over channels as map_server does."""
    from PIL import Image, UnidentifiedImageError

    name = shown_path(path)
    try:
        data = read_input_bytes(path, what="the image")  # regular files only, never read past the limit
    except MalformedFile as exc:
        reason = str(exc).removeprefix(f"{name}: ")
        if reason == "no such file":
            reason = "does not exist"
        raise MalformedFile(f"{shown_path(source, 50)}: image {shown_path(path, 60)} {reason}") from None
    Image.MAX_IMAGE_PIXELS = None  # our own bound below says it in one line instead of a warning
    try:
        with Image.open(io.BytesIO(data)) as image:
            width, height = image.size
            if width * height > MAX_PIXELS:
                raise MalformedFile(f"{name}: image is {width:,} × {height:,} pixels (at most {MAX_PIXELS:,})")
            refuse_beyond_memory(BYTES_PER_PIXEL * width * height, f"reading a map of {width:,} × {height:,} pixels")
            image.load()
            del data
            values, opaque = _grey_levels(image)
    except MalformedFile:
        raise
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError, EOFError, IndexError, TypeError,
            struct.error, zlib.error) as exc:
        raise MalformedFile(f"{name}: cannot read the image ({exc.__class__.__name__}: {str(exc)[:60]})") from None
    if values.size == 0:
        raise MalformedFile(f"{path}: the image is empty")
    return values, opaque


def read_occupancy_map(source: str | Path) -> OccupancyMap:
    """Read a ROS ``map_server`` map: the YAML file and the image it names.

    Parameters
    ----------
    source
        The YAML file; its ``image`` is relative to the YAML's folder unless absolute.

    Returns
    -------
    OccupancyMap
        Free and occupied cells, resolution (metres per cell) and origin (metres).

    Raises
    ------
    MalformedFile
        When the YAML is not a mapping, a key is missing or malformed, the thresholds are out of order
        (0 ≤ ``free_thresh`` < ``occupied_thresh`` ≤ 1), ``mode`` is unknown, or the image is missing,
        unreadable or larger than :data:`solverplan.limits.MAX_PIXELS`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> Image.fromarray(np.array([[0, 254, 254], [0, 254, 205]], np.uint8)).save(folder / "m.pgm")
    >>> _ = (folder / "m.yaml").write_text("image: m.pgm\\nresolution: 0.5\\norigin: [-1.0, 2.0, 0.0]\\n")
    >>> grid = read_occupancy_map(folder / "m.yaml")
    >>> grid.free.astype(int).tolist(), grid.occupied.astype(int).tolist(), grid.origin
    ([[0, 1, 1], [0, 1, 0]], [[1, 0, 0], [1, 0, 0]], (Fraction(-1, 1), Fraction(2, 1)))
    """
    source = Path(source)
    data = _read_yaml(source)
    image_name = data.get("image")
    if not isinstance(image_name, str) or not image_name.strip():
        raise MalformedFile(f"{source}: missing 'image' (a ROS map YAML has image, resolution and origin)")
    resolution = _number(data, "resolution", source)
    if resolution <= 0:
        raise MalformedFile(f"{source}: resolution must be positive (metres per cell), got {resolution}")
    if not MIN_RESOLUTION <= resolution <= MAX_RESOLUTION:
        raise MalformedFile(f"{source}: resolution must be between {MIN_RESOLUTION:g} and {MAX_RESOLUTION:g} metres "
                            f"per cell, got {resolution:g}")
    origin = data.get("origin")
    if not isinstance(origin, list) or len(origin) not in (2, 3):
        raise MalformedFile(f"{source}: origin must be [x, y, yaw] (metres, metres, radians), got {quote(str(origin))}")
    origin_numbers = [_yaml_number(value) for value in origin]
    if any(n is None or abs(n) > MAX_ORIGIN for n in origin_numbers):
        raise MalformedFile(f"{source}: origin must be three numbers [x, y, yaw] of magnitude at most {MAX_ORIGIN:g}, "
                            f"got {quote(str(origin))}")
    exact_origin_numbers = [n for n in origin_numbers if n is not None]
    occupied_thresh = float(_number(data, "occupied_thresh", source, DEFAULT_OCCUPIED_THRESH))
    free_thresh = float(_number(data, "free_thresh", source, DEFAULT_FREE_THRESH))
    if not 0 <= free_thresh < occupied_thresh <= 1:
        raise MalformedFile(f"{source}: thresholds out of order: need 0 <= free_thresh < occupied_thresh <= 1, got "
                            f"free_thresh {free_thresh:g} and occupied_thresh {occupied_thresh:g}")
    negate = data.get("negate", 0)
    if negate not in (0, 1) or isinstance(negate, float):
        raise MalformedFile(f"{source}: negate must be 0 or 1, got {quote(str(negate))}")
    mode = data.get("mode", "trinary")
    if mode not in _MODES:
        raise MalformedFile(f"{source}: unknown mode {quote(str(mode))}: use trinary, scale or raw")
    image = Path(image_name)
    if not image.is_absolute():
        image = source.parent / image
    values, opaque = _read_image(image, source)
    notes: list[str] = []
    if mode == "raw":
        free = (values < 100.0 * free_thresh) & opaque
        occupied = (values > 100.0 * occupied_thresh) & (values <= 100.0) & opaque
    else:
        probability = values / 255.0 if negate else (255.0 - values) / 255.0
        free = (probability < free_thresh) & opaque
        occupied = (probability > occupied_thresh) & opaque
        saver_grey = free & (values == (255 - SAVER_UNKNOWN if negate else SAVER_UNKNOWN))
        if saver_grey.any():
            free &= ~saver_grey
            notes.append(f"{int(saver_grey.sum()):,} cells of grey {int(values[saver_grey][0])} (map_saver's unknown) "
                         f"read as unknown, although free_thresh {free_thresh:g} would make them free (Nav2's saver "
                         f"writes 0.25): unknown is never free; write free_thresh 0.196 to silence this")
    yaw = float(exact_origin_numbers[2]) if len(exact_origin_numbers) == 3 else 0.0
    exact_origin = (Fraction(exact_origin_numbers[0]), Fraction(exact_origin_numbers[1]))
    return OccupancyMap(free, occupied, resolution, exact_origin, yaw, source, image, tuple(notes))


def _open_square(mask: np.ndarray, side: int) -> np.ndarray:
    """Morphological opening of ``mask`` by a ``side`` × ``side`` square, outside counted as background.

    Equal to ``ndimage.binary_opening(mask, structure=np.ones((side, side)))`` (tested), but as separable minimum and
    maximum filters: time independent of ``side`` (a 201-cell square on 2,000² cells: 0.05 s) and no structure
    array (``binary_opening`` ran out of memory on a 321-cell square). For an even side the dilation's window is
    shifted by one cell so that it is the erosion's reflected, as in ``binary_dilation``.
    """
    from scipy import ndimage

    eroded = ndimage.minimum_filter(mask.view(np.uint8), size=side, mode="constant", cval=0)
    return ndimage.maximum_filter(eroded, size=side, mode="constant", cval=0,
                                  origin=-1 if side % 2 == 0 else 0).astype(bool)


def _largest_label(labels: np.ndarray, count: int) -> int:
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    sizes[0] = 0
    return int(np.argmax(sizes))


def _component(free: np.ndarray, seed_cell: tuple[int, int] | None) -> tuple[np.ndarray, int, int]:
    """The free component at ``seed_cell`` (else the largest); returns (mask, other components, their cells)."""
    from scipy import ndimage

    labels, count = ndimage.label(free)  # the default structure is the cross: 4-connected
    if count == 0:
        raise InputError("the map has no free space (every cell is occupied or unknown)")
    chosen = _largest_label(labels, count) if seed_cell is None else int(labels[seed_cell])
    mask = labels == chosen
    return mask, count - 1, int(free.sum() - mask.sum())


def _cut_corners(ring: np.ndarray) -> list[tuple[int, tuple[float, float]]]:
    """The corners marching squares cut off a contour: (index of the diagonal step's first point, the corner).

    Contour points are midpoints of cell edges, so where an axis-parallel run of the contour meets a
    perpendicular one the contour cuts the corner by one diagonal half-cell step. Such a step (diagonal,
    between perpendicular axis-parallel steps) stands for the cell corner; diagonal steps between parallel
    steps or other diagonal steps are a slanted wall and stay (there the midpoints lie on it).
    """
    step = np.roll(ring, -1, axis=0) - ring  # step k goes from point k to point k + 1
    axis_x = np.isclose(step[:, 1], 0.0) & ~np.isclose(step[:, 0], 0.0)
    axis_y = np.isclose(step[:, 0], 0.0) & ~np.isclose(step[:, 1], 0.0)
    diagonal = ~(axis_x | axis_y)
    before_x, before_y = np.roll(axis_x, 1), np.roll(axis_y, 1)
    after_x, after_y = np.roll(axis_x, -1), np.roll(axis_y, -1)
    cut = diagonal & ((before_x & after_y) | (before_y & after_x))
    n = len(ring)
    corners = []
    for k in np.flatnonzero(cut).tolist():
        nxt = (k + 1) % n
        if before_x[k]:  # arriving along x (y constant), leaving along y (x constant)
            corners.append((k, (float(ring[nxt, 0]), float(ring[k, 1]))))
        else:
            corners.append((k, (float(ring[k, 0]), float(ring[nxt, 1]))))
    return corners


def _restore_corners(rings: list[np.ndarray]) -> list[np.ndarray]:
    """Put back the corners marching squares cuts off (:func:`_cut_corners`), except at saddles.

    At a saddle (two free cells meeting at a corner, diagonally, in the same component) two chamfers stand
    for the same corner point: restoring both would make the outline touch itself there, so a corner claimed
    twice keeps its chamfers (the outline passes the saddle at half a cell's distance, as traced).
    """
    from collections import Counter

    found = [_cut_corners(ring) for ring in rings]
    claims = Counter(corner for corners in found for _, corner in corners)
    out = []
    for ring, corners in zip(rings, found):
        n = len(ring)
        restored = ring.copy()
        drop = np.zeros(n, bool)
        for k, corner in corners:
            nxt = (k + 1) % n
            if claims[corner] > 1 or drop[k] or drop[nxt]:
                continue
            restored[k] = corner
            drop[nxt] = True
        out.append(restored[~drop])
    return out


def trace_free_space(
    grid: OccupancyMap,
    *,
    seed_point: tuple[Fraction, Fraction] | None = None,
    min_hole_area: float | None = None,
    spur_width: float | None = None,
    simplify: float | None = None,
    rectilinear: float | None = 0.0,
    min_obstacle: float | None = None,
    features: list[DroppedFeature] | None = None,
    chosen: dict[str, Any] | None = None,
) -> tuple[Environment, dict[str, Any]]:
    """The free-space component of an occupancy map as a valid environment in world coordinates (metres).

    Parameters
    ----------
    grid
        The map (:func:`read_occupancy_map`).
    seed_point
        A world point (metres) in the component to keep; ``None`` keeps the largest component.
    min_hole_area
        Obstacles inside the free space smaller than this (m²) are speckle and removed, in the raster and
        again after simplification; ``None``: 0 (the size rule ``min_obstacle`` decides).
    min_obstacle
        Obstacles whose bounding box's larger side is below this (metres) are speckle and removed;
        ``None``: :data:`DEFAULT_MIN_OBSTACLE` (2.5 cm, below a chair leg: on a map of 5 cm cells, every
        obstacle is kept).
    spur_width
        Free protrusions narrower than this (metres) are removed by a morphological opening with a square
        of side ``spur_width`` + one cell; ``None``: 2 cells; 0: none removed.
    simplify
        Topology-preserving simplification tolerance (metres); 0: no simplification. ``None``: chosen from the map
        and **conservative** (:func:`auto_simplification`): the tolerance is the walls' measured noise (at most 3
        cells), and the outline is made inside the traced free space (shrunk by the tolerance,
        then simplified within it: :func:`~solverplan.floorplan.outline.finish_outline` ``inside``), so that a plan
        valid on the environment is valid on the map; what the shrinking closes or joins is listed in ``features``.
    rectilinear
        Snap edges within this many degrees of an axis (0: no snapping); ``None``: :data:`AUTO_RECTILINEAR` when
        the walls are overwhelmingly axis-parallel (:data:`AXIS_PARALLEL_SHARE`), else 0 — conservatively when the
        simplification is.
    chosen
        When given, filled with what the defaults chose and why: ``simplify_m``, ``wall_noise_m``, ``inside``,
        ``rectilinear_deg``, ``axis_parallel_share``.

    Returns
    -------
    (Environment, dict)
        The environment (outer ring and holes, exact decimals on a grid of
        :func:`~solverplan.floorplan.outline.grid_quantum` of the resolution) and the counts of what was
        dropped (each dropped obstacle, component and spur is also appended to ``features``, when given, as a
        :class:`~solverplan.floorplan.drawing.DroppedFeature` with its world position and size): ``components`` (other free components) and ``component_area`` (their area, m²),
        ``speckle`` (obstacle blobs filled), ``spurs`` (free protrusions cut), then those of
        :func:`~solverplan.floorplan.outline.finish_outline`.

    Raises
    ------
    InputError
        When the map has no free space, the seed point is outside the image or not on a free cell.
    InvalidEnvironment
        When the traced outline is not a valid environment.

    Examples
    --------
    >>> cells = np.zeros((12, 12), bool); cells[1:11, 1:11] = True; cells[5:7, 5:7] = False
    >>> grid = OccupancyMap(cells, ~cells, Decimal("0.5"), (Fraction(0), Fraction(0)), 0.0, Path("m.yaml"), Path("m.pgm"))
    >>> env, dropped = trace_free_space(grid, min_hole_area=0.5)
    >>> float(env.area), len(env.holes), env.outer[0]
    (24.0, 1, (Fraction(11, 2), Fraction(1, 2)))
    """
    from scipy import ndimage
    from skimage.measure import find_contours

    res = float(grid.resolution)
    cell_area = res * res
    min_hole_area = 0.0 if min_hole_area is None else float(min_hole_area)
    min_obstacle = DEFAULT_MIN_OBSTACLE if min_obstacle is None else float(min_obstacle)
    features = [] if features is None else features
    spur_width = 2 * res if spur_width is None else float(spur_width)
    for name, value in (("--min-hole-area", min_hole_area), ("--spur-width", spur_width),
                        ("--simplify", 0.0 if simplify is None else simplify),
                        ("--rectilinear", 0.0 if rectilinear is None else rectilinear), ("--min-obstacle", min_obstacle)):
        if not math.isfinite(value) or value < 0:
            raise InputError(f"{name} must be a non-negative number, got {value:g}")
    if rectilinear is not None and rectilinear >= 45:
        raise InputError(f"--rectilinear must be below 45 degrees (an edge is near one axis only), got {rectilinear:g}")
    seed_cell = None
    if seed_point is not None:
        seed_cell = grid.cell_of(seed_point)
        where = f"({float(seed_point[0]):g}, {float(seed_point[1]):g})"
        if seed_cell is None:
            raise InputError(f"--seed-point {where} is outside the map")
        if not grid.free[seed_cell]:
            kind = "occupied" if grid.occupied[seed_cell] else "unknown"
            raise InputError(f"no free space at the seed point {where}: its cell is {kind}")
    mask, components, component_cells = _component(grid.free, seed_cell)
    features.extend(_blob_features(grid, grid.free & ~mask, "component", padded=False))
    exact_cell_area = grid.resolution * grid.resolution  # areas reported from cell counts, without binary noise
    dropped: dict[str, Any] = {"components": components, "component_area": float(component_cells * exact_cell_area)}
    # speckle: obstacle blobs (8-connected, the complement of 4-connected free space) not touching the border
    padded = np.pad(mask, 1, constant_values=False)
    eight = np.ones((3, 3), bool)
    blobs, count = ndimage.label(~padded, structure=eight)
    sizes = np.bincount(blobs.ravel(), minlength=count + 1)
    outside = blobs[0, 0]
    extents = np.zeros(count + 1)
    for label, box in enumerate(ndimage.find_objects(blobs), start=1):
        if box is not None:
            extents[label] = max(box[0].stop - box[0].start, box[1].stop - box[1].start) * res
    small = np.flatnonzero(((sizes * cell_area < min_hole_area) | (extents < min_obstacle))
                           & (np.arange(count + 1) != outside))
    small = small[small != 0]
    if small.size:
        speck = np.isin(blobs, small)
        features.extend(_blob_features(grid, speck, "speckle", padded=True))
        padded |= speck
    dropped["speckle"] = int(small.size)
    # spurs: free protrusions narrower than the opening's square; the opening may split the component
    # (a square wider than the map removes everything: clamp, so a huge width is an error, not a huge array)
    side = min(int(round(min(spur_width / res, 1e9))) + 1, max(padded.shape) + 1) if spur_width > 0 else 1
    if side > 1:
        opened = _open_square(padded, side)
        cut = padded & ~opened
        dropped["spurs"] = int(ndimage.label(cut, structure=eight)[1]) if cut.any() else 0
        features.extend(_blob_features(grid, cut, "spur", padded=True))
        if not opened.any():
            raise InputError(f"the free space is narrower than --spur-width {spur_width:g} m everywhere")
        core = opened[1:-1, 1:-1]
        keep_cell = seed_cell if seed_cell is not None and core[seed_cell] else None
        if seed_cell is not None and keep_cell is None:
            raise InputError(f"no free space at the seed point: it lies in a spur narrower than --spur-width "
                             f"{spur_width:g} m")
        before_split = core
        core, split, split_cells = _component(core, keep_cell)
        features.extend(_blob_features(grid, before_split & ~core, "component", padded=False))
        dropped["components"] += split
        dropped["component_area"] = float(Decimal(repr(dropped["component_area"])) + split_cells * exact_cell_area)
        padded = np.pad(core, 1, constant_values=False)
    else:
        dropped["spurs"] = 0
    contours = find_contours(padded.astype(np.float32), 0.5, fully_connected="low")
    rows = grid.shape[0]
    c, s = math.cos(grid.yaw), math.sin(grid.yaw)
    traced = [contour[:-1] if np.allclose(contour[0], contour[-1]) else contour for contour in contours
              if len(contour) >= 4]
    restored = _restore_corners(traced)
    inside = simplify is None

    def to_world(cell_rings: list[np.ndarray]) -> list[np.ndarray]:
        # padded (row, column) at cell centres → map frame (metres, y up): centre of cell (r, k) is (k + ½, rows − r − ½)
        out = []
        for ring in cell_rings:
            u = (ring[:, 1] - 0.5) * res
            v = (rows + 0.5 - ring[:, 0]) * res
            out.append(np.column_stack((c * u - s * v, s * u + c * v)))
        return out

    rings = to_world(restored)
    if not rings:
        raise InputError("the free space traced to nothing (the component is too small)")
    areas = [abs(0.5 * float(np.dot(r[:, 0], np.roll(r[:, 1], -1)) - np.dot(np.roll(r[:, 0], -1), r[:, 1])))
             for r in rings]
    outer_index = int(np.argmax(areas))
    quantum = grid_quantum(grid.resolution)
    auto = auto_simplification(rings, res)  # measured on the traced rings, slanted walls as diagonal steps
    rings = to_world(_on_cell_edges(restored))  # the free cells' exact boundary
    outer = rings[outer_index]
    holes = [r for k, r in enumerate(rings) if k != outer_index]
    simplify = auto["simplify_m"] if simplify is None else float(simplify)
    chosen_rectilinear_auto = rectilinear is None
    if rectilinear is None:
        rectilinear = auto["rectilinear_deg"]
    if chosen is not None:
        chosen.update(auto, simplify_m=simplify, rectilinear_deg=rectilinear, inside=inside)
    keep = None
    if seed_point is not None:
        keep = (float(seed_point[0] - grid.origin[0]), float(seed_point[1] - grid.origin[1]))
    axes = auto["axes_deg"] if chosen_rectilinear_auto else 0.0
    return finish_outline(outer, holes, quantum=quantum, axes=axes, offset=grid.origin, simplify=simplify,
                          min_hole_area=min_hole_area, rectilinear=rectilinear, name=grid.source.stem,
                          dropped=dropped, features=features, inside=inside, keep_point=keep)


def _on_cell_edges(rings: list[np.ndarray]) -> list[np.ndarray]:
    """Traced rings (cell units) with every diagonal step left by :func:`_restore_corners` (a wall at an angle, traced
    as a staircase) replaced by the two half steps along the cells' edges, through the cell corner: the boundary of
    the free cells exactly. A diagonal step cuts one cell's corner, and on the free space's reflex corners that cell is
    occupied: the traced ring then holds a sliver of it (up to √2/4 of a cell deep), which a conservative import must
    not give back. At a saddle (a corner cut twice) the chamfers stay: there they cut free cells.
    """
    from collections import Counter

    found = []
    for ring in rings:
        step = np.roll(ring, -1, axis=0) - ring
        diagonal = np.flatnonzero(~np.isclose(step[:, 0], 0.0) & ~np.isclose(step[:, 1], 0.0))
        nxt = np.roll(ring, -1, axis=0)[diagonal]
        here = ring[diagonal]
        on_row = np.isclose(here[:, 0], np.round(here[:, 0]))  # the step starts on a cell edge across the columns
        corners = np.where(on_row[:, None], np.column_stack((nxt[:, 0], here[:, 1])),
                           np.column_stack((here[:, 0], nxt[:, 1])))
        found.append((diagonal, corners))
    claims = Counter(tuple(c) for _, corners in found for c in corners.tolist())
    out = []
    for ring, (diagonal, corners) in zip(rings, found):
        keep = np.array([claims[tuple(c)] == 1 for c in corners.tolist()], bool)
        if not keep.any():
            out.append(ring)
            continue
        # insert each kept corner after its step's first point
        out.append(np.insert(ring, diagonal[keep] + 1, corners[keep], axis=0))
    return out


def auto_simplification(rings: list[np.ndarray], cell: float) -> dict[str, Any]:
    """The simplification a map import uses by default, from its traced rings (metres) and its cell size.

    ``simplify_m``: the walls' noise (:func:`~solverplan.floorplan.outline.wall_noise`, about half a cell on a clean
    map's slanted walls, traced in half-cell steps), at most 3 cells, to a tenth of a millimetre; 0 below a tenth of
    a cell (a clean map of straight walls traces them exactly: every vertex is a corner);
    ``rectilinear_deg``: :data:`AUTO_RECTILINEAR` if at least :data:`AXIS_PARALLEL_SHARE` of the walls' length
    (simplified within 3 cells) lies within it of an axis — of the walls' own axes, ``axes_deg`` (the turn,
    :func:`~solverplan.floorplan.outline.wall_axes`), for a map drawn at an angle — else 0. Also ``wall_noise_m`` and
    ``axis_parallel_share`` (the measurements).

    >>> ragged = np.array([[0, 0], [2, 0.05], [4, 0], [6, 0.05], [8, 0], [8, 3], [0, 3]], float)
    >>> auto_simplification([ragged], 0.05)
    {'simplify_m': 0.05, 'wall_noise_m': 0.05, 'rectilinear_deg': 10.0, 'axis_parallel_share': 1.0, 'axes_deg': 0.0}
    """
    from solverplan.floorplan.outline import axis_parallel_share, coarse_ring, wall_axes, wall_noise

    noise = wall_noise(rings, cell)
    tolerance = round(min(noise, 3 * cell), 4) if noise >= cell / 10 else 0.0
    coarse = [np.asarray(coarse_ring(r, 3 * cell).coords[:-1], float) for r in rings if len(r) >= 3]
    coarse = [c for c in coarse if len(c) >= 3]
    axes = 0.0
    share = axis_parallel_share(coarse, AUTO_RECTILINEAR)
    if share < AXIS_PARALLEL_SHARE:  # a map drawn at an angle: its walls' own axes
        turned = wall_axes(coarse, AUTO_RECTILINEAR / 2)
        turned_share = axis_parallel_share(coarse, AUTO_RECTILINEAR, turned)
        if turned_share >= AXIS_PARALLEL_SHARE:
            axes, share = turned, turned_share
    return {"simplify_m": tolerance, "wall_noise_m": noise,
            "rectilinear_deg": AUTO_RECTILINEAR if share >= AXIS_PARALLEL_SHARE else 0.0, "axis_parallel_share": share,
            "axes_deg": axes}


def cell_to_world(grid: OccupancyMap, rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """World coordinates (metres) of cell centres given by (row, column) of the image (floats allowed)."""
    res = float(grid.resolution)
    u = (np.asarray(columns, float) + 0.5) * res
    v = (grid.shape[0] - np.asarray(rows, float) - 0.5) * res
    c, s = math.cos(grid.yaw), math.sin(grid.yaw)
    return np.column_stack((float(grid.origin[0]) + c * u - s * v, float(grid.origin[1]) + s * u + c * v))


def _blob_features(grid: OccupancyMap, cells: np.ndarray, kind: str, *, padded: bool) -> list[DroppedFeature]:
    """One :class:`DroppedFeature` per 8-connected blob of ``cells`` (image rows; ``padded``: with a one-cell
    border to strip): the world position of a cell of it nearest its centre, the larger side of its bounding box,
    its area."""
    from scipy import ndimage

    if padded:
        cells = cells[1:-1, 1:-1]
    if not cells.any():
        return []
    res = float(grid.resolution)
    labels, count = ndimage.label(cells, structure=np.ones((3, 3), bool))
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    out = []
    for label, box in enumerate(ndimage.find_objects(labels), start=1):
        if box is None:
            continue
        rows, columns = np.nonzero(labels[box] == label)
        centre = np.array([rows.mean(), columns.mean()])
        k = int(np.argmin((rows - centre[0]) ** 2 + (columns - centre[1]) ** 2))  # a cell of the blob itself
        at = cell_to_world(grid, np.array([rows[k] + box[0].start]), np.array([columns[k] + box[1].start]))[0]
        extent = max(box[0].stop - box[0].start, box[1].stop - box[1].start) * res
        out.append(DroppedFeature(kind, (float(at[0]), float(at[1])), extent, float(sizes[label]) * res * res))
    return out


def cells_to_polygons(grid: OccupancyMap, cells: np.ndarray) -> Any:
    """The union of the given cells of a map as a shapely geometry in world coordinates (metres, exact cell edges
    up to float rounding): runs of cells along each row become rectangles, merged by ``shapely.union_all``."""
    import shapely

    res = float(grid.resolution)
    rows = grid.shape[0]
    boxes = []
    for r in np.flatnonzero(cells.any(axis=1)).tolist():
        line = np.concatenate(([False], cells[r], [False]))
        edges = np.flatnonzero(line[1:] != line[:-1])
        for start, stop in zip(edges[::2].tolist(), edges[1::2].tolist()):
            top = (rows - r) * res
            boxes.append(shapely.box(start * res, top - res, stop * res, top))
    if not boxes:
        return shapely.Polygon()
    union = shapely.union_all(boxes)
    c, s = math.cos(grid.yaw), math.sin(grid.yaw)
    ox, oy = float(grid.origin[0]), float(grid.origin[1])
    matrix = np.array([[c, s], [-s, c]])
    return shapely.transform(union, lambda p: p @ matrix + (ox, oy))


def read_keepout_mask(source: str | Path) -> tuple[Any, OccupancyMap]:
    """The keepout areas of a Nav2 keepout mask: the occupied cells of a map (YAML + image, read as any map).

    Nav2's keepout filter forbids the cells its mask marks occupied (lethal) and leaves free and unknown cells
    alone; solverplan does the same: the occupied cells, by the mask's own thresholds, resolution, origin and yaw,
    become polygons in world coordinates (metres) that the import takes out of the free space as obstacles.

    Parameters
    ----------
    source
        The mask's YAML file (``image``, ``resolution``, ``origin``, thresholds, as any ROS map).

    Returns
    -------
    (shapely geometry, OccupancyMap)
        The keepout areas (a Polygon or MultiPolygon, world metres; empty when the mask marks nothing) and the mask
        as read.

    Raises
    ------
    MalformedFile
        As :func:`read_occupancy_map`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> Image.fromarray(np.array([[254, 0, 0], [254, 254, 205]], np.uint8)).save(folder / "k.pgm")
    >>> _ = (folder / "k.yaml").write_text("image: k.pgm\\nresolution: 0.5\\norigin: [1.0, 0.0, 0.0]\\n")
    >>> areas, mask = read_keepout_mask(folder / "k.yaml")
    >>> areas.bounds, areas.area
    ((1.5, 0.5, 2.5, 1.0), 0.5)
    """
    mask = read_occupancy_map(source)
    return cells_to_polygons(mask, mask.occupied), mask
