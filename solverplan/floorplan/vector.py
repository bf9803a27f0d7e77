"""Drawn floor plans: DXF (ezdxf) and SVG (svgelements) outlines into rings, the largest one outer.

Both readers produce closed rings of **exact decimals** (the coordinates as written, times the unit factor),
so a plan drawn with round numbers reads back exactly. A drawing's rings are sorted by area: the largest
is the outer ring, the rings inside it are holes, rings inside a hole (islands, unreachable) and rings
outside the outer ring are dropped and counted.
"""

from __future__ import annotations

import contextlib
import io
import math
import struct
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path
from typing import Any, Iterable, Iterator, Sequence

import numpy as np

from solverplan._io import read_input_bytes, shown_path
from solverplan.errors import InputError, MalformedFile
from solverplan.exact import ring_without_repeats
from solverplan.limits import MAX_HOLES, MAX_VERTICES, quote

MAX_DRAWING_ENTITIES = 200_000
"""Most drawn entities a DXF or SVG file may expand to (DXF block references and SVG ``<use>`` copies
included), checked while expanding: each costs ezdxf or svgelements one to a few kilobytes, so the bound
keeps a file of a few kilobytes whose blocks insert blocks ten times over from growing to gigabytes."""

MAX_DRAWING_POINTS = 10 * MAX_VERTICES
"""Most outline points a drawing may give (before simplification): ten times the vertices of an environment."""

MAX_DRAWING_RINGS = MAX_HOLES + 1
"""Most closed outlines a drawing may give (one outer ring and at most :data:`~solverplan.limits.MAX_HOLES`)."""

MAX_SVG_DEPTH = 100
"""Deepest nesting of SVG elements read (drawing programs nest groups a dozen deep): svgelements walks the
tree recursively, so a file of ``<g>`` nested 10⁵ deep is refused here instead of exhausting the stack."""

_PARSER_FAILURES = (ValueError, TypeError, AttributeError, KeyError, IndexError, LookupError, StopIteration,
                    RecursionError, ZeroDivisionError, OverflowError, ArithmeticError, UnicodeError, AssertionError,
                    EOFError, struct.error)
"""What the third-party drawing parsers (ezdxf, svgelements) raise on malformed input they do not anticipate."""


@contextlib.contextmanager
def _dxf_failures(name: str) -> Iterator[None]:
    """ezdxf's errors, and what it raises on input it does not anticipate, as one-line bad input naming the file."""
    import ezdxf

    try:
        yield
    except (MalformedFile, InputError, MemoryError):
        raise
    except ezdxf.DXFError as exc:
        raise MalformedFile(f"{name}: not a valid DXF file ({str(exc)[:60] or exc.__class__.__name__})") from None
    except _PARSER_FAILURES as exc:
        raise MalformedFile(f"{name}: not a valid DXF file ({exc.__class__.__name__}: {str(exc)[:40]})") from None


class _Budget:
    """Counts entities, points and rings while a drawing is read; refuses past the documented bounds."""

    def __init__(self, name: str) -> None:
        self.name, self.entities, self.points, self.rings = name, 0, 0, 0

    def entity(self) -> None:
        self.entities += 1
        if self.entities > MAX_DRAWING_ENTITIES:
            raise MalformedFile(f"{self.name}: expands to more than {MAX_DRAWING_ENTITIES:,} drawn entities")

    def outline(self, points: int, closed: bool) -> None:
        self.points += points
        self.rings += closed
        if self.points > MAX_DRAWING_POINTS:
            raise MalformedFile(f"{self.name}: more than {MAX_DRAWING_POINTS:,} outline points")
        if self.rings > MAX_DRAWING_RINGS:
            raise MalformedFile(f"{self.name}: more than {MAX_DRAWING_RINGS:,} closed outlines")

__all__ = ["read_dxf_rings", "read_dxf_linework", "Linework", "read_svg_rings", "arrange_rings", "DXF_UNITS", "UNIT_NAMES", "ExactRing"]

ExactRing = list[tuple[Decimal, Decimal]]

DXF_UNITS: dict[int, tuple[str, Decimal | None]] = {
    0: ("unitless", None),
    1: ("in", Decimal("0.0254")),
    2: ("ft", Decimal("0.3048")),
    3: ("mi", Decimal("1609.344")),
    4: ("mm", Decimal("0.001")),
    5: ("cm", Decimal("0.01")),
    6: ("m", Decimal("1")),
    7: ("km", Decimal("1000")),
    8: ("uin", Decimal("0.0000000254")),
    9: ("mil", Decimal("0.0000254")),
    10: ("yd", Decimal("0.9144")),
    13: ("um", Decimal("0.000001")),
    14: ("dm", Decimal("0.1")),
}
"""``$INSUNITS`` codes of the DXF header read, with their exact size in metres (``None``: unitless, kept as drawn)."""

UNIT_NAMES: dict[str, Decimal | None] = {name: factor for name, factor in DXF_UNITS.values()}
"""The names ``--units`` accepts and their size in metres."""


