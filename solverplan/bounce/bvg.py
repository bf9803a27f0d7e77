"""The bounce visibility graph (BVG) and the safe BVG of P′ (paper §4–5, Def. 5–8, Prop. 1–3, 5).

- :func:`bounce_visibility_graph` — the directed edge-visibility graph of P′: an arc i → j for every
  two segments whose **open** segments see each other (some point of one sees some point of the
  other through the interior of the free space; paper Def. 5 — not "an end point is
  visible", which over-approximates). Visibility is symmetric, so the arc set is; never a self-loop, never an arc between two
  segments of one edge (collinear), none between the two segments at a reflex or flat vertex.
- :func:`safe_bounce_visibility_graph` — the same arcs, each labelled with the **exact set of safe
  headings** (Def. 7: every point of the open e_i reaches the open e_j), its widest interval, the
  transition side (Def. 8) and φ_ij: a :class:`SafeBVG`. The safe set is the one of
  :func:`solverplan.bounce.safe.safe_set` — Prop. 2's interval for entirely visible pairs (Cor. 1 for
  adjacent segments at convex corners), and the exact, possibly smaller set for every other pair;
  with holes it may be several intervals.

Algorithm (see :mod:`solverplan.bounce._sweep` for the sweeps)
--------------------------------------------------------------
1. From every vertex x of P′, in the frame of each segment it ends, an angular *sweep* lists which
   segment the ray from x first meets, as closed heading ranges ("entries").
2. **Arcs.** e_i and e_j see each other iff one of the four sweeps at their end points (a and b of
   e_i, c and d of e_j) meets the other segment over a heading range of positive width. *Proof.* The
   pairs (p, q) ∈ e_i × e_j that see each other form an open set V. Inside an open segment of P′ the
   combinatorial structure of the visibility polygon does not change (its changes happen where the
   line through a vertex and a reflex vertex meets the boundary — Algorithm 1's points), so each
   window through which q is seen slides monotonically with p, bounded by curves t = f(s) through
   fixed reflex vertices. A component of V therefore reaches the boundary of e_i × e_j in an open
   piece of one of its four sides, unless its window degenerates to a single line at both ends of e_i
   — impossible, since one pair of fixed reflex vertices is collinear with only one point of e_i's
   line. An open piece of a side, say s = a, is a range of positive width in the sweep from a. □
   (The tests compare this with the exact :func:`~solverplan.geometry.visibility.segments_see_each_other`
   on random polygons with holes.)
3. **Safe sets.** With A_a(j), A_b(j) the entries for j in the sweeps at a ("+") and b ("−") of e_i,
   the safe set is A_a(j) ∩ A_b(j) minus the open interval (max ang(v − a), min ang(v − b)) of every
   hole lying strictly on the free side of both segments' lines (:mod:`solverplan.bounce.safe`,
   proof (4)). The entries are closures, which can add only isolated points (the exact safe set is
   closed); every single-point interval is therefore re-checked exactly with
   :func:`~solverplan.bounce.safe.heading_is_safe`.

All comparisons of interval ends are exact when their floats are within the error bound (ends are
directions between two exact points of P′, or the frame ends 0 and π, which are excluded).

Cost: the sweeps (O(M·n log n), plus the first-hit tests that survive the occlusion pruning of
:func:`~solverplan.bounce._sweep._hit_edges`) and a sort-merge join, all numpy — no loop over
pairs of segments. Memory follows the output: the sweeps run in blocks and keep only their entries,
the join frees each intermediate once consumed, and the graph is a structure of arrays (source,
target, widest interval, interval offsets and ends, transition, φ: about 110 bytes per arc, under
200 at the build's peak). See ``benchmarks/bench_bvg.py`` and ``benchmarks/bench_cli.py --large``
for measured times and memory.
"""

from __future__ import annotations

import html
import io
import logging
import math
from dataclasses import dataclass, field, replace
from fractions import Fraction
from functools import cached_property
from typing import TYPE_CHECKING, Iterator

import numpy as np

from solverplan._arrays import ragged_arange
from solverplan.bounce import _cache, _sweep
from solverplan.bounce._cache import (
    DEFAULT_MAX_BYTES,
    DEFAULT_MIN_ARCS,
    GraphCacheReport,
    clear_graph_cache,
    default_cache_directory,
    discard_graphs,
    fresh_graphs,
    graph_cache_directory,
    graph_cache_report,
    partition_digest,
    purge_graph_cache,
    set_graph_cache,
)
from solverplan.bounce._sweep import MARK_PI, MARK_ZERO, ExactPoints, Sweeps, _ninf, build_sweeps
from solverplan.interval import Interval
from solverplan.bounce.partition import Partition, partition as make_partition
from solverplan.bounce.safe import Direction, SafeInterval, SafeSet
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.limits import memory_limit
from solverplan.progress import step

if TYPE_CHECKING:  # networkx costs ~0.1 s to import: only the conversions below load it
    import networkx as nx

__all__ = ["SafeBVG", "bounce_visibility_graph", "safe_bounce_visibility_graph", "GraphTooLarge", "estimate_graph",
           "check_graph_memory", "fitting_simplification", "reachable_safe_graph", "LAZY_MIN_ARCS", "set_graph_cache", "clear_graph_cache",
           "graph_cache_directory", "default_cache_directory", "graph_cache_report", "purge_graph_cache",
           "GraphCacheReport", "DEFAULT_MIN_ARCS", "DEFAULT_MAX_BYTES", "partition_digest", "discard_graphs", "fresh_graphs"]

logger = logging.getLogger(__name__)

_TRANSITIONS = {1: "right", -1: "left", 0: "parallel"}
# Float separating-axis tests of single-heading regions: orientations within this times the squared
# coordinate scale of zero are decided exactly.
_SAT_REL = 1e-12


def _as_partition(obj: Partition | Environment) -> Partition:
    if isinstance(obj, Partition):
        return obj
    if isinstance(obj, Environment):
        return make_partition(obj)
    raise InputError(f"expected a Partition or an Environment, got {type(obj).__name__}")


# ---------------------------------------------------------------------------------------------
# exact-on-ties comparison of interval ends
# ---------------------------------------------------------------------------------------------
class _Ends:
    """Compares heading ends given as (from P′ id, to P′ id or mark, float heading, error bound),
    all in the frame of one edge per row; exact (integer) arithmetic when the floats are too close."""

    def __init__(self, exact: ExactPoints) -> None:
        self.exact = exact
        self.checks = 0

    def cmp(self, edge, f1, t1, a1, e1, f2, t2, a2, e2) -> np.ndarray:
        d = a1 - a2
        out = np.sign(d).astype(np.int8)
        unsure = np.abs(d) <= e1 + e2
        idx = np.flatnonzero(unsure)
        self.checks += len(idx)
        hc = self.exact.heading_cmp
        for i in idx.tolist():
            out[i] = hc(int(edge[i]), int(f1[i]), int(t1[i]), int(f2[i]), int(t2[i]))
        return out


@dataclass
class _Pieces:
    """Flat table of candidate intervals: arc row, lo end, hi end (from, to, heading, error)."""

    arc: np.ndarray
    lo_from: np.ndarray
    lo_to: np.ndarray
    lo: np.ndarray
    lo_err: np.ndarray
    hi_from: np.ndarray
    hi_to: np.ndarray
    hi: np.ndarray
    hi_err: np.ndarray

    def take(self, idx: np.ndarray) -> _Pieces:
        return _Pieces(*(getattr(self, name)[idx] for name in self.__dataclass_fields__))

    @staticmethod
    def concat(parts: list[_Pieces]) -> _Pieces:
        return _Pieces(*(np.concatenate([getattr(p, name) for p in parts]) for name in _Pieces.__dataclass_fields__))


