"""Rewritings of an environment's walls that keep every answer, with the query mapped exactly (issue #22).

A proof is about the question asked, not about how the walls were written. Each function here takes an
:class:`~solverplan.environment.Environment` and the boundary sets of a query (start and goal sets, as
:class:`~solverplan.environment.BoundarySet` or strings such as ``"e3:0.25:0.75,e4"``) and returns a
:class:`Rewritten`: the environment as a user could have typed it instead, and the *same* sets in its
numbering. Every planner's answer (status, bounce counts, interval widths, contraction; lengths times
:attr:`Rewritten.length_scale`) must be the same for both; only segment and edge ids may differ.

Rewritings of the vertex list (the same free space):

- :func:`insert_vertices` — collinear vertices at given (edge, t);
- :func:`split_edges` — every edge split into k equal parts, or at given parameters;
- :func:`at_set_ends` — collinear vertices exactly where the sets end inside edges (the issue's case);
- :func:`roll_ring_start` — a ring written from another vertex;
- :func:`reverse_rings` — every ring written in the opposite order (the loader renormalises it).

Motions (the same room, moved):

- :func:`rotate` by an exact rational rotation (cos, sin) with cos² + sin² = 1 — Pythagorean triples such as
  (3/5, 4/5), (20/29, 21/29), (119/169, 120/169) (:data:`RATIONAL_ROTATIONS`, :func:`pythagorean_rotation`;
  they are dense in angle) — so the rotated room is exact;
- :func:`translate`, :func:`scale` (lengths scale; angles, widths and contraction do not);
- :func:`mirror` (a reflection: each edge's direction is reversed by the loader's renormalisation).

Everything is exact (:class:`fractions.Fraction`): no coordinate or parameter is ever a binary float, and the
rewritten environment is built with :meth:`Environment.from_coords`, as the user's file would be.

**How ids and parameters map.** Edge numbering is on the *normalised* environment (docs/contract.md: outer
ring counter-clockwise, holes clockwise; a ring given the other way is reversed keeping its first vertex).
Insertions and splits give an edge several sub-edges: a piece of a set on it becomes pieces of the sub-edges
with rescaled t (t ∈ [u_j, u_{j+1}] ↦ (t − u_j)/(u_{j+1} − u_j)); points where a piece only touches a sub-edge
are dropped (vertices are never positions). Motions keep ids and t. Rolling a ring shifts its ids. Writing a ring
backwards makes the loader reverse it again, keeping the new first vertex: the normalised ring is the old one
started one vertex earlier, so edge i becomes edge i + 1 of its ring **with the same t** (edges keep their
direction: the free space stays on their left). A mirror reverses every edge: edge i of a ring of n becomes
edge n − 1 − i, and t becomes 1 − t.

**Patrol edges.** A patrol's required visit "edge e" is satisfied by landing anywhere on e
(:mod:`solverplan.plan.patrols`): after e is split that is "e′ or e″", which no visit list can say.
:meth:`Rewritten.map_edges` therefore maps only edges kept whole and raises :class:`~solverplan.errors.InputError`
for a split one; test patrols with rewritings that keep the visited edges whole (insertions elsewhere, motions,
ring starts, reversal).

**Comparing answers.** :func:`answer_summary` reduces any planner's answer to what must not change (status,
proof, bounces, widths, contraction, lengths divided by the scale), and :func:`answer_differences` lists what
differs between two answers, to an absolute tolerance (10⁻⁹ by default).

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> r = at_set_ends(square, "e0:0.25:1", "e2:0:0.5")
>>> r.env.n_edges, [str(s) for s in r.sets]
(6, ['e1', 'e3'])
>>> r.env.ring(0)[1], r.map_point(0, Fraction(1, 8))
((Fraction(1, 1), Fraction(0, 1)), (0, Fraction(1, 2)))
>>> turned = rotate(square, Fraction(3, 5), Fraction(4, 5), "e0:0.25:1")
>>> turned.env.ring(0)[1], str(turned.sets[0])
((Fraction(12, 5), Fraction(16, 5)), 'e0:0.25:1')
>>> str(reverse_rings(square, "e0:0.25:1").sets[0])       # the same wall, one id further, the same t
'e1:0.25:1'
>>> str(mirror(square, "e0:0.25:1").sets[0])              # mirrored: edge 3 of 4, t ↦ 1 − t
'e3:0:0.75'
>>> split_edges(square, 2).map_edges([0, 2])
Traceback (most recent call last):
...
solverplan.errors.InputError: edge e0 is split into e0,e1 by split_edges(2): a patrol visit of e0 cannot be mapped to one edge
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable, Iterable, Mapping, Sequence

from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, format_number, to_fraction
from solverplan.plan._results import PositionStrategy
from solverplan.plan.patrols import Patrol
from solverplan.plan.result import ParetoFront, Plan

__all__ = [
    "Rewritten",
    "RATIONAL_ROTATIONS",
    "pythagorean_rotation",
    "identity",
    "insert_vertices",
    "split_edges",
    "at_set_ends",
    "rotate",
    "translate",
    "scale",
    "mirror",
    "roll_ring_start",
    "reverse_rings",
    "answer_summary",
    "answer_differences",
]

SetLike = BoundarySet | str

RATIONAL_ROTATIONS: tuple[tuple[Fraction, Fraction], ...] = (
    (Fraction(3, 5), Fraction(4, 5)),
    (Fraction(20, 29), Fraction(21, 29)),
    (Fraction(119, 169), Fraction(120, 169)),
    (Fraction(5, 13), Fraction(12, 13)),
    (Fraction(8, 17), Fraction(15, 17)),
)
"""Exact rotations (cos, sin) from Pythagorean triples: about 53.1°, 46.4°, 45.2°, 67.4° and 61.9°."""


@dataclass(frozen=True, slots=True)
class _Image:
    """Where the part t ∈ [a, b] of an old edge goes: onto new edge ``edge``, at new parameter
    (t − a)/(b − a) — or 1 − that when ``flip``."""

    edge: int
    a: Fraction
    b: Fraction
    flip: bool = False

    def new_t(self, t: Fraction) -> Fraction:
        s = (t - self.a) / (self.b - self.a)
        return 1 - s if self.flip else s


@dataclass(frozen=True)
class Rewritten:
    """An environment rewritten, and the query mapped into its numbering.

    Attributes
    ----------
    env
        The rewritten environment (built by :meth:`Environment.from_coords`, normalised as a loaded file is).
    sets
        The boundary sets given to the rewriting, mapped (exact), in the order given.
    source
        The environment before the rewriting.
    images
        For every edge of ``source``: where its parts go, in increasing t (private representation).
    length_scale
        How lengths change: new length = ``length_scale`` × old length (1 except for :func:`scale`).
    description
        What was done, e.g. ``"split_edges(2)"``, ``"rotate(3/5, 4/5) ∘ at_set_ends"``.
    """

    env: Environment
    sets: tuple[BoundarySet, ...]
    source: Environment
    images: tuple[tuple[_Image, ...], ...]
    length_scale: Fraction = Fraction(1)
    description: str = ""

    # ------------------------------------------------------------------ mapping
    def map_point(self, edge: int, t: Fraction | int | str) -> tuple[int, Fraction]:
        """The new (edge, t) of old boundary point (edge, t) (a point on a new vertex: the edge that starts there,
        or the last one at t = 1)."""
        self.source._check_edge_id(edge)
        t = to_fraction(t, where="boundary parameter")
        if not 0 <= t <= 1:
            raise InputError(f"boundary parameter t={format_number(t)} on edge e{edge} is not in [0, 1]")
        parts = self.images[edge]
        for im in parts:
            if im.a <= t < im.b:
                return im.edge, im.new_t(t)
        last = parts[-1]
        return last.edge, last.new_t(t)

    def map_set(self, bset: SetLike) -> BoundarySet:
        """The same boundary points as ``bset`` (a set of :attr:`source`), in the numbering of :attr:`env`."""
        if isinstance(bset, str):
            bset = self.source.boundary_set(bset)
        if not isinstance(bset, BoundarySet):
            raise InputError(f"expected a boundary set such as 'e3:0.25:0.75,e4', got {bset!r}")
        out: list[BoundaryPiece] = []
        for piece in bset.pieces:
            self.source._check_edge_id(piece.edge)
            for im in self.images[piece.edge]:
                lo, hi = max(piece.t0, im.a), min(piece.t1, im.b)
                if lo < hi:
                    s0, s1 = sorted((im.new_t(lo), im.new_t(hi)))
                    out.append(BoundaryPiece(im.edge, s0, s1))
        return BoundarySet(tuple(out))

    def map_edges(self, edges: Sequence[int] | str) -> tuple[int, ...]:
        """A patrol's visit list mapped edge by edge; every edge must stay whole (module docstring).

        Raises
        ------
        InputError
            If a listed edge is split into several edges by the rewriting.
        """
        if isinstance(edges, str):
            ids = [p.edge for p in self.source.boundary_set(edges).pieces]
        else:
            ids = [int(e) for e in edges]
        out = []
        for e in ids:
            self.source._check_edge_id(e)
            parts = self.images[e]
            if len(parts) != 1:
                names = ",".join(f"e{im.edge}" for im in parts)
                raise InputError(f"edge e{e} is split into {names} by {self.description}: a patrol visit of e{e} "
                                 "cannot be mapped to one edge")
            out.append(parts[0].edge)
        return tuple(out)

    def map_length(self, length: float) -> float:
        """A length of the old environment (an ε of localisation, a funnel width) in the new one."""
        return float(length) * float(self.length_scale)

    # ------------------------------------------------------------------ composition
    def then(self, rewriting: Callable[..., Rewritten], *args: Any) -> Rewritten:
        """This rewriting followed by ``rewriting(self.env, *args, *self.sets)``: one :class:`Rewritten` from
        :attr:`source` to the final environment.

        >>> from solverplan.environment import Environment
        >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
        >>> r = split_edges(square, 2, "e0:0.25:1").then(roll_ring_start, 0, 3).then(scale, 2)
        >>> str(r.sets[0]), r.length_scale, r.description
        ('e5:0.5:1,e6', Fraction(2, 1), 'split_edges(2) ∘ roll_ring_start(0, 3) ∘ scale(2)')
        """
        second = rewriting(self.env, *args, *self.sets)
        images = []
        for parts in self.images:
            out: list[_Image] = []
            for im in parts:
                width = im.b - im.a
                for nxt in second.images[im.edge]:
                    if im.flip:
                        lo, hi = im.a + (1 - nxt.b) * width, im.a + (1 - nxt.a) * width
                    else:
                        lo, hi = im.a + nxt.a * width, im.a + nxt.b * width
                    out.append(_Image(nxt.edge, lo, hi, im.flip != nxt.flip))
            images.append(tuple(sorted(out, key=lambda x: x.a)))
        description = " ∘ ".join(d for d in (self.description, second.description) if d)
        return Rewritten(second.env, second.sets, self.source, tuple(images),
                         self.length_scale * second.length_scale, description)


# ---------------------------------------------------------------------- the engine
_RawImages = list[list[tuple[int, int, Fraction, Fraction, bool]]]  # per old edge: (raw ring, raw edge, a, b, flip)


def _as_sets(env: Environment, sets: Sequence[SetLike]) -> tuple[BoundarySet, ...]:
    out = []
    for k, s in enumerate(sets):
        if isinstance(s, str):
            out.append(env.boundary_set(s))
        elif isinstance(s, BoundarySet):
            for p in s.pieces:
                env._check_edge_id(p.edge)
            out.append(s)
        else:
            raise InputError(f"set {k}: expected a boundary set such as 'e3:0.25:0.75,e4', got {s!r}")
    return tuple(out)


def _build(env: Environment, raw_rings: list[list[ExactPoint]], raw: _RawImages, sets: Sequence[SetLike],
           description: str, length_scale: Fraction = Fraction(1)) -> Rewritten:
    """Build the rewritten environment from rings as a user would type them and the map of every old edge onto
    raw (ring, edge) pairs; renormalisation by the loader is accounted for here."""
    given = _as_sets(env, sets)
    new = Environment.from_coords(raw_rings[0], raw_rings[1:], name=env.name)
    offsets = new.ring_offsets
    images = []
    for parts in raw:
        out = []
        for ring, j, a, b, flip in parts:
            n = len(raw_rings[ring])
            if new.reoriented[ring]:  # (w0, w1, …) became (w0, w_{n−1}, …, w1): raw edge j is edge n − 1 − j reversed
                local, flip = n - 1 - j, not flip
            else:
                local = j
            out.append(_Image(offsets[ring] + local, a, b, flip))
        images.append(tuple(sorted(out, key=lambda x: x.a)))
    partial = Rewritten(new, (), env, tuple(images), length_scale, description)
    return Rewritten(new, tuple(partial.map_set(s) for s in given), env, tuple(images), length_scale, description)


def _rings(env: Environment) -> list[list[ExactPoint]]:
    return [list(ring) for ring in env.rings]


def _whole(env: Environment) -> _RawImages:
    """Every edge onto itself (rings kept as they are)."""
    out: _RawImages = []
    for ring, pts in enumerate(env.rings):
        out.extend([(ring, j, Fraction(0), Fraction(1), False)] for j in range(len(pts)))
    return out


def _moved(env: Environment, f: Callable[[ExactPoint], ExactPoint], sets: Sequence[SetLike], description: str,
           length_scale: Fraction = Fraction(1)) -> Rewritten:
    rings = [[f(p) for p in ring] for ring in env.rings]
    return _build(env, rings, _whole(env), sets, description, length_scale)


def _exact(value: object, what: str) -> Fraction:
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(f"{what} {value!r} is not a finite number")
    return to_fraction(value, where=what)


# ---------------------------------------------------------------------- vertex lists
def identity(env: Environment, *sets: SetLike) -> Rewritten:
    """Nothing changed (the reference answer of a comparison): the environment rebuilt, the sets parsed."""
    return _build(env, _rings(env), _whole(env), sets, "identity")


def insert_vertices(env: Environment, points_on_edges: Mapping[int, Iterable[object]] | Iterable[tuple[int, object]],
                    *sets: SetLike) -> Rewritten:
    """Collinear vertices inserted at boundary points (edge, t), 0 < t < 1: the same walls, more vertices.

    Parameters
    ----------
    env
        The environment.
    points_on_edges
        ``{edge: [t, ...]}`` or pairs ``(edge, t)``; t exact (int, :class:`~fractions.Fraction`, decimal or a
        string like ``"1/3"``), strictly inside (0, 1). Repeated points are inserted once.
    *sets
        Boundary sets of ``env`` to map.

    Returns
    -------
    Rewritten
        Edge k with m points inserted becomes m + 1 consecutive edges (numbering shifts after it).

    Raises
    ------
    InputError
        An unknown edge, or a t outside (0, 1).

    >>> from solverplan.environment import Environment
    >>> tri = Environment.from_coords([[0, 0], [4, 0], [0, 4]])
    >>> r = insert_vertices(tri, {0: ["1/4", "3/4"]}, "e0:0:0.5,e2")
    >>> r.env.ring(0)[:4], str(r.sets[0])          # doctest: +NORMALIZE_WHITESPACE
    (((Fraction(0, 1), Fraction(0, 1)), (Fraction(1, 1), Fraction(0, 1)), (Fraction(3, 1), Fraction(0, 1)),
      (Fraction(4, 1), Fraction(0, 1))), 'e0,e1:0:0.5,e4')
    >>> insert_vertices(tri, {1: [1]})
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: insert_vertices: t=1 on edge e1 is not strictly inside (0, 1)
    """
    pairs = points_on_edges.items() if isinstance(points_on_edges, Mapping) else None
    wanted: dict[int, set[Fraction]] = {}
    if pairs is not None:
        for edge, ts in pairs:
            for t in ts:
                wanted.setdefault(edge, set()).add(_check_t(env, edge, t))
    else:
        for item in points_on_edges:
            if not isinstance(item, tuple) or len(item) != 2:
                raise InputError(f"insert_vertices: expected (edge, t) pairs, got {item!r}")
            edge, t = item
            wanted.setdefault(edge, set()).add(_check_t(env, edge, t))
    return _insert(env, {e: sorted(ts) for e, ts in wanted.items()}, sets,
                   f"insert_vertices({sum(map(len, wanted.values()))} points)")


def _check_t(env: Environment, edge: object, t: object) -> Fraction:
    if isinstance(edge, bool) or not isinstance(edge, int):
        raise InputError(f"insert_vertices: edge {edge!r} is not an edge id")
    env._check_edge_id(edge)
    value = _exact(t, f"insert_vertices: t on edge e{edge}")
    if not 0 < value < 1:
        raise InputError(f"insert_vertices: t={format_number(value)} on edge e{edge} is not strictly inside (0, 1)")
    return value


def _check_param(t: object) -> Fraction:
    value = _exact(t, "split_edges: parameter")
    if not 0 < value < 1:
        raise InputError(f"split_edges: parameter t={format_number(value)} is not strictly inside (0, 1)")
    return value


def _insert(env: Environment, cuts: Mapping[int, list[Fraction]], sets: Sequence[SetLike],
            description: str) -> Rewritten:
    rings: list[list[ExactPoint]] = []
    raw: _RawImages = []
    edge = 0
    for r, ring in enumerate(env.rings):
        out: list[ExactPoint] = []
        for i, a in enumerate(ring):
            b = ring[(i + 1) % len(ring)]
            ts = cuts.get(edge, [])
            bounds = [Fraction(0), *ts, Fraction(1)]
            parts = []
            for k in range(len(bounds) - 1):
                u = bounds[k]
                out.append((a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])))
                parts.append((r, len(out) - 1, bounds[k], bounds[k + 1], False))
            raw.append(parts)
            edge += 1
        rings.append(out)
    return _build(env, rings, raw, sets, description)


def split_edges(env: Environment, k: int | Sequence[object] = 2, *sets: SetLike) -> Rewritten:
    """Every edge split: into ``k`` equal parts (an int ≥ 2), or at the parameters ``k`` (each in (0, 1)).

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> r = split_edges(square, 2, "e1:0.25:0.75")
    >>> r.env.n_edges, str(r.sets[0])
    (8, 'e2:0.5:1,e3:0:0.5')
    >>> str(split_edges(square, ["1/3", "1/2"], "e0:0.4:1").sets[0])
    'e1:0.4:1,e2'
    >>> split_edges(square, 1)
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: split_edges: k=1 parts: need an integer k >= 2 or a list of parameters in (0, 1)
    """
    if isinstance(k, bool) or (isinstance(k, int) and k < 2):
        raise InputError(f"split_edges: k={k!r} parts: need an integer k >= 2 or a list of parameters in (0, 1)")
    if isinstance(k, int):
        ts = [Fraction(j, k) for j in range(1, k)]
        what = f"split_edges({k})"
    else:
        if isinstance(k, str) or not isinstance(k, Sequence) or not k:
            raise InputError(f"split_edges: expected k >= 2 or a list of parameters in (0, 1), got {k!r}")
        ts = sorted({_check_param(t) for t in k})
        what = f"split_edges([{', '.join(map(format_number, ts))}])"
    return _insert(env, {e: ts for e in range(env.n_edges)}, sets, what)


def at_set_ends(env: Environment, *sets: SetLike) -> Rewritten:
    """Collinear vertices exactly where the sets end inside edges (every t0 > 0 and t1 < 1 of their pieces).

    The issue's case (#22): a set that ends inside an edge asks about part of a wall; with a vertex at its end
    the same set is whole edges. The rewritten sets cover the same points, now in whole new edges (or pieces
    of them where two sets end at different points of one edge).

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> r = at_set_ends(square, "e0:0.25:0.75", "e2:0.5:1,e3:0:0.5")
    >>> [str(s) for s in r.sets], r.env.n_edges
    (['e1', 'e5,e6'], 8)
    """
    given = _as_sets(env, sets)
    cuts: dict[int, set[Fraction]] = {}
    for s in given:
        for p in s.pieces:
            for t in (p.t0, p.t1):
                if 0 < t < 1:
                    cuts.setdefault(p.edge, set()).add(t)
    n = sum(map(len, cuts.values()))
    return _insert(env, {e: sorted(ts) for e, ts in cuts.items()}, given, f"at_set_ends({n} points)")


def roll_ring_start(env: Environment, ring: int, k: int, *sets: SetLike) -> Rewritten:
    """Ring ``ring`` (0 = outer) written from its vertex ``k`` on: its edge i becomes edge i − k (mod its size).

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> r = roll_ring_start(square, 0, 1, "e0:0.5:1,e1")
    >>> r.env.ring(0)[0], str(r.sets[0])
    ((Fraction(4, 1), Fraction(0, 1)), 'e3:0.5:1,e0')
    """
    if isinstance(ring, bool) or not isinstance(ring, int) or not 0 <= ring < len(env.rings):
        raise InputError(f"roll_ring_start: ring {ring!r} does not exist (rings are 0..{len(env.rings) - 1}, 0 the outer)")
    if isinstance(k, bool) or not isinstance(k, int):
        raise InputError(f"roll_ring_start: k={k!r} is not an integer")
    rings = _rings(env)
    n = len(rings[ring])
    k %= n
    rings[ring] = rings[ring][k:] + rings[ring][:k]
    raw = _whole(env)
    base = env.ring_offsets[ring]
    for i in range(n):
        raw[base + i] = [(ring, (i - k) % n, Fraction(0), Fraction(1), False)]
    return _build(env, rings, raw, sets, f"roll_ring_start({ring}, {k})")


def reverse_rings(env: Environment, *sets: SetLike) -> Rewritten:
    """Every ring written in the opposite vertex order; the loader renormalises it (module docstring).

    The loader reverses a ring given the wrong way round *keeping its first vertex*, so the normalised ring is
    the old one started one vertex earlier: edge i of a ring becomes edge i + 1 (mod its size), same t.
    """
    rings = [list(reversed(ring)) for ring in env.rings]
    raw: _RawImages = []
    for r, ring in enumerate(env.rings):
        n = len(ring)
        # raw edge j of the reversed list runs from v_{n−1−j} to v_{n−2−j}: old edge i = n − 2 − j, reversed
        raw.extend([(r, (n - 2 - i) % n, Fraction(0), Fraction(1), True)] for i in range(n))
    return _build(env, rings, raw, sets, "reverse_rings")


# ---------------------------------------------------------------------- motions
def pythagorean_rotation(m: int, n: int) -> tuple[Fraction, Fraction]:
    """The exact rotation (cos, sin) = ((m² − n²)/(m² + n²), 2mn/(m² + n²)) for integers m > n > 0.

    Its angle is 2·atan(n/m): these rotations are dense in angle.

    >>> pythagorean_rotation(2, 1), pythagorean_rotation(5, 2)
    ((Fraction(3, 5), Fraction(4, 5)), (Fraction(21, 29), Fraction(20, 29)))
    """
    if isinstance(m, bool) or isinstance(n, bool) or not isinstance(m, int) or not isinstance(n, int) or not m > n > 0:
        raise InputError(f"pythagorean_rotation: need integers m > n > 0, got m={m!r}, n={n!r}")
    d = m * m + n * n
    return Fraction(m * m - n * n, d), Fraction(2 * m * n, d)


def rotate(env: Environment, cos: object, sin: object, *sets: SetLike) -> Rewritten:
    """The room rotated about the origin by the exact rotation (cos, sin): cos² + sin² must be exactly 1.

    >>> from solverplan.environment import Environment
    >>> tri = Environment.from_coords([[0, 0], [5, 0], [0, 5]])
    >>> rotate(tri, "20/29", "21/29").env.ring(0)[1]
    (Fraction(100, 29), Fraction(105, 29))
    >>> rotate(tri, 0.6, 0.8).env.ring(0)[1]                 # floats read as the decimals they print
    (Fraction(3, 1), Fraction(4, 1))
    >>> rotate(tri, "0.7", "0.7")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: rotate: (cos, sin) = (0.7, 0.7) is not an exact rotation: cos² + sin² = 0.98, not 1 (use a Pythagorean triple such as (3/5, 4/5))
    """
    c, s = _exact(cos, "rotate: cos"), _exact(sin, "rotate: sin")
    if c * c + s * s != 1:
        raise InputError(f"rotate: (cos, sin) = ({format_number(c)}, {format_number(s)}) is not an exact rotation: "
                         f"cos² + sin² = {format_number(c * c + s * s)}, not 1 (use a Pythagorean triple such as (3/5, 4/5))")
    return _moved(env, lambda p: (c * p[0] - s * p[1], s * p[0] + c * p[1]), sets,
                  f"rotate({format_number(c)}, {format_number(s)})")


def translate(env: Environment, dx: object, dy: object, *sets: SetLike) -> Rewritten:
    """The room moved by (dx, dy) (exact)."""
    x, y = _exact(dx, "translate: dx"), _exact(dy, "translate: dy")
    return _moved(env, lambda p: (p[0] + x, p[1] + y), sets, f"translate({format_number(x)}, {format_number(y)})")


def scale(env: Environment, factor: object, *sets: SetLike) -> Rewritten:
    """The room scaled about the origin by ``factor`` > 0 (exact); lengths scale by it (:attr:`Rewritten.length_scale`).

    >>> from solverplan.environment import Environment
    >>> scale(Environment.from_coords([[0, 0], [1, 0], [0, 1]]), 0)
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: scale: factor 0 must be positive (a half-turn is rotate(-1, 0))
    """
    f = _exact(factor, "scale: factor")
    if f <= 0:
        raise InputError(f"scale: factor {format_number(f)} must be positive (a half-turn is rotate(-1, 0))")
    return _moved(env, lambda p: (f * p[0], f * p[1]), sets, f"scale({format_number(f)})", length_scale=f)


def mirror(env: Environment, *sets: SetLike) -> Rewritten:
    """The room reflected in the x-axis, (x, y) ↦ (x, −y). Every ring comes out the wrong way round and the loader
    reverses it (keeping its first vertex): edge i of a ring of n becomes edge n − 1 − i, and t becomes 1 − t.
    Headings are measured from the edge's direction with the free space on the left, so a mirrored plan uses
    the mirrored intervals θ ↦ π − θ: the same widths."""
    rings = [[(p[0], -p[1]) for p in ring] for ring in env.rings]
    return _build(env, rings, _whole(env), sets, "mirror")


# ---------------------------------------------------------------------- comparing answers
def answer_summary(answer: Any, *, length_scale: object = 1) -> dict[str, Any]:
    """What of a planner's answer must not change under a rewriting, as a flat dict.

    Plans (:class:`~solverplan.plan.Plan`): status, proof, bounces and the objective's value (radians: the min
    width, or the sum of widths for ``sum``; for ``fewest`` the min width, its documented tie-break);
    Pareto fronts: status, proof and the points (bounces, min width); patrols: status, proof, cycle and entry
    bounces, periods, contraction, rate and tolerance; funnels and localisation (beam searches for the fewest
    bounces): status, bounces and tolerance (``length_scale`` is then unused). Ids of segments and edges are left out: they change with the numbering.
    """
    to_fraction(length_scale, where="length_scale")  # checked, for every kind
    status = answer.status.value
    proved = bool(answer.optimality.proved)
    if isinstance(answer, Plan):
        # the objective's value and the documented tie-break (fewest: the most tolerant of the fewest-bounce plans;
        # tolerance and constant: the fewest bounces among the widest); other widths are one optimal plan's, not the
        # answer's (a sum of widths of a most tolerant plan may differ between equally good plans)
        value = "sum_width" if answer.objective == "sum" else "min_width"
        return {"kind": f"plan/{answer.objective}", "status": status, "proved": proved, "bounces": answer.bounces,
                value: answer.value if answer.objective != "fewest" else answer.min_width}
    if isinstance(answer, ParetoFront):
        return {"kind": "pareto", "status": status, "proved": proved,
                "front": [(p.bounces, p.min_width) for p in answer.points]}
    if isinstance(answer, Patrol):
        return {"kind": f"patrol/{answer.objective}", "status": status, "proved": proved,
                "bounces": len(answer.cycle), "entry": len(answer.entry), "periods": answer.periods,
                "contraction": answer.contraction, "rate": answer.rate, "tolerance": answer.tolerance}
    if isinstance(answer, PositionStrategy):
        # a beam search's answer: its status and bounces (what it minimises) and its interval width; the position
        # widths are one strategy's among equally short ones, which float ties of a rotated copy may pick otherwise
        return {"kind": answer.kind, "status": status, "bounces": answer.bounces, "tolerance": answer.tolerance}
    raise InputError(f"answer_summary: no summary for a {type(answer).__name__}")


def answer_differences(a: Any, b: Any, *, length_scale: object = 1, tol: float = 1e-9) -> list[str]:
    """What differs between answer ``a`` (old environment) and ``b`` (rewritten, lengths × ``length_scale``):
    one line per field (``"min_width: 0.146 != 0.0836"``); empty when they agree (numbers to ``tol``, absolute).

    >>> from solverplan.environment import Environment
    >>> from solverplan.plan import find_plan
    >>> room = Environment.from_coords([[0, 0], [4, 0], [6, 3], [-2, 3]])
    >>> r = translate(room, 100, "-2.5", "e0", "e2")
    >>> answer_differences(find_plan(room, "e0", "e2"), find_plan(r.env, *r.sets))
    []
    >>> answer_differences(find_plan(room, "e0", "e2"), find_plan(r.env, "e0", "e1"))   # another question
    ['min_width: 1.175635929 != 0.462547609']
    """
    sa, sb = answer_summary(a), answer_summary(b, length_scale=length_scale)
    out = []
    for key in sa:
        if not _same(sa[key], sb.get(key), tol):
            out.append(f"{key}: {_show(sa[key])} != {_show(sb.get(key))}")
    return out


def _same(x: Any, y: Any, tol: float) -> bool:
    if isinstance(x, (list, tuple)) and isinstance(y, (list, tuple)):
        return len(x) == len(y) and all(_same(p, q, tol) for p, q in zip(x, y))
    if isinstance(x, float) and isinstance(y, (int, float)) and not isinstance(y, bool):
        if math.isinf(x) or math.isinf(y):
            return x == y
        return abs(x - y) <= tol
    return bool(x == y)


def _show(x: Any) -> str:
    if isinstance(x, float):
        return f"{x:.10g}"
    if isinstance(x, (list, tuple)):
        inner = ", ".join(_show(v) for v in x)
        return f"[{inner}]" if isinstance(x, list) else f"({inner})"
    return str(x)