def _decimal(value: float) -> Decimal:
    """A float coordinate as the decimal it prints as (what the file said, for files written with round numbers)."""
    if not math.isfinite(value):
        raise MalformedFile(f"coordinate {value!r} is not a finite number")
    return Decimal(repr(float(value)))




def _chain_loops(segments: Iterable[tuple[tuple[Decimal, Decimal], tuple[Decimal, Decimal]]]) -> tuple[list[ExactRing], int]:
    """Close line segments that share end points into loops; returns (loops, chains that do not close)."""
    import networkx as nx

    graph = nx.Graph()
    for a, b in segments:
        if a != b:
            graph.add_edge(a, b)
    loops: list[ExactRing] = []
    open_chains = 0
    for nodes in nx.connected_components(graph):
        sub = graph.subgraph(nodes)
        if any(degree != 2 for _, degree in sub.degree()):
            open_chains += 1  # a dangling line, or a junction of three walls: no single loop to take
            continue
        start = next(iter(nodes))
        ring = [start]
        previous, current = None, start
        while True:
            following = [n for n in sub.neighbors(current) if n != previous]
            step = following[0] if following else next(iter(sub.neighbors(current)))
            if step == start:
                break
            ring.append(step)
            previous, current = current, step
        loops.append(ring)
    return loops, open_chains


def _flattened(entities: Iterable[Any], budget: _Budget, inherited: str | None = None,
               depth: int = 0) -> Iterable[tuple[Any, str]]:
    """Model-space entities with block references (INSERT) expanded into their transformed entities, each with
    its layer (an entity of a block on layer 0 takes the layer of the reference, as CAD programs draw it).
    Every entity, expanded or not, counts against ``budget``."""
    from ezdxf.entities import Insert

    for entity in entities:
        budget.entity()
        layer = entity.dxf.get("layer", "0")
        if layer == "0" and inherited is not None:
            layer = inherited
        if isinstance(entity, Insert):
            if depth >= 16:  # a block nested 16 deep (or referencing itself): refuse rather than recurse forever
                raise MalformedFile("block references nested more than 16 deep")
            yield from _flattened(entity.virtual_entities(), budget, layer, depth + 1)
        else:
            yield entity, layer


def read_dxf_rings(path: str | Path, *, layer: str | None = None, units: str | None = None,
                   tolerance: float = 0.01) -> tuple[list[ExactRing], dict[str, Any]]:
    """The closed outlines of a DXF drawing's model space, in metres (or as drawn when unitless).

    Parameters
    ----------
    path
        The DXF file.
    layer
        Read only entities on this layer (DXF layer names compare case-insensitively); ``None``: every layer.
    units
        The drawing unit (``m``, ``cm``, ``mm``, ``in``, ``ft``, ... see :data:`UNIT_NAMES`), overriding the
        header's ``$INSUNITS``; ``unitless`` keeps the numbers as drawn.
    tolerance
        Largest distance (output units) between an arc of a polyline (a bulge) and the chords replacing it.

    Returns
    -------
    (rings, info)
        Closed rings of exact decimals: every closed LWPOLYLINE and POLYLINE, and the loops that LINEs and
        open polylines close when chained end to end; block references (INSERT) are expanded (their
        transformed coordinates are exact only where the transformation keeps them so). ``info`` says ``units`` (the unit used), and counts
        ``open_chains`` (chains that do not close), ``other_layers`` (entities skipped by ``layer``) and
        ``unsupported`` (entities of other kinds: circles, splines, text, ...).

    Raises
    ------
    MalformedFile
        When the file is not a DXF file, or names an unknown ``$INSUNITS`` code without ``units``.
    InputError
        When ``units`` is not a known unit.

    Examples
    --------
    >>> import ezdxf, tempfile, pathlib
    >>> doc = ezdxf.new(units=4)  # millimetres
    >>> _ = doc.modelspace().add_lwpolyline([(0, 0), (2500, 0), (2500, 1500), (0, 1500)], close=True)
    >>> file = pathlib.Path(tempfile.mkdtemp()) / "room.dxf"; doc.saveas(file)
    >>> rings, info = read_dxf_rings(file)
    >>> [tuple(map(float, p)) for p in rings[0]], info["units"]
    ([(0.0, 0.0), (2.5, 0.0), (2.5, 1.5), (0.0, 1.5)], 'mm')
    """
    path = Path(path)
    name = shown_path(path)
    data = read_input_bytes(path)  # regular files only, never read past the limit
    if units is not None and units not in UNIT_NAMES:
        raise InputError(f"--units {quote(units)}: use one of {', '.join(UNIT_NAMES)}")
    with _dxf_failures(name):
        return _dxf_rings(_dxf_document(data, name), name, layer, units, tolerance)


