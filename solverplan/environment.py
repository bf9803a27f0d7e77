"""Polygonal environments: rings, validation, orientation, boundary coordinates, file formats.

An :class:`Environment` is a polygon with holes, stored with **exact** rational coordinates
(decimals in files are read exactly) beside float arrays for fast numerics. It is always
valid and normalised: the outer ring is counter-clockwise, holes are clockwise, so the free
space lies on the **left** of every directed edge.

Edge numbering (docs/contract.md): the outer ring's edges are ``0 .. n0−1``, edge ``i`` going from
vertex ``i`` to the next vertex of its ring; each hole's edges continue the numbering in file
order. Vertex ``i`` is the first vertex of edge ``i``. A boundary point is ``(edge, t)`` with the
boundary parameter t ∈ [0, 1] along the directed edge; its perimeter position ("arc length") is
measured along the rings in numbering order.

>>> env = Environment.from_coords([[0, 0], [0, 1], [1, 1], [1, 0]], name="square")
>>> env.reoriented            # the outer ring was clockwise: its vertex order was reversed
(True,)
>>> env.ring(0)[:2]
((Fraction(0, 1), Fraction(0, 1)), (Fraction(1, 1), Fraction(0, 1)))
>>> env.area, env.perimeter
(Fraction(1, 1), 4.0)
>>> env.point_at(1, 0.25)
(1.0, 0.25)
>>> env.arc_length(1, 0.25)
1.25
>>> env.boundary_set("e1:0.25:0.75,e3")
BoundarySet(pieces=(BoundaryPiece(edge=1, t0=Fraction(1, 4), t1=Fraction(3, 4)), BoundaryPiece(edge=3, t0=Fraction(0, 1), t1=Fraction(1, 1))))
"""

from __future__ import annotations

import json
import operator
import os
import re
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from functools import cached_property
from os import PathLike
from pathlib import Path
from typing import Any, Iterable, Literal, Sequence

import numpy as np

from solverplan._io import atomic_write_text, check_json_values, file_format, read_input_text, shown_path
from solverplan._shipped import model_file, model_names
from solverplan.errors import InputError, InvalidBoundarySet, InvalidEnvironment, MalformedFile
from solverplan.limits import (
    COORDINATE_RESOLUTION,
    MAX_COORDINATE,
    MAX_FILE_BYTES,
    MAX_HOLES,
    MAX_JSON_DEPTH,
    MAX_NUMBER_CHARS,
    MAX_VERTICES,
    quote,
)
from solverplan.exact import (
    ExactPoint,
    format_number,
    format_point,
    json_point,
    orient,
    FLOAT_FILTER_REL,
    orient_filter,
    point_in_ring,
    segment_intersection,
    signed_area2,
    to_fraction,
)

__all__ = [
    "check_edges",
    "Environment",
    "Edge",
    "BoundaryPiece",
    "BoundarySet",
    "FileFormat",
    "load_environment",
    "parse_environment",
    "save_environment",
    "format_environment",
]

FileFormat = Literal["json", "geojson", "wkt"]
_EXTENSIONS: dict[str, FileFormat] = {".json": "json", ".geojson": "geojson", ".wkt": "wkt"}


def _ring_name(index: int) -> str:
    return "outer ring" if index == 0 else f"hole {index - 1}"


@dataclass(frozen=True, slots=True)
class Edge:
    """A directed boundary edge ``a → b`` (free space on its left), with its global ``id`` and ``ring``."""

    id: int
    ring: int
    a: ExactPoint
    b: ExactPoint


@dataclass(frozen=True, slots=True)
class BoundaryPiece:
    """The part of edge ``edge`` with boundary parameter t ∈ [t0, t1] (0 ≤ t0 < t1 ≤ 1).

    t runs along the directed edge, from its start vertex (t = 0) to its end vertex (t = 1), proportionally to
    arc length. ``str()`` gives the piece's text form, as in boundary-set strings.

    Attributes
    ----------
    edge
        The edge's id (``e3`` is 3): edges are numbered along the outer ring, then along each hole.
    t0, t1
        The piece's ends, exact boundary parameters in [0, 1].

    Examples
    --------
    >>> import solverplan as sp
    >>> piece = sp.load_environment("l_shape").boundary_set("e3:0.25:0.75").pieces[0]
    >>> piece
    BoundaryPiece(edge=3, t0=Fraction(1, 4), t1=Fraction(3, 4))
    >>> str(piece), str(sp.BoundaryPiece(4, 0, 1))
    ('e3:0.25:0.75', 'e4')
    """

    edge: int
    t0: Fraction
    t1: Fraction

    def __str__(self) -> str:
        if self.t0 == 0 and self.t1 == 1:
            return f"e{self.edge}"
        return f"e{self.edge}:{format_number(self.t0)}:{format_number(self.t1)}"


@dataclass(frozen=True, slots=True)
class BoundarySet:
    """A union of boundary pieces (start sets, goal sets, patrol edges); see docs/contract.md.

    Made from a string by :meth:`Environment.boundary_set`, which checks the edges exist; every planner also
    accepts the string itself. ``str()`` gives the string back.

    Attributes
    ----------
    pieces
        The :class:`BoundaryPiece` objects, in the order given (:meth:`merged` sorts and joins them).
    edges
        The distinct edges touched, in the order given.

    Examples
    --------
    >>> import solverplan as sp
    >>> start = sp.load_environment("l_shape").boundary_set("e3:0.25:0.75,e4")   # part of edge 3, all of edge 4
    >>> start.edges, str(start)
    ((3, 4), 'e3:0.25:0.75,e4')
    >>> start.by_edge()[3]
    [(Fraction(1, 4), Fraction(3, 4))]
    """

    pieces: tuple[BoundaryPiece, ...]

    def __str__(self) -> str:
        return ",".join(str(piece) for piece in self.pieces)

    @property
    def edges(self) -> tuple[int, ...]:
        """The distinct edges touched, in the order given."""
        return tuple(dict.fromkeys(piece.edge for piece in self.pieces))

    def merged(self) -> BoundarySet:
        """The same set of points, exact: overlapping or touching pieces of one edge joined, sorted by (edge, t).

        >>> BoundarySet((BoundaryPiece(2, Fraction(1, 2), Fraction(1)), BoundaryPiece(2, Fraction(0), Fraction(1, 2)),
        ...              BoundaryPiece(0, Fraction(0), Fraction(1, 4)))).merged()  # doctest: +NORMALIZE_WHITESPACE
        BoundarySet(pieces=(BoundaryPiece(edge=0, t0=Fraction(0, 1), t1=Fraction(1, 4)),
                            BoundaryPiece(edge=2, t0=Fraction(0, 1), t1=Fraction(1, 1))))
        """
        runs: list[list] = []  # [edge, t0, t1]
        for piece in sorted(self.pieces, key=lambda q: (q.edge, q.t0, q.t1)):
            if runs and runs[-1][0] == piece.edge and piece.t0 <= runs[-1][2]:
                runs[-1][2] = max(runs[-1][2], piece.t1)
            else:
                runs.append([piece.edge, Fraction(piece.t0), Fraction(piece.t1)])
        return BoundarySet(tuple(BoundaryPiece(e, a, b) for e, a, b in runs))

    def by_edge(self) -> dict[int, list[tuple[Fraction, Fraction]]]:
        """The :meth:`merged` pieces grouped per edge: ``{edge: [(t0, t1), ...]}`` in increasing t."""
        out: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for piece in self.merged().pieces:
            out.setdefault(piece.edge, []).append((piece.t0, piece.t1))
        return out


