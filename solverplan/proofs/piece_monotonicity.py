"""Landing on a piece is never worse than landing on its whole segment (issues #22 and #24).

The planner lets a stage land inside one *piece* of a segment of P′ (between the ends of the query's start and goal
sets) or anywhere on the whole segment, and keeps of the two only the piece where both work at the same headings
(:meth:`solverplan.plan._problem.Problem._combine`). That is sound and loses no plan because of the monotonicity
proved here: from a part of a segment, every heading admissible from the whole segment is admissible, with the same
targets; a belief that is a subset of another therefore has every plan of the larger one.

Setting. Source segment e = (a, b), a = (0, 0), b = (L, 0), L > 0, free space above (y > 0); a piece
[x₀, x₁] ⊆ [0, L] of it. The robot at s = (x, 0) leaves at heading θ ∈ (0, π) (CCW from +x) along
u = (cos θ, sin θ) and meets the line of the target t = c + λ·T at λ(x, θ).

Derivation checked here:

1. **The landing point is affine in x** (∂²λ/∂x² = 0): the image of the piece at θ is the segment between the
   images of its ends, inside the image of the whole segment (the ends' images lie between a's and b's). So a
   heading at which every point of e lands on t (or on a piece [g₀, g₁] of t) does so from every point of the
   piece: the safe set of the piece towards t holds the segment's.
2. **The cones widen.** Every point of e lands beyond g₀ iff θ ≥ ang(g₀ − b) and before g₁ iff θ ≤ ang(g₁ − a)
   (Prop. 2); from the piece the bounds are ang(g₀ − (x₁, 0)) and ang(g₁ − (x₀, 0)). ang(p − (x, 0)) =
   atan2(p_y, p_x − x) increases with x (derivative p_y / |p − s|² > 0), and x₁ ≤ L, x₀ ≥ 0: the piece's cone
   holds the segment's. The clearance κ pulls g₀, g₁ in along t (independent of the source) and is exempt at the
   segment's own corners for the piece as for the segment, so the cut cones are nested too.
3. **The margins keep nesting.** Every interval end moves μ inwards and is clipped to [δ, π − δ]: for
   lo′ ≤ lo ≤ hi ≤ hi′, (lo′ + μ, hi′ − μ) holds (lo + μ, hi − μ) and max(·, δ), min(·, π − δ) are monotone.

With 1–3, a piece's admissible intervals hold its segment's with the same target (and the same corner tags: the
arrival corner of an arc depends only on the corner the target shares with the segment), and by induction on the
stages every plan from a belief works from any belief whose elements lie inside its elements with no more corner
tags — the monotonicity :meth:`~solverplan.plan._problem.Problem._combine` states.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._core import ProofResult, Step


def prove() -> ProofResult:
    """Check that landings are affine in the position, that the cones widen for a piece, and that the margins keep
    nested intervals nested."""
    x, theta, lam = sp.symbols("x theta lambda", real=True)
    cx, cy, tx, ty = sp.symbols("c_x c_y T_x T_y", real=True)
    u = sp.Matrix([sp.cos(theta), sp.sin(theta)])
    s = sp.Matrix([x, 0])
    c, t_dir = sp.Matrix([cx, cy]), sp.Matrix([tx, ty])
    # s + r·u = c + λ·T: solve the 2×2 system for (r, λ)
    r = sp.symbols("r", real=True)
    solution = sp.solve(list(s + r * u - c - lam * t_dir), [r, lam], dict=True)
    affine = bool(solution) and sp.simplify(sp.diff(solution[0][lam], x, 2)) == 0
    slope = sp.simplify(sp.diff(solution[0][lam], x)) if solution else None

    px = sp.symbols("p_x", real=True)
    py = sp.symbols("p_y", positive=True)
    angle = sp.atan2(py, px - x)
    derivative = sp.simplify(sp.diff(angle, x))
    expected = py / ((px - x) ** 2 + py**2)
    widen = sp.simplify(derivative - expected) == 0 and bool(expected.is_positive)

    lo, hi, mu = sp.symbols("lo hi mu", real=True)
    d_lo, d_hi = sp.symbols("d_lo d_hi", nonnegative=True)  # lo′ = lo − d_lo, hi′ = hi + d_hi
    shrink = (sp.simplify((lo + mu) - ((lo - d_lo) + mu) - d_lo) == 0
              and sp.simplify(((hi + d_hi) - mu) - (hi - mu) - d_hi) == 0)
    delta = sp.symbols("delta", real=True)
    clip = _monotone_clip(lo, d_lo, delta)

    return ProofResult(
        "Piece monotonicity (a part of a segment has every admissible heading of the segment)",
        (
            Step("the landing parameter λ on the target's line is affine in the position x (∂²λ/∂x² = 0): a piece's "
                 "image lies between the images of its ends, inside the segment's", affine, str(slope)),
            Step("d/dx ang(p − (x, 0)) = p_y / |p − s|² > 0: from a piece [x₀, x₁] ⊆ [0, L] the cone "
                 "[ang(g₀ − (x₁, 0)), ang(g₁ − (x₀, 0))] holds the segment's [ang(g₀ − b), ang(g₁ − a)]", widen,
                 str(derivative)),
            Step("moving both ends μ inwards keeps nested intervals nested", shrink),
            Step("clipping to [δ, π − δ] (max with δ, min with π − δ) is monotone: nested stays nested", clip),
        ),
    )


def _monotone_clip(v: sp.Symbol, d: sp.Symbol, delta: sp.Symbol) -> bool:
    """max(v + d, δ) − max(v, δ) ≥ 0 and min(v + d, δ) − min(v, δ) ≥ 0 for d ≥ 0, by the cases v ≥ δ, v + d ≤ δ and
    v < δ < v + d (each a substitution sympy decides)."""
    e = sp.symbols("e", nonnegative=True)
    f = sp.symbols("f", positive=True)
    cases = [
        {v: delta + e},  # v ≥ δ: both maxima are the first argument
        {v: delta - d - e},  # v + d ≤ δ: both are δ (max) / the first argument (min)
    ]
    ok = True
    for case in cases:
        for op in (sp.Max, sp.Min):
            gap = sp.simplify(op(v + d, delta).subs(case) - op(v, delta).subs(case))
            ok = ok and gap.is_nonnegative is True
    # v < δ < v + d: v = δ − f, d = f + e (f > 0)
    between = {v: delta - f}
    for op in (sp.Max, sp.Min):
        gap = sp.simplify(op(delta - f + f + e, delta) - op(v, delta).subs(between))
        ok = ok and gap.is_nonnegative is True
    return ok
