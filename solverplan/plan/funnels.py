"""Funnels (paper Fig. 14, §7.1): plans that track the exact set of possible positions and use contraction to
shrink it until it fits through a gap that no plan over whole segments passes.

A safe-BVG plan (Def. 14, :func:`solverplan.plan.find_plan`) needs every stage to carry *every point of a whole
segment of P′* onto one segment; a funnel only needs it for the positions the robot can actually be at. Those
are tracked exactly: the set after a stage is the lifted transition f(S, Θ) of the set before it
(:func:`~solverplan.bounce.transitions.transition_set`), and contraction (Def. 11–12: small headings into a
corner shrink distances to the corner by C < 1 per bounce) makes it as small as needed — e.g. circling a room
until the position set is narrow enough to be aimed through a doorway. The paper shows such a strategy
(Fig. 14) and notes its planner cannot find it.

The search (:mod:`solverplan.plan._positions`) is over (position set, bounces) states with dominance (a state
whose positions contain an earlier state's is dropped) and a beam; every heading interval is 2ε wide (ε the
tolerance). It runs on the straight walls — the environment with its collinear vertices merged but where the
start or goal set ends (:mod:`solverplan.plan._walls`) — and answers in the user's edges
(:func:`~solverplan.plan._positions.to_user_stages`), so collinear vertices never change the strategy found. What it returns is exact — replayed in rational arithmetic, with the exact positions after every
stage — and certifiable (:func:`solverplan.certify.contraction.funnel_certificate`); its fewest-bounces claim is
heuristic (``optimality.method`` is ``heuristic``, ``proved`` false; when it finds nothing the status is
``not-found``, with its caps in ``optimality.limits``).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> f = funnel(square, "e0", "e2:0.45:0.55", tolerance=0.005)
>>> f.status.value, len(f.stages) > 1, f.stages[-1].positions[0].edge
('found', True, 2)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from solverplan._docstrings import fill_doc
from solverplan.bounce.bvg import SafeBVG
from solverplan.bounce.partitions import Partition
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.limits import MAX_BOUNCES, MAX_COUNT, quote
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN, MARGIN_DOCS, Margins
from solverplan.plan._deadline import Deadline, deadline_of
from solverplan.plan._positions import Flat, SearchOutcome, search_widening, to_user_stages
from solverplan.plan._results import PositionStrategy
from solverplan.plan._walls import PartitionedWalls
from solverplan.plan.search import straight_walls_graph
from solverplan.result import EnvironmentRecord, Method, Optimality, Reader, Stats, Status, answer_dataclass

__all__ = ["Funnel", "funnel", "DEFAULT_FUNNEL_TOLERANCE", "DEFAULT_MAX_ROWS", "NARROW_PASSES", "SearchBounds",
           "safe_plan_exists"]

DEFAULT_FUNNEL_TOLERANCE = 0.005
"""Radians: the half-width of every heading interval of a funnel when none is given."""

NARROW_PASSES = ((20, 60), (60, 120))
"""(beam, headings) of the cheap passes that funnels and localisation try before their full beam; each pass
keeps at most max(2, beam / 10) states per edge, so that a narrow beam still spreads over the room."""

DEFAULT_MAX_ROWS = 250_000
"""The default work budget of funnels and localisation: (piece, heading) images evaluated over all passes (a
few seconds of search on the shipped models)."""


def widening_passes(beam: int, n_headings: int) -> list[tuple[int, int]]:
    """The passes of a search whose full width is ``beam`` × ``n_headings``: the narrow ones that are smaller,
    then the full one."""
    return [(b, h) for b, h in NARROW_PASSES if b < beam and h <= n_headings] + [(beam, n_headings)]


@answer_dataclass("funnel", kw_only=True)
class Funnel(PositionStrategy):
    """A funnel (a plan whose stages carry exact ``positions``, ``docs/contract.md``), or why there is none.

    Made by :func:`funnel`: the heading intervals all have the same width 2ε, and the exact set of positions
    the robot may be on shrinks by contraction until it lies inside the goal.

    Attributes
    ----------
    status, reason
        A :class:`~solverplan.result.Status` (``found`` or ``not-found``: the search is heuristic) and why.
    optimality
        How the answer was found (never proved optimal; a capped search lists its caps in ``limits``).
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of the environment.
    start, goal
        The start set and the goal set every start ends in.
    tolerance
        ε, radians: every heading interval is 2ε wide.
    stages
        :class:`~solverplan.result.Stage` objects with their exact ``positions`` after the stage, ``sources``
        before it, ``cones`` (the exact world-frame directions each source was pushed through) and
        ``target_edges``.
    safe_plan
        Whether a plan over whole segments (the safe BVG, any tolerance) can exist at all, for comparison
        (``False`` is a proof that none does; ``True`` is only necessary).
    stats
        Search statistics (recorded, never asserted).
    partition
        The partition P′ of the environment (not serialised): for rollouts and certificates.

    Examples
    --------
    >>> import solverplan as sp
    >>> f = sp.funnel(sp.load_environment("square"), "e0", "e1:0.4:0.6")
    >>> f.status.value, f.bounces, f.tolerance, f.safe_plan    # no plan over whole segments could do this
    ('found', 2, 0.005, False)
    >>> [[round(float(p.t0), 4), round(float(p.t1), 4)] for p in f.stages[-1].positions]   # t on edge 1
    [[0.4144, 0.4903]]
    """

    safe_plan: bool | None = None

    def _extra_json(self) -> dict:
        return {"safe_plan_exists": self.safe_plan}

    @classmethod
    def _extra_from_json(cls, r: Reader) -> dict:
        return {"safe_plan": r.boolean("safe_plan_exists", None)}

    def _head(self) -> str:
        return f"{super()._head()} to {self.goal}"

    def _extra_text(self) -> list[str]:
        if self.safe_plan is None:
            return []
        return [f"plan over whole segments (safe BVG): {'exists' if self.safe_plan else 'none'}"]


def search_optimality(outcome: SearchOutcome, *, max_bounces: int, n_headings: int, beam: int,
                      scope: str, max_rows: int | None = None) -> tuple[Status, Optimality]:
    """The status and optimality of a beam search over position sets: found (a sound strategy; fewest bounces
    not proved), or not found within its caps (``limits``: the caps, then ``cut=...``, what ended the search —
    see :class:`~solverplan.plan._positions.SearchOutcome`; nothing is proved)."""
    algorithm = f"breadth-first beam search over position sets ({n_headings} headings, beam {beam})"
    if outcome.stages is None:
        caps = [f"max_bounces={max_bounces}", f"beam={beam}", f"n_headings={n_headings}"]
        if max_rows is not None:
            caps.append(f"max_rows={max_rows}")
        if outcome.cut is not None:
            caps.append(f"cut={outcome.cut}")
        limits = (*caps, *outcome.limits)
        return Status.NOT_FOUND, Optimality(Method.HEURISTIC, False, None, scope=scope, algorithm=algorithm,
                                            limits=limits)
    return Status.FOUND, Optimality(Method.HEURISTIC, False, None, scope=scope,
                                    algorithm=f"{algorithm}: fewest bounces not proved")


def search_stats(outcome: SearchOutcome, seconds: float) -> Stats:
    """The :class:`~solverplan.result.Stats` of a search over position sets: its wall time (seconds), the
    (state, heading) pairs it expanded, the bounces it searched and the exact replays that failed."""
    return Stats(seconds_search=round(seconds, 6), expanded=outcome.expanded,
                 counts={"bounces_searched": outcome.layers, "replay_failures": outcome.replay_failures})


def search_half_width(tolerance: float | None) -> float:
    """ε of a search over position sets: ``tolerance`` (default :data:`DEFAULT_FUNNEL_TOLERANCE`), checked."""
    eps = DEFAULT_FUNNEL_TOLERANCE if tolerance is None else float(tolerance)
    if not (0 < eps < math.pi / 2):
        raise InputError(f"tolerance {tolerance!r} must be a heading half-width in (0, π/2) radians")
    return eps


@dataclass(frozen=True, slots=True)
class SearchBounds:
    """The caps of a search over position sets (funnels and localisation take the same ones), checked when made:
    ``max_bounces``, ``n_headings`` (headings tried per stage), ``beam`` (states kept per bounce) and ``max_rows``
    (the work budget over all passes; None: none). A bad value is an :class:`InputError` naming it.

    >>> SearchBounds(30, 240, 400, None).beam
    400
    >>> SearchBounds(30, 0, 400, None)
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: n_headings must be an integer in [1, 100,000], got 0
    """

    max_bounces: int
    n_headings: int
    beam: int
    max_rows: int | None

    def __post_init__(self) -> None:
        for name, top in (("max_bounces", MAX_BOUNCES), ("n_headings", MAX_COUNT), ("beam", MAX_COUNT)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= top:
                raise InputError(f"{name} must be an integer in [1, {top:,}], got {quote(value)}")
        rows = self.max_rows
        if rows is not None and (isinstance(rows, bool) or not isinstance(rows, int) or rows < 0):
            raise InputError(f"max_rows must be a non-negative integer or None (no budget), got {quote(rows)}")


def graded_search(env: Environment, part: Partition, start: Sequence[BoundaryPiece], is_goal: Any, is_goal_exact: Any, *,
                  eps: float, bounds: SearchBounds, heading_margin: float, corner_clearance: float | None,
                  deadline: Deadline, **options: Any) -> tuple[SearchOutcome, Status, Optimality, Stats]:
    """The search of funnels and localisation strategies and its grades: :func:`search_widening` over the passes of
    :func:`widening_passes` under the margin policy, then the status and optimality (:func:`search_optimality`,
    scope :func:`position_scope`) and the statistics (:func:`search_stats`). ``options`` go to the search."""
    margins = Margins.for_environment(env, heading_margin=heading_margin, corner_clearance=corner_clearance)
    t0 = time.perf_counter()
    outcome, used_beam, used_headings = search_widening(
        env, part, start, is_goal, is_goal_exact, passes=widening_passes(bounds.beam, bounds.n_headings),
        max_rows=bounds.max_rows, tolerance=eps, max_bounces=bounds.max_bounces, margins=margins, deadline=deadline,
        **options)
    stats = search_stats(outcome, time.perf_counter() - t0)
    status, optimality = search_optimality(
        outcome, max_bounces=bounds.max_bounces, n_headings=used_headings, beam=used_beam, max_rows=bounds.max_rows,
        scope=position_scope(eps, bounds.max_bounces))
    return outcome, status, optimality, stats


POSITION_SEARCH_DOCS = {
    "tolerance": """
