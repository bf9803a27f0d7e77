"""``import_floorplan``: a ROS map, DXF or SVG file in, a validated environment (and its summary) out."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from os import PathLike
from pathlib import Path
from typing import Any, Literal, Sequence

import numpy as np

from solverplan.environment import Environment, save_environment
from solverplan.errors import InputError, MalformedFile
from solverplan.floorplan.occupancy import read_occupancy_map, trace_free_space
from solverplan.floorplan.outline import finish_outline, grid_quantum
from solverplan.floorplan.vector import arrange_rings, read_dxf_rings, read_svg_rings
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Stats, Status, answer_kind

__all__ = ["FloorplanImport", "import_floorplan", "PlanFormat"]

PlanFormat = Literal["ros", "dxf", "svg"]
_SUFFIXES: dict[str, PlanFormat] = {".yaml": "ros", ".yml": "ros", ".dxf": "dxf", ".svg": "svg"}
_ALGORITHMS = {
    "ros": "SciPy labelling and opening, scikit-image marching squares, GEOS topology-preserving simplification",
    "dxf": "ezdxf: closed polylines and chained lines; largest ring outer, contained rings holes",
    "svg": "svgelements: closed sub-paths, curves flattened; largest ring outer, contained rings holes",
}


@answer_kind("import")
@dataclass(frozen=True)
class FloorplanImport(Answer):
    """A floor plan read into an environment (the ``import`` answer of docs/contract.md).

    Attributes
    ----------
    status
        :attr:`Status.FOUND`: the environment is valid (it went through the environment validator).
    environment_value
        The :class:`~solverplan.environment.Environment` (world coordinates: metres for maps).
    written
        The environment file written, or ``None``.
    dropped
        What was removed or merged on the way, by name (counts; ``component_area`` in m²).
    source, format
        The input file and its kind (``ros``, ``dxf``, ``svg``).
    units
        The output's length unit: ``m`` for maps and DXF with units, ``unitless`` for a DXF without,
        ``scaled`` for SVG (user units times ``--scale``).
    resolution
        Metres per cell of a map (exact text), else ``None``.
    rectilinear_edges
        Edges snapped axis-parallel by ``rectilinear``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import solverplan as sp
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "room.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="3">'
    ...                                      '<rect width="4" height="3"/></svg>')
    >>> done = sp.import_floorplan(folder / "room.svg")
    >>> done.status.value, done.format, done.units, done.written
    ('found', 'svg', 'scaled', None)
    >>> done.environment_value, done.environment_value.area          # 4 × 3 user units, scale 1
    (Environment(name='room', vertices=4, holes=0, reflex=0), Fraction(12, 1))
    """

    status: Status
    environment_value: Environment
    written: str | None
    dropped: dict[str, Any]
    source: str
    format: PlanFormat
    units: str
    resolution: str | None = None
    rectilinear_edges: int = 0
    optimality: Optimality = field(default_factory=lambda: Optimality(Method.NONE, False, None))
    stats: Stats = field(default_factory=Stats)

    @property
    def environment(self) -> EnvironmentRecord:
        """The record of the environment made (name and SHA-256 of its exact rings)."""
        return EnvironmentRecord.of(self.environment_value)

    @property
    def outer_vertices(self) -> int:
        return len(self.environment_value.outer)

    @property
    def holes(self) -> int:
        return len(self.environment_value.holes)

    @property
    def area(self) -> float:
        """Area of the free space (output units squared)."""
        return float(self.environment_value.area)

    @property
    def advice(self) -> str | None:
        """What to change before planning on the result, or None.

        The bounce planner's graph grows as n⁴ in the number of vertices n, and a traced map keeps a vertex every
        few cells until simplified: past :data:`PLANNING_VERTICES` vertices, ``plan`` takes tens of seconds.
        """
        n = self.environment_value.n_vertices
        if n <= PLANNING_VERTICES:
            return None
        hint = f"--simplify {2 * float(self.resolution):g} (two cells)" if self.resolution else "a larger --simplify"
        return (f"{n} vertices: planning time grows as n^4, so plans on this environment will be slow; "
                f"for planning, import with {hint}, and --rectilinear 10 for an indoor map")

    def _fields(self) -> dict:
        """The import summary of docs/contract.md."""
        out: dict[str, Any] = {
            "written": self.written,
            "outer_vertices": self.outer_vertices,
            "holes": self.holes,
            "dropped": dict(self.dropped),
            "area": self.area,
            "format": self.format,
            "source": self.source,
            "name": self.environment_value.name,
            "vertices": self.environment_value.n_vertices,
            "units": self.units,
            "rectilinear_edges": self.rectilinear_edges,
        }
        if self.resolution is not None:
            out["resolution"] = self.resolution
        if self.advice is not None:
            out["advice"] = self.advice
        return out

    def to_text(self, *, width: int = 100) -> str:
        """A short report: what was made, then what was dropped."""
        lines = [
            f"import {self.source} ({self.format}): {self.status.value}",
            f"outer ring {self.outer_vertices} vertices, {self.holes} holes, area {self.area:.6g} ({self.units} squared)",
            f"written: {self.written or '(not written)'}",
        ]
        dropped = ", ".join(f"{k} {v:.6g}" if isinstance(v, float) else f"{k} {v}" for k, v in self.dropped.items() if v)
        lines.append(f"dropped: {dropped or 'nothing'}"[:width])
        if self.advice is not None:
            lines.append(f"advice: {self.advice}")
        return "\n".join(lines) + "\n"


PLANNING_VERTICES = 150
"""Vertices above which an import's summary advises more simplification (``plan`` then takes over ~10 s)."""


