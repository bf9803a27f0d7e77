"""From a traced or drawn outline to a valid environment: holes, simplification, snapping, exact rounding.

Every reader of :mod:`solverplan.floorplan` ends here. A traced outline (floats, in metres) goes through

1. dropping holes smaller than ``min_hole_area`` (speckle that survived the raster stage),
2. topology-preserving simplification with a distance tolerance (GEOS's ``TopologyPreservingSimplifier``
   through :meth:`shapely.Polygon.simplify`: rings never cross, holes never leave the outer ring),
3. optional rectilinear snapping of the edges within a given angle of an axis,
4. rounding every coordinate to a decimal grid (``quantum``), so that the environment written is made of
   short terminating decimals and reads back exactly; exactly collinear and repeated vertices are removed
   in integer arithmetic on that grid,
5. validation by :meth:`solverplan.environment.Environment.from_coords` (the project's one validator).

What each step removed is counted in a ``dropped`` dictionary, reported by the import's summary.
"""

from __future__ import annotations

import math
from dataclasses import replace
from decimal import Decimal
from fractions import Fraction
from typing import Any, Sequence

import numpy as np

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.limits import MAX_VERTICES

__all__ = ["finish_outline", "snap_rectilinear", "grid_quantum", "environment_from_polygon", "separate_touches",
           "largest_part", "wall_noise", "axis_parallel_share", "coarse_ring", "simplify_inside", "part_to_keep", "wall_axes"]

FloatRing = np.ndarray  # (n, 2) float coordinates, not closed


def grid_quantum(resolution: Decimal) -> Decimal:
    """The rounding step of traced coordinates: the largest power of ten at most ``resolution / 8``.

    An eighth of a cell keeps the rounding error (at most half the step) below a sixteenth of a cell, far
    inside the tracing's own error, while the coordinates stay short decimals (5 cm cells → millimetres).

    >>> grid_quantum(Decimal("0.05")), grid_quantum(Decimal("0.1")), grid_quantum(Decimal("2"))
    (Decimal('0.001'), Decimal('0.01'), Decimal('0.1'))
    """
    if resolution <= 0:
        raise InvalidEnvironment(f"the rounding grid needs a positive resolution, got {resolution}")
    exponent = math.floor(math.log10(float(resolution / 8)))
    return Decimal(1).scaleb(exponent)


