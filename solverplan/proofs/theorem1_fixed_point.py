"""Theorem 1 (paper §6.1): the return map of a convex n-gon under a constant rule, and its fixed point.

Statement. In a convex polygon with edges e₀, …, e_{n−1} (CCW, lengths ℓ_k), under the constant rule
b = θ in Lemma 3's range, let d be the distance from the clockwise vertex v_k of the current edge and
C_k = C(θ, φ_{k,k+1}) (φ_{k,k+1} the interior angle at v_{k+1}, indices mod n). One transition is
d_{k+1} = C_k (ℓ_k − d_k), and the return map to e₀ is

    F(d) = A + (−1)^n (Π_{k=0}^{n−1} C_k) d,   A = Σ_{j=0}^{n−1} (−1)^{n−1−j} ℓ_j Π_{k=j}^{n−1} C_k,

with the fixed point d_FP = A / (1 − (−1)^n Π_k C_k) (the paper's Eq. (1)).

Setting. The one-step map is Lemma 2's right transition at the shared vertex v_{k+1}: the robot is
ℓ_k − d_k from the corner and lands C_k (ℓ_k − d_k) from it, which is the distance from the clockwise
vertex of e_{k+1}. Symbols C_k, ℓ_k are positive; n is a positive integer symbol for the induction.

Derivation. (1) For n = 3..8, compose the n maps and compare the expanded constant and slope with
the library's A and (−1)^n Π C_k. (2) For the same n, solve F(d) = d and compare with d_FP. (3) Induction for
general n: if the composite after n steps is a generic a + b·d, one more step gives
C_n ℓ_n − C_n a − C_n b·d; the library's closed forms satisfy exactly these recurrences — the slope because
Π_{k<n+1} = (Π_{k<n})·C_n, the constant because A_{n+1} splits into its j = n term C_n ℓ_n plus, term
by term, −C_n times A_n's terms. The two range-splitting rules used (peel the last term of a Σ or Π with
a symbolic upper limit) are checked for concrete lengths 1..6, and the base case n = 1 directly.
(4) The fixed point of a + b·d is a / (1 − b), unique when b ≠ 1 (here |b| = Π C_k < 1).
(5) A concrete cross-check by exact ray casting: the quadrilateral (0,0), (4,0), (7,4), (0,4) with
sin θ = 5/13, cos θ = 12/13 (all edge lengths and directions rational, so everything is rational): the
ray-cast return map, each hit inside the next edge, equals Theorem 1's with C_k = sin θ / sin(θ + φ_k).

Errata. None: the library's A, slope and d_FP, and the paper's Eq. (1) (hard to read in the text but
the same formula), agree with the derivation; C_{n−1} uses the angle φ_{n−1,0} at v₀ (indices mod n).
"""

from __future__ import annotations

import sympy as sp

from solverplan.proofs._common import is_zero, text
from solverplan.proofs._core import ProofResult, Step

__all__ = ["prove", "return_map", "design_constant", "design_fixed_point"]


def return_map(cs: list[sp.Expr], ells: list[sp.Expr], d: sp.Expr) -> sp.Expr:
    """Compose d ↦ C_k (ℓ_k − d) for k = 0 .. n−1 (Lemma 2's right transition into the next edge)."""
    for c, ell in zip(cs, ells):
        d = c * (ell - d)
    return d


def design_constant(cs: list[sp.Expr], ells: list[sp.Expr]) -> sp.Expr:
    """The library's A = Σ_j (−1)^{n−1−j} ℓ_j Π_{k=j}^{n−1} C_k."""
    n = len(cs)
    return sp.Add(*[(-1) ** (n - 1 - j) * ells[j] * sp.Mul(*cs[j:]) for j in range(n)])


def design_fixed_point(cs: list[sp.Expr], ells: list[sp.Expr]) -> sp.Expr:
    """The library's d_FP = A / (1 − (−1)^n Π C_k)."""
    return design_constant(cs, ells) / (1 - (-1) ** len(cs) * sp.Mul(*cs))


def _concrete(n: int) -> tuple[list[sp.Symbol], list[sp.Symbol]]:
    return list(sp.symbols(f"C_0:{n}", positive=True)), list(sp.symbols(f"ell_0:{n}", positive=True))


