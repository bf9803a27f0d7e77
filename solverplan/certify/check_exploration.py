"""Exact check of an ``exploration`` certificate: the views, their chain, their union and their count.

The claims (``claims`` block):

- ``range``: ``null`` (unlimited views) or R (length units, exact): a view is then VP(z) ∩ disc(z, R) — kept exact
  as its polygon and the circle (centre z, radius R), nothing approximated;
- ``views``: ``[{"viewpoint": [x, y], "parent": k or null, "polygon": [[x, y], ...]}]`` in visiting order, each
  polygon counter-clockwise and star-shaped from its viewpoint (the exact visibility polygon, or a part of it);
- ``reflex``, ``holes``: the counts the bound uses; ``bound``: r + 1 (Theorem 1) without range, Lemma 4's
  ⌊8·Area/(3R²)⌋ + ⌊Perimeter/R⌋ + r + h + 1 with one.

Re-derived exactly:

1. **Views are seen, and whole.** Each viewpoint lies in the free space (closed); for every side ab of its polygon
   the fan triangle (z, a, b) turns counter-clockwise, no boundary point lies in its interior, and its interior
   lies in the free space (a point of it is strictly inside). Every point of the polygon lies in such a triangle,
   so the whole polygon is seen from z (within R when the range is limited: the view is the polygon cut by the
   disc). Every side lies on one boundary edge or along a line of sight from z: in every direction but finitely
   many the polygon then reaches the first boundary point, so it *is* the visibility polygon VP(z).
2. **Chain.** The first view has no parent; every other viewpoint lies in the view (polygon, and disc when
   limited) of an earlier viewpoint, its parent: the robot reaches it along a line of sight.
3. **Cover** (views no disc cuts). The union U of the views covers the free space F: every side of every view that is
   not on the boundary is cut at every point where another view's side or a boundary vertex meets it, and just
   beyond the middle of each piece (outside its view, inside F) some other view must lie. If a point of F were
   outside U, a path in the interior of F from a point of U to it would leave U across such a piece, whose far
   side would then be uncovered — so no uncovered piece means F ⊆ U.
4. **Count.** r and h are the polygon's reflex vertices (a hole's convex corners count: they are reflex for the
   free space) and holes; the number of views is at most the bound, which must be the theorem's value exactly
   (the perimeter's floor decided with rigorous integer square-root enclosures).

With a range, the cover (3.) is re-derived when no disc cuts a view (every polygon vertex within R of its viewpoint:
Theorem 3's case, RVP = VP); otherwise it is **not** re-derived: it is the explorer's claim (its overlay draws arcs
as inscribed chords and ignores slivers below 10⁻⁹ of the area), and the report lists it under *not checked*.
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.check_models import (Env, Malformed, ModelChecker, Reader as R, apart, area2, box, dist2, inside_open,
                                             param_on, pt, text)
from solverplan.certify.exact2d import clip_segment, cross, on_closed_segment, orient, sub
from solverplan.certify.schema import Point

__all__ = ["check"]


def _strictly_inside_triangle(p: Point, a: Point, b: Point, c: Point) -> bool:
    return orient(a, b, p) > 0 and orient(b, c, p) > 0 and orient(c, a, p) > 0


def _edge_enters_triangle(u: Point, w: Point, tri: tuple[Point, Point, Point]) -> bool:
    """Does the closed segment uw have a point in the open (counter-clockwise, non-degenerate) triangle?"""
    clipped = clip_segment(u, w, list(tri))
    if clipped is None:
        return False
    t0, t1 = clipped
    m = (t0 + t1) / 2
    p = (u[0] + m * (w[0] - u[0]), u[1] + m * (w[1] - u[1]))
    return _strictly_inside_triangle(p, *tri)


def _in_closed_ring(p: Point, ring: list[Point]) -> bool:
    n = len(ring)
    if any(on_closed_segment(p, ring[i], ring[(i + 1) % n]) for i in range(n)):
        return True
    return inside_open(p, ring)


def _covers_beyond(m: Point, normal: Point, ring: list[Point], sides: list) -> bool:
    """Do the points m + ε·normal, ε > 0 small, lie in the closed polygon ``ring`` (CCW)? (m is no vertex of it.)"""
    for a, b, bb in sides:
        if bb[0] <= m[0] <= bb[2] and bb[1] <= m[1] <= bb[3] and orient(a, b, m) == 0:
            return cross(sub(b, a), normal) > 0
    return inside_open(m, ring)


def _isqrt(n: int) -> int:
    if n < 2:
        return n
    x = 1 << ((n.bit_length() + 1) // 2)
    while True:
        y = (x + n // x) // 2
        if y >= x:
            return x
        x = y


def _perimeter_floor(edges: list[tuple[Point, Point]], R: Fraction) -> int | None:
    """⌊Perimeter / R⌋ exactly, from rigorous enclosures of the edge lengths (None if undecided at 2⁻²⁰⁰)."""
    for bits in (32, 64, 128, 200):
        scale = 1 << bits
        lo = hi = Fraction(0)
        for a, b in edges:
            d = sub(b, a)
            q = (d[0] * d[0] + d[1] * d[1]) * scale * scale
            root = _isqrt(q.numerator // q.denominator)  # ⌊√q⌋ ≤ √q < ⌊√q⌋ + 2 (the floor of q loses < 1)
            lo += Fraction(root, scale)
            hi += Fraction(root + 2, scale)
        if int(lo / R) == int(hi / R) and hi / R != int(hi / R):
            return int(lo / R)
    return None


def check(c: ModelChecker) -> None:
    env = c.env
    assert env is not None
    claims = c.cert.claims
    range_raw = R.field(claims, "range", "claims")
    radius = None if range_raw is None else R.number(range_raw, "claims.range")
    if radius is not None and radius <= 0:
        raise Malformed("claims.range", "the range must be positive")
    raw_views = R.lst(R.field(claims, "views", "claims"), "claims.views")
    if not raw_views:
        raise Malformed("claims.views", "an exploration has at least one view")
    views: list[tuple[Point, int | None, list[Point]]] = []
    for k, item in enumerate(raw_views):
        where = f"claims.views[{k}]"
        obj = R.obj(item, where)
        parent_raw = R.field(obj, "parent", where)
        parent = None if parent_raw is None else R.integer(parent_raw, f"{where}.parent")
        views.append((R.point(R.field(obj, "viewpoint", where), f"{where}.viewpoint"), parent,
                      R.ring(R.field(obj, "polygon", where), f"{where}.polygon")))
    edges = env.edges
    edge_boxes = [box(e) for e in edges]
    boxes = [box(ring) for _, _, ring in views]
    # 1. every view is seen from its viewpoint
    for k, (z, _, ring) in enumerate(views):
        where = f"claims.views[{k}]"
        c.count("views")
        if env.locate(z) < 0:
            c.fail(f"{where}.viewpoint", f"{pt(z)} is not in the free space")
            continue
        if len(ring) < 3 or area2(ring) <= 0:
            c.fail(f"{where}.polygon", "is not a counter-clockwise polygon of positive area")
            continue
        for i in range(len(ring)):
            a, b = ring[i], ring[(i + 1) % len(ring)]
            turn = orient(z, a, b)
            c.count("fan_triangles")
            if turn < 0:
                c.fail(f"{where}.polygon[{i}]", f"the side {pt(a)}–{pt(b)} turns clockwise around the viewpoint: "
                       f"the polygon is not star-shaped from it")
                break
            if turn == 0:
                if not (on_closed_segment(a, z, b) or on_closed_segment(b, z, a)):
                    c.fail(f"{where}.polygon[{i}]", f"the side {pt(a)}–{pt(b)} doubles back through the viewpoint")
                    break
                continue  # a side along a line of sight
            side_box = box([a, b])
            if not any(not apart(side_box, eb) and orient(u, w, a) == 0 and orient(u, w, b) == 0
                       and on_closed_segment(a, u, w) and on_closed_segment(b, u, w) for (u, w), eb in zip(edges, edge_boxes)):
                c.fail(f"{where}.polygon[{i}]", f"the side {pt(a)}–{pt(b)} is neither on the boundary nor along a line "
                       f"of sight: the polygon is not the view from {pt(z)}")
                break
            tri = (z, a, b)
            bb = box(tri)
            if any(not apart(bb, eb) and _edge_enters_triangle(e[0], e[1], tri) for e, eb in zip(edges, edge_boxes)):
                c.fail(f"{where}.polygon[{i}]", f"the boundary enters the triangle from the viewpoint to {pt(a)}–{pt(b)}: "
                       f"that part is not seen")
                break
            centroid = ((z[0] + a[0] + b[0]) / 3, (z[1] + a[1] + b[1]) / 3)
            if env.locate(centroid) != 1:
                c.fail(f"{where}.polygon[{i}]", f"the triangle from the viewpoint to {pt(a)}–{pt(b)} lies outside the free space")
                break
    # 2. the chain
    for k, (z, parent, _) in enumerate(views):
        c.count("chain_links")
        where = f"claims.views[{k}].parent"
        if k == 0:
            if parent is not None:
                c.fail(where, "the first view has no parent")
            continue
        if parent is None or not 0 <= parent < k:
            c.fail(where, f"must be an earlier view (0 … {k - 1}), got {parent}")
            continue
        pz, _, pring = views[parent]
        if not _in_closed_ring(z, pring) or (radius is not None and dist2(z, pz) > radius * radius):
            c.fail(where, f"viewpoint {k} {pt(z)} is not in the view from viewpoint {parent} {pt(pz)}")
    # 3. the cover
    uncut = radius is None or all(dist2(p, z) <= radius * radius for z, _, ring in views for p in ring)
    if uncut:  # no disc cuts a view (always without a range; Theorem 3's case with one): the views are polygons
        _check_cover(c, env, views, boxes)
    else:
        c.not_checked.append("that the views cover the free space (with a range, the explorer's overlay: arcs drawn as "
                             "inscribed chords, slivers below 10⁻⁹ of the area ignored)")
    # 4. the count
    reflex, holes = len(env.reflex()), len(env.rings) - 1
    for key, real in (("reflex", reflex), ("holes", holes)):
        claimed = R.integer(R.field(claims, key, "claims"), f"claims.{key}")
        if claimed != real:
            c.fail(f"claims.{key}", f"claims {claimed}, the polygon has {real}")
    bound = R.integer(R.field(claims, "bound", "claims"), "claims.bound")
    if radius is None:
        real_bound: int | None = reflex + 1
        rule = "r + 1 (Theorem 1)"
    else:
        floor_p = _perimeter_floor(edges, radius)
        area = env.area2() / 2
        real_bound = None if floor_p is None else int(8 * area / (3 * radius * radius)) + floor_p + reflex + holes + 1
        rule = "⌊8·Area/(3R²)⌋ + ⌊Perimeter/R⌋ + r + h + 1 (Lemma 4)"
        if real_bound is None:
            c.not_checked.append("the bound's ⌊Perimeter/R⌋ (undecided at 200 bits)")
    if real_bound is not None and bound != real_bound:
        c.fail("claims.bound", f"claims {bound}, {rule} is {real_bound}")
    if len(views) > bound:
        c.fail("claims.views", f"{len(views)} views exceed the bound {bound}")
    c.summary = {"views": len(views), "bound": bound, "reflex": reflex, "holes": holes,
                 "range": "none" if radius is None else text(radius)}
    within = "" if radius is None else f" within range {text(radius)}"
    c.scope = (f"the {len(views)} views{within} taken at the listed viewpoints, in this environment"
               f"{' with holes' if holes else ''}; the bound is {rule}")
    c.proved.append(f"every view is seen from its viewpoint{within}, and every viewpoint after the first lies in an "
                    f"earlier view (a chain of lines of sight)")
    if uncut:
        c.proved.append("the views together cover the whole free space")
    c.proved.append(f"{len(views)} views ≤ the bound {bound}")


def _check_cover(c: ModelChecker, env: Env, views: list, boxes: list) -> None:
    # every side with its bounding box, so that only sides whose boxes meet are compared (exact tests are costly)
    sides = [[(ring[h], ring[(h + 1) % len(ring)], box([ring[h], ring[(h + 1) % len(ring)]])) for h in range(len(ring))]
             for _, _, ring in views]
    walls = [(u, w, box([u, w])) for u, w in env.edges]
    vertices = [(v, v[0], v[1]) for v in env.vertices]
    for k, (_, _, ring) in enumerate(views):
        for i, (a, b, bb) in enumerate(sides[k]):
            if a == b:
                continue
            near_walls = [(u, w) for u, w, wb in walls if not apart(bb, wb)]
            if any(orient(u, w, a) == 0 and orient(u, w, b) == 0 and on_closed_segment(a, u, w) and on_closed_segment(b, u, w)
                   for u, w in near_walls):
                continue  # a side on the boundary: nothing beyond it
            d = sub(b, a)
            normal = (d[1], -d[0])  # outward: the views are counter-clockwise
            params = {Fraction(0), Fraction(1)}
            for v, x, y in vertices:
                if bb[0] <= x <= bb[2] and bb[1] <= y <= bb[3] and orient(a, b, v) == 0:
                    params.add(param_on(a, d, v))
            others = [j for j in range(len(views)) if j != k and not apart(bb, boxes[j])]
            for j in others:
                for p, q, side_box in sides[j]:
                    if apart(bb, side_box):
                        continue
                    for x in (p, q):
                        if orient(a, b, x) == 0 and on_closed_segment(x, a, b):
                            params.add(param_on(a, d, x))
                    e = sub(q, p)
                    den = cross(d, e)
                    if den != 0:
                        s = cross(sub(p, a), e) / den
                        t = cross(sub(p, a), d) / den
                        if 0 < s < 1 and 0 <= t <= 1:
                            params.add(s)
            ordered = sorted(params)
            for s0, s1 in zip(ordered, ordered[1:]):
                c.count("cover_pieces")
                mid = (s0 + s1) / 2
                m = (a[0] + mid * d[0], a[1] + mid * d[1])
                wall = next(((u, w) for u, w in near_walls if orient(u, w, m) == 0 and on_closed_segment(m, u, w)), None)
                if wall is not None and cross(sub(wall[1], wall[0]), normal) <= 0:
                    continue  # beyond it lies the outside of the free space
                if not any(_covers_beyond(m, normal, views[j][2], sides[j]) for j in others
                           if boxes[j][0] <= m[0] <= boxes[j][2] and boxes[j][1] <= m[1] <= boxes[j][3]):
                    c.fail(f"claims.views[{k}].polygon[{i}]", f"the free space just beyond {pt(m)} (outside view {k}) "
                           f"is in no view: the views do not cover the free space")
                    return


