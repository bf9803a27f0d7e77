"""``import_floorplan``: a ROS map, DXF or SVG file in, a validated environment (and its summary) out."""

from __future__ import annotations

import math
import time
from dataclasses import field
from decimal import Decimal
from fractions import Fraction
from os import PathLike
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from solverplan.choices import FloorplanFormat
from solverplan._io import cannot_write
from solverplan.environment import Environment, save_environment
from solverplan.errors import InputError, MalformedFile
from solverplan.floorplan.drawing import DroppedFeature, free_space_from_linework, plausibility_warnings
from solverplan.floorplan.occupancy import DEFAULT_MIN_OBSTACLE, read_keepout_mask, read_occupancy_map, trace_free_space
from solverplan.floorplan.outline import environment_from_polygon, finish_outline, grid_quantum
from solverplan.floorplan.robot import erode_free_space, inflation_distance
from solverplan.floorplan.vector import arrange_rings, read_dxf_linework, read_svg_rings
from solverplan.result import (Answer, EnvironmentRecord, Method, Optimality, Stats, Status, answer_dataclass,
                               protocol_json)

__all__ = ["FloorplanImport", "ImportResult", "import_floorplan", "PlanFormat"]

PlanFormat = FloorplanFormat  # the floor plan formats: the library's choice, its values written once
_SUFFIXES: dict[str, FloorplanFormat] = {".yaml": FloorplanFormat.ROS, ".yml": FloorplanFormat.ROS,
                                         ".dxf": FloorplanFormat.DXF, ".svg": FloorplanFormat.SVG}
_ALGORITHMS = {
    "ros": "SciPy labelling and opening, scikit-image marching squares, GEOS topology-preserving simplification",
    "dxf": "ezdxf linework (lines, polylines, circles, arcs, splines, hatches, blocks) joined, noded and polygonized "
           "with shapely (GEOS); the largest face, or the one at the seed point, is the free space",
    "svg": "svgelements: closed sub-paths, curves flattened; largest ring outer, contained rings holes",
}


MAX_LISTED = 200
"""Components, spurs, faces and dangling lines listed one by one in ``features`` (the largest first; the rest are
counted in ``features_not_listed``). Obstacles (speckle, small holes) and topology changes are always all listed."""

_ALWAYS_LISTED = {"door_swing", "speckle", "small_hole", "merged_obstacle", "passage_closed", "disconnected", "touch", "keepout",
                  "cut_off"}


