"""Pursuit-evasion plans for the wall-following robot: Strategy 2, the gap sensor (§VI-B of the paper), and the
search shared with Strategy 3 (the bitangent sensor, :mod:`~solverplan.wallfollow.pursuit_primitives`) and
Strategy 5 (Strategy 3 on the bitangents that Strategy 4 learns with the pebble-visibility sensor,
:mod:`~solverplan.wallfollow.pebble`).

The pursuer moves by RFOLLOW, LFOLLOW and JUMP between the points of the cut ordering. The **gap sensor**
reports the gaps of its view — one per shadow component, named here by the reflex vertex the gap's window
starts at — and tracks them while the pursuer moves: which gap appeared, disappeared, split off another or
merged into another. The derived I-state of Strategy 2 is (position in the cut ordering, the arrival direction
at a reflex vertex (which JUMP is possible), the gaps labelled 1); a complete breadth-first search over the
reachable I-states finds a plan whose end state has every label 0, with the fewest actions, or proves that none
exists (Prop. 8: the reachable I-space is finite).

How the labels travel over one action is derived from the events the motion crosses, as the paper describes
them: the motion (a segment along an edge, or along a cut for a JUMP) is cut at every crossing with

- an **inflection** (:func:`~solverplan.wallfollow.bitangent.inflections`) of reflex vertex v: the gap at v
  appears (label 0) or disappears;
- any other cut — it extends an edge between two consecutive reflex vertices v, w: the gap **slides** from v
  to w or back (same component, same label);
- a **bitangent ray** (:func:`~solverplan.wallfollow.bitangent.bitangents`) from v_i to b_ij: the gap at v_j
  splits off the gap at v_i (it inherits its label) or merges into it (the label becomes the OR).

and the gap sensor's reading between two crossings says which gaps there are. A change of the gaps that these
events do not explain is a :class:`~solverplan.errors.SolverFailed` (never silently ignored). The ground truth
(:func:`~solverplan.wallfollow.pursuit_check.check_pursuit`: exact shadow polygons, labels by overlap) replays
every plan found; the tests compare the two action by action.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
>>> plan = pursuit_plan(room, start="v1")
>>> plan.status.value, plan.actions, plan.verified
('found', ('LFOLLOW',), True)
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import field
from fractions import Fraction
from typing import Any

from solverplan.choices import Sensor
from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.limits import quote
from solverplan.exact import ExactPoint, format_point, segment_intersection
from solverplan.geometry.visibility import visibility_polygon
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Stats, Status, answer_dataclass
from solverplan.wallfollow.bitangent import bitangents
from solverplan.wallfollow.cut import corner_polygon, cut_ordering, cuts, merged_count
from solverplan.wallfollow.ordering import CutOrdering, parse_label
from solverplan.wallfollow.pursuit_check import PursuitCheck, Transfer, check_pursuit
from solverplan.wallfollow.world import Action

__all__ = ["GapSensor", "PursuitPlan", "pursuit_plan", "SENSORS", "DEFAULT_MAX_STATES"]

#: The sensors ``pursuit_plan`` knows.
SENSORS = Sensor.values()

#: The strategy of each implemented sensor.
STRATEGY = {"gap": "Strategy 2", "bitangent": "Strategy 3", "pebble": "Strategy 5", "contact": "Strategy 6"}

#: The strategies whose search is complete (a failure proves that no plan exists).
COMPLETE = ("gap", "bitangent", "pebble")

#: The cap on derived I-states a search expands (the I-space is exponential in the number of gaps).
DEFAULT_MAX_STATES = 200_000

#: An event a motion crosses: ("inflection", v, v), ("slide", v, w) for consecutive reflex v, w, or
#: ("bitangent", near, far) for the bitangent ray that starts at ``near``.
Event = tuple[str, int, int]


def _gaps(env: Environment, p: ExactPoint) -> frozenset[int]:
    """The gap sensor's reading at p: the reflex vertices that start a window of the visibility polygon."""
    return frozenset(piece.reflex_vertex for piece in visibility_polygon(env, p).pieces
                     if piece.kind == "constructed" and piece.reflex_vertex is not None)


