"""An independent exact check of a rooms answer (the JSON of ``solverplan rooms``): does it describe a valid
decomposition of the polygon into rooms by doors, with the right numbers?

It reads only the answer's numbers and the polygon, and re-derives every claim with the exact predicates of
:mod:`solverplan.exact` — none of the decomposition code runs — so a bug there cannot hide here:

1. **Doors.** Each door is horizontal or vertical, of positive length; its end ``a`` is a reflex vertex of P and
   ``b`` a point of the boundary; the open segment between them lies in the interior of P (no boundary vertex on
   it, no boundary edge meeting it, its midpoint inside).
2. **No crossings** (Prop. 2 as the answer needs it): two doors meet at most at a common end point.
3. **Rooms.** Each room polygon is rectilinear and simple with positive area, its vertices in P, and its area
   is as claimed; the areas add up to the area of P exactly (so rooms inside P that add up cannot overlap).
4. **Sides.** Every side of every room lies on the boundary of P or on a door, and each door is a side of
   exactly the two rooms it names.
5. **Tree** (Remark 5): one room more than doors, and the doors connect all rooms.
6. **Escapability.** Each door's ``escapability_exact`` is its length over the room's straight side containing it.

A check finds *all* failures, each naming the claim, the door or room, and what is wrong.

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear.decomposition import decompose_rooms
>>> env = load_environment("three_chambers")
>>> answer = decompose_rooms(env).to_json()
>>> check_rooms(env, answer).valid
True
>>> answer["doors"][0]["b"] = [30, 16]
>>> print(check_rooms(env, answer).failures[0])
door 0: end a (30, 14.5) to b (30, 16) does not run through the interior of the polygon
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from os import PathLike
from pathlib import Path

from solverplan.environment import Environment, read_json
from solverplan.errors import MalformedFile
from solverplan.limits import read_text_within_limits
from solverplan.exact import ExactPoint, format_number, format_point, on_segment, orient, point_in_ring, segment_intersection, signed_area2, to_fraction

__all__ = ["RoomsCheck", "check_rooms", "load_rooms_answer"]


@dataclass(frozen=True)
class RoomsCheck:
    """The verdict: ``valid`` when ``failures`` is empty; ``checked`` counts the claims examined."""

    failures: tuple[str, ...]
    checked: int

    @property
    def valid(self) -> bool:
        return not self.failures

    def to_json(self) -> dict:
        return {"valid": self.valid, "checked": self.checked, "failures": list(self.failures)}

    def to_text(self, *, width: int = 100) -> str:
        if self.valid:
            return f"valid: {self.checked} claims checked exactly\n"
        return "invalid:\n" + "".join(f"  {failure}\n" for failure in self.failures)


def load_rooms_answer(path: str | PathLike[str]) -> dict:
    """Read a rooms answer file (the JSON of ``solverplan rooms -o FILE``), numbers exact, within the input
    limits; :class:`~solverplan.errors.MalformedFile` for a missing, unreadable or non-JSON file."""
    file = Path(path)
    text = read_text_within_limits(file)
    try:
        data = read_json(text)
    except ValueError as exc:  # json.JSONDecodeError
        raise MalformedFile(f"{file}: not valid JSON ({str(exc).splitlines()[0][:80]})") from None
    if not isinstance(data, dict) or "rooms" not in data or "doors" not in data:
        raise MalformedFile(f"{file}: not a rooms answer (expected an object with rooms and doors)")
    return data


def _point(value: Any, where: str) -> ExactPoint:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise ValueError(f"{where}: expected [x, y], got {value!r}")
    return (to_fraction(value[0], where=where), to_fraction(value[1], where=where))


def _covered(p: ExactPoint, q: ExactPoint, pieces: list[tuple[ExactPoint, ExactPoint]]) -> bool:
    """Is the axis-parallel segment p–q covered by the union of the collinear ``pieces``?"""
    horizontal = p[1] == q[1]
    axis = 0 if horizontal else 1
    lo, hi = sorted((p[axis], q[axis]))
    spans = sorted(sorted((a[axis], b[axis])) for a, b in pieces
                   if orient(a, b, p) == 0 and orient(a, b, q) == 0 and (a[1] == b[1]) == horizontal and a != b)
    reach = lo
    for a, b in spans:
        if a > reach:
            break
        reach = max(reach, b)
        if reach >= hi:
            return True
    return reach >= hi


def check_rooms(env: Environment, answer: dict) -> RoomsCheck:
    """Check a rooms answer (``Decomposition.to_json()`` or the JSON of ``solverplan rooms``) against ``env``."""
    failures: list[str] = []
    checked = 0
    ring = list(env.outer)
    edges = list(zip(ring, ring[1:] + ring[:1]))
    reflex = {env.exact_vertices[v] for v in env.reflex_vertices}
    try:
        doors = [(_point(d["a"], f"door {k} a"), _point(d["b"], f"door {k} b"), tuple(d["rooms"]), d) for k, d in enumerate(answer["doors"])]
        rooms = [([_point(p, f"room {k} vertex") for p in r["polygon"]], to_fraction(r.get("area_exact", r["area"]), where=f"room {k} area"))
                 for k, r in enumerate(answer["rooms"])]
    except (KeyError, TypeError, ValueError) as exc:
        return RoomsCheck((f"malformed answer: {exc}",), 0)

    # 1. doors
    for k, (a, b, _, _) in enumerate(doors):
        checked += 1
        where = f"door {k}: end a {format_point(a)} to b {format_point(b)}"
        if a == b or (a[0] != b[0] and a[1] != b[1]):
            failures.append(f"{where} is not a horizontal or vertical segment of positive length")
            continue
        if a not in reflex:
            failures.append(f"{where}: a is not a reflex vertex of the polygon")
        if not any(on_segment(b, u, w) for u, w in edges):
            failures.append(f"{where}: b is not on the boundary")
        middle = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        blocked = any(v not in (a, b) and on_segment(v, a, b) for v in ring)
        for u, w in edges:
            hit = segment_intersection(a, b, u, w)
            if hit is not None and (hit.kind == "overlap" or hit.points[0] not in (a, b)):
                blocked = True
        if blocked or point_in_ring(middle, ring) != 1:
            failures.append(f"{where} does not run through the interior of the polygon")
    # 2. no crossings
    for i in range(len(doors)):
        for j in range(i + 1, len(doors)):
            checked += 1
            s, t = doors[i][:2], doors[j][:2]
            hit = segment_intersection(*s, *t)
            if hit is not None and not (hit.kind == "point" and hit.points[0] in s and hit.points[0] in t):
                failures.append(f"doors {i} and {j} cross")
    # 3. rooms
    total = Fraction(0)
    for k, (polygon, area) in enumerate(rooms):
        checked += 1
        sides = list(zip(polygon, polygon[1:] + polygon[:1]))
        if len(polygon) < 4 or any(p == q or (p[0] != q[0] and p[1] != q[1]) for p, q in sides):
            failures.append(f"room {k}: its polygon is not rectilinear")
            continue
        try:
            Environment.from_coords(polygon)
        except ValueError as exc:
            failures.append(f"room {k}: its polygon is not simple ({exc})")
            continue
        real = signed_area2(polygon) / 2
        if real <= 0:
            failures.append(f"room {k}: its polygon is clockwise or flat (area {format_number(real)})")
        if real != area:
            failures.append(f"room {k}: area {format_number(area)} claimed, {format_number(real)} exactly")
        if any(point_in_ring(p, ring) < 0 for p in polygon):
            failures.append(f"room {k}: a vertex lies outside the polygon")
        total += real
    checked += 1
    if total != env.area:
        failures.append(f"the room areas add up to {format_number(total)}, the polygon's area is {format_number(env.area)}")
    # 4. sides: on the boundary or on a door; each door a side of exactly its two rooms
    door_segments = [(a, b) for a, b, _, _ in doors]
    for k, (polygon, _) in enumerate(rooms):
        for p, q in zip(polygon, polygon[1:] + polygon[:1]):
            checked += 1
            if p == q or (p[0] != q[0] and p[1] != q[1]):
                continue
            if not _covered(p, q, edges + door_segments):
                failures.append(f"room {k}: its side {format_point(p)}–{format_point(q)} is neither wall nor door")
    for k, (a, b, named, _) in enumerate(doors):
        checked += 1
        sides_of = [r for r, (polygon, _) in enumerate(rooms)
                    if any(on_segment(a, p, q) and on_segment(b, p, q) for p, q in zip(polygon, polygon[1:] + polygon[:1]))]
        if sorted(sides_of) != sorted(named):
            failures.append(f"door {k} lies on a side of rooms {sides_of}; the answer says it joins rooms {list(named)}")
    # 5. tree
    checked += 1
    n_rooms = len(rooms)
    if n_rooms != len(doors) + 1:
        failures.append(f"{n_rooms} rooms for {len(doors)} doors: the rooms cannot form a tree")
    reached, stack = {0}, [0]
    while stack and n_rooms:
        room = stack.pop()
        for _, _, named, _ in doors:
            if room in named:
                for other in named:
                    if other not in reached and isinstance(other, int) and 0 <= other < n_rooms:
                        reached.add(other)
                        stack.append(other)
    if n_rooms and len(reached) != n_rooms:
        failures.append(f"the doors connect {len(reached)} of the {n_rooms} rooms")
    # 6. escapability
    for k, (a, b, named, data) in enumerate(doors):
        claimed = data.get("escapability_by_room_exact")
        if claimed is None:
            continue
        for side, room in enumerate(named):
            checked += 1
            if not (isinstance(room, int) and 0 <= room < n_rooms):
                failures.append(f"door {k}: unknown room {room!r}")
                continue
            wall = _wall(rooms[room][0], a, b)
            if wall is None:
                continue  # reported above: the door is not a side of that room
            expected = (abs(b[0] - a[0]) + abs(b[1] - a[1])) / wall
            if to_fraction(claimed[side], where=f"door {k} escapability") != expected:
                failures.append(f"door {k}: escapability from room {room} claimed {claimed[side]}, "
                                f"{format_number(expected)} exactly")
    return RoomsCheck(tuple(failures), checked)


def _wall(polygon: list[ExactPoint], a: ExactPoint, b: ExactPoint) -> Fraction | None:
    """Length of the side of ``polygon`` (no collinear vertices) that contains the segment a–b."""
    for p, q in zip(polygon, polygon[1:] + polygon[:1]):
        if on_segment(a, p, q) and on_segment(b, p, q):
            return abs(q[0] - p[0]) + abs(q[1] - p[1])
    return None
