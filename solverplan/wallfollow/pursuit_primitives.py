"""Strategy 3: pursuit with the bitangent sensor — primitives and compounds instead of gaps (§VI-C).

Without a gap sensor the pursuer names shadow components by **primitives**: every reflex chain (a maximal run
of consecutive reflex vertices, :func:`~solverplan.wallfollow.bitangent.reflex_chains`) c₁ … c_k has a right
primitive ``R{c₁}`` (its shadow appears when the pursuer crosses the right inflection, the right cut of c₁) and
a left primitive ``L{c_k}`` (the left cut of c_k). Which primitives are **active** at a point of the cut
ordering follows from the ordering alone: ``R{c₁}`` exactly strictly between v_{c₁} and r_{c₁}
(counter-clockwise), ``L{c_k}`` strictly between ℓ_{c_k} and v_{c_k}. While the pursuer moves along a reflex
chain the shadow *slides* from vertex to vertex but keeps its primitive's name.

A shadow component is a **compound**: the set of active primitives merged into it. The bitangent sensor reports
every crossing of a bitangent ray — the two reflex vertices, which one is nearer, and whether the far one's
shadow merged into the near one's or split off it — and the primitives involved (Prop. 9). The I-state is the
position, the merges in force (a forest on the active primitives whose edges are the bitangent rays that merged
them; a split removes its edge) and the labels of the compounds. Events of one action are applied in the order
of Lemma 16 where they coincide (splits, then appearances and disappearances, then merges). Initially no
compound is known: every active primitive is its own component with label 1 (the proof of Prop. 10 shows this
is harmless). Breadth-first search over these I-states is complete (Prop. 10) and explores the same I-space as
Strategy 2; the tests check that both find plans on the same polygons, of the same length, and that the ground
truth (:func:`~solverplan.wallfollow.pursuit_check.check_pursuit`) verifies every plan.

>>> from solverplan.environment import Environment
>>> room = Environment.from_coords([[0, 0], [20, 0], [21, 9], [14, 10], [13, 4], [12, 11], [7, 13], [6, 5],
...                                 [5, 12], [0, 11]])             # two spikes hang from the ceiling: tips 4 and 7
>>> sensor = BitangentSensor(room)
>>> sensor.primitives, sorted(sensor.active("v0")), sorted(sensor.active("v5"))
(('R4', 'L4', 'R7', 'L7'), ['R4', 'R7'], ['L7', 'R4'])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import SolverFailed
from solverplan.exact import ExactPoint, cross, orient, segment_intersection
from solverplan.wallfollow.bitangent import bitangents, reflex_chains
from solverplan.wallfollow.cut import cut_ordering, cuts

__all__ = ["BitangentSensor", "PrimitiveState", "BitangentRay"]

#: Lemma 16's order of coinciding events.
_ORDER = {"split": 0, "appear": 1, "disappear": 1, "merge": 2}


@dataclass(frozen=True, slots=True)
class BitangentRay:
    """What the bitangent sensor knows of one bitangent ray: from ``near`` (a reflex vertex) to the boundary,
    with the far vertex ``far`` behind it; ``near_primitive`` / ``far_primitive`` name the two shadows it splits
    or merges; ``split_side`` is the side (±1, as :func:`~solverplan.exact.orient` of the line far → near) on
    which the far shadow is separate."""

    index: int
    near: int
    far: int
    start: ExactPoint
    end: ExactPoint
    near_primitive: str
    far_primitive: str
    split_side: int


#: A Strategy 3 I-state's pursuit status: (merges in force as (ray, far primitive, near primitive), labelled 1)
PrimitiveState = tuple[frozenset[tuple[int, str, str]], frozenset[str]]


def _cot(d: ExactPoint, w: ExactPoint) -> Fraction:
    """cot of the angle from d to w (w not parallel to d)."""
    dot = d[0] * w[0] + d[1] * w[1]
    cross = d[0] * w[1] - d[1] * w[0]
    return dot / abs(cross)


class BitangentSensor:
    """Primitives, their activity along the cut ordering and the bitangent sensor's reports, for one polygon."""

    def __init__(self, env: Environment, pairs: Sequence[tuple[int, int]] | None = None) -> None:
        """``pairs``: the bitangents' vertex pairs when learned (Strategy 5, :mod:`~solverplan.wallfollow.pebble`);
        default: the exact geometry's (:func:`~solverplan.wallfollow.bitangent.bitangents`)."""
        self.env = env
        self.ordering = cut_ordering(env)
        n = env.n_vertices
        pts = env.exact_vertices
        chains = reflex_chains(env)
        self._chain = {v: c for c in chains for v in c}
        self.primitives = tuple(p for c in chains for p in (f"R{c[0]}", f"L{c[-1]}"))
        cut_at = {(c.vertex, c.side): c for c in cuts(env)}
        labels = self.ordering.labels
        size = len(labels)
        # the open interval of the ordering where each primitive is active
        self._interval: dict[str, tuple[int, int]] = {}
        self.inflection_rays: dict[str, tuple[ExactPoint, ExactPoint]] = {}
        for c in chains:
            first, last = c[0], c[-1]
            self._interval[f"R{first}"] = (self.ordering.index(f"v{first}"), self.ordering.index(f"r{first}"))
            self._interval[f"L{last}"] = (self.ordering.index(f"l{last}"), self.ordering.index(f"v{last}"))
            self.inflection_rays[f"R{first}"] = (pts[first], cut_at[(first, "r")].point)
            self.inflection_rays[f"L{last}"] = (pts[last], cut_at[(last, "l")].point)
        self._size = size
        rays: list[BitangentRay] = []
        for b in bitangents(env, pairs):
            for near, far, end in ((b.i, b.j, b.point_ij), (b.j, b.i, b.point_ji)):
                edges_side = orient(pts[far], pts[near], pts[(near - 1) % n])
                d = (pts[far][0] - pts[near][0], pts[far][1] - pts[near][1])  # looking past near towards far
                near_shadow, far_shadow = self._shadow_of(near, d), self._shadow_of(far, d)
                assert near_shadow is not None and far_shadow is not None  # a bitangent is no edge
                rays.append(BitangentRay(len(rays), near, far, pts[near], end, near_shadow, far_shadow, -edges_side))
        self.rays = tuple(rays)
        self._events: dict[tuple[str, str], list[tuple[Fraction, int, str, object]]] = {}

    def _shadow_of(self, v: int, d: ExactPoint) -> str | None:
        """The primitive of the shadow behind reflex vertex v seen along direction d: the pocket holds the edge
        at v angularly nearest to d (towards v − 1: a right primitive; towards v + 1: a left one)."""
        pts = self.env.exact_vertices
        n = len(pts)
        back = (pts[(v - 1) % n][0] - pts[v][0], pts[(v - 1) % n][1] - pts[v][1])
        ahead = (pts[(v + 1) % n][0] - pts[v][0], pts[(v + 1) % n][1] - pts[v][1])
        chain = self._chain[v]
        right, left = f"R{chain[0]}", f"L{chain[-1]}"
        for edge, other in ((back, left), (ahead, right)):
            if cross(d, edge) == 0:
                # along a cut (the edge's extension): the pocket beyond holds the other edge; along the edge
                # itself: nothing is hidden behind v
                return other if d[0] * edge[0] + d[1] * edge[1] < 0 else None
        return right if _cot(d, back) > _cot(d, ahead) else left

    def _blocked(self, ray: BitangentRay, m: ExactPoint) -> bool:
        """From v_near + εm (ε → 0), do the walls at the near vertex hide the far vertex?"""
        pts = self.env.exact_vertices
        n = len(pts)
        v = pts[ray.near]
        d = (pts[ray.far][0] - v[0], pts[ray.far][1] - v[1])
        walls = [(pts[(ray.near + k) % n][0] - v[0], pts[(ray.near + k) % n][1] - v[1]) for k in (-1, 1)]
        u, w = (m, d) if cross(m, d) > 0 else (d, m)  # the sweep from p's direction to the far one, CCW
        return any(cross(u, e) > 0 and cross(e, w) > 0 for e in walls)

    def active(self, label: str) -> frozenset[str]:
        """The primitives active at a point of the cut ordering."""
        k = self.ordering.index(label)
        out = set()
        for prim, (a, b) in self._interval.items():
            inside = a < k < b if a < b else (k > a or k < b)
            if inside:
                out.add(prim)
        return frozenset(out)

    def events(self, x: str, y: str, p0: ExactPoint, p1: ExactPoint) -> list[tuple[Fraction, int, str, object]]:
        """The events of the motion from point x to point y (straight, p0 → p1), in the order they happen
        (coinciding ones in Lemma 16's order): ``(parameter, rank, kind, primitive or ray)``."""
        key = (x, y)
        if key in self._events:
            return self._events[key]
        out: list[tuple[Fraction, int, str, object]] = []
        before, after = self.active(x), self.active(y)
        for prim, (a, b) in self.inflection_rays.items():
            if (prim in before) == (prim in after):
                continue
            meet = segment_intersection(p0, p1, a, b)
            if meet is None:  # pragma: no cover - activity changes only across the inflection
                raise SolverFailed(f"primitive {prim} changes from {x} to {y} without crossing its inflection")
            params = [_param(p0, p1, q) for q in meet.points]
            kind = "appear" if prim in after else "disappear"
            s = max(params) if kind == "appear" else min(params)
            out.append((s, _ORDER[kind], kind, prim))
        for ray in self.rays:
            meet = segment_intersection(p0, p1, ray.start, ray.end)
            if meet is None or meet.kind != "point":
                continue
            (q,) = meet.points
            s = _param(p0, p1, q)
            far, near = self.env.exact_vertices[ray.far], ray.start
            side0, side1 = orient(far, near, p0), orient(far, near, p1)
            # a motion that starts or ends on the ray does so at its near vertex (general position), and standing
            # there the pursuer sees the far shadow on its own: leaving it to the merge side merges, arriving
            # from the merge side splits
            # (there the near shadow is the one behind the near vertex seen along the motion, not along the ray)
            # — and from a point p next to it, the near vertex hides the far one exactly when the walls at the
            # near vertex lie between the directions to p and to the far vertex
            near_primitive = ray.near_primitive
            m = (p1[0] - p0[0], p1[1] - p0[1])
            if s == 0:
                kind = "merge" if self._blocked(ray, m) else ""
                look = (-m[0], -m[1])
            elif s == 1:
                kind = "split" if self._blocked(ray, (-m[0], -m[1])) else ""
                look = m
            else:
                kind = "split" if side1 == ray.split_side else "merge"
                look = None
            if kind and look is not None:
                found = self._shadow_of(ray.near, look)
                if found is None:
                    raise SolverFailed(f"a bitangent ray of vertices {ray.near} and {ray.far} starts where the "
                                       f"pursuer moves along an edge at vertex {ray.near}: not supported")
                near_primitive = found
            if kind:
                out.append((s, _ORDER[kind], kind, (ray, near_primitive)))
        out.sort(key=lambda e: (e[0], e[1]))
        self._events[key] = out
        return out

    def apply(self, x: str, y: str, p0: ExactPoint, p1: ExactPoint, status: PrimitiveState) -> PrimitiveState:
        """The pursuit status after moving from x to y."""
        merges, ones = set(status[0]), set(status[1])
        active = set(self.active(x))
        for _, _, kind, what in self.events(x, y, p0, p1):
            if kind == "appear":
                assert isinstance(what, str)
                active.add(what)
                ones.discard(what)
            elif kind == "disappear":
                assert isinstance(what, str)
                active.discard(what)
                ones.discard(what)
                merges = {m for m in merges if what not in m[1:]}
            else:
                assert isinstance(what, tuple)
                ray: BitangentRay = what[0]
                near: str = what[1]
                if kind == "split":
                    merges = {m for m in merges if m[0] != ray.index}
                elif ray.far_primitive in active and near in active:
                    group = _component(merges, ray.far_primitive) | _component(merges, near)
                    if ray.far_primitive not in _component(merges, near):
                        merges.add((ray.index, ray.far_primitive, near))
                    if group & ones:
                        ones |= group
        if active != self.active(y):  # pragma: no cover - the crossings follow from the ordering
            raise SolverFailed(f"primitives after {x} → {y}: {sorted(active)} ≠ {sorted(self.active(y))}")
        return frozenset(merges), frozenset(ones)


def _component(merges: set[tuple[int, str, str]], prim: str) -> set[str]:
    """The primitives merged with ``prim`` (its compound)."""
    seen, todo = {prim}, [prim]
    while todo:
        p = todo.pop()
        for _, a, b in merges:
            for u, w in ((a, b), (b, a)):
                if u == p and w not in seen:
                    seen.add(w)
                    todo.append(w)
    return seen


def _param(p0: ExactPoint, p1: ExactPoint, x: ExactPoint) -> Fraction:
    c = 0 if p1[0] != p0[0] else 1
    return (x[c] - p0[c]) / (p1[c] - p0[c])