def _symbolic_n_steps() -> list[Step]:
    d = sp.Symbol("d", real=True)
    steps = []
    maps_ok, fixed_ok = [], []
    for n in range(3, 9):
        cs, ells = _concrete(n)
        f = sp.expand(return_map(cs, ells, d))
        constant, slope = f.subs(d, 0), sp.diff(f, d)
        maps_ok.append(
            is_zero(constant - sp.expand(design_constant(cs, ells)))
            and is_zero(slope - (-1) ** n * sp.Mul(*cs))
            and sp.diff(f, d, 2) == 0
        )
        (solved,) = sp.solve(sp.Eq(f, d), d)
        fixed_ok.append(is_zero(sp.together(solved - design_fixed_point(cs, ells))))
    steps.append(Step(
        "n = 3..8: composing d ↦ C_k(ℓ_k − d) gives F(d) = A + (−1)^n (Π C_k) d with the library's A",
        all(maps_ok),
        "per n: " + ", ".join(f"{n}: {'ok' if ok else 'MISMATCH'}" for n, ok in zip(range(3, 9), maps_ok)),
    ))
    steps.append(Step(
        "n = 3..8: solving F(d) = d gives d_FP = A / (1 − (−1)^n Π C_k)",
        all(fixed_ok),
        "per n: " + ", ".join(f"{n}: {'ok' if ok else 'MISMATCH'}" for n, ok in zip(range(3, 9), fixed_ok)),
    ))
    return steps


