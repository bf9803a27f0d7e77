"""Straight walls: an environment with its collinear vertices merged, exactly, and the map between the numberings.

A vertex whose interior angle is exactly π (the previous and next vertices on one line through it, on either side)
is not a corner: the wall goes on straight through it. Every model that reads corners, edges or their numbering
(the bounce partition P′, rooms and doors, visibility windows, wall-following cuts, reflection cells) would
otherwise answer differently for the same free space written with more vertices. :class:`StraightWalls` is the
one way to get the **canonical walls** of an environment:

- every collinear vertex merged (the same free space, exactly: :func:`collinear_vertices`);
- every ring started at a canonical vertex (:func:`canonical_start`, Booth's least rotation of the ring's exact
  shape sequence), so that rotations, translations, uniform scalings and the ring's first vertex do not change the
  numbering either;

and the exact maps between the two numberings: user edge k lies on canonical edge ``m`` with canonical parameter
s = s₀ + t·(s₁ − s₀) (:attr:`StraightWalls.edge_map`), and back (:meth:`StraightWalls.to_user`,
:meth:`StraightWalls.user_edge_at`, :meth:`StraightWalls.user_point`). Models compute on :attr:`StraightWalls.merged`
and map the edge ids of their answers back with these.

>>> from solverplan.environment import Environment
>>> split = Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])   # (2, 0) is collinear
>>> walls = StraightWalls(split)
>>> walls.identity, walls.merged.n_edges, walls.edge_map[1]
(False, 4, (0, Fraction(1, 2), Fraction(1, 1)))
>>> str(walls.to_merged(split.boundary_set("e1:0:0.5,e2")))
'e0:0.5:0.75,e1'
>>> walls.user_point(0, Fraction(1, 4)), walls.user_edges_of(0)
((0, Fraction(1, 2)), (0, 1))
"""

from __future__ import annotations

from fractions import Fraction
from functools import cached_property
from typing import Iterable

from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.exact import ExactPoint, orient

__all__ = ["StraightWalls", "canonical_start", "collinear_vertices", "is_straight"]


def is_straight(p: ExactPoint, v: ExactPoint, q: ExactPoint) -> bool:
    """Is v a collinear vertex between p and q (angle exactly π: on the line pq, strictly between them)? Exact.

    >>> is_straight((0, 0), (1, 0), (3, 0)), is_straight((0, 0), (1, 0), (1, 1)), is_straight((0, 0), (2, 0), (1, 0))
    (True, False, False)
    """
    if orient(p, v, q) != 0:
        return False
    return (v[0] - p[0]) * (q[0] - v[0]) + (v[1] - p[1]) * (q[1] - v[1]) > 0


def collinear_vertices(env: Environment) -> tuple[int, ...]:
    """Global indices of the vertices of ``env`` whose interior angle is exactly π (exact test).

    >>> from solverplan.environment import Environment
    >>> collinear_vertices(Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]]))
    (1,)
    """
    out: list[int] = []
    base = 0
    for ring in env.rings:
        n = len(ring)
        out.extend(base + i for i in range(n) if is_straight(ring[i - 1], ring[i], ring[(i + 1) % n]))
        base += n
    return tuple(out)