# ---------------------------------------------------------------------------------------------
# the safe BVG
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SafeBVG:
    """The bounce visibility graph of P′ with the safe headings of every arc.

    Build it with :func:`safe_bounce_visibility_graph`. Arcs are stored as numpy arrays of length
    ``n_arcs``, sorted by (source, target):

    ``source``, ``target``
        Segment ids (int64).
    ``lo``, ``hi``
        The widest safe interval (radians, float64), NaN when the arc has no safe heading. An end
        equal to 0 or π means "open there" (Cor. 1's intervals at convex corners).
    ``n_intervals``
        Number of disjoint safe intervals (0, 1, or more with holes); all of them are in
        ``set_lo``/``set_hi`` (flat, ``set_offsets[k]:set_offsets[k+1]`` for arc k).
    ``transition``
        int8: +1 right, −1 left, 0 parallel (Def. 8); see :attr:`transitions` for the strings.
    ``phi``
        φ_ij in radians (0 for parallel lines).

    Exact end directions (for certificates) are rebuilt on demand by :meth:`safe_set`.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> g = safe_bounce_visibility_graph(square)
    >>> g.n_arcs, g.n_safe_arcs          # every ordered pair of sides, all safe (Cor. 1: adjacent sides too)
    (12, 12)
    >>> g.safe_set(0, 1).interval        # bottom → right side: Cor. 1, (0, π/4]
    Interval(lo=0.0, hi=0.7853981633974483)
    >>> g.to_json()["arcs"][0]
    {'from': 0, 'to': 1, 'safe': [0.0, 0.7853981633974483], 'transition': 'right', 'phi': 1.5707963267948966, 'safe_set': [[0.0, 0.7853981633974483]]}
    """

    partition: Partition
    source: np.ndarray
    target: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    n_intervals: np.ndarray
    set_offsets: np.ndarray
    set_lo: np.ndarray
    set_hi: np.ndarray
    transition: np.ndarray
    phi: np.ndarray
    _set_ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] = field(repr=False)
    stats: dict = field(default_factory=dict, repr=False)
    labelled: bool = True
    """Whether :meth:`to_json` and the other outputs show the safe headings by default (``False``
    after ``select(safe=False)``: the plain BVG)."""

    # ------------------------------------------------------------------ size and lookup
    @property
    def n_segments(self) -> int:
        return len(self.partition.segments)

    @property
    def n_arcs(self) -> int:
        return len(self.source)

    @property
    def n_safe_arcs(self) -> int:
        return int(np.count_nonzero(self.n_intervals))

    @property
    def safe(self) -> np.ndarray:
        """Boolean mask of the arcs with at least one safe heading."""
        return self.n_intervals > 0

    @property
    def transitions(self) -> list[str]:
        """Def. 8 per arc: ``"left"``, ``"right"`` or ``"parallel"``."""
        return [_TRANSITIONS[int(s)] for s in self.transition]

    def _check_segment(self, segment: object, name: str = "") -> int:
        n = self.n_segments
        if isinstance(segment, bool) or not isinstance(segment, (int, np.integer)) or not 0 <= int(segment) < n:
            raise InvalidBoundarySet(f"unknown segment {segment!r}: segments are 0..{n - 1}")
        return int(segment)

    def select(self, *, source: int | None = None, heading: float | None = None, safe: bool = True) -> SafeBVG:
        """A copy restricted to the arcs leaving ``source`` and/or the arcs whose safe set contains
        ``heading`` (radians, in (0, π)); ``safe=False`` makes the outputs show the plain BVG.

        >>> from solverplan.environment import Environment
        >>> square = safe_bounce_visibility_graph(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]]))
        >>> [(a["from"], a["to"]) for a in square.select(source=0, heading=0.5).to_json()["arcs"]]
        [(0, 1)]
        >>> square.select(heading=3.5)
        Traceback (most recent call last):
        ...
        solverplan.errors.InvalidBoundarySet: heading 3.5 is not inside (0, π)
        """
        if source is None and heading is None:  # every arc: share the arrays (a copy would double the graph)
            return replace(self, labelled=safe)
        keep = np.ones(self.n_arcs, dtype=bool)
        if source is not None:
            keep &= self.source == self._check_segment(source)
        if heading is not None:
            h = float(heading)
            if not (math.isfinite(h) and 0 < h < math.pi):
                raise InvalidBoundarySet(f"heading {h:g} is not inside (0, π)")
            inside = (self.set_lo <= h) & (h <= self.set_hi)
            arc_of = np.repeat(np.arange(self.n_arcs), self.n_intervals)
            hit = np.zeros(self.n_arcs, dtype=bool)
            hit[arc_of[inside]] = True
            keep &= hit
        rows = np.flatnonzero(keep)
        counts = self.n_intervals[rows]
        starts = self.set_offsets[rows]
        take = np.repeat(starts, counts) + ragged_arange(counts)
        return SafeBVG(
            partition=self.partition,
            source=self.source[rows],
            target=self.target[rows],
            lo=self.lo[rows],
            hi=self.hi[rows],
            n_intervals=counts,
            set_offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
            set_lo=self.set_lo[take],
            set_hi=self.set_hi[take],
            transition=self.transition[rows],
            phi=self.phi[rows],
            _set_ends=tuple(a[take] for a in self._set_ends),
            stats=self.stats,
            labelled=safe,
        )

    def arc_index(self, source: int, target: int) -> int | None:
        """Row of the arc source → target, ``None`` if the segments do not see each other.

        Raises :class:`~solverplan.errors.InvalidBoundarySet` for an unknown segment id.
        """
        i = self._check_segment(source)
        j = self._check_segment(target)
        key = i * self.n_segments + j
        k = int(np.searchsorted(self._keys, key))
        return k if k < len(self._keys) and int(self._keys[k]) == key else None

    @cached_property
    def _keys(self) -> np.ndarray:
        return self.source * self.n_segments + self.target

    def safe_set(self, source: int, target: int) -> SafeSet:
        """The exact safe set of the arc source → target (empty if there is no such arc or no safe heading),
        with exact end directions (:class:`~solverplan.bounce.safe.SafeInterval`)."""
        k = self.arc_index(source, target)
        if k is None:
            return SafeSet()
        s0, s1 = int(self.set_offsets[k]), int(self.set_offsets[k + 1])
        lo_from, lo_to, hi_from, hi_to = self._set_ends
        seg = self.partition.segments[int(self.source[k])]
        pts = [s.a for s in self.partition.segments]
        e = (seg.b[0] - seg.a[0], seg.b[1] - seg.a[1])

        def direction(frm: int, to: int) -> Direction:
            if to == MARK_ZERO:
                return e
            if to == MARK_PI:
                return (-e[0], -e[1])
            p, q = pts[frm], pts[to]
            return (q[0] - p[0], q[1] - p[1])

        return SafeSet(tuple(
            SafeInterval(Interval(float(self.set_lo[r]), float(self.set_hi[r])),
                         direction(int(lo_from[r]), int(lo_to[r])), direction(int(hi_from[r]), int(hi_to[r])))
            for r in range(s0, s1)
        ))

    def interval(self, source: int, target: int) -> Interval:
        """The widest safe interval of source → target (:data:`Interval.EMPTY` if none or no arc)."""
        k = self.arc_index(source, target)
        if k is None or self.n_intervals[k] == 0:
            return Interval.EMPTY
        return Interval(float(self.lo[k]), float(self.hi[k]))

    def successors(self, segment: int, *, safe_only: bool = False) -> np.ndarray:
        """Targets of the arcs leaving ``segment`` (only the safe ones with ``safe_only``)."""
        i = self._check_segment(segment)
        a, b = np.searchsorted(self.source, [i, i + 1])
        rows = np.arange(a, b)
        if safe_only:
            rows = rows[self.n_intervals[rows] > 0]
        return self.target[rows]

    # ------------------------------------------------------------------ conversions
    def to_networkx(self, *, safe_only: bool = False) -> nx.DiGraph:
        """A :class:`networkx.DiGraph` on the segment ids.

        Node attributes: ``edge``, ``t0``, ``t1`` (floats). Arc attributes: ``safe`` (the widest
        :class:`Interval`, EMPTY if none), ``safe_set`` (tuple of Intervals), ``transition``
        (``"left"``/``"right"``/``"parallel"``), ``phi`` (radians). ``safe_only`` keeps only arcs with
        safe headings (the paper's BVG_safe).
        """
        import networkx as nx  # here, not at the top: only the conversions load it (~0.1 s)

        g = nx.DiGraph(name=f"safe BVG of {self.partition.env.name!r}")
        for s in self.partition.segments:
            g.add_node(s.id, edge=s.edge, t0=float(s.t0), t1=float(s.t1))
        sets = self._float_sets()
        names = self.transitions
        for k in range(self.n_arcs):
            if safe_only and not self.n_intervals[k]:
                continue
            safe = Interval(float(self.lo[k]), float(self.hi[k])) if self.n_intervals[k] else Interval.EMPTY
            g.add_edge(int(self.source[k]), int(self.target[k]), safe=safe, safe_set=sets[k],
                       transition=names[k], phi=float(self.phi[k]))
        return g

    def _float_sets(self) -> list[tuple[Interval, ...]]:
        out = []
        off = self.set_offsets
        for k in range(self.n_arcs):
            out.append(tuple(Interval(float(self.set_lo[r]), float(self.set_hi[r])) for r in range(int(off[k]), int(off[k + 1]))))
        return out

    def to_json(self, *, safe: bool | None = None) -> dict:
        """The answer of ``solverplan graph`` (docs/contract.md): ``{"arcs": [{"from", "to", "safe": [lo, hi] or null, "transition"}]}``,
        plus ``phi`` and ``safe_set`` (every safe interval; more than one only with holes), and counts.
        With ``safe=False`` (the plain BVG; the default after ``select(safe=False)``) arcs carry only
        ``from``, ``to``, ``transition``."""
        safe = self.labelled if safe is None else safe
        out = self._json_header(safe)
        out["arcs"] = self._arc_dicts(0, self.n_arcs, safe)
        return out

    def json_bytes(self, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 16) -> bytearray:
        """:meth:`to_json` as compact JSON (UTF-8) followed by ``end``, encoded a chunk of arcs at a
        time into one growing buffer: the same bytes as ``orjson.dumps(self.to_json()) + end``,
        without a dict per arc at once nor a second copy of the text (2.4 million arcs: ≈ 0.3 GB
        of text instead of ≈ 2 GB of dicts)."""
        out = bytearray()
        for chunk in self.json_chunks(safe=safe, end=end, arcs_per_chunk=arcs_per_chunk):
            out += chunk
        return out

    def json_chunks(self, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 16) -> Iterator[bytes]:
        """:meth:`json_bytes` a chunk of arcs at a time, for writing as it is made (``solverplan graph -o``): only one
        chunk's dicts and text exist at once, never the whole text."""
        import orjson

        safe = self.labelled if safe is None else safe
        head = orjson.dumps(self._json_header(safe))
        yield head[:-1] + (b',"arcs":[' if len(head) > 2 else b'"arcs":[')
        for a in range(0, self.n_arcs, arcs_per_chunk):
            text = orjson.dumps(self._arc_dicts(a, min(self.n_arcs, a + arcs_per_chunk), safe))[1:-1]
            yield b"," + text if a else text
        yield b"]}" + end

    def _json_header(self, safe: bool) -> dict:
        out = {
            "name": self.partition.env.name,
            "n_segments": self.n_segments,
            "n_arcs": self.n_arcs,
        }
        if safe:
            out["n_safe_arcs"] = self.n_safe_arcs
        return out

    def _arc_dicts(self, a: int, b: int, safe: bool) -> list[dict]:
        """The JSON arcs of rows a..b−1."""
        # Built column-wise with zip (no per-arc indexing, one list slice per safe set): this runs
        # once per `solverplan graph` over up to ~10⁶ arcs, where it was the slowest step.
        names = [_TRANSITIONS[t] for t in self.transition[a:b].tolist()]
        src, dst = self.source[a:b].tolist(), self.target[a:b].tolist()
        if not safe:
            return [{"from": i, "to": j, "transition": t} for i, j, t in zip(src, dst, names)]
        off = self.set_offsets[a : b + 1]
        r0, r1 = int(off[0]), int(off[-1])
        pieces = [[x, y] for x, y in zip(self.set_lo[r0:r1].tolist(), self.set_hi[r0:r1].tolist())]
        off = (off - r0).tolist()
        sets = [pieces[x:y] for x, y in zip(off, off[1:])]
        widest = [[x, y] if c else None for x, y, c in zip(self.lo[a:b].tolist(), self.hi[a:b].tolist(), self.n_intervals[a:b].tolist())]
        return [
            {"from": i, "to": j, "safe": w, "transition": t, "phi": f, "safe_set": ss}
            for i, j, w, t, f, ss in zip(src, dst, widest, names, self.phi[a:b].tolist(), sets)
        ]

    def to_text(self, *, width: int = 100, safe: bool | None = None) -> str:
        """A summary and one line per segment listing its out-arcs (safe ones with their intervals)."""
        safe = self.labelled if safe is None else safe
        buffer = io.StringIO()
        env = self.partition.env
        buffer.write(f"{'safe ' if safe else ''}bounce visibility graph of {env.name!r}\n")
        buffer.write(f"  segments: {self.n_segments}   arcs: {self.n_arcs}")
        if safe:
            buffer.write(f"   safe arcs: {self.n_safe_arcs}")
            multi = int(np.count_nonzero(self.n_intervals > 1))
            if multi:
                buffer.write(f"   arcs with several safe intervals: {multi}")
        buffer.write("\n")
        starts = np.searchsorted(self.source, np.arange(self.n_segments + 1))
        for i in range(self.n_segments):
            rows = range(int(starts[i]), int(starts[i + 1]))
            if not rows:
                continue
            seg = self.partition.segments[i]
            head = f"{i:>5} (e{seg.edge}) →"
            if not safe:
                items = [str(int(self.target[k])) for k in rows]
            else:
                items = []
                for k in rows:
                    j = int(self.target[k])
                    if self.n_intervals[k]:
                        extra = f"+{int(self.n_intervals[k]) - 1}" if self.n_intervals[k] > 1 else ""
                        items.append(f"{j}[{self.lo[k]:.4f},{self.hi[k]:.4f}]{extra}")
                    else:
                        items.append(f"{j}")
            line, lines = head, []
            for item in items:
                if len(line) + 1 + len(item) > width:
                    lines.append(line)
                    line = " " * len(head)
                line += " " + item
            lines.append(line)
            buffer.write("\n".join(lines) + "\n")
        return buffer.getvalue()

    def to_graphml(self, *, safe: bool | None = None) -> str:
        """GraphML text: nodes with ``edge``, ``t0``, ``t1``; arcs with ``transition``, ``phi`` and, when
        ``safe``, ``safe_lo``/``safe_hi`` (absent without safe headings) and ``safe_set`` (JSON text)."""
        import json

        import networkx as nx  # here, not at the top: only this conversion needs it

        safe = self.labelled if safe is None else safe
        g = nx.DiGraph()
        for s in self.partition.segments:
            g.add_node(s.id, edge=int(s.edge), t0=float(s.t0), t1=float(s.t1))
        names = self.transitions
        off = self.set_offsets
        for k in range(self.n_arcs):
            attrs = {"transition": names[k], "phi": float(self.phi[k])}
            if safe:
                if self.n_intervals[k]:
                    attrs["safe_lo"] = float(self.lo[k])
                    attrs["safe_hi"] = float(self.hi[k])
                attrs["safe_set"] = json.dumps([[float(self.set_lo[r]), float(self.set_hi[r])] for r in range(int(off[k]), int(off[k + 1]))])
            g.add_edge(int(self.source[k]), int(self.target[k]), **attrs)
        return "\n".join(nx.generate_graphml(g)) + "\n"

    def to_dot(self, *, safe: bool | None = None) -> str:
        """Graphviz DOT text; safe arcs are solid and labelled ``[lo, hi]``, the others dashed and grey."""
        safe = self.labelled if safe is None else safe
        out = io.StringIO()
        name = self.partition.env.name.replace('"', "'")
        out.write(f'digraph "bvg {html.escape(name)}" {{\n  node [shape=circle, fontsize=10];\n')
        for s in self.partition.segments:
            out.write(f'  {s.id} [tooltip="e{s.edge} t=[{float(s.t0):.4g}, {float(s.t1):.4g}]"];\n')
        names = self.transitions
        for k in range(self.n_arcs):
            i, j = int(self.source[k]), int(self.target[k])
            if safe and self.n_intervals[k]:
                label = f"[{self.lo[k]:.3f}, {self.hi[k]:.3f}]"
                if self.n_intervals[k] > 1:
                    label += f" +{int(self.n_intervals[k]) - 1}"
                out.write(f'  {i} -> {j} [label="{label}", transition={names[k]}];\n')
            elif safe:
                out.write(f'  {i} -> {j} [style=dashed, color=gray70, transition={names[k]}];\n')
            else:
                out.write(f"  {i} -> {j} [transition={names[k]}];\n")
        out.write("}\n")
        return out.getvalue()


