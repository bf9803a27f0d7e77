"""Escapability, reachability and the reachability graph of a room decomposition (the paper's §VII).

- **Escapability** Φ of leaving room i through door ℓ: |ℓ| / |w(ℓ)|, the door's length over the length of the
  wall of room i it lies on (the maximal straight stretch of the room's boundary containing it). Φ = 1 when
  the door is the whole wall; the paper calls a door "too narrow" below 0.1. It depends on the side: a
  doorway's end is the whole wall of the doorway (Φ = 1) but a small part of the chamber's wall.
- **Reachability** Ψ(s, g) along the unique room sequence s = r₀, r₁, …, r_m = g (Remark 5): the product of
  Φ(r_k → r_{k+1}) over the doors crossed; Ψ(s, s) = 1. Exact rationals.
- The **reachability graph**: rooms as nodes, an arc i → j of weight Φ(i → j) for every door, in both
  directions (a :class:`networkx.DiGraph`).
- The **rule recommendation**: the smart rule when Ψ is low, where the random and billiard robots rarely find
  the doors; random bouncing otherwise (the billiard robot is as quick on average but can be trapped for ever,
  Fig. 3a). "Low" is Ψ < :data:`SMART_THRESHOLD` = 1/10: the paper's conclusion finds no clear advantage for
  the smart rule when the escapability factors exceed 0.1 and calls a door narrower than that too narrow.

>>> from solverplan.environment import Environment
>>> from solverplan.rectilinear.decomposition import decompose_rooms
>>> ell = decompose_rooms(Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]]))
>>> escapability(ell, 0, 1), escapability(ell, 1, 0)          # the door is half of room 0's wall, all of room 1's
(Fraction(1, 2), Fraction(1, 1))
>>> reachability(ell, 0, 1).psi, recommend_rule(ell, 0, 1).rule
(Fraction(1, 2), 'random')
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.exact import format_number
from solverplan.rectilinear.decomposition import Decomposition

__all__ = [
    "SMART_THRESHOLD",
    "escapability",
    "RoomReachability",
    "reachability",
    "reachability_along",
    "reachability_graph",
    "RuleRecommendation",
    "recommend_rule",
]

SMART_THRESHOLD = Fraction(1, 10)
"""Below this reachability Ψ the smart rule is recommended (module docstring)."""


def escapability(dec: Decomposition, room: int, to: int) -> Fraction:
    """Φ of leaving ``room`` for the neighbouring room ``to`` through their door (exact, in (0, 1]).

    Raises :class:`~solverplan.errors.InputError` for an unknown room or rooms that share no door.
    """
    return dec.door_between(room, to).escapability(room)


@dataclass(frozen=True, slots=True)
class RoomReachability:
    """Ψ along a room sequence: ``rooms`` (start first), the Φ of each door crossed (``factors``, one fewer
    than rooms) and their product ``psi`` (exact)."""

    rooms: tuple[int, ...]
    factors: tuple[Fraction, ...]

    @property
    def psi(self) -> Fraction:
        product = Fraction(1)
        for phi in self.factors:
            product *= phi
        return product

    def to_json(self) -> dict:
        return {"rooms": list(self.rooms), "escapability": [float(f) for f in self.factors],
                "escapability_exact": [format_number(f) for f in self.factors],
                "reachability": float(self.psi), "reachability_exact": format_number(self.psi)}


def reachability(dec: Decomposition, start: int, goal: int) -> RoomReachability:
    """Ψ(start, goal): the product of the escapability factors along the room sequence from ``start`` to ``goal``."""
    return reachability_along(dec, dec.path(start, goal))


def reachability_along(dec: Decomposition, rooms: Sequence[int]) -> RoomReachability:
    """Ψ along any room sequence (each room a neighbour of the one before; a tour may come back through a room)."""
    rooms = tuple(rooms)
    return RoomReachability(rooms, tuple(escapability(dec, i, j) for i, j in zip(rooms, rooms[1:])))


def reachability_graph(dec: Decomposition):
    """The reachability graph: a :class:`networkx.DiGraph` with a node per room (attributes ``area``, exact)
    and, per door and direction, an arc i → j with ``weight`` Φ(i → j) (float), ``escapability`` (exact) and
    ``door`` (its id)."""
    import networkx as nx

    graph = nx.DiGraph()
    for room in dec.rooms:
        graph.add_node(room.id, area=room.area)
    for door in dec.doors:
        for i in door.rooms:
            j = door.other(i)
            phi = door.escapability(i)
            graph.add_edge(i, j, weight=float(phi), escapability=phi, door=door.id)
    return graph


@dataclass(frozen=True, slots=True)
class RuleRecommendation:
    """Which bounce rule to use from ``start`` to ``goal``: ``"smart"`` when Ψ < ``threshold``, else ``"random"``."""

    rule: str
    reachability: RoomReachability
    threshold: Fraction

    @property
    def reason(self) -> str:
        psi = format_number(self.reachability.psi)
        if self.rule == "smart":
            return f"reachability {psi} < {format_number(self.threshold)}: narrow doors, the smart rule is certain to pass them"
        return (f"reachability {psi} >= {format_number(self.threshold)}: random bouncing passes the doors about as fast "
                "(billiard bouncing too, but it can be trapped in a periodic orbit)")

    def to_json(self) -> dict:
        return {"rule": self.rule, "threshold": float(self.threshold), "reason": self.reason, **self.reachability.to_json()}


def recommend_rule(dec: Decomposition, start: int, goal: int, *, threshold: Fraction | float = SMART_THRESHOLD,
                   rooms: Sequence[int] | None = None) -> RuleRecommendation:
    """The rule recommendation of §VII for going from room ``start`` to room ``goal`` (module docstring), along
    ``rooms`` when given (a tour), else along the tree path."""
    limit = Fraction(threshold)
    reach = reachability(dec, start, goal) if rooms is None else reachability_along(dec, rooms)
    return RuleRecommendation("smart" if reach.psi < limit else "random", reach, limit)
