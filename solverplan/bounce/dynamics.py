"""Dynamics of fixed-heading bounces (paper §6): contraction coefficients, Lemma 3's range, Theorem 1's
fixed point, Corollaries 3 and 4 — and exact headings.

Conventions: a heading θ ∈ (0, π) is radians CCW from the directed edge the robot
leaves (π/2 = inward normal). A transition from segment e_i to e_j is a *right* transition when the
corner V where their supporting lines meet lies ahead of the robot (consecutive edges of a convex
polygon), a *left* one when V lies behind; φ is the interior angle of the triangle (robot, V, hit) at
V. Distances are measured along the boundary from V (Def. 11, Lemma 2):

    right:  C(θ, φ) = sin θ / sin(θ + φ)   on 0 < θ < π − φ,   C < 1  ⇔  θ < π/2 − φ/2
    left:   C(θ, φ) = sin θ / sin(θ − φ)   on φ < θ < π,       C < 1  ⇔  θ > π/2 + φ/2

C is increasing in θ for right transitions and decreasing for left ones (solverplan.proofs.contraction_monotonicity),
so over an action interval the worst case is at θ_hi (right) or θ_lo (left). Parallel source and target
(opposite walls) are the right transition with φ = 0: C = 1.

**Exact headings.** A heading is *exact* when it is given by a rational direction pair (c, s), s > 0:
the heading is θ = atan2(s, c), and the direction leaving edge e (edge vector v) is v rotated by the
matrix [[c, −s], [s, c]] — rational for rational vertices, whatever the length of (c, s) (only the ratio
matters, so a rational tangent tan θ = s/c is the same thing). :class:`ExactHeading` holds such a pair;
``ExactHeading.from_tangent(Fraction(1, 3))`` is θ = atan(1/3) exactly, and ``ExactHeading.from_float(θ)``
takes the float θ at the binary rationals (cos θ, sin θ) computed in floats — the heading atan2 of those,
within ~1e-16 rad of θ, the same direction :func:`~solverplan.bounce.transitions.exact_direction` uses.
The same pair gives every edge the same exact heading, which is what a constant rule b = θ means.

>>> round(float(contraction_coefficient(math.pi / 6, math.pi / 2)), 12)     # sin 30° / sin 120°
0.57735026919
>>> bool(is_contracting(0.7, math.pi / 2)), bool(is_contracting(0.8, math.pi / 2))   # threshold π/4
(True, False)
>>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
>>> lemma3_max_heading(square) == math.pi / 4
True
>>> fp = theorem1_fixed_point(square, ExactHeading.from_tangent(Fraction(1, 2)))
>>> fp.t_exact, round(fp.d, 12)             # tan θ / (1 + tan θ) = 1/3
(Fraction(1, 3), 0.333333333333)
>>> cycles_to_epsilon(Fraction(9, 10), 1, Fraction(1, 1000))   # tight Cor. 4 (the paper's factor 2 gives 73)
66
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction
from typing import Iterable, Literal, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike

from solverplan.interval import Interval
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, dot, format_number, to_fraction
from solverplan.limits import MIN_HEADING
from solverplan.bounce.safe import transition_angle as transition_phi, transition_side

__all__ = [
    "Side",
    "ExactHeading",
    "HeadingSpec",
    "parse_heading",
    "heading_value",
    "contraction_coefficient",
    "contraction_threshold",
    "is_contracting",
    "worst_case_contraction",
    "composite_contraction",
    "edge_transition",
    "interior_angles",
    "lemma3_max_heading",
    "Lemma3Range",
    "lemma3_range",
    "Theorem1FixedPoint",
    "theorem1_fixed_point",
    "cycles_to_epsilon",
    "distance_bound",
]

Side = Literal["right", "left"]


# ---------------------------------------------------------------------- exact headings
@dataclass(frozen=True, slots=True, init=False)  # __init__ takes any rational pair and stores it primitive
class ExactHeading:
    """The exact heading θ = atan2(sin, cos) ∈ (0, π) of the rational direction pair (cos, sin).

    Only the ratio of the pair matters; it is stored as a primitive integer pair (sin > 0). The
    direction leaving edge e with edge vector v is ``R v`` with R = [[cos, −sin], [sin, cos]]: exact,
    and at heading exactly θ from *every* edge (a constant rule).

    >>> ExactHeading.from_tangent(Fraction(-1, 2))          # tan θ = −1/2: θ ∈ (π/2, π)
    ExactHeading(cos=-2, sin=1)
    >>> ExactHeading(Fraction(3, 5), Fraction(4, 5)).direction((2, 0))
    (Fraction(6, 1), Fraction(8, 1))
    """

    cos: int
    sin: int

    def __init__(self, cos: int | Fraction, sin: int | Fraction) -> None:
        c, s = to_fraction(cos, where="heading cos"), to_fraction(sin, where="heading sin")
        if s <= 0:
            raise InputError(
                f"exact heading ({format_number(c)}, {format_number(s)}) is not inside (0, π): its sin part must be > 0"
            )
        if c != 0 and s / abs(c) < _MIN_TANGENT:
            # tan of the angle to the wall: exact, so a pair with huge parts is refused before any float sees it
            raise InputError(f"exact heading ({_short(c)}, {_short(s)}) is within {MIN_HEADING:g} rad of the wall: floats cannot follow it")
        scale = math.lcm(c.denominator, s.denominator)
        ci, si = int(c * scale), int(s * scale)
        g = math.gcd(ci, si)
        object.__setattr__(self, "cos", ci // g)
        object.__setattr__(self, "sin", si // g)

    @classmethod
    def from_float(cls, theta: float) -> ExactHeading:
        """θ taken at the binary rationals (cos θ, sin θ) computed in floats (within ~1e-16 rad of θ)."""
        theta = _check_theta(theta)
        return cls(Fraction(math.cos(theta)), Fraction(math.sin(theta)))

    @classmethod
    def from_tangent(cls, tangent: object) -> ExactHeading:
        """The heading in (0, π) with tan θ = ``tangent`` (a rational; negative means θ > π/2)."""
        q = to_fraction(tangent, where="heading tangent")
        if q == 0:
            raise InputError("heading tangent 0 is not inside (0, π): the heading would run along the wall")
        return cls(Fraction(1), q) if q > 0 else cls(Fraction(-1), -q)

    @property
    def theta(self) -> float:
        """The heading in radians (float)."""
        return math.atan2(self.sin, self.cos)

    @property
    def tangent(self) -> Fraction | None:
        """tan θ exactly (None at θ = π/2)."""
        return None if self.cos == 0 else Fraction(self.sin, self.cos)

    def direction(self, edge_vector: Sequence[object]) -> ExactPoint:
        """The exact direction at this heading from an edge with vector ``edge_vector``."""
        ex, ey = (to_fraction(v, where="edge vector") for v in edge_vector)
        return (self.cos * ex - self.sin * ey, self.sin * ex + self.cos * ey)

    def spec(self) -> str:
        """The text that :func:`parse_heading` reads back: ``tan:p/q``, or ``dir:c,s`` at π/2."""
        if self.cos == 0:
            return "dir:0,1"
        return f"tan:{format_number(Fraction(self.sin, self.cos))}"

    def __str__(self) -> str:
        return f"atan2({self.sin}, {self.cos}) ≈ {self.theta!r}"


HeadingSpec = Union[float, int, ExactHeading, str, tuple]
"""A heading: a number (radians, float), an :class:`ExactHeading`, a pair ``(cos, sin)`` of exact
numbers, or text (:func:`parse_heading`)."""

_NUMBER = r"[-+]?[0-9.]+(?:e[-+]?[0-9]+)?(?:/[0-9]+)?"


def parse_heading(spec: HeadingSpec) -> float | ExactHeading:
    """A heading from its command-line spelling or a Python value.

    Text forms: ``1.2`` or ``pi/6`` (radians, a float); ``tan:1/3`` (alias ``atan:1/3``): the heading
    with that exact rational tangent (negative: in (π/2, π)); ``dir:C,S``: the exact direction pair
    (cos, sin) up to scale. Numbers are floats in radians; pairs are ``(cos, sin)``.

    >>> parse_heading("tan:1/3")
    ExactHeading(cos=3, sin=1)
    >>> parse_heading("dir:-3,4").theta == math.atan2(4, -3)
    True
    >>> parse_heading("pi/4") == math.pi / 4
    True
    >>> parse_heading("4")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: heading 4 is not inside (0, π) (radians)
    """
    if isinstance(spec, ExactHeading):
        return spec
    if isinstance(spec, bool):
        raise InputError(f"heading {spec!r} is not a number")
    if isinstance(spec, (int, float, Fraction, np.integer, np.floating)):
        return _check_theta(float(spec))
    if isinstance(spec, tuple):
        if len(spec) != 2:
            raise InputError(f"an exact heading is a pair (cos, sin), got {spec!r}")
        return ExactHeading(to_fraction(spec[0], where="heading cos"), to_fraction(spec[1], where="heading sin"))
    if not isinstance(spec, str):
        raise InputError(f"heading {spec!r} is not a number, a pair (cos, sin) or text")
    text = spec.strip().lower().replace(" ", "")
    kind, _, rest = text.partition(":")
    if rest and kind in ("tan", "atan"):
        if not re.fullmatch(_NUMBER, rest):
            raise InputError(f"heading {spec!r}: {rest!r} is not a rational number (e.g. tan:1/3)")
        return ExactHeading.from_tangent(rest)
    if rest and kind == "dir":
        parts = rest.split(",")
        if len(parts) != 2 or not all(re.fullmatch(_NUMBER, p) for p in parts):
            raise InputError(f"heading {spec!r}: expected dir:C,S with rational C and S (e.g. dir:3,4)")
        return ExactHeading(to_fraction(parts[0], where="heading cos"), to_fraction(parts[1], where="heading sin"))
    if rest:
        raise InputError(f"heading {spec!r}: unknown form {kind!r}: use radians (1.2, pi/6), tan:P/Q or dir:C,S")
    match = re.fullmatch(r"([0-9.]*)\*?(pi|π)(?:/([0-9.]+))?", text)
    try:
        if match:
            factor = float(match.group(1)) if match.group(1) else 1.0
            value = factor * math.pi / (float(match.group(3)) if match.group(3) else 1.0)
        else:
            value = float(text)
    except (ValueError, ZeroDivisionError):
        raise InputError(f"heading {spec!r} is not an angle: use radians (1.2, pi/6), tan:P/Q or dir:C,S") from None
    return _check_theta(value)


def heading_value(theta: float | ExactHeading) -> float:
    """The heading in radians, whichever form it has."""
    return theta.theta if isinstance(theta, ExactHeading) else float(theta)


def _check_theta(theta: float) -> float:
    value = float(theta)
    if not (math.isfinite(value) and 0 < value < math.pi):
        raise InputError(f"heading {value:g} is not inside (0, π) (radians)")
    if min(value, math.pi - value) < MIN_HEADING:
        raise InputError(f"heading {value:g} is within {MIN_HEADING:g} rad of the wall: floats cannot follow it")
    return value


# tan(MIN_HEADING) rounded down: a heading whose exact tangent to the wall is below this is refused
_MIN_TANGENT = Fraction(MIN_HEADING) * Fraction(999_999, 1_000_000)


def _short(value: Fraction) -> str:
    """An exact number for a message, its long spellings cut (headings may hold huge integers)."""
    text = format_number(value)
    return text if len(text) <= 24 else f"{float(value):.3g}" if abs(value) < 10**300 else text[:20] + "…"


# ---------------------------------------------------------------------- Def. 11, Lemma 2
def _sides(side: object) -> np.ndarray:
    arr = np.asarray(side)
    ok = np.isin(arr, ("right", "left"))
    if not np.all(ok):
        bad = arr.reshape(-1)[np.flatnonzero(~ok.reshape(-1))[0]]
        raise InputError(f"transition side {str(bad)!r} is neither 'right' nor 'left'")
    return arr == "right"


def _scalar_or_array(value: np.ndarray, *inputs: ArrayLike):
    if all(np.ndim(x) == 0 for x in inputs):
        return value.item()
    return value


def contraction_coefficient(theta, phi, side: Side | Sequence[str] = "right"):
    """C(θ, φ) of a transition (Def. 11, Lemma 2): how distances from the corner scale, vectorised.

    Parameters
    ----------
    theta
        Heading(s), radians in (0, π).
    phi
        Interior angle(s) at the corner, radians in [0, π) (0: parallel walls, C = 1).
    side
        ``"right"`` (corner ahead: sin θ / sin(θ + φ)) or ``"left"`` (corner behind: sin θ / sin(θ − φ)).

    Returns
    -------
    float or numpy array
        C > 0 on the transition's domain (right: θ + φ < π, left: θ > φ); NaN outside it, where the
        ray cannot reach the target line ahead.

    >>> contraction_coefficient(np.array([0.5, 1.0]), np.pi / 2).round(6).tolist()      # tan θ in a rectangle
    [0.546302, 1.557408]
    >>> math.isnan(contraction_coefficient(2.0, 2.0))
    True
    """
    t = np.asarray(theta, dtype=float)
    p = np.asarray(phi, dtype=float)
    right = _sides(side)
    den = np.where(right, np.sin(t + p), np.sin(t - p))
    valid = (t > 0) & (t < math.pi) & (p >= 0) & (p < math.pi) & np.where(right, t + p < math.pi, t > p)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(valid, np.sin(t) / np.where(valid, den, 1.0), np.nan)
    return _scalar_or_array(np.asarray(out, dtype=float), theta, phi, side)


def contraction_threshold(phi, side: Side | Sequence[str] = "right"):
    """Lemma 2's threshold: right transitions contract iff θ < π/2 − φ/2, left ones iff θ > π/2 + φ/2."""
    p = np.asarray(phi, dtype=float)
    out = np.where(_sides(side), math.pi / 2 - p / 2, math.pi / 2 + p / 2)
    return _scalar_or_array(np.asarray(out, dtype=float), phi, side)