_PIECE = re.compile(r"^e(\d+)(?::([^:]+):([^:]+))?$")


@dataclass(frozen=True, eq=False)
class Environment:
    """A valid polygonal environment with holes, exact and normalised.

    Build one with :meth:`from_coords` or :func:`load_environment`; the constructor itself takes
    rings that are already exact and oriented (outer CCW, holes CW) and validates them.

    Parameters
    ----------
    rings
        ``rings[0]`` is the outer ring (CCW), ``rings[1:]`` the holes (CW); each a tuple of
        exact points, not closed (the first vertex is not repeated).
    name
        Free text, kept in files.
    reoriented
        For each ring, whether its input vertex order was reversed to normalise orientation.

    Raises
    ------
    InvalidEnvironment
        With one line saying what is wrong and where (ring, edge, point).

    Examples
    --------
    >>> import solverplan as sp
    >>> room = sp.Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], holes=[[[1, 1], [1, 2], [2, 2], [2, 1]]])
    >>> room, room.n_edges, room.area                  # lengths in the environment's units, areas exact
    (Environment(name='', vertices=8, holes=1, reflex=4), 8, Fraction(15, 1))
    >>> env = sp.load_environment("l_shape")
    >>> env.reflex_vertices, env.point_at(3, 0.25)     # edge 3 at t = 0.25
    ((3,), (4.0, 5.5))
    """

    rings: tuple[tuple[ExactPoint, ...], ...]
    name: str = ""
    reoriented: tuple[bool, ...] = field(default=())

    def __post_init__(self) -> None:
        if not self.rings:
            raise InvalidEnvironment("environment is empty: no outer ring")
        if not self.reoriented:
            object.__setattr__(self, "reoriented", (False,) * len(self.rings))
        for index, ring in enumerate(self.rings):
            _check_ring_shape(ring, index)
        for index, ring in enumerate(self.rings):
            want = 1 if index == 0 else -1
            area2 = signed_area2(ring)
            if (area2 > 0) - (area2 < 0) != want:
                raise InvalidEnvironment(
                    f"{_ring_name(index)} is {'clockwise' if area2 < 0 else 'counter-clockwise'}: "
                    "use Environment.from_coords to normalise orientation"
                )
        _check_float_span(self)
        _check_crossings(self)
        _check_nesting(self)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_coords(
        cls,
        outer: Iterable[Sequence[object]],
        holes: Iterable[Iterable[Sequence[object]]] | None = (),
        *,
        name: str = "",
    ) -> Environment:
        """Build an environment from coordinate lists in either orientation.

        Coordinates may be ints, floats (taken at their shortest decimal), decimals, fractions or
        numeric strings; a closing vertex equal to the first is dropped (GeoJSON/WKT style).
        Rings are reoriented (outer CCW, holes CW) and validated.

        >>> Environment.from_coords([[0, 0], [2, 2], [2, 0], [0, 2]])
        Traceback (most recent call last):
        ...
        solverplan.errors.InvalidEnvironment: outer ring self-intersects: edge 0 crosses edge 2 at (1, 1)
        """
        if holes is None:  # "no holes", as users write it
            holes = ()
        if isinstance(outer, (str, bytes)) or not isinstance(outer, Iterable) or not isinstance(holes, Iterable) \
                or isinstance(holes, (str, bytes)):
            raise InvalidEnvironment(f"an environment is a list of vertices (outer ring) and a list of rings "
                                     f"(holes), got {type(outer).__name__} and {type(holes).__name__}")
        raw_rings = [outer, *holes]
        if len(raw_rings) - 1 > MAX_HOLES:
            raise InvalidEnvironment(f"environment has {len(raw_rings) - 1} holes (at most {MAX_HOLES})")
        rings: list[tuple[ExactPoint, ...]] = []
        flipped: list[bool] = []
        for index, raw in enumerate(raw_rings):
            ring = _exact_ring(raw, index)
            _check_ring_shape(ring, index)
            area2 = signed_area2(ring)
            if area2 == 0:
                if all(orient(ring[0], ring[1], p) == 0 for p in ring[2:]):
                    raise InvalidEnvironment(f"{_ring_name(index)} has zero area (all its vertices are collinear)")
                _check_ring_simple(ring, index)  # a bowtie has zero signed area: name the crossing first
                raise InvalidEnvironment(f"{_ring_name(index)} has zero area (its vertices are collinear)")
            flip = (area2 > 0) != (index == 0)  # outer CCW, holes CW
            if flip:
                ring = (ring[0], *reversed(ring[1:]))
            rings.append(ring)
            flipped.append(flip)
        total = sum(map(len, rings))
        if total > MAX_VERTICES:
            raise InvalidEnvironment(f"environment has {total} vertices (at most {MAX_VERTICES})")
        return cls(tuple(rings), name=name, reoriented=tuple(flipped))

    @classmethod
    def from_shapely(cls, geometry: Any, *, name: str = "") -> Environment:
        """An environment from a shapely ``Polygon`` (or a ``MultiPolygon`` of one part), coordinates taken at their
        shortest decimal, rings in either orientation, validated like every environment.

        >>> import shapely
        >>> env = Environment.from_shapely(shapely.Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], [[(1, 1), (2, 1), (2, 2)]]))
        >>> env.area, len(env.holes)
        (Fraction(23, 2), 1)
        >>> Environment.from_shapely(env.to_shapely()) == env
        True
        """
        kind = getattr(geometry, "geom_type", None)
        if kind == "MultiPolygon":
            parts = list(geometry.geoms)
            if len(parts) != 1:
                raise InvalidEnvironment(f"a MultiPolygon of {len(parts)} parts is not one environment: pass one part "
                                         "(e.g. the largest: max(geometry.geoms, key=lambda p: p.area))")
            geometry, kind = parts[0], "Polygon"
        if kind != "Polygon":
            raise InvalidEnvironment(f"expected a shapely Polygon (or a MultiPolygon of one part), got {kind or type(geometry).__name__}")
        if geometry.is_empty:
            raise InvalidEnvironment("the shapely Polygon is empty")
        outer = [(float(x), float(y)) for x, y, *_ in geometry.exterior.coords]
        holes = [[(float(x), float(y)) for x, y, *_ in ring.coords] for ring in geometry.interiors]
        return cls.from_coords(outer, holes, name=name)

    # ------------------------------------------------------------------ structure
    def ring(self, index: int) -> tuple[ExactPoint, ...]:
        """Ring ``index`` (0 = outer), normalised."""
        return self.rings[index]

    @property
    def outer(self) -> tuple[ExactPoint, ...]:
        return self.rings[0]

    @property
    def holes(self) -> tuple[tuple[ExactPoint, ...], ...]:
        return self.rings[1:]

    @cached_property
    def ring_offsets(self) -> tuple[int, ...]:
        """Global index of each ring's first vertex/edge, plus the total at the end."""
        offsets = [0]
        for ring in self.rings:
            offsets.append(offsets[-1] + len(ring))
        return tuple(offsets)

    @property
    def n_edges(self) -> int:
        """Number of edges (= number of vertices) over all rings."""
        return self.ring_offsets[-1]

    @property
    def n_vertices(self) -> int:
        return self.ring_offsets[-1]

    @cached_property
    def exact_vertices(self) -> tuple[ExactPoint, ...]:
        """All vertices in global numbering, exact."""
        return tuple(p for ring in self.rings for p in ring)

    @cached_property
    def vertices(self) -> np.ndarray:
        """All vertices in global numbering, float array of shape (n, 2) (read-only)."""
        arr = np.array([[float(x), float(y)] for x, y in self.exact_vertices], dtype=float)
        arr.setflags(write=False)
        return arr

    @cached_property
    def ring_of(self) -> np.ndarray:
        """Ring index of each vertex / edge, int array of shape (n,)."""
        sizes = np.diff(np.array(self.ring_offsets))
        arr = np.repeat(np.arange(len(self.rings)), sizes)
        arr.setflags(write=False)
        return arr

    @cached_property
    def next_vertex(self) -> np.ndarray:
        """Global index of the next vertex along each vertex's ring (edge i ends there)."""
        idx = np.arange(self.n_vertices) + 1
        starts = np.array(self.ring_offsets[:-1])
        ends = np.array(self.ring_offsets[1:])
        idx[ends - 1] = starts
        idx.setflags(write=False)
        return idx

    @cached_property
    def prev_vertex(self) -> np.ndarray:
        """Global index of the previous vertex along each vertex's ring (edge prev[i] ends at i)."""
        idx = np.empty(self.n_vertices, dtype=int)
        idx[self.next_vertex] = np.arange(self.n_vertices)
        idx.setflags(write=False)
        return idx

    def edge(self, index: int) -> Edge:
        """Edge ``index`` as exact end points. Raises :class:`InvalidBoundarySet` if unknown."""
        self._check_edge_id(index)
        verts = self.exact_vertices
        return Edge(index, int(self.ring_of[index]), verts[index], verts[int(self.next_vertex[index])])

    @property
    def edges(self) -> tuple[Edge, ...]:
        return tuple(self.edge(i) for i in range(self.n_edges))

    @cached_property
    def edge_start(self) -> np.ndarray:
        """Float start points of all edges, shape (n, 2)."""
        return self.vertices

    @cached_property
    def edge_end(self) -> np.ndarray:
        """Float end points of all edges, shape (n, 2)."""
        arr = self.vertices[self.next_vertex]
        arr.setflags(write=False)
        return arr

    @cached_property
    def edge_lengths(self) -> np.ndarray:
        """Euclidean length of every edge (float), shape (n,)."""
        arr = np.hypot(*(self.edge_end - self.edge_start).T)
        arr.setflags(write=False)
        return arr

    @cached_property
    def edge_offsets(self) -> np.ndarray:
        """Perimeter position of each edge's start, plus the total perimeter at the end, shape (n+1,)."""
        arr = np.concatenate([[0.0], np.cumsum(self.edge_lengths)])
        arr.setflags(write=False)
        return arr

    @property
    def perimeter(self) -> float:
        """Total length of all rings."""
        return float(self.edge_offsets[-1])

    @cached_property
    def area(self) -> Fraction:
        """Exact area of the free space (outer minus holes)."""
        return sum((signed_area2(ring) for ring in self.rings), Fraction(0)) / 2

    @cached_property
    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the outer ring, floats."""
        lo = self.vertices.min(axis=0)
        hi = self.vertices.max(axis=0)
        return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    @cached_property
    def reflex_vertices(self) -> tuple[int, ...]:
        """Global indices of vertices whose free-space angle exceeds π.

        With the free space on the left of every edge this is a right turn prev → v → next,
        so the convex corners of holes are reflex. Collinear vertices (angle exactly π) are not.
        """
        verts = self.exact_vertices
        prev, nxt = self.prev_vertex, self.next_vertex
        # the certified float filter decides almost every vertex; exact orient only the near-collinear ones
        turn = orient_filter(self.vertices[prev], self.vertices, self.vertices[nxt])
        for i in np.flatnonzero(turn == 0).tolist():
            turn[i] = orient(verts[prev[i]], verts[i], verts[nxt[i]])
        return tuple(np.flatnonzero(turn < 0).tolist())

    def is_reflex(self, vertex: int) -> bool:
        """Is global vertex ``vertex`` reflex with respect to the free space?"""
        return vertex in self._reflex_set

    @cached_property
    def _reflex_set(self) -> frozenset[int]:
        return frozenset(self.reflex_vertices)

    # ------------------------------------------------------------------ boundary coordinates
    def _check_edge_id(self, index: int) -> None:
        if not (0 <= int(index) < self.n_edges) or int(index) != index:
            raise InvalidBoundarySet(f"unknown edge e{index}: edges are e0..e{self.n_edges - 1}")

    def point_at(self, edge: int, t: float) -> tuple[float, float]:
        """Float point of boundary coordinate (edge, t), t ∈ [0, 1]."""
        self._check_edge_id(edge)
        p = self.edge_start[edge] + float(t) * (self.edge_end[edge] - self.edge_start[edge])
        return (float(p[0]), float(p[1]))

    def exact_point_at(self, edge: int, t: Fraction | int) -> ExactPoint:
        """Exact point of boundary coordinate (edge, t)."""
        e = self.edge(edge)
        t = Fraction(t)
        return (e.a[0] + t * (e.b[0] - e.a[0]), e.a[1] + t * (e.b[1] - e.a[1]))

    def points_at(self, edges: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Vectorised :meth:`point_at`: arrays of edge ids and parameters → points, shape (m, 2)."""
        edges = np.asarray(edges, dtype=int)
        t = np.asarray(t, dtype=float)
        a, b = self.edge_start[edges], self.edge_end[edges]
        return a + t[..., None] * (b - a)

    def arc_length(self, edge: int | np.ndarray, t: float | np.ndarray) -> float | np.ndarray:
        """Perimeter position of (edge, t): rings in numbering order, each edge from its start."""
        edge_arr = np.asarray(edge, dtype=int)
        s = self.edge_offsets[edge_arr] + np.asarray(t, dtype=float) * self.edge_lengths[edge_arr]
        return float(s) if np.ndim(s) == 0 else s

    def from_arc_length(self, s: float | np.ndarray) -> tuple[np.ndarray | int, np.ndarray | float]:
        """Inverse of :meth:`arc_length`; s is taken modulo the perimeter."""
        s_arr = np.mod(np.asarray(s, dtype=float), self.perimeter)
        edge = np.clip(np.searchsorted(self.edge_offsets, s_arr, side="right") - 1, 0, self.n_edges - 1)
        t = (s_arr - self.edge_offsets[edge]) / self.edge_lengths[edge]
        t = np.clip(t, 0.0, 1.0)
        if np.ndim(s_arr) == 0:
            return int(edge), float(t)
        return edge, t

    def locate(self, point: Sequence[object]) -> tuple[int, Fraction]:
        """Exact boundary coordinate (edge, t) of a point lying exactly on the boundary.

        A vertex is reported on the edge it starts (t = 0). Raises :class:`InvalidBoundarySet`
        if the point is not on the boundary.
        """
        p = (to_fraction(point[0], where="point"), to_fraction(point[1], where="point"))
        verts = self.exact_vertices
        for i in range(self.n_edges):
            a, b = verts[i], verts[int(self.next_vertex[i])]
            if orient(a, b, p) == 0 and min(a, b) <= p <= max(a, b):
                dx, dy = b[0] - a[0], b[1] - a[1]
                t = (p[0] - a[0]) / dx if dx != 0 else (p[1] - a[1]) / dy
                if t == 1:
                    return int(self.next_vertex[i]), Fraction(0)
                return i, t
        raise InvalidBoundarySet(f"point {format_point(p)} is not on the boundary")

    def nearest_boundary_coordinate(self, xy: Sequence[float]) -> tuple[int, float]:
        """Float (edge, t) of the boundary point nearest to ``xy``."""
        p = np.asarray(xy, dtype=float)
        a, b = self.edge_start, self.edge_end
        d = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
        dist = np.hypot(*(a + t[:, None] * d - p).T)
        i = int(np.argmin(dist))
        return i, float(t[i])

    def boundary_set(self, spec: str) -> BoundarySet:
        """Parse a boundary set such as ``e3``, ``e3:0.25:0.75`` or ``e3:0.5:1,e4`` (docs/contract.md).

        >>> Environment.from_coords([[0, 0], [1, 0], [0, 1]]).boundary_set("e7")
        Traceback (most recent call last):
        ...
        solverplan.errors.InvalidBoundarySet: unknown edge e7: edges are e0..e2
        """
        if not isinstance(spec, str) or not spec.strip():
            raise InvalidBoundarySet(f"boundary set {quote(spec)} is empty: expected e.g. 'e3' or 'e3:0.25:0.75,e4'")
        pieces = []
        for part in spec.split(","):
            text = part.strip()
            match = _PIECE.match(text)
            if not match:
                raise InvalidBoundarySet(
                    f"boundary set piece {quote(text)} is malformed: expected 'eK' or 'eK:T0:T1' with 0 <= T0 < T1 <= 1"
                )
            digits = match.group(1)
            if len(digits) > 18:  # int() of thousands of digits is refused by Python itself: no edge has such an id
                raise InvalidBoundarySet(f"unknown edge e{digits[:20]}…: edges are e0..e{self.n_edges - 1}")
            edge = int(digits)
            self._check_edge_id(edge)
            if match.group(2) is None:
                t0, t1 = Fraction(0), Fraction(1)
            else:
                where = f"boundary set piece {quote(text)}"
                try:
                    t0 = to_fraction(match.group(2), where=where)
                    t1 = to_fraction(match.group(3), where=where)
                except InputError as exc:
                    raise InvalidBoundarySet(str(exc)) from None
                if not (0 <= t0 < t1 <= 1):
                    raise InvalidBoundarySet(
                        f"{where}: need 0 <= t0 < t1 <= 1, got t0={_brief(t0)}, t1={_brief(t1)}"
                    )
                if float(t0) == float(t1) or max(t0.denominator, t1.denominator) > COORDINATE_RESOLUTION:
                    raise InvalidBoundarySet(f"{where}: the piece is narrower than floats carry (t0={_brief(t0)}, t1={_brief(t1)})")
            pieces.append(BoundaryPiece(edge, t0, t1))
        return BoundarySet(tuple(pieces))

    # ------------------------------------------------------------------ conversion
    def to_shapely(self):
        """The free space as a :class:`shapely.Polygon` (floats; outer ring CCW, holes CW).

        :meth:`from_shapely` and :func:`load_environment` take it back (coordinates at their shortest decimal).
        """
        import shapely

        return shapely.Polygon(
            [tuple(map(float, p)) for p in self.outer], [[tuple(map(float, p)) for p in h] for h in self.holes]
        )

    def to_dict(self) -> dict:
        """JSON-ready dict as in docs/contract.md (numbers exact where they are terminating decimals)."""
        data: dict = {"name": self.name, "outer": [json_point(p) for p in self.outer]}
        if self.holes:
            data["holes"] = [[json_point(p) for p in hole] for hole in self.holes]
        return data

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Environment):
            return NotImplemented
        return self.rings == other.rings

    def __hash__(self) -> int:
        return self._hash

    @cached_property
    def _hash(self) -> int:
        # hashing every Fraction is O(n) and caches keyed on environments ask often
        return hash(self.rings)

    def __repr__(self) -> str:
        return (
            f"Environment(name={self.name!r}, vertices={self.n_vertices}, holes={len(self.holes)}, "
            f"reflex={len(self.reflex_vertices)})"
        )


