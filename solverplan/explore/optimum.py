"""The fewest chained views over a finite candidate set: set cover with a connectivity constraint (a MILP).

The offline problem behind the exploration (Ghosh et al., "Online algorithms with discrete visibility",
section "Background"): viewpoints p₁ = start, p₂, …, p_k whose views cover P, each p_i in the view of some
earlier p_j, k minimum. Over a finite candidate set C (start included) the views split P into cells (the
faces of the arrangement of their boundaries); a chosen set S covers P iff every cell lies in the view of a
member, and S can be ordered as a chain iff the visibility graph on S is connected and contains the start
(visibility is symmetric). Connectivity is a single-commodity flow from the start: each chosen candidate
other than the start consumes one unit, flow runs only along visibility pairs between chosen candidates.

The optimum is over C only: an upper bound on the true optimum over all points of P; with the online
algorithm's own viewpoints in C it never exceeds the online number of views, so the measured ratio
online/optimum is a lower estimate of the true competitive ratio on that instance.

**Candidates.** C holds the start, the polygon's vertices, the points given, and (``refine=True``, the default)
a point inside every cell of the arrangement of those views (issue #26: over vertices and an online run's
viewpoints alone the optimum was 3 where two chained views cover) — a point inside a cell sees at least what the
cell's corners see jointly, often more.

**Lower bound.** Witness points whose visibility polygons are pairwise disjoint need one view each: no point sees
two of them. Greedily, from points near the convex vertices and the cells' points (smallest views first), a
witness is taken when its view (slightly grown, so that touching counts as meeting) meets none taken before.
``lower_bound`` is that count (at least 1), ``gap`` = views − lower_bound; the optimum is proved when the gap is
0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import ExactPoint, exact_point
from solverplan.geometry.visibility import sees, visibility_polygon

__all__ = ["ChainedOptimum", "chained_optimum"]


@dataclass(frozen=True, slots=True)
class ChainedOptimum:
    """The fewest chained views over the candidates: ``viewpoints`` (the start first), ``cells`` the number
    of arrangement cells covered, ``candidates`` how many points were offered, ``lower_bound`` a proved lower
    bound on the fewest views from any points (pairwise invisible witnesses, module docstring) and ``witnesses``
    those points."""

    viewpoints: tuple[ExactPoint, ...]
    cells: int
    candidates: int
    lower_bound: int = 1
    witnesses: tuple[ExactPoint, ...] = ()

    @property
    def views(self) -> int:
        return len(self.viewpoints)

    @property
    def gap(self) -> int:
        """views − lower_bound: 0 when the optimum over the candidates is the optimum over all of P."""
        return self.views - self.lower_bound

    def to_json(self) -> dict:
        return {"views": self.views, "viewpoints": [[float(x), float(y)] for x, y in self.viewpoints],
                "lower_bound": self.lower_bound, "gap": self.gap, "candidates": self.candidates, "cells": self.cells,
                "witnesses": [[float(x), float(y)] for x, y in self.witnesses]}


def _arrangement(free, shapes: list, floor: float) -> list:
    cells = [free]
    for shape in shapes:  # refine the arrangement one view at a time
        nxt = []
        for cell in cells:
            for piece in (cell.intersection(shape), cell.difference(shape)):
                for part in getattr(piece, "geoms", [piece]):
                    if part.geom_type == "Polygon" and part.area > floor:
                        nxt.append(part)
        cells = nxt
    return cells


def _inside_point(env: Environment, x: float, y: float) -> ExactPoint | None:
    """The float point as an exact rational one, if it lies strictly inside the free space."""
    from fractions import Fraction

    from solverplan.exact import point_in_ring

    q = (Fraction(x), Fraction(y))
    if point_in_ring(q, env.outer) > 0 and all(point_in_ring(q, h) < 0 for h in env.holes):
        return q
    return None


def _lower_bound(env: Environment, spots: list[ExactPoint], scale: float) -> tuple[ExactPoint, ...]:
    """Pairwise invisible witnesses, greedily, smallest visibility polygon first (module docstring)."""
    import shapely

    grown = []
    for q in spots:
        try:
            vp = visibility_polygon(env, q)
        except InputError:
            continue
        shape = shapely.Polygon([tuple(map(float, x)) for x in vp.ring]).buffer(1e-7 * scale)
        grown.append((shape.area, q, shape))
    grown.sort(key=lambda t: t[0])
    taken: list = []
    for _, q, shape in grown:
        if all(not shape.intersects(other) for _, other in taken):
            taken.append((q, shape))
    return tuple(q for q, _ in taken)


def chained_optimum(env: Environment, start: Sequence[object], candidates: Sequence[Sequence[object]] = (), *,
                    min_cell_area: float = 1e-9, refine: bool = True, max_candidates: int = 400) -> ChainedOptimum:
    """Solve the chained cover MILP over ``start``, the polygon's vertices and ``candidates``.

    Parameters
    ----------
    env
        The free space.
    start
        p₁ (always chosen).
    candidates
        Further points of the free space to offer (e.g. an online run's viewpoints).
    min_cell_area
        Cells smaller than this fraction of the free space's area are rounding slivers of the arrangement and
        are dropped (floats, shapely).
    refine
        Offer a point inside every cell of the arrangement too (module docstring), up to ``max_candidates``
        points in all.

    Raises
    ------
    InputError
        If a point is not in the free space.
    SolverFailed
        If the MILP solver does not report an optimum.
    """
    import cvxpy as cp
    import numpy as np
    import shapely

    points: list[ExactPoint] = []
    for q in [start, *env.exact_vertices, *candidates]:
        p = exact_point(q, where="candidate")
        if p not in points:
            points.append(p)
    try:
        views = [visibility_polygon(env, p) for p in points]
    except InputError as exc:
        raise InputError(f"chained optimum: {exc}") from None
    shapes = [shapely.Polygon([tuple(map(float, x)) for x in vp.ring]).buffer(0) for vp in views]
    free = env.to_shapely()
    floor = min_cell_area * free.area
    scale = max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1])
    cells = _arrangement(free, shapes, floor)
    cell_points = [q for q in (_inside_point(env, c.representative_point().x, c.representative_point().y)
                               for c in cells) if q is not None]
    if refine:
        extra = [q for q in cell_points if q not in points][:max(0, max_candidates - len(points))]
        if extra:
            points += extra
            more = [visibility_polygon(env, p) for p in extra]
            shapes += [shapely.Polygon([tuple(map(float, x)) for x in vp.ring]).buffer(0) for vp in more]
            cells = _arrangement(free, shapes, floor)
    near_corners: list[ExactPoint] = []
    reflex = set(env.reflex_vertices)
    for corner in range(env.n_vertices):
        if corner in reflex:
            continue
        a, b = env.vertices[int(env.prev_vertex[corner])], env.vertices[int(env.next_vertex[corner])]
        here = env.vertices[corner]
        inside = _inside_point(env, *(here + 1e-3 * ((a - here) + (b - here))))
        if inside is not None:
            near_corners.append(inside)
    witnesses = _lower_bound(env, near_corners + cell_points, scale)
    n, m = len(points), len(cells)
    spots = [c.representative_point() for c in cells]
    cover = np.array([[shape.buffer(1e-9 * max(1.0, free.length)).contains(s) for shape in shapes] for s in spots],
                     dtype=float)
    if not cover.any(axis=1).all():  # pragma: no cover - the vertices' views cover P
        raise SolverFailed("chained optimum: some cell is seen by no candidate")
    arcs = [(i, j) for i in range(n) for j in range(n) if i != j and sees(env, points[i], points[j])]
    x = cp.Variable(n, boolean=True)
    f = cp.Variable(len(arcs), nonneg=True)
    cons = [cover @ x >= 1, x[0] == 1]
    out_of: list[list[int]] = [[] for _ in range(n)]
    into: list[list[int]] = [[] for _ in range(n)]
    for k, (i, j) in enumerate(arcs):
        out_of[i].append(k)
        into[j].append(k)
        cons += [f[k] <= (n - 1) * x[i], f[k] <= (n - 1) * x[j]]
    for v in range(1, n):
        inflow = sum(f[k] for k in into[v]) if into[v] else 0
        outflow = sum(f[k] for k in out_of[v]) if out_of[v] else 0
        cons.append(inflow - outflow == x[v])
    problem = cp.Problem(cp.Minimize(cp.sum(x)), cons)
    problem.solve(solver=cp.HIGHS)
    if problem.status != cp.OPTIMAL or x.value is None:
        raise SolverFailed(f"chained optimum: the MILP solver stopped with status {problem.status}")
    chosen = [i for i in range(n) if x.value[i] > 0.5]
    return ChainedOptimum(tuple(points[i] for i in chosen), m, n, max(1, len(witnesses)), witnesses)
