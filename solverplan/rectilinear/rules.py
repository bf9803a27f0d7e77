"""The three bounce rules of the rooms paper (§VI, §VIII): billiard, random and the one-bit smart rule.

Headings are radians in (0, π), counter-clockwise from the wall hit (π/2 straight into the room), as
everywhere in solverplan; α is the paper's hitting angle, measured from the wall back along the incoming path.

- **billiard** (the paper's reflecting robot, β = α): the mirror reflection, heading π − α.
- **random**: a heading drawn uniformly from (0, π) at every bounce, whatever α (the paper leaves the
  distribution open; uniform in angle is the choice here).
- **smart** (Eq. 1, one bit k of memory that flips at every wall hit, closed doors included). The reading
  used: after each hit k flips and the robot leaves along the inward normal when k = 0 (heading π/2) and at θ
  off the normal when k = 1 (heading π/2 + θ), always turned the same way relative to the wall's direction;
  α plays no part (Eq. 1's π/2 − α is read as "turn from the incoming direction to the normal"). Starting
  from k = 0, the first hit sets k = 1. So the robot goes straight across the room and comes back tilted:
  between two parallel walls, each tilted crossing moves its hits along both walls by H·tan θ for walls H
  apart, and when it reaches a side wall it sweeps the other pair of walls the same way, going round the room.
  Eq. 1's θ = arctan(ℓ/h) (arcsin(ℓ/√(ℓ² + h²))) would move the hits by exactly ℓ, the door's length, across
  a room h deep — with nothing to spare, and only for the door's own pair of walls: in a flat room (W ≫ H) the
  tilted crossing of the long side moves W·tan θ ≫ ℓ and skips doors on the short sides. Here the step is half
  the door on *every* pair of walls: θ = arctan(ℓ / (2·D)), D the larger side of the room's bounding box, so
  each sweep past a door lands one hit on its middle half (clear of its end points, where the float caster
  would flag the hit). Without per-room values the robot is given the smallest θ over the rooms it will cross
  (the paper's "minimum value of θ for every ℓ and h, in the beginning"); :func:`smart_tangent` computes it
  exactly (tan θ is rational).

  **How far Prop. 3 holds under this reading.** With door control, the smart robot visited every room of the
  sequence from every one of 2,000 random starts in 2,000 random rectilinear polygons (tests). It is not a
  theorem: the sweeps of one round of the room need not cover what the previous round missed, and from special
  starts the robot settles into a periodic orbit that avoids the door — in a 12 × 2 room with the door [3, 4] in
  its ceiling, from (10.48, 0) along (1, 1), a 40-bounce orbit (tan θ = 1/24). Such orbits are isolated: moving
  the start by 1e-7 the robot arrives. With the literal θ = arctan(ℓ/h) they are not rare: in a 13 × 2 room with
  a 1-wide door in the ceiling, 3 of 100 random rational starts are trapped.

>>> from fractions import Fraction
>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear.decomposition import decompose_rooms
>>> dec = decompose_rooms(load_environment("three_chambers"))
>>> smart_tangent(dec, dec.path(0, 2))     # the 1-wide door out of a 30 × 30 chamber: 1 / (2 · 30)
Fraction(1, 60)
>>> rule = Smart.for_walk(dec, dec.path(0, 2))
>>> [round(h, 6) for h in rule.headings_at(step=1, n=1).tolist() + rule.headings_at(step=2, n=1).tolist()]
[1.587461, 1.570796]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import ClassVar, Sequence

import numpy as np

from solverplan.choices import RoomRule, ThetaMode
from solverplan.errors import InputError
from solverplan.rectilinear.decomposition import Decomposition

__all__ = ["RULES", "RULE_VARIANTS", "THETA_MODES", "GUARANTEES", "Billiard", "Random", "Smart", "smart_tangent",
           "room_tangents", "make_rule", "door_depth"]

RULES: tuple[str, ...] = ("smart", "random", "billiard")
"""The paper's three rules."""

THETA_MODES: tuple[str, ...] = ThetaMode.values()
"""How the smart rule's θ is chosen (module docstring): ``safe`` tan θ = ℓ/(2D), the least over the rooms left on
the way; ``paper`` Eq. 1's tan θ = ℓ/h, the least over the same rooms; ``per-room`` the safe θ of the room the
robot is in (the central system tells it)."""

