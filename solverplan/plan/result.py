"""What the planners return: :class:`Plan` (``docs/contract.md``, "A plan") and :class:`ParetoFront`, on the
shared result protocol of :mod:`solverplan.result` (``status``, ``optimality``, ``stats``, ``environment``,
``to_json()``, ``to_text()``; stages are :class:`solverplan.result.Stage`).

Results are frozen dataclasses; :meth:`Plan.to_json` is the only place a plan becomes a dict, and
:func:`parse_plan` / :func:`load_plan` read one back (for ``solverplan simulate`` and ``render --plan``).

A plan's JSON is the contract's ``{"status", "objective", "bounces", "min_width", "tolerance", "stages":
[{"from_segments", "to_segments", "interval"}], "optimality": {"method", "proved", "bound"}, "reason"}``
plus, for its readers: per stage the ``moves`` ([source, target] segment pairs, one per source: where the
robot lands from each possible segment) and ``width``; the optimality's ``scope`` (the class of plans the
claim is about) and ``gap`` (|value − bound| over that scope); the query (``start``, ``goal``,
``max_bounces``), the environment (``environment``: name, SHA-256 of its exact normalised rings, number of
P′ segments), the heading margins the admissible intervals were built with, ``sum_width`` and ``stats``
(recorded, never asserted). Headings are radians in (0, π), measured counter-clockwise from the wall the
robot is on.

>>> plan = Plan.infeasible("fewest", "goal segments have no incoming safe arc",
...                        Optimality(Method.SEARCH_EXHAUSTED, True, None, algorithm="precheck"))
>>> plan.to_json()["status"], plan.to_json()["reason"], plan.bounces, plan.status.group.value
('infeasible', 'goal segments have no incoming safe arc', None, 'proven-infeasible')
"""

from __future__ import annotations

import io
import json
import math
from dataclasses import KW_ONLY, dataclass, field, replace
from pathlib import Path
from typing import Any

from solverplan.choices import Objective
from solverplan._io import read_input_text, shown_path
from solverplan.environment import BoundaryPiece, Environment, read_json
from solverplan.errors import InputError, MalformedFile
from solverplan.exact import to_fraction
from solverplan.interval import Interval
from solverplan.limits import quote
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Stage, Stats, Status, answer_dataclass, finite_number, index_list

__all__ = [
    "Objective",
    "OBJECTIVES",
    "Plan",
    "ParetoPoint",
    "ParetoFront",
    "parse_plan",
    "load_plan",
    "read_optimality",
    "read_environment",
    "read_stats",
]


OBJECTIVES: tuple[str, ...] = Objective.values()

_OLD_METHODS = {"dag-exhausted": Method.SEARCH_EXHAUSTED, "search": Method.HEURISTIC}
"""Method spellings of older answers and what they mean now (reading is lenient; constructing is strict)."""


def read_optimality(data: object, where: str = "optimality") -> Optimality:
    """An :class:`~solverplan.result.Optimality` from an answer's JSON, old or new.

    Old files may lack ``scope``, ``gap`` and ``limits``, and may use old method spellings:
    ``dag-exhausted`` is read as ``search-exhausted``, ``search`` as ``heuristic``; any other unknown
    spelling becomes ``none`` with ``proved`` false (a claim nobody can say how it was made proves nothing).
    Raises :class:`~solverplan.errors.MalformedFile` naming ``where`` on a malformed object.
    """
    if isinstance(data, dict) and isinstance(data.get("method"), str):
        method = data["method"]
        known = {m.value for m in Method}
        if method not in known:
            data = {**data, "method": _OLD_METHODS.get(method, Method.NONE).value}
            if data["method"] == Method.NONE.value:
                data["proved"] = False
    try:
        return Optimality.from_json(data, where)
    except ValueError as exc:
        raise MalformedFile(str(exc)) from None


def read_environment(data: object, where: str = "environment") -> EnvironmentRecord | None:
    """The :class:`~solverplan.result.EnvironmentRecord` of an answer's JSON (None when it has none)."""
    try:
        return EnvironmentRecord.from_json(data, where)
    except ValueError as exc:
        raise MalformedFile(str(exc)) from None


