"""Strategy 1: the robot learns the cut ordering from its own actions and sensor readings (§V-C of the paper).

The strategy talks to the robot only through ``act(action) -> Observation`` (the geometric simulator
:class:`~solverplan.wallfollow.world.WallWorld`, the combinatorial :class:`OrderingWorld`, or a real robot):
it never sees coordinates. It numbers the vertices itself, counter-clockwise with 0 where it drops the pebble,
so its ordering equals the geometric one up to renaming the vertices (the only freedom a cut ordering has).

1. INIT, DROP, then LFOLLOW until the pebble is sensed again: n is the number of follows, and the touch sensor
   tells which vertices are reflex. After j follows the robot is at vertex −j (mod n).
2. For each reflex vertex k: go to k arriving by LFOLLOW, JUMP (along the left cut), then LFOLLOW until the
   pebble, counting c follows: ℓ_k lies on edge c − 1 (the first follow reaches the edge's start vertex, then
   c − 1 more reach vertex 0). The same with RFOLLOW for r_k: it lies on edge n − c. (The paper's index
   formula, between v_{n−m+1} and v_{n−m}, is off by one on one side and uses the clockwise numbering.)
3. For two end points on one edge: JUMP along the first cut, DROP the pebble there, JUMP along the second and
   RFOLLOW: the pebble is met first exactly when the first end point comes after the second
   counter-clockwise. Then fetch the pebble back to vertex 0. ``comparisons="pairwise"`` compares every pair
   on an edge, as the paper does; ``"sort"`` runs a merge sort (O(k log k) comparisons for k end points).

**Cost.** Steps 1–2 take O(n) actions per cut, O(n²) in all, as Prop. 5 says. Each comparison also costs O(n)
actions (going to the cut's vertex and back), so an edge that receives k end points costs O(k² n) actions
pairwise and O(k log k · n) sorted: with Θ(n) end points on one edge Strategy 1 takes Θ(n³) actions, more than
Prop. 5's O(n²). Memory: the learned map — a type per vertex and an edge and a rank per cut end point — plus a
few counters, O(n) words.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
>>> learned = learn_cut_ordering(room, start=(2, 2), heading=(0, -1))
>>> learned.ordering.labels, learned.pebble_vertex, learned.matches_geometry
(('v0', 'v1', 'v2', 'v3', 'v4', 'r2', 'v5', 'l2'), 1, True)
>>> learned.actions, learned.memory
(24, 12)
"""

from __future__ import annotations

import functools
from dataclasses import field
from typing import Any, Protocol, Sequence

from solverplan.choices import Comparisons
from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.result import Construction, EnvironmentRecord, Method, Optimality, Reader, Stats, answer_dataclass
from solverplan.wallfollow.cut import cut_ordering
from solverplan.wallfollow.ordering import CutOrdering
from solverplan.wallfollow.world import Action, Observation, Touch, WallWorld

__all__ = ["Robot", "LearnedOrdering", "strategy1", "learn_cut_ordering"]



class Robot(Protocol):
    """Anything the strategy can drive: one action in, one observation out."""

    def act(self, action: Action | str) -> Observation: ...


