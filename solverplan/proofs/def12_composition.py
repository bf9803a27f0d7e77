"""Def. 12 (paper §6): the contraction coefficient of a sequence of transitions is the product.

Statement. For transitions f₀, …, f_{m−1} with fixed headings (each right or left, coefficient
C_k = C(θ_k, φ_k) from Lemma 2), the composite F = f_{m−1} ∘ … ∘ f₀ satisfies
|F(x) − F(y)| = (Π_k C_k)·|x − y| for all x, y: the coefficients multiply, and the ratio is exact (the
same for every pair), so F contracts iff Π C_k < 1, even when single steps expand.

Setting. Positions are arclength coordinates along the boundary. Transition k maps a source position x
to its distance from the corner, δ = σ_k (x − X_k) (X_k the corner's coordinate on the source line,
σ_k = ±1 the side), multiplies it by C_k (Lemma 2: |VQ| = C·|VP|), and places the hit at
y = Y_k + ρ_k C_k δ on the target (Y_k, ρ_k = ±1 likewise). The target coordinate of step k is the source
coordinate of step k + 1. C_k is the ratio derived from the transition's triangle
(:func:`solverplan.proofs._common.transition_triangle`), right and left steps alternating.

Derivation. For m = 2..5: compose the maps symbolically; (1) F'' = 0: the composite is affine;
(2) F' = Π_k σ_k ρ_k C_k (the chain rule, checked on the composed expression); (3) with σ_k² = ρ_k² = 1,
(F(x) − F(y))² − (Π C_k)²(x − y)² = 0, i.e. the distance ratio is exactly Π C_k for every pair;
(4) each C_k > 0 on its domain (three positive sines), so |F'| = Π C_k. (5) An example where a single
step expands and the product still contracts, in exact arithmetic.

Errata. The paper says "as f is a linear mapping, the contraction coefficient of a composition … can be
determined by multiplying". The transition is *affine*, not linear (d′ = C·(ℓ − d) has an offset); the
product rule holds because only the slopes multiply under composition and the offsets drop out of
differences. The conclusion (Def. 12, and "C(F) tells us the exact ratio") is right.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import is_zero, text, transition_triangle
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove"]


def _chain(m: int) -> Step:
    x, y = sp.symbols("x y", real=True)
    kinds = ["right" if k % 2 == 0 else "left" for k in range(m)]
    coefficients, signs, positive = [], [], True
    fx, fy = x, y
    for k, kind in enumerate(kinds):
        tri = transition_triangle(kind)
        theta_k, phi_k = sp.symbols(f"theta_{k} phi_{k}", positive=True)
        c_k = tri.ratio.subs({tri.theta: theta_k, tri.phi: phi_k}, simultaneous=True)
        positive = positive and all(tri.domain.sin_positive(a) for a in (tri.angle_p, tri.angle_q))
        big_x, big_y = sp.symbols(f"X_{k} Y_{k}", real=True)
        s_k, r_k = sp.symbols(f"sigma_{k} rho_{k}", real=True)

        def step(position: sp.Expr) -> sp.Expr:
            distance = s_k * (position - big_x)  # distance from the corner on the source
            return big_y + r_k * c_k * distance  # Lemma 2: the target distance is C·distance

        fx, fy = step(fx), step(fy)
        coefficients.append(c_k)
        signs += [s_k, r_k]
    product = sp.Mul(*coefficients)
    slope = sp.diff(fx, x)
    affine = sp.diff(fx, x, 2) == 0
    chain_rule = is_zero(slope - sp.Mul(*signs) * product)
    squared = sp.expand((fx - fy) ** 2 - product**2 * (x - y) ** 2)
    for s in signs:
        squared = sp.expand(squared.subs(s**2, 1))
    exact_ratio = squared == 0
    return Step(
        f"m = {m} transitions ({', '.join(kinds)}): the composite is affine, F′ = Π σ_k ρ_k C_k, and "
        "(F(x) − F(y))² = (Π C_k)² (x − y)² with σ_k² = ρ_k² = 1; C_k > 0 on each domain, so |F(x) − F(y)| = Π C_k·|x − y|",
        affine and chain_rule and exact_ratio and positive,
        f"F′ = {text(slope)}",
    )


def _example() -> Step:
    """A right transition that expands (θ = π/3 at a right angle) followed by one that contracts strongly."""
    tri = transition_triangle("right")
    c0 = tri.ratio.subs({tri.theta: sp.pi / 3, tri.phi: sp.pi / 2}, simultaneous=True)
    c1 = tri.ratio.subs({tri.theta: sp.pi / 12, tri.phi: sp.pi / 2}, simultaneous=True)
    c0, c1 = sp.simplify(c0), sp.simplify(c1)
    product = sp.simplify(c0 * c1)
    return Step(
        "example: C(π/3, π/2) = √3 > 1 expands, C(π/12, π/2) = 2 − √3, yet the product 2√3 − 3 < 1 contracts",
        is_zero(c0 - sp.sqrt(3))
        and is_zero(c1 - (2 - sp.sqrt(3)))
        and is_zero(product - (2 * sp.sqrt(3) - 3))
        and (c0 - 1).is_positive is True
        and (1 - product).is_positive is True,
        f"C₀ = {text(c0)}, C₁ = {text(c1)}, C₀C₁ = {text(product)}",
    )


def prove() -> ProofResult:
    """Def. 12: composing transitions multiplies their contraction coefficients (m = 2..5)."""
    steps = [_chain(m) for m in range(2, 6)] + [_example()]
    errata = (
        "Seed 000 §6 (before Def. 12) calls a transition 'a linear mapping'; it is affine (d′ = C(ℓ − d)). "
        "Coefficients multiply because slopes multiply under composition; the offsets cancel in differences.",
    )
    return ProofResult("Def. 12 (coefficients multiply under composition)", tuple(steps), errata=errata)
