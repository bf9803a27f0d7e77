"""The exact cycle of the constant rule along an edge sequence, its basins, and a start's proved entry
into them (paper §6.1; used by :mod:`solverplan.bounce.cycles` and :mod:`solverplan.bounce.controller`).

**A cycle along an edge sequence.** Compose the affine maps of f_θ (:class:`~solverplan.bounce.constant_map.ConstantMap`)
along the sequence e_0 → e_1 → … → e_{m−1} → e_0 into the return map R(t) = α t + β on e_0; its fixed
point is t* = β / (1 − α) and its contraction is |α| = Π C_k (Def. 12; in arc length the edge lengths
cancel). The cycle is **verified** (:func:`cycle_along`) when (1) every point t_k of the orbit of t* lies
strictly inside its edge and strictly inside a piece of f_θ whose target is e_{k+1}, (2) an exact ray cast
from each t_k along d_k first hits e_{k+1}, at no vertex, exactly at t_{k+1}, and the orbit closes
(t_m = t_0), and (3) |α| < 1. Then the orbit is a true periodic trajectory of the robot and it attracts:
the open interval of radius ρ_r = min_k dist(t_{r+k}, ends of its piece) / |α_r ⋯ α_{r+k−1}| around each
contact point t_r is carried along the whole sequence inside the pieces, and R maps the symmetric interval
into itself (|α| < 1), so every start in it converges to the cycle (the **basin**, exact ends).

**Finding and entering a cycle.** :func:`find_cycle_edges` iterates f_θ in floats and detects the
eventually periodic sequence of pieces (a candidate only: :func:`cycle_along` decides); :func:`prove_entry`
carries an exact grid enclosure of a start's orbit until it lies inside a basin.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import NamedTuple, Sequence

import numpy as np

from solverplan.bounce.constant_map import GRID_ONE, ConstantMap
from solverplan.bounce.transitions import AffineMap, affine_map
from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import format_number
from solverplan.geometry.raycast import cast_ray
from solverplan.result import Status

__all__ = ["CycleCore", "cycle_along", "rotation", "edge_sequence_text", "find_cycle_edges", "basins_grid",
           "Entry", "prove_entry", "check_epsilon"]


def check_epsilon(epsilon: object) -> float:
    """``epsilon`` as a positive finite float (a length); :class:`InputError` otherwise."""
    try:
        eps = float(epsilon)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"epsilon {epsilon!r} is not a number") from None
    if not (math.isfinite(eps) and eps > 0):
        raise InputError(f"epsilon {epsilon!r} must be a positive length")
    return eps


# ---------------------------------------------------------------------- the exact cycle along an edge sequence
@dataclass
class CycleCore:
    """The outcome of :func:`cycle_along`: the ``status`` (``found`` or why not) and ``reason``; the
    sequence's exact affine ``maps`` and return map ``ret``; the exact ``orbit`` of the fixed point (empty
    when it is not a trajectory) and the basin ``radii`` around each contact (t units of its edge)."""

    status: Status
    reason: str
    edges: tuple[int, ...]
    maps: list[AffineMap] = field(default_factory=list)
    ret: AffineMap | None = None
    orbit: list[Fraction] = field(default_factory=list)
    radii: list[Fraction] = field(default_factory=list)


def cycle_along(env: Environment, cmap: ConstantMap, edges: Sequence[int], broken: Status,
                hint: Fraction | None = None) -> CycleCore:
    """Compose, find the fixed point, verify it exactly (module docstring); ``broken`` is the status for
    an orbit that leaves the sequence."""
    edges = tuple(int(e) for e in edges)
    m = len(edges)
    maps: list[AffineMap] = []
    for k, src in enumerate(edges):
        dst = edges[(k + 1) % m]
        if dst == src:
            return CycleCore(broken, f"e{src} → e{dst}: a ray cannot land on the edge it leaves", edges)
        try:
            maps.append(affine_map(env, src, cmap.direction(src), dst))
        except InputError as exc:
            return CycleCore(broken, f"step e{src} → e{dst}: {exc}", edges)
    ret = maps[0]
    for mk in maps[1:]:
        ret = ret.then(mk)
    core = CycleCore(broken, "", edges, maps, ret)
    if ret.alpha == 1 and ret.beta != 0:
        core.reason = f"the return map on e{edges[0]} is the translation t ↦ t + {format_number(ret.beta)}: no periodic orbit"
        return core
    # α = 1, β = 0: the identity — every point is periodic; check one (the iteration's, or the middle)
    fixed = ret.fixed_point()
    t: Fraction = fixed if fixed is not None else (hint if hint is not None else Fraction(1, 2))
    orbit: list[Fraction] = [t]
    for k in range(m):
        orbit.append(maps[k](orbit[-1]))
    if orbit[-1] != orbit[0]:  # pragma: no cover - algebra
        raise SolverFailed("the orbit of the return map's fixed point does not close")
    orbit = orbit[:m]
    core.orbit = orbit
    for k, (src, tk) in enumerate(zip(edges, orbit)):
        dst = edges[(k + 1) % m]
        if tk in (0, 1):
            core.status = Status.VERTEX
            core.reason = (f"the return map's fixed point is the vertex at t = {format_number(tk)} of e{src}: orbits along "
                           f"{edge_sequence_text(edges)} run into that corner (outside the model), no periodic orbit")
            core.orbit = []
            return core
        if not 0 < tk < 1:
            core.reason = (f"the fixed point of the return map puts contact {k} at t = {float(tk):.6g} on the line of e{src}, "
                           f"outside the edge: no periodic orbit visits {edge_sequence_text(edges)} at this heading")
            core.orbit = []  # not a trajectory: report no contact points
            return core
        hit = cast_ray(env, env.exact_point_at(src, tk), cmap.direction(src))
        if hit.vertex is not None:
            core.status = Status.VERTEX
            core.reason = f"from e{src} at t = {float(tk):.6g} the periodic orbit runs into vertex v{hit.vertex}"
            core.orbit = []
            return core
        if hit.edge != dst or hit.t != orbit[(k + 1) % m]:
            core.reason = (f"from the cycle's contact on e{src} (t = {float(tk):.6g}) the ray first hits e{hit.edge} "
                           f"(t = {float(hit.t):.6g}), not e{dst}: the orbit does not visit {edge_sequence_text(edges)}")
            core.orbit = []
            return core
        piece = cmap.locate(src, tk)
        if piece is None or cmap.pieces(src)[piece].target != dst:  # pragma: no cover - consistency of two exact methods
            raise SolverFailed(f"piece map and ray cast disagree on e{src} at t = {format_number(tk)}")
    # basins: radius around each contact carried along one full cycle inside the pieces
    radii: list[Fraction] = []
    for r in range(m):
        slope, best = Fraction(1), Fraction(-1)  # -1: no room measured yet (rooms are positive)
        for j in range(m):
            k = (r + j) % m
            index = cmap.locate(edges[k], orbit[k])
            assert index is not None  # every contact was located strictly inside a piece above
            p = cmap.pieces(edges[k])[index]
            room = min(orbit[k] - p.lo, p.hi - orbit[k]) / abs(slope)
            best = room if best < 0 else min(best, room)
            slope *= maps[k].alpha
            if slope == 0:
                break
        radii.append(best)
    core.radii = radii
    if ret.alpha == 1:
        core.status = Status.NOT_CONTRACTING
        core.reason = (f"the return map on e{edges[0]} is the identity (contraction exactly 1): every nearby start is "
                       "periodic too (a neutral family, e.g. between parallel walls), so no start is attracted: not a limit cycle")
        return core
    if abs(ret.alpha) >= 1:
        core.status = Status.NOT_CONTRACTING
        core.reason = (f"the periodic orbit {edge_sequence_text(edges)} exists, but its exact return map has |α| = "
                       f"{float(abs(ret.alpha)):.6g} ≥ 1 (Def. 12): it does not attract")
        return core
    core.status = Status.FOUND
    return core


def edge_sequence_text(edges: Sequence[int]) -> str:
    """``e0 → e1 → e0``: a cycle's edges, back to the first."""
    return " → ".join(f"e{e}" for e in (*edges, edges[0]))


