"""Exact check of a ``rooms`` certificate: doors, rooms, the room tree, areas, escapability Φ and reachability Ψ.

The claims (``claims`` block; coordinates and numbers exact):

- ``rooms``: ``[{"id", "polygon": [[x, y], ...] (CCW), "area"}]``, ids 0 … m − 1 in order;
- ``doors``: ``[{"id", "a", "b", "rooms": [i, j], "length", "escapability": [Φ(i → j), Φ(j → i)]}]``;
- ``tree``: the room pairs the doors join, ascending (``[[i, j], ...]``, i < j);
- ``area``: the polygon's area;
- ``reachability``: ``{"from": s, "to": [{"room", "path": [s, ..., room], "psi"}, ...]}`` for every room.

What is re-derived (all exactly, nothing trusted):

1. **Doors** are horizontal or vertical segments of positive length ``length``; ``a`` is a reflex vertex of the
   polygon, ``b`` a boundary point, and the open door lies in the interior (no boundary point on it, its midpoint
   inside). Two doors meet at most in a common end point.
2. **Rooms** are rectilinear simple counter-clockwise polygons of the claimed ``area``; every side of every room
   lies on the boundary of the polygon or on doors (so, the polygon being simply connected, each room lies in
   it); no door enters a room's interior; no two rooms share an interior point; the areas add up to the area of
   the polygon. Then the rooms are faces of the subdivision of the polygon by the doors, each once, and as their
   areas add up to the whole, **they tile the polygon**.
3. Each door is a side of exactly the two rooms it names; there is one room more than doors and the doors connect
   every room: the rooms and doors form **a tree** (Remark 5); ``tree`` lists exactly its edges.
4. **Φ** of leaving room i through a door is |door| / |wall|, the wall being the maximal straight stretch of room
   i's boundary containing the door; **Ψ** along the unique tree path from ``from`` to each room is the product
   of the Φ of the doors crossed, each from the room being left. Both must equal the claims exactly.

The polygon must have no holes (the room tree exists only then).
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.check_models import (Malformed, ModelChecker, Reader as R, apart, area2, box, inside_open, param_on, pt,
                                             segment_crosses_open, text)
from solverplan.certify.exact2d import on_closed_segment, orient
from solverplan.certify.schema import Point

__all__ = ["check"]


def _inside_strictly(p: Point, ring: list[Point]) -> bool:
    if any(on_closed_segment(p, ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))):
        return False
    return inside_open(p, ring)


def _covered(p: Point, q: Point, pieces: list[tuple[Point, Point]]) -> bool:
    """Is the axis-parallel segment p–q covered by the union of the collinear axis-parallel ``pieces``?"""
    horizontal = p[1] == q[1]
    axis = 0 if horizontal else 1
    lo, hi = sorted((p[axis], q[axis]))
    spans = sorted(sorted((a[axis], b[axis])) for a, b in pieces
                   if a != b and orient(a, b, p) == 0 and orient(a, b, q) == 0)
    reach = lo
    for a, b in spans:
        if a > reach:
            break
        reach = max(reach, b)
    return reach >= hi


def _simple(ring: list[Point]) -> bool:
    n = len(ring)
    sides = [(ring[i], ring[(i + 1) % n]) for i in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            (a, b), (c, d) = sides[i], sides[j]
            if j == i + 1 or (i == 0 and j == n - 1):
                shared = b if j == i + 1 else a
                other_i, other_j = (a, d) if j == i + 1 else (b, c)
                if orient(other_i, shared, other_j) == 0 and on_closed_segment(other_j, shared, other_i) or \
                        orient(other_i, shared, other_j) == 0 and on_closed_segment(other_i, shared, other_j):
                    return False  # folds back
                continue
            if _meet(a, b, c, d):
                return False
    return True


def _meet(a: Point, b: Point, c: Point, d: Point) -> bool:
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return ((o1 == 0 and on_closed_segment(c, a, b)) or (o2 == 0 and on_closed_segment(d, a, b))
            or (o3 == 0 and on_closed_segment(a, c, d)) or (o4 == 0 and on_closed_segment(b, c, d)))


def _touch_at_common_end(a: Point, b: Point, p: Point, q: Point) -> bool:
    """Do the closed segments ab and pq (which meet) meet only in an end point of both?"""
    common = {a, b} & {p, q}
    if len(common) != 1:
        return False
    (x,) = common
    far_ab = b if x == a else a
    far_pq = q if x == p else p
    if orient(a, b, p) == 0 and orient(a, b, q) == 0:  # collinear: they must leave x in opposite directions
        return (far_ab[0] - x[0]) * (far_pq[0] - x[0]) + (far_ab[1] - x[1]) * (far_pq[1] - x[1]) < 0
    return True  # not collinear: their one common point is x


def _length(a: Point, b: Point) -> Fraction:
    return abs(b[0] - a[0]) + abs(b[1] - a[1])  # axis-parallel


def _wall(polygon: list[Point], a: Point, b: Point) -> Fraction | None:
    """The length of the maximal straight stretch of ``polygon``'s boundary containing the segment a–b."""
    n = len(polygon)
    for i in range(n):
        p, q = polygon[i], polygon[(i + 1) % n]
        if on_closed_segment(a, p, q) and on_closed_segment(b, p, q):
            lo, hi = i, (i + 1) % n
            steps = 0
            while orient(polygon[lo - 1], polygon[lo], polygon[hi]) == 0 and steps < n:
                lo = (lo - 1) % n
                steps += 1
            while orient(polygon[lo], polygon[hi], polygon[(hi + 1) % n]) == 0 and steps < 2 * n:
                hi = (hi + 1) % n
                steps += 1
            return _length(polygon[lo], polygon[hi])
    return None


