"""The geometric ground truth of pursuit-evasion for the wall-following robot (§VI-A of the paper).

An evader hides in the *shadow* S = P \\ V(p) of the pursuer at p (V: the visibility region) and moves arbitrarily
fast; it is detected as soon as it is in V. Each connected component of S carries a label: 1 when the evader may
be in it, 0 when it cannot. :func:`check_pursuit` replays a plan (a start point of the cut ordering and a sequence
of RFOLLOW / LFOLLOW / JUMP actions) in the geometric simulator :class:`~solverplan.wallfollow.world.WallWorld`
and follows the labels **continuously** along every motion, independently of any strategy's reasoning:

- every motion is a straight segment (a follow runs along one edge, a JUMP along a cut); the shadow can change
  its topology only where the pursuer crosses a line through two reflex vertices or the line of an edge at a
  reflex vertex (every window starts at a reflex vertex: inflections, bitangents and the extensions of edges),
  so the checker cuts the segment at **every** crossing with such a line (exact) and looks at the shadow just after
  the start and just before the end of each piece (a millionth of its length in) and at the segment's ends;
- the shadow is computed exactly: the project's exact visibility polygon
  (:func:`~solverplan.geometry.visibility.visibility_polygon`) has one *window* per shadow component (in a
  simple polygon each window cuts off one pocket, and the pockets are the components), so each component is the
  exact polygon bounded by its window and the piece of the boundary beyond it — and it is named by the window's
  reflex vertex. The areas are checked exactly: area(V) + Σ area(pockets) = area(P);
- inside a piece every component keeps its window's vertex (checked), so it keeps its label; across a crossing a
  component inherits the OR of the labels of the components it overlaps by at least half the smaller one's area
  (so close to the crossing a component that continues another covers nearly all of it, while one that vanished
  or appeared meets the others only in a sliver); one overlapping none gets 0: appear → 0, split → both
  inherit, merge → OR. The areas are exact (:func:`overlap_area`): a component as thin as a symbolic perturbation
  (:mod:`~solverplan.wallfollow.perturbation`) is a component, with no tolerance that could drop it.

The plan is verified — the replay's :class:`~solverplan.verdict.Verdict` is ``valid`` — when at some instant every
label is 0 (no component may hold the evader: it has been seen). Labels are also followed symbolically (each label as the set of start components it comes from), which
is how the tests compare a strategy's bookkeeping with the ground truth action by action.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])   # reflex vertex 3
>>> check = check_pursuit(room, ["RFOLLOW", "RFOLLOW"], start="v1")   # v1 → v2 → v3
>>> check.valid, check.cleared_after, [sorted(step.labels) for step in check.steps]
(True, 2, [[3], [3], []])
>>> check_pursuit(room, ["RFOLLOW"], start="v1").valid   # at v2 the top left is still hidden
False
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from itertools import combinations
from typing import Any, Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import (ExactPoint, cross, dot, format_point, on_segment, point_in_ring, segment_intersection,
                              signed_area2)
from solverplan.limits import quote
from solverplan.verdict import Failure, Verdict
from solverplan.geometry.visibility import VisibilityPolygon, visibility_polygon
from solverplan.wallfollow.world import Action, WallWorld, parse_action

__all__ = ["PursuitStep", "PursuitCheck", "shadow_components", "motion_samples", "check_pursuit",
           "Transfer", "propagate", "motion_transfer", "PURSUIT_ACTIONS"]

#: The actions a pursuit plan is made of (the pursuer keeps its pebble: GRAB, DROP and INIT play no part).
PURSUIT_ACTIONS = (Action.RFOLLOW, Action.LFOLLOW, Action.JUMP)

#: How labels travel over a stretch of motion: each component at the end → the components at the start it
#: comes from (its label is the OR of theirs; an empty set means label 0).
Transfer = dict[int, frozenset[int]]


def _boundary_chain(env: Environment, a: ExactPoint, b: ExactPoint) -> list[ExactPoint]:
    """The boundary points from a counter-clockwise to b: a, the vertices strictly between, b."""
    ea, ta = env.locate(a)
    eb, tb = env.locate(b)
    n = env.n_vertices
    pts = env.exact_vertices
    chain = [a]
    if not (ea == eb and ta < tb):
        k = (ea + 1) % n
        while True:
            chain.append(pts[k])
            if k == eb:
                break
            k = (k + 1) % n
        if tb == 0:
            chain.pop()  # b is vertex eb itself
    chain.append(b)
    return chain


def _line_crossing(p0: ExactPoint, p1: ExactPoint, a: ExactPoint, b: ExactPoint) -> Fraction | None:
    """The parameter s ∈ [0, 1] where the segment p0 + s (p1 − p0) meets the line ab (None: parallel/outside)."""
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    ux, uy = b[0] - a[0], b[1] - a[1]
    den = dx * uy - dy * ux
    if den == 0:
        return None  # parallel or on the line: no crossing
    s = ((a[0] - p0[0]) * uy - (a[1] - p0[1]) * ux) / den
    return s if 0 <= s <= 1 else None


#: How close to the ends of a piece (as a fraction of its length) the checker looks: across a crossing the shadow
#: then deforms by a vanishing amount, so overlaps say exactly which components continue which.
NEAR = Fraction(1, 10**6)


def motion_samples(env: Environment, p0: ExactPoint, p1: ExactPoint,
                   per_piece: int = 0) -> list[tuple[ExactPoint, bool]]:
    """Where the checker looks along the segment p0 → p1: ``(point, across)`` with ``across`` true when an event
    line lies between the point and the one before it (exact points).

    The event lines are the lines through two reflex vertices and the lines of the edges at reflex vertices: a
    window starts at a reflex vertex r, it appears or vanishes where the line of sight through r turns along an
    edge at r, and r is hidden or seen again only where the sight line touches another vertex between — which
    must be reflex (a sight line cannot pass a convex corner inside the free space). Where the sight line past r
    meets a convex vertex the component changes shape, not identity. The segment is cut at every crossing with an
    event line; in each piece the checker looks just
    after its start and just before its end (a fraction :data:`NEAR` of its length in) and at ``per_piece``
    evenly spaced points between; the segment's ends come first and last.
    """
    if per_piece < 0:
        raise InputError(f"per_piece must be at least 0, got {per_piece}")
    pts = env.exact_vertices
    reflex = set(env.reflex_vertices)
    n = len(pts)
    params = {Fraction(0), Fraction(1)}
    for i, j in combinations(range(n), 2):
        if not (i in reflex and j in reflex) and not ((i in reflex or j in reflex) and (j - i) % n in (1, n - 1)):
            continue  # neither two reflex vertices nor an edge at a reflex vertex
        a, b = pts[i], pts[j]
        s = _line_crossing(p0, p1, a, b)
        if s is not None:
            params.add(s)
    ordered = sorted(params)
    out = [(p0, False)]
    for s0, s1 in zip(ordered, ordered[1:]):
        inside = [s0 + (s1 - s0) * NEAR] + [s0 + (s1 - s0) * k / (per_piece + 1) for k in range(1, per_piece + 1)]
        inside.append(s1 - (s1 - s0) * NEAR)
        for k, m in enumerate(inside):
            out.append(((p0[0] + m * (p1[0] - p0[0]), p0[1] + m * (p1[1] - p0[1])), k == 0))
    out.append((p1, True))
    return out


Ring = tuple[ExactPoint, ...]


@dataclass(frozen=True, slots=True)
class _Pocket:
    """A shadow component: its ring (from the window's end a along the boundary counter-clockwise to its other end
    b; the closing edge b → a is the window), the polygon edge its first edge lies on, the boundary coordinates
    (edge + t) of a and b, its exact area and its box in floats."""

    ring: Ring
    first_edge: int
    arc: tuple[Fraction, Fraction]
    area: Fraction
    box: tuple[float, float, float, float]


def _pockets(env: Environment, p: Sequence[object], vis: VisibilityPolygon | None = None) -> dict[int, _Pocket]:
    vis = vis if vis is not None else visibility_polygon(env, p)
    out: dict[int, _Pocket] = {}
    for piece in vis.pieces:
        if piece.kind != "constructed":
            continue
        assert piece.reflex_vertex is not None
        (ea, ta), (eb, tb) = env.locate(piece.a), env.locate(piece.b)
        ring = tuple(_boundary_chain(env, piece.a, piece.b))
        if piece.reflex_vertex in out:  # pragma: no cover - one ray per vertex from p
            raise SolverFailed(f"two windows at reflex vertex {piece.reflex_vertex} from {format_point(vis.viewpoint)}")
        xs, ys = [float(x) for x, _ in ring], [float(y) for _, y in ring]
        out[piece.reflex_vertex] = _Pocket(ring, ea, (ea + ta, eb + tb), signed_area2(ring) / 2,
                                           (min(xs), min(ys), max(xs), max(ys)))
    total = vis.area + sum((c.area for c in out.values()), Fraction(0))
    if total != env.area:
        raise SolverFailed(f"shadow of {format_point(vis.viewpoint)}: visible area + pockets = {float(total)} "
                           f"≠ the polygon's area {float(env.area)}")
    return out


def shadow_components(env: Environment, p: Sequence[object],
                      vis: VisibilityPolygon | None = None) -> dict[int, tuple[ExactPoint, ...]]:
    """The shadow components of a pursuer at p: window reflex vertex → the component's exact ring (CCW).

    Raises
    ------
    SolverFailed
        If the exact areas do not add up (the pockets would not partition the shadow).

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
    >>> shadow_components(room, (9, 1))     # on the right wall: a triangle behind reflex vertex 3 = (4, 5)
    {3: ((Fraction(4, 1), Fraction(5, 1)), (Fraction(3, 1), Fraction(9, 1)), (Fraction(3, 17), Fraction(137, 17)))}
    """
    return {g: c.ring for g, c in _pockets(env, p, vis).items()}


def _float_box(p: ExactPoint, q: ExactPoint) -> tuple[float, float, float, float]:
    """The segment's box in floats, widened by far more than the rounding of its ends (a filter: boxes apart in
    floats are apart exactly)."""
    x0, x1 = sorted((float(p[0]), float(q[0])))
    y0, y1 = sorted((float(p[1]), float(q[1])))
    pad = 1e-9 * (1.0 + max(abs(x0), abs(x1), abs(y0), abs(y1)))
    return x0 - pad, y0 - pad, x1 + pad, y1 + pad


def _split(p: ExactPoint, q: ExactPoint, by: Sequence[tuple[ExactPoint, ExactPoint]]) -> list[tuple[ExactPoint, ExactPoint]]:
    """The segment p → q cut at every point where it meets one of the segments ``by`` (exact)."""
    d = (q[0] - p[0], q[1] - p[1])
    length2 = dot(d, d)
    params = {Fraction(0), Fraction(1)}
    x0, y0, x1, y1 = _float_box(p, q)
    for r, s in by:
        u0, v0, u1, v1 = _float_box(r, s)
        if u0 > x1 or x0 > u1 or v0 > y1 or y0 > v1:
            continue
        hit = segment_intersection(p, q, r, s)
        if hit is not None:
            params.update(dot((x[0] - p[0], x[1] - p[1]), d) / length2 for x in hit.points)
    cut = [(p[0] + t * d[0], p[1] + t * d[1]) for t in sorted(params)]
    return list(zip(cut, cut[1:]))


def _edges(ring: Ring) -> list[tuple[ExactPoint, ExactPoint]]:
    return [(ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))]


def _mid(p: ExactPoint, q: ExactPoint) -> ExactPoint:
    return (p[0] + q[0]) / 2, (p[1] + q[1]) / 2


def _along_boundary(p: ExactPoint, q: ExactPoint, ring: Ring) -> bool:
    """Does the piece p → q (on the boundary of ``ring``) run the same way as that boundary (CCW)?"""
    mid, d = _mid(p, q), (q[0] - p[0], q[1] - p[1])
    for r, s in _edges(ring):
        e = (s[0] - r[0], s[1] - r[1])
        if cross(d, e) == 0 and on_segment(mid, r, s):
            return dot(d, e) > 0
    return False


def overlap_area(env: Environment, a: _Pocket, b: _Pocket) -> Fraction:
    """The exact area of the intersection of two shadow components of ``env`` (Green's theorem over the boundary of
    the intersection).

    Both are parts of the polygon cut off by a window, so the boundary of a ∩ b is made of the pieces of a's
    boundary arc inside b's arc (shared, both run counter-clockwise: counted once), the pieces of a's window inside
    b or on b's boundary the same way, and the pieces of b's window inside a; the polygon's own edges never cross,
    so only the two windows are intersected with edges — linear, not quadratic, in the rings' sizes.

    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
    >>> low, high = _pockets(room, (9, 1))[3], _pockets(room, (9, 2))[3]   # the pocket from higher up is larger
    >>> overlap_area(room, low, high) == overlap_area(room, high, low) == low.area < high.area
    True
    """
    n = env.n_vertices
    pts = env.exact_vertices
    s0, s1 = b.arc
    span = (s1 - s0) % n
    total = Fraction(0)
    window_b = (b.ring[-1], b.ring[0])
    for j in range(len(a.ring) - 1):  # a's boundary arc: on b's boundary where it is inside b's arc
        e = (a.first_edge + j) % n
        v, w = pts[e], pts[(e + 1) % n]
        d = (w[0] - v[0], w[1] - v[1])
        for p, q in _split(a.ring[j], a.ring[j + 1], [window_b]):
            mid = _mid(p, q)
            at = e + dot((mid[0] - v[0], mid[1] - v[1]), d) / dot(d, d)
            if 0 < (at - s0) % n < span:
                total += cross(p, q)
    for p, q in _split(a.ring[-1], a.ring[0], _edges(b.ring)):  # a's window
        where = point_in_ring(_mid(p, q), b.ring)
        if where > 0 or (where == 0 and _along_boundary(p, q, b.ring)):
            total += cross(p, q)
    for p, q in _split(b.ring[-1], b.ring[0], _edges(a.ring)):  # b's window, strictly inside a
        if point_in_ring(_mid(p, q), a.ring) > 0:
            total += cross(p, q)
    return total / 2


def _overlap_transfer(env: Environment, before: dict[int, _Pocket], after: dict[int, _Pocket]) -> Transfer:
    """Across a crossing: a component continues those it overlaps by at least half the smaller one's area (a
    component that continues another covers nearly all of it, this close to the crossing; one that vanished or
    appeared meets the others in a vanishing sliver). Exact: slivers as thin as a symbolic perturbation count."""
    out: Transfer = {}
    for g, new in after.items():
        x0, y0, x1, y1 = new.box
        keep = []
        for h, old in before.items():
            u0, v0, u1, v1 = old.box
            pad = 1e-9 * (1.0 + max(abs(x0), abs(x1), abs(y0), abs(y1), abs(u0), abs(u1), abs(v0), abs(v1)))
            if u0 > x1 + pad or x0 > u1 + pad or v0 > y1 + pad or y0 > v1 + pad:
                continue
            area = overlap_area(env, old, new)
            if area > 0 and 2 * area >= min(old.area, new.area):
                keep.append(h)
        out[g] = frozenset(keep)
    return out


def _step(env: Environment, before: dict[int, _Pocket], after: dict[int, _Pocket], across: bool,
          where: ExactPoint) -> Transfer:
    if across:
        return _overlap_transfer(env, before, after)
    if set(before) != set(after):  # pragma: no cover - between crossings the windows stay at their vertices
        raise SolverFailed(f"shadow near {format_point(where)}: windows at {sorted(before)} became "
                           f"{sorted(after)} "
                           f"without a crossing")
    return {g: frozenset({g}) for g in after}


def propagate(labels: dict[int, frozenset[int]], transfer: Transfer) -> dict[int, frozenset[int]]:
    """Apply a transfer to symbolic labels (component → the start components whose evader may be there)."""
    return {g: frozenset().union(*(labels.get(h, frozenset()) for h in src)) for g, src in transfer.items()}


def motion_transfer(env: Environment, p0: ExactPoint, p1: ExactPoint, per_piece: int = 0) -> Transfer:
    """The ground truth over one straight motion p0 → p1: every shadow component at p1 → the components at p0
    whose labels it ORs (composed over :func:`motion_samples`, by overlap)."""
    polys = _pockets(env, p0)
    total: Transfer = {g: frozenset({g}) for g in polys}
    for q, across in motion_samples(env, p0, p1, per_piece)[1:]:
        new_polys = _pockets(env, q)
        total = propagate(total, _step(env, polys, new_polys, across, q))
        polys = new_polys
    return total


@dataclass(frozen=True, slots=True)
class PursuitStep:
    """The pursuit status after one action of the plan (index 0: at the start, before any action).

    Attributes
    ----------
    action
        The action just executed (``None`` for the start).
    label
        The pursuer's position as a point of the cut ordering (``v3``, ``r5``).
    point
        Its exact position, in the environment's length units.
    components
        Every shadow component: window reflex vertex → exact ring.
    labels
        The components labelled 1 (the evader may be there), by window reflex vertex.
    sources
        Symbolically, for every component: the start components its evader may come from.
    samples
        Positions looked at during the action (0 for the start).
    """

    action: Action | None
    label: str | None
    point: ExactPoint
    components: dict[int, tuple[ExactPoint, ...]]
    labels: frozenset[int]
    sources: dict[int, frozenset[int]]
    samples: int


@dataclass(frozen=True, slots=True)
class PursuitCheck(Verdict):
    """The ground-truth replay of a pursuit plan, and its verdict (:class:`~solverplan.verdict.Verdict`).

    Attributes
    ----------
    start
        The start point's name in the cut ordering.
    actions
        The plan.
    steps
        The status at the start and after every action (:class:`PursuitStep`).
    cleared_after
        The number of actions after which every label was first 0 during the replay (the evader has been seen
        wherever it was), or ``None``.
    samples
        Positions at which the shadow was computed, in all.
    kind
        ``pursuit-replay``.
    valid
        True when the plan guarantees detection (``cleared_after`` is not ``None``).
    failures
        Without detection, one :class:`~solverplan.verdict.Failure` of ``cleared_after`` naming the components that
        may still hold the evader.
    checked
        What was computed exactly: the actions replayed and the shadows (exact visibility polygons whose area and
        their components' add up to the polygon's).
    not_checked
        How labels cross an event: by the exact overlap of the components next to it (the rule of this replay,
        not the event rules the certificate's checker decides).
    proved
        When valid, the instant at which no component can hold the evader, in words.
    scope
        The evader, the polygon and the plan the verdict speaks about, in words.

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> replay = sp.check_pursuit(room, ["LFOLLOW"])
    >>> replay.valid, replay.cleared_after, [step.label for step in replay.steps]
    (True, 1, ['v0', 'v6'])
    >>> replay.proved[0]
    'during action 1 no shadow component can hold the evader: an evader anywhere in the polygon has been seen'
    >>> print(sp.check_pursuit(room, ["RFOLLOW"]).failures[0])
    cleared_after: the replay never clears the shadow: after the last action the evader may still be behind v3
    """

    start: str
    actions: tuple[Action, ...]
    steps: tuple[PursuitStep, ...]
    cleared_after: int | None
    samples: int

    kind = "pursuit-replay"

    @property
    def valid(self) -> bool:
        """True when the plan guarantees detection: at some instant no shadow component can hold the evader."""
        return self.cleared_after is not None

    @property
    def failures(self) -> tuple[Failure, ...]:
        if self.valid:
            return ()
        hidden = ", ".join(f"v{g}" for g in sorted(self.steps[-1].labels))
        return (Failure("cleared_after", "the replay never clears the shadow: after the last action the evader may "
                                         f"still be behind {hidden}"),)

    @property
    def checked(self) -> tuple[tuple[str, int], ...]:
        return ("actions", len(self.actions)), ("shadows", self.samples)

    @property
    def not_checked(self) -> tuple[str, ...]:
        return ("labels across an event: carried by the exact overlap of the components a millionth of a piece "
                "from it (this replay's rule; the pursuit certificate's checker decides them by the event rules)",)

    @property
    def proved(self) -> tuple[str, ...]:
        if self.cleared_after is None:
            return ()
        when = "at the start" if self.cleared_after == 0 else f"during action {self.cleared_after}"
        return (f"{when} no shadow component can hold the evader: an evader anywhere in the polygon has been seen",)

    @property
    def scope(self) -> str:
        return ("an evader moving arbitrarily fast in this simple polygon, seen once in the pursuer's line of sight; "
                f"the pursuer starting at {self.start} and moving by the wall-following rules")

    @property
    def title(self) -> str:
        return f"pursuit replay from {self.start}, {len(self.actions)} action{'' if len(self.actions) == 1 else 's'}"

    def subject_json(self) -> dict[str, Any]:
        return {"start": self.start, "actions": [a.value for a in self.actions], "cleared_after": self.cleared_after,
                "samples": self.samples,
                "steps": [{"action": None if step.action is None else step.action.value, "label": step.label,
                           "shadow": sorted(step.components), "contaminated": sorted(step.labels)}
                          for step in self.steps]}

    def subject_lines(self) -> list[str]:
        return ["actions: " + (" ".join(a.value for a in self.actions) or "none")]

    def claim_lines(self) -> list[str]:
        cleared = self.cleared_after
        return ["cleared: " + ("never" if cleared is None else "at the start" if cleared == 0
                               else f"during action {cleared}")]


def _start_world(env: Environment, start: str) -> WallWorld:
    from solverplan.wallfollow.ordering import parse_label

    kind, k = parse_label(start)
    if kind == "v":
        if not 0 <= k < env.n_vertices:
            raise InputError(f"start {start!r}: the polygon has vertices v0 … v{env.n_vertices - 1}")
        return WallWorld(env, env.exact_vertices[k])
    world = WallWorld(env)
    cut = next((c for c in world.cuts if c.label == start), None)
    if cut is None:
        raise InputError(f"start {quote(start)} is not a point of the cut ordering")
    return WallWorld(env, cut.point)


def check_pursuit(env: Environment, actions: Sequence[Action | str], start: str = "v0") -> PursuitCheck:
    """Replay a pursuit plan geometrically and follow the shadow labels continuously (see the module).

    Parameters
    ----------
    env
        A simple polygon in general position.
    actions
        RFOLLOW, LFOLLOW and JUMP actions (JUMP only at a reflex vertex reached by a follow).
    start
        The pursuer's start, a point of the cut ordering (default ``v0``); the evader may be anywhere out of
        sight there (every component starts with label 1).

    Raises
    ------
    InputError
        An action that is not a pursuit action, or that does not apply where the pursuer is.

    Returns
    -------
    PursuitCheck
        The status after every action, and the verdict: ``valid`` when at some instant no shadow can hold the
        evader.

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> sp.check_pursuit(room, ["LFOLLOW"]).valid, sp.check_pursuit(room, ["RFOLLOW"]).valid
    (True, False)
    >>> sp.check_pursuit(room, ["DROP"])
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: DROP is not a pursuit action: use RFOLLOW, LFOLLOW or JUMP
    """
    world = _start_world(env, start)
    plan = tuple(parse_action(a) for a in actions)
    for a in plan:
        if a not in PURSUIT_ACTIONS:
            raise InputError(f"{a.value} is not a pursuit action: use RFOLLOW, LFOLLOW or JUMP")
    here = world.point
    polys = _pockets(env, here)
    comps = {g: c.ring for g, c in polys.items()}
    sources = {g: frozenset({g}) for g in comps}
    steps = [PursuitStep(None, world.label, here, comps, frozenset(comps), sources, 0)]
    cleared = 0 if not comps else None
    total = 1
    for index, action in enumerate(plan, start=1):
        before = world.point
        world.act(action)
        after = world.point
        samples = motion_samples(env, before, after)[1:]
        for q, across in samples:
            new_polys = _pockets(env, q)
            comps = {g: c.ring for g, c in new_polys.items()}
            sources = propagate(sources, _step(env, polys, new_polys, across, q))
            polys = new_polys
            if cleared is None and not any(sources.values()):
                cleared = index
        total += len(samples)
        steps.append(PursuitStep(action, world.label, after, comps,
                                 frozenset(g for g, s in sources.items() if s), sources, len(samples)))
    return PursuitCheck(start, plan, tuple(steps), cleared, total)
