"""The geometric ground truth of pursuit-evasion for the wall-following robot (§VI-A of the paper).

An evader hides in the *shadow* S = P \\ V(p) of the pursuer at p (V: the visibility region) and moves arbitrarily
fast; it is detected as soon as it is in V. Each connected component of S carries a label: 1 when the evader may
be in it, 0 when it cannot. :func:`check_pursuit` replays a plan (a start point of the cut ordering and a sequence
of RFOLLOW / LFOLLOW / JUMP actions) in the geometric simulator :class:`~solverplan.wallfollow.world.WallWorld`
and follows the labels **continuously** along every motion, independently of any strategy's reasoning:

- every motion is a straight segment (a follow runs along one edge, a JUMP along a cut); the shadow can change
  its topology only where the pursuer crosses a line through two vertices (inflections, bitangents and the
  extensions of edges are all such lines), so the checker cuts the segment at **every** crossing with a line
  through two vertices (exact) and looks at the shadow just after the start and just before the end of each
  piece (a millionth of its length in) and at the segment's ends;
- the shadow is computed exactly: the project's exact visibility polygon
  (:func:`~solverplan.geometry.visibility.visibility_polygon`) has one *window* per shadow component (in a
  simple polygon each window cuts off one pocket, and the pockets are the components), so each component is the
  exact polygon bounded by its window and the piece of the boundary beyond it — and it is named by the window's
  reflex vertex. The areas are checked exactly: area(V) + Σ area(pockets) = area(P);
- inside a piece every component keeps its window's vertex (checked), so it keeps its label; across a crossing a
  component inherits the OR of the labels of the components it overlaps by at least half the smaller one's area
  (so close to the crossing a component that continues another covers nearly all of it, while one that vanished
  or appeared meets the others only in a sliver); one overlapping none gets 0: appear → 0, split → both
  inherit, merge → OR. The areas are measured by shapely on the exact pockets.

The plan is *verified* when at some instant every label is 0 (no component may hold the evader: it has been
seen). Labels are also followed symbolically (each label as the set of start components it comes from), which
is how the tests compare a strategy's bookkeeping with the ground truth action by action.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])   # reflex vertex 3
>>> check = check_pursuit(room, ["RFOLLOW", "RFOLLOW"], start="v1")   # v1 → v2 → v3
>>> check.verified, check.cleared_after, [sorted(step.labels) for step in check.steps]
(True, 2, [[3], [3], []])
>>> check_pursuit(room, ["RFOLLOW"], start="v1").verified   # at v2 the top left is still hidden
False
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from itertools import combinations
from typing import Sequence

from shapely.geometry import Polygon

from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import ExactPoint, format_point, signed_area2
from solverplan.limits import quote
from solverplan.geometry.visibility import VisibilityPolygon, visibility_polygon
from solverplan.wallfollow.world import Action, WallWorld, parse_action

__all__ = ["PursuitStep", "PursuitCheck", "shadow_components", "motion_samples", "check_pursuit",
           "Transfer", "propagate", "motion_transfer", "PURSUIT_ACTIONS"]

#: The actions a pursuit plan is made of (the pursuer keeps its pebble: GRAB, DROP and INIT play no part).
PURSUIT_ACTIONS = (Action.RFOLLOW, Action.LFOLLOW, Action.JUMP)

#: An overlap of two shadow components counts when its area exceeds this fraction of the polygon's area.
OVERLAP_FRACTION = 1e-9

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
    vis = vis if vis is not None else visibility_polygon(env, p)
    out: dict[int, tuple[ExactPoint, ...]] = {}
    for piece in vis.pieces:
        if piece.kind != "constructed":
            continue
        assert piece.reflex_vertex is not None
        ring = tuple(_boundary_chain(env, piece.a, piece.b))
        if piece.reflex_vertex in out:  # pragma: no cover - one ray per vertex from p
            raise SolverFailed(f"two windows at reflex vertex {piece.reflex_vertex} from {format_point(vis.viewpoint)}")
        out[piece.reflex_vertex] = ring
    total = vis.area + sum((signed_area2(r) for r in out.values()), Fraction(0)) / 2
    if total != env.area:
        raise SolverFailed(f"shadow of {format_point(vis.viewpoint)}: visible area + pockets = {float(total)} "
                           f"≠ the polygon's area {float(env.area)}")
    return out


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
    """Where the checker looks along the segment p0 → p1: ``(point, across)`` with ``across`` true when a line
    through two vertices lies between the point and the one before it (exact points).

    The segment is cut at every crossing with a line through two vertices; in each piece the checker looks just
    after its start and just before its end (a fraction :data:`NEAR` of its length in) and at ``per_piece``
    evenly spaced points between; the segment's ends come first and last.
    """
    if per_piece < 0:
        raise InputError(f"per_piece must be at least 0, got {per_piece}")
    pts = env.exact_vertices
    params = {Fraction(0), Fraction(1)}
    for a, b in combinations(pts, 2):
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


def _shapely(ring: Sequence[ExactPoint]) -> Polygon:
    poly = Polygon([(float(x), float(y)) for x, y in ring])
    return poly if poly.is_valid else poly.buffer(0)


def _overlap_transfer(before: dict[int, Polygon], after: dict[int, Polygon], tol: float) -> Transfer:
    """Across a crossing: a component continues those it overlaps by at least half the smaller one's area (a
    component that continues another covers nearly all of it, this close to the crossing; one that vanished or
    appeared meets the others in a vanishing sliver)."""
    out: Transfer = {}
    for g, poly in after.items():
        out[g] = frozenset(h for h, old in before.items()
                           if old.bounds[0] <= poly.bounds[2] and poly.bounds[0] <= old.bounds[2]
                           and old.bounds[1] <= poly.bounds[3] and poly.bounds[1] <= old.bounds[3]
                           and (area := old.intersection(poly).area) > tol
                           and area >= 0.5 * min(old.area, poly.area))
    return out


def _step(before: dict[int, Polygon], after: dict[int, Polygon], across: bool, tol: float, where: ExactPoint) -> Transfer:
    if across:
        return _overlap_transfer(before, after, tol)
    if set(before) != set(after):  # pragma: no cover - between crossings the windows stay at their vertices
        raise SolverFailed(f"shadow near {format_point(where)}: windows at {sorted(before)} became {sorted(after)} "
                           f"without a crossing")
    return {g: frozenset({g}) for g in after}


def propagate(labels: dict[int, frozenset[int]], transfer: Transfer) -> dict[int, frozenset[int]]:
    """Apply a transfer to symbolic labels (component → the start components whose evader may be there)."""
    return {g: frozenset().union(*(labels.get(h, frozenset()) for h in src)) for g, src in transfer.items()}


def motion_transfer(env: Environment, p0: ExactPoint, p1: ExactPoint, per_piece: int = 0) -> Transfer:
    """The ground truth over one straight motion p0 → p1: every shadow component at p1 → the components at p0
    whose labels it ORs (composed over :func:`motion_samples`, by overlap)."""
    tol = OVERLAP_FRACTION * float(env.area)
    comps = shadow_components(env, p0)
    total: Transfer = {g: frozenset({g}) for g in comps}
    polys = {g: _shapely(r) for g, r in comps.items()}
    for q, across in motion_samples(env, p0, p1, per_piece)[1:]:
        new_polys = {g: _shapely(r) for g, r in shadow_components(env, q).items()}
        total = propagate(total, _step(polys, new_polys, across, tol, q))
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
class PursuitCheck:
    """The ground-truth replay of a pursuit plan.

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
    verified
        True when the plan guarantees detection (``cleared_after`` is not ``None``).

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> replay = sp.check_pursuit(room, ["LFOLLOW"])
    >>> replay.verified, replay.cleared_after, [step.label for step in replay.steps]
    (True, 1, ['v0', 'v6'])
    """

    start: str
    actions: tuple[Action, ...]
    steps: tuple[PursuitStep, ...]
    cleared_after: int | None
    samples: int

    @property
    def verified(self) -> bool:
        """True when the plan guarantees detection: at some instant no shadow component can hold the evader."""
        return self.cleared_after is not None


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
        The status after every action; ``verified`` when at some instant no shadow can hold the evader.

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> sp.check_pursuit(room, ["LFOLLOW"]).verified, sp.check_pursuit(room, ["RFOLLOW"]).verified
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
    tol = OVERLAP_FRACTION * float(env.area)
    here = world.point
    comps = shadow_components(env, here)
    sources = {g: frozenset({g}) for g in comps}
    polys = {g: _shapely(r) for g, r in comps.items()}
    steps = [PursuitStep(None, world.label, here, comps, frozenset(comps), sources, 0)]
    cleared = 0 if not comps else None
    total = 1
    for index, action in enumerate(plan, start=1):
        before = world.point
        world.act(action)
        after = world.point
        samples = motion_samples(env, before, after)[1:]
        for q, across in samples:
            comps = shadow_components(env, q)
            new_polys = {g: _shapely(r) for g, r in comps.items()}
            sources = propagate(sources, _step(polys, new_polys, across, tol, q))
            polys = new_polys
            if cleared is None and not any(sources.values()):
                cleared = index
        total += len(samples)
        steps.append(PursuitStep(action, world.label, after, comps,
                                 frozenset(g for g, s in sources.items() if s), sources, len(samples)))
    return PursuitCheck(start, plan, tuple(steps), cleared, total)
