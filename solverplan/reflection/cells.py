"""Convex cells of the free space, their adjacency over shared facets, and cell sequences (Stager and Tanner, §II).

The decomposition is Hertel and Mehlhorn's: a constrained Delaunay triangulation of the free space (GEOS, through
shapely; holes included, no Steiner points), then every diagonal whose removal keeps both of its end points strictly
convex is removed, longest first. Every cell vertex is a vertex of the environment, so every coordinate is the
environment's exact rational vertex and every decision — convexity of a merge, which side of a cell a point is on,
whether two cells share a facet — is exact. Two cells are adjacent when they share a whole side (a *facet*); a side
that is not a facet lies on a wall of the environment. Strict convexity (no angle of exactly π) keeps the cells of
a rectilinear corridor whose walls carry the projections of its reflex corners as rectangles and corner squares,
the cells the flow-through fields of :mod:`~solverplan.reflection.fields` are made for.

A cell with m sides is its m side midpoints and inward normals (p_i, n_i) (paper Eq. 1); q is in the cell iff
n_i·(q − p_i) ≥ 0 for every i. Normals here are the exact left normals of the counter-clockwise sides (not unit).

>>> from solverplan.environment import load_environment
>>> dec = decompose_free_space(load_environment("l_shape"))
>>> len(dec.cells), dec.adjacency
(2, ((0, 1),))
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from fractions import Fraction
from functools import cached_property
from typing import Sequence

import numpy as np

from solverplan.choices import CellKind
from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import ExactPoint, cross, exact_point, format_point, signed_area2
from solverplan.geometry.walls import StraightWalls

__all__ = ["Side", "Cell", "CellDecomposition", "decompose_free_space", "with_corner_projections", "CELL_KINDS",
           "cut_at_sides"]


def _turn(a: ExactPoint, b: ExactPoint, c: ExactPoint) -> Fraction:
    """Twice the signed area of (a, b, c): > 0 for a left turn at b."""
    return cross((b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1]))


@dataclass(frozen=True, slots=True)
class Side:
    """One side of a cell: from vertex ``a`` to vertex ``b`` (counter-clockwise around the cell, exact).

    ``neighbour`` is the cell across the side when it is a facet, ``None`` when the side lies on a wall.
    ``normal`` is the exact inward (left) normal (b − a)^⊥, of length |b − a|; ``midpoint`` is exact.
    """

    a: ExactPoint
    b: ExactPoint
    neighbour: int | None

    @property
    def is_wall(self) -> bool:
        return self.neighbour is None

    @property
    def midpoint(self) -> ExactPoint:
        return ((self.a[0] + self.b[0]) / 2, (self.a[1] + self.b[1]) / 2)

    @property
    def normal(self) -> ExactPoint:
        return (-(self.b[1] - self.a[1]), self.b[0] - self.a[0])

    def unit_normal(self) -> np.ndarray:
        """The inward unit normal in floats."""
        n = np.array([float(self.normal[0]), float(self.normal[1])])
        return n / np.hypot(*n)

    def float_midpoint(self) -> np.ndarray:
        return np.array([float(self.midpoint[0]), float(self.midpoint[1])])

    def side_of(self, q: Sequence[Fraction]) -> Fraction:
        """n·(q − a): positive inside the side's half-plane, zero on its line (exact)."""
        n = self.normal
        return n[0] * (q[0] - self.a[0]) + n[1] * (q[1] - self.a[1])


@dataclass(frozen=True)
class Cell:
    """A convex cell: its exact vertices counter-clockwise (``vertices``) and ``sides`` (side i from vertex i)."""

    id: int
    vertices: tuple[ExactPoint, ...]
    sides: tuple[Side, ...]

    @cached_property
    def float_vertices(self) -> np.ndarray:
        return np.array([[float(x), float(y)] for x, y in self.vertices])

    @cached_property
    def centroid(self) -> np.ndarray:
        """The area centroid (floats)."""
        import shapely

        c = shapely.Polygon(self.float_vertices).centroid
        return np.array([c.x, c.y])

    def contains(self, q: Sequence[Fraction]) -> bool:
        """Is the exact point ``q`` in the closed cell?"""
        return all(s.side_of(q) >= 0 for s in self.sides)

    def facet_to(self, other: int) -> int:
        """The index of the side shared with cell ``other``; :class:`ValueError` when they are not adjacent."""
        for i, s in enumerate(self.sides):
            if s.neighbour == other:
                return i
        raise ValueError(f"cells {self.id} and {other} share no facet")

    def to_json(self) -> dict:
        return {"id": self.id, "polygon": [[float(x), float(y)] for x, y in self.vertices]}