@answer_dataclass("import")
class FloorplanImport(Answer):
    """A floor plan read into an environment (the ``import`` answer of docs/contract.md).

    Attributes
    ----------
    status
        :attr:`Status.FOUND`: the environment is valid (it went through the environment validator).
    environment
        The :class:`~solverplan.environment.Environment` made (world coordinates: metres for maps); for a robot
        of radius R, the free space of its centre. (Until 0.x this was ``environment_value``, which still works
        with a :class:`DeprecationWarning`; the record of the answer protocol is :attr:`environment_record`.)
    written
        The environment file written, or ``None``.
    dropped
        What was removed or merged on the way, by name (counts; ``component_area`` in m²).
    source, format
        The input file and its kind (``ros``, ``dxf``, ``svg``).
    units
        The output's length unit: ``m`` for maps and DXF with units, ``unitless`` for a DXF without,
        ``m`` for SVG with a ``--scale`` given, else ``user units``.
    resolution
        Metres per cell of a map (exact text), else ``None``.
    rectilinear_edges
        Edges snapped axis-parallel by ``rectilinear``.
    features
        Every feature of the input left out, with where it was and its size (:class:`DroppedFeature`).
    warnings
        Why the result may not be what the drawing means (an implausible free space), one line each.
    settings
        The thresholds used, with their units (what "nothing dropped without saying" refers to).
    uninflated
        The free space before the robot's inflation and the keepout areas (an Environment), when either was asked.
    keepout
        The keepout areas applied (a shapely geometry, world coordinates), or ``None``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import solverplan as sp
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "room.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="3">'
    ...                                      '<rect width="4" height="3"/></svg>')
    >>> done = sp.import_floorplan(folder / "room.svg")
    >>> done.status.value, done.format.value, done.units, done.written
    ('found', 'svg', 'user units', None)
    >>> done.environment, done.environment.area          # 4 × 3 user units, scale 1
    (Environment(name='room', vertices=4, holes=0, reflex=0), Fraction(12, 1))
    """

    status: Status
    environment: Environment
    written: str | None
    dropped: dict[str, Any]
    source: str
    format: FloorplanFormat
    units: str
    resolution: str | None = None
    rectilinear_edges: int = 0
    optimality: Optimality = field(default_factory=lambda: Optimality(Method.NONE, False, None))
    stats: Stats = field(default_factory=Stats)
    features: tuple[DroppedFeature, ...] = ()
    warnings: tuple[str, ...] = ()
    settings: dict[str, Any] = field(default_factory=dict)
    uninflated: Environment | None = None
    keepout: Any = None

    @property
    def environment_value(self) -> Environment:
        """Deprecated name of :attr:`environment`."""
        import warnings

        warnings.warn("FloorplanImport.environment_value is deprecated: use .environment (the Environment) or "
                      ".environment_record (its record)", DeprecationWarning, stacklevel=2)
        return self.environment

    @property
    def environment_record(self) -> EnvironmentRecord:
        """The record of the environment made (name and SHA-256 of its exact rings), as in every answer's JSON."""
        return EnvironmentRecord.of(self.environment)

    @property
    def outer_vertices(self) -> int:
        return len(self.environment.outer)

    @property
    def holes(self) -> int:
        return len(self.environment.holes)

    @property
    def area(self) -> float:
        """Area of the free space (output units squared)."""
        return float(self.environment.area)

    @property
    def advice(self) -> str | None:
        """What to change before planning on the result, or None.

        The bounce planner's graph grows as n⁴ in the number of vertices n, and a traced map keeps a vertex every
        few cells until simplified: past :data:`PLANNING_VERTICES` vertices, ``plan`` takes tens of seconds.
        """
        n = self.environment.n_vertices
        if n <= PLANNING_VERTICES:
            return None
        hint = f"--simplify {2 * float(self.resolution):g} (two cells)" if self.resolution else "a larger --simplify"
        if self.settings.get("inside_traced"):
            hint += ", which unlike the default does not keep the outline inside the traced free space"
        return (f"{n} vertices: planning time grows as n^4, so plans on this environment will be slow; "
                f"for planning, import with {hint}, and --rectilinear 10 for an indoor map")

    def listed_features(self) -> tuple[list[DroppedFeature], int]:
        """The features the summary lists one by one, and how many more it only counts (:data:`MAX_LISTED`)."""
        always = [f for f in self.features if f.kind in _ALWAYS_LISTED]
        others = sorted((f for f in self.features if f.kind not in _ALWAYS_LISTED), key=lambda f: (-f.area, -f.size))
        return always + others[:MAX_LISTED], max(len(others) - MAX_LISTED, 0)

    def to_json(self) -> dict:
        """The answer as JSON (:meth:`Answer.to_json`), with the environment's record as every answer's."""
        out: dict[str, Any] = {"kind": self.kind, "status": self.status.value}
        out.update(self._fields())
        out.update(protocol_json(self.optimality, self.stats, self.environment_record))
        return out

    def _fields(self) -> dict:
        """The import summary of docs/contract.md."""
        listed, more = self.listed_features()
        out: dict[str, Any] = {
            "written": self.written,
            "outer_vertices": self.outer_vertices,
            "holes": self.holes,
            "dropped": dict(self.dropped),
            "area": self.area,
            "format": self.format,
            "source": self.source,
            "name": self.environment.name,
            "vertices": self.environment.n_vertices,
            "units": self.units,
            "rectilinear_edges": self.rectilinear_edges,
            "features": [f.to_json() for f in listed],
            "features_not_listed": more,
            "warnings": list(self.warnings),
            "settings": dict(self.settings),
        }
        if self.uninflated is not None:
            out["area_before_robot"] = float(self.uninflated.area)
        if self.resolution is not None:
            out["resolution"] = self.resolution
        if self.advice is not None:
            out["advice"] = self.advice
        return out

    def to_text(self, *, width: int = 100) -> str:
        """A short report: what was made, then what was dropped and where."""
        lines = [
            f"import {self.source} ({self.format}): {self.status.value}",
            f"outer ring {self.outer_vertices} vertices, {self.holes} holes, area {self.area:.6g} ({self.units} squared)",
            f"written: {self.written or '(not written)'}",
        ]
        dropped = ", ".join(f"{k} {v:.6g}" if isinstance(v, float) else f"{k} {v}" for k, v in self.dropped.items()
                            if v and not isinstance(v, dict))
        lines.append(f"dropped: {dropped or 'nothing'}"[:width])
        important = [f for f in self.features if f.kind in _ALWAYS_LISTED]
        for f in important[:50]:
            lines.append(f"  {f.kind} at ({f.at[0]:.4g}, {f.at[1]:.4g}): size {f.size:.3g}, area {f.area:.3g}")
        if len(important) > 50:
            lines.append(f"  ... and {len(important) - 50} more obstacles and changes (all in the JSON summary)")
        rest: dict[str, int] = {}
        for f in self.features:
            if f.kind not in _ALWAYS_LISTED:
                rest[f.kind] = rest.get(f.kind, 0) + 1
        if rest:
            lines.append("  also left out (positions in the JSON summary): "
                         + ", ".join(f"{n} {kind}" for kind, n in sorted(rest.items())))
        for warning in self.warnings:
            lines.append(f"warning: {warning}")
        if self.advice is not None:
            lines.append(f"advice: {self.advice}")
        return "\n".join(lines) + "\n"


