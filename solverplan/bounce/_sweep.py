"""Angular visibility sweeps from the vertices of P′ (the engine of :mod:`solverplan.bounce.bvg`).

For every vertex x of P′ and every frame in which x is the end of a segment (the edge direction of
the segment starting at x — role "+", x = a of that segment — and of the segment ending at x —
role "−", x = b), a *sweep* lists, in increasing heading θ ∈ (0, π), which segment of P′ the ray
from x first meets: a sequence of **entries** (sweep, segment j, [θ_lo, θ_hi]) of positive width.
The headings of an entry are the closure of the headings whose ray from x (not passing through a
vertex) lands in the open segment j; its ends are directions from x towards a vertex of P′, or
the frame ends 0 / π, kept as exact references.

Why this is enough (see :mod:`solverplan.bounce.safe`, proof (4), and :mod:`solverplan.bounce.bvg`):
for a fixed heading that is not critical the first hit from x + ε(b − a) converges to the first hit
from x, so these closures are the closures of the paper's "rays from the points of e_i next to a
(resp. b)"; the first-hit edge changes only at directions towards **original** vertices, and the
segment inside a stretch of one edge changes at directions towards the **P′** vertices on it.

Algorithm (all sweeps at once, numpy; exact rational arithmetic only near ties):

1. headings of all original vertices from every sweep origin, classified against the sweep's
   region (below the frame line, on it, inside, beyond a convex corner's wall) — exact where the
   float filter cannot decide;
2. per sweep, the distinct critical directions in increasing order (exactly equal directions —
   collinear vertices, systematic in P′ — merged exactly); the open *sectors* between them;
3. every front-facing edge covers a contiguous range of sectors (from its start vertex's rank to its
   end vertex's rank); the first-hit edge of a sector is the nearest covering edge along the sector's
   bisector (a near-tie, a thin sector or an uncovered one is cast exactly with
   :func:`~solverplan.geometry.raycast.cast_ray` along an exact bisector);
4. consecutive sectors hitting one edge form a *run*; the P′ vertices of that edge strictly inside
   the run's angular range (decided exactly near ties) cut it into entries, one per segment;
5. at a convex original vertex, the headings beyond the wall (towards the neighbouring segment on the
   other edge) form one more entry (paper Cor. 1).

Cost: O(M·n log n) for M sweeps (M ≤ 2·|P′|) and n original vertices, plus the number of
(sector, covering edge) pairs and of entries (about the number of visible segment pairs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from solverplan._arrays import ragged_arange
from solverplan.errors import SolverFailed
from solverplan.geometry.raycast import cast_ray
from solverplan.progress import step

# Float tolerances (public: the graph's build in bvg decides its own float ties with the same ones).
# Headings (radians) closer than this are compared exactly; the tolerance is
# scaled by the conditioning of each direction (coordinate magnitude / vector length).
ANGLE_REL = 1e-13
# Float cross products of differences of rounded points closer to 0 than this times the product of
# the magnitudes involved are decided exactly (the float error is about 1e-15 of it).
CROSS_REL = 1e-13
# Sectors narrower than this (radians) are resolved with an exact ray (their float bisector may not
# be strictly inside); relative gap of the two nearest edges along a bisector that counts as a tie.
_THIN = 1e-9
_DEPTH_REL = 1e-9
# Elements per numpy block: (sweep × vertex) cells in the classification (a few dozen bytes of
# temporaries each), (sector, edge) tests in the hit search, candidates when cutting runs.
_CELLS = 1 << 19
_BLOCK = 1 << 21

# Vertex classes against a sweep's region (headings relative to the frame).
_NONE, _BELOW, _AHEAD, _BEHIND, _IN, _AT_LO, _BEFORE_LO, _AT_HI, _BEYOND_HI = range(9)
_START_LOW = (_AHEAD, _BEFORE_LO, _AT_LO, _BELOW)  # start rank 0
_END_LOW = (_AHEAD, _BEFORE_LO, _AT_LO)  # end rank 0 (a BELOW end wraps through π: rank K+1)

MARK_ZERO, MARK_PI = -1, -2
"""Reference ids of the frame ends: heading 0 (direction b − a) and heading π (direction a − b)."""

# A float heading or edge direction formed from rounded coordinates is off by up to about
# 2⁻⁵² × (magnitude of the coordinates) / (length of the difference): nothing at a wall's scale, but
# 1e-7 rad for a 1e-9-long feature at coordinates near 2, or 1e-5 rad for a 10-long one translated
# by 1e12. Where that bound (with ANGLE_REL's margin) exceeds REFINE (radians), the value is
# recomputed from the exact coordinates, so every float answer is accurate to about 1e-16 of the
# angle whatever the translation; elsewhere the plain float value is already that accurate.
REFINE = 1e-10
_ROUND = 2.0**-52


def _local_points(partition) -> np.ndarray:
    """Float coordinates of the points of P′ for the sweeps: the rounded points, or, for an environment
    lying farther from 0 than 4 times its size, the rounded exact differences from a float point c at
    the centre of its bounding box. Every sweep quantity is a difference of points, unchanged by the
    shift, but rounding far from 0 would cost up to 2⁻⁵³ × |coordinate| on each: 1e-4 at 1e12."""
    P = np.asarray(partition.seg_start, dtype=float)
    if not len(P):
        return P
    low, high = P.min(axis=0), P.max(axis=0)
    if float(np.max(np.abs(P))) <= 4.0 * float(np.max(high - low)):
        return P
    c = [Fraction(float(x)) for x in (low + high) / 2]
    return np.array([[float(s.a[0] - c[0]), float(s.a[1] - c[1])] for s in partition.segments], dtype=float)


def float_edge_vectors(env) -> np.ndarray:
    """Float edge vectors b − a of ``env`` (shape (n, 2)), accurate to rounding: the difference of the
    float vertices where it is well conditioned, else the exact difference rounded once."""
    A, B = env.edge_start, env.edge_end
    ev = B - A
    mag = max_norm(A) + max_norm(B)
    bad = np.flatnonzero(ANGLE_REL * mag > REFINE * np.hypot(ev[:, 0], ev[:, 1]))
    if len(bad):
        ev = ev.copy()
        verts, nv = env.exact_vertices, env.next_vertex
        for e in bad.tolist():
            a, b = verts[e], verts[int(nv[e])]
            ev[e] = (float(b[0] - a[0]), float(b[1] - a[1]))
    return ev


def accurate_headings(partition, edge: np.ndarray, frm: np.ndarray, to: np.ndarray) -> np.ndarray:
    """Headings (radians, in [0, π]) of the directions P′[to] − P′[frm] (P′ vertex ids; ``to`` ≥ 0)
    in the frames of ``edge``, accurate to a few units of 1e-16 whatever the coordinates' magnitude.

    The points involved are carried as double-doubles (hi = float(x), lo = float(x − hi), from the
    exact coordinates; :meth:`~solverplan.bounce.partitions.Partition.point_vectors`), so the
    differences are accurate to rounding relative to the *difference*; the frame is the edge's
    exact direction rounded.
    """
    if not len(frm):
        return np.zeros(0)
    env = partition.env
    r = partition.point_vectors(frm, to, accurate=True)
    r = r / np.maximum(np.abs(r).max(axis=1), 1e-300)[:, None]  # atan2 is scale-free; no underflow below
    verts, nv = env.exact_vertices, env.next_vertex
    vec = {}
    for e in np.unique(edge).tolist():
        a, b = verts[e], verts[int(nv[e])]
        dx, dy = b[0] - a[0], b[1] - a[1]
        m = max(abs(dx), abs(dy))
        vec[e] = (float(dx / m), float(dy / m))
    f = np.array([vec[e] for e in edge.tolist()], dtype=float).reshape(-1, 2)
    cr = f[:, 0] * r[:, 1] - f[:, 1] * r[:, 0]
    dt = f[:, 0] * r[:, 0] + f[:, 1] * r[:, 1]
    h = np.arctan2(cr, dt)
    # on the frame line (cross exactly 0, or rounded just below it): 0 ahead, π behind
    return np.where(h < 0, np.where(dt > 0, 0.0, math.pi), h)


# ---------------------------------------------------------------------------------------------
# exact points as homogeneous integers
# ---------------------------------------------------------------------------------------------
class ExactPoints:
    """The vertices of P′ as homogeneous integers (X, Y, W), W > 0: exact cross-product signs in
    Python integer arithmetic, plus exact edge directions of the original edges."""

    def __init__(self, points, edge_vectors) -> None:
        self.X, self.Y, self.W = [], [], []
        for x, y in points:
            w = math.lcm(x.denominator, y.denominator)
            self.X.append(x.numerator * (w // x.denominator))
            self.Y.append(y.numerator * (w // y.denominator))
            self.W.append(w)
        self.edge_vectors = edge_vectors  # exact (dx, dy) of every original edge, as Fractions

    def vec(self, frm: int, to: int) -> tuple[int, int, int]:
        """to − from as a homogeneous vector (x, y, w): the direction is (x, y) (w > 0)."""
        X, Y, W = self.X, self.Y, self.W
        wf, wt = W[frm], W[to]
        return X[to] * wf - X[frm] * wt, Y[to] * wf - Y[frm] * wt, wf * wt

    def point(self, k: int) -> tuple[int, int, int]:
        """P′ vertex k as homogeneous integers (X, Y, W), W > 0."""
        return self.X[k], self.Y[k], self.W[k]

    def direction(self, frm: int, to: int, edge: int) -> tuple[int, int]:
        """An integer vector with the direction of ``to`` − ``from`` (P′ ids), or of the frame ends:
        ``to`` = MARK_ZERO is the direction of ``edge``, MARK_PI its reverse."""
        if to >= 0:
            x, y, _ = self.vec(frm, to)
            return x, y
        dx, dy = self.edge_vectors[edge]
        w = math.lcm(dx.denominator, dy.denominator)
        x, y = dx.numerator * (w // dx.denominator), dy.numerator * (w // dy.denominator)
        return (x, y) if to == MARK_ZERO else (-x, -y)

    def cross_sign(self, o: int, p: int, q: int) -> int:
        """Exact sign of cross(p − o, q − o)."""
        ux, uy, _ = self.vec(o, p)
        vx, vy, _ = self.vec(o, q)
        c = ux * vy - uy * vx
        return (c > 0) - (c < 0)

    def heading_cmp(self, edge: int, frm1: int, to1: int, frm2: int, to2: int) -> int:
        """Exact comparison of the headings (in the frame of ``edge``) of two directions; both must
        lie in the closed upper half-plane of the edge (headings in [0, π])."""
        e = self.direction(0, MARK_ZERO, edge)
        u = self.direction(frm1, to1, edge)
        v = self.direction(frm2, to2, edge)

        def cls(w: tuple[int, int]) -> int:
            c = e[0] * w[1] - e[1] * w[0]
            if c > 0:
                return 1
            return 0 if (c == 0 and e[0] * w[0] + e[1] * w[1] > 0) else 2 if c == 0 else -1

        cu, cv = cls(u), cls(v)
        if cu != cv:
            return -1 if cu < cv else 1
        if cu != 1:
            return 0
        c = u[0] * v[1] - u[1] * v[0]
        return -((c > 0) - (c < 0))


# ---------------------------------------------------------------------------------------------
# the sweeps
# ---------------------------------------------------------------------------------------------
@dataclass
class Sweeps:
    """All sweeps of one partition and their entries (flat numpy arrays).

    Sweep arrays (length M): ``origin`` (P′ vertex id), ``frame`` (edge id whose direction is
    heading 0), ``plus_seg`` / ``minus_seg`` (the segment this sweep is the "+" / "−" end of, or −1).
    Entry arrays (length K): ``sweep``, ``seg``, ``lo_to`` / ``hi_to`` (P′ vertex id or MARK_*),
    ``lo`` / ``hi`` (float headings), ``lo_err`` / ``hi_err`` (their error bounds).
    Hole arrays (when the environment has holes, shape (M, holes)): ``hole_alpha`` (max heading of a
    hole's vertices), ``hole_alpha_v`` (that vertex, P′ id), ``hole_beta`` / ``hole_beta_v`` (min).
    """

    origin: np.ndarray
    frame: np.ndarray
    plus_seg: np.ndarray
    minus_seg: np.ndarray
    sweep: np.ndarray
    seg: np.ndarray
    lo_to: np.ndarray
    hi_to: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    lo_err: np.ndarray
    hi_err: np.ndarray
    hole_alpha: np.ndarray | None = None
    hole_alpha_v: np.ndarray | None = None
    hole_beta: np.ndarray | None = None
    hole_beta_v: np.ndarray | None = None
    exact_checks: int = 0
    exact_casts: int = 0


class SweepContext:
    """Float and exact views of one partition shared by the sweep steps."""

    depth_pairs: int  # set by _hit_edges (diagnostics): (sector, covering edge) pairs, and those tested after pruning
    depth_tested: int

    def __init__(self, partition) -> None:
        env = partition.env
        self.partition = partition
        self.env = env
        segs = partition.segments
        self.N = N = len(segs)
        self.n = n = env.n_vertices
        self.P = _local_points(partition)  # P′ vertex k = start of segment k
        self.seg_edge = np.asarray(partition.seg_edge, dtype=np.int64)
        self.nxt = np.asarray(partition.next_segment, dtype=np.int64)
        self.prv = np.asarray(partition.prev_segment, dtype=np.int64)
        self.edge_first = np.searchsorted(self.seg_edge, np.arange(n + 1), side="left").astype(np.int64)
        self.orig_pv = self.edge_first[:n].copy()  # original vertex v starts edge v: its P′ id
        self.pv_orig = np.full(N, -1, dtype=np.int64)
        self.pv_orig[self.orig_pv] = np.arange(n)
        verts = env.exact_vertices
        nv = env.next_vertex
        edge_vectors = [(verts[int(nv[e])][0] - verts[e][0], verts[int(nv[e])][1] - verts[e][1]) for e in range(n)]
        self.exact = ExactPoints([s.a for s in segs], edge_vectors)
        self.edge_vec = float_edge_vectors(env)
        self.edge_unit = self.edge_vec / np.hypot(self.edge_vec[:, 0], self.edge_vec[:, 1])[:, None]
        self.V = self.P[self.orig_pv]
        self.A = self.V
        self.B = self.V[np.asarray(env.next_vertex, dtype=np.int64)]
        self.scale = float(np.max(np.abs(self.V))) + 1.0
        self.exact_checks = 0
        self.exact_casts = 0
        self.depth_pairs = self.depth_tested = 0
        # turn at each original vertex: +1 convex, -1 reflex, 0 flat (exact)
        reflex = set(env.reflex_vertices)
        pv = env.prev_vertex
        from solverplan.exact import orient

        self.turn = np.array(
            [-1 if v in reflex else orient(verts[int(pv[v])], verts[v], verts[int(nv[v])]) for v in range(n)],
            dtype=np.int8,
        )

    # exact helpers used by the float filters ---------------------------------------------------
    def cross_sign(self, o: int, p: int, q: int) -> int:
        self.exact_checks += 1
        return self.exact.cross_sign(o, p, q)

    def frame_cross_sign(self, edge: int, o: int, p: int) -> int:
        """Exact sign of cross(direction of ``edge``, P′[p] − P′[o])."""
        self.exact_checks += 1
        ex, ey = self.exact.direction(0, MARK_ZERO, edge)
        vx, vy, _ = self.exact.vec(o, p)
        c = ex * vy - ey * vx
        return (c > 0) - (c < 0)


def build_sweeps(partition, sources: np.ndarray | None = None, context: SweepContext | None = None) -> Sweeps:
    """All sweeps of ``partition`` and their entries (see the module docstring); with ``sources`` (segment ids),
    only the sweeps at the two ends of those segments (each sweep is computed on its own: the same entries).

    Memory follows the output: the (sweep × vertex) tables of steps 1–2 exist for one block of
    sweeps at a time (:data:`_BLOCK` cells), and only their compact results are kept — the
    direction tables, and per (sweep, covering edge) pair its range of sectors. ``context``: the partition's
    :class:`SweepContext`, when the caller keeps one for several calls.
    """
    ctx = context if context is not None else SweepContext(partition)
    ctx.exact_checks = ctx.exact_casts = 0
    origin, frame, plus_seg, minus_seg, lo_lim, hi_lim = _define_sweeps(ctx)
    if sources is not None:
        wanted = np.zeros(ctx.N + 1, dtype=bool)  # index −1 (no segment) reads the last, False
        wanted[np.asarray(sources, dtype=np.int64)] = True
        keep = np.flatnonzero(wanted[plus_seg] | wanted[minus_seg])
        origin, frame, plus_seg, minus_seg, lo_lim, hi_lim = (a[keep] for a in (origin, frame, plus_seg, minus_seg,
                                                                               lo_lim, hi_lim))
    M, n = len(origin), ctx.n
    holes = len(ctx.env.rings) > 1
    rows = max(1, _CELLS // max(n, 1))
    parts: list[tuple] = []
    for s0 in range(0, M, rows):
        step("safe BVG: sweeps", s0, M)  # the progress bar, and where a timeout stops the build
        sl = slice(s0, min(M, s0 + rows))
        o, fr = origin[sl], frame[sl]
        # ---- 1. headings and classes of all original vertices, and the critical directions
        cls, ang, err = _classify(ctx, o, fr, lo_lim[sl], hi_lim[sl])
        rank, K, dir_ang, dir_to, dir_err, dir_off, thin = _rank(ctx, o, fr, lo_lim[sl], hi_lim[sl], cls, ang, err)
        pairs = _covering(ctx, o, cls, rank, K)
        extremes = _hole_extremes(ctx, o, fr, ang, err) if holes else None
        del cls, rank, ang, err
        # ---- 2. first-hit edge of every sector
        hit = _hit_edges(ctx, o, fr, K, dir_ang, dir_to, dir_off, thin, pairs)
        del pairs
        # ---- 3. runs and entries
        block = list(_entries(ctx, o, fr, K, dir_ang, dir_to, dir_err, dir_off, hit))
        block[0] = block[0] + s0
        parts.append((block, extremes))
    # the entries of all blocks, one column at a time
    entries = []
    for t in range(8):
        entries.append(np.concatenate([q[0][t] for q in parts]) if parts else np.zeros(0, dtype=np.int64 if t < 4 else float))
        for q in parts:
            q[0][t] = None
    ext = [q[1] for q in parts]
    del parts
    special = _special_entries(ctx, origin, frame, lo_lim, hi_lim)
    # Order by (sweep, heading). The entries of a sweep are already in heading order, and its
    # Cor. 1 entries are its first (from heading 0) or last (up to π) one: a stable sort on the
    # sweep alone of [entries from 0, entries, entries up to π] is that order.
    n_hi = int(np.count_nonzero(hi_lim >= 0))  # the special entries list the "+" rows (up to π) first
    entries, special = list(entries), list(special)
    order = np.argsort(np.concatenate([special[0][n_hi:], entries[0], special[0][:n_hi]]), kind="stable")
    cols = []
    for t in range(len(entries)):  # one column at a time: the unsorted copy is dropped at once
        a, b = entries[t], special[t]
        entries[t] = special[t] = None  # type: ignore[call-overload]  # drop each column once copied
        cols.append(np.concatenate([b[n_hi:], a, b[:n_hi]])[order])
        del a, b
    del order
    sweep, seg, lo_to, hi_to, lo, hi, lo_err, hi_err = cols
    del cols
    sweeps = Sweeps(origin, frame, plus_seg, minus_seg, sweep, seg, lo_to, hi_to, lo, hi, lo_err, hi_err)
    if holes:
        sweeps.hole_alpha, sweeps.hole_alpha_v, sweeps.hole_beta, sweeps.hole_beta_v = (
            np.concatenate([x[t] for x in ext]) for t in range(4))
    sweeps.exact_checks = ctx.exact_checks
    sweeps.exact_casts = ctx.exact_casts
    return sweeps


def _define_sweeps(ctx: SweepContext):
    """One sweep per inserted / flat vertex of P′, two per convex or reflex original vertex."""
    N = ctx.N
    k = np.arange(N, dtype=np.int64)
    orig = ctx.pv_orig >= 0
    turn = np.where(orig, ctx.turn[np.maximum(ctx.pv_orig, 0)], 0)
    single = turn == 0  # inserted points and flat original vertices: one frame serves both roles
    double = ~single
    ks, kd = k[single], k[double]
    convex_d = turn[double] > 0
    origin = np.concatenate([ks, kd, kd])
    frame = np.concatenate([ctx.seg_edge[ks], ctx.seg_edge[kd], ctx.seg_edge[ctx.prv[kd]]])
    none = np.full(len(kd), -1, dtype=np.int64)
    plus_seg = np.concatenate([ks, kd, none])
    minus_seg = np.concatenate([ctx.prv[ks], none, ctx.prv[kd]])
    # region limits (P′ id of the point whose direction bounds the region, or a frame mark)
    lo_lim = np.concatenate([np.full(len(ks), MARK_ZERO), np.full(len(kd), MARK_ZERO),
                             np.where(convex_d, ctx.nxt[kd], MARK_ZERO)]).astype(np.int64)
    hi_lim = np.concatenate([np.full(len(ks), MARK_PI), np.where(convex_d, ctx.prv[kd], MARK_PI),
                             np.full(len(kd), MARK_PI)]).astype(np.int64)
    return origin, frame, plus_seg, minus_seg, lo_lim, hi_lim


def _headings(ctx: SweepContext, origin: np.ndarray, frame: np.ndarray, pts: np.ndarray):
    """Float headings of points ``pts`` (shape (M, k, 2)) from the sweep origins, with error bounds
    and the raw cross/dot (frame unit vector × relative vector)."""
    X = ctx.P[origin][:, None, :]
    f = ctx.edge_unit[frame][:, None, :]
    rel = pts - X
    cr = f[..., 0] * rel[..., 1] - f[..., 1] * rel[..., 0]
    dt = f[..., 0] * rel[..., 0] + f[..., 1] * rel[..., 1]
    length = np.hypot(rel[..., 0], rel[..., 1])
    mag = max_norm(X) + max_norm(pts)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = ANGLE_REL * mag / length + 1e-15
    return np.arctan2(cr, dt), err, cr, length, mag


def _classify(ctx: SweepContext, origin, frame, lo_lim, hi_lim):
    """Class of every (sweep, original vertex), its heading and heading error (exact near ties)."""
    M, n = len(origin), ctx.n
    cls = np.empty((M, n), dtype=np.int8)
    ang = np.empty((M, n))
    err = np.empty((M, n))
    rows = max(1, _BLOCK // max(n, 1))
    A_of = ctx.orig_pv  # P′ ids of the original vertices
    nv = np.asarray(ctx.env.next_vertex, dtype=np.int64)
    for s0 in range(0, M, rows):
        sl = slice(s0, min(M, s0 + rows))
        o, fr = origin[sl], frame[sl]
        V = np.broadcast_to(ctx.V, (len(o), n, 2))
        a, e, cr, length, mag = _headings(ctx, o, fr, V)
        thr = ANGLE_REL * mag + 1e-15 * length  # bound on the float error of cr
        upper = cr > thr  # certainly strictly above the frame line
        lower = cr < -thr
        c = np.where(upper, _IN, np.where(lower, _BELOW, _NONE)).astype(np.int8)
        # structure: the origin itself; the frame edge's own end points lie on the frame line
        same = A_of[None, :] == o[:, None]
        c[same] = _NONE
        r = np.arange(len(o))
        fstart, fend = fr, nv[fr]
        c[r, fend] = np.where(A_of[fend] == o, _NONE, _AHEAD)
        c[r, fstart] = np.where(A_of[fstart] == o, _NONE, _BEHIND)
        # undecided: exact sign against the frame line
        und = (c == _NONE) & ~same
        und[r, fend] = False
        und[r, fstart] = False
        for i, w in zip(*np.nonzero(und)):
            m = s0 + int(i)
            s = ctx.frame_cross_sign(int(frame[m]), int(origin[m]), int(A_of[w]))
            if s > 0:
                c[i, w] = _IN
            elif s < 0:
                c[i, w] = _BELOW
            else:
                c[i, w] = _AHEAD if float(np.dot(ctx.V[w] - ctx.P[origin[m]], ctx.edge_unit[frame[m]])) > 0 else _BEHIND
        # convex corners: the region ends at the wall of the other edge
        for lim, at, beyond in ((hi_lim[sl], _AT_HI, _BEYOND_HI), (lo_lim[sl], _AT_LO, _BEFORE_LO)):
            rows_lim = np.flatnonzero(lim >= 0)
            if len(rows_lim) == 0:
                continue
            Lp = ctx.P[lim[rows_lim]]
            X = ctx.P[o[rows_lim]]
            Lrel = Lp - X
            rel = V[rows_lim] - X[:, None, :]
            # hi limit: IN iff cross(w − x, L − x) > 0; lo limit: IN iff cross(L − x, w − x) > 0
            crl = rel[..., 0] * Lrel[:, None, 1] - rel[..., 1] * Lrel[:, None, 0]
            if at == _AT_LO:
                crl = -crl
            tol = CROSS_REL * (max_norm(rel) * max_norm(Lrel)[:, None] + 0.1 * ctx.scale * (max_norm(rel) + max_norm(Lrel)[:, None])) + 1e-300
            sub = c[rows_lim]
            cand = sub == _IN
            sure_in = cand & (crl > tol)
            sure_out = cand & (crl < -tol)
            sub[sure_out] = beyond
            for i, w in zip(*np.nonzero(cand & ~sure_in & ~sure_out)):
                m = s0 + int(rows_lim[i])
                o_id, l_id, w_id = int(origin[m]), int(lim[rows_lim[i]]), int(A_of[w])
                s = ctx.cross_sign(o_id, w_id, l_id) if at == _AT_HI else ctx.cross_sign(o_id, l_id, w_id)
                sub[i, w] = _IN if s > 0 else (at if s == 0 else beyond)
            c[rows_lim] = sub
        cls[sl], ang[sl], err[sl] = c, a, e
    return cls, ang, err


def _lim_heading(ctx: SweepContext, origin, frame, lim, default: float):
    out = np.full(len(origin), default)
    errs = np.zeros(len(origin))
    rows = np.flatnonzero(lim >= 0)
    if len(rows):
        a, e, *_ = _headings(ctx, origin[rows], frame[rows], ctx.P[lim[rows]][:, None, :])
        out[rows], errs[rows] = a[:, 0], e[:, 0]
    return out, errs


def _rank(ctx: SweepContext, origin, frame, lo_lim, hi_lim, cls, ang, err):
    """Distinct critical directions per sweep (exact ties merged), ranks of the vertices, sector tables.

    Returns rank (M, n) (1..K for inside vertices), K (M,), flat direction tables indexed by
    ``dir_off[m] + r`` for r = 0..K+1 (angle, reference P′ id or mark, error), and a flag per sector
    ``dir_off[m] + k`` (k = 0..K) for thin sectors.
    """
    M, n = cls.shape
    inside = cls == _IN
    key = np.where(inside, ang, np.inf)
    order = np.argsort(key, axis=1, kind="stable")
    skey = np.take_along_axis(key, order, axis=1)
    serr = np.take_along_axis(np.where(inside, err, 0.0), order, axis=1)
    count = inside.sum(axis=1)
    valid = np.arange(n)[None, :] < count[:, None]
    with np.errstate(invalid="ignore"):
        gap = np.diff(skey, axis=1)
    near = valid[:, 1:] & (gap <= serr[:, 1:] + serr[:, :-1])
    new = np.ones((M, n), dtype=bool)
    new[:, 1:] = ~near
    for m, j in zip(*np.nonzero(near)):
        w1, w2 = int(order[m, j]), int(order[m, j + 1])
        s = ctx.cross_sign(int(origin[m]), int(ctx.orig_pv[w1]), int(ctx.orig_pv[w2]))
        new[m, j + 1] = s != 0
    new &= valid
    srank = np.cumsum(new, axis=1)
    rank = np.zeros((M, n), dtype=np.int64)
    np.put_along_axis(rank, order, np.where(valid, srank, 0), axis=1)
    K = srank[:, -1] if n else np.zeros(M, dtype=np.int64)
    # direction tables: r = 0 (lower limit), 1..K (first vertex of each rank), K+1 (upper limit)
    dir_off = np.concatenate([[0], np.cumsum(K + 2)])
    total = int(dir_off[-1])
    dir_ang = np.empty(total)
    dir_to = np.empty(total, dtype=np.int64)
    dir_err = np.zeros(total)
    lo_a, lo_e = _lim_heading(ctx, origin, frame, lo_lim, 0.0)
    hi_a, hi_e = _lim_heading(ctx, origin, frame, hi_lim, math.pi)
    dir_ang[dir_off[:-1]] = lo_a
    dir_to[dir_off[:-1]] = lo_lim
    dir_err[dir_off[:-1]] = lo_e
    dir_ang[dir_off[1:] - 1] = hi_a
    dir_to[dir_off[1:] - 1] = hi_lim
    dir_err[dir_off[1:] - 1] = hi_e
    mm, jj = np.nonzero(new)
    pos = dir_off[mm] + srank[mm, jj]
    dir_ang[pos] = skey[mm, jj]
    dir_to[pos] = ctx.orig_pv[order[mm, jj]]
    dir_err[pos] = serr[mm, jj]
    # sector k of sweep m lies between directions k and k+1: flat index dir_off[m] + k (k <= K)
    width = np.diff(dir_ang)
    # a float bisector is strictly inside its sector when the sector is wider than twice either end's error
    thin = width <= np.maximum(_THIN, 2.0 * np.maximum(dir_err[1:], dir_err[:-1]))
    return rank, K, dir_ang, dir_to, dir_err, dir_off, thin


def max_norm(x: np.ndarray) -> np.ndarray:
    """Max-norm over the last axis (of length 2), without a slow axis reduction."""
    return np.maximum(np.abs(x[..., 0]), np.abs(x[..., 1]))


def _front_facing(ctx: SweepContext, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (sweep row, edge) with the origin strictly left of the edge's line (exact near ties)."""
    M, n = len(origin), ctx.n
    rows_out, edges_out = [], []
    rows = max(1, _BLOCK // max(n, 1))
    A, d = ctx.A, ctx.edge_vec  # d accurate to rounding: the float ends of a short edge far from 0 are not
    own = ctx.seg_edge  # edge of the segment starting at each P′ vertex
    for s0 in range(0, M, rows):
        o = origin[s0 : s0 + rows]
        X = ctx.P[o]
        rel = X[:, None, :] - A[None, :, :]
        cr = d[None, :, 0] * rel[..., 1] - d[None, :, 1] * rel[..., 0]
        tol = 0.1 * CROSS_REL * (max_norm(d)[None, :] * (max_norm(rel) + ctx.scale))
        front = cr > tol
        unsure = np.abs(cr) <= tol
        r = np.arange(len(o))
        # structure: the origin lies on its own edge (and on the previous edge when it is a vertex)
        front[r, own[o]] = False
        unsure[r, own[o]] = False
        pe = ctx.seg_edge[ctx.prv[o]]
        front[r, pe] = False
        unsure[r, pe] = False
        for i, e in zip(*np.nonzero(unsure)):
            a_id, b_id = int(ctx.orig_pv[e]), int(ctx.orig_pv[int(ctx.env.next_vertex[e])])
            front[i, e] = ctx.cross_sign(a_id, b_id, int(o[i])) > 0
        ii, ee = np.nonzero(front)
        rows_out.append(ii + s0)
        edges_out.append(ee)
    return np.concatenate(rows_out).astype(np.int64), np.concatenate(edges_out).astype(np.int64)


def _covering(ctx: SweepContext, origin, cls, rank, K):
    """(sweep row, edge, first sector, sector count) of every front-facing edge covering at least one
    sector of its sweep: the edge spans the sectors from its start vertex's rank to its end's."""
    m_idx, e_idx = _front_facing(ctx, origin)
    nv = np.asarray(ctx.env.next_vertex, dtype=np.int64)
    a_v, b_v = e_idx, nv[e_idx]
    ca, cb = cls[m_idx, a_v], cls[m_idx, b_v]
    Kp1 = K[m_idx] + 1
    sr = np.where(ca == _IN, rank[m_idx, a_v], np.where(np.isin(ca, _START_LOW), 0, Kp1))
    er = np.where(cb == _IN, rank[m_idx, b_v], np.where(np.isin(cb, _END_LOW), 0, Kp1))
    both_below = (ca == _BELOW) & (cb == _BELOW)
    er = np.where(both_below, sr, er)
    cnt = np.maximum(er - sr, 0)
    keep = cnt > 0
    return m_idx[keep], e_idx[keep], sr[keep].astype(np.int64), cnt[keep].astype(np.int64)


def _point_segment_distance(X: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Float distance from each point X to the closed segment AB (rows)."""
    d = B - A
    w = X - A
    dd = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]
    t = np.clip((w[:, 0] * d[:, 0] + w[:, 1] * d[:, 1]) / dd, 0.0, 1.0)
    return np.hypot(w[:, 0] - t * d[:, 0], w[:, 1] - t * d[:, 1])


def _hit_edges(ctx: SweepContext, origin, frame, K, dir_ang, dir_to, dir_off, thin, pairs) -> np.ndarray:
    """The first-hit edge of every sector (flat index dir_off[m] + k − m), −1 if none.

    ``pairs`` = (sweep, edge, first sector, count) of the covering edges (:func:`_covering`),
    sorted by sweep. The nearest covering edge along each sector's bisector wins; a near-tie, a
    thin sector or a sector without a finite hit is cast exactly.

    Occlusion pruning (it changes no answer): the sectors of a sweep are grouped in chunks of
    :data:`_CHUNK`. The nearest edge spanning a whole chunk (its *occluder*) is hit by every ray
    of the chunk at a distance at most its larger distance along the chunk's two end directions
    (the distance to a line along the heading θ is h / sin(θ − α), convex in θ); an edge whose
    distance from the sweep origin exceeds that bound, with a wide margin, is never the first
    hit nor within the tie margin in that chunk, and is not tested there. This makes the work
    follow the visible structure instead of every (sector, covering edge) pair.
    """
    m_idx, e_idx, sr, cnt = pairs
    M = len(K)
    n_sec = K + 1
    sec_off = np.concatenate([[0], np.cumsum(n_sec)]).astype(np.int64)
    total = int(sec_off[-1])
    hit = np.full(total, -1, dtype=np.int64)
    bad = np.zeros(total, dtype=bool)
    ctx.depth_pairs += int(cnt.sum())
    # blocks of whole sweeps (the pairs are sorted by sweep), about _BLOCK sector tests each
    p_of_m = np.searchsorted(m_idx, np.arange(M + 1))
    work = np.concatenate([[0], np.cumsum(cnt)])[p_of_m]
    m0 = 0
    while m0 < M:
        m1 = max(int(np.searchsorted(work, work[m0] + _BLOCK, side="right")) - 1, m0 + 1)
        m1 = min(m1, M)
        p0, p1 = int(p_of_m[m0]), int(p_of_m[m1])
        g0, g1 = int(sec_off[m0]), int(sec_off[m1])
        if p1 > p0:
            h, b = _hit_block(ctx, origin, frame, dir_ang, dir_off, thin, n_sec, sec_off, m0, m1,
                              m_idx[p0:p1], e_idx[p0:p1], sr[p0:p1], cnt[p0:p1])
            hit[g0:g1], bad[g0:g1] = h, b
        else:  # no covering edge at all: every sector is cast exactly (never happens in a valid room)
            bad[g0:g1] = True
        m0 = m1
    sec_m = np.repeat(np.arange(M), n_sec)
    for i in np.flatnonzero(bad).tolist():
        m = int(sec_m[i])
        k = i - int(sec_off[m])
        hit[i] = _exact_sector_hit(ctx, int(origin[m]), int(frame[m]),
                                   int(dir_to[dir_off[m] + k]), int(dir_to[dir_off[m] + k + 1]))
    return hit


# Sectors per occlusion chunk in _hit_edges; relative margin of its pruning bound.
_CHUNK = 8
_PRUNE_REL = 1e-6


def _hit_block(ctx, origin, frame, dir_ang, dir_off, thin, n_sec, sec_off, m0, m1,
               m_idx, e_idx, sr, cnt):
    """:func:`_hit_edges` for the sweeps m0..m1−1 and their pairs: (hit edge, needs an exact cast)
    per sector of these sweeps."""
    C = _CHUNK
    # per (sweep, edge) pair: numerator cross(A − X, d) of the distance along any unit direction
    # u, which is numer / cross(u, d); and the distance from X to the edge (a lower bound)
    X = ctx.P[origin[m_idx]]
    A, B = ctx.A[e_idx], ctx.B[e_idx]
    dvec = ctx.edge_vec[e_idx]
    dxp, dyp = dvec[:, 0], dvec[:, 1]
    rel = A - X
    numer = rel[:, 0] * dyp - rel[:, 1] * dxp
    dmin = _point_segment_distance(X, A, B)
    # error of a distance numer / cross(u, d) along a unit u: the coordinates are rounded (2⁻⁵³ of
    # their magnitude), d is accurate to rounding; with a margin of 8, it is at most
    # 2⁻⁴⁹ (err_num + distance · err_den) / |cross(u, d)| (see the tie test below)
    dn = max_norm(dvec)
    err_num = (max_norm(X) + max_norm(A) + max_norm(rel)) * dn
    del X, A, B, rel, dvec
    ms = np.arange(m0, m1)
    ns = n_sec[m0:m1]
    g0 = int(sec_off[m0])
    L = int(sec_off[m1]) - g0
    # sectors: sweep, index k, direction index, bisector unit vector
    s_m = np.repeat(ms, ns)
    s_k = ragged_arange(ns)
    s_g = dir_off[s_m] + s_k
    mid = 0.5 * (dir_ang[s_g] + dir_ang[s_g + 1])
    f = ctx.edge_unit[frame[s_m]]
    c, s = np.cos(mid), np.sin(mid)
    UX, UY = c * f[:, 0] - s * f[:, 1], s * f[:, 0] + c * f[:, 1]
    del mid, c, s
    # chunks of each sweep: chunk q of sweep m holds its sectors qC .. min(qC + C, K + 1) − 1
    nc = (ns + C - 1) // C
    c_off = np.concatenate([[0], np.cumsum(nc)]).astype(np.int64)  # local chunk numbering
    n_chunks = int(c_off[-1])
    lm = m_idx - m0  # local sweep of each pair
    first, stop = sr, sr + cnt  # sector range [first, stop) of each pair
    # pairs spanning whole chunks: chunk q is spanned iff first <= qC and min(qC + C, K + 1) <= stop
    q_lo = (first + C - 1) // C
    q_hi = np.where(stop == n_sec[m_idx], nc[lm], stop // C)  # exclusive
    nfull = np.maximum(q_hi - q_lo, 0)
    thr = np.full(n_chunks, np.inf)
    scale = ctx.scale
    if nfull.any():
        fp = np.repeat(np.arange(len(lm)), nfull)
        fq = np.repeat(q_lo, nfull) + ragged_arange(nfull)
        fc = c_off[lm[fp]] + fq  # local chunk id
        # distance along the bisector of the chunk's middle sector
        q_sec = np.minimum(fq * C + C // 2, n_sec[m_idx[fp]] - 1)
        gl = sec_off[m_idx[fp]] - g0 + q_sec
        with np.errstate(divide="ignore", invalid="ignore"):
            dist = numer[fp] / (UX[gl] * dyp[fp] - UY[gl] * dxp[fp])
        dist[~(dist > 0)] = np.inf
        best = np.full(n_chunks, np.inf)
        np.minimum.at(best, fc, dist)
        owner = np.full(n_chunks, -1, dtype=np.int64)
        win = np.isfinite(dist) & (dist == best[fc])
        owner[fc[win]] = fp[win]
        del fp, fq, q_sec, gl, dist, win
        # the occluder's distances along the chunk's two end directions
        oc = np.flatnonzero(owner >= 0)
        if len(oc):
            op = owner[oc]
            c_m = np.searchsorted(c_off, oc, side="right") - 1  # local sweep of the chunk
            q = oc - c_off[c_m]
            gm = c_m + m0
            r_lo = dir_off[gm] + q * C
            r_hi = dir_off[gm] + np.minimum(q * C + C, n_sec[gm])
            fo = ctx.edge_unit[frame[gm]]
            bound = np.zeros(len(oc))
            ok = np.ones(len(oc), dtype=bool)
            dlen = np.hypot(dxp[op], dyp[op])
            for r in (r_lo, r_hi):
                a = dir_ang[r]
                ca, sa = np.cos(a), np.sin(a)
                ux, uy = ca * fo[:, 0] - sa * fo[:, 1], sa * fo[:, 0] + ca * fo[:, 1]
                den = ux * dyp[op] - uy * dxp[op]
                with np.errstate(divide="ignore", invalid="ignore"):
                    d = numer[op] / den
                # well conditioned only: the ray crosses the line at a clear angle, inside the room
                ok &= (np.abs(den) > 1e-3 * dlen) & (d > 0) & (d < 3.0 * scale)
                bound = np.maximum(bound, np.where(ok, d, 0.0))
            thr[oc[ok]] = bound[ok] * (1.0 + _PRUNE_REL) + _PRUNE_REL * scale
    # pairs × overlapped chunks; keep those not certainly behind the chunk's occluder
    qa = first // C
    qb = (stop - 1) // C
    nq = qb - qa + 1
    pp = np.repeat(np.arange(len(lm)), nq)
    pq = np.repeat(qa, nq) + ragged_arange(nq)
    live = dmin[pp] <= thr[c_off[lm[pp]] + pq]
    pp, pq = pp[live], pq[live]
    lo = np.maximum(first[pp], pq * C)
    n_t = np.minimum(stop[pp], pq * C + C) - lo
    del live, pq
    # the surviving (pair, sector) tests
    rep = np.repeat(pp, n_t)
    gl = np.repeat(sec_off[m_idx[pp]] - g0 + lo, n_t) + ragged_arange(n_t)
    del pp, lo, n_t
    ctx.depth_tested += len(rep)
    den = UX[gl] * dyp[rep] - UY[gl] * dxp[rep]
    with np.errstate(divide="ignore", invalid="ignore"):
        dist = numer[rep] / den
        dist[~(dist > 0)] = np.inf
        # the float error bound of each distance: rounded coordinates far from 0 or a grazing ray
        # make distances unreliable, and the sector is then a tie, cast exactly
        err = _ROUND * 8.0 * (err_num[rep] + dist * dn[rep]) / np.abs(den)
    del den
    best = np.full(L, np.inf)
    np.minimum.at(best, gl, dist)
    hit = np.full(L, -1, dtype=np.int64)
    b = best[gl]
    win = dist == b
    hit[gl[win]] = e_idx[rep[win]]
    best_err = np.zeros(L)
    best_err[gl[win]] = err[win]
    # near the nearest: within the relative tie margin, or not separated by the two error bounds
    with np.errstate(invalid="ignore"):
        near = np.bincount(gl[dist - err <= b * (1.0 + _DEPTH_REL) + best_err[gl]], minlength=L)
    bad = thin[s_g] | ~np.isfinite(best) | (near != 1)
    return hit, bad


def _exact_sector_hit(ctx: SweepContext, o: int, frame: int, lo_to: int, hi_to: int) -> int:
    """The edge hit inside an open sector, by an exact ray along an exact bisector."""
    ctx.exact_casts += 1
    ex = ctx.exact
    u = ex.direction(o, lo_to, frame)
    v = ex.direction(o, hi_to, frame)
    nu = abs(u[0]) + abs(u[1])
    nv = abs(v[0]) + abs(v[1])
    d = (Fraction(u[0], nu) + Fraction(v[0], nv), Fraction(u[1], nu) + Fraction(v[1], nv))
    if d[0] == d[1] == 0:  # opposite directions (a sector of width π): turn the frame direction by π/2
        e = ex.direction(o, MARK_ZERO, frame)
        d = (Fraction(-e[1]), Fraction(e[0]))
    x = ctx.partition.segments[o].a
    hit = cast_ray(ctx.env, x, d)
    if hit.vertex is not None:  # pragma: no cover - no vertex lies strictly inside a sector
        raise SolverFailed(f"exact bisector from P′ vertex {o} hit vertex {hit.vertex} inside a sector")
    return hit.edge


def _entries(ctx: SweepContext, origin, frame, K, dir_ang, dir_to, dir_err, dir_off, hit):
    """Runs of sectors hitting one edge, cut by the P′ vertices on that edge into entries."""
    n_sec = K + 1
    sec_off = np.concatenate([[0], np.cumsum(n_sec)]).astype(np.int64)  # first sector of each sweep
    if len(hit) and (hit < 0).any():  # pragma: no cover - every ray in a valid environment hits
        i = int(np.flatnonzero(hit < 0)[0])
        m = int(np.searchsorted(sec_off, i, side="right")) - 1
        raise SolverFailed(f"no edge found for sector {i - int(sec_off[m])} of the sweep from P′ vertex {int(origin[m])}")
    # runs: maximal stretches of consecutive sectors of one sweep with one hit edge
    first = np.ones(len(hit), dtype=bool)
    first[1:] = hit[1:] != hit[:-1]
    first[sec_off[:-1][n_sec > 0]] = True
    starts = np.flatnonzero(first)
    del first
    ends = np.append(starts[1:], len(hit))  # exclusive
    r_m = np.searchsorted(sec_off, starts, side="right") - 1
    r_e = hit[starts]
    r_lo = dir_off[r_m] + starts - sec_off[r_m]  # direction index of the run's start
    r_hi = dir_off[r_m] + ends - sec_off[r_m]  # ... and of its end (k of its last sector + 1)
    # candidates: the interior P′ vertices of the run's edge; per run, how many lie before its
    # start direction (nb) and strictly inside it (ni) — in blocks of runs (memory)
    c0 = ctx.edge_first[r_e] + 1
    ccount = ctx.edge_first[r_e + 1] - c0
    nb = np.zeros(len(starts), dtype=np.int64)
    ni = np.zeros(len(starts), dtype=np.int64)
    csum = np.concatenate([[0], np.cumsum(ccount)])
    r0 = 0
    while r0 < len(starts):
        r1 = min(max(int(np.searchsorted(csum, csum[r0] + _BLOCK // 16, side="right")) - 1, r0 + 1), len(starts))
        b_nb, b_ni = _run_cuts(ctx, origin, frame, dir_to, r_m[r0:r1], r_lo[r0:r1], r_hi[r0:r1],
                               c0[r0:r1], ccount[r0:r1])
        nb[r0:r1], ni[r0:r1] = b_nb, b_ni
        r0 = r1
    # entries: piece p = 0..ni of run r lies on segment base + p (filled in blocks of runs)
    base = ctx.edge_first[r_e] + nb
    pieces = ni + 1
    total = int(pieces.sum())
    em, seg, lo_to, hi_to = (np.empty(total, dtype=np.int64) for _ in range(4))
    lo, hi, lo_err, hi_err = (np.empty(total) for _ in range(4))
    psum = np.concatenate([[0], np.cumsum(pieces)])
    r0 = 0
    while r0 < len(starts):
        r1 = min(max(int(np.searchsorted(psum, psum[r0] + _BLOCK // 16, side="right")) - 1, r0 + 1), len(starts))
        out = slice(int(psum[r0]), int(psum[r1]))
        er = np.repeat(np.arange(r0, r1), pieces[r0:r1])
        p = ragged_arange(pieces[r0:r1])
        sg = base[er] + p
        last = p == ni[er]
        seg[out] = sg
        lo_to[out] = np.where(p == 0, dir_to[r_lo[er]], sg)
        hi_to[out] = np.where(last, dir_to[r_hi[er]], sg + 1)
        em[out] = r_m[er]
        # headings of the piece ends that are P′ vertices of the edge; an inner upper end is the
        # next piece's lower end (the same vertex seen from the same origin)
        lo[out] = dir_ang[r_lo[er]]
        lo_err[out] = dir_err[r_lo[er]]
        h, he = dir_ang[r_hi[er]], dir_err[r_hi[er]]
        ix = np.flatnonzero(~last)
        if len(ix):
            a, e, *_ = _headings(ctx, origin[r_m[er[ix]]], frame[r_m[er[ix]]], ctx.P[sg[ix] + 1][:, None, :])
            h[ix], he[ix] = a[:, 0], e[:, 0]
        hi[out], hi_err[out] = h, he
        lo_b, le_b = lo[out], lo_err[out]  # views
        lo_b[ix + 1], le_b[ix + 1] = h[ix], he[ix]
        r0 = r1
    return em, seg, lo_to, hi_to, lo, hi, lo_err, hi_err


def _run_cuts(ctx: SweepContext, origin, frame, dir_to, r_m, r_lo, r_hi, c0, ccount):
    """For runs (sweep, start and end direction index, first interior P′ vertex of the edge and
    their count): the number of interior vertices before the run's start direction, and strictly
    inside the run (exact near ties).

    Seen from the sweep's origin (in front of the edge), the directions to the edge's points turn one way along
    it: the vertices before the start direction are a prefix of the edge's, those at or after the end direction a
    suffix. Both boundaries are found by a vectorised bisection (each decision float with an error bound, exact
    when unsure: the exact decisions are monotone), so a run costs the logarithm of its edge's vertices, not their
    number (a long outer wall of a warehouse holds hundreds, and thousands of runs end on it)."""
    o = origin[r_m]
    X = ctx.P[o]
    fr = frame[r_m]
    f = ctx.edge_unit[fr]

    def dvec(to: np.ndarray) -> np.ndarray:
        """Float direction vectors of direction references (marks: ± frame)."""
        out = np.where((to >= 0)[:, None], ctx.P[np.maximum(to, 0)] - X, f)
        return np.where((to == MARK_PI)[:, None], -f, out)

    s_to, e_to = dir_to[r_lo], dir_to[r_hi]
    ds, de = dvec(s_to), dvec(e_to)
    n_ds, n_de, n_x = max_norm(ds), max_norm(de), max_norm(X)

    def crosses(rows: np.ndarray, y: np.ndarray, d: np.ndarray, n_d: np.ndarray, start: bool) -> np.ndarray:
        """before (start: cross(y − x, Ds) ≥ 0) or not after (cross(De, y − x) < 0), exact where unsure."""
        Y = ctx.P[y]
        rel = Y - X[rows]
        dd = d[rows]
        c = rel[:, 0] * dd[:, 1] - rel[:, 1] * dd[:, 0]
        if not start:
            c = -c
        mag = n_x[rows] + max_norm(Y)
        n_rel = max_norm(rel)
        tol = CROSS_REL * (n_rel * n_d[rows] + 0.1 * mag * (n_d[rows] + n_rel)) + 1e-300
        out = c > tol
        to = s_to if start else e_to
        for i in np.flatnonzero(np.abs(c) <= tol).tolist():
            r = int(rows[i])
            sign = _dir_cross_sign(ctx, int(o[r]), int(y[i]), int(to[r]), int(fr[r]))
            out[i] = (sign if start else -sign) >= 0
        return out if start else ~out

    def first_false(lo: np.ndarray, hi: np.ndarray, d: np.ndarray, n_d: np.ndarray, start: bool) -> np.ndarray:
        """Per run, the first index in [lo, hi) whose vertex fails the test (which holds on a prefix)."""
        lo, hi = lo.copy(), hi.copy()
        act = np.flatnonzero(lo < hi)
        while len(act):
            mid = (lo[act] + hi[act]) // 2
            ok = crosses(act, c0[act] + mid, d, n_d, start)
            lo[act[ok]] = mid[ok] + 1
            hi[act[~ok]] = mid[~ok]
            act = act[lo[act] < hi[act]]
        return lo

    count = np.asarray(ccount, dtype=np.int64)
    nb = first_false(np.zeros(len(r_m), dtype=np.int64), count, ds, n_ds, True)
    na = first_false(nb, count, de, n_de, False)
    return nb, na - nb


def _dir_cross_sign(ctx: SweepContext, o: int, y: int, to: int, frame: int) -> int:
    """Exact sign of cross(P′[y] − P′[o], D) for a direction reference D (P′ id or mark)."""
    ctx.exact_checks += 1
    ux, uy, _ = ctx.exact.vec(o, y)
    dx, dy = ctx.exact.direction(o, to, frame)
    c = ux * dy - uy * dx
    return (c > 0) - (c < 0)


def _special_entries(ctx: SweepContext, origin, frame, lo_lim, hi_lim):
    """Cor. 1 at convex vertices: beyond the wall, the ray from x ± ε meets the neighbouring segment."""
    rows_hi = np.flatnonzero(hi_lim >= 0)  # "+" sweep of a convex vertex: (ang(prev − x), π) → prev segment
    rows_lo = np.flatnonzero(lo_lim >= 0)  # "−" sweep: (0, ang(next − x)) → the segment starting at x
    sweep = np.concatenate([rows_hi, rows_lo])
    seg = np.concatenate([ctx.prv[origin[rows_hi]], origin[rows_lo]])
    lo_to = np.concatenate([hi_lim[rows_hi], np.full(len(rows_lo), MARK_ZERO)])
    hi_to = np.concatenate([np.full(len(rows_hi), MARK_PI), lo_lim[rows_lo]])
    a_hi, e_hi = _lim_heading(ctx, origin[rows_hi], frame[rows_hi], hi_lim[rows_hi], math.pi)
    a_lo, e_lo = _lim_heading(ctx, origin[rows_lo], frame[rows_lo], lo_lim[rows_lo], 0.0)
    lo = np.concatenate([a_hi, np.zeros(len(rows_lo))])
    hi = np.concatenate([np.full(len(rows_hi), math.pi), a_lo])
    lo_err = np.concatenate([e_hi, np.zeros(len(rows_lo))])
    hi_err = np.concatenate([np.zeros(len(rows_hi)), e_lo])
    return sweep.astype(np.int64), seg.astype(np.int64), lo_to, hi_to, lo, hi, lo_err, hi_err


def _hole_extremes(ctx: SweepContext, origin, frame, ang, err) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per sweep and hole: the largest and smallest heading of the hole's vertices (their P′ ids):
    ``(alpha, alpha_v, beta, beta_v)``, each of shape (sweeps, holes)."""
    env = ctx.env
    H = len(env.rings) - 1
    M = len(origin)
    alpha = np.full((M, H), np.nan)
    beta = np.full((M, H), np.nan)
    alpha_v = np.full((M, H), -1, dtype=np.int64)
    beta_v = np.full((M, H), -1, dtype=np.int64)
    for h in range(H):
        lo, hi = env.ring_offsets[h + 1], env.ring_offsets[h + 2]
        a = ang[:, lo:hi]
        e = err[:, lo:hi]
        ia = np.argmax(a, axis=1)
        ib = np.argmin(a, axis=1)
        r = np.arange(M)
        # exact extremes where another vertex of the hole is within the error bound
        for pick, sign in ((ia, 1), (ib, -1)):
            best = a[r, pick]
            close = (sign * (a - best[:, None]) >= -(e + e[r, pick][:, None])) & (np.arange(hi - lo)[None, :] != pick[:, None])
            for m in np.flatnonzero(close.any(axis=1)).tolist():
                o, fr = int(origin[m]), int(frame[m])
                cur = int(pick[m])
                for w in np.flatnonzero(close[m]).tolist():
                    c = ctx.exact.heading_cmp(fr, o, int(ctx.orig_pv[lo + w]), o, int(ctx.orig_pv[lo + cur]))
                    if sign * c > 0:
                        cur = w
                pick[m] = cur
        alpha[:, h] = a[r, ia]
        beta[:, h] = a[r, ib]
        alpha_v[:, h] = ctx.orig_pv[lo + ia]
        beta_v[:, h] = ctx.orig_pv[lo + ib]
    return alpha, alpha_v, beta, beta_v


def estimate_entries(partition, sample: int = 256) -> tuple[int, int]:
    """(estimated number of entries of all sweeps, number of sweeps), from the sweeps of an evenly
    spaced sample of ``sample`` origins (all of them when there are fewer): the size of the BVG
    before it is built (its arcs are about 0.95 times its entries)."""
    ctx = SweepContext(partition)
    origin, frame, plus_seg, minus_seg, lo_lim, hi_lim = _define_sweeps(ctx)
    M = len(origin)
    rows = np.unique(np.linspace(0, M - 1, min(M, sample)).astype(np.int64)) if M else np.zeros(0, dtype=np.int64)
    found = 0
    for b0 in range(0, len(rows), 32):  # in blocks: a progress step (and a stop point) between them
        step("safe BVG: estimating its size", b0, len(rows))
        block = rows[b0:b0 + 32]
        o, fr, lo, hi = origin[block], frame[block], lo_lim[block], hi_lim[block]
        cls, ang, err = _classify(ctx, o, fr, lo, hi)
        rank, K, dir_ang, dir_to, dir_err, dir_off, thin = _rank(ctx, o, fr, lo, hi, cls, ang, err)
        pairs = _covering(ctx, o, cls, rank, K)
        del cls, ang, err, rank
        hit = _hit_edges(ctx, o, fr, K, dir_ang, dir_to, dir_off, thin, pairs)
        found += len(_entries(ctx, o, fr, K, dir_ang, dir_to, dir_err, dir_off, hit)[0])
    special = int(np.count_nonzero(lo_lim >= 0) + np.count_nonzero(hi_lim >= 0))
    return int(round(found * M / max(len(rows), 1))) + special, M