def _format_of(path: Path, fmt: str | None) -> PlanFormat:
    if fmt is not None:
        if fmt not in ("ros", "dxf", "svg"):
            raise MalformedFile(f"unknown floor plan format {fmt!r}: use ros, dxf or svg")
        return fmt  # type: ignore[return-value]
    try:
        return _SUFFIXES[path.suffix.lower()]
    except KeyError:
        raise MalformedFile(f"{path}: cannot tell the floor plan's format from {path.suffix or 'no extension'!r}: "
                            "use .yaml (ROS map), .dxf or .svg") from None


def _non_negative(name: str, value: float | None) -> None:
    if value is not None and (not math.isfinite(value) or value < 0):
        raise InputError(f"{name} must be a non-negative number, got {value:g}")


def import_floorplan(
    source: str | PathLike[str],
    *,
    output: str | PathLike[str] | None = None,
    fmt: PlanFormat | None = None,
    seed_point: Sequence[Any] | None = None,
    simplify: float | None = None,
    min_hole_area: float | None = None,
    spur_width: float | None = None,
    rectilinear: float = 0.0,
    layer: str | None = None,
    units: str | None = None,
    scale: str | Decimal = "1",
    tolerance: float | None = None,
    name: str | None = None,
) -> FloorplanImport:
    """Read a floor plan into a valid environment: a ROS occupancy map, a DXF drawing or an SVG drawing.

    Parameters
    ----------
    source
        ``MAP.yaml`` (ROS ``map_server``, with its PGM/PNG image), ``PLAN.dxf`` or ``PLAN.svg``.
    output
        Write the environment here (atomically; format by extension: ``.json``, ``.geojson``, ``.wkt``).
    fmt
        ``ros``, ``dxf`` or ``svg`` when the extension does not say.
    seed_point
        Maps: a world point ``(x, y)`` (metres; numbers or numeric strings, read exactly) in the free-space
        component to keep; ``None``: the largest component.
    simplify
        Topology-preserving simplification tolerance (output units); maps default to half a cell, drawings
        to 0 (every vertex kept, coordinates exact).
    min_hole_area
        Holes (and, in maps, obstacle speckle) smaller than this (output units squared) are removed; maps
        default to 9 cells, drawings to 0.
    spur_width
        Maps: free protrusions narrower than this (metres) are cut; default 2 cells.
    rectilinear
        Snap edges within this many degrees of an axis to it (0: no snapping; below 45).
    layer
        DXF: read only this layer.
    units
        DXF: the drawing unit, overriding ``$INSUNITS`` (``m``, ``cm``, ``mm``, ``in``, ``ft``, ``unitless``, ...).
    scale
        SVG: output units (metres) per SVG user unit, an exact decimal.
    tolerance
        DXF and SVG: largest distance between a curve and the chords replacing it (output units); default 0.01.
    name
        The environment's name (default: the file's stem).

    Returns
    -------
    FloorplanImport
        The environment, where it was written, and what was dropped on the way.

    Raises
    ------
    MalformedFile
        For an unreadable or malformed file (missing image, thresholds out of order, YAML that is not a map,
        corrupt image, a drawing without a closed outline).
    InputError
        For options that do not fit (a seed point on no free space, negative tolerances, an option of
        another format).
    InvalidEnvironment
        When the outline is not a valid environment after all.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "room.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="3">'
    ...                                      '<rect width="4" height="3"/><rect x="1" y="1" width="1" height="1"/></svg>')
    >>> done = import_floorplan(folder / "room.svg", output=folder / "room.json", scale="0.5")
    >>> {k: done.to_json()[k] for k in ("outer_vertices", "holes", "area")}
    {'outer_vertices': 4, 'holes': 1, 'area': 2.75}
    """
    started = time.perf_counter()
    path = Path(source)
    kind = _format_of(path, fmt)
    if output is not None:  # say so before the work, not after it
        if str(output) == "-":
            raise InputError("-o - is not available for import: the summary goes to stdout; name an environment file")
        if Path(output).suffix.lower() not in (".json", ".geojson", ".wkt"):
            raise MalformedFile(f"{output}: cannot tell the environment format from the extension "
                                f"{Path(output).suffix!r}: use .json, .geojson or .wkt")
    for option, value in (("--simplify", simplify), ("--min-hole-area", min_hole_area), ("--spur-width", spur_width),
                          ("--rectilinear", rectilinear), ("--tolerance", tolerance)):
        _non_negative(option, value)
    if not 0 <= rectilinear < 45:
        raise InputError(f"--rectilinear must be below 45 degrees (an edge is near one axis only), got {rectilinear:g}")
    if tolerance is not None and tolerance <= 0:
        raise InputError(f"--tolerance must be positive, got {tolerance:g}")
    if kind == "ros" and tolerance is not None:
        raise InputError("--tolerance applies to DXF and SVG drawings (a map's outline has no curves)")
    chord_tolerance = 0.01 if tolerance is None else tolerance
    if kind != "ros" and (seed_point is not None or spur_width is not None):
        raise InputError("--seed-point and --spur-width apply to occupancy maps (.yaml)")
    if kind != "dxf" and (layer is not None or units is not None):
        raise InputError("--layer and --units apply to DXF drawings")
    scale_value = _scale(scale)
    if kind != "svg" and scale_value != 1:
        raise InputError("--scale applies to SVG drawings")
    resolution = None
    rectilinear_edges = 0
    if kind == "ros":
        if not path.is_file():
            raise MalformedFile(f"{path}: no such file")
        grid = read_occupancy_map(path)
        point = None
        if seed_point is not None:
            from solverplan.exact import to_fraction

            if len(seed_point) != 2:
                raise InputError(f"--seed-point must be X,Y, got {seed_point!r}")
            point = (to_fraction(seed_point[0], where="--seed-point"), to_fraction(seed_point[1], where="--seed-point"))
        environment, dropped = trace_free_space(grid, seed_point=point, min_hole_area=min_hole_area,
                                                spur_width=spur_width, simplify=simplify, rectilinear=rectilinear)
        resolution, unit = str(grid.resolution), "m"
    else:
        if kind == "dxf":
            rings, info = read_dxf_rings(path, layer=layer, units=units, tolerance=chord_tolerance)
            unit = "m" if info["units"] != "unitless" else "unitless"
        else:
            rings, info = read_svg_rings(path, scale=scale_value, tolerance=chord_tolerance)
            unit = "scaled"
        outer, holes, counts = arrange_rings(rings, str(path))
        dropped = {k: v for k, v in info.items() if k != "units"} | counts
        environment, more = _drawn_environment(outer, holes, simplify or 0.0, min_hole_area or 0.0, rectilinear,
                                               name or path.stem)
        dropped |= more
    rectilinear_edges = int(dropped.pop("rectilinear_edges", 0))
    if name is not None and environment.name != name:
        environment = Environment(environment.rings, name=name, reoriented=environment.reoriented)
    written = None
    if output is not None:
        try:
            save_environment(environment, output)
        except OSError as exc:
            raise InputError(f"{output}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
        written = str(output)
    optimality = Optimality(Method.NONE, False, None, scope="", algorithm=_ALGORITHMS[kind])
    stats = Stats(seconds_setup=time.perf_counter() - started)
    return FloorplanImport(Status.FOUND, environment, written, dropped, str(path), kind, unit, resolution,
                           rectilinear_edges, optimality, stats)


def _scale(value: str | Decimal) -> Decimal:
    from decimal import InvalidOperation

    try:
        scale = value if isinstance(value, Decimal) else Decimal(str(value).strip())
    except InvalidOperation:
        raise InputError(f"--scale must be a number, got {value!r}") from None
    if not scale.is_finite() or scale <= 0:
        raise InputError(f"--scale must be a positive number, got {value!r}")
    return scale


def _drawn_environment(outer: list, holes: list, simplify: float, min_hole_area: float, rectilinear: float,
                       name: str) -> tuple[Environment, dict[str, int]]:
    """A drawing's rings as an environment: exactly as drawn, unless simplification or snapping is asked for."""
    if simplify == 0 and rectilinear == 0:
        def area(ring: list) -> float:
            return abs(float(sum(ring[i - 1][0] * ring[i][1] - ring[i][0] * ring[i - 1][1] for i in range(len(ring))))) / 2

        kept = [h for h in holes if area(h) >= min_hole_area]
        environment = Environment.from_coords(outer, kept, name=name)
        return environment, {"small_holes": len(holes) - len(kept)}
    floats = [np.array([(float(x), float(y)) for x, y in ring]) for ring in (outer, *holes)]
    extent = float(np.ptp(floats[0], axis=0).max()) or 1.0
    quantum = grid_quantum(Decimal(repr(simplify))) if simplify > 0 else Decimal(1).scaleb(math.floor(math.log10(extent)) - 6)
    return finish_outline(floats[0], floats[1:], quantum=quantum, offset=(Fraction(0), Fraction(0)), simplify=simplify,
                          min_hole_area=min_hole_area, rectilinear=rectilinear, name=name)
