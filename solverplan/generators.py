"""Seeded generators of valid environments: random star polygons (with holes) and the paper's worst case.

Every generator returns a valid :class:`~solverplan.environment.Environment`: candidates are built
in floating point, rounded to **exact decimals** (``decimals`` places, so the exact kernel reads
the numbers a user would type), validated by :meth:`Environment.from_coords`, and resampled when
invalid. After ``max_attempts`` failures a generator raises
:class:`~solverplan.errors.InvalidEnvironment` naming the parameters (they make valid polygons
too rare), never a half-valid polygon.

Random generators take ``seed`` (an ``int``, a :class:`numpy.random.Generator` or ``None``); the
same integer seed gives the same environment, and the environment's ``name`` records the
parameters and the seed.

>>> env = star_polygon(8, 0.3, 0.2, seed=3)
>>> env.n_vertices, env == star_polygon(8, 0.3, 0.2, seed=3)
(8, True)
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from fractions import Fraction
from typing import Callable, Literal

import numpy as np

from solverplan._io import cannot_write
from solverplan.environment import Environment, format_environment, save_environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.exact import ExactPoint, orient
from solverplan.limits import MAX_COUNT, MAX_GENERATED_VERTICES, MAX_ROOMS, quote

__all__ = [
    "star_polygon",
    "star_polygon_with_holes",
    "rooms_and_corridors",
    "rectilinear_floor_plan",
    "rectilinear_polygon",
    "worst_case_polygon",
    "spiked_comb",
    "GENERATORS",
    "generate",
    "GeneratedEnvironment",
]

Seed = int | np.random.Generator | None

HoleKind = Literal["convex", "star"]


# ---------------------------------------------------------------------- argument checks
_MAXIMA = {
    **dict.fromkeys(("n", "hole_vertices", "width", "height", "teeth", "wall", "door", "min_room", "max_size", "grid"),
                    MAX_GENERATED_VERTICES),
    **dict.fromkeys(("n_holes", "n_rooms", "loops", "pillars", "n_cells"), MAX_ROOMS),
    "t": 64,  # worst_case_polygon(t) has 4t + 4 vertices whose coordinates grow like 2^t
    "decimals": 30,
    "max_attempts": MAX_COUNT,
}
"""The largest value of each integer parameter, whoever asks (``solverplan generate`` and studies alike):
the documented limits of solverplan.limits, so that a study cell cannot ask for more than ``generate`` may."""


def _check_int(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"expected an integer {name}, got {name}={quote(value)} (type={type(value).__name__})")
    if value < minimum:
        raise InputError(f"expected {name} >= {minimum}, got {name}={quote(value)}")
    maximum = _MAXIMA.get(name)
    if maximum is not None and value > maximum:
        raise InputError(f"expected {name} <= {maximum:,}, got {name}={quote(value)}")
    return int(value)


def _check_fraction_of_one(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"expected a number {name} in [0, 1], got {name}={value!r}")
    if not 0 <= value <= 1:
        raise InputError(f"expected {name} in [0, 1], got {name}={value!r}")
    return float(value)


def _check_positive(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"expected a positive number {name}, got {name}={value!r}")
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"expected a finite {name} > 0, got {name}={value!r}")
    return float(value)


def _seed_text(seed: Seed) -> str:
    return "rng" if isinstance(seed, np.random.Generator) else repr(seed)


# ---------------------------------------------------------------------- exact rounding
def _to_decimals(xy: np.ndarray, decimals: int) -> list[ExactPoint]:
    """Round float points to exact decimals with ``decimals`` places (Fractions, no binary error)."""
    scale = 10**decimals
    return [(Fraction(round(float(x) * scale), scale), Fraction(round(float(y) * scale), scale)) for x, y in xy]


def _is_strictly_convex(ring: list[ExactPoint]) -> bool:
    n = len(ring)
    turns = {orient(ring[i - 1], ring[i], ring[(i + 1) % n]) for i in range(n)}
    return turns == {1} or turns == {-1}


# ---------------------------------------------------------------------- star polygons
def _first_valid(candidate: Callable[[int], Environment], max_attempts: int, failure: str, hint: str = "") -> Environment:
    """The first environment ``candidate(attempt)`` returns in ``max_attempts`` attempts (0, 1, ...); a rejected
    candidate raises :class:`InvalidEnvironment` saying why. After the last attempt: InvalidEnvironment with
    ``failure``, the number of attempts, the last reason and ``hint``. A bad ``max_attempts`` is an InputError."""
    max_attempts = _check_int("max_attempts", max_attempts, 1)
    problem = "no candidate tried"
    for attempt in range(max_attempts):
        try:
            return candidate(attempt)
        except InvalidEnvironment as exc:
            problem = str(exc)
    raise InvalidEnvironment(f"{failure} in {max_attempts} attempts (last: {problem}){hint}")


def _star_points(
    rng: np.random.Generator, n: int, irregularity: float, spikiness: float, radius: float
) -> np.ndarray:
    """Float vertices (n, 2) of a random star polygon around the origin, at increasing angles.

    Angle steps are uniform in [2π/n·(1 − irregularity), 2π/n·(1 + irregularity)] — the
    irregularity is *scaled* by the mean step, so steps are never negative —
    then normalised to sum to 2π; radii are Gaussian(radius, spikiness·radius) clipped to
    [0, 2·radius].
    """
    mean_step = 2 * math.pi / n
    steps = rng.uniform(mean_step * (1 - irregularity), mean_step * (1 + irregularity), size=n)
    steps *= 2 * math.pi / steps.sum()
    start = rng.uniform(0, 2 * math.pi)
    angles = start + np.concatenate([[0.0], np.cumsum(steps[:-1])])
    radii = np.clip(rng.normal(radius, spikiness * radius, size=n), 0, 2 * radius)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


def star_polygon(
    n: int,
    irregularity: float,
    spikiness: float,
    *,
    radius: float = 1.0,
    seed: Seed,
    decimals: int = 6,
    max_attempts: int = 100,
) -> Environment:
    """A random star-shaped polygon with ``n`` vertices around the origin (the paper's §7.3 family).

    The k-th vertex is at angle a_k and distance r_k from the origin, with a_0 uniform in [0, 2π),
    steps a_{k+1} − a_k uniform in [2π/n·(1 − irregularity), 2π/n·(1 + irregularity)] normalised to
    sum to 2π, and r_k ~ Gaussian(radius, spikiness·radius) clipped to [0, 2·radius]. Coordinates
    are rounded to exact decimals; an invalid candidate (a rounding collision, or two radii clipped
    to 0 putting two vertices at the centre) is resampled. Clipped radii are rare at the paper's
    parameters (n = 20, spikiness ≤ 0.5: at most about 7 % of candidates are resampled) but certain for
    large n with a large spikiness (n = 1000, spikiness = 0.5), which then raises: lower the
    spikiness (0.2 or less) for polygons with thousands of vertices.

    Parameters
    ----------
    n
        Number of vertices (≥ 3); the result has exactly ``n`` vertices (collinear ones are kept).
    irregularity
        In [0, 1]: spread of the angle steps, as a fraction of the mean step 2π/n
        (0 gives equal steps). Scaled (unscaled, up to a third of the polygons self-intersect at the paper's parameters).
    spikiness
        In [0, 1]: standard deviation of the radii as a fraction of ``radius`` (0 gives a
        polygon inscribed in a circle).
    radius
        Mean distance of the vertices from the origin (length units of the environment).
    seed
        ``int``, :class:`numpy.random.Generator` or ``None`` (fresh entropy: not reproducible).
    decimals
        Number of decimal places of the exact coordinates.
    max_attempts
        Candidates tried before giving up.

    Returns
    -------
    Environment
        Valid, outer ring counter-clockwise, no holes; ``name`` records the parameters and seed.

    Raises
    ------
    InputError
        A parameter is out of range (named with its value).
    InvalidEnvironment
        No valid candidate in ``max_attempts`` tries.

    Examples
    --------
    >>> env = star_polygon(20, 0.3, 0.3, radius=10, seed=7)
    >>> env.n_vertices, len(env.holes)
    (20, 0)
    >>> env.name
    'star_polygon(n=20, irregularity=0.3, spikiness=0.3, radius=10, seed=7)'
    >>> all((x * 10**6).denominator == 1 for point in env.outer for x in point)  # exact 6-place decimals
    True
    """
    n = _check_int("n", n, 3)
    irregularity = _check_fraction_of_one("irregularity", irregularity)
    spikiness = _check_fraction_of_one("spikiness", spikiness)
    radius_f = _check_positive("radius", radius)
    decimals = _check_int("decimals", decimals, 0)
    rng = np.random.default_rng(seed)
    name = (
        f"star_polygon(n={n}, irregularity={irregularity:g}, spikiness={spikiness:g}, "
        f"radius={radius_f:g}, seed={_seed_text(seed)})"
    )

    def candidate(_: int) -> Environment:
        env = Environment.from_coords(_to_decimals(_star_points(rng, n, irregularity, spikiness, radius_f), decimals),
                                      name=name)
        if env.n_vertices != n:  # a rounded last vertex equal to the first closed the ring early
            raise InvalidEnvironment("the last vertex rounded onto the first")
        return env

    return _first_valid(candidate, max_attempts, f"no valid star polygon with n={n}, irregularity={irregularity:g}, "
                        f"spikiness={spikiness:g}, radius={radius_f:g}, decimals={decimals}")


def _hole_ring(
    rng: np.random.Generator, kind: HoleKind, vertices: int, hole_radius: float, decimals: int, centre: np.ndarray
) -> list[ExactPoint] | None:
    """One hole within distance ``hole_radius`` of ``centre``, or None if rounding spoilt it."""
    if kind == "convex":
        # a jittered regular polygon inscribed in the circle: in convex position before rounding
        step = 2 * math.pi / vertices
        angles = rng.uniform(0, 2 * math.pi) + step * (np.arange(vertices) + rng.uniform(-0.3, 0.3, size=vertices))
        xy = hole_radius * np.column_stack([np.cos(angles), np.sin(angles)])
    else:
        xy = _star_points(rng, vertices, 0.5, 0.3, hole_radius / 2)  # radii ≤ 2 · (hole_radius / 2)
    ring = _to_decimals(xy + centre, decimals)
    if len(set(ring)) != vertices:
        return None
    if kind == "convex" and not _is_strictly_convex(ring):
        return None
    return ring


def _hole_centres(
    rng: np.random.Generator, outer_xy: np.ndarray, count: int, hole_radius: float, radius: float
) -> np.ndarray | None:
    """Centres of ``count`` discs of radius 1.25·hole_radius inside the outer ring, pairwise apart."""
    import shapely

    outer = shapely.Polygon(outer_xy)
    boundary = outer.exterior
    shapely.prepare(outer)
    shapely.prepare(boundary)
    clearance = 1.25 * hole_radius
    accepted: list[np.ndarray] = []
    batch = max(64, 8 * count)
    for _ in range(50):
        r = 2 * radius * np.sqrt(rng.uniform(0, 1, size=batch))
        a = rng.uniform(0, 2 * math.pi, size=batch)
        cand = np.column_stack([r * np.cos(a), r * np.sin(a)])
        ok = shapely.contains_xy(outer, cand[:, 0], cand[:, 1])
        cand = cand[ok]
        if len(cand) == 0:
            continue
        cand = cand[shapely.distance(boundary, shapely.points(cand)) > clearance]
        for c in cand:
            if accepted:
                d = np.hypot(*(np.asarray(accepted) - c).T)
                if d.min() <= 2 * clearance:
                    continue
            accepted.append(c)
            if len(accepted) == count:
                return np.asarray(accepted)
    return None


def star_polygon_with_holes(
    n: int,
    n_holes: int,
    *,
    seed: Seed,
    irregularity: float = 0.2,
    spikiness: float = 0.15,
    radius: float = 1.0,
    hole_vertices: int = 6,
    hole_kind: HoleKind = "convex",
    hole_radius: float | None = None,
    decimals: int = 6,
    max_attempts: int = 20,
) -> Environment:
    """A random star polygon with ``n`` outer vertices and ``n_holes`` small holes strictly inside.

    The outer ring is drawn as in :func:`star_polygon`. Hole centres are sampled uniformly and kept
    when a disc of radius 1.25·``hole_radius`` around them lies inside the outer ring and misses
    the other holes' discs; each hole lies within ``hole_radius`` of its centre, so holes never
    touch each other or the outer ring. Holes are jittered regular polygons (``"convex"``, checked
    strictly convex after rounding) or small star polygons (``"star"``). The environment has
    ``n + n_holes · hole_vertices`` edges: pick the sizes for ray-casting tests and benchmarks
    from 10 to 10,000 edges. Validation time grows with holes × edges (each hole is located
    exactly against every ring), so for large sizes prefer few holes with many vertices:
    ``star_polygon_with_holes(9000, 10, hole_vertices=100, seed=0)`` (10,000 edges) takes about
    2 s, while 1,000 holes of 6 vertices take minutes.

    Parameters
    ----------
    n
        Vertices of the outer ring (≥ 3).
    n_holes
        Number of holes (≥ 0).
    seed, irregularity, spikiness, radius, decimals
        As in :func:`star_polygon` (the last four: of the outer ring).
    hole_vertices
        Vertices per hole (≥ 3).
    hole_kind
        ``"convex"`` or ``"star"``.
    hole_radius
        Size of each hole (distance of its vertices from its centre at most); default
        ``0.15 · radius / sqrt(n_holes)`` so the holes fit comfortably.
    max_attempts
        Outer rings (with their holes) tried before giving up.

    Returns
    -------
    Environment
        As :func:`star_polygon`'s, with the holes clockwise.

    Raises
    ------
    InputError, InvalidEnvironment
        As :func:`star_polygon`; also InvalidEnvironment when the holes could not be placed (too many or too large).

    Examples
    --------
    >>> env = star_polygon_with_holes(12, 3, seed=0)
    >>> env.n_edges, len(env.holes), len(env.outer)
    (30, 3, 12)
    >>> all(len(env.ring(k)) == 6 for k in (1, 2, 3))
    True
    """
    n = _check_int("n", n, 3)
    n_holes = _check_int("n_holes", n_holes, 0)
    irregularity = _check_fraction_of_one("irregularity", irregularity)
    spikiness = _check_fraction_of_one("spikiness", spikiness)
    radius_f = _check_positive("radius", radius)
    hole_vertices = _check_int("hole_vertices", hole_vertices, 3)
    if hole_kind not in ("convex", "star"):
        raise InputError(f"expected hole_kind 'convex' or 'star', got hole_kind={hole_kind!r}")
    if hole_radius is None:
        hole_radius_f = 0.15 * radius_f / math.sqrt(max(n_holes, 1))
    else:
        hole_radius_f = _check_positive("hole_radius", hole_radius)
    decimals = _check_int("decimals", decimals, 0)
    rng = np.random.default_rng(seed)
    name = (
        f"star_polygon_with_holes(n={n}, n_holes={n_holes}, irregularity={irregularity:g}, "
        f"spikiness={spikiness:g}, radius={radius_f:g}, hole_vertices={hole_vertices}, "
        f"hole_kind={hole_kind!r}, hole_radius={hole_radius_f:.6g}, seed={_seed_text(seed)})"
    )

    def candidate(_: int) -> Environment:
        outer_xy = _star_points(rng, n, irregularity, spikiness, radius_f)
        outer = _to_decimals(outer_xy, decimals)
        centres = _hole_centres(rng, outer_xy, n_holes, hole_radius_f, radius_f) if n_holes else np.empty((0, 2))
        if centres is None:
            raise InvalidEnvironment(f"could not place {n_holes} holes of radius {hole_radius_f:.6g}")
        holes = []
        for centre in centres:
            for _ in range(20):
                ring = _hole_ring(rng, hole_kind, hole_vertices, hole_radius_f, decimals, centre)
                if ring is not None:
                    holes.append(ring)
                    break
            else:
                raise InvalidEnvironment(f"holes of radius {hole_radius_f:.6g} do not survive rounding to {decimals} decimals")
        env = Environment.from_coords(outer, holes, name=name)
        if env.n_edges != n + n_holes * hole_vertices:
            raise InvalidEnvironment("the last vertex of a ring rounded onto its first")
        return env

    return _first_valid(candidate, max_attempts, f"no valid star polygon with n={n} and n_holes={n_holes} "
                        f"(hole_radius={hole_radius_f:.6g}, radius={radius_f:g})", "; use fewer or smaller holes")


# ---------------------------------------------------------------------- the paper's worst case
_WORST_CASE_RADIUS = 10
_WORST_CASE_DECIMALS = 6


def spiked_comb(teeth: int, seed: int = 0, max_attempts: int = 100) -> Environment:
    """A room whose ceiling has ``teeth`` spikes hanging down, in general position for the wall-following robot.

    Both cuts of every spike's tip (a reflex vertex) land on the floor, so one edge receives 2·teeth cut end points
    (n = 2·teeth + 5 vertices): the case where Strategy 1's comparisons dominate. Integer vertices up to ~10⁶;
    heights are perturbed (seeded) to keep general position, and a perturbation that breaks it is replaced by the
    next attempt's.

    Examples
    --------
    >>> spiked_comb(3).n_vertices
    11
    """
    import random

    from solverplan.wallfollow.cut import cuts

    teeth = _check_int("teeth", teeth, 1)

    def candidate(attempt: int) -> Environment:
        rng = random.Random(seed * 1000 + attempt)
        # wide random ranges make collinear triples rare even for many teeth
        width = 10_000 * teeth + 10_000
        ring = [(0, 0), (width, 0), (width, 1_000_000 + rng.randint(0, 50_000))]
        for i in reversed(range(teeth)):
            x = 10_000 * i + 5_000
            ring += [(x + 8_000 + rng.randint(-500, 500), 1_000_000 + rng.randint(0, 50_000)),
                     (x + 4_000 + rng.randint(-500, 500), 300_000 + rng.randint(0, 200_000))]
        ring += [(5_000, 1_000_000 + rng.randint(0, 50_000)), (0, 1_000_000 + rng.randint(0, 50_000))]
        env = Environment.from_coords(ring, name=f"spiked_comb(teeth={teeth}, seed={seed})")
        cuts(env)
        return env

    return _first_valid(candidate, max_attempts, f"no spiked comb with {teeth} teeth in general position")


def worst_case_polygon(t: int) -> Environment:
    """The paper's worst case for Algorithm 1 (§4.0.1, Fig. 3): n = 4t + 2 vertices, r = 2t reflex.

    Construction (ours; the paper gives only the idea). Let ρ = 10, s = 90°/t, and put 2t + 1
    *slots* on the top arc at the angles 45° + j·s/2, j = 0 … 2t. Odd slots hold the t **reflex**
    vertices r_1 … r_t, on the circle of radius ρ (uniformly spaced, s apart); even slots hold
    the t + 1 **convex** spike tips c_0 … c_t, on the circle of radius S·ρ with
    S = 1.25·cos(A/2)/cos 45°, A = (t − 1)·s the arc spanned by the reflex vertices. The top
    chain c_0, r_1, c_1, …, r_t, c_t is mirrored in the x axis (y ↦ −y, exactly), and the two
    halves are joined by the vertical edges c_t → c_t′ (left) and c_0′ → c_0 (right): 2t + 1
    vertices per half, none on the axis of symmetry.

    Why it works. With δ = s/2, the edge from r_k to its neighbour c_k makes the angle
    β = atan((S cos δ − 1)/(S sin δ)) with the circle's tangent at r_k, and the choice of S gives
    S·(cos δ − tan(A/2)·sin δ) = 1.25 > 1, i.e. 0 < A/2 < β < 90°:

    - S cos δ > 1: each r_k lies strictly inside the chord c_{k−1}c_k (a **reflex** turn), and
      both its edges leave the disc of radius ρ outwards, so no spike edge meets the convex hull
      of the reflex vertices except at its own vertex; the vertical edges, at |x| = S·ρ·cos 45°,
      lie beyond every reflex vertex (|x| ≤ ρ·cos(45° + δ)). The 2t reflex vertices lie on one
      circle (the mirror of the top arc is on the same circle), so every chord between two of
      them runs through the interior: **all reflex vertices see each other**.
    - A/2 < β: the ray from r_j through another top reflex vertex r_k leaves r_k at an angle
      of at most A/2 from the tangent, so it continues *inside* the spike next to r_k and
      Algorithm 1 inserts a new vertex there: each reflex vertex gets **at least t − 1 new
      vertices** in its partial local sequence, as the paper requires.
    - The line through a spike edge r_k → c_k continues beyond c_k away from the disc of
      radius S·ρ, which holds the whole polygon, so it meets no other edge there; no line
      through an edge passes through a third vertex.

    Coordinates are these points rounded to 6 decimals (exact decimals; the margins above are
    orders of magnitude larger than 10⁻⁶); the tests re-check validity, symmetry, mutual
    visibility and the t − 1 continuing rays in exact arithmetic for t = 1 … 20.

    Parameters
    ----------
    t
        Positive integer: the polygon has 4t + 2 vertices, 2t of them reflex.

    Returns
    -------
    Environment
        Named ``worst_case_t{t}``. Vertex 0 is c_0 (top right), vertices 1, 3, …, 2t − 1 are the
        top reflex vertices r_1 … r_t, vertex 2t is c_t, vertex 2t + 1 its mirror image c_t′, and
        the bottom reflex vertices are 2t + 2, 2t + 4, …, 4t (mirror images of r_t … r_1).

    Examples
    --------
    >>> env = worst_case_polygon(4)
    >>> env.n_vertices, len(env.reflex_vertices)
    (18, 8)
    >>> env.reflex_vertices
    (1, 3, 5, 7, 10, 12, 14, 16)
    >>> sorted(env.outer) == sorted((x, -y) for x, y in env.outer)  # symmetric about y = 0
    True
    """
    t = _check_int("t", t, 1)
    step = math.pi / (2 * t)  # s = 90°/t
    half_arc = (t - 1) * step / 2  # A/2
    spike = 1.25 * math.cos(half_arc) / math.cos(math.pi / 4)
    rho = _WORST_CASE_RADIUS
    scale = 10**_WORST_CASE_DECIMALS

    def slot(j: int) -> ExactPoint:
        r = rho if j % 2 else spike * rho
        angle = math.pi / 4 + j * step / 2
        return (Fraction(round(r * math.cos(angle) * scale), scale), Fraction(round(r * math.sin(angle) * scale), scale))

    top = [slot(j) for j in range(2 * t + 1)]  # c_0, r_1, c_1, …, r_t, c_t
    bottom = [(x, -y) for x, y in reversed(top)]  # c_t′, r_t′, …, r_1′, c_0′
    return Environment.from_coords(top + bottom, name=f"worst_case_t{t}")


# ---------------------------------------------------------------------- shapes from shapely unions
def _rings_of(shape, decimals: int | None) -> tuple[list[ExactPoint], list[list[ExactPoint]]] | None:
    """Exact rings (outer, holes) of a shapely Polygon; ``None`` if it is not one polygon.

    Collinear points left by the union are dropped (``simplify(0)``); coordinates are rounded to
    ``decimals`` places (``None``: the floats are integers already) and repeated points merged.
    """
    import shapely

    if shape.geom_type != "Polygon" or shape.is_empty:
        return None
    shape = shapely.simplify(shape, 0.0)
    if shape.geom_type != "Polygon":
        return None

    def ring(coords) -> list[ExactPoint]:
        xy = np.asarray(coords)[:-1]
        if decimals is None:
            points = [(Fraction(round(float(x))), Fraction(round(float(y)))) for x, y in xy]
        else:
            points = _to_decimals(xy, decimals)
        merged = [p for k, p in enumerate(points) if p != points[k - 1]] if len(points) > 1 else points
        return merged

    return ring(shape.exterior.coords), [ring(h.coords) for h in shape.interiors]


# ---------------------------------------------------------------------- rooms joined by corridors
def _grid_tree(rng: np.random.Generator, n_rooms: int, side: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """``n_rooms`` cells of a side × side grid grown at random from one cell, and the tree joining them.

    Returns the cells (in order of growth) and the tree's edges as pairs of cell indices.
    """
    cells = [(int(rng.integers(side)), int(rng.integers(side)))]
    index = {cells[0]: 0}
    edges: list[tuple[int, int]] = []
    while len(cells) < n_rooms:
        frontier = sorted(
            {
                (x + dx, y + dy)
                for x, y in cells
                for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= x + dx < side and 0 <= y + dy < side and (x + dx, y + dy) not in index
            }
        )
        new = frontier[int(rng.integers(len(frontier)))]
        neighbours = [index[(new[0] + dx, new[1] + dy)] for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
                      if (new[0] + dx, new[1] + dy) in index]
        edges.append((neighbours[int(rng.integers(len(neighbours)))], len(cells)))
        index[new] = len(cells)
        cells.append(new)
    return cells, edges


def rooms_and_corridors(
    n_rooms: int,
    *,
    seed: Seed,
    loops: int = 0,
    room_size: float = 4.0,
    spacing: float = 10.0,
    corridor_width: float = 1.0,
    room_vertices: tuple[int, int] = (4, 8),
    decimals: int = 3,
    max_attempts: int = 50,
) -> Environment:
    """Convex rooms on a jittered grid, joined by straight corridors (an office-like environment, §8.1).

    Rooms sit on ``n_rooms`` cells of a square grid (side ⌈√n_rooms⌉ + 1), grown at random from one
    cell; the corridors follow the spanning tree of that growth, plus ``loops`` extra corridors
    between adjacent rooms, each of which closes a loop and so encloses one **hole**. Room centres are
    jittered by up to ±10 % of ``spacing``; a room is the convex hull of k vertices (k uniform in
    ``room_vertices``) at jittered angles and radii 0.85…1.15 × ``room_size``/2 around its centre; a
    corridor is a ``corridor_width``-wide strip from centre to centre. The union is rounded to exact
    decimals, validated, and resampled if invalid.

    Parameters
    ----------
    n_rooms
        Number of rooms (≥ 1).
    seed
        ``int``, :class:`numpy.random.Generator` or ``None``.
    loops
        Extra corridors closing loops (each makes one hole), at most ``n_rooms // 2 - 1``; layouts
        with many loops are rare, so keep loops to about ``n_rooms / 4`` or raise ``max_attempts``.
    room_size
        Nominal room diameter (length units).
    spacing
        Distance between neighbouring grid cells; at least 1.6 × ``room_size`` so rooms never overlap.
    corridor_width
        Width of the corridors; less than ``room_size``/3 so a corridor enters a room through one wall.
    room_vertices
        Inclusive range (lo, hi) of the number of vertices of a room before the convex hull, 3 ≤ lo ≤ hi.
    decimals
        Decimal places of the exact coordinates.
    max_attempts
        Layouts tried before giving up.

    Raises
    ------
    InputError
        A parameter is out of range (named with its value).
    InvalidEnvironment
        No valid layout in ``max_attempts`` tries (e.g. more loops than the layouts allow).

    Examples
    --------
    >>> env = rooms_and_corridors(5, loops=1, seed=2)
    >>> len(env.holes), env == rooms_and_corridors(5, loops=1, seed=2)
    (1, True)
    >>> env.name
    'rooms_and_corridors(n_rooms=5, loops=1, room_size=4, spacing=10, corridor_width=1, seed=2)'
    """
    import shapely

    n_rooms = _check_int("n_rooms", n_rooms, 1)
    loops = _check_int("loops", loops, 0)
    room_size_f = _check_positive("room_size", room_size)
    spacing_f = _check_positive("spacing", spacing)
    width_f = _check_positive("corridor_width", corridor_width)
    decimals = _check_int("decimals", decimals, 0)
    if loops > max(n_rooms // 2 - 1, 0):
        raise InputError(f"expected loops <= n_rooms // 2 - 1 = {max(n_rooms // 2 - 1, 0)} (a loop needs a ring of rooms), "
                         f"got loops={loops!r}")
    if spacing_f < 1.6 * room_size_f:
        raise InputError(f"expected spacing >= 1.6 * room_size = {1.6 * room_size_f:g}, got spacing={spacing!r}")
    if width_f >= room_size_f / 3:
        raise InputError(f"expected corridor_width < room_size / 3 = {room_size_f / 3:g}, got corridor_width={corridor_width!r}")
    try:
        k_lo, k_hi = (int(k) for k in room_vertices)
    except (TypeError, ValueError):
        raise InputError(f"expected room_vertices as a pair (lo, hi), got room_vertices={room_vertices!r}") from None
    if not 3 <= k_lo <= k_hi:
        raise InputError(f"expected 3 <= lo <= hi in room_vertices, got room_vertices={room_vertices!r}")
    rng = np.random.default_rng(seed)
    name = (
        f"rooms_and_corridors(n_rooms={n_rooms}, loops={loops}, room_size={room_size_f:g}, spacing={spacing_f:g}, "
        f"corridor_width={width_f:g}, seed={_seed_text(seed)})"
    )
    side = math.isqrt(n_rooms - 1) + 2

    def candidate(_: int) -> Environment:
        cells, tree = _grid_tree(rng, n_rooms, side)
        where = {cell: k for k, cell in enumerate(cells)}
        spare = sorted(
            {(min(a, b), max(a, b)) for a, cell in enumerate(cells) for b in
             (where.get((cell[0] + 1, cell[1])), where.get((cell[0], cell[1] + 1))) if b is not None}
            - {(min(a, b), max(a, b)) for a, b in tree}
        )
        if len(spare) < loops:
            raise InvalidEnvironment(f"only {len(spare)} room pairs left to close loops, {loops} asked")
        extra = [spare[int(k)] for k in rng.choice(len(spare), size=loops, replace=False)] if loops else []
        centres = np.asarray(cells, dtype=float) * spacing_f + rng.uniform(-0.1, 0.1, size=(n_rooms, 2)) * spacing_f
        pieces = []
        for c in centres:
            k = int(rng.integers(k_lo, k_hi + 1))
            angles = rng.uniform(0, 2 * math.pi) + (2 * math.pi / k) * (np.arange(k) + rng.uniform(-0.2, 0.2, size=k))
            radii = room_size_f / 2 * rng.uniform(0.85, 1.15, size=k)
            pts = c + np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
            pieces.append(shapely.MultiPoint(pts).convex_hull)
        for a, b in [*tree, *extra]:
            pieces.append(shapely.LineString([centres[a], centres[b]]).buffer(width_f / 2, cap_style="flat"))
        rings = _rings_of(shapely.union_all(pieces), decimals)
        if rings is None:
            raise InvalidEnvironment("the rooms and corridors do not form one polygon")
        env = Environment.from_coords(*rings, name=name)
        if len(env.holes) != loops:
            raise InvalidEnvironment(f"{len(env.holes)} holes instead of {loops}")
        return env

    return _first_valid(candidate, max_attempts, f"no valid rooms-and-corridors layout with n_rooms={n_rooms}, loops={loops}")


# ---------------------------------------------------------------------- rectilinear floor plans
@dataclass
class _Room:
    x0: int
    y0: int
    x1: int
    y1: int
    doors: dict[str, list[tuple[int, int]]]  # per side ("left", "right", "bottom", "top"): door spans along it

    @property
    def area(self) -> int:
        return (self.x1 - self.x0) * (self.y1 - self.y0)


def _door_free(doors: list[tuple[int, int]], lo: int, hi: int) -> bool:
    return all(b <= lo or a >= hi for a, b in doors)


def _clip_doors(doors: list[tuple[int, int]], lo: int, hi: int) -> list[tuple[int, int]]:
    return [(a, b) for a, b in doors if a < hi and b > lo]


def _split_positions(room: _Room, vertical: bool, wall: int, min_room: int) -> list[int]:
    """Where a wall ``wall`` thick may go (its low coordinate) so both parts keep ``min_room`` and the
    wall's ends meet solid wall (one unit clear of any door in the two sides it ends on)."""
    if vertical:
        lo, hi, ends = room.x0 + min_room, room.x1 - min_room - wall, (room.doors["bottom"], room.doors["top"])
    else:
        lo, hi, ends = room.y0 + min_room, room.y1 - min_room - wall, (room.doors["left"], room.doors["right"])
    return [p for p in range(lo, hi + 1) if all(_door_free(d, p - 1, p + wall + 1) for d in ends)]


def rectilinear_floor_plan(
    n_rooms: int,
    *,
    seed: Seed,
    width: int | None = None,
    height: int | None = None,
    wall: int = 1,
    door: int = 2,
    min_room: int = 4,
    pillars: int = 0,
    max_attempts: int = 50,
) -> Environment:
    """A rectangular building cut into ``n_rooms`` rooms by walls with one door each (the setting of Çağırıcı, Bahoo and LaValle, "Bouncing robots in rectilinear polygons").

    A width × height rectangle is split recursively (binary space partition): the room to split is
    drawn with probability proportional to its area, the cut runs across its longer side when it can
    (else across the other), at an integer position leaving both parts at least ``min_room`` wide and
    meeting solid wall at both ends; the cut is a wall ``wall`` thick with one door ``door`` wide at
    an integer position at least one unit from its ends. The free space is the rectangle minus the
    walls: a rectilinear polygon with **integer** coordinates whose notches are the walls (walls meet
    the outer wall or other walls; none floats). ``pillars`` unit-square pillars, each in its own room
    at least one unit from its walls, are holes. Valid by construction; validated anyway.

    Parameters
    ----------
    n_rooms
        Number of rooms (≥ 1).
    seed
        ``int``, :class:`numpy.random.Generator` or ``None``.
    width, height
        Building size in units; default ⌈2.5·min_room·√n_rooms⌉ + wall for both.
    wall, door, min_room
        Wall thickness, door width and the smallest room width (positive integers,
        ``min_room >= door + 2``).
    pillars
        Number of square pillars (holes), at most ``n_rooms``.
    max_attempts
        Partitions tried before giving up (when the building is too small for ``n_rooms``).

    Examples
    --------
    >>> env = rectilinear_floor_plan(4, pillars=1, seed=1)
    >>> len(env.holes), all(x.denominator == 1 for p in env.exact_vertices for x in p)
    (1, True)
    >>> env.name
    'rectilinear_floor_plan(n_rooms=4, width=21, height=21, wall=1, door=2, min_room=4, pillars=1, seed=1)'
    """
    import shapely

    n_rooms = _check_int("n_rooms", n_rooms, 1)
    wall = _check_int("wall", wall, 1)
    door = _check_int("door", door, 1)
    min_room = _check_int("min_room", min_room, door + 2)
    pillars = _check_int("pillars", pillars, 0)
    if pillars > n_rooms:
        raise InputError(f"expected pillars <= n_rooms = {n_rooms}, got pillars={pillars!r}")
    default = math.ceil(2.5 * min_room * math.sqrt(n_rooms)) + wall
    width = default if width is None else _check_int("width", width, min_room)
    height = default if height is None else _check_int("height", height, min_room)
    rng = np.random.default_rng(seed)
    name = (
        f"rectilinear_floor_plan(n_rooms={n_rooms}, width={width}, height={height}, wall={wall}, door={door}, "
        f"min_room={min_room}, pillars={pillars}, seed={_seed_text(seed)})"
    )

    def candidate(_: int) -> Environment:
        rooms = [_Room(0, 0, width, height, {"left": [], "right": [], "bottom": [], "top": []})]
        walls = []
        while len(rooms) < n_rooms:
            options = []
            for k, room in enumerate(rooms):
                for vertical in (True, False):
                    positions = _split_positions(room, vertical, wall, min_room)
                    if positions:
                        longer = (room.x1 - room.x0 >= room.y1 - room.y0) == vertical
                        options.append((k, vertical, positions, room.area * (3 if longer else 1)))
            if not options:
                break
            weights = np.array([w for *_, w in options], dtype=float)
            k, vertical, positions, _ = options[int(rng.choice(len(options), p=weights / weights.sum()))]
            room = rooms[k]
            p = positions[int(rng.integers(len(positions)))]
            if vertical:
                d = int(rng.integers(room.y0 + 1, room.y1 - door))  # door [d, d + door], ≥ 1 from the ends
                walls += [shapely.box(p, room.y0, p + wall, d), shapely.box(p, d + door, p + wall, room.y1)]
                low = _Room(room.x0, room.y0, p, room.y1, dict(room.doors, right=[(d, d + door)],
                            bottom=_clip_doors(room.doors["bottom"], room.x0, p), top=_clip_doors(room.doors["top"], room.x0, p)))
                high = _Room(p + wall, room.y0, room.x1, room.y1, dict(room.doors, left=[(d, d + door)],
                             bottom=_clip_doors(room.doors["bottom"], p + wall, room.x1), top=_clip_doors(room.doors["top"], p + wall, room.x1)))
            else:
                d = int(rng.integers(room.x0 + 1, room.x1 - door))
                walls += [shapely.box(room.x0, p, d, p + wall), shapely.box(d + door, p, room.x1, p + wall)]
                low = _Room(room.x0, room.y0, room.x1, p, dict(room.doors, top=[(d, d + door)],
                            left=_clip_doors(room.doors["left"], room.y0, p), right=_clip_doors(room.doors["right"], room.y0, p)))
                high = _Room(room.x0, p + wall, room.x1, room.y1, dict(room.doors, bottom=[(d, d + door)],
                             left=_clip_doors(room.doors["left"], p + wall, room.y1), right=_clip_doors(room.doors["right"], p + wall, room.y1)))
            rooms[k:k + 1] = [low, high]
        if len(rooms) < n_rooms:
            raise InvalidEnvironment(f"a {width} x {height} building holds only {len(rooms)} rooms of width >= {min_room}")
        holes = []
        for k in sorted(rng.choice(len(rooms), size=pillars, replace=False).tolist()) if pillars else []:
            room = rooms[k]
            x = int(rng.integers(room.x0 + 1, room.x1 - 1))
            y = int(rng.integers(room.y0 + 1, room.y1 - 1))
            holes.append([(x, y), (x, y + 1), (x + 1, y + 1), (x + 1, y)])
        free = shapely.box(0, 0, width, height).difference(shapely.union_all(walls)) if walls else shapely.box(0, 0, width, height)
        rings = _rings_of(free, None)
        if rings is None:
            raise InvalidEnvironment("the walls cut the building apart")
        return Environment.from_coords(rings[0], holes, name=name)

    return _first_valid(candidate, max_attempts, f"no rectilinear floor plan with n_rooms={n_rooms} in a {width} x {height} "
                        "building", "; use a larger building or a smaller min_room")


# ---------------------------------------------------------------------- random rectilinear polygons
def _pinches(occupied: np.ndarray, i: int, j: int) -> bool:
    """Would occupying cell (i, j) make it touch an occupied cell at a corner only (a pinched boundary)?"""
    for di in (-1, 1):
        for dj in (-1, 1):
            if occupied[i + di, j + dj] and not occupied[i + di, j] and not occupied[i, j + dj]:
                return True
    return False


def _encloses(occupied: np.ndarray) -> bool:
    """Do the occupied cells enclose an empty one (a hole)? Flood fill of the empty cells from the border."""
    free = ~occupied
    reached = np.zeros_like(occupied)
    stack = [(0, 0)]
    reached[0, 0] = True
    rows, cols = occupied.shape
    while stack:
        i, j = stack.pop()
        for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= a < rows and 0 <= b < cols and free[a, b] and not reached[a, b]:
                reached[a, b] = True
                stack.append((a, b))
    return bool((free & ~reached).any())


def rectilinear_polygon(
    n_cells: int,
    *,
    seed: Seed,
    max_size: int = 6,
    grid: int | None = None,
) -> Environment:
    """A random simple rectilinear polygon (no holes): a random polyomino on a grid of random cell sizes.

    Column widths and row heights are integers drawn uniformly from 1..``max_size``, so the polygon has
    narrow passages beside wide rooms. From the middle cell, cells are added one at a time, each drawn
    uniformly among the empty cells beside the shape that keep its boundary one simple ring (no two cells
    touching at a corner only, no enclosed empty cell), until ``n_cells`` cells are in. The polygon is the
    union, without collinear vertices, with **integer** coordinates. The test bed of the rooms-and-doors
    decomposition (Çağırıcı, Bahoo and LaValle): every edge horizontal or vertical.

    Parameters
    ----------
    n_cells
        Number of grid cells (≥ 1).
    seed
        ``int``, :class:`numpy.random.Generator` or ``None``.
    max_size
        Largest cell width or height (≥ 1).
    grid
        Cells per side of the grid (default ⌈√n_cells⌉ + 3, room for every shape of n_cells cells to grow).

    >>> env = rectilinear_polygon(12, seed=4)
    >>> len(env.holes), all(a[0] == b[0] or a[1] == b[1] for a, b in zip(env.outer, env.outer[1:] + env.outer[:1]))
    (0, True)
    >>> env == rectilinear_polygon(12, seed=4), env.name
    (True, 'rectilinear_polygon(n_cells=12, max_size=6, seed=4)')
    """
    import shapely

    n_cells = _check_int("n_cells", n_cells, 1)
    max_size = _check_int("max_size", max_size, 1)
    side = math.isqrt(n_cells - 1) + 4 if grid is None else _check_int("grid", grid, 1)
    if side * side < n_cells:
        raise InputError(f"a {side} x {side} grid holds fewer than n_cells = {n_cells} cells")
    rng = np.random.default_rng(seed)
    widths = rng.integers(1, max_size + 1, side)
    heights = rng.integers(1, max_size + 1, side)
    xs = np.concatenate([[0], np.cumsum(widths)])
    ys = np.concatenate([[0], np.cumsum(heights)])
    occupied = np.zeros((side + 2, side + 2), dtype=bool)  # a border of empty cells: no bounds checks
    start = side // 2 + 1
    occupied[start, start] = True
    count = 1
    while count < n_cells:
        frontier = sorted({(a, b) for i, j in zip(*np.nonzero(occupied)) for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
                           if 1 <= a <= side and 1 <= b <= side and not occupied[a, b]})
        options = [cell for cell in frontier if not _pinches(occupied, *cell)]
        rng.shuffle(options)
        for i, j in options:
            occupied[i, j] = True
            if _encloses(occupied):
                occupied[i, j] = False
                continue
            count += 1
            break
        else:
            raise InvalidEnvironment(f"rectilinear_polygon: the shape cannot grow to n_cells = {n_cells} in a {side} x {side} grid")
    boxes = [shapely.box(xs[j - 1], ys[i - 1], xs[j], ys[i]) for i, j in zip(*np.nonzero(occupied))]
    rings = _rings_of(shapely.union_all(boxes), None)
    if rings is None or rings[1]:  # pragma: no cover - the growth rules keep one simple ring
        raise InvalidEnvironment("rectilinear_polygon: the cells did not make one polygon without holes")
    name = f"rectilinear_polygon(n_cells={n_cells}, max_size={max_size}, seed={_seed_text(seed)})"
    return Environment.from_coords(rings[0], name=name)


# ---------------------------------------------------------------------- by name
GENERATORS: dict[str, Callable[..., Environment]] = {
    "star": star_polygon,
    "holes": star_polygon_with_holes,
    "rooms": rooms_and_corridors,
    "rectilinear": rectilinear_floor_plan,
    "polyomino": rectilinear_polygon,
}
"""The random generators by their short name (CLI ``solverplan generate NAME``, study ``generator``)."""


def generate(kind: str, *, seed: Seed, **params: object) -> Environment:
    """The environment of generator ``kind`` (a key of :data:`GENERATORS`) with ``params`` and ``seed``.

    >>> generate("star", n=6, irregularity=0.2, spikiness=0.1, seed=0) == star_polygon(6, 0.2, 0.1, seed=0)
    True
    >>> generate("blob", seed=0)
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: unknown generator 'blob': use star, holes, rooms, rectilinear or polyomino
    """
    try:
        make = GENERATORS[kind]
    except (KeyError, TypeError):
        raise InputError(f"unknown generator {kind!r}: use {', '.join(list(GENERATORS)[:-1])} or {list(GENERATORS)[-1]}") from None
    try:
        return make(seed=seed, **params)
    except TypeError as exc:  # an unknown or missing parameter name
        raise InputError(f"generator {kind!r}: {exc}".replace(f"{make.__name__}() ", "")) from None


@dataclass(frozen=True)
class GeneratedEnvironment:
    """A generated environment as a CLI answer: its JSON is the environment file itself (docs/contract.md)."""

    env: Environment

    def to_json(self) -> dict:
        return self.env.to_dict()

    def to_text(self, *, width: int = 100) -> str:
        return format_environment(self.env, "json")

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the environment file atomically, format by extension (.json, .geojson, .wkt)."""
        try:
            save_environment(self.env, path)
        except OSError as exc:
            raise InputError(cannot_write(path, exc)) from None
