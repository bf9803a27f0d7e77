"""The exact piecewise affine boundary map f_θ of the constant rule b = θ (paper §6.1).

Under a constant heading the robot's boundary dynamics is a piecewise affine map f_θ of ∂P: on edge e_i
the rays of one exact direction d_i (:class:`~solverplan.bounce.dynamics.ExactHeading`) pass through a
vertex only at finitely many parameters t_v = cross(v − a, d)/cross(e, d) (one per vertex ahead of the
edge's line); between two consecutive ones no ray touches a vertex, so the first-hit edge is constant and
the map is the exact affine map t ↦ α t + β onto that edge
(:func:`~solverplan.bounce.transitions.affine_map`, rational α, β). Adjacent pieces with the same target
have the same map and are merged (the map is continuous there; the single ray through the vertex is
outside the model, as every ray through a vertex is).

Sets of positions are enclosed exactly by closed intervals on the grid t = k / 2^:data:`GRID_BITS`,
rounded outward at every bounce (:meth:`ConstantMap.grid_image`): a sound enclosure of the true image
whose numbers keep a fixed size however many bounces it is carried.

>>> from solverplan.bounce.dynamics import ExactHeading
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> f = ConstantMap(square, ExactHeading.from_tangent("2"))      # steep: the bottom edge sees two walls
>>> [(str(p.lo), str(p.hi), p.target, str(p.map.alpha), str(p.map.beta)) for p in f.pieces(0)]
[('0', '1/2', 2, '-1', '1/2'), ('1/2', '1', 1, '-2', '2')]
>>> f.locate(0, Fraction(1, 3)), f.locate(0, Fraction(1, 2))     # t = 1/2: the ray through the corner (4, 4)
(0, None)
>>> [(e, lo / GRID_ONE, hi / GRID_ONE) for e, lo, hi, _ in f.grid_image(0, GRID_ONE // 4, 3 * GRID_ONE // 4)]
[(2, 0.0, 0.25), (1, 0.5, 1.0)]
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, replace
from fractions import Fraction

from solverplan.bounce.dynamics import ExactHeading
from solverplan.bounce.transitions import AffineMap, affine_map
from solverplan.environment import Environment
from solverplan.errors import SolverFailed
from solverplan.exact import ExactPoint, format_number
from solverplan.geometry.raycast import cast_rays_exact

__all__ = ["ConstantMap", "Piece", "GRID_BITS", "GRID_ONE", "merge_grid_intervals"]

GRID_BITS = 96
"""Exact enclosures of positions live on the grid t = k / 2**GRID_BITS, rounded outward at every bounce."""
GRID_ONE = 1 << GRID_BITS
"""The grid's t = 1 (an integer): grid interval [lo, hi] stands for t ∈ [lo / GRID_ONE, hi / GRID_ONE]."""


