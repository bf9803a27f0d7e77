"""Exact checks of the wall-following robot's certificates: ``cut-ordering`` and ``pursuit``.

Vertices of angle exactly π are no corners for the robot (it cannot sense them): both checks first drop them, and
vertex k of the claims is the k-th remaining corner in the order written.

**Cut ordering** (``claims``: ``cuts`` ``[{"label": "r3", "vertex": 3, "side": "r", "edge", "point": [x, y]}]`` for
every reflex vertex and side, and ``ordering``: the labels in boundary order). Re-derived exactly: the reflex
vertices of the (hole-free, counter-clockwise) polygon; each cut's end point as the first boundary point hit by the
ray from the reflex vertex v_i continuing the edge v_{i−1} → v_i (right cut, ``rK``) or v_{i+1} → v_i (left cut,
``lK``) — it must be the claimed point, strictly inside the claimed edge (a cut running into a vertex breaks the
model's general position); then the ordering is every vertex and cut end point sorted by (edge, parameter) from
``v0`` counter-clockwise, with no two at the same point.

**Pursuit** (``claims``: ``start`` label, ``steps`` ``[{"action", "label", "point", "shadow", "contaminated"}]``,
step 0 being the start with action ``null``, and ``cleared_after``). The plan's motions are re-derived from the
robot's rules (RFOLLOW: to the next vertex counter-clockwise; LFOLLOW: to the previous one, or to the start of the
edge it is on; JUMP: at a reflex vertex reached by a follow, along its right or left cut as the follow was), and
the pursuer's shadow is replayed exactly along every motion:

- the **shadow components** at a point q are named by their window vertices: the reflex vertices v seen from q
  (the open segment qv meets no boundary point and runs inside) past which the line of sight goes on into the
  free space (its direction v − q lies strictly inside the interior angle at v, off the closed exterior wedge
  between v's edges). In a simple polygon each window cuts off one component, so the set of window vertices is the
  shadow's combinatorial state;
- that set changes only where the pursuer crosses the extension of an edge at a reflex vertex (a window appears or
  vanishes with zero area) or a line through two reflex vertices (one hides behind the other). The checker cuts
  every motion at every such crossing (exact parameters) and computes the window set exactly at the motion's
  ends and at the middle of every piece;
- labels (1: the evader may be in the component) start at 1 for every component at the start; across an event at
  point e, a continuing window keeps its label; where e lies on the line of an edge between two reflex vertices and
  the window passes from one to the other, the component (the same one) keeps its label; a window appearing on an
  edge's extension through e gets 0 (it was seen just before); one appearing from behind an occluder u (e, u, v collinear, u between) takes u's label (it
  splits off u's component); a vanishing window on an edge's extension loses its label (its component shrank to
  nothing in sight); one hiding behind u ORs its label into u's (merge). At a vertex v the pursuer leaves, v's
  window appears carrying the labels of the windows that vanish behind v at once; at a vertex v it arrives at,
  the windows appearing past v take v's label and v's own vanishes (what is left of its component is in sight).
  A change that none of these explains is resolved conservatively: an appearing window takes the OR of every
  label, a vanishing one ORs into every window.

The claims checked are every step's position (label and exact point), window set (``shadow``) and contaminated
windows, and ``cleared_after``: the first action during which every label was 0 — at that instant no component
can hold the evader, so an evader anywhere in the polygon has been seen. The model assumes general position (no
three vertices collinear); the checker does not re-check it, but a cut into a vertex or two coinciding cut ends
fail.
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.check_models import Malformed, ModelChecker, Reader as R, pt
from solverplan.certify.exact2d import cross, on_closed_segment, orient, sub
from solverplan.certify.schema import Point

__all__ = ["check_cut_ordering", "check_pursuit", "exact_cuts"]

Cut = tuple[int, str, int, Fraction, Point]  # vertex, side, edge, t, point


def exact_cuts(ring: list[Point]) -> tuple[dict[tuple[int, str], Cut], list[str]]:
    """Every cut of the counter-clockwise hole-free ``ring``: (vertex, side) → (vertex, side, edge, t, point), and the
    problems found (a cut into a vertex, no hit)."""
    n = len(ring)
    out: dict[tuple[int, str], Cut] = {}
    problems: list[str] = []
    for i in range(n):
        if orient(ring[i - 1], ring[i], ring[(i + 1) % n]) >= 0:
            continue  # convex (or flat): no cut
        for side, behind in (("r", ring[i - 1]), ("l", ring[(i + 1) % n])):
            v = ring[i]
            d = sub(v, behind)
            best: tuple[Fraction, int, Fraction] | None = None
            for e in range(n):
                a, b = ring[e], ring[(e + 1) % n]
                u = sub(b, a)
                den = cross(d, u)
                if den == 0:
                    continue
                s = cross(sub(a, v), u) / den
                t = cross(sub(a, v), d) / den
                if s > 0 and 0 <= t <= 1 and (best is None or s < best[0]):
                    best = (s, e, t)
            if best is None:
                problems.append(f"the {side} cut of vertex {i} hits no boundary")
                continue
            s, e, t = best
            if t in (0, 1):
                problems.append(f"the {side} cut of vertex {i} runs into vertex {(e + int(t)) % n} (general position)")
                continue
            out[(i, side)] = (i, side, e, t, (v[0] + s * d[0], v[1] + s * d[1]))
    return out, problems


def _ordering(n: int, cuts: dict[tuple[int, str], Cut]) -> list[str]:
    keyed = [((k, Fraction(0)), f"v{k}") for k in range(n)]
    keyed += [((c[2], c[3]), f"{c[1]}{c[0]}") for c in cuts.values()]
    return [label for _, label in sorted(keyed)]


def _needs_simple(c: ModelChecker) -> bool:
    assert c.env is not None
    if len(c.env.rings) != 1:
        c.fail("environment", f"has {len(c.env.rings) - 1} holes: the wall-following robot needs a simply connected polygon")
        return False
    return True


def corners(ring: list[Point]) -> list[Point]:
    """The ring's corners: every vertex of angle exactly π dropped (the robot cannot sense it; the free space is the
    same), the others in the order written — vertex k of the answers is the k-th corner."""
    n = len(ring)
    return [ring[i] for i in range(n) if orient(ring[i - 1], ring[i], ring[(i + 1) % n]) != 0]


def _ring_and_cuts(c: ModelChecker, claim: str) -> tuple[list[Point], dict[tuple[int, str], Cut]] | None:
    """The simple polygon's corners and its exact cuts; ``None`` (failures recorded under ``claim``) if it has
    holes."""
    if not _needs_simple(c):
        return None
    assert c.env is not None
    ring = corners(c.env.outer)
    cuts, problems = exact_cuts(ring)
    for problem in problems:
        c.fail(claim, problem)
    return ring, cuts


def check_cut_ordering(c: ModelChecker) -> None:
    found = _ring_and_cuts(c, "claims.cuts")
    if found is None:
        return
    ring, cuts = found
    n = len(ring)
    claims = c.cert.claims
    raw = R.lst(R.field(claims, "cuts", "claims"), "claims.cuts")
    claimed: set[tuple[int, str]] = set()
    previous = (-1, "")
    for k, item in enumerate(raw):
        where = f"claims.cuts[{k}]"
        obj = R.obj(item, where)
        vertex = R.integer(R.field(obj, "vertex", where), f"{where}.vertex")
        side = R.text(R.field(obj, "side", where), f"{where}.side")
        edge = R.integer(R.field(obj, "edge", where), f"{where}.edge")
        point = R.point(R.field(obj, "point", where), f"{where}.point")
        label = R.text(R.field(obj, "label", where), f"{where}.label")
        c.count("cuts")
        if k and (vertex, side) <= previous:
            c.fail(where, "cuts are listed by vertex, the left cut first")
        previous = (vertex, side)
        real = cuts.get((vertex, side))
        if real is None:
            c.fail(where, f"vertex {vertex} has no {side!r} cut (it is not a reflex vertex, or the side is not l or r)")
            continue
        claimed.add((vertex, side))
        if label != f"{side}{vertex}":
            c.fail(f"{where}.label", f"is {label!r}, the cut is {side}{vertex}")
        if edge != real[2]:
            c.fail(f"{where}.edge", f"claims edge {edge}, the cut ends on edge {real[2]}")
        if point != real[4]:
            c.fail(f"{where}.point", f"claims {pt(point)}, the cut ends at {pt(real[4])}")
    missing = sorted(set(cuts) - claimed)
    if missing:
        c.fail("claims.cuts", f"misses the cuts {', '.join(f'{s}{v}' for v, s in missing[:5])}")
    if len(raw) != len(claimed):
        c.fail("claims.cuts", "lists a cut twice")
    ends = sorted((cut[2], cut[3]) for cut in cuts.values())
    for first, second in zip(ends, ends[1:]):
        if first == second:
            c.fail("claims.cuts", f"two cuts end at the same point of edge {first[0]} (general position)")
    order = _ordering(n, cuts)
    ordering = [R.text(x, f"claims.ordering[{i}]") for i, x in enumerate(R.lst(R.field(claims, "ordering", "claims"), "claims.ordering"))]
    c.count("ordering_labels", len(order))
    if ordering != order:
        at = next((i for i, (x, y) in enumerate(zip(ordering, order)) if x != y), min(len(ordering), len(order)))
        c.fail(f"claims.ordering[{at}]", f"is {ordering[at] if at < len(ordering) else 'missing'}, the boundary "
               f"order has {order[at] if at < len(order) else 'nothing'} there")
    c.summary = {"vertices": n, "reflex": len({v for v, _ in cuts}), "cuts": len(cuts)}
    c.scope = ("the cut ordering of this simply connected polygon: the end points of the left and right cuts of every "
               "reflex vertex and their order along the boundary, counter-clockwise from v0")
    c.proved.append(f"the {len(cuts)} cut end points are the exact first boundary hits of the extended edges at the "
                    f"reflex vertices, and the ordering of {len(order)} labels is their counter-clockwise boundary order")


# ====================================================================== pursuit
class _Shadow:
    """Exact window sets of a pursuer in a simple polygon."""

    def __init__(self, ring: list[Point]) -> None:
        self.ring = ring
        self.n = len(ring)
        self.edges = [(ring[i], ring[(i + 1) % self.n]) for i in range(self.n)]
        self.reflex = [i for i in range(self.n) if orient(ring[i - 1], ring[i], ring[(i + 1) % self.n]) < 0]
        lines: list[tuple[Point, Point, str, int, int]] = []
        for v in self.reflex:
            lines.append((ring[v], ring[v - 1], "extension", v, v))
            lines.append((ring[v], ring[(v + 1) % self.n], "extension", v, v))
        for i, u in enumerate(self.reflex):
            for v in self.reflex[i + 1:]:
                lines.append((ring[u], ring[v], "occlusion", u, v))
        self.lines = lines
        self.index = {p: i for i, p in enumerate(ring)}
        self.evaluations = 0

    def sees(self, q: Point, v: int) -> bool:
        """Is vertex v seen from q: does the segment q–v lie in the closed free space? A line of sight may graze the
        boundary — run along an edge, or pass a vertex without entering the outside there — but not cross it."""
        p = self.ring[v]
        if p == q:
            return False
        for a, b in self.edges:  # a proper crossing of an edge
            o1, o2 = orient(q, p, a), orient(q, p, b)
            if o1 * o2 < 0 and orient(a, b, q) * orient(a, b, p) < 0:
                return False
        if not self._into(v, sub(q, p)):
            return False  # the sight arrives at v from outside
        at_q = self.index.get(q)
        if at_q is not None and not self._into(at_q, sub(p, q)):
            return False
        for w in range(self.n):  # a vertex on the open segment: both ways from it must stay in the closed free space
            x = self.ring[w]
            if w == v or x == q or orient(q, p, x) != 0 or not on_closed_segment(x, q, p):
                continue
            if not (self._into(w, sub(q, x)) and self._into(w, sub(p, x))):
                return False
        mid = ((q[0] + p[0]) / 2, (q[1] + p[1]) / 2)
        return self._inside_or_on(mid)

    def _into(self, w: int, d: Point) -> bool:
        """Does direction d from vertex w point into the closed free space (the closed interior angle at w)?"""
        x = self.ring[w]
        e_next, e_prev = sub(self.ring[(w + 1) % self.n], x), sub(self.ring[w - 1], x)
        if cross(e_prev, e_next) > 0:  # reflex at w: the exterior is the open wedge from e_prev CCW to e_next (< π)
            return not (cross(e_prev, d) > 0 and cross(d, e_next) > 0)
        # convex (or flat) at w: the interior is the closed wedge from e_next CCW to e_prev (≤ π)
        return cross(e_next, d) >= 0 and cross(d, e_prev) >= 0

    def _inside_or_on(self, p: Point) -> bool:
        if any(on_closed_segment(p, a, b) for a, b in self.edges):
            return True
        inside = False
        for a, b in self.edges:
            if (a[1] > p[1]) != (b[1] > p[1]):
                side = orient(a, b, p)
                if (b[1] > a[1] and side > 0) or (b[1] < a[1] and side < 0):
                    inside = not inside
        return inside

    def windows(self, q: Point) -> frozenset[int]:
        self.evaluations += 1
        out = set()
        for v in self.reflex:
            p = self.ring[v]
            if p == q:
                continue
            d = sub(p, q)  # the line of sight, going on past v
            e_next, e_prev = sub(self.ring[(v + 1) % self.n], p), sub(self.ring[v - 1], p)
            in_exterior = cross(e_prev, d) >= 0 and cross(d, e_next) >= 0  # the closed exterior wedge (< π) at v
            if not in_exterior and self.sees(q, v):
                out.add(v)
        return frozenset(out)

    def events(self, p0: Point, p1: Point) -> list[Fraction]:
        """Parameters s ∈ (0, 1) where p0 + s (p1 − p0) crosses one of the event lines."""
        d = sub(p1, p0)
        params = set()
        for a, b, *_ in self.lines:
            u = sub(b, a)
            den = cross(d, u)
            if den == 0:
                continue
            s = cross(sub(a, p0), u) / den
            if 0 < s < 1:
                params.add(s)
        return sorted(params)

    def transfer(self, e: Point, before: dict[int, bool], after: frozenset[int]) -> dict[int, bool]:
        """Labels after an event at e (module docstring)."""
        ring = self.ring
        out = {g: before[g] for g in after if g in before}
        any_label = any(before.values())

        def extension_through(v: int) -> bool:
            return orient(ring[v], ring[v - 1], e) == 0 or orient(ring[v], ring[(v + 1) % self.n], e) == 0

        def occluder(v: int, among) -> int | None:
            for u in among:
                if u != v and orient(e, ring[u], ring[v]) == 0 and on_closed_segment(ring[u], e, ring[v]) and ring[u] != e:
                    return u
            return None

        vanished = [h for h in before if h not in after]
        at = self.index.get(e)  # the pursuer is at this vertex (it arrives there or leaves it)
        if at is not None:
            # Leaving vertex v: v's window appears, its component made of what v saw and of the components of the
            # windows hidden behind v at once (they vanish). Arriving at v: v's component splits into the windows
            # v now sees past itself (they appear), what is left of it is in sight. In general position nothing
            # else changes at a vertex (no line through it and two other vertices).
            for g in after:
                if g in before:
                    continue
                if g == at:
                    out[g] = any(before[h] for h in vanished)
                elif at in before and at not in after:
                    out[g] = before[at]
                else:
                    out[g] = any_label
            for h in vanished:
                if before[h] and h != at and at not in after:
                    for t in after:
                        out[t] = True  # unexplained: the conservative rule
            return out
        handed: set[int] = set()
        for g in after:  # across the line of an edge between two reflex vertices: the window passes from one to the other
            if g in before:
                continue
            for h in ((g - 1) % self.n, (g + 1) % self.n):
                if h in vanished and h not in handed and orient(ring[g], ring[h], e) == 0:
                    out[g] = before[h]
                    handed.add(h)
                    break
        for g in after:
            if g in before or g in out:
                continue
            if extension_through(g):
                out[g] = False
            else:
                u = occluder(g, [x for x in after if x in before])
                out[g] = before[u] if u is not None else any_label
        for h in vanished:
            if not before[h] or h in handed or extension_through(h):
                continue
            u = occluder(h, after)
            for t in ([u] if u is not None else list(after)):
                out[t] = True
        return out


def _motion(ring: list[Point], cuts: dict[tuple[int, str], Cut], here: tuple[int, Fraction], arrived: str | None,
            action: str) -> tuple[tuple[int, Fraction], str | None, str]:
    """The robot's next position (edge, t), how it arrived, and the label there; ValueError if not applicable."""
    n = len(ring)
    edge, t = here
    if action == "RFOLLOW":
        return ((edge + 1) % n, Fraction(0)), "R", f"v{(edge + 1) % n}"
    if action == "LFOLLOW":
        if t == 0:
            edge = (edge - 1) % n
        return (edge, Fraction(0)), "L", f"v{edge}"
    if action == "JUMP":
        side = {"R": "r", "L": "l"}.get(arrived or "")
        if t != 0 or side is None or (edge, side) not in cuts:
            raise ValueError("JUMP needs a reflex vertex reached by RFOLLOW or LFOLLOW")
        cut = cuts[(edge, side)]
        return (cut[2], cut[3]), None, f"{side}{edge}"
    raise ValueError(f"{action!r} is not a pursuit action (RFOLLOW, LFOLLOW, JUMP)")


