"""The geometric simulator of the wall-following robot: actions, the touch sensor and the pebble sensor (§III).

The robot is a point in a simply connected polygon in general position (:mod:`solverplan.wallfollow.cut`).
Its actions (:class:`Action`):

- ``RFOLLOW`` — follow the wall counter-clockwise (the wall on the robot's right) until the next vertex or the
  pebble, whichever comes first; ``LFOLLOW`` — the same clockwise. Both need the robot on the boundary.
- ``JUMP`` — only at a reflex vertex the robot reached by following a wall: go straight on, along the edge just
  followed, until the boundary is hit again (the end point of that vertex's right cut after RFOLLOW, of its left
  cut after LFOLLOW). The hit is computed by the project's exact ray caster.
- ``GRAB`` — pick up the pebble lying at the robot's position; ``DROP`` — put the carried pebble down here.
- ``INIT`` — from anywhere: straight along the robot's heading to the wall (from the interior), then
  counter-clockwise along it to the next vertex; at a vertex it does nothing. The pebble does not stop it.

After each action the robot observes an :class:`Observation`: the touch sensor (INTERIOR, EDGE, CONVEX,
REFLEX) and the pebble sensor — true when the pebble *lies* at the robot's position. A carried pebble is not
sensed (the robot knows it holds it: it did the GRAB), so "follow until the pebble" means a pebble on the floor.

Positions are exact: a boundary point is ``(edge, t)`` with a rational t ∈ [0, 1) (t = 0 is the vertex that
starts the edge). An action that does not apply (JUMP at a convex vertex, GRAB away from the pebble, a follow
from the interior) raises :class:`ActionNotApplicable` and changes nothing.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
>>> world = WallWorld(room)                    # at vertex 0, carrying the pebble
>>> [str(world.act(a)) for a in ["DROP", "LFOLLOW", "LFOLLOW", "LFOLLOW"]]   # clockwise: v5, v4, v3
['convex+pebble', 'convex', 'convex', 'reflex']
>>> str(world.act("JUMP")), world.label, str(world.act("LFOLLOW"))    # along the left cut of v3, then back
('edge', 'l3', 'convex+pebble')
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, format_number, format_point, point_in_ring, to_fraction
from solverplan.geometry.raycast import cast_ray
from solverplan.wallfollow.cut import Cut, corner_polygon, cuts

__all__ = ["Action", "Touch", "Observation", "ActionNotApplicable", "WallWorld", "Position", "parse_action"]

#: A boundary point ``(edge, t)``, t ∈ [0, 1); t = 0 is vertex ``edge``.
Position = tuple[int, Fraction]


class Action(StrEnum):
    """The robot's actions (§III-A)."""

    RFOLLOW = "RFOLLOW"
    LFOLLOW = "LFOLLOW"
    JUMP = "JUMP"
    GRAB = "GRAB"
    DROP = "DROP"
    INIT = "INIT"


class Touch(StrEnum):
    """The touch sensor's reading (Eq. 2)."""

    INTERIOR = "interior"
    EDGE = "edge"
    CONVEX = "convex"
    REFLEX = "reflex"


@dataclass(frozen=True, slots=True)
class Observation:
    """What the robot senses after an action: the touch sensor and the pebble sensor (the pebble lies here)."""

    touch: Touch
    pebble: bool

    @property
    def at_vertex(self) -> bool:
        """True at a convex or reflex vertex."""
        return self.touch in (Touch.CONVEX, Touch.REFLEX)

    def __str__(self) -> str:
        return f"{self.touch.value}{'+pebble' if self.pebble else ''}"


class ActionNotApplicable(InputError):
    """An action was asked for where it does not apply (the state is unchanged)."""


def parse_action(action: Action | str) -> Action:
    """An :class:`Action` from its name (case-insensitive); :class:`~solverplan.errors.InputError` otherwise."""
    if isinstance(action, Action):
        return action
    try:
        return Action(str(action).upper())
    except ValueError:
        raise InputError(f"unknown action {action!r}: use {', '.join(a.value for a in Action)}") from None


