"""One margin policy for every planner: how far every strategy keeps from walls, interval ends and corners.

Planning runs in floating point and answers must replay both in exact arithmetic (certificates) and in plain
floating-point rollouts (a robot's own controller, :mod:`solverplan.simulate`). An answer that is exactly sound
but drives the robot within 10⁻⁹ of a corner, or leaves a wall at 10⁻⁶ rad, is sound only on paper: a float
ray cast cannot call which side of the corner it lands. So every planner (plans, patrols, funnels,
localisation) builds its heading intervals under the same three margins:

``heading_margin`` δ (radians, default :data:`DEFAULT_HEADING_MARGIN` = 0.001)
    No stage leaves within δ of the wall it is on: every interval lies in [δ, π − δ].
``safe_margin`` μ (radians, default :data:`DEFAULT_SAFE_MARGIN` = 10⁻⁹)
    Every interval lies at least μ inside the exact safe set it was taken from (the float ends of the exact
    safe sets are off by ~10⁻¹⁵).
``corner_clearance`` κ (a length, default :func:`default_corner_clearance`: 10⁻⁴ × the environment's
diameter D, the largest distance between two of its vertices — unchanged by rotations, translations and by how
the walls are written, unlike a bounding box)
    No contact point of any stage's possible positions comes within κ of a segment end (a vertex of P or an
    inserted point of P′, where the next stage would not know its segment) — except the end a stage's target
    shares with its source, where positions near the corner come from positions near it and the map contracts
    towards it (paper Cor. 1's corners). For arcs of the safe BVG from source (a, b) to target (c, d) this is
    Prop. 2's cone with the target pulled in by κ: θ ≥ ang(c′ − b), θ ≤ ang(d′ − a). Interval ends that come
    from an obstruction (a vertex the corner rays touch) are moved κ / D radians inwards (D the diameter), so
    that no ray of an interval end passes nearer than that angle to the touching ray.

**No corner ping-pong.** The exemption at shared corners is sound one stage at a time, but two consecutive
stages into the same corner (back and forth between the two segments at a vertex) multiply the distance to it
by the contraction coefficient of each (≈ δ at the heading margin), and repeated they drive robots into the
vertex. So every planner remembers, for each possible segment, whether the robot arrived by an arc into one
of its corners (:func:`corner_arcs`), and never takes a second arc into that corner next. Then every contact
point stays at least C_min·κ ≥ sin(δ)·κ from every vertex it did not start near (C_min the smallest contraction
coefficient of an admissible heading): 10⁻⁷ D with the defaults, a hundred times the float caster's tolerance.

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> m = Margins.for_environment(square)
>>> m.heading_margin, round(m.corner_clearance / math.hypot(4, 4), 12), round(m.end_margin, 12)
(0.001, 0.0001, 0.0001)
>>> m.to_json()["end"] == m.end_margin   # what every interval end actually moves inwards, in radians
True
>>> Margins.for_environment(square, heading_margin=0.0)
Traceback (most recent call last):
...
solverplan.errors.InputError: heading_margin must be in (0, π/4) radians, got 0.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from solverplan.bounce.bvg import SafeBVG
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.interval import DEFAULT_HEADING_MARGIN

__all__ = ["DEFAULT_HEADING_MARGIN", "DEFAULT_SAFE_MARGIN", "CORNER_CLEARANCE_FRACTION", "MARGIN_DOCS", "Margins",
           "environment_diameter", "default_corner_clearance", "AdmissibleIntervals", "admissible_intervals", "corner_arcs"]

DEFAULT_SAFE_MARGIN = 1e-9
"""μ (radians): intervals stay μ inside the exact safe sets (floats → sound plans)."""

CORNER_CLEARANCE_FRACTION = 1e-4
"""κ / D of the default corner clearance: 10⁻⁴ of the environment's diameter D (1 mm in a 10 m room). One arc into
a corner at the heading margin shrinks distances to it by ≈ δ = 10⁻³, so contact points stay ≥ 10⁻⁷ D from
vertices: far above double rounding (10⁻¹⁶ D) and the float caster's tie tolerance (10⁻⁹ D)."""


MARGIN_DOCS = {
    "margins": """
heading_margin, safe_margin, corner_clearance
    The margin policy of every planner (:mod:`solverplan.plan.margins`): no interval within δ radians of a wall,
    every interval μ radians inside the exact safe set it is taken from, no landing within κ (a length; default
    10⁻⁴ of the environment's diameter) of a segment end.""",
    "position_margins": """
heading_margin, corner_clearance
    The margin policy of every planner (:mod:`solverplan.plan.margins`) but μ (position sets are tracked exactly,
    with no safe sets): no interval within δ radians of a wall, no landing within κ (a length; default 10⁻⁴ of the
    environment's diameter) of a segment end.""",
}
"""The margin parameters as the planners describe them (:func:`~solverplan._docstrings.fill_doc` fragments)."""