def is_contracting(theta, phi, side: Side | Sequence[str] = "right"):
    """Lemma 2: is the transition at heading θ a contraction (C(θ, φ) < 1)? Vectorised; False outside the domain.

    >>> is_contracting([0.2, 2.2], [1.0, 1.0], ["right", "left"]).tolist()     # 0.2 < π/2 − 1/2; 2.2 > π/2 + 1/2
    [True, True]
    """
    t = np.asarray(theta, dtype=float)
    right = _sides(side)
    threshold = np.asarray(contraction_threshold(phi, side), dtype=float)
    c = np.asarray(contraction_coefficient(theta, phi, side), dtype=float)
    out = np.isfinite(c) & np.where(right, t < threshold, t > threshold)
    return _scalar_or_array(np.asarray(out, dtype=bool), theta, phi, side)


def worst_case_contraction(interval: Interval | Sequence[float], phi: float, side: Side = "right") -> float:
    """The largest C(θ, φ) over θ in an action interval: at θ_hi for a right transition, θ_lo for a left
    one (C is monotone: solverplan.proofs.contraction_monotonicity). NaN if that end is outside the domain.

    >>> worst_case_contraction((0.3, 0.5), math.pi / 2) == contraction_coefficient(0.5, math.pi / 2)
    True
    """
    if isinstance(interval, Interval):
        if interval.is_empty:
            raise InputError("worst-case contraction over an empty heading interval")
        lo, hi = interval.lo, interval.hi
    else:
        try:
            lo, hi = (float(v) for v in interval)
        except (TypeError, ValueError):
            raise InputError(f"expected a heading interval [lo, hi], got {interval!r}") from None
    if lo > hi:
        raise InputError(f"heading interval [{lo:g}, {hi:g}] is reversed")
    right = bool(_sides(side))
    return float(contraction_coefficient(hi if right else lo, phi, side))