ImportResult = FloorplanImport
"""Another name of :class:`FloorplanImport` (the result of :func:`import_floorplan`)."""

PLANNING_VERTICES = 150
"""Vertices above which an import's summary advises more simplification (``plan`` then takes over ~10 s)."""


def _format_of(path: Path, fmt: str | None) -> FloorplanFormat:
    if fmt is not None:
        if fmt not in FloorplanFormat.values():
            raise MalformedFile(f"unknown floor plan format {fmt!r}: use ros, dxf or svg")
        return FloorplanFormat(fmt)
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
    fmt: FloorplanFormat | str | None = None,
    seed_point: Sequence[Any] | None = None,
    simplify: float | None = None,
    min_hole_area: float | None = None,
    min_obstacle: float | None = None,
    spur_width: float | None = None,
    rectilinear: float | None = None,
    layer: str | None = None,
    units: str | None = None,
    scale: str | Decimal | None = None,
    tolerance: float | None = None,
    snap: float | None = None,
    max_jamb: float | None = None,
    robot_radius: str | float | Decimal | None = None,
    keepout: str | PathLike[str] | None = None,
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
        A point ``(x, y)`` (output units: metres; numbers or numeric strings, read exactly) in the free space to
        keep: a map's free component, a DXF drawing's face; ``None``: the largest.
    simplify
        Topology-preserving simplification tolerance (output units); drawings default to 0 (every vertex kept,
        coordinates exact). Maps default to the walls' measured noise (half a cell to 3 cells), **conservatively**:
        the environment then lies inside the traced free space, so a plan valid on it is valid on the map
        (:func:`~solverplan.floorplan.occupancy.auto_simplification`; ``settings`` says what was chosen, and what the
        shrinking closed is listed in ``features``).
    min_hole_area
        Holes (and, in maps, obstacle speckle) smaller than this (output units squared) are removed; default 0.
    min_obstacle
        Obstacles whose bounding box's larger side is below this (output units: metres) are removed, each listed
        with its position; maps default to 0.025 (2.5 cm, below a chair leg), drawings to 0.
    spur_width
        Maps: free protrusions narrower than this (metres) are cut; default 2 cells.
    rectilinear
        Snap edges within this many degrees of an axis to it (0: no snapping; below 45). Default: drawings 0; maps
        10 when 90 % of their walls' length lies that close to an axis, else 0 (``settings["rectilinear_deg"]``).
    layer
        DXF: read only this layer (or these, joined by commas).
    units
        DXF: the drawing unit, overriding ``$INSUNITS`` (``m``, ``cm``, ``mm``, ``in``, ``ft``, ``unitless``, ...).
    scale
        SVG: output units (metres) per SVG **user unit** (the viewBox's unit), an exact decimal; default from the
        document's ``width`` when it has an absolute unit (``210mm`` over a viewBox 210 wide: 0.001), else 1.
    tolerance
        DXF and SVG: largest distance between a curve and the chords replacing it (output units); default 0.01.
    snap
        DXF: line ends closer than this (**drawing units**) are joined, and an end this close to a line is put
        on it; default 10⁻⁵ of the drawing's extent (0.1 mm on a 10 m plan drawn in millimetres).
    max_jamb
        DXF: the two lines of a wall band left open at a door are closed when their ends are each other's nearest
        loose ends and at most this far apart (output units: metres; drawing units when unitless); default 0.5;
        0: never.
    robot_radius
        The robot's radius (output units: metres; an exact decimal): the environment is the free space of its
        centre, walls and obstacles inflated by it (:mod:`~solverplan.floorplan.robot`); what that disconnects,
        closes or merges is listed in ``features``.
    keepout
        A Nav2 keepout mask (a map YAML and its image): its occupied cells are taken out of the free space as
        obstacles (before the robot's inflation).
    name
        The environment's name (default: the file's stem).

    Returns
    -------
    FloorplanImport
        The environment, where it was written, what was dropped on the way and where, and warnings.

    Raises
    ------
    MalformedFile
        For an unreadable or malformed file (missing image, thresholds out of order, YAML that is not a map,
        corrupt image, a drawing without a closed outline).
    InputError
        For options that do not fit (a seed point on no free space, negative tolerances, an option of
        another format, a robot that fits nowhere).
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
    >>> done.environment.name, done.environment.area
    ('room', Fraction(11, 4))
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
                          ("--rectilinear", rectilinear), ("--tolerance", tolerance), ("--min-obstacle", min_obstacle),
                          ("--snap", snap), ("--max-jamb", max_jamb)):
        _non_negative(option, value)
    drawn_rectilinear = 0.0 if rectilinear is None else rectilinear  # drawings are taken as drawn by default
    if rectilinear is not None and not 0 <= rectilinear < 45:
        raise InputError(f"--rectilinear must be below 45 degrees (an edge is near one axis only), got {rectilinear:g}")
    if tolerance is not None and tolerance <= 0:
        raise InputError(f"--tolerance must be positive, got {tolerance:g}")
    if kind == "ros" and tolerance is not None:
        raise InputError("--tolerance applies to DXF and SVG drawings (a map's outline has no curves)")
    chord_tolerance = 0.01 if tolerance is None else tolerance
    if kind != "ros" and spur_width is not None:
        raise InputError("--spur-width applies to occupancy maps (.yaml)")
    if kind == "svg" and seed_point is not None:
        raise InputError("--seed-point applies to occupancy maps and DXF drawings")
    if kind != "dxf" and (layer is not None or units is not None or snap is not None or max_jamb is not None):
        raise InputError("--layer, --units, --snap and --max-jamb apply to DXF drawings")
    scale_value = None if scale is None else _scale(scale)
    if kind != "svg" and scale_value is not None and scale_value != 1:
        raise InputError("--scale applies to SVG drawings")
    radius = None if robot_radius is None else _radius(robot_radius)
    point = None
    if seed_point is not None:
        from solverplan.exact import to_fraction

        if len(seed_point) != 2:
            raise InputError(f"--seed-point must be X,Y, got {seed_point!r}")
        point = (to_fraction(seed_point[0], where="--seed-point"), to_fraction(seed_point[1], where="--seed-point"))
    resolution = None
    features: list[DroppedFeature] = []
    warnings: list[str] = []
    settings: dict[str, Any] = {}
    offset = (Fraction(0), Fraction(0))
    if kind == "ros":
        if not path.is_file():
            raise MalformedFile(f"{path}: no such file")
        grid = read_occupancy_map(path)
        chosen: dict[str, Any] = {}
        environment, dropped = trace_free_space(grid, seed_point=point, min_hole_area=min_hole_area,
                                                spur_width=spur_width, simplify=simplify, rectilinear=rectilinear,
                                                min_obstacle=min_obstacle, features=features, chosen=chosen)
        resolution, unit = str(grid.resolution), "m"
        quantum, offset = grid_quantum(grid.resolution), grid.origin
        settings = {"min_obstacle_m": DEFAULT_MIN_OBSTACLE if min_obstacle is None else min_obstacle,
                    "min_hole_area_m2": min_hole_area or 0.0,
                    "spur_width_m": 2 * float(grid.resolution) if spur_width is None else spur_width,
                    "simplify_m": chosen["simplify_m"], "inside_traced": chosen["inside"],
                    "rectilinear_deg": chosen["rectilinear_deg"], "rectilinear_axes_deg": chosen["axes_deg"],
                    "measured": {"wall_noise_m": chosen["wall_noise_m"],
                                 "axis_parallel_share": chosen["axis_parallel_share"]}}
        warnings += [*grid.notes, *_map_default_warnings(dropped, chosen, min_obstacle, simplify, rectilinear)]
    elif kind == "dxf":
        environment, dropped, unit, quantum, more = _dxf_environment(
            path, layer=layer, units=units, tolerance=chord_tolerance, snap=snap, max_jamb=max_jamb, point=point,
            simplify=simplify or 0.0, min_hole_area=min_hole_area or 0.0, min_obstacle=min_obstacle or 0.0,
            rectilinear=drawn_rectilinear, name=name or path.stem, features=features, warnings=warnings)
        settings = more
    else:
        rings, info = read_svg_rings(path, scale=scale_value, tolerance=chord_tolerance)
        unit = info.pop("units")
        settings = {"scale_m_per_user_unit" if unit == "m" else "scale": info.pop("scale"),
                    "tolerance": chord_tolerance}
        outer, holes, counts = arrange_rings(rings, str(path))
        dropped = dict(info) | counts
        environment, more = _drawn_environment(outer, holes, simplify or 0.0, min_hole_area or 0.0, drawn_rectilinear,
                                               name or path.stem, features)
        dropped |= more
        quantum = _drawing_quantum(environment)
        largest = max((float(Environment.from_coords(h).area) for h in environment.holes), default=0.0)
        xs = [float(x) for ring in rings for x, _ in ring]
        ys = [float(y) for ring in rings for _, y in ring]
        warnings += plausibility_warnings(float(environment.area), largest, (min(xs), min(ys), max(xs), max(ys)))
    if min_obstacle and kind != "ros":
        environment = _drop_small_obstacles(environment, min_obstacle, features)
    rectilinear_edges = int(dropped.pop("rectilinear_edges", 0))
    uninflated = None
    keepout_areas = None
    if keepout is not None or radius is not None:
        uninflated = environment
        free = environment.to_shapely()
        if keepout is not None:
            keepout_areas, mask = read_keepout_mask(Path(keepout))
            settings["keepout"] = str(keepout)
            if not keepout_areas.is_empty:
                for part in getattr(keepout_areas, "geoms", [keepout_areas]):
                    if part.intersects(free):
                        features.append(DroppedFeature.of("keepout", part.intersection(free)))
                free = free.difference(keepout_areas)
        if radius is not None:
            before = float(settings.get("simplify_m", simplify or 0.0))  # how far the outline may have moved in
            settings["robot_radius_m"] = str(radius)
            settings["inflation_m"] = round(inflation_distance(float(radius), float(quantum)) + before, 9)
            free, changes = erode_free_space(free, float(radius), grid=float(quantum),
                                             seed_point=None if point is None else (float(point[0]), float(point[1])),
                                             simplify=before, margin=before)
            features.extend(changes)
        environment, lost, touched = environment_from_polygon(free, quantum=quantum, offset=offset,
                                                              name=environment.name)
        features.extend(DroppedFeature.of("disconnected", g) for g in lost)
        features.extend(DroppedFeature("touch", (p.x, p.y), 0.0) for p in touched)
    if name is not None and environment.name != name:
        environment = Environment(environment.rings, name=name, reoriented=environment.reoriented)
    written = None
    if output is not None:
        try:
            save_environment(environment, output)
        except OSError as exc:
            raise InputError(cannot_write(output, exc)) from None
        written = str(output)
    optimality = Optimality(Method.NONE, False, None, scope="", algorithm=_ALGORITHMS[kind])
    stats = Stats(seconds_setup=time.perf_counter() - started)
    return FloorplanImport(Status.FOUND, environment, written, dropped, str(path), kind, unit, resolution,
                           rectilinear_edges, optimality, stats, tuple(features), tuple(warnings), settings,
                           uninflated, keepout_areas)


