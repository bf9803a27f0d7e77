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

With a range, a view is V = VP(z) ∩ disc(z, R) and the cover (3.) is re-derived on its exact boundary: the pieces
of the polygon's sides inside the disc and the **arcs** of the circle inside the polygon — nothing drawn as chords.
Each side is cut at the rational points of 3. and where it meets its own circle and the other views' circles;
each circle, parametrised rationally by t = tan(θ/2) (the point z + R·(1 − t², 2t)/(1 + t²)), is cut where it
meets the lines of its own and the other views' sides and the other circles (through their radical line). Every
cut point is a root of a quadratic with rational coefficients, enclosed by rigorous integer square roots to
2⁻¹⁶⁰ (extra cuts only split pieces, so every root of every such quadratic is taken). Between two consecutive cuts
the checker picks a rational parameter — an exact point m on the side or on the arc — and, where m is on the
view's boundary and not on a wall, asks that just beyond m (outside, along the side's normal or radially) some
other view lie: inside its polygon and inside its disc (exactly, with the tangent cases decided by the direction).
Two cut points not told apart at 2⁻¹⁶⁰ (and not roots of the same quadratic) leave the cover *not checked*.
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.check_models import (Env, Malformed, ModelChecker, Reader as R, apart, area2, box, dist2, inside_open,
                                             param_on, pt, text)
from solverplan.certify.exact2d import clip_segment, cross, dot, on_closed_segment, orient, sub
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
    first_at: dict[Point, int] = {}
    for k, (z, _, _) in enumerate(views):
        if z in first_at:  # the same view again: it covers nothing new, and counts against the bound twice
            c.fail(f"claims.views[{k}].viewpoint", f"repeats the viewpoint of views[{first_at[z]}]: a view is taken "
                                                   "once at each viewpoint")
        first_at.setdefault(z, k)
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
                       and on_closed_segment(a, u, w) and on_closed_segment(b, u, w) for (u, w), eb in zip(edges, edge_boxes)) \
                    and not env.on_wall(a, b):  # on one edge, or along a run of collinear ones
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
    covered: bool | None = None
    if c.failures:
        pass  # views that are not views: their union proves nothing
    elif uncut:  # no disc cuts a view (always without a range; Theorem 3's case with one): the views are polygons
        _check_cover(c, env, views, boxes)
        covered = not c.failures
    else:
        assert radius is not None
        covered = _check_range_cover(c, env, views, radius)
        if covered is None:
            c.not_checked.append("that the views cover the free space: two cut points of a view's boundary agree to "
                                 "2⁻¹⁶⁰ and were not told apart")
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
    if covered:
        c.proved.append("the views together cover the whole free space" +
                        ("" if uncut else " (arcs kept exact: cut points as roots of quadratics)"))
    c.proved.append(f"{len(views)} views ≤ the bound {bound}")


ROOT_BITS = 160


class _Undecided(Exception):
    """Two cut points could not be told apart (the cover check is then inconclusive, never wrong)."""


Cut = tuple[Fraction, Fraction, tuple]  # enclosure lo ≤ root ≤ hi, and a key naming the root exactly


def _roots(a2: Fraction, a1: Fraction, a0: Fraction) -> list[Cut]:
    """Enclosures of the real roots of a2·x² + a1·x + a0 (rational coefficients), each keyed by the monic quadratic
    and the branch, so that a root met twice is recognised."""
    if a2 == 0:
        if a1 == 0:
            return []
        r = -a0 / a1
        return [(r, r, ("q", r))]
    b, c0 = a1 / a2, a0 / a2  # x² + b·x + c0
    disc = b * b - 4 * c0
    if disc < 0:
        return []
    num = disc.numerator * disc.denominator  # √disc = √num / den
    den = disc.denominator
    root = _isqrt(num)
    if root * root == num:
        return [(r, r, ("q", r)) for r in {(-b + Fraction(root, den)) / 2, (-b - Fraction(root, den)) / 2}]
    scale = 1 << ROOT_BITS
    lo = Fraction(_isqrt(num * scale * scale), den * scale)  # lo ≤ √disc < hi
    hi = lo + Fraction(1, den * scale)
    return [((-b + lo) / 2, (-b + hi) / 2, ("r", b, c0, 1)), ((-b - hi) / 2, (-b - lo) / 2, ("r", b, c0, -1))]