def composite_contraction(sequence: Iterable[object]) -> float:
    """Def. 12: the contraction coefficient of a sequence of transitions is the product Π C_k.

    Each item is a coefficient C_k (a number) or a triple ``(theta, phi, side)``; a ``(interval, phi,
    side)`` triple contributes its worst case. The composite contracts iff the product is < 1, even when
    single steps expand.

    >>> round(composite_contraction([(0.3, math.pi / 2, "right"), 2.0, ((0.2, 0.4), math.pi / 2, "right")]), 12)
    0.26157053729
    """
    total = 1.0
    for k, item in enumerate(sequence):
        if isinstance(item, tuple) and len(item) == 3:
            theta, phi, side = item
            if isinstance(theta, (Interval, tuple, list)):
                c = worst_case_contraction(theta, phi, side)
            else:
                c = float(contraction_coefficient(float(theta), float(phi), side))
        else:
            try:
                c = float(item)  # type: ignore[arg-type]
            except (TypeError, ValueError):
                raise InputError(f"transition {k}: expected a coefficient or (theta, phi, side), got {item!r}") from None
        if not c > 0:
            raise InputError(f"transition {k}: contraction coefficient {c!r} is not positive (outside the domain)")
        total *= c
    return total


def edge_transition(env: Environment, source: int, target: int) -> tuple[float, Side]:
    """(φ, side) of the transition from edge ``source`` to edge ``target`` (Def. 8, Lemma 2): the exact side
    and φ of :func:`solverplan.bounce.safe.transition_side` and :func:`~solverplan.bounce.safe.transition_angle`
    on the two edges. Opposite walls (parallel, facing) are ``("right", 0)`` (C = 1); edges pointing the same
    way cannot be hit from the free side: an InputError.

    >>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> edge_transition(square, 0, 1) == (math.pi / 2, "right"), edge_transition(square, 0, 3) == (math.pi / 2, "left")
    (True, True)
    """
    src, tgt = env.edge(int(source)), env.edge(int(target))
    side = transition_side((src.a, src.b), (tgt.a, tgt.b))  # Def. 8, exact
    if side == "parallel":
        if dot((src.b[0] - src.a[0], src.b[1] - src.a[1]), (tgt.b[0] - tgt.a[0], tgt.b[1] - tgt.a[1])) > 0:
            raise InputError(f"edges e{source} and e{target} point the same way: no ray from e{source} meets e{target} from its free side")
        return 0.0, "right"  # opposite walls: C = 1 either way
    return transition_phi((src.a, src.b), (tgt.a, tgt.b)), side


