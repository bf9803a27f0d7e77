"""Rooms and doors of a rectilinear polygon: the decomposition of Çağırıcı, Bahoo and LaValle (Algorithm 1).

For every reflex vertex v of a simple polygon P the algorithm draws a *bottleneck segment* (Def. 1): the
shortest segment from v to the closest point of an edge that lies inside P. Those segments are the
*virtual doors*; doors that are not horizontal or vertical are dropped (line 19), and of a chain of three
doors only the middle one is kept (lines 20–21). Cutting P along the doors gives the *rooms*; since P
has no holes, the rooms and doors form a tree (Remark 5).

Everything is exact (rational coordinates, exact lengths compared squared), so the answer does not depend
on rounding. The paper leaves some choices open; they are settled here as follows.

**Input.** P must be a simple polygon (no holes: Remark 5 and the room tree need it) whose edges are all
horizontal or vertical. Anything else is an :class:`~solverplan.errors.InvalidEnvironment` naming the first
offending hole or edge (no generalisation is attempted: line 19 would drop every door of a polygon without
axis-parallel doors, and the room rules assume rectangular walls). Collinear consecutive vertices are
allowed; they are not reflex.

**Iteration order and ties.** Reflex vertices are visited in the normalised vertex order (docs/contract.md:
the outer ring counter-clockwise from the file's first vertex), edges in edge order. Line 10 keeps a
candidate only when it is *strictly* shorter, so among segments of equal length the one to the edge that
comes first in edge order wins. The answer therefore depends on the vertex numbering only through ties.

**Edges incident to v.** Their closest point to v is v itself: a segment of length 0, never a candidate.

**A blocked closest point.** Line 7 looks at one point per edge, the closest one. When the segment to it
leaves P or touches the boundary before its end (it passes a vertex, or runs along an edge), that edge
offers no candidate at all, even if other points of it are visible from v: Def. 1's segment must lie inside
P and meet the boundary only at its ends, and the algorithm only ever looks at closest points. A reflex
vertex of a rectilinear polygon always has a valid candidate (the extension of either incident edge meets
the boundary perpendicularly, at the closest point of the edge or vertex it meets first).

**"Not already a door" (line 9).** The shortest valid segment of v is found first; if it is already a
door (drawn from its other end, e.g. two reflex vertices facing each other across a doorway), v is served
by that door and nothing is added. Read literally, line 9 would instead make v take its *next* shortest
segment, a second door at a vertex that already has one — typically a cut straight across the next room;
the paper's Fig. 5 (exactly one door at each end of a doorway) is what the reading here gives.

**Line 19** drops non-axis-parallel doors *after* the selection: a reflex vertex whose shortest segment is
diagonal ends up with no door, as in the paper's Fig. 2 (green segments).

**Crossing doors.** Prop. 2 says the segments never cross, but its proof lets a door end anywhere on an
edge while line 7 only ever ends one at an edge's *closest* point, and the two can differ: in the polygon
``(9,4) (9,0) (15,0) (15,2) (21,2) (21,4) (15,4) (15,7) (21,7) (21,13) (22,13) (22,18) (18,18) (18,17) (1,17)
(1,16) (9,16) (9,7) (3,7) (3,4)`` the door of (21, 13) runs up to (21, 18) (length 5; the point (22, 17) that
the proof would use is not the closest point of its edge) and crosses the door (18, 17)–(22, 17) of length 4.
Rooms need doors that do not cross, so after line 19 the doors are taken shortest first (ties in the order
found) and a door that crosses one already taken is dropped (reason ``"crossing"``). When Prop. 2 holds,
nothing is dropped. (That is in the vertex order as written; :func:`decompose_rooms` breaks ties between equally
short bottlenecks in the order of the straight walls — the ring from its canonical vertex, so that the rooms do not
depend on how the polygon is written — and there (21, 13) reaches (18, 17), a diagonal that line 19 drops.) Prop. 1 (two segments ab, bc span a triangle inside P) fails the same way, for diagonal
segments: (22, 20)–(18, 16) and (18, 16)–(14, 15) in ``(31,10) (31,22) (22,22) (22,20) (18,20) (18,16) (14,16)
(14,15) (10,15) (10,11) (18,11) (18,10)``; line 19 drops both, and no counterexample among the doors is known.

**Chains (lines 20–21).** Doors that share end points form a graph. It is cut into maximal chains at the
points where one door or three or more meet; a maximal chain of k ≥ 3 doors loses its first and its last
door ("we remove the first and the last edge of this chain") and keeps the k − 2 in between — for k = 3
that is line 21 exactly. Closed loops of doors have no first or last door and are kept whole.

**Splitting (line 23).** Doors never cross (Prop. 2; checked exactly), and each runs between two boundary
points through the interior, so the faces of the planar graph of boundary and doors are the rooms. With every
segment horizontal or vertical, a face is traced by taking, at each node, the first direction clockwise from
the way back.

**Numbering.** Rooms are numbered by their lowest vertex (smallest y, then smallest x); a room's polygon is
counter-clockwise from that vertex, without collinear vertices. Doors keep the order in which Algorithm 1
adds them (reflex vertex order); a door's ``a`` is its reflex vertex, ``b`` the closest point it reaches.

>>> from solverplan.environment import Environment
>>> ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
>>> rooms = decompose_rooms(ell)
>>> [room.polygon for room in rooms.rooms] == [((0, 0), (4, 0), (4, 2), (0, 2)), ((0, 2), (2, 2), (2, 4), (0, 4))]
True
>>> door = rooms.doors[0]     # the floor and the left wall tie at length 2: the first in the walls' canonical order wins
>>> door.a, door.b, door.rooms, door.length
((Fraction(2, 1), Fraction(2, 1)), (Fraction(0, 1), Fraction(2, 1)), (0, 1), Fraction(2, 1))
>>> [room.area for room in rooms.rooms], rooms.tree
([Fraction(8, 1), Fraction(4, 1)], ((0, 1),))
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from fractions import Fraction
from functools import cached_property
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidEnvironment, MalformedFile, SolverFailed
from solverplan.exact import (ExactPoint, exact_point, format_number, format_point, json_point, point_in_ring,
                              segment_intersection)
from solverplan.geometry.raycast import cast_ray
from solverplan.geometry.walls import StraightWalls
from solverplan.result import Construction, EnvironmentRecord, Method, Optimality, Stats, answer_dataclass
from typing import Any

__all__ = [
    "Door",
    "Room",
    "Decomposition",
    "decompose_rooms",
    "check_rectilinear",
    "bottleneck_segments",
]

def _direction(a: ExactPoint, b: ExactPoint) -> int:
    """The direction of the axis-parallel segment a → b as 0 (east), 1 (north), 2 (west) or 3 (south):
    counter-clockwise order, so turning clockwise by 90° is subtracting 1 (mod 4)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    if dy == 0:
        return 0 if dx > 0 else 2
    return 1 if dy > 0 else 3