# ---------------------------------------------------------------------- validation helpers
def _exact_ring(raw: Iterable[Sequence[object]], index: int) -> tuple[ExactPoint, ...]:
    name = _ring_name(index)
    if isinstance(raw, (str, bytes)):
        raise InvalidEnvironment(f"{name}: expected a list of [x, y] pairs, got a string")
    try:
        items = list(raw)
    except TypeError:
        raise InvalidEnvironment(f"{name}: expected a list of [x, y] pairs, got {raw!r}") from None
    if len(items) > MAX_VERTICES:
        raise InvalidEnvironment(f"{name} has {len(items)} vertices (at most {MAX_VERTICES})")
    ring = []
    for k, item in enumerate(items):
        where = f"{name} vertex {k}"
        if isinstance(item, (str, bytes, dict)) or not hasattr(item, "__len__") or len(item) != 2:
            raise InvalidEnvironment(f"{where}: expected a pair [x, y], got {quote(item)}")
        try:
            point = (to_fraction(item[0], where=where), to_fraction(item[1], where=where))
        except ValueError as exc:
            raise InvalidEnvironment(str(exc)) from None
        for c in point:
            _check_coordinate(c, where)
        ring.append(point)
    if len(ring) >= 2 and ring[0] == ring[-1]:
        ring.pop()  # closed ring (GeoJSON, WKT): the closing vertex is not a vertex of its own
    return tuple(ring)


