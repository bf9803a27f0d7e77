"""Limit cycles of the constant rule b = θ (paper §6.1): Theorem 1 in convex polygons, and Prop. 4 made
constructive in any polygon (holes too), every answer verified in exact arithmetic.

**The map.** Under a constant heading the robot's boundary dynamics is a piecewise affine map f_θ of ∂P:
on edge e_i the rays of one exact direction d_i (:class:`~solverplan.bounce.dynamics.ExactHeading`) pass
through a vertex only at finitely many parameters t_v = cross(v − a, d)/cross(e, d) (one per vertex ahead
of the edge's line); between two consecutive ones no ray touches a vertex, so the first-hit edge is
constant and the map is the exact affine map t ↦ α t + β onto that edge
(:func:`~solverplan.bounce.transitions.affine_map`, rational α, β). Adjacent pieces with the same target
have the same map and are merged (the map is continuous there; the single ray through the vertex is
outside the model, as every ray through a vertex is).

**A cycle along an edge sequence** (:func:`limit_cycle`, all methods). Compose the affine maps along the
sequence e_0 → e_1 → … → e_{m−1} → e_0 into the return map R(t) = α t + β on e_0; its fixed point is
t* = β / (1 − α) and its contraction is |α| = Π C_k (Def. 12; in arc length the edge lengths cancel). The
cycle is **verified** when (1) every point t_k of the orbit of t* lies strictly inside its edge and strictly
inside a piece of f_θ whose target is e_{k+1}, (2) an exact ray cast from each t_k along d_k first hits
e_{k+1}, at no vertex, exactly at t_{k+1}, and the orbit closes (t_m = t_0), and (3) |α| < 1. Then the orbit
is a true periodic trajectory of the robot and it attracts: the open interval of radius
ρ_r = min_k dist(t_{r+k}, ends of its piece) / |α_r ⋯ α_{r+k−1}| around each contact point t_r is carried
along the whole sequence inside the pieces, and R maps the symmetric interval into itself (|α| < 1), so
every start in it converges to the cycle (the **basin**, exact ends).

**Methods.**

- ``"theorem1"`` (default for a strictly convex polygon without holes): the sequence e_0, …, e_{n−1}. For θ in
  Lemma 3's range (:func:`~solverplan.bounce.dynamics.lemma3_max_heading`) every start converges (Lemma 3,
  Theorem 1); outside it the cycle is still checked as above and reported with its status —
  ``not-contracting`` (|α| ≥ 1: the periodic orbit exists but repels), ``edge-order-broken`` (the orbit of
  t* does not visit the edges in CCW order), or ``found`` with a local guarantee (its basin) and the reason
  Lemma 3 does not apply.
- ``"iterate"`` (default otherwise): Prop. 4 made constructive. Iterate f_θ from a start in floats, detect
  the eventually periodic sequence of pieces, then verify the cycle exactly as above; the start itself is
  proved to converge by carrying an exact enclosure of its orbit (intervals on a 2⁻⁹⁶ grid, rounded
  outward) until it lies inside a basin. The *entry* stages are those bounces.
- ``"edges"`` (``edges=...``): the cycle along a given edge sequence; ``not-realised`` when the heading
  does not carry the fixed point along it.

:func:`constant_controller` searches for one constant heading under which **every** start converges to a
verified cycle (Prop. 4) and proves it by iterating exact enclosures of the whole boundary (see there).

>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> cycle = limit_cycle(square, "tan:1/2")
>>> cycle.status.value, cycle.edges, cycle.contraction_exact, [str(p.t) for p in cycle.points]
('found', (0, 1, 2, 3), Fraction(1, 16), ['1/3', '1/3', '1/3', '1/3'])
>>> limit_cycle(square, "tan:2").status.value        # θ > π/4: the period-4 orbit exists but repels
'not-contracting'
"""

from __future__ import annotations

import bisect
import logging
import math
from dataclasses import dataclass, field, replace
from enum import StrEnum
from fractions import Fraction
from typing import Literal, Sequence

import numpy as np

from solverplan.bounce.dynamics import (
    ExactHeading,
    HeadingSpec,
    Lemma3Range,
    cycles_to_epsilon,
    lemma3_range,
    parse_heading,
    theorem1_fixed_point,
)
from solverplan.bounce.partition import Partition, partition
from solverplan.bounce.rules import check_edges
from solverplan.bounce.transitions import AffineMap, affine_map
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet, SolverFailed
from solverplan.exact import ExactPoint, format_number, to_fraction
from solverplan.geometry.raycast import cast_ray, cast_rays_exact

__all__ = [
    "CycleStatus",
    "CycleStage",
    "CyclePoint",
    "LimitCycle",
    "limit_cycle",
    "limit_cycles",
    "ConstantController",
    "constant_controller",
    "DEFAULT_CONTROLLER_TANGENTS",
]

logger = logging.getLogger(__name__)

GRID_BITS = 96
"""Exact enclosures of positions live on the grid t = k / 2**GRID_BITS, rounded outward at every bounce."""
_ONE = 1 << GRID_BITS

Method = Literal["auto", "theorem1", "iterate", "edges"]


class CycleStatus(StrEnum):
    """The answer of :func:`limit_cycle` (``found`` is the only one with a stable cycle)."""

    FOUND = "found"  #: a verified, contracting periodic orbit
    NOT_CONTRACTING = "not-contracting"  #: the periodic orbit exists, but |α| ≥ 1: it does not attract
    EDGE_ORDER_BROKEN = "edge-order-broken"  #: Theorem 1 mode: the fixed point's orbit leaves the CCW order
    NOT_REALISED = "not-realised"  #: edges mode: the heading does not carry the orbit along the sequence
    VERTEX = "vertex"  #: the orbit runs into a vertex (outside the model)
    NO_CYCLE = "no-cycle-found"  #: iterate mode: no periodic piece sequence within the bounce budget


