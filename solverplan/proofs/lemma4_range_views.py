"""Lemma 4 and Theorem 5 of Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility"
(range-limited exploration, Algorithm B).

Lemma 4: Algorithm B takes at most ⌊8·Area/(3R²)⌋ + ⌊Perimeter/R⌋ + r + h + 1 views. The proof lays P on a grid
of squares whose diagonal is √3R/2 and counts views per square; views along the boundary are R apart, and every
point within √3R/2 of the segment between two consecutive boundary viewpoints is within R of one of them
(Fig. 19). Theorem 5: a view sees at most πR² of area, so any exploration takes ⌈Area/(πR²)⌉ views, and the
ratio is at most 8π/3 + πR·Perimeter/Area + (r + h + 1)·πR²/Area.

Derivation checked here:
1. A square of diagonal √3R/2 has side √3R/(2√2) and area 3R²/8, so at most Area/(3R²/8) = 8·Area/(3R²) squares
   lie wholly inside P.
2. Two points of such a square are at most its diagonal apart, √3R/2 < R: one view inside a square sees every
   point of it that it can see at all (range is not what limits it).
3. Fig. 19: with p_i = (0, 0), p_{i+1} = (R, 0) and q = (x, y), 0 ≤ x ≤ R, |y| ≤ √3R/2, the nearer of the two
   viewpoints is within R of q: min(x², (R − x)²) ≤ R²/4, and R²/4 + 3R²/4 = R² (tight at x = R/2,
   y = √3R/2).
4. The disc of radius R has area πR² (integrated), so ⌈Area/(πR²)⌉ views are necessary.
5. Lemma 4's count over Area/(πR²) is exactly Theorem 5's expression (simplified to zero difference), and the
   floors and the ceiling only make the true ratio smaller; the library's float formula
   (:func:`~solverplan.explore.bounds.range_ratio_bound`) agrees with the symbolic one on a test polygon.
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._core import ProofResult, Step


def grid_square_area(R: sp.Expr) -> sp.Expr:
    """The area of a grid square of Lemma 4's proof, as the paper states it: 3R²/8."""
    return 3 * R**2 / 8


def ratio_bound_formula(area: sp.Expr, perimeter: sp.Expr, R: sp.Expr, c: sp.Expr) -> sp.Expr:
    """Theorem 5's bound as the paper states it (c = r + h + 1)."""
    return 8 * sp.pi / 3 + sp.pi * R * perimeter / area + c * sp.pi * R**2 / area


def prove() -> ProofResult:
    """Check the grid, the two-circle cover of Fig. 19, the disc area and Theorem 5's algebra."""
    R = sp.symbols("R", positive=True)
    x, y, rho, phi = sp.symbols("x y rho phi", real=True)
    area, perimeter, c = sp.symbols("A P c", positive=True)

    diagonal = sp.sqrt(3) * R / 2
    side = diagonal / sp.sqrt(2)
    square = sp.simplify(side**2 - grid_square_area(R)) == 0
    count = sp.simplify(area / grid_square_area(R) - 8 * area / (3 * R**2)) == 0
    within_range = bool(sp.simplify(diagonal / R) < 1)

    # Fig. 19: the worst point is over the middle of the segment at the largest admitted distance
    half = sp.simplify(sp.Max(0, sp.Min(x, R - x)).subs(x, R / 2))
    tight = sp.simplify(half**2 + diagonal**2 - R**2) == 0
    # for 0 ≤ x ≤ R/2 the nearer viewpoint is p_i: x² + y² ≤ R²/4 + 3R²/4 on the admitted strip
    t = sp.symbols("t", nonnegative=True)
    bound_left = sp.simplify((R / 2 - t) ** 2 + diagonal**2 - R**2)  # x = R/2 − t, |y| = √3R/2
    nearer_ok = sp.simplify(sp.expand(bound_left) - (t**2 - R * t)) == 0  # = t(t − R) ≤ 0 for 0 ≤ t ≤ R/2

    disc = sp.integrate(sp.integrate(rho, (rho, 0, R)), (phi, 0, 2 * sp.pi))
    disc_ok = sp.simplify(disc - sp.pi * R**2) == 0

    lemma4_count = 8 * area / (3 * R**2) + perimeter / R + c
    derived_ratio = sp.simplify(lemma4_count / (area / (sp.pi * R**2)))
    ratio_ok = sp.simplify(derived_ratio - ratio_bound_formula(area, perimeter, R, c)) == 0

    from solverplan.environment import Environment
    from solverplan.explore.bounds import range_ratio_bound

    square_env = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
    numeric = float(ratio_bound_formula(sp.Integer(16), sp.Integer(16), sp.Integer(2), sp.Integer(1)))
    library_ok = abs(range_ratio_bound(square_env, 2.0) - numeric) <= 1e-12 * numeric

    return ProofResult(
        "Lemma 4 and Theorem 5 (range-limited exploration: view bound, lower bound, competitive ratio)",
        (
            Step("a square of diagonal √3R/2 has area 3R²/8", square, str(sp.simplify(side**2))),
            Step("at most 8·Area/(3R²) squares lie wholly inside P", count),
            Step("the diagonal √3R/2 is shorter than R: one view in a square reaches all of it", within_range),
            Step("Fig. 19: the farthest admitted point over the segment is at distance exactly R from the nearer "
                 "viewpoint", tight),
            Step("Fig. 19: for x = R/2 − t (0 ≤ t ≤ R/2), x² + 3R²/4 − R² = t(t − R) ≤ 0", nearer_ok,
                 str(bound_left)),
            Step("the disc of radius R has area πR² (polar integral): ⌈Area/(πR²)⌉ views are necessary", disc_ok,
                 str(disc)),
            Step("Lemma 4's count over Area/(πR²) is 8π/3 + πR·Perimeter/Area + (r + h + 1)·πR²/Area", ratio_ok,
                 str(derived_ratio)),
            Step("the library's range_ratio_bound equals the formula on the 4 × 4 square with R = 2", library_ok),
        ),
    )