def _check_coordinate(c: Fraction, where: str) -> None:
    """A coordinate within the documented magnitude and resolution (``solverplan.limits``)."""
    if abs(c.numerator) > MAX_COORDINATE * c.denominator:  # |c| > MAX_COORDINATE, in integers
        raise InvalidEnvironment(f"{where}: coordinate {_about(c)} is larger than 1e100 in magnitude: rescale the file")
    if c.denominator > COORDINATE_RESOLUTION:
        raise InvalidEnvironment(f"{where}: coordinate {_about(c)} is finer than 1e-100 (the finest step read): rescale the file")


def _brief(c: Fraction) -> str:
    """``c`` exactly when that is short, else :func:`_about` it."""
    text = format_number(c)
    return text if len(text) <= 30 else _about(c)


def _about(c: Fraction) -> str:
    """Three significant digits of ``c`` at any magnitude (a float would overflow past 1e308)."""
    return f"{Decimal(c.numerator) / Decimal(c.denominator):.3g}"


def _check_float_span(env: Environment) -> None:
    """Every edge must keep a positive length in floats, where the planner measures and replays.

    Coordinates far apart in magnitude (1 and 1 + 1e-30) are distinct exactly but equal as floats: an
    answer computed there could be wrong, so such an environment is refused rather than answered.
    """
    lengths = env.edge_lengths
    if np.all(lengths > 0):
        return
    edge = int(np.flatnonzero(~(lengths > 0))[0])
    ring = int(env.ring_of[edge])
    raise InvalidEnvironment(
        f"{_ring_name(ring)} edge {_input_edge(env, edge)} has length 0 in floats "
        f"(both ends round to {format_point(env.vertices[edge].tolist())}): rescale the file"
    )


