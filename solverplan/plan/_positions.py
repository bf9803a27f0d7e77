"""Search over sets of possible positions (private): the engine of funnels and localisation.

A *state* is the exact set of positions the robot may occupy: a tuple of boundary pieces (edge, t0, t1). A
stage applies one heading interval [θ − ε, θ + ε] (each piece measured from its own edge) and the state becomes
the lifted transition f(S, Θ) (:func:`~solverplan.bounce.transitions.transition_set`). The search does not
restrict stages to whole segments of P′, so it can use contraction: a piece shrinks by the contraction
coefficient of each transition (Def. 11) until it fits through a gap no segment fits through.

**Search.** Breadth-first by bounces, on floats, with

- *candidates*: a grid of ``n_headings`` nominal headings θ over [δ + ε, π − δ − ε] (δ the heading margin of
  :mod:`solverplan.plan.margins`) plus the headings from each piece's midpoint towards the goal set; a candidate
  is kept when, for every piece, its four corner rays (piece ends × cone ends) land on one edge other than the
  source, at least the corner clearance κ from that edge's ends (but the corner it shares with the source edge),
  and no vertex of P other than the ends of the two edges lies inside the convex hull of the piece and the corner
  hits (the swept region) or within κ of it. Then the image of the piece is the interval spanned by the corner
  hits, the same test the exact checker makes, and every landing replays in floating point too. All (candidate,
  piece) rows of a bounce are tested at once: two diagonal corner rays for every row, the other two and the hull
  test only for rows of candidates still alive (one failing piece kills its candidate), the hull test only on
  (row, vertex) pairs inside the row's bounding box;
- *dominance*: a state whose position set contains a set already reached (with no more bounces) is dropped:
  every strategy from the larger set works from the smaller one (:class:`_Reached`: indexed lookups against
  single-piece sets and sets occupying the same edges);
- *beam*: per bounce at most ``beam`` states survive (at most ``per_edge`` per edge of their first piece), the
  ones with the fewest pieces and the shortest total length first (or the fewest edges occupied:
  ``rank="edges"``); states are built, ranked and goal-tested as flat arrays (:class:`Flat`);
- *work budget*: ``max_rows`` (piece, heading) images over the whole search; a bounce that would pass it is not
  started, and the outcome says what cut the search (:class:`SearchOutcome`). :func:`search_widening` runs
  narrow passes first (a narrow beam that keeps few states per edge is fast and often enough) and the full
  beam only when they fail, within one budget.

A state inside the goal is replayed **exactly**: the interval of every stage becomes rational directions just
outside it (:func:`~solverplan.plan._results.heading_cone`; every heading of the float interval is in the cone), each piece is pushed through
:func:`~solverplan.bounce.transitions.transition_set`, and the exact final set must lie in the goal. Only replayed
strategies are returned. The search is a heuristic (the heading grid and the beam): it proves what it returns,
never that nothing exists. A ``deadline`` (:class:`~solverplan.plan._deadline.Deadline`) is asked before each
bounce, between blocks of the vectorised corner-ray tests and for each new state (before its dominance check
or its exact replay); when it has passed the search stops with nothing found and the timeout in
``limits``.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from solverplan.interval import Interval
from solverplan.bounce.partitions import Partition
from solverplan.bounce.transitions import transition_set
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.geometry.raycast import cast_from_boundary
from solverplan.plan._deadline import Deadline, in_chunks
from solverplan.plan._results import heading_cone
from solverplan.plan._walls import PartitionedWalls
from solverplan.result import Stage
from solverplan.plan.margins import Margins

__all__ = ["PositionSearch", "SearchOutcome", "search_positions", "merge_pieces", "replay", "to_user_stages"]

logger = logging.getLogger(__name__)

Pieces = tuple[tuple[int, float, float], ...]


@dataclass(frozen=True)
class SearchOutcome:
    """What the search found: exact ``stages`` (None if nothing), and statistics. ``cut`` names what ended a
    search that found nothing: ``"max_bounces"`` (the bounce budget), ``"max_rows"`` (the work budget:
    (piece, heading) images evaluated), or ``"exhausted"`` (no state was left to expand: every candidate heading
    of the grid failed or led to a dominated state — still only a statement about the grid and the beam), or
    ``"timeout"`` (the deadline; ``limits`` says so)."""

    stages: tuple[Stage, ...] | None
    expanded: int
    layers: int
    replay_failures: int
    reason: str
    cut: str | None = None
    rows: int = 0
    limits: tuple[str, ...] = ()  # what stopped the search early (a timeout), besides its caps


@dataclass
class _Node:
    pieces: Pieces
    parent: int
    interval: tuple[float, float] | None
    depth: int


def merge_pieces(items: Sequence[tuple[int, float, float]], tol: float = 0.0) -> Pieces:
    """Sorted union of float pieces, merging overlaps on the same edge (and gaps up to ``tol``)."""
    by_edge: dict[int, list[list[float]]] = {}
    for e, a, b in sorted(items):
        runs = by_edge.setdefault(int(e), [])
        if runs and a <= runs[-1][1] + tol:
            runs[-1][1] = max(runs[-1][1], b)
        else:
            runs.append([a, b])
    return tuple((e, a, b) for e in sorted(by_edge) for a, b in by_edge[e])


def merge_exact(items: Sequence[BoundaryPiece]) -> tuple[BoundaryPiece, ...]:
    """Sorted union of exact pieces (overlapping or touching pieces of one edge merged)."""
    return BoundarySet(tuple(items)).merged().pieces


class PositionSearch:
    """The float machinery: corner rays and swept-hull tests for many (piece, heading) pairs at once."""

    def __init__(self, env: Environment, tolerance: float, *, n_headings: int, margins: Margins) -> None:
        self.env = env
        self.eps = float(tolerance)
        self.margins = margins
        delta = self.margins.heading_margin
        lo, hi = self.eps + delta, math.pi - self.eps - delta
        if not lo < hi:
            raise InputError(f"tolerance {tolerance!r} leaves no heading interval inside [{delta:g}, π − {delta:g}] "
                             "(the heading margin)")
        self.grid = np.linspace(lo, hi, n_headings)
        self.verts = np.asarray(env.vertices, dtype=float)
        self.scale = float(np.max(np.abs(self.verts))) + 1.0
        self.lengths = np.asarray(env.edge_lengths, dtype=float)

    def images(self, edges: np.ndarray, a: np.ndarray, b: np.ndarray, theta: np.ndarray,
               group: np.ndarray | None = None):
        """For pieces (edges, a, b) and nominal headings theta (same length m): (ok, target, lo, hi).

        ``group`` (optional, length m): the candidate each row belongs to. A candidate is only useful when all
        its rows are ok, so the swept-hull tests (the costly part) are skipped for the rows of candidates that
        already failed the ray tests; those rows come back not ok.
        """
        m = len(edges)
        eps = self.eps
        # piece ends pulled in a little so that rays never start at a vertex (a filter: the replay is exact)
        pull = 1e-6 * (b - a)
        ta, tb = a + pull, b - pull
        # two diagonal corner rays first, for every row; the other two only for rows of candidates still alive
        # (a candidate dies with any of its rows, so most rows of a many-piece state need no second cast)
        he = np.full((m, 4), -1, dtype=np.int64)
        ht = np.zeros((m, 4))
        hx, hy = np.zeros((m, 4)), np.zeros((m, 4))
        flagged = np.zeros((m, 4), dtype=bool)

        def cast(rows: np.ndarray, cols: tuple[int, int]) -> None:
            T = np.stack([ta[rows] if c < 2 else tb[rows] for c in cols], axis=1).reshape(-1)
            H = np.stack([theta[rows] - eps if c % 2 == 0 else theta[rows] + eps for c in cols], axis=1).reshape(-1)
            hits = cast_from_boundary(self.env, np.repeat(edges[rows], len(cols)), T, H)
            k = len(cols)
            for j, c in enumerate(cols):
                he[rows, c] = hits.edge.reshape(-1, k)[:, j]
                ht[rows, c] = hits.t.reshape(-1, k)[:, j]
                hx[rows, c] = hits.x.reshape(-1, k)[:, j]
                hy[rows, c] = hits.y.reshape(-1, k)[:, j]
                flagged[rows, c] = hits.vertex.reshape(-1, k)[:, j] >= 0

        def alive_rows(ok: np.ndarray) -> np.ndarray:
            if group is not None and m:
                alive = np.ones(int(group.max()) + 1, dtype=bool)
                np.logical_and.at(alive, group, ok)
                ok = ok & alive[group]
            return ok

        every = np.arange(m)
        cast(every, (0, 3))
        ok = (he[:, 0] == he[:, 3]) & ~flagged[:, 0] & ~flagged[:, 3] & (he[:, 0] != edges)
        ok = alive_rows(ok)
        rest = np.flatnonzero(ok)
        if len(rest):
            cast(rest, (1, 2))
        ok &= (he == he[:, :1]).all(axis=1) & ~flagged.any(axis=1)
        target = he[:, 0]
        ok &= self._clear_of_ends(edges, target, ht)
        ok = alive_rows(ok)
        # the hull of the piece ends and the corner hits must hold no vertex of P (nor come within κ of one)
        rows = np.flatnonzero(ok)
        if len(rows):
            P = self.env.points_at(edges[rows], ta[rows])
            Q = self.env.points_at(edges[rows], tb[rows])
            sub_t = ht[rows]
            lo_k = np.argmin(sub_t, axis=1)
            hi_k = np.argmax(sub_t, axis=1)
            r = np.arange(len(rows))
            H1 = np.stack([hx[rows][r, lo_k], hy[rows][r, lo_k]], axis=1)
            H2 = np.stack([hx[rows][r, hi_k], hy[rows][r, hi_k]], axis=1)
            ok[rows[self._hull_blocked(P, Q, H1, H2, edges[rows], target[rows])]] = False
        lo = ht.min(axis=1)
        hi = ht.max(axis=1)
        return ok, target, lo, hi

    def _hull_blocked(self, P: np.ndarray, Q: np.ndarray, H1: np.ndarray, H2: np.ndarray, source: np.ndarray,
                      target: np.ndarray) -> np.ndarray:
        """Per row: does a vertex of P lie strictly inside one of the triangles PQH1, PQH2, PH1H2, QH1H2 (their
        union is the swept hull), with a relative margin, or within κ of one of their sides (vertices of the
        source and target edges exempt from the latter)?

        Only (row, vertex) pairs inside the rows' bounding boxes grown by κ (and the margin) are tested: a
        vertex outside the box is neither inside a triangle nor within κ of a side. The box test is a few
        comparisons per pair; the distance tests, the costly part, run on the few pairs that pass it.
        """
        V = self.verts
        kappa = max(self.margins.corner_clearance, 0.0)
        tol = 1e-9 * self.scale * self.scale
        pts = np.stack([P, Q, H1, H2], axis=1)  # rows × 4 × 2
        grow = kappa + 1e-9 * self.scale
        lo = pts.min(axis=1) - grow
        hi = pts.max(axis=1) + grow
        pair_r, pair_v = np.nonzero((V[None, :, 0] >= lo[:, None, 0]) & (V[None, :, 0] <= hi[:, None, 0])
                                    & (V[None, :, 1] >= lo[:, None, 1]) & (V[None, :, 1] <= hi[:, None, 1]))
        blocked = np.zeros(len(P), dtype=bool)
        if not len(pair_r):
            return blocked
        W = V[pair_v]
        A, B, C, D = P[pair_r], Q[pair_r], H1[pair_r], H2[pair_r]

        def side(p, q):
            d = q - p
            return d[:, 0] * (W[:, 1] - p[:, 1]) - d[:, 1] * (W[:, 0] - p[:, 0])

        inside = np.zeros(len(pair_r), dtype=bool)
        for X, Y, Z in ((A, B, C), (A, B, D), (A, C, D), (B, C, D)):
            s1, s2, s3 = side(X, Y), side(Y, Z), side(Z, X)
            inside |= ((s1 > tol) & (s2 > tol) & (s3 > tol)) | ((s1 < -tol) & (s2 < -tol) & (s3 < -tol))
        if kappa > 0:
            exempt = self._is_end(source[pair_r], pair_v) | self._is_end(target[pair_r], pair_v)
            near = np.zeros(len(pair_r), dtype=bool)
            for X, Y in ((A, B), (A, C), (A, D), (B, C), (B, D), (C, D)):
                d = Y - X
                w = W - X
                dd = np.maximum((d * d).sum(axis=1), 1e-300)
                lam = np.clip((w * d).sum(axis=1) / dd, 0.0, 1.0)
                gap = w - lam[:, None] * d
                near |= (gap * gap).sum(axis=1) < kappa * kappa
            inside |= near & ~exempt
        np.logical_or.at(blocked, pair_r, inside)
        return blocked

    def _is_end(self, edges: np.ndarray, vertex: np.ndarray) -> np.ndarray:
        """Is vertex ``vertex`` (an index into the float vertices) an end of edge ``edges``, pairwise? (Floats of
        one exact point are equal.)"""
        V = self.verts[vertex]
        return (np.all(V == self.env.edge_start[edges], axis=1) | np.all(V == self.env.edge_end[edges], axis=1))

    def _clear_of_ends(self, source: np.ndarray, target: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Do the corner hits ``t`` (rows × 4, on ``target``) stay κ from the target's ends, but the end shared
        with the source edge?"""
        kappa = self.margins.corner_clearance
        if kappa <= 0:
            return np.ones(len(target), dtype=bool)
        room = kappa / self.lengths[target]
        env = self.env
        shared_lo = np.all(env.edge_start[target] == env.edge_end[source], axis=1)
        shared_hi = np.all(env.edge_end[target] == env.edge_start[source], axis=1)
        low_ok = shared_lo | (t.min(axis=1) >= room)
        high_ok = shared_hi | (t.max(axis=1) <= 1 - room)
        return low_ok & high_ok

    def aim(self, edges: np.ndarray, a: np.ndarray, b: np.ndarray, goal_points: np.ndarray) -> np.ndarray:
        """Nominal headings from each piece's midpoint towards each goal point: shape (pieces, points)."""
        mid = self.env.points_at(edges, (a + b) / 2)
        e = self.env.edge_end[edges] - self.env.edge_start[edges]
        d = goal_points[None, :, :] - mid[:, None, :]
        cross = e[:, None, 0] * d[..., 1] - e[:, None, 1] * d[..., 0]
        dot = e[:, None, 0] * d[..., 0] + e[:, None, 1] * d[..., 1]
        return np.arctan2(cross, dot)


