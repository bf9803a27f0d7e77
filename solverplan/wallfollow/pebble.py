"""The pebble-visibility sensor and Strategy 4: learning the bitangents from sensing alone (§VI-D of the paper).

The **pebble-visibility sensor** h_p reads 1 exactly when the robot and the pebble lying on the floor see each
other (*closed* visibility: the closed segment between them lies in the polygon,
:func:`~solverplan.geometry.visibility.sees`). The robot watches it while it moves, so after each motion it
knows the sequence of values h_p took along the way (:meth:`PebbleWorld.pebble_trace`: ``(1, 0)`` = seen at the
start, then lost), but not where along the way they changed.

**Strategy 4** (:func:`learn_bitangents`) knows the cut ordering (Strategy 1 learns it,
:mod:`~solverplan.wallfollow.learning`) and from it the bitangent *candidates* (Prop. 11: v_i ∉ (r_j, ℓ_j),
v_j ∉ (r_i, ℓ_i), not neighbours — an edge is no bitangent; named right-handed, v_j ∈ [v_i, r_i]). For each candidate
it drops the pebble at v_j and goes to v_i: h_p = 1 there iff (i, j) is a bitangent (the visible direction is
tangent at v_i and v_j exactly when it lies outside both cut wedges, which the candidate test says). Then it
follows away from v_i — clockwise (LFOLLOW) when v_j ∈ [v_i, r_i], as the paper has it, else counter-clockwise:
with reflex chains a pair can be right-handed from both ends, and then both end points lie clockwise of their
vertices, so the paper's RFOLLOW scan for b_{j,i} would run the wrong way — and the first motion during which h_p turns 1 runs along the edge holding
b_{i,j} (Prop. 12). Among the cut end points c on that edge it places b_{i,j} by JUMPing to c and following
back towards v_i (RFOLLOW after a clockwise scan): h_p = 1 at some moment iff that motion passes b_{i,j} — a
monotone test in c, so a binary search over the edge's cut end points suffices where the paper tries each.
b_{j,i} is found the same way with the pebble at v_i. Only actions and the two pebble sensors are used; the geometry stays
inside :class:`PebbleWorld`.

Cost: each candidate takes O(n) follows to reach its vertices and scan, plus O(n log k) to place each end point
among the k cut end points of its edge, so Θ(m² n) actions for m reflex vertices when most candidate pairs are
real. Measured: combs of 2–12 spikes (n = 9 … 29, every spike pair a candidate) take 27 … 2592 actions, a
fitted n^3.7 over that range; 500 random star-shaped polygons with n ≤ 20 at most 1877 actions (n = 20).

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [20, 0], [21, 9], [14, 10], [13, 4], [12, 11], [7, 13], [6, 5],
...                                 [5, 12], [0, 11]])                # two spikes hang from the ceiling: tips 4 and 7
>>> learned = learn_bitangents(room)
>>> [(b.i, b.j, b.after_ij, b.after_ji) for b in learned.bitangents], learned.candidates
([(4, 7, 'v1', 'v9')], 1)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import ExactPoint, line_intersection, orient
from solverplan.geometry.visibility import sees
from solverplan.wallfollow.cut import corner_polygon, cut_ordering
from solverplan.wallfollow.ordering import CutOrdering, parse_label
from solverplan.wallfollow.world import Action, Observation, WallWorld

__all__ = ["PebbleWorld", "LearnedBitangent", "LearnedBitangents", "learn_bitangents", "bitangent_candidates",
           "learned_pairs"]


class PebbleWorld(WallWorld):
    """:class:`~solverplan.wallfollow.world.WallWorld` with the pebble-visibility sensor.

    Every query of the sensor is counted in :attr:`visibility_queries`.

    Parameters
    ----------
    env
        A simple polygon in general position.
    *args, **kwargs
        :class:`~solverplan.wallfollow.world.WallWorld`'s ``start``, ``heading`` and ``carrying``.

    Attributes
    ----------
    visibility_queries
        How many times the pebble-visibility sensor was read.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])   # v3 is reflex
    >>> world = PebbleWorld(ell)
    >>> [str(o) for o in world.run(["RFOLLOW", "DROP", "RFOLLOW"])], world.pebble_visible()   # pebble at v1
    (['convex', 'convex+pebble', 'convex'], True)
    >>> str(world.act("RFOLLOW")), world.pebble_trace()       # v2 → v3 (the reflex corner): v1 stays in sight
    ('reflex', (1,))
    >>> str(world.act("RFOLLOW")), world.pebble_trace()       # v3 → v4: v1 is lost just after the corner
    ('convex', (1, 0))
    >>> world.visibility_queries
    3
    """

    def __init__(self, env: Environment, *args, **kwargs) -> None:
        super().__init__(env, *args, **kwargs)
        self.visibility_queries = 0
        self._last_path: tuple[ExactPoint, ExactPoint] | None = None

    def act(self, action: Action | str) -> Observation:
        before = self.point
        inside_before = self.position is None
        obs = super().act(action)
        # INIT from the interior bends at the wall: its path is not one segment (no trace for it)
        bent = inside_before and self.position is not None and self.transcript[-1][0] is Action.INIT
        self._last_path = None if bent else (before, self.point)
        return obs

    def _pebble_point(self) -> ExactPoint:
        if self._pebble is None:
            raise InputError("pebble visibility: the robot holds the pebble (DROP it first)")
        kind, where = self._pebble
        if kind == "boundary":
            return self.env.exact_point_at(*where)  # type: ignore[misc]
        return where  # type: ignore[return-value]

    def pebble_visible(self) -> bool:
        """h_p now: do the robot and the pebble on the floor see each other (closed visibility)?"""
        q = self._pebble_point()
        self.visibility_queries += 1
        return sees(self.env, self.point, q)

    def pebble_trace(self) -> tuple[int, ...]:
        """The values h_p took along the last motion, in order, repeats merged: ``(0, 1)`` = seen from some
        point on, ``(1,)`` = seen all along. One query.

        Raises
        ------
        InputError
            Before any action, after an INIT from the interior (a bent path), or while the pebble is carried.
        """
        if self._last_path is None:
            raise InputError("pebble trace: needs a straight last motion (RFOLLOW, LFOLLOW, JUMP, GRAB, DROP)")
        p0, p1 = self._last_path
        q = self._pebble_point()
        self.visibility_queries += 1
        if p0 == p1:
            return (int(sees(self.env, p0, q)),)
        # h_p can change only where the line from the pebble through a vertex meets the path: test there and
        # once strictly between two such parameters
        params = {Fraction(0), Fraction(1)}
        for w in self.env.exact_vertices:
            if w == q or orient(q, w, p0) == orient(q, w, p1) == 0:
                continue
            meet = line_intersection(q, w, p0, p1)
            if meet is None:
                continue
            c = 0 if p1[0] != p0[0] else 1
            s = (meet[c] - p0[c]) / (p1[c] - p0[c])
            if 0 < s < 1:
                params.add(s)
        ordered = sorted(params)
        probes = [ordered[0]]
        for a, b in zip(ordered, ordered[1:]):
            probes += [(a + b) / 2, b]
        values: list[int] = []
        for s in probes:
            v = int(sees(self.env, (p0[0] + s * (p1[0] - p0[0]), p0[1] + s * (p1[1] - p0[1])), q))
            if not values or values[-1] != v:
                values.append(v)
        return tuple(values)


@dataclass(frozen=True, slots=True)
class LearnedBitangent:
    """A bitangent as Strategy 4 learns it: reflex vertices ``i``, ``j`` (right-handed: v_j ∈ [v_i, r_i]) and
    the point of the cut ordering just before each end point counter-clockwise (as
    :class:`~solverplan.wallfollow.bitangent.Bitangent`)."""

    i: int
    j: int
    after_ij: str
    after_ji: str


@dataclass(frozen=True, slots=True)
class LearnedBitangents:
    """What Strategy 4 learned, and what it cost.

    Attributes
    ----------
    bitangents
        The bitangents found, in the order of :func:`~solverplan.wallfollow.bitangent.bitangents`.
    candidates
        Bitangent candidates tested (Prop. 11).
    actions
        Actions executed (RFOLLOW, LFOLLOW, JUMP, GRAB, DROP).
    visibility_queries
        Readings of the pebble-visibility sensor used.
    """

    bitangents: tuple[LearnedBitangent, ...]
    candidates: int
    actions: int
    visibility_queries: int
    transcript: tuple[str, ...] = field(default=(), repr=False)


def bitangent_candidates(order: CutOrdering) -> list[tuple[int, int]]:
    """The bitangent candidates (i, j) of Prop. 11, from the cut ordering alone: v_i ∉ (r_j, ℓ_j) and
    v_j ∉ (r_i, ℓ_i) (the line v_i v_j is tangent at both ends *if* they see each other), neighbours (an edge,
    never a bitangent) left out. Named as :func:`~solverplan.wallfollow.bitangent.bitangents` names them:
    right-handed (v_j ∈ [v_i, r_i]) with the smaller id first when both namings are.

    >>> order = CutOrdering.from_labels(["v0", "v1", "v2", "v3", "l4", "v4", "r4"])
    >>> bitangent_candidates(order)
    []
    """
    n = order.n
    reflex = order.reflex
    out = []
    for x, a in enumerate(reflex):
        for b in reflex[x + 1:]:
            if (b - a) % n in (1, n - 1):
                continue
            if order.between(f"r{a}", f"l{a}", f"v{b}") or order.between(f"r{b}", f"l{b}", f"v{a}"):
                continue
            out.append((a, b) if _in_closed(order, f"v{a}", f"r{a}", f"v{b}") else (b, a))
    return out


def _in_closed(order: CutOrdering, start: str, end: str, label: str) -> bool:
    return label in (start, end) or order.between(start, end, label)


class _Robot:
    """Strategy 4's robot: drives a :class:`PebbleWorld` and keeps its own belief of where it is (a point of
    the cut ordering), updated from the actions and the known cut ordering only."""

    def __init__(self, world: PebbleWorld, order: CutOrdering) -> None:
        self.world, self.order, self.n = world, order, order.n
        self.at = "v0"  # the world starts at vertex 0, carrying the pebble
        self.arrived: str | None = None
        self.actions: list[str] = []

    def act(self, action: str) -> Observation:
        obs = self.world.act(action)
        self.actions.append(action)
        kind, k = parse_label(self.at)
        if action == "RFOLLOW":
            self.at = f"v{(self.order.edge_of(self.at) + 1) % self.n}"
            self.arrived = "R"
        elif action == "LFOLLOW":
            self.at = f"v{(k - 1) % self.n}" if kind == "v" else f"v{self.order.edge_of(self.at)}"
            self.arrived = "L"
        elif action == "JUMP":
            assert self.arrived is not None
            self.at, self.arrived = f"{self.arrived.lower()}{k}", None
        return obs

    def goto(self, v: int, arrival: str | None = None) -> None:
        """Follow to vertex ``v``, the last step an RFOLLOW (``"R"``) or LFOLLOW (``"L"``) if asked."""
        kind, k = parse_label(self.at)
        if kind != "v":
            self.act("RFOLLOW")
            k = parse_label(self.at)[1]
        ccw = (v - k) % self.n
        if ccw == 0 and arrival is not None and self.arrived != arrival:
            self.act("LFOLLOW" if arrival == "R" else "RFOLLOW")
            ccw = (v - parse_label(self.at)[1]) % self.n
        if arrival == "R" or (arrival is None and ccw <= self.n - ccw):
            for _ in range(ccw):
                self.act("RFOLLOW")
        else:
            for _ in range((self.n - ccw) % self.n):
                self.act("LFOLLOW")

    def goto_cut(self, label: str) -> None:
        """Reach cut end point ``label`` (``r5``: RFOLLOW into v5, JUMP)."""
        kind, k = parse_label(label)
        self.goto(k, "R" if kind == "r" else "L")
        self.act("JUMP")


def _place(robot: _Robot, near: int, scan: str, compare: str) -> str:
    """With the pebble at the far vertex and the robot at ``near``: the point of the ordering just before the
    bitangent's end point beyond ``near`` (``scan`` the follow towards it, ``compare`` the opposite one)."""
    world, order = robot.world, robot.order
    n = order.n
    for _ in range(n):
        robot.act(scan)
        if 1 in world.pebble_trace()[1:]:
            break
    else:  # pragma: no cover - Prop. 12: the end point comes before the far vertex
        raise SolverFailed(f"Strategy 4: no bitangent end point beyond v{near} after {n} follows")
    k = parse_label(robot.at)[1]
    edge = k if scan == "LFOLLOW" else (k - 1) % n
    start = order.index(f"v{edge}")
    on_edge = []
    x = (start + 1) % len(order.labels)
    while order.labels[x][0] != "v":
        on_edge.append(order.labels[x])
        x = (x + 1) % len(order.labels)
    # binary search: the end point lies after on_edge[:lo] and before on_edge[hi:]
    lo, hi = 0, len(on_edge)
    while lo < hi:
        mid = (lo + hi) // 2
        robot.goto_cut(on_edge[mid])
        robot.act(compare)
        seen = 1 in world.pebble_trace()
        # RFOLLOW from c sees the pebble iff c is before the end point; LFOLLOW from c iff c is after it
        before = seen if compare == "RFOLLOW" else not seen
        if before:
            lo = mid + 1
        else:
            hi = mid
    return on_edge[lo - 1] if lo > 0 else f"v{edge}"