def _length(a: ExactPoint, b: ExactPoint) -> Fraction:
    """Exact length of an axis-parallel segment."""
    return abs(b[0] - a[0]) + abs(b[1] - a[1])


def _ring_area(ring: tuple[ExactPoint, ...]) -> Fraction:
    n = len(ring)
    return sum((ring[i][0] * ring[(i + 1) % n][1] - ring[(i + 1) % n][0] * ring[i][1] for i in range(n)), Fraction(0)) / 2


def _on_segment(p: ExactPoint, a: ExactPoint, b: ExactPoint) -> bool:
    """Is ``p`` on the closed segment a–b (exact)?"""
    cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    return cross == 0 and min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def _ring_with_doors(polygon: list[ExactPoint], doors: list[tuple[ExactPoint, ExactPoint]]) -> tuple[list[ExactPoint], list[int]]:
    """A room's boundary with every door end point on it as a vertex, and what each piece is (−1 a wall, else the
    door id): the ``ring`` and ``sides`` of :class:`Room`, from its polygon and the doors (exact)."""
    ends = {p for door in doors for p in door}
    ring: list[ExactPoint] = []
    n = len(polygon)
    for k in range(n):
        a, b = polygon[k], polygon[(k + 1) % n]
        inner = [p for p in ends if p != a and p != b and _on_segment(p, a, b)]
        inner.sort(key=lambda p: abs(p[0] - a[0]) + abs(p[1] - a[1]))
        ring += [a, *inner]
    where = {frozenset(door): i for i, door in enumerate(doors)}
    sides = [where.get(frozenset((ring[k], ring[(k + 1) % len(ring)])), -1) for k in range(len(ring))]
    return ring, sides


def _simplify(ring: list[ExactPoint]) -> list[ExactPoint]:
    """The ring without collinear vertices (axis-parallel rings: a vertex where the direction does not change)."""
    n = len(ring)
    return [ring[i] for i in range(n) if _direction(ring[i - 1], ring[i]) != _direction(ring[i], ring[(i + 1) % n])]


