"""Partition of the boundary (paper Algorithm 1): the segments of P′.

For every reflex vertex r (outer ring and holes alike; a hole's convex corners are reflex for the
free space) and every vertex v that r sees, the line from v through r is where a robot sliding along
the boundary sees v appear or disappear behind r. Algorithm 1 shoots the ray from v through r and
inserts its **first hit beyond r** into ∂P; the two edges incident to r are extended the same way
(v = the previous or the next vertex of r). The boundary cut at the original vertices and at every
inserted point is P′; its pieces are the :class:`PartitionSegment` s, numbered in boundary order.

Definitions used here (decided exactly):

- *v is seen from r* when the **closed** segment rv lies in the closed free space (grazing a vertex
  and running along an edge count). Counting the grazing pairs changes nothing: if rv passes through
  a vertex u, then u is seen from r too and lies on the same line, so it produces the same ray.
- *The ray continues beyond r* when the direction r − v points into the **open** free wedge at r,
  i.e. v lies in one of the two wedges beside the obstacle (bounded by the lines of r's edges),
  boundaries towards r's own edges included (those pairs are the edge extensions). When r − v runs
  along an edge of r, the line stays on the boundary: its event is produced at the far vertex of
  that edge (by that vertex's own edge extension, if it is reflex), so nothing is shot from r.
- *The first hit beyond r* is where the boundary first **blocks** the line: the ray goes on past
  vertices it only grazes (and along edges it runs on), and stops where it crosses an edge into the
  obstacle or meets a vertex that blocks it. This is :func:`~solverplan.geometry.raycast.cast_ray`
  with ``through_vertices=True``. A hit on a vertex inserts nothing (the vertex is already a
  partition point); coincident hits are merged (the key is the exact pair (edge, t)).

Exactness. Every decision is exact. The kernel works on all pairs of one reflex vertex at once with
numpy: the orientation of every vertex against every line r–v is a float determinant whose sign is
certified by the bound of :func:`solverplan.exact.orient_filter`; uncertain signs are recomputed in
integer arithmetic (the coordinates scaled by their common denominator). The order of the crossings
along a line is decided with interval bounds on the float positions; a pair whose bounds overlap,
or whose line passes exactly through another vertex before the hit, is re-resolved by the exact
scalar :func:`~solverplan.geometry.raycast.cast_ray`. Inserted points are always computed exactly:
t = cross(r − a, r − v) / cross(b − a, r − v) on the hit edge a → b, a rational number.

>>> from solverplan.environment import Environment
>>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]], name="L")
>>> p = partition(ell)
>>> [(q.edge, q.t, q.point, q.from_vertex) for q in p.inserted]
[(0, Fraction(1, 2), (Fraction(4, 1), Fraction(0, 1)), None), (5, Fraction(1, 2), (Fraction(0, 1), Fraction(4, 1)), None)]
>>> len(p), p.segment_at(0, Fraction(1, 2)), p.segment_at(0, Fraction(1, 3))
(8, 1, 0)
>>> p.segments[1]
PartitionSegment(id=1, edge=0, t0=Fraction(1, 2), t1=Fraction(1, 1), a=(Fraction(4, 1), Fraction(0, 1)), b=(Fraction(8, 1), Fraction(0, 1)))

References
----------
Nilles, Ren, Becerra, LaValle: *A visibility-based approach to computing non-deterministic bouncing
strategies*, IJRR 2021, §4 (Algorithm 1, Prop. 1).
"""

from __future__ import annotations

import bisect
import threading
from collections import OrderedDict
import io
import logging
import math
from dataclasses import dataclass, replace
from fractions import Fraction
from functools import cached_property
from typing import Iterator, Sequence

import numpy as np

from solverplan.limits import refuse_beyond_memory
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.exact import FLOAT_FILTER_REL, ExactPoint, format_number, format_point, json_number, json_point
from solverplan.geometry.raycast import cast_ray
from solverplan.progress import step
from solverplan.runtime import jobs, parallel_map

__all__ = ["PartitionSegment", "InsertedPoint", "Partition", "partition"]

logger = logging.getLogger(__name__)

# Relative error allowance of the float positions along a line (λ below): about 20 u ≈ 4.4e-15 is
# the worst case of the few operations involved; 1e-13 keeps a wide margin.
_LAMBDA_REL = 1e-13
# Largest number of (pair, vertex) entries handled in one numpy block (bounds the memory).
_BLOCK_ENTRIES = 1 << 18


# ---------------------------------------------------------------------------------------------
# data types
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class PartitionSegment:
    """One segment of P′: the part t ∈ [t0, t1] of original edge ``edge``, from ``a`` to ``b``.

    ``id`` is global, in boundary order ring by ring; the first segment of each ring starts at the
    ring's vertex 0. ``t0``/``t1`` are exact boundary parameters on ``edge`` (0 ≤ t0 < t1 ≤ 1),
    ``a``/``b`` the exact end points; free space is on the left of a → b.
    """

    id: int
    edge: int
    t0: Fraction
    t1: Fraction
    a: ExactPoint
    b: ExactPoint

    def to_json(self) -> dict:
        return {
            "id": self.id,
            "edge": self.edge,
            "t0": json_number(self.t0),
            "t1": json_number(self.t1),
            "a": json_point(self.a),
            "b": json_point(self.b),
        }


