"""What the planners return: :class:`Plan` (docs/contract.md, "A plan"), :class:`ParetoFront`, and how
optimality was established (:class:`Optimality`).

Results are frozen dataclasses; :meth:`Plan.to_json` is the only place a plan becomes a dict, and
:func:`parse_plan` / :func:`load_plan` read one back (for ``solverplan simulate`` and ``render --plan``).

A plan's JSON is docs/contract.md's ``{"status", "objective", "bounces", "min_width", "tolerance", "stages":
[{"from_segments", "to_segments", "interval"}], "optimality": {"method", "proved", "bound"}, "reason"}``
plus, for its readers: per stage the ``moves`` ([source, target] segment pairs, one per source: where the
robot lands from each possible segment) and ``width``; the query (``start``, ``goal``, ``max_bounces``),
the environment (``environment``: name, SHA-256 of its canonical JSON text, number of P′ segments), the
heading margins the admissible intervals were built with, ``sum_width`` and ``stats`` (recorded, never
asserted). Headings are radians in (0, π), measured counter-clockwise from the wall the robot is on.

>>> plan = Plan.infeasible("fewest", "goal segments have no incoming safe arc",
...                        Optimality("search-exhausted", True, None, algorithm="precheck"))
>>> plan.to_json()["status"], plan.to_json()["reason"], plan.bounces
('infeasible', 'goal segments have no incoming safe arc', None)
"""

from __future__ import annotations

import hashlib
import io
import json
import math
from dataclasses import dataclass, field, replace
from enum import StrEnum
from pathlib import Path
from typing import Any, Literal

from solverplan.interval import Interval
from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.exact import format_number

__all__ = [
    "Status",
    "Objective",
    "OBJECTIVES",
    "Optimality",
    "Stage",
    "Plan",
    "ParetoPoint",
    "ParetoFront",
    "parse_plan",
    "load_plan",
    "environment_record",
]


def environment_record(env: Environment, n_segments: int | None = None) -> dict:
    """``{"name", "sha256", "n_segments"}``: identifies the environment a plan was made in (the digest is
    over the exact normalised rings, so it does not depend on the name or the file format)."""
    rings = [[[format_number(x), format_number(y)] for x, y in ring] for ring in env.rings]
    digest = hashlib.sha256(json.dumps(rings, separators=(",", ":")).encode()).hexdigest()
    out: dict[str, Any] = {"name": env.name, "sha256": digest}
    if n_segments is not None:
        out["n_segments"] = n_segments
    return out


class Status(StrEnum):
    """A plan was found, or none exists (proven: an answer with exit code 0, never an exception)."""

    FOUND = "found"
    INFEASIBLE = "infeasible"


Objective = Literal["fewest", "tolerance", "sum", "constant"]
OBJECTIVES: tuple[str, ...] = ("fewest", "tolerance", "sum", "constant")


@dataclass(frozen=True, slots=True)
class Optimality:
    """How optimality was established.

    ``method``: ``search-exhausted`` (a label-setting / breadth-first search over every belief state
    that could matter ran to completion), ``lp-duality`` (an LP solved to optimality; ``gap`` is the
    primal–dual gap) or ``milp`` (a MILP solved to optimality; ``gap`` is the solver's absolute gap).
    ``proved``: the claim holds for every plan over the admissible intervals (see
    :func:`solverplan.plan.find_plan`). ``bound``: the best value any plan could reach, in the units the
    certificate checker expects: bounces for ``fewest``, the narrowest interval's width (radians) for
    ``tolerance`` and ``constant``, the sum of widths for ``sum``; ``None`` when no plan exists.
    ``algorithm`` says which search ran.
    """

    method: str
    proved: bool
    bound: float | None
    algorithm: str = ""
    gap: float | None = None

    def to_json(self) -> dict:
        out: dict[str, Any] = {"method": self.method, "proved": self.proved, "bound": self.bound}
        if self.algorithm:
            out["algorithm"] = self.algorithm
        if self.gap is not None:
            out["gap"] = self.gap
        return out

    @classmethod
    def from_json(cls, data: object, where: str = "optimality") -> Optimality:
        if not isinstance(data, dict):
            raise MalformedFile(f"{where}: expected an object with method, proved, bound")
        method = data.get("method")
        proved = data.get("proved")
        bound = data.get("bound")
        if not isinstance(method, str) or not isinstance(proved, bool):
            raise MalformedFile(f"{where}: method must be a string and proved a boolean")
        if bound is not None and (isinstance(bound, bool) or not isinstance(bound, (int, float))):
            raise MalformedFile(f"{where}.bound: expected a number or null, got {bound!r}")
        gap = data.get("gap")
        if gap is not None and (isinstance(gap, bool) or not isinstance(gap, (int, float))):
            raise MalformedFile(f"{where}.gap: expected a number or null, got {gap!r}")
        return cls(method, proved, None if bound is None else float(bound), str(data.get("algorithm", "")),
                   None if gap is None else float(gap))


