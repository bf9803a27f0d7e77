"""A fixed-heading transition is affine in the boundary parameter, linear-fractional in cot θ.

Statement. In the frame of the source segment (x along it, free space y > 0) write the heading by
u = cot θ (direction ∝ (u, 1), u decreasing in θ). A ray from (x, 0) meets the line n·p = h at

    x′ = (n_y x + h u) / (n_x u + n_y),     y′ = (h − n_x x) / (n_x u + n_y),

so the parameter τ of the hit on the target e_j = (c, d) is (α₁ x + α₂ u + α₃) / (n_x u + n_y): affine in x
for a fixed heading, monotone in u for a fixed x (on either side of the one u where the ray is parallel
to the target), and the corner conditions 0 ≤ τ ≤ 1 are linear in (x, u) once multiplied by the
denominator. In world coordinates, with source point a + t(b − a) and a direction vector w,
τ(t) = ((a + t(b − a) − c) × w) / ((d − c) × w) = α t + β, where α and β are ratios of integer polynomials
in the coordinates of a, b, c, d, w — rational for rational inputs. In arclength the slope is ∓C (Lemma 2).

Setting. Symbols for x, u, the normal n, the offset h, the target's ends c, d (with n ⊥ d − c and
h = n·c), and in world coordinates a, b, c, d, w; all real.

Derivation. (1) (cos θ, sin θ) = sin θ·(cot θ, 1) with sin θ > 0 on (0, π), and d(cot θ)/dθ = −1/sin²θ < 0.
(2) Solve n·((x, 0) + s(u, 1)) = h for s and compare x′ = x + u s, y′ = s with the formulas. (3) Define
τ = ((x′, y′) − c)·(d − c)/|d − c|²; the hit is c + τ(d − c) (zero cross product), and τ times the
denominator is a polynomial of total degree ≤ 1 in (x, u) — the form (α₁x + α₂u + α₃)/(n_x u + n_y), and
(1 − τ) times it too (linear corner conditions). (4) ∂²τ/∂x² = 0; ∂τ/∂x · D and ∂τ/∂u · D² do not depend on
u (resp. x for the first), and D = n_x u + n_y has at most one root in u: the signs of the partial
derivatives are constant where D keeps its sign, so τ is monotone in x and in u there. (5) Solve
a + t(b − a) + s w = c + τ(d − c) for τ, check the cross-product form, ∂²τ/∂t² = 0, and that numerator and
denominator are polynomials over ℤ in the coordinates; (6) it agrees with (3) in the source frame
(a = 0, b = (L, 0), x = tL, w = (u, 1)); (7) in Lemma 2's right-transition triangle the arclength slope
(ℓ_j/ℓ_i)·dτ/dt is −C(θ, φ); (8) a rational example gives rational α, β.

Errata. None: the library's x′, y′ and the form of τ are confirmed. Precision: τ is monotone in u only on
each side of the parallel direction u = −n_y/n_x (where the denominator vanishes); within a safe interval
the ray always hits the target line ahead, so the denominator is sign-definite there, as the library assumes.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import is_zero, sin_positive_on_open_0_pi, text, transition_triangle
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove", "hit_parameter_world"]


def _cross(p: sp.Matrix, q: sp.Matrix) -> sp.Expr:
    return p[0] * q[1] - p[1] * q[0]


def hit_parameter_world(a, b, c, d, w, t) -> sp.Expr:
    """τ of the hit of the ray from a + t(b − a) with direction w on the line c + τ(d − c), by solving."""
    s, tau = sp.symbols("s tau", real=True)
    start = a + t * (b - a)
    (solution,) = sp.solve(list(start + s * w - (c + tau * (d - c))), [s, tau], dict=True)
    return solution[tau]


def prove() -> ProofResult:
    """A fixed-heading transition is affine in the source parameter and linear-fractional in cot θ."""
    theta = sp.Symbol("theta", positive=True)
    x, u, s = sp.symbols("x u s", real=True)
    nx, ny, h = sp.symbols("n_x n_y h", real=True)
    cx, cy, dx, dy = sp.symbols("c_x c_y d_x d_y", real=True)
    steps: list[Step] = []

    direction_ok = is_zero(sp.cos(theta) - sp.sin(theta) * sp.cot(theta)) and sin_positive_on_open_0_pi()
    du = sp.diff(sp.cot(theta), theta)
    steps.append(Step(
        "(cos θ, sin θ) = sin θ·(u, 1) with u = cot θ and sin θ > 0 on (0, π); du/dθ = −1/sin²θ < 0 (u decreases)",
        direction_ok and is_zero(du + 1 / sp.sin(theta) ** 2),
        f"du/dθ = {text(sp.simplify(du))}",
    ))
    (s_hit,) = sp.solve(sp.Eq(nx * (x + s * u) + ny * s, h), s)
    x_hit, y_hit = x + u * s_hit, s_hit
    denominator = nx * u + ny
    steps.append(Step(
        "solving n·((x, 0) + s(u, 1)) = h: x′ = (n_y x + h u)/(n_x u + n_y), y′ = (h − n_x x)/(n_x u + n_y)",
        is_zero(sp.together(x_hit - (ny * x + h * u) / denominator))
        and is_zero(sp.together(y_hit - (h - nx * x) / denominator)),
        f"s = {text(s_hit)}",
    ))
    c, d = sp.Matrix([cx, cy]), sp.Matrix([dx, dy])
    normal = sp.Matrix([-(dy - cy), dx - cx])  # ⊥ d − c
    on_line = {nx: normal[0], ny: normal[1], h: normal.dot(c)}
    hit = sp.Matrix([x_hit, y_hit]).subs(on_line)
    den = denominator.subs(on_line)
    tau = sp.together((hit - c).dot(d - c) / (d - c).dot(d - c))
    num_poly = sp.Poly(sp.cancel(tau * den), x, u)  # a polynomial in (x, u) (coefficients from c, d)
    one_minus = sp.Poly(sp.cancel((1 - tau) * den), x, u)
    steps.append(Step(
        "on e_j = (c, d) (n = (d − c)^⊥, h = n·c): the hit is c + τ(d − c), and τ·(n_x u + n_y) and (1 − τ)·(n_x u + n_y) "
        "have total degree ≤ 1 in (x, u): τ = (α₁x + α₂u + α₃)/(n_x u + n_y), corner conditions linear in (x, u)",
        is_zero(sp.together(_cross(hit - c, d - c)))
        and num_poly.total_degree() <= 1
        and one_minus.total_degree() <= 1,
        f"τ·D = {text(num_poly.as_expr())}, D = {text(den)}",
    ))
    dtau_du = sp.together(sp.diff(tau, u))
    dtau_dx = sp.together(sp.diff(tau, x))
    u_free = sp.diff(sp.cancel(dtau_du * den**2), u) == 0
    x_rate = sp.cancel(dtau_dx * den)
    roots = sp.solve(denominator, u)
    steps.append(Step(
        "for a fixed heading τ is affine in x (∂²τ/∂x² = 0); ∂τ/∂x·D and ∂τ/∂u·D² do not depend on u and D has at most "
        "one root in u (the ray parallel to e_j): τ is monotone in x and in u wherever D keeps its sign",
        is_zero(sp.diff(tau, x, 2))
        and u_free
        and sp.diff(x_rate, u) == 0
        and sp.diff(x_rate, x) == 0
        and len(roots) <= 1,
        f"∂τ/∂u·D² = {text(sp.factor(sp.cancel(dtau_du * den**2)))}; root of D: u = {text(roots)}",
    ))

    ax, ay, bx, by, wx, wy, t = sp.symbols("a_x a_y b_x b_y w_x w_y t", real=True)
    a, b, w = sp.Matrix([ax, ay]), sp.Matrix([bx, by]), sp.Matrix([wx, wy])
    tau_world = sp.together(hit_parameter_world(a, b, c, d, w, t))
    cross_form = _cross(a + t * (b - a) - c, w) / _cross(d - c, w)
    coordinates = (ax, ay, bx, by, cx, cy, dx, dy, wx, wy)
    num_w, den_w = sp.fraction(sp.cancel(tau_world))
    alpha = sp.cancel(sp.diff(tau_world, t))
    beta = sp.cancel(tau_world.subs(t, 0))
    integer_polys = all(
        sp.Poly(part, *coordinates).domain == sp.ZZ
        for expr in (alpha, beta)
        for part in sp.fraction(expr)
    )
    steps.append(Step(
        "world frame: τ(t) = ((a + t(b − a) − c) × w)/((d − c) × w) = α t + β (∂²τ/∂t² = 0) with α, β ratios of integer "
        "polynomials in the coordinates: rational vertices and a rational direction give rational α, β",
        is_zero(sp.together(tau_world - cross_form))
        and is_zero(sp.diff(tau_world, t, 2))
        and integer_polys
        and sp.Poly(num_w, t).degree() <= 1,
        f"α = {text(alpha)}",
    ))
    length = sp.Symbol("L", positive=True)
    in_frame = tau_world.subs({ax: 0, ay: 0, bx: length, by: 0, wx: u, wy: 1, t: x / length}, simultaneous=True)
    steps.append(Step(
        "the world-frame τ agrees with the source-frame τ (a = 0, b = (L, 0), x = tL, w = (u, 1))",
        is_zero(sp.together(in_frame - tau)),
    ))

    tri = transition_triangle("right")
    ell_i, ell_j = sp.symbols("ell_i ell_j", positive=True)
    a_r, b_r = sp.Matrix([-ell_i, 0]), sp.Matrix([0, 0])  # the source ends at the corner V = origin
    c_r, d_r = sp.Matrix([0, 0]), ell_j * sp.Matrix([-sp.cos(tri.phi), sp.sin(tri.phi)])
    w_r = sp.Matrix([sp.cos(tri.theta), sp.sin(tri.theta)])
    tau_r = hit_parameter_world(a_r, b_r, c_r, d_r, w_r, t)
    arclength_slope = sp.diff(tau_r, t) * ell_j / ell_i
    steps.append(Step(
        "in Lemma 2's right-transition triangle the arclength slope (ℓ_j/ℓ_i)·dτ/dt is −C(θ, φ) = −sin θ/sin(θ + φ) "
        "(the map reverses orientation: both distances are measured from the corner)",
        is_zero(arclength_slope + tri.ratio),
        f"(ℓ_j/ℓ_i)·dτ/dt = {text(sp.simplify(arclength_slope))}",
    ))

    q = {ax: 0, ay: 0, bx: 4, by: 0, cx: 4, cy: 0, dx: 7, dy: 4, wx: 12, wy: 5}  # e0 → e1 of Theorem 1's example
    alpha_q, beta_q = alpha.subs(q), beta.subs(q)
    steps.append(Step(
        "example a = (0,0), b = (4,0), c = (4,0), d = (7,4), w = (12,5) (heading with cot θ = 12/5): α, β are exact "
        "rationals, and the arclength slope is −C₀ = −25/33 as in Theorem 1's example",
        alpha_q.is_Rational is True
        and beta_q.is_Rational is True
        and 0 <= beta_q <= 1
        and 0 <= alpha_q + beta_q <= 1
        and alpha_q * sp.Rational(5, 4) == -sp.Rational(25, 33),  # ℓ₁/ℓ₀ = 5/4; Theorem 1's C₀ = 25/33
        f"τ(t) = {alpha_q}·t + {beta_q}; arclength slope {alpha_q * sp.Rational(5, 4)} = −C₀ of Theorem 1's example",
    ))
    return ProofResult("a fixed-heading transition is affine; linear-fractional in cot θ", tuple(steps))