def environment_diameter(env: Environment) -> float:
    """The largest distance between two vertices of ``env`` (its length units): the diameter of its outer ring's
    convex hull (shapely), over every pair of its corners. A size that rotations, translations, ring start indices, vertex order and
    collinear vertices leave unchanged (to rounding), so the margins scaled by it are too.

    >>> from solverplan.environment import Environment
    >>> environment_diameter(Environment.from_coords([[0, 0], [4, 0], [4, 3], [2, 3], [0, 3]]))
    5.0
    """
    hull = shapely.MultiPoint([(float(x), float(y)) for x, y in env.rings[0]]).convex_hull
    ring = list(hull.exterior.coords)[:-1]  # a proper outer ring spans an area: its hull is a polygon
    # the hull's corners only (shapely keeps vertices on the hull's edges: collinear vertices of the walls), then every
    # pair of them, in blocks: rotating calipers tie on parallel hull edges (rectilinear rooms), and which of two
    # equally far vertices they stop at turned with the room (and with a vertex written on the hull)
    pts = []
    for k, p in enumerate(ring):
        before, after = ring[k - 1], ring[(k + 1) % len(ring)]
        if abs(_turn(before, p, after)) > 1e-12 * math.dist(before, p) * math.dist(p, after):
            pts.append(p)
    xy = np.asarray(pts, dtype=float).reshape(-1, 2)
    best = 0.0
    for i in range(0, len(xy), 512):
        block = xy[i:i + 512]
        d = (block[:, None, 0] - xy[None, :, 0]) ** 2 + (block[:, None, 1] - xy[None, :, 1]) ** 2
        best = max(best, float(d.max()))
    return math.sqrt(best)


