"""The combinatorial simulator: the robot driven by the cut ordering alone, without geometry (Prop. 7).

Every action from a point of M (a vertex or a cut end point) ends at a point of M, and the cut ordering says
which: a follow goes to the next vertex (or the pebble, if it lies on the way) in cyclic order, forwards for
RFOLLOW and backwards for LFOLLOW; a JUMP from reflex vertex K goes to ``rK`` after RFOLLOW and to ``lK``
after LFOLLOW. The sensors are read off the ordering too: a vertex is reflex exactly when it has cuts, and a cut
end point lies inside an edge. Prop. 7 says this predicts every action sequence of the geometric simulator
(:class:`~solverplan.wallfollow.world.WallWorld`) started at a point of M — the tests check it.

>>> from solverplan.wallfollow.ordering import CutOrdering
>>> order = CutOrdering.from_labels(["v0", "l3", "v1", "v2", "v3", "v4", "v5", "r3"])
>>> robot = OrderingWorld(order)
>>> [str(robot.act(a)) for a in ["DROP", "RFOLLOW", "RFOLLOW", "RFOLLOW", "JUMP", "RFOLLOW"]]
['convex+pebble', 'convex', 'convex', 'reflex', 'edge', 'convex+pebble']
>>> robot.label
'v0'
"""

from __future__ import annotations

from solverplan.errors import InputError
from solverplan.wallfollow.ordering import CutOrdering, parse_label
from solverplan.wallfollow.world import Action, ActionNotApplicable, Observation, Touch, parse_action

__all__ = ["OrderingWorld"]


class OrderingWorld:
    """The robot on the points of a cut ordering, with the same actions and sensors as the geometric simulator.

    Parameters
    ----------
    ordering
        The cut ordering.
    start
        The starting point's name (``"v0"``, ``"l3"``); default ``"v0"``.
    carrying
        Whether the robot starts with the pebble (default True); otherwise the pebble lies at ``start``.
    """

    def __init__(self, ordering: CutOrdering, start: str = "v0", *, carrying: bool = True) -> None:
        self.ordering = ordering
        self._labels = ordering.labels
        self._reflex = frozenset(ordering.reflex)
        self.position = ordering.index(start)
        self.arrived: str | None = None
        self.pebble: int | None = None if carrying else self.position
        self.transcript: list[tuple[Action, Observation]] = []

    @property
    def label(self) -> str:
        """The robot's position (a point name)."""
        return self._labels[self.position]

    @property
    def carrying(self) -> bool:
        return self.pebble is None

    def observe(self) -> Observation:
        kind, k = parse_label(self.label)
        touch = Touch.EDGE if kind != "v" else Touch.REFLEX if k in self._reflex else Touch.CONVEX
        return Observation(touch, self.pebble == self.position)

    def act(self, action: Action | str) -> Observation:
        """Execute one action (:class:`~solverplan.wallfollow.world.ActionNotApplicable` where it does not
        apply, as in the geometric simulator)."""
        action = parse_action(action)
        size = len(self._labels)
        if action in (Action.RFOLLOW, Action.LFOLLOW, Action.INIT):
            step = -1 if action is Action.LFOLLOW else 1
            if action is Action.INIT and self.label[0] == "v":
                pass  # already at a vertex: INIT does nothing
            else:
                i = self.position
                while True:
                    i = (i + step) % size
                    if self._labels[i][0] == "v" or (action is not Action.INIT and self.pebble == i):
                        break
                self.position, self.arrived = i, "L" if step < 0 else "R"
        elif action is Action.JUMP:
            kind, k = parse_label(self.label)
            if kind != "v" or k not in self._reflex or self.arrived is None:
                raise ActionNotApplicable(f"JUMP needs a reflex vertex reached by following the wall; the robot "
                                          f"is at {self.label}")
            self.position = self.ordering.index(f"{'r' if self.arrived == 'R' else 'l'}{k}")
            self.arrived = None
        elif action is Action.GRAB:
            if self.pebble != self.position:
                raise ActionNotApplicable("GRAB needs the pebble at the robot's position"
                                          if self.pebble is not None else "GRAB: the robot already holds the pebble")
            self.pebble = None
        elif action is Action.DROP:
            if self.pebble is not None:
                raise ActionNotApplicable("DROP: the robot does not hold the pebble")
            self.pebble = self.position
        else:  # pragma: no cover - Action is exhaustive
            raise InputError(f"unknown action {action}")
        obs = self.observe()
        self.transcript.append((action, obs))
        return obs