def _tree_paths(m: int, adjacency: dict[int, list[tuple[int, int]]], root: int) -> dict[int, list[int]]:
    paths = {root: [root]}
    stack = [root]
    while stack:
        room = stack.pop()
        for other, _ in adjacency.get(room, []):
            if other not in paths:
                paths[other] = paths[room] + [other]
                stack.append(other)
    return paths


def check(c: ModelChecker) -> None:
    env = c.env
    assert env is not None
    claims = c.cert.claims
    if len(env.rings) != 1:
        c.fail("environment", f"has {len(env.rings) - 1} holes: rooms and their tree need a polygon without holes")
        return
    ring = env.outer
    edges = env.edges
    reflex = {ring[i] for i in env.reflex()}
    raw_rooms = R.lst(R.field(claims, "rooms", "claims"), "claims.rooms")
    raw_doors = R.lst(R.field(claims, "doors", "claims"), "claims.doors")
    rooms: list[tuple[list[Point], Fraction | None]] = []
    for k, raw in enumerate(raw_rooms):
        where = f"claims.rooms[{k}]"
        obj = R.obj(raw, where)
        if R.integer(R.field(obj, "id", where), f"{where}.id") != k:
            c.fail(f"{where}.id", f"is {obj['id']}, rooms are numbered 0, 1, … in order")
        area_raw = c.optional(obj, "area", where)
        rooms.append((R.ring(R.field(obj, "polygon", where), f"{where}.polygon"),
                      None if area_raw is None else R.number(area_raw, f"{where}.area")))
    doors: list[tuple[Point, Point, tuple[int, int], Fraction | None, list[Fraction] | None]] = []
    m = len(rooms)
    for k, raw in enumerate(raw_doors):
        where = f"claims.doors[{k}]"
        obj = R.obj(raw, where)
        if R.integer(R.field(obj, "id", where), f"{where}.id") != k:
            c.fail(f"{where}.id", f"is {obj['id']}, doors are numbered 0, 1, … in order")
        named_raw = R.lst(R.field(obj, "rooms", where), f"{where}.rooms")
        if len(named_raw) != 2:
            raise Malformed(f"{where}.rooms", "a door joins two rooms")
        pair = (R.integer(named_raw[0], f"{where}.rooms[0]"), R.integer(named_raw[1], f"{where}.rooms[1]"))
        if not all(0 <= r < m for r in pair) or pair[0] == pair[1]:
            raise Malformed(f"{where}.rooms", f"{list(pair)} are not two different rooms of 0 … {m - 1}")
        phis_raw = c.optional(obj, "escapability", where)
        phis = None if phis_raw is None else R.lst(phis_raw, f"{where}.escapability")
        if phis is not None and len(phis) != 2:
            raise Malformed(f"{where}.escapability", "one Φ per room of the door")
        length_raw = c.optional(obj, "length", where)
        doors.append((R.point(R.field(obj, "a", where), f"{where}.a"), R.point(R.field(obj, "b", where), f"{where}.b"), pair,
                      None if length_raw is None else R.number(length_raw, f"{where}.length"),
                      None if phis is None else [R.number(phis[i], f"{where}.escapability[{i}]") for i in range(2)]))
    area_raw = c.optional(claims, "area", "claims")
    area_claim = None if area_raw is None else R.number(area_raw, "claims.area")
    c.summary = {"rooms": m, "doors": len(doors), "area": "not stated" if area_claim is None else text(area_claim)}
    if c.partial and (any(d[3] is None or d[4] is None for d in doors) or any(r[1] is None for r in rooms)):
        c.not_checked.append("exact lengths, areas or Φ the answer does not state")

    # 1. doors
    for k, (a, b, _, length, _) in enumerate(doors):
        c.count("doors")
        where = f"claims.doors[{k}]"
        if a == b or (a[0] != b[0] and a[1] != b[1]):
            c.fail(where, f"{pt(a)}–{pt(b)} is not a horizontal or vertical segment of positive length")
            continue
        if length is not None and length != _length(a, b):
            c.fail(f"{where}.length", f"claims {text(length)}, the door is {text(_length(a, b))} long")
        if a not in reflex:
            c.fail(f"{where}.a", f"{pt(a)} is not a reflex vertex of the polygon")
        if not env.on_boundary(b):
            c.fail(f"{where}.b", f"{pt(b)} is not on the boundary")
        middle = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        blocked = any(v not in (a, b) and on_closed_segment(v, a, b) for v in ring)
        blocked = blocked or any(segment_crosses_open(a, b, u, w) for u, w in edges)
        if blocked or env.locate(middle) != 1:
            c.fail(where, f"{pt(a)}–{pt(b)} does not run through the interior of the polygon")
    for i in range(len(doors)):
        for j in range(i + 1, len(doors)):
            c.count("door_pairs")
            (a, b), (p, q) = doors[i][:2], doors[j][:2]
            if _meet(a, b, p, q) and not _touch_at_common_end(a, b, p, q):
                c.fail(f"claims.doors[{j}]", f"crosses or overlaps door {i}")
    # 2. rooms
    total = Fraction(0)
    door_segments = [(a, b) for a, b, *_ in doors]
    good_rooms: list[int] = []
    for k, (polygon, area) in enumerate(rooms):
        c.count("rooms")
        where = f"claims.rooms[{k}]"
        sides = list(zip(polygon, polygon[1:] + polygon[:1]))
        if len(polygon) < 4 or any(p == q or (p[0] != q[0] and p[1] != q[1]) for p, q in sides):
            c.fail(f"{where}.polygon", "is not rectilinear")
            continue
        if not _simple(polygon):
            c.fail(f"{where}.polygon", "is not simple")
            continue
        real = area2(polygon) / 2
        if real <= 0:
            c.fail(f"{where}.polygon", f"is clockwise or flat (signed area {text(real)})")
            continue
        if area is not None and real != area:
            c.fail(f"{where}.area", f"claims {text(area)}, the room's area is {text(real)}")
        total += real
        for p, q in sides:
            c.count("room_sides")
            if not _covered(p, q, edges + door_segments):
                c.fail(f"{where}.polygon", f"side {pt(p)}–{pt(q)} is neither wall nor door")
                break
        else:
            good_rooms.append(k)
    polygon_area = area2(ring) / 2
    if area_claim is not None and area_claim != polygon_area:
        c.fail("claims.area", f"claims {text(area_claim)}, the polygon's area is {text(polygon_area)}")
    if total != polygon_area:
        c.fail("claims.rooms", f"the room areas add up to {text(total)}, the polygon's area is {text(polygon_area)}")
    samples = {k: _interior_point(rooms[k][0]) for k in good_rooms}
    for k in good_rooms:
        polygon = rooms[k][0]
        bb = box(polygon)
        for d, (a, b, *_) in enumerate(doors):
            if apart(bb, box([a, b])):
                continue
            c.count("door_room_tests")
            if _enters(a, b, polygon):
                c.fail(f"claims.doors[{d}]", f"runs through the interior of room {k}")
        for j in good_rooms:
            if j != k and not apart(bb, box(rooms[j][0])) and _inside_strictly(samples[j], polygon):
                c.fail(f"claims.rooms[{j}]", f"overlaps room {k}")
    # 3. doors as sides, the tree
    adjacency: dict[int, list[tuple[int, int]]] = {}
    for k, (a, b, named, _, _) in enumerate(doors):
        c.count("door_sides")
        sides_of = sorted(r for r, (polygon, _) in enumerate(rooms)
                          if any(on_closed_segment(a, p, q) and on_closed_segment(b, p, q) for p, q in zip(polygon, polygon[1:] + polygon[:1])))
        if sides_of != sorted(named):
            c.fail(f"claims.doors[{k}].rooms", f"claims rooms {list(named)}, the door is a side of rooms {sides_of}")
        adjacency.setdefault(named[0], []).append((named[1], k))
        adjacency.setdefault(named[1], []).append((named[0], k))
    if m != len(doors) + 1:
        c.fail("claims.doors", f"{m} rooms for {len(doors)} doors: rooms and doors cannot form a tree")
    reach_raw = c.optional(claims, "reachability", "claims")
    root = 0 if reach_raw is None else R.integer(R.field(R.obj(reach_raw, "claims.reachability"), "from", "claims.reachability"),
                                                 "claims.reachability.from")
    if not 0 <= root < max(m, 1):
        raise Malformed("claims.reachability.from", f"room {root} does not exist")
    paths = _tree_paths(m, adjacency, root)
    if len(paths) != m:
        c.fail("claims.doors", f"the doors connect {len(paths)} of the {m} rooms")
    tree = sorted(sorted(named) for _, _, named, _, _ in doors)
    claimed_tree = [sorted((R.integer(e[0], f"claims.tree[{i}]"), R.integer(e[1], f"claims.tree[{i}]")))
                    for i, e in enumerate(R.lst(R.field(claims, "tree", "claims"), "claims.tree"))
                    if isinstance(e, list) and len(e) == 2]
    if claimed_tree != tree or len(claimed_tree) != len(R.lst(claims["tree"], "claims.tree")):
        c.fail("claims.tree", f"is not the room pairs the doors join, ascending ({tree[:6]}{' …' if len(tree) > 6 else ''})")
    # 4. Φ and Ψ
    phi: dict[tuple[int, int], Fraction] = {}
    for k, (a, b, named, _, claimed) in enumerate(doors):
        for side, room in enumerate(named):
            c.count("escapability")
            wall = _wall(rooms[room][0], a, b)
            if wall is None:
                continue  # reported: the door is not a side of that room
            value = _length(a, b) / wall
            phi[(room, named[1 - side])] = value
            if claimed is not None and claimed[side] != value:
                c.fail(f"claims.doors[{k}].escapability[{side}]", f"claims {text(claimed[side])}, Φ from room {room} is "
                       f"|door| / |wall| = {text(_length(a, b))} / {text(wall)} = {text(value)}")
    if reach_raw is None:
        c.not_checked.append("Ψ (the answer states no reachability)")
        reach: list = []
    else:
        reach = R.lst(R.field(reach_raw, "to", "claims.reachability"), "claims.reachability.to")
    seen: set[int] = set()
    for i, raw in enumerate(reach):
        where = f"claims.reachability.to[{i}]"
        obj = R.obj(raw, where)
        room = R.integer(R.field(obj, "room", where), f"{where}.room")
        path = [R.integer(x, f"{where}.path") for x in R.lst(R.field(obj, "path", where), f"{where}.path")]
        psi = R.number(R.field(obj, "psi", where), f"{where}.psi")
        c.count("reachability")
        if room != i:
            c.fail(f"{where}.room", f"is {room}: the reachability is listed room by room, 0, 1, …")
        seen.add(room)
        if paths.get(room) != path:
            c.fail(f"{where}.path", f"is not the tree path from room {root} to room {room} ({paths.get(room)})")
            continue
        product = Fraction(1)
        for x, y in zip(path, path[1:]):
            product *= phi.get((x, y), Fraction(0))
        if psi != product:
            c.fail(f"{where}.psi", f"claims {text(psi)}, the product of Φ along the path is {text(product)}")
    if reach_raw is not None and (seen != set(range(m)) or len(reach) != m):
        c.fail("claims.reachability.to", f"must list every room once ({len(reach)} entries for {m} rooms)")
    c.summary.update({"tree_edges": len(tree), "reachability_from": root})
    c.scope = (f"the {m} rooms and {len(doors)} doors claimed in this polygon (no holes); Φ and Ψ are the paper's "
               f"exact escapability and reachability numbers, Ψ from room {root} to every room")
    c.proved.append(f"the {m} rooms tile the polygon (area {text(polygon_area)}) and are cut from one another only by the "
                    f"{len(doors)} doors, each a segment from a reflex vertex through the interior")
    c.proved.append("rooms and doors form a tree; every door's Φ from each side and every Ψ from room "
                    f"{root} are the exact values")


