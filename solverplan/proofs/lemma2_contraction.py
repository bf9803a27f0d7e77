"""Lemma 2 and Def. 11 (paper §6): the contraction coefficient of a transition and when it is < 1.

Statement. Let a transition go from a source segment to a target segment whose supporting lines meet at
the corner V with interior angle φ ∈ (0, π), the robot leaving at heading θ (CCW from the source's
direction). Measured from V, a start at distance d lands at distance C·d with

    right transition (V ahead of the robot):   C(θ, φ) = sin θ / sin(θ + φ),  domain 0 < θ < π − φ,
    left transition  (V behind the robot):     C(θ, φ) = sin θ / sin(θ − φ),  domain φ < θ < π,

and on its domain C < 1 iff θ < π/2 − φ/2 (right), resp. θ > π/2 + φ/2 (left).

Setting. The triangle P V Q (robot, corner, hit) in the frame of the source line (x-axis, free space
above, V at the origin), built and solved in coordinates by :func:`solverplan.proofs._common.transition_triangle`.
Its angles are ∠P = θ (right) or π − θ (left), ∠V = φ, ∠Q = π − ∠P − ∠V. The domain is exactly
"the triangle is non-degenerate": the three angles are positive (the ray meets the target half-line
beyond V, ahead of the robot). Signs on the domain are decided by writing θ, φ and π through the three
positive triangle angles (:class:`solverplan.proofs._common.AngleDomain`).

Derivation. (1) Law of sines: |VQ| / |VP| = sin ∠P / sin ∠Q, which is the library's C. (2) The same ratio
from solving the triangle in coordinates (P + s·w = r·e), and |PQ| / |VP| = sin ∠V / sin ∠Q. (3) On the
domain all three sines are positive, so C > 0 and the hit is ahead of the robot. (4) Multiplying by the
positive denominator, C < 1 iff sin(θ ± φ) − sin θ > 0. (5) Sum to product:
sin(θ + φ) − sin θ = 2 cos(θ + φ/2) sin(φ/2), sin(θ − φ) − sin θ = −2 cos(θ − φ/2) sin(φ/2).
(6) sin(φ/2) > 0, and w = θ ± φ/2 lies in (0, π) on the domain. (7) On (0, π), cos w > 0 iff w < π/2
and cos w < 0 iff w > π/2 (sympy ``solveset``). (8) Solving w = π/2 for θ gives the library's threshold, and
w increases with θ, so the inequality keeps its direction. (9) The threshold lies strictly inside the
domain (both contracting and expanding headings exist: Cor. 2). (10) Independently: C = 1 exactly at
the threshold, for every φ.

Errata. None in the formulas: the library and the paper's Lemma 2 / Def. 11 agree with the derivation. The
absolute values in the paper's Def. 11 (|sin θ / sin(θ ± φ)|) are redundant on the domain, where C > 0.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import (
    TransitionTriangle,
    cos_sign_on_open_0_pi,
    is_zero,
    sin_positive_on_open_0_pi,
    text,
    transition_triangle,
)
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove", "design_coefficient", "design_threshold"]


def design_coefficient(kind: str, theta: sp.Expr, phi: sp.Expr) -> sp.Expr:
    """The library's C(θ, φ) for a right or left transition (the formula under test)."""
    return sp.sin(theta) / sp.sin(theta + phi if kind == "right" else theta - phi)


def design_threshold(kind: str, phi: sp.Expr) -> sp.Expr:
    """The library's contraction threshold: θ < π/2 − φ/2 (right) or θ > π/2 + φ/2 (left)."""
    return sp.pi / 2 - phi / 2 if kind == "right" else sp.pi / 2 + phi / 2