def _param(p0: ExactPoint, p1: ExactPoint, x: ExactPoint) -> Fraction:
    """The parameter of x on the segment p0 → p1 (x is on it)."""
    c = 0 if p1[0] != p0[0] else 1
    return (x[c] - p0[c]) / (p1[c] - p0[c])


def _collinear(p0: ExactPoint, p1: ExactPoint, x: ExactPoint) -> bool:
    return (p1[0] - p0[0]) * (x[1] - p0[1]) - (p1[1] - p0[1]) * (x[0] - p0[0]) == 0


def _on_segment(p0: ExactPoint, p1: ExactPoint, x: ExactPoint) -> bool:
    return _collinear(p0, p1, x) and min(p0[0], p1[0]) <= x[0] <= max(p0[0], p1[0]) \
        and min(p0[1], p1[1]) <= x[1] <= max(p0[1], p1[1])


class GapSensor:
    """The gap sensor of one polygon: the gaps at a point and how their labels travel over a motion.

    Parameters
    ----------
    env
        A simple polygon in general position.
    """

    def __init__(self, env: Environment) -> None:
        self.env = env
        n = env.n_vertices
        reflex = set(env.reflex_vertices)
        pts = env.exact_vertices
        rays: list[tuple[ExactPoint, ExactPoint, Event]] = []
        for c in cuts(env):
            v = c.vertex
            w = (v - 1) % n if c.side == "r" else (v + 1) % n  # the neighbour whose edge the cut extends
            event: Event = ("slide", min(v, w), max(v, w)) if w in reflex else ("inflection", v, v)
            rays.append((pts[v], c.point, event))
        for b in bitangents(env):
            rays.append((pts[b.i], b.point_ij, ("bitangent", b.i, b.j)))
            rays.append((pts[b.j], b.point_ji, ("bitangent", b.j, b.i)))
        self.rays = tuple(rays)
        # moving into or out of a vertex the pursuer also passes the lines of the chain edges at it
        self._slides_at: dict[ExactPoint, list[Event]] = {}
        for v in reflex:
            for w in ((v - 1) % n, (v + 1) % n):
                if w in reflex:
                    self._slides_at.setdefault(pts[v], []).append(("slide", min(v, w), max(v, w)))
        self._cache: dict[tuple[ExactPoint, ExactPoint], Transfer] = {}

    def gaps(self, p: ExactPoint) -> frozenset[int]:
        """The gaps at p (reflex vertices)."""
        return _gaps(self.env, p)

    def _events(self, p0: ExactPoint, p1: ExactPoint) -> dict[Fraction, list[Event]]:
        out: dict[Fraction, list[Event]] = {}
        for a, b, event in self.rays:
            if _collinear(p0, p1, a) and _collinear(p0, p1, b):
                hits = [x for x in (a, b) if _on_segment(p0, p1, x)]
            else:
                meet = segment_intersection(p0, p1, a, b)
                hits = [] if meet is None else list(meet.points)
            for x in hits:
                out.setdefault(_param(p0, p1, x), []).append(event)
        for s, x in ((Fraction(0), p0), (Fraction(1), p1)):
            out.setdefault(s, []).extend(self._slides_at.get(x, []))
        return out

    def transfer(self, p0: ExactPoint, p1: ExactPoint) -> Transfer:
        """How the labels travel from p0 to p1 along the segment between them: every gap at p1 → the gaps at
        p0 whose labels it ORs (an empty set: label 0).

        Raises
        ------
        SolverFailed
            If the gaps change in a way that the crossed events do not explain.
        """
        key = (p0, p1)
        if key in self._cache:
            return self._cache[key]
        events = self._events(p0, p1)
        params = sorted(set(events) | {Fraction(0), Fraction(1)})
        samples = [p0] + [(p0[0] + m * (p1[0] - p0[0]), p0[1] + m * (p1[1] - p0[1]))
                          for m in ((s0 + s1) / 2 for s0, s1 in zip(params, params[1:]))] + [p1]
        # the events at params[k] lie between samples[k] and samples[k + 1]
        total: Transfer = {g: frozenset({g}) for g in self.gaps(p0)}
        before = frozenset(total)
        for k, s in enumerate(params):
            after = self.gaps(samples[k + 1])
            step = self._step(before, after, events.get(s, []), samples[k + 1])
            total = {g: frozenset().union(*(total[h] for h in src)) for g, src in step.items()}
            before = after
        self._cache[key] = total
        return total

    def _step(self, before: frozenset[int], after: frozenset[int], events: list[Event], where: ExactPoint) -> Transfer:
        """One group of simultaneous events: the gaps after → the gaps before they come from."""
        out: Transfer = {g: frozenset({g}) if g in before else frozenset() for g in after}
        new, gone = set(after - before), set(before - after)
        moved: dict[int, int] = {}
        for kind, a, b in events:  # slides first: a slid gap keeps its label under its new name
            if kind != "slide":
                continue
            for x, y in ((a, b), (b, a)):
                if x in before - after and y in after - before:
                    out[y] = out[y] | {x}
                    moved[x] = y
                    new.discard(y)
                    gone.discard(x)
        for kind, a, b in events:
            if kind == "inflection":
                new.discard(a)  # appears with label 0 (already empty)
                gone.discard(a)
        for kind, near, far in events:
            if kind != "bitangent":
                continue
            target = near if near in after else moved.get(near)
            if far in before and far not in after and target is not None:  # merge into the near gap
                out[target] = out[target] | {far}
                gone.discard(far)
            elif far in after and far not in before:  # split off the near gap
                out[far] = out[far] | (frozenset({near}) if near in before else out.get(near, frozenset()))
                new.discard(far)
        if new or gone:
            raise SolverFailed(f"gap sensor near {format_point(where)}: gaps {sorted(before)} became {sorted(after)} "
                               f"but the crossed events {sorted(set(events))} explain neither "
                               f"{sorted(new)} appearing nor {sorted(gone)} vanishing")
        return out


