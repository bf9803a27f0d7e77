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

Algorithm (see :mod:`solverplan.bounce._sweep` for the sweeps, :mod:`~solverplan.bounce.bvg._safe_sets` for step 3)
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

import logging
import math
import time
from typing import TYPE_CHECKING

import numpy as np

from solverplan._arrays import can_fork, ragged_arange, sorted_intersection, sorted_unique
from solverplan.bounce import _cache, _sweep
from solverplan.bounce._sweep import MARK_PI, MARK_ZERO, build_sweeps
from solverplan.bounce.bvg._safe_sets import (Pieces, equal_ends, nonempty, refine_ends, single_headings_safe, singletons,
                                             sorted_by_arc_lo, subtract_holes, transitions_and_phi)
from solverplan.bounce.bvg.graph import SafeBVG, as_partition
from solverplan.bounce.bvg.size import (BASE_BYTES, PLANNED_BYTES_PER_ARC, check_graph_memory, estimate_graph,
                                        refuse_reachable)
from solverplan.bounce.bvg.tolerances import EndComparator
from solverplan.bounce.partitions import Partition
from solverplan.environment import Environment
from solverplan.errors import InvalidBoundarySet
from solverplan.limits import memory_limit
from solverplan.progress import step
from solverplan.runtime import config, jobs as _settings_jobs, parallel_map

if TYPE_CHECKING:  # networkx costs ~0.1 s to import: only bounce_visibility_graph loads it
    import networkx as nx

__all__ = ["bounce_visibility_graph", "safe_bounce_visibility_graph", "reachable_safe_graph"]

logger = logging.getLogger(__name__)


