"""Result building blocks shared by patrol, funnel and localisation answers (private).

Plain plan stages and optimality claims are :class:`solverplan.plan.result.Stage` and
:class:`solverplan.plan.result.Optimality`; a :class:`PositionStage` is a stage of a funnel or localisation
strategy: a plan stage in the sense of docs/contract.md (``from_segments``, ``to_segments``, ``interval``) that also
carries the exact ``positions`` after it and the exact cones (rational world directions) it was computed with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from solverplan.bounce.cones import heading_cone
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