class WallWorld:
    """The robot, the pebble and the polygon: a geometric simulator with exact positions.

    Parameters
    ----------
    env
        A simple polygon in general position (checked: :func:`~solverplan.wallfollow.cut.cuts`).
    start
        The robot's start, a point of the polygon (interior or boundary), in the environment's length units;
        default vertex 0.
    heading
        The direction (any non-zero vector) INIT drives in from an interior start; default (1, 0).
    carrying
        Whether the robot starts with the pebble (default True); otherwise the pebble lies at ``start``.

    Attributes
    ----------
    transcript
        ``(action, observation)`` for every action executed.
    label
        Where the robot is, as a point of the cut ordering (``v3``, ``l5``), or ``None`` elsewhere.
    carrying, pebble
        Whether the robot holds the pebble, and where the pebble lies otherwise (``(edge, t)`` or a point).

    Examples
    --------
    >>> import solverplan as sp
    >>> world = sp.WallWorld(sp.load_environment("l_shape"))     # at v0, carrying the pebble
    >>> world.act("RFOLLOW"), world.label
    (Observation(touch=<Touch.CONVEX: 'convex'>, pebble=False), 'v1')
    >>> [str(seen) for seen in world.run(["RFOLLOW", "DROP", "RFOLLOW", "JUMP"])]
    ['convex', 'convex+pebble', 'reflex', 'edge']
    >>> world.label, world.pebble, world.carrying     # jumped along v3's cut to r3; the pebble is on v2
    ('r3', (2, Fraction(0, 1)), False)
    """

    def __init__(self, env: Environment, start: Sequence[object] | None = None,
                 heading: Sequence[object] = (1, 0), *, carrying: bool = True) -> None:
        env = corner_polygon(env)  # collinear vertices are no corners: the robot passes them on an edge
        self.env = env
        self.cuts: tuple[Cut, ...] = cuts(env)  # validates the environment
        self._pts = env.exact_vertices
        self.n = len(self._pts)
        self._reflex = frozenset(env.reflex_vertices)
        self._cut_at = {(c.vertex, c.side): c for c in self.cuts}
        self._label_at = {(c.edge, c.t): c.label for c in self.cuts}
        self._heading = (to_fraction(heading[0], where="heading"), to_fraction(heading[1], where="heading"))
        if self._heading[0] == 0 and self._heading[1] == 0:
            raise InputError("heading (0, 0) is zero")
        self._interior: ExactPoint | None = None
        self.position: Position | None = (0, Fraction(0))
        if start is not None:
            p = (to_fraction(start[0], where="start"), to_fraction(start[1], where="start"))
            where = point_in_ring(p, self._pts)
            if where < 0:
                raise InputError(f"start {format_point(p)} is outside the polygon")
            if where > 0:
                self._interior, self.position = p, None
            else:
                self.position = env.locate(p)
        self.arrived: str | None = None  # "R" or "L": the follow that brought the robot to its vertex
        # where the pebble lies, tagged "boundary" (a Position) or "interior" (a point); None while carried
        self._pebble: tuple[str, object] | None = None if carrying else self._here()
        self.transcript: list[tuple[Action, Observation]] = []

    # ------------------------------------------------------------------ state
    @property
    def carrying(self) -> bool:
        """Does the robot hold the pebble?"""
        return self._pebble is None

    @property
    def pebble(self) -> Position | ExactPoint | None:
        """Where the pebble lies: a boundary position ``(edge, t)``, an interior point, or ``None`` (carried)."""
        return None if self._pebble is None else self._pebble[1]  # type: ignore[return-value]

    @property
    def point(self) -> ExactPoint:
        """The robot's exact position."""
        if self.position is None:
            assert self._interior is not None
            return self._interior
        return self.env.exact_point_at(*self.position)

    @property
    def label(self) -> str | None:
        """The robot's position as a point of the cut ordering (``v3``, ``l5``), or ``None`` elsewhere."""
        if self.position is None:
            return None
        edge, t = self.position
        return f"v{edge}" if t == 0 else self._label_at.get((edge, t))

    def _here(self) -> tuple[str, object]:
        return ("boundary", self.position) if self.position is not None else ("interior", self._interior)

    def observe(self) -> Observation:
        """The sensors' reading now."""
        if self.position is None:
            touch = Touch.INTERIOR
        elif self.position[1] != 0:
            touch = Touch.EDGE
        else:
            touch = Touch.REFLEX if self.position[0] in self._reflex else Touch.CONVEX
        return Observation(touch, self._pebble is not None and self._pebble == self._here())

    # ------------------------------------------------------------------ actions
    def act(self, action: Action | str) -> Observation:
        """Execute one action and return the observation after it (:class:`ActionNotApplicable` if it does
        not apply here)."""
        action = parse_action(action)
        step = {Action.RFOLLOW: self._rfollow, Action.LFOLLOW: self._lfollow, Action.JUMP: self._jump,
                Action.GRAB: self._grab, Action.DROP: self._drop, Action.INIT: self._init}[action]
        step()
        obs = self.observe()
        self.transcript.append((action, obs))
        return obs

    def run(self, actions: Sequence[Action | str]) -> list[Observation]:
        """Execute ``actions`` in turn; the observations after each."""
        return [self.act(a) for a in actions]

    def _where(self) -> str:
        if self.position is None:
            return f"in the interior at {format_point(self.point)}"
        edge, t = self.position
        return f"at vertex {edge}" if t == 0 else f"on edge {edge} at t = {format_number(t)}"

    def _on_boundary(self, action: str) -> Position:
        if self.position is None:
            raise ActionNotApplicable(f"{action} needs the robot on the wall; it is {self._where()} (use INIT)")
        return self.position

    def _floor_pebble(self) -> Position | None:
        """The pebble's position when it lies on the boundary (it stops a follow there)."""
        if self._pebble is None or self._pebble[0] != "boundary":
            return None
        return self._pebble[1]  # type: ignore[return-value]

    def _rfollow(self) -> None:
        edge, t = self._on_boundary("RFOLLOW")
        pebble = self._floor_pebble()
        if pebble is not None and pebble[0] == edge and t < pebble[1]:
            self.position = pebble
        else:
            self.position = ((edge + 1) % self.n, Fraction(0))
        self.arrived = "R"

    def _lfollow(self) -> None:
        edge, t = self._on_boundary("LFOLLOW")
        if t == 0:  # leave the vertex backwards along the previous edge, from its end (t = 1)
            edge, t = (edge - 1) % self.n, Fraction(1)
        pebble = self._floor_pebble()
        if pebble is not None and pebble[0] == edge and 0 < pebble[1] < t:
            self.position = pebble
        else:
            self.position = (edge, Fraction(0))
        self.arrived = "L"

    def _jump(self) -> None:
        edge, t = self._on_boundary("JUMP")
        if t != 0 or edge not in self._reflex or self.arrived is None:
            raise ActionNotApplicable(f"JUMP needs a reflex vertex reached by following the wall; the robot is "
                                      f"{self._where()}" + ("" if t != 0 or edge not in self._reflex
                                                           else " and did not arrive by RFOLLOW or LFOLLOW"))
        cut = self._cut_at[(edge, "r" if self.arrived == "R" else "l")]
        self.position, self.arrived = (cut.edge, cut.t), None

    def _grab(self) -> None:
        if self._pebble is None:
            raise ActionNotApplicable("GRAB: the robot already holds the pebble")
        if self._pebble != self._here():
            raise ActionNotApplicable(f"GRAB needs the pebble at the robot's position; the robot is {self._where()}")
        self._pebble = None

    def _drop(self) -> None:
        if self._pebble is not None:
            raise ActionNotApplicable("DROP: the robot does not hold the pebble")
        self._pebble = self._here()

    def _init(self) -> None:
        if self.position is None:
            assert self._interior is not None
            hit = cast_ray(self.env, self._interior, self._heading)
            self._interior = None
            if hit.vertex is not None:  # straight into a vertex: no wall was followed
                self.position, self.arrived = (hit.vertex, Fraction(0)), None
                return
            self.position = (hit.edge, hit.t)
        edge, t = self.position
        if t != 0:
            self.position, self.arrived = ((edge + 1) % self.n, Fraction(0)), "R"
