"""Limit cycles of the constant rule b = θ (paper §6.1): Theorem 1 in convex polygons, and Prop. 4 made
constructive in any polygon (holes too), every answer verified in exact arithmetic.

Under a constant heading the boundary dynamics is the exact piecewise affine map f_θ
(:class:`~solverplan.bounce.constant_map.ConstantMap`). A cycle along an edge sequence is the fixed point
of the composed return map, verified by exact ray casts, with exact basins (see
:mod:`solverplan.bounce._cycle_core` for the argument); :func:`limit_cycle` picks the sequence.

**Methods.**

- ``"theorem1"`` (default for a strictly convex polygon without holes): the sequence e_0, …, e_{n−1}. For θ in
  Lemma 3's range (:func:`~solverplan.bounce.dynamics.lemma3_max_heading`) every start converges (Lemma 3,
  Theorem 1); outside it the cycle is still checked exactly and reported with its status —
  ``not-contracting`` (``|α|`` ≥ 1: the periodic orbit exists but repels), ``edge-order-broken`` (the orbit of
  t* does not visit the edges in CCW order), or ``found`` with a local guarantee (its basin) and the reason
  Lemma 3 does not apply.
- ``"iterate"`` (default otherwise): Prop. 4 made constructive. Iterate f_θ from a start in floats, detect
  the eventually periodic sequence of pieces, then verify the cycle exactly; the start itself is proved to
  converge by carrying an exact enclosure of its orbit (intervals on a 2⁻⁹⁶ grid, rounded outward) until
  it lies inside a basin. The *entry* stages are those bounces. When no period shows within the bounce
  budget the status is ``not-found``: a bounded iteration that found nothing proves nothing.
- ``"edges"`` (``edges=...``): the cycle along a given edge sequence; ``not-realised`` when the heading
  does not carry the fixed point along it.

:func:`~solverplan.bounce.controller.constant_controller` searches for one constant heading under which
**every** start converges to a verified cycle (Prop. 4).

>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> cycle = limit_cycle(square, "tan:1/2")
>>> cycle.status.value, cycle.edges, cycle.contraction_exact, [str(p.t) for p in cycle.points]
('found', (0, 1, 2, 3), Fraction(1, 16), ['1/3', '1/3', '1/3', '1/3'])
>>> cycle.optimality.method.value, cycle.optimality.proved, cycle.stages[0].step.alpha
('exact-check', True, Fraction(-1, 2))
>>> limit_cycle(square, "tan:2").status.value        # θ > π/4: the period-4 orbit exists but repels
'not-contracting'
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Iterable, Sequence

from solverplan.choices import CycleMethod
from solverplan.bounce._cycle_core import (
    CycleCore,
    basins_grid,
    check_epsilon,
    cycle_along,
    edge_sequence_text,
    find_cycle_edges,
    prove_entry,
    rotation,
)
from solverplan.bounce.constant_map import ConstantMap
from solverplan.bounce.dynamics import (
    ExactHeading,
    HeadingSpec,
    Lemma3Range,
    cycles_to_epsilon,
    lemma3_range,
    parse_heading,
    theorem1_fixed_point,
)
from solverplan.bounce.partitions import Partition, partition
from solverplan.bounce.rules import check_edges
from solverplan.bounce.transitions import AffineMap
from solverplan.environment import Environment
from solverplan.errors import InputError, InvalidBoundarySet, MalformedFile, SolverFailed
from solverplan.limits import MAX_BOUNCES, quote
from solverplan.exact import ExactPoint, format_number, to_fraction
from solverplan.interval import Interval
from solverplan.result import AffineStep, Answer, EnvironmentRecord, Method, Optimality, Stage, Stats, Status, answer_dataclass

__all__ = ["CyclePoint", "LimitCycle", "limit_cycle", "limit_cycles"]

logger = logging.getLogger(__name__)


_SCOPES = {
    "every-start": "every start on the boundary converges to the cycle (rays through vertices excepted)",
    "start+basin": "the start and every start in the cycle's basins converge to it",
    "basin": "every start in the cycle's basins converges to it",
}


@dataclass(frozen=True, slots=True)
class CyclePoint:
    """A contact point of the cycle: ``edge``, exact ``t``, the exact ``point``, and the certified ``basin``
    (an open t-interval on the edge from which every start converges to the cycle; None if unknown)."""

    edge: int
    t: Fraction
    point: ExactPoint
    basin: tuple[Fraction, Fraction] | None = None

    def to_json(self, env: Environment, cycles: int | None = None) -> dict:
        out = {
            "edge": self.edge,
            "t": float(self.t),
            "t_exact": format_number(self.t),
            "point": [float(self.point[0]), float(self.point[1])],
            "d": float(self.t) * float(env.edge_lengths[self.edge]),
            "basin": None if self.basin is None else [float(self.basin[0]), float(self.basin[1])],
        }
        if cycles is not None:
            out["cycles_to_epsilon"] = cycles
        return out


@answer_dataclass("cycle")
class LimitCycle(Answer):
    """A limit cycle of the constant rule, or the reason there is none.

    Made by :func:`limit_cycle`.

    Attributes
    ----------
    env
        The environment the cycle lives in.
    status, reason
        The answer (:class:`~solverplan.result.Status`: ``found``; ``not-contracting``,
        ``edge-order-broken``, ``not-realised``, ``vertex`` (proved for the edge sequence examined); or
        ``not-found``, a bounded iteration that reached no period) and, unless ``found`` with a global
        guarantee, why (one sentence per fact).
    method
        ``theorem1``, ``iterate`` or ``edges`` (see the module docstring).
    heading, theta
        The exact heading used, and the heading asked for (radians, float).
    edges
        The cycle's edge sequence e_0, …, e_{m−1} (then back to e_0).
    stages, entry
        The cycle's bounces, and the bounces from ``start`` into the cycle (iterate mode), as
        :class:`~solverplan.result.Stage` objects with a singleton interval [θ, θ] and their exact
        :class:`~solverplan.result.AffineStep` (``stage.affine``: edges, exact direction, α, β, C_k).
    points
        The contact points (fixed points of the return maps, one per stage), exact, with basins.
    contraction_exact, contraction
        ``|α|`` of the exact return map (= Π C_k, Def. 12), and as a float.
    scope
        What is proved to converge: ``every-start`` (Theorem 1 with Lemma 3's edge order, or
        :func:`~solverplan.bounce.controller.constant_controller`'s proof), ``start+basin`` (``start`` provably enters the basins, iterate
        mode), ``basin`` (the certified basins only), or ``none`` (no stable cycle).
    start
        (edge, t) the iteration started from (iterate mode).
    lemma3
        Lemma 3's range when the environment is strictly convex, else None.
    theorem1_d
        Theorem 1's d_FP by its float formula (:func:`~solverplan.bounce.dynamics.theorem1_fixed_point`), on edge ``edges[0]`` (theorem1 method, for comparison).
    epsilon, cycles_to_epsilon, epsilon_width
        Cor. 4 (tight) when ``epsilon`` was given: cycles until a position set of width ``epsilon_width`` on
        ``edges[0]`` (the whole edge for ``every-start``, else the basin; arc length) is at most ε wide.
    optimality
        What is proved: :attr:`~solverplan.result.Method.EXACT_CHECK` (proved) for a verified cycle, with
        ``scope`` saying which starts provably converge, and for a proved failure of the edge sequence
        examined; :attr:`~solverplan.result.Method.HEURISTIC` with ``limits`` when the bounce budget ran out.
    stats
        ``seconds_setup`` (partition), ``seconds_search``, and counts: ``bounces_simulated`` (float
        iteration), ``entry_bounces`` (exact enclosure steps of the start's entry).
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of ``env``.

    Examples
    --------
    >>> import solverplan as sp
    >>> cycle = sp.limit_cycle(sp.load_environment("square"), "pi/8")
    >>> cycle.status.value, cycle.edges, cycle.scope
    ('found', (0, 1, 2, 3), 'every-start')
    >>> round(float(cycle.points[0].t), 6), round(cycle.contraction, 6)   # t* = 1 − 1/√2 on e0; |α| per cycle
    (0.292893, 0.029437)
    """

    env: Environment
    status: Status
    reason: str
    method: str
    heading: ExactHeading
    theta: float
    edges: tuple[int, ...] = ()
    stages: tuple[Stage, ...] = ()
    entry: tuple[Stage, ...] = ()
    points: tuple[CyclePoint, ...] = ()
    contraction_exact: Fraction | None = None
    contraction: float | None = None
    scope: str = "none"
    start: tuple[int, Fraction] | None = None
    lemma3: Lemma3Range | None = None
    theorem1_d: float | None = None
    epsilon: float | None = None
    cycles_to_epsilon: int | None = None
    epsilon_width: float | None = None
    point_cycles: tuple[int | None, ...] = ()
    optimality: Optimality = Optimality(Method.NONE, False, None)
    stats: Stats = field(default_factory=Stats)
    environment: EnvironmentRecord | None = None

    @property
    def found(self) -> bool:
        """True for a verified, contracting cycle (status ``found``)."""
        return self.status is Status.FOUND

    @property
    def period(self) -> int:
        """The number of bounces per cycle."""
        return len(self.edges)

    def fixed_point(self, edge: int | None = None) -> CyclePoint:
        """The first contact point (on ``edges[0]``), or the first one on ``edge``."""
        for p in self.points:
            if edge is None or p.edge == edge:
                return p
        raise InputError(f"the cycle has no contact point on edge e{edge}")

    def with_epsilon(self, epsilon: float | None) -> LimitCycle:
        """The same cycle with Cor. 4's counts for ``epsilon`` (arc length; None clears them)."""
        if epsilon is None:
            return replace(self, epsilon=None, cycles_to_epsilon=None, epsilon_width=None, point_cycles=())
        eps = check_epsilon(epsilon)
        if not self.found or self.contraction is None or not self.points:
            return replace(self, epsilon=eps, cycles_to_epsilon=None, epsilon_width=None, point_cycles=())
        c = float(self.contraction_exact) if self.contraction_exact is not None else self.contraction
        widths = [self._width(p) for p in self.points]
        counts = tuple(cycles_to_epsilon(c, w, eps) if c > 0 else int(w > eps) for w in widths)
        return replace(self, epsilon=eps, cycles_to_epsilon=counts[0], epsilon_width=widths[0], point_cycles=counts)

    def _width(self, p: CyclePoint) -> float:
        """The arc length of the position set Cor. 4 starts from at ``p``: its edge, or its basin."""
        length = float(self.env.edge_lengths[p.edge])
        if self.scope == "every-start" or p.basin is None:
            return length
        return float(p.basin[1] - p.basin[0]) * length

    # ------------------------------------------------------------------ output
    def title(self, *, others: int = 0) -> str:
        """A two-line caption for pictures (``others``: how many more cycles the picture shows)."""
        name = self.env.name or "environment"
        head = f"{name}: constant heading θ = {self.theta:.4g}"
        more = f" (+{others} more cycle{'s' if others > 1 else ''})" if others else ""
        if not self.points:
            return f"{head}\n{self.status.value}"
        seq = edge_sequence_text(self.edges) if len(self.edges) <= 8 else f"period {len(self.edges)} from e{self.edges[0]}"
        if self.found:
            return f"{head}, limit cycle {seq}{more}\ncontraction {self.contraction:.3g} per cycle ({self.scope})"
        return f"{head}, periodic orbit {seq}{more}\n{self.status.value} (contraction {self.contraction:.3g}): not a stable cycle"

    def to_json(self) -> dict:
        """The cycle answer of ``docs/contract.md`` (plus the exact details): ``method`` is the way the cycle
        was chosen (theorem1 / iterate / edges), ``optimality`` what is proved about it."""
        if self.environment is None:
            return replace(self, environment=EnvironmentRecord.of(self.env)).to_json()
        return super().to_json()

    def _fields(self) -> dict:
        pc = self.point_cycles or (None,) * len(self.points)
        out: dict = {
            "reason": self.reason,
            "method": self.method,
            "theta": self.theta,
            "theta_exact": self.heading.spec(),
            "theta_used": self.heading.theta,
            "edges": list(self.edges),
            "period": len(self.edges),
            "entry": [s.to_json() for s in self.entry],
            "cycle": [s.to_json() for s in self.stages],
            "contraction": self.contraction,
            "contraction_exact": None if self.contraction_exact is None else format_number(self.contraction_exact),
            "fixed_point": [p.to_json(self.env, c) for p, c in zip(self.points, pc)],
            "scope": self.scope,
            "start": None if self.start is None else {"edge": self.start[0], "t": float(self.start[1]), "t_exact": format_number(self.start[1])},
        }
        if self.lemma3 is not None:
            out["lemma3"] = {
                "range": list(self.lemma3.interval),
                "clockwise": self.lemma3.clockwise,
                "inside": self.lemma3.contains(self.heading.theta),
                "order_bound": self.lemma3.order_bound,
                "contraction_bound": self.lemma3.contraction_bound,
            }
        if self.theorem1_d is not None:
            out["theorem1"] = {"edge": self.edges[0] if self.edges else 0, "d": self.theorem1_d}
        if self.epsilon is not None:
            out.update(epsilon=self.epsilon, cycles_to_epsilon=self.cycles_to_epsilon, epsilon_width=self.epsilon_width)
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> LimitCycle:
        """Read a limit cycle back in ``env`` (required: the cycle's distances and Lemma 3 are of its edges)."""
        r, env, record = cls._reader_in(data, env, "limit cycle")
        heading = parse_heading(r.string("theta_exact"))
        if not isinstance(heading, ExactHeading):
            raise MalformedFile(f"cycle.theta_exact: expected an exact heading (tan:P/Q or dir:C,S), got {quote(r.get('theta_exact'))}")
        points, counts = [], []
        for p in r.items("fixed_point"):
            basin = p.get("basin", None)
            b = p.numbers("basin", 2) if basin is not None else None
            t = p.exact("t_exact")
            points.append(CyclePoint(p.integer("edge"), t, env.exact_point_at(p.integer("edge"), t),
                                     None if b is None else (Fraction(b[0]), Fraction(b[1]))))
            counts.append(p.integer("cycles_to_epsilon", None))
        start = r.sub("start") if r.has("start") else None
        lemma3 = None
        if r.has("lemma3"):
            lemma3 = lemma3_range(env, clockwise=r.sub("lemma3").boolean("clockwise"))
        theorem1 = r.sub("theorem1") if r.has("theorem1") else None
        exact = r.get("contraction_exact", None)
        return cls(env=env, status=r.status(), reason=r.string("reason", ""), method=r.string("method"),
                   heading=heading, theta=r.number("theta"), edges=tuple(r.ints("edges")),
                   stages=tuple(Stage.from_json(st.data, st.where) for st in r.items("cycle")),
                   entry=tuple(Stage.from_json(st.data, st.where) for st in r.items("entry")), points=tuple(points),
                   contraction_exact=None if exact is None else r.exact("contraction_exact"),
                   contraction=r.number("contraction", None), scope=r.string("scope", "none"),
                   start=None if start is None else (start.integer("edge"), start.exact("t_exact")), lemma3=lemma3,
                   theorem1_d=None if theorem1 is None else theorem1.number("d"), epsilon=r.number("epsilon", None),
                   cycles_to_epsilon=r.integer("cycles_to_epsilon", None), epsilon_width=r.number("epsilon_width", None),
                   point_cycles=tuple(counts) if any(c is not None for c in counts) else (),
                   optimality=r.optimality(), stats=r.stats(), environment=record)

    def to_text(self, *, width: int = 100) -> str:
        lines = [f"limit cycle of the constant heading θ = {self.theta:.12g} ({self.heading.spec()}) in "
                 f"{self.env.name or 'the environment'}: {self.status.value} (method {self.method})"]
        if self.reason:
            lines.append(f"reason: {self.reason}")
        if self.edges:
            lines.append("edges: " + " → ".join(f"e{e}" for e in (*self.edges, self.edges[0])))
        if self.contraction is not None:
            exact = format_number(self.contraction_exact) if self.contraction_exact is not None else "?"
            if len(exact) > 60:
                exact = exact[:28] + "…" + exact[-28:]
            lines.append(f"contraction per cycle: {self.contraction:.12g} (exact {exact})")
        if self.entry:
            lines.append(f"entry: {len(self.entry)} bounces from e{self.start[0]}:{float(self.start[1]):.12g}" if self.start else
                         f"entry: {len(self.entry)} bounces")
        for p in self.points:
            basin = "" if p.basin is None else f", basin t ∈ ({float(p.basin[0]):.6g}, {float(p.basin[1]):.6g})"
            lines.append(f"  e{p.edge}: t = {float(p.t):.15g}, point ({float(p.point[0]):.12g}, {float(p.point[1]):.12g}){basin}")
        lines.append(f"guarantee: {self.scope}")
        if self.cycles_to_epsilon is not None:
            lines.append(f"cycles to ε = {self.epsilon:g}: {self.cycles_to_epsilon} (from a position set {self.epsilon_width:.6g} wide)")
        lines.append(f"optimality: {self.optimality.to_text()}")
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- building the answer
def _segments(part: Partition | None, edge: int, lo: Fraction, hi: Fraction | None = None) -> tuple[int, ...]:
    if part is None:
        return ()
    if hi is None:
        return (part.segment_at(edge, lo),)
    ids = part.edge_segments[edge]
    return tuple(k for k in ids if part.segments[k].t1 > lo and part.segments[k].t0 < hi)


def _stage(env: Environment, cmap: ConstantMap, m: AffineMap, theta: float, part: Partition | None,
           t_from: Fraction | None, whole: bool) -> Stage:
    """One bounce by the exact map ``m`` at the heading ``theta`` (radians), labelled with the P′ segments
    of its contact ``t_from`` and of its image (of the whole edge and its image when ``whole``)."""
    lengths = env.edge_lengths
    c = float(abs(m.alpha)) * float(lengths[m.target]) / float(lengths[m.source])
    if whole or t_from is None:
        src = _segments(part, m.source, Fraction(0), Fraction(1))
        dom = m.domain()
        dst = _segments(part, m.target, *(sorted((m(dom[0]), m(dom[1]))) if dom else (Fraction(0), Fraction(1))))
    else:
        src = _segments(part, m.source, t_from)
        dst = _segments(part, m.target, m(t_from))
    step = AffineStep(m.source, m.target, theta, cmap.direction(m.source), m.alpha, m.beta, c)
    return Stage(src, dst, Interval(theta, theta), affine=step)


def _optimality(status: Status, scope: str, edges: Sequence[int], *, algorithm: str, start=None,
                limits: tuple[str, ...] = (), claim: str | None = None) -> Optimality:
    """What the answer proves, for :attr:`LimitCycle.optimality` (nothing is optimised: the cycle, or
    its failure, is checked in exact arithmetic; a bounded iteration that ran out proves nothing)."""
    where = "" if start is None else f"e{start[0]}:{format_number(start[1])}"
    if status is Status.NOT_FOUND:
        return Optimality(Method.HEURISTIC, False, None, algorithm=algorithm, limits=limits,
                          scope=f"a periodic orbit reached from the start {where} within the bounce budget")
    if status is Status.FOUND:
        if limits:  # the cycle is verified, the start's entry is not: the question asked stays open
            return Optimality(Method.EXACT_CHECK, False, None, algorithm=algorithm, limits=limits,
                              scope=f"the start {where} converges to the cycle (not proved within the bounce budget; "
                                    f"{_SCOPES['basin']}: verified exactly)")
        text = claim or _SCOPES[scope]
        if scope == "start+basin":
            text = text.replace("the start", f"the start {where}")
        return Optimality(Method.EXACT_CHECK, True, None, scope=text, algorithm=algorithm)
    seq = edge_sequence_text(edges) if edges else "the edge sequence examined"
    return Optimality(Method.EXACT_CHECK, True, None, algorithm=algorithm,
                      scope=f"the cycle along {seq} at this exact heading")


def _build(env: Environment, cmap: ConstantMap, core: CycleCore, *, method: str, theta: float, scope: str,
           reason: str, rotate: bool, algorithm: str, entry: tuple[Stage, ...] = (), start=None, lemma3=None,
           theorem1_d=None, part: Partition | None = None, whole_edges: bool = False,
           limits: tuple[str, ...] = (), counts: dict | None = None, claim: str | None = None) -> LimitCycle:
    """The :class:`LimitCycle` of a checked core, rotated to start at its smallest contact when ``rotate``;
    ``claim`` replaces the words of what a found cycle proves (package-internal:
    :mod:`solverplan.bounce.controller` builds its cycles with it too)."""
    m = len(core.edges)
    r = rotation(core) if (rotate and core.orbit) else 0
    edges = core.edges[r:] + core.edges[:r]
    stages: tuple[Stage, ...] = ()
    points: tuple[CyclePoint, ...] = ()
    c_exact = c_float = None
    if core.maps:
        maps = core.maps[r:] + core.maps[:r]
        orbit = (core.orbit[r:] + core.orbit[:r]) if core.orbit else []
        radii = (core.radii[r:] + core.radii[:r]) if core.radii else []
        stages = tuple(_stage(env, cmap, mk, theta, part, orbit[k] if orbit else None, whole_edges)
                       for k, mk in enumerate(maps))
        if core.ret is not None and core.status in (Status.FOUND, Status.NOT_CONTRACTING):
            c_exact = abs(core.ret.alpha)  # only for a real periodic orbit
            c_float = float(c_exact)
        pts = []
        for k, tk in enumerate(orbit):
            basin = None
            if core.status is Status.FOUND:
                if whole_edges:
                    basin = (Fraction(0), Fraction(1))
                elif radii:
                    basin = (max(Fraction(0), tk - radii[k]), min(Fraction(1), tk + radii[k]))
            pts.append(CyclePoint(edges[k], tk, env.exact_point_at(edges[k], tk), basin))
        points = tuple(pts)
    scope = scope if core.status is Status.FOUND else "none"
    optimality = _optimality(core.status, scope, edges, algorithm=algorithm, start=start, limits=limits, claim=claim)
    return LimitCycle(
        env=env, status=core.status, reason=reason, method=method, heading=cmap.heading, theta=theta,
        edges=edges if m else (), stages=stages, entry=entry, points=points, contraction_exact=c_exact,
        contraction=c_float, scope=scope, start=start, lemma3=lemma3, theorem1_d=theorem1_d,
        optimality=optimality, stats=Stats(counts=dict(counts or {})),
        environment=EnvironmentRecord.of(env, None if part is None else part.n_segments),
    )


# ---------------------------------------------------------------------- public: limit_cycle
def _parse_start(env: Environment, start: object) -> tuple[int, Fraction]:
    if start is None:
        return 0, Fraction(1, 2)
    if isinstance(start, str):
        text = start.strip()
        if not text.startswith("e") or text.count(":") != 1:
            raise InvalidBoundarySet(f"start point {start!r}: expected eK:T, e.g. e0:0.5")
        e_text, t_text = text[1:].split(":")
        try:
            e = int(e_text)
        except ValueError:
            raise InvalidBoundarySet(f"start point {start!r}: {e_text!r} is not an edge number") from None
        t = to_fraction(t_text, where=f"start point {start!r}")
    else:
        try:
            e, t = start  # type: ignore[misc]
        except (TypeError, ValueError):
            raise InputError(f"start must be 'eK:T' or (edge, t), got {start!r}") from None
        t = Fraction(t) if isinstance(t, float) else to_fraction(t, where="start t")
    e = int(check_edges(env, [e])[0])
    if not 0 < t < 1:
        raise InvalidBoundarySet(f"start point e{e}:{format_number(t)} is not inside the edge: t must be in (0, 1)")
    return e, t


def _parse_edges(env: Environment, edges: object) -> tuple[int, ...]:
    if isinstance(edges, str):
        items = [x.strip() for x in edges.split(",") if x.strip()]
        try:
            ids = [int(x[1:]) if x.startswith("e") else int(x) for x in items]
        except ValueError:
            raise InvalidBoundarySet(f"edge sequence {edges!r}: expected e0,e1,... (edge ids)") from None
    elif isinstance(edges, Iterable):
        ids = list(edges)
    else:
        raise InvalidBoundarySet(f"edge sequence {edges!r}: expected e0,e1,... or a sequence of edge ids")
    if len(ids) < 2:
        raise InvalidBoundarySet(f"edge sequence {edges!r}: a cycle needs at least two edges")
    return tuple(int(e) for e in check_edges(env, ids))


def _strictly_convex(env: Environment, clockwise: bool = False) -> Lemma3Range | None:
    try:
        return lemma3_range(env, clockwise=clockwise)
    except InputError:
        return None


def limit_cycle(
    env: Environment,
    theta: HeadingSpec,
    *,
    edges: Sequence[int] | str | None = None,
    method: CycleMethod | str = "auto",
    start: str | tuple | None = None,
    epsilon: float | None = None,
    max_bounces: int = 20000,
    segments: bool = True,
) -> LimitCycle:
    """The limit cycle of the constant rule b = θ (paper §6.1), verified exactly (module docstring).

    Parameters
    ----------
    env
        The environment (any polygon with holes).
    theta
        The heading: radians (a float, taken at the exact direction (cos θ, sin θ) of its binary floats,
        within ~1e-16 rad), an :class:`~solverplan.bounce.dynamics.ExactHeading`, a ``(cos, sin)`` pair,
        or text (``"0.3"``, ``"pi/8"``, ``"tan:1/3"``, ``"dir:12,5"``: :func:`~solverplan.bounce.dynamics.parse_heading`).
    edges
        Ask for the cycle along this edge sequence (``"e0,e2,e5"`` or ids): method ``edges``.
    method
        ``auto`` (edges if given, else ``theorem1`` for a strictly convex polygon without holes, else
        ``iterate``), or one of ``theorem1`` / ``iterate`` / ``edges``.
    start
        Iterate mode: where the robot starts, ``"eK:T"`` or ``(edge, t)`` with exact t ∈ (0, 1) (default
        the middle of e0).
    epsilon
        Also report Cor. 4's cycle counts for this width (arc length).
    max_bounces
        Iterate mode: the float iteration's budget (and the exact entry's).
    segments
        Label stages with P′ segment ids (Algorithm 1's partition); False skips the partition.

    Returns
    -------
    LimitCycle
        ``status`` says whether a stable cycle was found (``optimality`` what is proved about it, ``stats``
        what it cost); never raises for a heading that merely fails. A heading close to a wall is used as
        asked (the planners' heading margin is for searches over headings).

    Raises
    ------
    InputError
        Bad heading (outside (0, π)), unknown edges, a bad start, ``theorem1`` on a non-convex polygon.

    Examples
    --------
    In a regular hexagon, θ = 0.3 rad lies in Lemma 3's range (0, π/6): Theorem 1 gives a cycle through every edge
    that every start converges to.

    >>> import solverplan as sp
    >>> cycle = sp.limit_cycle(sp.load_environment("hexagon"), 0.3)
    >>> cycle.status.value, cycle.method, cycle.edges, cycle.scope, cycle.optimality.proved
    ('found', 'theorem1', (0, 1, 2, 3, 4, 5), 'every-start', True)

    In the L-shaped room, θ = 1 rad settles between two parallel walls, where nothing contracts:

    >>> cycle = sp.limit_cycle(sp.load_environment("l_shape"), 1.0)
    >>> cycle.status.value, cycle.edges, cycle.contraction_exact
    ('not-contracting', (0, 2), Fraction(1, 1))
    """
    heading = parse_heading(theta)
    if not isinstance(heading, ExactHeading):
        value = heading
        heading = ExactHeading.from_float(heading)
    else:
        value = heading.theta
    method = CycleMethod.parse(method, "cycle method").value
    if isinstance(max_bounces, bool) or not isinstance(max_bounces, int) or not 1 <= max_bounces <= MAX_BOUNCES:
        raise InputError(f"max_bounces must be an integer in [1, {MAX_BOUNCES:,}], got {quote(max_bounces)}")
    seq = _parse_edges(env, edges) if edges is not None else None
    lemma3 = _strictly_convex(env, clockwise=heading.theta > math.pi / 2)
    if method == "auto":
        method = "edges" if seq is not None else ("theorem1" if lemma3 is not None else "iterate")
    if method == "edges" and seq is None:
        raise InputError("method 'edges' needs an edge sequence (edges=...)")
    if method == "theorem1":
        if lemma3 is None:
            lemma3_range(env)  # raises the reason
        if seq is not None:
            raise InputError("method 'theorem1' visits every edge in CCW order: drop edges=..., or use method 'edges'")
    begin = time.perf_counter()
    cmap = ConstantMap(env, heading)
    part = partition(env) if segments else None
    setup = time.perf_counter()
    if method == "theorem1":
        assert lemma3 is not None  # checked above: theorem1 needs a strictly convex polygon
        result = _theorem1(env, cmap, value, lemma3, part)
    elif method == "edges":
        assert seq is not None  # checked above: method 'edges' needs the sequence
        core = cycle_along(env, cmap, seq, Status.NOT_REALISED)
        reason = core.reason or (
            "the cycle is verified exactly and attracts every start in its basins; starts elsewhere are not covered"
        )
        result = _build(env, cmap, core, method="edges", theta=value, scope="basin", reason=reason, rotate=False,
                        lemma3=lemma3, part=part, algorithm="exact return map along the given edges, exact ray casts")
    else:
        result = _iterate(env, cmap, value, _parse_start(env, start), max_bounces, lemma3, part)
    done = time.perf_counter()
    result = replace(result, stats=result.stats.with_(seconds_setup=setup - begin, seconds_search=done - setup))
    return result.with_epsilon(epsilon) if epsilon is not None else result


def _keeps_edge_order(env: Environment, cmap: ConstantMap, clockwise: bool) -> int | None:
    """Exact Lemma 3 edge-order test: None if from every open edge e_i every ray reaches the open next edge
    (CCW: θ ≤ ∠v_{i+2} v_i v_{i+1}, i.e. d_i is not counter-clockwise of v_{i+2} − v_i; CW, the mirror image:
    d_i is not clockwise of v_{i−1} − v_{i+1}; solverplan.proofs.lemma3_convex_order), else the first edge i where it fails."""
    verts = env.exact_vertices
    n = env.n_edges
    for i in range(n):
        d = cmap.direction(i)
        a, b = (verts[(i + 1) % n], verts[i - 1]) if clockwise else (verts[i], verts[(i + 2) % n])
        w = (b[0] - a[0], b[1] - a[1])
        cross = w[0] * d[1] - w[1] * d[0]
        if (cross < 0) if clockwise else (cross > 0):
            return i
    return None


def limit_cycles(
    env: Environment,
    theta: HeadingSpec,
    starts: Sequence[tuple[int, object]],
    *,
    max_bounces: int = 20000,
    limit: int = 32,
) -> tuple[LimitCycle, ...]:
    """The distinct stable cycles the constant rule b = θ reaches from ``starts`` ((edge, t) pairs, t ∈ (0, 1);
    others are skipped), at most ``limit`` of the starts examined; the first item is :func:`limit_cycle`'s
    default answer (alone when it already covers every start). Each is verified as in :func:`limit_cycle`.

    >>> dumbbell = Environment.from_coords([(0, 0), (4, 0), (4, 1), (8, 1), (8, 0), (12, 0), (12, 4), (8, 4), (8, 3),
    ...                                     (4, 3), (4, 4), (0, 4)])
    >>> [c.edges for c in limit_cycles(dumbbell, "tan:1/4", [(0, 0.5), (5, 0.5)])]     # one cycle per room
    [(0, 1, 10, 11), (4, 5, 6, 7)]
    """
    first = limit_cycle(env, theta, max_bounces=max_bounces)
    out = [first]
    if first.scope == "every-start":
        return tuple(out)
    seen = {(frozenset(zip(c.edges, (p.t for p in c.points)))) for c in out if c.found}
    for edge, t in list(starts)[:limit]:
        try:
            cycle = limit_cycle(env, first.heading, method="iterate", start=(int(edge), t), max_bounces=max_bounces)
        except InputError:
            continue
        if not cycle.found:
            continue
        key = frozenset(zip(cycle.edges, (p.t for p in cycle.points)))
        if key not in seen:
            seen.add(key)
            out.append(replace(cycle, theta=first.theta))
    return tuple(out)


def _theorem1(env: Environment, cmap: ConstantMap, value: float, lemma3: Lemma3Range,
              part: Partition | None) -> LimitCycle:
    """The CCW (or, for θ > π/2, CW) cycle over every edge, with Lemma 3's guarantee when it applies."""
    n = env.n_edges
    clockwise = lemma3.clockwise
    order = tuple((-k) % n for k in range(n)) if clockwise else tuple(range(n))
    core = cycle_along(env, cmap, order, Status.EDGE_ORDER_BROKEN)
    theta = cmap.heading.theta
    inside = lemma3.contains(theta)
    d = None
    if not clockwise:
        try:
            d = theorem1_fixed_point(env, value).d
        except InputError:
            d = None
    broken_at = _keeps_edge_order(env, cmap, clockwise)
    lo, hi = lemma3.interval
    sense = "CW" if clockwise else "CCW"
    where = f"({lo:.6g}, {hi:.6g})"
    algorithm = "Theorem 1 and Lemma 3 (exact edge-order test, exact return map and ray casts)"
    if core.status is Status.FOUND and broken_at is None:
        assert core.ret is not None  # a found cycle has its return map
        if inside:
            reason = f"θ is inside Lemma 3's {sense} range {where}: every start converges (Theorem 1)"
        else:
            reason = (f"θ is outside Lemma 3's {sense} range {where}: {lemma3.reason_outside(theta)}; but every start "
                      f"still visits the edges in {sense} order (within the edge-order bound {lemma3.order_bound:.6g}, checked "
                      f"exactly) and the whole return map contracts (|α| = {float(abs(core.ret.alpha)):.6g} < 1, Def. 12), so "
                      "every start converges (Lemma 3's per-step condition is sufficient, not necessary)")
        return _build(env, cmap, core, method="theorem1", theta=value, scope="every-start", reason=reason,
                      rotate=False, lemma3=lemma3, theorem1_d=d, part=part, whole_edges=True, algorithm=algorithm)
    if inside and min(theta - lo, hi - theta) > lemma3.bound * 1e-9:  # pragma: no cover - would contradict Lemma 3
        raise SolverFailed(f"θ = {value!r} is inside Lemma 3's range but the {sense} cycle failed: {core.reason}")
    outside = f"θ is outside Lemma 3's {sense} range {where}: {lemma3.reason_outside(theta)}"
    if core.status is Status.FOUND:
        assert broken_at is not None  # the found-and-unbroken case returned above
        nxt = (broken_at - 1) % n if clockwise else (broken_at + 1) % n
        reason = (f"{outside}. The {sense} cycle is verified exactly and attracts the starts in its basins, but some "
                  f"starts on e{broken_at} miss e{nxt}: convergence from every start is not guaranteed")
    else:
        reason = f"{outside}. {core.reason} (method 'iterate' finds the cycle this heading does reach, if any)"
    return _build(env, cmap, core, method="theorem1", theta=value, scope="basin", reason=reason, rotate=False,
                  lemma3=lemma3, theorem1_d=d, part=part, algorithm=algorithm)


def _iterate(env: Environment, cmap: ConstantMap, value: float, start: tuple[int, Fraction], max_bounces: int,
             lemma3: Lemma3Range | None, part: Partition | None) -> LimitCycle:
    """Prop. 4 made constructive from one start: float iteration, exact verification, exact entry."""
    e0, t0 = start
    algorithm = "float iteration of f_θ, exact return map and ray casts, exact entry enclosure"
    start_index, cycle_edges, (f_edges, f_ts) = find_cycle_edges(cmap, e0, float(t0), max_bounces)
    counts = {"bounces_simulated": len(f_edges) - 1}
    if cycle_edges is None:
        tail = " → ".join(f"e{e}" for e in f_edges[-12:])
        core = CycleCore(Status.NOT_FOUND, "", ())
        return _build(env, cmap, core, method="iterate", theta=value, scope="none", rotate=False, start=start,
                      lemma3=lemma3, part=part, counts=counts, algorithm=algorithm, limits=(f"max_bounces={max_bounces}",),
                      reason=(f"the orbit from e{e0}:{float(t0):.6g} did not settle into a periodic edge sequence within "
                              f"{max_bounces} bounces (last edges {tail}): no attracting cycle was reached (a neutral "
                              "orbit, e.g. between parallel walls, never settles)"))
    core = cycle_along(env, cmap, cycle_edges, Status.NOT_REALISED, hint=Fraction(float(f_ts[start_index])))
    if core.status is not Status.FOUND:
        return _build(env, cmap, core, method="iterate", theta=value, scope="none", rotate=True, start=start,
                      lemma3=lemma3, part=part, counts=counts, algorithm=algorithm,
                      reason=f"the float orbit settled on {edge_sequence_text(cycle_edges)}, but {core.reason}")
    r = rotation(core)
    found = prove_entry(cmap, e0, t0, basins_grid(core.edges, core.orbit, core.radii), max_bounces)
    entry: tuple[Stage, ...] = ()
    limits: tuple[str, ...] = ()
    if found.steps is not None and found.phase is not None:
        # walk on from the basin reached to the rotated cycle's first contact
        phase = found.phase
        extra = (r - phase) % len(core.edges)
        stages = [_stage(env, cmap, mk, value, part, mid, False) for mk, mid in found.steps]
        t = core.orbit[phase]
        for j in range(extra):
            mk = core.maps[(phase + j) % len(core.maps)]
            stages.append(_stage(env, cmap, mk, value, part, t, False))
            t = mk(t)
        entry = tuple(stages)
        counts["entry_bounces"] = len(found.steps)
        reason = (f"the cycle is verified exactly; the start e{e0}:{float(t0):.6g} provably enters its basin after "
                  f"{len(found.steps)} bounces (exact enclosure), and every start in the basins converges")
        scope = "start+basin"
    else:
        reason = f"the cycle is verified exactly and attracts every start in its basins; {found.failure}"
        scope = "basin"
        if found.budget_hit:
            limits = (f"max_bounces={max_bounces}",)
    return _build(env, cmap, core, method="iterate", theta=value, scope=scope, reason=reason, rotate=True,
                  entry=entry, start=start, lemma3=lemma3, part=part, counts=counts, algorithm=algorithm,
                  limits=limits)