@dataclass(frozen=True)
class CellDecomposition:
    """Convex cells covering the free space, and their adjacency over shared facets.

    ``adjacency``: the pairs (i, j), i < j, of cells that share a facet, sorted.
    """

    env: Environment
    cells: tuple[Cell, ...]
    adjacency: tuple[tuple[int, int], ...]

    @cached_property
    def graph(self):
        """The adjacency graph (networkx), arcs weighted by the distance between the facet midpoints' cells'
        centroids through the facet midpoint (a path length through the cells)."""
        import networkx as nx

        g = nx.Graph()
        g.add_nodes_from(range(len(self.cells)))
        for i, j in self.adjacency:
            mid = self.cells[i].sides[self.cells[i].facet_to(j)].float_midpoint()
            w = float(np.hypot(*(self.cells[i].centroid - mid)) + np.hypot(*(self.cells[j].centroid - mid)))
            g.add_edge(i, j, weight=w)
        return g

    def locate(self, q: Sequence[object], *, where: str = "point") -> int:
        """The cell holding the point ``q`` (exact; the lowest id when it is on a facet).

        Raises :class:`InputError` when ``q`` is outside the free space or on a wall (a robot position is
        a point of the open free space; facets between cells are fine).
        """
        p = exact_point(q, where=where)
        inside = [c.id for c in self.cells if c.contains(p)]
        on_wall = any(s.is_wall and s.side_of(p) == 0 and _between(p, s.a, s.b)
                      for c in self.cells for s in c.sides if c.id in inside)
        if not inside:
            raise InputError(f"{where} {format_point(p)} is not in the free space of {self.env.name or 'the environment'}")
        if on_wall:
            raise InputError(f"{where} {format_point(p)} is on a wall: choose a point inside the free space")
        return inside[0]

    def sequence(self, start_cell: int, goal_cell: int) -> tuple[int, ...]:
        """The shortest cell sequence from ``start_cell`` to ``goal_cell`` (networkx Dijkstra on :attr:`graph`).

        Raises :class:`InputError` when the goal is not reachable (they lie in different components).
        """
        import networkx as nx

        try:
            return tuple(nx.shortest_path(self.graph, start_cell, goal_cell, weight="weight"))
        except nx.NetworkXNoPath:
            raise InputError(f"cell {goal_cell} cannot be reached from cell {start_cell}") from None

    def successors(self, goal_cell: int) -> dict[int, int | None]:
        """For every cell, the next cell of a shortest path to ``goal_cell`` (``None`` for the goal cell itself and
        for cells that cannot reach it): the composition's outlet of every cell, on the sequence or off it."""
        import networkx as nx

        paths = nx.single_source_dijkstra_path(self.graph, goal_cell, weight="weight")
        out: dict[int, int | None] = {c.id: None for c in self.cells}
        for cell, path in paths.items():
            if len(path) > 1:
                out[cell] = path[-2]
        return out

    @cached_property
    def halfplanes(self) -> tuple[np.ndarray, np.ndarray]:
        """Padded float arrays for vectorised point location: normals (cells, m, 2) unit, offsets (cells, m) with
        n·q − h ≥ 0 inside; padding rows (0, 0, −1) always hold."""
        m = max(len(c.sides) for c in self.cells)
        normals = np.zeros((len(self.cells), m, 2))
        offsets = np.full((len(self.cells), m), -1.0)
        for c in self.cells:
            for i, s in enumerate(c.sides):
                n = s.unit_normal()
                normals[c.id, i] = n
                offsets[c.id, i] = n @ np.array([float(s.a[0]), float(s.a[1])])
        return normals, offsets

    def inside(self, points: np.ndarray, tolerance: float = 0.0) -> np.ndarray:
        """Boolean (k, cells): point k is in cell c up to ``tolerance`` (a length; floats)."""
        normals, offsets = self.halfplanes
        values = np.einsum("cmj,kj->kcm", normals, points) - offsets[None]
        return np.all(values >= -tolerance, axis=2)