def search_positions(
    env: Environment,
    part: Partition,
    start: Sequence[BoundaryPiece],
    is_goal: Callable[["Flat"], np.ndarray],
    is_goal_exact: Callable[[tuple[BoundaryPiece, ...]], bool],
    *,
    tolerance: float,
    max_bounces: int,
    n_headings: int,
    beam: int,
    per_edge: int,
    margins: Margins,
    max_rows: int | None,
    deadline: Deadline,
    goal_points: np.ndarray | None = None,
    rank: str = "pieces",
    max_replays: int = 20,
) -> SearchOutcome:
    """Breadth-first search with dominance and a beam (module docstring) for a state satisfying ``is_goal``
    (floats, vectorised: a :class:`Flat` batch of states → one bool per state), confirmed by ``is_goal_exact``
    on the exact replay. ``margins``: the margin policy; ``max_rows``: a work budget, the (piece, heading) images
    evaluated over the whole search (a bounce that would exceed it is not started; None: no budget);
    ``goal_points``: points of the goal set to aim at; ``rank``: how states compete for the beam
    (:func:`_rank_keys`); ``max_replays``: the most goal states replayed exactly over the search. The bounds have no
    defaults here: the planners' own (:func:`~solverplan.plan.funnels.funnel`, ...) are the only ones."""
    ps = PositionSearch(env, tolerance, n_headings=n_headings, margins=margins)
    first = merge_pieces([(p.edge, float(p.t0), float(p.t1)) for p in start])
    nodes = [_Node(first, -1, None, 0)]
    reached = _Reached(env.n_edges)  # every state kept so far, for dominance
    reached.add(first)
    layer = [0]
    expanded = 0
    replays = 0
    failures = 0
    rows_done = 0
    if is_goal(Flat.of([first]))[0]:
        stages = replay(env, part, start, [], is_goal_exact)
        if stages is not None:
            return SearchOutcome(stages, 0, 0, 0, "the start set already lies in the goal")
        failures += 1
    for depth in range(1, max_bounces + 1):
        if not layer:
            break
        if deadline.expired():
            return _timed_out(deadline, expanded, depth - 1, failures, rows_done)
        # flatten the layer's pieces × candidate headings
        pe, pa, pb = [], [], []
        for i in layer:
            for e, a, b in nodes[i].pieces:
                pe.append(e)
                pa.append(a)
                pb.append(b)
        pe_a, pa_a, pb_a = np.array(pe, dtype=np.int64), np.array(pa), np.array(pb)
        # candidate headings per state: the grid, plus aims at the goal from single-piece states
        cand_state, cand_theta = [], []
        K = len(ps.grid)
        for i in layer:
            cand_state.append(np.full(K, i))
            cand_theta.append(ps.grid)
        if goal_points is not None and len(goal_points):
            single = [i for i in layer if len(nodes[i].pieces) == 1]
            if single:
                aims = ps.aim(np.array([nodes[i].pieces[0][0] for i in single]),
                              np.array([nodes[i].pieces[0][1] for i in single]),
                              np.array([nodes[i].pieces[0][2] for i in single]), goal_points)
                lo, hi = ps.grid[0], ps.grid[-1]
                for row, i in enumerate(single):
                    th = aims[row]
                    th = th[(th > lo) & (th < hi)]
                    cand_state.append(np.full(len(th), i))
                    cand_theta.append(th)
        cs = np.concatenate(cand_state)
        ct = np.concatenate(cand_theta)
        # one row per (candidate, piece of its state); a state's pieces are contiguous rows of the flat arrays
        slot = {i: k for k, i in enumerate(layer)}
        n_of = np.array([len(nodes[i].pieces) for i in layer], dtype=np.int64)
        off_of = np.cumsum(n_of) - n_of
        cs_slot = np.array([slot[i] for i in cs.tolist()], dtype=np.int64)
        count = n_of[cs_slot]
        rc = np.repeat(np.arange(len(cs)), count)
        rp = np.repeat(off_of[cs_slot] - (np.cumsum(count) - count), count) + np.arange(int(count.sum()))
        if max_rows is not None and rows_done + len(rc) > max_rows:
            reason = (f"work budget reached at bounce {depth}: {rows_done} (piece, heading) images evaluated, the next "
                      f"bounce needs {len(rc)} more (max_rows={max_rows}); heuristic search (a grid of {n_headings} "
                      f"headings, beam {beam}; {expanded} (state, heading) pairs expanded, {failures} exact replays "
                      "failed)")
            return SearchOutcome(None, expanded, depth - 1, failures, reason, "max_rows", rows_done)
        imaged = in_chunks(deadline, ps.images, pe_a[rp], pa_a[rp], pb_a[rp], ct[rc], rc)
        if imaged is None:
            return _timed_out(deadline, expanded, depth - 1, failures, rows_done)
        ok, tgt, lo_t, hi_t = imaged
        expanded += len(cs)
        rows_done += len(rc)
        good = np.ones(len(cs), dtype=bool)
        np.logical_and.at(good, rc, ok)
        # the new states, all at once: the images of each good candidate's pieces, merged per edge
        cand = np.flatnonzero(good)
        flat = _merged_images(rc, tgt, lo_t, hi_t, good)
        goal = is_goal(flat)[cand]
        keys = _rank_keys(flat, ps.lengths, rank)
        order = cand[np.lexsort(tuple(k[cand] for k in reversed(keys)))]
        starts = flat.starts

        def state(c: int) -> Pieces:
            s, t = starts[c], starts[c + 1]
            return tuple(zip(flat.edge[s:t].tolist(), flat.lo[s:t].tolist(), flat.hi[s:t].tolist()))

        next_layer: list[int] = []
        per: dict[int, int] = {}
        is_goal_c = np.zeros(len(cs), dtype=bool)
        is_goal_c[cand] = goal
        # goals first, best ranked first: replay exactly
        for c_index in order[is_goal_c[order]].tolist():
            if replays >= max_replays:
                break
            if deadline.expired():
                return _timed_out(deadline, expanded, depth - 1, failures, rows_done)
            theta = float(ct[c_index])
            nodes.append(_Node(state(c_index), int(cs[c_index]), (theta - ps.eps, theta + ps.eps), depth))
            replays += 1
            stages = replay(env, part, start, _path(nodes, len(nodes) - 1), is_goal_exact)
            if stages is not None:
                return SearchOutcome(stages, expanded, depth, failures,
                                     f"found after expanding {expanded} (state, heading) pairs", None, rows_done)
            failures += 1
            nodes.pop()
        first_edge = flat.edge[np.minimum(starts[:-1], max(len(flat.edge) - 1, 0))].tolist() if len(flat.edge) else []
        for c_index in order.tolist():
            if len(next_layer) >= beam:
                break
            key = first_edge[c_index]
            if per.get(key, 0) >= per_edge:
                continue
            pieces = state(c_index)
            parent = int(cs[c_index])
            theta = float(ct[c_index])
            interval = (theta - ps.eps, theta + ps.eps)
            if reached.dominated(pieces):
                continue
            per[key] = per.get(key, 0) + 1
            nodes.append(_Node(pieces, parent, interval, depth))
            reached.add(pieces)
            next_layer.append(len(nodes) - 1)
        logger.info("position search: bounce %d, %d candidates, %d kept", depth, len(cand), len(next_layer))
        layer = next_layer
        if not layer:
            what = ("no candidate heading carried every piece whole onto one edge" if not len(cand) else
                    "every new state contained one reached before")
            reason = (f"the search ran out of states at bounce {depth}: {what} (heuristic search: a grid of "
                      f"{n_headings} headings, beam {beam}; {expanded} (state, heading) pairs expanded, {failures} "
                      "exact replays failed; a stage that splits a piece over several edges sweeps across a vertex, which "
                      "no stage of this search (nor a move of its certificate) does: give a smaller start set)")
            return SearchOutcome(None, expanded, depth, failures, reason, "exhausted", rows_done)
    reason = (f"no strategy found within {max_bounces} bounces (heuristic search: a grid of {n_headings} headings, "
              f"beam {beam}; {expanded} (state, heading) pairs expanded, {failures} exact replays failed)")
    return SearchOutcome(None, expanded, max_bounces, failures, reason, "max_bounces", rows_done)


