"""Hypothesis strategies for the wall-following model: simple polygons in general position (integer vertices)."""

from __future__ import annotations

import math

from hypothesis import assume
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.generators import spiked_comb
from solverplan.wallfollow import cuts


def in_general_position(ring) -> Environment | None:
    """``ring`` as an environment when the wall-following model takes it (a simple polygon, no three vertices
    collinear, no two cut end points at one point); None when it does not."""
    try:
        env = Environment.from_coords(ring)
        cuts(env)
    except InvalidEnvironment:
        return None
    return env


@st.composite
def general_position_polygons(draw, min_vertices: int = 3, max_vertices: int = 14, scale: int = 1000,
                              spiky: bool = False) -> Environment:
    """Star-shaped simple polygons (usually with reflex vertices) whose vertices and cuts are in general position.

    Radii vary by a factor of up to 4 so that reflex vertices and chains of them are common (``spiky``: every
    other vertex pulled in further); polygons that break general position (rare at this scale) are rejected.
    """
    n = draw(st.integers(min_vertices, max_vertices))
    jitter = draw(st.lists(st.floats(-0.4, 0.4), min_size=n, max_size=n))
    radii = draw(st.lists(st.integers(scale // 4, scale), min_size=n, max_size=n))
    if spiky:  # every other vertex pulled in: many reflex vertices that see each other, so bitangents are common
        radii = [r if k % 2 == 0 else r * 2 // 5 for k, r in enumerate(radii)]
    ring = [(round(r * math.cos(2 * math.pi * (k + j) / n)), round(r * math.sin(2 * math.pi * (k + j) / n)))
            for k, (r, j) in enumerate(zip(radii, jitter))]
    env = in_general_position(ring)
    assume(env is not None)
    return env


comb = spiked_comb  # the tests' name for the studies' generator


def bent_arms(seed: int) -> Environment:
    """Two to four corridors bent at random angles round a hub (seeded; the family of the ``three_arms`` model):
    reflex chains that see each other, bitangents that are right-handed from neither end. A seed whose polygon
    breaks general position or is not simple is replaced by the next attempt."""
    import random

    from shapely.geometry import LineString
    from shapely.ops import unary_union

    for attempt in range(100):
        rng = random.Random(seed * 1000 + attempt)
        lines = []
        arms = rng.randint(2, 4)
        for a in range(arms):
            out = 2 * math.pi * a / arms + rng.uniform(-0.3, 0.3)
            bend = out + rng.uniform(-2.2, 2.2)
            first, second = rng.uniform(4, 10), rng.uniform(3, 10)
            knee = (first * math.cos(out), first * math.sin(out))
            foot = (knee[0] + second * math.cos(bend), knee[1] + second * math.sin(bend))
            lines.append(LineString([(0, 0), knee, foot]))
        width = rng.uniform(0.8, 1.6)
        shape = unary_union(lines).buffer(width, cap_style=2, join_style=2, mitre_limit=5).simplify(0.01)
        if shape.geom_type != "Polygon" or len(shape.interiors):
            continue
        ring = [(round(x * 10) + rng.randint(-2, 2), round(y * 10) + rng.randint(-2, 2))
                for x, y in list(shape.exterior.coords)[:-1]]
        env = in_general_position(ring)
        if env is not None:
            return env
    raise AssertionError("no bent arms in general position found")