def _case(kind: str) -> list[Step]:
    tri: TransitionTriangle = transition_triangle(kind)
    theta, phi, dom = tri.theta, tri.phi, tri.domain
    c = design_coefficient(kind, theta, phi)
    sign = 1 if kind == "right" else -1
    sigma = theta + sign * phi  # θ ± φ
    name = f"{kind} transition"
    steps: list[Step] = []

    law_of_sines = sp.sin(tri.angle_p) / sp.sin(tri.angle_q)
    steps.append(Step(
        f"{name}: law of sines |VQ|/|VP| = sin∠P / sin∠Q equals the library's C = sin θ / sin(θ {'+' if sign > 0 else '−'} φ)",
        is_zero(law_of_sines - c),
        f"sin∠P/sin∠Q = {text(sp.simplify(law_of_sines))}",
    ))
    steps.append(Step(
        f"{name}: solving the triangle in coordinates gives the same |VQ|/|VP|, and |PQ|/|VP| = sin∠V / sin∠Q",
        is_zero(tri.ratio - c) and is_zero(tri.along - sp.sin(tri.angle_v) / sp.sin(tri.angle_q)),
        f"|VQ|/|VP| = {text(tri.ratio)}, |PQ|/|VP| = {text(tri.along)}",
    ))
    angles_ok = all(dom.in_open_0_pi(a) for a in (tri.angle_p, tri.angle_v, tri.angle_q))
    dom_text = "0 < θ, θ + φ < π" if sign > 0 else "φ < θ < π"
    steps.append(Step(
        f"{name}: on the domain ({dom_text}, 0 < φ) every angle of the triangle is in (0, π), so sin θ, sin φ "
        f"and sin(θ {'+' if sign > 0 else '−'} φ) are positive: C > 0 and the hit is ahead of the robot",
        angles_ok
        and dom.sin_positive(theta)
        and dom.sin_positive(sigma)
        and dom.sin_positive(phi)
        and is_zero(sp.sin(sigma) - sp.sin(tri.angle_q)),
        f"triangle angles {', '.join(text(a) for a in (tri.angle_p, tri.angle_v, tri.angle_q))} rewritten as "
        f"{', '.join(text(dom.rewrite(a)) for a in (tri.angle_p, tri.angle_v, tri.angle_q))} (positive symbols)",
    ))
    steps.append(Step(
        f"{name}: (C − 1)·sin(θ {'+' if sign > 0 else '−'} φ) = sin θ − sin(θ {'+' if sign > 0 else '−'} φ) with a positive "
        "factor, so C < 1 iff sin(θ ± φ) − sin θ > 0",
        is_zero((c - 1) * sp.sin(sigma) - (sp.sin(theta) - sp.sin(sigma))) and dom.sin_positive(sigma),
    ))
    w = theta + sign * phi / 2
    product = sign * 2 * sp.cos(w) * sp.sin(phi / 2)
    steps.append(Step(
        f"{name}: sum to product sin(θ {'+' if sign > 0 else '−'} φ) − sin θ = "
        f"{'' if sign > 0 else '−'}2 cos(θ {'+' if sign > 0 else '−'} φ/2) sin(φ/2)",
        is_zero(sp.sin(sigma) - sp.sin(theta) - product),
        f"w = {text(w)}",
    ))
    steps.append(Step(
        f"{name}: sin(φ/2) > 0 and w = {text(w)} ∈ (0, π) on the domain",
        dom.sin_positive(phi / 2) and dom.in_open_0_pi(w),
        f"w = {text(dom.rewrite(w))}, π − w = {text(dom.rewrite(sp.pi - w))} (positive symbols)",
    ))
    steps.append(Step(
        f"{name}: on (0, π) cos w {'> 0 iff w < π/2' if sign > 0 else '< 0 iff w > π/2'} (solveset), so "
        f"C < 1 iff w {'<' if sign > 0 else '>'} π/2",
        cos_sign_on_open_0_pi() and sin_positive_on_open_0_pi(),
    ))
    (solved,) = sp.solve(sp.Eq(w, sp.pi / 2), theta)
    threshold = design_threshold(kind, phi)
    steps.append(Step(
        f"{name}: w = π/2 solved for θ gives the library's threshold θ* = {text(threshold)}, and dw/dθ = 1 > 0 keeps "
        f"the inequality's direction: C < 1 iff θ {'<' if sign > 0 else '>'} {text(threshold)}",
        is_zero(solved - threshold) and sp.diff(w, theta).is_positive is True,
        f"θ* = {text(solved)}",
    ))
    low, high = (0, sp.pi - phi) if sign > 0 else (phi, sp.pi)
    steps.append(Step(
        f"{name}: the threshold lies strictly inside the domain ({text(low)}, {text(high)}), so contracting and expanding "
        "headings both exist (Cor. 2)",
        dom.positive(threshold - low) and dom.positive(high - threshold),
        f"θ* − lo = {text(dom.rewrite(threshold - low))}, hi − θ* = {text(dom.rewrite(high - threshold))}",
    ))
    steps.append(Step(
        f"{name}: C(θ*, φ) = 1 exactly at the threshold, for every φ",
        is_zero(tri.ratio.subs(theta, threshold) - 1),
        f"C(θ*, φ) = {text(sp.simplify(tri.ratio.subs(theta, threshold)))}",
    ))
    return steps


def prove() -> ProofResult:
    """Lemma 2 and Def. 11, right and left transitions: C from the law of sines, and C < 1 iff θ beyond π/2 ∓ φ/2."""
    steps = _case("right") + _case("left")
    return ProofResult("Lemma 2 / Def. 11 (contraction coefficient, both cases)", tuple(steps))
