"""The result protocol shared by every planner and robot model.

Every answer solverplan gives — a plan, a Pareto front, a patrol, a funnel, a localisation strategy, a limit
cycle, a constant controller — is a frozen dataclass with the same five things:

- ``status``: a :class:`Status`, in one of three groups (:class:`StatusGroup`): *answered* (there is an
  answer to use), *proven infeasible* (there is provably none, within the stated scope: an answer too, exit
  code 0) and *search incomplete* (a bounded or heuristic search found nothing: not a proof);
- ``optimality``: an :class:`Optimality` — how the answer's optimality (or the infeasibility) was
  established (:class:`Method`), whether it is ``proved``, the ``bound`` any strategy of the ``scope``
  could reach, the ``gap`` between the answer and that bound, and the ``limits`` that were hit (a hit
  limit always makes ``proved`` false);
- ``stats``: a :class:`Stats` record (times, counts; recorded, never asserted);
- ``environment``: the :class:`EnvironmentRecord` of the environment the answer was made in;
- ``to_json()`` and ``to_text()``: the only places the answer becomes a dict or a table.

Stages of every strategy are one type, :class:`Stage`: a heading interval executed from a set of possible
segments, with what the strategy knows about it (per-source moves, exact positions, an exact affine map).

>>> Status.FOUND.group, Status.NOT_FOUND.group, Status.INFEASIBLE.proven_infeasible
(<StatusGroup.ANSWERED: 'answered'>, <StatusGroup.INCOMPLETE: 'incomplete'>, True)
>>> opt = Optimality("search-exhausted", True, 0.5, scope="plans over admissible intervals")
>>> opt.method, opt.to_json()["gap"]
(<Method.SEARCH_EXHAUSTED: 'search-exhausted'>, None)
>>> Optimality(Method.SEARCH_EXHAUSTED, True, None, limits=("max_beliefs=20000",))
Traceback (most recent call last):
...
ValueError: an optimality claim cannot be proved when a limit was hit (max_beliefs=20000)
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field, replace
from enum import StrEnum
from fractions import Fraction
from typing import Any, Callable, ClassVar, Mapping, Protocol, TypeVar, dataclass_transform, runtime_checkable

from solverplan.environment import BoundaryPiece, Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.exact import ExactPoint, format_number, to_fraction
from solverplan.limits import quote
from solverplan.interval import Interval

__all__ = [
    "Status",
    "StatusGroup",
    "ANSWERED",
    "PROVEN_INFEASIBLE",
    "INCOMPLETE",
    "Method",
    "Optimality",
    "Stats",
    "EnvironmentRecord",
    "AffineStep",
    "Stage",
    "Result",
    "Answer",
    "Construction",
    "answer_dataclass",
    "answer_class",
    "answer_kinds",
    "ANSWER_KEY_ORDER",
    "protocol_json",
    "piece_json",
    "Reader",
]


# ---------------------------------------------------------------------- statuses
class StatusGroup(StrEnum):
    """The three kinds of answer: answered, proven infeasible, or a search that ended without either.

    cvxpy's ``SOLUTION_PRESENT`` / ``INFEASIBLE`` split, with a third kind for bounded searches that prove nothing
    when they fail. Every :class:`Status` belongs to one group (:attr:`Status.group`).

    Attributes
    ----------
    ANSWERED
        ``"answered"``: there is an answer to execute.
    PROVEN_INFEASIBLE
        ``"proven-infeasible"``: provably none exists within the optimality scope (an answer too, exit code 0).
    INCOMPLETE
        ``"incomplete"``: a bounded or heuristic search found nothing; not a proof.

    Examples
    --------
    >>> import solverplan as sp
    >>> [group.value for group in sp.StatusGroup]
    ['answered', 'proven-infeasible', 'incomplete']
    >>> sp.Status.NOT_CONTRACTING.group
    <StatusGroup.PROVEN_INFEASIBLE: 'proven-infeasible'>
    """

    ANSWERED = "answered"  #: there is an answer to execute
    PROVEN_INFEASIBLE = "proven-infeasible"  #: provably none exists within the optimality scope
    INCOMPLETE = "incomplete"  #: a bounded or heuristic search found nothing: not a proof


class Status(StrEnum):
    """What an answer is; the same enum on every result. :attr:`group` says which kind it is.

    A string enum: ``Status("found") is Status.FOUND`` and a status compares equal to its JSON value.

    Attributes
    ----------
    FOUND
        ``"found"``: a strategy (plan, cycle, funnel, controller) that is sound.
    INFEASIBLE
        ``"infeasible"``: proven, no strategy of the scope exists.
    NOT_CONTRACTING
        ``"not-contracting"``: proven, the best (or the given) cycle exists but does not contract.
    EDGE_ORDER_BROKEN
        ``"edge-order-broken"``: proven, the fixed point's orbit leaves the required edge order.
    NOT_REALISED
        ``"not-realised"``: proven, the heading does not carry the orbit along the required edges.
    VERTEX
        ``"vertex"``: proven, the orbit runs into a vertex (outside the model).
    NOT_FOUND
        ``"not-found"``: a bounded search found nothing (its limits are in ``optimality.limits``).
    group
        The :class:`StatusGroup` of the status; ``answered``, ``proven_infeasible`` and ``incomplete`` test it.

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("square"), "e0", "e2")
    >>> plan.status, plan.status == "found", plan.status.answered
    (<Status.FOUND: 'found'>, True, True)
    >>> sp.Status("not-found").group
    <StatusGroup.INCOMPLETE: 'incomplete'>
    """

    FOUND = "found"  #: a strategy (plan, cycle, funnel, controller) that is sound
    INFEASIBLE = "infeasible"  #: proven: no strategy of the scope exists
    NOT_CONTRACTING = "not-contracting"  #: proven: the best (or the given) cycle exists but does not contract
    EDGE_ORDER_BROKEN = "edge-order-broken"  #: proven: the fixed point's orbit leaves the required edge order
    NOT_REALISED = "not-realised"  #: proven: the heading does not carry the orbit along the required edges
    VERTEX = "vertex"  #: proven: the orbit runs into a vertex (outside the model)
    NOT_FOUND = "not-found"  #: a bounded search found nothing (its limits are in ``optimality.limits``)

    @property
    def group(self) -> StatusGroup:
        if self in ANSWERED:
            return StatusGroup.ANSWERED
        if self in PROVEN_INFEASIBLE:
            return StatusGroup.PROVEN_INFEASIBLE
        return StatusGroup.INCOMPLETE

    @property
    def answered(self) -> bool:
        """True when there is a strategy to execute."""
        return self in ANSWERED

    @property
    def proven_infeasible(self) -> bool:
        """True when it is proved that no strategy of the scope exists."""
        return self in PROVEN_INFEASIBLE

    @property
    def incomplete(self) -> bool:
        """True when a bounded search found nothing (nothing is proved)."""
        return self in INCOMPLETE


ANSWERED: frozenset[Status] = frozenset({Status.FOUND})
PROVEN_INFEASIBLE: frozenset[Status] = frozenset(
    {Status.INFEASIBLE, Status.NOT_CONTRACTING, Status.EDGE_ORDER_BROKEN, Status.NOT_REALISED, Status.VERTEX})
INCOMPLETE: frozenset[Status] = frozenset({Status.NOT_FOUND})


# ---------------------------------------------------------------------- optimality
class Method(StrEnum):
    """How an optimality (or infeasibility) claim was established.

    The ``method`` of every :class:`Optimality`; a string enum, so its JSON value reads back with ``Method(value)``.

    Attributes
    ----------
    SEARCH_EXHAUSTED
        ``"search-exhausted"``: an exhaustive search (BFS, label setting, DP) over a finite graph.
    LP_DUALITY
        ``"lp-duality"``: an LP solved to optimality; its duality gap is ``gap``.
    MILP
        ``"milp"``: a MILP solved to optimality; the solver's absolute gap is ``gap``.
    BISECTION
        ``"bisection"``: bisection on a monotone feasibility question; the bracket width is ``gap``.
    EXACT_CHECK
        ``"exact-check"``: the object itself was verified in exact arithmetic (no optimisation).
    SYMMETRY
        ``"symmetry"``: an exact symmetry argument (localisation impossible).
    HEURISTIC
        ``"heuristic"``: a bounded search; it proves what it returns, never optimality or absence.
    NONE
        ``"none"``: nothing is claimed.

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("square"), "e0", "e2")
    >>> plan.optimality.method
    <Method.SEARCH_EXHAUSTED: 'search-exhausted'>
    >>> sp.Method("lp-duality") is sp.Method.LP_DUALITY
    True
    """

    SEARCH_EXHAUSTED = "search-exhausted"  #: an exhaustive search (BFS, label setting, DP) over a finite graph
    LP_DUALITY = "lp-duality"  #: an LP solved to optimality; its duality gap is ``gap``
    MILP = "milp"  #: a MILP solved to optimality; the solver's absolute gap is ``gap``
    BISECTION = "bisection"  #: bisection on a monotone feasibility question; the bracket width is ``gap``
    EXACT_CHECK = "exact-check"  #: the object itself was verified in exact arithmetic (no optimisation)
    SYMMETRY = "symmetry"  #: an exact symmetry argument (localisation impossible)
    HEURISTIC = "heuristic"  #: a bounded search: it proves what it returns, never optimality or absence
    NONE = "none"  #: nothing is claimed


def _method(value: str) -> Method:
    """The :class:`Method` named ``value``; raises :class:`ValueError` listing the known names."""
    try:
        return Method(value)
    except ValueError:
        raise ValueError(f"unknown optimality method {value!r}: use {', '.join(m.value for m in Method)}") from None


@dataclass(frozen=True, slots=True)
class Optimality:
    """How optimality was established, and how far it goes.

    Attributes
    ----------
    method
        A :class:`Method` (strings are accepted and converted).
    proved
        The claim holds for every strategy of ``scope``. Never true when a limit was hit.
    bound
        The best value any strategy of ``scope`` could reach, in the objective's units (bounces, radians of
        width, contraction); equal to the answer's value when proved; ``None`` when there is none.
    scope
        The class of strategies the claim is about, in words (e.g. "plans whose intervals lie in the
        admissible intervals of the safe BVG").
    gap
        ``|value − bound|`` for the answer's value and ``bound``, **both over** ``scope``: 0 (up to the
        solver's tolerance) when proved, ``None`` when not measured. Bounds over wider classes are reported
        elsewhere (never as this gap).
    algorithm
        Which search or solver ran, in words.
    limits
        The caps of a bounded search that were hit (``"max_beliefs=20000"``): the search is incomplete.

    Examples
    --------
    >>> import solverplan as sp
    >>> opt = sp.find_plan(sp.load_environment("square"), "e0", "e2").optimality
    >>> opt.method.value, opt.proved, opt.bound, opt.gap       # 2 bounces, and no plan has fewer
    ('search-exhausted', True, 2.0, 0.0)
    >>> sp.Optimality("heuristic", False, None, limits=("max_beliefs=20000",)).to_json()
    {'method': 'heuristic', 'proved': False, 'bound': None, 'scope': '', 'gap': None, 'limits': ['max_beliefs=20000']}
    """

    method: Method
    proved: bool
    bound: float | None
    scope: str = ""
    gap: float | None = None
    algorithm: str = ""
    limits: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.method, Method):
            object.__setattr__(self, "method", _method(self.method))
        object.__setattr__(self, "limits", tuple(self.limits))
        if self.proved and self.limits:
            raise ValueError(f"an optimality claim cannot be proved when a limit was hit ({', '.join(self.limits)})")

    def to_json(self) -> dict:
        out: dict[str, Any] = {"method": self.method.value, "proved": self.proved, "bound": _finite(self.bound),
                               "scope": self.scope, "gap": _finite(self.gap)}
        if self.algorithm:
            out["algorithm"] = self.algorithm
        if self.limits:
            out["limits"] = list(self.limits)
        return out

    def to_text(self) -> str:
        """One line: ``search-exhausted (BFS), proved, bound 3; scope …``."""
        algorithm = f" ({self.algorithm})" if self.algorithm else ""
        proof = "proved" if self.proved else "not proved"
        bound = "" if self.bound is None else f", bound {self.bound:.10g}"
        gap = "" if self.gap is None else f", gap {self.gap:.3g}"
        limits = f", limits hit: {', '.join(self.limits)}" if self.limits else ""
        scope = f"; {self.scope}" if self.scope else ""
        return f"{self.method.value}{algorithm}, {proof}{bound}{gap}{limits}{scope}"

    @classmethod
    def from_json(cls, data: object, where: str = "optimality") -> Optimality:
        """Read :meth:`to_json`'s output back; raises :class:`ValueError` naming ``where`` on bad input."""
        if not isinstance(data, dict):
            raise ValueError(f"{where}: expected an object with method, proved, bound")
        method, proved = data.get("method"), data.get("proved")
        if not isinstance(method, str) or not isinstance(proved, bool):
            raise ValueError(f"{where}: method must be a string and proved a boolean")
        numbers = {}
        for key in ("bound", "gap"):
            value = data.get(key)
            if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
                raise ValueError(f"{where}.{key}: expected a number or null, got {value!r}")
            numbers[key] = None if value is None else float(value)
        limits = data.get("limits", [])
        if not isinstance(limits, list) or not all(isinstance(x, str) for x in limits):
            raise ValueError(f"{where}.limits: expected a list of strings")
        scope, algorithm = data.get("scope", ""), data.get("algorithm", "")
        if not isinstance(scope, str) or not isinstance(algorithm, str):
            raise ValueError(f"{where}: scope and algorithm must be strings")
        try:
            return cls(_method(method), proved and not limits, numbers["bound"], scope=scope, gap=numbers["gap"],
                       algorithm=algorithm, limits=tuple(limits))
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None


# ---------------------------------------------------------------------- stats
@dataclass(frozen=True)
class Stats:
    """What a solve cost (recorded for benchmarks and curious users, never asserted).

    Attributes
    ----------
    seconds_setup, seconds_search
        Wall time (seconds) building the search structures, and searching; ``None`` when not measured.
    expanded
        States (beliefs, position sets, product nodes) expanded.
    counts
        Further named numbers of the engine that ran (flattened into the JSON).

    Examples
    --------
    >>> import solverplan as sp
    >>> stats = sp.Stats(seconds_search=0.5, expanded=12).with_(beliefs=3)
    >>> stats.counts, stats.to_json()
    ({'beliefs': 3}, {'seconds_search': 0.5, 'expanded': 12, 'beliefs': 3})
    >>> sp.find_plan(sp.load_environment("square"), "e0", "e2").stats.counts["beliefs"]
    3
    """

    seconds_setup: float | None = None
    seconds_search: float | None = None
    expanded: int | None = None
    counts: Mapping[str, Any] = field(default_factory=dict)

    def with_(self, **changes: Any) -> Stats:
        """A copy with fields changed; unknown names go into ``counts``."""
        known = {k: v for k, v in changes.items() if k in ("seconds_setup", "seconds_search", "expanded")}
        extra = {k: v for k, v in changes.items() if k not in known}
        return replace(self, **known, counts={**self.counts, **extra})

    def to_json(self) -> dict:
        out: dict[str, Any] = {k: v for k, v in (("seconds_setup", self.seconds_setup),
                                                  ("seconds_search", self.seconds_search),
                                                  ("expanded", self.expanded)) if v is not None}
        out.update(self.counts)
        return out

    def __bool__(self) -> bool:
        return bool(self.to_json())


# ---------------------------------------------------------------------- environment
@dataclass(frozen=True, slots=True)
class EnvironmentRecord:
    """Identifies the environment an answer was made in: its name and the SHA-256 of its exact normalised
    rings (so it does not depend on the name or the file format); ``n_segments``: the size of its partition
    P′ when the answer refers to segment ids."""

    name: str
    sha256: str
    n_segments: int | None = None

    @classmethod
    def of(cls, env: Environment, n_segments: int | None = None) -> EnvironmentRecord:
        rings = [[[format_number(x), format_number(y)] for x, y in ring] for ring in env.rings]
        digest = hashlib.sha256(json.dumps(rings, separators=(",", ":")).encode()).hexdigest()
        return cls(env.name, digest, n_segments)

    def matches(self, env: Environment) -> bool:
        """Is ``env`` (exactly) the environment recorded?"""
        return self.sha256 == EnvironmentRecord.of(env).sha256

    def to_json(self) -> dict:
        out: dict[str, Any] = {"name": self.name, "sha256": self.sha256}
        if self.n_segments is not None:
            out["n_segments"] = self.n_segments
        return out

    @classmethod
    def from_json(cls, data: object, where: str = "environment") -> EnvironmentRecord | None:
        """``None`` for a missing record (``{}`` or null); raises :class:`ValueError` on a malformed one."""
        if data is None or data == {}:
            return None
        if not isinstance(data, dict) or not isinstance(data.get("sha256"), str):
            raise ValueError(f"{where}: expected an object with name and sha256")
        n = data.get("n_segments")
        if n is not None and (isinstance(n, bool) or not isinstance(n, int)):
            raise ValueError(f"{where}.n_segments: expected an integer, got {n!r}")
        return cls(str(data.get("name", "")), data["sha256"], n)


def protocol_json(optimality: Optimality, stats: Stats | None = None,
                  environment: EnvironmentRecord | None = None) -> dict:
    """The protocol's closing fields of an answer, in the contract's order: ``optimality``, then ``stats`` (when
    there are any) and ``environment`` (when known)."""
    out: dict = {"optimality": optimality.to_json()}
    if stats:
        out["stats"] = stats.to_json()
    if environment is not None:
        out["environment"] = environment.to_json()
    return out


# ---------------------------------------------------------------------- stages
def piece_json(piece: BoundaryPiece) -> dict:
    """A boundary piece as JSON: edge, float t0/t1 and their exact text."""
    return {"edge": piece.edge, "t0": float(piece.t0), "t1": float(piece.t1),
            "t0_exact": format_number(piece.t0), "t1_exact": format_number(piece.t1)}


@dataclass(frozen=True, slots=True)
class AffineStep:
    """The exact motion of one bounce under a nominal heading: leave ``from_edge`` along the exact direction
    ``direction`` (a rational world vector whose heading is ``heading``, radians), land on ``to_edge``; the
    landing parameter is t ↦ ``alpha`` t + ``beta`` (boundary parameters t ∈ [0, 1], rational).
    ``contraction``: the worst-case contraction coefficient C over the stage's interval (arc length, Def. 11;
    for a single heading, C of that heading); ``transition`` (``left``, ``right``, ``parallel``) and ``phi``
    (radians) when the stage is an arc of the safe BVG."""

    from_edge: int
    to_edge: int
    heading: float
    direction: ExactPoint
    alpha: Fraction
    beta: Fraction
    contraction: float
    transition: str = ""
    phi: float | None = None

    def to_json(self) -> dict:
        out: dict[str, Any] = {"from_edge": self.from_edge, "to_edge": self.to_edge}
        if self.transition:
            out["transition"] = self.transition
        if self.phi is not None:
            out["phi"] = self.phi
        out["contraction"] = self.contraction
        out["nominal"] = self.heading
        out["direction"] = [format_number(self.direction[0]), format_number(self.direction[1])]
        out["map"] = {"alpha": format_number(self.alpha), "beta": format_number(self.beta)}
        return out

    @classmethod
    def from_json(cls, data: object, where: str = "stage") -> AffineStep:
        """Read the affine fields of a stage's JSON back (:meth:`to_json`)."""
        r = Reader(data, where)
        m = r.sub("map")
        direction = r.array("direction")
        return cls(r.integer("from_edge"), r.integer("to_edge"), r.number("nominal"),
                   (r.at("direction", direction).exact(0), r.at("direction", direction).exact(1)),
                   m.exact("alpha"), m.exact("beta"), r.number("contraction"), transition=r.string("transition", ""),
                   phi=r.number("phi") if r.has("phi") else None)


@dataclass(frozen=True, slots=True)
class Stage:
    """One bounce of a strategy: a heading interval executed from some segments of P′, landing on others.

    Attributes
    ----------
    from_segments
        The segments of P′ the robot may be on before the bounce.
    to_segments
        The segments it may land on (sorted).
    interval
        The heading :class:`~solverplan.interval.Interval` (radians, CCW from the wall the robot is on, inside
        (0, π); a singleton for a constant heading).
    moves, positions, sources, cones, target_edges, affine, margins
        What the strategy knows besides, when it knows it (empty or ``None`` otherwise; below).

    Notes
    -----
    ``moves``
        For each possible source segment, the segment it lands on (belief plans). Where a plan's stage leaves
        from part of a segment only (a start set ending inside it), ``sources`` holds each move's exact source
        piece, aligned with ``moves``.
    ``positions``
        The exact pieces of boundary the robot may be on after the stage (funnels, localisation);
        ``sources``, ``cones`` and ``target_edges`` are the exact pieces before it, the exact world-frame
        cone (d_lo, d_hi) each was pushed through, and the edge each landed on.
    ``affine``
        The exact affine map of the stage's nominal heading (cycles and patrols), :class:`AffineStep`.
    ``margins``
        ``(lo, hi)``, radians: how far the interval's ends lie inside the exact safe sets of its moves (the smallest
        over the moves) — the margin the planner actually left (belief plans).

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("square"), "e0", "e2")     # edge 0 to edge 2 in two bounces
    >>> [(stage.from_segments, stage.to_segments) for stage in plan.stages]
    [((0,), (1,)), ((1,), (2,))]
    >>> stage = plan.stages[0]
    >>> stage.interval, round(stage.width, 6), stage.moves
    (Interval(lo=0.001, hi=0.7852981633974483), 0.784298, ((0, 1),))
    """

    from_segments: tuple[int, ...]
    to_segments: tuple[int, ...]
    interval: Interval
    moves: tuple[tuple[int, int], ...] = ()
    positions: tuple[BoundaryPiece, ...] = ()
    sources: tuple[BoundaryPiece, ...] = ()
    cones: tuple[tuple[ExactPoint, ExactPoint], ...] = ()
    target_edges: tuple[int, ...] = ()
    affine: AffineStep | None = None
    margins: tuple[float, float] | None = None

    @property
    def width(self) -> float:
        """The interval's width (radians)."""
        return self.interval.width

    @property
    def step(self) -> AffineStep:
        """``affine``, for stages that have one (cycles and patrols); :class:`ValueError` otherwise."""
        if self.affine is None:
            raise ValueError("this stage has no exact affine map (only cycle and patrol stages have one)")
        return self.affine

    @property
    def from_segment(self) -> int:
        """The source segment of a stage with one source (cycles and patrols)."""
        return self.from_segments[0]

    @property
    def to_segment(self) -> int:
        """The target segment of a stage with one target (cycles and patrols)."""
        return self.to_segments[0]

    def to_json(self) -> dict:
        out: dict[str, Any] = {
            "from_segments": list(self.from_segments),
            "to_segments": list(self.to_segments),
            "interval": [self.interval.lo, self.interval.hi],
            "width": self.interval.width,
        }
        if self.margins is not None:
            out["margins"] = [self.margins[0], self.margins[1]]
        if self.moves:
            out["moves"] = [[i, j] for i, j in self.moves]
            if self.sources and not self.cones:  # a plan stage leaving from parts of segments: the exact parts
                out["sources"] = [piece_json(p) for p in self.sources]
        if self.positions:
            out["positions"] = [piece_json(p) for p in self.positions]
        if self.cones:  # a position strategy's exact pieces and cones: enough to read it back and certify it
            out["sources"] = [piece_json(p) for p in self.sources]
            out["cones"] = [[[format_number(c) for c in d] for d in cone] for cone in self.cones]
            out["target_edges"] = list(self.target_edges)
        if self.affine is not None:
            out.update(self.affine.to_json())
        return out

    @classmethod
    def from_json(cls, data: object, where: str = "stage") -> Stage:
        """Read :meth:`to_json`'s output back; :class:`~solverplan.errors.MalformedFile` naming ``where`` if malformed."""
        r = Reader(data, where)
        lo, hi = r.numbers("interval", 2)
        margins = r.numbers("margins", 2) if r.has("margins") else None
        moves = tuple((int(i), int(j)) for i, j in r.int_pairs("moves")) if r.has("moves") else ()
        cones: tuple[tuple[ExactPoint, ExactPoint], ...] = ()
        if r.has("cones"):
            raw = r.array("cones")
            cones = tuple((r.at(f"cones[{k}]", c).exact_pair(0), r.at(f"cones[{k}]", c).exact_pair(1))
                          for k, c in enumerate(raw))
        affine = AffineStep.from_json(data, where) if r.has("map") else None
        return cls(tuple(r.ints("from_segments")), tuple(r.ints("to_segments")), Interval(lo, hi), moves=moves,
                   positions=r.pieces("positions") if r.has("positions") else (),
                   sources=r.pieces("sources") if r.has("sources") else (), cones=cones,
                   target_edges=tuple(r.ints("target_edges")) if r.has("target_edges") else (), affine=affine,
                   margins=None if margins is None else (margins[0], margins[1]))


# ---------------------------------------------------------------------- the protocol
@runtime_checkable
class Result(Protocol):
    """What every answer has (module docstring)."""

    @property
    def status(self) -> Status: ...

    @property
    def optimality(self) -> Optimality: ...

    @property
    def stats(self) -> Stats: ...

    @property
    def environment(self) -> EnvironmentRecord | None: ...

    def to_json(self) -> dict: ...

    def to_text(self, *, width: int = 100) -> str: ...


def _finite(x: float | None) -> float | None:
    """JSON has no infinities or NaN: those become null."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


# ---------------------------------------------------------------------- the answer base and its kinds
ANSWER_KEY_ORDER: tuple[str, ...] = ("kind", "status", "...", "optimality", "stats", "environment")
"""The one key order of every answer's JSON: ``kind`` (what the answer is, a key of :func:`answer_kinds`),
``status``, the kind's own fields in the order of docs/contract.md (``...``), then the protocol's closing fields
``optimality``, ``stats`` (when there are any) and ``environment`` (when known)."""

_KINDS: dict[str, type] = {}

_T = TypeVar("_T")


@dataclass_transform(frozen_default=True)
def answer_dataclass(kind: str, *, eq: bool = True, kw_only: bool = False) -> Callable[[type[_T]], type[_T]]:
    """Class decorator: make an answer class a frozen dataclass and register it under ``kind``.

    What every answer class is, said once: a ``@dataclass(frozen=True)`` (``eq`` and ``kw_only`` as in
    :func:`dataclasses.dataclass`) whose ``kind`` attribute is set to ``kind``, registered under it for
    :func:`answer_class`. One class per kind, one kind per class; the registry holds the kinds of the modules
    imported so far (``solverplan.answers`` imports every one). Type checkers see the dataclass through
    :func:`typing.dataclass_transform`.

    >>> @answer_dataclass("example-kind")
    ... class Example(Answer):
    ...     steps: int
    >>> Example(3), Example.kind, answer_class("example-kind") is Example
    (Example(steps=3), 'example-kind', True)
    >>> _ = _KINDS.pop("example-kind")
    """
    if not kind or kind != kind.strip():
        raise ValueError(f"answer kind {kind!r} is empty or has surrounding blanks")

    def make(cls: type[_T]) -> type[_T]:
        made = dataclass(frozen=True, eq=eq, kw_only=kw_only)(cls)
        if kind in _KINDS and _KINDS[kind] is not made:
            raise ValueError(f"answer kind {kind!r} is already taken by {_KINDS[kind].__name__}")
        made.kind = kind  # type: ignore[attr-defined]
        _KINDS[kind] = made
        return made
    return make


def answer_class(kind: str) -> type:
    """The class registered for ``kind``; :class:`KeyError` naming the known kinds otherwise."""
    try:
        return _KINDS[kind]
    except KeyError:
        raise KeyError(f"unknown answer kind {kind!r}: known kinds are {', '.join(sorted(_KINDS))}") from None


def answer_kinds() -> dict[str, type]:
    """Every kind registered so far and its class (import ``solverplan.answers`` for all of them)."""
    return dict(_KINDS)


class Answer:
    """The base of every answer: its ``kind`` and the one :meth:`to_json` (in :data:`ANSWER_KEY_ORDER`).

    A subclass is a (frozen) dataclass with ``status``, ``optimality``, ``stats`` and ``environment`` (fields or
    properties), registered with :func:`answer_dataclass`; it writes its own fields in :meth:`_fields` and reads its
    JSON back in :meth:`from_json` (``from_json(a.to_json(), env=...)`` gives an answer with the same JSON).
    Robot models are not classes here: the kinds are kinds of *answers*.

    Attributes
    ----------
    kind
        What the answer is (``"plan"``, ``"rooms"``, ``"pursuit"``, ...): the first key of its JSON.

    Examples
    --------
    >>> from solverplan.wallfollow.cut import cut_ordering
    >>> from solverplan.models import load
    >>> answer = cut_ordering(load("l_shape"))
    >>> isinstance(answer, Answer), list(answer.to_json())[:3], list(answer.to_json())[-3:]
    (True, ['kind', 'status', 'cut_ordering'], ['optimality', 'stats', 'environment'])
    """

    kind: ClassVar[str] = ""

    def _fields(self) -> dict:  # pragma: no cover - every kind writes its own
        """The kind's own fields, in the contract's order (between ``status`` and ``optimality``)."""
        raise NotImplementedError(f"{type(self).__name__} does not write its fields")

    def to_json(self) -> dict:
        """The answer as JSON, in :data:`ANSWER_KEY_ORDER`."""
        out: dict[str, Any] = {"kind": self.kind, "status": Status(getattr(self, "status")).value}
        out.update(self._fields())
        out.update(protocol_json(getattr(self, "optimality"), getattr(self, "stats", None),
                                 getattr(self, "environment", None)))
        return out

    @classmethod
    def from_json(cls, data: Mapping[str, Any], *, env: Environment | None = None) -> Answer:  # pragma: no cover
        """Read :meth:`to_json`'s output back (``env``: the environment, for kinds that refer to it)."""
        raise NotImplementedError(f"{cls.__name__} cannot be read back")

    @classmethod
    def _reader_in(cls, data: object, env: Environment | None,
                   what: str) -> tuple[Reader, Environment, EnvironmentRecord | None]:
        """How :meth:`from_json` of a kind that names the edges of its environment begins: a :class:`Reader` of
        ``data`` (messages start at the kind), ``env`` (required) and the answer's environment record, checked
        against ``env`` (:meth:`Reader.in_environment`; ``what`` names the answer in its messages)."""
        r = Reader(data, cls.kind)
        env, record = r.in_environment(env, what)
        return r, env, record


class Construction(Answer):
    """The base of an answer that is built, not searched for (a decomposition, a cut ordering, what a robot
    learned): there is always one, so its ``status`` is always found.

    Examples
    --------
    >>> from solverplan.wallfollow.cut import cut_ordering
    >>> from solverplan.models import load
    >>> answer = cut_ordering(load("l_shape"))
    >>> isinstance(answer, Construction), answer.status
    (True, <Status.FOUND: 'found'>)
    """

    @property
    def status(self) -> Status:
        """Found: a construction always has its answer."""
        return Status.FOUND


# ---------------------------------------------------------------------- reading answers back
def finite_number(value: object, where: str) -> float:
    """``value`` as a float when it is a finite JSON number (not a boolean); else :class:`MalformedFile` at ``where``.

    >>> finite_number(2, "plan.stages[0].interval[0]")
    2.0
    >>> finite_number(True, "pareto.points[0].min_width")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: pareto.points[0].min_width: expected a finite number, got True
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise MalformedFile(f"{where}: expected a finite number, got {quote(value)}")
    return float(value)


def index_list(value: object, where: str, what: str = "non-negative integers") -> list[int]:
    """``value`` when it is a JSON list of non-negative integers (ids: ``what`` says of what, for the message); else
    :class:`MalformedFile` at ``where``.

    >>> index_list([0, 3], "stages[0].from_segments")
    [0, 3]
    >>> index_list([0, -1], "stages[0].from_segments", "segment ids")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: stages[0].from_segments: expected a list of segment ids
    """
    if not isinstance(value, list) or not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in value):
        raise MalformedFile(f"{where}: expected a list of {what}")
    return list(value)


class Reader:
    """Typed access to one JSON object of an answer being read back: every getter checks the value's type and
    raises :class:`~solverplan.errors.MalformedFile` naming the place (``where.key``) and quoting the value.

    >>> r = Reader({"bounces": 2, "start": "e0", "t": "1/3"}, "plan")
    >>> r.integer("bounces"), r.string("start"), r.exact("t")
    (2, 'e0', Fraction(1, 3))
    >>> r.integer("start")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: plan.start: expected an integer, got 'e0'
    """

    _MISSING = object()

    def __init__(self, data: object, where: str) -> None:
        if not isinstance(data, (dict, list)):
            raise MalformedFile(f"{where}: expected a JSON object")
        self.data, self.where = data, where

    def at(self, key: str, value: object) -> Reader:
        """A reader of ``value``, a part of this object named ``key``."""
        return Reader(value, f"{self.where}.{key}")

    def has(self, key: str) -> bool:
        return isinstance(self.data, dict) and self.data.get(key) is not None

    def get(self, key: object, default: object = _MISSING) -> object:
        data = self.data
        if isinstance(data, dict):
            if key in data:
                return data[key]
        elif isinstance(key, int) and 0 <= key < len(data):
            return data[key]
        if default is Reader._MISSING:
            raise MalformedFile(f"{self.where}: {key} is missing")
        return default

    def _bad(self, key: object, what: str, value: object) -> MalformedFile:
        return MalformedFile(f"{self.where}.{key}: expected {what}, got {quote(value)}")

    def _typed(self, key: object, default: object, ok: Callable[[object], bool], what: str) -> Any:
        """The value at ``key`` if ``ok`` says it has the right type (``default`` when missing, if given)."""
        v = self.get(key, default)
        if v is default and default is not Reader._MISSING:
            return v
        if not ok(v):
            raise self._bad(key, what, v)
        return v

    def integer(self, key: object, default: object = _MISSING) -> Any:
        return self._typed(key, default, lambda v: isinstance(v, int) and not isinstance(v, bool), "an integer")

    def number(self, key: object, default: object = _MISSING) -> Any:
        v = self._typed(key, default, lambda v: isinstance(v, (int, float)) and not isinstance(v, bool), "a number")
        return v if v is default else float(v)

    def string(self, key: object, default: object = _MISSING) -> Any:
        return self._typed(key, default, lambda v: isinstance(v, str), "a string")

    def boolean(self, key: object, default: object = _MISSING) -> Any:
        return self._typed(key, default, lambda v: isinstance(v, bool), "true or false")

    def exact(self, key: object) -> Fraction:
        v = self.get(key)
        try:
            return to_fraction(v, where=f"{self.where}.{key}")
        except InputError as exc:
            raise MalformedFile(str(exc)) from None

    def exact_pair(self, key: object) -> ExactPoint:
        sub = self.at(str(key), self.get(key))
        return (sub.exact(0), sub.exact(1))

    def array(self, key: object) -> list:
        v = self.get(key)
        if not isinstance(v, list):
            raise self._bad(key, "a list", v)
        return v

    def sub(self, key: object) -> Reader:
        return self.at(str(key), self.get(key))

    def items(self, key: object) -> list[Reader]:
        """A list of objects, each as a reader."""
        return [self.at(f"{key}[{k}]", item) for k, item in enumerate(self.array(key))]

    def ints(self, key: object) -> list[int]:
        values = self.array(key)
        sub = self.at(str(key), values)
        return [sub.integer(k) for k in range(len(values))]

    def texts(self, key: object) -> list[str]:
        values = self.array(key)
        sub = self.at(str(key), values)
        return [sub.string(k) for k in range(len(values))]

    def numbers(self, key: object, count: int | None = None) -> list[float]:
        values = self.array(key)
        if count is not None and len(values) != count:
            raise self._bad(key, f"{count} numbers", values)
        sub = self.at(str(key), values)
        return [sub.number(k) for k in range(len(values))]

    def int_pairs(self, key: object) -> list[tuple[int, int]]:
        out = []
        for k, item in enumerate(self.array(key)):
            pair = self.at(f"{key}[{k}]", item)
            if not isinstance(item, list) or len(item) != 2:
                raise self._bad(f"{key}[{k}]", "a pair", item)
            out.append((pair.integer(0), pair.integer(1)))
        return out

    def points(self, key: object) -> list[ExactPoint]:
        """A list of exact points ``[[x, y], ...]`` (numbers or exact strings)."""
        sub = self.at(str(key), self.array(key))
        return [sub.exact_pair(k) for k in range(len(sub.data))]

    def pieces(self, key: object) -> tuple[BoundaryPiece, ...]:
        """Boundary pieces written by :func:`piece_json` (their exact ``t0_exact`` / ``t1_exact``)."""
        out = []
        for item in self.items(key):
            out.append(BoundaryPiece(item.integer("edge"), item.exact("t0_exact"), item.exact("t1_exact")))
        return tuple(out)

    def optimality(self, key: str = "optimality") -> Optimality:
        try:
            return Optimality.from_json(self.get(key), f"{self.where}.{key}")
        except ValueError as exc:
            raise MalformedFile(str(exc)) from None

    def stats(self, key: str = "stats") -> Stats:
        data = self.get(key, {})
        if not isinstance(data, dict):
            raise self._bad(key, "an object", data)
        known = {k: data[k] for k in ("seconds_setup", "seconds_search", "expanded") if k in data}
        return Stats(**known, counts={k: v for k, v in data.items() if k not in known})

    def environment(self, key: str = "environment") -> EnvironmentRecord | None:
        try:
            return EnvironmentRecord.from_json(self.get(key, None), f"{self.where}.{key}")
        except ValueError as exc:
            raise MalformedFile(str(exc)) from None

    def in_environment(self, env: Environment | None, kind: str) -> tuple[Environment, EnvironmentRecord | None]:
        """``env`` and the answer's environment record, checked against it: an answer that names the edges of its
        environment is read back in it (:class:`~solverplan.errors.InputError` when ``env`` is missing or another)."""
        if env is None:
            raise InputError(f"a {kind} answer is read back in its environment: give env")
        record = self.environment()
        if record is not None and not record.matches(env):
            raise InputError(f"the {kind} answer was made in another environment ({record.name!r}), not in {env.name!r}")
        return env, record

    def status(self, key: str = "status") -> Status:
        v = self.string(key)
        try:
            return Status(v)
        except ValueError:
            raise self._bad(key, "a status (" + ", ".join(x.value for x in Status) + ")", v) from None