def canonical_start(ring: list[ExactPoint] | tuple[ExactPoint, ...]) -> int:
    """The index a ring's vertex list starts at in the straight walls: the vertex whose sequence of shapes (per
    vertex from there on: the squared length of the edge into it, and the dot and cross products of the edges into
    and out of it, all exact) is lexicographically least among the ring's rotations (Booth's least rotation, O(n)).
    Rotations, translations and the first vertex of the input do not change the sequence, and a uniform scaling
    multiplies every term by one positive factor, which keeps the order: so the models number the walls the same
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


class StraightWalls:
    """The canonical walls of ``env``: its merged environment and the maps between the two numberings.

    Attributes
    ----------
    env
        The user's environment.
    merged
        ``env`` without its collinear vertices, each ring from its canonical vertex (``env`` itself when that
        changes nothing: :attr:`identity`).
    edge_map
        For every user edge k: ``(m, s0, s1)``, the merged edge it lies on and the merged parameters of its
        two ends (user t ↦ s0 + t·(s1 − s0)).
    vertex_map
        For every merged vertex (global index): the user's vertex at the same point (global index).

    ``keep_start=True`` keeps each ring's start where the user put it (the first vertex that is a corner, from
    vertex 0 on) instead of the canonical vertex: for models whose answers name vertices by their position in the
    user's ring (the wall-following robot's v0, v1, …), which then only skip the collinear vertices.

    >>> from solverplan.environment import Environment
    >>> ring = Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 1], [0, 2]])
    >>> StraightWalls(ring).vertex_map, StraightWalls(ring, keep_start=True).vertex_map
    ((3, 4, 0, 2), (0, 2, 3, 4))
    """

    def __init__(self, env: Environment, *, keep_start: bool = False) -> None:
        self.env = env
        rings: list[tuple[ExactPoint, ...]] = []
        edge_map: list[tuple[int, Fraction, Fraction]] = []
        vertex_map: list[int] = []
        merged_base = 0
        for r, ring in enumerate(env.rings):
            n = len(ring)
            keep = [i for i in range(n) if not is_straight(ring[i - 1], ring[i], ring[(i + 1) % n])]
            first = 0 if keep_start else canonical_start([ring[i] for i in keep])
            keep = keep[first:] + keep[:first]
            rings.append(tuple(ring[i] for i in keep))
            vertex_map.extend(env.ring_offsets[r] + i for i in keep)
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
        self.vertex_map: tuple[int, ...] = tuple(vertex_map)
        self.identity = all(m == k and s0 == 0 and s1 == 1 for k, (m, s0, s1) in enumerate(edge_map))
        self.merged = env if self.identity else Environment(tuple(rings), name=env.name, reoriented=env.reoriented)

    @property
    def n_merged_vertices(self) -> int:
        """How many collinear vertices were merged away."""
        return self.env.n_vertices - self.merged.n_vertices

    def user_vertex(self, vertex: int) -> int:
        """The user's vertex (global index) at merged vertex ``vertex``."""
        return self.vertex_map[vertex]

    def user_edge_of_point(self, edge: int, point: ExactPoint) -> int:
        """The user edge holding ``point``, a point of merged edge ``edge`` (at a collinear vertex: the edge that
        starts there)."""
        a, b = self.merged.edge(edge).a, self.merged.edge(edge).b
        return self.user_edge_at(edge, _param(a, b, point))

    # ------------------------------------------------------------------ sets and points
    def to_merged(self, bset: BoundarySet) -> BoundarySet:
        """The same boundary points, in the merged numbering (exact; pieces of one wall joined)."""
        if self.identity:
            return bset
        pieces = []
        for piece in bset.pieces:
            m, s0, s1 = self.edge_map[piece.edge]
            pieces.append(BoundaryPiece(m, s0 + piece.t0 * (s1 - s0), s0 + piece.t1 * (s1 - s0)))
        return BoundarySet(tuple(pieces)).merged()

    def merged_point(self, edge: int, t: Fraction) -> tuple[int, Fraction]:
        """User boundary point (edge, t) as (merged edge, s), exact."""
        m, s0, s1 = self.edge_map[edge]
        return m, s0 + t * (s1 - s0)

    @cached_property
    def user_edges(self) -> tuple[tuple[tuple[int, Fraction, Fraction], ...], ...]:
        """For every merged edge m: the user edges on it, in order along it, each ``(k, s0, s1)`` (its merged
        parameter range)."""
        out: list[list[tuple[int, Fraction, Fraction]]] = [[] for _ in range(self.merged.n_edges)]
        for k, (m, s0, s1) in enumerate(self.edge_map):
            out[m].append((k, s0, s1))
        return tuple(tuple(sorted(items, key=lambda item: item[1])) for items in out)

    def user_edges_of(self, edge: int) -> tuple[int, ...]:
        """The user edges making up merged edge ``edge``, in order along it."""
        return tuple(k for k, _, _ in self.user_edges[edge])

    def user_edge_at(self, edge: int, s: Fraction) -> int:
        """The user edge holding the point at merged parameter ``s`` of merged edge ``edge`` (at a collinear
        vertex: the edge that starts there)."""
        users = self.user_edges[edge]
        return next((k for k, s0, s1 in users if s0 <= s < s1), users[-1][0])

    def user_point(self, edge: int, s: Fraction) -> tuple[int, Fraction]:
        """Merged boundary point (edge, s) as (user edge, t) (at a collinear vertex: t = 0 of the edge starting
        there), exact."""
        k = self.user_edge_at(edge, s)
        _, s0, s1 = self.edge_map[k]
        return k, (s - s0) / (s1 - s0)

    def to_user(self, pieces: Iterable[BoundaryPiece]) -> tuple[BoundaryPiece, ...]:
        """Merged pieces as pieces of the user's edges, in order: a piece on a merged edge splits at the
        collinear vertices into pieces of consecutive user edges (exact; a point stays one point)."""
        if self.identity:
            return tuple(pieces)
        out: list[BoundaryPiece] = []
        for piece in pieces:
            users = self.user_edges[piece.edge]
            if piece.t0 == piece.t1:
                k, t = self.user_point(piece.edge, piece.t0)
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