RULE_VARIANTS: tuple[str, ...] = RoomRule.values()
"""The rules compared by a recommendation: ``smart`` is the smart rule with the safe θ, ``smart-paper`` and
``smart-per-room`` the other θ modes."""

GUARANTEES: dict[str, str] = {
    "smart": "arrives from every start tried (2,000 random floors); not a theorem: isolated periodic orbits exist, "
             "found exactly when met",
    "smart-per-room": "as smart (the safe θ of each room)",
    "smart-paper": "none: with tan θ = ℓ/h a positive share of starts is trapped in periodic orbits (about 4 % in "
                   "random rooms)",
    "random": "arrives with probability 1 (every door has positive length)",
    "billiard": "none: periodic orbits trap it for ever (the paper's Fig. 3a)",
}
"""What each rule of :data:`RULE_VARIANTS` guarantees about arriving."""

GUARANTEED: frozenset[str] = frozenset({"smart", "smart-per-room", "random"})

_MARGIN = 1e-12  # headings are kept inside (0, π)


def _frames(edge_start: np.ndarray, edge_end: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    d = edge_end[edges] - edge_start[edges]
    tangent = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    return tangent, np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)


@dataclass(frozen=True, slots=True)
class Billiard:
    """β = α: the mirror reflection (heading π − α)."""

    name: ClassVar[str] = "billiard"
    deterministic: ClassVar[bool] = True

    def headings(self, world, edges: np.ndarray, incoming: np.ndarray, step: int, rng: np.random.Generator) -> np.ndarray:
        tangent, normal = _frames(world.edge_start, world.edge_end, np.asarray(edges, dtype=np.int64))
        v = np.asarray(incoming, dtype=float)
        out = np.arctan2(-np.einsum("ij,ij->i", v, normal), np.einsum("ij,ij->i", v, tangent))
        return np.clip(out, _MARGIN, math.pi - _MARGIN)


@dataclass(frozen=True, slots=True)
class Random:
    """A uniform heading in (0, π) at every bounce."""

    name: ClassVar[str] = "random"
    deterministic: ClassVar[bool] = False

    def headings(self, world, edges: np.ndarray, incoming: np.ndarray, step: int, rng: np.random.Generator) -> np.ndarray:
        return np.clip(rng.uniform(0.0, math.pi, len(edges)), _MARGIN, math.pi - _MARGIN)


def _check_theta(theta: str) -> str:
    return ThetaMode.parse(theta, "θ mode").value


def door_depth(dec: Decomposition, room: int, door: int) -> Fraction:
    """h of Eq. 1: how deep ``room`` is across ``door`` — the side of the room's bounding box perpendicular to the
    (axis-parallel) door (length units, exact)."""
    x0, y0, x1, y1 = dec.rooms[room].bounds
    a, b = dec.doors[door].a, dec.doors[door].b
    return (x1 - x0) if a[0] == b[0] else (y1 - y0)


def _tangent(dec: Decomposition, room: int, door: int, theta: str) -> Fraction:
    length = dec.doors[door].length
    if theta == "paper":
        return length / door_depth(dec, room, door)
    x0, y0, x1, y1 = dec.rooms[room].bounds
    return length / (2 * max(x1 - x0, y1 - y0))


def smart_tangent(dec: Decomposition, walk: Sequence[int], theta: str = "safe") -> Fraction:
    """tan θ of the smart rule for a room sequence: the least ℓ / (2·D) over the rooms left on the way, ℓ the
    door out of the room, D the larger side of its bounding box (module docstring); with ``theta="paper"`` the
    least ℓ / h (Eq. 1, h from :func:`door_depth`). A walk of one room uses every door of it (or, for a room
    without doors, θ = arctan(1/2))."""
    if _check_theta(theta) == "per-room":
        raise InputError("smart_tangent: the per-room mode has one θ per room (room_tangents)")
    walk = tuple(walk)
    pairs = [(walk[k], dec.door_between(walk[k], walk[k + 1]).id) for k in range(len(walk) - 1)]
    if not pairs:
        only = dec.rooms[dec.check_room(walk[0])] if walk else dec.rooms[0]
        pairs = [(only.id, d) for d in only.doors]
    return min((_tangent(dec, room, door, theta) for room, door in pairs), default=Fraction(1, 2))


