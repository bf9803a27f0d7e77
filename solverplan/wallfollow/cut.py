"""Cuts of a simply connected polygon and the general position the wall-following robot needs.

A robot that follows the wall and reaches a reflex vertex v_i can JUMP: keep going straight, past the vertex,
until it hits the boundary again (Yershova et al., *Mapping and pursuit-evasion strategies for a simple
wall-following robot*, §III–V). The segment it travels is a **cut**:

- the **right cut** of v_i continues the edge v_{i−1} → v_i (the robot arrived by RFOLLOW, counter-clockwise,
  the wall on its right): the ray from v_i in direction v_i − v_{i−1}; its end point on the boundary is r_i;
- the **left cut** continues the edge v_{i+1} → v_i (arrived by LFOLLOW, clockwise): the ray from v_i in
  direction v_i − v_{i+1}; its end point is ℓ_i.

End points are found by the project's exact ray caster, so they are exact rational points.

**Corners.** A vertex with an angle of exactly π (collinear with its two neighbours) is no corner: the robot
following the wall passes it sensing "on an edge", and no cut starts or ends there. Every entry point of the model
therefore works on :func:`corner_polygon` — the polygon with those vertices merged, exactly, the same free space —
and its vertices v0, v1, … are the polygon's **corners** in the order written, from the first corner at or after
vertex 0 (the same numbers as the file's when it has no collinear vertex); answers record how many were merged.

**General position.** The paper assumes that no three vertices are collinear, and, for the cut ordering, that
no two cut end points coincide; checked on the corners. A cut lies on the line of an edge, so a cut that runs into a vertex means three
collinear vertices; it is reported as such a cut because that names the cause. Every violation is an
:class:`~solverplan.errors.InvalidEnvironment` naming the offending vertices, as are holes (the model needs a
simply connected environment).

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])   # one reflex vertex, 3
>>> [(c.label, c.edge, str(c.t)) for c in cuts(room)]
[('l3', 0, '7/12'), ('r3', 5, '11/40')]
>>> cuts(Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]]))   # a symmetric L
Traceback (most recent call last):
...
solverplan.errors.InvalidEnvironment: vertices 1, 3 and 5 are collinear ((8, 0), (4, 4), (0, 8)): the wall-following model needs general position
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

import numpy as np

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.exact import ExactPoint, format_point, orient
from solverplan.geometry.raycast import cast_ray
from solverplan.geometry.walls import StraightWalls
from solverplan.result import EnvironmentRecord, Method, Optimality, Stats
from solverplan.wallfollow.ordering import CutOrdering

__all__ = ["Cut", "cuts", "cut_ordering", "check_general_position", "collinear_triple", "corner_polygon"]

Side = Literal["l", "r"]


@dataclass(frozen=True, slots=True)
class Cut:
    """One cut: from reflex vertex ``vertex`` to its end point on the boundary.

    Attributes
    ----------
    vertex
        The reflex vertex the cut starts at (vertex id of the normalised environment).
    side
        ``"l"`` for the left cut (the robot arrived by LFOLLOW), ``"r"`` for the right cut (RFOLLOW).
    edge
        The edge the end point lies on (edge ``e`` runs from vertex ``e`` to vertex ``e + 1``).
    t
        The end point's exact boundary parameter on ``edge``, in (0, 1) (never a vertex, by general position).
    point
        The exact end point, in the environment's length units.
    """

    vertex: int
    side: Side
    edge: int
    t: Fraction
    point: ExactPoint

    @property
    def label(self) -> str:
        """The end point's name in a cut ordering: ``l4`` (ℓ₄) or ``r4`` (r₄)."""
        return f"{self.side}{self.vertex}"


def corner_polygon(env: Environment) -> Environment:
    """The polygon the wall-following robot perceives: ``env`` with every vertex of angle exactly π merged (exact:
    the same free space, :class:`~solverplan.geometry.walls.StraightWalls`), its corners in the order written from
    the first corner at or after vertex 0. ``env`` itself when it has no such vertex.

    >>> from solverplan.environment import Environment
    >>> corner_polygon(Environment.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])).outer[1]
    (Fraction(4, 1), Fraction(0, 1))
    """
    return StraightWalls(env, keep_start=True).merged


def merged_count(env: Environment, corners: Environment) -> dict[str, int]:
    """``{"collinear_vertices_merged": k}`` for an answer's stats when :func:`corner_polygon` merged k > 0 vertices."""
    k = env.n_vertices - corners.n_vertices
    return {"collinear_vertices_merged": k} if k else {}


def _check_simply_connected(env: Environment) -> None:
    if env.holes:
        count = len(env.holes)
        raise InvalidEnvironment(f"the wall-following robot needs a polygon without holes: "
                                 f"{env.name or 'the environment'} has {count} hole{'s' if count > 1 else ''}")