def _check_ring_shape(ring: Sequence[ExactPoint], index: int) -> None:
    name = _ring_name(index)
    distinct: list[ExactPoint] = []  # the first three distinct vertices (enough to decide)
    for p in ring:
        if p not in distinct:
            distinct.append(p)
            if len(distinct) == 3:
                break
    if len(distinct) < 3:
        raise InvalidEnvironment(f"{name} has fewer than 3 distinct vertices ({len(distinct)})")
    n = len(ring)
    if any(map(operator.eq, ring, (*ring[1:], ring[0]))):
        for i in range(n):
            j = (i + 1) % n
            if ring[i] == ring[j]:
                raise InvalidEnvironment(f"{name} repeats vertex {i} at {format_point(ring[i])} as vertex {j}")


def _check_ring_simple(ring: Sequence[ExactPoint], index: int) -> None:
    """Self-intersection of one ring, reported with edge ids local to that ring."""
    starts = np.array([[float(x), float(y)] for x, y in ring])
    pairs = _candidate_pairs(starts, np.roll(np.arange(len(ring)), -1), ring)
    for i, j in pairs:
        problem = _edge_pair_problem(ring, len(ring), i, j)
        if problem:
            raise InvalidEnvironment(f"{_ring_name(index)} self-intersects: {problem}")


def _edge_pair_problem(ring: Sequence[ExactPoint], n: int, i: int, j: int) -> str | None:
    """Describe how edges i < j of one ring meet illegally, or None."""
    a, b = ring[i], ring[(i + 1) % n]
    c, d = ring[j], ring[(j + 1) % n]
    hit = segment_intersection(a, b, c, d)
    if hit is None:
        return None
    adjacent = (j == i + 1) or (i == 0 and j == n - 1)
    if adjacent and hit.kind == "point":
        return None  # the shared vertex
    if hit.kind == "overlap":
        return f"edge {i} overlaps edge {j} from {format_point(hit.points[0])} to {format_point(hit.points[1])}"
    point = hit.points[0]
    proper = point not in (a, b, c, d)
    return f"edge {i} {'crosses' if proper else 'touches'} edge {j} at {format_point(point)}"


def _candidate_pairs(
    starts: np.ndarray, next_index: np.ndarray, exact: Sequence[ExactPoint]
) -> list[tuple[int, int]]:
    """Pairs i < j of edges to test exactly: if any two edges meet illegally, one listed pair does.

    Edge ``i`` runs from vertex ``i`` to vertex ``next_index[i]``; ``starts`` holds the float
    vertices (roundings of ``exact``). A pair "meets illegally" unless the two edges are
    neighbours meeting only at their shared vertex; the caller decides each listed pair with
    exact :func:`segment_intersection`. A few vertices are compared pair by pair; otherwise a
    Shamos–Hoey sweep (:func:`_sweep_pairs`) lists O(n) pairs in O(n log n) time. Pairs the
    certified float filter proves apart are dropped, in either case.
    """
    n = len(starts)
    ends = starts[next_index]
    if n <= 64:
        ii, jj = np.triu_indices(n, k=1)
        extra = np.empty((0, 2), dtype=np.intp)
    else:
        pairs, extra = _sweep_pairs(starts, next_index, exact)
        pairs = np.sort(pairs, axis=1)
        pairs = pairs[pairs[:, 0] != pairs[:, 1]]
        # neighbours are decided by the vertex test in _sweep_pairs (their candidates are in `extra`)
        neighbours = (next_index[pairs[:, 0]] == pairs[:, 1]) | (next_index[pairs[:, 1]] == pairs[:, 0])
        pairs = pairs[~neighbours]
        ii, jj = pairs[:, 0], pairs[:, 1]
    a, b, c, d = starts[ii], ends[ii], starts[jj], ends[jj]
    o1, o2 = orient_filter(a, b, c), orient_filter(a, b, d)
    o3, o4 = orient_filter(c, d, a), orient_filter(c, d, b)
    apart = (o1 * o2 > 0) | (o3 * o4 > 0)
    kept = np.concatenate([np.stack([ii[~apart], jj[~apart]], axis=1), np.sort(extra, axis=1)])
    return sorted(set(map(tuple, kept.tolist())))


