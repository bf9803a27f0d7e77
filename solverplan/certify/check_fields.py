"""Exact check of a ``fields`` certificate: convex cells tiling the free space, each cell's field carrying the cell
into its outlet, the outlets leading to the goal.

The claims (``claims`` block):

- ``cells``: ``[{"id", "polygon": [[x, y], ...] (CCW, convex), "neighbours": [cell id or null, one per side]}]``,
  side i running from vertex i to vertex i + 1; ``area``: the free space's area;
- ``start``, ``goal``: points; ``sequence``: the cells from the start's to the goal's;
- ``policies``: one per cell, ``{"cell", "next", "outlet_side", "field", "flows_through"}`` (``flows_through``: line
  fields only, whether the field provably flows through — false where the planner found no such field); ``field`` is ``{"kind": "line", "origin",
  "target", "gain"}`` (Eq. 2: v(q) = d + p (I − d dᵀ)(q₀ − q), d the unit vector from ``origin`` to ``target``),
  ``{"kind": "goal", "goal"}`` (v = (g − q)/|g − q|, in the goal's cell) or ``{"kind": "arc", "centre", "radius",
  "gain", "clockwise"}`` (Eq. 3).

Re-derived exactly:

1. **Cells tile the free space.** Each cell is a convex counter-clockwise polygon of positive area lying in the free
   space (no boundary point in its interior, an interior point strictly inside); no two cells share an interior
   point (a side of one separates them); their areas add up to the free space's. Each side is either on a wall (on
   boundary edges: one, or a run of collinear ones) or exactly a side of the neighbour it names, reversed, naming it back.
2. **Sequence.** The start lies in the first cell, the goal in the last, consecutive cells are neighbours.
3. **Policies.** Every cell has one; the goal's cell (the last of the sequence) has the goal field of the claimed
   goal, which lies in it: the straight line to the goal stays in the convex cell. Every other cell's ``next`` is
   the neighbour across its ``outlet_side``, and following ``next`` from any cell reaches the goal's cell.
4. **Flow-through of line fields.** n·v is affine along a side (n its inward normal), so v points strictly into the
   cell on a whole side iff it does at both ends; the sign of n·v at a vertex is that of A√L + B (A, B, L
   rational, L = |target − origin|²), decided exactly. With v strictly inward on every side but the outlet and
   d·v = 1 everywhere (the robot advances at unit rate along d), every trajectory from every point of the closed
   cell leaves the bounded cell, through the outlet (Stager and Tanner, Eq. 2; ``solverplan.proofs.line_field``).
   The claim ``flows_through`` must be the test's exact outcome (true or false).

**Arc fields are not checked**: their flow-through is the planner's dense sample of RK4 trajectories, not a proof
(the report lists the cells). The simulated scenarios of a fields answer are statistics, not certified.
"""

from __future__ import annotations

from fractions import Fraction

from solverplan.certify.check_models import Malformed, ModelChecker, Reader as R, apart, area2, box, pt, text
from solverplan.certify.exact2d import clip_segment, orient
from solverplan.certify.schema import Point

__all__ = ["check", "line_inward_sign"]


def _sign_a_sqrt_l_plus_b(a: Fraction, b: Fraction, l: Fraction) -> int:
    """The exact sign of a·√l + b (l > 0)."""
    sa = (a > 0) - (a < 0)
    sb = (b > 0) - (b < 0)
    if sa == 0 or sa == sb:
        return sb if sa == 0 else sa
    if sb == 0:
        return sa
    lhs, rhs = a * a * l, b * b
    return sa if lhs > rhs else sb if lhs < rhs else 0


def line_inward_sign(origin: Point, target: Point, gain: Fraction, normal: Point, q: Point) -> int:
    """The exact sign of n·v(q) for the line field (n any positive multiple of the inward normal):
    n·v·|w|² = (n·w)|w| + p(|w|² n·(q₀ − q) − (n·w)(w·(q₀ − q))), w = target − q₀."""
    wx, wy = target[0] - origin[0], target[1] - origin[1]
    ax, ay = origin[0] - q[0], origin[1] - q[1]
    nw = normal[0] * wx + normal[1] * wy
    l2 = wx * wx + wy * wy
    b = gain * (l2 * (normal[0] * ax + normal[1] * ay) - nw * (wx * ax + wy * ay))
    return _sign_a_sqrt_l_plus_b(nw, b, l2)


def _convex(ring: list[Point]) -> bool:
    n = len(ring)
    if n < 3 or area2(ring) <= 0:
        return False
    return all(orient(ring[i], ring[(i + 1) % n], p) >= 0 for i in range(n) for p in ring)


def _separated(p: list[Point], q: list[Point]) -> bool:
    """Is there a side of p or q whose line leaves the other convex polygon on its outer (right or on) side?"""
    for ring, other in ((p, q), (q, p)):
        n = len(ring)
        for i in range(n):
            a, b = ring[i], ring[(i + 1) % n]
            if all(orient(a, b, x) <= 0 for x in other):
                return True
    return False


def _in_cell(p: Point, ring: list[Point]) -> bool:
    n = len(ring)
    return all(orient(ring[i], ring[(i + 1) % n], p) >= 0 for i in range(n))