def _turn(o: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def default_corner_clearance(env: Environment) -> float:
    """The default κ (length units of ``env``): :data:`CORNER_CLEARANCE_FRACTION` × :func:`environment_diameter`."""
    return CORNER_CLEARANCE_FRACTION * environment_diameter(env)


@dataclass(frozen=True, slots=True)
class Margins:
    """The margins of one query (module docstring): δ and μ in radians, κ in length units, ``size`` the
    environment's size D (:func:`environment_diameter`); ``end_margin`` = max(μ, κ / D) radians is what interval
    ends move inwards."""

    heading_margin: float
    safe_margin: float
    corner_clearance: float
    size: float

    @classmethod
    def for_environment(cls, env: Environment, *, heading_margin: float = DEFAULT_HEADING_MARGIN,
                        safe_margin: float = DEFAULT_SAFE_MARGIN, corner_clearance: float | None = None) -> Margins:
        """Validated margins for ``env`` (``corner_clearance=None``: :func:`default_corner_clearance`)."""
        if isinstance(heading_margin, bool) or not (isinstance(heading_margin, (int, float))
                                                    and 0 < heading_margin < math.pi / 4):
            raise InputError(f"heading_margin must be in (0, π/4) radians, got {heading_margin!r}")
        if isinstance(safe_margin, bool) or not (isinstance(safe_margin, (int, float)) and 0 <= safe_margin < 0.1):
            raise InputError(f"safe_margin must be in [0, 0.1) radians, got {safe_margin!r}")
        size = environment_diameter(env)
        if corner_clearance is None:
            kappa = CORNER_CLEARANCE_FRACTION * size
        elif isinstance(corner_clearance, bool) or not (isinstance(corner_clearance, (int, float))
                                                        and math.isfinite(corner_clearance)
                                                        and 0 <= corner_clearance < 0.01 * size):
            raise InputError(f"corner_clearance must be a length in [0, {0.01 * size:.6g}) (1% of the "
                             f"environment's diameter), got {corner_clearance!r}")
        else:
            kappa = float(corner_clearance)
        return cls(float(heading_margin), float(safe_margin), kappa, size)

    @property
    def end_margin(self) -> float:
        """Radians every interval end moves inside its exact safe set: max(μ, κ / D)."""
        return max(self.safe_margin, self.corner_clearance / self.size if self.size > 0 else 0.0)

    def to_json(self) -> dict:
        """The margins as answers report them: ``heading`` δ, ``safe`` μ and ``end`` max(μ, κ/D) in radians (``end``
        is what every interval end is actually moved inside its exact safe set), ``corner_clearance`` κ and
        ``size`` D in the environment's length units."""
        return {"heading": self.heading_margin, "safe": self.safe_margin, "end": self.end_margin,
                "corner_clearance": self.corner_clearance, "size": self.size}


@dataclass(frozen=True)
class AdmissibleIntervals:
    """The intervals a strategy may use on the arcs of a safe BVG, one row per (arc, safe interval) that keeps
    a positive width: ``arc`` (row of the graph), ``source``, ``target`` (segments), ``lo``/``hi`` (radians)."""

    arc: np.ndarray
    source: np.ndarray
    target: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    def __len__(self) -> int:
        return len(self.lo)


def corner_arcs(partition, source: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For arcs source → target of P′ segments: ``dive``, the end of the source the arc runs into when the two
    segments share it (1: the source's start a, 2: its end b, 0: no shared corner), and ``arrival``, the end of
    the target the robot then arrives near (1: its start, 2: its end, 0: none). Positions near a shared corner
    land near it (paper Cor. 1's arcs); a robot that arrived near a segment's corner takes no arc into that
    corner next (module docstring)."""
    ends = np.array([[float(x) for x in (*seg.a, *seg.b)] for seg in partition.segments]).reshape(-1, 4)
    source, target = np.asarray(source, dtype=np.int64), np.asarray(target, dtype=np.int64)
    into_b = np.all(ends[source, 2:] == ends[target, :2], axis=1)  # i → i+1 (floats of one exact point are equal)
    into_a = np.all(ends[source, :2] == ends[target, 2:], axis=1)  # i → i−1
    dive = np.where(into_a, 1, np.where(into_b, 2, 0))
    arrival = np.where(into_b, 1, np.where(into_a, 2, 0))
    return dive, arrival


def _angle_from(ex: np.ndarray, ey: np.ndarray, wx: np.ndarray, wy: np.ndarray) -> np.ndarray:
    """CCW angle of w from e, in (−π, π] (vectorised)."""
    return np.arctan2(ex * wy - ey * wx, ex * wx + ey * wy)


def admissible_intervals(graph: SafeBVG, margins: Margins) -> AdmissibleIntervals:
    """Every safe interval of ``graph`` cut by ``margins`` (module docstring); rows of zero width dropped.

    >>> from solverplan.environment import Environment
    >>> from solverplan.bounce.bvg import safe_bounce_visibility_graph
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> g = safe_bounce_visibility_graph(square)
    >>> adm = admissible_intervals(g, Margins.for_environment(square))
    >>> bool(adm.lo.min() >= 0.001 and adm.hi.max() <= math.pi - 0.001), len(adm)   # e0 → e2 is a singleton
    (True, 8)
    """
    counts = np.asarray(graph.n_intervals, dtype=np.int64)
    arc = np.repeat(np.arange(graph.n_arcs), counts)
    src = np.asarray(graph.source, dtype=np.int64)[arc]
    tgt = np.asarray(graph.target, dtype=np.int64)[arc]
    lo = np.asarray(graph.set_lo, dtype=float)
    hi = np.asarray(graph.set_hi, dtype=float)
    if margins.corner_clearance > 0 and len(arc):
        part = graph.partition
        a = np.array([[float(s.a[0]), float(s.a[1])] for s in part.segments])
        b = np.array([[float(s.b[0]), float(s.b[1])] for s in part.segments])
        A, B, C, D = a[src], b[src], a[tgt], b[tgt]
        nxt = part.next_segment
        # the directions from differences of the exact points, accurate however far from 0 the environment
        # lies (differences of its rounded points are not)
        own = part.point_vectors(np.arange(len(part.segments)), nxt)  # b − a of every segment, once (not per row)
        lo, hi = cut_to_margins(lo, hi, margins, edge=own[src], target=own[tgt], cb=part.point_vectors(nxt[src], tgt),
                                da=part.point_vectors(src, nxt[tgt]),
                                shared_c=np.all(C == B, axis=1), shared_d=np.all(D == A, axis=1))
    else:
        lo, hi = cut_to_margins(lo, hi, margins)
    keep = hi > lo
    return AdmissibleIntervals(arc[keep], src[keep], tgt[keep], lo[keep], hi[keep])


def cut_to_margins(lo: np.ndarray, hi: np.ndarray, margins: Margins, *, edge: np.ndarray | None = None,
                   target: np.ndarray | None = None, cb: np.ndarray | None = None, da: np.ndarray | None = None,
                   shared_c: np.ndarray | None = None, shared_d: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Safe intervals [lo, hi] (radians, rows) cut by ``margins`` (module docstring); empty rows get hi ≤ lo.

    For the corner clearance κ each row also needs its geometry as float vectors: ``edge`` = b − a of the source
    (a, b), ``target`` = d − c of the target (c, d), ``cb`` = c − b, ``da`` = d − a, and whether the target's end c
    (``shared_c``: c = b) or d (``shared_d``: d = a) is the corner it shares with the source (exempt, Cor. 1)."""
    mu = margins.end_margin
    lo = np.maximum(lo + mu, margins.heading_margin)
    hi = np.minimum(hi - mu, math.pi - margins.heading_margin)
    kappa = margins.corner_clearance
    if kappa <= 0 or edge is None or not len(lo):
        return lo, hi
    assert target is not None and cb is not None and da is not None and shared_c is not None and shared_d is not None
    length = np.hypot(*target.T)
    u = target / np.where(length > 0, length, 1.0)[:, None]
    ex, ey = edge.T
    cb, da = cb + kappa * u, da - kappa * u  # the target's ends pulled in by κ: c_in − b = (c − b) + κu
    cone_lo = np.where(shared_c, 0.0, _angle_from(ex, ey, cb[:, 0], cb[:, 1]))
    cone_hi = np.where(shared_d, math.pi, _angle_from(ex, ey, da[:, 0], da[:, 1]))
    # a target too short for the clearance at both (unshared) ends cannot be used at all
    needed = kappa * ((~shared_c).astype(float) + (~shared_d).astype(float))
    lo = np.maximum(lo, cone_lo + margins.safe_margin)
    hi = np.minimum(hi, cone_hi - margins.safe_margin)
    return lo, np.where(length > needed, hi, -np.inf)