def _lexicographic_order(starts: np.ndarray, exact: Sequence[ExactPoint]) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Vertices sorted by their exact points (x, then y), and the pairs of vertices at the same point.

    Rounding to float is monotone, so the float order is the exact order except among points whose
    x rounds to the same float; only there are exact coordinates compared (a run of such points is
    re-sorted exactly when its exact x differ, or two of its y round alike).
    """
    order = np.lexsort((starts[:, 1], starts[:, 0]))
    sx, sy = starts[order, 0], starts[order, 1]
    tied = np.flatnonzero(sx[1:] == sx[:-1])
    if not len(tied):
        return order, []
    ordered = order.tolist()
    # positions k where order[k], order[k + 1] round to one float x but the float order may be wrong
    rough = [k for k in tied.tolist()
             if exact[ordered[k]][0] != exact[ordered[k + 1]][0]
             or (sy[k] == sy[k + 1] and exact[ordered[k]] != exact[ordered[k + 1]])]
    if rough:  # sort each run of equal float x holding such a position exactly
        bounds = np.concatenate([[0], np.flatnonzero(sx[1:] != sx[:-1]) + 1, [len(sx)]])
        for run in sorted(set(np.searchsorted(bounds, rough, side="right").tolist())):
            lo, hi = int(bounds[run - 1]), int(bounds[run])
            ordered[lo:hi] = sorted(ordered[lo:hi], key=exact.__getitem__)
        order = np.array(ordered, dtype=np.intp)
        sx, sy = starts[order, 0], starts[order, 1]
    # equal exact points are adjacent in the exact order, and round to one float point
    alike = np.flatnonzero((sx[1:] == sx[:-1]) & (sy[1:] == sy[:-1])).tolist()
    same = [(ordered[k], ordered[k + 1]) for k in alike if exact[ordered[k]] == exact[ordered[k + 1]]]
    return order, same


def _sweep_pairs(
    starts: np.ndarray, next_index: np.ndarray, exact: Sequence[ExactPoint]
) -> tuple[np.ndarray, np.ndarray]:
    """Candidate pairs of a Shamos–Hoey sweep over the edges, and pairs of neighbours to test exactly.

    Returns ``(pairs, neighbours)``, two int arrays of shape (m, 2). Three exact facts together
    cover every way two edges can meet illegally:

    1. Two vertices at the same point: their edges touch there. All pairs of their edges are listed
       and the sweep is skipped.
    2. Neighbours u → v → w meet beyond v only if they fold back along one line: the pair is listed
       in ``neighbours`` unless the float filter proves u, v, w not collinear.
    3. Any other meeting is found by the sweep. A vertical line moves over the vertices in exact
       lexicographic order (x, then y: a vertical edge counts as slightly tilted), keeping the
       edges it crosses sorted from bottom to top. Every time two edges become adjacent in that
       order (an edge enters next to others, or leaves from between two) the pair is listed.
       Let q be the first point (in sweep order) where two edges meet illegally. Just before the
       line reaches q the order is a true order (no meeting to its left), and the edges through q
       lie in one block of it: edges between two of them are squeezed through q too. Some edge t
       has q inside (after point 1, two edges meeting at a common end point are one vertex's
       neighbours, a legal meeting). If t's block holds another edge, t and its block neighbour
       meet illegally at q, and became adjacent at an event before q: listed. Otherwise t is alone
       in its block, and the illegal meeting is an edge starting at q; locating q in the order
       ends at the lowest edge through q, t, finds q exactly on it, and lists the pair.

    Comparisons are exact: the float orientation with the certified bound of :func:`orient_filter`
    decides when it can, exact :func:`orient` otherwise. Time O(n log n) comparisons; memory O(n).
    """
    n = len(starts)
    prev = np.empty(n, dtype=np.intp)
    prev[next_index] = np.arange(n)
    # 2. neighbours at each vertex v: edge prev[v] (u → v) and edge v (v → w)
    turn = orient_filter(starts[prev], starts, starts[next_index])
    neighbours = np.flatnonzero(turn == 0)
    neighbour_pairs = np.stack([prev[neighbours], neighbours], axis=1)

    order, same = _lexicographic_order(starts, exact)
    if same:  # 1. coincident vertices
        touching = []
        for u, v in same:
            incident_u, incident_v = (int(prev[u]), u), (int(prev[v]), v)
            touching += [(e, f) for e in incident_u for f in incident_v]
        return np.array(touching, dtype=np.intp), neighbour_pairs

    rank = np.empty(n, dtype=np.intp)
    rank[order] = np.arange(n)
    forward = rank < rank[next_index]  # edge i runs left to right in sweep order
    left = np.where(forward, np.arange(n), next_index)
    right = np.where(forward, next_index, np.arange(n))
    lo_pt, hi_pt = starts[left], starts[right]
    # per edge, as Python floats: the left end, the direction, and the magnitudes of orient_filter's bound
    LX, LY = lo_pt[:, 0].tolist(), lo_pt[:, 1].tolist()
    DX, DY = (hi_pt[:, 0] - lo_pt[:, 0]).tolist(), (hi_pt[:, 1] - lo_pt[:, 1]).tolist()
    MX = (np.abs(lo_pt[:, 0]) + np.abs(hi_pt[:, 0])).tolist()
    MY = (np.abs(lo_pt[:, 1]) + np.abs(hi_pt[:, 1])).tolist()
    X, Y = starts[:, 0].tolist(), starts[:, 1].tolist()
    R, L = right.tolist(), left.tolist()
    P = prev.tolist()
    rel = FLOAT_FILTER_REL

    status: list[int] = []  # edges crossing the sweep line, bottom to top
    found: list[tuple[int, int]] = []
    for v in order.tolist():
        px, py = X[v], Y[v]
        apx, apy = abs(px), abs(py)
        e_in, e_out = P[v], v  # the two edges at v
        # locate v: i = number of edges strictly below v
        lo, hi = 0, len(status)
        while lo < hi:
            mid = (lo + hi) >> 1
            t = status[mid]
            if R[t] == v:  # t ends at v: v is on t, not above it
                hi = mid
                continue
            det = DX[t] * (py - LY[t]) - DY[t] * (px - LX[t])
            bound = rel * (MX[t] + apx) * (MY[t] + apy)
            if det > bound:
                lo = mid + 1
            elif det < -bound:
                hi = mid
            else:
                side = orient(exact[L[t]], exact[R[t]], exact[v])
                if side > 0:
                    lo = mid + 1
                elif side < 0:
                    hi = mid
                else:  # v lies inside edge t (t began before v and ends after it): a touch
                    found += [(t, e_in), (t, e_out)]
                    return np.array(found, dtype=np.intp), neighbour_pairs
        i = lo
        ending = [e for e in (e_in, e_out) if R[e] == v]
        for e in ending:
            if i < len(status) and status[i] == e:
                del status[i]
            elif i + 1 < len(status) and status[i + 1] == e:
                del status[i + 1]
            else:  # the order is no longer a true order: a meeting to the left is listed already
                j = status.index(e)
                del status[j]
                i -= j < i
        starting = [e for e in (e_in, e_out) if L[e] == v]
        if len(starting) == 2:
            a, b = starting
            # both leave v to the right: b lies above a when a's far end → b's far end turns left
            det = DX[a] * DY[b] - DY[a] * DX[b]
            bound = rel * (MX[a] + MX[b]) * (MY[a] + MY[b])
            side = 1 if det > bound else -1 if det < -bound else orient(exact[v], exact[R[a]], exact[R[b]])
            if side < 0:
                starting = [b, a]
        if starting:
            status[i:i] = starting
            if i > 0:
                found.append((status[i - 1], starting[0]))
            top = i + len(starting)
            if top < len(status):
                found.append((starting[-1], status[top]))
        elif 0 < i < len(status):
            found.append((status[i - 1], status[i]))
    return np.array(found, dtype=np.intp).reshape(-1, 2), neighbour_pairs


def _input_edge(env: Environment, edge: int) -> int:
    """Ring-local edge id of global ``edge`` in the ring's *input* vertex order (for messages)."""
    ring = int(env.ring_of[edge])
    local = edge - env.ring_offsets[ring]
    if env.reoriented[ring]:
        n = len(env.rings[ring])
        local = (n - local - 1) % n  # reversing (v0, v1, ..., vn-1) to (v0, vn-1, ..., v1)
    return local


def _check_crossings(env: Environment) -> None:
    """Edges of different rings must not meet; edges of one ring only at their shared vertex.

    Messages name edges as numbered in the input ring, so users can find them in their file.
    """
    verts = env.exact_vertices
    nxt = env.next_vertex
    ring_of = env.ring_of
    for i, j in _candidate_pairs(env.vertices, nxt, verts):
        ri, rj = int(ring_of[i]), int(ring_of[j])
        hit = segment_intersection(verts[i], verts[nxt[i]], verts[j], verts[nxt[j]])
        if hit is None:
            continue
        if ri == rj:
            if hit.kind == "point" and (nxt[i] == j or nxt[j] == i):
                continue  # neighbours meeting at their shared vertex
            li, lj = sorted((_input_edge(env, i), _input_edge(env, j)))
            ring = verts[env.ring_offsets[ri] : env.ring_offsets[ri + 1]]
            if env.reoriented[ri]:
                ring = (ring[0], *reversed(ring[1:]))
            problem = _edge_pair_problem(ring, len(ring), li, lj)
            raise InvalidEnvironment(f"{_ring_name(ri)} self-intersects: {problem}")
        where = format_point(hit.points[0])
        li, lj = _input_edge(env, i), _input_edge(env, j)
        if ri == 0:
            raise InvalidEnvironment(f"hole {rj - 1} touches the outer ring at {where} (hole edge {lj}, outer edge {li})")
        raise InvalidEnvironment(f"hole {ri - 1} touches hole {rj - 1} at {where} (edge {li} of hole {ri - 1}, edge {lj} of hole {rj - 1})")


