"""Localisation (paper §8.4): an open-loop strategy after which the robot's possible positions, from anywhere on
the boundary (or a given start set S), lie in **one interval shorter than ε**.

The robot senses nothing but its bounces, so the strategy is a fixed sequence of heading intervals (each 2·tolerance
wide, measured from the wall the robot is on). The set of possible positions is tracked exactly
(:mod:`solverplan.plan._positions`): from the whole boundary it starts as one piece per edge; a stage maps each
piece onto one edge (its whole image must land there), pieces landing on one edge are merged, and contracting
transitions (Def. 11, Lemma 2: small headings into corners) shrink them and the gaps between them. The beam search
ranks states by how many edges they still occupy, then by their spread, and stops at the first state that lies on
one edge within an interval shorter than ε; that strategy is replayed exactly and returned as a
:class:`Localization` whose goal is that interval (certifiable like any funnel).

**Symmetry.** If a rotation T ≠ id maps the environment onto itself (edges to edges, directions kept) and the
start set onto itself, no strategy localises: headings are measured from the wall the robot is on, so f(T S, Θ) =
T f(S, Θ) and every position set stays T-invariant; a T-invariant set meets T(e) ≠ e whenever it meets e, so it is
never one interval of one edge. :func:`localize` checks this exactly first and answers ``impossible`` with the
rotation (status ``infeasible``, method ``symmetry``, proved: the square, the regular hexagon,
``narrow_door``'s half-turn).

**Search and its limits.** The search widens (narrow passes first, the full beam only when they fail) within a
work budget (``max_rows``), so it answers in seconds; on the shipped models it finds strategies from the whole
boundary in convex rooms, L-shaped and two-room plans, rooms with holes, the comb and the star. A stage must
carry each piece whole onto a single straight wall (a piece whose image spans a corner sweeps across a vertex,
which the exact checker's moves never do; collinear vertices are no corners: the search runs on the environment
with them merged, :mod:`solverplan.plan._walls`, and answers in the user's edges, so a final interval may hold
pieces of two collinear edges), so from the whole boundary of a room where every heading splits some edge
(a corridor with alcoves, the warehouse) the search stops at once with that reason; give a start set S instead.
The search is heuristic: not finding is not a proof (status ``not-found``, with its caps and ``cut=...``, what
ended it, in ``optimality.limits``).

>>> from solverplan.environment import Environment
>>> tri = Environment.from_coords([[0, 0], [10, 0], [3, 7]], name="triangle")
>>> loc = localize(tri, 0.05, start="e0", tolerance=0.002)
>>> loc.status.value, loc.goal.pieces[0].edge == loc.stages[-1].positions[0].edge
('found', True)
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from solverplan._docstrings import fill_doc
from solverplan.bounce.bvg import SafeBVG
from solverplan.bounce.partitions import partition
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN
from solverplan.plan._deadline import Deadline, deadline_of
from solverplan.plan._positions import Flat, to_user_stages
from solverplan.plan._results import PositionStrategy
from solverplan.plan._walls import PartitionedWalls
from solverplan.plan.funnels import (DEFAULT_MAX_ROWS, POSITION_SEARCH_DOCS, SearchBounds, boundary_pieces, graded_search,
                                     search_half_width)
from solverplan.result import EnvironmentRecord, Method, Optimality, Reader, Status, answer_dataclass

__all__ = ["Localization", "localize", "rotational_symmetry"]


@answer_dataclass("localize", kw_only=True)
class Localization(PositionStrategy):
    """A localisation strategy: after its stages every start of ``start`` lies in ``goal``, one interval of one
    edge (or of one straight wall: pieces of consecutive collinear edges) shorter than ``epsilon`` (arc length) — or why there is none (``infeasible`` by symmetry, proved; or
    ``not-found`` by the capped search, nothing proved). The other fields are
    :class:`~solverplan.plan._results.PositionStrategy`'s.
    """

    epsilon: float

    def _extra_json(self) -> dict:
        return {"epsilon": self.epsilon}

    @classmethod
    def _extra_from_json(cls, r: Reader) -> dict:
        return {"epsilon": r.number("epsilon")}

    def _head(self) -> str:
        return f"{super()._head()} to one interval shorter than {self.epsilon:g}"


def rotational_symmetry(env: Environment, start: BoundarySet | None = None):
    """A rotation T ≠ id (exact) mapping every directed edge of ``env`` onto a directed edge and ``start`` onto
    itself: ``((cos, sin), k)`` with T(edge 0) = edge k, or None. T maps edge 0 onto some edge k of equal length;
    its matrix [[c, −s], [s, c]] is rational (c, s = dot and cross of the edge vectors over the squared length)."""
    verts = env.exact_vertices
    nxt = env.next_vertex
    edges = {(verts[i], verts[int(nxt[i])]): i for i in range(env.n_edges)}
    a0, b0 = verts[0], verts[int(nxt[0])]
    e0 = (b0[0] - a0[0], b0[1] - a0[1])
    n2 = e0[0] ** 2 + e0[1] ** 2
    for k in range(1, env.n_edges):
        ak, bk = verts[k], verts[int(nxt[k])]
        ek = (bk[0] - ak[0], bk[1] - ak[1])
        if ek[0] ** 2 + ek[1] ** 2 != n2:
            continue
        c = (e0[0] * ek[0] + e0[1] * ek[1]) / n2
        s = (e0[0] * ek[1] - e0[1] * ek[0]) / n2
        if c == 1 and s == 0:
            continue
        tx, ty = ak[0] - (c * a0[0] - s * a0[1]), ak[1] - (s * a0[0] + c * a0[1])

        def T(p):
            return (c * p[0] - s * p[1] + tx, s * p[0] + c * p[1] + ty)

        image = {}
        for (p, q), i in edges.items():
            j = edges.get((T(p), T(q)))
            if j is None:
                break
            image[i] = j
        else:
            if start is None or _invariant(start, image):
                return (c, s), k
    return None


def _invariant(start: BoundarySet, image: dict[int, int]) -> bool:
    """Is the start set mapped onto itself (a piece t ∈ [t0, t1] of edge i goes to the same t-range of image[i])?"""
    def union(items):
        by: dict[int, list] = {}
        for e, a, b in sorted(items):
            if by.get(e) and a <= by[e][-1][1]:
                by[e][-1][1] = max(by[e][-1][1], b)
            else:
                by.setdefault(e, []).append([a, b])
        return {e: [tuple(r) for r in v] for e, v in by.items()}

    pieces = [(p.edge, p.t0, p.t1) for p in start.pieces]
    return union(pieces) == union((image[e], a, b) for e, a, b in pieces)


@fill_doc(**POSITION_SEARCH_DOCS)
def localize(
    env: Environment,
    epsilon: float,
    *,
    start: str | BoundarySet | None = None,
    tolerance: float | None = None,
    max_bounces: int = 40,
    n_headings: int = 240,
    beam: int = 400,
    graph: SafeBVG | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
    corner_clearance: float | None = None,
    max_rows: int | None = DEFAULT_MAX_ROWS,
    timeout: float | Deadline | None = None,
) -> Localization:
    """A localisation strategy: stages after which every start lies in one interval shorter than ``epsilon``.

    After its stages every start in ``start`` (default: the whole boundary) is inside one interval of one edge
    shorter than ``epsilon`` (arc length). The search widens: narrow passes
    (:data:`~solverplan.plan.funnels.NARROW_PASSES`) run first and the full ``beam`` × ``n_headings`` pass only if
    they find nothing, all within one work budget ``max_rows``, so that the answer comes in seconds.

    Parameters
    ----------
    env
        The environment.
    epsilon
        The length (environment's units) the final interval must be shorter than.
    start
        The boundary set the robot may start on (default: the whole boundary).
    %(tolerance)s
    %(bounds)s
    graph
        A precomputed safe BVG of ``env`` (its partition is reused).
    %(margins)s
    %(timeout)s

    Returns
    -------
    Localization
        ``found`` with the stages and, as its goal, the final interval; ``infeasible`` when a symmetry of the
        environment and the start set forbids it (proved); or ``not-found`` with the search's caps in
        ``optimality.limits``.

    Raises
    ------
    InputError
        ε not a positive length, a bad start set, a tolerance outside (0, π/2), a bound out of its range, a timeout
        that is not a positive finite number.

    Examples
    --------
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> where = sp.localize(env, 0.5)                 # wherever it starts, end within 0.5 units of a known point
    >>> where.status.value, where.bounces, where.goal.edges
    ('found', 6, (5,))

    The square looks the same after a quarter turn, so no open-loop strategy can tell its walls apart:

    >>> where = sp.localize(sp.load_environment("square"), 0.5)
    >>> where.status.value, where.optimality.method.value
    ('infeasible', 'symmetry')
    """
    if isinstance(epsilon, bool) or not isinstance(epsilon, (int, float)) or not (math.isfinite(epsilon) and epsilon > 0):
        raise InputError(f"epsilon {epsilon!r} must be a positive length")
    eps = search_half_width(tolerance)
    bounds = SearchBounds(max_bounces, n_headings, beam, max_rows)
    if start is None:
        start_set = BoundarySet(tuple(BoundaryPiece(e, Fraction(0), Fraction(1)) for e in range(env.n_edges)))
    else:
        start_set = boundary_pieces(env, start, "start")
    deadline = deadline_of(timeout)
    # Collinear vertices are no corners: search the straight walls (the same free space with them merged) and
    # answer in the user's edges (plan._walls, to_user_stages). A final interval may then straddle a collinear
    # vertex: it is one interval of one straight wall.
    walls = PartitionedWalls(env)
    user_start = start_set
    # the search needs only the partition of the straight walls (the graph's, when one is given): no safe BVG
    part = graph.partition if graph is not None and graph.partition.env == walls.merged else partition(walls.merged)
    if walls.identity:
        user_part = part
    else:
        user_part = graph.partition if graph is not None and graph.partition.env == env else walls.user_partition
        env, start_set = walls.merged, walls.to_merged(start_set)
    record = EnvironmentRecord.of(walls.env, user_part.n_segments)
    scope = "open-loop strategies from the start set (headings measured from the wall the robot is on)"
    # on the straight walls: a rotation of the merged environment is one of the user's free space (a split
    # square is still a square), and it maps the start set onto itself there exactly when it does in the user's
    symmetry = rotational_symmetry(env, start_set)
    if symmetry is not None:
        (a, b), shift = symmetry
        if walls.identity:
            edges = f"edge e0 to e{shift}"
        else:
            first = walls.user_edges[0][0][0], walls.user_edges[shift][0][0]
            edges = f"the straight wall from edge e{first[0]} to the one from edge e{first[1]}"
        reason = (f"the rotation by atan2({b}, {a}) = {math.atan2(float(b), float(a)):.6g} rad maps the environment and "
                  f"the start set onto themselves ({edges}), so every position set stays invariant under it "
                  "and never lies on one edge: no open-loop strategy localises")
        return Localization(status=Status.INFEASIBLE, reason=reason, environment=record, start=user_start, tolerance=eps,
                            epsilon=float(epsilon), partition=user_part,
                            optimality=Optimality(Method.SYMMETRY, True, None, scope=scope,
                                                  algorithm="exact rotational symmetry"))
    lengths = np.asarray(env.edge_lengths, dtype=float)
    limit = float(epsilon)

    def done(flat: Flat) -> np.ndarray:
        # one edge, hull shorter than ε (floats, with a relative margin; the exact test decides)
        owner, edge, lo, hi = flat.hulls()
        count = np.bincount(owner, minlength=flat.n)
        short = np.zeros(flat.n, dtype=bool)
        short[owner] = (hi - lo) * lengths[edge] < limit * (1 - 1e-9)
        return (count == 1) & short

    def done_exact(pieces) -> bool:
        if len({p.edge for p in pieces}) != 1:
            return False
        lo, hi = min(p.t0 for p in pieces), max(p.t1 for p in pieces)
        return float(hi - lo) * float(lengths[pieces[0].edge]) < limit

    outcome, status, optimality, stats = graded_search(
        env, part, start_set.pieces, done, done_exact, eps=eps, bounds=bounds, heading_margin=heading_margin,
        corner_clearance=corner_clearance, deadline=deadline, rank="edges")
    goal = None
    if outcome.stages is not None:
        final = outcome.stages[-1].positions if outcome.stages else start_set.pieces
        goal = walls.to_user_set(
            BoundarySet((BoundaryPiece(final[0].edge, min(p.t0 for p in final), max(p.t1 for p in final)),)))
    return Localization(status=status, optimality=optimality, environment=record, start=user_start, goal=goal,
                        tolerance=eps, epsilon=limit, partition=user_part, stages=to_user_stages(walls, outcome.stages or ()),
                        reason="" if outcome.stages is not None else outcome.reason, stats=stats)
