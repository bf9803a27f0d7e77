"""Straight walls: an environment with its collinear vertices merged, and the exact map between the two (private).

A vertex whose interior angle is exactly π (the previous and next vertices on one line through it, on
either side) is not a corner: the wall goes on straight through it. Yet the partition P′ cuts the boundary
at every vertex, so a collinear vertex splits a wall into segments, and the rays of Algorithm 1 through it
add further cut points that mark no visibility event. A planner whose stages land on one segment of P′
would then see a different (smaller) class of plans in the same free space, and its "optimal" answers would
change with the vertex list.

The planners therefore search the **merged** environment (:mod:`solverplan.geometry.walls`, shared with every
robot model) — the same rings with every collinear vertex
removed (the same free space, exactly) — and report in the user's numbering:

- user edge k lies on merged edge ``m`` with merged parameter s = s₀ + t·(s₁ − s₀) (exact: the merged edge
  is the same line, and s is the ratio of the distances along it);
- every segment of the user's P′ lies inside exactly one segment of the merged P′ (the user's partition
  points are the merged ones plus the collinear vertices and the cut points of the rays through them), so a
  merged segment is a *run* of consecutive user segments, listed in boundary order.

The edge maps are :class:`~solverplan.geometry.walls.StraightWalls`' (example there); :class:`PartitionedWalls` adds
the segments of P′. On the bottom wall of a square written with a collinear vertex at (2, 0), a visit of user
edge 1 cuts the merged edge 0 at its middle, and the middle half of that wall overlaps one user segment on each side:

>>> from solverplan.environment import BoundaryPiece, Environment
>>> walls = PartitionedWalls(Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]]))
>>> walls.visit_cuts([1])
{0: [Fraction(1, 2)]}
>>> [(u, str(p)) for u, p in walls.pieces_of(BoundaryPiece(0, Fraction(1, 4), Fraction(3, 4)))]
[(0, 'e0:0.5:1'), (1, 'e1:0:0.5')]
"""

from __future__ import annotations

import bisect
from fractions import Fraction
from functools import cached_property
from typing import Iterable, Mapping

from solverplan.bounce.partitions import Partition, PartitionSegment, partition as make_partition, renumbered
from solverplan.environment import BoundaryPiece
from solverplan.geometry.walls import StraightWalls, canonical_start, collinear_vertices

__all__ = ["PartitionedWalls", "canonical_start", "collinear_vertices", "cut_partition"]


def cut_partition(part: Partition, cuts: Mapping[int, Iterable[Fraction]]) -> Partition:
    """``part`` cut again at the points ``cuts`` (edge → parameters strictly inside (0, 1)), exact. The new points
    are no vertices and no Algorithm-1 events: they are where a query's sets end (patrol visits ending at a
    collinear vertex), so the searched segments lie inside or outside them. ``part`` when nothing new is cut.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> p = cut_partition(make_partition(square), {0: [Fraction(1, 2)], 2: [Fraction(1, 4), Fraction(1, 2)]})
    >>> [(s.edge, s.t0, s.t1) for s in p.segments][:3], len(p.segments)
    ([(0, Fraction(0, 1), Fraction(1, 2)), (0, Fraction(1, 2), Fraction(1, 1)), (1, Fraction(0, 1), Fraction(1, 1))], 7)
    """
    extra = {e: {Fraction(t) for t in ts} for e, ts in cuts.items()}
    for e, ts in extra.items():
        if any(not 0 < t < 1 for t in ts):
            raise ValueError(f"cut_partition: a cut of edge {e} is not strictly inside (0, 1)")
    env = part.env
    segments: list[PartitionSegment] = []
    changed = False
    for seg in part.segments:
        inside = sorted(t for t in extra.get(seg.edge, ()) if seg.t0 < t < seg.t1)
        if not inside:
            segments.append(PartitionSegment(len(segments), seg.edge, seg.t0, seg.t1, seg.a, seg.b))
            continue
        changed = True
        bounds = [seg.t0, *inside, seg.t1]
        ps = [seg.a, *(env.exact_point_at(seg.edge, t) for t in inside), seg.b]
        for k in range(len(bounds) - 1):
            segments.append(PartitionSegment(len(segments), seg.edge, bounds[k], bounds[k + 1], ps[k], ps[k + 1]))
    if not changed:
        return part
    offsets = [0]
    for ring in range(len(env.rings)):
        last = env.ring_offsets[ring + 1] - 1
        offsets.append(1 + max(s.id for s in segments if s.edge <= last))
    return Partition(env, tuple(segments), tuple(offsets), part.inserted)


class PartitionedWalls(StraightWalls):
    """The straight walls of ``env`` (:class:`~solverplan.geometry.walls.StraightWalls`: its merged environment and
    the maps between the two numberings), with the maps between the segments of P′ of the two environments that
    the planners need.

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

    def visit_cuts(self, edges: Iterable[int]) -> dict[int, list[Fraction]]:
        """Where the user edges ``edges`` end inside merged edges (at collinear vertices): merged edge → its
        parameters there, sorted. A patrol visit of user edge k means landing on k's part of its wall, so the
        searched partition is cut there (:func:`cut_partition`)."""
        out: dict[int, set[Fraction]] = {}
        for k in edges:
            m, s0, s1 = self.edge_map[k]
            out.setdefault(m, set()).update(s for s in (s0, s1) if 0 < s < 1)
        return {m: sorted(ts) for m, ts in out.items() if ts}

    # ------------------------------------------------------------------ segments
    @cached_property
    def user_partition(self) -> Partition:
        """The partition P′ of the user's environment (the ids answers are reported in). When the straight walls are
        the user's rings started elsewhere (no vertex merged), it is the straight walls' P′ renumbered
        (:func:`~solverplan.bounce.partitions.renumbered`: the same points, without casting the rays again)."""
        if not self.identity and self.merged.n_vertices == self.env.n_vertices:
            return renumbered(make_partition(self.merged), self.env, self.vertex_map)
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

    @cached_property
    def _user_starts_by_edge(self) -> tuple[tuple[Fraction, ...], ...]:
        """For every merged edge: the merged parameter ``s1`` where each of its user segments ends, in order."""
        return tuple(tuple(s1 for _, s1, _ in items) for items in self._user_segments_by_edge)

    def pieces_of(self, piece: BoundaryPiece) -> tuple[tuple[int, BoundaryPiece], ...]:
        """A piece of a merged edge (positive length) as the user segments it overlaps, in order along it, each with
        the exact overlap as a piece of the user's edge."""
        user = self.user_partition
        out = []
        items = self._user_segments_by_edge[piece.edge]
        first = bisect.bisect_right(self._user_starts_by_edge[piece.edge], piece.t0)  # the first ending after t0
        for s0, s1, u in items[first:]:
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
        if self.identity and len(search.segments) == len(self.user_partition.segments):  # P′ of the same walls
            return tuple(((seg.id, BoundaryPiece(seg.edge, seg.t0, seg.t1)),) for seg in search.segments)
        return tuple(self.pieces_of(BoundaryPiece(seg.edge, seg.t0, seg.t1)) for seg in search.segments)

    def runs(self, search: Partition) -> tuple[tuple[int, ...], ...]:
        """For every segment of ``search`` (:meth:`user_pieces`), the user segments it overlaps, in boundary order."""
        return tuple(tuple(u for u, _ in pieces) for pieces in self.user_pieces(search))