@dataclass(frozen=True, slots=True)
class Piece:
    """One affine piece of f_θ on an edge: the open parameter interval (``lo``, ``hi``) lands on edge
    ``target`` by the exact ``map``. ``grid`` = (num_a, num_b, den) is the map on grid numerators:
    L ↦ (num_a L + num_b) / den."""

    lo: Fraction
    hi: Fraction
    target: int
    map: AffineMap
    grid: tuple[int, int, int]

    def grid_image(self, lo: int, hi: int) -> tuple[int, int]:
        """The image of the grid interval [lo, hi] (inside this piece), rounded outward to the grid and
        clipped to the target edge."""
        na, nb, den = self.grid
        a, b = na * lo + nb, na * hi + nb
        if a > b:
            a, b = b, a
        return max(0, a // den), min(GRID_ONE, -((-b) // den))


class ConstantMap:
    """f_θ for one exact heading, built lazily per edge (see the module docstring).

    Parameters
    ----------
    env
        The environment (any polygon with holes).
    heading
        The exact heading θ (radians CCW from each directed edge, inside (0, π)).
    """

    def __init__(self, env: Environment, heading: ExactHeading) -> None:
        self.env, self.heading = env, heading
        self._pieces: dict[int, list[Piece]] = {}
        self._float: dict[int, tuple[list[float], list[int], list[float], list[float]]] = {}
        self._dirs: dict[int, ExactPoint] = {}

    def direction(self, edge: int) -> ExactPoint:
        """The exact world direction d of the heading leaving ``edge`` (rational components)."""
        d = self._dirs.get(edge)
        if d is None:
            e = self.env.edge(edge)
            d = self._dirs[edge] = self.heading.direction((e.b[0] - e.a[0], e.b[1] - e.a[1]))
        return d

    def pieces(self, edge: int) -> list[Piece]:
        """The pieces of f_θ on ``edge``, in increasing t, covering [0, 1] (ends are rays through vertices)."""
        cached = self._pieces.get(edge)
        if cached is not None:
            return cached
        env = self.env
        e = env.edge(edge)
        a = e.a
        ev = (e.b[0] - a[0], e.b[1] - a[1])
        d = self.direction(edge)
        den = ev[0] * d[1] - ev[1] * d[0]  # > 0: d points into the free space
        cuts = {Fraction(0), Fraction(1)}
        for v in env.exact_vertices:
            w = (v[0] - a[0], v[1] - a[1])
            if ev[0] * w[1] - ev[1] * w[0] > 0:  # strictly on the free side of the edge's line
                t = (w[0] * d[1] - w[1] * d[0]) / den
                if 0 < t < 1:
                    cuts.add(t)
        cuts_sorted = sorted(cuts)
        mids = [(lo + hi) / 2 for lo, hi in zip(cuts_sorted, cuts_sorted[1:])]
        hits = cast_rays_exact(env, [env.exact_point_at(edge, t) for t in mids], [d] * len(mids))
        pieces: list[Piece] = []
        for (lo, hi), hit in zip(zip(cuts_sorted, cuts_sorted[1:]), hits):
            if hit is None or hit.vertex is not None:  # pragma: no cover - excluded by the choice of cuts
                raise SolverFailed(f"constant map: the ray from e{edge} at t = {format_number((lo + hi) / 2)} hits a vertex")
            if pieces and pieces[-1].target == hit.edge:
                pieces[-1] = replace(pieces[-1], hi=hi)
                continue
            m = affine_map(env, edge, d, hit.edge)
            an, ad, bn, bd = m.alpha.numerator, m.alpha.denominator, m.beta.numerator, m.beta.denominator
            pieces.append(Piece(lo, hi, hit.edge, m, (an * bd, bn * ad * GRID_ONE, ad * bd)))
        self._pieces[edge] = pieces
        return pieces

    def locate(self, edge: int, t: Fraction) -> int | None:
        """Index of the piece holding t strictly inside, None at a piece end (a ray through a vertex)."""
        pieces = self.pieces(edge)
        k = bisect.bisect_right([p.lo for p in pieces], t) - 1
        if k < 0 or not pieces[k].lo < t < pieces[k].hi:
            return None
        return k

    def float_table(self, edge: int) -> tuple[list[float], list[int], list[float], list[float]]:
        """The pieces of ``edge`` in floats for fast iteration: (interior piece ends, targets, α, β)."""
        table = self._float.get(edge)
        if table is None:
            pieces = self.pieces(edge)
            table = self._float[edge] = (
                [float(p.lo) for p in pieces[1:]],
                [p.target for p in pieces],
                [float(p.map.alpha) for p in pieces],
                [float(p.map.beta) for p in pieces],
            )
        return table

    def grid_image(self, edge: int, lo: int, hi: int) -> list[tuple[int, int, int, int]]:
        """An outward-rounded enclosure of f_θ([lo, hi] / GRID_ONE on ``edge``): (edge', lo', hi', piece
        index) per piece met (an interval only touching a piece at an end point skips it; a point on a
        piece end meets both neighbours)."""
        out = []
        flo, fhi = Fraction(lo, GRID_ONE), Fraction(hi, GRID_ONE)
        for k, p in enumerate(self.pieces(edge)):
            if p.hi < flo or p.lo > fhi or (lo < hi and (p.hi == flo or p.lo == fhi)):
                continue
            a = max(lo, (p.lo.numerator * GRID_ONE) // p.lo.denominator)
            b = min(hi, -((-p.hi.numerator * GRID_ONE) // p.hi.denominator))
            ia, ib = p.grid_image(a, b)
            out.append((p.target, ia, ib, k))
        return out


def merge_grid_intervals(intervals: list[tuple[int, int, int]]) -> list[tuple[int, int, int]]:
    """Merge overlapping (edge, lo, hi) grid intervals of the same edge; sorted by edge, then lo."""
    out: list[tuple[int, int, int]] = []
    for e, lo, hi in sorted(intervals):
        if out and out[-1][0] == e and lo <= out[-1][2]:
            if hi > out[-1][2]:
                out[-1] = (e, out[-1][1], hi)
        else:
            out.append((e, lo, hi))
    return out
