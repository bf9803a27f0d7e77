"""The steps of the safe BVG's build after the sweeps: candidate safe intervals as a flat table (:class:`Pieces`),
holes cut out of them, single headings checked exactly, float ends refined, transitions and φ per arc.

Private to :mod:`~solverplan.bounce.bvg.build` (its module docstring has the algorithm and its proof).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from solverplan._arrays import sorted_unique
from solverplan.bounce import _sweep
from solverplan.bounce._sweep import ExactPoints, Sweeps, max_norm
from solverplan.bounce.bvg import tolerances
from solverplan.bounce.bvg.tolerances import EndComparator, angle_error
from solverplan.bounce.partitions import Partition
from solverplan.environment import Environment
from solverplan.progress import step


@dataclass
class Pieces:
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

    def take(self, idx: np.ndarray) -> Pieces:
        return Pieces(*(getattr(self, name)[idx] for name in self.__dataclass_fields__))

    @staticmethod
    def concat(parts: list[Pieces]) -> Pieces:
        return Pieces(*(np.concatenate([getattr(p, name) for p in parts]) for name in Pieces.__dataclass_fields__))


def refine_ends(p: Partition, pieces: Pieces, edge_of: np.ndarray) -> None:
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


def sorted_by_arc_lo(pieces: Pieces) -> bool:
    """Are the pieces already in (arc, lo) order? (Then sorting them would change nothing.)"""
    arc, lo = pieces.arc, pieces.lo
    if len(arc) < 2:
        return True
    d = np.diff(arc)
    return bool((d >= 0).all() and (lo[1:][d == 0] >= lo[:-1][d == 0]).all())


def _edge_vectors(env: Environment) -> list[tuple[Fraction, Fraction]]:
    verts, nv = env.exact_vertices, env.next_vertex
    return [(verts[int(nv[e])][0] - verts[e][0], verts[int(nv[e])][1] - verts[e][1]) for e in range(env.n_edges)]


@functools.lru_cache(maxsize=8)
def _integer_edge_vectors(env: Environment) -> np.ndarray | None:
    """The exact edge vectors of ``env`` times one positive integer (the lcm of their denominators) as int64, when
    every coordinate is below 2³¹ in magnitude — the cross product of two is then exact in int64, its sign that of
    the exact cross product —, else None (a map's edges on a millimetre grid: always)."""
    vectors = _edge_vectors(env)
    scale = 1
    for x, y in vectors:
        scale = math.lcm(scale, x.denominator, y.denominator)
        if scale >= 1 << 31:
            return None
    out = [(x.numerator * (scale // x.denominator), y.numerator * (scale // y.denominator)) for x, y in vectors]
    if any(abs(c) >= 1 << 31 for pair in out for c in pair):
        return None
    return np.array(out, dtype=np.int64).reshape(-1, 2)


def _cmp_ends(pieces: Pieces, ends: EndComparator, edge_of: np.ndarray, which1: str, which2: str) -> np.ndarray:
    g = lambda w, name: getattr(pieces, f"{w}_{name}")  # noqa: E731
    return ends.cmp(edge_of[pieces.arc], g(which1, "from"), g(which1, "to"), getattr(pieces, which1), g(which1, "err"),
                    g(which2, "from"), g(which2, "to"), getattr(pieces, which2), g(which2, "err"))


def nonempty(pieces: Pieces, ends: EndComparator, edge_of: np.ndarray) -> Pieces:
    """Keep pieces with lo ≤ hi (exactly)."""
    if not len(pieces.arc):
        return pieces
    c = _cmp_ends(pieces, ends, edge_of, "lo", "hi")
    return pieces.take(np.flatnonzero(c <= 0))


def single_headings_safe(p: Partition, exact: ExactPoints, source, target, sp: Pieces, edge_of) -> np.ndarray:
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
    tol = tolerances.SAT_REL * scale * scale
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


def singletons(pieces: Pieces, ends: EndComparator, edge_of: np.ndarray) -> np.ndarray:
    if not len(pieces.arc):
        return np.zeros(0, dtype=bool)
    return _cmp_ends(pieces, ends, edge_of, "lo", "hi") == 0


def equal_ends(pieces: Pieces, ends: EndComparator, edge_of: np.ndarray) -> np.ndarray:
    return singletons(pieces, ends, edge_of)


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
        tol = 0.1 * _sweep.CROSS_REL * max_norm(d)[:, None] * (max_norm(rel) + scale)
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


def subtract_holes(p: Partition, sw: Sweeps, pieces: Pieces, ends: EndComparator, source, target, edge_of) -> Pieces:
    """Remove, for every hole H strictly left of the lines of e_i and e_j, the open heading interval
    (max ang(v − a), min ang(v − b)) during which all of H lies inside the swept region.

    That interval depends on the source segment and the hole only (the sweeps at the source's two ends), not on the
    target: it is found, with its error bounds and whether it is a real interval, once per (source, hole) — on a
    warehouse map most holes are wider than a segment of P′ sees them, so few pairs are real — and each hole then
    touches only the pieces of the sources it can be inside the swept region of."""
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
    # ---- per (source, hole): the blocked interval's ends, their error bounds, and whether it is a real interval
    srcs = sorted_unique(source[pieces.arc])
    uu, hh = np.nonzero(side[seg_edge[srcs]])  # the hole strictly left of the source's line
    ma, mb = plus_of[srcs[uu]], minus_of[srcs[uu]]
    a_id, b_id = sw.origin[ma], sw.origin[mb]
    bl, bl_to = sw.hole_alpha[ma, hh], sw.hole_alpha_v[ma, hh]
    bh, bh_to = sw.hole_beta[mb, hh], sw.hole_beta_v[mb, hh]
    # blocked error bounds: recompute with the angle filter's scale (cheap, conservative)
    berr, herr = angle_error(p, a_id, bl_to), angle_error(p, b_id, bh_to)
    real = ends.cmp(seg_edge[srcs[uu]], a_id, bl_to, bl, berr, b_id, bh_to, bh, herr) < 0  # bl < bh
    order = np.flatnonzero(real)
    order = order[np.argsort(hh[order], kind="stable")]  # by hole
    pair_src, pair_hole = srcs[uu[order]], hh[order]
    a_id, b_id, bl, bl_to, bh, bh_to, berr, herr = (x[order] for x in (a_id, b_id, bl, bl_to, bh, bh_to, berr, herr))
    bounds = np.searchsorted(pair_hole, np.arange(H + 1))
    pair_of = np.full(N, -1, dtype=np.int64)
    for h in range(H):
        step("safe BVG: holes", h, H)
        first, last = int(bounds[h]), int(bounds[h + 1])
        if first == last:
            continue
        pair_of[pair_src[first:last]] = np.arange(first, last)
        arc = pieces.arc
        k = pair_of[source[arc]]
        rows = np.flatnonzero(k >= 0)
        pair_of[pair_src[first:last]] = -1
        rows = rows[side[seg_edge[target[arc[rows]]], h]]  # and strictly left of the target's line
        if not len(rows):
            continue
        k = k[rows]
        eg = edge_of[arc[rows]]
        sub = pieces.take(rows)
        c1 = ends.cmp(eg, a_id[k], bl_to[k], bl[k], berr[k], sub.hi_from, sub.hi_to, sub.hi, sub.hi_err)  # bl < hi
        c2 = ends.cmp(eg, b_id[k], bh_to[k], bh[k], herr[k], sub.lo_from, sub.lo_to, sub.lo, sub.lo_err)  # bh > lo
        hit = (c1 < 0) & (c2 > 0)
        if not hit.any():
            continue
        hit_rows = rows[hit]
        untouched = np.ones(len(arc), dtype=bool)
        untouched[hit_rows] = False
        hs = sub.take(np.flatnonzero(hit))
        kh, eh = k[hit], eg[hit]
        # left piece [lo, bl] if lo <= bl; right piece [bh, hi] if bh <= hi
        cl = ends.cmp(eh, hs.lo_from, hs.lo_to, hs.lo, hs.lo_err, a_id[kh], bl_to[kh], bl[kh], berr[kh])
        cr = ends.cmp(eh, b_id[kh], bh_to[kh], bh[kh], herr[kh], hs.hi_from, hs.hi_to, hs.hi, hs.hi_err)
        lk = np.flatnonzero(cl <= 0)
        left = hs.take(lk)
        left.hi_from, left.hi_to, left.hi, left.hi_err = a_id[kh][lk], bl_to[kh][lk], bl[kh][lk], berr[kh][lk]
        rk = np.flatnonzero(cr <= 0)
        right = hs.take(rk)
        right.lo_from, right.lo_to, right.lo, right.lo_err = b_id[kh][rk], bh_to[kh][rk], bh[kh][rk], herr[kh][rk]
        pieces = Pieces.concat([pieces.take(np.flatnonzero(untouched)), left, right])
    return pieces


def transitions_and_phi(env: Environment, ei: np.ndarray, ej: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    tol = 0.1 * _sweep.CROSS_REL * (max_norm(u) * scale + max_norm(v) * scale)
    side = np.sign(cr).astype(np.int8)
    unsure = np.flatnonzero(np.abs(cr) <= tol)
    exact = _integer_edge_vectors(env) if len(unsure) else None
    if exact is not None:  # (nearly) parallel edges — half the pairs of a map's axis-parallel walls — at once
        u_i, v_j = exact[ei[unsure]], exact[ej[unsure]]
        side[unsure] = np.sign(u_i[:, 0] * v_j[:, 1] - u_i[:, 1] * v_j[:, 0])
    elif len(unsure):
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
