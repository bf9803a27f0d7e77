"""Reflection candidates and reflection zones (Stager and Tanner, §III), decided in exact arithmetic.

**Candidates (§III-A).** For a cell of the sequence with an inlet (inward normal n_in) and an outlet (inward normal
n_out, the cell's normal on the outlet side), α = arccos(n_in·n_out); the cell gets a reflection when α ≤ π/2, i.e.
when n_in·n_out ≥ 0 — a sign of a dot product of rational vectors, so the boundary case α = π/2 of a corner square is
decided exactly. Straight-through cells (α = π) are skipped.

**Zones (§III-B, Eq. 4 corrected).** Among the other sides S, with v_in(p) the unit vector from p_in to the side
midpoint p and v_out(p) the one from p_out to p, choose the p minimising

    J(p) = (1 − (n_in·v_in(p))²) + (1 − (n_out·v_out(p))²)        (the squared cross products)

"enter along n_in, leave along n_out" with the least change of direction. Erratum: the paper prints
(n_in·v_in)² + (n_out·v_out)², which is 2 — its maximum — in the paper's own isosceles right triangle, where the text
says the minimum is 0 with v_in = n_in and v_out = n_out; J is 0 there (proved in ``solverplan.proofs.line_field``).
Ties (symmetric cells) go to the smallest n_in·v_in(p) (the paper's rule), then to the lowest side index. J and
n_in·v_in (≥ 0 in a convex cell) are compared through their squares, which are rational: every tie is exact.

Two choices of ours: S holds only **walls** (a reflection needs a wall to bounce on: a facet to another cell cannot
be one), and a zone is kept only if the reflection field — the line field from p_in towards p — provably flows to a
wall or to the outlet (:func:`~solverplan.reflection.fields.line_flows_through` with every wall and the outlet as
exits); otherwise the next zone in the order is tried, and a cell with none keeps its nominal field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

from solverplan.exact import ExactPoint, format_number
from solverplan.reflection.cells import Cell
from solverplan.reflection.fields import FlowCheck, LineField, line_flows_through

__all__ = ["ReflectionZone", "is_reflection_candidate", "alpha", "zone_cost", "zone_cost_printed", "rank_zones",
           "select_zone"]


def _dot(u: ExactPoint, v: ExactPoint) -> Fraction:
    return u[0] * v[0] + u[1] * v[1]


def _sub(u: ExactPoint, v: ExactPoint) -> ExactPoint:
    return (u[0] - v[0], u[1] - v[1])


def is_reflection_candidate(cell: Cell, inlet: int, outlet: int) -> bool:
    """α ≤ π/2, decided exactly as n_in·n_out ≥ 0.

    >>> from solverplan.environment import load_environment
    >>> from solverplan.reflection.cells import decompose_free_space
    >>> square = decompose_free_space(load_environment("square")).cells[0]
    >>> is_reflection_candidate(square, 0, 1), is_reflection_candidate(square, 0, 2)
    (True, False)
    """
    return _dot(cell.sides[inlet].normal, cell.sides[outlet].normal) >= 0


def alpha(cell: Cell, inlet: int, outlet: int) -> float:
    """α = arccos(n_in·n_out) in radians (unit normals; floats, for reports)."""
    n_in, n_out = cell.sides[inlet].unit_normal(), cell.sides[outlet].unit_normal()
    return math.acos(max(-1.0, min(1.0, float(n_in @ n_out))))


def _cos2(n: ExactPoint, w: ExactPoint) -> Fraction:
    """(n·w)² / (|n|²|w|²): the squared cosine between n and w, exact."""
    return _dot(n, w) ** 2 / (_dot(n, n) * _dot(w, w))


def zone_cost(cell: Cell, inlet: int, outlet: int, side: int) -> Fraction:
    """The corrected Eq. 4, J(p) = 2 − cos²(n_in, v_in) − cos²(n_out, v_out), exact."""
    p = cell.sides[side].midpoint
    w_in, w_out = _sub(p, cell.sides[inlet].midpoint), _sub(p, cell.sides[outlet].midpoint)
    return 2 - _cos2(cell.sides[inlet].normal, w_in) - _cos2(cell.sides[outlet].normal, w_out)


def zone_cost_printed(cell: Cell, inlet: int, outlet: int, side: int) -> Fraction:
    """Eq. 4 as printed, (n_in·v_in)² + (n_out·v_out)² (kept to show the erratum)."""
    return 2 - zone_cost(cell, inlet, outlet, side)


def rank_zones(cell: Cell, inlet: int, outlet: int) -> list[int]:
    """The wall sides other than the inlet and outlet, best first: corrected Eq. 4, then the smallest n_in·v_in,
    then the lowest index."""
    def key(i: int) -> tuple[Fraction, Fraction, int]:
        w_in = _sub(cell.sides[i].midpoint, cell.sides[inlet].midpoint)
        return zone_cost(cell, inlet, outlet, i), _cos2(cell.sides[inlet].normal, w_in), i

    walls = [i for i, s in enumerate(cell.sides) if s.is_wall and i not in (inlet, outlet)]
    return sorted(walls, key=key)


@dataclass(frozen=True, slots=True)
class ReflectionZone:
    """The reflection planned in one cell: aim from the inlet midpoint at the midpoint of wall side ``side``."""

    cell: int
    inlet: int
    outlet: int
    side: int
    alpha: float
    cost: Fraction
    field: LineField
    check: FlowCheck

    @property
    def point(self) -> ExactPoint:
        return self.field.target

    def to_json(self) -> dict:
        return {"cell": self.cell, "inlet_side": self.inlet, "outlet_side": self.outlet, "side": self.side,
                "point": [float(c) for c in self.point], "alpha": self.alpha, "cost": float(self.cost),
                "cost_exact": format_number(self.cost), "field": self.field.to_json(), "flow": self.check.to_json()}


def select_zone(cell: Cell, inlet: int, outlet: int, gains: tuple[Fraction, ...]) -> ReflectionZone | None:
    """The reflection zone of a candidate cell: the best-ranked wall whose reflection field (line field from p_in
    to the wall's midpoint, first gain of ``gains`` that works) flows to a wall or the outlet; ``None`` when the
    cell is no candidate or no wall works.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> from solverplan.environment import load_environment
    >>> from solverplan.reflection.cells import decompose_free_space
    >>> square = decompose_free_space(load_environment("square")).cells[0]
    >>> zone = select_zone(square, 0, 1, (F(3, 10),))
    >>> zone.side, float(zone.cost)  # a tie between the two walls (J = 1/2), broken by the smallest n_in·v_in
    (3, 0.5)
    """
    if not is_reflection_candidate(cell, inlet, outlet):
        return None
    exits = frozenset(i for i, s in enumerate(cell.sides) if s.is_wall) | {outlet}
    for side in rank_zones(cell, inlet, outlet):
        for gain in gains:
            field = LineField(cell.sides[inlet].midpoint, cell.sides[side].midpoint, gain)
            check = line_flows_through(field, cell, exits)
            if check.verified:
                return ReflectionZone(cell.id, inlet, outlet, side, alpha(cell, inlet, outlet),
                                      zone_cost(cell, inlet, outlet, side), field, check)
    return None