tolerance
    ε, radians: every interval is [θ − ε, θ + ε] (default :data:`~solverplan.plan.funnels.DEFAULT_FUNNEL_TOLERANCE`).""",
    "bounds": """
max_bounces, n_headings, beam
    The search's bounds: bounces, headings tried per stage (a uniform grid; a funnel also aims at its goal), states
    kept per bounce. The search widens: the passes of :data:`~solverplan.plan.funnels.NARROW_PASSES` narrower
    than ``beam`` × ``n_headings`` run first, the full one only if they find nothing.
max_rows
    The work budget over all passes: (piece, heading) images evaluated (None: no budget). When it ends the
    search, ``optimality.limits`` says so (``cut=max_rows``).""",
    "margins": MARGIN_DOCS["position_margins"],
    "timeout": """
timeout
    Seconds of wall time (positive, finite; None: no limit), the walls' partition and graph build included (they
    are not interrupted); at the deadline the search stops: ``not-found``, with the timeout in
    ``optimality.limits``.""",
}
"""The parameters funnels and localisation describe alike (:func:`~solverplan._docstrings.fill_doc` fragments)."""


def boundary_pieces(env: Environment, value: str | BoundarySet, what: str) -> BoundarySet:
    """The ``what`` set of a search (a :class:`BoundarySet` or its text), or one line saying it is neither."""
    if isinstance(value, BoundarySet):
        return value
    if isinstance(value, str):
        return env.boundary_set(value)
    raise InputError(f"{what} set {value!r}: expected a boundary set such as 'e3:0.25:0.75,e4'")


def safe_plan_exists(graph: SafeBVG, start: BoundarySet, goal: BoundarySet) -> bool:
    """Is there a plan over whole segments (safe-BVG arcs, any positive or zero width) from every segment the
    start set overlaps to segments inside the goal? Reachability of beliefs' members is necessary for a
    belief plan, so ``False`` proves no safe-BVG plan exists (``True`` is only necessary)."""
    part = graph.partition

    def overlapping(bs: BoundarySet, inside: bool):
        out = set()
        for p in bs.pieces:
            for s in part.edge_segments[p.edge]:
                seg = part.segments[s]
                if inside and p.t0 <= seg.t0 and seg.t1 <= p.t1:
                    out.add(s)
                elif not inside and min(seg.t1, p.t1) > max(seg.t0, p.t0):
                    out.add(s)
        return out

    starts, goals = overlapping(start, False), overlapping(goal, True)
    if not goals:
        return False
    for s in starts:
        # depth-first reachability over safe arcs (the graph's own successor lists)
        reach, todo = {s}, [s]
        while todo and not reach & goals:
            for t in graph.successors(todo.pop(), safe_only=True).tolist():
                if t not in reach:
                    reach.add(t)
                    todo.append(t)
        if not reach & goals:
            return False
    return True


@fill_doc(**POSITION_SEARCH_DOCS)
def funnel(
    env: Environment,
    start: str | BoundarySet,
    goal: str | BoundarySet,
    *,
    tolerance: float | None = None,
    max_bounces: int = 30,
    n_headings: int = 240,
    beam: int = 400,
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    corner_clearance: float | None = None,
    max_rows: int | None = DEFAULT_MAX_ROWS,
    timeout: float | Deadline | None = None,
) -> Funnel:
    """A funnel from ``start`` to ``goal``: fixed-width heading intervals that squeeze every start into the goal.

    The exact position sets shrink by contraction until they fit the goal (module docstring).

    Parameters
    ----------
    env
        The environment.
    start, goal
        Boundary sets (``"e0"``, ``"e3:0.25:0.75,e4"``); every point of ``start`` must end inside ``goal``.
    %(tolerance)s
    %(bounds)s
    %(margins)s
    graph
        A precomputed safe BVG (for the comparison with plans over whole segments).
    %(timeout)s

    Returns
    -------
    Funnel
        Status ``found`` with exact stages, or ``not-found`` with the search's caps in ``optimality.limits``
        (the search is heuristic: not finding is not a proof).

    Raises
    ------
    InputError
        A bad start or goal set, a tolerance outside (0, π/2), a bound out of its range, a margin out of its
        range, a timeout that is not a positive finite number.

    Examples
    --------
    From all of the square's bottom edge into the middle fifth of its right edge, with headings ±0.005 rad:

    >>> import solverplan as sp
    >>> f = sp.funnel(sp.load_environment("square"), "e0", "e1:0.4:0.6")
    >>> f.status.value, [stage.interval for stage in f.stages]
    ('found', [Interval(lo=3.0775487103086103, hi=3.08754871030861), Interval(lo=1.963625901403769, hi=1.9736259014037687)])
    >>> str(f.goal)
    'e1:0.4:0.6'
    """
    start_set = boundary_pieces(env, start, "start")
    goal_set = boundary_pieces(env, goal, "goal")
    eps = search_half_width(tolerance)
    bounds = SearchBounds(max_bounces, n_headings, beam, max_rows)
    deadline = deadline_of(timeout)
    # Collinear vertices are no corners: search the straight walls (the same free space with them merged) and
    # answer in the user's edges (plan._walls, to_user_stages)
    walls = PartitionedWalls(env)
    user_start, user_goal = start_set, goal_set
    g = straight_walls_graph(walls, graph)
    part = g.partition
    # the goal's touching pieces joined: whether a position set fits must not depend on how the goal is written
    env, start_set, goal_set = walls.merged, walls.to_merged(start_set), walls.to_merged(goal_set).merged()
    goal_f = [(p.edge, float(p.t0), float(p.t1)) for p in goal_set.pieces]

    def inside(flat: Flat) -> np.ndarray:
        # every piece of the state strictly inside some goal piece (floats; the exact test decides)
        fits = np.zeros(len(flat.owner), dtype=bool)
        for E, A, B in goal_f:
            fits |= (flat.edge == E) & (A + 1e-12 <= flat.lo) & (flat.hi <= B - 1e-12)
        out = np.ones(flat.n, dtype=bool)
        np.logical_and.at(out, flat.owner, fits)
        return out

    def inside_exact(pieces) -> bool:
        return all(any(p.edge == q.edge and q.t0 <= p.t0 and p.t1 <= q.t1 for q in goal_set.pieces) for p in pieces)

    points = []
    for p in goal_set.pieces:
        for s in np.linspace(0.1, 0.9, 5):
            points.append(env.point_at(p.edge, float(p.t0) + s * float(p.t1 - p.t0)))
    outcome, status, optimality, stats = graded_search(
        env, part, start_set.pieces, inside, inside_exact, eps=eps, bounds=bounds, heading_margin=heading_margin,
        corner_clearance=corner_clearance, deadline=deadline, goal_points=np.array(points))
    safe = safe_plan_exists(g, start_set, goal_set)
    user_part = walls.user_partition if not walls.identity else part
    return Funnel(status=status, optimality=optimality, environment=EnvironmentRecord.of(walls.env, user_part.n_segments),
                  start=user_start, goal=user_goal, tolerance=eps, partition=user_part,
                  stages=to_user_stages(walls, outcome.stages or ()),
                  reason="" if outcome.stages is not None else outcome.reason, safe_plan=safe, stats=stats)


def position_scope(eps: float, max_bounces: int) -> str:
    """The class of strategies a search over position sets is about (``optimality.scope``): its pieces are carried
    onto straight walls, not single edges (the same words however the walls are written)."""
    return (f"open-loop strategies of intervals {2 * eps:g} rad wide over exact position sets, ≤ {max_bounces} bounces, "
            "each stage carrying every piece whole onto one straight wall (collinear vertices merged: a run of "
            "collinear edges is one landing unit)")