def bounce_visibility_graph(partition: Partition | Environment) -> nx.DiGraph:
    """The bounce visibility graph of P′ (paper §4), as a :class:`networkx.DiGraph` on segment ids.

    An arc i → j whenever the open segments i and j see each other (Def. 5).

    Parameters
    ----------
    partition
        As for :func:`safe_bounce_visibility_graph`, whose arcs these are (without their safe headings).

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
        The partition P′ (:func:`~solverplan.bounce.partitions.partition`), or an environment (it is partitioned
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
    (:func:`~solverplan.bounce._cache.set_graph_cache`; the command line keeps one, see docs/contract.md). The graph
    of P′ itself is found on disk by the environment's exact rings, with P′, so a call with an environment that
    finds it makes no partition either.
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
    plain = isinstance(partition, Environment)  # P′ made here: later calls with the environment find it
    if isinstance(partition, Environment):
        found = _cache.lookup_environment(partition)
        if found is not None:
            return found
    p = as_partition(partition)
    digest = _cache.partition_digest(p)  # the key: the partition's exact content (no rebuild to check it)
    found = _cache.lookup(p, digest, plain=plain)
    if found is not None:
        return found
    jobs, arcs = _jobs(p)
    t0 = time.process_time()  # CPU time: what is worth keeping does not depend on the machine's load
    graph = _build(p) if jobs < 2 else _build_split(p, jobs, -(-arcs // SPLIT_ARCS_PER_BATCH))
    return _cache.store(p, digest, graph, time.process_time() - t0, plain=plain)


SPLIT_MIN_SEGMENTS = 1_000
"""Partitions with fewer segments are built in this process: their graphs take well under a second."""
SPLIT_MIN_ARCS = 200_000
"""Graphs estimated to have fewer arcs (:func:`~solverplan.bounce.bvg.size.estimate_graph`) are built in this process:
≈ 0.3 CPU s, less than forking and gathering would save."""
SPLIT_ARCS_PER_BATCH = 1 << 18
"""Arcs per batch of sources of a split build (about 50 MB at a batch's peak, ``benchmarks/README.md``)."""


def _jobs(p: Partition) -> tuple[int, int]:
    """Check the graph's memory up front (:func:`check_graph_memory`) and say how many processes build it: 1 for small
    graphs, else the setting ``jobs`` (:func:`solverplan.config`; by default the cores this process may use); and
    the estimated arcs when they were estimated (else 0)."""
    jobs = _settings_jobs()
    if jobs < 2 or len(p.segments) < SPLIT_MIN_SEGMENTS or not can_fork():
        check_graph_memory(p)
        return 1, 0
    estimate = estimate_graph(p)
    check_graph_memory(p, estimate)
    return (jobs if estimate[0] >= SPLIT_MIN_ARCS else 1), estimate[0]


def _build_split(p: Partition, jobs: int, batches: int = 1) -> SafeBVG:
    """:func:`_build` in ``jobs`` worker processes (:func:`~solverplan._arrays.process_map`): equal arrays.

    The sources are cut into runs of consecutive segments (``batches`` of them, and at least four per process); a
    worker builds every arc
    leaving its run that the sweeps at the run's ends meet (``_build(…, met=True)``: the rows of the whole graph,
    since an arc's safe set needs only the sweeps at its source's ends). The arcs that only the sweeps at their
    target meet have no safe heading: they are the reverses of built arcs that no batch built, added here with
    their transition and φ. Every row is computed by the same code on the same entries in the same order as in one
    process, so the arrays are equal, bit for bit (a test compares them)."""
    t0 = time.perf_counter()
    N = len(p.segments)
    batches = max(batches, 8 * jobs)
    bounds = np.unique(np.linspace(0, N, min(batches, N) + 1).astype(np.int64)).tolist()
    runs = list(zip(bounds[:-1], bounds[1:]))
    ctx = _sweep.SweepContext(p)  # made once, before the workers fork

    def batch(run: tuple[int, int]) -> tuple:
        g = _build(p, np.arange(*run, dtype=np.int64), ctx, met=True)
        reverse = g.target * N  # the keys of the reverses of its arcs, sorted here (in parallel)
        reverse += g.source
        reverse.sort()
        return tuple(getattr(g, name) for name in _ROW_COLUMNS + _SET_COLUMNS) + g._set_ends + (reverse, g.stats)

    parts: list[list] = []
    with config(jobs=jobs):
        for done, got in enumerate(parallel_map(batch, runs)):
            parts.append(list(got))
            step("safe BVG: sweeps", done + 1, len(runs))
    return _join_batches(p, parts, time.perf_counter() - t0, jobs)


_ROW_COLUMNS = ("source", "target", "lo", "hi", "n_intervals", "transition", "phi")
_SET_COLUMNS = ("set_lo", "set_hi")


def _join_batches(p: Partition, parts: list[list], seconds: float, jobs: int) -> SafeBVG:
    """One graph of the batches of :func:`_build_split` (consecutive runs of sources, in order) and the reverses of
    their arcs that no batch built. Column by column, each batch's column dropped once copied: the peak is the graph
    and one column more."""
    N = len(p.segments)
    n_rows = len(_ROW_COLUMNS)
    # the arcs built, sorted by (source, target) since the batches are consecutive runs of sources
    own = np.concatenate([q[0] * N + q[1] for q in parts]) if parts else np.zeros(0, dtype=np.int64)
    reverse = np.concatenate([q[-2] for q in parts]) if parts else np.zeros(0, dtype=np.int64)
    for q in parts:
        q[-2] = None
    reverse.sort(kind="stable")  # sorted runs, one per batch: merged
    if np.array_equal(reverse, own):  # as many keys, so every reverse was built (usual: none missing)
        missing = reverse[:0]
    else:
        at = np.minimum(np.searchsorted(own, reverse), max(len(own) - 1, 0))
        missing = np.unique(reverse[own[at] != reverse]) if len(own) else np.unique(reverse)
        del at
    del reverse
    # where the rows go: the arcs built and the missing ones, merged in key order
    n_arcs = len(own) + len(missing)
    miss_at = np.arange(len(missing), dtype=np.int64) + np.searchsorted(own, missing)
    built = np.ones(n_arcs, dtype=bool)
    built[miss_at] = False
    del own
    m_source, m_target = missing // N, missing % N
    del missing
    seg_edge = np.asarray(p.seg_edge, dtype=np.int64)
    m_transition, m_phi = transitions_and_phi(p.env, seg_edge[m_source], seg_edge[m_target])
    fill = {"source": m_source, "target": m_target, "lo": np.nan, "hi": np.nan, "n_intervals": 0,
            "transition": m_transition, "phi": m_phi}
    rows: dict[str, np.ndarray] = {}
    for t, name in enumerate(_ROW_COLUMNS):
        column = np.concatenate([q[t] for q in parts])
        for q in parts:
            q[t] = None
        if name in ("source", "target", "n_intervals"):
            column = column.astype(np.int64, copy=False)
        if len(miss_at):
            out = np.empty(n_arcs, dtype=column.dtype)
            out[built] = column
            out[miss_at] = fill[name]
            column = out
        rows[name] = column
        del column
    sets = []
    for t in range(n_rows, n_rows + len(_SET_COLUMNS) + 4):  # the intervals: only built arcs have them, in order
        sets.append(np.concatenate([q[t] for q in parts]) if parts else np.zeros(0, dtype=np.float64))
        for q in parts:
            q[t] = None
    counts = rows["n_intervals"]
    stats: dict = {"jobs": jobs, "batches": len(parts), "seconds_total": seconds}
    for q in parts:
        for key in ("sweeps", "entries", "exact_checks", "exact_casts", "singletons_checked"):
            stats[key] = stats.get(key, 0) + q[-1].get(key, 0)
    return SafeBVG(
        partition=p,
        source=rows["source"],
        target=rows["target"],
        lo=rows["lo"],
        hi=rows["hi"],
        n_intervals=counts,
        set_offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
        set_lo=sets[0],
        set_hi=sets[1],
        transition=rows["transition"],
        phi=rows["phi"],
        _set_ends=(sets[2], sets[3], sets[4], sets[5]),
        stats=stats,
    )


def _build(p: Partition, sources: np.ndarray | None = None, context: _sweep.SweepContext | None = None, *,
           met: bool = False) -> SafeBVG:
    """Build the safe BVG of ``p`` (no cache, no size check).

    With ``sources`` (segment ids), only the arcs leaving them that have a safe heading: their safe sets need only
    the sweeps at the two ends of each source (module docstring, step 3), so the work is that of those sweeps. The
    rows are those of the whole graph's arcs from ``sources`` with ``n_intervals > 0``, equal arrays
    (:func:`reachable_safe_graph`; a property test compares them). With ``met`` too, every arc from ``sources`` that
    those sweeps meet, safe or not: the whole graph's rows of those arcs (:func:`_build_split` adds the arcs that
    only the sweeps at their targets meet)."""
    env = p.env
    N = len(p.segments)
    t0 = time.perf_counter()
    ctx = context if context is not None else _sweep.SweepContext(p)
    sw = build_sweeps(p, sources, ctx)
    t1 = time.perf_counter()
    n_sweeps, n_entries = len(sw.origin), len(sw.seg)
    sweep_checks, sweep_casts = sw.exact_checks, sw.exact_casts
    exact = ctx.exact  # the points of P′ as homogeneous integers, with the exact edge vectors
    ends = EndComparator(exact)
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
    sw.seg = None  # type: ignore[assignment]  # consumed (the build frees each array once it is done with it)

    if wanted is None:
        # ---- arcs: every pair met by some sweep, both directions
        both = np.concatenate([A_key, B_key])
        swapped = both % N
        swapped *= N
        swapped += both // N
        keys = np.concatenate([both, swapped])
        del both, swapped
        keys = sorted_unique(keys, overwrite=True)
    elif met:  # ---- the arcs from the sources that their sweeps meet
        keys = sorted_unique(np.concatenate([A_key, B_key]), overwrite=True)
    else:  # ---- arcs that may be safe: met by the sweeps at both ends of the source
        keys = sorted_intersection(A_key, B_key)
    n_arcs = len(keys)

    # ---- candidate safe sets: A_a(j) ∩ A_b(j) (closures), a sort-merge join on (i, j)
    order = np.argsort(A_key, kind="stable")
    A_key = A_key[order]
    ia = ia[order]
    order = np.argsort(B_key, kind="stable")
    B_key = B_key[order]
    ib = ib[order]
    del order
    b_start = np.searchsorted(B_key, A_key, side="left")
    cnt = np.searchsorted(B_key, A_key, side="right") - b_start
    del B_key
    pkey = np.repeat(A_key, cnt)
    del A_key
    pa = np.repeat(ia, cnt)
    del ia
    pb = ib[np.repeat(b_start, cnt) + ragged_arange(cnt)]
    del ib, b_start, cnt
    lo_pick, hi_pick = _intersect_ends(ends, seg_edge, N, pkey, sw, pa, pb)
    del pa, pb
    arc = np.searchsorted(keys, pkey)
    del pkey
    pieces = _take_entries(sw, arc, lo_pick, hi_pick)  # the entries are consumed: the hole step reads the rest of sw
    del arc, lo_pick, hi_pick
    source, target = keys // N, keys % N
    del keys
    step("safe BVG: safe sets", 1, 4)
    edge_of = seg_edge[source]
    pieces = nonempty(pieces, ends, edge_of)

    # ---- holes lying strictly inside every swept region of a range of headings
    if len(env.rings) > 1 and len(pieces.arc):
        pieces = subtract_holes(p, sw, pieces, ends, source, target, edge_of)
    del sw

    # ---- single points: closures may add isolated points; check them exactly
    step("safe BVG: safe sets", 2, 4)
    single = singletons(pieces, ends, edge_of)
    n_single = int(np.count_nonzero(single))
    if n_single:
        rows = np.flatnonzero(single)
        ok = single_headings_safe(p, exact, source, target, pieces.take(rows), edge_of)
        keep = np.ones(len(pieces.arc), dtype=bool)
        keep[rows[~ok]] = False
        pieces = pieces.take(np.flatnonzero(keep))
    del single
    refine_ends(p, pieces, edge_of)
    t2 = time.perf_counter()

    # ---- per arc: all intervals (sorted), the widest one
    if not sorted_by_arc_lo(pieces):
        pieces = pieces.take(np.lexsort((pieces.lo, pieces.arc)))
    counts = np.bincount(pieces.arc, minlength=n_arcs).astype(np.int64)
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    # exact ends: an end at a frame mark is exactly 0 or π; equal exact ends share one float
    set_lo = np.where(pieces.lo_to == MARK_ZERO, 0.0, pieces.lo)
    set_hi = np.where(pieces.hi_to == MARK_PI, math.pi, pieces.hi)
    equal = equal_ends(pieces, ends, edge_of)
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
    transition, phi = transitions_and_phi(env, seg_edge[source], seg_edge[target])
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
    if wanted is not None and not met:  # only the arcs with a safe heading
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


def _intersect_ends(ends: EndComparator, seg_edge: np.ndarray, N: int, pkey: np.ndarray, sw: _sweep.Sweeps,
                    pa: np.ndarray, pb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each joined pair of entries (``pa`` from the sweep at a, ``pb`` at b, same arc ``pkey``), the entry whose lo
    end is the larger and the one whose hi end is the smaller: the ends of A_a(j) ∩ A_b(j). In blocks, so that the
    comparison's gathered operands (eight arrays per row) never exist for all pairs at once."""
    lo_pick = np.empty_like(pa)
    hi_pick = np.empty_like(pa)
    block = 1 << 18
    for s0 in range(0, len(pa), block):
        a, b = pa[s0 : s0 + block], pb[s0 : s0 + block]
        edge = seg_edge[pkey[s0 : s0 + block] // N]
        fa, fb = sw.origin[sw.sweep[a]], sw.origin[sw.sweep[b]]
        c = ends.cmp(edge, fa, sw.lo_to[a], sw.lo[a], sw.lo_err[a], fb, sw.lo_to[b], sw.lo[b], sw.lo_err[b])
        lo_pick[s0 : s0 + block] = np.where(c >= 0, a, b)
        c = ends.cmp(edge, fa, sw.hi_to[a], sw.hi[a], sw.hi_err[a], fb, sw.hi_to[b], sw.hi[b], sw.hi_err[b])
        hi_pick[s0 : s0 + block] = np.where(c <= 0, a, b)
    return lo_pick, hi_pick


def _take_entries(sw: _sweep.Sweeps, arc: np.ndarray, lo_pick: np.ndarray, hi_pick: np.ndarray) -> Pieces:
    """The candidate intervals: for each joined pair, its arc row, the lo end of entry ``lo_pick`` and the hi end of
    entry ``hi_pick``. Each of the sweeps' entry arrays is dropped from ``sw`` as soon as it has been read, so the
    entries and the pieces never exist whole at once."""
    def take(name: str, rows: np.ndarray) -> np.ndarray:
        out = getattr(sw, name)[rows]
        setattr(sw, name, None)
        return out

    lo_from, hi_from = sw.origin[sw.sweep[lo_pick]], sw.origin[take("sweep", hi_pick)]
    return Pieces(arc, lo_from, take("lo_to", lo_pick), take("lo", lo_pick), take("lo_err", lo_pick),
                  hi_from, take("hi_to", hi_pick), take("hi", hi_pick), take("hi_err", hi_pick))


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
    p = as_partition(partition)
    N = len(p.segments)
    frontier = np.unique(np.asarray(start, dtype=np.int64))
    if len(frontier) and not (0 <= frontier[0] and frontier[-1] < N):
        raise InvalidBoundarySet(f"start segments must be in 0..{N - 1}")
    t0 = time.perf_counter()
    ctx = _sweep.SweepContext(p)
    seen = np.zeros(N, dtype=bool)
    parts: list[SafeBVG] = []
    batch, depth, sweeps, kept = 64, 0, 0, 0
    limit, limit_source = memory_limit()
    while len(frontier) and (max_depth is None or depth < max_depth):
        seen[frontier] = True
        found = []
        b0 = 0
        while b0 < len(frontier):  # the batch size changes as it goes: step by the chunk built, never a fixed stride
            step("safe BVG: reachable part", int(seen.sum()) - len(frontier) + b0, N)
            chunk = frontier[b0:b0 + batch]
            b0 += len(chunk)
            g = _build(p, chunk, ctx)
            parts.append(g)
            found.append(g.target)
            kept += g.n_arcs
            if limit is not None and BASE_BYTES + PLANNED_BYTES_PER_ARC * kept > limit:
                refuse_reachable(p, kept, int(seen.sum()), limit, limit_source)
            sweeps += g.stats["sweeps"]
            # next batch: about 2²⁰ sweep entries (≈ 200 MB of temporaries at the build's peak)
            per_source = max(1.0, g.stats["entries"] / len(chunk))
            batch = int(min(8192, max(8, (1 << 20) / per_source)))
        targets = sorted_unique(np.concatenate(found)) if found else np.zeros(0, dtype=np.int64)
        frontier = targets[~seen[targets]]
        depth += 1
    graph = _concat_rows(p, parts)
    graph.stats.update({"reachable_sources": int(seen.sum()), "sweeps": sweeps, "layers": depth,
                        "seconds_total": time.perf_counter() - t0, "lazy": True})
    return graph


def _concat_rows(p: Partition, parts: list[SafeBVG]) -> SafeBVG:
    """One graph of the arcs of ``parts`` (disjoint sources), sorted by (source, target)."""
    cat = lambda name: np.concatenate([getattr(g, name) for g in parts]) if parts else np.zeros(0)  # noqa: E731
    source = cat("source").astype(np.int64)
    target = cat("target").astype(np.int64)
    counts = cat("n_intervals").astype(np.int64)
    order = np.argsort(source * len(p.segments) + target, kind="stable")  # = lexsort((target, source)), twice as fast
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