# ---------------------------------------------------------------------- Lemma 3, Theorem 1
def _require_convex(env: Environment, what: str) -> None:
    if env.holes:
        raise InputError(f"{what} needs a convex polygon without holes: {env.name or 'the environment'} has {len(env.holes)} hole(s)")
    if env.reflex_vertices:
        v = env.reflex_vertices[0]
        raise InputError(f"{what} needs a convex polygon: vertex v{v} of {env.name or 'the environment'} is reflex")
    verts = env.exact_vertices
    n = env.n_vertices
    for k in range(n):
        a, b, c = verts[k - 1], verts[k], verts[(k + 1) % n]
        if (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) == 0:
            raise InputError(
                f"{what} needs a strictly convex polygon: vertex v{k} is collinear with its neighbours "
                "(interior angle π), so Lemma 3's range is empty"
            )


def interior_angles(env: Environment) -> np.ndarray:
    """Interior angle at every vertex (radians, in the free space: > π at reflex vertices), indexed by vertex."""
    n = env.n_vertices
    out = np.empty(n)
    prev = env.prev_vertex
    for v in range(n):
        u = env.vertices[v] - env.vertices[int(prev[v])]
        w = env.vertices[int(env.next_vertex[v])] - env.vertices[v]
        turn = math.atan2(float(u[0] * w[1] - u[1] * w[0]), float(u @ w))
        out[v] = math.pi - turn
    return out


