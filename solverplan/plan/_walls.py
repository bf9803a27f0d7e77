"""Straight walls: an environment with its collinear vertices merged, and the exact map between the two (private).

A vertex whose interior angle is exactly π (the previous and next vertices on one line through it, on
either side) is not a corner: the wall goes on straight through it. Yet the partition P′ cuts the boundary
at every vertex, so a collinear vertex splits a wall into segments, and the rays of Algorithm 1 through it
add further cut points that mark no visibility event. A planner whose stages land on one segment of P′
would then see a different (smaller) class of plans in the same free space, and its "optimal" answers would
change with the vertex list.

The planners therefore search the **merged** environment — the same rings with every collinear vertex
removed (the same free space, exactly) — and report in the user's numbering:

- user edge k lies on merged edge ``m`` with merged parameter s = s₀ + t·(s₁ − s₀) (exact: the merged edge
  is the same line, and s is the ratio of the distances along it);
- every segment of the user's P′ lies inside exactly one segment of the merged P′ (the user's partition
  points are the merged ones plus the collinear vertices and the cut points of the rays through them), so a
  merged segment is a *run* of consecutive user segments, listed in boundary order.

>>> from solverplan.environment import Environment
>>> split = Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])   # (2, 0) is collinear
>>> walls = Walls(split)
>>> walls.identity, walls.merged.n_edges, walls.edge_map[1]
(False, 4, (0, Fraction(1, 2), Fraction(1, 1)))
>>> str(walls.to_merged(split.boundary_set("e1:0:0.5,e2")))
'e0:0.5:0.75,e1'
"""

from __future__ import annotations

from fractions import Fraction
from functools import cached_property
from typing import Iterable

from solverplan.bounce.partition import Partition, partition as make_partition
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.exact import ExactPoint, orient

__all__ = ["Walls", "canonical_start", "collinear_vertices"]


def _straight(p: ExactPoint, v: ExactPoint, q: ExactPoint) -> bool:
    """Is v a collinear vertex between p and q (angle exactly π: on the line pq, strictly between them)?"""
    if orient(p, v, q) != 0:
        return False
    return (v[0] - p[0]) * (q[0] - v[0]) + (v[1] - p[1]) * (q[1] - v[1]) > 0


def collinear_vertices(env: Environment) -> tuple[int, ...]:
    """Global indices of the vertices of ``env`` whose interior angle is exactly π (exact test)."""
    out: list[int] = []
    base = 0
    for ring in env.rings:
        n = len(ring)
        out.extend(base + i for i in range(n) if _straight(ring[i - 1], ring[i], ring[(i + 1) % n]))
        base += n
    return tuple(out)


def canonical_start(ring: list[ExactPoint]) -> int:
    """The index a ring's vertex list starts at in the straight walls: the vertex whose sequence of shapes (per
    vertex from there on: the squared length of the edge into it, and the dot and cross products of the edges into
    and out of it, all exact) is lexicographically least among the ring's rotations (Booth's least rotation, O(n)).
    Rotations, translations and the first vertex of the input do not change the sequence, and a uniform scaling
    multiplies every term by one positive factor, which keeps the order: so the planners number the walls the same
    however the environment is written, and break ties the same way. A symmetric ring has several least rotations,
    which the symmetry maps onto each other: any of them gives the same answers.

    >>> canonical_start([(0, 0), (4, 0), (4, 1), (0, 2)]), canonical_start([(4, 1), (0, 2), (0, 0), (4, 0)])
    (2, 0)
    """
    n = len(ring)
    shape = []
    for i in range(n):
        p, v, q = ring[i - 1], ring[i], ring[(i + 1) % n]
        ux, uy, wx, wy = v[0] - p[0], v[1] - p[1], q[0] - v[0], q[1] - v[1]
        shape.append((ux * ux + uy * uy, ux * wx + uy * wy, ux * wy - uy * wx))
    # Booth's algorithm on the doubled sequence
    seq = shape + shape
    fail = [-1] * len(seq)
    k = 0
    for j in range(1, len(seq)):
        sj = seq[j]
        i = fail[j - k - 1]
        while i != -1 and sj != seq[k + i + 1]:
            if sj < seq[k + i + 1]:
                k = j - i - 1
            i = fail[i]
        if sj != seq[k + i + 1]:
            if sj < seq[k]:
                k = j
            fail[j - k] = -1
        else:
            fail[j - k] = i + 1
    return k % n


