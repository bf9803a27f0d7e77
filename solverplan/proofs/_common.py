"""Helpers shared by the proofs: the triangle of a transition, its angle domain, sign facts on (0, π).

Nothing here asserts a result: the helpers *build* derived objects (the triangle of a left or right
transition solved in coordinates) and *check* facts with sympy (the sign of sin and cos on (0, π) by
``solveset``; positivity of an angle by the assumption system). The proof modules turn the checks
into :class:`~solverplan.proofs._core.Step` records.

The angle domain. A transition from a source segment to a target segment is a triangle P V Q: P the
robot on the source, V the corner where the two supporting lines meet, Q the hit on the target. The
ray meets the target half-line beyond V exactly when the triangle is non-degenerate, i.e. its three
angles are positive (and they sum to π). So the domain of a transition is written with positive
symbols for the three angles, and π is replaced by their sum wherever a sign is decided: then
"0 < w < π" for a derived angle w is a positivity question sympy's assumptions answer exactly.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from typing import Literal

import sympy as sp

__all__ = [
    "Kind",
    "AngleDomain",
    "TransitionTriangle",
    "transition_triangle",
    "sin_positive_on_open_0_pi",
    "cos_sign_on_open_0_pi",
    "is_zero",
    "text",
]

Kind = Literal["right", "left"]


_GREEK = {"theta": "θ", "phi": "φ", "psi": "ψ", "alpha": "α", "pi": "π", "epsilon": "ε", "ell": "ℓ", "tau": "τ",
          "sigma": "σ", "rho": "ρ", "delta": "δ", "lambda": "λ"}
_WORD = re.compile(r"\b(" + "|".join(_GREEK) + r")(?=\b|_)")


def text(expr: object) -> str:
    """A short readable form of a sympy expression for a step's detail (Greek letters, ·, ^)."""
    out = _WORD.sub(lambda m: _GREEK[m.group(1)], sp.sstr(expr))
    return out.replace("**", "^").replace("*", "·")


def _weierstrass(expr: sp.Expr) -> sp.Expr | None:
    """``expr`` with sin x, cos x of each symbol x written through t = tan(x/2), or None if that does not apply.

    After ``expand_trig`` a trigonometric identity in angle symbols becomes an identity between rational
    functions of the t's, which ``cancel`` decides exactly (wherever both sides are defined).
    """
    expr = expr.replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a)).replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a))
    expr = sp.expand_trig(expr)
    trig = expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)
    if not all(isinstance(f, (sp.sin, sp.cos)) and f.args[0].is_Symbol for f in trig):
        return None
    subs: dict[sp.Expr, sp.Expr] = {}
    for f in trig:
        t = sp.Dummy(f"t_{f.args[0]}")
        subs.setdefault(f.args[0], t)
    rational = {}
    for f in trig:
        t = subs[f.args[0]]
        rational[f] = 2 * t / (1 + t**2) if isinstance(f, sp.sin) else (1 - t**2) / (1 + t**2)
    return expr.xreplace(rational)


def is_zero(expr: sp.Expr) -> bool:
    """True iff ``expr`` is identically zero: by expansion, by the tan-half-angle substitution for trig
    identities in angle symbols, or else by ``simplify`` (after expanding trig functions)."""
    expr = sp.sympify(expr)
    if sp.expand(expr) == 0:
        return True
    rational = _weierstrass(expr)
    if rational is not None and sp.cancel(sp.together(rational)) == 0:
        return True
    if sp.simplify(expr) == 0:
        return True
    return sp.simplify(sp.expand_trig(expr)) == 0


@functools.cache
def sin_positive_on_open_0_pi() -> bool:
    """sin x > 0 exactly for x ∈ (0, π) (sympy's ``solveset`` on that interval returns all of it)."""
    x = sp.Symbol("x", real=True)
    interval = sp.Interval.open(0, sp.pi)
    return sp.solveset(sp.sin(x) > 0, x, interval) == interval


@functools.cache
def cos_sign_on_open_0_pi() -> bool:
    """On (0, π): cos x > 0 exactly on (0, π/2) and cos x < 0 exactly on (π/2, π)."""
    x = sp.Symbol("x", real=True)
    interval = sp.Interval.open(0, sp.pi)
    positive = sp.solveset(sp.cos(x) > 0, x, interval) == sp.Interval.open(0, sp.pi / 2)
    negative = sp.solveset(sp.cos(x) < 0, x, interval) == sp.Interval.open(sp.pi / 2, sp.pi)
    return positive and negative