@dataclass(frozen=True, slots=True)
class Lemma3Range:
    """Lemma 3's admissible headings for a convex polygon, and what binds them.

    Counter-clockwise (the paper's statement): θ ∈ (0, bound), with ``order_bound`` = min_i ∠v_{i+2} v_i v_{i+1}
    (every start of e_i reaches e_{i+1}: the CCW edge order, solverplan.proofs.lemma3_convex_order) and
    ``contraction_bound`` = min_i (π/2 − φ_i/2) (every step contracts, Lemma 2); ``bound`` is the smaller.
    ``clockwise`` (the mirror image, θ > π/2): θ ∈ (π − bound, π), the order angles being ∠v_{i−1} v_{i+1} v_i
    (every start of e_i reaches e_{i−1}) and the steps left transitions (Lemma 2: contract iff θ > π/2 + φ/2).
    ``order_edge`` is the edge whose starts miss their next edge first, ``contraction_vertex`` the corner
    whose step expands first.
    """

    bound: float
    n: int
    order_bound: float
    order_edge: int
    contraction_bound: float
    contraction_vertex: int
    clockwise: bool = False

    @property
    def interval(self) -> tuple[float, float]:
        """The admissible open interval of headings (radians)."""
        return (math.pi - self.bound, math.pi) if self.clockwise else (0.0, self.bound)

    def contains(self, theta: float) -> bool:
        lo, hi = self.interval
        return lo < theta < hi

    def _order_angle(self) -> str:
        i, n = self.order_edge, self.n
        if self.clockwise:
            return f"∠v{(i - 1) % n} v{(i + 1) % n} v{i}"
        return f"∠v{(i + 2) % n} v{i} v{(i + 1) % n}"

    def reason_outside(self, theta: float) -> str:
        """Why θ is not in the range (empty string if it is)."""
        parts = []
        x, name = (math.pi - theta, "π − θ") if self.clockwise else (theta, "θ")
        i, n = self.order_edge, self.n
        if x >= self.order_bound:
            near, nxt = ((i + 1) % n, (i - 1) % n) if self.clockwise else (i, (i + 1) % n)
            sense = "CW" if self.clockwise else "CCW"
            parts.append(
                f"{name} = {x:.6g} ≥ {self.order_bound:.6g} = {self._order_angle()} "
                f"(starts near v{near} on edge e{i} miss edge e{nxt}: the {sense} edge order breaks)"
            )
        if x >= self.contraction_bound:
            v = self.contraction_vertex
            parts.append(
                f"{name} = {x:.6g} ≥ {self.contraction_bound:.6g} = π/2 − φ/2 at v{v} (the step into the corner v{v} expands, Lemma 2)"
            )
        return "; ".join(parts)