@answer_dataclass("pursuit")
class PursuitPlan(Answer):
    """A pursuit plan of the wall-following robot, or the proof that none exists.

    Attributes
    ----------
    status
        ``found``; ``infeasible`` (the reachable I-space was exhausted: no plan exists, Props. 8 and 10);
        ``not-found`` (the cap on I-states was hit, or Strategy 6 found none).
    actions
        The plan (RFOLLOW, LFOLLOW, JUMP), fewest actions; empty when not found.
    start
        The pursuer's start, a point of the cut ordering.
    sensor
        The sensor model (``gap``: Strategy 2).
    positions
        The points of the cut ordering the plan visits, the start first.
    states
        Derived I-states explored.
    check
        The ground-truth replay of the plan (:func:`~solverplan.wallfollow.pursuit_check.check_pursuit`): a
        :class:`~solverplan.verdict.Verdict` (``valid``, ``failures``, ``checked``, ``not_checked``, ...) with the
        replay's steps; ``verified`` is its ``valid`` (``None`` without a plan).
    reason
        Why there is no plan, in words (``infeasible`` / ``not-found``).
    learning
        With the pebble-visibility sensor: what Strategy 4 learned first, and its cost
        (:class:`~solverplan.wallfollow.pebble.LearnedBitangents`).

    Examples
    --------
    A room with a wall jutting in from the right: from v0 the pocket above the wall is out of sight.

    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> chase = sp.pursuit_plan(room)
    >>> chase.status.value, chase.actions, chase.positions, chase.verified
    ('found', ('LFOLLOW',), ('v0', 'v6'), True)
    >>> chase.check.valid, chase.check.proved[0][:44], chase.to_json()["verdict"]["valid"]
    (True, 'during action 1 no shadow component can hold', True)
    """

    status: Status
    actions: tuple[str, ...]
    start: str
    sensor: str
    positions: tuple[str, ...]
    states: int
    ordering: CutOrdering
    check: PursuitCheck | None = None
    reason: str = ""
    limits: tuple[str, ...] = ()
    environment: EnvironmentRecord | None = None
    stats: Stats = field(default_factory=Stats)
    learning: Any = None

    @property
    def verified(self) -> bool | None:
        """The ground-truth checker's verdict on the plan (``None`` without a plan)."""
        return None if self.check is None else self.check.valid

    @property
    def optimality(self) -> Optimality:
        scope = (f"plans of RFOLLOW, LFOLLOW and JUMP actions from the start, judged at action ends by the "
                 f"{self.sensor} sensor")
        algorithm = f"{STRATEGY[self.sensor]} (BFS)"
        if self.limits:
            return Optimality(Method.HEURISTIC, False, None, scope=scope, algorithm=algorithm, limits=self.limits)
        if self.sensor not in COMPLETE:  # shortest under its own pessimism only; failure proves nothing
            return Optimality(Method.HEURISTIC, False, None, scope=scope, algorithm=algorithm)
        bound = float(len(self.actions)) if self.status is Status.FOUND else None
        return Optimality(Method.SEARCH_EXHAUSTED, True, bound, scope=scope, algorithm=algorithm)

    def _fields(self) -> dict:
        out: dict[str, Any] = {"plan": list(self.actions), "verified": self.verified,
                               "sensor": self.sensor, "start": self.start, "plan_length": len(self.actions),
                               "positions": list(self.positions), "states": self.states,
                               "cut_ordering": list(self.ordering.labels)}
        if self.check is not None:
            out["cleared_after"] = self.check.cleared_after
            out["check_samples"] = self.check.samples
            out["shadow_labels"] = [sorted(f"v{g}" for g in step.labels) for step in self.check.steps]
            out["verdict"] = self.check.verdict_json()
        if self.reason:
            out["reason"] = self.reason
        if self.learning is not None:
            out["learning_actions"] = self.learning.actions
            out["visibility_queries"] = self.learning.visibility_queries
            out["bitangents"] = [[f"v{b.i}", f"v{b.j}", b.after_ij, b.after_ji] for b in self.learning.bitangents]
            out["bitangent_candidates"] = self.learning.candidates
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> PursuitPlan:
        """Read a pursuit plan back in ``env`` (required): the plan is replayed again by the geometric ground-truth
        checker (its verdict, samples and shadow labels are recomputed, not read)."""
        from solverplan.wallfollow.pebble import LearnedBitangent, LearnedBitangents

        r, env, record = cls._reader_in(data, env, "pursuit")
        actions = tuple(r.texts("plan"))
        start = r.string("start")
        learning = None
        if r.has("learning_actions"):
            found = []
            for k, b in enumerate(r.array("bitangents")):
                item = r.at(f"bitangents[{k}]", b)
                found.append(LearnedBitangent(parse_label(item.string(0))[1], parse_label(item.string(1))[1],
                                              item.string(2), item.string(3)))
            learning = LearnedBitangents(tuple(found), r.integer("bitangent_candidates"), r.integer("learning_actions"),
                                         r.integer("visibility_queries"))
        return cls(r.status(), actions, start, r.string("sensor"), tuple(r.texts("positions")), r.integer("states"),
                   CutOrdering.from_labels(r.texts("cut_ordering")),
                   check=check_pursuit(env, actions, start) if r.get("verified", None) is not None else None,
                   reason=r.string("reason", ""), limits=r.optimality().limits, environment=record, stats=r.stats(),
                   learning=learning)

    def to_text(self, *, width: int = 100) -> str:
        if self.status is Status.FOUND:
            verdict = {True: "verified by the ground-truth checker", False: "REJECTED by the ground-truth checker",
                       None: "not checked"}[self.verified]
            lines = [f"pursuit plan ({self.sensor} sensor) from {self.start}: {len(self.actions)} actions, "
                     f"{self.states} I-states explored, {verdict}",
                     " ".join(self.actions) or "(no action: nothing is hidden)",
                     "positions: " + " ".join(self.positions)]
        else:
            lines = [f"no pursuit plan ({self.status.value}, {self.sensor} sensor) from {self.start}: {self.reason}",
                     f"{self.states} I-states explored"]
        if self.learning is not None:
            lines.append(f"Strategy 4 learned {len(self.learning.bitangents)} bitangents first: "
                         f"{self.learning.actions} actions, {self.learning.visibility_queries} pebble-visibility "
                         f"readings")
        text = "\n".join(lines) + "\n"
        return text if self.check is None else text + self.check.to_text(width=width)