def _ring_area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def snap_rectilinear(ring: FloatRing, degrees: float, max_chamfer: float = 0.0, *,
                     inside: bool = False, max_step: float = 0.0) -> tuple[FloatRing, int]:
    """Make the edges of ``ring`` within ``degrees`` of an axis exactly axis-parallel.

    Consecutive near-horizontal edges form a run that gets one y (their length-weighted mean); likewise
    near-vertical runs get one x. A vertex between a horizontal and a vertical run moves to their
    crossing; a vertex between a snapped run and an oblique edge moves only across the run (the oblique
    edge follows it). An oblique edge no longer than ``max_chamfer`` between a horizontal and a vertical run
    is a cut-off corner (traced maps have them where a wall's raggedness met the simplification): both its
    ends move to the runs' crossing. Returns the new ring (vertices of a run's interior, and the two ends of
    a collapsed corner, are left collinear or repeated for the rounding step to remove) and the number of
    edges snapped or collapsed.

    ``inside``: give back no free space, the free space lying on the **left** of the ring's edges (an outer ring
    counter-clockwise, holes clockwise): a run gets the coordinate of its vertex farthest into the free space
    instead of the mean (a run whose edges go both ways is left as it is), and a chain of oblique edges (together
    at most ``max_chamfer`` long) between a horizontal and a vertical run is collapsed into their corner when every
    one of its edges has the corner on its free side (the obstacle takes what is cut off). That keeps each run's line on the free side of its own vertices;
    :func:`finish_outline` checks the whole ring. With ``inside``, an edge that strays at most ``max_step`` across an
    axis (and less than half its length) belongs to that axis's runs, and so do the edges between two runs of one
    kind that together stray at most ``max_step`` across its axis: the jogs and teeth of a ragged wall go, the wall's
    line taking their farther side.

    >>> ring = np.array([[0, 0], [4, 0.05], [4.02, 3], [0, 3]], float)
    >>> snapped, count = snap_rectilinear(ring, 2.0)
    >>> count, snapped.round(3).tolist()
    (4, [[0.0, 0.025], [4.01, 0.025], [4.01, 3.0], [0.0, 3.0]])
    >>> snap_rectilinear(ring, 2.0, inside=True)[0].round(3).tolist()   # counter-clockwise: the room shrinks
    [[0.0, 0.05], [4.0, 0.05], [4.0, 3.0], [0.0, 3.0]]
    """
    n = len(ring)
    if n < 3 or degrees <= 0:
        return ring.copy(), 0
    starts, ends = ring, np.roll(ring, -1, axis=0)
    delta = ends - starts
    lengths = np.hypot(delta[:, 0], delta[:, 1])
    angle = np.degrees(np.arctan2(delta[:, 1], delta[:, 0])) % 180.0  # undirected: [0, 180)
    kind = np.full(n, "o")
    kind[(angle <= degrees) | (angle >= 180.0 - degrees)] = "h"
    kind[np.abs(angle - 90.0) <= degrees] = "v"
    if (kind == "o").all():
        return ring.copy(), 0
    own = kind.copy()
    if inside and max_step > 0:
        # a ragged wall simplified zigzags across a band a step wide: an edge rising at most a step (and by less than
        # half its run) belongs to the run of its axis, whose line takes the band's farther side
        dx, dy = np.abs(delta[:, 0]), np.abs(delta[:, 1])
        kind[(kind == "o") & (dy <= max_step) & (dx > 2 * dy)] = "h"
        kind[(kind == "o") & (dx <= max_step) & (dy > 2 * dx)] = "v"
        _absorb_steps(kind, starts, ends, max_step)
    # runs of one kind, cyclically: start the walk just after a change of kind (there is one unless all edges
    # share a kind, impossible for a closed ring of h edges only or v edges only with non-zero area)
    changes = [i for i in range(n) if kind[i] != kind[i - 1]]
    if not changes:
        return ring.copy(), 0
    run_of = np.empty(n, int)
    values: list[float] = []
    first = changes[0]
    run = -1
    weights: list[tuple[float, float]] = []
    extremes: list[set[float]] = []  # inside: the run's farthest coordinate into the free space, signed (+ max, − min)
    for step in range(n):
        i = (first + step) % n
        if step == 0 or kind[i] != kind[i - 1]:
            run += 1
            weights.append((0.0, 0.0))
            extremes.append(set())
        run_of[i] = run
        if kind[i] != "o":
            axis = 1 if kind[i] == "h" else 0  # the coordinate a run shares
            middle = 0.5 * (starts[i, axis] + ends[i, axis])
            total, weighted = weights[run]
            weights[run] = (total + lengths[i], weighted + lengths[i] * middle)
            # the free side (left) of an edge going +x is +y, of an edge going +y is −x; a step joined to the run
            # (another kind of its own) says nothing of the direction, its ends count for the extreme
            extremes[run].update((starts[i, axis], ends[i, axis]))
            if own[i] == kind[i]:
                up = bool(delta[i, 0] > 0) if kind[i] == "h" else bool(delta[i, 1] < 0)
                extremes[run].add(math.inf if up else -math.inf)  # the direction, to find runs that go both ways
    for (total, weighted), found in zip(weights, extremes):
        coordinates = found - {math.inf, -math.inf}
        if not inside:
            values.append(weighted / total if total > 0 else 0.0)
        elif (math.inf in found) == (-math.inf in found):
            values.append(math.nan)  # both ways (or no direction): not snapped
        else:
            values.append(max(coordinates) if math.inf in found else min(coordinates))
    if inside:
        for i in range(n):
            if kind[i] != "o" and math.isnan(values[run_of[i]]):
                kind[i] = "o"
    out = ring.astype(float).copy()
    for i in range(n):  # vertex i sits between edge i - 1 and edge i
        for edge in (i - 1, i):
            k = kind[edge % n]
            if k == "h":
                out[i, 1] = values[run_of[edge % n]]
            elif k == "v":
                out[i, 0] = values[run_of[edge % n]]
    collapsed = 0
    if max_chamfer > 0 and not inside:
        for i in np.flatnonzero((kind == "o") & (lengths <= max_chamfer)).tolist():
            before, after = kind[i - 1], kind[(i + 1) % n]
            if {before, after} != {"h", "v"}:
                continue
            horizontal = (i - 1) % n if before == "h" else (i + 1) % n
            vertical = (i + 1) % n if before == "h" else (i - 1) % n
            corner = (values[run_of[vertical]], values[run_of[horizontal]])
            out[i] = corner
            out[(i + 1) % n] = corner
            collapsed += 1
    elif max_chamfer > 0:  # a chain of oblique edges between a horizontal and a vertical run, cut off from free space
        oblique = kind == "o"
        if oblique.any() and not oblique.all():
            first_edge = int(np.flatnonzero(~oblique)[0])
            t = 0
            while t < n:
                i = (first_edge + t) % n
                if not oblique[i]:
                    t += 1
                    continue
                u = t
                while u < n and oblique[(first_edge + u) % n]:
                    u += 1
                chain = [(first_edge + k) % n for k in range(t, u)]
                t = u
                before, after = kind[chain[0] - 1], kind[(chain[-1] + 1) % n]
                if {before, after} != {"h", "v"} or float(lengths[chain].sum()) > max_chamfer:
                    continue
                horizontal = (chain[0] - 1) % n if before == "h" else (chain[-1] + 1) % n
                vertical = (chain[-1] + 1) % n if before == "h" else (chain[0] - 1) % n
                corner = (values[run_of[vertical]], values[run_of[horizontal]])
                # every edge of the chain must have the corner on its left: the region given to the obstacle is free
                if any(delta[k, 0] * (corner[1] - starts[k, 1]) - delta[k, 1] * (corner[0] - starts[k, 0]) < 0
                       for k in chain):
                    continue
                for k in chain:
                    out[k] = corner
                out[(chain[-1] + 1) % n] = corner
                collapsed += len(chain)
    return out, int((kind != "o").sum()) + collapsed


def _absorb_steps(kind: np.ndarray, starts: np.ndarray, ends: np.ndarray, max_step: float) -> None:
    """Relabel, in place, every maximal sequence of edges not of kind K (``h``, then ``v``) that lies between two edges
    of kind K and strays at most ``max_step`` across K's axis, as K (:func:`snap_rectilinear` ``max_step``)."""
    n = len(kind)
    for axis in ("h", "v"):
        across = 1 if axis == "h" else 0
        mine = np.flatnonzero(kind == axis)
        if not len(mine) or len(mine) == n:
            continue
        order = (int(mine[0]) + np.arange(n)) % n  # from an edge of this kind, once round
        t = 0
        while t < n:
            if kind[order[t]] != axis:
                u = t
                while u < n and kind[order[u]] != axis:
                    u += 1
                gap = order[t:u]  # between order[t - 1] and order[u % n], both of this kind
                values = np.concatenate((starts[gap, across], ends[gap, across]))
                if float(values.max() - values.min()) <= max_step:
                    kind[gap] = axis
                t = u
            t += 1