def _dxf_document(data: bytes, name: str) -> Any:
    """An ezdxf document of a DXF file's bytes (ASCII in the encoding its header names, or binary)."""
    import io

    import ezdxf
    from ezdxf.document import Drawing
    from ezdxf.lldxf.tagger import binary_tags_loader
    from ezdxf.lldxf.validator import is_dxf_stream

    if data.startswith(b"AutoCAD Binary DXF\r\n\x1a\x00"):
        return Drawing.load(binary_tags_loader(data, errors="surrogateescape"))
    probe = data.decode("utf-8", errors="ignore")
    if not is_dxf_stream(io.StringIO(probe)):
        raise MalformedFile(f"{name}: not a valid DXF file (no SECTION before other tags)")
    info = ezdxf.filemanagement.dxf_stream_info(io.StringIO(probe))
    del probe
    try:
        text = data.decode(info.encoding, errors="surrogateescape")
    except LookupError:
        raise MalformedFile(f"{name}: unknown text encoding {quote(info.encoding)}") from None
    return ezdxf.read(io.StringIO(text))


def _dxf_units(doc: Any, path: str | Path, units: str | None) -> tuple[str, Decimal | None]:
    """The drawing's unit and its factor to metres: ``units`` (--units) when given, else the header's $INSUNITS,
    which must name a length."""
    if units is not None:
        return units, UNIT_NAMES[units]
    code = doc.header.get("$INSUNITS", 0)
    if code not in DXF_UNITS:
        raise MalformedFile(f"{path}: $INSUNITS {code} is not a length unit solverplan reads: say --units")
    return DXF_UNITS[code]


def _dxf_rings(doc: Any, path: str, layer: str | None, units: str | None,
               tolerance: float) -> tuple[list[ExactRing], dict[str, Any]]:
    """The rings of an ezdxf document (see :func:`read_dxf_rings`)."""
    from ezdxf import path as dxf_path
    from ezdxf.entities import Line, LWPolyline, Polyline

    budget = _Budget(path)
    unit_name, factor = _dxf_units(doc, path, units)

    def scaled(x: float, y: float) -> tuple[Decimal, Decimal]:
        px, py = _decimal(x), _decimal(y)
        return (px, py) if factor is None else (px * factor, py * factor)

    drawing_tolerance = tolerance / float(factor) if factor else tolerance
    rings: list[ExactRing] = []
    segments: list[tuple[tuple[Decimal, Decimal], tuple[Decimal, Decimal]]] = []
    counts = {"open_chains": 0, "other_layers": 0, "unsupported": 0}
    wanted = layer.lower() if layer is not None else None
    for entity, entity_layer in _flattened(doc.modelspace(), budget):
        if wanted is not None and entity_layer.lower() != wanted:
            counts["other_layers"] += 1
            continue
        if isinstance(entity, Line):
            start, end = entity.dxf.start, entity.dxf.end
            segments.append((scaled(start.x, start.y), scaled(end.x, end.y)))
            continue
        if isinstance(entity, LWPolyline):
            closed = bool(entity.closed)
            bulged = any(b for *_, b in entity.get_points("xyb"))
            points = [(x, y) for x, y, *_ in entity.get_points("xy")]
        elif isinstance(entity, Polyline) and not (entity.is_polygon_mesh or entity.is_poly_face_mesh):
            closed = bool(entity.is_closed)
            bulged = any(v.dxf.get("bulge", 0) for v in entity.vertices)
            points = [(p.x, p.y) for p in entity.points()]
        else:
            counts["unsupported"] += 1
            continue
        if bulged:  # arcs between vertices: chords within the tolerance (these points are not exact input)
            flat = list(dxf_path.make_path(entity).flattening(drawing_tolerance))
            points = [(p.x, p.y) for p in flat]
            if closed and len(points) > 1 and points[0] == points[-1]:
                points.pop()
        ring = ring_without_repeats([scaled(x, y) for x, y in points])
        budget.outline(len(ring), closed)
        if closed:
            if len(ring) >= 3:
                rings.append(ring)
        else:
            segments.extend(zip(ring, ring[1:]))
    loops, counts["open_chains"] = _chain_loops(segments)
    budget.outline(0, False)
    for loop in loops:
        budget.outline(0, True)
    rings.extend(loops)
    return rings, {"units": unit_name, **counts}


def _circumscribed(cx: float, cy: float, r: float, tolerance: float) -> np.ndarray:
    """A regular polygon around the circle (centre, radius r): every point of the circle is inside it, and it is
    at most ``tolerance`` from the circle (its corners at r / cos(π/n)); closed (first point repeated)."""
    if r <= 0:
        return np.empty((0, 2))
    ratio = min(max(1.0 - tolerance / (r + tolerance), -1.0), 1.0)  # cos(π/n) ≥ r / (r + tolerance)
    n = max(8, math.ceil(math.pi / math.acos(ratio))) if ratio < 1 else 8
    n = min(n, 4096)
    corner = r / math.cos(math.pi / n)
    angles = 2 * math.pi * (np.arange(n + 1) % n) / n
    return np.column_stack((cx + corner * np.cos(angles), cy + corner * np.sin(angles)))