# ---------------------------------------------------------------------- the answer
@dataclass(frozen=True, slots=True)
class Door:
    """A virtual door: the segment ``a`` – ``b`` between rooms ``rooms[0]`` and ``rooms[1]`` (ids, ascending).

    ``a`` is the reflex vertex it was drawn from (global vertex id ``vertex``), ``b`` the closest point of
    edge ``edge`` it reaches (``b_vertex`` when that point is a vertex of P). ``walls`` are the lengths of
    the wall the door lies on in each of its two rooms (in the order of ``rooms``): the maximal straight
    stretch of that room's boundary containing the door.
    """

    id: int
    a: ExactPoint
    b: ExactPoint
    vertex: int
    edge: int
    b_vertex: int | None
    rooms: tuple[int, int]
    walls: tuple[Fraction, Fraction]

    @property
    def length(self) -> Fraction:
        """The door's length (exact, length units of the environment)."""
        return _length(self.a, self.b)

    @property
    def horizontal(self) -> bool:
        return self.a[1] == self.b[1]

    def escapability(self, room: int) -> Fraction:
        """Φ of leaving ``room`` through this door: |door| / |wall it lies on in that room| (exact, in (0, 1])."""
        if room not in self.rooms:
            _not_a_side(self, room)
        return self.length / self.walls[self.rooms.index(room)]

    def other(self, room: int) -> int:
        """The room on the other side of the door from ``room``."""
        if room not in self.rooms:
            _not_a_side(self, room)
        return self.rooms[1] if self.rooms[0] == room else self.rooms[0]

    def to_json(self) -> dict:
        return {
            "id": self.id,
            "a": json_point(self.a),
            "b": json_point(self.b),
            "rooms": list(self.rooms),
            "length": float(self.length),
            # the door's Φ is the harder way through it (the chamber side: Fig. 5's 1/30); both sides follow
            "escapability": float(min(sides := [self.escapability(r) for r in self.rooms])),
            "escapability_exact": format_number(min(sides)),
            "escapability_by_room": [float(f) for f in sides],
            "escapability_by_room_exact": [format_number(f) for f in sides],
            "vertex": self.vertex,
        }


def _not_a_side(door: Door, room: int) -> None:
    raise InputError(f"room {room} is not a side of door {door.id} (it joins rooms {door.rooms[0]} and {door.rooms[1]})")


@dataclass(frozen=True, slots=True)
class Room:
    """A room: ``polygon`` (counter-clockwise, no collinear vertices, exact), its exact ``area``, and
    ``ring``: the same boundary with every door end point as a vertex, ``sides[k]`` saying what the
    piece ``ring[k]`` → ``ring[k + 1]`` is (``-1`` a wall, else the id of the door it is)."""

    id: int
    polygon: tuple[ExactPoint, ...]
    area: Fraction
    ring: tuple[ExactPoint, ...]
    sides: tuple[int, ...]

    @property
    def doors(self) -> tuple[int, ...]:
        """Ids of the room's doors, in boundary order."""
        return tuple(d for d in self.sides if d >= 0)

    @property
    def bounds(self) -> tuple[Fraction, Fraction, Fraction, Fraction]:
        """(xmin, ymin, xmax, ymax), exact."""
        xs = [p[0] for p in self.polygon]
        ys = [p[1] for p in self.polygon]
        return (min(xs), min(ys), max(xs), max(ys))

    @property
    def is_rectangle(self) -> bool:
        return len(self.polygon) == 4

    def to_json(self) -> dict:
        return {
            "id": self.id,
            "polygon": [json_point(p) for p in self.polygon],
            "area": float(self.area),
            "area_exact": format_number(self.area),
            "doors": list(self.doors),
        }


