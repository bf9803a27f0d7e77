"""A symbolic perturbation for the wall-following model: degenerate polygons made general (simulation of simplicity).

The wall-following model (Yershova et al.) assumes general position: no three collinear vertices, no two cut end
points at one point. Rectilinear floor plans and most hand-drawn polygons break it (a row of reflex corners on one
line: a JUMP runs into the next corner). :func:`perturb` first merges the vertices of angle exactly π (the robot
cannot sense them: :func:`~solverplan.wallfollow.cut.corner_polygon`), then moves the corner of rank r — in the
lexicographic (x, y) order of the corners, so the perturbation does not depend on where the ring starts or on
split edges — by

    δ = ε · s · (r + 1, (r + 1)²)          (s: the polygon's size over n², length units)

for a rational ε small enough to be *infinitesimal* for the polygon: every orientation of three vertices is then
a polynomial D₀ + ε D₁ + ε² D₂ in ε whose ε² term is the orientation of three points of a parabola (distinct
ranks) — never 0 —, so no three vertices stay collinear, and every predicate that was not degenerate keeps its
sign. ε starts at 2⁻²⁴
and shrinks by 2⁻¹⁰ until (a) the perturbed polygon is simple, (b) it is in general position
(:func:`~solverplan.wallfollow.cut.check_general_position`, exact) and (c) its cut ordering is the same at ε and
at ε·2⁻¹⁰ (the combinatorial model no longer depends on ε: it is the limit ε → 0⁺). The answer records ε and the
displacement; everything downstream (cuts, orderings, Strategy 1, pursuit) runs on the perturbed polygon exactly.

**What it means for the robot.** The robot moves in a polygon infinitesimally different from the given one, chosen
once and for all (a fixed order of the vertices, as in simulation of simplicity): a JUMP that would graze a vertex
(three collinear vertices) passes it on one fixed side — it lands on the wall just beyond or just before the
vertex, as the perturbation decides —; two cut end points that would coincide are ordered one way along the wall;
a vertex in the middle of a straight wall is no corner (merged first, as without ``--perturb``). For a real robot whose walls are not exact this is one of the polygons it may be in; plans and orderings
are exact for that polygon, and a plan verified there is a plan for every polygon close enough with the same
combinatorics. Without ``--perturb`` a degenerate polygon is refused with the offending vertices named.

>>> from solverplan.environment import Environment
>>> ell = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]])   # vertices 1, 3, 5 collinear
>>> p = perturb(ell)
>>> p.general, p.env.n_vertices, p.epsilon
(False, 6, Fraction(1, 16777216))
>>> from solverplan.wallfollow.cut import cut_ordering
>>> cut_ordering(p.env).labels
('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3')
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidEnvironment
from solverplan.exact import ExactPoint, format_number

__all__ = ["Perturbation", "perturb", "PerturbedAnswer"]

_FIRST = Fraction(1, 2**24)
_SHRINK = Fraction(1, 2**10)
_TRIES = 6


@dataclass(frozen=True)
class Perturbation:
    """The perturbed environment ``env`` (its corners: vertices of angle π merged), ε, each corner's displacement
    (length units, exact) and whether the input was already in general position (``general``: then ``env`` is the
    input and ε is 0)."""

    env: Environment
    epsilon: Fraction
    displacement: tuple[ExactPoint, ...]
    general: bool

    def to_json(self) -> dict:
        return {"applied": not self.general, "epsilon": format_number(self.epsilon),
                "displacement_max": max((float(max(abs(d[0]), abs(d[1]))) for d in self.displacement), default=0.0),
                "rule": "the corner of rank r in (x, y) order moves by epsilon * s * (r + 1, (r + 1)^2), s = size / n^2 "
                        "(simulation of simplicity)"}


def _general(env: Environment) -> bool:
    from solverplan.wallfollow.cut import check_general_position

    try:
        check_general_position(env)
    except InvalidEnvironment as exc:
        if "hole" in str(exc):
            raise
        return False
    return True


def _moved(env: Environment, epsilon: Fraction) -> tuple[Environment, tuple[ExactPoint, ...]] | None:
    pts = env.exact_vertices
    n = len(pts)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    size = max(max(xs) - min(xs), max(ys) - min(ys))
    s = size / (n * n)
    rank = {i: r for r, i in enumerate(sorted(range(n), key=lambda i: pts[i]))}
    shift = tuple((epsilon * s * (rank[i] + 1), epsilon * s * (rank[i] + 1) ** 2) for i in range(n))
    ring = [(p[0] + d[0], p[1] + d[1]) for p, d in zip(pts, shift)]
    try:
        moved = Environment.from_coords(ring, name=env.name)
    except InvalidEnvironment:
        return None
    if moved.exact_vertices != tuple(ring):  # normalisation must keep the vertex order (labels refer to it)
        return None
    return moved, shift


def perturb(env: Environment) -> Perturbation:
    """The environment in general position by an infinitesimal symbolic perturbation (module docstring).

    Parameters
    ----------
    env
        A simple polygon without holes (any degeneracy; vertices of angle π are merged first).

    Returns
    -------
    Perturbation
        The input itself (``general=True``, ε = 0) when it is in general position already.

    Raises
    ------
    InvalidEnvironment
        For holes (the wall-following model needs a simply connected polygon).
    InputError
        If no ε down to 2⁻⁸⁴ gives a stable general polygon (never seen).
    """
    from solverplan.wallfollow.cut import corner_polygon, cut_ordering

    if _general(env):
        return Perturbation(env, Fraction(0), tuple((Fraction(0), Fraction(0)) for _ in range(env.n_vertices)), True)
    env = corner_polygon(env)
    epsilon = _FIRST
    for _ in range(_TRIES):
        here, finer = _moved(env, epsilon), _moved(env, epsilon * _SHRINK)
        if here is not None and finer is not None and _general(here[0]) and _general(finer[0]):
            if cut_ordering(here[0]).labels == cut_ordering(finer[0]).labels:
                return Perturbation(here[0], epsilon, here[1], False)
        epsilon *= _SHRINK
    raise InputError(f"no symbolic perturbation of {env.name or 'the polygon'} down to ε = {epsilon} is stable")


@dataclass(frozen=True)
class PerturbedAnswer:
    """A wall-following answer computed on a perturbed polygon: the answer's own JSON with ``perturbation`` added."""

    answer: Any
    perturbation: Perturbation

    def __getattr__(self, name: str) -> Any:
        return getattr(self.answer, name)

    def to_json(self) -> dict:
        out = dict(self.answer.to_json())
        out["perturbation"] = self.perturbation.to_json()
        return out

    def to_text(self, *, width: int = 100) -> str:
        text = self.answer.to_text(width=width)
        p = self.perturbation
        note = ("in general position: no perturbation" if p.general else
                f"symbolic perturbation applied (ε = {format_number(p.epsilon)}): degeneracies resolved one fixed way")
        return text.rstrip("\n") + "\n" + note + "\n"