@dataclass(frozen=True, slots=True)
class Stage:
    """One bounce of a plan.

    ``from_segments``: the P′ segments the robot may be on (its belief); ``interval``: the heading
    interval it executes (radians, CCW from the wall it is on, inside (0, π)); ``moves``: for each
    possible source the segment it lands on, whatever heading of ``interval`` it executes;
    ``to_segments``: the segments it may land on (the next belief), sorted.
    """

    from_segments: tuple[int, ...]
    to_segments: tuple[int, ...]
    interval: Interval
    moves: tuple[tuple[int, int], ...]

    @property
    def width(self) -> float:
        return self.interval.width

    def to_json(self) -> dict:
        return {
            "from_segments": list(self.from_segments),
            "to_segments": list(self.to_segments),
            "interval": [self.interval.lo, self.interval.hi],
            "width": self.interval.width,
            "moves": [[i, j] for i, j in self.moves],
        }


@dataclass(frozen=True)
class Plan:
    """A plan (docs/contract.md): heading intervals, one per bounce, that take the robot from every point of
    the start set to the goal set whatever headings inside the intervals it executes — or a proof
    that there is none (``status == "infeasible"`` with a ``reason``).

    ``min_width`` is the narrowest interval's width (radians), ``tolerance`` = min_width / 2 (the
    precision the robot needs), ``sum_width`` the sum of the widths; all ``None`` when infeasible.
    ``bounces`` is the number of stages (0 when the start set already lies in the goal set).
    """

    status: Status
    objective: str
    stages: tuple[Stage, ...]
    optimality: Optimality
    reason: str | None = None
    start: str | None = None
    goal: str | None = None
    max_bounces: int | None = None
    environment: dict = field(default_factory=dict)
    margins: dict = field(default_factory=dict)
    stats: dict = field(default_factory=dict, compare=False)

    # ------------------------------------------------------------------ construction
    @classmethod
    def infeasible(cls, objective: str, reason: str, optimality: Optimality, **extra: Any) -> Plan:
        return cls(Status.INFEASIBLE, objective, (), optimality, reason=reason, **extra)

    def with_(self, **changes: Any) -> Plan:
        """A copy with some fields changed."""
        return replace(self, **changes)

    # ------------------------------------------------------------------ numbers
    @property
    def found(self) -> bool:
        return self.status is Status.FOUND

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
    def intervals(self) -> tuple[Interval, ...]:
        return tuple(s.interval for s in self.stages)

    def check_environment(self, env: Environment, n_segments: int) -> None:
        """Raise :class:`InputError` unless the plan can be executed in ``env`` (whose partition has
        ``n_segments`` segments): same exact rings when the plan records them, known segment ids."""
        recorded = self.environment.get("sha256") if self.environment else None
        if recorded is not None and recorded != environment_record(env)["sha256"]:
            name = self.environment.get("name", "?")
            raise InputError(f"the plan was made in another environment ({name!r}, sha256 {recorded[:12]}…), not in {env.name!r}")
        for k, stage in enumerate(self.stages):
            for seg in (*stage.from_segments, *stage.to_segments):
                if not 0 <= seg < n_segments:
                    raise InputError(f"plan stage {k} names segment {seg}, but the partition of {env.name!r} has segments "
                                     f"0..{n_segments - 1}")

    # ------------------------------------------------------------------ output
    def to_json(self) -> dict:
        """The plan of docs/contract.md, then the extra fields described in the module docstring."""
        out: dict[str, Any] = {
            "status": self.status.value,
            "objective": self.objective,
            "bounces": self.bounces,
            "min_width": self.min_width,
            "tolerance": self.tolerance,
            "stages": [s.to_json() for s in self.stages],
            "optimality": self.optimality.to_json(),
        }
        if not self.found:
            out["reason"] = self.reason
        out["sum_width"] = self.sum_width
        out["start"] = self.start
        out["goal"] = self.goal
        out["max_bounces"] = self.max_bounces
        if self.environment:
            out["environment"] = dict(self.environment)
        if self.margins:
            out["margins"] = dict(self.margins)
        if self.stats:
            out["stats"] = dict(self.stats)
        return out

    def to_text(self, *, width: int = 100) -> str:
        """A table like the paper's (§7.1.2): stage, from, to, interval, width."""
        buf = io.StringIO()
        env = self.environment.get("name") or "environment"
        query = f"from {self.start} to {self.goal}" if self.start else ""
        budget = f", at most {self.max_bounces} bounces" if self.max_bounces is not None else ""
        buf.write(f"{self.objective} plan in {env!r} {query}{budget}\n")
        opt = self.optimality
        proof = "proved" if opt.proved else "not proved"
        bound = "" if opt.bound is None else f", bound {opt.bound:.10g}"
        gap = "" if opt.gap is None else f", gap {opt.gap:.3g}"
        algorithm = f" ({opt.algorithm})" if opt.algorithm else ""
        if not self.found:
            buf.write(f"  infeasible: {self.reason}\n")
            buf.write(f"  optimality: {opt.method}{algorithm}, {proof}{bound}\n")
            return buf.getvalue()
        buf.write(f"  bounces {self.bounces}   min width {self.min_width:.6f} rad   tolerance ±{self.tolerance:.6f} rad "
                  f"(±{math.degrees(self.tolerance or 0.0):.4f}°)   sum of widths {self.sum_width:.6f}\n")
        buf.write(f"  optimality: {opt.method}{algorithm}, {proof}{bound}{gap}\n")
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