@answer_dataclass("rooms", eq=False)
class Decomposition(Construction):
    """The rooms and doors of a rectilinear polygon (Algorithm 1), with the room tree (Remark 5).

    Attributes
    ----------
    env
        The decomposed environment.
    rooms, doors
        :class:`Room` and :class:`Door` records; ids are positions in these tuples.
    dropped
        Segments Algorithm 1 found and then dropped, as ``(a, b, reason)`` with reason ``"diagonal"``
        (line 19), ``"crossing"`` (a door crossing a shorter one) or ``"chain"`` (lines 20–21).
    """

    env: Environment
    rooms: tuple[Room, ...]
    doors: tuple[Door, ...]
    dropped: tuple[tuple[ExactPoint, ExactPoint, str], ...] = ()
    stats: Stats = field(default_factory=Stats)

    # -- the result protocol

    @property
    def optimality(self) -> Optimality:
        return Optimality(Method.NONE, False, None, scope="a decomposition (Algorithm 1): nothing is optimised",
                          algorithm="Algorithm 1 of Çağırıcı, Bahoo and LaValle, exact arithmetic")

    @property
    def environment(self) -> EnvironmentRecord:
        return EnvironmentRecord.of(self.env)

    # -- structure
    @cached_property
    def room_environments(self) -> tuple[Environment, ...]:
        """Each room as an environment of its own: its sides in counter-clockwise order, door end points included
        as vertices (so every side is all wall or all door: side k of room r is ``rooms[r].sides[k]``)."""
        return tuple(Environment.from_coords(room.ring, name=f"{self.env.name} room {room.id}") for room in self.rooms)

    @property
    def tree(self) -> tuple[tuple[int, int], ...]:
        """The room adjacency tree as sorted room-id pairs, one per door (Remark 5)."""
        return tuple(sorted(door.rooms for door in self.doors))

    @cached_property
    def neighbours(self) -> dict[int, tuple[tuple[int, int], ...]]:
        """For each room, its ``(neighbour room, door id)`` pairs."""
        out: dict[int, list[tuple[int, int]]] = {room.id: [] for room in self.rooms}
        for door in self.doors:
            i, j = door.rooms
            out[i].append((j, door.id))
            out[j].append((i, door.id))
        return {k: tuple(sorted(v)) for k, v in out.items()}

    def door_between(self, i: int, j: int) -> Door:
        """The door joining rooms ``i`` and ``j``; :class:`InputError` if they are not neighbours."""
        self.check_room(i)
        self.check_room(j)
        for other, door in self.neighbours[i]:
            if other == j:
                return self.doors[door]
        raise InputError(f"rooms {i} and {j} do not share a door")

    def check_room(self, room: object) -> int:
        """``room`` as a room id, or a one-line :class:`InputError`."""
        if isinstance(room, bool) or not isinstance(room, int) or not 0 <= room < len(self.rooms):
            raise InputError(f"unknown room {room!r}: rooms are 0..{len(self.rooms) - 1}")
        return room

    def path(self, start: int, goal: int) -> tuple[int, ...]:
        """The unique sequence of rooms from ``start`` to ``goal`` in the room tree (Remark 5), both included."""
        self.check_room(start)
        self.check_room(goal)
        parent = {start: -1}
        stack = [start]
        while stack:
            room = stack.pop()
            for other, _ in self.neighbours[room]:
                if other not in parent:
                    parent[other] = room
                    stack.append(other)
        rooms = [goal]
        while rooms[-1] != start:
            rooms.append(parent[rooms[-1]])
        return tuple(reversed(rooms))

    def tour(self, start: int) -> tuple[int, ...]:
        """A walk through every room from ``start`` (depth first, neighbours by id, back to each room after a
        branch): the room sequence of the polygon patrolling problem (Def. 4). Ends at the last room entered."""
        self.check_room(start)
        walk = [start]
        seen = {start}
        last_new = 0  # where the last room entered for the first time sits in the walk
        stack = [(start, iter(self.neighbours[start]))]  # depth first, without recursion (deep trees)
        while stack:
            room, children = stack[-1]
            for child, _ in children:
                if child not in seen:
                    seen.add(child)
                    walk.append(child)
                    last_new = len(walk) - 1
                    stack.append((child, iter(self.neighbours[child])))
                    break
            else:
                stack.pop()
                if stack:
                    walk.append(stack[-1][0])  # back to the parent
        return tuple(walk[: last_new + 1])

    def room_of(self, point: tuple[object, object]) -> int:
        """The room containing ``point`` (exact; a point on a door belongs to the lower room id); :class:`InputError` outside P."""
        p = exact_point(point, where="point")
        for room in self.rooms:
            if point_in_ring(p, room.polygon) >= 0:
                return room.id
        raise InputError(f"point {format_point(p)} is not in the polygon")

    # -- answers
    def _fields(self) -> dict:
        return {
            "rooms": [room.to_json() for room in self.rooms],
            "doors": [door.to_json() for door in self.doors],
            "tree": [list(edge) for edge in self.tree],
            "dropped": [{"a": json_point(a), "b": json_point(b),
                         "reason": reason} for a, b, reason in self.dropped],
        }

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> Decomposition:
        """Read a rooms answer back in ``env`` (required: doors are drawn from its vertices to its edges).

        Room rings (door end points as vertices) and each door's edge and walls are recomputed exactly from the
        polygons, the doors and their exact Φ (the answer's claims are checked by the rooms checker of ``solverplan
        rooms --check``, not here)."""
        r, env, _ = cls._reader_in(data, env, "rooms")
        verts = env.exact_vertices
        doors_raw = r.items("doors")
        segments = [(d.exact_pair("a"), d.exact_pair("b")) for d in doors_raw]
        rooms = []
        for k, room in enumerate(r.items("rooms")):
            polygon = room.points("polygon")
            ring, sides = _ring_with_doors(polygon, segments)
            rooms.append(Room(room.integer("id"), tuple(polygon), room.exact("area_exact"), tuple(ring), tuple(sides)))
        doors = []
        for k, (d, (a, b)) in enumerate(zip(doors_raw, segments)):
            pair = d.ints("rooms")
            phi = d.at("escapability_by_room_exact", d.array("escapability_by_room_exact"))
            if len(pair) != 2 or a == b:
                raise MalformedFile(f"rooms.doors[{k}]: expected two rooms and two distinct end points")
            length = _length(a, b)
            walls = (length / phi.exact(0), length / phi.exact(1))
            edge = next((i for i in range(env.n_edges) if _on_segment(b, env.edge(i).a, env.edge(i).b)), -1)
            doors.append(Door(d.integer("id"), a, b, d.integer("vertex"), edge, verts.index(b) if b in verts else None,
                              (pair[0], pair[1]), walls))
        dropped = tuple((x.exact_pair("a"), x.exact_pair("b"), x.string("reason")) for x in r.items("dropped"))
        return cls(env, tuple(rooms), tuple(doors), dropped, r.stats())

    def to_text(self, *, width: int = 100) -> str:
        def count(n: int, noun: str) -> str:
            return f"{n} {noun}" + ("" if n == 1 else "s")

        lines = [f"{count(len(self.rooms), 'room')} and {count(len(self.doors), 'door')} in "
                 f"{self.env.name or 'the environment'} (Algorithm 1; {count(len(self.dropped), 'segment')} dropped)"]
        lines.append("rooms:")
        for room in self.rooms:
            x0, y0, x1, y1 = room.bounds
            shape = "rectangle" if room.is_rectangle else f"{len(room.polygon)} vertices"
            lines.append(f"  {room.id:>3}  area {format_number(room.area):>10}  {shape:<12} "
                         f"[{format_number(x0)}, {format_number(x1)}] × [{format_number(y0)}, {format_number(y1)}]  "
                         f"doors {', '.join(map(str, room.doors)) or '-'}")
        lines.append("doors:")
        for door in self.doors:
            i, j = door.rooms
            lines.append(f"  {door.id:>3}  {format_point(door.a)} – {format_point(door.b)}  rooms {i}–{j}  "
                         f"length {format_number(door.length)}  Φ {format_number(door.escapability(i))} from {i}, "
                         f"{format_number(door.escapability(j))} from {j}")
        return "\n".join(line[:width] if len(line) > width else line for line in lines) + "\n"