@dataclass(frozen=True)
class Linework:
    """A drawing's lines and solids in drawing units, and what was read (see :func:`read_dxf_linework`)."""

    lines: list[np.ndarray]
    solids: list[Any]
    unit: str
    factor: Decimal | None
    counts: dict[str, Any]
    door_swings: list[tuple[float, float, float]] = field(default_factory=list)  # (cx, cy, r), drawing units


DOOR_SWING_RADII = (0.5, 1.3)
"""Radii (metres) of an ARC read as a door's swing when it turns 75–105°: not a wall (it would close the doorway)."""


def read_dxf_linework(path: str | Path, *, layer: str | None = None, units: str | None = None,
                      tolerance: float = 0.01) -> Linework:
    """Every line of a DXF drawing's model space, curves flattened, hatches and SOLIDs as solids (drawing units).

    Parameters
    ----------
    path
        The DXF file.
    layer
        Read only entities on these layers: one name or several joined by commas (case-insensitive); ``None``:
        every layer.
    units
        The drawing unit (:data:`UNIT_NAMES`), overriding the header's ``$INSUNITS``.
    tolerance
        Largest distance (output units: metres, or drawing units when unitless) between a curve and the chords
        replacing it. ARC, ELLIPSE, SPLINE and polyline bulges: chords between points on the curve; CIRCLE: a
        regular polygon *around* the circle (a column is never made thinner), its corners within ``tolerance``.

    Returns
    -------
    Linework
        ``lines`` (polylines as float arrays, closed ones repeating their first point), ``solids`` (shapely
        polygons of HATCH boundary paths, even-odd, of SOLID/TRACE/3DFACE entities and of the band of a polyline
        drawn with a width), MLINE multilines as their lines, the unit and its size
        in metres, and counts: ``lines``, ``polylines``, ``circles``, ``curves`` (arcs, ellipses, splines,
        bulged polylines), ``hatches``, ``solids``, ``door_swings`` (ARCs of 75–105° with a radius in
        :data:`DOOR_SWING_RADII`: a door's swing, left out with the line of its leaf, ``door_leaves``, so that the
        doorway stays open; listed in ``door_swings``), ``other_layers`` (entities
        skipped by ``layer``) and ``unsupported`` (entities of other kinds by type: TEXT, DIMENSION, ...).

    Examples
    --------
    >>> import ezdxf, tempfile, pathlib
    >>> doc = ezdxf.new(units=4)  # millimetres
    >>> space = doc.modelspace()
    >>> _ = space.add_line((0, 0), (2500, 0)); _ = space.add_circle((1000, 1000), 150)
    >>> _ = space.add_text("Room 1")
    >>> file = pathlib.Path(tempfile.mkdtemp()) / "plan.dxf"; doc.saveas(file)
    >>> work = read_dxf_linework(file)
    >>> work.unit, work.counts["lines"], work.counts["circles"], work.counts["unsupported"]
    ('mm', 1, 1, {'TEXT': 1})
    """
    # the drawing may break while it is read or while its entities are (a block reference to a missing block)
    with _dxf_failures(shown_path(Path(path))):
        return _read_dxf_linework(path, layer=layer, units=units, tolerance=tolerance)