@answer_dataclass("learned-ordering")
class LearnedOrdering(Construction):
    """What Strategy 1 learned, and what it cost.

    Attributes
    ----------
    ordering
        The cut ordering in the robot's own numbering (v0 = the vertex where it dropped the pebble).
    actions
        Actions executed in all.
    memory
        Words of the learned map when done: n vertex types, and an edge and a rank per cut end point, plus the
        counters n and the robot's position (2).
    counts
        Actions by phase (``count`` — step 1; ``locate`` — step 2; ``order`` — step 3), ``comparisons``, and
        actions by kind.
    transcript
        Every ``(action, observation)``, when kept.
    pebble_vertex, matches_geometry
        When learned in a :class:`~solverplan.wallfollow.world.WallWorld`: the environment's vertex the robot
        calls v0, and whether the learned ordering renamed by it is exactly the geometric one (ground truth).
    """

    ordering: CutOrdering
    actions: int
    memory: int
    counts: dict[str, int]
    transcript: tuple[tuple[Action, Observation], ...] | None = None
    pebble_vertex: int | None = None
    matches_geometry: bool | None = None
    environment: EnvironmentRecord | None = None
    stats: Stats = field(default_factory=Stats)


    @property
    def optimality(self) -> Optimality:
        proved = bool(self.matches_geometry)
        return Optimality(Method.EXACT_CHECK if proved else Method.NONE, proved, None,
                          scope="the learned ordering against the exact geometric cut ordering" if proved else "",
                          algorithm="Strategy 1")

    def _fields(self) -> dict:
        out: dict[str, Any] = {"cut_ordering": list(self.ordering.labels),
                               "n": self.ordering.n, "reflex": list(self.ordering.reflex), "actions": self.actions,
                               "memory": self.memory, "counts": dict(self.counts)}
        if self.pebble_vertex is not None:
            out["pebble_vertex"] = self.pebble_vertex
            out["matches_geometry"] = self.matches_geometry
        if self.transcript is not None:
            out["transcript"] = [{"action": a.value, "touch": o.touch.value, "pebble": o.pebble}
                                 for a, o in self.transcript]
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Any = None) -> LearnedOrdering:
        """Read what Strategy 1 learned back (every field is in its JSON; ``env`` is not needed)."""
        r = Reader(data, "learned_ordering")
        transcript = None
        if r.has("transcript"):
            transcript = tuple((Action(t.string("action")), Observation(Touch(t.string("touch")), t.boolean("pebble")))
                               for t in r.items("transcript"))
        counts = r.sub("counts")
        return cls(CutOrdering.from_labels(r.texts("cut_ordering")), r.integer("actions"), r.integer("memory"),
                   {str(k): counts.integer(k) for k in counts.data}, transcript, r.integer("pebble_vertex", None),
                   r.boolean("matches_geometry", None), r.environment(), r.stats())

    def to_text(self, *, width: int = 100) -> str:
        lines = [f"Strategy 1: learned from {self.actions} actions ({self.counts.get('comparisons', 0)} comparisons), "
                 f"memory {self.memory} words"]
        if self.matches_geometry is not None:
            verdict = "equals" if self.matches_geometry else "DIFFERS FROM"
            lines.append(f"the robot's v0 is vertex {self.pebble_vertex}; renamed, the ordering {verdict} the "
                         f"geometric one")
        return "\n".join(lines) + "\n" + self.ordering.to_text(width=width)


