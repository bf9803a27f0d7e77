"""Monotonicity of the contraction coefficient in the heading (used by the planners).

Statement. On its domain, C(θ, φ) is strictly increasing in θ for a right transition
(C = sin θ / sin(θ + φ), 0 < θ < π − φ) and strictly decreasing for a left one (C = sin θ / sin(θ − φ),
φ < θ < π), with d/dθ log C = cot θ − cot(θ ± φ). Hence over an action interval [θ_lo, θ_hi] inside the
domain the worst (largest) C is at θ_hi for a right transition and at θ_lo for a left one, the best at
the other end; and 1/C = cos φ ± cot θ · sin φ is affine in u = cot θ.

Setting. C is the ratio derived from the transition's triangle (:func:`solverplan.proofs._common.transition_triangle`,
the same object Lemma 2 checks), not retyped. Domains are written through positive triangle angles
(:class:`solverplan.proofs._common.AngleDomain`): for one heading, the triangle's three angles; for two headings
θ₁ < θ₂, θ₂ = θ₁ + δ with δ > 0 and both triangles non-degenerate.

Derivation. (1) Differentiate log C and compare with cot θ − cot(θ ± φ). (2) cot a − cot b =
sin(b − a) / (sin a sin b) gives d/dθ log C = ± sin φ / (sin θ sin(θ ± φ)). (3) All three sines are
positive on the domain, so the sign is + (right) or − (left). (4) Without calculus: the two-point
difference C(θ₂) − C(θ₁) = ± sin φ sin(θ₂ − θ₁) / (sin(θ₁ ± φ) sin(θ₂ ± φ)), every factor positive for
θ₁ < θ₂ in the domain — so the extreme values over an interval are at its ends, worst at the stated end.
(5) 1/C expands to cos φ ± u sin φ, so "C ≤ c" is a linear condition on u.

Errata. None: the library's derivative and direction of monotonicity are confirmed.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import AngleDomain, is_zero, text, transition_triangle
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove"]


def _case(kind: str) -> list[Step]:
    tri = transition_triangle(kind)
    theta, phi, dom = tri.theta, tri.phi, tri.domain
    sign = 1 if kind == "right" else -1
    c = tri.ratio  # derived from the triangle
    sigma = theta + sign * phi
    name = f"{kind} transition"
    pm = "+" if sign > 0 else "−"
    steps: list[Step] = []

    log_derivative = sp.diff(sp.log(c), theta)
    steps.append(Step(
        f"{name}: d/dθ log C = cot θ − cot(θ {pm} φ) (C from the triangle)",
        is_zero(log_derivative - (sp.cot(theta) - sp.cot(sigma))),
        f"d/dθ log C = {text(sp.simplify(log_derivative))}",
    ))
    closed = sign * sp.sin(phi) / (sp.sin(theta) * sp.sin(sigma))
    steps.append(Step(
        f"{name}: cot θ − cot(θ {pm} φ) = {'' if sign > 0 else '−'}sin φ / (sin θ · sin(θ {pm} φ))",
        is_zero(sp.cot(theta) - sp.cot(sigma) - closed),
    ))
    steps.append(Step(
        f"{name}: sin φ, sin θ, sin(θ {pm} φ) > 0 on the domain, so d/dθ log C {'> 0: C increasing' if sign > 0 else '< 0: C decreasing'} in θ",
        dom.sin_positive(phi) and dom.sin_positive(theta) and dom.sin_positive(sigma),
    ))

    # two headings θ1 < θ2 in the domain
    theta1, delta, psi, alpha = sp.symbols("theta_1 delta psi alpha", positive=True)
    theta2 = theta1 + delta
    if sign > 0:  # 0 < θ1 < θ2, θ2 + φ < π: π = θ2 + φ + ψ
        two = AngleDomain((theta1, delta, phi, psi), ((sp.pi, theta1 + delta + phi + psi),))
    else:  # φ < θ1 < θ2 < π: θ1 = φ + ψ, π = θ2 + α
        two = AngleDomain(
            (phi, psi, delta, alpha),
            ((theta1, phi + psi), (sp.pi, phi + psi + delta + alpha)),
        )
    c1, c2 = c.subs(theta, theta1), c.subs(theta, theta2)
    s1, s2 = theta1 + sign * phi, theta2 + sign * phi
    difference = sign * sp.sin(phi) * sp.sin(theta2 - theta1) / (sp.sin(s1) * sp.sin(s2))
    all_positive = all(two.sin_positive(a) for a in (phi, theta2 - theta1, s1, s2, theta1, theta2))
    worst = "θ_hi" if sign > 0 else "θ_lo"
    steps.append(Step(
        f"{name}: C(θ₂) − C(θ₁) = {'' if sign > 0 else '−'}sin φ sin(θ₂ − θ₁) / (sin(θ₁ {pm} φ) sin(θ₂ {pm} φ)) with every "
        f"factor positive for θ₁ < θ₂ in the domain: the worst case over [θ_lo, θ_hi] is C({worst})",
        is_zero(c2 - c1 - difference) and all_positive,
        f"θ₂ − θ₁ = δ; angles rewritten: θ₁ = {text(two.rewrite(theta1))}, θ₂ {pm} φ = {text(two.rewrite(s2))}, "
        f"π − (θ₂ {pm} φ) = {text(two.rewrite(sp.pi - s2))}",
    ))
    u = sp.Symbol("u", real=True)
    inverse = sp.expand(sp.expand_trig(1 / c)).subs(sp.cos(theta), u * sp.sin(theta))
    steps.append(Step(
        f"{name}: 1/C = cos φ {pm} u·sin φ with u = cot θ — affine in u, so C ≤ c is linear in u",
        is_zero(inverse - (sp.cos(phi) + sign * u * sp.sin(phi))),
        f"1/C = {text(sp.simplify(inverse))}",
    ))
    return steps


def prove() -> ProofResult:
    """C is increasing in θ (right) and decreasing (left); worst case at a known end of an interval."""
    return ProofResult("Monotonicity of C in θ (worst case at an interval end)", tuple(_case("right") + _case("left")))