def _read_dxf_linework(path: str | Path, *, layer: str | None, units: str | None, tolerance: float) -> Linework:
    """:func:`read_dxf_linework` without the mapping of the parser's errors."""
    import ezdxf
    import shapely
    from ezdxf import path as dxf_path
    from ezdxf.entities import Arc, Circle, Ellipse, Hatch, Line, LWPolyline, Polyline, Spline

    path = Path(path)
    name = shown_path(path)
    data = read_input_bytes(path)  # regular files only, never read past the limit
    if units is not None and units not in UNIT_NAMES:
        raise InputError(f"--units {quote(units)}: use one of {', '.join(UNIT_NAMES)}")
    doc = _dxf_document(data, name)  # its errors: read_dxf_linework's _dxf_failures
    del data
    unit_name, factor = _dxf_units(doc, path, units)
    drawing_tolerance = tolerance / float(factor) if factor else tolerance
    wanted = None if layer is None else {name.strip().lower() for name in layer.split(",") if name.strip()}
    counts: dict[str, Any] = {"lines": 0, "polylines": 0, "circles": 0, "curves": 0, "hatches": 0, "solids": 0,
                              "other_layers": 0, "unsupported": {}}
    lines: list[np.ndarray] = []
    solids: list[Any] = []
    swings: list[tuple[float, float, float]] = []

    def flat(entity: Any) -> np.ndarray:
        points = [(v.x, v.y) for v in dxf_path.make_path(entity).flattening(drawing_tolerance)]
        return np.asarray(points, float).reshape(-1, 2)

    for entity, entity_layer in _flattened(doc.modelspace(), _Budget(name)):
        if wanted is not None and entity_layer.lower() not in wanted:
            counts["other_layers"] += 1
            continue
        try:
            if isinstance(entity, Line):
                start, end = entity.dxf.start, entity.dxf.end
                lines.append(np.array([(start.x, start.y), (end.x, end.y)], float))
                counts["lines"] += 1
            elif isinstance(entity, LWPolyline) or (isinstance(entity, Polyline) and not (
                    entity.is_polygon_mesh or entity.is_poly_face_mesh)):
                width = 0.0
                if isinstance(entity, LWPolyline):
                    bulged = any(b for *_, b in entity.get_points("xyb"))
                    points = np.array([(x, y) for x, y, *_ in entity.get_points("xy")], float)
                    closed = bool(entity.closed)
                    widths = [w for _, _, s0, e0, _ in entity.get_points("xyseb") for w in (s0, e0)]
                    width = max([float(entity.dxf.get("const_width", 0) or 0), *map(float, widths)])
                else:
                    bulged = any(v.dxf.get("bulge", 0) for v in entity.vertices)
                    points = np.array([(p.x, p.y) for p in entity.points()], float)
                    closed = bool(entity.is_closed)
                if bulged:
                    points = flat(entity)
                    counts["curves"] += 1
                elif closed and len(points) >= 2:
                    points = np.vstack((points, points[:1]))
                counts["polylines"] += 1
                lines.append(points.reshape(-1, 2))
                if width > 0 and len(points) >= 2:  # a wall drawn as a thick polyline: its band is solid
                    band = shapely.LineString(points).buffer(width / 2, cap_style="flat", join_style="mitre")
                    if not band.is_empty:
                        solids.append(band)
                        counts["solids"] += 1
            elif isinstance(entity, Circle) and not isinstance(entity, Arc):
                centre = entity.dxf.center
                lines.append(_circumscribed(centre.x, centre.y, float(entity.dxf.radius), drawing_tolerance))
                counts["circles"] += 1
            elif isinstance(entity, (Arc, Ellipse, Spline)):
                if isinstance(entity, Arc) and factor is not None:
                    sweep = (float(entity.dxf.end_angle) - float(entity.dxf.start_angle)) % 360
                    radius_m = float(entity.dxf.radius) * float(factor)
                    if DOOR_SWING_RADII[0] <= radius_m <= DOOR_SWING_RADII[1] and 75 <= sweep <= 105:
                        centre = entity.dxf.center
                        swings.append((float(centre.x), float(centre.y), float(entity.dxf.radius)))
                        continue
                lines.append(flat(entity))
                counts["curves"] += 1
            elif isinstance(entity, Hatch):
                rings = []
                for boundary in dxf_path.from_hatch(entity):
                    ring = [(v.x, v.y) for v in boundary.flattening(drawing_tolerance)]
                    if len(ring) >= 3:
                        rings.append(shapely.Polygon(ring).buffer(0))
                region = None
                for ring_shape in rings:  # even-odd: a path inside another is a hole of it
                    region = ring_shape if region is None else region.symmetric_difference(ring_shape)
                if region is not None and not region.is_empty:
                    solids.append(region)
                counts["hatches"] += 1
            elif entity.dxftype() == "MLINE":  # a multiline (AutoCAD's wall tool): its parallel lines
                for part in entity.virtual_entities():
                    if isinstance(part, Line):
                        start, end = part.dxf.start, part.dxf.end
                        lines.append(np.array([(start.x, start.y), (end.x, end.y)], float))
                counts["lines"] += 1
            elif entity.dxftype() in ("SOLID", "TRACE", "3DFACE"):  # SOLID, TRACE, 3DFACE: corners 1, 2, 4, 3 in drawing order
                corners = [entity.dxf.get(f"vtx{k}") for k in (0, 1, 3, 2)]
                ring = [(v.x, v.y) for v in corners if v is not None]
                shape = shapely.Polygon(ring).buffer(0) if len(ring) >= 3 else None
                if shape is not None and not shape.is_empty:
                    solids.append(shape)
                counts["solids"] += 1
            else:
                kind = entity.dxftype()
                counts["unsupported"][kind] = counts["unsupported"].get(kind, 0) + 1
        except (ezdxf.DXFError, ValueError, TypeError, AttributeError) as exc:
            raise MalformedFile(f"{path}: cannot read a {entity.dxftype()} entity "
                                f"({str(exc)[:60] or exc.__class__.__name__})") from None
    for line in lines:
        if not np.isfinite(line).all():
            raise MalformedFile(f"{path}: a coordinate is not a finite number")
    if swings:  # a door's leaf: a two-point line from a swing's centre out to its radius
        def is_leaf(line: np.ndarray) -> bool:
            if len(line) != 2:
                return False
            for cx, cy, r in swings:
                d0, d1 = (math.hypot(p[0] - cx, p[1] - cy) for p in line)
                tol = 0.02 * r
                if min(d0, d1) <= tol and abs(max(d0, d1) - r) <= tol:
                    return True
            return False

        kept = [line for line in lines if not is_leaf(line)]
        counts["door_leaves"] = len(lines) - len(kept)
        lines = kept
    counts["door_swings"] = len(swings)
    return Linework(lines, solids, unit_name, factor, counts, swings)