def _between(p: Sequence[Fraction], a: ExactPoint, b: ExactPoint) -> bool:
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


CELL_KINDS = CellKind.values()
"""Decompositions: ``convex`` (Hertel–Mehlhorn on the environment's own vertices) and ``corners`` (the same after
adding the projections of every reflex vertex along its two walls, :func:`with_corner_projections`)."""


def with_corner_projections(env: Environment) -> Environment:
    """``env`` with a vertex added where each wall through a reflex vertex, extended past it into the free space,
    first meets a wall (exact ray casts; a hit on a vertex adds nothing). The free space is the same; the new
    vertices are collinear with their wall's ends, and Hertel–Mehlhorn never merges across an angle of π, so the
    cells of a corridor become its straight stretches and **corner cells** — the cells where the path turns by
    90° or more, the reflection candidates of §III — also where the corridor's walls are diagonal (zigzags, 45°
    cuts) and the plain decomposition merges each turn into a long quadrilateral.

    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [4, 0], [4, 4], [2, 4], [2, 2], [0, 2]])
    >>> [tuple(map(int, p)) for p in with_corner_projections(ell).exact_vertices]
    [(0, 0), (2, 0), (4, 0), (4, 2), (4, 4), (2, 4), (2, 2), (0, 2)]
    """
    from solverplan.geometry.raycast import cast_rays_exact

    verts = env.exact_vertices
    prev, nxt = env.prev_vertex, env.next_vertex
    origins, directions = [], []
    for v in env.reflex_vertices:
        for u in (int(prev[v]), int(nxt[v])):  # the wall from u to v, continued past v
            origins.append(verts[v])
            directions.append((verts[v][0] - verts[u][0], verts[v][1] - verts[u][1]))
    extra: dict[int, set[Fraction]] = {}
    for hit in cast_rays_exact(env, origins, directions, skip_invalid=True) if origins else []:
        if hit is not None and hit.vertex is None and 0 < hit.t < 1:
            extra.setdefault(hit.edge, set()).add(Fraction(hit.t))
    if not extra:
        return env
    rings = []
    for k in range(len(env.rings)):
        lo, hi = env.ring_offsets[k], env.ring_offsets[k + 1]
        ring = []
        for e in range(lo, hi):
            a, b = verts[e], verts[int(nxt[e])]
            ring.append(a)
            for t in sorted(extra.get(e, ())):
                ring.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
        rings.append(ring)
    return Environment.from_coords(rings[0], rings[1:], name=env.name)