def lemma3_range(env: Environment, *, clockwise: bool = False) -> Lemma3Range:
    """Lemma 3's range for a strictly convex polygon, with its two bounds (see :class:`Lemma3Range`);
    ``clockwise`` gives the mirror-image range of headings near π (clockwise cycles, by symmetry).

    Raises
    ------
    InputError
        For holes, a reflex vertex, or a collinear vertex (the range would be empty).

    >>> r = lemma3_range(Environment.from_coords([[0, 0], [2, 0], [2, 1], [0, 1]]), clockwise=True)
    >>> r.interval == (math.pi - math.atan(1 / 2), math.pi), r.order_edge
    (True, 0)
    """
    _require_convex(env, "Lemma 3")
    n = env.n_vertices
    phi = interior_angles(env)
    contraction = math.pi / 2 - phi / 2
    order = np.empty(n)
    verts = env.vertices
    for i in range(n):
        if clockwise:  # from e_i towards e_{i-1}: the angle at v_{i+1} between v_i and v_{i-1}
            a, e, w = verts[(i + 1) % n], verts[i] - verts[(i + 1) % n], verts[i - 1] - verts[(i + 1) % n]
        else:  # from e_i towards e_{i+1}: the angle at v_i between v_{i+1} and v_{i+2}
            a = verts[i]
            e, w = verts[(i + 1) % n] - a, verts[(i + 2) % n] - a
        order[i] = math.atan2(abs(float(e[0] * w[1] - e[1] * w[0])), float(e @ w))
    oi, ci = int(np.argmin(order)), int(np.argmin(contraction))
    return Lemma3Range(
        bound=float(min(order[oi], contraction[ci])),
        n=n,
        order_bound=float(order[oi]),
        order_edge=oi,
        contraction_bound=float(contraction[ci]),
        contraction_vertex=ci,
        clockwise=bool(clockwise),
    )