def _interior_point(polygon: list[Point]) -> Point:
    """A point strictly inside a simple rectilinear polygon: the middle of the thinnest slab at the lowest left corner."""
    xs = sorted({p[0] for p in polygon})
    x = (xs[0] + xs[1]) / 2 if len(xs) > 1 else xs[0]
    ys = sorted(p[1] + 0 for p in _crossings_at(polygon, x))
    y = (ys[0] + ys[1]) / 2 if len(ys) > 1 else polygon[0][1]
    return (x, y)


def _crossings_at(polygon: list[Point], x: Fraction) -> list[Point]:
    out = []
    for i in range(len(polygon)):
        a, b = polygon[i], polygon[(i + 1) % len(polygon)]
        if a[1] == b[1] and min(a[0], b[0]) <= x <= max(a[0], b[0]) and a[0] != b[0]:
            out.append((x, a[1]))
    return out


def _enters(a: Point, b: Point, polygon: list[Point]) -> bool:
    """Does the open segment a–b have a point strictly inside ``polygon``? (Split at every side it meets.)"""
    cuts = {Fraction(0), Fraction(1)}
    d = (b[0] - a[0], b[1] - a[1])
    for i in range(len(polygon)):
        p, q = polygon[i], polygon[(i + 1) % len(polygon)]
        for v in (p, q):
            if orient(a, b, v) == 0 and on_closed_segment(v, a, b):
                cuts.add(param_on(a, d, v))
        e = (q[0] - p[0], q[1] - p[1])
        den = d[0] * e[1] - d[1] * e[0]
        if den != 0:
            s = ((p[0] - a[0]) * e[1] - (p[1] - a[1]) * e[0]) / den
            t = ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / den
            if 0 < s < 1 and 0 <= t <= 1:
                cuts.add(s)
    ordered = sorted(cuts)
    for s0, s1 in zip(ordered, ordered[1:]):
        mid = (s0 + s1) / 2
        if _inside_strictly((a[0] + mid * d[0], a[1] + mid * d[1]), polygon):
            return True
    return False