@dataclass(frozen=True)
class ParetoFront:
    """The Pareto front bounces ↔ tolerance: points with strictly increasing bounces and strictly
    increasing min width. Every plan with b bounces has min width ≤ that of the last point with
    ≤ b bounces (proved when ``optimality.proved``). Empty (``status`` infeasible) when no plan exists."""

    points: tuple[ParetoPoint, ...]
    optimality: Optimality
    start: str | None = None
    goal: str | None = None
    max_bounces: int | None = None
    reason: str | None = None
    environment: dict = field(default_factory=dict)
    stats: dict = field(default_factory=dict, compare=False)

    @property
    def status(self) -> Status:
        return Status.FOUND if self.points else Status.INFEASIBLE

    def best(self, bounces: int | None = None) -> ParetoPoint | None:
        """The most tolerant point with at most ``bounces`` bounces (any number when None)."""
        chosen = None
        for p in self.points:
            if bounces is None or p.bounces <= bounces:
                chosen = p
        return chosen

    def to_json(self) -> dict:
        out: dict[str, Any] = {
            "status": self.status.value,
            "objective": "tolerance",
            "front": [{"bounces": p.bounces, "min_width": p.min_width, "tolerance": p.tolerance} for p in self.points],
            "points": [p.to_json() for p in self.points],
            "optimality": self.optimality.to_json(),
            "start": self.start,
            "goal": self.goal,
            "max_bounces": self.max_bounces,
        }
        if not self.points:
            out["reason"] = self.reason
        if self.environment:
            out["environment"] = dict(self.environment)
        if self.stats:
            out["stats"] = dict(self.stats)
        return out

    def to_text(self, *, width: int = 100) -> str:
        buf = io.StringIO()
        env = self.environment.get("name") or "environment"
        budget = f", at most {self.max_bounces} bounces" if self.max_bounces is not None else ""
        buf.write(f"Pareto front bounces ↔ tolerance in {env!r} from {self.start} to {self.goal}{budget}\n")
        if not self.points:
            buf.write(f"  infeasible: {self.reason}\n")
            return buf.getvalue()
        buf.write(f"  {'bounces':>7}  {'min width (rad)':>16}  {'tolerance (rad)':>16}  {'tolerance (°)':>13}\n")
        for p in self.points:
            buf.write(f"  {p.bounces:>7}  {p.min_width:>16.9f}  {p.tolerance:>16.9f}  {math.degrees(p.tolerance):>13.5f}\n")
        opt = self.optimality
        buf.write(f"  optimality: {opt.method} ({opt.algorithm}), {'proved' if opt.proved else 'not proved'}\n")
        return buf.getvalue()