def _scan(order: CutOrdering, near: int, far: int) -> tuple[str, str]:
    """Which follow reaches the bitangent's end beyond ``near`` first, and the opposite one. Seen from v_near,
    the boundary runs v_near, …, r_near, …, ℓ_near, …, v_near in angular order; the line to v_far is tangent at
    v_near, so v_far lies in [v_near, r_near] or in [ℓ_near, v_near], and the ray beyond v_near points to the
    other of the two: [ℓ_near, v_near] (clockwise: LFOLLOW) or [v_near, r_near] (RFOLLOW)."""
    if _in_closed(order, f"v{near}", f"r{near}", f"v{far}"):
        return "LFOLLOW", "RFOLLOW"
    return "RFOLLOW", "LFOLLOW"


def learn_bitangents(env: Environment, order: CutOrdering | None = None) -> LearnedBitangents:
    """Strategy 4: every bitangent and its end points' places in the cut ordering, learned with the pebble.

    The robot starts at vertex 0 with the pebble and knows the cut ordering (default: the exact one, which
    Strategy 1 learns from sensing alone).

    Parameters
    ----------
    env
        A simple polygon in general position (only the simulator :class:`PebbleWorld` reads it).
    order
        The cut ordering the robot knows, labelled from its start vertex 0.

    Returns
    -------
    LearnedBitangents
        The bitangents with ``after_ij`` / ``after_ji`` as in :func:`~solverplan.wallfollow.bitangent`, and
        the action and sensor-query counts.

    Examples
    --------
    >>> from solverplan.models import load
    >>> learned = learn_bitangents(load("l_shape"))
    >>> learned.bitangents, learned.actions
    ((), 0)
    >>> learned = learn_bitangents(load("star"))
    >>> learned.bitangents[0], len(learned.bitangents), learned.actions, learned.visibility_queries
    (LearnedBitangent(i=9, j=12, after_ij='v6', after_ji='v13'), 2, 120, 14)
    """
    env = corner_polygon(env)
    order = order or cut_ordering(env)
    world = PebbleWorld(env)
    robot = _Robot(world, order)
    found = []
    pairs = bitangent_candidates(order)
    for i, j in pairs:
        robot.goto(j)
        robot.act("DROP")
        robot.goto(i)
        if not world.pebble_visible():
            robot.goto(j)
            robot.act("GRAB")
            continue
        after_ij = _place(robot, i, *_scan(order, i, j))
        robot.goto(j)
        robot.act("GRAB")
        robot.goto(i)
        robot.act("DROP")
        robot.goto(j)
        after_ji = _place(robot, j, *_scan(order, j, i))
        robot.goto(i)
        robot.act("GRAB")
        found.append(LearnedBitangent(i, j, after_ij, after_ji))
    return LearnedBitangents(tuple(found), len(pairs), len(robot.actions),
                             world.visibility_queries, tuple(robot.actions))


