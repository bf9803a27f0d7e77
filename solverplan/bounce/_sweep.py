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

# Float tolerances. Headings (radians) closer than this are compared exactly; the tolerance is
# scaled by the conditioning of each direction (coordinate magnitude / vector length).
_ANGLE_REL = 1e-13
# Float cross products of differences of rounded points closer to 0 than this times the product of
# the magnitudes involved are decided exactly (the float error is about 1e-15 of it).
_CROSS_REL = 1e-13
# Sectors narrower than this (radians) are resolved with an exact ray (their float bisector may not
# be strictly inside); relative gap of the two nearest edges along a bisector that counts as a tie.
_THIN = 1e-9
_DEPTH_REL = 1e-9
# Rows of (sweep × vertex) per numpy block.
_BLOCK = 1 << 21

# Vertex classes against a sweep's region (headings relative to the frame).
_NONE, _BELOW, _AHEAD, _BEHIND, _IN, _AT_LO, _BEFORE_LO, _AT_HI, _BEYOND_HI = range(9)
_START_LOW = (_AHEAD, _BEFORE_LO, _AT_LO, _BELOW)  # start rank 0
_END_LOW = (_AHEAD, _BEFORE_LO, _AT_LO)  # end rank 0 (a BELOW end wraps through π: rank K+1)

MARK_ZERO, MARK_PI = -1, -2
"""Reference ids of the frame ends: heading 0 (direction b − a) and heading π (direction a − b)."""


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


class _Context:
    """Float and exact views of one partition shared by the sweep steps."""

    depth_pairs: int  # set by _hit_edges: (sweep, edge) pairs with at least one sector to test (diagnostic)

    def __init__(self, partition) -> None:
        env = partition.env
        self.partition = partition
        self.env = env
        segs = partition.segments
        self.N = N = len(segs)
        self.n = n = env.n_vertices
        self.P = np.asarray(partition.seg_start, dtype=float)  # P′ vertex k = start of segment k
        self.V = np.asarray(env.vertices, dtype=float)
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
        ev = env.edge_end - env.edge_start
        self.edge_unit = ev / np.hypot(ev[:, 0], ev[:, 1])[:, None]
        self.A = np.asarray(env.edge_start, dtype=float)
        self.B = np.asarray(env.edge_end, dtype=float)
        self.scale = float(np.max(np.abs(self.V))) + 1.0
        self.exact_checks = 0
        self.exact_casts = 0
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


def build_sweeps(partition) -> Sweeps:
    """All sweeps of ``partition`` and their entries (see the module docstring)."""
    ctx = _Context(partition)
    origin, frame, plus_seg, minus_seg, lo_lim, hi_lim = _define_sweeps(ctx)
    M = len(origin)
    # ---- 1. headings and classes of all original vertices, and the critical directions
    cls, ang, err = _classify(ctx, origin, frame, lo_lim, hi_lim)
    rank, K, dir_ang, dir_to, dir_err, dir_off, thin = _rank(ctx, origin, frame, lo_lim, hi_lim, cls, ang, err)
    # ---- 2. first-hit edge of every sector
    hit = _hit_edges(ctx, origin, frame, cls, rank, K, dir_ang, dir_to, dir_off, thin)
    # ---- 3. runs and entries
    entries = _entries(ctx, origin, frame, K, dir_ang, dir_to, dir_err, dir_off, hit)
    special = _special_entries(ctx, origin, frame, lo_lim, hi_lim)
    cols = [np.concatenate([a, b]) for a, b in zip(entries, special)]
    order = np.lexsort((cols[4], cols[0]))  # by sweep, then heading
    sweep, seg, lo_to, hi_to, lo, hi, lo_err, hi_err = (c[order] for c in cols)
    sweeps = Sweeps(origin, frame, plus_seg, minus_seg, sweep, seg, lo_to, hi_to, lo, hi, lo_err, hi_err)
    if len(ctx.env.rings) > 1:
        _hole_extremes(ctx, sweeps, origin, cls, ang, err)
    sweeps.exact_checks = ctx.exact_checks
    sweeps.exact_casts = ctx.exact_casts
    return sweeps


def _define_sweeps(ctx: _Context):
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