def _peel(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Split a Sum or Product over i = lo..hi into (the same over lo..hi−1, the term i = hi)."""
    (index, low, high), function = expr.limits[0], expr.function
    return expr.func(function, (index, low, high - 1)), function.subs(index, high)


def _induction_steps() -> list[Step]:
    n = sp.Symbol("n", integer=True, positive=True)
    j, k = sp.symbols("j k", integer=True, nonnegative=True)
    big_c, ell = sp.IndexedBase("C"), sp.IndexedBase("ell")
    a, b, d = sp.symbols("a b d", real=True)

    def product(lo: sp.Expr, hi: sp.Expr) -> sp.Product:
        return sp.Product(big_c[k], (k, lo, hi))

    def summand(m: sp.Expr) -> sp.Expr:
        return (-1) ** (m - 1 - j) * ell[j] * product(j, m - 1)

    def constant(m: sp.Expr) -> sp.Sum:  # the library's A_m with a symbolic number of edges m
        return sp.Sum(summand(m), (j, 0, m - 1))

    def slope(m: sp.Expr) -> sp.Expr:
        return (-1) ** m * product(0, m - 1)

    steps = []
    # one more transition after a generic composite a + b·d
    nxt = sp.expand(big_c[n] * (ell[n] - (a + b * d)))
    new_a, new_b = nxt.subs(d, 0), sp.diff(nxt, d)
    steps.append(Step(
        "induction: one more transition after a generic composite a + b·d gives a′ = C_n(ℓ_n − a), b′ = −C_n·b",
        is_zero(new_a - big_c[n] * (ell[n] - a)) and is_zero(new_b + big_c[n] * b) and sp.diff(nxt, d, 2) == 0,
        f"C_n(ℓ_n − (a + b·d)) = {text(nxt)}",
    ))
    # the splitting rules, checked for concrete lengths
    rules_ok = True
    for m in range(1, 7):
        s_rest, s_last = _peel(constant(n + 1))
        p_rest, p_last = _peel(product(j, n))
        rules_ok &= is_zero((constant(n + 1) - s_rest - s_last).subs(n, m).doit())
        rules_ok &= is_zero((product(j, n) - p_rest * p_last).subs({n: m, j: 0}).doit())
    steps.append(Step(
        "the range-splitting rules Σ_{lo..hi} = Σ_{lo..hi−1} + (term hi) and Π likewise hold for lengths 1..6 "
        "(for general n they are the definitions of Σ and Π over an integer range)",
        rules_ok,
    ))
    # slope: (−1)^{n+1} Π_{k≤n} C_k = −C_n · (−1)^n Π_{k<n} C_k
    p_rest, p_last = _peel(product(0, n))
    slope_next = (-1) ** (n + 1) * p_rest * p_last
    steps.append(Step(
        "induction: the slope (−1)^n Π_{k<n} C_k satisfies b_{n+1} = −C_n·b_n",
        is_zero(slope_next - (-big_c[n] * slope(n))),
        f"b_(n+1) = {text(slope_next)}",
    ))
    # constant: A_{n+1} = C_n ℓ_n − C_n A_n
    rest, last = _peel(constant(n + 1))
    last = last.doit()  # Π_{k=n}^{n} C_k = C_n
    inner_rest, inner_last = _peel(product(j, n))
    rest_summand = rest.function.subs(product(j, n), inner_rest * inner_last)
    same_range = rest.limits == constant(n).limits
    termwise = is_zero(sp.powsimp(sp.expand(rest_summand + big_c[n] * summand(n)), force=True))
    steps.append(Step(
        "induction: the library's A satisfies A_{n+1} = C_n ℓ_n − C_n A_n — the j = n term of A_{n+1} is C_n ℓ_n and, "
        "over j = 0..n−1, each term of A_{n+1} is −C_n times the matching term of A_n",
        is_zero(last - big_c[n] * ell[n]) and same_range and termwise,
        f"last term {text(last)}; term_(n+1)(j) + C_n·term_n(j) = {text(sp.simplify(rest_summand + big_c[n] * summand(n)))}",
    ))
    base_constant = constant(sp.Integer(1)).doit()
    base_slope = slope(sp.Integer(1)).doit()
    steps.append(Step(
        "base case n = 1: F₁(d) = C₀(ℓ₀ − d) has A₁ = ℓ₀C₀ and slope −C₀",
        is_zero(base_constant - big_c[0] * ell[0]) and is_zero(base_slope + big_c[0]),
        f"A₁ = {text(base_constant)}, b₁ = {text(base_slope)}",
    ))
    (fixed,) = sp.solve(sp.Eq(a + b * d, d), d)
    steps.append(Step(
        "the fixed point of d ↦ a + b·d is a / (1 − b) (unique for b ≠ 1; here |b| = Π C_k < 1), "
        "so d_FP = A / (1 − (−1)^n Π C_k) for every n",
        is_zero(fixed - a / (1 - b)) and sp.solve(sp.Eq(a + sp.Integer(1) * d, d), d) == [],
        f"d = {text(fixed)}",
    ))
    return steps


_QUAD = [(0, 0), (4, 0), (7, 4), (0, 4)]  # convex, CCW, integer edge lengths 4, 5, 7, 4
_SIN, _COS = sp.Rational(5, 13), sp.Rational(12, 13)  # θ = atan(5/12) ≈ 22.6°, inside Lemma 3's range


def _concrete_polygon() -> list[Step]:
    pts = [sp.Matrix(p) for p in _QUAD]
    n = len(pts)
    edges = [pts[(i + 1) % n] - pts[i] for i in range(n)]
    lengths = [sp.sqrt(e.dot(e)) for e in edges]
    units = [e / length for e, length in zip(edges, lengths)]
    x = sp.Symbol("x", real=True)
    s, r = sp.symbols("s r", real=True)
    one_step_ok, lands_inside, cs, maps = True, True, [], []
    for i in range(n):  # exact ray cast from e_i, distance x from v_i, heading θ CCW from e_i
        nxt = (i + 1) % n
        u = units[i]
        ray = sp.Matrix([_COS * u[0] - _SIN * u[1], _SIN * u[0] + _COS * u[1]])
        (sol,) = sp.solve(list(pts[i] + x * u + s * ray - (pts[nxt] + r * edges[nxt])), [s, r], dict=True)
        # the hit parameter r on e_{i+1} is affine in x: r(ℓ_i) = 0 (the corner) and 0 < r(0) < 1 put every
        # start on the open edge e_i onto the open edge e_{i+1}, ahead of the robot (s > 0)
        r0, r1 = sol[r].subs(x, 0), sol[r].subs(x, lengths[i])
        lands_inside &= bool(r1 == 0 and 0 < r0 < 1 and sol[s].subs(x, 0) > 0)
        g = sp.expand(sol[r] * lengths[nxt])  # distance from v_{i+1}, the clockwise vertex of e_{i+1}
        sin_phi = (edges[i][0] * edges[nxt][1] - edges[i][1] * edges[nxt][0]) / (lengths[i] * lengths[nxt])
        cos_phi = -edges[i].dot(edges[nxt]) / (lengths[i] * lengths[nxt])
        c = _SIN / (_SIN * cos_phi + _COS * sin_phi)  # sin θ / sin(θ + φ) with φ the interior angle at v_{i+1}
        one_step_ok &= is_zero(g - c * (lengths[i] - x))
        cs.append(c)
        maps.append(g)
    composed = x
    for g in maps:
        composed = sp.expand(g.subs(x, composed))
    ells = list(lengths)
    constant, slope = composed.subs(x, 0), sp.diff(composed, x)
    fixed = design_fixed_point(cs, ells)
    rational = all(v.is_Rational for v in (constant, slope, fixed, *cs))
    return [
        Step(
            "example quadrilateral (0,0),(4,0),(7,4),(0,4), sin θ = 5/13: each exact ray cast from e_i lands on the "
            "open edge e_{i+1}, at distance C_i (ℓ_i − d) from v_{i+1} with C_i = sin θ / sin(θ + φ_i)",
            one_step_ok and lands_inside,
            "C = " + ", ".join(str(c) for c in cs),
        ),
        Step(
            "example quadrilateral: the ray-cast return map equals Theorem 1's (A and slope), its fixed point is "
            "inside e₀ and attracting (|slope| < 1), all exact rationals",
            is_zero(constant - design_constant(cs, ells))
            and is_zero(slope - (-1) ** n * sp.Mul(*cs))
            and is_zero(composed.subs(x, fixed) - fixed)
            and 0 < fixed < lengths[0]
            and abs(slope) < 1
            and rational,
            f"F(d) = {text(composed.subs(x, sp.Symbol('d')))}, d_FP = {fixed}",
        ),
    ]


def prove() -> ProofResult:
    """Theorem 1: the return map around a convex n-gon and its fixed point (n = 3..8, induction, an example)."""
    steps = _symbolic_n_steps() + _induction_steps() + _concrete_polygon()
    return ProofResult("Theorem 1 (limit cycle of a convex polygon: return map, fixed point)", tuple(steps))