# ---------------------------------------------------------------------- input
def check_rectilinear(env: Environment) -> None:
    """Raise :class:`InvalidEnvironment` unless ``env`` is a simple polygon without holes with only
    horizontal and vertical edges (what Algorithm 1 and the room tree need)."""
    if env.holes:
        raise InvalidEnvironment(
            f"rooms need a polygon without holes (the room tree of Remark 5 does not exist otherwise): "
            f"{env.name or 'the environment'} has {len(env.holes)} hole{'s' if len(env.holes) > 1 else ''}")
    for edge in env.edges:
        if edge.a[0] != edge.b[0] and edge.a[1] != edge.b[1]:
            raise InvalidEnvironment(
                f"rooms need a rectilinear polygon: edge {edge.id} from {format_point(edge.a)} to "
                f"{format_point(edge.b)} is neither horizontal nor vertical")


# ---------------------------------------------------------------------- Algorithm 1, lines 3–17
def _closest_point(v: ExactPoint, a: ExactPoint, b: ExactPoint) -> ExactPoint:
    """The point of the axis-parallel segment a–b closest to v (exact): v's coordinate along it, clamped."""
    if a[1] == b[1]:
        return (min(max(v[0], min(a[0], b[0])), max(a[0], b[0])), a[1])
    return (a[0], min(max(v[1], min(a[1], b[1])), max(a[1], b[1])))


def _along(v: ExactPoint, p: ExactPoint, w: ExactPoint) -> bool:
    """Does the segment v → p start along the segment v → w (same direction)?"""
    d, e = (p[0] - v[0], p[1] - v[1]), (w[0] - v[0], w[1] - v[1])
    return d[0] * e[1] == d[1] * e[0] and d[0] * e[0] + d[1] * e[1] > 0


def _inside(env: Environment, v_id: int, p: ExactPoint) -> bool:
    """Does the segment v–p (v = vertex ``v_id``) lie inside P, meeting the boundary only at its ends (Def. 1)?

    It must not start along an edge at v; then the exact ray from v towards p must leave v into the free
    space and reach p before any other boundary point (a vertex grazed on the way counts as touching).
    """
    verts = env.exact_vertices
    v = verts[v_id]
    if _along(v, p, verts[int(env.next_vertex[v_id])]) or _along(v, p, verts[int(env.prev_vertex[v_id])]):
        return False
    try:
        hit = cast_ray(env, v, (p[0] - v[0], p[1] - v[1]))
    except InputError:  # the segment leaves v into the obstacle
        return False
    return hit.s == 1