def _check_nesting(env: Environment) -> None:
    """With no crossings left, each hole lies wholly inside the outer ring and outside every other hole.

    One vertex per hole decides. Floats answer where the vertex is clearly away from the other ring
    (shapely, vectorised); exact :func:`point_in_ring` decides the rest.
    """
    if not env.holes:
        return
    import shapely

    firsts = np.array([[float(h[0][0]), float(h[0][1])] for h in env.holes])
    scale = max(1.0, float(np.abs(env.vertices).max()))
    margin = 1e-9 * scale

    def float_rings(index: int):
        coords = env.vertices[env.ring_offsets[index] : env.ring_offsets[index + 1]]
        return shapely.Polygon(coords), shapely.LinearRing(coords)

    def location(point_index: int, ring_index: int, polygon, ring) -> int:
        x, y = firsts[point_index]
        if shapely.distance(ring, shapely.Point(x, y)) > margin:
            return 1 if shapely.contains_xy(polygon, x, y) else -1
        return point_in_ring(env.holes[point_index][0], env.rings[ring_index])

    outer_polygon, outer_ring = float_rings(0)
    for k in range(len(env.holes)):
        if location(k, 0, outer_polygon, outer_ring) < 0:
            raise InvalidEnvironment(f"hole {k} lies outside the outer ring")
    if len(env.holes) < 2:
        return
    # candidates by bounding box (rounding is monotone, so exact containment implies float box overlap)
    hole_rings = [float_rings(m + 1) for m in range(len(env.holes))]
    tree = shapely.STRtree([polygon for polygon, _ in hole_rings])
    points, holes = tree.query(shapely.points(firsts))
    for k, m in zip(points.tolist(), holes.tolist()):
        if k != m and location(k, m + 1, *hole_rings[m]) > 0:
            raise InvalidEnvironment(f"hole {k} lies inside hole {m}")


# ---------------------------------------------------------------------- file formats
def _reject_constant(name: str) -> None:
    raise MalformedFile(f"non-finite number {name} in file")


def _parse_int(text: str) -> int:
    # int() refuses more than 4,300 digits with a ValueError naming sys.set_int_max_str_digits: say it our way
    if len(text) > MAX_NUMBER_CHARS:
        raise MalformedFile(f"integer of {len(text)} digits in file (at most {MAX_NUMBER_CHARS})")
    return int(text)


def _parse_decimal(text: str) -> Decimal:
    if len(text) > MAX_NUMBER_CHARS:
        raise MalformedFile(f"number of {len(text)} characters in file (at most {MAX_NUMBER_CHARS})")
    return Decimal(text)


_JSON_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"')


def json_depth(text: str) -> int:
    """How deep arrays and objects nest in JSON ``text`` (strings skipped), without parsing it.

    Vectorised over the bytes a megabyte at a time, so it is fast on large files, cannot exhaust the stack
    and needs a few megabytes whatever the file's size.
    """
    data = _JSON_STRING.sub(b'""', text.encode("utf-8", "surrogatepass"))
    deepest, level = 0, 0
    for start in range(0, len(data), _DEPTH_CHUNK):
        chunk = np.frombuffer(data, dtype=np.uint8, count=min(_DEPTH_CHUNK, len(data) - start), offset=start)
        step = (chunk == ord("[")).astype(np.int32)
        step += chunk == ord("{")
        step -= chunk == ord("]")
        step -= chunk == ord("}")
        levels = np.cumsum(step, dtype=np.int64)
        if len(levels):
            deepest = max(deepest, level + int(levels.max()))
            level += int(levels[-1])
    return deepest


_DEPTH_CHUNK = 1 << 20


def read_json(text: str, *, exact: bool = True, source: str = "") -> object:
    """Parse JSON input text within the documented limits: numbers, values and nesting bounded.

    Decimals are read as exact :class:`~decimal.Decimal` values, or as floats with ``exact=False``.

    Raises
    ------
    MalformedFile
        For nesting deeper than :data:`~solverplan.limits.MAX_JSON_DEPTH`, more values than
        :data:`~solverplan.limits.MAX_JSON_VALUES` (checked before parsing, so that parsing costs memory in
        proportion to the file), a number longer than :data:`~solverplan.limits.MAX_NUMBER_CHARS`, or
        NaN/Infinity; ``json.JSONDecodeError`` for bad syntax.
    """
    check_json_values(text, source)
    depth = json_depth(text)
    if depth > MAX_JSON_DEPTH:
        raise MalformedFile(f"JSON nested {depth} levels deep (at most {MAX_JSON_DEPTH})")
    parse_float = _parse_decimal if exact else lambda number: float(_parse_decimal(number))
    return json.loads(text, parse_float=parse_float, parse_int=_parse_int, parse_constant=_reject_constant)