def _gives_back(ring: np.ndarray, snapped: np.ndarray, *, hole: bool) -> bool:
    """Does ``snapped`` (the ring after snapping) add free space to ``ring``: reach outside an outer ring, or uncover
    part of a hole? (Grid units; a sliver of area below a hundredth of a unit square is rounding, not a gift.)"""
    import shapely

    before, after = shapely.Polygon(ring).buffer(0), shapely.Polygon(snapped).buffer(0)
    gained = before.difference(after) if hole else after.difference(before)
    return bool(gained.area > 1e-2)


def _join_walls(rings: list[np.ndarray], joined: set[int]) -> tuple[np.ndarray, set[int]] | None:
    """The outer ring ``rings[0]`` (grid units) with the holes that meet it taken out of it (the obstacles join the
    wall: free space only shrinks), and those holes; ``None`` when that does not leave one ring without holes."""
    import shapely

    outer = shapely.Polygon(rings[0]).buffer(0)
    line = shapely.LinearRing(rings[0])
    meeting = {k for k in range(1, len(rings)) if k not in joined and shapely.LinearRing(rings[k]).intersects(line)}
    if not meeting:
        return None
    cut = outer.difference(shapely.union_all([shapely.Polygon(rings[k]).buffer(0) for k in meeting]))
    part, _ = largest_part(shapely.set_precision(cut, 1.0))
    if part is None or len(part.interiors):
        return None
    coords = np.asarray(part.exterior.coords[:-1], float)
    if shapely.LinearRing(coords).is_ccw != line.is_ccw:
        coords = coords[::-1]
    return coords, meeting


def _turned_back(ring: np.ndarray, turn: np.ndarray, *, hole: bool) -> np.ndarray:
    """A ring snapped in a turned frame (:func:`finish_outline` ``axes``), without its straight and repeated vertices,
    grown (a hole) or shrunk (the outer ring) by one grid step, mitred, and turned back to the map's frame."""
    import shapely

    keep = np.any(np.abs(ring - np.roll(ring, 1, axis=0)) > 1e-9, axis=1)
    ring = ring[keep]
    if len(ring) >= 3:
        a, b = ring - np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0) - ring
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        scale = np.hypot(*a.T) * np.hypot(*b.T)
        ring = ring[np.abs(cross) > 1e-9 * np.maximum(scale, 1.0)]
    if len(ring) < 3:
        return ring @ turn.T
    moved, _ = largest_part(shapely.Polygon(ring).buffer(1.0 if hole else -1.0, join_style="mitre", mitre_limit=10.0))
    if moved is None:
        return ring @ turn.T
    coords = np.asarray(moved.exterior.coords[:-1], float)
    if shapely.LinearRing(coords).is_ccw != shapely.LinearRing(ring).is_ccw:
        coords = coords[::-1]
    return coords @ turn.T


def _box_of(ring: np.ndarray, step: float) -> np.ndarray | None:
    """The bounding box of a hole (grid units, clockwise like the hole) when it adds no more area than a band ``step``
    wide along the hole's outline (a ragged rack or post), else ``None``."""
    import shapely

    hole = shapely.Polygon(ring)
    low, high = np.floor(ring.min(axis=0)), np.ceil(ring.max(axis=0))
    box = shapely.box(low[0], low[1], high[0], high[1])
    if box.area - hole.area > step * hole.length:
        return None
    corners = np.array([[low[0], low[1]], [low[0], high[1]], [high[0], high[1]], [high[0], low[1]]])  # clockwise
    return corners if not shapely.LinearRing(ring).is_ccw else corners[::-1]


def _simple(ring: np.ndarray) -> bool:
    """Is ``ring`` (repeated vertices allowed) a simple ring?"""
    import shapely

    keep = np.any(ring != np.roll(ring, 1, axis=0), axis=1)
    return len(ring[keep]) >= 3 and bool(shapely.LinearRing(ring[keep]).is_simple)


def _within(ring: np.ndarray, snapped: np.ndarray, *, hole: bool) -> np.ndarray | None:
    """The snapped ring cut back to give back nothing: an outer ring intersected with ``ring``'s polygon, a hole
    joined with it (on the grid); ``None`` if that is not one simple ring."""
    import shapely

    before, after = shapely.Polygon(ring).buffer(0), shapely.Polygon(snapped).buffer(0)
    fixed = shapely.set_precision(after.union(before) if hole else after.intersection(before), 1.0)
    part, _ = largest_part(fixed)
    if part is None or (hole and len(part.interiors)):
        return None
    coords = np.asarray(part.exterior.coords[:-1], float)
    return coords if shapely.LinearRing(ring).is_ccw == shapely.LinearRing(coords).is_ccw else coords[::-1]