def check(c: ModelChecker) -> None:
    env = c.env
    assert env is not None
    claims = c.cert.claims
    cells: list[tuple[list[Point], list[int | None]]] = []
    for k, item in enumerate(R.lst(R.field(claims, "cells", "claims"), "claims.cells")):
        where = f"claims.cells[{k}]"
        obj = R.obj(item, where)
        if R.integer(R.field(obj, "id", where), f"{where}.id") != k:
            c.fail(f"{where}.id", f"is {obj['id']}, cells are numbered 0, 1, … in order")
        ring = R.ring(R.field(obj, "polygon", where), f"{where}.polygon")
        raw = R.lst(R.field(obj, "neighbours", where), f"{where}.neighbours")
        if len(raw) != len(ring):
            raise Malformed(f"{where}.neighbours", f"one per side: {len(ring)} sides, {len(raw)} neighbours")
        cells.append((ring, [None if x is None else R.integer(x, f"{where}.neighbours[{i}]") for i, x in enumerate(raw)]))
    m = len(cells)
    if not m:
        raise Malformed("claims.cells", "no cells")
    # 1. the tiling
    total = Fraction(0)
    boxes = [box(ring) for ring, _ in cells]
    for k, (ring, neighbours) in enumerate(cells):
        where = f"claims.cells[{k}]"
        c.count("cells")
        if not _convex(ring):
            c.fail(f"{where}.polygon", "is not a convex counter-clockwise polygon of positive area")
            continue
        total += area2(ring) / 2
        inner = (sum((p[0] for p in ring), Fraction(0)) / len(ring), sum((p[1] for p in ring), Fraction(0)) / len(ring))
        if env.locate(inner) != 1 or any(env.locate(p) < 0 for p in ring):
            c.fail(f"{where}.polygon", "is not in the free space")
            continue
        for u, w in env.edges:
            if apart(boxes[k], box([u, w])):
                continue
            clipped = clip_segment(u, w, ring)
            if clipped is not None:
                mid = (clipped[0] + clipped[1]) / 2
                p = (u[0] + mid * (w[0] - u[0]), u[1] + mid * (w[1] - u[1]))
                if all(orient(ring[i], ring[(i + 1) % len(ring)], p) > 0 for i in range(len(ring))):
                    c.fail(f"{where}.polygon", f"the boundary edge {pt(u)}–{pt(w)} runs through the cell")
                    break
        for i, nb in enumerate(neighbours):
            c.count("sides")
            a, b = ring[i], ring[(i + 1) % len(ring)]
            if nb is None:
                if not env.on_wall(a, b):
                    c.fail(f"{where}.neighbours[{i}]", f"the side {pt(a)}–{pt(b)} is not on a wall, yet names no neighbour")
                continue
            if not 0 <= nb < m or nb == k:
                c.fail(f"{where}.neighbours[{i}]", f"{nb} is not another cell")
                continue
            other, back = cells[nb]
            j = next((j for j in range(len(other)) if other[j] == b and other[(j + 1) % len(other)] == a), None)
            if j is None or back[j] != k:
                c.fail(f"{where}.neighbours[{i}]", f"cell {nb} does not have the side {pt(b)}–{pt(a)} naming cell {k} back")
    for k in range(m):
        for j in range(k + 1, m):
            if apart(boxes[k], boxes[j]):
                continue
            c.count("cell_pairs")
            if not _separated(cells[k][0], cells[j][0]):
                c.fail(f"claims.cells[{j}]", f"overlaps cell {k}")
    free = env.area2() / 2
    area = R.number(R.field(claims, "area", "claims"), "claims.area")
    if area != free:
        c.fail("claims.area", f"claims {text(area)}, the free space's area is {text(free)}")
    if total != free:
        c.fail("claims.cells", f"the cells' areas add up to {text(total)}, the free space's area is {text(free)}")
    # 2. the sequence
    start = R.point(R.field(claims, "start", "claims"), "claims.start")
    goal = R.point(R.field(claims, "goal", "claims"), "claims.goal")
    sequence = [R.integer(x, "claims.sequence") for x in R.lst(R.field(claims, "sequence", "claims"), "claims.sequence")]
    if not sequence or not all(0 <= x < m for x in sequence):
        raise Malformed("claims.sequence", "must list cells")
    if not _in_cell(start, cells[sequence[0]][0]):
        c.fail("claims.sequence[0]", f"the start {pt(start)} is not in cell {sequence[0]}")
    if not _in_cell(goal, cells[sequence[-1]][0]):
        c.fail(f"claims.sequence[{len(sequence) - 1}]", f"the goal {pt(goal)} is not in cell {sequence[-1]}")
    for i, (x, y) in enumerate(zip(sequence, sequence[1:])):
        if y not in cells[x][1]:
            c.fail(f"claims.sequence[{i + 1}]", f"cell {y} is not a neighbour of cell {x}")
    goal_cell = sequence[-1]
    # 3. and 4. policies and flow-through
    nexts: dict[int, int | None] = {}
    arcs: list[int] = []
    unproved: list[int] = []
    lines = 0
    for i, item in enumerate(R.lst(R.field(claims, "policies", "claims"), "claims.policies")):
        where = f"claims.policies[{i}]"
        obj = R.obj(item, where)
        cell = R.integer(R.field(obj, "cell", where), f"{where}.cell")
        if not 0 <= cell < m or cell in nexts:
            raise Malformed(f"{where}.cell", f"{cell} is not a cell without a policy yet")
        field = R.obj(R.field(obj, "field", where), f"{where}.field")
        kind = R.field(field, "kind", f"{where}.field")
        ring, neighbours = cells[cell]
        c.count("policies")
        if i and cell <= R.integer(R.field(R.obj(claims["policies"][i - 1], where), "cell", where), where):
            c.fail(f"{where}.cell", "policies are listed by ascending cell")
        if cell == goal_cell:
            nexts[cell] = None
            if obj.get("next") is not None or obj.get("outlet_side") is not None:
                c.fail(f"{where}.next", f"the goal's cell {cell} has no outlet and no next cell")
            if kind != "goal" or R.point(R.field(field, "goal", f"{where}.field"), f"{where}.field.goal") != goal:
                c.fail(f"{where}.field", f"the goal's cell {cell} must carry the goal field of the goal {pt(goal)}")
            continue
        outlet = R.integer(R.field(obj, "outlet_side", where), f"{where}.outlet_side")
        nxt = R.integer(R.field(obj, "next", where), f"{where}.next")
        if not 0 <= outlet < len(ring) or neighbours[outlet] != nxt:
            c.fail(f"{where}.next", f"cell {nxt} is not across side {outlet} of cell {cell}")
            continue
        nexts[cell] = nxt
        if kind == "line":
            lines += 1
            origin = R.point(R.field(field, "origin", f"{where}.field"), f"{where}.field.origin")
            target = R.point(R.field(field, "target", f"{where}.field"), f"{where}.field.target")
            gain = R.number(R.field(field, "gain", f"{where}.field"), f"{where}.field.gain")
            if origin == target or gain <= 0:
                c.fail(f"{where}.field", "a line field needs two different points and a positive gain")
                continue
            claimed = R.field(obj, "flows_through", where)
            if not isinstance(claimed, bool):
                raise Malformed(f"{where}.flows_through", "expected true or false")
            failing = None
            for s in range(len(ring)):
                if s == outlet:
                    continue
                a, b = ring[s], ring[(s + 1) % len(ring)]
                normal = (-(b[1] - a[1]), b[0] - a[0])
                c.count("inward_tests", 2)
                bad = next((q for q in (a, b) if line_inward_sign(origin, target, gain, normal, q) <= 0), None)
                if bad is not None:
                    failing = (s, bad)
                    break
            if claimed and failing is not None:
                c.fail(f"{where}.flows_through", f"the line field of cell {cell} does not point strictly into it at "
                       f"{pt(failing[1])} on side {failing[0]}: a trajectory may leave through a side that is not the outlet")
            elif not claimed and failing is None:
                c.fail(f"{where}.flows_through", f"claims false, but the line field of cell {cell} points strictly into "
                       f"it on every side but the outlet")
            elif not claimed:
                unproved.append(cell)
        elif kind == "arc":
            arcs.append(cell)
        else:
            c.fail(f"{where}.field.kind", f"{kind!r} is not a field for a cell that is not the goal's (line or arc)")
    missing = [k for k in range(m) if k not in nexts]
    if missing:
        c.fail("claims.policies", f"cells {missing[:8]} have no policy")
    for k in range(m):
        seen: set[int] = set()
        at: int | None = k
        while at is not None and at not in seen and at in nexts:
            seen.add(at)
            at = nexts[at]
        if at is not None:
            c.fail("claims.policies", f"following the outlets from cell {k} never reaches the goal's cell {goal_cell}")
            break
    if unproved:
        c.not_checked.append(f"a way out of cells {unproved[:10]}: the planner found no field there that flows through "
                             f"(as the answer says)")
    if arcs:
        c.not_checked.append(f"the flow-through of the arc fields of cells {arcs} (the planner's dense sample of RK4 "
                             f"trajectories, not a proof)")
    c.not_checked.append("the simulated scenarios (statistics of random runs, not claims)")
    c.summary = {"cells": m, "sequence": len(sequence), "line_fields": lines, "arc_fields": len(arcs)}
    c.scope = (f"the composed fields of {m} convex cells in this environment{' with holes' if len(env.rings) > 1 else ''}, "
               f"for a robot following the field exactly (the integrator model), from {pt(start)} to {pt(goal)}")
    c.proved.append(f"the {m} cells tile the free space, and the outlets lead every cell to the goal's cell")
    if arcs or unproved:
        c.proved.append(f"in the {lines - len(unproved)} cells whose line fields flow through, every trajectory leaves "
                        f"through the outlet; the goal is reached straight from anywhere in its cell")
    else:
        c.proved.append("every cell's line field carries every point of the cell out through its outlet, and the goal "
                        "field takes the goal's cell straight to the goal: from every point of the free space the "
                        "composed fields reach the goal")