def _param(a: ExactPoint, b: ExactPoint, x: ExactPoint) -> Fraction:
    """The parameter of point x on the line a → b (x on it): (x − a)·(b − a) / |b − a|², exact."""
    ex, ey = b[0] - a[0], b[1] - a[1]
    return Fraction((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / (ex * ex + ey * ey)


class Walls:
    """The straight walls of ``env``: its merged environment and the maps between the two numberings.

    Attributes
    ----------
    env
        The user's environment.
    merged
        ``env`` without its collinear vertices (``env`` itself when it has none: :attr:`identity`).
    edge_map
        For every user edge k: ``(m, s0, s1)``, the merged edge it lies on and the merged parameters of its
        two ends (user t ↦ s0 + t·(s1 − s0)).

    Every collinear vertex is merged, wherever a query's sets end (the planners take the sets as they are, parts
    of segments included: :mod:`solverplan.plan._problem`), so the walls, their partition and every answer are
    the same however the walls are written.
    """

    def __init__(self, env: Environment) -> None:
        self.env = env
        rings: list[tuple[ExactPoint, ...]] = []
        edge_map: list[tuple[int, Fraction, Fraction]] = []
        merged_base = 0
        for ring in env.rings:
            n = len(ring)
            keep = [i for i in range(n) if not _straight(ring[i - 1], ring[i], ring[(i + 1) % n])]
            first = canonical_start([ring[i] for i in keep])
            keep = keep[first:] + keep[:first]
            rings.append(tuple(ring[i] for i in keep))
            # the merged edge of user edge i starts at the last kept vertex at or before i (cyclically)
            owner = [0] * n
            last = max(keep)  # the last kept vertex before vertex 0, cyclically
            kept = set(keep)
            for i in range(n):
                if i in kept:
                    last = i
                owner[i] = last
            index = {v: k for k, v in enumerate(keep)}
            for i in range(n):
                k = index[owner[i]]
                a, b = ring[keep[k]], ring[keep[(k + 1) % len(keep)]]
                s0 = _param(a, b, ring[i])
                s1 = _param(a, b, ring[(i + 1) % n]) if (i + 1) % n != keep[(k + 1) % len(keep)] else Fraction(1)
                edge_map.append((merged_base + k, s0, s1))
            merged_base += len(keep)
        self.edge_map: tuple[tuple[int, Fraction, Fraction], ...] = tuple(edge_map)
        self.identity = all(m == k and s0 == 0 and s1 == 1 for k, (m, s0, s1) in enumerate(edge_map))
        self.merged = env if self.identity else Environment(tuple(rings), name=env.name, reoriented=env.reoriented)

    # ------------------------------------------------------------------ sets
    def to_merged(self, bset: BoundarySet) -> BoundarySet:
        """The same boundary points, in the merged numbering (exact; pieces of one wall joined)."""
        if self.identity:
            return bset
        pieces = []
        for piece in bset.pieces:
            m, s0, s1 = self.edge_map[piece.edge]
            pieces.append(BoundaryPiece(m, s0 + piece.t0 * (s1 - s0), s0 + piece.t1 * (s1 - s0)))
        return BoundarySet(tuple(pieces)).merged()

    @cached_property
    def user_edges(self) -> tuple[tuple[tuple[int, Fraction, Fraction], ...], ...]:
        """For every merged edge m: the user edges on it, in order along it, each ``(k, s0, s1)`` (its merged
        parameter range)."""
        out: list[list[tuple[int, Fraction, Fraction]]] = [[] for _ in range(self.merged.n_edges)]
        for k, (m, s0, s1) in enumerate(self.edge_map):
            out[m].append((k, s0, s1))
        return tuple(tuple(sorted(items, key=lambda item: item[1])) for items in out)

    def user_edge_at(self, edge: int, s: Fraction) -> int:
        """The user edge holding the point at merged parameter ``s`` of merged edge ``edge`` (at a collinear
        vertex: the edge that starts there)."""
        users = self.user_edges[edge]
        return next((k for k, s0, s1 in users if s0 <= s < s1), users[-1][0])

    def to_user(self, pieces: Iterable[BoundaryPiece]) -> tuple[BoundaryPiece, ...]:
        """Merged pieces as pieces of the user's edges, in order: a piece on a merged edge splits at the
        collinear vertices into pieces of consecutive user edges (exact; a point stays one point)."""
        if self.identity:
            return tuple(pieces)
        out: list[BoundaryPiece] = []
        for piece in pieces:
            users = self.user_edges[piece.edge]
            if piece.t0 == piece.t1:
                k = self.user_edge_at(piece.edge, piece.t0)
                _, s0, s1 = self.edge_map[k]
                t = (piece.t0 - s0) / (s1 - s0)
                out.append(BoundaryPiece(k, t, t))
                continue
            for k, s0, s1 in users:
                lo, hi = max(piece.t0, s0), min(piece.t1, s1)
                if lo < hi:
                    out.append(BoundaryPiece(k, (lo - s0) / (s1 - s0), (hi - s0) / (s1 - s0)))
        return tuple(out)

    def to_user_set(self, bset: BoundarySet) -> BoundarySet:
        """:meth:`to_user` of a boundary set (pieces of one user edge joined)."""
        return bset if self.identity else BoundarySet(self.to_user(bset.pieces)).merged()

    # ------------------------------------------------------------------ segments
    @cached_property
    def user_partition(self) -> Partition:
        """The partition P′ of the user's environment (the ids answers are reported in)."""
        return make_partition(self.env)

    @cached_property
    def _user_segments_by_edge(self) -> tuple[tuple[tuple[Fraction, Fraction, int], ...], ...]:
        """For every merged edge: the user segments on it as ``(s0, s1, id)``, their merged parameter ranges, in order."""
        user = self.user_partition
        by_edge: list[list[tuple[Fraction, Fraction, int]]] = [[] for _ in range(self.merged.n_edges)]
        for seg in user.segments:
            m, s0, s1 = self.edge_map[seg.edge]
            by_edge[m].append((s0 + seg.t0 * (s1 - s0), s0 + seg.t1 * (s1 - s0), seg.id))
        return tuple(tuple(sorted(items)) for items in by_edge)

    def pieces_of(self, piece: BoundaryPiece) -> tuple[tuple[int, BoundaryPiece], ...]:
        """A piece of a merged edge (positive length) as the user segments it overlaps, in order along it, each with
        the exact overlap as a piece of the user's edge."""
        user = self.user_partition
        out = []
        for s0, s1, u in self._user_segments_by_edge[piece.edge]:
            if s0 >= piece.t1:
                break
            lo, hi = max(s0, piece.t0), min(s1, piece.t1)
            if lo < hi:
                edge = user.segments[u].edge
                _, e0, e1 = self.edge_map[edge]
                out.append((u, BoundaryPiece(edge, (lo - e0) / (e1 - e0), (hi - e0) / (e1 - e0))))
        return tuple(out)

    def user_pieces(self, search: Partition) -> tuple[tuple[tuple[int, BoundaryPiece], ...], ...]:
        """For every segment of ``search`` (P′ of :attr:`merged`): the user segments it overlaps, in boundary order,
        each with the exact overlap as a piece of the user's edge (:meth:`pieces_of`; the user's P′ refines the
        merged one, so these are whole user segments)."""
        if search.env != self.merged:
            raise ValueError("the partition is not one of the merged environment of these walls")
        return tuple(self.pieces_of(BoundaryPiece(seg.edge, seg.t0, seg.t1)) for seg in search.segments)

    def runs(self, search: Partition) -> tuple[tuple[int, ...], ...]:
        """For every segment of ``search`` (:meth:`user_pieces`), the user segments it overlaps, in boundary order."""
        return tuple(tuple(u for u, _ in pieces) for pieces in self.user_pieces(search))
