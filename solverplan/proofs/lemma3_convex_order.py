"""Lemma 3 (paper §6.1): in a convex polygon a small constant heading visits the edges in CCW order.

Statement. Let P be a strictly convex polygon, CCW, edges e_i = v_i → v_{i+1}. If
0 < θ < min_i ∠v_{i+2} v_i v_{i+1}, the ray at heading θ (CCW from e_i) from any point of the open edge
e_i first meets ∂P on the open edge e_{i+1}, at distance C(θ, φ_{i,i+1})·(ℓ_i − d) from v_{i+1} (Lemma 2's
right transition, φ_{i,i+1} the interior angle at v_{i+1}); so the constant rule visits e₀, e₁, … in CCW
order forever, from any start. Adding θ < min_i (π/2 − φ_{i,i+1}/2) makes every step contract (Lemma 2),
hence the return map too (Def. 12), and Theorem 1's limit cycle attracts every start.

Setting. The frame of e_i: v_i = (0, 0), v_{i+1} = (L, 0), v_{i+2} = q = (q_x, q_y) with q_y > 0 (a left turn
at v_{i+1}); the start p = (x, 0) with 0 < x < L written as x = L − m, m > 0; u = cot θ (direction ∝ (u, 1),
u decreasing in θ, see ``affine_transition``).

Derivation. (1) Solving p + s(u, 1) = v_{i+1} + r(q − v_{i+1}) gives r = (L − x)/(q_y u + L − q_x), s = r q_y.
(2) Hit on the open edge, ahead: if u = (q_x − x)/q_y + g/q_y with g > 0, then r, 1 − r and s are positive;
if g ≤ 0 then r(1 − r) ≤ 0, so r ∉ (0, 1): the ray from p meets the open e_{i+1} iff u > (q_x − x)/q_y,
i.e. iff θ < ang(q − p) (cot ang(q − p) = (q_x − x)/q_y, cot decreasing on (0, π)). (3) (q_x − x)/q_y
decreases in x, so the binding start is x → 0: θ < ∠v_{i+2} v_i v_{i+1} (cot = q_x/q_y) works for every start
of the open edge. (4) With q = v_{i+1} + ℓ(−cos φ, sin φ), the hit is C(θ, φ)(L − x) from v_{i+1}. (5) The
range lies inside the right-transition domain: ∠v_{i+2} v_i v_{i+1} < π − φ_{i,i+1}. (6) First hit: every edge's
signed distance g is affine along the segment from p to the hit h, nonnegative at both ends and positive at
one (strict convexity: p lies only on e_i's line, h only on e_{i+1}'s), hence positive strictly between:
the open segment is interior, and h is the first boundary point on the ray. (7) An example.

Written part (induction). Steps (1)–(6) hold for every i, so from e_i the robot reaches the open e_{i+1},
where the same argument applies: edges are visited in CCW order forever, from any start on any edge.

Errata / remarks (no formula errors).
- The strict bound is not sharp: for the *open* edge, θ = min_i ∠v_{i+2} v_i v_{i+1} also works (the binding
  start x → 0 is a vertex, which is never a robot position). For θ above it, the starts with
  0 < x ≤ min(L, q_x − u q_y) miss e_{i+1}.
- The paper's Lemma 3 range also requires θ < π/2 − φ/2 at every vertex (each step contracts). Theorem 1
  needs only Π_k C_k < 1, which can hold when some steps expand (Def. 12); the per-step bound is sufficient,
  not necessary.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import is_zero, text
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove"]


def prove() -> ProofResult:
    """Lemma 3: small constant headings visit the edges of a convex polygon in CCW order."""
    length, qy, m = sp.symbols("L q_y m", positive=True)
    qx, u, x = sp.symbols("q_x u x", real=True)
    s, r = sp.symbols("s r", real=True)
    steps: list[Step] = []

    p = sp.Matrix([x, 0])
    v1, q = sp.Matrix([length, 0]), sp.Matrix([qx, qy])
    (sol,) = sp.solve(list(p + s * sp.Matrix([u, 1]) - (v1 + r * (q - v1))), [s, r], dict=True)
    r_hit, s_hit = sol[r], sol[s]
    steps.append(Step(
        "solving p + s(u, 1) = v_{i+1} + r(v_{i+2} − v_{i+1}): r = (L − x)/(q_y u + L − q_x), s = r·q_y",
        is_zero(sp.together(r_hit - (length - x) / (qy * u + length - qx))) and is_zero(sp.together(s_hit - r_hit * qy)),
        f"r = {text(r_hit)}",
    ))
    g_pos, g_non = sp.Symbol("g", positive=True), sp.Symbol("g", nonnegative=True)
    start = {x: length - m}
    good = {**start, u: (qx - (length - m)) / qy + g_pos / qy}
    r_good = sp.simplify(r_hit.subs(good))
    hits = all(sp.simplify(e).is_positive is True for e in (r_good, 1 - r_good, s_hit.subs(good)))
    bad = {**start, u: (qx - (length - m)) / qy - g_non / qy}
    r_bad = sp.factor(sp.simplify(r_hit.subs(bad)))
    product_num, product_den = sp.fraction(sp.factor(sp.simplify(r_bad * (1 - r_bad))))
    # numerator ≤ 0 over a square (nonzero unless the ray is parallel to e_{i+1}): r(1 − r) ≤ 0
    misses = product_num.is_nonpositive is True and product_den.is_Pow and product_den.exp == 2
    steps.append(Step(
        "the ray meets the open edge e_{i+1} ahead of p iff u > (q_x − x)/q_y: with u − (q_x − x)/q_y = g/q_y, g > 0 "
        "makes r, 1 − r, s positive and g ≤ 0 makes r(1 − r) ≤ 0",
        hits and misses,
        f"g > 0: r = {text(r_good)}; g ≤ 0: r(1 − r) = {text(sp.factor(sp.simplify(r_bad * (1 - r_bad))))}",
    ))
    steps.append(Step(
        "u > (q_x − x)/q_y iff θ < ang(v_{i+2} − p): cot(atan2(q_y, q_x − x)) = (q_x − x)/q_y and cot decreases on (0, π)",
        is_zero(sp.cot(sp.atan2(qy, qx - x)) - (qx - x) / qy)
        and (sp.diff(sp.cot(sp.Symbol("t")), sp.Symbol("t")) + 1 + sp.cot(sp.Symbol("t")) ** 2) == 0,
    ))
    bound_at = (qx - x) / qy
    steps.append(Step(
        "(q_x − x)/q_y decreases in x, so θ < ∠v_{i+2} v_i v_{i+1} (u > q_x/q_y, the value at x = 0) gives u > (q_x − x)/q_y "
        "for every start 0 < x < L",
        sp.diff(bound_at, x).is_negative is True
        and is_zero(qx / qy - bound_at - x / qy)
        and (sp.Symbol("x", positive=True) / qy).is_positive is True
        and is_zero(sp.cot(sp.atan2(qy, qx)) - qx / qy),
        f"q_x/q_y − (q_x − x)/q_y = {text(sp.simplify(qx / qy - bound_at))} > 0 for x > 0",
    ))

    theta, phi, ell = sp.symbols("theta phi ell", positive=True)
    q_angle = {qx: length - ell * sp.cos(phi), qy: ell * sp.sin(phi)}
    distance = (r_hit * ell).subs(q_angle).subs(u, sp.cos(theta) / sp.sin(theta))
    steps.append(Step(
        "with v_{i+2} = v_{i+1} + ℓ(−cos φ, sin φ) (interior angle φ at v_{i+1}) the hit is C(θ, φ)·(L − x) from v_{i+1}, "
        "C = sin θ / sin(θ + φ): Lemma 2's right transition",
        is_zero(sp.simplify(distance - sp.sin(theta) / sp.sin(theta + phi) * (length - x))),
        f"distance = {text(sp.simplify(distance))}",
    ))
    steps.append(Step(
        "the range lies inside the right-transition domain: cot ∠v_{i+2} v_i v_{i+1} = q_x/q_y > (q_x − L)/q_y = cot(π − φ), "
        "so θ < ∠v_{i+2} v_i v_{i+1} implies θ + φ < π",
        is_zero(qx / qy - (qx - length) / qy - length / qy)
        and (length / qy).is_positive is True
        and is_zero(sp.cot(sp.pi - phi) - ((qx - length) / qy).subs(q_angle)),
    ))

    lam = 1 / (1 + sp.Symbol("mu", positive=True))  # λ ∈ (0, 1)
    nx, ny, h0 = sp.symbols("n_x n_y h_0", real=True)
    px, py, hx, hy = sp.symbols("p_x p_y h_x h_y", real=True)

    def g(point: sp.Matrix) -> sp.Expr:
        return nx * point[0] + ny * point[1] - h0

    pp, hh = sp.Matrix([px, py]), sp.Matrix([hx, hy])
    affine = is_zero(g((1 - lam) * pp + lam * hh) - ((1 - lam) * g(pp) + lam * g(hh)))
    a_pos, b_non = sp.Symbol("a", positive=True), sp.Symbol("b", nonnegative=True)
    interior = ((1 - lam) * a_pos + lam * b_non).is_positive is True and ((1 - lam) * b_non + lam * a_pos).is_positive is True
    steps.append(Step(
        "first hit: an edge line's signed distance g is affine along the segment p→h, g((1−λ)p + λh) = (1−λ)g(p) + λg(h); "
        "with g ≥ 0 at both ends and > 0 at one (strict convexity), g > 0 for 0 < λ < 1: the open segment is interior",
        affine and interior,
    ))

    pts = [sp.Matrix(v) for v in ((0, 0), (4, 0), (7, 4), (0, 4))]
    n = len(pts)
    cot_angles = []
    for i in range(n):
        e = pts[(i + 1) % n] - pts[i]
        w = pts[(i + 2) % n] - pts[i]
        cot_angles.append(e.dot(w) / (e[0] * w[1] - e[1] * w[0]))  # cot ∠v_{i+2} v_i v_{i+1}
    u_example = sp.Rational(12, 5)  # sin θ = 5/13, cos θ = 12/13: Theorem 1's example
    steps.append(Step(
        "example quadrilateral (0,0),(4,0),(7,4),(0,4): cot θ = 12/5 exceeds every cot ∠v_{i+2} v_i v_{i+1}, so θ = atan(5/12) "
        "is in Lemma 3's range (Theorem 1's ray casting confirms every hit lands on the next edge)",
        all(u_example > c for c in cot_angles),
        "cot ∠ = " + ", ".join(str(c) for c in cot_angles),
    ))
    errata = (
        "Lemma 3: the bound θ < min_i ∠v_{i+2} v_i v_{i+1} may be non-strict (≤) for open edges — the binding start "
        "is the vertex v_i, never a robot position.",
        "Lemma 3: requiring θ < π/2 − φ/2 at every vertex (each step contracts) is sufficient, not necessary, "
        "for Theorem 1's limit cycle: Π_k C_k < 1 suffices (Def. 12).",
    )
    return ProofResult("Lemma 3 (convex polygon: constant heading visits edges in CCW order)", tuple(steps), errata=errata)
