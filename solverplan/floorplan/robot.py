"""Robots as they are: a disc of radius R instead of a point, and areas it must keep out of.

A disc robot of radius R collides with nothing exactly when its centre stays in the free space eroded by R: the
free space minus the Minkowski sum of walls and obstacles with the disc (Nav2's inflation). The bounce planner then
plans for the centre: the eroded free space is the environment, and a "bounce" is the disc touching a wall.

The erosion is ``shapely.buffer(-R′)`` with round joins of ``QUAD_SEGS`` chords per quarter circle. The chords of a
round join cut inside the true arc by up to R′(1 − cos(π / (4 · QUAD_SEGS))), so the distance used is
R′ = R / cos(π / (4 · QUAD_SEGS)) + (one grid step, for the rounding that follows): every point of the result is at
least R from every wall and obstacle (conservative), and straight walls move in by at most 2 % of R more than R.
The import adds the simplification tolerance its outline was made with (``margin``): a simplified outline may lie
that much inside the walls as traced, and the robot keeps R from those.

What the inflation changes in the topology is reported, with positions (:class:`DroppedFeature`):
``disconnected`` (parts of the free space the centre can no longer reach from the part kept: rooms behind a door
narrower than 2R), ``passage_closed`` (where: the gap between the part kept and each part lost, or between an
obstacle and what it merged with), ``merged_obstacle`` (obstacles joined to a wall or to one another).
"""

from __future__ import annotations

import math
from typing import Any

from solverplan.errors import InputError
from solverplan.floorplan.drawing import DroppedFeature
from solverplan.floorplan.outline import part_to_keep, simplify_inside

__all__ = ["QUAD_SEGS", "inflation_distance", "erode_free_space", "topology_changes"]

QUAD_SEGS = 4
"""Chords per quarter circle of the rounded inflation (16 per full turn)."""


def inflation_distance(radius: float, grid: float) -> float:
    """The buffer distance that keeps every point at least ``radius`` from the walls (module docstring).

    >>> round(inflation_distance(0.17, 0.001), 6)
    0.17433
    """
    return radius / math.cos(math.pi / (4 * QUAD_SEGS)) + grid


def erode_free_space(free: Any, radius: float, *, grid: float, seed_point: tuple[float, float] | None = None,
                     simplify: float = 0.0, margin: float = 0.0) -> tuple[Any, list[DroppedFeature]]:
    """The free space where the centre of a disc of ``radius`` may be, and what that changed.

    Parameters
    ----------
    free
        The free space (shapely Polygon, output units).
    radius
        The robot's radius (output units), positive.
    grid
        The coordinate grid step the result will be rounded to (output units).
    seed_point
        A point whose component to keep (it must lie in the eroded free space); ``None``: the largest component.
    margin
        Added to the inflation (output units): how far the outline given may lie inside the true walls (a traced
        map simplified within ``--simplify`` moved its walls by up to that much), so that the result keeps R from
        the walls as they were before that simplification. Default 0.
    simplify
        A simplification tolerance (output units) that never gives back free space: the eroded free space is
        shrunk by it (mitred) and then simplified within it (Douglas–Peucker moves a boundary by at most the
        tolerance, so the result lies inside the eroded free space). The arcs of the inflation otherwise cost a
        vertex every 22.5°, and the planner's work grows as n⁴. At most a quarter of ``radius`` is used (so gaps
        up to 2.5 R wide stay open); 0: none.

    Returns
    -------
    (Polygon, list of DroppedFeature)
        The component kept and the topology changes: ``disconnected`` parts (area, position), ``passage_closed``
        gaps (position: the middle of the narrowest gap; size: its width in the free space before inflation) and
        ``merged_obstacle`` (each obstacle that now touches a wall or another obstacle: position, size, area).

    Raises
    ------
    InputError
        When nothing is left (the robot fits nowhere) or the seed point is not in the eroded free space.

    Examples
    --------
    Two 2 m rooms joined by a 0.3 m door: a 0.17 m robot does not pass.

    >>> import shapely
    >>> rooms = shapely.Polygon([(0, 0), (2, 0), (2, 0.85), (2.5, 0.85), (2.5, 0), (4.5, 0), (4.5, 2), (2.5, 2),
    ...                          (2.5, 1.15), (2, 1.15), (2, 2), (0, 2)])
    >>> kept, changes = erode_free_space(rooms, 0.17, grid=0.001)
    >>> [c.kind for c in changes], round(kept.area, 2), round(changes[1].size, 2)
    (['disconnected', 'passage_closed'], 2.74, 0.3)
    """
    if not math.isfinite(radius) or radius <= 0:
        raise InputError(f"--robot-radius must be a positive number of metres, got {radius:g}")
    distance = inflation_distance(radius, grid) + margin
    eroded = free.buffer(-distance, quad_segs=QUAD_SEGS, join_style="round")
    simplify = min(simplify, radius / 4)
    if simplify > 0:
        eroded = simplify_inside(eroded, simplify)
    reach = distance + simplify  # what the walls grew by, at most
    main, rest, held = part_to_keep(eroded, seed_point)
    if main is None:
        raise InputError(f"a robot of radius {radius:g} fits nowhere in the free space (its widest place is narrower "
                         f"than {2 * radius:g})")
    if seed_point is not None and not held:
        raise InputError(f"the seed point ({seed_point[0]:g}, {seed_point[1]:g}) is closer than --robot-radius "
                         f"{radius:g} to a wall or obstacle")
    return main, topology_changes(free, main, rest, reach=reach, grid=grid)