# ---------------------------------------------------------------------- the piecewise affine map f_θ
@dataclass(frozen=True, slots=True)
class _Piece:
    lo: Fraction
    hi: Fraction
    target: int
    map: AffineMap
    grid: tuple[int, int, int]  # (num_a, num_b, den): grid image L' = (num_a L + num_b) / den

    def grid_image(self, lo: int, hi: int) -> tuple[int, int]:
        na, nb, den = self.grid
        a, b = na * lo + nb, na * hi + nb
        if a > b:
            a, b = b, a
        return max(0, a // den), min(_ONE, -((-b) // den))


class _ConstantMap:
    """f_θ for one exact heading, built lazily per edge (see the module docstring)."""

    def __init__(self, env: Environment, heading: ExactHeading) -> None:
        self.env, self.heading = env, heading
        self._pieces: dict[int, list[_Piece]] = {}
        self._float: dict[int, tuple[list[float], list[int], list[float], list[float]]] = {}
        self._dirs: dict[int, ExactPoint] = {}

    def direction(self, edge: int) -> ExactPoint:
        d = self._dirs.get(edge)
        if d is None:
            e = self.env.edge(edge)
            d = self._dirs[edge] = self.heading.direction((e.b[0] - e.a[0], e.b[1] - e.a[1]))
        return d

    def pieces(self, edge: int) -> list[_Piece]:
        cached = self._pieces.get(edge)
        if cached is not None:
            return cached
        env = self.env
        e = env.edge(edge)
        a = e.a
        ev = (e.b[0] - a[0], e.b[1] - a[1])
        d = self.direction(edge)
        den = ev[0] * d[1] - ev[1] * d[0]  # > 0: d points into the free space
        cuts = {Fraction(0), Fraction(1)}
        for v in env.exact_vertices:
            w = (v[0] - a[0], v[1] - a[1])
            if ev[0] * w[1] - ev[1] * w[0] > 0:  # strictly on the free side of the edge's line
                t = (w[0] * d[1] - w[1] * d[0]) / den
                if 0 < t < 1:
                    cuts.add(t)
        cuts_sorted = sorted(cuts)
        mids = [(lo + hi) / 2 for lo, hi in zip(cuts_sorted, cuts_sorted[1:])]
        hits = cast_rays_exact(env, [env.exact_point_at(edge, t) for t in mids], [d] * len(mids))
        pieces: list[_Piece] = []
        for (lo, hi), hit in zip(zip(cuts_sorted, cuts_sorted[1:]), hits):
            if hit is None or hit.vertex is not None:  # pragma: no cover - excluded by the choice of cuts
                raise SolverFailed(f"constant map: the ray from e{edge} at t = {format_number((lo + hi) / 2)} hits a vertex")
            if pieces and pieces[-1].target == hit.edge:
                pieces[-1] = replace(pieces[-1], hi=hi)
                continue
            m = affine_map(env, edge, d, hit.edge)
            an, ad, bn, bd = m.alpha.numerator, m.alpha.denominator, m.beta.numerator, m.beta.denominator
            pieces.append(_Piece(lo, hi, hit.edge, m, (an * bd, bn * ad * _ONE, ad * bd)))
        self._pieces[edge] = pieces
        return pieces

    def locate(self, edge: int, t: Fraction) -> int | None:
        """Index of the piece holding t strictly inside, None at a piece end (a ray through a vertex)."""
        pieces = self.pieces(edge)
        k = bisect.bisect_right([p.lo for p in pieces], t) - 1
        if k < 0 or not pieces[k].lo < t < pieces[k].hi:
            return None
        return k

    def float_table(self, edge: int):
        table = self._float.get(edge)
        if table is None:
            pieces = self.pieces(edge)
            table = self._float[edge] = (
                [float(p.lo) for p in pieces[1:]],
                [p.target for p in pieces],
                [float(p.map.alpha) for p in pieces],
                [float(p.map.beta) for p in pieces],
            )
        return table

    def grid_image(self, edge: int, lo: int, hi: int) -> list[tuple[int, int, int, int]]:
        """An outward-rounded enclosure of f_θ([lo, hi] / 2**GRID_BITS on ``edge``): (edge', lo', hi', piece index)
        per piece met (an interval only touching a piece at an end point skips it; a point on a piece end
        meets both neighbours)."""
        out = []
        flo, fhi = Fraction(lo, _ONE), Fraction(hi, _ONE)
        for k, p in enumerate(self.pieces(edge)):
            if p.hi < flo or p.lo > fhi or (lo < hi and (p.hi == flo or p.lo == fhi)):
                continue
            a = max(lo, (p.lo.numerator * _ONE) // p.lo.denominator)
            b = min(hi, -((-p.hi.numerator * _ONE) // p.hi.denominator))
            ia, ib = p.grid_image(a, b)
            out.append((p.target, ia, ib, k))
        return out


def _merge(intervals: list[tuple[int, int, int]]) -> list[tuple[int, int, int]]:
    out: list[tuple[int, int, int]] = []
    for e, lo, hi in sorted(intervals):
        if out and out[-1][0] == e and lo <= out[-1][2]:
            if hi > out[-1][2]:
                out[-1] = (e, out[-1][1], hi)
        else:
            out.append((e, lo, hi))
    return out


# ---------------------------------------------------------------------- results
def _num(value: Fraction) -> str:
    return format_number(value)


def _check_epsilon(epsilon: object) -> float:
    try:
        eps = float(epsilon)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"epsilon {epsilon!r} is not a number") from None
    if not (math.isfinite(eps) and eps > 0):
        raise InputError(f"epsilon {epsilon!r} must be a positive length")
    return eps


@dataclass(frozen=True, slots=True)
class CycleStage:
    """One bounce of a cycle or an entry: leave ``from_edge`` along ``direction`` (the exact heading θ),
    land on ``to_edge``: t ↦ ``alpha`` t + ``beta``; ``contraction`` = C_k = |α|·ℓ_to/ℓ_from (arc length)."""

    from_edge: int
    to_edge: int
    theta: float
    direction: ExactPoint
    alpha: Fraction
    beta: Fraction
    contraction: float
    from_segments: tuple[int, ...] = ()
    to_segments: tuple[int, ...] = ()

    def to_json(self) -> dict:
        return {
            "from_segments": list(self.from_segments),
            "to_segments": list(self.to_segments),
            "interval": [self.theta, self.theta],
            "from_edge": self.from_edge,
            "to_edge": self.to_edge,
            "direction": [_num(self.direction[0]), _num(self.direction[1])],
            "map": {"alpha": _num(self.alpha), "beta": _num(self.beta)},
            "contraction": self.contraction,
        }


@dataclass(frozen=True, slots=True)
class CyclePoint:
    """A contact point of the cycle: ``edge``, exact ``t``, the exact ``point``, and the certified ``basin``
    (an open t-interval on the edge from which every start converges to the cycle; None if unknown)."""

    edge: int
    t: Fraction
    point: ExactPoint
    basin: tuple[Fraction, Fraction] | None = None

    def to_json(self, env: Environment, cycles: int | None = None) -> dict:
        out = {
            "edge": self.edge,
            "t": float(self.t),
            "t_exact": _num(self.t),
            "point": [float(self.point[0]), float(self.point[1])],
            "d": float(self.t) * float(env.edge_lengths[self.edge]),
            "basin": None if self.basin is None else [float(self.basin[0]), float(self.basin[1])],
        }
        if cycles is not None:
            out["cycles_to_epsilon"] = cycles
        return out


@dataclass(frozen=True)
class LimitCycle:
    """A limit cycle of the constant rule, or the reason there is none (:class:`CycleStatus`).

    Attributes
    ----------
    status, reason
        The answer and, unless ``found`` with a global guarantee, why (one sentence per fact).
    method
        ``theorem1``, ``iterate`` or ``edges`` (see the module docstring).
    heading, theta
        The exact heading used, and the heading asked for (radians, float).
    edges
        The cycle's edge sequence e_0, …, e_{m−1} (then back to e_0).
    stages, entry
        The cycle's bounces, and the bounces from ``start`` into the cycle (iterate mode).
    points
        The contact points (fixed points of the return maps, one per stage), exact, with basins.
    contraction_exact, contraction
        |α| of the exact return map (= Π C_k, Def. 12), and as a float.
    scope
        What is proved to converge: ``every-start`` (Theorem 1 with Lemma 3's edge order, or
        :func:`constant_controller`'s proof), ``start+basin`` (``start`` provably enters the basins, iterate
        mode), ``basin`` (the certified basins only), or ``none`` (no stable cycle).
    start
        (edge, t) the iteration started from (iterate mode).
    lemma3
        Lemma 3's range when the environment is strictly convex, else None.
    theorem1_d
        Theorem 1's d_FP by its float closed form, on edge ``edges[0]`` (theorem1 method, for comparison).
    epsilon, cycles_to_epsilon, epsilon_width
        Cor. 4 (tight) when ``epsilon`` was given: cycles until a position set of width ``epsilon_width`` on
        ``edges[0]`` (the whole edge for ``every-start``, else the basin; arc length) is at most ε wide.
    """

    env: Environment
    status: CycleStatus
    reason: str
    method: str
    heading: ExactHeading
    theta: float
    edges: tuple[int, ...] = ()
    stages: tuple[CycleStage, ...] = ()
    entry: tuple[CycleStage, ...] = ()
    points: tuple[CyclePoint, ...] = ()
    contraction_exact: Fraction | None = None
    contraction: float | None = None
    scope: str = "none"
    start: tuple[int, Fraction] | None = None
    lemma3: Lemma3Range | None = None
    theorem1_d: float | None = None
    epsilon: float | None = None
    cycles_to_epsilon: int | None = None
    epsilon_width: float | None = None
    point_cycles: tuple[int | None, ...] = ()
    bounces_simulated: int | None = None

    @property
    def found(self) -> bool:
        return self.status is CycleStatus.FOUND

    @property
    def period(self) -> int:
        return len(self.edges)

    def fixed_point(self, edge: int | None = None) -> CyclePoint:
        """The first contact point (on ``edges[0]``), or the first one on ``edge``."""
        for p in self.points:
            if edge is None or p.edge == edge:
                return p
        raise InputError(f"the cycle has no contact point on edge e{edge}")

    def with_epsilon(self, epsilon: float | None) -> LimitCycle:
        """The same cycle with Cor. 4's counts for ``epsilon`` (arc length; None clears them)."""
        if epsilon is None:
            return replace(self, epsilon=None, cycles_to_epsilon=None, epsilon_width=None, point_cycles=())
        eps = _check_epsilon(epsilon)
        if not self.found or self.contraction is None or not self.points:
            return replace(self, epsilon=eps, cycles_to_epsilon=None, epsilon_width=None, point_cycles=())
        c = float(self.contraction_exact) if self.contraction_exact is not None else self.contraction
        widths = [self._width(p) for p in self.points]
        counts = tuple(cycles_to_epsilon(c, w, eps) if c > 0 else int(w > eps) for w in widths)
        return replace(self, epsilon=eps, cycles_to_epsilon=counts[0], epsilon_width=widths[0], point_cycles=counts)

    def _width(self, p: CyclePoint) -> float:
        length = float(self.env.edge_lengths[p.edge])
        if self.scope == "every-start" or p.basin is None:
            return length
        return float(p.basin[1] - p.basin[0]) * length

    # ------------------------------------------------------------------ output
    def title(self, *, others: int = 0) -> str:
        """A two-line caption for pictures (``others``: how many more cycles the picture shows)."""
        name = self.env.name or "environment"
        head = f"{name}: constant heading θ = {self.theta:.4g}"
        more = f" (+{others} more cycle{'s' if others > 1 else ''})" if others else ""
        if not self.points:
            return f"{head}\n{self.status.value}"
        seq = _seq(self.edges) if len(self.edges) <= 8 else f"period {len(self.edges)} from e{self.edges[0]}"
        if self.found:
            return f"{head}, limit cycle {seq}{more}\ncontraction {self.contraction:.3g} per cycle ({self.scope})"
        return f"{head}, periodic orbit {seq}{more}\n{self.status.value} (contraction {self.contraction:.3g}): not a stable cycle"

    def to_json(self) -> dict:
        """The cycle answer of docs/contract.md (plus the exact details)."""
        pc = self.point_cycles or (None,) * len(self.points)
        out: dict = {
            "status": self.status.value,
            "reason": self.reason,
            "method": self.method,
            "environment": self.env.name,
            "theta": self.theta,
            "theta_exact": self.heading.spec(),
            "theta_used": self.heading.theta,
            "edges": list(self.edges),
            "period": len(self.edges),
            "entry": [s.to_json() for s in self.entry],
            "cycle": [s.to_json() for s in self.stages],
            "contraction": self.contraction,
            "contraction_exact": None if self.contraction_exact is None else _num(self.contraction_exact),
            "fixed_point": [p.to_json(self.env, c) for p, c in zip(self.points, pc)],
            "scope": self.scope,
            "start": None if self.start is None else {"edge": self.start[0], "t": float(self.start[1]), "t_exact": _num(self.start[1])},
        }
        if self.lemma3 is not None:
            out["lemma3"] = {
                "range": list(self.lemma3.interval),
                "clockwise": self.lemma3.clockwise,
                "inside": self.lemma3.contains(self.heading.theta),
                "order_bound": self.lemma3.order_bound,
                "contraction_bound": self.lemma3.contraction_bound,
            }
        if self.theorem1_d is not None:
            out["theorem1"] = {"edge": self.edges[0] if self.edges else 0, "d": self.theorem1_d}
        if self.epsilon is not None:
            out["epsilon"] = self.epsilon
            out["cycles_to_epsilon"] = self.cycles_to_epsilon
            out["epsilon_width"] = self.epsilon_width
        out["optimality"] = {"method": self.method, "proved": self.found, "bound": None}
        return out

    def to_text(self, *, width: int = 100) -> str:
        lines = [f"limit cycle of the constant heading θ = {self.theta:.12g} ({self.heading.spec()}) in "
                 f"{self.env.name or 'the environment'}: {self.status.value} (method {self.method})"]
        if self.reason:
            lines.append(f"reason: {self.reason}")
        if self.edges:
            lines.append("edges: " + " → ".join(f"e{e}" for e in (*self.edges, self.edges[0])))
        if self.contraction is not None:
            exact = _num(self.contraction_exact) if self.contraction_exact is not None else "?"
            if len(exact) > 60:
                exact = exact[:28] + "…" + exact[-28:]
            lines.append(f"contraction per cycle: {self.contraction:.12g} (exact {exact})")
        if self.entry:
            lines.append(f"entry: {len(self.entry)} bounces from e{self.start[0]}:{float(self.start[1]):.12g}" if self.start else
                         f"entry: {len(self.entry)} bounces")
        for p in self.points:
            basin = "" if p.basin is None else f", basin t ∈ ({float(p.basin[0]):.6g}, {float(p.basin[1]):.6g})"
            lines.append(f"  e{p.edge}: t = {float(p.t):.15g}, point ({float(p.point[0]):.12g}, {float(p.point[1]):.12g}){basin}")
        lines.append(f"guarantee: {self.scope}")
        if self.cycles_to_epsilon is not None:
            lines.append(f"cycles to ε = {self.epsilon:g}: {self.cycles_to_epsilon} (from a position set {self.epsilon_width:.6g} wide)")
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- the exact cycle along an edge sequence
@dataclass
class _Core:
    status: CycleStatus
    reason: str
    edges: tuple[int, ...]
    maps: list[AffineMap] = field(default_factory=list)
    ret: AffineMap | None = None
    orbit: list[Fraction] = field(default_factory=list)
    radii: list[Fraction] = field(default_factory=list)


def _cycle_along(env: Environment, cmap: _ConstantMap, edges: Sequence[int], broken: CycleStatus,
                 hint: Fraction | None = None) -> _Core:
    """Compose, find the fixed point, verify it exactly (module docstring); ``broken`` is the status for
    an orbit that leaves the sequence."""
    edges = tuple(int(e) for e in edges)
    m = len(edges)
    maps: list[AffineMap] = []
    for k, src in enumerate(edges):
        dst = edges[(k + 1) % m]
        if dst == src:
            return _Core(broken, f"e{src} → e{dst}: a ray cannot land on the edge it leaves", edges)
        try:
            maps.append(affine_map(env, src, cmap.direction(src), dst))
        except InputError as exc:
            return _Core(broken, f"step e{src} → e{dst}: {exc}", edges)
    ret = maps[0]
    for mk in maps[1:]:
        ret = ret.then(mk)
    core = _Core(broken, "", edges, maps, ret)
    if ret.alpha == 1 and ret.beta != 0:
        core.reason = f"the return map on e{edges[0]} is the translation t ↦ t + {_num(ret.beta)}: no periodic orbit"
        return core
    # α = 1, β = 0: the identity — every point is periodic; check one (the iteration's, or the middle)
    t = ret.fixed_point() if ret.alpha != 1 else (hint if hint is not None else Fraction(1, 2))
    orbit = [t]
    for k in range(m):
        orbit.append(maps[k](orbit[-1]))
    if orbit[-1] != orbit[0]:  # pragma: no cover - algebra
        raise SolverFailed("the orbit of the return map's fixed point does not close")
    orbit = orbit[:m]
    core.orbit = orbit
    for k, (src, tk) in enumerate(zip(edges, orbit)):
        dst = edges[(k + 1) % m]
        if tk in (0, 1):
            core.status = CycleStatus.VERTEX
            core.reason = (f"the return map's fixed point is the vertex at t = {_num(tk)} of e{src}: orbits along "
                           f"{_seq(edges)} run into that corner (outside the model), no periodic orbit")
            core.orbit = []
            return core
        if not 0 < tk < 1:
            core.reason = (f"the fixed point of the return map puts contact {k} at t = {float(tk):.6g} on the line of e{src}, "
                           f"outside the edge: no periodic orbit visits {_seq(edges)} at this heading")
            core.orbit = []  # not a trajectory: report no contact points
            return core
        hit = cast_ray(env, env.exact_point_at(src, tk), cmap.direction(src))
        if hit.vertex is not None:
            core.status = CycleStatus.VERTEX
            core.reason = f"from e{src} at t = {float(tk):.6g} the periodic orbit runs into vertex v{hit.vertex}"
            core.orbit = []
            return core
        if hit.edge != dst or hit.t != orbit[(k + 1) % m]:
            core.reason = (f"from the cycle's contact on e{src} (t = {float(tk):.6g}) the ray first hits e{hit.edge} "
                           f"(t = {float(hit.t):.6g}), not e{dst}: the orbit does not visit {_seq(edges)}")
            core.orbit = []
            return core
        piece = cmap.locate(src, tk)
        if piece is None or cmap.pieces(src)[piece].target != dst:  # pragma: no cover - consistency of two exact methods
            raise SolverFailed(f"piece map and ray cast disagree on e{src} at t = {_num(tk)}")
    # basins: radius around each contact carried along one full cycle inside the pieces
    radii = []
    for r in range(m):
        slope, best = Fraction(1), None
        for j in range(m):
            k = (r + j) % m
            p = cmap.pieces(edges[k])[cmap.locate(edges[k], orbit[k])]
            room = min(orbit[k] - p.lo, p.hi - orbit[k]) / abs(slope)
            best = room if best is None else min(best, room)
            slope *= maps[k].alpha
            if slope == 0:
                break
        radii.append(best)
    core.radii = radii
    if ret.alpha == 1:
        core.status = CycleStatus.NOT_CONTRACTING
        core.reason = (f"the return map on e{edges[0]} is the identity (contraction exactly 1): every nearby start is "
                       "periodic too (a neutral family, e.g. between parallel walls), so no start is attracted: not a limit cycle")
        return core
    if abs(ret.alpha) >= 1:
        core.status = CycleStatus.NOT_CONTRACTING
        core.reason = (f"the periodic orbit {_seq(edges)} exists, but its exact return map has |α| = "
                       f"{float(abs(ret.alpha)):.6g} ≥ 1 (Def. 12): it does not attract")
        return core
    core.status = CycleStatus.FOUND
    return core


def _seq(edges: Sequence[int]) -> str:
    return " → ".join(f"e{e}" for e in (*edges, edges[0]))


def _segments(part: Partition | None, edge: int, lo: Fraction, hi: Fraction | None = None) -> tuple[int, ...]:
    if part is None:
        return ()
    if hi is None:
        return (part.segment_at(edge, lo),)
    ids = part.edge_segments[edge]
    return tuple(k for k in ids if part.segments[k].t1 > lo and part.segments[k].t0 < hi)


def _stage(env: Environment, cmap: _ConstantMap, m: AffineMap, theta: float, part: Partition | None,
           t_from: Fraction | None, whole: bool) -> CycleStage:
    lengths = env.edge_lengths
    c = float(abs(m.alpha)) * float(lengths[m.target]) / float(lengths[m.source])
    if whole or t_from is None:
        src = _segments(part, m.source, Fraction(0), Fraction(1))
        dom = m.domain()
        dst = _segments(part, m.target, *(sorted((m(dom[0]), m(dom[1]))) if dom else (Fraction(0), Fraction(1))))
    else:
        src = _segments(part, m.source, t_from)
        dst = _segments(part, m.target, m(t_from))
    return CycleStage(m.source, m.target, theta, cmap.direction(m.source), m.alpha, m.beta, c, src, dst)


def _rotate(core: _Core) -> int:
    """The rotation putting the smallest (edge, t) contact first."""
    keys = [(e, t) for e, t in zip(core.edges, core.orbit)]
    return min(range(len(keys)), key=keys.__getitem__)


def _build(env: Environment, cmap: _ConstantMap, core: _Core, *, method: str, theta: float, scope: str,
           reason: str, rotate: bool, entry: tuple[CycleStage, ...] = (), start=None, lemma3=None,
           theorem1_d=None, part: Partition | None = None, whole_edges: bool = False,
           bounces_simulated: int | None = None) -> LimitCycle:
    m = len(core.edges)
    r = _rotate(core) if (rotate and core.orbit) else 0
    edges = core.edges[r:] + core.edges[:r]
    stages: tuple[CycleStage, ...] = ()
    points: tuple[CyclePoint, ...] = ()
    c_exact = c_float = None
    if core.maps:
        maps = core.maps[r:] + core.maps[:r]
        orbit = (core.orbit[r:] + core.orbit[:r]) if core.orbit else []
        radii = (core.radii[r:] + core.radii[:r]) if core.radii else []
        stages = tuple(_stage(env, cmap, mk, theta, part, orbit[k] if orbit else None, whole_edges)
                       for k, mk in enumerate(maps))
        if core.ret is not None and core.status in (CycleStatus.FOUND, CycleStatus.NOT_CONTRACTING):
            c_exact = abs(core.ret.alpha)  # only for a real periodic orbit
            c_float = float(c_exact)
        pts = []
        for k, tk in enumerate(orbit):
            basin = None
            if core.status is CycleStatus.FOUND:
                if whole_edges:
                    basin = (Fraction(0), Fraction(1))
                elif radii:
                    basin = (max(Fraction(0), tk - radii[k]), min(Fraction(1), tk + radii[k]))
            pts.append(CyclePoint(edges[k], tk, env.exact_point_at(edges[k], tk), basin))
        points = tuple(pts)
    return LimitCycle(
        env=env, status=core.status, reason=reason, method=method, heading=cmap.heading, theta=theta,
        edges=edges if m else (), stages=stages, entry=entry, points=points, contraction_exact=c_exact,
        contraction=c_float, scope=scope if core.status is CycleStatus.FOUND else "none", start=start,
        lemma3=lemma3, theorem1_d=theorem1_d, bounces_simulated=bounces_simulated,
    )


# ---------------------------------------------------------------------- iteration (floats) and entry (exact)
def _float_orbit(cmap: _ConstantMap, edge: int, t: float, bounces: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Edges, piece indices and parameters of the float orbit (bounces + 1 contacts)."""
    edges = np.empty(bounces + 1, dtype=np.int64)
    piece = np.empty(bounces + 1, dtype=np.int64)
    ts = np.empty(bounces + 1)
    e, x = int(edge), float(t)
    for k in range(bounces + 1):
        splits, targets, a, b = cmap.float_table(e)
        j = bisect.bisect_right(splits, x)
        edges[k], piece[k], ts[k] = e, j, x
        if k == bounces:
            break
        e, x = targets[j], min(1.0, max(0.0, a[j] * x + b[j]))
    return edges, piece, ts


def _detect_period(codes: np.ndarray, window: int) -> tuple[int, int] | None:
    """(start of the periodic tail, period) of the code sequence, judged on its last ``window`` entries."""
    n = len(codes)
    w = min(window, n)
    tail = codes[n - w:]
    for p in range(1, w // 3 + 1):
        if np.array_equal(tail[p:], tail[:-p]):
            mismatch = np.flatnonzero(codes[p:] != codes[:-p])
            start = int(mismatch[-1]) + 1 if len(mismatch) else 0
            return start, p
    return None


def _find_cycle_edges(cmap: _ConstantMap, edge: int, t: float, max_bounces: int):
    """Float iteration with growing horizons: (entry length, edge sequence of one period, float orbit) or None."""
    horizon = min(256, max_bounces)
    while True:
        edges, piece, ts = _float_orbit(cmap, edge, t, horizon)
        codes = edges * (1 << 24) + piece
        found = _detect_period(codes, max(200, horizon // 2))
        if found is not None:
            start, p = found
            return start, tuple(int(e) for e in edges[start:start + p]), (edges, ts)
        if horizon >= max_bounces:
            return None, None, (edges, ts)
        horizon = min(max_bounces, horizon * 4)


def _basins_grid(cycle_edges: Sequence[int], orbit: Sequence[Fraction], radii: Sequence[Fraction]):
    """Per edge, closed grid intervals strictly inside the open basins: {edge: [(lo, hi, phase)]}."""
    out: dict[int, list[tuple[int, int, int]]] = {}
    for k, (e, t, r) in enumerate(zip(cycle_edges, orbit, radii)):
        lo, hi = t - r, t + r
        g_lo = (lo.numerator * _ONE) // lo.denominator + 1
        g_hi = -((-hi.numerator * _ONE) // hi.denominator) - 1
        if g_lo <= g_hi:
            out.setdefault(e, []).append((g_lo, g_hi, k))
    return out


def _prove_entry(cmap: _ConstantMap, edge: int, t: Fraction, basins, max_bounces: int):
    """Carry an exact enclosure of the start's orbit until it lies inside a basin. Returns (steps, phase,
    failure): steps = [(map, enclosure midpoint)] of the bounces taken, phase = the contact whose basin
    was reached; or (None, None, reason)."""
    lo = (t.numerator * _ONE) // t.denominator
    hi = -((-t.numerator * _ONE) // t.denominator)
    e = edge
    steps: list[tuple[AffineMap, Fraction]] = []
    for _ in range(max_bounces + 1):
        for b_lo, b_hi, phase in basins.get(e, ()):
            if b_lo <= lo and hi <= b_hi:
                return steps, phase, None
        if len(steps) == max_bounces:
            break
        image = cmap.grid_image(e, lo, hi)
        if len(image) != 1:
            return None, None, (f"after {len(steps)} bounces the exact enclosure of the start's orbit straddles a ray "
                                "through a vertex: its entry into the cycle is not proved")
        steps.append((cmap.pieces(e)[image[0][3]].map, Fraction(lo + hi, 2 * _ONE)))
        e, lo, hi, _ = image[0]
    return None, None, f"the exact enclosure of the start's orbit did not enter a basin within {max_bounces} bounces"


# ---------------------------------------------------------------------- public: limit_cycle
def _parse_start(env: Environment, start: object) -> tuple[int, Fraction]:
    if start is None:
        return 0, Fraction(1, 2)
    if isinstance(start, str):
        text = start.strip()
        if not text.startswith("e") or text.count(":") != 1:
            raise InvalidBoundarySet(f"start point {start!r}: expected eK:T, e.g. e0:0.5")
        e_text, t_text = text[1:].split(":")
        try:
            e = int(e_text)
        except ValueError:
            raise InvalidBoundarySet(f"start point {start!r}: {e_text!r} is not an edge number") from None
        t = to_fraction(t_text, where=f"start point {start!r}")
    else:
        try:
            e, t = start  # type: ignore[misc]
        except (TypeError, ValueError):
            raise InputError(f"start must be 'eK:T' or (edge, t), got {start!r}") from None
        t = Fraction(t) if isinstance(t, float) else to_fraction(t, where="start t")
    e = int(check_edges(env, [e])[0])
    if not 0 < t < 1:
        raise InvalidBoundarySet(f"start point e{e}:{format_number(t)} is not inside the edge: t must be in (0, 1)")
    return e, t


def _parse_edges(env: Environment, edges: object) -> tuple[int, ...]:
    if isinstance(edges, str):
        items = [x.strip() for x in edges.split(",") if x.strip()]
        try:
            ids = [int(x[1:]) if x.startswith("e") else int(x) for x in items]
        except ValueError:
            raise InvalidBoundarySet(f"edge sequence {edges!r}: expected e0,e1,... (edge ids)") from None
    else:
        ids = list(edges)  # type: ignore[arg-type]
    if len(ids) < 2:
        raise InvalidBoundarySet(f"edge sequence {edges!r}: a cycle needs at least two edges")
    return tuple(int(e) for e in check_edges(env, ids))


def _strictly_convex(env: Environment, clockwise: bool = False) -> Lemma3Range | None:
    try:
        return lemma3_range(env, clockwise=clockwise)
    except InputError:
        return None


def limit_cycle(
    env: Environment,
    theta: HeadingSpec,
    *,
    edges: Sequence[int] | str | None = None,
    method: Method = "auto",
    start: str | tuple | None = None,
    epsilon: float | None = None,
    max_bounces: int = 20000,
    segments: bool = True,
) -> LimitCycle:
    """The limit cycle of the constant rule b = θ (paper §6.1), verified exactly (module docstring).

    Parameters
    ----------
    env
        The environment (any polygon with holes).
    theta
        The heading: radians (a float, taken at the exact direction (cos θ, sin θ) of its binary floats,
        within ~1e-16 rad), an :class:`~solverplan.bounce.dynamics.ExactHeading`, a ``(cos, sin)`` pair,
        or text (``"0.3"``, ``"pi/8"``, ``"tan:1/3"``, ``"dir:12,5"``: :func:`~solverplan.bounce.dynamics.parse_heading`).
    edges
        Ask for the cycle along this edge sequence (``"e0,e2,e5"`` or ids): method ``edges``.
    method
        ``auto`` (edges if given, else ``theorem1`` for a strictly convex polygon without holes, else
        ``iterate``), or one of ``theorem1`` / ``iterate`` / ``edges``.
    start
        Iterate mode: where the robot starts, ``"eK:T"`` or ``(edge, t)`` with exact t ∈ (0, 1) (default
        the middle of e0).
    epsilon
        Also report Cor. 4's cycle counts for this width (arc length).
    max_bounces
        Iterate mode: the float iteration's budget (and the exact entry's).
    segments
        Label stages with P′ segment ids (Algorithm 1's partition); False skips the partition.

    Returns
    -------
    LimitCycle
        ``status`` says whether a stable cycle was found; never raises for a heading that merely fails.

    Raises
    ------
    InputError
        Bad heading (outside (0, π)), unknown edges, a bad start, ``theorem1`` on a non-convex polygon.
    """
    heading = parse_heading(theta)
    if not isinstance(heading, ExactHeading):
        value = heading
        heading = ExactHeading.from_float(heading)
    else:
        value = heading.theta
    if method not in ("auto", "theorem1", "iterate", "edges"):
        raise InputError(f"unknown cycle method {method!r}: use auto, theorem1, iterate or edges")
    if isinstance(max_bounces, bool) or not isinstance(max_bounces, int) or max_bounces < 1:
        raise InputError(f"max_bounces must be a positive integer, got {max_bounces!r}")
    seq = _parse_edges(env, edges) if edges is not None else None
    lemma3 = _strictly_convex(env, clockwise=heading.theta > math.pi / 2)
    if method == "auto":
        method = "edges" if seq is not None else ("theorem1" if lemma3 is not None else "iterate")
    if method == "edges" and seq is None:
        raise InputError("method 'edges' needs an edge sequence (edges=...)")
    if method == "theorem1":
        if lemma3 is None:
            lemma3_range(env)  # raises the reason
        if seq is not None:
            raise InputError("method 'theorem1' visits every edge in CCW order: drop edges=..., or use method 'edges'")
    cmap = _ConstantMap(env, heading)
    part = partition(env) if segments else None
    if method == "theorem1":
        result = _theorem1(env, cmap, value, lemma3, part)
    elif method == "edges":
        core = _cycle_along(env, cmap, seq, CycleStatus.NOT_REALISED)
        reason = core.reason or (
            "the cycle is verified exactly and attracts every start in its basins; starts elsewhere are not covered"
        )
        result = _build(env, cmap, core, method="edges", theta=value, scope="basin", reason=reason, rotate=False,
                        lemma3=lemma3, part=part)
    else:
        result = _iterate(env, cmap, value, _parse_start(env, start), max_bounces, lemma3, part)
    return result.with_epsilon(epsilon) if epsilon is not None else result


def _keeps_edge_order(env: Environment, cmap: _ConstantMap, clockwise: bool) -> int | None:
    """Exact Lemma 3 edge-order test: None if from every open edge e_i every ray reaches the open next edge
    (CCW: θ ≤ ∠v_{i+2} v_i v_{i+1}, i.e. d_i is not counter-clockwise of v_{i+2} − v_i; CW, the mirror image:
    d_i is not clockwise of v_{i−1} − v_{i+1}; solverplan.proofs.lemma3_convex_order), else the first edge i where it fails."""
    verts = env.exact_vertices
    n = env.n_edges
    for i in range(n):
        d = cmap.direction(i)
        a, b = (verts[(i + 1) % n], verts[i - 1]) if clockwise else (verts[i], verts[(i + 2) % n])
        w = (b[0] - a[0], b[1] - a[1])
        cross = w[0] * d[1] - w[1] * d[0]
        if (cross < 0) if clockwise else (cross > 0):
            return i
    return None


def limit_cycles(
    env: Environment,
    theta: HeadingSpec,
    starts: Sequence[tuple[int, object]],
    *,
    max_bounces: int = 20000,
    limit: int = 32,
) -> tuple[LimitCycle, ...]:
    """The distinct stable cycles the constant rule b = θ reaches from ``starts`` ((edge, t) pairs, t ∈ (0, 1);
    others are skipped), at most ``limit`` of the starts examined; the first item is :func:`limit_cycle`'s
    default answer (alone when it already covers every start). Each is verified as in :func:`limit_cycle`.

    >>> dumbbell = Environment.from_coords([(0, 0), (4, 0), (4, 1), (8, 1), (8, 0), (12, 0), (12, 4), (8, 4), (8, 3),
    ...                                     (4, 3), (4, 4), (0, 4)])
    >>> [c.edges for c in limit_cycles(dumbbell, "tan:1/4", [(0, 0.5), (5, 0.5)])]     # one cycle per room
    [(0, 1, 10, 11), (4, 5, 6, 7)]
    """
    first = limit_cycle(env, theta, max_bounces=max_bounces)
    out = [first]
    if first.scope == "every-start":
        return tuple(out)
    seen = {(frozenset(zip(c.edges, (p.t for p in c.points)))) for c in out if c.found}
    for edge, t in list(starts)[:limit]:
        try:
            cycle = limit_cycle(env, first.heading, method="iterate", start=(int(edge), t), max_bounces=max_bounces)
        except InputError:
            continue
        if not cycle.found:
            continue
        key = frozenset(zip(cycle.edges, (p.t for p in cycle.points)))
        if key not in seen:
            seen.add(key)
            out.append(replace(cycle, theta=first.theta))
    return tuple(out)


def _theorem1(env, cmap, value, lemma3: Lemma3Range, part) -> LimitCycle:
    n = env.n_edges
    clockwise = lemma3.clockwise
    order = tuple((-k) % n for k in range(n)) if clockwise else tuple(range(n))
    core = _cycle_along(env, cmap, order, CycleStatus.EDGE_ORDER_BROKEN)
    theta = cmap.heading.theta
    inside = lemma3.contains(theta)
    d = None
    if not clockwise:
        try:
            d = theorem1_fixed_point(env, value).d
        except InputError:
            d = None
    broken_at = _keeps_edge_order(env, cmap, clockwise)
    lo, hi = lemma3.interval
    sense = "CW" if clockwise else "CCW"
    where = f"({lo:.6g}, {hi:.6g})"
    if core.status is CycleStatus.FOUND and broken_at is None:
        if inside:
            reason = f"θ is inside Lemma 3's {sense} range {where}: every start converges (Theorem 1)"
        else:
            reason = (f"θ is outside Lemma 3's {sense} range {where}: {lemma3.reason_outside(theta)}; but every start "
                      f"still visits the edges in {sense} order (within the edge-order bound {lemma3.order_bound:.6g}, checked "
                      f"exactly) and the whole return map contracts (|α| = {float(abs(core.ret.alpha)):.6g} < 1, Def. 12), so "
                      "every start converges (Lemma 3's per-step condition is sufficient, not necessary)")
        return _build(env, cmap, core, method="theorem1", theta=value, scope="every-start", reason=reason,
                      rotate=False, lemma3=lemma3, theorem1_d=d, part=part, whole_edges=True)
    if inside and min(theta - lo, hi - theta) > lemma3.bound * 1e-9:  # pragma: no cover - would contradict Lemma 3
        raise SolverFailed(f"θ = {value!r} is inside Lemma 3's range but the {sense} cycle failed: {core.reason}")
    outside = f"θ is outside Lemma 3's {sense} range {where}: {lemma3.reason_outside(theta)}"
    if core.status is CycleStatus.FOUND:
        nxt = (broken_at - 1) % n if clockwise else (broken_at + 1) % n
        reason = (f"{outside}. The {sense} cycle is verified exactly and attracts the starts in its basins, but some "
                  f"starts on e{broken_at} miss e{nxt}: convergence from every start is not guaranteed")
    else:
        reason = f"{outside}. {core.reason} (method 'iterate' finds the cycle this heading does reach, if any)"
    return _build(env, cmap, core, method="theorem1", theta=value, scope="basin", reason=reason, rotate=False,
                  lemma3=lemma3, theorem1_d=d, part=part)


def _iterate(env, cmap: _ConstantMap, value: float, start: tuple[int, Fraction], max_bounces: int, lemma3, part) -> LimitCycle:
    e0, t0 = start
    start_index, cycle_edges, (f_edges, f_ts) = _find_cycle_edges(cmap, e0, float(t0), max_bounces)
    if cycle_edges is None:
        tail = " → ".join(f"e{e}" for e in f_edges[-12:])
        core = _Core(CycleStatus.NO_CYCLE, "", ())
        return _build(env, cmap, core, method="iterate", theta=value, scope="none", rotate=False, start=start,
                      lemma3=lemma3, part=part, bounces_simulated=len(f_edges) - 1,
                      reason=(f"the orbit from e{e0}:{float(t0):.6g} did not settle into a periodic edge sequence within "
                              f"{max_bounces} bounces (last edges {tail}): no attracting cycle was reached (a neutral "
                              "orbit, e.g. between parallel walls, never settles)"))
    core = _cycle_along(env, cmap, cycle_edges, CycleStatus.NOT_REALISED, hint=Fraction(float(f_ts[start_index])))
    if core.status is not CycleStatus.FOUND:
        return _build(env, cmap, core, method="iterate", theta=value, scope="none", rotate=True, start=start,
                      lemma3=lemma3, part=part, reason=f"the float orbit settled on {_seq(cycle_edges)}, but {core.reason}")
    r = _rotate(core)
    basins = _basins_grid(core.edges, core.orbit, core.radii)
    steps, phase, failure = _prove_entry(cmap, e0, t0, basins, max_bounces)
    entry: tuple[CycleStage, ...] = ()
    if steps is not None:
        # walk on from the basin reached to the rotated cycle's first contact
        extra = (r - phase) % len(core.edges)
        stages = [_stage(env, cmap, mk, value, part, mid, False) for mk, mid in steps]
        t = core.orbit[phase]
        for j in range(extra):
            mk = core.maps[(phase + j) % len(core.maps)]
            stages.append(_stage(env, cmap, mk, value, part, t, False))
            t = mk(t)
        entry = tuple(stages)
        reason = (f"the cycle is verified exactly; the start e{e0}:{float(t0):.6g} provably enters its basin after "
                  f"{len(steps)} bounces (exact enclosure), and every start in the basins converges")
        scope = "start+basin"
    else:
        reason = f"the cycle is verified exactly and attracts every start in its basins; {failure}"
        scope = "basin"
    return _build(env, cmap, core, method="iterate", theta=value, scope=scope, reason=reason, rotate=True,
                  entry=entry, start=start, lemma3=lemma3, part=part, bounces_simulated=None)


# ---------------------------------------------------------------------- Prop. 4: a constant controller
DEFAULT_CONTROLLER_TANGENTS: tuple[str, ...] = (
    "1/4", "1/3", "1/5", "1/2", "1/6", "1/8", "2/3", "1/10", "1", "1/16", "1/32", "1/64",
    "-1/4", "-1/3", "-1/5", "-1/2", "-1/6", "-1/8", "-2/3", "-1/10", "-1", "-1/16", "-1/32", "-1/64",
)
"""Tangents of the headings :func:`constant_controller` tries, in order: small headings first (the robot
runs close to the walls, where Prop. 4's proof looks for contraction), then their mirror images (θ near π)."""


@dataclass(frozen=True)
class ConstantController:
    """A constant heading under which every start converges to a verified limit cycle (Prop. 4), or the
    best attempt. ``proved``: the exact enclosure of f_θ^k(∂P) lay inside the cycles' basins after
    ``bounces`` bounces. ``tried`` lists (heading spec, outcome) for every heading tried."""

    env: Environment
    heading: ExactHeading | None
    cycles: tuple[LimitCycle, ...]
    proved: bool
    bounces: int | None
    tried: tuple[tuple[str, str], ...]

    def to_json(self) -> dict:
        return {
            "status": "found" if self.proved else "not-proved",
            "environment": self.env.name,
            "theta": None if self.heading is None else self.heading.theta,
            "theta_exact": None if self.heading is None else self.heading.spec(),
            "proved": self.proved,
            "bounces": self.bounces,
            "cycles": [c.to_json() for c in self.cycles],
            "tried": [{"theta_exact": s, "outcome": o} for s, o in self.tried],
        }

    def to_text(self, *, width: int = 100) -> str:
        head = (f"constant controller θ = {self.heading.theta:.12g} ({self.heading.spec()}): "
                if self.heading is not None else "no constant controller: ")
        lines = [head + (f"every start enters one of {len(self.cycles)} verified cycle(s) within {self.bounces} bounces"
                         if self.proved else "not proved")]
        for c in self.cycles:
            lines.append(f"  cycle {_seq(c.edges)}: contraction {c.contraction:.6g}")
        for s, o in self.tried:
            lines.append(f"  tried {s}: {o}")
        return "\n".join(lines) + "\n"


def _global_proof(env: Environment, cmap: _ConstantMap, *, max_steps: int, max_intervals: int):
    """Iterate an exact enclosure of f_θ^k(∂P), removing what lies in certified basins; discover cycles
    from what is left. Returns (cycles, proved, bounces, outcome text)."""
    cores: list[_Core] = []
    keys: set[tuple] = set()
    basins: dict[int, list[tuple[int, int, int]]] = {}

    def discover(S) -> None:
        for e, lo, hi in sorted(S, key=lambda x: x[1] - x[2])[:6]:
            _, cyc, _ = _find_cycle_edges(cmap, e, (lo + hi) / (2 * _ONE), 4096)
            if cyc is None:
                continue
            core = _cycle_along(env, cmap, cyc, CycleStatus.NOT_REALISED)
            if core.status is not CycleStatus.FOUND:
                continue
            r = _rotate(core)
            key = (core.edges[r:] + core.edges[:r], core.orbit[r])
            if key in keys:
                continue
            keys.add(key)
            cores.append(core)
            for be, items in _basins_grid(core.edges, core.orbit, core.radii).items():
                basins.setdefault(be, []).extend(items)

    def subtract(S):
        kept = []
        for e, lo, hi in S:
            parts = [(lo, hi)]
            for b_lo, b_hi, _ in basins.get(e, ()):
                nxt = []
                for a, b in parts:
                    if b < b_lo or a > b_hi:
                        nxt.append((a, b))
                        continue
                    if a < b_lo:
                        nxt.append((a, b_lo))
                    if b > b_hi:
                        nxt.append((b_hi, b))
                parts = nxt
            kept.extend((e, a, b) for a, b in parts)
        return kept

    S = [(e, 0, _ONE) for e in range(env.n_edges)]
    step, discovery = 0, 2
    while True:
        S = subtract(S)
        if S and step >= discovery:
            discover(S)
            discovery = 2 * discovery
            S = subtract(S)
        if not S:
            return cores, True, step, f"every start is in a basin after {step} bounces"
        if step == max_steps:
            break
        S = _merge([(e, a, b) for lo_e, lo, hi in S for e, a, b, _ in cmap.grid_image(lo_e, lo, hi)])
        step += 1
        if len(S) > max_intervals:
            return cores, False, step, f"the enclosure grew past {max_intervals} intervals"
    measure = sum((hi - lo) / _ONE * float(env.edge_lengths[e]) for e, lo, hi in S)
    return cores, False, max_steps, (f"after {max_steps} bounces {len(S)} intervals (total length {measure:.3g}) "
                                     "were still outside the basins of the cycles found")


def constant_controller(
    env: Environment,
    *,
    tangents: Sequence[str] | None = None,
    max_steps: int = 400,
    max_intervals: int = 20000,
    epsilon: float | None = None,
) -> ConstantController:
    """Prop. 4 made constructive: a constant heading θ and the cycle(s) it drives **every** start into.

    For each candidate heading (exact, tan θ from ``tangents``, default
    :data:`DEFAULT_CONTROLLER_TANGENTS`) build f_θ exactly and iterate an exact enclosure S_k ⊇ f_θ^k(∂P)
    (unions of intervals on a 2⁻⁹⁶ grid, rounded outward, split at the pieces' ends). Cycles are discovered
    by float iteration from the widest parts of S_k and verified exactly (:func:`limit_cycle`'s checks,
    with their basins); the parts of S_k inside a basin are dropped. When S_k is empty every start —
    except the finitely many rays through vertices, outside the model — has entered a basin within k
    bounces and converges to a verified stable cycle: the first heading for which that happens is returned
    with ``proved=True``.

    **The argument and its limits.** The paper states Prop. 4 per start ("for all points s … a constant
    fixed-angle controller exists"): the heading may depend on s. Its proof picks, per segment of P′, the
    safe contracting headings next to the wall (Prop. 3, Lemma 2) and concludes that one constant heading
    works everywhere; that does not follow — a constant small heading hugs the wall only up to a *reflex*
    vertex, where the ray leaves across the room, and the headings that are safe from different segments
    need not share a value. This function asks for more than the paper (one heading for **every** start)
    and proves it per polygon instead of by a general argument. It can fail for a reason the paper's proof
    misses: two long parallel walls facing each other carry *neutral* period-2 orbits (the two bounces
    compose to the identity, contraction exactly 1), which never converge — in a 50 × 2 corridor every
    heading with tan θ > 2/50 leaves such orbits, and only shallower ones reach the corners (where
    consecutive right transitions contract). A polygon where every candidate fails gets ``proved=False``
    with the reasons. Several cycles may share the boundary (different starts, different cycles); all are
    reported. Rays through vertices (finitely many per heading and edge) are outside the model, as always.

    >>> room = Environment.from_coords([[0, 0], [12, 0], [12, 9], [0, 9]], [[[4, 3], [4, 5], [7, 6], [8, 3]]])
    >>> ctrl = constant_controller(room)
    >>> ctrl.proved, ctrl.heading.spec(), [c.edges for c in ctrl.cycles]
    (True, 'tan:0.25', [(0, 1, 2, 3)])
    """
    if epsilon is not None:
        _check_epsilon(epsilon)
    specs = tuple(tangents) if tangents is not None else DEFAULT_CONTROLLER_TANGENTS
    if not specs:
        raise InputError("constant_controller needs at least one candidate tangent")
    part = partition(env)
    tried: list[tuple[str, str]] = []
    for spec in specs:
        heading = ExactHeading.from_tangent(spec)
        cmap = _ConstantMap(env, heading)
        cores, proved, steps, outcome = _global_proof(env, cmap, max_steps=max_steps, max_intervals=max_intervals)
        tried.append((heading.spec(), outcome))
        logger.info("constant controller %s: %s", heading.spec(), outcome)
        if proved:
            cycles = tuple(
                _build(env, cmap, core, method="iterate", theta=heading.theta, scope="every-start", rotate=True, part=part,
                       reason=f"every start converges to one of the {len(cores)} verified cycle(s) of this heading "
                              f"(exact enclosure of all orbits inside their basins after {steps} bounces)")
                .with_epsilon(epsilon)
                for core in cores
            )
            return ConstantController(env, heading, cycles, True, steps, tuple(tried))
    return ConstantController(env, None, (), False, None, tuple(tried))