@dataclass(frozen=True, slots=True)
class InsertedPoint:
    """A partition point inserted by Algorithm 1 at ``(edge, t)``, 0 < t < 1, exactly ``point``.

    ``reflex_vertex`` is the reflex vertex r the ray passed through and ``from_vertex`` the vertex v it
    was shot from (``None`` for the extension of an edge incident to r): the first pair found, in the
    order (r ascending; r's two edge extensions first, then v ascending). ``sources`` lists every
    pair (r, v) whose ray lands here (v ``None`` for extensions), in the same order.
    """

    point: ExactPoint
    edge: int
    t: Fraction
    reflex_vertex: int
    from_vertex: int | None
    sources: tuple[tuple[int, int | None], ...] = ()

    def to_json(self) -> dict:
        return {
            "point": json_point(self.point),
            "edge": self.edge,
            "t": json_number(self.t),
            "reflex_vertex": self.reflex_vertex,
            "from_vertex": self.from_vertex,
            "sources": [[r, v] for r, v in self.sources],
        }


@dataclass(frozen=True)
class Partition:
    """The partitioned boundary P′ of an environment (paper Algorithm 1); build it with :func:`partition`.

    Attributes
    ----------
    env
        The environment.
    segments
        All segments, ``segments[k].id == k``, in boundary order ring by ring (each ring from its
        vertex 0, along its edges in order, each edge cut at increasing t).
    ring_offsets
        First segment id of each ring, plus the total at the end.
    inserted
        The inserted points (never an original vertex, each once), sorted by (edge, t).

    Float views (read-only numpy arrays, length m = number of segments): ``seg_start``, ``seg_end``
    (m, 2); ``seg_edge``, ``seg_t0``, ``seg_t1``; ``next_segment``/``prev_segment`` (the neighbours
    along the segment's ring).
    """

    env: Environment
    segments: tuple[PartitionSegment, ...]
    ring_offsets: tuple[int, ...]
    inserted: tuple[InsertedPoint, ...]

    # ------------------------------------------------------------------ structure
    def __len__(self) -> int:
        return len(self.segments)

    @property
    def n_segments(self) -> int:
        return len(self.segments)

    def vertices(self) -> tuple[tuple[ExactPoint, ...], ...]:
        """The vertices of P′ per ring, in boundary order (original vertices and inserted points)."""
        rings = []
        for k in range(len(self.ring_offsets) - 1):
            rings.append(tuple(s.a for s in self.segments[self.ring_offsets[k] : self.ring_offsets[k + 1]]))
        return tuple(rings)

    @cached_property
    def edge_segments(self) -> tuple[range, ...]:
        """For each original edge, the range of ids of its segments."""
        ranges = []
        for e in range(self.env.n_edges):
            lo = int(self._edge_first[e])
            ranges.append(range(lo, int(self._edge_first[e + 1])))
        return tuple(ranges)

    def ring_of_segment(self, segment: int) -> int:
        """The ring (0 = outer) of a segment."""
        return int(self.env.ring_of[self.segments[segment].edge])

    # ------------------------------------------------------------------ float views
    @cached_property
    def seg_start(self) -> np.ndarray:
        return _frozen(np.array([[float(s.a[0]), float(s.a[1])] for s in self.segments], dtype=float).reshape(-1, 2))

    @cached_property
    def seg_start_lo(self) -> np.ndarray:
        """The rounding left over by :attr:`seg_start`: ``float(x − seg_start)`` per coordinate, so that
        (``seg_start``, ``seg_start_lo``) carries every point of P′ as a double-double (106 bits)."""
        lo = [float(c - Fraction(h)) for s, hs in zip(self.segments, self.seg_start.tolist()) for c, h in zip(s.a, hs)]
        return _frozen(np.array(lo, dtype=float).reshape(-1, 2))

    def point_vectors(self, frm: np.ndarray, to: np.ndarray, *, accurate: bool = False) -> np.ndarray:
        """Float vectors P′[to] − P′[frm] (P′ vertex ids: vertex k starts segment k), shape (rows, 2).

        The difference of the rounded points is off by about 2⁻⁵³ of the points' magnitude: nothing
        for points far apart, but a large part of a tiny difference, or of any difference once the
        environment is translated far from 0. Rows where that error could exceed 1e-13 of the
        difference (or every row, with ``accurate``) are formed from the double-doubles instead,
        (hi_to − hi_frm) + (lo_to − lo_frm): accurate to rounding relative to the difference itself.
        A difference below 1e-12 of the coordinates is formed exactly.

        >>> from solverplan.environment import Environment
        >>> far = partition(Environment.from_coords([[10**12, 0], [10**12 + 1, 0], [10**12, "3e-9"]]))
        >>> far.point_vectors(np.array([1]), np.array([2]), accurate=True).tolist()   # exactly (−1, 3e-9)
        [[-1.0, 3e-09]]
        """
        frm, to = np.asarray(frm, dtype=np.int64), np.asarray(to, dtype=np.int64)
        P = self.seg_start
        r = P[to] - P[frm]
        mag = np.maximum(np.abs(P[frm]), np.abs(P[to])).max(axis=1) if len(r) else np.zeros(0)
        size = np.abs(r).max(axis=1) if len(r) else np.zeros(0)
        rows = np.arange(len(r)) if accurate else np.flatnonzero(mag > 1e3 * size)
        if not len(rows):
            return r
        lo = self.seg_start_lo
        f, t = frm[rows], to[rows]
        r[rows] = (P[t] - P[f]) + (lo[t] - lo[f])
        for k in rows[size[rows] <= 1e-12 * mag[rows]].tolist():
            p, q = self.segments[int(frm[k])].a, self.segments[int(to[k])].a
            dx, dy = q[0] - p[0], q[1] - p[1]
            r[k] = (float(dx), float(dy))
        return r

    @cached_property
    def seg_end(self) -> np.ndarray:
        return _frozen(np.array([[float(s.b[0]), float(s.b[1])] for s in self.segments], dtype=float).reshape(-1, 2))

    @cached_property
    def seg_edge(self) -> np.ndarray:
        return _frozen(np.array([s.edge for s in self.segments], dtype=np.int64))

    @cached_property
    def seg_t0(self) -> np.ndarray:
        return _frozen(np.array([float(s.t0) for s in self.segments], dtype=float))

    @cached_property
    def seg_t1(self) -> np.ndarray:
        return _frozen(np.array([float(s.t1) for s in self.segments], dtype=float))

    @cached_property
    def next_segment(self) -> np.ndarray:
        ids = np.arange(len(self.segments), dtype=np.int64) + 1
        for k in range(len(self.ring_offsets) - 1):
            ids[self.ring_offsets[k + 1] - 1] = self.ring_offsets[k]
        return _frozen(ids)

    @cached_property
    def prev_segment(self) -> np.ndarray:
        ids = np.empty(len(self.segments), dtype=np.int64)
        ids[self.next_segment] = np.arange(len(self.segments), dtype=np.int64)
        return _frozen(ids)

    @cached_property
    def _edge_first(self) -> np.ndarray:
        """First segment id of each edge, plus the total at the end (length n_edges + 1)."""
        return _frozen(np.searchsorted(self.seg_edge, np.arange(self.env.n_edges + 1), side="left").astype(np.int64))

    # ------------------------------------------------------------------ lookup
    def segment_at(self, edge: int, t: Fraction | int | float) -> int:
        """Id of the segment holding boundary point ``(edge, t)``, t ∈ [0, 1], decided exactly.

        A point exactly on a partition point (an original vertex or an inserted point) belongs to the
        segment **starting** there: segments are half-open, t ∈ [t0, t1). Hence t = 1 (the end vertex
        of ``edge``) gives the first segment of the next edge of the ring. Floats are taken at their
        exact binary value.

        Raises
        ------
        InvalidBoundarySet
            Unknown edge, or t outside [0, 1] (both are :class:`InputError`).
        """
        self.env._check_edge_id(edge)
        edge = int(edge)
        tt = Fraction(t) if not isinstance(t, Fraction) else t
        if not 0 <= tt <= 1:
            raise InvalidBoundarySet(f"boundary parameter t={format_number(tt)} on edge {edge} is not in [0, 1]")
        if tt == 1:
            return int(self._edge_first[int(self.env.next_vertex[edge])])
        ids = self.edge_segments[edge]
        starts = [self.segments[k].t0 for k in ids]
        return ids[bisect.bisect_right(starts, tt) - 1]

    def segments_at(self, edges: Sequence[int] | np.ndarray, t: Sequence[float] | np.ndarray) -> np.ndarray:
        """Vectorised :meth:`segment_at` on float parameters: int64 segment ids, same convention.

        Each float t is compared with the float of each partition parameter, so a float t within
        rounding of an inserted point may land on either side of it; use :meth:`segment_at` with an
        exact t when that matters.
        """
        edges_arr = np.asarray(edges, dtype=np.int64).reshape(-1)
        t_arr = np.asarray(t, dtype=float).reshape(-1)
        if len(edges_arr) != len(t_arr):
            raise InputError(f"edges and t differ in length: {len(edges_arr)} and {len(t_arr)}")
        n = self.env.n_edges
        bad = np.flatnonzero((edges_arr < 0) | (edges_arr >= n))
        if len(bad):
            raise InvalidBoundarySet(f"unknown edge e{int(edges_arr[bad[0]])}: edges are e0..e{n - 1}")
        bad = np.flatnonzero(~((t_arr >= 0) & (t_arr <= 1)))
        if len(bad):
            raise InvalidBoundarySet(f"t[{int(bad[0])}] = {float(t_arr[bad[0]])!r} is not in [0, 1]")
        at_end = t_arr == 1
        edges_arr = np.where(at_end, np.asarray(self.env.next_vertex)[edges_arr], edges_arr)
        t_arr = np.where(at_end, 0.0, t_arr)
        lo = self._edge_first[edges_arr].copy()  # invariant: seg_t0[lo] <= t
        hi = self._edge_first[edges_arr + 1].copy()  # exclusive
        t0 = self.seg_t0
        while True:
            active = hi - lo > 1
            if not active.any():
                return lo
            mid = (lo + hi) // 2
            go_right = active & (t0[np.minimum(mid, len(t0) - 1)] <= t_arr)
            lo = np.where(go_right, mid, lo)
            hi = np.where(active & ~go_right, mid, hi)

    # ------------------------------------------------------------------ output
    def to_json(self) -> dict:
        """The answer of ``solverplan partition`` (docs/contract.md): ``vertices`` per ring, ``segments``, plus ``inserted`` with provenance."""
        return {
            "name": self.env.name,
            "n_segments": len(self.segments),
            "n_inserted": len(self.inserted),
            "vertices": [[json_point(p) for p in ring] for ring in self.vertices()],
            "segments": [s.to_json() for s in self.segments],
            "inserted": [q.to_json() for q in self.inserted],
        }

    def to_text(self, *, width: int = 100) -> str:
        """A readable summary and the segment table (inserted end points marked with ``*``)."""
        from rich import box
        from rich.console import Console
        from rich.table import Table

        buffer = io.StringIO()
        console = Console(file=buffer, width=width, color_system=None, force_terminal=False, highlight=False)
        env = self.env
        console.print(f"partition P′ of {env.name!r} (paper Algorithm 1)")
        summary = Table(box=box.SIMPLE, show_header=False)
        summary.add_column("field", style="bold")
        summary.add_column("value")
        summary.add_row("vertices of P", str(env.n_vertices))
        summary.add_row("reflex vertices", str(len(env.reflex_vertices)))
        summary.add_row("inserted points", str(len(self.inserted)))
        summary.add_row("segments", str(len(self.segments)))
        for k in range(len(self.ring_offsets) - 1):
            kind = "outer ring" if k == 0 else f"hole {k - 1}"
            summary.add_row(kind, f"segments {self.ring_offsets[k]}..{self.ring_offsets[k + 1] - 1}")
        console.print(summary)
        inserted = {(q.edge, q.t): q for q in self.inserted}
        table = Table(box=box.SIMPLE_HEAD, title="segments (* = inserted end point)")
        for column in ("id", "edge", "t0", "t1", "a", "b", "a made by (r, v)"):
            table.add_column(column, justify="right" if column in ("id", "edge") else "left")
        for s in self.segments:
            start = inserted.get((s.edge, s.t0))
            table.add_row(
                str(s.id),
                f"e{s.edge}",
                format_number(s.t0),
                format_number(s.t1),
                format_point(s.a) + ("*" if start else ""),
                format_point(s.b) + ("*" if (s.edge, s.t1) in inserted else ""),
                _provenance(start) if start else "",
            )
        console.print(table)
        return buffer.getvalue()


