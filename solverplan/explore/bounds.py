"""The cost of an exploration and the paper's bounds on the number of views.

Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility":

- the cost of an exploration is the time T = t_M·N_M + t_S·N_S + d/r (N_M straight moves planned in t_M each,
  N_S views sensed in t_S each, path length d driven at speed r);
- Algorithm A takes at most r + 1 views, r the number of reflex vertices (Theorem 1), and its competitive ratio
  is (r + 1)/2 (Theorem 2);
- Algorithm B with range R takes at most ⌊8·Area/(3R²)⌋ + ⌊Perimeter/R⌋ + r + h + 1 views (Lemma 4); any
  algorithm needs at least ⌈Area/(πR²)⌉ (Theorem 5), so the ratio is at most
  8π/3 + πR·Perimeter/Area + (r + h + 1)·πR²/Area.

Lengths are in the environment's unit, areas in its square, times in any one unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from solverplan.environment import Environment
from solverplan.errors import InputError

__all__ = ["Cost", "exploration_cost", "views_bound", "range_views_bound", "range_views_lower_bound",
           "range_ratio_bound", "depth_first_ratio"]


@dataclass(frozen=True, slots=True)
class Cost:
    """The time T = t_M·N_M + t_S·N_S + d/r of an exploration, and its three terms (time units)."""

    planning: float
    sensing: float
    driving: float

    @property
    def total(self) -> float:
        return self.planning + self.sensing + self.driving

    def to_json(self) -> dict:
        return {"total": self.total, "planning": self.planning, "sensing": self.sensing, "driving": self.driving}


def exploration_cost(moves: int, views: int, path_length: float, *, t_move: float = 1.0, t_sense: float = 1.0,
                     speed: float = 1.0) -> Cost:
    """T = t_M·N_M + t_S·N_S + d/r.

    Parameters
    ----------
    moves, views
        N_M straight moves and N_S views.
    path_length
        d, in the environment's length unit.
    t_move, t_sense
        Time to plan one move and to compute one visibility polygon (≥ 0).
    speed
        r, length units per time unit (> 0).

    >>> exploration_cost(3, 4, 10.0, t_move=0.5, t_sense=2.0, speed=5.0).total
    11.5
    """
    if not (t_move >= 0 and t_sense >= 0 and math.isfinite(t_move) and math.isfinite(t_sense)):
        raise InputError(f"planning and sensing times must be finite and >= 0, got {t_move} and {t_sense}")
    if not (speed > 0 and math.isfinite(speed)):
        raise InputError(f"speed must be finite and > 0, got {speed}")
    return Cost(t_move * moves, t_sense * views, path_length / speed)


def views_bound(env: Environment) -> int:
    """r + 1: Theorem 1's bound on Algorithm A's views (r reflex vertices, a hole's convex corners included)."""
    return len(env.reflex_vertices) + 1


def depth_first_ratio(env: Environment) -> float:
    """(r + 1)/2: Theorem 2's competitive ratio of Algorithm A (against an optimum of at least two views)."""
    return views_bound(env) / 2


def _check_range(range_: float) -> float:
    if not (isinstance(range_, (int, float)) and math.isfinite(range_) and range_ > 0):
        raise InputError(f"range R must be a finite number > 0, got {range_!r}")
    return float(range_)


def range_views_bound(env: Environment, range_: float) -> int:
    """Lemma 4: ⌊8·Area(P)/(3R²)⌋ + ⌊Perimeter(P)/R⌋ + r + h + 1 views for Algorithm B with range R.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> range_views_bound(square, 2.0)                  # ⌊128/12⌋ + ⌊16/2⌋ + 0 + 0 + 1
    19
    """
    R = _check_range(range_)
    area = float(env.area)
    return (math.floor(8 * area / (3 * R * R)) + math.floor(env.perimeter / R) + len(env.reflex_vertices)
            + len(env.holes) + 1)


def range_views_lower_bound(env: Environment, range_: float) -> int:
    """Theorem 5's premise: a view sees at most πR² of area, so any exploration takes ⌈Area(P)/(πR²)⌉ views."""
    R = _check_range(range_)
    return max(1, math.ceil(float(env.area) / (math.pi * R * R)))


def range_ratio_bound(env: Environment, range_: float) -> float:
    """Theorem 5: 8π/3 + πR·Perimeter/Area + (r + h + 1)·πR²/Area bounds Algorithm B's competitive ratio."""
    R = _check_range(range_)
    area = float(env.area)
    r, h = len(env.reflex_vertices), len(env.holes)
    return 8 * math.pi / 3 + math.pi * R * env.perimeter / area + (r + h + 1) * math.pi * R * R / area