def _shrink_inside(polygon: Any, tolerance: float, *, keep_point: tuple[float, float] | None) -> tuple[Any, list]:
    """``polygon`` (grid units) shrunk by ``tolerance`` + 1 (mitred) and simplified within ``tolerance``: inside
    ``polygon`` with a margin for the rounding to the grid (:func:`finish_outline` ``inside``); with the changes of
    topology (:func:`~solverplan.floorplan.robot.topology_changes`, grid units)."""
    from solverplan.floorplan.robot import topology_changes

    simplified = simplify_inside(polygon.buffer(-1.0, join_style="mitre", mitre_limit=10.0), tolerance)
    main, rest, held = part_to_keep(simplified, keep_point)
    if main is None:
        raise InvalidEnvironment(f"the free space vanished when shrunk by the simplification tolerance "
                                 f"({tolerance:g} grid steps): simplify less (--simplify METRES)")
    if keep_point is not None and not held and rest:  # the seed point lies in the strip shrunk away: its nearest part
        import shapely

        parts = [main, *rest]
        main = min(parts, key=lambda part: part.distance(shapely.Point(keep_point)))
        rest = [part for part in parts if part is not main]
    return main, topology_changes(polygon, main, rest, reach=2 * tolerance + 1.0, grid=1.0)


def simplify_inside(region: Any, tolerance: float) -> Any:
    """``region`` (a shapely polygon) shrunk by ``tolerance`` (mitred: corners are not rounded off) and simplified
    within it, so that the result lies inside ``region``.

    Douglas–Peucker keeps every point of its result within the tolerance of the boundary it simplifies, so nothing
    passes back out of ``region``; but GEOS's topology-preserving simplifier may also drop a ring's first vertex by
    another rule (seen 1.26 tolerances away), so what still leaves ``region`` is cut off.

    >>> import shapely
    >>> room = shapely.Polygon([(0, 0), (4, 0), (4, 0.05), (4.1, 0.05), (4.1, 3), (0, 3)])
    >>> inner = simplify_inside(room, 0.1)
    >>> room.covers(inner), len(inner.exterior.coords) - 1
    (True, 4)
    """
    shrunk = region.buffer(-tolerance, join_style="mitre", mitre_limit=10.0)
    simplified = shrunk.simplify(tolerance, preserve_topology=True)
    return simplified if region.covers(simplified) else simplified.intersection(region)


def part_to_keep(geometry: Any, point: tuple[float, float] | None) -> tuple[Any, list[Any], bool]:
    """The polygon of ``geometry`` to keep: the one covering ``point`` when one does (then True), else the largest
    (then False); with the other polygons. ``(None, [], False)`` when there is none.

    >>> import shapely
    >>> kept, others, held = part_to_keep(shapely.MultiPolygon([shapely.box(0, 0, 2, 2), shapely.box(3, 0, 4, 1)]), (3.5, 0.5))
    >>> kept.bounds, len(others), held
    ((3.0, 0.0, 4.0, 1.0), 1, True)
    """
    import shapely

    main, rest = largest_part(geometry)
    if main is None or point is None:
        return main, rest, False
    where = shapely.Point(point)
    for part in (main, *rest):
        if part.covers(where):
            return part, [p for p in (main, *rest) if p is not part], True
    return main, rest, False


def wall_noise(rings: Sequence[FloatRing], cell: float) -> float:
    """How far a traced outline strays from its walls (output units): the 90th percentile of the distance from its
    vertices to the outline simplified within 3 cells, over the rings at least 12 cells across.

    A clean map traces its straight walls exactly (0) and its slanted ones in half-cell steps (about half a cell);
    a lidar map's ragged walls, where cells along a wall come out free or occupied at random, a cell or more.

    >>> square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    >>> wall_noise([square], 0.5)
    0.0
    >>> x = np.arange(0, 10, 0.5)
    >>> ragged = np.vstack([np.column_stack([x, np.where(np.arange(len(x)) % 2, 0.5, 0.0)]), [[10, 0], [10, 10], [0, 10]]])
    >>> wall_noise([ragged], 0.5)
    0.5
    """
    import shapely

    distances = []
    for ring in rings:
        if len(ring) < 4 or float(np.ptp(ring, axis=0).max()) < 12 * cell:
            continue
        coarse = coarse_ring(ring, 3 * cell)
        if coarse.is_empty:
            continue
        distances.append(shapely.distance(shapely.points(ring), coarse))
    if not distances:
        return 0.0
    return float(np.round(np.percentile(np.concatenate(distances), 90), 9))


def coarse_ring(ring: FloatRing, tolerance: float) -> Any:
    """``ring`` simplified within ``tolerance`` (Douglas–Peucker) as a shapely LinearRing, started at its lowest
    vertex (a corner of its convex hull: Douglas–Peucker keeps the start of a ring, which must not be the middle of a
    wall)."""
    import shapely

    first = int(np.lexsort((ring[:, 0], ring[:, 1]))[0])
    return shapely.LinearRing(np.roll(ring, -first, axis=0)).simplify(tolerance, preserve_topology=False)


def axis_parallel_share(rings: Sequence[FloatRing], degrees: float, axes: float = 0.0) -> float:
    """The share of the outline's length (0–1) in edges within ``degrees`` of an axis (of the axes turned by ``axes``
    degrees).

    >>> axis_parallel_share([np.array([[0, 0], [4, 0], [4, 3], [1, 4]], float)], 10.0)   # 7 of 7 + √10 + √17
    0.49
    """
    total = near = 0.0
    for ring in rings:
        delta = np.roll(ring, -1, axis=0) - ring
        lengths = np.hypot(delta[:, 0], delta[:, 1])
        angle = (np.degrees(np.arctan2(delta[:, 1], delta[:, 0])) - axes) % 90.0
        total += float(lengths.sum())
        near += float(lengths[(angle <= degrees) | (angle >= 90.0 - degrees)].sum())
    return round(near / total, 4) if total > 0 else 0.0