def topology_changes(free: Any, main: Any, rest: list[Any], *, reach: float, grid: float) -> list[DroppedFeature]:
    """What shrinking ``free`` into ``main`` (and the lost parts ``rest``) changed in its topology, with positions.

    ``disconnected`` parts and the ``passage_closed`` gap to each; every obstacle (hole of ``free``) that is no longer
    alone in a hole of ``main`` (``merged_obstacle``) and the gap to its nearest wall or obstacle. ``reach`` is how
    far the walls moved at most (obstacles farther than 1.5 ``reach`` from ``main`` lie in lost parts: not listed).

    >>> import shapely
    >>> free = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 2), (2, 2), (2, 1)]])
    >>> main = free.buffer(-0.6, join_style="mitre")
    >>> [(c.kind, c.size) for c in topology_changes(free, main, [], reach=0.6, grid=0.01)]
    [('merged_obstacle', 1.0), ('passage_closed', 1.0)]
    """
    import shapely

    changes: list[DroppedFeature] = []
    for part in rest:
        changes.append(DroppedFeature.of("disconnected", part))
        a, b = _nearest(part, main)
        changes.append(_gap(free, a, b))
    # obstacles that merged: an original hole no longer alone in a hole of the result
    holes = [shapely.Polygon(r) for r in free.interiors]
    if holes:
        result_holes = [shapely.Polygon(r) for r in main.interiors]
        tree = shapely.STRtree(holes)
        alone: set[int] = set()
        for h in result_holes:
            inside = tree.query(h, predicate="intersects").tolist()
            if len(inside) == 1:
                alone.add(inside[0])
        outer = shapely.Polygon(free.exterior)
        for k, hole in enumerate(holes):
            if k in alone or not main.intersects(hole.buffer(reach * 1.5)):
                continue  # alone in its inflated hole, or far from the part kept (in a lost room)
            changes.append(DroppedFeature.of("merged_obstacle", hole))
            others = [holes[j] for j in tree.query(hole.buffer(2 * reach + grid)).tolist() if j != k]
            walls = outer.exterior
            nearest = min([(hole.distance(o), o) for o in others] + [(hole.distance(walls), walls)],
                          key=lambda item: item[0])
            a, b = _nearest(hole, nearest[1])
            changes.append(_gap(free, a, b))
    return changes


def _nearest(a: Any, b: Any) -> tuple[Any, Any]:
    from shapely.ops import nearest_points

    return nearest_points(a, b)


def _gap(free: Any, a: Any, b: Any) -> DroppedFeature:
    """The passage between two things, at the middle of their nearest points ``a`` and ``b``; its width is that of
    the largest disc of the free space (before inflation) centred there."""
    import shapely

    middle = ((a.x + b.x) / 2, (a.y + b.y) / 2)
    return DroppedFeature("passage_closed", middle, 2 * free.boundary.distance(shapely.Point(middle)))