def _line_circle(a: Point, d: Point, z: Point, r2: Fraction) -> list[Cut]:
    """Parameters s of the points a + s·d on the circle |x − z|² = r2."""
    w = sub(a, z)
    return _roots(dot(d, d), 2 * dot(d, w), dot(w, w) - r2)


def _circle_line(z: Point, R: Fraction, a: Point, n: Point, c: Fraction) -> list[Cut]:
    """Parameters t of the points z + R·(1 − t², 2t)/(1 + t²) on the line n·x = c (t = ∞, the point z − (R, 0),
    is a cut of every circle anyway)."""
    k = dot(n, z) - c  # n·(z − x₀)·(1 + t²) + R·(n_x (1 − t²) + 2 n_y t) = 0
    return _roots(k - R * n[0], 2 * R * n[1], k + R * n[0])


def _pieces_between(cuts: list[Cut], lo: Fraction | None, hi: Fraction | None) -> list[Fraction]:
    """A rational parameter strictly inside every gap between consecutive cuts (within [lo, hi] when given; on a
    circle, lo = hi = None: the gaps wrap round through t = ∞)."""
    unique: dict[tuple, Cut] = {}
    for cut in cuts:
        if (lo is not None and cut[1] <= lo) or (hi is not None and cut[0] >= hi):
            continue  # outside the side (its ends are cuts of their own)
        if (lo is not None and cut[0] < lo) or (hi is not None and cut[1] > hi):
            raise _Undecided
        unique.setdefault(cut[2], cut)
    ordered = sorted(unique.values(), key=lambda cut: cut[0])
    if lo is not None and hi is not None:
        ordered = [(lo, lo, ("q", lo))] + ordered + [(hi, hi, ("q", hi))]
    out = []
    for first, second in zip(ordered, ordered[1:]):
        if first[1] >= second[0]:
            if first[0] == first[1] == second[0] == second[1]:
                continue  # one rational point reached twice
            raise _Undecided
        out.append((first[1] + second[0]) / 2)
    if lo is None:  # the circle: the gap through t = ∞, and the whole circle when nothing cuts it
        out.append(ordered[-1][1] + 1 if ordered else Fraction(0))
        if ordered:
            out.append(ordered[0][0] - 1)
    return out


def _beyond_in_view(m: Point, normal: Point, z: Point, R: Fraction, ring: list[Point], sides: list) -> bool:
    """Do the points m + ε·normal (ε > 0 small) lie in the view ring ∩ disc(z, R)?"""
    d2 = dist2(m, z)
    if d2 > R * R or (d2 == R * R and dot(normal, sub(z, m)) <= 0):
        return False
    return _covers_beyond(m, normal, ring, sides)