def _map_default_warnings(dropped: dict, chosen: dict, min_obstacle: float | None, simplify: float | None,
                          rectilinear: float | None) -> list[str]:
    """What a map's defaults did that changes the free space, one line each (the details are in ``features``)."""
    out = []
    if min_obstacle is None and dropped.get("speckle"):
        out.append(f"{dropped['speckle']} obstacles smaller than {DEFAULT_MIN_OBSTACLE:g} m (lidar specks) dropped, each "
                   "listed in features: --min-obstacle 0 keeps them")
    if simplify is None and chosen["simplify_m"] > 0:
        closed = dropped.get("passages_closed", 0)
        text = (f"outline simplified within {chosen['simplify_m']:g} m (the walls' measured noise) inside the traced "
                f"free space: walls move in by up to {2 * chosen['simplify_m']:g} m")
        if closed:
            text += f"; {closed} passages narrower than that closed (listed in features)"
        out.append(text + "; --simplify M for another tolerance (not shrunk)")
    if rectilinear is None and chosen["rectilinear_deg"]:
        axes = f" (the walls' axes, turned {chosen['axes_deg']:g}°)" if chosen["axes_deg"] else ""
        out.append(f"walls within {chosen['rectilinear_deg']:g}° of an axis{axes} snapped to it, inwards "
                   f"({100 * chosen['axis_parallel_share']:.0f} % of them are): --rectilinear 0 keeps them as traced")
    return out


