"""A planning query over the safe BVG as a graph of belief states (private: used by :mod:`.search`).

Belief states
-------------
A *belief* is the set of places the robot may be on (a sorted tuple of elements: segment ids of P′ and *landing
units*, tagged when the robot arrived near one of their corners, see :meth:`Problem.segment`). The start belief is
the start set **as given**: every segment of P′ it covers whole, and for every part of a segment it covers in part
the landing unit of that part, whose admissible intervals are computed for the piece itself (the exact safe sets
of :func:`~solverplan.bounce.safe.safe_set`, cut by the same margins): a plan must work from every point of the
start set, and need not work from the rest of a segment it touches. Positions exactly on a partition point are
limits of both neighbouring segments and have measure zero; like the paper we do not treat them separately (the
certificate checker covers them by closure).

Landing units
-------------
The ends of the start and goal sets that fall strictly inside segments of P′ cut those segments into pieces. Each
piece is a *landing unit* (:attr:`Problem.units`, :attr:`Problem.units_of`); the segments stay units too, and the
parts of segments the start set covers are units of the start belief (a part may span several pieces). A stage may
land on a segment (every landing point on it, the paper's abstraction) or on a unit (every landing point inside the
unit's piece: Prop. 2's cone with the piece's ends, cut into the arc's admissible interval, exactly as a goal piece
is, :meth:`Problem._landings`), and a later stage leaves from the unit with the unit's own exact safe sets. Both
are open to every search, so the class of plans is exact for the query's cuts: a plan that needs the part of a
segment beyond a set's end is found (it lands on the piece and leaves from it), and one whose landing straddles the
end still lands on the whole segment. (Runs of several pieces are not landing units: at one heading a landing would
then have as many choices as runs that hold it, and a belief of k sources their product; the certificates' class is
the same, :mod:`solverplan.certify.negative`.) A segment's rows then overlap (a landing on a unit lies inside the
landing on its segment): :meth:`Problem.options` keeps of the choices they give only those no other choice dominates
(a landing on the piece at the same interval beats one on the whole segment: the robot is known to be in a smaller
set, from which every plan from the larger one works — the proof is in :meth:`Problem._combine`), so that a belief of
many sources does not have 2^k options at one heading. A unit that holds a corner of its
segment keeps the corner tag of an arc into it (the ping-pong rule of :mod:`solverplan.plan.margins`); the
clearance κ applies at the set ends a unit lands between, as at a goal piece.

A *stage* from belief B executes one heading interval I (radians, measured from the wall the robot
is on) that is admissible from **every** segment of B: for each source i ∈ B there is a target j_i
with I inside one admissible interval of the arc i → j_i. The next belief is {j_i : i ∈ B}. For a
fixed source the admissible intervals of all its targets are pairwise disjoint (two targets cannot
both receive the whole open segment at one heading), so for a heading θ the target of every source
is determined; the intervals that work from all of B are therefore the cells of the arrangement of
the sources' interval lists, and :meth:`Problem.options` lists each cell once by merging the sorted
lists source by source (the intersection of two sorted lists of disjoint intervals is again one). A
cell's interval (the intersection of one interval per source) is the widest interval for that
choice of targets; any sub-interval has the same targets. |B′| ≤ |B|: beliefs never grow. (Landings on units
overlap the landings on their segments: there a heading has several targets per source, one of them the segment,
and each undominated choice is an option of its own.)

Admissible intervals
--------------------
The safe set of an arc (exact, :mod:`solverplan.bounce.safe`) is a union of closed intervals whose
ends may be the open ends 0 or π (paper Cor. 1). Plans use only the *admissible* part of each safe
interval: the part kept by the one margin policy of every planner (:mod:`solverplan.plan.margins`:
δ = ``heading_margin`` from the walls, μ = ``safe_margin`` inside the exact safe set, and the corner
clearance κ: no landing point within κ of a segment end other than the corner shared with the source).
All optimality claims are over plans whose intervals lie in admissible intervals. Safe singletons (the
parallel case of Prop. 2) have no admissible part: an exact heading is not an interval a robot can execute.

Goal
----
A belief is at the goal when the robot is sure to be in the goal set G. Segments lying wholly in G
(pieces of G are merged per edge first) are *goal segments*: landing anywhere on them is enough. A
segment G covers only in part is usable by the **last** stage only: from source i = (a, b) onto the
piece [g₀, g₁] of target j, the landing point of every robot position is inside the piece iff both
corner landings are (the landing point is affine in the position for a fixed heading), i.e. iff
θ ∈ [ang(g₀ − b), ang(g₁ − a)] (Prop. 2's cone with the piece's ends; ang measured from b − a; an
end of the piece at the shared corner imposes nothing). The admissible interval of i → j is cut to
that cone (shrunk by μ) — the *goal intervals* of i. Intermediate stages land on whole segments or on landing units
(the next stage must work from every point of them).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Callable, Iterable, NamedTuple, Sequence

import numpy as np

from solverplan.errors import InputError
from solverplan.bounce.bvg import SafeBVG
from solverplan.environment import BoundaryPiece, BoundarySet
from solverplan.plan._walls import PartitionedWalls
from solverplan.interval import Interval
from solverplan.result import Stage
from solverplan.plan.margins import (DEFAULT_HEADING_MARGIN, DEFAULT_SAFE_MARGIN, Margins, admissible_intervals,
                                     corner_arcs, cut_to_margins)

__all__ = ["Option", "Problem", "StartPiece", "DEFAULT_HEADING_MARGIN", "DEFAULT_SAFE_MARGIN", "merged_pieces"]

Belief = tuple[int, ...]
Cell = tuple[float, float, tuple[int, ...], Belief]
"""A choice of :meth:`Problem._combine` so far: its interval, the target of each source folded, their ``join``."""


PIECE_CODES = 4
"""Belief elements ≥ ``PIECE_CODES`` × n_segments are landing units (below: segment ids with corner tags s + n·k, k < 4)."""

UNIT_TAGS = 4
"""A unit's element is ``PIECE_CODES`` × n_segments + ``UNIT_TAGS`` × unit + its corner tags (as a segment's)."""


class StartPiece(NamedTuple):
    """A landing unit: a part of segment ``host`` between ends of the start or goal set (not the whole segment; the
    start set's parts of segments are units): ``piece`` on the search's edge, from exact point ``a`` to ``b`` (the
    free space on the left, as on every segment)."""

    host: int
    piece: BoundaryPiece
    a: tuple
    b: tuple


class Option(NamedTuple):
    """One way to leave a belief: the widest interval [lo, hi] for one choice of targets, the next
    belief and the (source, target) pair of every source."""

    lo: float
    hi: float
    next: Belief
    moves: tuple[tuple[int, int], ...]

    @property
    def width(self) -> float:
        return self.hi - self.lo


def merged_pieces(bset: BoundarySet) -> dict[int, list[tuple[Fraction, Fraction]]]:
    """The pieces of a boundary set merged per edge (overlapping or touching pieces joined), exact."""
    return bset.by_edge()


def _angle(e: tuple[float, float], w: tuple[float, float]) -> float:
    """CCW angle of w from e, in (−π, π]."""
    return math.atan2(e[0] * w[1] - e[1] * w[0], e[0] * w[0] + e[1] * w[1])


class Problem:
    """The belief-state graph of one query (start set, goal set) over a safe BVG."""

    def __init__(
        self,
        graph: SafeBVG,
        start: BoundarySet,
        goal: BoundarySet | None,
        *,
        margins: Margins | None = None,
        walls: PartitionedWalls | None = None,
        landing_units: bool = True,
    ) -> None:
        """``goal=None``: a problem without a goal (reachability sweeps: no goal options).

        ``landing_units``: stages may land on the pieces of segments between the query's set ends and leave from
        them later (module docstring, *Landing units*); False: units are only the start set's pieces, and every
        stage lands on whole segments (the patrols' entries, which end on a visited edge's whole segments).

        ``walls``: the straight walls of the user's environment when ``graph`` was built on its merged
        environment (:mod:`solverplan.plan._walls`); ``start`` and ``goal`` are then in the user's numbering
        and are mapped here. :attr:`runs` maps every segment of the search back to the user's segments."""
        self.graph = graph
        self.partition = graph.partition
        self.walls = walls
        self.user_env = walls.env if walls is not None else self.partition.env
        self.user_start_set, self.user_goal_set = start, goal
        if walls is not None:
            if walls.merged != self.partition.env:
                raise ValueError("the graph is not built on the merged environment of the walls given")
            start = walls.to_merged(start)
            goal = walls.to_merged(goal) if goal is not None else None
        self.env = self.partition.env
        self.start_set = start
        self.goal_set = goal
        self.margins = margins if margins is not None else Margins.for_environment(self.env)
        self.heading_margin = self.margins.heading_margin
        self.safe_margin = self.margins.safe_margin
        self.landing_units = landing_units
        self._build_intervals()
        self._goal_pieces = merged_pieces(goal) if goal is not None else {}
        whole, partial = set(), {}
        for edge, pieces in self._goal_pieces.items():
            for k in self.partition.edge_segments[edge]:
                s = self.partition.segments[k]
                if any(p <= s.t0 and s.t1 <= q for p, q in pieces):
                    whole.add(k)
                    continue
                parts = [(max(p, s.t0), min(q, s.t1)) for p, q in pieces if s.t0 < q and p < s.t1]
                if parts:
                    partial[k] = parts
        self.goal_whole = frozenset(whole)
        self.goal_partial = partial
        self._make_units(start, goal, landings=landing_units)
        self.start_belief: Belief = self._start_belief(start)
        if landing_units:
            self._add_unit_landings()
        start_pieces = merged_pieces(start)
        self.start_in_goal = all(
            any(p <= lo and hi <= q for p, q in self._goal_pieces.get(edge, ()))
            for edge, items in start_pieces.items() for lo, hi in items
        )
        self._unit_bounds: dict[int, tuple[float, float]] = {}
        self._options: dict[Belief, list[Option]] = {}
        self._goal_options: dict[Belief, list[Option]] = {}
        self._goal_lists: dict[int, tuple[list[float], list[float], list[int]]] = {}

    # ------------------------------------------------------------------ admissible intervals
    def _build_intervals(self) -> None:
        n = self.n_segments = self.graph.n_segments
        adm = admissible_intervals(self.graph, self.margins)
        src, tgt, lo, hi = adm.source, adm.target, adm.lo, adm.hi
        order = np.lexsort((hi, tgt, lo, src))
        src, tgt, lo, hi = src[order], tgt[order], lo[order], hi[order]
        # a row listed twice (an arc the graph holds twice) is one interval: kept twice it would make a source's
        # list overlap itself, and the options of a belief double with every such source (_combine)
        if len(lo) > 1:
            again = np.concatenate([[False], (src[1:] == src[:-1]) & (tgt[1:] == tgt[:-1]) & (lo[1:] == lo[:-1])
                                    & (hi[1:] == hi[:-1])])
            if again.any():
                keep = np.flatnonzero(~again)
                src, tgt, lo, hi = src[keep], tgt[keep], lo[keep], hi[keep]
        off = np.searchsorted(src, np.arange(n + 1))
        dive, arrival = corner_arcs(self.partition, src, tgt)
        self._off = off.tolist()
        self._lo = lo.tolist()
        self._hi = hi.tolist()
        self._tgt = tgt.tolist()
        self._dive = dive.tolist()
        self._tgt_code = (tgt + n * arrival).tolist()
        self._restricted: dict[int, tuple[list[float], list[float], list[int]]] = {}
        self.n_admissible = int(len(lo))

    # ------------------------------------------------------------------ landing units
    def _make_units(self, start: BoundarySet, goal: BoundarySet | None, *, landings: bool) -> None:
        """The landing units (module docstring): for every segment that an end of the start or goal set cuts (strictly
        inside it), each piece between consecutive cuts — the units a stage may land on (:attr:`units_of`) — and the
        parts of segments the start set covers (start elements; a part may span several pieces). Without
        ``landings`` only the start set's parts."""
        part = self.partition
        cuts: dict[int, set] = {}
        for bset in (start,) if goal is None or not landings else (start, goal):
            for edge, items in merged_pieces(bset).items():
                for k in part.edge_segments[edge]:
                    seg = part.segments[k]
                    for p, q in items:
                        cuts.setdefault(k, set()).update(t for t in (p, q) if seg.t0 < t < seg.t1)
        units: list[StartPiece] = []
        index: dict[tuple[int, object, object], int] = {}
        by_host: dict[int, list[int]] = {}

        def add(k: int, lo, hi) -> int | None:
            seg = part.segments[k]
            if lo == seg.t0 and hi == seg.t1:
                return None
            if (k, lo, hi) not in index:
                index[(k, lo, hi)] = len(units)
                units.append(StartPiece(k, BoundaryPiece(seg.edge, lo, hi), _point_on(seg, lo), _point_on(seg, hi)))
            return index[(k, lo, hi)]

        if landings:
            for k in sorted(cuts):
                if not cuts[k]:
                    continue
                seg = part.segments[k]
                ends = [seg.t0, *sorted(cuts[k]), seg.t1]
                for lo, hi in zip(ends, ends[1:]):
                    u = add(k, lo, hi)
                    if u is not None:
                        by_host.setdefault(k, []).append(u)
        for edge, items in merged_pieces(start).items():
            for k in part.edge_segments[edge]:
                seg = part.segments[k]
                for p, q in items:
                    lo, hi = max(p, seg.t0), min(q, seg.t1)
                    if lo < hi:
                        add(k, lo, hi)
        self.units: tuple[StartPiece, ...] = tuple(units)
        self._unit_index = index
        self.units_of: dict[int, tuple[int, ...]] = {k: tuple(v) for k, v in by_host.items()}
        """The units each cut segment's landings may end on: its pieces between consecutive cuts."""
        self._unit_rows: dict[int, tuple[list[float], list[float], list[int], list[int]]] = {}
        self._unit_restricted: dict[int, tuple[list[float], list[float], list[int]]] = {}
        self._piece_safe: dict[tuple[int, int], list[tuple[float, float]]] = {}

    def _start_belief(self, start: BoundarySet) -> Belief:
        """The start belief: the segments the start set covers whole, and the unit of every part of a segment it
        covers in part (its ends are cuts, module docstring)."""
        part = self.partition
        elements: set[int] = set()
        for edge, items in merged_pieces(start).items():
            for k in part.edge_segments[edge]:
                seg = part.segments[k]
                for p, q in items:
                    lo, hi = max(p, seg.t0), min(q, seg.t1)
                    if lo >= hi:
                        continue
                    if lo == seg.t0 and hi == seg.t1:
                        elements.add(k)
                    else:
                        elements.add(self.unit_code(self._unit_index[(k, lo, hi)]))
        return tuple(sorted(elements))

    @property
    def start_pieces(self) -> tuple[StartPiece, ...]:
        """The units of the start belief (the parts of segments the start set covers in part)."""
        return tuple(self.piece(c) for c in self.start_belief if self.is_piece(c))

    def unit_code(self, unit: int, tags: int = 0) -> int:
        """The belief element of landing unit ``unit`` (an index of :attr:`units`) with corner tags ``tags``."""
        return PIECE_CODES * self.n_segments + UNIT_TAGS * unit + tags

    def _unit_lists(self, unit: int) -> tuple[list[float], list[float], list[int], list[int]]:
        """The admissible intervals of a unit (sorted by their low ends; those landing on units may overlap the
        others): lows, highs, target elements and the corner each arc dives into (as :func:`corner_arcs`)."""
        cached = self._unit_rows.get(unit)
        if cached is None:
            piece = self.units[unit]
            los, his, tgts, dives = self._piece_intervals(self.unit_code(unit), piece)
            rows = list(zip(los, his, tgts, dives))
            if self.landing_units:
                rows += self._landings(piece.a, piece.b, self.partition.segments[piece.host], rows)
            a, b = self._off[piece.host], self._off[piece.host + 1]
            rows = _holding(rows, zip(self._lo[a:b], self._hi[a:b], self._tgt_code[a:b], self._dive[a:b]))
            los, his, tgts, dives = ([r[0] for r in rows], [r[1] for r in rows], [r[2] for r in rows],
                                     [r[3] for r in rows])
            cached = self._unit_rows[unit] = (los, his, tgts, dives)
        return cached

    def _piece_intervals(self, code: int, piece: StartPiece) -> tuple[list[float], list[float], list[int], list[int]]:
        """The admissible intervals of a unit onto whole segments: the exact safe sets from the piece to every
        segment its host segment sees (a part sees no more than the whole), cut by the margins as every arc is."""
        from solverplan.bounce.safe import safe_set

        part, n = self.partition, self.n_segments
        a, b = piece.a, piece.b
        host = part.segments[piece.host]
        rows: list[tuple[float, float, int, int]] = []  # (lo, hi, target, shared) shared: 1 c = b, 2 d = a
        for j in self.graph.successors(piece.host).tolist():
            t = part.segments[j]
            # the corners the target shares with the piece's segment: exempt from the clearance as they are for the
            # segment (the piece's landings are some of the segment's), so a piece never does worse than its segment
            corner = 1 if t.a == host.b else 2 if t.b == host.a else 0
            found = [(iv.lo, iv.hi) for iv in safe_set(self.env, (a, b), (t.a, t.b)).intervals]
            if found:
                self._piece_safe[(code, j)] = found
            rows.extend((lo, hi, j, corner) for lo, hi in found)
        if not rows:
            return [], [], [], []
        lo = np.array([r[0] for r in rows])
        hi = np.array([r[1] for r in rows])
        tgt = np.array([r[2] for r in rows], dtype=np.int64)
        shared = np.array([r[3] for r in rows])

        def vectors(pairs) -> np.ndarray:
            return np.array([(float(q[0] - p[0]), float(q[1] - p[1])) for p, q in pairs]).reshape(-1, 2)

        targets = [part.segments[j] for j in tgt.tolist()]
        lo, hi = cut_to_margins(lo, hi, self.margins, edge=vectors([(a, b)] * len(rows)),
                                target=vectors([(t.a, t.b) for t in targets]), cb=vectors([(b, t.a) for t in targets]),
                                da=vectors([(a, t.b) for t in targets]), shared_c=shared == 1, shared_d=shared == 2)
        # arcs into a corner the piece shares with the target arrive near it (the corner tags of corner_arcs)
        arrival = np.where(shared == 1, 1, np.where(shared == 2, 2, 0))
        dive = np.where(shared == 1, 2, np.where(shared == 2, 1, 0))
        keep = np.flatnonzero(hi > lo)
        keep = keep[np.argsort(lo[keep], kind="stable")]
        return lo[keep].tolist(), hi[keep].tolist(), (tgt[keep] + n * arrival[keep]).tolist(), dive[keep].tolist()

    def _landings(self, a, b, host, rows) -> list[tuple[float, float, int, int]]:
        """The rows landing on units: for every row (lo, hi, target element, dive) of a source (a, b) on segment
        ``host`` whose target segment has units, each unit's part of it — the headings whose every landing point
        lies in the unit: Prop. 2's cone with the unit's ends, pulled in by the clearance as a goal piece is
        (:meth:`goal_intervals`), shrunk by μ. The unit keeps the row's corner tag if it holds that corner."""
        n, part = self.n_segments, self.partition
        e = (float(b[0] - a[0]), float(b[1] - a[1]))
        out = []
        for lo, hi, code, dive in rows:
            j, arrival = code % n, code // n
            for u in self.units_of.get(j, ()):
                unit, tseg = self.units[u], part.segments[j]
                g0, g1 = _pulled_in(tseg, unit.piece.t0, unit.piece.t1, self.margins.corner_clearance, host)
                if g0 is None:
                    continue
                cone_lo = 0.0 if g0 == host.b else _angle(e, (float(g0[0] - b[0]), float(g0[1] - b[1]))) + self.safe_margin
                cone_hi = math.pi if g1 == host.a else _angle(e, (float(g1[0] - a[0]), float(g1[1] - a[1]))) - self.safe_margin
                l2, h2 = max(lo, cone_lo), min(hi, cone_hi)
                if h2 > l2:
                    holds = (1 if unit.piece.t0 == tseg.t0 else 0) | (2 if unit.piece.t1 == tseg.t1 else 0)
                    out.append((l2, h2, self.unit_code(u, arrival & holds), dive))
        return out

    def _add_unit_landings(self) -> None:
        """Add to every segment's admissible intervals its landings on units (:meth:`_landings`), keeping each
        segment's rows sorted by their low ends; ``_tgt`` of such a row is the unit's place (:meth:`place`)."""
        if not self.units:
            return
        n = self.n_segments
        hosts = set(self.units_of)
        extra: list[tuple[int, float, float, int, int, int]] = []  # (source, lo, hi, place, code, dive)
        segs = self.partition.segments
        into = np.flatnonzero(np.isin(np.asarray(self._tgt, dtype=np.int64), sorted(hosts)))  # rows into cut segments
        sources = np.searchsorted(np.asarray(self._off), into, side="right") - 1
        by_source: dict[int, list[int]] = {}
        for r, s in zip(into.tolist(), sources.tolist()):
            by_source.setdefault(s, []).append(r)
        for s, found in by_source.items():
            rows = [(self._lo[r], self._hi[r], self._tgt_code[r], self._dive[r]) for r in found]
            for lo, hi, code, dive in self._landings(segs[s].a, segs[s].b, segs[s], rows):
                extra.append((s, lo, hi, self.place(code), code, dive))
        if not extra:
            return
        src = np.repeat(np.arange(n), np.diff(np.asarray(self._off)))
        src = np.concatenate([src, np.array([r[0] for r in extra], dtype=np.int64)])
        los = np.concatenate([np.asarray(self._lo, dtype=float), np.array([r[1] for r in extra])])
        his = np.concatenate([np.asarray(self._hi, dtype=float), np.array([r[2] for r in extra])])
        places = np.concatenate([np.asarray(self._tgt, dtype=np.int64), np.array([r[3] for r in extra], dtype=np.int64)])
        codes = np.concatenate([np.asarray(self._tgt_code, dtype=np.int64), np.array([r[4] for r in extra], dtype=np.int64)])
        dives = np.concatenate([np.asarray(self._dive, dtype=np.int64), np.array([r[5] for r in extra], dtype=np.int64)])
        order = np.lexsort((los, src))
        self._off = np.searchsorted(src[order], np.arange(n + 1)).tolist()
        self._lo, self._hi = los[order].tolist(), his[order].tolist()
        self._tgt, self._tgt_code, self._dive = places[order].tolist(), codes[order].tolist(), dives[order].tolist()
        self.n_admissible += len(extra)

    def is_piece(self, code: int) -> bool:
        """Is this belief element a landing unit (a piece of a segment, module docstring) rather than a segment?"""
        return code >= PIECE_CODES * self.n_segments

    def piece(self, code: int) -> StartPiece:
        """The landing unit of a belief element (:meth:`is_piece`)."""
        return self.units[(code - PIECE_CODES * self.n_segments) // UNIT_TAGS]

    # ------------------------------------------------------------------ belief elements
    def segment(self, code: int) -> int:
        """The segment of a belief element. Elements are segment ids, plus ``n_segments`` × k where the bits of k
        say the robot may have arrived by an arc into the segment's start (1) or end (2) corner: positions near
        that corner, from which a second arc into the same corner is not admissible (the corner ping-pong of
        :mod:`solverplan.plan.margins`); or units (:meth:`unit_code`, tagged alike). A unit's segment is the
        segment it is part of."""
        if self.is_piece(code):
            return self.piece(code).host
        return code % self.n_segments

    def segments(self, belief: Belief) -> tuple[int, ...]:
        """The segments of a belief (sorted, distinct; a unit counts as its segment)."""
        return tuple(sorted({self.segment(c) for c in belief}))

    def place(self, code: int) -> int:
        """A belief element without its corner tags: a segment id, or ``n_segments + k`` for unit k (the index
        of :attr:`user_pieces` and :attr:`runs`)."""
        if self.is_piece(code):
            return self.n_segments + (code - PIECE_CODES * self.n_segments) // UNIT_TAGS
        return code % self.n_segments

    def moves(self, moves: tuple[tuple[int, int], ...]) -> tuple[tuple[int, int], ...]:
        """An option's (source, target) moves as places (:meth:`place`: segment ids, start pieces after them), distinct."""
        return tuple(dict.fromkeys((self.place(i), self.place(j)) for i, j in moves))

    # ------------------------------------------------------------------ the user's numbering
    @property
    def runs(self) -> tuple[tuple[int, ...], ...]:
        """For every segment of the search, the segments of the user's P′ it is made of (boundary order): one
        each, unless collinear vertices were merged (:mod:`solverplan.plan._walls`)."""
        cached = getattr(self, "_runs", None)
        if cached is None:
            cached = self._runs = tuple(tuple(u for u, _ in pieces) for pieces in self.user_pieces)
        return cached

    @property
    def user_pieces(self):
        """For every place of the search (:meth:`place`: segments, then start pieces), the user segments it overlaps
        with the exact overlap of each (a piece of the user's edge): :meth:`PartitionedWalls.user_pieces`, or each segment itself
        when no walls were given."""
        cached = getattr(self, "_user_pieces", None)
        if cached is None:
            if self.walls is not None:
                cached = self.walls.user_pieces(self.partition) + tuple(self.walls.pieces_of(p.piece)
                                                                         for p in self.units)
            else:
                cached = (tuple(((k, BoundaryPiece(s.edge, s.t0, s.t1)),) for k, s in enumerate(self.partition.segments))
                          + tuple(((p.host, p.piece),) for p in self.units))
            self._user_pieces = cached
        return cached

    @property
    def user_partition(self):
        """The partition P′ of the user's environment (the one answers name segments of)."""
        return self.walls.user_partition if self.walls is not None else self.partition

    def user_segments(self, segments) -> tuple[int, ...]:
        """The user's segments making up some segments of the search (sorted, distinct)."""
        runs = self.runs
        return tuple(sorted({u for s in segments for u in runs[self.place(s)]}))

    def user_stage(self, belief: Belief, option: Option, interval: Interval, *, last: bool = False) -> Stage:
        """A stage of a path (``option`` taken from ``belief`` with heading ``interval``) in the user's numbering:
        the user segments the robot may be on and lands on, every move (a move onto a run of collinear segments
        lists each segment of the run). Where the stage leaves from part of a user segment only (a start piece),
        ``sources`` gives each move's exact source piece (a user segment may then appear in several moves).
        ``last``: the goal stage, whose moves land inside the goal set — where it lands on a run that the goal
        covers in part, not on the run's other segments (its interval was cut for it)."""
        runs, user = self.runs, self.user_partition.segments
        goal = self.user_goal_set.by_edge() if last and self.user_goal_set is not None else {}

        def lands(v: int) -> bool:
            seg = user[v]
            return not last or any(seg.t0 < q and p < seg.t1 for p, q in goal.get(seg.edge, ()))

        items = {(u, v, piece): None for i, j in self.moves(option.moves)
                 for u, piece in self.user_pieces[i] for v in runs[j] if lands(v)}
        if {u for u, _, _ in items} != set(self.user_segments(belief)):  # pragma: no cover - every source lands
            raise AssertionError("a stage has a source that lands nowhere (outside the goal set in a last stage)")
        moves = tuple(dict.fromkeys((u, v) for u, v, _ in items))
        sources: tuple[BoundaryPiece, ...] = ()
        if not all(piece.t0 == user[u].t0 and piece.t1 == user[u].t1 for u, _, piece in items):
            moves = tuple((u, v) for u, v, _ in items)
            sources = tuple(piece for _, _, piece in items)
        return Stage(self.user_segments(belief), tuple(sorted({v for _, v in moves})), interval, moves=moves,
                     sources=sources, margins=self.margins_left(option, interval))

    def margins_left(self, option: Option, interval: Interval) -> tuple[float, float] | None:
        """How far (radians) the ends of ``interval`` lie inside the exact safe sets of ``option``'s moves, the
        smallest over the moves: (lo − safe lo, safe hi − hi). ``None`` if a move's safe set does not hold the
        interval (never for the planners' own options)."""
        lo_left = hi_left = math.inf
        for i, j in option.moves:
            found = None
            for l, h in self._exact_safe(i, self.segment(j)):
                if l <= interval.lo and interval.hi <= h:
                    found = (interval.lo - l, h - interval.hi)
            if found is None:
                return None
            lo_left, hi_left = min(lo_left, found[0]), min(hi_left, found[1])
        return (lo_left, hi_left) if option.moves else None

    def _exact_safe(self, source: int, target: int) -> list[tuple[float, float]]:
        """The exact safe set (float ends, radians) of a belief element ``source`` towards segment ``target``."""
        if self.is_piece(source):
            self._unit_lists(self.place(source) - self.n_segments)
            return self._piece_safe.get((self.unit_code(self.place(source) - self.n_segments), target), [])
        g = self.graph
        k = g.arc_index(source % self.n_segments, target)
        if k is None:
            return []
        rows = range(int(g.set_offsets[k]), int(g.set_offsets[k + 1]))
        return [(float(g.set_lo[r]), float(g.set_hi[r])) for r in rows]

    def segment_text(self, segment: int) -> str:
        """A segment of the search named in the user's numbering: ``segment 3 (on e2)``, or a run of them."""
        part = self.user_partition
        users = self.runs[self.place(segment)]
        edges = sorted({part.segments[u].edge for u in users})
        ids = ", ".join(map(str, users))
        on = ", ".join(f"e{e}" for e in edges)
        return f"segment {ids} (on {on})" if len(users) == 1 else f"segments {ids} (one wall: {on})"

    def intervals(self, source: int) -> tuple[list[float], list[float], list[int]]:
        """The admissible intervals of belief element ``source`` (sorted, disjoint): lows, highs, target
        elements. An element that arrived near a corner has no interval of an arc into that corner."""
        if self.is_piece(source):
            rel = source - PIECE_CODES * self.n_segments
            u, k = rel // UNIT_TAGS, rel % UNIT_TAGS
            los, his, tgts, dives = self._unit_lists(u)
            if k == 0:
                return los, his, tgts
            cached = self._unit_restricted.get(source)
            if cached is None:
                rows = [r for r in range(len(los)) if not dives[r] & k]
                cached = ([los[r] for r in rows], [his[r] for r in rows], [tgts[r] for r in rows])
                self._unit_restricted[source] = cached
            return cached
        s, k = source % self.n_segments, source // self.n_segments
        a, b = self._off[s], self._off[s + 1]
        if k == 0:
            return self._lo[a:b], self._hi[a:b], self._tgt_code[a:b]
        cached = self._restricted.get(source)
        if cached is None:
            rows = [r for r in range(a, b) if not self._dive[r] & k]
            cached = ([self._lo[r] for r in rows], [self._hi[r] for r in rows], [self._tgt_code[r] for r in rows])
            self._restricted[source] = cached
        return cached

    def goal_intervals(self, source: int) -> tuple[list[float], list[float], list[int]]:
        """The intervals of ``source`` whose every landing point lies in the goal set (sorted, disjoint)."""
        cached = self._goal_lists.get(source)
        if cached is not None:
            return cached
        los, his, tgts = self.intervals(source)
        items = []
        seg = self.piece(source) if self.is_piece(source) else self.partition.segments[source % self.n_segments]
        # a start piece is exempt from the clearance at the corners of its segment, as the segment is (the landings
        # from the piece are some of the segment's: never nearer the corner), so that it never does worse
        host = self.partition.segments[self.segment(source)]
        e = (float(seg.b[0] - seg.a[0]), float(seg.b[1] - seg.a[1]))
        for lo, hi, j in zip(los, his, tgts):
            if self.is_piece(j):
                continue  # a landing on a unit: the goal cone of its segment's row below holds it if it is in the goal
            if j % self.n_segments in self.goal_whole:
                items.append((lo, hi, j))
                continue
            pieces = self.goal_partial.get(j % self.n_segments)
            if not pieces:
                continue
            tseg = self.partition.segments[j % self.n_segments]
            for t0, t1 in pieces:
                g0, g1 = _pulled_in(tseg, t0, t1, self.margins.corner_clearance, host)
                if g0 is None:
                    continue
                cone_lo = 0.0 if g0 == host.b else _angle(e, (float(g0[0] - seg.b[0]), float(g0[1] - seg.b[1]))) + self.safe_margin
                cone_hi = math.pi if g1 == host.a else _angle(e, (float(g1[0] - seg.a[0]), float(g1[1] - seg.a[1]))) - self.safe_margin
                l2, h2 = max(lo, cone_lo), min(hi, cone_hi)
                if h2 > l2:
                    items.append((l2, h2, j))
        if self.is_piece(source):  # a piece's goal intervals hold its segment's (monotonicity, :meth:`_combine`)
            tags = (source - PIECE_CODES * self.n_segments) % UNIT_TAGS
            items = [(lo, hi, j) for lo, hi, j, _ in
                     _holding([(lo, hi, j, 0) for lo, hi, j in items],
                              ((lo, hi, j, 0) for lo, hi, j in zip(*self.goal_intervals(self.segment(source)
                                                                                         + self.n_segments * tags))))]
        items.sort()
        out = ([x[0] for x in items], [x[1] for x in items], [x[2] for x in items])
        self._goal_lists[source] = out
        return out

    # ------------------------------------------------------------------ options
    def options(self, belief: Belief) -> list[Option]:
        """Every way to leave ``belief`` (one per choice of targets), widest interval each."""
        return self._options_from(self._options, belief, self.intervals)

    def goal_options(self, belief: Belief) -> list[Option]:
        """The options of ``belief`` that land in the goal set from every source (last stages)."""
        return self._options_from(self._goal_options, belief, self.goal_intervals)

    def _options_from(self, cache: dict[Belief, list[Option]], belief: Belief,
                      intervals: Callable[[int], tuple[list[float], list[float], list[int]]]) -> list[Option]:
        """The options of ``belief`` combined from the ``intervals`` of each of its sources, built once per belief
        and kept in ``cache``."""
        cached = cache.get(belief)
        if cached is None:
            cached = cache[belief] = self._combine(belief, [intervals(s) for s in belief], self._merged, self._finer)
        return cached

    @property
    def options_built(self) -> int:
        """How many options (:meth:`options`, not the goal ones) were built so far: a statistic of the search."""
        return sum(map(len, self._options.values()))

    def _merged(self, targets) -> Belief:
        """The next belief of a choice of target elements: one element per segment or unit, the corner tags of its
        copies joined (a robot that may be near either corner takes no arc into either). A unit whose segment is in
        the belief too is left out, its tags joined into the segment's: the two allow the same options. (At a
        heading where the segment's interval lands on target σ, the unit's lands on σ too — every point of the
        segment does — or on a piece of σ, by an arc into the same corner, so its tags forbid that interval exactly
        when they would forbid it to the segment; the unit's intervals hold the segment's, :func:`_holding`; and the
        unit's landing is inside the segment's, with no tag the segment's lacks, so it is left out of the next
        belief in turn.)"""
        n = self.n_segments
        if all(c < n for c in targets):
            return tuple(sorted(set(targets)))
        base = PIECE_CODES * n
        tags: dict[int, int] = {}
        for c in targets:
            if c >= base:
                key, tag = c - (c - base) % UNIT_TAGS, (c - base) % UNIT_TAGS
            else:
                key, tag = c % n, c // n
            tags[key] = tags.get(key, 0) | tag
        units = [key for key in tags if key >= base and self.units[(key - base) // UNIT_TAGS].host in tags]
        for key in units:
            tags[self.units[(key - base) // UNIT_TAGS].host] |= tags.pop(key)
        return tuple(sorted(key + (tag if key >= base else n * tag) for key, tag in tags.items()))

    def _finer(self, unit: int, code: int) -> bool:
        """Is belief element ``unit`` a landing on a piece of the segment that element ``code`` lands on whole, with
        no corner tag ``code`` lacks? Then a robot that lands there is somewhere a robot landing on ``code`` may be,
        with no more history: the belief with ``unit`` is the smaller one (:meth:`_combine`)."""
        n = self.n_segments
        if not self.is_piece(unit) or self.is_piece(code):
            return False
        rel = unit - PIECE_CODES * n
        return self.units[rel // UNIT_TAGS].host == code % n and not (rel % UNIT_TAGS) & ~(code // n)

    @staticmethod
    def _combine(belief: Belief, lists: list[tuple[list[float], list[float], list[int]]],
                 join: Callable[[Sequence[int]], Belief] = lambda t: tuple(sorted(set(t))),
                 finer: Callable[[int, int], bool] | None = None) -> list[Option]:
        """Intersect the sources' interval lists (sorted by their low ends), folding source by source; ``join``
        makes the next belief of the targets chosen. Lists of disjoint intervals are merged (the intersection of
        two sorted lists of disjoint intervals is again one). A list with overlapping intervals (landings on units
        inside a landing on their segment) is joined with every cell it overlaps, keeping only the choices no other
        choice *dominates* — one whose interval holds this one's and whose next belief is the same or smaller:

        (a) two partial choices with the same ``join`` of their targets so far and nested intervals: the inner
            one is dropped (every way to complete it completes the outer one to the same next belief, wider);
        (b) in one cell, a source's landing on a whole segment whose part of the cell a landing on one of that
            segment's pieces covers too (``finer(piece, segment)``, :meth:`_finer`): the segment's is dropped.

        So a belief of k sources whose landings may end on a piece or on its segment has, at one heading, the
        options of the distinct nested intervals of (a), not the 2^k choices of the pair-by-pair product.

        *Nothing is lost.* (a) compares equal beliefs. For (b), write x′ ⪯ x for belief elements when x′ is x with
        fewer corner tags, or a piece of x's segment with no tag x lacks; and B′ ⪯ B for beliefs (multisets of
        elements) when every element of B′ has one of B above it. Every option of B — an interval I and one row
        (interval ⊇ I, target τ) per element — is matched from B′ by I itself: the element x′ ⪯ x takes a row of
        its own with the same target τ holding I (x′'s rows hold x's: a piece's admissible intervals are cut from
        safe sets of a part of the segment, which every heading safe from the whole segment is safe from, under
        the same margins — the clearance κ is exempt at the segment's own corners for the piece as for the
        segment, :meth:`_piece_intervals`; and :func:`_holding` makes it so in floats too, where the ends differ by
        ulps; fewer tags forbid fewer rows; the same for goal intervals), so the next
        belief of B′ takes a sub-multiset of B's targets: again ⪯. Joining copies of one place (``join``: their
        tags united) changes nothing either (the copies can all take the finest of their common rows), nor does
        folding a unit into its segment when both are in a belief (:meth:`_merged`). By
        induction on the stages, every plan from B — k stages, intervals I₁ … I_k — is a plan from B′ with the
        same k stages and intervals (a plan from a belief works from any subset of it, *monotonicity*), so the
        fewest stages, the widest min width, the largest sum, the widest constant interval and the Pareto front
        from B′ are no worse than from B. A choice dropped by (b) has a kept choice with the same interval and a
        next belief ⪯ it (the segment replaced by the piece, tag ⊆): every plan through it is matched, stage by
        stage, by one through the kept choice. Both rules are kept by every later fold step (the same row
        completes both choices), so what is dropped early stays dominated.

        Raises :class:`InputError` when the choices kept still exceed :data:`MAX_JOINED_ENTRIES` (targets
        held), instead of filling the memory."""
        if len(belief) == 1:
            (s,) = belief
            los, his, tgts = lists[0]
            if finer is None or _disjoint(los, his):
                return [Option(lo, hi, (j,), ((s, j),)) for lo, hi, j in zip(los, his, tgts)]
            return [Option(lo, hi, key, ((s, t[0]),)) for lo, hi, t, key in
                    _closed(_join_pruned([(-math.inf, math.inf, (), ())], los, his, tgts, join, finer), lists, join,
                            finer)]
        if any(not item[0] for item in lists):
            return []
        los, his, tgts = lists[0]
        cells: list = list(zip(los, his, [(j,) for j in tgts]))
        keyed = False
        if not _disjoint(los, his):
            cells = _join_pruned([(-math.inf, math.inf, (), ())], los, his, tgts, join, finer)
            keyed = True
        for los, his, tgts in lists[1:]:
            if not keyed and _disjoint(los, his):
                merged = _merge_disjoint(cells, los, his, tgts)
            else:
                if not keyed:
                    cells = [(lo, hi, t, join(t)) for lo, hi, t in cells]
                    keyed = True
                merged = _join_pruned(cells, los, his, tgts, join, finer)
                if merged and len(merged) * len(merged[0][2]) > MAX_JOINED_ENTRIES:
                    raise InputError(
                        f"a belief of {len(belief)} segments of P′ has {len(merged):,} undominated ways to leave it "
                        "(landings on pieces between the set ends or on their whole segments): too many to hold; "
                        "give a start set that spans fewer segments, or ends at vertices")
            if not merged:
                return []
            cells = merged
        if keyed:
            if finer is not None:
                cells = _closed(cells, lists, join, finer)
            return [Option(lo, hi, key, tuple(zip(belief, t))) for lo, hi, t, key in cells]
        if len(belief) == 2:
            s0, s1 = belief
            return [Option(lo, hi, join(t), ((s0, t[0]), (s1, t[1]))) for lo, hi, t in cells]
        return [Option(lo, hi, join(t), tuple(zip(belief, t))) for lo, hi, t in cells]

    # ------------------------------------------------------------------ bounds from single segments
    @property
    def singleton_bounds(self) -> tuple[list[float], list[float]]:
        """For every segment s: the fewest stages d(s) of any plan from {s} (∞ if none) and the largest
        min width h(s) of any plan from {s} (0 if none).

        A plan from a belief B works from every segment of B, so it is a plan from each {s}, s ∈ B:
        **d(B) ≥ max_{s∈B} d(s) and W(B) ≤ min_{s∈B} h(s)**. The searches use these as admissible bounds
        (A*-style pruning) when beliefs have several segments. Computed backwards from the goal over the
        segment graph: breadth-first for d, max-min Dijkstra for h.
        """
        cached = getattr(self, "_singleton", None)
        if cached is None:
            cached = self._singleton = self._backward()
        return cached

    def _backward(self) -> tuple[list[float], list[float]]:
        """d and h (:attr:`singleton_bounds`) of every place (:meth:`place`: segments, then units). A unit's own arcs
        are relaxed (it may reach every segment its host sees, and their units, with any width, and it is one stage
        from the goal if its host sees a goal segment): its exact intervals are built only when a search reaches it
        (:meth:`_piece_bounds` looks one stage ahead with them), and the relaxation keeps both bounds admissible."""
        import heapq

        n, n_units = self.n_segments, len(self.units)
        places = n + n_units
        src_of = np.repeat(np.arange(n), np.diff(self._off))
        tgt = np.asarray(self._tgt, dtype=np.int64)
        width = np.asarray(self._hi) - np.asarray(self._lo)
        widest = math.pi - 2 * self.heading_margin
        goal_targets = sorted(self.goal_whole | set(self.goal_partial))
        relaxed_first: list[int] = []
        if n_units:
            us: list[int] = []
            ut: list[int] = []
            goal_set = set(goal_targets)
            for u, unit in enumerate(self.units):
                seen = self.graph.successors(unit.host).tolist()
                for j in seen:
                    us.append(n + u)
                    ut.append(j)
                    for v in self.units_of.get(j, ()):
                        us.append(n + u)
                        ut.append(n + v)
                if goal_set.intersection(seen):
                    relaxed_first.append(n + u)
            src_of = np.concatenate([src_of, np.asarray(us, dtype=np.int64)])
            tgt = np.concatenate([tgt, np.asarray(ut, dtype=np.int64)])
            width = np.concatenate([width, np.full(len(us), widest)])
        order = np.argsort(tgt, kind="stable")
        pred_src = src_of[order].tolist()
        pred_w = width[order].tolist()
        pred_off = np.searchsorted(tgt[order], np.arange(places + 1)).tolist()
        first = np.unique(src_of[:len(self._tgt)][np.isin(tgt[:len(self._tgt)], goal_targets)]).tolist() if goal_targets else []
        dist = [math.inf] * places
        best = [0.0] * places
        heap = []
        level = []
        for s in first:
            los, his, _ = self.goal_intervals(s)
            if los:
                dist[s] = 1
                level.append(s)
                best[s] = max(h - l for l, h in zip(los, his))
                heap.append((-best[s], s))
        for s in relaxed_first:
            dist[s] = 1
            level.append(s)
            best[s] = widest
            heap.append((-widest, s))
        d = 1
        while level:
            nxt = []
            for j in level:
                for k in range(pred_off[j], pred_off[j + 1]):
                    i = pred_src[k]
                    if dist[i] == math.inf:
                        dist[i] = d + 1
                        nxt.append(i)
            level = nxt
            d += 1
        heapq.heapify(heap)
        done = [False] * places
        while heap:
            neg, j = heapq.heappop(heap)
            if done[j] or -neg < best[j]:
                continue
            done[j] = True
            v = -neg
            for k in range(pred_off[j], pred_off[j + 1]):
                i = pred_src[k]
                w = pred_w[k] if pred_w[k] < v else v
                if w > best[i]:
                    best[i] = w
                    heapq.heappush(heap, (-w, i))
        return dist, best

    def belief_bounds(self, belief: Belief) -> tuple[float, float]:
        """(lower bound on the stages, upper bound on the min width) of any plan from ``belief``."""
        dist, best = self.singleton_bounds
        n = self.n_segments
        d, h = 0.0, math.inf
        for s in belief:
            ds, hs = self._piece_bounds(s) if self.is_piece(s) else (dist[s % n], best[s % n])
            d, h = max(d, ds), min(h, hs)
        return d, h

    def _piece_bounds(self, code: int) -> tuple[float, float]:
        """:meth:`belief_bounds` of a unit alone, one stage ahead of the places' bounds: its own goal intervals, or
        its options followed by the best from their targets (and no better than its relaxed bound)."""
        cached = self._unit_bounds.get(code)
        if cached is not None:
            return cached
        dist, best = self.singleton_bounds
        glo, ghi, _ = self.goal_intervals(code)
        d = 1.0 if glo else math.inf
        h = max((hi - lo for lo, hi in zip(glo, ghi)), default=0.0)
        for lo, hi, j in zip(*self.intervals(code)):
            p = self.place(j)
            d = min(d, 1 + dist[p])
            h = max(h, min(hi - lo, best[p]))
        own = self.place(code)
        cached = self._unit_bounds[code] = (max(d, dist[own]), min(h, best[own]))
        return cached

    # ------------------------------------------------------------------ facts for reasons
    def goal_has_incoming(self) -> bool:
        """Is there any source (a segment or a unit) with a goal interval (so that some last stage exists)?"""
        targets = set(self.goal_whole) | set(self.goal_partial)
        if not targets:
            return False
        if any(self.goal_intervals(c)[0] for c in self.start_belief if self.is_piece(c)):
            return True
        g = self.graph
        tgt_arr = np.asarray(self._tgt)
        if np.isin(tgt_arr, sorted(self.goal_whole)).any():
            return True
        candidates = np.unique(np.repeat(np.arange(g.n_segments), np.diff(self._off))[np.isin(tgt_arr, sorted(self.goal_partial))])
        if any(self.goal_intervals(int(s))[0] for s in candidates):
            return True
        return self.landing_units and any(self.goal_intervals(self.unit_code(u))[0] for u in range(len(self.units)))


def _pulled_in(tseg, t0: Fraction, t1: Fraction, kappa: float, source):
    """The ends of the goal piece [t0, t1] of target segment ``tseg``, each moved κ inwards (floats) unless it is
    the corner the target shares with ``source`` (exempt, see :mod:`solverplan.plan.margins`); ``(None, None)``
    when the piece is shorter than the clearance needs."""
    g0, g1 = _point_on(tseg, t0), _point_on(tseg, t1)
    if kappa <= 0:
        return g0, g1
    x0, y0, x1, y1 = float(g0[0]), float(g0[1]), float(g1[0]), float(g1[1])
    length = math.hypot(x1 - x0, y1 - y0)
    pull0, pull1 = g0 != source.b, g1 != source.a
    if length <= kappa * (pull0 + pull1):
        return None, None
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    p0 = (x0 + kappa * ux, y0 + kappa * uy) if pull0 else g0
    p1 = (x1 - kappa * ux, y1 - kappa * uy) if pull1 else g1
    return p0, p1


def _point_on(seg, t: Fraction):
    """The exact point of parameter t (on the segment's edge) — t within [seg.t0, seg.t1]."""
    if seg.t1 == seg.t0:  # pragma: no cover - segments have positive length
        return seg.a
    lam = (t - seg.t0) / (seg.t1 - seg.t0)
    return (seg.a[0] + lam * (seg.b[0] - seg.a[0]), seg.a[1] + lam * (seg.b[1] - seg.a[1]))


def _closed(cells: list[Cell], lists: Sequence[tuple[list[float], list[float], list[int]]],
            join: Callable[[Sequence[int]], Belief], finer: Callable[[int, int], bool]) -> list[Cell]:
    """Rule (b) of :meth:`Problem._combine` once more, on the choices a fold ends with: where a choice's interval
    narrowed after a source was folded in, the source's landing on a whole segment may now lie inside one of its
    landings on a piece of that segment, at the same interval: the choice takes the piece (a smaller next belief),
    then rule (a) again. The pieces of a list are the intervals that lie inside another of the same list and are
    ``finer`` than it (the segment's intervals are disjoint, so there are few)."""
    from bisect import bisect_right

    rules = []  # per source with pieces: sorted (lo, hi, piece element, segment element) of its pieces
    for q, (los, his, tgts) in enumerate(lists):
        if _disjoint(los, his):
            continue
        found = []
        for i in range(len(los)):
            k = i + 1
            while k < len(los) and los[k] < his[i]:
                for inner, outer in ((k, i), (i, k)):
                    if los[outer] <= los[inner] and his[inner] <= his[outer] and finer(tgts[inner], tgts[outer]):
                        found.append((los[inner], his[inner], tgts[inner], tgts[outer]))
                k += 1
        if found:
            found.sort()
            rules.append((q, found, [r[0] for r in found], _disjoint([r[0] for r in found], [r[1] for r in found])))
    if not rules:
        return cells
    changed = False
    groups: dict[Belief, list[Cell]] = {}
    for lo, hi, t, key in cells:
        new = None
        for q, found, starts, single in rules:
            at = bisect_right(starts, lo)
            for r_lo, r_hi, inner, outer in (found[at - 1:at] if single else found[:at]):
                if r_hi >= hi and t[q] == outer:
                    new = new or list(t)
                    new[q] = inner
                    break
        if new is not None:
            changed = True
            t = tuple(new)
            key = join(t)
        groups.setdefault(key, []).append((lo, hi, t, key))
    return _undominated(groups) if changed else cells


def _holding(rows: list[tuple[float, float, int, int]], host_rows: Iterable[tuple[float, float, int, int]],
             ) -> list[tuple[float, float, int, int]]:
    """The rows (lo, hi, target element, dive) of a piece, sorted by low ends, widened so that every row of its
    segment (``host_rows``) lies inside one with the same target: the hull of the piece's rows of that target it
    meets, or the segment's row itself where it meets none. Sound: a heading admissible from the whole segment is
    admissible from every part of it (the same margins; the piece's landings are some of the segment's). The
    piece's own rows hold the segment's already in exact arithmetic; their float ends differ by a few ulps
    (≤ 10⁻¹⁴ rad), which this removes, so that a piece is never worse than its segment in floats either
    (:meth:`Problem._combine` relies on it)."""
    out = list(rows)
    by_target: dict[int, list[int]] = {}
    for i, row in enumerate(out):
        by_target.setdefault(row[2], []).append(i)
    dead: set[int] = set()
    for lo, hi, code, dive in host_rows:
        meets = [i for i in by_target.get(code, ()) if i not in dead and out[i][0] <= hi and lo <= out[i][1]]
        if not meets:
            by_target.setdefault(code, []).append(len(out))
            out.append((lo, hi, code, dive))
            continue
        keep = meets[0]
        if out[keep][0] <= lo and hi <= out[keep][1] and len(meets) == 1:
            continue
        out[keep] = (min(lo, *(out[i][0] for i in meets)), max(hi, *(out[i][1] for i in meets)), code, out[keep][3])
        dead.update(meets[1:])
    if dead:
        out = [row for i, row in enumerate(out) if i not in dead]
    out.sort(key=lambda r: r[0])
    return out


def _disjoint(los: list[float], his: list[float]) -> bool:
    """Are the intervals of a list sorted by low ends pairwise disjoint (touching at most)?"""
    return all(h <= l for h, l in zip(his, los[1:]))


def _merge_disjoint(cells, los, his, tgts):
    """The intersections of sorted disjoint cells with a sorted list of disjoint intervals (a merge)."""
    merged = []
    i = j = 0
    n_cells, n_list = len(cells), len(los)
    while i < n_cells and j < n_list:
        c_lo, c_hi, c_t = cells[i]
        l_j, h_j = los[j], his[j]
        if h_j <= c_lo:
            j += 1
            continue
        if c_hi <= l_j:
            i += 1
            continue
        lo = c_lo if c_lo > l_j else l_j
        hi = c_hi if c_hi < h_j else h_j
        if hi > lo:
            merged.append((lo, hi, c_t + (tgts[j],)))
        if c_hi < h_j:
            i += 1
        else:
            j += 1
    return merged


MAX_JOINED_ENTRIES = 20_000_000
"""Most targets the undominated choices of one fold step of :meth:`Problem._combine` may hold (choices × sources so
far, about 160 MB of references): a guard that refuses the query in one line rather than fill the memory. The
pruning of :meth:`Problem._combine` keeps far fewer on real queries (a belief of 204 sources landing on pieces: see
benchmarks/README.md)."""


def _join_pruned(cells: list[Cell], los: list[float], his: list[float], tgts: list[int],
                 join: Callable[[Sequence[int]], Belief], finer: Callable[[int, int], bool] | None) -> list[Cell]:
    """One fold step of :meth:`Problem._combine` over a list that may overlap (cells too): every cell
    (lo, hi, targets, key = ``join(targets)``) intersected with every interval of the list it meets with positive
    width, less the dominated choices of rules (a) and (b) there; sorted by low ends. For each cell the list is
    scanned from the first interval whose prefix maximum of high ends passes the cell's low end up to the first
    starting past its high end."""
    from bisect import bisect_right
    from itertools import accumulate

    top = list(accumulate(his, max))
    n_list = len(los)
    groups: dict[Belief, list[Cell]] = {}
    for c_lo, c_hi, c_t, c_key in cells:
        k = bisect_right(top, c_lo)
        hits = []
        while k < n_list and los[k] < c_hi:
            h_k = his[k]
            if h_k > c_lo:
                lo = c_lo if c_lo > los[k] else los[k]
                hi = c_hi if c_hi < h_k else h_k
                if hi > lo:
                    hits.append((lo, hi, tgts[k]))
            k += 1
        if finer is not None and len(hits) > 1:  # rule (b)
            hits = [h for h in hits if not any(g[0] <= h[0] and h[1] <= g[1] and finer(g[2], h[2]) for g in hits)]
        for lo, hi, code in hits:
            key = join(c_key + (code,))
            groups.setdefault(key, []).append((lo, hi, c_t + (code,), key))
    return _undominated(groups)


def _undominated(groups: dict[Belief, list[Cell]]) -> list[Cell]:
    """Rule (a) of :meth:`Problem._combine`: of the cells grouped by next belief, those whose interval no other cell
    of the group holds (one of equal ones), all sorted by their ends."""
    merged = []
    for items in groups.values():
        if len(items) > 1:
            items.sort(key=lambda cell: (cell[0], -cell[1]))
            reach = -math.inf
            kept = []
            for cell in items:
                if cell[1] > reach:
                    kept.append(cell)
                    reach = cell[1]
            items = kept
        merged.extend(items)
    merged.sort(key=lambda cell: (cell[0], cell[1]))
    return merged