def lemma3_max_heading(env: Environment) -> float:
    """The supremum of Lemma 3's range: in a strictly convex polygon every constant heading
    0 < θ < min_i min(π/2 − φ_i/2, ∠v_{i+2} v_i v_{i+1}) visits the edges in CCW order forever from any
    start, every step contracting, so the trajectory converges to Theorem 1's period-n limit cycle.

    The two bounds are those of solverplan.proofs.lemma3_convex_order: the angle bound is exactly the edge-order
    condition (for the open edges θ equal to it still works), and the per-step contraction bound is
    sufficient, not necessary — Theorem 1 needs only Π C_k < 1 (Def. 12). φ_i runs over all interior
    angles (the paper's φ_{i−1,i} and the φ_i here index the same set). See :func:`lemma3_range`.

    Raises
    ------
    InputError
        For a non-convex environment, holes, or a collinear vertex.

    >>> lemma3_max_heading(Environment.from_coords([[0, 0], [2, 0], [2, 1], [0, 1]])) == math.atan(1 / 2)
    True
    """
    return lemma3_range(env).bound


@dataclass(frozen=True, slots=True)
class Theorem1FixedPoint:
    """Theorem 1's fixed point on edge e_edge: ``d`` the distance from the edge's first vertex (float, by
    Theorem 1's closed form), ``t`` = d / ℓ, and ``t_exact`` the same by composing the exact rational affine
    maps of the n transitions (only for an :class:`ExactHeading`), ``contraction`` = Π C_k (float) and
    ``contraction_exact`` = |α| of the exact return map."""

    edge: int
    d: float
    t: float
    contraction: float
    t_exact: Fraction | None = None
    contraction_exact: Fraction | None = None


def theorem1_fixed_point(env: Environment, theta: float | ExactHeading, *, edge: int = 0) -> Theorem1FixedPoint:
    """Theorem 1: the fixed point of the CCW return map of a convex polygon under the constant rule b = θ.

    d_FP = A / (1 − (−1)^n Π C_k),  A = Σ_j (−1)^{n−1−j} ℓ_j Π_{k=j}^{n−1} C_k, with C_k = C(θ, φ_{k,k+1})
    (right transitions, the corner v_{k+1}), edges re-indexed to start at ``edge``. When θ is an
    :class:`ExactHeading` (or a ``(cos, sin)`` pair / ``tan:`` text) the fixed point is also computed
    exactly, t* = β / (1 − α) of the composed rational maps
    (:func:`~solverplan.bounce.transitions.affine_map`). It is the limit cycle when θ is in Lemma 3's range
    (:func:`lemma3_max_heading`); outside it, it is only the fixed point of the formula's map, which the
    robot may not follow — :func:`~solverplan.bounce.cycles.limit_cycle` checks that.

    Raises
    ------
    InputError
        Non-convex environments; θ outside (0, π) or past a right-transition domain (θ + φ_k ≥ π).
    """
    from solverplan.bounce.transitions import AffineMap, affine_map

    _require_convex(env, "Theorem 1")
    heading = parse_heading(theta) if not isinstance(theta, (float, int)) else _check_theta(theta)
    value = heading_value(heading)
    n = env.n_edges
    if not 0 <= int(edge) < n:
        raise InputError(f"unknown edge e{edge}: edges are e0..e{n - 1}")
    order = [(int(edge) + k) % n for k in range(n)]
    phi = interior_angles(env)
    lengths = env.edge_lengths
    c = np.array([contraction_coefficient(value, phi[(k + 1) % n], "right") for k in order])
    if not np.all(np.isfinite(c)):
        k = order[int(np.flatnonzero(~np.isfinite(c))[0])]
        raise InputError(f"heading {value:.6g} is past the right-transition domain at v{(k + 1) % n}: θ + φ ≥ π")
    ell = np.array([lengths[k] for k in order])
    a_sum = sum((-1) ** (n - 1 - j) * ell[j] * float(np.prod(c[j:])) for j in range(n))
    product = float(np.prod(c))
    d = a_sum / (1 - (-1) ** n * product)
    t_exact = c_exact = None
    if isinstance(heading, ExactHeading):
        ret: AffineMap | None = None
        for k, src in enumerate(order):
            e = env.edge(src)
            m = affine_map(env, src, heading.direction((e.b[0] - e.a[0], e.b[1] - e.a[1])), order[(k + 1) % n])
            ret = m if ret is None else ret.then(m)
        assert ret is not None  # a polygon has at least three edges
        t_exact, c_exact = ret.fixed_point(), ret.contraction
    return Theorem1FixedPoint(int(edge), float(d), float(d / ell[0]), product, t_exact, c_exact)


