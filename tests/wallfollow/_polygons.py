"""Hypothesis strategies for the wall-following model: simple polygons in general position (integer vertices)."""

from __future__ import annotations

import math

from hypothesis import assume
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.wallfollow import cuts


@st.composite
def general_position_polygons(draw, min_vertices: int = 3, max_vertices: int = 14, scale: int = 1000) -> Environment:
    """Star-shaped simple polygons (usually with reflex vertices) whose vertices and cuts are in general position.

    Radii vary by a factor of up to 4 so that reflex vertices and chains of them are common; polygons that
    break general position (rare at this scale) are rejected.
    """
    n = draw(st.integers(min_vertices, max_vertices))
    jitter = draw(st.lists(st.floats(-0.4, 0.4), min_size=n, max_size=n))
    radii = draw(st.lists(st.integers(scale // 4, scale), min_size=n, max_size=n))
    ring = [(round(r * math.cos(2 * math.pi * (k + j) / n)), round(r * math.sin(2 * math.pi * (k + j) / n)))
            for k, (r, j) in enumerate(zip(radii, jitter))]
    try:
        env = Environment.from_coords(ring)
        cuts(env)
    except InvalidEnvironment:
        assume(False)
        raise  # unreachable
    return env


def comb(teeth: int, seed: int = 0) -> Environment:
    """A room whose ceiling has ``teeth`` spikes hanging down: both cuts of every spike's tip (a reflex vertex)
    land on the floor, so one edge receives 2·teeth cut end points (n = 2·teeth + 5 vertices). Heights are
    perturbed (seeded) to keep general position; a perturbation that breaks it is replaced by the next seed's."""
    import random

    for attempt in range(100):
        rng = random.Random(seed * 1000 + attempt)
        width = 10 * teeth + 10
        ring = [(0, 0), (width, 0), (width, 1000 + rng.randint(0, 50))]
        for i in reversed(range(teeth)):
            x = 10 * i + 5
            ring += [(x + 8, 1000 + rng.randint(0, 50)), (x + 4, 300 + rng.randint(0, 200))]
        ring += [(5, 1000 + rng.randint(0, 50)), (0, 1000 + rng.randint(0, 50))]
        try:
            env = Environment.from_coords(ring)
            cuts(env)
            return env
        except InvalidEnvironment:
            continue
    raise AssertionError("no comb in general position found")
