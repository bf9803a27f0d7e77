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

Ties. On axis-parallel walls J ties (a square corner: both walls J = 1/2), and the paper's tie-break (smallest
n_in·v_in) picks the wall opposite the exit, which the robot entering along n_in never meets. Ties here go first to
the wall the robot runs into (inward normal most against the entry direction), then to the wall facing the exit
most (both compared through signed squared cosines, exactly: :func:`facing`), then to the paper's rule, then to the
lowest side index.

Choices of ours: S holds only **walls** (a reflection needs a wall to bounce on: a facet to another cell cannot be
one); a wall is a zone only if bouncing on it **turns the robot towards the exit** (:func:`turns_towards_exit`: its
inward normal n faces back against the entry, n·n_in < 0, and towards the exit, n·e > 0 for e = −n_out — a wall
across the outer corner; in a square corner no wall does); and only if the reflection field — the line field from p_in towards
p — provably flows to a wall or to the outlet (:func:`~solverplan.reflection.fields.line_flows_through` with every
wall and the outlet as exits). Otherwise the next wall in the order is tried, and a cell with none keeps its nominal
field. Every wall passed over is recorded with the reason (:class:`RejectedZone`). Whether a zone *pays* depends on
the robot (it must overshoot the turn) and is decided by rollouts in :mod:`~solverplan.reflection.payoff`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

from solverplan.exact import ExactPoint, format_number
from solverplan.reflection.cells import Cell
from solverplan.reflection.fields import FlowCheck, LineField, line_flows_through

__all__ = ["ReflectionZone", "RejectedZone", "is_reflection_candidate", "alpha", "zone_cost", "zone_cost_printed",
           "rank_zones", "select_zone", "select_zone_recorded", "turns_towards_exit", "facing"]


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


def _signed_cos2(u: ExactPoint, v: ExactPoint) -> Fraction:
    """sign(u·v)·cos²(u, v): orders angles like the cosine does, in exact rationals."""
    c = _dot(u, v)
    return (1 if c >= 0 else -1) * c * c / (_dot(u, u) * _dot(v, v))


def facing(cell: Cell, inlet: int, outlet: int, side: int) -> tuple[Fraction, Fraction]:
    """How wall ``side`` faces the turn: (signed cos² between its inward normal n and the entry direction n_in —
    −1 for the wall straight ahead —, signed cos² between n and the exit direction e = −n_out). Exact."""
    n = cell.sides[side].normal
    e = (-cell.sides[outlet].normal[0], -cell.sides[outlet].normal[1])
    return _signed_cos2(n, cell.sides[inlet].normal), _signed_cos2(n, e)


def turns_towards_exit(cell: Cell, inlet: int, outlet: int, side: int) -> bool:
    """Can bouncing on wall ``side`` turn the robot towards the exit? A bounce changes the velocity along the wall's
    inward normal n only, so n must face back against the entry direction (n·n_in < 0: the robot going in along
    n_in runs into the wall and loses the speed it must lose anyway) and towards the exit (n·e > 0, e = −n_out):
    a wall across the outer corner. Exact signs of dot products of rational vectors.

    >>> from solverplan.environment import Environment, load_environment
    >>> from solverplan.reflection.cells import decompose_free_space
    >>> square = decompose_free_space(load_environment("square")).cells[0]   # in at side 0, out at side 1
    >>> turns_towards_exit(square, 0, 1, 2), turns_towards_exit(square, 0, 1, 3)   # a square corner: neither
    (False, False)
    >>> cut = decompose_free_space(Environment.from_coords([(0, 0), (2, 0), (2, 1), (1, 2), (0, 2)])).cells[0]
    >>> turns_towards_exit(cut, 0, 4, 2), turns_towards_exit(cut, 0, 4, 1)  # up, out to the left: the 45° cut helps
    (True, False)
    """
    n = cell.sides[side].normal
    n_in = cell.sides[inlet].normal
    e = (-cell.sides[outlet].normal[0], -cell.sides[outlet].normal[1])
    return _dot(n, n_in) < 0 and _dot(n, e) > 0