def bottleneck_segments(env: Environment) -> list[tuple[int, ExactPoint, int]]:
    """Lines 3–17 of Algorithm 1: for each reflex vertex (in vertex order), its bottleneck segment.

    Returns ``(vertex, p, edge)`` triples: the segment from vertex ``vertex`` to ``p``, the closest point of
    edge ``edge``, in the order the doors are added; a vertex whose segment is already a door adds nothing
    (module docstring). Diagonal segments are still in (line 19 drops them).
    """
    check_rectilinear(env)
    verts = env.exact_vertices
    nxt, prev = env.next_vertex, env.prev_vertex
    edges = [(i, verts[i], verts[int(nxt[i])]) for i in range(env.n_edges)]
    chosen: list[tuple[int, ExactPoint, int]] = []
    seen: set[frozenset[ExactPoint]] = set()
    for v_id in env.reflex_vertices:
        v = verts[v_id]
        candidates = []
        for i, a, b in edges:
            if i == v_id or i == int(prev[v_id]):
                continue  # the incident edges: closest point v itself, length 0
            p = _closest_point(v, a, b)
            d2 = (p[0] - v[0]) ** 2 + (p[1] - v[1]) ** 2
            candidates.append((d2, i, p))
        candidates.sort(key=lambda c: (c[0], c[1]))  # strictly shorter wins: equal lengths keep edge order
        for d2, i, p in candidates:
            if _inside(env, v_id, p):
                key = frozenset((v, p))
                if key not in seen:
                    seen.add(key)
                    chosen.append((v_id, p, i))
                break
    return chosen


# ---------------------------------------------------------------------- lines 19–22
def _chain_drops(segments: list[tuple[ExactPoint, ExactPoint]]) -> set[int]:
    """Indices of the segments lines 20–21 remove: the first and last door of every maximal chain of ≥ 3."""
    at: dict[ExactPoint, list[int]] = {}
    for k, (a, b) in enumerate(segments):
        at.setdefault(a, []).append(k)
        at.setdefault(b, []).append(k)
    used: set[int] = set()
    drop: set[int] = set()

    def walk(start: ExactPoint, first: int) -> list[int]:
        chain, point, seg = [], start, first
        while True:
            chain.append(seg)
            used.add(seg)
            a, b = segments[seg]
            point = b if point == a else a
            following = [s for s in at[point] if s != seg]
            if len(at[point]) != 2 or following[0] in used:
                return chain
            seg = following[0]

    # chains start at points where one, three or more doors meet
    for point in sorted(at):
        if len(at[point]) != 2:
            for seg in at[point]:
                if seg not in used:
                    chain = walk(point, seg)
                    if len(chain) >= 3:
                        drop.update((chain[0], chain[-1]))
    return drop  # what is left unused is closed loops of doors: kept whole


# ---------------------------------------------------------------------- line 23: SPLIT
def _faces(env: Environment, doors: list[tuple[ExactPoint, ExactPoint]]):
    """The faces of boundary + doors: for each, its node cycle and the door id (or −1) of each piece."""
    ring = list(env.outer)
    on_edge: dict[int, list[ExactPoint]] = {}
    for a, b in doors:
        for p in (a, b):
            if p in env.exact_vertices:
                continue
            edge, _ = env.locate(p)
            on_edge.setdefault(edge, []).append(p)
    nodes: list[ExactPoint] = []
    for i, v in enumerate(ring):
        nodes.append(v)
        w = ring[(i + 1) % len(ring)]
        inner = sorted(set(on_edge.get(i, [])), key=lambda p: _length(v, p))
        nodes.extend(p for p in inner if p != w)
    # out[node][direction] = (next node, door id or −1)
    out: dict[ExactPoint, dict[int, tuple[ExactPoint, int]]] = {}
    for k, p in enumerate(nodes):
        q = nodes[(k + 1) % len(nodes)]
        out.setdefault(p, {})[_direction(p, q)] = (q, -1)
    for d, (a, b) in enumerate(doors):
        out.setdefault(a, {})[_direction(a, b)] = (b, d)
        out.setdefault(b, {})[_direction(b, a)] = (a, d)
    used: set[tuple[ExactPoint, int]] = set()
    faces = []
    for p in nodes + [a for a, _ in doors] + [b for _, b in doors]:
        for direction in sorted(out[p]):
            if (p, direction) in used:
                continue
            cycle, sides = [], []
            node, d = p, direction
            while (node, d) not in used:
                used.add((node, d))
                target, door = out[node][d]
                cycle.append(node)
                sides.append(door)
                back = (d + 2) % 4
                node = target
                for turn in (1, 2, 3):  # the first direction clockwise from the way back
                    if (back - turn) % 4 in out[node]:
                        d = (back - turn) % 4
                        break
            faces.append((cycle, sides))
    return faces