def rotation(core: CycleCore) -> int:
    """The rotation putting the smallest (edge, t) contact first."""
    keys = [(e, t) for e, t in zip(core.edges, core.orbit)]
    return min(range(len(keys)), key=keys.__getitem__)


# ---------------------------------------------------------------------- iteration (floats) and entry (exact)
def _float_orbit(cmap: ConstantMap, edge: int, t: float, bounces: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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


def find_cycle_edges(cmap: ConstantMap, edge: int, t: float, max_bounces: int):
    """Float iteration of f_θ from (``edge``, ``t``) with growing horizons, at most ``max_bounces`` bounces:
    (index where the periodic tail starts, edge sequence of one period, (edges, ts) of the float orbit), or
    (None, None, (edges, ts)) when no period showed within the budget."""
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


def basins_grid(cycle_edges: Sequence[int], orbit: Sequence[Fraction],
                radii: Sequence[Fraction]) -> dict[int, list[tuple[int, int, int]]]:
    """Per edge, closed grid intervals strictly inside the open basins: {edge: [(lo, hi, phase)]}."""
    out: dict[int, list[tuple[int, int, int]]] = {}
    for k, (e, t, r) in enumerate(zip(cycle_edges, orbit, radii)):
        lo, hi = t - r, t + r
        g_lo = (lo.numerator * GRID_ONE) // lo.denominator + 1
        g_hi = -((-hi.numerator * GRID_ONE) // hi.denominator) - 1
        if g_lo <= g_hi:
            out.setdefault(e, []).append((g_lo, g_hi, k))
    return out


class Entry(NamedTuple):
    """What :func:`prove_entry` found: the bounces taken, ``steps`` = [(exact map, enclosure midpoint)],
    and the ``phase`` (contact index) whose basin the enclosure reached; or, when not proved, ``steps``
    and ``phase`` None, the ``failure`` in words and whether the bounce budget was what ran out
    (``budget_hit``)."""

    steps: list[tuple[AffineMap, Fraction]] | None
    phase: int | None
    failure: str | None = None
    budget_hit: bool = False


def prove_entry(cmap: ConstantMap, edge: int, t: Fraction, basins, max_bounces: int) -> Entry:
    """Carry an exact enclosure of the start (``edge``, ``t``)'s orbit (a grid interval, rounded outward)
    until it lies inside one of ``basins`` (:func:`basins_grid`), for at most ``max_bounces`` bounces."""
    lo = (t.numerator * GRID_ONE) // t.denominator
    hi = -((-t.numerator * GRID_ONE) // t.denominator)
    e = edge
    steps: list[tuple[AffineMap, Fraction]] = []
    for _ in range(max_bounces + 1):
        for b_lo, b_hi, phase in basins.get(e, ()):
            if b_lo <= lo and hi <= b_hi:
                return Entry(steps, phase)
        if len(steps) == max_bounces:
            break
        image = cmap.grid_image(e, lo, hi)
        if len(image) != 1:
            return Entry(None, None, f"after {len(steps)} bounces the exact enclosure of the start's orbit straddles "
                                     "a ray through a vertex: its entry into the cycle is not proved")
        steps.append((cmap.pieces(e)[image[0][3]].map, Fraction(lo + hi, 2 * GRID_ONE)))
        e, lo, hi, _ = image[0]
    return Entry(None, None, f"the exact enclosure of the start's orbit did not enter a basin within {max_bounces} "
                             "bounces", budget_hit=True)