def _radius(value: str | float | Decimal) -> Decimal:
    from decimal import InvalidOperation

    try:
        radius = value if isinstance(value, Decimal) else Decimal(repr(value) if isinstance(value, float) else str(value).strip())
    except InvalidOperation:
        raise InputError(f"--robot-radius must be a number of metres, got {str(value)[:40]!r}") from None
    if not radius.is_finite() or radius <= 0:
        raise InputError(f"--robot-radius must be a positive number of metres, got {str(value)[:40]!r}")
    return radius


def _drawing_quantum(environment: Environment) -> Decimal:
    """A decimal grid for a drawing's environment after geometric operations: 10⁻⁶ of its extent, a power of ten."""
    xmin, ymin, xmax, ymax = environment.bounds
    extent = max(xmax - xmin, ymax - ymin) or 1.0
    return Decimal(1).scaleb(math.floor(math.log10(extent)) - 6)


def _drop_small_obstacles(environment: Environment, min_obstacle: float, features: list) -> Environment:
    """The environment without the holes whose bounding box's larger side is below ``min_obstacle`` (listed)."""
    kept = []
    for hole in environment.holes:
        xs, ys = [float(x) for x, _ in hole], [float(y) for _, y in hole]
        size = max(max(xs) - min(xs), max(ys) - min(ys))
        if size < min_obstacle:
            area = float(Environment.from_coords(hole).area)
            features.append(DroppedFeature("small_hole", (sum(xs) / len(xs), sum(ys) / len(ys)), size, area))
        else:
            kept.append(hole)
    if len(kept) == len(environment.holes):
        return environment
    return Environment.from_coords(environment.outer, kept, name=environment.name)