def _wall_length(cycle: list[ExactPoint], k: int) -> Fraction:
    """Length of the maximal straight stretch of the face boundary containing piece k."""
    n = len(cycle)
    d = _direction(cycle[k], cycle[(k + 1) % n])
    lo, hi = k, k
    while _direction(cycle[(lo - 1) % n], cycle[lo]) == d and (lo - 1) % n != hi:
        lo = (lo - 1) % n
    while _direction(cycle[(hi + 1) % n], cycle[(hi + 2) % n]) == d and (hi + 1) % n != lo:
        hi = (hi + 1) % n
    return _length(cycle[lo], cycle[(hi + 1) % n])


def _crosses(s: tuple[ExactPoint, ExactPoint], t: tuple[ExactPoint, ExactPoint]) -> bool:
    """Do two doors meet anywhere but at a common end point?"""
    hit = segment_intersection(*s, *t)
    if hit is None:
        return False
    return not (hit.kind == "point" and hit.points[0] in s and hit.points[0] in t)


def _crossing_drops(segments: list[tuple[ExactPoint, ExactPoint]]) -> set[int]:
    """Indices of the segments that cross a shorter one (shortest first, ties in order): see "Crossing doors"."""
    order = sorted(range(len(segments)), key=lambda k: (_length(*segments[k]), k))
    taken: list[int] = []
    drop: set[int] = set()
    for k in order:
        if any(_crosses(segments[k], segments[j]) for j in taken):
            drop.add(k)
        else:
            taken.append(k)
    return drop


def _check_no_crossings(doors: list[tuple[ExactPoint, ExactPoint]]) -> None:
    """Doors meet at most at common end points (made so by :func:`_crossing_drops`); anything else is an internal error."""
    for i in range(len(doors)):
        for j in range(i + 1, len(doors)):
            if _crosses(doors[i], doors[j]):
                raise SolverFailed(f"doors {format_point(doors[i][0])}–{format_point(doors[i][1])} and "
                               f"{format_point(doors[j][0])}–{format_point(doors[j][1])} cross (Prop. 2 fails)")


def decompose_rooms(env: Environment) -> Decomposition:
    """Rooms and doors of a rectilinear polygon by Algorithm 1 (module docstring), exact.

    Parameters
    ----------
    env
        A polygon without holes whose edges are horizontal or vertical.

    Returns
    -------
    Decomposition
        Rooms (polygons, exact areas), doors (end points, the two rooms they join, wall lengths) and the
        room tree. The areas add up to the area of P exactly and there is one room more than doors
        (Remark 5); both are checked.

    Raises
    ------
    InvalidEnvironment
        For holes or an edge that is neither horizontal nor vertical.

    Notes
    -----
    Algorithm 1 runs on the straight walls of ``env`` (:class:`~solverplan.geometry.walls.StraightWalls`: collinear
    vertices merged, the ring from its canonical vertex), so that how the walls are written — collinear vertices,
    split edges, the first vertex, the orientation — changes neither the rooms nor the doors, nor which of equally
    short bottlenecks wins; door ids (in the order of their reflex vertices in ``env``) and vertex and edge numbers
    are then given in ``env``'s numbering.

    Examples
    --------
    >>> import solverplan as sp
    >>> rooms = sp.decompose_rooms(sp.load_environment("l_shape"))
    >>> [room.area for room in rooms.rooms], rooms.tree       # exact areas (square units); the tree's edges
    ([Fraction(40, 1), Fraction(24, 1)], ((0, 1),))
    >>> door = rooms.doors[0]
    >>> door.rooms, door.a, door.b                               # the door's end points
    ((0, 1), (Fraction(4, 1), Fraction(4, 1)), (Fraction(0, 1), Fraction(4, 1)))
    >>> sp.decompose_rooms(sp.load_environment("two_rooms"))
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidEnvironment: rooms need a rectilinear polygon: edge 2 from (10, 3) to (16, 2) is neither horizontal nor vertical
    """
    check_rectilinear(env)  # bad input is named in the file's numbering
    walls = StraightWalls(env)
    if not walls.identity:
        return _in_user_numbering(walls, decompose_rooms(walls.merged))
    started = time.perf_counter()
    found = bottleneck_segments(env)
    verts = env.exact_vertices
    segments = [(verts[v], p) for v, p, _ in found]
    dropped: list[tuple[ExactPoint, ExactPoint, str]] = []
    straight = [k for k, (a, b) in enumerate(segments) if a[0] == b[0] or a[1] == b[1]]
    dropped += [(segments[k][0], segments[k][1], "diagonal") for k in range(len(segments)) if k not in set(straight)]
    crossing = _crossing_drops([segments[k] for k in straight])
    dropped += [(segments[straight[pos]][0], segments[straight[pos]][1], "crossing") for pos in sorted(crossing)]
    straight = [k for pos, k in enumerate(straight) if pos not in crossing]
    chain = _chain_drops([segments[k] for k in straight])
    kept = [k for pos, k in enumerate(straight) if pos not in chain]
    dropped += [(segments[straight[pos]][0], segments[straight[pos]][1], "chain") for pos in sorted(chain)]
    door_segments = [segments[k] for k in kept]
    _check_no_crossings(door_segments)

    faces = _faces(env, door_segments)
    # the faces are the rooms; number them by their lowest vertex (y, then x)
    faces.sort(key=lambda face: min((p[1], p[0]) for p in face[0]))
    rooms: list[Room] = []
    door_rooms: dict[int, list[tuple[int, Fraction]]] = {}
    for room_id, (cycle, sides) in enumerate(faces):
        start = min(range(len(cycle)), key=lambda k: (cycle[k][1], cycle[k][0]))
        cycle, sides = cycle[start:] + cycle[:start], sides[start:] + sides[:start]
        polygon = _simplify(cycle)
        rooms.append(Room(room_id, tuple(polygon), _ring_area(tuple(cycle)), tuple(cycle), tuple(sides)))
        for k, door in enumerate(sides):
            if door >= 0:
                door_rooms.setdefault(door, []).append((room_id, _wall_length(cycle, k)))
    doors = []
    for d, k in enumerate(kept):
        v_id, p, edge = found[k]
        (r0, w0), (r1, w1) = sorted(door_rooms[d])
        b_vertex = verts.index(p) if p in verts else None
        doors.append(Door(d, verts[v_id], p, v_id, edge, b_vertex, (r0, r1), (w0, w1)))
    result = Decomposition(env, tuple(rooms), tuple(doors), tuple(dropped),
                           Stats(seconds_search=time.perf_counter() - started,
                                 counts={"reflex": len(env.reflex_vertices), "segments": len(segments)}))
    _check_remark_5(result)
    return result