@dataclass
class Flat:
    """A batch of position sets in flat arrays: piece k is (``edge[k]``, ``lo[k]``, ``hi[k]``) of set
    ``owner[k]``, sorted by set, edge and ``lo``, each set's pieces merged per edge (as :func:`merge_pieces`);
    set c's pieces are ``starts[c]:starts[c + 1]`` (empty for a set that does not exist)."""

    owner: np.ndarray
    edge: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    n: int

    @property
    def starts(self) -> np.ndarray:
        return np.searchsorted(self.owner, np.arange(self.n + 1))

    @classmethod
    def of(cls, states: Sequence[Pieces]) -> "Flat":
        owner = [c for c, s in enumerate(states) for _ in s]
        cols = [p for s in states for p in s]
        return cls(np.array(owner, dtype=np.int64), np.array([p[0] for p in cols], dtype=np.int64),
                   np.array([p[1] for p in cols], dtype=float), np.array([p[2] for p in cols], dtype=float),
                   len(states))

    def hulls(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per (set, edge) occupied: (set, edge, min lo, max hi), sorted by set then edge."""
        if not len(self.owner):
            empty = np.zeros(0)
            return empty.astype(np.int64), empty.astype(np.int64), empty, empty
        first = np.ones(len(self.owner), dtype=bool)
        first[1:] = (self.owner[1:] != self.owner[:-1]) | (self.edge[1:] != self.edge[:-1])
        at = np.flatnonzero(first)
        return self.owner[at], self.edge[at], self.lo[at], np.maximum.reduceat(self.hi, at)

    def edge_counts(self) -> np.ndarray:
        """Per set: how many edges it occupies."""
        owner, _, _, _ = self.hulls()
        return np.bincount(owner, minlength=self.n)


def _merged_images(rc: np.ndarray, tgt: np.ndarray, lo: np.ndarray, hi: np.ndarray, good: np.ndarray) -> Flat:
    """The new states of the good candidates as a :class:`Flat` batch: each candidate's image pieces (rows
    ``rc == c``) merged per edge exactly as :func:`merge_pieces` does (a piece starting at or before the running
    end of its edge joins it)."""
    sel = good[rc]
    c, e, a, b = rc[sel], tgt[sel].astype(np.int64), lo[sel], hi[sel]
    order = np.lexsort((a, e, c))
    c, e, a, b = c[order], e[order], a[order], b[order]
    m = len(c)
    if not m:
        return Flat(c, e, a, b, len(good))
    new_group = np.ones(m, dtype=bool)
    new_group[1:] = (c[1:] != c[:-1]) | (e[1:] != e[:-1])
    group = np.cumsum(new_group)
    # running end of each (candidate, edge) group: a segmented cumulative max (Hillis–Steele doubling, log of the
    # largest group's size steps)
    run_end = b.copy()
    sizes = np.diff(np.append(np.flatnonzero(new_group), m))
    k = 1
    while k < sizes.max():
        same = group[k:] == group[:-k]
        run_end[k:] = np.where(same, np.maximum(run_end[k:], run_end[:-k]), run_end[k:])
        k *= 2
    start = new_group.copy()
    start[1:] |= a[1:] > run_end[:-1]
    at = np.flatnonzero(start)
    return Flat(c[at], e[at], a[at], np.maximum.reduceat(b, at), len(good))


def _rank_keys(flat: Flat, lengths: np.ndarray, rank: str) -> tuple[np.ndarray, ...]:
    """Sort keys per candidate, most significant first: ``"pieces"`` — fewest pieces, then the shortest total
    length; ``"edges"`` — fewest edges occupied, then the shortest sum over edges of the hull of the pieces
    there (arc length)."""
    n = flat.n
    if rank == "pieces":
        count = np.bincount(flat.owner, minlength=n)
        total = np.bincount(flat.owner, weights=(flat.hi - flat.lo) * lengths[flat.edge], minlength=n)
        return count, total
    if rank == "edges":
        owner, edge, lo, hi = flat.hulls()
        return np.bincount(owner, minlength=n), np.bincount(owner, weights=(hi - lo) * lengths[edge], minlength=n)
    raise ValueError(f"unknown rank {rank!r}")


def _timed_out(deadline: Deadline, expanded: int, layers: int, failures: int, rows: int) -> SearchOutcome:
    limit = deadline.limit(f"{expanded} (state, heading) pairs, {layers} bounces searched")
    return SearchOutcome(None, expanded, layers, failures, f"{limit} before a strategy was found: not a proof",
                         "timeout", rows, (limit,))


def _path(nodes: list[_Node], i: int) -> list[tuple[float, float]]:
    out = []
    while nodes[i].parent >= 0:
        interval = nodes[i].interval
        assert interval is not None  # only the root has no interval, and it has no parent
        out.append(interval)
        i = nodes[i].parent
    return out[::-1]


def _contains(big: Pieces, small: Pieces, tol: float = 1e-12) -> bool:
    for e, a, b in small:
        if not any(E == e and A <= a + tol and b <= B + tol for E, A, B in big):
            return False
    return True



class _Reached:
    """The position sets reached so far, indexed for dominance (is a new set a superset of one of them?).

    A new set is dominated when one of its pieces contains a single-piece set reached before (per edge: is
    there a reached [c, d] with a ≤ c and d ≤ b? — a vectorised test over that edge's intervals), or when it
    contains a reached set of several pieces *occupying the same edges* (a bucket per edge set, tested first
    on the per-edge hulls, vectorised, then piece by piece). Sets of several pieces occupying fewer edges are
    not looked up: dominance only prunes, so checking a subset of the reached sets costs search time, never
    soundness, and a lookup by edge set is a dictionary access where a scan over every reached set was the
    search's main cost.
    """

    def __init__(self, n_edges: int, tol: float = 1e-12) -> None:
        self.n_edges = n_edges
        self.tol = tol
        self.single: dict[int, _Grow] = {}
        self.multi: dict[tuple[int, ...], tuple[_Grow, list[Pieces]]] = {}

    def add(self, pieces: Pieces) -> None:
        if len(pieces) == 1:
            e, a, b = pieces[0]
            self.single.setdefault(e, _Grow(2)).append((a, b))
            return
        edges, lo, hi = self._hulls(pieces)
        grow, members = self.multi.setdefault(edges, (_Grow(2 * len(edges)), []))
        grow.append(tuple(lo) + tuple(hi))
        members.append(pieces)

    @staticmethod
    def _hulls(pieces: Pieces) -> tuple[tuple[int, ...], list[float], list[float]]:
        edges: list[int] = []
        lo: list[float] = []
        hi: list[float] = []
        for e, a, b in pieces:  # pieces are sorted by edge (merge_pieces)
            if edges and edges[-1] == e:
                hi[-1] = max(hi[-1], b)
            else:
                edges.append(e)
                lo.append(a)
                hi.append(b)
        return tuple(edges), lo, hi

    def dominated(self, pieces: Pieces) -> bool:
        """Does ``pieces`` contain a position set already reached?"""
        tol = self.tol
        for e, a, b in pieces:
            grow = self.single.get(e)
            if grow is not None:
                rows = grow.view()
                if np.any((a <= rows[:, 0] + tol) & (rows[:, 1] <= b + tol)):
                    return True
        if len(pieces) == 1:
            return False
        edges, lo, hi = self._hulls(pieces)
        bucket = self.multi.get(edges)
        if bucket is None:
            return False
        grow, members = bucket
        rows = grow.view()
        k = len(edges)
        fits = np.all(rows[:, :k] >= np.asarray(lo) - tol, axis=1) & np.all(rows[:, k:] <= np.asarray(hi) + tol, axis=1)
        return any(_contains(pieces, members[i], tol) for i in np.flatnonzero(fits).tolist())


class _Grow:
    """A float matrix with a fixed number of columns that grows by appending rows (amortised doubling)."""

    def __init__(self, columns: int) -> None:
        self.data = np.empty((8, columns))
        self.size = 0

    def append(self, row: Sequence[float]) -> None:
        if self.size == len(self.data):
            self.data = np.concatenate([self.data, np.empty_like(self.data)])
        self.data[self.size] = row
        self.size += 1

    def view(self) -> np.ndarray:
        return self.data[:self.size]


def replay(env: Environment, part: Partition, start: Sequence[BoundaryPiece], path: Sequence[tuple[float, float]],
           is_goal_exact: Callable[[tuple[BoundaryPiece, ...]], bool]) -> tuple[Stage, ...] | None:
    """The exact strategy of the heading intervals ``path`` from ``start``, or None when a stage splits a piece
    (or leaves its swept region unclean) or the exact final set misses the goal."""
    current = merge_exact(start)
    stages = []
    for lo, hi in path:
        interval = Interval(lo, hi)
        images, cones, targets = [], [], []
        for piece in current:
            edge = env.edge(piece.edge)
            vec = (edge.b[0] - edge.a[0], edge.b[1] - edge.a[1])
            cone = heading_cone(vec, interval, outside=True)
            try:
                image = transition_set(env, piece, cone)
            except InputError:
                return None
            if len(image) != 1 or image[0].edge == piece.edge:
                return None
            images.append(image[0])
            cones.append(cone)
            targets.append(image[0].edge)
        positions = merge_exact(images)
        stages.append(Stage(
            from_segments=_segments(part, current), to_segments=_segments(part, positions), interval=interval,
            positions=positions, sources=current, cones=tuple(cones), target_edges=tuple(targets)))
        current = positions
    if not is_goal_exact(current):
        return None
    return tuple(stages)


def _segments(part: Partition, pieces: Sequence[BoundaryPiece]) -> tuple[int, ...]:
    out = set()
    for p in pieces:
        for s in part.edge_segments[p.edge]:
            seg = part.segments[s]
            if min(seg.t1, p.t1) > max(seg.t0, p.t0) or (p.t0 == p.t1 and seg.t0 <= p.t0 <= seg.t1):
                out.add(s)
    return tuple(sorted(out))


def to_user_stages(walls: PartitionedWalls, stages: Sequence[Stage]) -> tuple[Stage, ...]:
    """Stages found on the straight walls (:attr:`PartitionedWalls.merged <solverplan.plan._walls.PartitionedWalls.merged>`) in the
    user's edges and segments (exact).

    Every piece (a source or a position) on a merged edge splits at the collinear vertices into pieces of
    consecutive user edges; each source piece keeps the cone of the merged piece it is part of (its points move
    as they did: the user edges of one wall have its direction, so the headings are the same), and its target
    edge is the user edge where its exact image starts (the image may run on over the collinear neighbours of
    that edge: the straight wall it lands on). The segment ids are the user's partition P′
    (:attr:`PartitionedWalls.user_partition <solverplan.plan._walls.PartitionedWalls.user_partition>`).
    """
    if walls.identity:
        return tuple(stages)
    part = walls.user_partition
    out = []
    for stage in stages:
        rows = []
        for piece, cone in zip(stage.sources, stage.cones):
            for sub in walls.to_user((piece,)):
                m, s0, s1 = walls.edge_map[sub.edge]
                on_merged = BoundaryPiece(m, s0 + sub.t0 * (s1 - s0), s0 + sub.t1 * (s1 - s0))
                image = transition_set(walls.merged, on_merged, cone)
                rows.append((sub, cone, walls.user_edge_at(image[0].edge, image[0].t0)))
        rows.sort(key=lambda row: (row[0].edge, row[0].t0))
        sources = tuple(row[0] for row in rows)
        positions = merge_exact(walls.to_user(stage.positions))
        out.append(Stage(from_segments=_segments(part, sources), to_segments=_segments(part, positions),
                         interval=stage.interval, positions=positions, sources=sources,
                         cones=tuple(row[1] for row in rows), target_edges=tuple(row[2] for row in rows)))
    return tuple(out)


def search_widening(env: Environment, part: Partition, start: Sequence[BoundaryPiece], is_goal, is_goal_exact, *,
                    passes: Sequence[tuple[int, int]], max_rows: int | None, **options) -> tuple[SearchOutcome, int, int]:
    """:func:`search_positions` with a widening beam: one pass per ``(beam, n_headings)`` of ``passes``,
    cheapest first, all sharing one work budget ``max_rows``; the first pass that finds a strategy answers
    (it is replayed exactly like any other). Narrow passes are cheap and often enough; the wide ones only run
    when they fail. Each pass keeps at most max(2, beam / 10) states per edge (diversity matters more than
    depth in a narrow beam). Returns ``(outcome, beam, n_headings)`` of the pass that answered (the last one run when
    none found anything: its ``cut`` and ``reason`` say what ended it)."""
    used = 0
    outcome = None
    beam = n_headings = 0
    for beam, n_headings in passes:
        left = None if max_rows is None else max_rows - used
        outcome = search_positions(env, part, start, is_goal, is_goal_exact, beam=beam, n_headings=n_headings,
                                   per_edge=max(2, beam // 10), max_rows=left, **options)
        used += outcome.rows
        if outcome.stages is not None or outcome.cut in ("max_rows", "timeout"):
            break
    assert outcome is not None, "at least one pass"
    return outcome, beam, n_headings