def wall_axes(rings: Sequence[FloatRing], degrees: float) -> float:
    """The turn of the axes (degrees in [0, 90), to a tenth) that the most outline length lies within ``degrees`` of:
    the walls' directions of a map drawn at an angle.

    >>> square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    >>> turned = square @ np.array([[np.cos(0.5), np.sin(0.5)], [-np.sin(0.5), np.cos(0.5)]])   # 0.5 rad ≈ 28.6°
    >>> wall_axes([turned], 5.0), wall_axes([square], 5.0)
    (28.6, 0.0)
    """
    angles, weights = [], []
    for ring in rings:
        delta = np.roll(ring, -1, axis=0) - ring
        angles.append(np.degrees(np.arctan2(delta[:, 1], delta[:, 0])) % 90.0)
        weights.append(np.hypot(delta[:, 0], delta[:, 1]))
    if not angles:
        return 0.0
    angle, weight = np.concatenate(angles), np.concatenate(weights)
    candidates = np.arange(0.0, 90.0, 0.1)
    off = np.abs((angle[None, :] - candidates[:, None] + 45.0) % 90.0 - 45.0)
    best = float(candidates[int(np.argmax(((off <= degrees) * weight[None, :]).sum(axis=1)))])
    near = np.abs((angle - best + 45.0) % 90.0 - 45.0) <= degrees  # refine: the weighted mean offset of those near it
    mean = best + float(np.average((angle[near] - best + 45.0) % 90.0 - 45.0, weights=weight[near]))
    return round(mean % 90.0, 1) % 90.0


def _valid_rings(rings: Sequence[np.ndarray]) -> bool:
    """Do the rings make a valid environment: a valid polygon whose rings do not even touch one another?

    (GEOS accepts a hole touching the outer ring at a point; the environment validator does not.)
    """
    import shapely

    if not shapely.Polygon(rings[0], rings[1:]).is_valid:
        return False
    closed = [np.vstack((ring, ring[:1])) for ring in rings]
    return bool(shapely.MultiLineString(closed).is_simple)


def _bad_rings(rings: Sequence[np.ndarray]) -> set[int]:
    """Rings that are not simple, or that cross or touch another ring (an STR-tree finds the pairs)."""
    import shapely

    bad = {i for i, r in enumerate(rings) if len(np.unique(r, axis=0)) < 3 or _ring_area(r) == 0}  # collapsed
    lines = [shapely.LinearRing(r) if i not in bad else shapely.LinearRing() for i, r in enumerate(rings)]
    bad |= {i for i, line in enumerate(lines) if i not in bad and not line.is_simple}
    if len(lines) > 1:
        tree = shapely.STRtree(lines)
        pairs = tree.query(lines, predicate="intersects")
        for i, j in zip(*pairs.tolist()):
            if i != j:
                bad.update((i, j))
    return bad


def _clean_grid_ring(ring: np.ndarray) -> tuple[np.ndarray, int]:
    """Remove repeated and exactly collinear vertices (integer arithmetic); returns the ring and how many went."""
    removed = 0
    while len(ring) >= 3:
        prev, nxt = np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0)
        a, b = ring - prev, nxt - ring
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]  # exact: grid integers well inside int64
        keep = cross != 0
        if keep.all():
            break
        if not keep.any():
            return ring[:0], removed + len(ring)
        # drop one vertex of each run of collinear ones at a time would be slow; dropping all of them at once
        # is right: a vertex collinear with its neighbours is not a corner of the ring, and the corners stay
        removed += int((~keep).sum())
        ring = ring[keep]
    return ring, removed