# ---------------------------------------------------------------------------------------------
# construction
# ---------------------------------------------------------------------------------------------
def bounce_visibility_graph(partition: Partition | Environment) -> nx.DiGraph:
    """The bounce visibility graph of P′ (paper §4), as a :class:`networkx.DiGraph` on segment ids.

    An arc i → j whenever the open segments i and j see each other (Def. 5).

    Parameters
    ----------
    partition
        The partition P′ (:func:`~solverplan.bounce.partition.partition`), or an environment (it is partitioned
        first).

    Returns
    -------
    networkx.DiGraph
        Node attributes ``edge``, ``t0``, ``t1`` (the segment's edge and boundary parameters, floats in [0, 1]);
        arc attribute ``transition`` (``"right"``, ``"left"`` or ``"parallel"``, Def. 8).

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
    >>> g = bounce_visibility_graph(ell)
    >>> g.number_of_nodes(), g.number_of_edges()
    (8, 40)
    >>> g.has_edge(0, 1), g.has_edge(3, 4), g.has_edge(2, 3)   # one edge; the reflex corner; a convex one
    (False, False, True)
    """
    import networkx as nx  # here, not at the top: the safe BVG itself is numpy only

    safe = safe_bounce_visibility_graph(partition)
    g = nx.DiGraph(name=f"BVG of {safe.partition.env.name!r}")
    for s in safe.partition.segments:
        g.add_node(s.id, edge=s.edge, t0=float(s.t0), t1=float(s.t1))
    names = safe.transitions
    g.add_edges_from(
        (int(i), int(j), {"transition": names[k]}) for k, (i, j) in enumerate(zip(safe.source.tolist(), safe.target.tolist()))
    )
    return g


