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
from fractions import Fraction
from typing import Literal

import numpy as np

from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.exact import ExactPoint, orient

__all__ = ["star_polygon", "star_polygon_with_holes", "worst_case_polygon"]

Seed = int | np.random.Generator | None

HoleKind = Literal["convex", "star"]


# ---------------------------------------------------------------------- argument checks
def _check_int(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"expected an integer {name}, got {name}={value!r} (type={type(value).__name__})")
    if value < minimum:
        raise InputError(f"expected {name} >= {minimum}, got {name}={value!r}")
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
def _star_points(
    rng: np.random.Generator, n: int, irregularity: float, spikiness: float, radius: float
) -> np.ndarray:
    """Float vertices (n, 2) of a random star polygon around the origin, at increasing angles.

    Angle steps are uniform in [2π/n·(1 − irregularity), 2π/n·(1 + irregularity)] — the
    irregularity is *scaled* by the mean step (note 000, trap 7), so steps are never negative —
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
        (0 gives equal steps). Scaled, unlike the implementation criticised in note 000, trap 7.
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
    max_attempts = _check_int("max_attempts", max_attempts, 1)
    rng = np.random.default_rng(seed)
    name = (
        f"star_polygon(n={n}, irregularity={irregularity:g}, spikiness={spikiness:g}, "
        f"radius={radius_f:g}, seed={_seed_text(seed)})"
    )
    problem = "no candidate tried"
    for _ in range(max_attempts):
        ring = _to_decimals(_star_points(rng, n, irregularity, spikiness, radius_f), decimals)
        try:
            env = Environment.from_coords(ring, name=name)
        except InvalidEnvironment as exc:
            problem = str(exc)
            continue
        if env.n_vertices == n:  # a rounded last vertex equal to the first would close the ring early
            return env
        problem = "the last vertex rounded onto the first"
    raise InvalidEnvironment(
        f"no valid star polygon with n={n}, irregularity={irregularity:g}, spikiness={spikiness:g}, "
        f"radius={radius_f:g}, decimals={decimals} in {max_attempts} attempts (last: {problem})"
    )


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
    seed
        ``int``, :class:`numpy.random.Generator` or ``None`` (fresh entropy: not reproducible).
    irregularity, spikiness, radius
        Of the outer ring, as in :func:`star_polygon`.
    hole_vertices
        Vertices per hole (≥ 3).
    hole_kind
        ``"convex"`` or ``"star"``.
    hole_radius
        Size of each hole (distance of its vertices from its centre at most); default
        ``0.15 · radius / sqrt(n_holes)`` so the holes fit comfortably.
    decimals
        Number of decimal places of the exact coordinates.
    max_attempts
        Outer rings (with their holes) tried before giving up.

    Returns
    -------
    Environment
        Valid, outer ring counter-clockwise, holes clockwise; ``name`` records the parameters and seed.

    Raises
    ------
    InputError
        A parameter is out of range (named with its value).
    InvalidEnvironment
        The holes could not be placed (too many or too large) or no valid candidate was found.

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
    max_attempts = _check_int("max_attempts", max_attempts, 1)
    rng = np.random.default_rng(seed)
    name = (
        f"star_polygon_with_holes(n={n}, n_holes={n_holes}, irregularity={irregularity:g}, "
        f"spikiness={spikiness:g}, radius={radius_f:g}, hole_vertices={hole_vertices}, "
        f"hole_kind={hole_kind!r}, hole_radius={hole_radius_f:.6g}, seed={_seed_text(seed)})"
    )
    problem = "no candidate tried"
    for _ in range(max_attempts):
        outer_xy = _star_points(rng, n, irregularity, spikiness, radius_f)
        outer = _to_decimals(outer_xy, decimals)
        centres = _hole_centres(rng, outer_xy, n_holes, hole_radius_f, radius_f) if n_holes else np.empty((0, 2))
        if centres is None:
            problem = f"could not place {n_holes} holes of radius {hole_radius_f:.6g}"
            continue
        holes = []
        for centre in centres:
            for _ in range(20):
                ring = _hole_ring(rng, hole_kind, hole_vertices, hole_radius_f, decimals, centre)
                if ring is not None:
                    holes.append(ring)
                    break
            else:
                break
        if len(holes) != n_holes:
            problem = f"holes of radius {hole_radius_f:.6g} do not survive rounding to {decimals} decimals"
            continue
        try:
            env = Environment.from_coords(outer, holes, name=name)
        except InvalidEnvironment as exc:
            problem = str(exc)
            continue
        if env.n_edges == n + n_holes * hole_vertices:
            return env
        problem = "the last vertex of a ring rounded onto its first"
    raise InvalidEnvironment(
        f"no valid star polygon with n={n} and n_holes={n_holes} (hole_radius={hole_radius_f:.6g}, "
        f"radius={radius_f:g}) in {max_attempts} attempts (last: {problem}); use fewer or smaller holes"
    )


# ---------------------------------------------------------------------- the paper's worst case
_WORST_CASE_RADIUS = 10
_WORST_CASE_DECIMALS = 6


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
