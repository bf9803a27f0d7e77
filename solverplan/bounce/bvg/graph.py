"""The safe BVG as a type: :class:`SafeBVG`, a structure of arrays with one row per arc, and its look-ups.

Its outputs (JSON, text, GraphML, DOT, networkx) are in :mod:`~solverplan.bounce.bvg.serialise`; it is built by
:mod:`~solverplan.bounce.bvg.build`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Iterator

import numpy as np

from solverplan._arrays import ragged_arange
from solverplan.bounce._sweep import MARK_PI, MARK_ZERO
from solverplan.bounce.bvg import serialise
from solverplan.bounce.partitions import Partition, partition as make_partition
from solverplan.bounce.safe import Direction, SafeInterval, SafeSet
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.interval import Interval

if TYPE_CHECKING:  # networkx costs ~0.1 s to import: only the conversions load it
    import networkx as nx

__all__ = ["SafeBVG", "as_partition"]


def as_partition(obj: Partition | Environment) -> Partition:
    """``obj`` if it is a partition P′, else the partition of the environment ``obj``.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> len(as_partition(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])).segments)
    4
    >>> as_partition("square")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: expected a Partition or an Environment, got str
    """
    if isinstance(obj, Partition):
        return obj
    if isinstance(obj, Environment):
        return make_partition(obj)
    raise InputError(f"expected a Partition or an Environment, got {type(obj).__name__}")


@dataclass(frozen=True, eq=False)
class SafeBVG:
    """The bounce visibility graph of P′ with the safe headings of every arc.

    Build it with :func:`~solverplan.bounce.bvg.build.safe_bounce_visibility_graph`. Arcs are stored as numpy arrays of length
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

    >>> from solverplan.bounce.bvg import safe_bounce_visibility_graph
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
        return [serialise.TRANSITION_NAMES[int(s)] for s in self.transition]

    def _check_segment(self, segment: object, name: str = "") -> int:
        n = self.n_segments
        if isinstance(segment, bool) or not isinstance(segment, (int, np.integer)) or not 0 <= int(segment) < n:
            raise InvalidBoundarySet(f"unknown segment {segment!r}: segments are 0..{n - 1}")
        return int(segment)

    def select(self, *, source: int | None = None, heading: float | None = None, safe: bool = True) -> SafeBVG:
        """A copy restricted to the arcs leaving ``source`` and/or the arcs whose safe set contains
        ``heading`` (radians, in (0, π)); ``safe=False`` makes the outputs show the plain BVG.

        >>> from solverplan.bounce.bvg import safe_bounce_visibility_graph
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
            SafeInterval(float(self.set_lo[r]), float(self.set_hi[r]), direction(int(lo_from[r]), int(lo_to[r])),
                         direction(int(hi_from[r]), int(hi_to[r])))
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

    # ------------------------------------------------------------------ outputs (serialise.py)
    def to_networkx(self, *, safe_only: bool = False) -> nx.DiGraph:
        """A :class:`networkx.DiGraph` on the segment ids.

        Node attributes: ``edge``, ``t0``, ``t1`` (floats). Arc attributes: ``safe`` (the widest
        :class:`Interval`, EMPTY if none), ``safe_set`` (tuple of Intervals), ``transition``
        (``"left"``/``"right"``/``"parallel"``), ``phi`` (radians). ``safe_only`` keeps only arcs with
        safe headings (the paper's BVG_safe).
        """
        return serialise.to_networkx(self, safe_only=safe_only)

    def to_json(self, *, safe: bool | None = None) -> dict:
        """The answer of ``solverplan graph`` (docs/contract.md): ``{"arcs": [{"from", "to", "safe": [lo, hi] or null, "transition"}]}``,
        plus ``phi`` and ``safe_set`` (every safe interval; more than one only with holes), and counts.
        With ``safe=False`` (the plain BVG; the default after ``select(safe=False)``) arcs carry only
        ``from``, ``to``, ``transition``."""
        return serialise.to_json(self, safe=safe)

    def json_bytes(self, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 13) -> bytearray:
        """:meth:`to_json` as compact JSON (UTF-8) followed by ``end``, encoded a chunk of arcs at a
        time into one growing buffer: the same bytes as ``orjson.dumps(self.to_json()) + end``,
        without a dict per arc at once nor a second copy of the text (2.4 million arcs: ≈ 0.3 GB
        of text instead of ≈ 2 GB of dicts)."""
        return serialise.json_bytes(self, safe=safe, end=end, arcs_per_chunk=arcs_per_chunk)

    def json_chunks(self, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 13) -> Iterator[bytes]:
        """:meth:`json_bytes` a chunk of arcs at a time, for writing as it is made (``solverplan graph -o``): only one
        chunk's dicts and text exist at once, never the whole text."""
        return serialise.json_chunks(self, safe=safe, end=end, arcs_per_chunk=arcs_per_chunk)

    def to_text(self, *, width: int = 100, safe: bool | None = None) -> str:
        """A summary and one line per segment listing its out-arcs (safe ones with their intervals)."""
        return serialise.to_text(self, width=width, safe=safe)

    def to_graphml(self, *, safe: bool | None = None) -> str:
        """GraphML text: nodes with ``edge``, ``t0``, ``t1``; arcs with ``transition``, ``phi`` and, when
        ``safe``, ``safe_lo``/``safe_hi`` (absent without safe headings) and ``safe_set`` (JSON text)."""
        return serialise.to_graphml(self, safe=safe)

    def to_dot(self, *, safe: bool | None = None) -> str:
        """Graphviz DOT text; safe arcs are solid and labelled ``[lo, hi]``, the others dashed and grey."""
        return serialise.to_dot(self, safe=safe)