def _vertex_after(order: CutOrdering, index: int, step: int) -> int:
    size = len(order.labels)
    i = (index + step) % size
    while order.labels[i][0] != "v":
        i = (i + step) % size
    return i


def pursuit_plan(env: Environment, *, sensor: str = "gap", start: str = "v0", max_states: int = DEFAULT_MAX_STATES,
                 check: bool = True) -> PursuitPlan:
    """A shortest pursuit plan (Strategy 2, gap sensor), replayed by the ground-truth checker.

    Parameters
    ----------
    env
        A simple polygon in general position.
    sensor
        ``"gap"`` (Strategy 2), ``"bitangent"`` (Strategy 3, :mod:`~solverplan.wallfollow.pursuit_primitives`)
        ``"pebble"`` (Strategy 5: Strategy 4, :func:`~solverplan.wallfollow.pebble.learn_bitangents`, learns the
        bitangents with the pebble-visibility sensor, then Strategy 3's search runs on them) or ``"contact"``
        (Strategy 6, :mod:`~solverplan.wallfollow.pursuit_contact`: sound, not complete — no plan found is
        ``not-found``).
    start
        The pursuer's start point in the cut ordering (``v0``, ``r3``); the evader may be anywhere out of sight.
    max_states
        Cap on the derived I-states explored (≥ 1); hitting it gives ``not-found``.
    check
        Replay the plan found with :func:`~solverplan.wallfollow.pursuit_check.check_pursuit`.

    Returns
    -------
    PursuitPlan
        ``found`` with the fewest actions (and their replay when ``check``), ``infeasible`` (proved), or
        ``not-found``.

    Raises
    ------
    InputError
        An unknown sensor or start, a bad ``max_states``; the polygon must be simple and in general position
        (:class:`~solverplan.errors.InvalidEnvironment`).

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> sp.pursuit_plan(room).actions                   # follow the wall left to v6, which sees the pocket
    ('LFOLLOW',)
    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [2, 0], [2, 2], [0, 2]])
    >>> pursuit_plan(square).actions                    # convex: the evader is seen at once
    ()
    """
    sensor = Sensor.parse(sensor, "sensor").value
    if isinstance(max_states, bool) or not isinstance(max_states, int) or max_states < 1:
        raise InputError(f"max_states must be a positive integer, got {max_states!r}")
    t0 = time.perf_counter()
    user, env = env, corner_polygon(env)  # collinear vertices are no corners (wallfollow.cut)
    order = cut_ordering(env)
    if start not in order.labels:
        names = " ".join(order.labels[:8]) + (" ..." if len(order.labels) > 8 else "")  # one short line
        raise InputError(f"start {quote(start)} is not a point of the cut ordering ({names})")
    pts = env.exact_vertices
    points: dict[str, ExactPoint] = {f"v{k}": p for k, p in enumerate(pts)}
    points.update({c.label: c.point for c in cuts(env)})
    reflex = set(order.reflex)
    # the pursuit status of an I-state, how an action changes it, and whether it is won
    status0: Any
    learning = None
    if sensor == "gap":
        gap = GapSensor(env)
        status0 = frozenset(gap.gaps(points[start]))

        def step(x: str, y: str, status: Any, action: str) -> Any:
            transfer = gap.transfer(points[x], points[y])
            return frozenset(g for g, src in transfer.items() if src & status)

        def won(status: Any) -> bool:
            return not status
    elif sensor == "contact":
        from solverplan.wallfollow.pursuit_contact import ContactPursuit

        contact = ContactPursuit(order)  # the cut ordering alone
        status0 = contact.start(start)

        def step(x: str, y: str, status: Any, action: str) -> Any:
            return contact.apply(x, y, status, action)

        def won(status: Any) -> bool:
            return contact.won(status)
    else:
        from solverplan.wallfollow.pursuit_primitives import BitangentSensor

        pairs = None
        if sensor == "pebble":
            from solverplan.wallfollow.pebble import learn_bitangents, learned_pairs

            learning = learn_bitangents(env, order)
            pairs = learned_pairs(env, learning)
        primitives = BitangentSensor(env, pairs)
        status0 = (frozenset(), primitives.active(start))

        def step(x: str, y: str, status: Any, action: str) -> Any:
            return primitives.apply(x, y, points[x], points[y], status)

        def won(status: Any) -> bool:
            return not status[1]
    t1 = time.perf_counter()
    start_index = order.index(start)
    # a derived I-state: (index in the ordering, "R"/"L" = the follow that reached a vertex, the pursuit status)
    IState = tuple[int, str | None, Any]
    first: IState = (start_index, None, status0)
    parent: dict[IState, tuple[IState, str] | None] = {first: None}
    queue: deque[IState] = deque([first])
    goal: IState | None = first if won(status0) else None
    limits: tuple[str, ...] = ()
    while queue and goal is None:
        if len(parent) >= max_states:
            limits = (f"max_states={max_states}",)
            break
        state = queue.popleft()
        index, arrived, status = state
        label = order.labels[index]
        moves: list[tuple[str, int, str | None]] = [("RFOLLOW", _vertex_after(order, index, 1), "R"),
                                                    ("LFOLLOW", _vertex_after(order, index, -1), "L")]
        kind, k = parse_label(label)
        if kind == "v" and k in reflex and arrived is not None:
            moves.append(("JUMP", order.index(f"{arrived.lower()}{k}"), None))
        for action, target, arrival in moves:
            nxt: IState = (target, arrival, step(label, order.labels[target], status, action))
            if nxt in parent:
                continue
            parent[nxt] = (state, action)
            if won(nxt[2]):
                goal = nxt
                break
            queue.append(nxt)
    t2 = time.perf_counter()
    states = len(parent)
    stats = Stats(seconds_setup=t1 - t0, seconds_search=t2 - t1, expanded=states)
    record = EnvironmentRecord.of(user)
    stats = stats.with_(**merged_count(user, env))
    if goal is None:
        status = Status.NOT_FOUND if limits or sensor not in COMPLETE else Status.INFEASIBLE
        if limits:
            reason = f"the cap of {max_states} I-states was reached"
        elif sensor in COMPLETE:
            reason = (f"every one of the {states} reachable I-states (position, labels) keeps a label 1: no plan "
                      f"exists for this cut ordering with the {sensor} sensor "
                      f"({'Prop. 8' if sensor == 'gap' else 'Prop. 10'})")
            if sensor == "pebble":
                reason += " (Strategy 5: as complete as Strategy 3)"
        else:
            reason = (f"every one of the {states} reachable I-states keeps a label 1 under Strategy 6's pessimistic "
                      f"bookkeeping; Strategy 6 is sound but not known to be complete, so a plan may still exist")
        return PursuitPlan(status, (), start, sensor, (start,), states, order, None, reason, limits, record, stats,
                           learning)
    actions: list[str] = []
    positions: list[str] = []
    node: IState | None = goal
    while node is not None:
        positions.append(order.labels[node[0]])
        back = parent[node]
        if back is None:
            break
        node, action = back
        actions.append(action)
    actions.reverse()
    positions.reverse()
    replay = check_pursuit(env, actions, start) if check else None
    t3 = time.perf_counter()
    stats = stats.with_(seconds_check=t3 - t2)
    return PursuitPlan(Status.FOUND, tuple(actions), start, sensor, tuple(positions), states, order, replay, "",
                       (), record, stats, learning)