def safe_bounce_visibility_graph(partition: Partition | Environment) -> SafeBVG:
    """The safe bounce visibility graph of P′ (paper §5, MKSAFEBVG, with exact safe sets).

    Parameters
    ----------
    partition
        The partition P′ (:func:`~solverplan.bounce.partition.partition`), or an environment (it is partitioned
        first).

    Returns
    -------
    SafeBVG
        The arcs of the BVG as numpy arrays, each with its widest safe interval (radians), its number of safe
        intervals, its transition side and φ.

    Raises
    ------
    GraphTooLarge
        When the graph's estimated memory exceeds the limit (an :class:`~solverplan.errors.InputError`).

    Notes
    -----
    Every arc of the BVG carries the exact set of safe headings (radians, CCW from the source
    segment's direction), its widest interval, the transition side (Def. 8) and φ_ij. See the module
    docstring for the algorithm and its proof; the safe sets equal
    :func:`solverplan.bounce.safe.safe_set` for every pair. Accepts an environment too.

    Built graphs are reused: the last few of this process are kept in memory, keyed by the
    partition's exact content (:func:`~solverplan.bounce._cache.partition_digest`: the rings and every
    segment's exact ``(edge, t0, t1)``, so a partition refined at extra cut points has its own graph),
    and on disk when a cache directory is set
    (:func:`set_graph_cache`; the command line keeps one, see docs/contract.md).
    A reused graph is the same answer (equal arrays), with ``stats["cached"]`` set when it was read
    from disk; its arrays are read-only, shared by every caller.

    Memory follows the output: the graph is a structure of arrays (about 110 bytes per arc), and
    the build's peak is under 200 bytes per arc (see ``benchmarks/README.md``). Before building a
    large graph its size is estimated from a sample of the sweeps; a graph that would need more
    memory than the limit (:func:`solverplan.limits.set_memory_limit`, by default half the memory available) is
    refused up front with :class:`GraphTooLarge`, naming the estimate.

    Examples
    --------
    >>> import solverplan as sp
    >>> g = sp.safe_bounce_visibility_graph(sp.load_environment("l_shape"))
    >>> g.n_segments, g.n_arcs, g.n_safe_arcs     # P′ has 10 segments; 34 of the 58 arcs have a safe heading
    (10, 58, 34)
    >>> g.safe_set(0, 3).interval                 # segment 0 (on edge 0) → segment 3 (edge 1): radians
    Interval(lo=0.0, hi=0.3805063771123649)
    >>> g.safe_set(0, 5).interval.is_empty        # edge 3 is seen from segment 0, but no heading is safe
    True
    """
    import time

    plain = isinstance(partition, Environment)  # P′ made here: later calls with the environment find it
    if isinstance(partition, Environment):
        found = _cache.lookup_environment(partition)
        if found is not None:
            return found
    p = _as_partition(partition)
    digest = _cache.partition_digest(p)  # the key: the partition's exact content (no rebuild to check it)
    found = _cache.lookup(p, digest, plain=plain)
    if found is not None:
        return found
    check_graph_memory(p)
    t0 = time.perf_counter()
    graph = _build(p)
    return _cache.store(p, digest, graph, time.perf_counter() - t0, plain=plain)


