"""The structure of the exact safe set of any two segments (paper §5, generalising Prop. 2).

Setting (as in :mod:`solverplan.bounce.safe`, whose module docstring holds the full written proof).
Source e_i = (a, b), target e_j = (c, d), free space on the left of both; a heading θ ∈ (0, π) is
safe when the ray from every point of the open e_i first meets the boundary in the open e_j. R(θ) is
the open region swept by those rays up to the line of e_j; Open = the points strictly left of both
segments' lines.

Claims and what is checked here (sympy, with a = (0, 0), b = (L, 0), L > 0 — every configuration is
one of these after a rotation, a translation and a scaling, which preserve headings):

1. *Strip membership.* For p = a + r(cos α, sin α) = b + ρ(cos β, sin β) above the line of e_i and
   u = (cos θ, sin θ): cross(u, p − a) = r·sin(α − θ) and cross(u, p − b) = ρ·sin(β − θ). With α, β,
   θ ∈ (0, π) the signs are those of α − θ and β − θ, so p ∈ R(θ) ⇔ p ∈ Open and α < θ < β: a point
   blocks exactly the open interval (ang(p − a), ang(p − b)).
2. *A point has the larger heading seen from b.* cross(p − a, p − b) = L·p_y > 0 above the line, so
   that interval is never empty (and Prop. 2's θ_lo = ang(c − b) is the larger lower bound).
3. *Landing points are affine.* The ray from s = a + σ(b − a) at direction u meets the line c + τδ at
   τ(σ) = cross(s − c, u) / cross(δ, u), affine in σ: all of the open e_i lands in the open e_j iff the
   two limit landings (σ = 0, 1) lie in [c, d] (the unobstructed set Θ₀).
4. *Headings along a segment are monotone.* d/dλ ang(p₀ + λv − a) = cross(p₀ − a, v) / |p₀ + λv − a|²,
   of constant sign: an edge blocks the open interval between the extreme headings of the ends of its
   part inside Open, so the safe set is Θ₀ minus finitely many open intervals — closed.
5. *Prop. 2's cases.* For c, d above the line, the lines a–d and b–c meet below e_i exactly when
   cross(c − b, d − a) > 0, i.e. θ_lo < θ_hi (the meeting point's height times cross(d − a, c − b)
   equals L·c_y·d_y > 0), and are parallel exactly when θ_lo = θ_hi.
6. *With holes the safe set can be several intervals* (the erratum below): in the 24 × 8 room with a
   1 × 1 hole above the middle of the floor piece (−1, 0)–(1, 0), the exact safe set towards the
   ceiling, computed by :func:`solverplan.bounce.safe.safe_set` in rational arithmetic, is two
   intervals; the headings of (1, 1) and (−1, 1) are safe and the heading of (0, 1) is not — checked
   exactly, the blocking edge and the two landing conditions recomputed here with sympy rationals.

The topological part — without holes the safe set is one interval, because a boundary point hit
between two headings that both reach e_j from one point would lie on a ring trapped in a triangle
whose sides are free, i.e. on a hole — is a written proof (:mod:`solverplan.bounce.safe`, (4));
``tests/bounce/test_safe.py`` checks it on random polygons.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._core import ProofResult, Step

ERRATUM = (
    "One might expect that the exact set of safe headings of any two segments is an interval; that holds only "
    "for environments without holes. With holes it is a finite union of closed intervals: a hole strictly "
    "above the middle of e_i blocks θ = π/2 but not π/4 or 3π/4 (step 6). The safe BVG keeps every interval "
    "(safe_set) and reports the widest as `safe`."
)


def blocked_interval(alpha, beta):
    """The headings a point p blocks, as (lower, upper) of an open interval: (ang(p − a), ang(p − b))."""
    return alpha, beta


def landing_parameter(s, u, c, delta):
    """τ such that the ray from s with direction u meets the line c + τ·δ at c + τ·δ."""
    return _cross(s[0] - c[0], s[1] - c[1], u[0], u[1]) / _cross(delta[0], delta[1], u[0], u[1])


def _cross(ux, uy, vx, vy):
    return ux * vy - uy * vx


def prove() -> ProofResult:
    """Check the algebraic facts behind the structure of the exact safe set, and the hole counterexample."""
    L = sp.symbols("L", positive=True)
    r, rho = sp.symbols("r rho", positive=True)
    alpha, beta, theta = sp.symbols("alpha beta theta", real=True)
    steps = []

    # 1. strip membership
    p = (r * sp.cos(alpha), r * sp.sin(alpha))  # p − a
    u = (sp.cos(theta), sp.sin(theta))
    side_a = sp.simplify(_cross(u[0], u[1], p[0], p[1]) - r * sp.sin(alpha - theta))
    q = (rho * sp.cos(beta), rho * sp.sin(beta))  # p − b
    side_b = sp.simplify(_cross(u[0], u[1], q[0], q[1]) - rho * sp.sin(beta - theta))
    lo, hi = blocked_interval(alpha, beta)
    # on (0, π) × (0, π), α − θ ∈ (−π, π), where sin has the sign of its argument
    x = sp.symbols("x", real=True)
    window = sp.Interval.open(-sp.pi, sp.pi)
    sign_rule = (sp.solveset(sp.sin(x) > 0, x, window) == sp.Interval.open(0, sp.pi)
                 and sp.simplify(sp.sin(-x) + sp.sin(x)) == 0)  # positive on (0, π) and odd
    steps.append(Step(
        "p ∈ R(θ) ⇔ ang(p − a) < θ < ang(p − b): cross(u, p − a) = r·sin(α − θ), cross(u, p − b) = ρ·sin(β − θ)",
        side_a == 0 and side_b == 0 and (lo, hi) == (alpha, beta) and sign_rule,
        "a point of Open lies strictly right of the corner ray from a iff α < θ, strictly left of the one from b iff θ < β",
    ))

    # 2. the larger heading from b
    px = sp.symbols("p_x", real=True)
    py = sp.symbols("p_y", positive=True)
    larger = sp.simplify(_cross(px, py, px - L, py) - L * py)
    steps.append(Step("cross(p − a, p − b) = L·p_y > 0: ang(p − a) < ang(p − b), the blocked interval is non-empty",
                      larger == 0))

    # 3. landing parameter affine in σ
    sigma = sp.symbols("sigma", real=True)
    ux, uy, cx, cy, dx, dy = sp.symbols("u_x u_y c_x c_y delta_x delta_y", real=True)
    s = (sigma * L, sp.Integer(0))
    tau = landing_parameter(s, (ux, uy), (cx, cy), (dx, dy))
    affine = sp.simplify(sp.diff(tau, sigma, 2)) == 0
    steps.append(Step("the landing parameter τ(σ) on e_j's line is affine in the source point σ ∈ [0, 1]", affine,
                      str(sp.simplify(sp.diff(tau, sigma)))))

    # 4. monotone heading along a segment
    lam = sp.symbols("lambda", real=True)
    x0, y0, vx, vy = sp.symbols("x_0 y_0 v_x v_y", real=True)
    heading = sp.atan2(y0 + lam * vy, x0 + lam * vx)
    derivative = sp.simplify(sp.diff(heading, lam) - _cross(x0, y0, vx, vy) / ((x0 + lam * vx) ** 2 + (y0 + lam * vy) ** 2))
    steps.append(Step("d/dλ ang(p₀ + λv − a) = cross(p₀ − a, v)/|p₀ + λv − a|²: one sign along an edge", derivative == 0))

    # 5. Prop. 2's cases: the lines a–d and b–c meet below e_i iff cross(c − b, d − a) > 0
    Cx, Dx = sp.symbols("C_x D_x", real=True)
    Cy, Dy = sp.symbols("C_y D_y", positive=True)
    # X = a + t (d − a) = b + w (c − b): solve for t
    t, w = sp.symbols("t w", real=True)
    sol = sp.solve([t * Dx - (L + w * (Cx - L)), t * Dy - w * Cy], [t, w], dict=True)[0]
    height = sp.simplify(sol[t] * Dy)
    meet = sp.simplify(height * _cross(Dx, Dy, Cx - L, Cy) - L * Cy * Dy)
    steps.append(Step(
        "Prop. 2 cases: height(X) · cross(d − a, c − b) = L·c_y·d_y > 0, so X is below e_i ⇔ cross(c − b, d − a) > 0 ⇔ θ_lo < θ_hi",
        meet == 0, f"height(X) = {height}",
    ))

    # 6. the hole counterexample, exactly
    steps.extend(_hole_counterexample())
    return ProofResult("Structure of the exact safe set (Prop. 2 generalised; several intervals with holes)",
                       tuple(steps), errata=(ERRATUM,))


def _hole_counterexample() -> list[Step]:
    from fractions import Fraction

    from solverplan.bounce.safe import heading_is_safe, safe_set
    from solverplan.environment import Environment

    room = Environment.from_coords([[-12, 0], [12, 0], [12, 8], [-12, 8]],
                                   [[[-0.5, 2], [0.5, 2], [0.5, 3], [-0.5, 3]]], name="room with a hole")
    floor, ceiling = ((-1, 0), (1, 0)), ((12, 8), (-12, 8))
    found = safe_set(room, floor, ceiling)
    one = Fraction(1)
    diag_r = heading_is_safe(room, floor, ceiling, (one, one))
    diag_l = heading_is_safe(room, floor, ceiling, (-one, one))
    up = heading_is_safe(room, floor, ceiling, (0, one))
    # recompute with sympy rationals: at θ = π/2 the hole's bottom edge y = 2, |x| ≤ 1/2 lies inside the strip
    # |x| < 1 below the ceiling; at θ = π/4 the strip at height y is (y − 1, y + 1), which misses the hole
    # (|x| ≤ 1/2 at 2 ≤ y ≤ 3) and lands on the ceiling at x ∈ (7, 9) ⊂ (−12, 12).
    y = sp.symbols("y", real=True)
    half = sp.Rational(1, 2)
    blocked_up = bool(-1 < -half) and bool(half < 1)
    clear_diag = all(sp.Interval.open(yy - 1, yy + 1).intersect(sp.Interval(-half, half)) == sp.EmptySet
                     for yy in (2, sp.Rational(5, 2), 3))
    lands = sp.Interval.open(8 - 1, 8 + 1).is_subset(sp.Interval.open(-12, 12))
    del y
    return [
        Step("hole counterexample: the exact safe set floor → ceiling is two intervals", len(found) == 2,
             str(found.to_json())),
        Step("heading of (1, 1) and of (−1, 1) safe, of (0, 1) not (exact rational check)", diag_r and diag_l and not up),
        Step("sympy recomputation: at π/2 the hole's bottom edge lies in the swept strip; at π/4 the strip misses "
             "the hole and lands on the ceiling", blocked_up and clear_diag and bool(lands)),
    ]
