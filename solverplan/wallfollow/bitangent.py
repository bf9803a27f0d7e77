"""Inflections and bitangents, computed geometrically and exactly (§VI-B and D of the paper).

These are the rays whose crossing changes the shadow of a pursuer (the part of the polygon it cannot see):

- an **inflection** is a cut where the boundary turns from convex to reflex: the right cut of a reflex vertex
  whose counter-clockwise predecessor is convex (*right inflection*), or the left cut of a reflex vertex whose
  successor is convex (*left inflection*). Crossing one makes a shadow component appear or disappear.
- a **bitangent** is a maximal segment inside the polygon whose line is tangent to the boundary at two mutually
  visible reflex vertices v_i, v_j (both edges at each vertex on one side of the line). Its end points are
  b_{i,j} (beyond v_i) and b_{j,i} (beyond v_j); the pieces from v_i to b_{i,j} and from v_j to b_{j,i} are the
  *bitangent rays*, whose crossing splits or merges shadow components.

Each bitangent is stored **right-handed** (the paper's convention): v_j lies in the closed counter-clockwise
interval [v_i, r_i]. End points are found by the project's exact ray caster, and placed in the cut ordering
(:attr:`Bitangent.after_ij`: the point of the ordering just before b_{i,j} counter-clockwise).

The paper's checkable facts are tests: Prop. 11 (a bitangent pair is a *candidate*: v_i ∉ (r_j, ℓ_j) and
v_j ∉ (r_i, ℓ_i)), Prop. 13 (b_{i,j} ∈ [ℓ_i, v_i] ∩ [ℓ_j, v_i], b_{j,i} ∈ [v_j, r_i] ∩ [v_j, r_j]) and Prop. 18
(at most four bitangents between two reflex chains).

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [20, 0], [21, 9], [14, 10], [13, 4], [12, 11], [7, 13], [6, 5], [5, 12],
...                                 [0, 11]])                # two spikes hang from the ceiling: tips 4 and 7
>>> [(b.i, b.j, b.after_ij, b.after_ji) for b in bitangents(room)], [c.label for c in inflections(room)]
([(4, 7, 'v1', 'v9')], ['l4', 'r4', 'l7', 'r7'])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.exact import ExactPoint, format_point, orient, point_in_ring, segment_intersection
from solverplan.geometry.raycast import cast_ray
from solverplan.wallfollow.cut import Cut, corner_polygon, cuts
from solverplan.wallfollow.ordering import CutOrdering

__all__ = ["Bitangent", "inflections", "bitangents", "mutually_visible", "reflex_chains", "boundary_between"]

#: A boundary point as ``(edge, t)`` with t ∈ [0, 1): comparable along the boundary from vertex 0.
Place = tuple[int, Fraction]


@dataclass(frozen=True, slots=True)
class Bitangent:
    """A bitangent between reflex vertices ``i`` and ``j`` (right-handed: v_j ∈ [v_i, r_i]).

    Attributes
    ----------
    i, j
        The two reflex vertices.
    b_ij, b_ji
        The end points beyond v_i and beyond v_j, as ``(edge, t)`` (exact t ∈ (0, 1)).
    point_ij, point_ji
        The same end points as exact points, in the environment's length units.
    after_ij, after_ji
        The point of the cut ordering just before each end point counter-clockwise (a vertex or cut end point).
    """

    i: int
    j: int
    b_ij: Place
    b_ji: Place
    point_ij: ExactPoint
    point_ji: ExactPoint
    after_ij: str
    after_ji: str


def inflections(env: Environment) -> tuple[Cut, ...]:
    """The right and left inflections (cuts), in the order of :func:`~solverplan.wallfollow.cut.cuts`."""
    env = corner_polygon(env)
    n = env.n_vertices
    reflex = set(env.reflex_vertices)
    return tuple(c for c in cuts(env)
                 if (c.side == "r" and (c.vertex - 1) % n not in reflex)
                 or (c.side == "l" and (c.vertex + 1) % n not in reflex))


def reflex_chains(env: Environment) -> tuple[tuple[int, ...], ...]:
    """Maximal runs of consecutive reflex vertices (counter-clockwise), each a tuple of vertex ids (of the corners,
    :func:`~solverplan.wallfollow.cut.corner_polygon`)."""
    env = corner_polygon(env)
    n = env.n_vertices
    reflex = set(env.reflex_vertices)
    if len(reflex) == n:  # impossible for a polygon, but keep the loop below finite
        return (tuple(range(n)),)
    chains = []
    for v in sorted(reflex):
        if (v - 1) % n in reflex:
            continue  # not the first of its chain
        chain = [v]
        while (chain[-1] + 1) % n in reflex:
            chain.append((chain[-1] + 1) % n)
        chains.append(tuple(chain))
    return tuple(chains)


def mutually_visible(env: Environment, a: int, b: int) -> bool:
    """Exactly: does the open segment between vertices ``a`` and ``b`` lie in the interior of the polygon?

    In general position the segment contains no other vertex, so it is inside iff it crosses no edge away from
    its ends and its midpoint is inside.
    """
    pts = corner_polygon(env).exact_vertices
    n = len(pts)
    p, q = pts[a], pts[b]
    for e in range(n):
        f = (e + 1) % n
        if a in (e, f) or b in (e, f):
            if {a, b} == {e, f}:
                return False  # an edge: on the boundary, not through the interior
            continue  # an edge at a or b meets the segment only there (no three collinear vertices)
        if segment_intersection(p, q, pts[e], pts[f]) is not None:
            return False
    mid = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)
    return point_in_ring(mid, pts) > 0


def _tangent_at(pts, v: int, w: int) -> bool:
    """Is the line through vertices v and w tangent to the boundary at v (both edges at v on one side)?"""
    n = len(pts)
    return orient(pts[v], pts[w], pts[(v - 1) % n]) == orient(pts[v], pts[w], pts[(v + 1) % n])


def boundary_between(start: Place, end: Place, x: Place, *, closed: bool = True) -> bool:
    """Is boundary place ``x`` in the counter-clockwise interval from ``start`` to ``end`` (closed by default)?"""
    if closed and x in (start, end):
        return True
    if x in (start, end):
        return False
    if start <= end:
        return start < x < end
    return x > start or x < end


def _place_in(order: CutOrdering, cut_places: dict[str, Place], place: Place) -> str:
    """The point of the ordering just before ``place`` counter-clockwise."""
    before = f"v{place[0]}"
    for label in order.labels[order.index(before) + 1:]:
        if label[0] == "v" or cut_places[label] > place:
            break
        before = label
    return before


def bitangents(env: Environment, pairs: Sequence[tuple[int, int]] | None = None) -> tuple[Bitangent, ...]:
    """Every bitangent of ``env``, right-handed, with exact end points placed in the cut ordering.

    Parameters
    ----------
    env
        A simple polygon in general position.
    pairs
        The bitangents' vertex pairs (i, j), right-handed, when they are already known — learned by Strategy 4
        (:mod:`~solverplan.wallfollow.pebble`) — so that only their rays are cast; default: found here from the
        geometry (tangent at both ends, mutually visible).

    Raises
    ------
    InvalidEnvironment
        As :func:`~solverplan.wallfollow.cut.cuts`, and when a bitangent ends exactly at a cut end point (the
        paper's general position leaves that out too).
    """
    from solverplan.wallfollow.cut import cut_ordering

    env = corner_polygon(env)
    all_cuts = cuts(env)
    order = cut_ordering(env)
    pts = env.exact_vertices
    reflex = env.reflex_vertices
    right_end = {c.vertex: (c.edge, c.t) for c in all_cuts if c.side == "r"}
    cut_places = {c.label: (c.edge, c.t) for c in all_cuts}
    if pairs is None:
        found = []
        for x in range(len(reflex)):
            for y in range(x + 1, len(reflex)):
                a, b = reflex[x], reflex[y]
                if not (_tangent_at(pts, a, b) and _tangent_at(pts, b, a) and mutually_visible(env, a, b)):
                    continue
                # right-handed: v_j ∈ [v_i, r_i]
                found.append((a, b) if boundary_between((a, Fraction(0)), right_end[a], (b, Fraction(0))) else (b, a))
        pairs = found
    out = []
    for i, j in pairs:
        ends = []
        for v, w in ((i, j), (j, i)):
            hit = cast_ray(env, pts[v], (pts[v][0] - pts[w][0], pts[v][1] - pts[w][1]))
            place = (hit.edge, hit.t)
            if hit.vertex is not None or place in cut_places.values():
                raise InvalidEnvironment(f"the bitangent of reflex vertices {i} and {j} ends at "
                                         f"{format_point(hit.point)}, a vertex or cut end point: the "
                                         f"wall-following model needs general position")
            ends.append((place, hit.point))
        (b_ij, p_ij), (b_ji, p_ji) = ends
        out.append(Bitangent(i, j, b_ij, b_ji, p_ij, p_ji, _place_in(order, cut_places, b_ij),
                             _place_in(order, cut_places, b_ji)))
    return tuple(out)