@dataclass(frozen=True)
class AngleDomain:
    """A domain of angles written through positive triangle angles whose sum stands for π.

    ``subs`` rewrites the free symbols of a formula (and π) in terms of the positive triangle angles
    ``angles``; :meth:`positive` then asks sympy's assumption system whether the rewritten, expanded
    expression is positive — a linear combination of positive symbols with positive coefficients is.
    """

    angles: tuple[sp.Symbol, ...]
    subs: tuple[tuple[sp.Expr, sp.Expr], ...]

    def rewrite(self, expr: sp.Expr) -> sp.Expr:
        return sp.expand(sp.sympify(expr).subs(dict(self.subs), simultaneous=True))

    def positive(self, expr: sp.Expr) -> bool:
        return self.rewrite(expr).is_positive is True

    def in_open_0_pi(self, expr: sp.Expr) -> bool:
        """0 < expr < π on the whole domain."""
        return self.positive(expr) and self.positive(sp.pi - expr)

    def sin_positive(self, expr: sp.Expr) -> bool:
        """sin(expr) > 0 on the domain: expr ∈ (0, π) there, and sin > 0 on (0, π)."""
        return self.in_open_0_pi(expr) and sin_positive_on_open_0_pi()


@dataclass(frozen=True)
class TransitionTriangle:
    """The triangle P V Q of a transition, solved in coordinates.

    Frame: the source line is the x-axis, free space above, the corner V at the origin. The robot P
    is at distance ``d`` from V; it leaves at heading ``theta`` (CCW from the source's direction, +x).
    The target leaves V into the upper half plane making the interior angle ``phi`` with the ray V→P.

    ``ratio`` = |VQ| / |VP| and ``along`` = |PQ| / |VP| come from solving P + s·w = r·e for (s, r);
    ``angle_p``, ``angle_v``, ``angle_q`` are the triangle's angles (∠Q from the angle sum);
    ``domain`` expresses θ, φ and π through the three positive triangle angles.
    """

    kind: Kind
    theta: sp.Symbol
    phi: sp.Symbol
    d: sp.Symbol
    ratio: sp.Expr
    along: sp.Expr
    angle_p: sp.Expr
    angle_v: sp.Expr
    angle_q: sp.Expr
    domain: AngleDomain


@functools.cache
def transition_triangle(kind: Kind) -> TransitionTriangle:
    """Build and solve the triangle of a ``kind`` transition (see :class:`TransitionTriangle`)."""
    theta, phi, d = sp.symbols("theta phi d", positive=True)
    s, r = sp.symbols("s r", real=True)
    ray = sp.Matrix([sp.cos(theta), sp.sin(theta)])
    if kind == "right":
        # P left of V: the ray from P towards V points along +x (angle 0); the target leaves V at
        # angle π − φ, so the interior angle between V→P (angle π) and the target is φ.
        p = sp.Matrix([-d, 0])
        target = sp.Matrix([-sp.cos(phi), sp.sin(phi)])
        angle_p = theta  # between P→V (angle 0) and the ray (angle θ)
    else:
        # P right of V: V→P points along +x, the target leaves V at angle φ.
        p = sp.Matrix([d, 0])
        target = sp.Matrix([sp.cos(phi), sp.sin(phi)])
        angle_p = sp.pi - theta  # between P→V (angle π) and the ray (angle θ)
    (solution,) = sp.solve(list(p + s * ray - r * target), [s, r], dict=True)
    angle_v = phi
    angle_q = sp.pi - angle_p - angle_v
    psi, alpha = sp.symbols("psi alpha", positive=True)
    if kind == "right":
        # triangle angles θ, φ, ψ = π − θ − φ, all positive
        domain = AngleDomain((theta, phi, psi), ((sp.pi, theta + phi + psi),))
    else:
        # triangle angles α = π − θ, φ, ψ = θ − φ, all positive: θ = φ + ψ, π = α + φ + ψ
        domain = AngleDomain((alpha, phi, psi), ((theta, phi + psi), (sp.pi, alpha + phi + psi)))
    return TransitionTriangle(
        kind=kind,
        theta=theta,
        phi=phi,
        d=d,
        ratio=sp.simplify(solution[r] / d),
        along=sp.simplify(solution[s] / d),
        angle_p=angle_p,
        angle_v=angle_v,
        angle_q=angle_q,
        domain=domain,
    )
