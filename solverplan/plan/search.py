"""Optimal plans for bouncing robots (paper §7.1, Def. 14, Algorithm 2, and the open questions of §8.3).

One public function per query: :func:`find_plan` (objectives ``fewest``, ``tolerance``, ``sum``,
``constant``) and :func:`pareto_front` (bounces ↔ tolerance). Both search the **belief-state graph**
of the safe bounce visibility graph (:mod:`solverplan.plan._problem`): when the start set spans
several segments the robot does not know which one it is on, so every stage is one heading interval
admissible from every segment it may be on (conformant planning). Headings are radians in (0, π),
measured counter-clockwise from the wall the robot is on.

Objectives and why the answers are optimal
------------------------------------------
``fewest``
    Fewest bounces: breadth-first search over beliefs (the paper's BFS, generalised to sets). Among
    the plans with the fewest bounces, the most tolerant one (layered max-min labels up to that depth).
``tolerance``
    The narrowest interval as wide as possible (the robot's required precision is half of it):
    a bottleneck path. Without a budget, Dijkstra with max-min labels gives the optimum W*, and a BFS
    over the options of width ≥ W* the fewest bounces among the plans achieving it. With
    ``max_bounces`` K, label setting with labels (bounces, width) and Pareto dominance gives the whole
    front (:func:`pareto_front`) and its best point within K. ``method="milp"`` solves the budgeted
    problem as a MILP with HiGHS instead (a cross-check).
``sum``
    The sum of the widths as large as possible within K bounces (paper §8.3's wording; needs K: each
    extra stage adds width): dynamic programming over (belief, bounces). ``method="lp"`` solves it as an
    LP over path flows in the time-expanded network with clarabel and reports the duality gap.
``constant``
    Paper Algorithm 2: one interval used at every stage. Labels are running intersections with ⊇
    dominance; the answer is the widest constant interval (fewest bounces among the widest).

Every plan interval lies in an *admissible* interval: the exact safe set shrunk by μ =
``safe_margin`` and kept δ = ``heading_margin`` away from the wall (see :mod:`solverplan.plan._problem`);
optimality is over such plans. Stages land on segments of P′ of the environment's *straight walls*: a
vertex with an angle of exactly π is no corner, so the search runs on the environment with those vertices
merged (:mod:`solverplan.plan._walls`; the same free space) and the answer names the user's edges and
segments — a stage onto a run of collinear segments lists every segment of the run. Inserting collinear
vertices never changes an answer, wherever they are. The query is answered as asked: the ends of the start and
goal sets cut the segments they fall inside into pieces, and every piece is a *landing unit* as well as the whole
segment (:mod:`solverplan.plan._problem`): any stage may land on a piece — every landing point inside it — and a
later stage leave from it with the piece's own exact safe sets (the stage lists the pieces in ``sources``), and a
start set that covers part of a segment starts from that part (its own exact safe sets: the plan works from every
point of the start set, not from the whole segment); the goal is reached on segments lying wholly in the goal set, or on the part of a segment
the goal set covers, with the interval cut so that every landing point is inside it. So a plan that needs the
part of a segment beyond a set's end is found, and one that lands across the end is too.

Timeouts
--------
``timeout=`` (seconds) bounds the wall time of a query (:mod:`solverplan.plan._deadline`). The partition and the
safe BVG are built first and stop at the deadline too (between reflex vertices and blocks of sweeps: the query
then answers ``not-found`` with the step it reached); every search then stops at the deadline and the query answers its best plan
so far (found, exact like every plan) or ``not-found``, with ``optimality.proved`` false, ``optimality.bound``
the bound the search had proved (a lower bound on the bounces for ``fewest``, an upper bound on the width or
the sum otherwise) and ``"timeout T s reached after …"`` in ``optimality.limits``. The LP and MILP of
``method="lp"`` / ``"milp"`` are not interrupted once started.

A proven "infeasible" is an answer (``status="infeasible"`` with a ``reason``), never an exception. Every
optimality claim states its ``scope`` (plans over the admissible intervals, within the budget) and its ``gap``
(|value − bound| over that scope: 0 for the exhaustive searches, the solver's gap for the LP and the MILP).

A room whose ceiling is wider than its floor: one bounce, every heading in [ang(c − b), ang(d − a)]
(paper Prop. 2) takes the whole floor to the ceiling. In a square the same shot is the single heading
π/2 (parallel walls, Prop. 2's singleton): not an interval a robot can execute, so it takes two.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [4, 0], [6, 3], [-2, 3]], name="room")
>>> plan = find_plan(room, "e0", "e2", objective="fewest")
>>> plan.bounces, plan.stages[0].moves, round(plan.stages[0].interval.lo, 6), round(plan.min_width, 6)
(1, ((0, 2),), 0.982978, 1.175636)
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> plan = find_plan(square, "e0", "e2", objective="tolerance")
>>> plan.bounces, [s.moves for s in plan.stages], plan.optimality.method.value, plan.optimality.proved
(2, [((0, 1),), ((1, 2),)], 'search-exhausted', True)
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import replace

from solverplan.choices import Objective
from solverplan._docstrings import fill_doc
from solverplan.bounce.bvg import SafeBVG, safe_bounce_visibility_graph
from solverplan.interval import Interval
from solverplan.environment import BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.limits import MAX_BOUNCES, quote
from solverplan.plan import _search
from solverplan.plan._deadline import NEVER, Deadline, deadline_of
from solverplan.plan._problem import Problem
from solverplan.plan._walls import PartitionedWalls
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN, DEFAULT_SAFE_MARGIN, MARGIN_DOCS, Margins
from solverplan.plan.result import ParetoFront, ParetoPoint, Plan
from solverplan.progress import Stopped
from solverplan.result import EnvironmentRecord, Method, Optimality, Stage, Stats, Status

__all__ = ["find_plan", "pareto_front", "planning_problem", "METHODS", "DEFAULT_HEADING_MARGIN", "DEFAULT_SAFE_MARGIN"]

logger = logging.getLogger(__name__)

METHODS: dict[str, tuple[str, ...]] = {
    "fewest": ("auto", "bfs"),
    "tolerance": ("auto", "label", "milp"),
    "sum": ("auto", "dp", "lp"),
    "constant": ("auto", "label"),
}
"""The methods each objective accepts (``auto`` picks the first after it)."""

_GAP_PROVED = 1e-7  # an LP/MILP answer counts as proved optimal when its gap is below this (radians)


# ---------------------------------------------------------------------- inputs
def _boundary(env: Environment, value: str | BoundarySet, what: str) -> BoundarySet:
    if isinstance(value, BoundarySet):
        for p in value.pieces:
            env._check_edge_id(p.edge)
        if not value.pieces:
            raise InputError(f"the {what} set is empty")
        return value
    if isinstance(value, str):
        return env.boundary_set(value)
    raise InputError(f"{what} set must be a boundary-set string like 'e3:0.25:0.75,e4', got {value!r}")


MAX_SUM_STAGES = 10_000
"""Largest budget of the ``sum`` objective (and ``milp``): its optimum uses every stage it may (each adds width), so
the work and the answer grow linearly with the budget — ten million stages would be hours and gigabytes."""


def _check_budget(max_bounces: object) -> int | None:
    if max_bounces is None:
        return None
    if isinstance(max_bounces, bool) or not isinstance(max_bounces, int) or not 1 <= max_bounces <= MAX_BOUNCES:
        raise InputError(f"max_bounces must be an integer in [1, {MAX_BOUNCES:,}], got {quote(max_bounces)}")
    return int(max_bounces)


def planning_problem(
    env: Environment,
    start: str | BoundarySet,
    goal: str | BoundarySet,
    *,
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    safe_margin: float = DEFAULT_SAFE_MARGIN,
    corner_clearance: float | None = None,
    max_depth: int | None = None,
) -> Problem:
    """The belief-state graph of a query (for tests, benchmarks and the other planners of the package); ``max_depth``:
    the bounce budget, when the query has one (a graph built on demand stops there, :func:`query_graph`)."""
    if not isinstance(env, Environment):
        raise InputError(f"expected an Environment, got {type(env).__name__}")
    margins = Margins.for_environment(env, heading_margin=heading_margin, safe_margin=safe_margin,
                                      corner_clearance=corner_clearance)
    start_set = _boundary(env, start, "start")
    goal_set = _boundary(env, goal, "goal")
    walls = PartitionedWalls(env)
    if graph is not None and graph.partition.env not in (env, walls.merged):
        raise InputError("the safe BVG given was built for another environment")
    if graph is None or graph.partition.env != walls.merged:
        graph = query_graph(walls, start_set, max_depth)
    return Problem(graph, start_set, goal_set, margins=margins, walls=walls)


def straight_walls_graph(walls: PartitionedWalls, graph: SafeBVG | None = None) -> SafeBVG:
    """The safe BVG the planners search: the one of P′ of the straight walls (collinear vertices merged, the same
    free space: :mod:`solverplan.plan._walls`), so that it does not depend on how the walls are written; ``graph``
    when it is that graph already."""
    if graph is not None and graph.partition.env == walls.merged:
        return graph
    return safe_bounce_visibility_graph(walls.merged)


def query_graph(walls: PartitionedWalls, start: BoundarySet, max_depth: int | None = None) -> SafeBVG:
    """The safe BVG one query from ``start`` needs (on the straight walls): the whole graph when it is cached or
    small (under :data:`~solverplan.bounce.bvg.LAZY_MIN_ARCS` estimated arcs), else only the safe arcs a search
    from the start segments can reach within ``max_depth`` stages (:func:`~solverplan.bounce.bvg.reachable_safe_graph`:
    the same rows, so the same answers, for a fraction of the work and memory on large maps).

    A start set covering part of a segment needs every segment its host sees (a start piece sees no more than the
    whole segment, but sees parts of it the ends do not), which only the whole graph lists: such queries use it.
    Landing units of the goal set's ends on a graph built on demand leave only along the safe arcs of their segment
    (the answer's scope says so)."""
    from solverplan.bounce import _cache
    from solverplan.bounce.bvg import LAZY_MIN_ARCS, check_graph_memory, estimate_graph, reachable_safe_graph
    from solverplan.bounce.partitions import partition

    found = _cache.lookup_environment(walls.merged)
    if found is not None:
        return found
    p = partition(walls.merged)
    N = len(p.segments)
    starts: list[int] = []
    for edge, pieces in walls.to_merged(start).by_edge().items():
        for k in p.edge_segments[edge]:
            seg = p.segments[k]
            for lo, hi in pieces:
                if lo <= seg.t0 and seg.t1 <= hi:
                    starts.append(k)
                elif lo < seg.t1 and seg.t0 < hi:  # a start piece
                    return safe_bounce_visibility_graph(p)
    if N * (N - 1) < LAZY_MIN_ARCS:
        return safe_bounce_visibility_graph(p)
    estimate = estimate_graph(p)
    if estimate[0] < LAZY_MIN_ARCS:
        return safe_bounce_visibility_graph(p)
    if max_depth is None:
        # without a budget a search reaches nearly every segment of a connected map within a few layers
        # (benchmarks/README.md): refuse now, not after minutes of building, what would not fit whole
        check_graph_memory(p, estimate)
    return reachable_safe_graph(p, starts, max_depth=max_depth)


# ---------------------------------------------------------------------- results
def _stages(problem: Problem, path: _search.Path, constant: tuple[float, float] | None = None) -> tuple[Stage, ...]:
    """The stages of a path, in the user's segment ids (:meth:`Problem.user_stage`)."""
    steps = list(_search.walk(problem, path))
    return tuple(problem.user_stage(belief, o, Interval(*(constant or (o.lo, o.hi))), last=k == len(steps) - 1)
                 for k, (belief, o) in enumerate(steps))


def _common(problem: Problem, max_bounces: int | None) -> dict:
    return {
        "start": str(problem.user_start_set),
        "goal": str(problem.user_goal_set),
        "max_bounces": max_bounces,
        "environment": EnvironmentRecord.of(problem.user_env, problem.user_partition.n_segments),
        "margins": problem.margins.to_json(),
    }


def _scope(problem: Problem, max_bounces: int | None) -> str:
    """The class of plans every optimality claim of :func:`find_plan` and :func:`pareto_front` is about."""
    budget = f" with at most {max_bounces} bounces" if max_bounces is not None else ""
    m = problem.margins
    lazy = (" (this large map's safe BVG was built for the query, so a piece leaves only towards segments its whole "
            "segment has a safe heading to)" if problem.graph.stats.get("lazy") and problem.units else "")
    return (f"plans{budget} whose first stage works from every point of the start set as given and whose stages each "
            f"land on one landing unit and leave from it: a segment of P′ of the straight walls (collinear vertices "
            f"merged), a run of collinear user segments being one, or one of the pieces such a segment is cut into by "
            f"the ends of the start and goal sets{lazy} — the last stage inside the goal set —, with intervals in the "
            f"admissible intervals of the exact safe sets (heading margin {m.heading_margin:g} rad, interval ends "
            f"{m.end_margin:.3g} rad inside, corner clearance {m.corner_clearance:.3g} at real corners and at the set "
            f"ends a stage lands between, no two consecutive arcs into one corner)")


def _claim(method: Method, proved: bool, bound: float | None, algorithm: str, problem: Problem,
           max_bounces: int | None, gap: float | None = None) -> Optimality:
    return Optimality(method, proved, bound, scope=_scope(problem, max_bounces), gap=gap, algorithm=algorithm)


def _precheck(problem: Problem, objective: str, max_bounces: int | None) -> str | None:
    """A reason why no plan can exist, found without searching (None if the search must decide)."""
    if not problem.goal_has_incoming():
        segs = problem.user_segments(problem.goal_whole | set(problem.goal_partial))
        which = f"segment {segs[0]}" if len(segs) == 1 else f"segments {', '.join(map(str, segs))}"
        return f"goal segments have no incoming safe arc ({which} of P′)"
    for s in problem.start_belief:
        if not problem.intervals(s)[0]:
            return f"start {problem.segment_text(s)} has no admissible outgoing interval"
    b = problem.start_belief
    if len(b) > 1 and not problem.options(b) and not problem.goal_options(b):
        return (f"no heading interval is admissible from every start segment at once (segments "
                f"{', '.join(map(str, problem.user_segments(b)))}): a belief-state plan cannot even begin")
    return None


def _exhausted(objective: str, max_bounces: int | None, beliefs: int, cut: bool) -> str:
    if objective == "constant":
        budget = f" with ≤ {max_bounces} bounces" if max_bounces is not None else ""
        return f"no constant interval survives: exhausted every running intersection{budget} ({beliefs} beliefs reached)"
    if max_bounces is not None and cut:
        return f"exhausted all plans with ≤ {max_bounces} bounces ({beliefs} beliefs reached): none reaches the goal"
    if beliefs == 1:
        return "exhausted the only reachable belief: no plan reaches the goal"
    return f"exhausted all {beliefs} reachable beliefs: no plan reaches the goal"


# ---------------------------------------------------------------------- the public queries
@fill_doc(margins=MARGIN_DOCS["margins"])
def find_plan(
    env: Environment,
    start: str | BoundarySet,
    goal: str | BoundarySet,
    *,
    objective: str = "fewest",
    max_bounces: int | None = None,
    method: str = "auto",
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    safe_margin: float = DEFAULT_SAFE_MARGIN,
    corner_clearance: float | None = None,
    timeout: float | Deadline | None = None,
    min_width: float | None = None,
) -> Plan:
    """The optimal plan from ``start`` to ``goal`` for ``objective``, or a proof that there is none.

    Parameters
    ----------
    env
        The environment.
    start, goal
        Boundary sets (``"e3:0.25:0.75,e4"`` or :class:`~solverplan.environment.BoundarySet`); they may
        span several edges and segments, on holes too.
    objective
        ``fewest``, ``tolerance``, ``sum`` or ``constant`` (module docstring).
    max_bounces
        The bounce budget K (stages ≤ K); required for ``sum``.
    method
        ``auto`` or one of :data:`METHODS` for the objective: ``bfs``; ``label`` / ``milp``; ``dp`` /
        ``lp``; ``label``.
    graph
        A prebuilt safe BVG of ``env`` (built when not given).
    %(margins)s
    timeout
        Seconds of wall time (positive, finite; None: no limit; or a running
        :class:`~solverplan.plan._deadline.Deadline`), the partition and the graph build included (they stop at it
        too). At the deadline the search stops: the best plan found so far, or ``not-found``, with
        ``optimality.proved`` false, the bound proved so far and the timeout in ``optimality.limits``.
    min_width
        The robot's heading accuracy A (radians): plan only with intervals at least A wide (a robot that turns
        within ±a needs A = 2a). ``fewest``: the fewest bounces among plans whose every interval is at least A wide
        (breadth-first search over the options that wide; the claim is about that class, so ``optimality.proved``
        is false: certificates do not express it); ``tolerance`` and ``constant``: the optimum, if it is at least
        A. When no plan is that wide the answer is ``infeasible`` and its reason gives the best accuracy that
        would work (the tolerance optimum W*) and the start pieces that block (those whose own best plan is
        narrower than A).

    Returns
    -------
    Plan
        ``status`` found (stages, widths, ``optimality`` with method, proof and bound) or infeasible
        (``reason``; ``optimality.proved`` says the search was exhaustive); ``not-found`` when the timeout
        came before any plan.

    Raises
    ------
    InputError
        Bad sets (unknown edge, malformed piece), unknown objective or method, a bad budget, ``sum``
        without a budget, ``milp`` without a budget, a timeout that is not a positive finite number.

    Examples
    --------
    From the middle of the left room's floor to the right half of the right room's floor, with the widest
    heading intervals any plan has:

    >>> import solverplan as sp
    >>> env = sp.load_environment("two_rooms")
    >>> plan = sp.find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")
    >>> plan.status.value, plan.bounces, round(plan.tolerance, 4), plan.optimality.proved   # ± radians
    ('found', 7, 0.0521, True)

    In the square no single bounce carries all of the bottom edge to the top one, and that is proved:

    >>> plan = sp.find_plan(sp.load_environment("square"), "e0", "e2", max_bounces=1)
    >>> plan.status.value, plan.optimality.proved, plan.reason
    ('infeasible', True, 'exhausted all plans with ≤ 1 bounces (1 beliefs reached): none reaches the goal')
    """
    objective = Objective.parse(objective, "objective").value
    allowed = METHODS[objective]
    if method not in allowed:
        raise InputError(f"unknown method {method!r} for objective {objective!r}: use {', '.join(allowed)}")
    k_max = _check_budget(max_bounces)
    if objective == "sum" and k_max is None:
        raise InputError("objective 'sum' needs max_bounces (--max-bounces K): every extra stage adds width")
    if (objective == "sum" or method == "milp") and k_max is not None and k_max > MAX_SUM_STAGES:
        raise InputError(f"max_bounces {k_max:,} is too large for {'the sum objective' if objective == 'sum' else 'milp'}"
                         f" (at most {MAX_SUM_STAGES:,}): its plan uses every stage it may, so work and answer grow "
                         "with the budget")
    if method == "milp" and k_max is None:
        raise InputError("method 'milp' needs max_bounces (--max-bounces K): it works on the time-expanded network")
    if method == "auto":
        method = allowed[1]
    if min_width is not None:
        if isinstance(min_width, bool) or not isinstance(min_width, (int, float)) or not 0 < min_width < math.pi:
            raise InputError(f"the heading accuracy must be a number of radians in (0, π), got {quote(min_width)}")
        if objective == "sum" or method in ("milp", "lp"):
            raise InputError("a heading accuracy (--heading-accuracy) applies to the fewest, tolerance and constant "
                             "objectives with their default methods")
    deadline = deadline_of(timeout)
    t0 = time.perf_counter()
    problem = _query_problem(env, start, goal, objective, k_max, deadline, t0, graph=graph,
                             heading_margin=heading_margin, safe_margin=safe_margin, corner_clearance=corner_clearance)
    if isinstance(problem, Plan):
        return problem
    common = _common(problem, k_max)
    t1 = time.perf_counter()
    if deadline.expired():
        plan = _cut(problem, objective, k_max, deadline, "building the safe BVG and the query", None,
                    "", common, {})
    elif min_width is not None:
        plan = _solve_accuracy(problem, objective, k_max, method, common, deadline, float(min_width))
    else:
        plan = _solve(problem, objective, k_max, method, common, deadline)
    t2 = time.perf_counter()
    stats = plan.stats.with_(seconds_setup=round(t1 - t0, 6), seconds_search=round(t2 - t1, 6),
                             start_segments=list(problem.user_segments(problem.start_belief)),
                             goal_segments=list(problem.user_segments(problem.goal_whole)),
                             partial_goal_segments=_partial_user_goal(problem), options_built=problem.options_built,
                             admissible_intervals=problem.n_admissible, **_graph_counts(problem))
    logger.info("%s plan: %s in %.3f s", objective, plan.status.value, t2 - t1)
    return plan.with_(stats=stats)


def _query_problem(env: Environment, start: str | BoundarySet, goal: str | BoundarySet, objective: str,
                   k_max: int | None, deadline: Deadline, t0: float, *, graph: SafeBVG | None, heading_margin: float,
                   safe_margin: float, corner_clearance: float | None) -> Problem | Plan:
    """The query's planning problem, built under ``deadline`` (started at ``t0``); or, when the timeout comes while
    it is built, the ``not-found`` plan of :func:`_stopped_in_setup`."""
    try:
        with deadline.watching():
            return planning_problem(env, start, goal, graph=graph, heading_margin=heading_margin,
                                    safe_margin=safe_margin, corner_clearance=corner_clearance, max_depth=k_max)
    except Stopped as exc:
        margins = Margins.for_environment(env, heading_margin=heading_margin, safe_margin=safe_margin,
                                          corner_clearance=corner_clearance)
        return _stopped_in_setup(env, start, goal, objective, k_max, deadline, exc, time.perf_counter() - t0, margins)


def _stopped_in_setup(env: Environment, start: str | BoundarySet, goal: str | BoundarySet, objective: str,
                      k_max: int | None, deadline: Deadline, exc: Stopped, seconds: float, margins: Margins) -> Plan:
    """The answer of a query whose timeout came while it built its partition or safe BVG: ``not-found``, nothing
    proved, the timeout and the step it reached in ``optimality.limits``."""
    start_set, goal_set = _boundary(env, start, "start"), _boundary(env, goal, "goal")
    where = str(exc).removeprefix("stopped during ")
    limit = deadline.limit(f"{where}, while building the query's graph")
    opt = Optimality(Method.SEARCH_EXHAUSTED, False, None, scope="", algorithm="none: the timeout came before the search",
                     limits=(limit,))
    return Plan(Status.NOT_FOUND, objective, (), opt, reason=f"{limit} before any plan was found: not a proof",
                stats=Stats(seconds_setup=round(seconds, 6)), start=str(start_set), goal=str(goal_set),
                max_bounces=k_max, environment=EnvironmentRecord.of(env), margins=margins.to_json())


def _graph_counts(problem: Problem) -> dict:
    """What the query built of the safe BVG (``stats``): its arcs, and for a graph built on demand
    (:func:`query_graph`) the source segments it reached of all the segments."""
    g = problem.graph
    out = {"graph_arcs": g.n_arcs, "graph_segments": g.n_segments}
    if g.stats.get("lazy"):
        out["graph_reachable_sources"] = g.stats["reachable_sources"]
    return out


def _partial_user_goal(problem: Problem) -> list[int]:
    """The user's segments the goal set covers only in part (what a certificate must claim images on)."""
    if problem.walls is None:
        return sorted(problem.goal_partial)
    part = problem.user_partition
    out = []
    for edge, pieces in (problem.user_goal_set.by_edge() if problem.user_goal_set is not None else {}).items():
        for k in part.edge_segments[edge]:
            s = part.segments[k]
            if not any(p <= s.t0 and s.t1 <= q for p, q in pieces) and any(s.t0 < q and p < s.t1 for p, q in pieces):
                out.append(k)
    return sorted(out)


def _found(problem: Problem, objective: str, path: _search.Path, optimality: Optimality, common: dict,
           stats: dict, constant: tuple[float, float] | None = None) -> Plan:
    """A found plan; an optimality claim with a bound but no measured gap gets gap = |value − bound|."""
    plan = Plan(Status.FOUND, objective, _stages(problem, path, constant), optimality, stats=Stats(counts=stats),
                **common)
    return _with_gap(plan)


def _with_gap(plan: Plan) -> Plan:
    opt = plan.optimality
    if opt.gap is not None or opt.bound is None or plan.value is None:
        return plan
    return plan.with_(optimality=replace(opt, gap=abs(plan.value - opt.bound)))


def _infeasible(objective: str, reason: str, optimality: Optimality, common: dict, stats: dict | None = None) -> Plan:
    return Plan.infeasible(objective, reason, optimality, stats=Stats(counts=stats or {}), **common)


def _cut(problem: Problem, objective: str, k_max: int | None, deadline: Deadline, progress: str,
         bound: float | None, algorithm: str, common: dict, stats: dict, path: _search.Path | None = None,
         method: Method = Method.SEARCH_EXHAUSTED) -> Plan:
    """The answer of a search the deadline stopped after ``progress``: its incumbent ``path`` (found, not
    proved optimal) or ``not-found``; either way with the ``bound`` proved so far and the timeout as a limit."""
    if bound is not None and not math.isfinite(bound):
        bound = None
    algorithm = f"{algorithm}, stopped by the timeout" if algorithm else "none: the timeout came before the search"
    opt = Optimality(method, False, bound, scope=_scope(problem, k_max), algorithm=algorithm,
                     limits=(deadline.limit(progress),))
    if path is not None:
        return _found(problem, objective, path, opt, common, stats)
    known = "" if bound is None else f" (the optimum is {'≥' if objective == 'fewest' else '≤'} {bound:.10g})"
    reason = f"{deadline.limit(progress)} before any plan was found{known}: not a proof"
    return Plan(Status.NOT_FOUND, objective, (), opt, reason=reason, stats=Stats(counts=stats), **common)


def _solve(problem: Problem, objective: str, k_max: int | None, method: str, common: dict,
           deadline: Deadline = NEVER) -> Plan:
    exhausted = Method.SEARCH_EXHAUSTED

    def claim(method_: Method, proved: bool, bound: float | None, algorithm: str, gap: float | None = None):
        return _claim(method_, proved, bound, algorithm, problem, k_max, gap)

    if problem.start_in_goal and objective != "sum":
        bound = {"fewest": 0.0, "tolerance": math.pi, "constant": math.pi}[objective]
        opt = claim(exhausted, True, bound, "the start set lies in the goal set", gap=0.0)
        return Plan(Status.FOUND, objective, (), opt, **common)
    reason = _precheck(problem, objective, k_max)
    if reason is not None:
        if not (objective == "sum" and problem.start_in_goal):
            return _infeasible(objective, reason, claim(exhausted, True, None, "precheck"), common)

    if objective == "fewest":
        return _fewest(problem, k_max, common, deadline)

    if deadline.expired():
        return _cut(problem, objective, k_max, deadline, "the precheck", None, "",
                    common, {})

    if objective == "tolerance":
        if method == "milp":
            from solverplan.plan._lp import tolerance_milp

            value, path, stats = tolerance_milp(problem, k_max)  # type: ignore[arg-type]
            if path is None:
                reason = _exhausted(objective, k_max, stats.get("nodes", 0), True)
                return _infeasible(objective, reason, claim(Method.MILP, True, None, "MILP (HiGHS) over path flows"),
                                   common, stats)
            opt = claim(Method.MILP, stats["gap"] <= _GAP_PROVED, stats["bound"],
                        "MILP (HiGHS) over path flows in the time-expanded network", gap=stats["gap"])
            return _found(problem, objective, path, opt, common, stats)
        if k_max is None:
            best, stats = _search.bottleneck(problem, deadline=deadline)
            incumbent = stats.pop("incumbent", None)
            if stats.pop("timed_out", False):
                return _cut(problem, objective, None, deadline, f"{stats['expanded']} beliefs expanded",
                            min(stats.pop("bound"), math.pi), "max-min Dijkstra over beliefs", common, stats, incumbent)
            if best <= 0.0:
                reason = _exhausted(objective, None, stats["beliefs"], False)
                return _infeasible(objective, reason, claim(exhausted, True, None, "max-min Dijkstra"), common, stats)
            path, bstats = _search.bfs(problem, threshold=best - _search.WIDTH_EPS, deadline=deadline)
            algorithm = "max-min Dijkstra over beliefs (W*), then BFS over options of width ≥ W* (fewest bounces)"
            if bstats.get("timed_out"):  # W* is proved; the plan attaining it may not have the fewest bounces
                return _cut(problem, objective, None, deadline, f"W* = {best:.10g} was proved, during the BFS for "
                            f"the fewest bounces ({bstats['beliefs']} beliefs)", best, algorithm, common,
                            {**stats, "bfs_beliefs": bstats["beliefs"]}, incumbent)
            if path is None:  # pragma: no cover - W* is attained by some plan
                raise AssertionError("no plan attains the bottleneck value")
            return _found(problem, objective, path, claim(exhausted, True, best, algorithm), common,
                          {**stats, "bfs_beliefs": bstats["beliefs"]})
        front = _search.layered_front(problem, k_max, deadline=deadline)
        algorithm = f"Pareto label setting (bounces, min width) up to {k_max} bounces"
        if front.timed_out:
            path = front.points[-1][2] if front.points else None
            return _cut(problem, objective, k_max, deadline, f"{front.scanned} of {k_max} layers ({front.beliefs} "
                        "beliefs)", front.bound, algorithm, common, {"beliefs": front.beliefs}, path)
        if not front.points:
            reason = _exhausted(objective, k_max, front.beliefs, not front.exhausted or front.budget_pruned)
            return _infeasible(objective, reason, claim(exhausted, True, None, algorithm), common,
                               {"beliefs": front.beliefs})
        k, w, path = front.points[-1]
        return _found(problem, objective, path, claim(exhausted, True, w, algorithm), common,
                      {"beliefs": front.beliefs, "front": [[p[0], p[1]] for p in front.points]})

    if objective == "sum":
        assert k_max is not None
        if method == "lp":
            from solverplan.plan._lp import sum_lp

            value, path, stats = sum_lp(problem, k_max)
            opt_method, algorithm = Method.LP_DUALITY, "LP over path flows in the time-expanded network (clarabel)"
        else:
            value, path, stats = _search.max_sum(problem, k_max, deadline=deadline)
            opt_method, algorithm = exhausted, f"dynamic programming over (belief, bounces ≤ {k_max})"
            if stats.pop("timed_out", False):
                return _cut(problem, objective, k_max, deadline, f"{stats['states']} (belief, bounces) states",
                            stats.pop("bound"), algorithm, common, stats, path)
        if problem.start_in_goal and (value is None or value <= 0.0):
            return Plan(Status.FOUND, objective, (), claim(opt_method, True, 0.0, algorithm, gap=0.0), **common)
        if path is None:
            reason = reason or _exhausted(objective, k_max, stats.get("states", 0), True)
            return _infeasible(objective, reason, claim(opt_method, True, None, algorithm), common, stats)
        if method == "lp":
            opt = claim(opt_method, stats["gap"] <= _GAP_PROVED * k_max, stats["bound"], algorithm, gap=stats["gap"])
        else:
            opt = claim(opt_method, True, value, algorithm)
        return _found(problem, objective, path, opt, common, stats)

    # constant
    interval, path, stats = _search.widest_constant(problem, k_max, deadline=deadline)
    algorithm = "Algorithm 2 labels (belief, running intersection) with ⊇ dominance"
    if stats.pop("timed_out", False):
        if path is not None:
            assert interval is not None
            plan = _cut(problem, objective, k_max, deadline, f"{stats['labels']} labels", stats.pop("bound"), algorithm,
                        common, stats)
            return _found(problem, objective, path, plan.optimality, common, stats, constant=interval)
        return _cut(problem, objective, k_max, deadline, f"{stats['labels']} labels", stats.pop("bound"), algorithm,
                    common, stats)
    if path is None:
        reason = _exhausted(objective, k_max, stats["beliefs"], stats["cut_by_budget"])
        return _infeasible(objective, reason, claim(exhausted, True, None, algorithm), common, stats)
    assert interval is not None
    return _found(problem, objective, path, claim(exhausted, True, interval[1] - interval[0], algorithm),
                  common, stats, constant=interval)


def _solve_accuracy(problem: Problem, objective: str, k_max: int | None, method: str, common: dict,
                    deadline: Deadline, accuracy: float) -> Plan:
    """:func:`find_plan` for a robot whose headings are only good to ``accuracy`` radians (``min_width``)."""
    scope = f"; every interval at least {accuracy:g} rad wide (the robot's heading accuracy)"

    def claim(proved: bool, bound: float | None, algorithm: str) -> Optimality:
        opt = _claim(Method.SEARCH_EXHAUSTED, proved, bound, algorithm, problem, k_max)
        return replace(opt, scope=opt.scope + scope)

    if objective == "fewest" and not problem.start_in_goal and _precheck(problem, objective, k_max) is None:
        path, stats = _search.bfs(problem, threshold=accuracy, max_bounces=k_max, deadline=deadline)
        algorithm = (f"belief-state BFS over the options at least {accuracy:g} rad wide: the fewest bounces among "
                     "plans whose intervals are all that wide")
        if stats.get("timed_out"):
            return _cut(problem, objective, k_max, deadline, f"{stats['beliefs']} beliefs", float(stats["depth"]),
                        algorithm, common, stats)
        if path is not None:
            return _found(problem, objective, path, claim(False, float(len(path)), algorithm), common,
                          {**stats, "heading_accuracy": accuracy})
        plan = None
    else:
        plan = _solve(problem, objective, k_max, method, common, deadline)
        if plan.status != Status.FOUND or plan.min_width is None or plan.min_width >= accuracy or not plan.stages:
            if plan.status == Status.FOUND:
                return plan.with_(optimality=replace(plan.optimality, scope=plan.optimality.scope + scope))
            return plan
    if deadline.expired():
        return _cut(problem, objective, k_max, deadline, "the search for a plan that wide", None, "", common, {})
    return _infeasible(objective, _accuracy_reason(problem, accuracy, k_max, deadline),
                       claim(True, None, "search over the options at least that wide, then the tolerance optimum W* "
                                         "and each start piece's own"), common, {"heading_accuracy": accuracy})


def _accuracy_reason(problem: Problem, accuracy: float, k_max: int | None, deadline: Deadline) -> str:
    """Why no plan is ``accuracy`` wide: the best accuracy that works (W*, no budget) and the start pieces that block."""
    best, _ = _search.bottleneck(problem, deadline=deadline)
    blocking = []
    for s in sorted(problem.start_belief):
        width = problem.belief_bounds((s,))[1]
        if width < accuracy:
            try:
                text = problem.segment_text(s)
            except (IndexError, KeyError, TypeError):
                text = f"start piece {s}"
            blocking.append((width, text))
    budget = f" within {k_max} bounces" if k_max is not None else ""
    reason = f"no plan{budget} has every interval at least {accuracy:g} rad wide"
    if best > 0:
        reason += (f"; the best heading accuracy that would work is {best:.6g} rad ({math.degrees(best):.4g}°: the "
                   f"widest narrowest interval of any plan, without a bounce budget)")
    else:
        reason += "; no plan exists at any accuracy"
    if blocking:
        blocking.sort()
        shown = "; ".join(f"{text} (its best {w:.4g} rad)" for w, text in blocking[:5])
        more = f"; and {len(blocking) - 5} more" if len(blocking) > 5 else ""
        reason += f"; start pieces that block (their own best plan is narrower): {shown}{more}"
    elif best > 0:
        reason += "; every start piece alone has such a plan: it is the start set as a whole (one interval from all of it) that blocks"
    return reason


def _fewest(problem: Problem, k_max: int | None, common: dict, deadline: Deadline = NEVER) -> Plan:
    """Fewest bounces; among those plans the most tolerant.

    One start segment: the layered label search in order of bounces (a BFS whose labels also carry the
    best min width) stops at the first layer with a plan. Several start segments: A* over beliefs with
    the single-segment bound h(b) = max_{s∈b} d(s) finds the fewest stages L (:func:`._search.fewest_stages`),
    then one layered search within the budget L, pruned by k + h(b) ≤ L, picks the most tolerant plan.
    """

    def claim(bound: float | None, algorithm: str) -> Optimality:
        return _claim(Method.SEARCH_EXHAUSTED, True, bound, algorithm, problem, k_max)

    algorithm = "belief-state BFS (layered labels); ties: the most tolerant of the fewest-bounce plans"
    start = problem.start_belief
    if len(start) == 1:
        front = _search.layered_front(problem, k_max, stop_at_first=True, deadline=deadline)
        stats = {"beliefs": front.beliefs}
        if front.timed_out and not front.points:
            return _cut(problem, "fewest", k_max, deadline, f"{front.scanned} layers ({front.beliefs} beliefs)",
                        float(front.scanned + 1), algorithm, common, stats)
        if not front.points:
            cut = not front.exhausted or front.budget_pruned
            reason = _exhausted("fewest", k_max, front.beliefs, cut)
            return _infeasible("fewest", reason, claim(None, algorithm), common, stats)
    else:
        algorithm = ("belief-state A* with single-segment bounds (fewest stages L), then layered labels within L "
                     "(the most tolerant of the fewest-bounce plans)")
        dist = {s: problem.belief_bounds((s,))[0] for s in start}
        lone = [s for s in start if dist[s] == math.inf]
        if lone:
            reason = (f"start {problem.segment_text(lone[0])} has no plan to the goal even on its own, so no plan "
                      f"works from the whole start set")
            return _infeasible("fewest", reason, claim(None, algorithm), common)
        if deadline.expired():
            return _cut(problem, "fewest", k_max, deadline, "the single-segment bounds", float(max(dist[s] for s in start)),
                        algorithm, common, {})
        fewest, astats = _search.fewest_stages(problem, k_max, deadline=deadline)
        if astats.pop("timed_out", False):
            return _cut(problem, "fewest", k_max, deadline, f"{astats['expanded']} beliefs expanded by A*",
                        float(astats.pop("bound")), algorithm, common, astats)
        if fewest is None:
            reason = _exhausted("fewest", k_max, astats["beliefs"], astats["cut_by_budget"])
            return _infeasible("fewest", reason, claim(None, algorithm), common, astats)
        front = _search.layered_front(problem, fewest, stop_at_first=True, deadline=deadline)
        stats = {"beliefs": front.beliefs, "a_star_beliefs": astats["beliefs"]}
        if front.timed_out and not front.points:
            return _cut(problem, "fewest", k_max, deadline, f"A* proved {fewest} stages, during the search for the "
                        f"most tolerant of them ({front.beliefs} beliefs)", float(fewest), algorithm, common, stats)
        if not front.points or front.points[0][0] != fewest:  # pragma: no cover - A* and the labels agree
            raise AssertionError("the layered search did not find the A* optimum")
    k, _, path = front.points[0]
    return _found(problem, "fewest", path, claim(float(k), algorithm), common, stats)


@fill_doc(margins=MARGIN_DOCS["margins"])
def pareto_front(
    env: Environment,
    start: str | BoundarySet,
    goal: str | BoundarySet,
    *,
    max_bounces: int | None = None,
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    safe_margin: float = DEFAULT_SAFE_MARGIN,
    corner_clearance: float | None = None,
    timeout: float | Deadline | None = None,
) -> ParetoFront:
    """The Pareto front bounces ↔ tolerance: the most tolerant plan for each bounce count that improves it.

    For each bounce count b at which the best achievable min width strictly improves, the most tolerant plan
    with ≤ b bounces (within ``max_bounces`` if given; without it the front is complete: no plan of any length
    beats its last point).

    Parameters
    ----------
    env
        The environment.
    start, goal
        Boundary sets (``"e3:0.25:0.75,e4"`` or :class:`~solverplan.environment.BoundarySet`).
    max_bounces
        The bounce budget K (None: no budget, the front is complete).
    graph
        A prebuilt safe BVG of ``env`` (built when not given).
    %(margins)s
    timeout
        Seconds of wall time, the graph build included (None: no limit). It stops the label setting: the
        points found so far are exact, the front's ``optimality`` is not proved, its bound is an upper bound on
        every plan's min width and its limits name the timeout.

    Returns
    -------
    ParetoFront
        The points (bounces, min width in radians, plan), fewest bounces first; empty and ``infeasible`` when
        no plan exists.

    Raises
    ------
    InputError
        Bad sets, a bad budget or margin, a timeout that is not a positive finite number.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
    >>> front = pareto_front(ell, "e5", "e0:0:0.3")
    >>> [(p.bounces, round(p.min_width, 4)) for p in front.points]
    [(1, 0.2903), (5, 0.4625)]
    """
    k_max = _check_budget(max_bounces)
    deadline = deadline_of(timeout)
    t0 = time.perf_counter()
    problem = _query_problem(env, start, goal, "tolerance", k_max, deadline, t0, graph=graph,
                             heading_margin=heading_margin, safe_margin=safe_margin, corner_clearance=corner_clearance)
    if isinstance(problem, Plan):  # the timeout came while the query was built
        plan = problem
        return ParetoFront((), plan.optimality, start=plan.start, goal=plan.goal, max_bounces=k_max,
                           reason=plan.reason, environment=plan.environment, stats=plan.stats)
    common = _common(problem, k_max)
    algorithm = "Pareto label setting (bounces, min width)" + (f" up to {k_max} bounces" if k_max else " to a fixed point")
    exhausted = Method.SEARCH_EXHAUSTED
    if problem.start_in_goal:
        opt = _claim(exhausted, True, math.pi, algorithm, problem, k_max, gap=0.0)
        plan = Plan(Status.FOUND, "tolerance", (), opt, **common)
        return ParetoFront((ParetoPoint(0, math.pi, plan),), opt, start=common["start"], goal=common["goal"],
                           max_bounces=k_max, environment=common["environment"])
    reason = _precheck(problem, "tolerance", k_max)
    points: list[ParetoPoint] = []
    beliefs = 0
    limits: tuple[str, ...] = ()
    bound = None
    if reason is None:
        front = _search.layered_front(problem, k_max, deadline=deadline)
        beliefs = front.beliefs
        if front.timed_out:
            limits, bound = (deadline.limit(f"{front.scanned} layers ({front.beliefs} beliefs)"),), front.bound
        for k, w, path in front.points:
            opt = _claim(exhausted, True, w, f"{algorithm}: the best plan with ≤ {k} bounces", problem, k)
            plan = _found(problem, "tolerance", path, opt, {**common, "max_bounces": k}, {})
            points.append(ParetoPoint(k, w, plan))
        if not points:
            reason = _exhausted("tolerance", k_max, front.beliefs, not front.exhausted or front.budget_pruned)
            if limits:
                reason = f"{limits[0]} before any plan was found: not a proof"
    best = points[-1].min_width if points else None
    stats = Stats(seconds_search=round(time.perf_counter() - t0, 6), counts={"beliefs": beliefs})
    if limits:
        gap = None if best is None or bound is None else abs(bound - best)
        opt = Optimality(exhausted, False, bound, scope=_scope(problem, k_max), gap=gap,
                         algorithm=f"{algorithm}, stopped by the timeout", limits=limits)
    else:
        opt = _claim(exhausted, True, best, algorithm, problem, k_max, gap=None if best is None else 0.0)
    return ParetoFront(tuple(points), opt, start=common["start"], goal=common["goal"], max_bounces=k_max,
                       reason=reason, environment=common["environment"], stats=stats)