def _in_user_numbering(walls: StraightWalls, dec: Decomposition) -> Decomposition:
    """A decomposition of the straight walls (:func:`decompose_rooms`) told in the user's numbering: each door's
    reflex vertex, the edge it reaches (the user edge holding its end ``b``) and ``b``'s vertex, if any; doors in the
    order of their reflex vertices. A door that Algorithm 1 also draws in the vertex order as written (every door
    but where a tie between equally short bottlenecks went the other way) keeps that drawing: a door between two
    reflex vertices starts at the one met first in the user's ring, as it always did."""
    env = walls.env
    verts = env.exact_vertices
    as_written = {frozenset((verts[v], p)): (v, p, e) for v, p, e in bottleneck_segments(env)}
    doors = []
    for door in dec.doors:
        same = as_written.get(frozenset((door.a, door.b)))
        if same is not None:
            v, p, e = same
            doors.append(replace(door, a=verts[v], b=p, vertex=v, edge=e))
        else:
            doors.append(replace(door, vertex=walls.user_vertex(door.vertex),
                                 edge=walls.user_edge_of_point(door.edge, door.b)))
    order = sorted(doors, key=lambda door: door.vertex)
    new_id = {door.id: k for k, door in enumerate(order)}
    doors = [replace(door, id=k, b_vertex=verts.index(door.b) if door.b in verts else None)
             for k, door in enumerate(order)]
    rooms = tuple(replace(room, sides=tuple(new_id.get(side, side) for side in room.sides)) for room in dec.rooms)
    return replace(dec, env=env, rooms=rooms, doors=tuple(doors))


def _check_remark_5(dec: Decomposition) -> None:
    """Remark 5 and the split, checked exactly: one room more than doors, rooms connected by the doors,
    areas adding up to the area of P. A failure is an internal error (never a silent wrong answer)."""
    if len(dec.rooms) != len(dec.doors) + 1:
        raise SolverFailed(f"{len(dec.rooms)} rooms for {len(dec.doors)} doors: the rooms do not form a tree")
    if sum((room.area for room in dec.rooms), Fraction(0)) != dec.env.area:
        raise SolverFailed("the room areas do not add up to the area of the polygon")
    if any(room.area <= 0 for room in dec.rooms):
        raise SolverFailed("a room has no positive area")
    reached = {0}
    stack = [0]
    while stack:
        for other, _ in dec.neighbours[stack.pop()]:
            if other not in reached:
                reached.add(other)
                stack.append(other)
    if len(reached) != len(dec.rooms):
        raise SolverFailed("the rooms are not connected by their doors")