@dataclass(frozen=True)
class _Query:
    """What a planner was asked and what closes its answer, the fields :class:`Plan` and :class:`ParetoFront`
    share: keyword-only, after each answer's own positional fields (``Plan(status, objective, stages,
    optimality, start=..., ...)``, ``ParetoFront(points, optimality, start=..., ...)``)."""

    _: KW_ONLY
    start: str | None = None
    goal: str | None = None
    max_bounces: int | None = None
    reason: str | None = None
    environment: EnvironmentRecord | None = None
    stats: Stats = field(default_factory=Stats, compare=False)


def _text_title(answer: Plan | ParetoFront, what: str) -> str:
    """The first line of a planner answer's text: what it is, in which environment, for which query."""
    record = answer.environment
    env = record.name if record is not None and record.name else "environment"
    query = f" from {answer.start} to {answer.goal}" if answer.start else ""
    budget = f", at most {answer.max_bounces} bounces" if answer.max_bounces is not None else ""
    return f"{what} in {env!r}{query}{budget}\n"


def _text_unanswered(answer: Plan | ParetoFront) -> str:
    """The text of a planner answer without a plan: its status and why, and the optimality claim."""
    return f"  {answer.status.value}: {answer.reason}\n  optimality: {answer.optimality.to_text()}\n"