# ---------------------------------------------------------------------- reading plans back
def _int_list(value: object, where: str) -> tuple[int, ...]:
    if not isinstance(value, list) or not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in value):
        raise MalformedFile(f"{where}: expected a list of segment ids (non-negative integers)")
    return tuple(value)


def _number(value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise MalformedFile(f"{where}: expected a finite number, got {value!r}")
    return float(value)


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
    if status not in ("found", "infeasible"):
        raise MalformedFile(f"{source}: status must be 'found' or 'infeasible', got {status!r}")
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
        lo, hi = _number(iv[0], f"{where}.interval[0]"), _number(iv[1], f"{where}.interval[1]")
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
            if sorted(i for i, _ in moves) != sorted(frm) or set(j for _, j in moves) != set(to):
                raise MalformedFile(f"{where}.moves: the pairs must use each from_segment once and reach exactly to_segments")
        stages.append(Stage(frm, tuple(sorted(set(to))), Interval(lo, hi), moves))
    for k in range(1, len(stages)):
        if set(stages[k].from_segments) != set(stages[k - 1].to_segments):
            raise MalformedFile(f"{source}: stages[{k}].from_segments must be stages[{k - 1}].to_segments")
    if status == "found" and data.get("bounces") is not None and data.get("bounces") != len(stages):
        raise MalformedFile(f"{source}: bounces is {data.get('bounces')!r} but there are {len(stages)} stages")
    optimality = (Optimality.from_json(data["optimality"], f"{source}: optimality") if "optimality" in data
                  else Optimality("unknown", False, None))
    start, goal = data.get("start"), data.get("goal")
    for name, value in (("start", start), ("goal", goal)):
        if value is not None and not isinstance(value, str):
            raise MalformedFile(f"{source}: {name} must be a boundary-set string like 'e3:0.25:0.75,e4'")
    environment = data.get("environment") or {}
    if not isinstance(environment, dict):
        raise MalformedFile(f"{source}: environment must be an object")
    max_bounces = data.get("max_bounces")
    return Plan(
        status=Status(status),
        objective=objective,
        stages=tuple(stages) if status == "found" else (),
        optimality=optimality,
        reason=data.get("reason") if status == "infeasible" else None,
        start=start,
        goal=goal,
        max_bounces=max_bounces if isinstance(max_bounces, int) and not isinstance(max_bounces, bool) else None,
        environment=environment,
        margins=data.get("margins") or {},
    )


def load_plan(path: str | Path) -> Plan:
    """Read a plan file written by ``solverplan plan -o PLAN.json`` (see :func:`parse_plan`)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise MalformedFile(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MalformedFile(f"{path}: cannot read ({exc.__class__.__name__})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MalformedFile(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    return parse_plan(data, str(path))