def _check_range_cover(c: ModelChecker, env: Env, views: list, R: Fraction) -> bool | None:
    """The cover of views cut by their discs, arcs kept exact (module docstring): True, False (a failure is recorded:
    a point of the free space in no view) or None (undecided)."""
    R2 = R * R
    sides = [[(ring[h], ring[(h + 1) % len(ring)], box([ring[h], ring[(h + 1) % len(ring)]])) for h in range(len(ring))]
             for _, _, ring in views]
    discs = [(z[0] - R, z[1] - R, z[0] + R, z[1] + R) for z, _, _ in views]
    boxes = [(max(b[0], d[0]), max(b[1], d[1]), min(b[2], d[2]), min(b[3], d[3]))
             for b, d in zip((box(ring) for _, _, ring in views), discs)]
    walls = [(u, w, box([u, w])) for u, w in env.edges]
    vertices = env.vertices
    try:
        for k, (z, _, ring) in enumerate(views):
            near = [j for j in range(len(views)) if j != k and not apart(boxes[j], discs[k])]
            # the sides of the view, inside its disc
            for i, (a, b, bb) in enumerate(sides[k]):
                if a == b:
                    continue
                near_walls = [(u, w) for u, w, wb in walls if not apart(bb, wb)]
                if any(orient(u, w, a) == 0 and orient(u, w, b) == 0 and on_closed_segment(a, u, w)
                       and on_closed_segment(b, u, w) for u, w in near_walls):
                    continue  # on the boundary: nothing beyond it
                d = sub(b, a)
                normal = (d[1], -d[0])
                cuts = [(t, t, ("q", t)) for t in _side_params(a, b, bb, vertices, [sides[j] for j in near])]
                for j in [k] + near:
                    cuts += _line_circle(a, d, views[j][0], R2)
                for s in _pieces_between(cuts, Fraction(0), Fraction(1)):
                    m = (a[0] + s * d[0], a[1] + s * d[1])
                    if dist2(m, z) > R2:
                        continue  # beyond the range: not the view's boundary
                    c.count("cover_pieces")
                    wall = next(((u, w) for u, w in near_walls if orient(u, w, m) == 0 and on_closed_segment(m, u, w)),
                                None)
                    if wall is not None and cross(sub(wall[1], wall[0]), normal) <= 0:
                        continue
                    if not any(_beyond_in_view(m, normal, views[j][0], R, views[j][2], sides[j]) for j in near):
                        c.fail(f"claims.views[{k}].polygon[{i}]", f"the free space just beyond {pt(m)} (outside view "
                               f"{k}) is in no view: the views do not cover the free space")
                        return False
            # the arc: the circle inside the polygon
            cuts = []
            for j in [k] + near:
                for a, b, _ in sides[j]:
                    if a != b:
                        n = (b[1] - a[1], a[0] - b[0])
                        cuts += _circle_line(z, R, a, n, dot(n, a))
            for j in near:
                zj = views[j][0]
                if zj != z:  # the radical line 2 (zj − z)·x = |zj|² − |z|² (equal radii)
                    n = (2 * (zj[0] - z[0]), 2 * (zj[1] - z[1]))
                    cuts += _circle_line(z, R, z, n, dot(zj, zj) - dot(z, z))
            for t in _pieces_between(cuts, None, None):
                q = 1 + t * t
                m = (z[0] + R * (1 - t * t) / q, z[1] + R * 2 * t / q)
                if not inside_open(m, ring) or any(orient(a, b, m) == 0 and on_closed_segment(m, a, b)
                                                   for a, b, _ in sides[k]):
                    continue  # outside the polygon: not the view's boundary
                c.count("arc_pieces")
                normal = sub(m, z)
                if not any(views[j][0] != z and _beyond_in_view(m, normal, views[j][0], R, views[j][2], sides[j])
                           for j in near):
                    c.fail(f"claims.views[{k}]", f"the free space just beyond {pt(m)} (past the range of view {k}) is "
                           f"in no view: the views do not cover the free space")
                    return False
    except _Undecided:
        return None
    return True


def _side_params(a: Point, b: Point, bb: tuple, vertices: list[Point], others: list[list]) -> set[Fraction]:
    """The rational cuts of the side ab: the boundary vertices on it, and where the other views' sides meet it."""
    d = sub(b, a)
    params = set()
    for v in vertices:
        if bb[0] <= v[0] <= bb[2] and bb[1] <= v[1] <= bb[3] and orient(a, b, v) == 0:
            params.add(param_on(a, d, v))
    for other in others:
        for p, q, side_box in other:
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
    return params


def _check_cover(c: ModelChecker, env: Env, views: list, boxes: list) -> None:
    # every side with its bounding box, so that only sides whose boxes meet are compared (exact tests are costly)
    sides = [[(ring[h], ring[(h + 1) % len(ring)], box([ring[h], ring[(h + 1) % len(ring)]])) for h in range(len(ring))]
             for _, _, ring in views]
    walls = [(u, w, box([u, w])) for u, w in env.edges]
    vertices = env.vertices
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
            others = [j for j in range(len(views)) if j != k and not apart(bb, boxes[j])]
            ordered = sorted({Fraction(0), Fraction(1)} | _side_params(a, b, bb, vertices, [sides[j] for j in others]))
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