@answer_dataclass("plan")
class Plan(_Query, Answer):
    """A plan (``docs/contract.md``): heading intervals, one per bounce, from every start to the goal set.

    The intervals take the robot from every point of the start set to the goal set whatever headings inside
    them it executes — or the plan is a proof that there is none (``status``
    :attr:`~solverplan.result.Status.INFEASIBLE` with a ``reason``). Made by :func:`find_plan`; read back by
    :func:`load_plan`.

    Attributes
    ----------
    status, reason
        A :class:`~solverplan.result.Status` (``found``, ``infeasible``, or ``not-found`` after a timeout) and,
        unless found, why.
    objective
        ``fewest``, ``tolerance``, ``sum`` or ``constant``.
    stages
        The bounces, as :class:`~solverplan.result.Stage` objects: heading intervals (radians, CCW from the wall
        the robot is on), each executed from the segments of P′ the robot may be on.
    optimality
        How the plan's optimality (or the infeasibility) is established, with its bound and scope.
    start, goal
        The boundary sets asked for, as text (``"e3:0.25:0.75,e4"``).
    max_bounces
        The bounce budget K, if one was given.
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of the environment; ``None`` for a plan read from a
        file that does not record it.
    margins
        The margin policy the planner used (heading margin δ and interval-end margin μ in radians, corner
        clearance κ in the environment's units).
    stats
        Times and counts (recorded, never compared).
    bounces
        The number of stages (0 when the start set already lies in the goal set); ``None`` unless found.
    min_width, tolerance, sum_width
        The narrowest interval's width (radians), half of it (the precision the robot needs), and the sum of
        the widths; ``None`` unless found.
    value
        The objective's value in the units of ``optimality.bound``.

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("l_shape"), "e5", "e0:0:0.3")
    >>> plan.status.value, plan.bounces, round(plan.tolerance, 4), plan.intervals
    ('found', 1, 0.1452, (Interval(lo=0.001, hi=0.29132704406479815),))
    >>> print(plan.to_text().splitlines()[0])
    fewest plan in 'l_shape' from e5 to e0:0:0.3
    """

    status: Status
    objective: str
    stages: tuple[Stage, ...]
    optimality: Optimality
    margins: dict = field(default_factory=dict, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", Status(self.status))

    # ------------------------------------------------------------------ construction
    @classmethod
    def infeasible(cls, objective: str, reason: str, optimality: Optimality, **extra: Any) -> Plan:
        return cls(Status.INFEASIBLE, objective, (), optimality, reason=reason, **extra)

    def with_(self, **changes: Any) -> Plan:
        """A copy with some fields changed."""
        return replace(self, **changes)

    # ------------------------------------------------------------------ numbers
    @property
    def bounces(self) -> int | None:
        return len(self.stages) if self.found else None

    @property
    def min_width(self) -> float | None:
        if not self.found:
            return None
        if not self.stages:
            return math.pi  # nothing to execute: no precision is needed
        return min(s.interval.width for s in self.stages)

    @property
    def tolerance(self) -> float | None:
        w = self.min_width
        return None if w is None else w / 2

    @property
    def sum_width(self) -> float | None:
        return sum(s.interval.width for s in self.stages) if self.found else None

    @property
    def value(self) -> float | None:
        """The objective's value in the units of ``optimality.bound``: bounces (``fewest``), the narrowest
        width (``tolerance``, ``constant``, radians) or the sum of the widths (``sum``, radians)."""
        if not self.found:
            return None
        if self.objective == "fewest":
            return float(len(self.stages))
        return self.sum_width if self.objective == "sum" else self.min_width

    @property
    def intervals(self) -> tuple[Interval, ...]:
        return tuple(s.interval for s in self.stages)

    def check_environment(self, env: Environment, n_segments: int) -> None:
        """Raise :class:`InputError` unless the plan can be executed in ``env`` (whose partition has
        ``n_segments`` segments): same exact rings when the plan records them, known segment ids."""
        record = self.environment
        if record is not None and not record.matches(env):
            raise InputError(f"the plan was made in another environment ({record.name or '?'!r}, sha256 "
                             f"{record.sha256[:12]}…), not in {env.name!r}")
        for k, stage in enumerate(self.stages):
            for seg in (*stage.from_segments, *stage.to_segments):
                if not 0 <= seg < n_segments:
                    raise InputError(f"plan stage {k} names segment {seg}, but the partition of {env.name!r} has segments "
                                     f"0..{n_segments - 1}")

    # ------------------------------------------------------------------ output
    def _fields(self) -> dict:
        """The contract's plan, then the extra fields described in the module docstring."""
        out: dict[str, Any] = {
            "objective": self.objective,
            "bounces": self.bounces,
            "min_width": self.min_width,
            "tolerance": self.tolerance,
            "stages": [s.to_json() for s in self.stages],
        }
        if not self.found:
            out["reason"] = self.reason
        out["sum_width"] = self.sum_width
        out["start"] = self.start
        out["goal"] = self.goal
        out["max_bounces"] = self.max_bounces
        if self.margins:
            out["margins"] = dict(self.margins)
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> Plan:
        """:func:`parse_plan` (``env`` is not needed: a plan names its environment by its SHA-256)."""
        return parse_plan(data)

    def to_text(self, *, width: int = 100) -> str:
        """A table like the paper's (§7.1.2): stage, from, to, interval, width."""
        buf = io.StringIO()
        buf.write(_text_title(self, f"{self.objective} plan"))
        if not self.found:
            return buf.getvalue() + _text_unanswered(self)
        buf.write(f"  bounces {self.bounces}   min width {self.min_width:.6f} rad   tolerance ±{self.tolerance:.6f} rad "
                  f"(±{math.degrees(self.tolerance or 0.0):.4f}°)   sum of widths {self.sum_width:.6f}\n")
        buf.write(f"  optimality: {self.optimality.to_text()}\n")
        if not self.stages:
            buf.write("  the start set lies in the goal set: nothing to do\n")
            return buf.getvalue()
        head = f"  {'stage':>5}  {'from':<18} {'to':<18} {'interval (rad)':<25} {'width':>9}\n"
        buf.write(head)
        for k, s in enumerate(self.stages, 1):
            frm = ",".join(map(str, s.from_segments))
            to = ",".join(map(str, s.to_segments))
            iv = f"[{s.interval.lo:.6f}, {s.interval.hi:.6f}]"
            buf.write(f"  {k:>5}  {frm:<18.18} {to:<18.18} {iv:<25} {s.width:>9.6f}\n")
        return buf.getvalue()


@dataclass(frozen=True, slots=True)
class ParetoPoint:
    """One point of the bounces ↔ tolerance front: the most tolerant plan with at most ``bounces``
    bounces (and no plan with fewer bounces is as tolerant)."""

    bounces: int
    min_width: float
    plan: Plan

    @property
    def tolerance(self) -> float:
        return self.min_width / 2

    def to_json(self) -> dict:
        return {"bounces": self.bounces, "min_width": self.min_width, "tolerance": self.tolerance,
                "plan": self.plan.to_json()}


@answer_dataclass("pareto")
class ParetoFront(_Query, Answer):
    """The Pareto front bounces ↔ tolerance: the most tolerant plan for each number of bounces that helps.

    Points have strictly increasing bounces and strictly increasing min width. Every plan with b bounces has
    min width ≤ that of the last point with ≤ b bounces (proved when ``optimality.proved``). Made by
    :func:`pareto_front`.

    Attributes
    ----------
    points
        The :class:`ParetoPoint` objects (``bounces``, ``min_width`` in radians, ``plan``), fewest bounces first;
        empty when no plan exists.
    optimality
        ``optimality.bound`` is the best min width (radians) of any plan of the scope.
    status, reason
        ``found`` when there is a point; ``infeasible`` (proved, with a ``reason``) when no plan exists;
        ``not-found`` when a timeout stopped the search first.
    start, goal, max_bounces
        The query: boundary sets as text, and the bounce budget if one was given.
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of the environment.
    stats
        Times and counts (recorded, never compared).

    Examples
    --------
    >>> import solverplan as sp
    >>> front = sp.pareto_front(sp.load_environment("l_shape"), "e5", "e0:0:0.3")
    >>> [(point.bounces, round(point.min_width, 4)) for point in front.points]   # 4 more bounces: wider headings
    [(1, 0.2903), (5, 0.3794)]
    >>> front.best(3).bounces, front.optimality.proved
    (1, True)
    """

    points: tuple[ParetoPoint, ...]
    optimality: Optimality

    @property
    def status(self) -> Status:
        """Found when the front has a point; infeasible (proved by the exhaustive label setting) otherwise, or
        not-found when a limit (a timeout) stopped the search first."""
        if self.points:
            return Status.FOUND
        return Status.NOT_FOUND if self.optimality.limits else Status.INFEASIBLE

    def best(self, bounces: int | None = None) -> ParetoPoint | None:
        """The most tolerant point with at most ``bounces`` bounces (any number when None)."""
        chosen = None
        for p in self.points:
            if bounces is None or p.bounces <= bounces:
                chosen = p
        return chosen

    def _fields(self) -> dict:
        out: dict[str, Any] = {
            "objective": "tolerance",
            "front": [{"bounces": p.bounces, "min_width": p.min_width, "tolerance": p.tolerance} for p in self.points],
            "points": [p.to_json() for p in self.points],
            "start": self.start,
            "goal": self.goal,
            "max_bounces": self.max_bounces,
        }
        if not self.points:
            out["reason"] = self.reason
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> ParetoFront:
        """Read a front back: each point's plan by :func:`parse_plan`; raises :class:`MalformedFile` naming the place."""
        if not isinstance(data, dict):
            raise MalformedFile("pareto: expected a JSON object (a Pareto front)")
        raw = data.get("points")
        if not isinstance(raw, list):
            raise MalformedFile("pareto: points: expected a list of {bounces, min_width, plan}")
        points = []
        for k, item in enumerate(raw):
            if not isinstance(item, dict) or not isinstance(item.get("bounces"), int):
                raise MalformedFile(f"pareto: points[{k}]: expected an object with bounces, min_width, plan")
            points.append(ParetoPoint(item["bounces"], finite_number(item.get("min_width"), f"pareto: points[{k}].min_width"),
                                      parse_plan(item.get("plan"), f"pareto: points[{k}].plan")))
        budget = data.get("max_bounces")
        return cls(tuple(points), read_optimality(data.get("optimality"), "pareto: optimality"),
                   start=_text_or_none(data.get("start"), "pareto: start"), goal=_text_or_none(data.get("goal"), "pareto: goal"),
                   max_bounces=budget if isinstance(budget, int) and not isinstance(budget, bool) else None,
                   reason=_text_or_none(data.get("reason"), "pareto: reason"),
                   environment=read_environment(data.get("environment"), "pareto: environment"),
                   stats=read_stats(data.get("stats")))

    def to_text(self, *, width: int = 100) -> str:
        buf = io.StringIO()
        buf.write(_text_title(self, "Pareto front bounces ↔ tolerance"))
        if not self.points:
            return buf.getvalue() + _text_unanswered(self)
        buf.write(f"  {'bounces':>7}  {'min width (rad)':>16}  {'tolerance (rad)':>16}  {'tolerance (°)':>13}\n")
        for p in self.points:
            buf.write(f"  {p.bounces:>7}  {p.min_width:>16.9f}  {p.tolerance:>16.9f}  {math.degrees(p.tolerance):>13.5f}\n")
        buf.write(f"  optimality: {self.optimality.to_text()}\n")
        return buf.getvalue()


# ---------------------------------------------------------------------- reading plans back
def _int_list(value: object, where: str) -> tuple[int, ...]:
    return tuple(index_list(value, where, "segment ids (non-negative integers)"))


def parse_plan(data: object, source: str = "plan") -> Plan:
    """A :class:`Plan` from its JSON (:meth:`Plan.to_json`, or a hand-written plan in the format of docs/contract.md).

    Checks the shape and that every interval lies inside (0, π) with lo ≤ hi; segment ids are checked
    against an environment by the readers (:func:`solverplan.simulate.simulate_plan`). Raises
    :class:`~solverplan.errors.MalformedFile` (bad input, exit code 2) naming the place.

    >>> p = parse_plan({"status": "found", "objective": "fewest", "stages": [
    ...     {"from_segments": [0], "to_segments": [1], "interval": [0.1, 0.7]}]})
    >>> p.bounces, p.stages[0].moves
    (1, ((0, 1),))
    >>> parse_plan({"status": "found", "stages": [{"from_segments": [0], "to_segments": [1], "interval": [0, 0.7]}]})
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: plan: stages[0].interval [0, 0.7] is not inside (0, π)
    """
    if not isinstance(data, dict):
        raise MalformedFile(f"{source}: expected a JSON object (a plan)")
    status = data.get("status")
    if status not in ("found", "infeasible", "not-found"):
        raise MalformedFile(f"{source}: status must be 'found', 'infeasible' or 'not-found', got {quote(status)}")
    objective = data.get("objective", "fewest")
    if not isinstance(objective, str):
        raise MalformedFile(f"{source}: objective must be a string")
    raw_stages = data.get("stages", [])
    if not isinstance(raw_stages, list):
        raise MalformedFile(f"{source}: stages must be a list")
    stages = []
    for k, raw in enumerate(raw_stages):
        where = f"{source}: stages[{k}]"
        if not isinstance(raw, dict):
            raise MalformedFile(f"{where}: expected an object with from_segments, to_segments, interval")
        frm = _int_list(raw.get("from_segments"), f"{where}.from_segments")
        to = _int_list(raw.get("to_segments"), f"{where}.to_segments")
        iv = raw.get("interval")
        if not isinstance(iv, list) or len(iv) != 2:
            raise MalformedFile(f"{where}.interval: expected [lo, hi]")
        lo, hi = finite_number(iv[0], f"{where}.interval[0]"), finite_number(iv[1], f"{where}.interval[1]")
        if not (0 < lo <= hi < math.pi):
            raise MalformedFile(f"{where}.interval [{iv[0]}, {iv[1]}] is not inside (0, π)")
        if not frm or not to:
            raise MalformedFile(f"{where}: from_segments and to_segments must not be empty")
        raw_moves = raw.get("moves")
        if raw_moves is None:
            if len(to) != 1 and len(frm) != 1:
                raise MalformedFile(f"{where}: several sources and targets need 'moves' ([source, target] pairs)")
            moves = tuple((i, to[0]) for i in frm) if len(to) == 1 else ()
        else:
            if not isinstance(raw_moves, list) or not all(isinstance(m, list) and len(m) == 2 for m in raw_moves):
                raise MalformedFile(f"{where}.moves: expected a list of [source, target] pairs")
            moves = tuple((int(m[0]), int(m[1])) for m in raw_moves)
        sources = _sources(raw.get("sources"), moves, f"{where}.sources")
        if raw_moves is not None:
            # one pair per source (piece), or one per segment of the run of collinear segments it lands on
            keys = list(zip(moves, sources)) if sources else moves
            if {i for i, _ in moves} != set(frm) or {j for _, j in moves} != set(to) or len(set(keys)) != len(keys):
                raise MalformedFile(f"{where}.moves: the pairs must use every from_segment, reach exactly to_segments "
                                    "and not repeat")
        left = raw.get("margins")
        margins = None
        if left is not None:
            if not isinstance(left, list) or len(left) != 2:
                raise MalformedFile(f"{where}.margins: expected [lo, hi] (radians)")
            margins = (finite_number(left[0], f"{where}.margins[0]"), finite_number(left[1], f"{where}.margins[1]"))
        stages.append(Stage(frm, tuple(sorted(set(to))), Interval(lo, hi), moves=moves, sources=sources, margins=margins))
    for k in range(1, len(stages)):
        if set(stages[k].from_segments) != set(stages[k - 1].to_segments):
            raise MalformedFile(f"{source}: stages[{k}].from_segments must be stages[{k - 1}].to_segments")
    if status == "found" and data.get("bounces") is not None and data.get("bounces") != len(stages):
        raise MalformedFile(f"{source}: bounces is {quote(data.get('bounces'))} but there are {len(stages)} stages")
    optimality = (read_optimality(data["optimality"], f"{source}: optimality") if "optimality" in data
                  else Optimality(Method.NONE, False, None))
    start, goal = data.get("start"), data.get("goal")
    for name, value in (("start", start), ("goal", goal)):
        if value is not None and not isinstance(value, str):
            raise MalformedFile(f"{source}: {name} must be a boundary-set string like 'e3:0.25:0.75,e4'")
    environment = read_environment(data.get("environment"), f"{source}: environment")
    max_bounces = data.get("max_bounces")
    return Plan(
        status=Status(status),
        objective=objective,
        stages=tuple(stages) if status == "found" else (),
        optimality=optimality,
        reason=data.get("reason") if status != "found" else None,
        start=start,
        goal=goal,
        max_bounces=max_bounces if isinstance(max_bounces, int) and not isinstance(max_bounces, bool) else None,
        environment=environment,
        margins=data.get("margins") or {},
        stats=read_stats(data.get("stats")),
    )


def _text_or_none(value: object, where: str) -> str | None:
    if value is not None and not isinstance(value, str):
        raise MalformedFile(f"{where}: expected a string or null, got {quote(value)}")
    return value


def read_stats(data: object) -> Stats:
    """The :class:`~solverplan.result.Stats` of an answer's JSON (empty when missing; stats are never checked)."""
    if not isinstance(data, dict):
        return Stats()
    known = {k: data[k] for k in ("seconds_setup", "seconds_search", "expanded") if k in data}
    return Stats(**known, counts={k: v for k, v in data.items() if k not in known})


def _sources(raw: object, moves: tuple[tuple[int, int], ...], where: str) -> tuple[BoundaryPiece, ...]:
    """A plan stage's exact source pieces (``[{"edge", "t0_exact", "t1_exact", ...}]``, one per move), or ``()``."""
    if raw is None:
        return ()
    if not isinstance(raw, list) or len(raw) != len(moves):
        raise MalformedFile(f"{where}: expected one piece per move ({len(moves)})")
    out = []
    for k, item in enumerate(raw):
        if not isinstance(item, dict) or not isinstance(item.get("edge"), int) or isinstance(item.get("edge"), bool):
            raise MalformedFile(f"{where}[{k}]: expected an object with edge, t0_exact, t1_exact")
        try:
            t0, t1 = (to_fraction(item.get(key), where=f"{where}[{k}].{key}") for key in ("t0_exact", "t1_exact"))
        except InputError as exc:
            raise MalformedFile(str(exc)) from None
        if not 0 <= t0 < t1 <= 1:
            raise MalformedFile(f"{where}[{k}]: needs 0 ≤ t0 < t1 ≤ 1")
        out.append(BoundaryPiece(item["edge"], t0, t1))
    return tuple(out)


def load_plan(path: str | Path) -> Plan:
    """Read a plan file written by ``solverplan plan -o PLAN.json`` (see :func:`parse_plan`).

    Parameters
    ----------
    path
        The plan file (JSON, ``docs/contract.md``).

    Returns
    -------
    Plan
        The plan as written, exact where the file is (stages, intervals, optimality); ``stats`` are not read.

    Raises
    ------
    MalformedFile
        A missing or unreadable file, invalid JSON, or JSON that is not a plan (the message names the field).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("l_shape"), "e5", "e0:0:0.3")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plan.json"
    >>> _ = path.write_text(json.dumps(plan.to_json()))
    >>> sp.load_plan(path) == plan               # stats are not compared
    True
    """
    path = Path(path)
    text = read_input_text(path)  # regular files only, never read past the limit (solverplan._io)
    name = shown_path(path)
    try:
        data = read_json(text, exact=False)  # bounded nesting and number sizes (solverplan.limits)
    except json.JSONDecodeError as exc:
        raise MalformedFile(f"{name}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except MalformedFile as exc:
        raise MalformedFile(f"{name}: {exc}") from None
    return parse_plan(data, name)