def learned_pairs(env: Environment, learned: LearnedBitangents) -> list[tuple[int, int]]:
    """The learned bitangents' vertex pairs, for Strategy 3's search (Strategy 5).

    The places Strategy 4 learned decide *which* motions cross which bitangent rays (a follow crosses a ray
    where it passes its end point; a JUMP crosses it iff their end points alternate along the boundary, tested
    in ``tests/wallfollow/test_pebble.py``), but not the *order* of several crossings along one JUMP — the
    paper's "enough to generate the same output as the bitangent sensor" glosses over that. So the search
    replays each learned bitangent ray as a segment of the polygon to time its crossings (as it does the
    inflections'), and that segment's end points must lie where Strategy 4 placed them.

    Raises
    ------
    SolverFailed
        When a learned end point's place disagrees with the ray's (a bug, never expected).
    """
    from solverplan.wallfollow.bitangent import bitangents

    pairs = [(b.i, b.j) for b in learned.bitangents]
    for got, ray in zip(learned.bitangents, bitangents(env, pairs)):
        if (got.after_ij, got.after_ji) != (ray.after_ij, ray.after_ji):
            raise SolverFailed(f"Strategy 4 placed the bitangent of v{got.i} and v{got.j} after {got.after_ij} "
                               f"and {got.after_ji}; its ray ends after {ray.after_ij} and {ray.after_ji}")
    return pairs