def rank_zones(cell: Cell, inlet: int, outlet: int) -> list[int]:
    """The wall sides other than the inlet and outlet, best first: corrected Eq. 4; on ties the wall the robot runs
    into (its normal most against the entry direction), then the one facing the exit most (:func:`facing`), then the
    smallest n_in·v_in (the paper's rule), then the lowest index."""
    def key(i: int) -> tuple[Fraction, Fraction, Fraction, Fraction, int]:
        w_in = _sub(cell.sides[i].midpoint, cell.sides[inlet].midpoint)
        against, towards = facing(cell, inlet, outlet, i)
        return zone_cost(cell, inlet, outlet, i), against, -towards, _cos2(cell.sides[inlet].normal, w_in), i

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


@dataclass(frozen=True, slots=True)
class RejectedZone:
    """A reflection considered and not planned: the ``cell``, the wall ``side`` (``None`` for the whole cell), the
    ``stage`` that rejected it (``candidate``: α > π/2; ``turn``: bouncing there does not turn the robot towards
    the exit; ``flow``: no reflection field verified; ``overshoot``: the robot turns in time without it;
    ``rollout``: simulated runs predict no gain) and a ``reason`` sentence."""

    cell: int
    side: int | None
    stage: str
    reason: str

    def to_json(self) -> dict:
        return {"cell": self.cell, "side": self.side, "stage": self.stage, "reason": self.reason}


def select_zone_recorded(cell: Cell, inlet: int, outlet: int,
                         gains: tuple[Fraction, ...]) -> tuple[ReflectionZone | None, tuple[RejectedZone, ...]]:
    """:func:`select_zone` with the record of every wall passed over and why."""
    rejected: list[RejectedZone] = []
    if not is_reflection_candidate(cell, inlet, outlet):
        a = math.degrees(alpha(cell, inlet, outlet))
        return None, (RejectedZone(cell.id, None, "candidate", f"α = {a:.1f}° > 90°: the path goes nearly straight "
                                                                "through, no turn to help"),)
    exits = frozenset(i for i, s in enumerate(cell.sides) if s.is_wall) | {outlet}
    for side in rank_zones(cell, inlet, outlet):
        if not turns_towards_exit(cell, inlet, outlet, side):
            rejected.append(RejectedZone(cell.id, side, "turn", "bouncing on this wall does not turn the robot "
                                                                "towards the exit (its normal does not match the turn)"))
            continue
        for gain in gains:
            field = LineField(cell.sides[inlet].midpoint, cell.sides[side].midpoint, gain)
            check = line_flows_through(field, cell, exits)
            if check.valid:
                return ReflectionZone(cell.id, inlet, outlet, side, alpha(cell, inlet, outlet),
                                      zone_cost(cell, inlet, outlet, side), field, check), tuple(rejected)
        rejected.append(RejectedZone(cell.id, side, "flow", "no gain makes the reflection field flow to a wall or "
                                                            "the outlet"))
    return None, tuple(rejected)


def select_zone(cell: Cell, inlet: int, outlet: int, gains: tuple[Fraction, ...]) -> ReflectionZone | None:
    """The reflection zone of a candidate cell: the best-ranked wall whose reflection field (line field from p_in
    to the wall's midpoint, first gain of ``gains`` that works) flows to a wall or the outlet; ``None`` when the
    cell is no candidate or no wall works.

    Examples
    --------
    >>> import solverplan as sp
    >>> from fractions import Fraction
    >>> square = sp.decompose_free_space(sp.load_environment("square")).cells[0]
    >>> print(select_zone(square, 0, 1, (Fraction(3, 10),)))  # a square corner: no wall turns the robot to the exit
    None
    """
    return select_zone_recorded(cell, inlet, outlet, gains)[0]