def room_tangents(dec: Decomposition, theta: str = "safe") -> tuple[Fraction, ...]:
    """tan θ of each room for a robot told the room it is in: the least ℓ / (2·D) over the room's doors
    (D the larger side of its bounding box; ``theta="paper"``: the least ℓ / h); 1/2 for a room without doors."""
    mode = "safe" if _check_theta(theta) == "per-room" else theta
    return tuple(min((_tangent(dec, room.id, d, mode) for d in room.doors), default=Fraction(1, 2))
                 for room in dec.rooms)


@dataclass(frozen=True, slots=True)
class Smart:
    """The one-bit smart rule with tilt θ (radians, 0 < θ < π/2): heading π/2 + (step mod 2)·θ at the
    step-th hit (module docstring). With ``per_room`` (one θ per room, :func:`room_tangents`) the central
    system tells the robot the θ of the room it is in — the paper's variant with updated information; the
    bit is still the robot's only memory. ``tangent`` and ``room_tangents`` are the exact tan θ when known
    (the exact replay of :func:`solverplan.rectilinear.simulation.periodic_orbit` moves along them)."""

    theta: float
    per_room: tuple[float, ...] = ()
    tangent: Fraction | None = None
    room_tangents: tuple[Fraction, ...] = ()
    name: ClassVar[str] = "smart"
    deterministic: ClassVar[bool] = True

    def __post_init__(self) -> None:
        for value in (self.theta, *self.per_room):
            if not (isinstance(value, (int, float)) and 0 < value < math.pi / 2):
                raise InputError(f"smart rule: θ = {value!r} must lie in (0, π/2)")

    @classmethod
    def for_walk(cls, dec: Decomposition, walk: Sequence[int], *, per_room: bool = False, theta: str = "safe") -> Smart:
        """The smart rule with θ = arctan(:func:`smart_tangent`) for the room sequence ``walk`` in the θ mode
        ``theta`` (:data:`THETA_MODES`; ``per_room`` is the same as ``theta="per-room"``: θ of each room from
        :func:`room_tangents`)."""
        if _check_theta(theta) == "per-room":
            per_room = True
        tangent = smart_tangent(dec, walk, "paper" if theta == "paper" else "safe")
        rooms = room_tangents(dec) if per_room else ()
        return cls(math.atan(tangent), tuple(math.atan(t) for t in rooms), tangent, rooms)

    @classmethod
    def with_tangent(cls, tangent: Fraction | int) -> Smart:
        """The smart rule with the exact tan θ = ``tangent`` (> 0)."""
        value = Fraction(tangent)
        if value <= 0:
            raise InputError(f"smart rule: tan θ = {value} must be positive")
        return cls(math.atan(value), (), value)

    def exact_tangent(self, room: int) -> Fraction:
        """The exact tan θ the robot uses in ``room`` (the float θ's exact binary value when none was given)."""
        if self.per_room:
            return self.room_tangents[room] if self.room_tangents else Fraction(math.tan(self.per_room[room]))
        return self.tangent if self.tangent is not None else Fraction(math.tan(self.theta))

    def headings_at(self, step: int, n: int) -> np.ndarray:
        return np.full(n, math.pi / 2 + (step % 2) * self.theta)

    def headings(self, world, edges: np.ndarray, incoming: np.ndarray, step: int, rng: np.random.Generator) -> np.ndarray:
        if not self.per_room:
            return self.headings_at(step, len(edges))
        theta = np.asarray(self.per_room)[world.room_of[np.asarray(edges, dtype=np.int64)]]
        return math.pi / 2 + (step % 2) * theta


Rule = Billiard | Random | Smart


def make_rule(name: str, dec: Decomposition, walk: Sequence[int], *, per_room: bool = False,
              theta: str = "safe") -> Rule:
    """The rule called ``name`` (one of :data:`RULE_VARIANTS`) for the room sequence ``walk``; the smart rule's θ
    in mode ``theta`` (:data:`THETA_MODES`; ``per_room`` means ``theta="per-room"``); ``smart-paper`` and
    ``smart-per-room`` fix the mode."""
    if name.startswith("smart"):
        mode = {"smart": theta, "smart-paper": "paper", "smart-per-room": "per-room", "smart-safe": "safe"}.get(name)
        if mode is not None:
            return Smart.for_walk(dec, walk, per_room=per_room and name == "smart", theta=mode)
    if name == "random":
        return Random()
    if name == "billiard":
        return Billiard()
    raise InputError(f"unknown rule {name!r}: use {', '.join(RULE_VARIANTS)}")
