"""Counting vertices and the winding number from actions and pebble readings alone (§IV of the paper).

Section IV's robot has INIT, RFOLLOW and LFOLLOW and a pebble fixed at a vertex, so every follow moves exactly
one vertex. Its history is the sequence of actions and observations; a filter keeps a few numbers and updates
them from each (action, observation) pair.

**Sign convention.** RFOLLOW moves counter-clockwise and counts a_i = +1, LFOLLOW clockwise, a_i = −1; a
positive winding number means counter-clockwise. (The paper sets a_i = +1 for LFOLLOW but calls a positive
winding counter-clockwise; its proof needs the convention used here.)

**The filter** (:class:`CountingFilter`). From the first stage at which the pebble is sensed, keep the
displacement disp = Σ a_i of the follows since then. The robot is back at the pebble with disp ≠ 0 only after
a whole turn around the boundary, so the first such stage gives n = |disp|. The winding number (base point the
pebble) is then disp / n truncated towards zero — the number of times the pebble was passed net — and it is 0
before n is known, since |disp| < n until the first whole turn.

**The printed filters are wrong** (:func:`printed_winding`, :func:`printed_vertex_count`, Eqs. 10 and 11 with
Prop. 2, kept verbatim to show it). Both sums start one stage *after* the first pebble contact and so drop the
action that leaves it; Eq. 10 also lacks the term of the current stage. From the pebble, one step
counter-clockwise, one back and one more clockwise gives κ₈ = 2 whatever n is, and a winding number of ±1 for
a walk that never went round.

>>> f = CountingFilter()
>>> for action, pebble in [("INIT", False), ("LFOLLOW", True), ("RFOLLOW", False), ("RFOLLOW", False),
...                        ("RFOLLOW", False), ("RFOLLOW", True), ("RFOLLOW", False)]:
...     f.update(action, pebble)
>>> f.n, f.winding, f.displacement
(4, 1, 5)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Reader, Stats, Status, answer_dataclass
from solverplan.wallfollow.world import Action, Observation, parse_action

__all__ = ["CountingFilter", "WalkCount", "count_random_walk", "count_walk", "printed_winding", "printed_vertex_count", "step_value"]


def step_value(action: Action | str) -> int:
    """a_i: +1 for RFOLLOW (counter-clockwise), −1 for LFOLLOW, 0 for anything else."""
    action = parse_action(action)
    return 1 if action is Action.RFOLLOW else -1 if action is Action.LFOLLOW else 0


def _pebble(observation: Observation | bool) -> bool:
    return observation.pebble if isinstance(observation, Observation) else bool(observation)


@dataclass
class CountingFilter:
    """The corrected vertex-count and winding-number filter (module docstring); O(1) memory.

    Feed it ``update(action, observation)`` for every action after the robot's first (the INIT that puts it at a
    vertex); an observation may be a :class:`~solverplan.wallfollow.world.Observation` or just the pebble bit.

    Attributes
    ----------
    stages
        Actions seen.
    displacement
        disp = Σ a_i since the first pebble contact (``None`` before it), in vertices.
    n
        The number of vertices once the robot has gone round once, else ``None``.
    """

    stages: int = 0
    displacement: int | None = None
    n: int | None = None

    def start(self, observation: Observation | bool) -> None:
        """The observation before the first action (at the stage where the robot starts)."""
        if self.displacement is None and _pebble(observation):
            self.displacement = 0

    def update(self, action: Action | str, observation: Observation | bool) -> None:
        """Account for one action and the observation after it."""
        a = step_value(action)
        self.stages += 1
        if self.displacement is not None:
            self.displacement += a
            if self.n is None and _pebble(observation) and self.displacement != 0:
                self.n = abs(self.displacement)
        elif _pebble(observation):
            self.displacement = 0

    @property
    def winding(self) -> int | None:
        """The winding number about the pebble (counter-clockwise positive), ``None`` before the first contact."""
        if self.displacement is None:
            return None
        if self.n is None:
            return 0  # |disp| < n until the first whole turn
        turns = abs(self.displacement) // self.n  # truncated towards zero, in integers
        return turns if self.displacement >= 0 else -turns


def count_walk(actions: Sequence[Action | str], observations: Sequence[Observation | bool],
               initial: Observation | bool = False) -> CountingFilter:
    """Run :class:`CountingFilter` over a history (``observations[i]`` is the reading after ``actions[i]``)."""
    if len(actions) != len(observations):
        raise InputError(f"count_walk: {len(actions)} actions but {len(observations)} observations")
    f = CountingFilter()
    f.start(initial)
    for action, obs in zip(actions, observations):
        f.update(action, obs)
    return f


# ---------------------------------------------------------------------- the printed filters, verbatim
def _printed_terms(actions: Sequence[Action | str], pebbles: Sequence[bool]) -> tuple[list[int], list[int], int | None]:
    """Paper's indexing: stage i = 1..k, u_i the action at stage i (a_i with the paper's sign: LFOLLOW +1),
    w_i the pebble bit of stage i; κ₄ the first stage with w_i = 1."""
    a = [0] + [-step_value(u) for u in actions]  # a[i] for i = 1..k−1 (a[0] unused)
    w = [0] + [int(bool(p)) for p in pebbles]  # w[i] for i = 1..k
    kappa4 = next((i for i in range(1, len(w)) if w[i]), None)
    return a, w, kappa4


def printed_winding(actions: Sequence[Action | str], pebbles: Sequence[bool]) -> int | None:
    """κ₅ of Eq. 10 at stage k, verbatim: Σ_{i=κ₄+1}^{k−1} w_i (a_{i−1} + a_i) / 2.

    ``pebbles`` has the k pebble bits of stages 1..k (``pebbles[0]`` before the first of the k − 1
    ``actions``). ``None`` before the first contact. Wrong in general (module docstring).
    """
    a, w, kappa4 = _printed_terms(actions, pebbles)
    if len(w) != len(a) + 1:
        raise InputError("printed_winding: give one more pebble bit than actions")
    if kappa4 is None:
        return None
    k = len(w) - 1
    total = sum(w[i] * (a[i - 1] + a[i]) for i in range(kappa4 + 1, k))
    return total // 2 if total % 2 == 0 else total / 2  # type: ignore[return-value]


def printed_vertex_count(actions: Sequence[Action | str], pebbles: Sequence[bool]) -> int | None:
    """κ₈ of Prop. 2 at stage k, verbatim: |κ₆(η_i)| at the first stage i with κ₅(η_i)·κ₆(η_i) ≠ 0, where
    κ₆ = Σ_{i=κ₄+1}^{k−1} a_i (Eq. 11); ``None`` while κ₈ = 0 (Prop. 2 then says nothing)."""
    for stage in range(1, len(pebbles) + 1):
        acts, bits = actions[:stage - 1], pebbles[:stage]
        a, w, kappa4 = _printed_terms(acts, bits)
        if kappa4 is None:
            continue
        kappa5 = printed_winding(acts, bits)
        kappa6 = sum(a[i] for i in range(kappa4 + 1, stage))
        if kappa5 and kappa6:
            return abs(kappa6)
    return None


@answer_dataclass("vertex-count")
class WalkCount(Answer):
    """The filter's answer after a seeded random walk in the geometric simulator, with the ground truth.

    Attributes
    ----------
    n, winding, displacement
        The filter's estimates at the end (``n`` is ``None`` until the walk has gone once round).
    known_after
        The number of follows after which n was known (``None`` if never).
    steps, seed
        The walk: ``steps`` follows, each RFOLLOW or LFOLLOW with probability 1/2 (``random.Random(seed)``).
    true_n, true_winding
        The polygon's vertex count and the walk's winding number about the pebble, from the simulator's exact
        positions (not from the filter).
    """

    n: int | None
    winding: int | None
    displacement: int | None
    known_after: int | None
    steps: int
    seed: int
    true_n: int
    true_winding: int
    environment: EnvironmentRecord | None = None

    @property
    def status(self) -> Status:
        return Status.FOUND if self.n is not None else Status.NOT_FOUND

    @property
    def optimality(self) -> Optimality:
        if self.n is None:
            return Optimality(Method.HEURISTIC, False, None, limits=(f"steps={self.steps}",),
                              algorithm="random walk")
        return Optimality(Method.EXACT_CHECK, self.n == self.true_n and self.winding == self.true_winding, None,
                          scope="the filter's n and winding against the simulator's ground truth",
                          algorithm="random walk")

    @property
    def stats(self) -> Stats:
        return Stats()

    def _fields(self) -> dict:
        return {"n": self.n, "winding": self.winding, "displacement": self.displacement,
                "known_after": self.known_after, "steps": self.steps, "seed": self.seed, "true_n": self.true_n,
                "true_winding": self.true_winding}

    @classmethod
    def from_json(cls, data: Any, *, env: Any = None) -> WalkCount:
        """Read a vertex count back (every field is in its JSON; ``env`` is not needed)."""
        r = Reader(data, "vertex_count")
        return cls(r.integer("n", None), r.integer("winding", None), r.integer("displacement", None),
                   r.integer("known_after", None), r.integer("steps"), r.integer("seed"), r.integer("true_n"),
                   r.integer("true_winding"), r.environment())

    def to_text(self, *, width: int = 100) -> str:
        known = f"n = {self.n} (known after {self.known_after} follows)" if self.n is not None else \
            f"n unknown after {self.steps} follows (the walk never went round)"
        return (f"random walk of {self.steps} follows (seed {self.seed}): {known}, winding {self.winding}\n"
                f"ground truth: n = {self.true_n}, winding {self.true_winding}\n")


def count_random_walk(env: Environment, steps: int = 1000, seed: int = 0,
                      start: Sequence[object] | None = None, heading: Sequence[object] = (1, 0)) -> WalkCount:
    """Section IV's task in the geometric simulator: INIT, DROP the pebble at that vertex, then ``steps``
    random follows, filtered by :class:`CountingFilter`.

    Parameters
    ----------
    env
        A simple polygon in general position.
    steps
        Number of follows (≥ 0); an unbiased walk needs about n² of them to go round once.
    seed
        Seed of the walk.
    start, heading
        The robot's start (default vertex 0) and INIT's direction from an interior start.
    """
    import random

    from solverplan.wallfollow.world import WallWorld

    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 0:
        raise InputError(f"steps must be a non-negative integer, got {steps!r}")
    world = WallWorld(env, start, heading)
    world.act(Action.INIT)
    world.act(Action.DROP)
    f = CountingFilter()
    f.start(world.observe())
    rng = random.Random(seed)
    n = world.env.n_vertices  # the corners (collinear vertices are passed on an edge)
    lift, known_after = 0, None
    for k in range(steps):
        action = Action.RFOLLOW if rng.random() < 0.5 else Action.LFOLLOW
        before = world.position
        f.update(action, world.act(action))
        assert before is not None and world.position is not None
        lift += 1 if (world.position[0] - before[0]) % n == 1 else -1  # exact positions: the ground truth
        if f.n is not None and known_after is None:
            known_after = k + 1
    turns = abs(lift) // n
    return WalkCount(f.n, f.winding, f.displacement, known_after, steps, seed, n, turns if lift >= 0 else -turns,
                     EnvironmentRecord.of(env))