def _build(p: Partition, sources: np.ndarray | None = None, context: _sweep._Context | None = None) -> SafeBVG:
    """Build the safe BVG of ``p`` (no cache, no size check).

    With ``sources`` (segment ids), only the arcs leaving them that have a safe heading: their safe sets need only
    the sweeps at the two ends of each source (module docstring, step 3), so the work is that of those sweeps. The
    rows are those of the whole graph's arcs from ``sources`` with ``n_intervals > 0``, equal arrays
    (:func:`reachable_safe_graph`; a property test compares them)."""
    import time

    env = p.env
    N = len(p.segments)
    t0 = time.perf_counter()
    ctx = context if context is not None else _sweep._Context(p)
    sw = build_sweeps(p, sources, ctx)
    t1 = time.perf_counter()
    n_sweeps, n_entries = len(sw.origin), len(sw.seg)
    sweep_checks, sweep_casts = sw.exact_checks, sw.exact_casts
    exact = ctx.exact  # the points of P′ as homogeneous integers, with the exact edge vectors
    ends = _Ends(exact)
    seg_edge = np.asarray(p.seg_edge, dtype=np.int64)
    wanted = None
    if sources is not None:
        wanted = np.zeros(N, dtype=bool)
        wanted[np.asarray(sources, dtype=np.int64)] = True

    # ---- roles: entries of "+" sweeps belong to the segment starting at the origin (x = a),
    # entries of "−" sweeps to the segment ending there (x = b)
    e_plus = sw.plus_seg[sw.sweep]
    ia = np.flatnonzero(e_plus >= 0)
    if wanted is not None:  # a sweep at a vertex serves the segments on both sides: keep the wanted role only
        ia = ia[wanted[e_plus[ia]]]
    A_key = e_plus[ia] * N + sw.seg[ia]
    del e_plus
    e_minus = sw.minus_seg[sw.sweep]
    ib = np.flatnonzero(e_minus >= 0)
    if wanted is not None:
        ib = ib[wanted[e_minus[ib]]]
    B_key = e_minus[ib] * N + sw.seg[ib]
    del e_minus

    if wanted is None:
        # ---- arcs: every pair met by some sweep, both directions
        keys = np.concatenate([A_key, B_key])
        keys = np.concatenate([keys, (keys % N) * N + keys // N])
        keys.sort()
        if len(keys):
            keys = keys[np.concatenate([[True], keys[1:] != keys[:-1]])]
    else:  # ---- arcs that may be safe: met by the sweeps at both ends of the source
        keys = np.intersect1d(A_key, B_key)
    source, target = keys // N, keys % N
    n_arcs = len(keys)

    # ---- candidate safe sets: A_a(j) ∩ A_b(j) (closures), a sort-merge join on (i, j)
    oa = np.argsort(A_key, kind="stable")
    ob = np.argsort(B_key, kind="stable")
    ia, ib, A_key, B_key = ia[oa], ib[ob], A_key[oa], B_key[ob]
    del oa, ob
    b_start = np.searchsorted(B_key, A_key, side="left")
    cnt = np.searchsorted(B_key, A_key, side="right") - b_start
    pa = np.repeat(ia, cnt)
    pb = ib[np.repeat(b_start, cnt) + ragged_arange(cnt)]
    pkey = np.repeat(A_key, cnt)
    del ia, ib, A_key, B_key, b_start, cnt
    frm = sw.origin[sw.sweep]
    edge_p = seg_edge[pkey // N]
    c_lo = ends.cmp(edge_p, frm[pa], sw.lo_to[pa], sw.lo[pa], sw.lo_err[pa], frm[pb], sw.lo_to[pb], sw.lo[pb], sw.lo_err[pb])
    lo_pick = np.where(c_lo >= 0, pa, pb)
    del c_lo
    c_hi = ends.cmp(edge_p, frm[pa], sw.hi_to[pa], sw.hi[pa], sw.hi_err[pa], frm[pb], sw.hi_to[pb], sw.hi[pb], sw.hi_err[pb])
    hi_pick = np.where(c_hi <= 0, pa, pb)
    del c_hi, pa, pb, edge_p
    pieces = _Pieces(
        np.searchsorted(keys, pkey),
        frm[lo_pick], sw.lo_to[lo_pick], sw.lo[lo_pick], sw.lo_err[lo_pick],
        frm[hi_pick], sw.hi_to[hi_pick], sw.hi[hi_pick], sw.hi_err[hi_pick],
    )
    del pkey, lo_pick, hi_pick, frm
    # the entries are consumed: keep only what the hole step reads
    sw.sweep = sw.seg = sw.lo_to = sw.hi_to = sw.lo = sw.hi = sw.lo_err = sw.hi_err = None  # type: ignore[assignment]
    step("safe BVG: safe sets", 1, 4)
    edge_of = seg_edge[source]
    pieces = _nonempty(pieces, ends, edge_of)

    # ---- holes lying strictly inside every swept region of a range of headings
    if len(env.rings) > 1 and len(pieces.arc):
        pieces = _subtract_holes(p, sw, pieces, ends, source, target, edge_of)
    del sw

    # ---- single points: closures may add isolated points; check them exactly
    step("safe BVG: safe sets", 2, 4)
    single = _singletons(pieces, ends, edge_of)
    n_single = int(np.count_nonzero(single))
    if n_single:
        rows = np.flatnonzero(single)
        ok = _single_headings_safe(p, exact, source, target, pieces.take(rows), edge_of)
        keep = np.ones(len(pieces.arc), dtype=bool)
        keep[rows[~ok]] = False
        pieces = pieces.take(np.flatnonzero(keep))
    del single
    _refine_ends(p, pieces, edge_of)
    t2 = time.perf_counter()

    # ---- per arc: all intervals (sorted), the widest one
    if not _sorted_by_arc_lo(pieces):
        pieces = pieces.take(np.lexsort((pieces.lo, pieces.arc)))
    counts = np.bincount(pieces.arc, minlength=n_arcs).astype(np.int64)
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    # exact ends: an end at a frame mark is exactly 0 or π; equal exact ends share one float
    set_lo = np.where(pieces.lo_to == MARK_ZERO, 0.0, pieces.lo)
    set_hi = np.where(pieces.hi_to == MARK_PI, math.pi, pieces.hi)
    equal = _equal_ends(pieces, ends, edge_of)
    set_hi = np.where(equal, set_lo, np.maximum(set_hi, set_lo))
    del equal
    lo = np.full(n_arcs, np.nan)
    hi = np.full(n_arcs, np.nan)
    if len(pieces.arc):
        # widest per arc (the first of equal widths): an arc's only interval, or among several
        # the first of the largest width
        one = counts[pieces.arc] == 1
        r1 = np.flatnonzero(one)
        lo[pieces.arc[r1]] = set_lo[r1]
        hi[pieces.arc[r1]] = set_hi[r1]
        rm = np.flatnonzero(~one)
        if len(rm):
            width = set_hi[rm] - set_lo[rm]
            arc_m = pieces.arc[rm]
            o2 = np.lexsort((-width, arc_m))
            firsts = rm[o2[np.concatenate([[True], arc_m[o2][1:] != arc_m[o2][:-1]])]]
            lo[pieces.arc[firsts]] = set_lo[firsts]
            hi[pieces.arc[firsts]] = set_hi[firsts]
        del one, r1, rm
    set_ends = (pieces.lo_from, pieces.lo_to, pieces.hi_from, pieces.hi_to)
    del pieces

    # ---- transitions and φ (they depend on the two edges only)
    step("safe BVG: safe sets", 3, 4)
    transition, phi = _transitions(env, seg_edge[source], seg_edge[target])
    t3 = time.perf_counter()
    stats = {
        "sweeps": n_sweeps,
        "entries": n_entries,
        "seconds_sweeps": t1 - t0,
        "seconds_join": t2 - t1,
        "seconds_total": t3 - t0,
        "exact_checks": sweep_checks + ends.checks,
        "exact_casts": sweep_casts,
        "singletons_checked": n_single,
    }
    logger.debug("safe BVG of %r: %s", env.name, stats)
    if wanted is not None:  # only the arcs with a safe heading
        keep = np.flatnonzero(counts > 0)
        take = np.repeat(offsets[keep], counts[keep]) + ragged_arange(counts[keep])
        source, target, lo, hi, counts = source[keep], target[keep], lo[keep], hi[keep], counts[keep]
        transition, phi = transition[keep], phi[keep]
        set_lo, set_hi = set_lo[take], set_hi[take]
        set_ends = tuple(a[take] for a in set_ends)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    return SafeBVG(
        partition=p,
        source=source.astype(np.int64),
        target=target.astype(np.int64),
        lo=lo,
        hi=hi,
        n_intervals=counts,
        set_offsets=offsets,
        set_lo=set_lo,
        set_hi=set_hi,
        transition=transition,
        phi=phi,
        _set_ends=set_ends,
        stats=stats,
    )


LAZY_MIN_ARCS = 2_000_000
"""Planners build only the reachable safe arcs (:func:`reachable_safe_graph`) when the whole safe BVG is estimated
to have at least this many arcs (and is not cached): below it the whole graph builds in a few seconds."""


def reachable_safe_graph(partition: Partition | Environment, start: np.ndarray | list[int], *,
                         max_depth: int | None = None) -> SafeBVG:
    """The part of the safe BVG a search from the segments ``start`` can use: every arc with a safe heading leaving a
    segment reachable from ``start`` by such arcs (within ``max_depth`` arcs when given: the sources at depths
    0 … max_depth − 1), built on demand layer by layer.

    The safe set of an arc needs only the sweeps at the two ends of its source, so each layer costs the sweeps of
    its new segments (vectorised, in batches sized to the entries they produce), not the whole graph's. The rows are
    exactly the whole graph's rows of those sources with a safe heading (equal arrays: a property test compares
    them), so a search over it gives the same answers; arcs without a safe heading, and those of unreachable
    sources, are left out. ``stats`` says how many sources and sweeps were built (``"reachable_sources"``).

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
    >>> whole, part = safe_bounce_visibility_graph(ell), reachable_safe_graph(ell, [0], max_depth=1)
    >>> part.source.tolist() == [0] * part.n_arcs, part.n_arcs == int(whole.select(source=0).safe.sum())
    (True, True)
    >>> reachable_safe_graph(ell, [0]).n_safe_arcs == whole.n_safe_arcs   # every segment is reachable here
    True
    """
    import time

    p = _as_partition(partition)
    N = len(p.segments)
    frontier = np.unique(np.asarray(start, dtype=np.int64))
    if len(frontier) and not (0 <= frontier[0] and frontier[-1] < N):
        raise InvalidBoundarySet(f"start segments must be in 0..{N - 1}")
    t0 = time.perf_counter()
    ctx = _sweep._Context(p)
    seen = np.zeros(N, dtype=bool)
    parts: list[SafeBVG] = []
    batch, depth, sweeps, kept = 64, 0, 0, 0
    limit, limit_source = memory_limit()
    while len(frontier) and (max_depth is None or depth < max_depth):
        seen[frontier] = True
        found = []
        for b0 in range(0, len(frontier), batch):
            step("safe BVG: reachable part", int(seen.sum()) - len(frontier) + b0, N)
            chunk = frontier[b0:b0 + batch]
            g = _build(p, chunk, ctx)
            parts.append(g)
            found.append(g.target)
            kept += g.n_arcs
            if limit is not None and _BASE_BYTES + PLANNED_BYTES_PER_ARC * kept > limit:
                _refuse_reachable(p, kept, int(seen.sum()), limit, limit_source)
            sweeps += g.stats["sweeps"]
            # next batch: about 2²⁰ sweep entries (≈ 200 MB of temporaries at the build's peak)
            per_source = max(1.0, g.stats["entries"] / len(chunk))
            batch = int(min(8192, max(8, (1 << 20) / per_source)))
        targets = np.unique(np.concatenate(found)) if found else np.zeros(0, dtype=np.int64)
        frontier = targets[~seen[targets]]
        depth += 1
    graph = _concat_rows(p, parts)
    graph.stats.update({"reachable_sources": int(seen.sum()), "sweeps": sweeps, "layers": depth,
                        "seconds_total": time.perf_counter() - t0, "lazy": True})
    return graph


PLANNED_BYTES_PER_ARC = 400
"""Memory per safe arc a query keeps (bytes): the graph's arrays, and the planner's admissible intervals (Python
lists of floats per source) — what :func:`reachable_safe_graph` checks against the memory limit as it grows."""


def _refuse_reachable(p: Partition, kept: int, sources: int, limit: int, source: str) -> None:
    """Raise :class:`GraphTooLarge` for a reachable part that outgrew the memory limit, naming a simplification."""
    arcs = estimate_graph(p)[0]
    name = p.env.name if len(p.env.name) <= 30 else p.env.name[:29] + "…"
    hint = fitting_simplification(p.env, arcs, limit)
    advice = f"; --simplify {hint[0]:g} at import would fit (≈ {hint[1]:,} vertices)" if hint is not None else ""
    raise GraphTooLarge(f"the safe arcs a query reaches in {name!r} outgrew {source} ({_gib(limit)}) after "
                        f"{kept:,} arcs from {sources:,} of {len(p.segments):,} segments{advice}")


def _concat_rows(p: Partition, parts: list[SafeBVG]) -> SafeBVG:
    """One graph of the arcs of ``parts`` (disjoint sources), sorted by (source, target)."""
    cat = lambda name: np.concatenate([getattr(g, name) for g in parts]) if parts else np.zeros(0)  # noqa: E731
    source = cat("source").astype(np.int64)
    target = cat("target").astype(np.int64)
    counts = cat("n_intervals").astype(np.int64)
    order = np.lexsort((target, source))
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    take = np.repeat(offsets[:-1][order], counts[order]) + ragged_arange(counts[order])
    counts = counts[order]
    ends = tuple(np.concatenate([g._set_ends[t] for g in parts])[take] if parts else np.zeros(0, dtype=np.int64)
                 for t in range(4))
    return SafeBVG(partition=p, source=source[order], target=target[order], lo=cat("lo")[order], hi=cat("hi")[order],
                   n_intervals=counts, set_offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
                   set_lo=cat("set_lo")[take], set_hi=cat("set_hi")[take],
                   transition=cat("transition").astype(np.int8)[order], phi=cat("phi")[order],
                   _set_ends=ends, stats={})  # type: ignore[arg-type]


def _refine_ends(p: Partition, pieces: _Pieces, edge_of: np.ndarray) -> None:
    """Recompute, from the exact coordinates, the float headings of the ends whose error bound exceeds
    :data:`~solverplan.bounce._sweep.REFINE` (directions between points far from 0 relative to their
    distance: tiny features, or a translated environment), so that every float end is the angle of
    its exact end direction to about 1e-16 (the comparisons made so far were exact where unsure)."""
    for which in ("lo", "hi"):
        to, err = getattr(pieces, f"{which}_to"), getattr(pieces, f"{which}_err")
        rows = np.flatnonzero((err > _sweep.REFINE) & (to >= 0))
        if len(rows):
            values = getattr(pieces, which).copy()
            values[rows] = _sweep.accurate_headings(p, edge_of[pieces.arc[rows]],
                                                    getattr(pieces, f"{which}_from")[rows], to[rows])
            setattr(pieces, which, values)


def _sorted_by_arc_lo(pieces: _Pieces) -> bool:
    """Are the pieces already in (arc, lo) order? (Then sorting them would change nothing.)"""
    arc, lo = pieces.arc, pieces.lo
    if len(arc) < 2:
        return True
    d = np.diff(arc)
    return bool((d >= 0).all() and (lo[1:][d == 0] >= lo[:-1][d == 0]).all())


def _edge_vectors(env: Environment) -> list[tuple[Fraction, Fraction]]:
    verts, nv = env.exact_vertices, env.next_vertex
    return [(verts[int(nv[e])][0] - verts[e][0], verts[int(nv[e])][1] - verts[e][1]) for e in range(env.n_edges)]


def _cmp_ends(pieces: _Pieces, ends: _Ends, edge_of: np.ndarray, which1: str, which2: str) -> np.ndarray:
    g = lambda w, name: getattr(pieces, f"{w}_{name}")  # noqa: E731
    return ends.cmp(edge_of[pieces.arc], g(which1, "from"), g(which1, "to"), getattr(pieces, which1), g(which1, "err"),
                    g(which2, "from"), g(which2, "to"), getattr(pieces, which2), g(which2, "err"))


def _nonempty(pieces: _Pieces, ends: _Ends, edge_of: np.ndarray) -> _Pieces:
    """Keep pieces with lo ≤ hi (exactly)."""
    if not len(pieces.arc):
        return pieces
    c = _cmp_ends(pieces, ends, edge_of, "lo", "hi")
    return pieces.take(np.flatnonzero(c <= 0))


def _single_headings_safe(p: Partition, exact: ExactPoints, source, target, sp: _Pieces, edge_of) -> np.ndarray:
    """Exactly: is the single heading of each piece safe? (Module docstring, step 3.)

    The heading u is in the closure of the landing sets from a and b, so its landing points L_a, L_b
    lie on [c, d]; it is safe iff no boundary edge meets the open swept region R = conv(a, b, L_b, L_a)
    (:mod:`solverplan.bounce.safe`, proof (1)). Edges are tested against R with the separating-axis
    test: a float pass with a margin settles almost all (edge, region) pairs, the rest are decided in
    exact integer arithmetic on homogeneous coordinates.
    """
    env = p.env
    S = len(sp.arc)
    k = sp.arc
    i, j = source[k], target[k]
    nxt = np.asarray(p.next_segment, dtype=np.int64)
    ia, ib, jc, jd = i, nxt[i], j, nxt[j]  # P′ ids of a, b, c, d
    # exact region corners (homogeneous integers) and their floats
    corners = []
    for r in range(S):
        u = exact.direction(int(sp.lo_from[r]), int(sp.lo_to[r]), int(edge_of[k[r]]))
        A, B, C, D = (exact.point(int(x)) for x in (ia[r], ib[r], jc[r], jd[r]))
        line_cd = _hcross(C, D)
        La = A if _on_line(line_cd, A) else _hmeet(_hcross(A, _hshift(A, u)), line_cd)
        Lb = B if _on_line(line_cd, B) else _hmeet(_hcross(B, _hshift(B, u)), line_cd)
        quad = [A, B, Lb, La]
        quad = [q for t, q in enumerate(quad) if not _hsame(q, quad[t - 1])]  # a shared corner: a triangle
        corners.append(quad)
    n_e = env.n_edges
    E0, E1 = env.edge_start, env.edge_end
    verts_h = [exact.point(int(x)) for x in _orig_pv(p)]
    nv = np.asarray(env.next_vertex, dtype=np.int64)
    seg_edge = np.asarray(p.seg_edge, dtype=np.int64)
    scale = float(np.max(np.abs(env.vertices))) + 1.0
    tol = _SAT_REL * scale * scale
    # float corners, triangles padded by repeating their last corner (a zero side is ignored)
    Q = np.empty((S, 4, 2))
    live = np.ones((S, 4), dtype=bool)
    for r, quad in enumerate(corners):
        pts = [(q[0] / q[2], q[1] / q[2]) for q in quad]
        if len(pts) == 3:
            pts.append(pts[-1])
            live[r, 2] = False  # side from corner 2 to the repeated corner 3
        Q[r] = pts
    ok = np.ones(S, dtype=bool)
    block = max(1, (1 << 20) // max(n_e, 1))
    for s0 in range(0, S, block):
        sl = slice(s0, min(S, s0 + block))
        q = Q[sl]
        lv = live[sl]
        m = len(q)
        sep = np.zeros((m, n_e), dtype=bool)
        inside_all = np.ones((m, n_e), dtype=bool)  # certainly not separated by any side
        for t in range(4):
            q0, q1 = q[:, t, :], q[:, (t + 1) % 4, :]
            d = q1 - q0
            o0 = d[:, None, 0] * (E0[None, :, 1] - q0[:, None, 1]) - d[:, None, 1] * (E0[None, :, 0] - q0[:, None, 0])
            o1 = d[:, None, 0] * (E1[None, :, 1] - q0[:, None, 1]) - d[:, None, 1] * (E1[None, :, 0] - q0[:, None, 0])
            on = lv[:, t][:, None]
            sep |= on & (o0 < -tol) & (o1 < -tol)
            inside_all &= ~on | (np.maximum(o0, o1) > tol)
        dE = E1 - E0
        oq = dE[None, :, None, 0] * (q[:, None, :, 1] - E0[None, :, None, 1]) - dE[None, :, None, 1] * (q[:, None, :, 0] - E0[None, :, None, 0])
        sep |= (oq > tol).all(axis=2) | (oq < -tol).all(axis=2)
        split = (oq > tol).any(axis=2) & (oq < -tol).any(axis=2)
        rows = np.arange(s0, s0 + m)
        skip = np.zeros((m, n_e), dtype=bool)
        skip[np.arange(m), seg_edge[i[rows]]] = True
        skip[np.arange(m), seg_edge[j[rows]]] = True
        hit = inside_all & split & ~skip & ~sep
        ok[rows[hit.any(axis=1)]] = False
        unsure = ~sep & ~skip & ~hit
        unsure[~ok[rows]] = False
        for rr, e in zip(*np.nonzero(unsure)):
            r = s0 + int(rr)
            if ok[r] and _meets_open_convex(corners[r], verts_h[e], verts_h[int(nv[e])]):
                ok[r] = False
    return ok


def _orig_pv(p: Partition) -> np.ndarray:
    return np.searchsorted(np.asarray(p.seg_edge), np.arange(p.env.n_edges), side="left")


def _hcross(p, q):
    """Homogeneous cross product: the line through two points, or the meeting point of two lines."""
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def _hmeet(l1, l2):
    x, y, w = _hcross(l1, l2)
    return (-x, -y, -w) if w < 0 else (x, y, w)


def _hshift(p, u):
    return (p[0] + u[0] * p[2], p[1] + u[1] * p[2], p[2])


def _on_line(line, p) -> bool:
    return line[0] * p[0] + line[1] * p[1] + line[2] * p[2] == 0


def _hsame(p, q) -> bool:
    return p[0] * q[2] == q[0] * p[2] and p[1] * q[2] == q[1] * p[2]


def _horient(p, q, r) -> int:
    """Exact orientation of three homogeneous points with positive weights."""
    det = (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0]))
    return (det > 0) - (det < 0)


def _meets_open_convex(quad, s0, s1) -> bool:
    """Does the closed segment s0s1 meet the interior of the convex CCW polygon ``quad``? Exact
    (separating axes: the polygon's sides and the segment's line)."""
    m = len(quad)
    for t in range(m):
        if _horient(quad[t], quad[(t + 1) % m], s0) <= 0 and _horient(quad[t], quad[(t + 1) % m], s1) <= 0:
            return False
    signs = {_horient(s0, s1, q) for q in quad}
    return 1 in signs and -1 in signs


def _singletons(pieces: _Pieces, ends: _Ends, edge_of: np.ndarray) -> np.ndarray:
    if not len(pieces.arc):
        return np.zeros(0, dtype=bool)
    return _cmp_ends(pieces, ends, edge_of, "lo", "hi") == 0


def _equal_ends(pieces: _Pieces, ends: _Ends, edge_of: np.ndarray) -> np.ndarray:
    return _singletons(pieces, ends, edge_of)


def _hole_side_table(p: Partition) -> np.ndarray:
    """S[e, h]: hole h lies strictly left of the line of edge e (the free side), exact near ties."""
    env = p.env
    H = len(env.rings) - 1
    A = env.edge_start
    d = _sweep.float_edge_vectors(env)  # accurate to rounding: the tolerance below assumes it
    scale = float(np.max(np.abs(env.vertices))) + 1.0
    out = np.zeros((env.n_edges, H), dtype=bool)
    verts = env.exact_vertices
    nv = env.next_vertex
    for h in range(H):
        lo, hi = env.ring_offsets[h + 1], env.ring_offsets[h + 2]
        V = env.vertices[lo:hi]
        rel = V[None, :, :] - A[:, None, :]
        cr = d[:, None, 0] * rel[..., 1] - d[:, None, 1] * rel[..., 0]
        tol = 0.1 * _sweep.CROSS_REL * _ninf(d)[:, None] * (_ninf(rel) + scale)
        sure_left = cr > tol
        unsure = np.abs(cr) <= tol
        left = sure_left.all(axis=1)
        maybe = ~left & (sure_left | unsure).all(axis=1)
        for e in np.flatnonzero(maybe).tolist():
            a, b = verts[e], verts[int(nv[e])]
            ok = True
            for w in range(lo, hi):
                q = verts[w]
                if (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]) <= 0:
                    ok = False
                    break
            left[e] = ok
        out[:, h] = left
    return out


def _subtract_holes(p: Partition, sw: Sweeps, pieces: _Pieces, ends: _Ends, source, target, edge_of) -> _Pieces:
    """Remove, for every hole H strictly left of the lines of e_i and e_j, the open heading interval
    (max ang(v − a), min ang(v − b)) during which all of H lies inside the swept region."""
    # build_sweeps sets the hole arrays whenever the environment has holes (the only case we are called)
    assert sw.hole_alpha is not None and sw.hole_alpha_v is not None
    assert sw.hole_beta is not None and sw.hole_beta_v is not None
    seg_edge = np.asarray(p.seg_edge, dtype=np.int64)
    side = _hole_side_table(p)
    N = len(p.segments)
    # the sweep of each segment's "+" end (at a) and "−" end (at b)
    plus_of = np.full(N, -1, dtype=np.int64)
    minus_of = np.full(N, -1, dtype=np.int64)
    ok = sw.plus_seg >= 0
    plus_of[sw.plus_seg[ok]] = np.flatnonzero(ok)
    ok = sw.minus_seg >= 0
    minus_of[sw.minus_seg[ok]] = np.flatnonzero(ok)
    H = side.shape[1]
    for h in range(H):
        step("safe BVG: holes", h, H)
        arc = pieces.arc
        i, j = source[arc], target[arc]
        applies = side[seg_edge[i], h] & side[seg_edge[j], h]
        rows = np.flatnonzero(applies)
        if not len(rows):
            continue
        ma, mb = plus_of[i[rows]], minus_of[i[rows]]
        a_id, b_id = sw.origin[ma], sw.origin[mb]
        bl, bl_to = sw.hole_alpha[ma, h], sw.hole_alpha_v[ma, h]
        bh, bh_to = sw.hole_beta[mb, h], sw.hole_beta_v[mb, h]
        eg = edge_of[arc[rows]]
        # blocked error bounds: recompute with the angle filter's scale (cheap, conservative)
        berr = _angle_err(p, a_id, bl_to)
        herr = _angle_err(p, b_id, bh_to)
        sub = pieces.take(rows)
        c_open = ends.cmp(eg, a_id, bl_to, bl, berr, b_id, bh_to, bh, herr)  # bl < bh: a real interval
        c1 = ends.cmp(eg, a_id, bl_to, bl, berr, sub.hi_from, sub.hi_to, sub.hi, sub.hi_err)  # bl < hi
        c2 = ends.cmp(eg, b_id, bh_to, bh, herr, sub.lo_from, sub.lo_to, sub.lo, sub.lo_err)  # bh > lo
        hit = (c_open < 0) & (c1 < 0) & (c2 > 0)
        if not hit.any():
            continue
        hit_rows = rows[hit]
        untouched = np.ones(len(arc), dtype=bool)
        untouched[hit_rows] = False
        hs = pieces.take(hit_rows)
        hb = np.flatnonzero(hit)
        # left piece [lo, bl] if lo <= bl; right piece [bh, hi] if bh <= hi
        cl = ends.cmp(eg[hb], hs.lo_from, hs.lo_to, hs.lo, hs.lo_err, a_id[hb], bl_to[hb], bl[hb], berr[hb])
        cr = ends.cmp(eg[hb], b_id[hb], bh_to[hb], bh[hb], herr[hb], hs.hi_from, hs.hi_to, hs.hi, hs.hi_err)
        left = hs.take(np.flatnonzero(cl <= 0))
        lk = np.flatnonzero(cl <= 0)
        left.hi_from, left.hi_to, left.hi, left.hi_err = a_id[hb][lk], bl_to[hb][lk], bl[hb][lk], berr[hb][lk]
        right = hs.take(np.flatnonzero(cr <= 0))
        rk = np.flatnonzero(cr <= 0)
        right.lo_from, right.lo_to, right.lo, right.lo_err = b_id[hb][rk], bh_to[hb][rk], bh[hb][rk], herr[hb][rk]
        pieces = _Pieces.concat([pieces.take(np.flatnonzero(untouched)), left, right])
    return pieces


def _angle_err(p: Partition, frm: np.ndarray, to: np.ndarray) -> np.ndarray:
    P = np.asarray(p.seg_start, dtype=float)
    rel = P[to] - P[frm]
    mag = _ninf(P[frm]) + _ninf(P[to])
    return _sweep.ANGLE_REL * mag / np.hypot(rel[:, 0], rel[:, 1]) + 1e-15


def _transitions(env: Environment, ei: np.ndarray, ej: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Def. 8 side (+1 right, −1 left, 0 parallel; exact) and φ (radians) for edge pairs (in blocks:
    a dozen temporaries per pair)."""
    side = np.empty(len(ei), dtype=np.int8)
    phi = np.empty(len(ei))
    block = 1 << 19
    for s0 in range(0, len(ei), block):
        side[s0 : s0 + block], phi[s0 : s0 + block] = _transitions_block(env, ei[s0 : s0 + block], ej[s0 : s0 + block])
    return side, phi


def _transitions_block(env: Environment, ei: np.ndarray, ej: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    d = _sweep.float_edge_vectors(env)  # accurate to rounding (φ of a short edge far from 0 too)
    u, v = d[ei], d[ej]
    cr = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dt = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
    scale = float(np.max(np.abs(env.vertices))) + 1.0
    tol = 0.1 * _sweep.CROSS_REL * (_ninf(u) * scale + _ninf(v) * scale)
    side = np.sign(cr).astype(np.int8)
    unsure = np.flatnonzero(np.abs(cr) <= tol)
    if len(unsure):
        vec = _edge_vectors(env)
        cache: dict[tuple[int, int], int] = {}
        for k in unsure.tolist():
            key = (int(ei[k]), int(ej[k]))
            if key not in cache:
                (ax, ay), (bx, by) = vec[key[0]], vec[key[1]]
                c = ax * by - ay * bx
                cache[key] = (c > 0) - (c < 0)
            side[k] = cache[key]
    heading = np.arctan2(cr, dt)  # heading of δ in the frame of e_i, in (−π, π]
    phi = np.where(side > 0, math.pi - heading, np.where(side < 0, heading + math.pi, 0.0))
    return side, phi


# ---------------------------------------------------------------------------------------------
# size limits
# ---------------------------------------------------------------------------------------------
class GraphTooLarge(InputError):
    """The safe BVG of an environment would not fit in the memory limit (raised before building it)."""


BYTES_PER_ARC = 200
"""Peak build memory per arc of the safe BVG (bytes; measured ≈ 175, see ``benchmarks/README.md``)."""
_BASE_BYTES = 150 * 2**20  # the process, the environment and the partition around the graph

def estimate_graph(partition: Partition | Environment) -> tuple[int, int]:
    """(estimated arcs, estimated peak bytes) of the safe BVG of ``partition``, from the sweeps of
    an evenly spaced sample of 256 of its vertices' frames — under a second for the largest inputs.

    The sweeps' entries are counted exactly on the sample and scaled to all sweeps; the arcs are
    0.95 times the entries, as measured where size matters (stars, rooms with many pillars: within
    3 % of the true count). Where each segment is seen whole from both its ends, as in a convex
    room, there are about two entries per arc and the estimate is up to twice too high: it errs on
    the safe side.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> estimate_graph(square)[0]      # 12 arcs, each seen from both ends of its source: 24 entries
    23
    """
    p = _as_partition(partition)
    entries, _ = _sweep.estimate_entries(p)
    arcs = int(round(0.95 * entries))
    return arcs, _BASE_BYTES + BYTES_PER_ARC * entries


def _gib(n: float) -> str:
    return f"{n / 2**30:.1f} GB" if n >= 2**30 else f"{n / 2**20:.0f} MB"


def check_graph_memory(p: Partition, estimate: tuple[int, int] | None = None) -> None:
    """Raise :class:`GraphTooLarge` when the safe BVG of ``p`` is estimated to exceed the memory limit
    (:func:`solverplan.limits.memory_limit`). Free for graphs that would fit even with every pair of segments
    as an arc; otherwise it samples the sweeps (:func:`estimate_graph`), unless the caller has its ``estimate``."""
    limit, source = memory_limit()
    N = len(p.segments)
    if limit is None or _BASE_BYTES + BYTES_PER_ARC * N * (N - 1) <= limit:
        return
    arcs, need = estimate if estimate is not None else estimate_graph(p)
    if need > limit:
        name = p.env.name if len(p.env.name) <= 30 else p.env.name[:29] + "…"
        hint = fitting_simplification(p.env, arcs, limit)
        advice = (f"; --simplify {hint[0]:g} at import would fit (≈ {hint[1]:,} vertices)" if hint is not None
                  else "; see --max-memory")
        raise GraphTooLarge(f"the safe BVG of {name!r} would need ≈ {_gib(need)} (≈ {arcs:,} arcs, {N:,} segments), "
                            f"more than {source} ({_gib(limit)}){advice}")


# Arcs grow about as the fourth power of the vertex count on ragged floor plans (segments of P′ as its square:
# every reflex vertex casts a line through every vertex it sees; arcs as the segments' square), measured on the
# warehouse maps of benchmarks/README.md; a smaller exponent would promise too much of a simplification.
_ARCS_EXPONENT = 4.0


def fitting_simplification(env: Environment, arcs: int, limit: int) -> tuple[float, int] | None:
    """The smallest simplification tolerance (a round number in the environment's units: 1, 2 or 5 × 10^k) after
    which the safe BVG is estimated to fit in ``limit`` bytes, and the vertex count it leaves; None if none does.

    The outline is simplified as the importer does (topology-preserving Douglas–Peucker, :mod:`shapely`), and the
    arcs are extrapolated from ``arcs`` (the estimate for ``env``) by the vertex count to the power 4 — a rule of
    thumb for the message of :class:`GraphTooLarge`, not a promise.

    >>> from solverplan.environment import Environment
    >>> ring = [[x / 10, (x % 2) / 100] for x in range(0, 101)] + [[10, 5], [0, 5]]
    >>> fitting_simplification(Environment.from_coords(ring), arcs=10**9, limit=2**30)
    (0.01, 4)
    """
    import shapely

    n = env.n_vertices
    shape = env.to_shapely()
    lo, hi = shape.bounds[:2], shape.bounds[2:]
    size = max(hi[0] - lo[0], hi[1] - lo[1])
    if not size > 0:
        return None
    step = 10.0 ** math.floor(math.log10(size * 1e-4))
    while step < size / 10:
        for factor in (1, 2, 5):
            tolerance = float(f"{factor * step:.1g}")
            simple = shapely.simplify(shape, tolerance, preserve_topology=True)
            if simple.is_empty or simple.geom_type != "Polygon":
                return None
            m = len(simple.exterior.coords) - 1 + sum(len(r.coords) - 1 for r in simple.interiors)
            if _BASE_BYTES + BYTES_PER_ARC * arcs * (m / n) ** _ARCS_EXPONENT <= limit:
                return tolerance, m
        step *= 10
    return None