def _headings(ctx: _Context, origin: np.ndarray, frame: np.ndarray, pts: np.ndarray):
    """Float headings of points ``pts`` (shape (M, k, 2)) from the sweep origins, with error bounds
    and the raw cross/dot (frame unit vector × relative vector)."""
    X = ctx.P[origin][:, None, :]
    f = ctx.edge_unit[frame][:, None, :]
    rel = pts - X
    cr = f[..., 0] * rel[..., 1] - f[..., 1] * rel[..., 0]
    dt = f[..., 0] * rel[..., 0] + f[..., 1] * rel[..., 1]
    length = np.hypot(rel[..., 0], rel[..., 1])
    mag = _ninf(X) + _ninf(pts)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = _ANGLE_REL * mag / length + 1e-15
    return np.arctan2(cr, dt), err, cr, length, mag


def _classify(ctx: _Context, origin, frame, lo_lim, hi_lim):
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
        thr = _ANGLE_REL * mag + 1e-15 * length  # bound on the float error of cr
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
            tol = _CROSS_REL * (_ninf(rel) * _ninf(Lrel)[:, None] + 0.1 * ctx.scale * (_ninf(rel) + _ninf(Lrel)[:, None])) + 1e-300
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


def _lim_heading(ctx: _Context, origin, frame, lim, default: float):
    out = np.full(len(origin), default)
    errs = np.zeros(len(origin))
    rows = np.flatnonzero(lim >= 0)
    if len(rows):
        a, e, *_ = _headings(ctx, origin[rows], frame[rows], ctx.P[lim[rows]][:, None, :])
        out[rows], errs[rows] = a[:, 0], e[:, 0]
    return out, errs


def _rank(ctx: _Context, origin, frame, lo_lim, hi_lim, cls, ang, err):
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
    thin = width <= np.maximum(_THIN, dir_err[1:] + dir_err[:-1])
    return rank, K, dir_ang, dir_to, dir_err, dir_off, thin


def _ninf(x: np.ndarray) -> np.ndarray:
    """Max-norm over the last axis (of length 2), without a slow axis reduction."""
    return np.maximum(np.abs(x[..., 0]), np.abs(x[..., 1]))


