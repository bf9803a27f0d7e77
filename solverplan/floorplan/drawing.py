"""Drawn linework → free space: walls as solids, as architects draw them (line pairs, polylines, hatches).

A floor plan drawn in CAD is not a list of rooms: it is lines. A wall is usually the band between two parallel
lines (a *line pair*), closed at its ends by short jamb lines; a column is a circle; a poché is a hatch. The free
space is what those lines enclose, so it is found the way a person reads the drawing:

1. **Join.** Line ends closer than ``snap`` (drawing units) are one point; an end closer than ``snap`` to another
   line is moved onto it (a partition wall drawn to stop at the outer wall does stop there).
2. **Node.** Every line is split where it meets another, on a decimal grid of ``grid`` drawing units
   (``shapely.unary_union`` with ``grid_size``: GEOS's snap-rounding, so crossings are exact grid points).
3. **Close jambs.** A wall band left open at a door (its two lines end without a jamb) is closed: two dangling
   ends that are each other's nearest dangling end and at most ``max_jamb`` apart are joined by a line.
4. **Faces.** ``shapely.polygonize_full`` gives every face the lines enclose (with its holes), the dangling lines
   and the cut lines. The free space is the face holding ``seed_point``, else the largest face; solids
   (hatches, SOLIDs) are taken out of it.
5. **Touches.** A hole touching the outer ring (or another hole) at one point is valid for GEOS but not for an
   environment (rings never touch): a square of ``4 × grid`` around the point is taken out of the free space,
   joining the obstacle to the wall there (the free space only shrinks).

Everything not used is listed with a position and a size (:class:`DroppedFeature`): dangling lines, faces that
are not the free space and do not touch it, parts of the free space cut off by solids, points joined.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from solverplan.errors import InputError, MalformedFile
from solverplan.floorplan.outline import largest_part, separate_touches

__all__ = ["DroppedFeature", "LineworkFace", "free_space_from_linework", "PLAUSIBLE_AREA_FRACTION",
           "plausibility_warnings"]

PLAUSIBLE_AREA_FRACTION = 0.05
"""A free space smaller than this share of the drawing's bounding box is reported as implausible (a warning)."""


@dataclass(frozen=True)
class DroppedFeature:
    """Something of the input that the environment does not contain, and where it was.

    Attributes
    ----------
    kind
        What it was: ``speckle`` (a map's obstacle below the size kept), ``component`` (free space not connected
        to the part kept), ``spur`` (a free protrusion cut), ``small_hole`` (an obstacle below ``min_hole_area``),
        ``dangling_line`` (a drawn line enclosing nothing), ``face`` (a closed face of the drawing that is not
        the free space and does not touch it), ``cut_off`` (free space cut off by a solid), ``touch`` (a point
        where an obstacle touched a wall: joined), ``disconnected`` (free space the robot cannot reach once
        inflated), ``passage_closed`` (a gap narrower than the robot), ``merged_obstacle`` (an obstacle that
        the robot's inflation joined to a wall or another obstacle), ``keepout`` (a keepout area applied),
        ``door_swing`` (a DXF door's swing and leaf, left out so the doorway stays open).
    at
        A representative point (output units: metres for maps), inside the feature.
    size
        The larger side of its bounding box (output units), or a length for lines and gaps.
    area
        Its area (output units squared; 0 for lines and points).
    """

    kind: str
    at: tuple[float, float]
    size: float
    area: float = 0.0

    def to_json(self) -> dict:
        return {"kind": self.kind, "at": [round(self.at[0], 6), round(self.at[1], 6)], "size": round(self.size, 6),
                "area": round(self.area, 6)}

    def scaled(self, factor: float) -> DroppedFeature:
        """The same feature in other units (``factor`` output units per drawing unit)."""
        return DroppedFeature(self.kind, (self.at[0] * factor, self.at[1] * factor), self.size * factor,
                              self.area * factor * factor)

    @staticmethod
    def of(kind: str, geometry: Any) -> DroppedFeature:
        """The feature of a shapely geometry: its representative point, the larger side of its bounds, its area."""
        point = geometry.representative_point() if not geometry.is_empty else None
        minx, miny, maxx, maxy = geometry.bounds
        size = max(maxx - minx, maxy - miny)
        if geometry.geom_type in ("LineString", "LinearRing"):  # a line: its middle, its length
            point = geometry.interpolate(0.5, normalized=True)
            size = geometry.length
        elif geometry.geom_type == "MultiLineString":
            size = geometry.length
        at = (float(point.x), float(point.y)) if point is not None else (0.0, 0.0)
        return DroppedFeature(kind, at, float(size), float(geometry.area))


@dataclass(frozen=True)
class LineworkFace:
    """The free space found in a drawing's linework (drawing units, coordinates on the grid)."""

    polygon: Any  # shapely Polygon
    dropped: tuple[DroppedFeature, ...]
    counts: dict[str, int]
    extent: tuple[float, float, float, float]  # the bounds of all linework
    largest_obstacle: float  # the area of the largest hole (drawing units squared)