class _Learner:
    """Strategy 1's state: what the robot knows (its position in its own numbering, where the pebble is)."""

    def __init__(self, robot: Robot, keep: bool, max_actions: int) -> None:
        self.robot = robot
        self.max_actions = max_actions
        self.done = 0
        self.n = 0
        self.at: tuple[str, int] = ("v", 0)  # ("v", vertex) or ("e", edge): on an edge's interior
        self.arrived: str | None = None
        self.pebble: tuple[str, int] | None = None  # where the pebble lies ("v", 0) / ("e", edge); None: carried
        self.phase = "count"
        self.counts: dict[str, int] = {"count": 0, "locate": 0, "order": 0, "comparisons": 0}
        self.transcript: list[tuple[Action, Observation]] | None = [] if keep else None

    def act(self, action: Action) -> Observation:
        if self.done >= self.max_actions:
            raise InputError(f"Strategy 1 stopped after max_actions = {self.max_actions:,} actions: the polygon is "
                             f"too large for it (it needs about n² actions, more with many cut end points on one edge)")
        self.done += 1
        obs = self.robot.act(action)
        self.counts[self.phase] += 1
        self.counts[action.value] = self.counts.get(action.value, 0) + 1
        if self.transcript is not None:
            self.transcript.append((action, obs))
        return obs

    # ------------------------------------------------------------------ moving with a known position
    def follow(self, action: Action) -> Observation:
        """One follow, tracking the position (a stop inside an edge can only be at the pebble)."""
        obs = self.act(action)
        kind, i = self.at
        forward = action is Action.RFOLLOW
        if obs.at_vertex:
            if kind == "v":
                self.at = ("v", (i + (1 if forward else -1)) % self.n)
            else:
                self.at = ("v", (i + 1) % self.n if forward else i)
        elif obs.touch is Touch.EDGE and obs.pebble and self.pebble is not None and self.pebble[0] == "e":
            self.at = ("e", self.pebble[1] if kind == "v" else i)
        else:
            raise SolverFailed(f"Strategy 1 lost track of the robot: {action.value} from {kind}{i} sensed {obs}")
        self.arrived = "R" if forward else "L"
        return obs

    def to_vertex(self, action: Action) -> None:
        """Follow until a vertex (passing the pebble where it lies inside an edge)."""
        while not self.follow(action).at_vertex:
            pass

    def goto(self, target: int, arrive: str | None = None) -> None:
        """Go to vertex ``target``, arriving by LFOLLOW (``"L"``), RFOLLOW (``"R"``) or either (``None``)."""
        n = self.n
        if self.at == ("v", target) and (arrive is None or self.arrived == arrive):
            return
        if self.at[0] == "e":  # first to a vertex: the edge's end
            self.to_vertex(Action.RFOLLOW)
        via = target if arrive is None else (target + 1) % n if arrive == "L" else (target - 1) % n
        d = (via - self.at[1]) % n
        action = Action.RFOLLOW if d <= n - d else Action.LFOLLOW
        for _ in range(d if action is Action.RFOLLOW else n - d):
            self.to_vertex(action)
        if arrive is not None:
            self.to_vertex(Action.LFOLLOW if arrive == "L" else Action.RFOLLOW)
        elif self.at != ("v", target):  # target == via but the loop did not run: already there
            raise SolverFailed("Strategy 1 navigation did not reach its target")

    def jump_along(self, side: str, k: int) -> None:
        self.goto(k, "L" if side == "l" else "R")
        obs = self.act(Action.JUMP)
        if obs.touch is not Touch.EDGE:
            raise SolverFailed(f"Strategy 1: JUMP from vertex {k} sensed {obs}, not an edge (general position)")
        self.at, self.arrived = ("e", -1), None  # edge not known yet (or known to the caller)

    # ------------------------------------------------------------------ the strategy
    def count(self) -> list[Touch]:
        self.act(Action.INIT)
        obs = self.act(Action.DROP)
        self.pebble = ("v", 0)
        types = [obs.touch]
        while True:
            obs = self.act(Action.LFOLLOW)
            if obs.pebble:
                break
            if not obs.at_vertex:
                raise SolverFailed(f"Strategy 1: LFOLLOW sensed {obs} while counting vertices")
            types.append(obs.touch)
        self.n, self.at, self.arrived = len(types), ("v", 0), "L"
        if self.n < 3:
            raise SolverFailed(f"Strategy 1 counted {self.n} vertices")
        # types[j] is the vertex reached after j clockwise follows: vertex −j (mod n)
        return [types[(-k) % self.n] for k in range(self.n)]

    def locate(self, side: str, k: int) -> int:
        """The edge of the end point of cut ``side`` of vertex ``k`` (the pebble at vertex 0)."""
        self.jump_along(side, k)
        action = Action.LFOLLOW if side == "l" else Action.RFOLLOW
        steps = 0
        while True:
            steps += 1
            if self.act(action).pebble:
                break
            if steps > self.n + 1:
                raise SolverFailed("Strategy 1 did not meet the pebble after a whole turn")
        self.at, self.arrived = ("v", 0), "L" if side == "l" else "R"
        return steps - 1 if side == "l" else self.n - steps

    def before(self, first: tuple[str, int], second: tuple[str, int], edge: int) -> bool:
        """Does end point ``first`` come before ``second`` (counter-clockwise) on ``edge``? Starts and ends with
        the robot and the pebble at vertex 0."""
        self.counts["comparisons"] += 1
        self.goto(0)
        self.act(Action.GRAB)
        self.pebble = None
        self.jump_along(*first)
        self.at = ("e", edge)
        self.act(Action.DROP)
        self.pebble = ("e", edge)
        self.jump_along(*second)
        self.at = ("e", edge)
        obs = self.follow(Action.RFOLLOW)
        answer = not obs.pebble  # reached the edge's end vertex first: the pebble (first) was behind
        if not obs.pebble:
            self.follow(Action.LFOLLOW)  # back along the edge to the pebble
        self.act(Action.GRAB)
        self.pebble = None
        self.goto(0)
        self.act(Action.DROP)
        self.pebble = ("v", 0)
        return answer


