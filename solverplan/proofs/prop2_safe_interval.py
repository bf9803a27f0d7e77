"""Paper Prop. 2 (Nilles et al., §5): the safe interval between entirely visible segments.

Setting. Source e_i = (a, b) with a = (0, 0), b = (L, 0), L > 0, free space above (y > 0); target
e_j = (c, d) with c, d strictly above the x-axis, oriented with the free space on its left, i.e. seen
from e_i the target runs from c (right) to d (left). A ray from s = (x, 0), 0 < x < L, at heading θ
(CCW from +x) meets the target's line at the point whose direction angle from s is θ; for an entirely
visible pair nothing blocks it, so it lands on e_j iff ang(c − s) ≤ θ ≤ ang(d − s).

Claim. The headings safe from *every* s of e_i form [θ_lo, θ_hi] with θ_lo = ang(c − b),
θ_hi = ang(d − a), empty when θ_lo > θ_hi, a singleton when c − b ∥ d − a.

Derivation checked here:
1. ang(p − s) = atan2(p_y, p_x − x) is strictly increasing in x for p above the axis
   (its x-derivative is p_y / |p − s|² > 0), so over x ∈ [0, L] the largest lower bound is at x = L
   (ang(c − b)) and the smallest upper bound at x = 0 (ang(d − a)).
2. The parallel case: θ_lo = θ_hi iff (c − b) × (d − a) = 0, i.e. the two corner rays are parallel
   and the swept region is a parallelogram with sides b→c and a→d.
3. θ_lo ≤ θ_hi iff the cross product (c − b) × (d − a) ≥ 0 (both vectors point into the upper half
   plane, where the angle order is the orientation order) — the exact test the code uses.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._core import ProofResult, Step


def prove() -> ProofResult:
    """Check Prop. 2's interval ends and its exact emptiness test."""
    x = sp.symbols("x", positive=True)
    px = sp.symbols("p_x", real=True)
    py = sp.symbols("p_y", positive=True)

    angle = sp.atan2(py, px - x)  # ang(p − s) for s = (x, 0)
    derivative = sp.simplify(sp.diff(angle, x))
    expected = py / ((px - x) ** 2 + py**2)
    monotone = sp.simplify(derivative - expected) == 0 and bool(expected.is_positive)

    # θ_lo ≤ θ_hi  ⇔  cross(c − b, d − a) ≥ 0 for vectors in the upper half plane:
    # with u = (u_x, u_y), v = (v_x, v_y), u_y, v_y > 0, cot is decreasing on (0, π), so
    # ang(u) ≤ ang(v) ⇔ cot ang(u) ≥ cot ang(v) ⇔ u_x/u_y ≥ v_x/v_y ⇔ u_x v_y − v_x u_y ≥ 0.
    ux, vx = sp.symbols("u_x v_x", real=True)
    uy, vy = sp.symbols("u_y v_y", positive=True)
    cot_gap = sp.simplify((ux / uy - vx / vy) * uy * vy - (ux * vy - vx * uy))
    cot_of_atan2 = sp.simplify(sp.cot(sp.atan2(uy, ux)) - ux / uy)
    cross_test = cot_gap == 0 and cot_of_atan2 == 0

    # the parallel case: equal angles iff zero cross product (u, v both in the upper half plane)
    k = sp.symbols("k", positive=True)
    parallel = sp.simplify((ux * (k * uy) - (k * ux) * uy)) == 0

    return ProofResult(
        "Prop. 2 (safe interval of entirely visible segments)",
        (
            Step("d/dx ang(p − (x, 0)) = p_y / |p − s|² > 0: the bound ang(c − s) is largest at s = b "
                 "and ang(d − s) smallest at s = a", monotone, str(derivative)),
            Step("θ_lo ≤ θ_hi ⇔ (c − b) × (d − a) ≥ 0 (cot is decreasing on (0, π))", cross_test),
            Step("singleton iff the corner rays are parallel (cross product 0)", parallel),
        ),
    )
