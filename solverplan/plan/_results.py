"""Result building blocks shared by patrol, funnel and localisation answers (private).

Plain plan stages and optimality claims are :class:`solverplan.plan.result.Stage` and
:class:`solverplan.plan.result.Optimality`; a :class:`PositionStage` is a stage of a funnel or localisation
strategy: a plan stage in the sense of docs/contract.md (``from_segments``, ``to_segments``, ``interval``) that also
carries the exact ``positions`` after it and the exact cones (rational world directions) it was computed with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

from solverplan.interval import Interval
from solverplan.environment import BoundaryPiece
from solverplan.exact import ExactPoint, format_number

__all__ = ["PositionStage", "SAFE_END_MARGIN", "piece_json", "heading_cone", "finite"]

SAFE_END_MARGIN = 1e-6
"""Radians kept away from both ends of every safe interval: its open ends (0 or π, Cor. 1's intervals at convex
corners), so that every interval a planner returns lies strictly inside (0, π), and its closed ends, where
corner rays land exactly on a vertex of the target (floating-point rollouts would graze it)."""


def finite(x: float | None):
    if x is None:
        return None
    return x if math.isfinite(x) else None


def piece_json(piece: BoundaryPiece) -> dict:
    """A boundary piece as JSON: edge, float t0/t1 and their exact text."""
    return {"edge": piece.edge, "t0": float(piece.t0), "t1": float(piece.t1),
            "t0_exact": format_number(piece.t0), "t1_exact": format_number(piece.t1)}


@dataclass(frozen=True, slots=True)
class PositionStage:
    """One stage of a funnel or localisation strategy: from the exact position pieces ``sources`` (on
    ``from_segments``), one heading interval (radians, CCW from the edge the robot is on), each source piece
    with its exact world-frame cone ``cones[i]`` = (d_lo, d_hi) inside the interval, landing on
    ``target_edges[i]``; ``positions``: the exact pieces the robot may be on afterwards (on ``to_segments``).
    """

    from_segments: tuple[int, ...]
    to_segments: tuple[int, ...]
    interval: Interval
    positions: tuple[BoundaryPiece, ...]
    sources: tuple[BoundaryPiece, ...]
    cones: tuple[tuple[ExactPoint, ExactPoint], ...]
    target_edges: tuple[int, ...]

    def to_json(self) -> dict:
        return {
            "from_segments": list(self.from_segments),
            "to_segments": list(self.to_segments),
            "interval": [self.interval.lo, self.interval.hi],
            "positions": [piece_json(p) for p in self.positions],
        }


def heading_cone(edge_vector: tuple[Fraction, Fraction], interval: Interval, *,
                 outside: bool = False) -> tuple[ExactPoint, ExactPoint]:
    """Exact world directions at the two ends of a heading interval from an edge: the simplest rationals
    u = cot θ within 1e-13 of the ends' cotangents, turned back by d = u·E + E⊥ (E⊥ is E rotated by +90°, of
    the same length, so the heading of d is exactly acot u). By default the cone lies *inside* the float interval
    (a worst case over it never exceeds the float one); with ``outside`` it *contains* the interval, so every
    heading a robot may execute from the float interval is in the exact cone (funnels: the exact positions then
    hold every landing point). Small numbers keep exact arithmetic over long strategies cheap."""
    lo, hi = float(interval.lo), float(interval.hi)
    margin = 1e-13 if outside else min(1e-13, (hi - lo) / 4)
    if outside:
        u_of_lo = _simplest_in(_cot(lo), _cot(lo - margin))  # cot decreases: outside is the larger side
        u_of_hi = _simplest_in(_cot(hi + margin), _cot(hi))
    else:
        u_of_lo = _simplest_in(_cot(lo + margin), _cot(lo))
        u_of_hi = _simplest_in(_cot(hi), _cot(hi - margin))
    return _turn(edge_vector, u_of_lo), _turn(edge_vector, u_of_hi)


def _cot(theta: float) -> Fraction:
    if theta == math.pi / 2:
        return Fraction(0)
    return Fraction(math.cos(theta) / math.sin(theta))


def _turn(e: tuple[Fraction, Fraction], u: Fraction) -> ExactPoint:
    ex, ey = Fraction(e[0]), Fraction(e[1])
    x, y = u * ex - ey, u * ey + ex
    den = math.lcm(x.denominator, y.denominator)
    xi, yi = int(x * den), int(y * den)
    g = math.gcd(xi, yi) or 1
    return (Fraction(xi // g), Fraction(yi // g))


def _simplest_in(a: Fraction, b: Fraction) -> Fraction:
    """The rational with the smallest denominator in [min(a, b), max(a, b)] (continued fractions)."""
    lo, hi = (a, b) if a <= b else (b, a)
    if lo <= 0 <= hi:
        return Fraction(0)
    if hi < 0:
        return -_simplest_in(-hi, -lo)
    whole = math.floor(lo)
    if whole == lo:
        return Fraction(whole)
    if whole + 1 <= hi:
        return Fraction(whole + 1)
    return whole + 1 / _simplest_in(1 / (hi - whole), 1 / (lo - whole))