def _flatten(segment: Any, tolerance: float, depth: int = 0, t0: float = 0.0, t1: float = 1.0) -> list[tuple[float, float]]:
    """Points of a curve segment after its start, up to its end: chords within ``tolerance`` of the curve.

    A piece [t0, t1] is split in two while the curve at t = ¼, ½ and ¾ of it lies farther than ``tolerance``
    from the chord (at most 16 halvings: 65,536 chords per segment).
    """
    a, b = segment.point(t0), segment.point(t1)
    ax, ay, bx, by = float(a.x), float(a.y), float(b.x), float(b.y)
    length = math.hypot(bx - ax, by - ay)
    worst = 0.0
    for fraction in (0.25, 0.5, 0.75):
        p = segment.point(t0 + fraction * (t1 - t0))
        px, py = float(p.x), float(p.y)
        if length > 0:
            worst = max(worst, abs((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / length)
        else:
            worst = max(worst, math.hypot(px - ax, py - ay))
    if worst <= tolerance or depth >= 16:
        return [(bx, by)]
    middle = 0.5 * (t0 + t1)
    return _flatten(segment, tolerance, depth + 1, t0, middle) + _flatten(segment, tolerance, depth + 1, middle, t1)


_CSS_UNITS: dict[str, Decimal] = {"mm": Decimal("0.001"), "cm": Decimal("0.01"), "m": Decimal(1), "in": Decimal("0.0254"),
                                  "pt": Decimal("0.0254") / 72, "pc": Decimal("0.0254") / 6, "q": Decimal("0.00025")}
"""Absolute CSS length units of an SVG ``width``/``height``, in metres (``px`` and bare numbers are not physical)."""


def _svg_length(text: object) -> tuple[Decimal, str] | None:
    """``"210mm"`` → (210, "mm"); a bare number → (n, ""); anything else (percentages, junk) → None."""
    import re

    if not isinstance(text, str):
        return None
    match = re.fullmatch(r"\s*([0-9.eE+-]+)\s*([a-zA-Z%]*)\s*", text)
    if not match:
        return None
    try:
        number = Decimal(match.group(1))
    except ArithmeticError:
        return None
    return (number, match.group(2).lower()) if number.is_finite() and number > 0 else None


def read_svg_rings(path: str | Path, *, scale: Decimal | None = None,
                   tolerance: float = 0.01) -> tuple[list[ExactRing], dict[str, Any]]:
    """The closed sub-paths of an SVG drawing (paths, rectangles, polygons, circles, ...) in user units, y up, scaled.

    Parameters
    ----------
    path
        The SVG file. Transforms are applied; coordinates are the root's **user units** (the ``viewBox``'s
        units; without a viewBox, CSS pixels), whatever ``width`` and ``height`` say.
    scale
        Output units (metres) per user unit. ``None``: from the document when its ``width`` has an absolute
        unit (``mm``, ``cm``, ``m``, ``in``, ``pt``, ``pc``): width in metres over the viewBox width (an
        Inkscape drawing of ``width="210mm" viewBox="0 0 210 297"`` is 1 mm per user unit); else 1 (user units).
    tolerance
        Largest distance (output units) between a curve (arc, Bézier) and the chords replacing it.

    Returns
    -------
    (rings, info)
        Closed rings of exact decimals: x' = scale · x and y' = scale · (top − y), with ``top`` the bottom edge
        of the viewBox (or the height; 0 when there is none), so the drawing keeps its look with y pointing up.
        Line end points are exact up to 10⁻⁹ of a user unit; curve points are rounded to a power of ten at most
        ``tolerance`` / 8. ``info``: ``units`` (``m`` when the scale is known, else ``user units``), ``scale``
        (exact text), ``open_paths`` (sub-paths that do not close).

    Raises
    ------
    MalformedFile
        When the file is not SVG.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> file = pathlib.Path(tempfile.mkdtemp()) / "plan.svg"
    >>> _ = file.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="30mm" viewBox="0 0 40 30">'
    ...                     '<path d="M 0 0 H 40 V 30 H 0 Z M 10 10 h 5 v 5 h -5 z"/></svg>')
    >>> rings, info = read_svg_rings(file)
    >>> [[tuple(map(float, p)) for p in ring] for ring in rings]  # doctest: +NORMALIZE_WHITESPACE
    [[(0.0, 0.03), (0.04, 0.03), (0.04, 0.0), (0.0, 0.0)], [(0.01, 0.02), (0.015, 0.02), (0.015, 0.015), (0.01, 0.015)]]
    >>> info["units"], info["scale"]
    ('m', '0.001')
    """
    import xml.etree.ElementTree as ElementTree

    import svgelements as svg

    path = Path(path)
    name = shown_path(path)
    data = read_input_bytes(path)  # regular files only, never read past the limit
    if scale is not None and not scale > 0:
        raise InputError(f"--scale must be positive, got {scale}")
    _check_svg_tree(data, name)
    try:
        document = svg.SVG.parse(io.BytesIO(data), reify=True)
        del data
        return _svg_rings(document, name, scale, tolerance)
    except (MalformedFile, InputError, MemoryError):
        raise
    except (ElementTree.ParseError, *_PARSER_FAILURES) as exc:
        raise MalformedFile(f"{name}: not a valid SVG file ({str(exc)[:60] or exc.__class__.__name__})") from None


def _check_svg_tree(data: bytes, name: str) -> None:
    """Refuse an SVG file whose tree svgelements could not expand within bounded memory and stack.

    Parsed once with the standard library (which never recurses) before svgelements sees it: no entity
    declarations (an entity repeating another ten times, eight levels deep, is 10⁸ characters), nesting at
    most :data:`MAX_SVG_DEPTH` deep, and the element count after expanding every ``<use>`` (a ``<use>``
    copies the element it names, with its subtree) at most :data:`MAX_DRAWING_ENTITIES`; a ``<use>`` that
    names itself or an element containing it is refused, since its expansion has no end.
    """
    import xml.etree.ElementTree as ElementTree

    if b"<!ENTITY" in data:
        raise MalformedFile(f"{name}: declares XML entities (<!ENTITY>), which an SVG drawing does not need")
    try:
        root = ElementTree.fromstring(data)
    except ElementTree.ParseError as exc:
        raise MalformedFile(f"{name}: not a valid SVG file ({str(exc)[:60]})") from None
    by_id: dict[str, Any] = {}
    children: dict[int, list[Any]] = {}
    stack = [(root, 1)]
    while stack:  # depth-first without recursion: the depth and the ids
        element, depth = stack.pop()
        if depth > MAX_SVG_DEPTH:
            raise MalformedFile(f"{name}: elements nested more than {MAX_SVG_DEPTH} deep")
        element_id = element.get("id")
        if element_id is not None:
            by_id.setdefault(element_id, element)
        kids = list(element)
        children[id(element)] = kids
        stack.extend((kid, depth + 1) for kid in kids)
    if len(children) > MAX_DRAWING_ENTITIES:
        raise MalformedFile(f"{name}: more than {MAX_DRAWING_ENTITIES:,} elements")

    def target(element: Any) -> Any:
        if not (isinstance(element.tag, str) and element.tag.rsplit("}", 1)[-1] == "use"):
            return None
        ref = element.get("{http://www.w3.org/1999/xlink}href") or element.get("href") or ""
        return by_id.get(ref[1:]) if ref.startswith("#") else None

    # expanded size of each element = 1 + its children's + its <use> target's, computed without recursion;
    # an element met again while it is being expanded is a cycle
    size: dict[int, int] = {}
    visiting: set[int] = set()
    work: list[tuple[Any, bool]] = [(root, False)]
    while work:
        element, done = work.pop()
        key = id(element)
        if done:
            visiting.discard(key)
            referenced = target(element)
            total = 1 + sum(size[id(kid)] for kid in children[key]) + (size[id(referenced)] if referenced is not None else 0)
            size[key] = min(total, MAX_DRAWING_ENTITIES + 1)
            continue
        if key in size:
            continue
        if key in visiting:
            raise MalformedFile(f"{name}: a <use> refers to itself (id {quote(element.get('id'))}): its copy has no end")
        visiting.add(key)
        work.append((element, True))
        referenced = target(element)
        pending = list(children[key]) + ([referenced] if referenced is not None else [])
        for kid in pending:
            if id(kid) in visiting:
                raise MalformedFile(f"{name}: a <use> refers to an element containing it "
                                    f"(id {quote(kid.get('id'))}): its copy has no end")
            if id(kid) not in size:
                work.append((kid, False))
    if size[id(root)] > MAX_DRAWING_ENTITIES:
        raise MalformedFile(f"{name}: its <use> copies expand to more than {MAX_DRAWING_ENTITIES:,} elements")


def _svg_rings(document: Any, path: str, scale: Decimal | None, tolerance: float) -> tuple[list[ExactRing], dict[str, Any]]:
    """The rings of an svgelements document (see :func:`read_svg_rings`)."""
    import svgelements as svg

    from solverplan.floorplan.outline import grid_quantum

    budget = _Budget(path)
    # svgelements maps the viewBox onto the viewport (CSS pixels); undo that to get back to user units
    to_user = None
    box = getattr(document, "viewbox", None)
    transform = getattr(document, "viewbox_transform", None)
    if box is not None and transform:
        to_user = ~svg.Matrix(transform)
    if box is not None and getattr(box, "height", None):
        top = _decimal(float(box.y) + float(box.height))
        user_width = Decimal(repr(float(box.width)))
    else:
        top = _decimal(float(document.height)) if getattr(document, "height", None) else Decimal(0)
        user_width = _decimal(float(document.width)) if getattr(document, "width", None) else Decimal(0)
    unit_name = "user units"
    if scale is None:
        width = _svg_length(document.values.get("width"))
        if width is not None and width[1] in _CSS_UNITS and user_width > 0:
            scale = width[0] * _CSS_UNITS[width[1]] / user_width
            unit_name = "m"
        else:
            scale = Decimal(1)
    else:
        unit_name = "m"
    drawing_tolerance = tolerance / float(scale)
    quantum = grid_quantum(Decimal(repr(float(tolerance))))

    def user(x: float, y: float) -> tuple[float, float]:
        if to_user is None:
            return x, y
        p = to_user.point_in_matrix_space((x, y))
        return float(p.x), float(p.y)

    def exact(x: float, y: float) -> tuple[Decimal, Decimal]:
        ux, uy = user(x, y)
        return _decimal(round(ux, 9)) * scale, (top - _decimal(round(uy, 9))) * scale

    def rounded(x: float, y: float) -> tuple[Decimal, Decimal]:
        px, py = exact(x, y)
        return px.quantize(quantum), py.quantize(quantum)

    user_scale = 1.0 if to_user is None else float(abs(to_user.a) or 1.0)
    rings: list[ExactRing] = []
    open_paths = 0
    for element in document.elements():
        budget.entity()
        if not isinstance(element, svg.Shape):
            continue
        shape = element if isinstance(element, svg.Path) else svg.Path(element)
        for sub in shape.as_subpaths():
            points: ExactRing = []
            closed = False
            for segment in sub:
                if isinstance(segment, svg.Move):
                    points.append(exact(segment.end.x, segment.end.y))
                elif isinstance(segment, svg.Close):
                    closed = True
                elif isinstance(segment, svg.Line):
                    points.append(exact(segment.end.x, segment.end.y))
                else:  # arcs and Bézier curves (in viewport pixels: the tolerance converted there)
                    chords = _flatten(segment, drawing_tolerance / user_scale)
                    points.extend(rounded(x, y) for x, y in chords[:-1])
                    points.append(exact(segment.end.x, segment.end.y))
            ring = ring_without_repeats(points)
            if not closed and points and points[0] == points[-1]:
                closed = True  # drawn back to its start without a Z
            budget.outline(len(ring), closed)
            if closed and len(ring) >= 3:
                rings.append(ring)
            elif points:
                open_paths += 1
    return rings, {"open_paths": open_paths, "units": unit_name, "scale": str(scale)}


def _area2(ring: Sequence[tuple[Decimal, Decimal]]) -> Decimal:
    return sum((ring[i - 1][0] * ring[i][1] - ring[i][0] * ring[i - 1][1] for i in range(len(ring))), Decimal(0))


def arrange_rings(rings: Sequence[ExactRing], source: str) -> tuple[ExactRing, list[ExactRing], dict[str, int]]:
    """The largest ring (by exact area) as the outer ring, the rings inside it as holes.

    A ring inside a hole (an island) or outside the outer ring is dropped; so is a ring of zero area and a
    ring drawn twice. Returns (outer, holes, counts of ``nested``, ``outside``, ``zero_area`` and
    ``duplicates`` rings).

    >>> D = Decimal
    >>> square = lambda x, y, s: [(D(x), D(y)), (D(x + s), D(y)), (D(x + s), D(y + s)), (D(x), D(y + s))]
    >>> outer, holes, counts = arrange_rings([square(1, 1, 1), square(0, 0, 10), square(20, 0, 1)], "plan")
    >>> outer == square(0, 0, 10), len(holes), counts
    (True, 1, {'nested': 0, 'outside': 1, 'zero_area': 0, 'duplicates': 0})
    """
    import shapely

    counts = {"nested": 0, "outside": 0, "zero_area": 0, "duplicates": 0}
    areas = [abs(_area2(r)) for r in rings]
    kept = [(a, r) for a, r in zip(areas, rings) if a > 0]
    counts["zero_area"] = len(rings) - len(kept)
    seen: set[tuple] = set()
    unique = []
    for area, ring in kept:  # a wall drawn twice (either direction, any start) is one ring
        key = tuple(sorted(ring))
        if key in seen:
            counts["duplicates"] += 1
            continue
        seen.add(key)
        unique.append((area, ring))
    kept = unique
    if not kept:
        raise MalformedFile(f"{source}: no closed outline found (closed polylines, loops of lines, or closed paths)")
    kept.sort(key=lambda item: -item[0])
    outer = kept[0][1]
    outer_shape = shapely.Polygon([(float(x), float(y)) for x, y in outer])
    holes: list[ExactRing] = []
    hole_shapes: list[Any] = []
    for _, ring in kept[1:]:
        shape = shapely.Polygon([(float(x), float(y)) for x, y in ring])
        if not outer_shape.covers(shape):
            counts["outside"] += 1
        elif any(h.covers(shape) for h in hole_shapes):
            counts["nested"] += 1
        else:
            holes.append(ring)
            hole_shapes.append(shape)
    return outer, holes, counts