def _dxf_environment(path: Path, *, layer: str | None, units: str | None, tolerance: float, snap: float | None,
                     max_jamb: float | None, point: tuple[Fraction, Fraction] | None, simplify: float,
                     min_hole_area: float, min_obstacle: float, rectilinear: float, name: str,
                     features: list, warnings: list) -> tuple[Environment, dict, str, Decimal, dict]:
    """A DXF drawing's free space (:mod:`~solverplan.floorplan.drawing`) as an environment in metres."""
    work = read_dxf_linework(path, layer=layer, units=units, tolerance=tolerance)
    factor = work.factor
    scale = float(factor) if factor is not None else 1.0
    unit = "m" if factor is not None else "unitless"
    coords = [line for line in work.lines if len(line)]
    extent_box = (np.vstack(coords).min(axis=0), np.vstack(coords).max(axis=0)) if coords else None
    extent = float(np.max(extent_box[1] - extent_box[0])) if extent_box is not None else 1.0
    extent = extent or 1.0
    snap_d = 1e-5 * extent if snap is None else snap
    grid_d = Decimal(1).scaleb(math.floor(math.log10(max(snap_d, 1e-12 * extent) / 100)))
    grid_d = max(grid_d, Decimal(1).scaleb(math.floor(math.log10(extent)) - 9))
    jamb_d = (0.5 if max_jamb is None else max_jamb) / scale
    seed = None if point is None else (float(point[0]) / scale, float(point[1]) / scale)
    face = free_space_from_linework(work.lines, work.solids, snap=snap_d, grid=float(grid_d), max_jamb=jamb_d,
                                    seed_point=seed)
    features.extend(f.scaled(scale) for f in face.dropped)
    features.extend(DroppedFeature("door_swing", (cx * scale, cy * scale), r * scale) for cx, cy, r in work.door_swings)
    quantum = grid_d * (factor if factor is not None else Decimal(1))
    polygon = face.polygon
    outer = np.asarray(polygon.exterior.coords[:-1], float) * scale
    holes = [np.asarray(r.coords[:-1], float) * scale for r in polygon.interiors]
    environment, dropped = finish_outline(outer, holes, quantum=quantum.normalize(), simplify=simplify,
                                          min_hole_area=min_hole_area, rectilinear=rectilinear, name=name,
                                          features=features)
    counts = dict(work.counts)
    dropped = {"dangling_lines": sum(1 for f in face.dropped if f.kind == "dangling_line"),
               "faces": sum(1 for f in face.dropped if f.kind == "face"),
               **{k: v for k, v in face.counts.items()}, "door_swings": counts.pop("door_swings", 0),
               "door_leaves": counts.pop("door_leaves", 0), "other_layers": counts.pop("other_layers"),
               "unsupported": counts.pop("unsupported"), **dropped}
    box = (face.extent[0] * scale, face.extent[1] * scale, face.extent[2] * scale, face.extent[3] * scale)
    warnings += plausibility_warnings(float(environment.area), face.largest_obstacle * scale * scale, box)
    settings = {"drawing_unit": work.unit, "snap_drawing_units": snap_d, "grid_drawing_units": str(grid_d),
                "max_jamb": jamb_d * scale, "tolerance": tolerance, "min_obstacle": min_obstacle,
                "read": {k: v for k, v in counts.items()}}
    return environment, dropped, unit, quantum.normalize(), settings


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
                       name: str, features: list | None = None) -> tuple[Environment, dict[str, int]]:
    """A drawing's rings as an environment: exactly as drawn, unless simplification or snapping is asked for."""
    if simplify == 0 and rectilinear == 0:
        def area(ring: list) -> float:
            return abs(float(sum(ring[i - 1][0] * ring[i][1] - ring[i][0] * ring[i - 1][1] for i in range(len(ring))))) / 2

        kept = [h for h in holes if area(h) >= min_hole_area]
        for h in holes:
            if area(h) < min_hole_area and features is not None:
                xs, ys = [float(x) for x, _ in h], [float(y) for _, y in h]
                features.append(DroppedFeature("small_hole", (sum(xs) / len(xs), sum(ys) / len(ys)),
                                               max(max(xs) - min(xs), max(ys) - min(ys)), area(h)))
        environment = Environment.from_coords(outer, kept, name=name)
        return environment, {"small_holes": len(holes) - len(kept)}
    floats = [np.array([(float(x), float(y)) for x, y in ring]) for ring in (outer, *holes)]
    extent = float(np.ptp(floats[0], axis=0).max()) or 1.0
    quantum = grid_quantum(Decimal(repr(simplify))) if simplify > 0 else Decimal(1).scaleb(math.floor(math.log10(extent)) - 6)
    return finish_outline(floats[0], floats[1:], quantum=quantum, offset=(Fraction(0), Fraction(0)), simplify=simplify,
                          min_hole_area=min_hole_area, rectilinear=rectilinear, name=name, features=features)