# ---------------------------------------------------------------------- Cor. 3, Cor. 4
def _positive(value: object, name: str) -> Fraction | float:
    if isinstance(value, (Fraction, int)) and not isinstance(value, bool):
        v: Fraction | float = Fraction(value)
    else:
        try:
            v = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise InputError(f"{name} {value!r} is not a number") from None
        if not math.isfinite(v):
            raise InputError(f"{name} {value!r} is not finite")
    if not v > 0:
        raise InputError(f"{name} {format_number(v)} must be positive")
    return v


def cycles_to_epsilon(contraction: object, width: object, epsilon: object) -> int:
    """Cor. 4, tight: the fewest cycles k ≥ 0 after which a position set of width ``width`` is at most
    ``epsilon`` wide, for a cycle whose return map contracts by ``contraction`` (0 < C < 1):

        k = max(0, ⌈log(ε / w) / log C⌉)

    (solverplan.proofs.cor3_cor4_uncertainty: the set's width is exactly C^k·w; the paper's ⌈log(ε/(2ℓ))/log C⌉ is
    sufficient, not tight). ``width`` and ``epsilon`` in the same unit (arc length, or the boundary
    parameter t of one edge); all-exact inputs (ints, Fractions) are decided exactly, floats are checked
    against C^k·w after the logarithms so a ratio that is an exact power does not round up a cycle.

    Raises
    ------
    InputError
        Unless 0 < C < 1 and w, ε > 0.

    >>> cycles_to_epsilon(0.5, 1.0, 0.25), cycles_to_epsilon(0.5, 1.0, 2.0)
    (2, 0)
    """
    c = _positive(contraction, "contraction")
    if not c < 1:
        raise InputError(f"contraction {format_number(c)} is not < 1: the position set never shrinks")
    w = _positive(width, "width")
    eps = _positive(epsilon, "epsilon")
    exact = all(isinstance(v, Fraction) for v in (c, w, eps))
    if not exact:
        c, w, eps = float(c), float(w), float(eps)
    if w <= eps:
        return 0
    k = max(0, math.ceil(math.log(float(eps) / float(w)) / math.log(float(c))) - 1)

    def width_after(j: int):
        return c**j * w

    while width_after(k) > eps:
        k += 1
    while k > 0 and width_after(k - 1) <= eps:
        k -= 1
    return k


def distance_bound(k: int, contraction: object, length: object) -> float | Fraction:
    """Cor. 3: after k cycles the robot is within C^k·ℓ of the fixed point (|F^k(x₀) − x*| = C^k|x₀ − x*|
    ≤ C^k ℓ for a start on the same edge of length ℓ). Exact for exact inputs.

    >>> distance_bound(3, Fraction(1, 2), 8)
    Fraction(1, 1)
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
        raise InputError(f"cycles k must be a non-negative integer, got {k!r}")
    c = _positive(contraction, "contraction")
    ell = _positive(length, "length")
    if isinstance(c, Fraction) and isinstance(ell, Fraction):
        return c ** int(k) * ell
    return float(c) ** int(k) * float(ell)