def _cluster_ends(lines: list[np.ndarray], snap: float) -> int:
    """Move line ends closer than ``snap`` to one point (the first of their cluster); returns the ends moved."""
    from scipy.spatial import cKDTree

    ends: list[np.ndarray] = []
    where: list[tuple[int, int]] = []
    for k, line in enumerate(lines):
        if len(line) >= 2 and not np.array_equal(line[0], line[-1]):
            ends.extend((line[0], line[-1]))
            where.extend(((k, 0), (k, len(line) - 1)))
    if len(ends) < 2 or snap <= 0:
        return 0
    points = np.array(ends, dtype=float)
    parent = list(range(len(points)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in cKDTree(points).query_pairs(snap):
        a, b = root(i), root(j)
        if a != b:
            parent[max(a, b)] = min(a, b)
    moved = 0
    for i, (k, index) in enumerate(where):
        r = root(i)
        if r != i and not np.array_equal(points[r], points[i]):
            lines[k][index] = points[r]
            moved += 1
    return moved


def _snap_ends_to_lines(lines: list[np.ndarray], snap: float) -> int:
    """Move each line end that lies within ``snap`` of another line (but on no line end) onto that line."""
    import shapely

    if snap <= 0 or len(lines) < 2:
        return 0
    shapes = [shapely.LineString(line) for line in lines]
    tree = shapely.STRtree(shapes)
    moved = 0
    for k, line in enumerate(lines):
        if len(line) < 2 or np.array_equal(line[0], line[-1]):
            continue
        for index in (0, len(line) - 1):
            point = shapely.Point(line[index])
            candidates = tree.query(point.buffer(snap))
            best = None
            for c in candidates.tolist():
                if c == k:
                    continue
                d = shapes[c].distance(point)
                if 0 < d <= snap and (best is None or d < best[0]):
                    best = (d, c)
            if best is not None:
                target = shapes[best[1]].interpolate(shapes[best[1]].project(point))
                line[index] = (target.x, target.y)
                moved += 1
    return moved


def _node_degrees(noded: Any) -> dict[tuple[float, float], int]:
    degrees: dict[tuple[float, float], int] = {}
    for piece in getattr(noded, "geoms", [noded]):
        coords = piece.coords
        if len(coords) < 2:
            continue
        for end in (coords[0], coords[-1]):
            degrees[end] = degrees.get(end, 0) + 1
    return degrees


def _jambs(noded: Any, max_jamb: float) -> list[np.ndarray]:
    """Lines that close wall bands left open: between mutually nearest dangling ends at most ``max_jamb`` apart."""
    from scipy.spatial import cKDTree

    if max_jamb <= 0:
        return []
    loose = np.array([p for p, d in _node_degrees(noded).items() if d == 1], float)
    if len(loose) < 2:
        return []
    tree = cKDTree(loose)
    distance, nearest = tree.query(loose, k=2)
    out = []
    for i in range(len(loose)):
        j = int(nearest[i, 1])
        if distance[i, 1] <= max_jamb and int(nearest[j, 1]) == i and i < j:
            out.append(np.array([loose[i], loose[j]]))
    return out


def _face_at(faces: Sequence[Any], seed_point: tuple[float, float] | None) -> int:
    import shapely

    if seed_point is None:
        return int(np.argmax([f.area for f in faces]))
    point = shapely.Point(seed_point)
    for k, face in enumerate(faces):
        if face.covers(point):
            return k
    raise InputError(f"--seed-point ({seed_point[0]:g}, {seed_point[1]:g}) is in no closed face of the drawing")


def free_space_from_linework(
    lines: Sequence[np.ndarray],
    solids: Sequence[Any] = (),
    *,
    snap: float,
    grid: float,
    max_jamb: float = 0.0,
    seed_point: tuple[float, float] | None = None,
) -> LineworkFace:
    """The free space a drawing's lines enclose (module docstring), in drawing units.

    Parameters
    ----------
    lines
        Polylines, ``(n, 2)`` float arrays in drawing units; a closed one repeats its first point last.
    solids
        Shapely polygons that are solid (hatches, SOLID entities): never free space.
    snap
        Line ends closer than this (drawing units) are joined; an end this close to a line is put on it.
    grid
        The coordinate grid (drawing units): every output coordinate is a multiple of it.
    max_jamb
        Dangling ends at most this far apart (drawing units) that are each other's nearest are joined: the open
        end of a wall band at a door. 0: none.
    seed_point
        A point (drawing units) in the face to keep; ``None``: the largest face.

    Returns
    -------
    LineworkFace
        The free space (a shapely Polygon with holes, coordinates on the grid) and what was dropped.

    Raises
    ------
    MalformedFile
        When the lines enclose no face at all.
    InputError
        When ``seed_point`` is in no face.

    Examples
    --------
    Walls drawn as pairs of lines (10 cm thick) around a 4 × 3 room, a partition touching the outer wall, a column:

    >>> import shapely
    >>> outer = np.array([[-0.1, -0.1], [4.1, -0.1], [4.1, 3.1], [-0.1, 3.1], [-0.1, -0.1]])
    >>> inner = np.array([[0, 0], [4, 0], [4, 3], [0, 3], [0, 0]], float)
    >>> partition = [np.array([[2, 0], [2, 1]], float), np.array([[2.1, 0], [2.1, 1]], float),
    ...              np.array([[2, 1], [2.1, 1]], float)]
    >>> column = np.array(shapely.Point(1, 2).buffer(0.2, 4).exterior.coords)
    >>> face = free_space_from_linework([outer, inner, *partition, column], snap=1e-6, grid=1e-6)
    >>> round(face.polygon.area, 4), len(face.polygon.interiors)
    (11.7775, 1)
    """
    import shapely

    counts: dict[str, int] = {"ends_joined": 0, "ends_put_on_lines": 0, "jambs_closed": 0}
    work = [np.array(line, float) for line in lines if len(line) >= 2]
    for solid in solids:
        for ring in (solid.exterior, *solid.interiors):
            work.append(np.asarray(ring.coords, float))
    if not work:
        raise MalformedFile("no closed outline found: the drawing has no lines (LINE, polylines, circles, arcs, hatches) "
                            "to read walls from")
    counts["ends_joined"] = _cluster_ends(work, snap)
    counts["ends_put_on_lines"] = _snap_ends_to_lines(work, snap)
    shapes = [shapely.LineString(line) for line in work if len(np.unique(line, axis=0)) >= 2]
    if not shapes:
        raise MalformedFile("no closed outline found: the drawing's lines all have zero length")
    noded = shapely.unary_union(shapely.MultiLineString(shapes), grid_size=grid)
    jambs = _jambs(noded, max_jamb)
    if jambs:
        counts["jambs_closed"] = len(jambs)
        noded = shapely.unary_union([noded, *[shapely.LineString(j) for j in jambs]], grid_size=grid)
    polygons, cuts, dangles, invalid = shapely.polygonize_full([noded])
    faces = [g for g in polygons.geoms if g.area > 0]
    extent = tuple(float(v) for v in noded.bounds)
    if not faces:
        raise MalformedFile("no closed outline found: the drawing's lines enclose no face (closed polylines, lines "
                            "meeting end to end, circles or hatches)")
    chosen_index = _face_at(faces, seed_point)
    free = faces[chosen_index]
    dropped: list[DroppedFeature] = []
    if solids:
        solid = shapely.union_all(list(solids))
        if free.intersects(solid):
            free = shapely.set_precision(free.difference(solid), grid)
            main, rest = largest_part(free)
            if main is None:
                raise MalformedFile("the free space found lies entirely inside a hatch or solid")
            dropped += [DroppedFeature.of("cut_off", part) for part in rest]
            free = main
    free, touches = separate_touches(free, grid)
    main, rest = largest_part(free)
    if main is None:
        raise MalformedFile("the free space vanished when touching rings were separated")
    free = main
    dropped += [DroppedFeature.of("cut_off", part) for part in rest]
    dropped += [DroppedFeature("touch", (p.x, p.y), 0.0) for p in touches]
    boundary = free.boundary
    for k, face in enumerate(faces):
        if k != chosen_index and not face.intersects(boundary) and not free.contains(face):
            dropped.append(DroppedFeature.of("face", face))
    for collection in (dangles, cuts, invalid):
        for line in collection.geoms:
            if line.length > 0:
                dropped.append(DroppedFeature.of("dangling_line", line))
    largest = max((shapely.Polygon(r).area for r in free.interiors), default=0.0)
    return LineworkFace(free, tuple(dropped), counts, extent, largest)  # type: ignore[arg-type]


def plausibility_warnings(area: float, largest_obstacle: float, extent: tuple[float, float, float, float],
                          unit: str = "") -> list[str]:
    """Why a free space read from a drawing looks wrong, if it does: smaller than its largest obstacle (the
    'free space' is probably the outside of the building, or a wall), or below :data:`PLAUSIBLE_AREA_FRACTION`
    of the drawing's bounding box.

    >>> plausibility_warnings(11.3, 0.0, (0, 0, 20, 12))
    ["the free space (11.3) is 4.7% of the drawing's bounding box (240): probably a wall or a piece of furniture, not the rooms; choose the face with --seed-point or the walls' layer with --layer"]
    """
    warnings = []
    if largest_obstacle > area:
        warnings.append(f"the free space ({area:.6g}{unit}) is smaller than its largest obstacle "
                        f"({largest_obstacle:.6g}{unit}): probably the outside of the building; choose the face "
                        "with --seed-point")
    box = (extent[2] - extent[0]) * (extent[3] - extent[1])
    if box > 0 and area < PLAUSIBLE_AREA_FRACTION * box:
        warnings.append(f"the free space ({area:.6g}{unit}) is {100 * area / box:.2g}% of the drawing's bounding box "
                        f"({box:.6g}{unit}): probably a wall or a piece of furniture, not the rooms; choose the face "
                        "with --seed-point or the walls' layer with --layer")
    return warnings