def _point(ring: list[Point], pos: tuple[int, Fraction]) -> Point:
    a, b = ring[pos[0]], ring[(pos[0] + 1) % len(ring)]
    return (a[0] + pos[1] * (b[0] - a[0]), a[1] + pos[1] * (b[1] - a[1]))


def check_pursuit(c: ModelChecker) -> None:
    walls = _ring_and_cuts(c, "claims")
    if walls is None or c.failures:
        return
    ring, cuts = walls
    n = len(ring)
    claims = c.cert.claims
    start = R.text(R.field(claims, "start", "claims"), "claims.start")
    if start[:1] == "v" and start[1:].isdigit() and int(start[1:]) < n:
        here: tuple[int, Fraction] = (int(start[1:]), Fraction(0))
    else:
        found = next((cut for cut in cuts.values() if f"{cut[1]}{cut[0]}" == start), None)
        if found is None:
            raise Malformed("claims.start", f"{start!r} is not a point of the cut ordering")
        here = (found[2], found[3])
    steps = R.lst(R.field(claims, "steps", "claims"), "claims.steps")
    if not steps:
        raise Malformed("claims.steps", "lists at least the start")
    shadow = _Shadow(ring)
    q = _point(ring, here)
    wins = shadow.windows(q)
    labels = {g: True for g in wins}
    cleared: int | None = 0 if not wins else None
    arrived: str | None = None
    label = start
    for k, raw in enumerate(steps):
        where = f"claims.steps[{k}]"
        obj = R.obj(raw, where)
        action = R.field(obj, "action", where)
        if k == 0:
            if action is not None:
                c.fail(f"{where}.action", "step 0 is the start: its action is null")
        else:
            action = R.text(action, f"{where}.action")
            try:
                nxt, arrived, label = _motion(ring, cuts, here, arrived, action)
            except ValueError as exc:
                c.fail(f"{where}.action", f"{action} at {label}: {exc}")
                return
            p0, p1 = q, _point(ring, nxt)
            params = [Fraction(0)] + shadow.events(p0, p1) + [Fraction(1)]
            c.count("motions")
            c.count("events", len(params) - 2)
            event = p0  # where the state may change between the last sample and the next one
            for s0, s1 in zip(params, params[1:]):
                mid = (s0 + s1) / 2
                for sample in ((p0[0] + mid * (p1[0] - p0[0]), p0[1] + mid * (p1[1] - p0[1])), p1) if s1 == 1 else \
                        ((p0[0] + mid * (p1[0] - p0[0]), p0[1] + mid * (p1[1] - p0[1])),):
                    new = shadow.windows(sample)
                    labels = shadow.transfer(event, labels, new)
                    wins = new
                    if cleared is None and not any(labels.values()):
                        cleared = k
                    event = (p0[0] + s1 * (p1[0] - p0[0]), p0[1] + s1 * (p1[1] - p0[1]))
            here, q = nxt, p1
        c.count("steps")
        claimed_label = R.text(R.field(obj, "label", where), f"{where}.label")
        if claimed_label != label:
            c.fail(f"{where}.label", f"claims {claimed_label}, the robot is at {label}")
        point = R.point(R.field(obj, "point", where), f"{where}.point")
        if point != q:
            c.fail(f"{where}.point", f"claims {pt(point)}, the robot is at {pt(q)}")
        claimed_shadow = sorted(R.integer(x, f"{where}.shadow") for x in R.lst(R.field(obj, "shadow", where), f"{where}.shadow"))
        if claimed_shadow != sorted(wins):
            c.fail(f"{where}.shadow", f"claims windows at {claimed_shadow}, the exact shadow has windows at {sorted(wins)}")
        dirty = sorted(g for g, v in labels.items() if v)
        claimed_dirty = sorted(R.integer(x, f"{where}.contaminated")
                               for x in R.lst(R.field(obj, "contaminated", where), f"{where}.contaminated"))
        if claimed_dirty != dirty:
            c.fail(f"{where}.contaminated", f"claims {claimed_dirty}, the exact replay has {dirty}")
    c.count("shadow_evaluations", shadow.evaluations)
    claimed_cleared = R.field(claims, "cleared_after", "claims")
    if claimed_cleared is not None:
        claimed_cleared = R.integer(claimed_cleared, "claims.cleared_after")
    if claimed_cleared != cleared:
        c.fail("claims.cleared_after", f"claims {claimed_cleared}, the exact replay clears "
               f"{'never' if cleared is None else f'during action {cleared}'}")
    c.summary = {"start": start, "actions": len(steps) - 1, "cleared_after": "none" if cleared is None else cleared}
    c.scope = ("the pursuit plan from " + start + " in this simply connected polygon (general position): the "
               "pursuer's motions by the wall-following rules and the shadow labels along them, an evader moving "
               "arbitrarily fast")
    if cleared is not None:
        c.proved.append(f"during action {cleared} no shadow component can hold the evader: the plan sees an evader "
                        f"anywhere in the polygon")
    else:
        c.proved.append("the replayed labels are as claimed; the plan does not clear the shadow")