def parse_environment(
    text: str, fmt: FileFormat, *, name: str = "", default_name: str = "", source: str = "input"
) -> Environment:
    """Parse environment text in ``fmt`` (``json``, ``geojson`` or ``wkt``); decimals read exactly.

    Raises :class:`MalformedFile` for unreadable text and :class:`InvalidEnvironment` for an
    invalid polygon, each with ``source`` (a file name) in the message.
    """
    try:
        if fmt == "wkt":
            rings, file_name = _parse_wkt(text), ""
        elif fmt in ("json", "geojson"):
            try:
                data = read_json(text)
            except json.JSONDecodeError as exc:
                raise MalformedFile(f"{source}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
            rings, file_name = (_parse_geojson(data) if fmt == "geojson" or _looks_geojson(data) else _parse_json(data))
        else:
            raise MalformedFile(f"{source}: unknown format {fmt!r}: use json, geojson or wkt")
        return Environment.from_coords(rings[0], rings[1:], name=name or file_name or default_name)
    except (MalformedFile, InvalidEnvironment) as exc:
        message = str(exc)
        if not message.startswith(f"{source}:"):
            message = f"{source}: {message}"
        raise type(exc)(message) from None


def _looks_geojson(data: object) -> bool:
    return isinstance(data, dict) and "type" in data and "outer" not in data


def _parse_json(data: object) -> tuple[list, str]:
    if not isinstance(data, dict):
        raise MalformedFile('expected a JSON object {"outer": [[x, y], ...], "holes": [...]}')
    if "outer" not in data:
        raise MalformedFile('missing "outer": expected {"outer": [[x, y], ...], "holes": [...]}')
    outer = data["outer"]
    holes = data.get("holes", [])
    if not isinstance(outer, list) or not isinstance(holes, list):
        raise MalformedFile('"outer" must be a list of [x, y] pairs and "holes" a list of such lists')
    name = data.get("name", "")
    return [outer, *holes], name if isinstance(name, str) else str(name)


def _parse_geojson(data: object) -> tuple[list, str]:
    name = ""
    if isinstance(data, dict) and data.get("type") == "FeatureCollection":
        features = data.get("features")
        if not isinstance(features, list) or len(features) != 1:
            count = len(features) if isinstance(features, list) else 0
            raise MalformedFile(f"GeoJSON FeatureCollection must hold exactly one feature, found {count}")
        data = features[0]
    if isinstance(data, dict) and data.get("type") == "Feature":
        props = data.get("properties") or {}
        name = str(props.get("name", "")) if isinstance(props, dict) else ""
        data = data.get("geometry")
    if not isinstance(data, dict) or data.get("type") != "Polygon":
        kind = data.get("type") if isinstance(data, dict) else type(data).__name__
        raise MalformedFile(f"GeoJSON geometry must be a Polygon, got {kind}")
    coords = data.get("coordinates")
    if not isinstance(coords, list) or not coords:
        raise MalformedFile("GeoJSON Polygon has no coordinates (empty polygon)")
    return coords, name


_WKT_HEAD = re.compile(r"^\s*POLYGON\s*", re.IGNORECASE)


def _parse_wkt(text: str) -> list[list[list[str]]]:
    match = _WKT_HEAD.match(text)
    if not match:
        head = text.strip().split("(")[0].strip()[:30] or "empty text"
        raise MalformedFile(f"WKT must be a POLYGON, got {head!r}")
    body = text[match.end() :].strip()
    if body.upper() == "EMPTY":
        raise MalformedFile("WKT polygon is EMPTY")
    if not (body.startswith("(") and body.endswith(")")):
        raise MalformedFile("WKT polygon must be POLYGON ((x y, ...), (...)); unbalanced parentheses")
    inner = body[1:-1].strip()
    rings: list[list[list[str]]] = []
    for ring_match in re.finditer(r"\(([^()]*)\)|([^\s,])", inner):
        if ring_match.group(2) is not None:
            raise MalformedFile(f"WKT: unexpected {ring_match.group(2)!r} between rings")
        points = []
        for k, chunk in enumerate(ring_match.group(1).split(",")):
            parts = chunk.split()
            if len(parts) != 2:
                raise MalformedFile(f"WKT ring {len(rings)} point {k}: expected 'x y', got {quote(chunk.strip())}")
            points.append(parts)
        rings.append(points)
    if not rings:
        raise MalformedFile("WKT polygon has no rings")
    return rings


def format_environment(env: Environment, fmt: FileFormat = "json") -> str:
    """Text of ``env`` in ``fmt``. JSON keeps exact decimals (ratios as ``"p/q"`` strings);
    GeoJSON and WKT close their rings; WKT writes non-terminating ratios to 17 digits."""
    if fmt == "json":
        # one vertex per line: readable, diffable, and still plain JSON
        def ring_text(ring: Sequence[ExactPoint], indent: str) -> str:
            rows = ",\n".join(f"{indent}  {json.dumps(json_point(p))}" for p in ring)
            return f"[\n{rows}\n{indent}]"

        parts = [f'  "name": {json.dumps(env.name)}', f'  "outer": {ring_text(env.outer, "  ")}']
        if env.holes:
            holes = ",\n".join(f"    {ring_text(h, '    ')}" for h in env.holes)
            parts.append(f'  "holes": [\n{holes}\n  ]')
        return "{\n" + ",\n".join(parts) + "\n}\n"
    if fmt == "geojson":
        rings = [[json_point(p) for p in (*ring, ring[0])] for ring in env.rings]
        feature = {
            "type": "Feature",
            "properties": {"name": env.name},
            "geometry": {"type": "Polygon", "coordinates": rings},
        }
        return json.dumps(feature) + "\n"
    if fmt == "wkt":
        def num(x: Fraction) -> str:
            text = format_number(x)
            return repr(float(x)) if "/" in text else text

        ring_texts = ", ".join(
            "(" + ", ".join(f"{num(x)} {num(y)}" for x, y in (*ring, ring[0])) + ")" for ring in env.rings
        )
        return f"POLYGON ({ring_texts})\n"
    raise MalformedFile(f"unknown format {fmt!r}: use json, geojson or wkt")


def _format_of(path: Path, fmt: str | None) -> FileFormat:
    return file_format(path, fmt, _EXTENSIONS)  # type: ignore[return-value]


def _no_such_file(path: str) -> str:
    """The one-line error for a path that is neither a file nor a shipped model: for a bare name, the shipped models
    it resembles (the whole list would pass the 200-character cap of an error line)."""
    if "/" in path or "\\" in path:
        return f"{shown_path(path)}: no such file, nor a shipped model"
    import difflib

    names = model_names()
    close = difflib.get_close_matches(path, names, n=3, cutoff=0.6)
    hint = f"did you mean {' or '.join(close)}?" if close else f"{len(names)} models, e.g. {', '.join(names[:4])}, …"
    return f"{shown_path(path)}: no such file, nor a shipped model ({hint})"


def load_environment(path: Any, fmt: FileFormat | None = None) -> Environment:
    """Read an environment file, or a shipped model by name, or take a shapely polygon.

    Parameters
    ----------
    path
        An environment file (``.json``, ``.geojson`` or ``.wkt``), or the name of a shipped model
        (``"two_rooms"`` or ``"two_rooms.json"``; see :func:`solverplan.models.names`). An existing
        file wins over a model of the same name. A shapely ``Polygon`` (or ``MultiPolygon`` of one part)
        is made an environment directly (:meth:`Environment.from_shapely`).
    fmt
        The file's format, when its extension does not say (``"json"``, ``"geojson"`` or ``"wkt"``).
        Shipped models are JSON whatever ``fmt`` says.

    Returns
    -------
    Environment
        Named by the file when it gives a name, else by the file's stem.

    Raises
    ------
    MalformedFile
        If the path is neither a file nor a shipped model's name, cannot be read, or is not a valid
        environment file.

    Examples
    --------
    >>> load_environment("l_shape").name
    'l_shape'
    >>> load_environment("no/such/file.json")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: no/such/file.json: no such file, nor a shipped model
    """
    if hasattr(path, "geom_type"):  # a shapely geometry
        return Environment.from_shapely(path)
    if fmt:
        _format_of(Path(path), fmt)  # an unknown format is an error even for a shipped model
    file = Path(path)
    try:
        present = os.path.lexists(file)
    except (OSError, ValueError):  # a NUL byte in the name: the reader says so
        present = True
    if not present:
        shipped = model_file(str(path))
        if shipped is None:
            raise MalformedFile(_no_such_file(str(path)))
        file, fmt = shipped, "json"
    kind = _format_of(file, fmt)
    text = read_input_text(file, limit=MAX_FILE_BYTES)  # regular files only, never read past the limit
    return parse_environment(text, kind, default_name=file.stem, source=shown_path(file))


def save_environment(env: Environment, path: str | PathLike[str], fmt: FileFormat | None = None) -> None:
    """Write ``env`` atomically, format from the extension unless ``fmt`` is given."""
    path = Path(path)
    atomic_write_text(path, format_environment(env, _format_of(path, fmt)))


def check_edges(env: Environment, edges: object, *, name: str = "edge") -> np.ndarray:
    """Edge ids as an int array, or a one-line :class:`InvalidBoundarySet` naming the first unknown one.

    >>> check_edges(Environment.from_coords([[0, 0], [1, 0], [0, 1]]), [0, 7])
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidBoundarySet: unknown edge e7: edges are e0..e2
    """
    try:
        arr = np.asarray(edges, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{name} ids must be integers, got {edges!r}") from None
    n = env.n_edges
    bad = np.flatnonzero(~((arr >= 0) & (arr < n) & (arr == np.floor(arr))))
    if len(bad):
        value = arr[bad[0]]
        shown = f"{int(value)}" if np.isfinite(value) and value == np.floor(value) else f"{value:g}"
        raise InvalidBoundarySet(f"unknown edge e{shown}: edges are e0..e{n - 1}")
    return arr.astype(np.int64)