def collinear_triple(env: Environment) -> tuple[int, int, int] | None:
    """Three collinear vertices of the outer ring, or ``None``; exact.

    For each vertex i, the directions to the later vertices are sorted by angle modulo π (floats); vertices j, k
    collinear with i have equal angles, so only runs of nearly equal angles need the exact predicate.
    O(n² log n) float work and, in general position, almost no exact work (n = 2,000: about a second).
    """
    pts = env.exact_vertices
    n = len(pts)
    xy = env.vertices.astype(float)
    # angles of exactly collinear directions differ by rounding only (~1e-15); 1e-9 leaves a wide margin
    tol = 1e-9
    for i in range(n - 2):
        d = xy[i + 1:] - xy[i]
        angle = np.mod(np.arctan2(d[:, 1], d[:, 0]), np.pi)
        order = np.argsort(angle, kind="stable")
        sorted_angle = angle[order]
        close = np.flatnonzero(np.diff(sorted_angle) <= tol)
        runs: list[list[int]] = []
        for c in close.tolist():  # runs of consecutive nearly equal angles
            if runs and runs[-1][-1] == c:
                runs[-1].append(c + 1)
            else:
                runs.append([c, c + 1])
        if len(sorted_angle) > 1 and sorted_angle[-1] - sorted_angle[0] >= np.pi - tol:  # 0 and π: one direction
            runs.append([0, len(sorted_angle) - 1])
        found = []
        for run in runs:
            members = sorted(i + 1 + int(order[r]) for r in run)
            for x, a in enumerate(members):
                for b in members[x + 1:]:
                    if orient(pts[i], pts[a], pts[b]) == 0:
                        found.append((i, a, b))
        if found:
            return min(found)
    return None


def _cast_cut(env: Environment, vertex: int, side: Side) -> Cut:
    pts = env.exact_vertices
    n = len(pts)
    v = pts[vertex]
    w = pts[(vertex - 1) % n] if side == "r" else pts[(vertex + 1) % n]
    hit = cast_ray(env, v, (v[0] - w[0], v[1] - w[1]))
    if hit.vertex is not None:
        name = "right" if side == "r" else "left"
        behind = (vertex - 1) % n if side == "r" else (vertex + 1) % n
        raise InvalidEnvironment(
            f"the {name} cut of reflex vertex {vertex} runs into vertex {hit.vertex} at {format_point(hit.point)}: "
            f"vertices {behind}, {vertex} and {hit.vertex} are collinear (the wall-following model needs general "
            f"position)")
    return Cut(vertex, side, hit.edge, hit.t, hit.point)


def cuts(env: Environment) -> tuple[Cut, ...]:
    """The left and right cuts of every reflex vertex, exactly, after checking general position.

    Parameters
    ----------
    env
        A simple polygon (no holes) whose vertices are in general position: no three collinear and no two cut
        end points at the same point.

    Returns
    -------
    tuple of Cut
        For each reflex vertex in vertex order, its left cut then its right cut.

    Raises
    ------
    InvalidEnvironment
        For holes, three collinear vertices (a cut running into a vertex is reported as that cut) or two cut
        end points at the same point — one line naming the vertices.
    """
    _check_simply_connected(env)
    env = corner_polygon(env)
    out: list[Cut] = []
    for vertex in env.reflex_vertices:
        out.append(_cast_cut(env, vertex, "l"))
        out.append(_cast_cut(env, vertex, "r"))
    triple = collinear_triple(env)
    if triple is not None:
        i, j, k = triple
        pts = env.exact_vertices
        raise InvalidEnvironment(
            f"vertices {i}, {j} and {k} are collinear ({format_point(pts[i])}, {format_point(pts[j])}, "
            f"{format_point(pts[k])}): the wall-following model needs general position")
    seen: dict[tuple[int, Fraction], Cut] = {}
    for cut in out:
        other = seen.get((cut.edge, cut.t))
        if other is not None:
            raise InvalidEnvironment(
                f"cut end points {other.label} and {cut.label} (of reflex vertices {other.vertex} and {cut.vertex}) "
                f"coincide at {format_point(cut.point)}: the cut ordering needs distinct end points")
        seen[(cut.edge, cut.t)] = cut
    return tuple(out)


def check_general_position(env: Environment) -> None:
    """Raise :class:`~solverplan.errors.InvalidEnvironment` unless ``env`` suits the wall-following model
    (see :func:`cuts`)."""
    cuts(env)



def cut_ordering(env: Environment) -> CutOrdering:
    """The cut ordering of ``env``, computed geometrically and exactly (the contract's format).

    Parameters
    ----------
    env
        A simple polygon in general position (see :func:`cuts`).

    Returns
    -------
    CutOrdering
        Vertices and cut end points in counter-clockwise boundary order from ``v0``; end points on one edge in
        order of their exact parameter t. ``optimality`` says the order is exact; ``stats`` counts n and m.

    Raises
    ------
    InvalidEnvironment
        A polygon with holes, or not in general position (three collinear vertices, a cut through a vertex).

    Examples
    --------
    ``r3`` and ``l3`` are where the right and left cuts of the reflex vertex v3 (the extensions of its two walls)
    end on the boundary:

    >>> import solverplan as sp
    >>> sp.cut_ordering(sp.load_environment("l_shape")).labels
    ('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3')
    >>> from solverplan.environment import Environment
    >>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
    >>> cut_ordering(room).labels
    ('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3')
    """
    user, env = env, corner_polygon(env)
    all_cuts = cuts(env)
    by_edge: dict[int, list[Cut]] = {}
    for cut in all_cuts:
        by_edge.setdefault(cut.edge, []).append(cut)
    labels: list[str] = []
    for e in range(env.n_vertices):
        labels.append(f"v{e}")
        labels.extend(c.label for c in sorted(by_edge.get(e, ()), key=lambda c: c.t))
    return CutOrdering(
        tuple(labels), EnvironmentRecord.of(user),
        Optimality(Method.EXACT_CHECK, True, None, scope="the exact cut end points of the polygon",
                   algorithm="exact ray casts from each reflex vertex"),
        Stats(counts={"n": env.n_vertices, "m": len(all_cuts) // 2, **merged_count(user, env)}))