def decompose_free_space(env: Environment, cells: str = "convex") -> CellDecomposition:
    """Convex cells of ``env``'s free space (holes included), with their adjacency over shared facets.

    The cells are made by Hertel–Mehlhorn merging of a constrained Delaunay triangulation. Every cell vertex is an
    exact vertex of ``env``; the cells are counter-clockwise, strictly convex (no angle of π is created by a merge),
    and cover the free space exactly (their areas sum to the environment's exact area — checked). The triangulation
    is made of the canonical walls of ``env`` (:class:`~solverplan.geometry.walls.StraightWalls`: collinear vertices
    merged — they are no corners — and each ring from its canonical vertex), so that the cells do not depend on how
    the walls are written.

    Parameters
    ----------
    env
        A valid environment (any polygon with holes).
    cells
        ``convex`` (default) or ``corners``: first add the projections of the reflex vertices along their walls
        (:func:`with_corner_projections`), so turns get corner cells. The decomposition's ``env`` is then the
        environment with those vertices (the same free space).

    Returns
    -------
    CellDecomposition
        The cells (exact, counter-clockwise vertices in the environment's units) and the pairs of cells that share
        a facet.

    Raises
    ------
    SolverFailed
        If the triangulation is not made of the environment's vertices or does not cover it (never expected).

    Examples
    --------
    >>> from solverplan.environment import load_environment
    >>> dec = decompose_free_space(load_environment("one_hole"))
    >>> sum(len(c.sides) for c in dec.cells) >= 3 * len(dec.cells), len(dec.adjacency) >= len(dec.cells) - 1
    (True, True)
    >>> dec = decompose_free_space(load_environment("l_shape"))      # two cells, split along the reflex corner's diagonal
    >>> [[(int(x), int(y)) for x, y in cell.vertices] for cell in dec.cells], dec.adjacency
    ([[(0, 0), (10, 0), (10, 4), (4, 4)], [(0, 0), (4, 4), (4, 10), (0, 10)]], ((0, 1),))
    """
    import shapely

    cells = CellKind.parse(cells, "decomposition").value
    walls = StraightWalls(env)
    if not walls.identity:  # canonical walls first: the corner projections below add collinear vertices of their own
        return replace(decompose_free_space(walls.merged, cells), env=env)
    if cells == "corners":
        env = with_corner_projections(env)
    exact = env.exact_vertices
    index = {(float(x), float(y)): k for k, (x, y) in enumerate(exact)}
    triangles: list[list[int]] = []
    for tri in shapely.constrained_delaunay_triangles(env.to_shapely()).geoms:
        coords = list(tri.exterior.coords)[:3]
        try:
            ids = [index[(float(x), float(y))] for x, y in coords]
        except KeyError as exc:
            raise SolverFailed(f"the triangulation of {env.name!r} made a point that is not a vertex: {exc}") from None
        if _turn(exact[ids[0]], exact[ids[1]], exact[ids[2]]) < 0:
            ids.reverse()
        if _turn(exact[ids[0]], exact[ids[1]], exact[ids[2]]) == 0:
            continue  # a flat triangle on collinear vertices covers nothing: its sides are shared by others
        triangles.append(ids)
    polygons = _merge(triangles, exact)
    area = sum((signed_area2([exact[k] for k in poly]) for poly in polygons), Fraction(0)) / 2
    if area != env.area:
        raise SolverFailed(f"the cells of {env.name!r} cover area {float(area):g}, not {float(env.area):g}")
    return _build(env, polygons)


def _merge(triangles: list[list[int]], exact: Sequence[ExactPoint]) -> list[list[int]]:
    """Hertel–Mehlhorn: remove diagonals (longest first) while both end points stay strictly convex."""
    polygons: dict[int, list[int]] = {k: list(t) for k, t in enumerate(triangles)}
    owner: dict[tuple[int, int], int] = {}  # directed side (u, v) → polygon holding it
    for k, poly in polygons.items():
        for i in range(len(poly)):
            owner[(poly[i], poly[(i + 1) % len(poly)])] = k

    def length2(u: int, v: int) -> Fraction:
        return (exact[u][0] - exact[v][0]) ** 2 + (exact[u][1] - exact[v][1]) ** 2

    diagonals = sorted({(min(u, v), max(u, v)) for (u, v) in owner if (v, u) in owner},
                       key=lambda e: (-length2(*e), e))
    for u, v in diagonals:
        if (u, v) not in owner or (v, u) not in owner:
            continue
        k1, k2 = owner[(u, v)], owner[(v, u)]
        if k1 == k2:
            continue
        p1, p2 = polygons[k1], polygons[k2]
        # p1 holds u → v, p2 holds v → u: glue p2's chain from u round to v in place of the side u → v
        i1, i2 = p1.index(u), p2.index(v)
        r1 = p1[i1 + 1:] + p1[:i1 + 1]  # starts after u ... ends with u; first element is v
        r2 = p2[i2 + 1:] + p2[:i2 + 1]  # first element is u, ends with v
        merged = r1[:-1] + [u] + r2[1:-1]  # v ... (p1 chain) ... u, then p2's chain strictly between u and v
        n = len(merged)
        if not all(_turn(exact[merged[i - 1]], exact[merged[i]], exact[merged[(i + 1) % n]]) > 0
                   for i in range(n) if merged[i] in (u, v)):
            continue
        del polygons[k2]
        polygons[k1] = merged
        del owner[(u, v)], owner[(v, u)]
        for i in range(n):
            owner[(merged[i], merged[(i + 1) % n])] = k1
    return [polygons[k] for k in sorted(polygons)]