#: Strategy 1 stops (InputError) after this many actions by default: n = 3,000 vertices already need ~10⁷.
MAX_ACTIONS = 20_000_000


def strategy1(robot: Robot, *, comparisons: Comparisons | str = "pairwise", transcript: bool = False,
              max_actions: int = MAX_ACTIONS) -> LearnedOrdering:
    """Learn the cut ordering by Strategy 1, from the robot's observations only.

    Parameters
    ----------
    robot
        Anything with ``act(action) -> Observation`` that starts carrying the pebble, in a simple polygon in
        general position.
    comparisons
        ``"pairwise"`` (the paper: every pair of end points on one edge) or ``"sort"`` (a merge sort).
    transcript
        Keep every action and observation.
    max_actions
        Stop with an :class:`~solverplan.errors.InputError` after this many actions.

    Returns
    -------
    LearnedOrdering
        The ordering in the robot's numbering (v0 where it dropped the pebble), with its costs.
    """
    comparisons = Comparisons.parse(comparisons, "comparisons").value
    learner = _Learner(robot, transcript, max_actions)
    types = learner.count()
    n = learner.n
    reflex = [k for k in range(n) if types[k] is Touch.REFLEX]
    learner.phase = "locate"
    on_edge: dict[int, list[tuple[str, int]]] = {}
    for k in reflex:
        for side in ("l", "r"):
            on_edge.setdefault(learner.locate(side, k), []).append((side, k))
    learner.phase = "order"
    labels: list[str] = []
    for e in range(n):
        labels.append(f"v{e}")
        ends = on_edge.get(e, [])
        if len(ends) > 1 and comparisons == "pairwise":
            later = {c: 0 for c in ends}  # how many end points of the edge come before c
            for i, a in enumerate(ends):
                for b in ends[i + 1:]:
                    later[b if learner.before(a, b, e) else a] += 1
            ends = sorted(ends, key=later.__getitem__)
        elif len(ends) > 1:
            def order(a: tuple[str, int], b: tuple[str, int], edge: int = e) -> int:
                return -1 if learner.before(a, b, edge) else 1

            ends = sorted(ends, key=functools.cmp_to_key(order))
        labels.extend(f"{side}{k}" for side, k in ends)
    counts = dict(learner.counts)
    actions = counts["count"] + counts["locate"] + counts["order"]
    return LearnedOrdering(CutOrdering.from_labels(labels), actions, n + 2 * 2 * len(reflex) + 2, counts,
                           None if learner.transcript is None else tuple(learner.transcript))


def learn_cut_ordering(env: Environment, start: Sequence[object] | None = None, heading: Sequence[object] = (1, 0),
                       *, comparisons: Comparisons | str = "pairwise", transcript: bool = False,
                       max_actions: int = MAX_ACTIONS) -> LearnedOrdering:
    """Run Strategy 1 in the geometric simulator and check the result against the exact cut ordering.

    Parameters
    ----------
    env
        A simple polygon in general position.
    start, heading
        The robot's start point (interior or boundary, length units; default vertex 0) and the direction INIT
        drives in from an interior start.
    comparisons, transcript, max_actions
        As for :func:`strategy1`.

    Returns
    -------
    LearnedOrdering
        With ``pebble_vertex`` (the environment vertex the robot calls v0) and ``matches_geometry``.

    Examples
    --------
    >>> import solverplan as sp
    >>> learned = sp.learn_cut_ordering(sp.load_environment("l_shape"))
    >>> learned.ordering.labels, learned.matches_geometry
    (('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3'), True)
    >>> learned.actions, learned.memory          # actions executed, words of memory at the end
    (18, 12)
    """
    world = WallWorld(env, start, heading)
    learned = strategy1(world, comparisons=comparisons, transcript=transcript, max_actions=max_actions)
    pebble = world.pebble
    assert pebble is not None and len(pebble) == 2 and pebble[1] == 0
    p = int(pebble[0])
    truth = cut_ordering(env)
    return LearnedOrdering(learned.ordering, learned.actions, learned.memory, learned.counts, learned.transcript,
                           p, learned.ordering.relabel(p).labels == truth.labels, EnvironmentRecord.of(env),
                           Stats(counts={"n": world.env.n_vertices, "m": len(env.reflex_vertices)}))