def _provenance(q: InsertedPoint) -> str:
    return f"r{q.reflex_vertex} " + ("ext" if q.from_vertex is None else f"v{q.from_vertex}")


def _frozen(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


# ---------------------------------------------------------------------------------------------
# the algorithm
# ---------------------------------------------------------------------------------------------
def partition(env: Environment) -> Partition:
    """The partition P′ of ``env``'s boundary (paper Algorithm 1), exact.

    For every reflex vertex r and every vertex v seen from r (closed visibility), the first point
    beyond r where the line v → r is blocked by the boundary is inserted, when the line continues
    into the free space beyond r; v = the neighbours of r give the extensions of r's two edges.
    See the module docstring for the exact definitions and how ties are decided.

    Parameters
    ----------
    env
        Any valid environment (holes, collinear vertices allowed).

    Returns
    -------
    Partition
        Segments in boundary order with exact t-ranges; inserted points with provenance.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> p = partition(square)
    >>> len(p.segments), p.inserted, p.ring_offsets
    (4, (), (0, 4))

    Notes
    -----
    Cost: for each reflex vertex one numpy pass over (candidate v) × (all vertices), so O(r·n²)
    float work with small constants, plus O(n) exact work per pair re-resolved by
    :func:`~solverplan.geometry.raycast.cast_ray` (pairs with exact collinearities only).
    """
    with _recent_lock:
        known = _recent.get(env)
        if known is not None:
            _recent.move_to_end(env)
            return known if known.env is env else replace(known, env=env)
    p = _partition(env)
    with _recent_lock:
        _recent[env] = p
        while len(_recent) > _RECENT:
            _recent.popitem(last=False)
    return p


def renumbered(p: Partition, env: Environment, vertex_of: Sequence[int]) -> Partition:
    """P′ of ``env``, an environment with the same rings as ``p.env`` each started at another vertex, from ``p``:
    ``vertex_of[k]`` is ``env``'s vertex (global index) at ``p.env``'s vertex k (so edge k, from vertex k, becomes edge
    ``vertex_of[k]``). Algorithm 1's points are where lines through two vertices meet the boundary, whatever the
    numbering: the same points, on the renamed edges, with the same pairs (r, v) renamed, the first in the order of
    the new numbers. Equal to ``partition(env)``, without casting the rays again.

    >>> from solverplan.environment import Environment
    >>> ell = [[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]]
    >>> p = partition(Environment.from_coords(ell))
    >>> turned = Environment.from_coords(ell[2:] + ell[:2])
    >>> renumbered(p, turned, [4, 5, 0, 1, 2, 3]) == partition(turned)
    True
    """
    old = p.env
    if len(vertex_of) != old.n_vertices or env.n_vertices != old.n_vertices or sorted(vertex_of) != list(range(env.n_vertices)):
        raise ValueError("renumbered: vertex_of must map every vertex of the partition's environment to one of env's")
    verts, mine = old.exact_vertices, env.exact_vertices
    if any(verts[k] != mine[vertex_of[k]] for k in range(len(vertex_of))) or any(
            int(env.next_vertex[vertex_of[k]]) != vertex_of[int(old.next_vertex[k])] for k in range(len(vertex_of))):
        raise ValueError("renumbered: env's rings are not the partition's, started elsewhere")

    def order(src: tuple[int, int | None]) -> tuple[int, int, int]:
        return (src[0], 0 if src[1] is None else 1, -1 if src[1] is None else src[1])

    inserted = []
    for q in p.inserted:
        sources = tuple(sorted(((vertex_of[r], None if v is None else vertex_of[v]) for r, v in q.sources), key=order))
        inserted.append(InsertedPoint(q.point, vertex_of[q.edge], q.t, sources[0][0], sources[0][1], sources))
    inserted.sort(key=lambda q: (q.edge, q.t))
    return _assemble(env, tuple(inserted))


_RECENT = 2
"""Partitions kept per process, by environment (equal environments share one): a query builds its own, and the
exact check of its answer, the certificate and the graph cache ask again — 30 s each for a raw 1,200-vertex map."""
_recent: OrderedDict[Environment, Partition] = OrderedDict()
_recent_lock = threading.Lock()


def _partition(env: Environment) -> Partition:
    """:func:`partition`, computed."""
    kernel = _Kernel(env)
    found: dict[tuple[int, Fraction], list[tuple[int, int | None]]] = {}
    points: dict[tuple[int, Fraction], ExactPoint] = {}
    reflex = env.reflex_vertices
    for done, (r, shots) in enumerate(_all_shots(kernel, reflex)):
        step("partition of the boundary", done, len(reflex))  # the progress bar, and where a timeout stops it
        for v, edge, t, point in shots:
            key = (edge, t)
            source = (r, None if v in (kernel.prv[r], kernel.nxt[r]) else v)
            found.setdefault(key, []).append(source)
            points.setdefault(key, point)
    logger.debug(
        "partition of %r: %d reflex vertices, %d pairs resolved exactly, %d inserted points",
        env.name, len(env.reflex_vertices), kernel.exact_pairs, len(found),
    )

    def order(src: tuple[int, int | None]) -> tuple[int, int, int]:
        return (src[0], 0 if src[1] is None else 1, -1 if src[1] is None else src[1])

    inserted = []
    for key in sorted(found):
        sources = tuple(sorted(set(found[key]), key=order))
        edge, t = key
        inserted.append(InsertedPoint(points[key], edge, t, sources[0][0], sources[0][1], sources))
    return _assemble(env, tuple(inserted))


SPLIT_MIN_PAIRS = 250_000
"""Partitions with fewer (reflex vertex, vertex) pairs than this are made in this process (≈ 0.5 CPU s); larger ones
cast the lines of runs of reflex vertices in the worker processes of :func:`solverplan.runtime.parallel_map`."""


def _all_shots(kernel: _Kernel, reflex: Sequence[int]) -> Iterator[tuple[int, list]]:
    """(r, the shots of r) for every reflex vertex r in order; in worker processes, runs of reflex vertices at a
    time, when the polygon is large and the setting ``jobs`` allows (the same shots: each r's are its own)."""
    n_jobs = jobs()
    if n_jobs < 2 or len(reflex) * kernel.n < SPLIT_MIN_PAIRS:
        for r in reflex:
            yield r, list(kernel.shots(r))
        return
    size = -(-len(reflex) // (8 * n_jobs))  # eight runs per process: a slow run delays little
    runs = [reflex[k : k + size] for k in range(0, len(reflex), size)]

    def run(rs: Sequence[int]) -> tuple[list[list], int]:
        kernel.exact_pairs = 0
        return [list(kernel.shots(r)) for r in rs], kernel.exact_pairs

    exact_pairs = 0
    for rs, (shots, pairs) in zip(runs, parallel_map(run, runs)):
        exact_pairs += pairs
        yield from zip(rs, shots)
    kernel.exact_pairs = exact_pairs


def _assemble(env: Environment, inserted: tuple[InsertedPoint, ...]) -> Partition:
    """Cut every edge at its inserted parameters; segments in edge order (= boundary order)."""
    cuts: dict[int, list[InsertedPoint]] = {}
    for q in inserted:
        cuts.setdefault(q.edge, []).append(q)
    verts = env.exact_vertices
    nxt = env.next_vertex
    segments: list[PartitionSegment] = []
    ring_offsets = [0]
    for ring in range(len(env.rings)):
        for e in range(env.ring_offsets[ring], env.ring_offsets[ring + 1]):
            ts = [Fraction(0)] + [q.t for q in cuts.get(e, ())] + [Fraction(1)]
            ps = [verts[e]] + [q.point for q in cuts.get(e, ())] + [verts[int(nxt[e])]]
            for k in range(len(ts) - 1):
                segments.append(PartitionSegment(len(segments), e, ts[k], ts[k + 1], ps[k], ps[k + 1]))
        ring_offsets.append(len(segments))
    return Partition(env, tuple(segments), tuple(ring_offsets), inserted)


class _Kernel:
    """Exact visibility and first hits for the lines through one reflex vertex, vectorised."""

    def __init__(self, env: Environment) -> None:
        self.env = env
        # The side of every vertex w.r.t. every edge is an n × n table, and each reflex vertex's pass
        # broadcasts over (candidates × vertices) in floats: about 72 bytes per pair of vertices at the
        # peak (measured: 20,000 vertices asked numpy for 3 GiB in one array). Refused up front, in one line.
        refuse_beyond_memory(72.0 * env.n_vertices ** 2, f"the partition of a polygon of {env.n_vertices:,} vertices")
        verts = env.exact_vertices
        den = 1
        for x, y in verts:
            den = math.lcm(den, x.denominator, y.denominator)
        self.den = den
        self.ix = [int(x * den) for x, _ in verts]  # exact integer coordinates (scaled by den)
        self.iy = [int(y * den) for _, y in verts]
        self.P = np.asarray(env.vertices, dtype=float)
        self.n = env.n_vertices
        self.nxt = np.asarray(env.next_vertex, dtype=np.int64)
        self.prv = np.asarray(env.prev_vertex, dtype=np.int64)
        self.mag = np.abs(self.P[:, 0]) + np.abs(self.P[:, 1])
        # one error bound for every orientation determinant of three vertices (orient_filter's bound,
        # maximised over all triples): |x_a| + |x_b| + |x_c| <= 3 max |x|, likewise for y
        self._bound = FLOAT_FILTER_REL * 9 * float(np.max(np.abs(self.P[:, 0]))) * float(np.max(np.abs(self.P[:, 1])))
        self.turn = np.array([self._orient(int(self.prv[v]), v, int(self.nxt[v])) for v in range(self.n)], dtype=np.int8)
        self.E = self._edge_signs()
        self.exact_pairs = 0

    # ------------------------------------------------------------------ exact helpers
    def _orient(self, a: int, b: int, c: int) -> int:
        ix, iy = self.ix, self.iy
        det = (ix[b] - ix[a]) * (iy[c] - iy[a]) - (iy[b] - iy[a]) * (ix[c] - ix[a])
        return (det > 0) - (det < 0)

    def _signs(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Float orientation determinants of (a, b, c) (broadcast), their certified signs (0 = too close
        to call) and error bounds, as :func:`solverplan.exact.orient_filter` computes them."""
        abx, aby = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
        acx, acy = c[..., 0] - a[..., 0], c[..., 1] - a[..., 1]
        det = abx * acy - aby * acx
        bound = FLOAT_FILTER_REL * (np.abs(a[..., 0]) + np.abs(b[..., 0]) + np.abs(c[..., 0])) * (
            np.abs(a[..., 1]) + np.abs(b[..., 1]) + np.abs(c[..., 1])
        )
        sign = np.zeros(det.shape, dtype=np.int8)
        sign[det > bound] = 1
        sign[det < -bound] = -1
        return det, sign, bound

    def _edge_signs(self) -> np.ndarray:
        """E[i, x] = exact orient(vertex i, next vertex of i, vertex x): the side of x w.r.t. edge i."""
        P, n, nxt = self.P, self.n, self.nxt
        sign = np.empty((n, n), dtype=np.int8)
        block = max(1, (1 << 20) // max(n, 1))  # rows at a time: the float temporaries stay near 50 MB
        for r0 in range(0, n, block):
            step("partition of the boundary: sides of the edges", r0, n)  # a stop point on very large maps
            rs = slice(r0, min(n, r0 + block))
            _, sign[rs], _ = self._signs(P[rs][:, None, :], P[nxt[rs]][:, None, :], P[None, :, :])
        rows, cols = np.nonzero(sign == 0)
        for i, x in zip(rows.tolist(), cols.tolist()):
            sign[i, x] = 0 if x in (i, nxt[i]) else self._orient(i, int(nxt[i]), x)
        return sign

    # ------------------------------------------------------------------ pairs
    def _candidates(self, r: int) -> np.ndarray:
        """Vertices v whose line through r continues into the open free wedge beyond r and whose
        direction from r (and to r) lies in the closed free wedge at both ends: exact."""
        E, pr, nr = self.E, int(self.prv[r]), int(self.nxt[r])
        s1 = E[r].astype(np.int64)  # cross(next − r, v − r)
        s2 = -E[pr].astype(np.int64)  # cross(prev − r, v − r)
        shoot = ((s1 > 0) & (s2 > 0)) | ((s1 < 0) & (s2 < 0)) | ((s1 == 0) & (s2 > 0)) | ((s2 == 0) & (s1 < 0))
        shoot[r] = False
        # the free wedge at v must contain r − v (closed): c1 = cross(u1_v, r − v), c2 = cross(r − v, u2_v)
        c1 = E[:, r].astype(np.int64)
        c2 = E[self.prv, r].astype(np.int64)
        turn = self.turn
        ok_v = np.where(turn > 0, (c1 >= 0) & (c2 >= 0), np.where(turn < 0, ~((c1 < 0) & (c2 < 0)), c1 >= 0))
        shoot &= ok_v
        shoot[pr] = shoot[nr] = True  # the edge extensions (s1/s2 put them there already)
        return np.flatnonzero(shoot)

    def shots(self, r: int) -> Iterator[tuple[int, int, Fraction, ExactPoint]]:
        """(v, edge, t, point) for every vertex v seen from r whose ray beyond r hits an edge interior."""
        cand = self._candidates(r)
        rows = max(1, _BLOCK_ENTRIES // max(1, self.n))
        for lo in range(0, len(cand), rows):
            yield from self._block(r, cand[lo : lo + rows])

    def _line_signs(self, r: int, V: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Float determinants and exact signs of orient(r, v, x) for v in V (rows), every vertex x
        (columns); and the (row, column) entries of the vertices x ∉ {r, v} exactly on the line r v."""
        P = self.P
        R = P[r]
        m = len(V)
        ar = np.arange(m)
        dvx, dvy = P[V, 0] - R[0], P[V, 1] - R[1]
        det = dvx[:, None] * (P[None, :, 1] - R[1]) - dvy[:, None] * (P[None, :, 0] - R[0])
        bound = self._bound
        S = (det > bound).view(np.int8) - (det < -bound).view(np.int8)
        S[:, r] = 1  # placeholders: r and v are on their own line (never looked at below)
        S[ar, V] = 1
        zk = zx = np.zeros(0, dtype=np.int64)
        if not S.all():
            rows_u, cols_u = np.nonzero(S == 0)
            exact = np.array([self._orient(r, int(V[k]), x) for k, x in zip(rows_u.tolist(), cols_u.tolist())], dtype=np.int8)
            S[rows_u, cols_u] = exact
            zk, zx = rows_u[exact == 0], cols_u[exact == 0]
        S[:, r] = 0
        S[ar, V] = 0
        return det, S, zk, zx

    def _between(self, r: int, v: int, x: int) -> bool:
        """For x on the line r v (exactly): is x strictly between r and v?"""
        ix, iy = self.ix, self.iy
        dx, dy = ix[v] - ix[r], iy[v] - iy[r]
        p = (ix[x] - ix[r]) * dx + (iy[x] - iy[r]) * dy
        return 0 < p < dx * dx + dy * dy

    def _block(self, r: int, V: np.ndarray) -> Iterator[tuple[int, int, Fraction, ExactPoint]]:
        P, nxt, prv, E = self.P, self.nxt, self.prv, self.E
        m = len(V)
        ar = np.arange(m)
        det, S, zk, zx = self._line_signs(r, V)
        # ---- phase 1, exact: which v does r see? Edge i (not incident to r or v) blocks the open
        # segment r v iff its ends lie strictly on both sides of the line r v and r, v strictly on both
        # sides of its line; a vertex exactly on the open segment needs the scalar exact caster.
        crosses_line = (S.astype(np.int16) * S[:, nxt]) < 0  # (m, n) over edges
        crosses_line[:, [r, int(prv[r])]] = False
        crosses_line[ar, V] = False
        crosses_line[ar, prv[V]] = False
        side = E[:, r].astype(np.int16)[None, :] * E[:, V].T  # (m, n): r and v against edge i's line
        blocked = (crosses_line & (side < 0)).any(axis=1)
        grazing = np.zeros(m, dtype=bool)
        for k, x in zip(zk.tolist(), zx.tolist()):
            if not blocked[k] and not grazing[k] and self._between(r, int(V[k]), x):
                grazing[k] = True
        visible = ~blocked & ~grazing

        # ---- phase 2, on the visible rows: the first crossing beyond r (λ < 0, x ≈ r + λ (v − r)),
        # ordered with interval bounds; ties and vertices on the ray go to the exact caster.
        seen = np.flatnonzero(visible)
        ck, ci = np.nonzero(crosses_line[seen] & (side[seen] > 0))
        ck = seen[ck]
        certain = np.zeros(m, dtype=bool)
        best_edge = np.full(m, -1, dtype=np.int64)
        if len(ck):
            R = P[r]
            dv = P[V] - R
            len2 = dv[:, 0] ** 2 + dv[:, 1] ** 2
            mag_r = self.mag[r]

            def lam(k: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
                value = ((P[x, 0] - R[0]) * dv[k, 0] + (P[x, 1] - R[1]) * dv[k, 1]) / len2[k]
                err = _LAMBDA_REL * ((self.mag[x] + mag_r) * (self.mag[V[k]] + mag_r) / len2[k] + np.abs(value))
                return value, err

            cb = nxt[ci]
            la, ea = lam(ck, ci)
            lb, eb = lam(ck, cb)
            da, db = det[ck, ci], det[ck, cb]
            bound = self._bound
            gap = np.abs(da - db)
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.clip(da / (da - db), 0.0, 1.0)
                t_err = np.where(gap > 2 * bound, 2 * bound / (gap - 2 * bound), 1.0)
            certain_t = (np.abs(da) > bound) & (np.abs(db) > bound)
            t_err = np.where(certain_t, np.minimum(t_err, 1.0), 1.0)
            t = np.where(np.isfinite(t), t, 0.5)
            lc = la + t * (lb - la)
            err = ea + eb + np.abs(lb - la) * t_err
            c_lo = np.maximum(lc - err, np.minimum(la, lb) - ea - eb)
            c_hi = np.minimum(lc + err, np.maximum(la, lb) + ea + eb)
            ahead = c_lo < 0  # beyond r (the others lie beyond v, λ > 1)
            ck, ci, lc, c_lo, c_hi = ck[ahead], ci[ahead], lc[ahead], c_lo[ahead], c_hi[ahead]
            if len(ck):
                order = np.lexsort((lc, ck))  # by row, then λ ascending: the last of a row is the best
                ck, ci, lc, c_lo, c_hi = ck[order], ci[order], lc[order], c_lo[order], c_hi[order]
                last = np.flatnonzero(np.append(ck[1:] != ck[:-1], True))
                rows = ck[last]
                best_edge[rows] = ci[last]
                best_lo = np.full(m, np.inf)
                best_lo[rows] = c_lo[last]
                ok = c_hi[last] < 0
                # the runner-up of the row must lie certainly before (further out than) the best
                prev = last - 1
                has_prev = (prev >= 0) & (ck[np.maximum(prev, 0)] == rows)
                ok &= ~has_prev | (c_hi[np.maximum(prev, 0)] < c_lo[last])
                certain[rows] = ok
                # a vertex exactly on the ray between r and the hit: exact caster
                if len(zk):
                    zl, ze = lam(zk, zx)
                    touch = (zl + ze >= best_lo[zk]) & (zl - ze <= 0)
                    certain[zk[touch]] = False
        certain &= visible
        for k in range(m):
            v = int(V[k])
            if certain[k]:
                yield (v, *self._exact_hit(r, v, int(best_edge[k])))
            elif visible[k] or grazing[k]:
                hit = self._resolve(r, v, check_visibility=bool(grazing[k]))
                if hit is not None:
                    yield (v, *hit)

    def _exact_hit(self, r: int, v: int, edge: int) -> tuple[int, Fraction, ExactPoint]:
        """The exact crossing of the line v → r with edge ``edge`` (known to be a proper crossing)."""
        ix, iy = self.ix, self.iy
        b = int(self.nxt[edge])
        dx, dy = ix[r] - ix[v], iy[r] - iy[v]
        ex, ey = ix[b] - ix[edge], iy[b] - iy[edge]
        num = (ix[r] - ix[edge]) * dy - (iy[r] - iy[edge]) * dx
        den = ex * dy - ey * dx
        if den < 0:
            num, den = -num, -den
        assert 0 < num < den, (r, v, edge, num, den)
        t = Fraction(num, den)
        scale = self.den * den
        point = (Fraction(ix[edge] * den + num * ex, scale), Fraction(iy[edge] * den + num * ey, scale))
        return edge, t, point

    def _resolve(self, r: int, v: int, *, check_visibility: bool) -> tuple[int, Fraction, ExactPoint] | None:
        """Exact fallback with :func:`cast_ray`: None if v is not seen from r or the ray stops at a vertex."""
        self.exact_pairs += 1
        verts = self.env.exact_vertices
        (rx, ry), (vx, vy) = verts[r], verts[v]
        if check_visibility:
            probe = cast_ray(self.env, (rx, ry), (vx - rx, vy - ry), through_vertices=True)
            if probe.s < 1:
                return None
        hit = cast_ray(self.env, (rx, ry), (rx - vx, ry - vy), through_vertices=True)
        if hit.vertex is not None:
            return None
        return hit.edge, hit.t, hit.point


# ---------------------------------------------------------------------------------------------
# P′ known without running Algorithm 1 (the graph cache keeps its inserted points)
# ---------------------------------------------------------------------------------------------
def assemble(env: Environment, inserted: Sequence[InsertedPoint]) -> Partition:
    """The boundary of ``env`` cut at the points ``inserted`` (sorted here by edge and parameter): P′ when they are
    the points Algorithm 1 inserts — read back from the graph cache, say — without running the algorithm.

    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])
    >>> assemble(ell, partition(ell).inserted) == partition(ell)
    True
    """
    return _assemble(env, tuple(sorted(inserted, key=lambda q: (q.edge, q.t))))


def remember(p: Partition) -> None:
    """Let :func:`partition` of ``p.env`` (or of an equal environment) return ``p`` in this process: ``p`` must be
    that partition (the graph cache calls it with P′ rebuilt from its inserted points and checked)."""
    with _recent_lock:
        _recent[p.env] = p
        _recent.move_to_end(p.env)
        while len(_recent) > _RECENT:
            _recent.popitem(last=False)


def is_remembered(p: Partition) -> bool:
    """Is ``p`` the partition :func:`partition` returns for ``p.env`` in this process — P′ itself, not a refinement
    of it nor a partition made by hand? No geometry: the process remembers the last partitions it made.

    >>> from solverplan.environment import Environment
    >>> p = partition(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]]))
    >>> is_remembered(p), is_remembered(Partition(p.env, p.segments[:2], (0, 2), ()))
    (True, False)
    """
    with _recent_lock:
        known = _recent.get(p.env)
    return known is not None and known.segments is p.segments and known.inserted is p.inserted
