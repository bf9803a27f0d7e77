"""Bounce rules (paper §3, Def. 1–2, Fig. 2): how the robot leaves a wall it has just hit.

A bounce rule maps the contact — the edge hit and the incoming direction of travel — to an
outgoing heading θ ∈ (0, π), radians CCW from the directed edge hit (π/2 = straight into the room). A *non-deterministic* rule returns an interval of headings (Def. 2); every rule here has
an ``epsilon``: it may execute any heading in [b − ε, b + ε] around its nominal heading b (clipped
to (0, π)), and ``epsilon = 0`` is the deterministic rule.

**The incoming angle α.** In the frame of the edge hit (x along the directed edge, y = inward
normal, the contact at the origin — the paper's Def. 1 frame), the robot arrives travelling along a
unit vector v with v_y < 0. The paper's α ∈ (0, π) is the direction *back along the incoming path*,
−v, measured CCW from the edge: α = atan2(−v_y, −v_x). This is the only reading under which the
paper's specular rule b = π − α is the mirror reflection (v_x, v_y) → (v_x, −v_y); see
:func:`incoming_angles`.

**The rules, exactly** (``b`` the nominal outgoing heading):

- :class:`Specular` — b = π − α (mirror reflection; billiards).
- :class:`Fixed` — b = θ_f whatever α (the paper's fixed rule; Thm. 1's limit cycles). The rule that
  returns a given interval [lo, hi] whatever α (a plan's action interval) is :class:`FixedInterval`.
- :class:`MonotoneFixed` — b ∈ {θ_m, π − θ_m}: the one whose outgoing direction has the larger
  component along σ·axis, where ``axis`` is the global x axis (by default) and σ = +1 if the
  incoming travel direction v has v·axis ≥ 0, else −1. So travel keeps its sense along the axis
  whenever one of the two choices allows it, and turns the least otherwise. Ties (the edge hit is
  perpendicular to the axis, or θ_m = π/2: both choices have equal components) keep θ_m.
- :class:`Relative` — rotate clockwise through θ_r, repeatedly, until pointing into the free space
  (paper Fig. 2: b = α − θ_r "rotating α through θ_r in the clockwise direction; if the robot still
  faces the boundary it rotates again"). With a start direction β, the outgoing heading is
  b = (β − k θ_r) mod 2π for the least k ≥ 1 that lands in the open interval (0, π) (headings
  exactly along the wall, 0 or π, do not count as free). Because 0 < θ_r < π the rotation cannot
  jump over (0, π), so k ≤ ⌈2π/θ_r⌉ and the result lies in [π − θ_r, π) whenever k > 1.
  ``reference="back"`` (default, the paper's formula) starts from β = α, the direction back along
  the incoming path; ``reference="travel"`` starts from β = α + π, the direction of travel — the
  robot turning in place from its heading at impact (Alam et al.'s robots). The paper's text
  supports the first reading through its formula and the second through "still facing the
  boundary"; both are offered and the choice is recorded in the rule.

Every rule is a frozen dataclass with a common vectorised interface (:class:`BounceRule`):
``bounds`` (the non-deterministic set per contact, arrays lo ≤ hi), ``headings`` / ``__call__``
(headings sampled in it), ``nominal`` and, for one contact, ``interval`` (an :class:`Interval`).

>>> import numpy as np
>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]])
>>> v = np.array([[1.0, -1.0]]) / np.sqrt(2)           # down and to the right, onto edge 0 (the floor)
>>> round(float(incoming_angles(square, [0], v)[0]), 6) == round(3 * np.pi / 4, 6)
True
>>> Specular()(square, [0], v).round(6).tolist()       # leaves up and to the right: π/4
[0.785398]
>>> Relative(np.pi / 2)(square, [0], v).round(6).tolist()   # α − θ_r = π/4
[0.785398]
>>> Relative(np.pi / 2, reference="travel")(square, [0], v).round(6).tolist()   # 7π/4 − π/2 → 5π/4 → 3π/4
[2.356194]
>>> Fixed(1.0, epsilon=0.25).interval(square, 0, v[0])
Interval(lo=0.75, hi=1.25)
>>> Fixed(3.5)
Traceback (most recent call last):
...
solverplan.errors.InvalidBoundarySet: fixed rule: heading interval [3.5, 3.5] is not inside (0, π): hi=3.5
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Literal, Protocol, Sequence, runtime_checkable

import numpy as np

from solverplan.choices import Sampling
from solverplan.interval import Interval, heading_interval
from solverplan.environment import check_edges
from solverplan.errors import InputError, InvalidBoundarySet

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.environment import Environment

__all__ = [
    "BounceRule",
    "Sampling",
    "SAMPLINGS",
    "HEADING_MARGIN",
    "Specular",
    "Fixed",
    "FixedInterval",
    "MonotoneFixed",
    "Relative",
    "incoming_angles",
    "edge_frames",
    "sample_headings",
    "parse_rule",
    "rotate_clockwise_into_free",
    "check_edges",
    "check_headings",
]

SAMPLINGS: tuple[str, ...] = Sampling.values()
"""How a heading is drawn from a non-deterministic set [lo, hi]: ``uniform`` on [lo, hi];
``endpoints`` lo or hi with probability 1/2 each (adversarial: worst cases of contraction and of
safety sit at the ends); ``lo`` / ``hi`` always that end; ``mid`` the midpoint."""

HEADING_MARGIN = 1e-12
"""Headings are kept in [HEADING_MARGIN, π − HEADING_MARGIN] (radians): a nominal heading at 0 or π
(a grazing arrival under the specular rule) or an interval reaching past (0, π) is clipped there, so
every heading a rule returns is a valid action. Such a ray runs along the wall into a vertex, and the
simulator flags it."""


# ---------------------------------------------------------------------- input checks
def check_headings(headings: object, *, name: str = "heading") -> np.ndarray:
    """Headings as a float array, or a one-line :class:`InvalidBoundarySet` naming the first one outside (0, π).

    >>> check_headings([1.0, 3.5])
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidBoundarySet: heading 3.5 is not inside (0, π)
    """
    try:
        arr = np.asarray(headings, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{name}s must be numbers (radians), got {headings!r}") from None
    bad = np.flatnonzero(~((arr > 0) & (arr < math.pi)))
    if len(bad):
        raise InvalidBoundarySet(f"{name} {arr[bad[0]]:g} is not inside (0, π)")
    return arr


def _check_directions(incoming: object, m: int) -> np.ndarray:
    try:
        arr = np.asarray(incoming, dtype=float)
    except (TypeError, ValueError):
        raise InputError("incoming directions must be numbers of shape (m, 2)") from None
    if arr.ndim == 1 and arr.shape == (2,):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(f"incoming directions must have shape (m, 2), got {arr.shape}")
    if len(arr) != m:
        raise InputError(f"edges and incoming directions differ in length: {m} and {len(arr)}")
    norm = np.hypot(arr[:, 0], arr[:, 1])
    bad = np.flatnonzero(~np.isfinite(norm) | (norm == 0))
    if len(bad):
        raise InputError(f"incoming direction {bad[0]} is zero or not finite")
    return arr / norm[:, None]


def _check_parameter(rule: str, theta: float) -> float:
    try:
        heading_interval(float(theta), float(theta))
    except InvalidBoundarySet as exc:
        raise InvalidBoundarySet(f"{rule} rule: {exc}") from None
    except (TypeError, ValueError):
        raise InputError(f"{rule} rule: heading {theta!r} is not a number") from None
    return float(theta)


def _check_epsilon(rule: str, epsilon: float) -> float:
    try:
        value = float(epsilon)
    except (TypeError, ValueError):
        raise InputError(f"{rule} rule: epsilon {epsilon!r} is not a number") from None
    if not (math.isfinite(value) and 0 <= value < math.pi):
        raise InputError(f"{rule} rule: epsilon {epsilon!r} must lie in [0, π)")
    return value


# ---------------------------------------------------------------------- geometry of a contact
def edge_frames(env: Environment, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents (along the directed edges) and unit inward normals (their left), each (m, 2)."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1)
    d = env.edge_end[edges] - env.edge_start[edges]
    tangent = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
    return tangent, normal


def incoming_angles(env: Environment, edges: Sequence[int] | np.ndarray, incoming: np.ndarray) -> np.ndarray:
    """The paper's incoming angle α ∈ (0, π) (Def. 1) of each contact, radians.

    α is the direction *back along the incoming path* (−v for the travel direction v), measured CCW
    from the directed edge hit: α = atan2(−v·n, −v·e) with e the edge's unit tangent and n its inward
    normal. A direction arriving from the free side has v·n < 0, so α ∈ (0, π); grazing arrivals are
    clipped into [HEADING_MARGIN, π − HEADING_MARGIN].

    Raises :class:`InputError` for an unknown edge, a zero direction, or a direction that clearly
    leaves the edge instead of arriving at it (v·n > 1e-9).
    """
    edges_arr = check_edges(env, edges)
    v = _check_directions(incoming, len(edges_arr))
    tangent, normal = edge_frames(env, edges_arr)
    return _alpha(edges_arr, v, tangent, normal)


def _alpha(edges: np.ndarray, v: np.ndarray, tangent: np.ndarray, normal: np.ndarray) -> np.ndarray:
    vn = np.einsum("ij,ij->i", v, normal)
    leaving = np.flatnonzero(vn > 1e-9)
    if len(leaving):
        k = int(leaving[0])
        raise InputError(
            f"incoming direction ({v[k, 0]:g}, {v[k, 1]:g}) leaves edge e{edges[k]} instead of arriving at it"
        )
    alpha = np.arctan2(-vn, -np.einsum("ij,ij->i", v, tangent))
    return np.clip(alpha, HEADING_MARGIN, math.pi - HEADING_MARGIN)


def sample_headings(
    lo: np.ndarray, hi: np.ndarray, rng: np.random.Generator | None, sampling: Sampling | str = "uniform"
) -> np.ndarray:
    """Draw one heading in each [lo[k], hi[k]] (see :data:`Sampling`); ``rng`` may be None for ``lo``/``hi``/``mid``
    and for degenerate sets (lo == hi everywhere)."""
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    if sampling == "lo":
        return lo.copy()
    if sampling == "hi":
        return hi.copy()
    if sampling == "mid":
        return 0.5 * (lo + hi)
    if sampling not in ("uniform", "endpoints"):
        raise InputError(f"unknown sampling {sampling!r}: use {', '.join(SAMPLINGS)}")
    if rng is None:
        if np.array_equal(lo, hi):
            return lo.copy()
        raise InputError(f"{sampling} sampling of a non-deterministic rule needs an rng")
    if sampling == "uniform":
        return np.minimum(lo + rng.random(lo.shape) * (hi - lo), hi)
    return np.where(rng.random(lo.shape) < 0.5, lo, hi)


# ---------------------------------------------------------------------- the protocol
@runtime_checkable
class BounceRule(Protocol):
    """What every bounce rule offers; all arrays have one entry per contact.

    ``edges`` are the ids of the edges hit and ``incoming`` the (m, 2) travel directions on arrival
    (any length; unit vectors are fine). Headings are radians in (0, π), CCW from the edge hit.
    """

    @property
    def epsilon(self) -> float:
        """The rule's angular uncertainty, in radians (read-only: the rules are frozen dataclasses)."""
        ...

    def nominal(self, env: Environment, edges: Sequence[int] | np.ndarray, incoming: np.ndarray) -> np.ndarray:
        """The deterministic heading b of each contact."""
        ...

    def bounds(self, env: Environment, edges: Sequence[int] | np.ndarray,
               incoming: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The non-deterministic set of each contact: arrays lo ≤ hi inside (0, π)."""
        ...

    def headings(self, env: Environment, edges: Sequence[int] | np.ndarray, incoming: np.ndarray,
                 rng: np.random.Generator | None = None, *, sampling: Sampling | str = "uniform") -> np.ndarray:
        """A heading executed at each contact, drawn from :meth:`bounds` by ``sampling``."""
        ...

    def interval(self, env: Environment, edge: int, incoming: Sequence[float]) -> Interval:
        """The non-deterministic set of one contact as an :class:`Interval`."""
        ...


class _Rule:
    """Shared implementation: subclasses define ``_nominal(alpha, tangent, normal, v)`` and ``spec``."""

    __slots__ = ()
    epsilon: float
    kind: ClassVar[str]

    def _nominal(self, alpha: np.ndarray, tangent: np.ndarray, normal: np.ndarray, v: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def nominal(self, env: Environment, edges: Sequence[int] | np.ndarray, incoming: np.ndarray) -> np.ndarray:
        edges_arr = check_edges(env, edges)
        v = _check_directions(incoming, len(edges_arr))
        tangent, normal = edge_frames(env, edges_arr)
        b = self._nominal(_alpha(edges_arr, v, tangent, normal), tangent, normal, v)
        return np.clip(b, HEADING_MARGIN, math.pi - HEADING_MARGIN)

    def bounds(self, env: Environment, edges: Sequence[int] | np.ndarray,
               incoming: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        b = self.nominal(env, edges, incoming)
        if self.epsilon == 0:
            return b, b.copy()
        return (np.maximum(b - self.epsilon, HEADING_MARGIN), np.minimum(b + self.epsilon, math.pi - HEADING_MARGIN))

    def headings(self, env: Environment, edges: Sequence[int] | np.ndarray, incoming: np.ndarray,
                 rng: np.random.Generator | None = None, *, sampling: Sampling | str = "uniform") -> np.ndarray:
        lo, hi = self.bounds(env, edges, incoming)
        return sample_headings(lo, hi, rng, sampling)

    __call__ = headings

    def interval(self, env: Environment, edge: int, incoming: Sequence[float]) -> Interval:
        lo, hi = self.bounds(env, [edge], np.asarray(incoming, dtype=float).reshape(1, 2))
        return Interval(float(lo[0]), float(hi[0]))

    @property
    def is_deterministic(self) -> bool:
        return self.epsilon == 0

    def __str__(self) -> str:
        text = self.spec  # type: ignore[attr-defined]
        return text if self.epsilon == 0 else f"{text}±{self.epsilon:g}"


@dataclass(frozen=True, slots=True)
class Specular(_Rule):
    """Mirror reflection, b = π − α (paper §3); non-deterministic with ``epsilon`` > 0."""

    epsilon: float = 0.0
    kind: ClassVar[str] = "specular"

    def __post_init__(self) -> None:
        object.__setattr__(self, "epsilon", _check_epsilon("specular", self.epsilon))

    def _nominal(self, alpha, tangent, normal, v):
        return math.pi - alpha

    @property
    def spec(self) -> str:
        return "specular"


@dataclass(frozen=True, slots=True)
class Fixed(_Rule):
    """The fixed rule b = θ_f, whatever the incoming angle (paper Fig. 2, first row)."""

    theta: float
    epsilon: float = 0.0
    kind: ClassVar[str] = "fixed"

    def __post_init__(self) -> None:
        object.__setattr__(self, "theta", _check_parameter("fixed", self.theta))
        object.__setattr__(self, "epsilon", _check_epsilon("fixed", self.epsilon))

    def _nominal(self, alpha, tangent, normal, v):
        return np.full(alpha.shape, self.theta)

    def bounds(self, env, edges, incoming):  # exact ends of the interval (no round trip through mid ± ε)
        b = self.nominal(env, edges, incoming)
        if self.epsilon == 0:
            return b, b.copy()
        lo = max(self.theta - self.epsilon, HEADING_MARGIN)
        hi = min(self.theta + self.epsilon, math.pi - HEADING_MARGIN)
        return np.full(b.shape, lo), np.full(b.shape, hi)

    @property
    def spec(self) -> str:
        return f"fixed:{self.theta!r}"


@dataclass(frozen=True, slots=True)
class FixedInterval(_Rule):
    """Any heading of [lo, hi] ⊂ (0, π), whatever the incoming angle: the non-deterministic fixed rule
    as a plan states it (an action interval), with its ends kept exactly (sampled ``lo``/``hi`` are
    these floats, not a midpoint ± half-width round trip)."""

    lo: float
    hi: float
    kind: ClassVar[str] = "interval"

    def __post_init__(self) -> None:
        try:
            heading_interval(float(self.lo), float(self.hi))
        except InvalidBoundarySet as exc:
            raise InvalidBoundarySet(f"fixed rule: {exc}") from None
        except (TypeError, ValueError):
            raise InputError(f"fixed rule: interval [{self.lo!r}, {self.hi!r}] is not numeric") from None
        object.__setattr__(self, "lo", float(self.lo))
        object.__setattr__(self, "hi", float(self.hi))

    @classmethod
    def of(cls, interval: Interval) -> FixedInterval:
        """The rule of a (non-empty) :class:`Interval`."""
        if interval.is_empty:
            raise InvalidBoundarySet("fixed rule: the heading interval is empty")
        return cls(interval.lo, interval.hi)

    @property
    def epsilon(self) -> float:  # type: ignore[override]
        """Half the width (0 for a single heading)."""
        return (self.hi - self.lo) / 2

    def _nominal(self, alpha, tangent, normal, v):
        return np.full(alpha.shape, 0.5 * (self.lo + self.hi))

    def bounds(self, env, edges, incoming):
        b = self.nominal(env, edges, incoming)
        return np.full(b.shape, self.lo), np.full(b.shape, self.hi)

    @property
    def spec(self) -> str:
        return f"interval:{self.lo!r}:{self.hi!r}"

    def __str__(self) -> str:
        return self.spec


@dataclass(frozen=True, slots=True)
class MonotoneFixed(_Rule):
    """θ_m or π − θ_m, whichever keeps travel monotone along ``axis`` (paper Fig. 2, second row).

    See the module docstring for the exact choice and its tie-breaking.
    """

    theta: float
    epsilon: float = 0.0
    axis: tuple[float, float] = (1.0, 0.0)
    kind: ClassVar[str] = "monotone"

    def __post_init__(self) -> None:
        object.__setattr__(self, "theta", _check_parameter("monotone", self.theta))
        object.__setattr__(self, "epsilon", _check_epsilon("monotone", self.epsilon))
        try:
            ax, ay = (float(c) for c in self.axis)
        except (TypeError, ValueError):
            raise InputError(f"monotone rule: axis {self.axis!r} is not a vector (x, y)") from None
        norm = math.hypot(ax, ay)
        if not (math.isfinite(norm) and norm > 0):
            raise InputError(f"monotone rule: axis {self.axis!r} is zero or not finite")
        object.__setattr__(self, "axis", (ax / norm, ay / norm))

    def _nominal(self, alpha, tangent, normal, v):
        ax, ay = self.axis
        sense = np.where(v[:, 0] * ax + v[:, 1] * ay >= 0, 1.0, -1.0)
        # the two choices' components along the axis differ by 2 cos θ_m (e·axis)
        gain = sense * math.cos(self.theta) * (tangent[:, 0] * ax + tangent[:, 1] * ay)
        return np.where(gain >= 0, self.theta, math.pi - self.theta)

    @property
    def spec(self) -> str:
        return f"monotone:{self.theta!r}"


@dataclass(frozen=True, slots=True)
class Relative(_Rule):
    """Rotate clockwise through θ_r until pointing into the free space (paper Fig. 2, third row).

    ``reference="back"`` starts the rotation from α (the paper's b = α − θ_r), ``"travel"`` from the
    direction of travel α + π; see the module docstring.
    """

    theta: float
    epsilon: float = 0.0
    reference: Literal["back", "travel"] = "back"
    kind: ClassVar[str] = "relative"

    def __post_init__(self) -> None:
        object.__setattr__(self, "theta", _check_parameter("relative", self.theta))
        object.__setattr__(self, "epsilon", _check_epsilon("relative", self.epsilon))
        if self.reference not in ("back", "travel"):
            raise InputError(f"relative rule: reference {self.reference!r} must be 'back' or 'travel'")

    def _nominal(self, alpha, tangent, normal, v):
        start = alpha if self.reference == "back" else alpha + math.pi
        return rotate_clockwise_into_free(start, self.theta)

    @property
    def spec(self) -> str:
        return f"relative:{self.theta!r}" + ("" if self.reference == "back" else ":travel")


def rotate_clockwise_into_free(start: np.ndarray, theta: float) -> np.ndarray:
    """(start − k θ) mod 2π for the least k ≥ 1 landing in the open interval (0, π), vectorised.

    With r = (start − θ) mod 2π: if 0 < r < π, k = 1. Otherwise r ∈ [π, 2π) (or r = 0, the wall,
    taken as 2π) and j = ⌊(r − π)/θ⌋ + 1 more rotations give r − jθ ∈ [π − θ, π) ⊂ (0, π): the first
    value below π, which cannot be ≤ 0 because θ < π.

    >>> rotate_clockwise_into_free(np.array([0.5, 2.0]), 1.0).round(6).tolist()   # −0.5 ≡ 5.78, 4.78, 3.78, 2.78
    [2.783185, 1.0]
    """
    start = np.asarray(start, dtype=float)
    r = np.mod(start - theta, 2 * math.pi)
    free = (r > 0) & (r < math.pi)
    r_wall = np.where(r == 0, 2 * math.pi, r)
    j = np.floor((r_wall - math.pi) / theta) + 1
    out = np.where(free, r, r_wall - j * theta)
    return np.clip(out, HEADING_MARGIN, math.pi - HEADING_MARGIN)


# ---------------------------------------------------------------------- parsing (CLI)
_RULE_SPEC = re.compile(r"^\s*(specular|fixed|relative|monotone)(?::([^:]+))?(?::(travel|back))?\s*$", re.IGNORECASE)
_RULE_HELP = "use specular, fixed:THETA, relative:THETA[:travel] or monotone:THETA (THETA in radians, e.g. 1.2 or pi/3)"


def _parse_angle(text: str, spec: str) -> float:
    """A number in radians, or a multiple/fraction of pi: ``1.2``, ``pi/3``, ``2pi/5``, ``0.25pi``."""
    t = text.strip().lower().replace(" ", "")
    match = re.fullmatch(r"([0-9.]*)\*?(pi|π)(?:/([0-9.]+))?", t)
    try:
        if match:
            factor = float(match.group(1)) if match.group(1) else 1.0
            divisor = float(match.group(3)) if match.group(3) else 1.0
            return factor * math.pi / divisor
        return float(t)
    except (ValueError, ZeroDivisionError):
        raise InputError(f"bounce rule {spec!r}: {text!r} is not an angle in radians") from None


def parse_rule(spec: str, *, epsilon: float = 0.0) -> BounceRule:
    """A rule from its command-line spelling: ``specular``, ``fixed:THETA``, ``relative:THETA[:travel]``,
    ``monotone:THETA`` (radians; ``pi/3`` style allowed).

    >>> parse_rule("fixed:pi/4")
    Fixed(theta=0.7853981633974483, epsilon=0.0)
    >>> parse_rule("bouncy")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: unknown bounce rule 'bouncy': use specular, fixed:THETA, relative:THETA[:travel] or monotone:THETA (THETA in radians, e.g. 1.2 or pi/3)
    """
    match = _RULE_SPEC.match(spec) if isinstance(spec, str) else None
    if not match:
        raise InputError(f"unknown bounce rule {spec!r}: {_RULE_HELP}")
    name, angle, reference = match.group(1).lower(), match.group(2), match.group(3)
    if name == "specular":
        if angle is not None or reference is not None:
            raise InputError(f"bounce rule {spec!r}: specular takes no angle")
        return Specular(epsilon)
    if angle is None:
        raise InputError(f"bounce rule {spec!r}: {name} needs an angle, e.g. {name}:1.2")
    theta = _parse_angle(angle, spec)
    if reference is not None and name != "relative":
        raise InputError(f"bounce rule {spec!r}: only the relative rule takes :{reference}")
    if name == "fixed":
        return Fixed(theta, epsilon)
    if name == "monotone":
        return MonotoneFixed(theta, epsilon)
    # the pattern admits only back|travel (any case), so the lowered text is one of the two literals
    return Relative(theta, epsilon, reference=(reference or "back").lower())  # type: ignore[arg-type]
