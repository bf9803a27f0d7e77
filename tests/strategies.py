"""Hypothesis strategies for environments: valid, exact (integer coordinates), shrinkable.

Integer coordinates make exact ties (collinear vertices, rays through vertices) reachable,
which is where geometry code breaks.
"""

from __future__ import annotations

import math

from hypothesis import assume
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment


def _star_ring(draw, n: int, centre: tuple[int, int], r_min: int, r_max: int) -> list[tuple[int, int]]:
    """Vertices at increasing angles around ``centre`` with random radii, rounded to integers."""
    jitter = draw(st.lists(st.floats(-0.35, 0.35), min_size=n, max_size=n))
    radii = draw(st.lists(st.integers(r_min, r_max), min_size=n, max_size=n))
    ring = []
    for k in range(n):
        angle = 2 * math.pi * (k + jitter[k]) / n
        ring.append((centre[0] + round(radii[k] * math.cos(angle)), centre[1] + round(radii[k] * math.sin(angle))))
    return ring


@st.composite
def simple_polygons(draw, min_vertices: int = 3, max_vertices: int = 16, scale: int = 40) -> Environment:
    """Star-shaped simple polygons (often non-convex) with integer vertices, no holes."""
    n = draw(st.integers(min_vertices, max_vertices))
    ring = _star_ring(draw, n, (0, 0), scale // 3, scale)
    try:
        return Environment.from_coords(ring)
    except InvalidEnvironment:
        assume(False)
        raise  # unreachable


@st.composite
def polygons_with_holes(draw, max_vertices: int = 14, max_holes: int = 3, scale: int = 60) -> Environment:
    """Star-shaped outer ring (radii ≥ scale/2) with up to ``max_holes`` small holes near the centre."""
    n = draw(st.integers(3, max_vertices))
    outer = _star_ring(draw, n, (0, 0), scale // 2, scale)
    holes = []
    for _ in range(draw(st.integers(0, max_holes))):
        cx = draw(st.integers(-scale // 5, scale // 5))
        cy = draw(st.integers(-scale // 5, scale // 5))
        m = draw(st.integers(3, 6))
        holes.append(_star_ring(draw, m, (cx, cy), 1, max(2, scale // 12)))
    try:
        return Environment.from_coords(outer, holes)
    except InvalidEnvironment:
        assume(False)
        raise  # unreachable


@st.composite
def convex_polygons(draw, max_coord: int = 60) -> Environment:
    """Strictly convex polygons with integer vertices (hull of random points, collinear points dropped)."""
    coord = st.integers(-max_coord, max_coord)
    points = draw(st.lists(st.tuples(coord, coord), min_size=3, max_size=25, unique=True))
    hull = convex_hull(points)
    assume(len(hull) >= 3)
    return Environment.from_coords(hull)


def convex_hull(points: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Andrew's monotone chain on integers; strictly convex, CCW."""
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[int, int]] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[int, int]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]