def _front_facing(ctx: _Context, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (sweep row, edge) with the origin strictly left of the edge's line (exact near ties)."""
    M, n = len(origin), ctx.n
    rows_out, edges_out = [], []
    rows = max(1, _BLOCK // max(n, 1))
    A, B = ctx.A, ctx.B
    d = B - A
    own = ctx.seg_edge  # edge of the segment starting at each P′ vertex
    for s0 in range(0, M, rows):
        o = origin[s0 : s0 + rows]
        X = ctx.P[o]
        rel = X[:, None, :] - A[None, :, :]
        cr = d[None, :, 0] * rel[..., 1] - d[None, :, 1] * rel[..., 0]
        tol = 0.1 * _CROSS_REL * (_ninf(d)[None, :] * (_ninf(rel) + ctx.scale))
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


def _hit_edges(ctx: _Context, origin, frame, cls, rank, K, dir_ang, dir_to, dir_off, thin) -> np.ndarray:
    """The first-hit edge of every sector (flat index dir_off[m] + k), −1 if none."""
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
    m_idx, e_idx, sr, cnt = m_idx[keep], e_idx[keep], sr[keep], cnt[keep]
    ctx.depth_pairs = int(cnt.sum())
    # sectors in one flat numbering gl = dir_off[m] + k - m (k = 0..K[m]); per sector: the origin
    # and the unit vector of the bisector
    M = len(K)
    n_sec = K + 1
    sec_off = dir_off[:-1] - np.arange(M)
    total = int(n_sec.sum())
    sec_m = np.repeat(np.arange(M), n_sec)
    sec_g = dir_off[sec_m] + ragged_arange(n_sec)
    mid = 0.5 * (dir_ang[sec_g] + dir_ang[sec_g + 1])
    f = ctx.edge_unit[frame[sec_m]]
    c, s = np.cos(mid), np.sin(mid)
    UX, UY = c * f[:, 0] - s * f[:, 1], s * f[:, 0] + c * f[:, 1]
    SX, SY = ctx.P[origin[sec_m], 0], ctx.P[origin[sec_m], 1]
    best = np.full(total, np.inf)
    hit = np.full(total, -1, dtype=np.int64)
    # per (sweep, edge) pair: numerator cross(A − X, d) of the distance along any unit direction u,
    # which is numer / cross(u, d)
    X = ctx.P[origin[m_idx]]
    dxp, dyp = ctx.B[e_idx, 0] - ctx.A[e_idx, 0], ctx.B[e_idx, 1] - ctx.A[e_idx, 1]
    numer = (ctx.A[e_idx, 0] - X[:, 0]) * dyp - (ctx.A[e_idx, 1] - X[:, 1]) * dxp
    gl_first = sec_off[m_idx] + sr
    csum = np.cumsum(cnt)
    blocks = []
    start = 0
    while start < len(cnt):
        base = csum[start - 1] if start else 0
        stop = max(int(np.searchsorted(csum, base + (1 << 21), side="right")), start + 1)
        c_blk = cnt[start:stop]
        rep = np.repeat(np.arange(start, stop), c_blk)
        gl = gl_first[rep] + ragged_arange(c_blk)
        dx, dy = dxp[rep], dyp[rep]
        with np.errstate(divide="ignore", invalid="ignore"):
            dist = numer[rep] / (UX[gl] * dy - UY[gl] * dx)
        dist[~(dist > 0)] = np.inf
        np.minimum.at(best, gl, dist)
        blocks.append((gl, rep, dist))
        start = stop
    near = np.zeros(total, dtype=np.int64)  # covering edges within the tie margin of the nearest
    for gl, rep, dist in blocks:
        b = best[gl]
        win = dist == b
        hit[gl[win]] = e_idx[rep[win]]
        close = dist <= b * (1.0 + _DEPTH_REL)
        near += np.bincount(gl[close], minlength=total)
    k_all = sec_g - dir_off[sec_m]
    m_all = sec_m
    bad = thin[sec_g] | ~np.isfinite(best) | (near != 1)
    out = hit
    for i in np.flatnonzero(bad).tolist():
        m, k = int(m_all[i]), int(k_all[i])
        out[i] = _exact_sector_hit(ctx, int(origin[m]), int(frame[m]),
                                   int(dir_to[dir_off[m] + k]), int(dir_to[dir_off[m] + k + 1]))
    return out  # indexed by dir_off[m] + k - m


def _exact_sector_hit(ctx: _Context, o: int, frame: int, lo_to: int, hi_to: int) -> int:
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


def _entries(ctx: _Context, origin, frame, K, dir_ang, dir_to, dir_err, dir_off, hit):
    """Runs of sectors hitting one edge, cut by the P′ vertices on that edge into entries."""
    M = len(origin)
    n_sec = K + 1
    m_all = np.repeat(np.arange(M), n_sec)
    k_all = ragged_arange(n_sec)
    if len(hit) and (hit < 0).any():  # pragma: no cover - every ray in a valid environment hits
        i = int(np.flatnonzero(hit < 0)[0])
        raise SolverFailed(f"no edge found for sector {int(k_all[i])} of the sweep from P′ vertex {int(origin[m_all[i]])}")
    # runs: maximal stretches of consecutive sectors of one sweep with one hit edge
    first = np.ones(len(hit), dtype=bool)
    first[1:] = (hit[1:] != hit[:-1]) | (k_all[1:] == 0)
    starts = np.flatnonzero(first)
    ends = np.append(starts[1:], len(hit))  # exclusive
    r_m = m_all[starts]
    r_e = hit[starts]
    r_lo = dir_off[r_m] + k_all[starts]  # direction index of the run's start
    r_hi = dir_off[r_m] + k_all[ends - 1] + 1
    # candidates: the interior P′ vertices of the run's edge
    c0 = ctx.edge_first[r_e] + 1
    ccount = ctx.edge_first[r_e + 1] - c0
    rr = np.repeat(np.arange(len(starts)), ccount)
    y = np.repeat(c0, ccount) + ragged_arange(ccount)
    mm = r_m[rr]
    o = origin[mm]
    X = ctx.P[o]
    Y = ctx.P[y]
    rel = Y - X
    fr = frame[mm]
    f = ctx.edge_unit[fr]

    def dvec(to: np.ndarray) -> np.ndarray:
        """Float direction vectors of direction references (marks: ± frame)."""
        out = np.where((to >= 0)[:, None], ctx.P[np.maximum(to, 0)] - X, f)
        return np.where((to == MARK_PI)[:, None], -f, out)

    ds, de = dvec(dir_to[r_lo[rr]]), dvec(dir_to[r_hi[rr]])
    # before: cross(y − x, Ds) >= 0; after: cross(De, y − x) >= 0
    cb = rel[:, 0] * ds[:, 1] - rel[:, 1] * ds[:, 0]
    ca = de[:, 0] * rel[:, 1] - de[:, 1] * rel[:, 0]
    mag = _ninf(X) + _ninf(Y)
    tol_b = _CROSS_REL * (_ninf(rel) * _ninf(ds) + 0.1 * mag * (_ninf(ds) + _ninf(rel))) + 1e-300
    tol_a = _CROSS_REL * (_ninf(rel) * _ninf(de) + 0.1 * mag * (_ninf(de) + _ninf(rel))) + 1e-300
    before = cb > tol_b
    after = ca > tol_a
    unsure_b = np.abs(cb) <= tol_b
    unsure_a = np.abs(ca) <= tol_a
    for i in np.flatnonzero(unsure_b).tolist():
        before[i] = _dir_cross_sign(ctx, int(o[i]), int(y[i]), int(dir_to[r_lo[rr[i]]]), int(fr[i])) >= 0
    for i in np.flatnonzero(unsure_a & ~before).tolist():
        after[i] = -_dir_cross_sign(ctx, int(o[i]), int(y[i]), int(dir_to[r_hi[rr[i]]]), int(fr[i])) >= 0
    after &= ~before
    inside = ~before & ~after
    nb = np.bincount(rr, weights=before, minlength=len(starts)).astype(np.int64)
    ni = np.bincount(rr, weights=inside, minlength=len(starts)).astype(np.int64)
    # entries: piece p = 0..ni of run r lies on segment base + p
    base = ctx.edge_first[r_e] + nb
    pieces = ni + 1
    er = np.repeat(np.arange(len(starts)), pieces)
    p = ragged_arange(pieces)
    seg = base[er] + p
    last = p == ni[er]
    lo_to = np.where(p == 0, dir_to[r_lo[er]], seg)
    hi_to = np.where(last, dir_to[r_hi[er]], seg + 1)
    em = r_m[er]
    # headings of the piece ends that are P′ vertices of the edge
    lo = dir_ang[r_lo[er]].copy()
    hi = dir_ang[r_hi[er]].copy()
    lo_err = dir_err[r_lo[er]].copy()
    hi_err = dir_err[r_hi[er]].copy()
    inner_lo = p > 0
    inner_hi = ~last
    for mask, vals, errs, ids in ((inner_lo, lo, lo_err, lo_to), (inner_hi, hi, hi_err, hi_to)):
        idx = np.flatnonzero(mask)
        if len(idx):
            a, e, *_ = _headings(ctx, origin[em[idx]], frame[em[idx]], ctx.P[ids[idx]][:, None, :])
            vals[idx], errs[idx] = a[:, 0], e[:, 0]
    return em, seg, lo_to, hi_to, lo, hi, lo_err, hi_err


def _dir_cross_sign(ctx: _Context, o: int, y: int, to: int, frame: int) -> int:
    """Exact sign of cross(P′[y] − P′[o], D) for a direction reference D (P′ id or mark)."""
    ctx.exact_checks += 1
    ux, uy, _ = ctx.exact.vec(o, y)
    dx, dy = ctx.exact.direction(o, to, frame)
    c = ux * dy - uy * dx
    return (c > 0) - (c < 0)


def _special_entries(ctx: _Context, origin, frame, lo_lim, hi_lim):
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


def _hole_extremes(ctx: _Context, sweeps: Sweeps, origin, cls, ang, err) -> None:
    """Per sweep and hole: the largest and smallest heading of the hole's vertices (their P′ ids)."""
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
                o, fr = int(origin[m]), int(sweeps.frame[m])
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
    sweeps.hole_alpha, sweeps.hole_alpha_v = alpha, alpha_v
    sweeps.hole_beta, sweeps.hole_beta_v = beta, beta_v
