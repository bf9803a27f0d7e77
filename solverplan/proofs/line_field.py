"""The line and arc fields of Stager and Tanner (Eq. 2, our Eq. 3) and the facts the composition relies on.

Statement. For the line field v = d + p (I − d dᵀ)(q₀ − q) with |d| = 1 (Eq. 2, written componentwise as in the
paper): (a) d·v = 1; (b) the cross-track error e = d^⊥·(q − q₀) obeys ė = −p e, so e(t) = e₀ e^{−pt}; (c) v = −∇φ
with φ = −d·(q − q₀) + (p/2)‖(I − d dᵀ)(q − q₀)‖²; (d) along a side a + λ(b − a), n·v is affine in λ (so its sign on
the closed side is decided at the end points: the exact flow-through test); (e) with d = w/|w|, n·v·|w|² =
(n·w)|w| + p(|w|² n·(q₀ − q) − (n·w)(w·(q₀ − q))) (the form A√L + B the verifier decides). For the arc field
v = c_w t̂ + p(r − ρ) r̂ (t̂ the clockwise tangent): (f) ρ̇ = p(r − ρ), so |ρ − r| decays as e^{−pt}, and the
tangential speed is 1. For the reflection zones (Eq. 4): (g) in the paper's isosceles right triangle the corrected
cost (squared cross products) is 0, as the text says, while the printed cost is 2.

Setting. Symbols q = (x, y), q₀ = (x₀, y₀), d = (d_X, d_Y) with d_X² + d_Y² = 1 substituted through d = (cos β,
sin β); p, t real; e₀ real; for the arc, the centre at the origin in polar coordinates (ρ, θ).

Derivation. (a) expand d·v and use cos² + sin² = 1. (b) differentiate e along q̇ = v and solve ė = −p e by dsolve.
(c) compute −∇φ and compare with v componentwise. (d) the second derivative of n·v(a + λ(b − a)) in λ vanishes.
(e) multiply n·v by |w|², with d = w/|w|. (f) the radial component r̂·v and the tangential component t̂·v. (g) the
triangle (0,0), (1,0), (0,1): inlet the leg y = 0, outlet the leg x = 0, the hypotenuse's midpoint.

Errata. Eq. 3 (the arc field) is missing from the paper's text: we use the field above (documented in
``solverplan.reflection.fields``). Eq. 4 as printed minimises (n_in·v_in)² + (n_out·v_out)², which is 2 — its
largest possible value — in the paper's own example where the text says the minimum is 0; the intent is the sum of
the squared cross products, 2 − (n_in·v_in)² − (n_out·v_out)², which is 0 there.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import is_zero, text
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove", "line_field_velocity", "zone_cost_corrected", "zone_cost_printed"]


def line_field_velocity(q: sp.Matrix, q0: sp.Matrix, d: sp.Matrix, p: sp.Expr) -> sp.Matrix:
    """Eq. 2 written as printed: ẋ = dX + p(x₀ − x − [(x₀ − x)dX + (y₀ − y)dY]dX), ẏ likewise."""
    a = q0 - q
    proj = a[0] * d[0] + a[1] * d[1]
    return sp.Matrix([d[0] + p * (a[0] - proj * d[0]), d[1] + p * (a[1] - proj * d[1])])


def _unit(w: sp.Matrix) -> sp.Matrix:
    return w / sp.sqrt(w.dot(w))


def zone_cost_corrected(n_in, v_in, n_out, v_out):
    """Eq. 4 corrected: the sum of the squared cross products (1 − (n·v)² for unit vectors)."""
    return (1 - n_in.dot(v_in) ** 2) + (1 - n_out.dot(v_out) ** 2)


def zone_cost_printed(n_in, v_in, n_out, v_out):
    """Eq. 4 as printed."""
    return n_in.dot(v_in) ** 2 + n_out.dot(v_out) ** 2


def prove() -> ProofResult:
    """Line-field properties (d·v = 1, exponential cross-track decay, v = −∇φ), the exact flow-through test, the
    arc field's radial decay, and the corrected Eq. 4."""
    x, y, x0, y0, p, t, e0, lam = sp.symbols("x y x_0 y_0 p t e_0 lambda", real=True)
    beta = sp.Symbol("beta", real=True)
    q, q0 = sp.Matrix([x, y]), sp.Matrix([x0, y0])
    d = sp.Matrix([sp.cos(beta), sp.sin(beta)])
    v = line_field_velocity(q, q0, d, p)
    steps: list[Step] = []

    along = sp.simplify(d.dot(v))
    steps.append(Step("Eq. 2: d·v = 1 for |d| = 1 (the robot advances at unit rate along d)",
                      is_zero(d.dot(v) - 1), f"d·v = {text(along)}"))

    d_perp = sp.Matrix([-d[1], d[0]])
    e = d_perp.dot(q - q0)
    e_dot = sp.diff(e, x) * v[0] + sp.diff(e, y) * v[1]
    func = sp.Function("e")
    solution = sp.dsolve(sp.Eq(func(t).diff(t), -p * func(t)), func(t), ics={func(0): e0})
    steps.append(Step("cross-track error e = d^⊥·(q − q₀): ė = −p e along q̇ = v, so e(t) = e₀ e^{−pt}",
                      is_zero(e_dot + p * e) and is_zero(solution.rhs - e0 * sp.exp(-p * t)),
                      f"ė + p e = {text(sp.simplify(e_dot + p * e))}; dsolve: e(t) = {text(solution.rhs)}"))

    r = q - q0
    across = r - r.dot(d) * d
    phi = -d.dot(r) + p / 2 * across.dot(across)
    grad = sp.Matrix([sp.diff(phi, x), sp.diff(phi, y)])
    steps.append(Step("v = −∇φ with φ = −d·(q − q₀) + (p/2)‖(I − d dᵀ)(q − q₀)‖² (a potential field)",
                      is_zero((v + grad)[0]) and is_zero((v + grad)[1]),
                      f"φ = {text(sp.simplify(phi))}"))

    ax, ay, bx, by, nx, ny = sp.symbols("a_x a_y b_x b_y n_x n_y", real=True)
    on_side = sp.Matrix([ax, ay]) + lam * (sp.Matrix([bx, by]) - sp.Matrix([ax, ay]))
    n_dot_v = sp.Matrix([nx, ny]).dot(line_field_velocity(on_side, q0, d, p))
    steps.append(Step("along a side a + λ(b − a), n·v is affine in λ: positive on the closed side iff positive at "
                      "both end points (the exact flow-through test)",
                      is_zero(sp.diff(n_dot_v, lam, 2)), f"∂²(n·v)/∂λ² = {text(sp.diff(n_dot_v, lam, 2))}"))

    wx, wy = sp.symbols("w_x w_y", real=True)  # any non-zero w (not only the first quadrant)
    w = sp.Matrix([wx, wy])
    n = sp.Matrix([nx, ny])
    vw = line_field_velocity(q, q0, _unit(w), p)
    length2 = w.dot(w)
    form = n.dot(w) * sp.sqrt(length2) + p * (length2 * n.dot(q0 - q) - n.dot(w) * w.dot(q0 - q))
    steps.append(Step("with d = w/|w|: n·v·|w|² = (n·w)|w| + p(|w|² n·(q₀ − q) − (n·w)(w·(q₀ − q))), a form A√L + B "
                      "with A, B, L rational for rational inputs",
                      is_zero(sp.simplify(n.dot(vw) * length2 - form)), f"A√L + B = {text(form)}"))

    rho, theta, radius = sp.symbols("rho theta r", positive=True)
    cw = sp.Symbol("c_w", real=True)
    r_hat = sp.Matrix([sp.cos(theta), sp.sin(theta)])
    t_cw = sp.Matrix([sp.sin(theta), -sp.cos(theta)])
    arc = cw * t_cw + p * (radius - rho) * r_hat
    rho_dot = sp.simplify(r_hat.dot(arc))
    rho_fun = sp.Function("rho")
    arc_solution = sp.dsolve(sp.Eq(rho_fun(t).diff(t), p * (radius - rho_fun(t))), rho_fun(t),
                             ics={rho_fun(0): radius + e0})
    steps.append(Step("arc field v = c_w t̂ + p(r − ρ) r̂: ρ̇ = p(r − ρ), so ρ(t) − r = (ρ₀ − r) e^{−pt}; the tangential "
                      "component is c_w (unit speed along the arc, clockwise for c_w = 1)",
                      is_zero(rho_dot - p * (radius - rho)) and is_zero(t_cw.dot(arc) - cw)
                      and is_zero(arc_solution.rhs - radius - e0 * sp.exp(-p * t)),
                      f"ρ̇ = {text(rho_dot)}; ρ(t) = {text(arc_solution.rhs)}"))

    p_in, p_out, p_hyp = sp.Matrix([sp.Rational(1, 2), 0]), sp.Matrix([0, sp.Rational(1, 2)]), \
        sp.Matrix([sp.Rational(1, 2), sp.Rational(1, 2)])
    n_in, n_out = sp.Matrix([0, 1]), sp.Matrix([1, 0])
    v_in, v_out = _unit(p_hyp - p_in), _unit(p_hyp - p_out)
    corrected = sp.simplify(zone_cost_corrected(n_in, v_in, n_out, v_out))
    printed = sp.simplify(zone_cost_printed(n_in, v_in, n_out, v_out))
    steps.append(Step("Eq. 4 in the paper's isosceles right triangle: v_in = n_in, v_out = n_out; the corrected cost "
                      "(squared cross products) is 0 as the text says; the printed one is 2, its maximum (erratum)",
                      v_in == n_in and v_out == n_out and corrected == 0 and printed == 2,
                      f"corrected {text(corrected)}, printed {text(printed)}"))
    errata = ("Eq. 3 (the arc field) is missing from the text: reconstructed as v = c_w t̂ + p(r − ρ) r̂",
              "Eq. 4 as printed gives 2 (its maximum) in the paper's own triangle example where the text says 0: "
              "minimise the squared cross products 2 − (n_in·v_in)² − (n_out·v_out)² instead")
    return ProofResult("Line and arc fields (Eq. 2, 3) and reflection zones (Eq. 4), Stager and Tanner",
                       tuple(steps), errata=errata)