def finish_outline(
    outer: FloatRing,
    holes: Sequence[FloatRing],
    *,
    quantum: Decimal,
    offset: tuple[Fraction, Fraction] = (Fraction(0), Fraction(0)),
    simplify: float = 0.0,
    min_hole_area: float = 0.0,
    rectilinear: float = 0.0,
    name: str = "",
    dropped: dict | None = None,
    features: list | None = None,
    inside: bool = False,
    keep_point: tuple[float, float] | None = None,
    axes: float = 0.0,
) -> tuple[Environment, dict]:
    """Simplify, snap, round and validate an outline with holes into an :class:`Environment`.

    Parameters
    ----------
    outer, holes
        Float rings (``(n, 2)`` arrays, not closed, any orientation), in output units (metres for maps)
        relative to ``offset``.
    quantum
        The decimal grid every output coordinate lies on (relative to ``offset``).
    offset
        An exact point added to every rounded coordinate (a map's origin), so the grid follows the map.
    simplify
        Topology-preserving simplification tolerance (output units); 0 keeps every vertex.
    min_hole_area
        Holes of smaller area (output units squared), before or after simplification, are dropped.
    rectilinear
        Snap edges within this many degrees of an axis (0: no snapping); oblique edges up to 4 ×
        ``simplify`` long between a horizontal and a vertical edge are collapsed into their corner.
    name
        The environment's name.
    dropped
        Counts of what earlier stages dropped; this stage adds its own.
    features
        When given, each hole dropped (small or flattened) is appended as a
        :class:`~solverplan.floorplan.drawing.DroppedFeature` (``small_hole``) with its position and size.
    inside
        Simplify and snap **conservatively**: the environment lies inside the outline given (a plan valid on it is
        valid on the map). The free space is first shrunk by ``simplify`` plus one grid step (mitred, so corners are
        not rounded off) and then simplified within ``simplify`` (Douglas–Peucker keeps every point within the
        tolerance of the boundary it simplifies, so nothing goes back past the outline given, rounding included);
        snapped runs take the coordinate of their vertex farthest into the free space
        (:func:`snap_rectilinear` ``inside``), and a ring whose snap still gives back free space keeps its
        simplified shape. Passages the shrinking closes and obstacles it joins to a wall or to one another are
        listed in ``features`` (``passage_closed``, ``merged_obstacle``, ``disconnected``), and counted in
        ``dropped["passages_closed"]``; an obstacle that meets a wall snapped inwards joins the wall (listed as
        ``merged_obstacle``, counted in ``dropped["obstacles_joined"]``), and rings the shrinking leaves touching at
        a point are joined there (:func:`separate_touches`; listed as ``touch``, counted in
        ``dropped["touches_joined"]``).
    axes
        The walls' directions (degrees, counter-clockwise from the x axis, below 90) that ``rectilinear`` snaps to, when
        they are not the axes: a map drawn at an angle is snapped in its own frame (turned back, the snapped rings
        one grid step further into the obstacles so that the rounding gives nothing back).
    keep_point
        With ``inside``: a point (output units, relative to ``offset``) whose part to keep when the shrinking splits
        the free space; ``None``: the largest part.

    Returns
    -------
    (Environment, dict)
        The validated environment and the ``dropped`` counts: ``small_holes``, ``simplified_vertices``,
        ``collinear_vertices``, ``degenerate_holes`` (holes the rounding flattened), ``rectilinear_skipped``
        (rings whose snapping would have made them invalid, kept unsnapped), and ``rectilinear_edges`` (edges
        snapped; not a loss, but reported with the rest).

    Raises
    ------
    InvalidEnvironment
        When the outline, after these steps, is not a valid environment (the validator's one line).

    Examples
    --------
    >>> square = np.array([[0, 0], [2, 0], [2, 0.0004], [2, 2], [0, 2]], float)
    >>> hole = np.array([[0.5, 0.5], [0.5, 0.6], [0.6, 0.6], [0.6, 0.5]], float)
    >>> env, dropped = finish_outline(square, [hole], quantum=Decimal("0.001"), min_hole_area=0.05)
    >>> env.outer, dropped["small_holes"], dropped["collinear_vertices"]
    (((Fraction(2, 1), Fraction(0, 1)), (Fraction(2, 1), Fraction(2, 1)), (Fraction(0, 1), Fraction(2, 1)), (Fraction(0, 1), Fraction(0, 1))), 1, 1)
    """
    import shapely

    counts = {"small_holes": 0, "simplified_vertices": 0, "collinear_vertices": 0, "degenerate_holes": 0,
              "rectilinear_skipped": 0, "rectilinear_edges": 0}
    counts = {**counts, **(dropped or {})}
    # Everything below works in units of the grid, on integer coordinates (held as floats, exact below 2⁵³):
    # GEOS's robust predicates are then exact, so a vertex that simplification leaves on another edge — common,
    # traced vertices lie on a half-cell lattice — is seen as the touch it is, not hidden by binary rounding.
    unit = float(quantum)
    unit_area = unit * unit
    fx, fy = float(offset[0]), float(offset[1])

    def note(ring: np.ndarray, scale: float = 1.0) -> None:
        if features is not None and len(ring):
            from solverplan.floorplan.drawing import DroppedFeature

            points = np.asarray(ring, float) * scale
            low, high = points.min(axis=0), points.max(axis=0)
            features.append(DroppedFeature("small_hole", (float(points[:, 0].mean()) + fx, float(points[:, 1].mean()) + fy),
                                           float((high - low).max()), abs(_ring_area(points))))

    kept = []
    for h in holes:
        if abs(_ring_area(h)) >= min_hole_area:
            kept.append(h)
        else:
            note(h)
    counts["small_holes"] += len(holes) - len(kept)
    grid_outer, grid_holes = np.rint(outer / unit), [np.rint(h / unit) for h in kept]
    polygon = shapely.Polygon(grid_outer, grid_holes)
    if not polygon.is_valid:
        # a traced outline is valid by construction; a drawn one may not be: say where, as the validator would
        reason = shapely.is_valid_reason(shapely.Polygon(outer, kept))
        raise InvalidEnvironment(f"the outline is not a valid polygon: {reason}")
    traced = polygon
    if simplify > 0 and inside:
        counts.setdefault("passages_closed", 0)
        before = len(polygon.exterior.coords) + sum(len(r.coords) for r in polygon.interiors)
        polygon, changes = _shrink_inside(polygon, simplify / unit, keep_point=None if keep_point is None else
                                          (keep_point[0] / unit, keep_point[1] / unit))
        after = len(polygon.exterior.coords) + sum(len(r.coords) for r in polygon.interiors)
        counts["simplified_vertices"] += max(before - after, 0)
        counts["passages_closed"] += sum(1 for c in changes if c.kind == "passage_closed")
        if features is not None:
            for change in (c.scaled(unit) for c in changes):
                features.append(replace(change, at=(change.at[0] + fx, change.at[1] + fy)))
    elif simplify > 0:
        before = len(polygon.exterior.coords) + sum(len(r.coords) for r in polygon.interiors)
        polygon = polygon.simplify(simplify / unit, preserve_topology=True)
        after = len(polygon.exterior.coords) + sum(len(r.coords) for r in polygon.interiors)
        counts["simplified_vertices"] += before - after
        small = [r for r in polygon.interiors if shapely.Polygon(r).area * unit_area < min_hole_area]
        for r in small:
            note(np.asarray(r.coords[:-1], float), unit)
        if small:
            counts["small_holes"] += len(small)
            polygon = shapely.Polygon(polygon.exterior,
                                      [r for r in polygon.interiors if shapely.Polygon(r).area * unit_area >= min_hole_area])
    if inside:  # on the grid (snap-rounding keeps it valid; the shrinking left a step of margin for it), free space
        # on the left of every edge
        polygon = largest_part(shapely.set_precision(polygon, 1.0))[0]
        # GEOS lets a hole touch another ring at a point, an environment does not: join them there (the free space
        # only shrinks), each listed
        polygon, touches = separate_touches(polygon, 1.0)
        if touches:
            polygon = largest_part(polygon)[0]
            counts["touches_joined"] = counts.get("touches_joined", 0) + len(touches)
            if features is not None:
                from solverplan.floorplan.drawing import DroppedFeature

                features.extend(DroppedFeature("touch", (p.x * unit + fx, p.y * unit + fy), 2 * unit) for p in touches)
        polygon = shapely.orient_polygons(polygon)
    rings = [np.asarray(polygon.exterior.coords[:-1], float)] + [np.asarray(r.coords[:-1], float) for r in polygon.interiors]
    if rectilinear > 0:
        snapped: list[np.ndarray] = []
        reverted: set[int] = set()
        for index, ring in enumerate(rings):
            turn = np.array([[math.cos(math.radians(axes)), -math.sin(math.radians(axes))],
                             [math.sin(math.radians(axes)), math.cos(math.radians(axes))]])
            frame = ring @ turn if axes else ring  # the ring with the walls' axes along x and y (turned by −axes)
            candidate, count = snap_rectilinear(frame, rectilinear, max_chamfer=(8 if inside else 4) * simplify / unit,
                                                inside=inside,
                                                max_step=3 * simplify / unit + 2)
            if inside and index > 0:  # an obstacle whose bounding box adds at most a step along its outline: the box
                box = _box_of(frame, 3 * simplify / unit + 2)
                if box is not None:
                    candidate, count = box, len(ring)
            if axes:  # back to the map's frame, one step further into the obstacles so that the rounding gives nothing
                candidate = _turned_back(candidate, turn, hole=index > 0)
            candidate = np.rint(candidate)
            if inside and (not _simple(candidate) or _gives_back(ring, candidate, hole=index > 0)):
                fixed = _within(ring, candidate, hole=index > 0)  # its new points lie on ``ring``'s edges,
                if fixed is not None:  # a step inside the traced outline: the rounding keeps them inside
                    candidate = fixed
                else:
                    candidate, count = ring, 0
                    reverted.add(index)
            snapped.append(candidate)
            counts["rectilinear_edges"] += count
        chosen = list(snapped)
        joined: set[int] = set()
        while True:  # revert the snaps that make a ring cross or touch itself or another, until none does
            bad = _bad_rings([r for k, r in enumerate(chosen) if k not in joined])
            bad = {[k for k in range(len(chosen)) if k not in joined][i] for i in bad} - reverted
            if not bad:
                break
            # an obstacle near a wall is what conflicts with the wall's snapped run: revert the obstacle's own
            # snap first and keep the walls straight (reverting the outer ring un-snapped every wall of a map
            # that keeps its posts); the outer ring goes back only when no hole is left to blame — or, inside, when
            # the obstacles it meets cannot join the wall (the free space only shrinks where they do)
            holes_bad = bad - {0}
            if inside and bad == {0}:
                merged = _join_walls(chosen, joined)
                if merged is not None:
                    chosen[0], more = merged
                    joined |= more
                    continue
            for index in holes_bad or bad:
                chosen[index] = rings[index]
            reverted |= holes_bad or bad
        if joined:
            counts["obstacles_joined"] = counts.get("obstacles_joined", 0) + len(joined)
            if features is not None:
                from solverplan.floorplan.drawing import DroppedFeature

                for k in sorted(joined):  # listed where they were (world coordinates), as the shrinking's are
                    features.append(DroppedFeature.of("merged_obstacle", shapely.Polygon(rings[k] * unit + (fx, fy))))
            chosen = [r for k, r in enumerate(chosen) if k not in joined]
            rings = [r for k, r in enumerate(rings) if k not in joined]
        walls_only = [chosen[0], *rings[1:]]
        if _valid_rings(chosen):
            rings = chosen
            counts["rectilinear_skipped"] += len(reverted)
        elif 0 not in reverted and _valid_rings(walls_only):  # keep the walls snapped, the obstacles as they were
            rings = walls_only
            counts["rectilinear_skipped"] += len(rings) - 1
        else:  # e.g. a hole snapped out of the outer ring: keep the outline as simplified
            counts["rectilinear_skipped"] += len(rings)
    grid_rings: list[np.ndarray] = []
    for index, ring in enumerate(rings):
        grid = ring.astype(np.int64)
        repeated = np.all(grid == np.roll(grid, 1, axis=0), axis=1)
        counts["collinear_vertices"] += int(repeated.sum())
        grid = grid[~repeated]
        grid, removed = _clean_grid_ring(grid)
        counts["collinear_vertices"] += removed
        if len(grid) < 3:
            if index == 0:
                raise InvalidEnvironment("the outline vanished when rounded to the coordinate grid: it is too small")
            counts["degenerate_holes"] += 1
            note(ring, unit)
            continue
        # a canonical first vertex (the lowest, rightmost among the lowest), so that edge ids do not depend on where
        # the tracer or the drawing happened to start the ring, nor on noise far from that corner
        first = int(np.lexsort((-grid[:, 0], grid[:, 1]))[0])
        grid_rings.append(np.roll(grid, -first, axis=0))
    step = Fraction(quantum)
    ox, oy = offset
    # one common denominator: each coordinate is then one Fraction built from two integers, not a sum of
    # products of Fractions (a traced map has 10⁴–10⁵ coordinates; this was a fifth of a large import's time)
    denominator = math.lcm(ox.denominator, oy.denominator, step.denominator)
    base_x = ox.numerator * (denominator // ox.denominator)
    base_y = oy.numerator * (denominator // oy.denominator)
    unit = step.numerator * (denominator // step.denominator)

    def exact(ring: np.ndarray) -> list[tuple[Fraction, Fraction]]:
        return [(Fraction(base_x + x * unit, denominator), Fraction(base_y + y * unit, denominator))
                for x, y in ring.tolist()]

    total = sum(map(len, grid_rings))
    if total > MAX_VERTICES:
        raise InvalidEnvironment(f"the outline has {total} vertices (an environment has at most {MAX_VERTICES}): "
                                 "simplify more (--simplify METRES)")
    environment = Environment.from_coords(exact(grid_rings[0]), [exact(r) for r in grid_rings[1:]], name=name)
    return environment, counts


def largest_part(geometry: Any) -> tuple[Any, list[Any]]:
    """The largest polygon of a shapely geometry and the other polygons (largest first); (None, []) if none."""
    parts = [g for g in getattr(geometry, "geoms", [geometry]) if g.geom_type == "Polygon" and not g.is_empty]
    if not parts:
        return None, []
    parts.sort(key=lambda g: -g.area)
    return parts[0], parts[1:]


def separate_touches(polygon: Any, grid: float) -> tuple[Any, list[Any]]:
    """Take a square of side 4 × ``grid`` out of ``polygon`` wherever two of its rings touch (GEOS allows a hole
    to touch the outer ring or another hole at a point, an environment does not): the obstacle is joined to the
    wall there and the free space only shrinks. Returns the polygon (or pieces) and the points separated."""
    import shapely

    rings = [polygon.exterior, *polygon.interiors]
    lines = [shapely.LineString(r.coords) for r in rings]
    points = []
    for k, line in enumerate(lines):  # a ring touching itself (a pinched outer ring)
        if not line.is_simple:
            nodes = shapely.node(line)
            counts: dict = {}
            for piece in nodes.geoms:
                for end in (piece.coords[0], piece.coords[-1]):
                    counts[end] = counts.get(end, 0) + 1
            points += [shapely.Point(p) for p, c in counts.items() if c > 2]
    if len(lines) > 1:
        tree = shapely.STRtree(lines)
        left, right = tree.query(lines, predicate="intersects")
        for i, j in zip(left.tolist(), right.tolist()):
            if i < j:
                meet = lines[i].intersection(lines[j])
                for part in getattr(meet, "geoms", [meet]):
                    if not part.is_empty:
                        points.append(part.representative_point())
    if not points:
        return polygon, []
    cut = shapely.union_all([p.buffer(2 * grid, cap_style="square") for p in points])
    return shapely.set_precision(polygon.difference(cut), grid), points


def environment_from_polygon(polygon: Any, *, quantum: Decimal, offset: tuple[Fraction, Fraction] = (Fraction(0), Fraction(0)),
                             name: str = "") -> tuple[Environment, list[Any], list[Any]]:
    """A shapely polygon (absolute float coordinates) as an environment on the decimal grid ``offset + k · quantum``.

    The polygon is rounded to the grid with GEOS's snap-rounding (``shapely.set_precision``, which keeps it
    valid), rings that touch are separated (:func:`separate_touches`), and the largest piece is made an
    environment through :func:`finish_outline` (exact decimals, the project's validator).

    Returns
    -------
    (Environment, list, list)
        The environment, the other pieces (shapely polygons, absolute coordinates: free space that is lost)
        and the points where touching rings were separated.

    Raises
    ------
    InvalidEnvironment
        When nothing is left on the grid, or the result is still not a valid environment.

    Examples
    --------
    >>> import shapely
    >>> ring = shapely.Polygon([(0, 0), (3, 0), (3, 2), (0, 2)], [[(0, 1), (1, 0.5), (1, 1.5)]])  # a hole touching
    >>> env, lost, touched = environment_from_polygon(ring, quantum=Decimal("0.01"))
    >>> len(env.holes), [(p.x, p.y) for p in touched], round(float(env.area), 4)
    (0, [(0.0, 1.0)], 5.4994)
    """
    import shapely

    ox, oy = float(offset[0]), float(offset[1])
    grid = float(quantum)
    moved = shapely.transform(polygon, lambda c: c - (ox, oy)) if (ox or oy) else polygon
    rounded = shapely.set_precision(moved, grid)
    main, rest = largest_part(rounded)
    if main is None:
        raise InvalidEnvironment("the free space vanished on the coordinate grid: it is too small")
    separated, touched = separate_touches(main, grid)
    main, more = largest_part(separated)
    if main is None:
        raise InvalidEnvironment("the free space vanished when its touching rings were separated")
    rest += more
    outer = np.asarray(main.exterior.coords[:-1], float)
    holes = [np.asarray(r.coords[:-1], float) for r in main.interiors]
    environment, _ = finish_outline(outer, holes, quantum=quantum, offset=offset, name=name)

    def back(g: Any) -> Any:
        return shapely.transform(g, lambda c: c + (ox, oy)) if (ox or oy) else g

    return environment, [back(g) for g in rest], [back(p) for p in touched]