def _build(env: Environment, polygons: list[list[int]],
           vertices: Sequence[ExactPoint] | None = None) -> CellDecomposition:
    """The cells of ``polygons`` (indices into ``vertices``, by default the environment's), numbered and linked."""
    exact = env.exact_vertices if vertices is None else vertices
    side_owner: dict[tuple[int, int], int] = {}
    ordered = sorted(polygons, key=lambda poly: (min(exact[k] for k in poly), len(poly)))
    for cid, poly in enumerate(ordered):
        for i in range(len(poly)):
            side_owner[(poly[i], poly[(i + 1) % len(poly)])] = cid
    cells = []
    pairs = set()
    for cid, poly in enumerate(ordered):
        start = min(range(len(poly)), key=lambda i: (exact[poly[i]][1], exact[poly[i]][0]))  # lowest, then leftmost
        poly = poly[start:] + poly[:start]
        sides = []
        for i in range(len(poly)):
            u, v = poly[i], poly[(i + 1) % len(poly)]
            neighbour = side_owner.get((v, u))
            sides.append(Side(exact[u], exact[v], neighbour))
            if neighbour is not None:
                pairs.add((min(cid, neighbour), max(cid, neighbour)))
        cells.append(Cell(cid, tuple(exact[k] for k in poly), tuple(sides)))
    return CellDecomposition(env, tuple(cells), tuple(sorted(pairs)))


def cut_at_sides(dec: CellDecomposition, cuts: dict[int, int]) -> CellDecomposition:
    """The decomposition with cell c's side ``cuts[c]`` cut off on a triangle, for every c of ``cuts``.

    Cell c (at least 4 vertices) is cut along a diagonal into a triangle holding side i = ``cuts[c]`` and the rest:
    the triangle (v_{i−1}, v_i, v_{i+1}) or (v_i, v_{i+1}, v_{i+2}), the fatter (larger area over its longest side
    squared, exact; ties to the first). Both parts are convex and share the whole diagonal, so the other cells keep
    their facets; every vertex is still an exact vertex of the environment. Cells are numbered afresh (as
    :func:`decompose_free_space` numbers them). The composition cuts a cell whose outlet no line field was found
    for: a triangle always has one (a constant field from the apex through the outlet, bent gently), and the rest
    gets the diagonal as a new way out.

    Examples
    --------
    >>> import solverplan as sp
    >>> square = sp.decompose_free_space(sp.load_environment("square"))
    >>> [[(int(x), int(y)) for x, y in c.vertices] for c in cut_at_sides(square, {0: 0}).cells]  # a tie: the first
    [[(0, 0), (10, 0), (0, 10)], [(10, 0), (10, 10), (0, 10)]]
    """
    exact = sorted({v for cell in dec.cells for v in cell.vertices})  # corner projections may not be env vertices
    index = {p: k for k, p in enumerate(exact)}
    polygons = []
    for cell in dec.cells:
        poly = [index[v] for v in cell.vertices]
        side = cuts.get(cell.id)
        if side is None or len(poly) < 4:
            polygons.append(poly)
            continue
        m = len(poly)
        options = [[(side - 1) % m, side, (side + 1) % m], [side, (side + 1) % m, (side + 2) % m]]
        tri = max(options, key=lambda t: _fatness([exact[poly[k]] for k in t]))  # max keeps the first of ties
        rest = [poly[k] for k in range(m) if k != tri[1]]
        polygons += [[poly[k] for k in tri], rest]
    return _build(dec.env, polygons, exact)


def _fatness(tri: list[ExactPoint]) -> Fraction:
    """A triangle's area over its longest side squared (exact; larger is fatter)."""
    longest = max((tri[k][0] - tri[k - 1][0]) ** 2 + (tri[k][1] - tri[k - 1][1]) ** 2 for k in range(3))
    return abs(signed_area2(tri)) / longest

