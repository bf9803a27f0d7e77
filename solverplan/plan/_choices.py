"""Per-arc interval choices of the safe BVG for a required tolerance (private).

For a tolerance ε (radians, the half-width of the heading interval the robot is allowed), each arc of the safe
bounce visibility graph may use any sub-interval of width 2ε of one of its admissible intervals (its safe
intervals cut by the one margin policy of every planner, :mod:`solverplan.plan.margins`). The contraction
coefficient C(θ, φ) is increasing in θ for a right transition and decreasing for a left one (Lemma 2,
solverplan.proofs.contraction_monotonicity), so the worst case over [θ, θ + 2ε] is at its expanding end and the best
such interval sits at the **contracting end** of the safe interval: [lo, lo + 2ε] (right), [hi − 2ε, hi] (left).
Parallel walls have C ≡ 1; their interval is centred. The arc's weight is log of that worst case — a closed form
in ε, increasing in ε (wider intervals reach further towards the expanding end), which is what makes the
bisection on ε of objective (b) sound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solverplan.bounce.bvg import SafeBVG
from solverplan.bounce.dynamics import contraction_coefficient
from solverplan.plan.margins import Margins, admissible_intervals, corner_arcs

__all__ = ["ArcChoices", "arc_choices", "max_tolerance"]


@dataclass(frozen=True)
class ArcChoices:
    """The usable arcs at one tolerance: ``arc`` (row of the safe BVG), the chosen interval ``lo``/``hi``,
    the worst-case coefficient ``worst`` (arc length, Def. 11), ``weight`` = log worst, and the corner the arc runs
    into (``dive``: end of the source, ``arrival``: end of the target; 0 for none — :func:`corner_arcs`)."""

    tolerance: float
    arc: np.ndarray
    source: np.ndarray
    target: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    worst: np.ndarray
    weight: np.ndarray
    dive: np.ndarray
    arrival: np.ndarray

    def index(self) -> dict[tuple[int, int], int]:
        """(source, target) → row of these arrays."""
        return {(int(s), int(t)): k for k, (s, t) in enumerate(zip(self.source.tolist(), self.target.tolist()))}


def _pieces(g: SafeBVG, margins: Margins):
    adm = admissible_intervals(g, margins)
    return adm.arc, adm.lo, adm.hi


def max_tolerance(g: SafeBVG, margins: Margins) -> float:
    """The largest ε any single arc allows (half its widest admissible interval)."""
    _, lo, hi = _pieces(g, margins)
    return float(np.max((hi - lo) / 2)) if len(lo) else 0.0


def arc_choices(g: SafeBVG, tolerance: float, margins: Margins) -> ArcChoices:
    """Every arc with an admissible interval at least 2ε wide, its best 2ε interval and worst-case coefficient."""
    eps = float(tolerance)
    arc_of, lo, hi = _pieces(g, margins)
    ok = hi - lo >= 2 * eps
    arc_of, lo, hi = arc_of[ok], lo[ok], hi[ok]
    side = np.asarray(g.transition, dtype=np.int64)[arc_of]
    phi = np.asarray(g.phi, dtype=float)[arc_of]
    mid = (lo + hi) / 2
    c_lo = np.where(side > 0, lo, np.where(side < 0, hi - 2 * eps, mid - eps))
    c_hi = c_lo + 2 * eps
    names = ["left" if x < 0 else "right" for x in side.tolist()]
    theta = np.where(side > 0, c_hi, np.where(side < 0, c_lo, mid))
    worst: np.ndarray = np.asarray(contraction_coefficient(theta, np.where(side == 0, 0.0, phi), names), dtype=np.float64)
    worst = np.where(side == 0, 1.0, worst)
    bad = ~np.isfinite(worst) | (worst <= 0)
    worst = np.where(bad, np.inf, worst)
    # best piece per arc
    order = np.lexsort((worst, arc_of))
    first = order[np.concatenate([[True], arc_of[order][1:] != arc_of[order][:-1]])] if len(order) else order
    first = first[np.isfinite(worst[first])]
    a = arc_of[first]
    source = np.asarray(g.source, dtype=np.int64)[a]
    target = np.asarray(g.target, dtype=np.int64)[a]
    dive, arrival = corner_arcs(g.partition, source, target)
    return ArcChoices(
        tolerance=eps,
        arc=a,
        source=source,
        target=target,
        lo=c_lo[first],
        hi=c_hi[first],
        worst=worst[first],
        weight=np.log(worst[first]),
        dive=dive,
        arrival=arrival,
    )
