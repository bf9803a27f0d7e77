"""Corridors for the reflection payoff tests and study (issue #26): square corners, 45° cut corners, zigzags,
with varying widths. Exact rational vertices (a polyline buffered by shapely, rounded to 1/1000)."""

from __future__ import annotations

from fractions import Fraction

from solverplan.environment import Environment

KINDS = ("square", "cut", "zigzag")


def corridor(kind: str, turns: int = 3, width: float = 0.5, leg: float = 3.0, seed: int = 0) -> tuple[Environment, tuple, tuple]:
    """A corridor of ``turns`` turns and its start and goal points (length units).

    ``square``: legs east and north alternately, square (mitred) corners; ``cut``: the same with the corners
    cut at 45° (bevelled); ``zigzag``: legs alternately north-east and south-east (diagonal, mitred). ``seed``
    varies the leg lengths (between 0.75 and 1.25 of ``leg``).
    """
    import numpy as np
    import shapely

    rng = np.random.default_rng(seed)
    points = [(0.0, 0.0)]
    for k in range(turns + 1):
        length = leg * (0.75 + 0.5 * rng.random())
        x, y = points[-1]
        if kind == "zigzag":
            step = (length / 2 ** 0.5, (1 if k % 2 == 0 else -1) * length / 2 ** 0.5)
        else:
            step = (length, 0.0) if k % 2 == 0 else (0.0, length)
        points.append((x + step[0], y + step[1]))
    line = shapely.LineString(points)
    join = "bevel" if kind == "cut" else "mitre"
    shape = line.buffer(width / 2, cap_style="flat", join_style=join, mitre_limit=10.0)
    ring = [(Fraction(round(x * 1000), 1000), Fraction(round(y * 1000), 1000)) for x, y in shape.exterior.coords[:-1]]
    env = Environment.from_coords(ring, name=f"corridor({kind}, turns={turns}, width={width}, seed={seed})")
    a, b = np.array(points[0]), np.array(points[1])
    start = a + 0.3 * (b - a) / np.linalg.norm(b - a)
    c, d = np.array(points[-1]), np.array(points[-2])
    goal = c + 0.3 * (d - c) / np.linalg.norm(d - c)
    as_text = lambda p: (f"{p[0]:.3f}", f"{p[1]:.3f}")  # noqa: E731
    return env, as_text(start), as_text(goal)
