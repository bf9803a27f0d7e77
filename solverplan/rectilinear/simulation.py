"""Bouncing through rooms and doors: the rules of the rooms paper compared by simulation (its §VIII, Table I).

A robot starts at a uniform random point of the start room, moving in a uniform random direction (the paper's
"random point in the starting room, with random movement vector"), and bounces by one of the rules of
:mod:`solverplan.rectilinear.rules` until it is in the target room or has made ``max_bounces`` bounces.
Doors follow the paper's door control (:class:`~solverplan.rectilinear.doors.DoorControl`) for the room
sequence from start to target, for every rule alike (``doors="control"``), or are all open
(``doors="open"``). Runs go through the simulator (:func:`solverplan.rollout.simulate_policy`) with the
rooms as its walls; a run that reaches the target room counts its bounces (a pass through an open door is not
a bounce; a bounce off a closed door is).

**Trapped runs.** A deterministic rule (billiard, smart) that has not reached the target within the budget may
be caught in a periodic orbit. Such a run is replayed in exact rational arithmetic (:func:`periodic_orbit`; its
start rounded to a nearby rational point and slope, to 1e-6): the exact state — the wall hit, the exact point, the exact direction
of travel, the position in the room sequence and the smart rule's bit — is remembered at every bounce, and the
run is *trapped* when a state repeats before the target is reached (then it never gets there). Runs that
neither reach the target nor repeat within the budget are only "not reached".

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear import decompose_rooms
>>> dec = decompose_rooms(load_environment("three_chambers"))
>>> runs = simulate_rooms(dec, 0, 2, rule="smart", trials=20, seed=1, max_bounces=3000)
>>> runs.success, runs.outcomes["goal"]
(1.0, 20)
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Sequence

import numpy as np

from solverplan.choices import DoorPolicy
from solverplan.limits import refuse_beyond_memory
from solverplan.errors import InputError
from solverplan.exact import format_number
from solverplan.result import answer_dataclass
from solverplan.geometry.raycast import cast_rays_exact
from solverplan.rectilinear.decomposition import Decomposition
from solverplan.rectilinear.doors import DoorControl, RoomWorld
from solverplan.rectilinear.metrics import RuleRecommendation, recommend_rule
from solverplan.rectilinear.rules import GUARANTEED, GUARANTEES, RULE_VARIANTS, RULES, Rule, Smart, make_rule
from solverplan.rollout import Contacts, Outcome, simulate_policy

__all__ = ["RoomPolicy", "RoomRuns", "RuleComparison", "RouteRecommendation", "simulate_rooms", "compare_rules",
           "recommend_from_runs", "periodic_orbit", "DEFAULT_MAX_BOUNCES", "RULE_VARIANTS", "NEAR_FASTEST"]

DEFAULT_MAX_BOUNCES = 5000
"""Bounce budget of a run when none is given (the smart rule sweeps a room in steps of half a door)."""

Doors = DoorPolicy | str


class RoomPolicy:
    """A rule executed in the rooms of a decomposition, with door control (:class:`solverplan.rollout.Policy`
    with its own :class:`~solverplan.rollout.PolicyWalls`).

    The robot of rollout i is at position ``positions[i]`` of the room sequence; it reaches the goal when it is
    at the last one. Without control (``control=None``) every door is open and the goal is being in ``goal``.
    """

    def __init__(self, dec: Decomposition, rule: Rule, walk: Sequence[int], initial: np.ndarray, *,
                 doors: Doors = "control") -> None:
        self.dec = dec
        self.rule = rule
        self.control = DoorControl(dec, walk)
        self.doors = DoorPolicy.parse(doors, "door policy").value
        self.initial = np.asarray(initial, dtype=float)
        self.positions = np.zeros(len(self.initial), dtype=np.int64)
        self.walls = RoomWorld(dec, is_open=None if doors == "open" else self._is_open)

    def _is_open(self, rollouts: np.ndarray, doors: np.ndarray) -> np.ndarray:
        return self.control.is_open(self.positions[rollouts], doors)

    def headings(self, contacts: Contacts, rng: np.random.Generator) -> np.ndarray:
        if contacts.step == 0:
            return self.initial[contacts.rollout]
        return self.rule.headings(self.walls, contacts.edge, contacts.incoming, contacts.step, rng)

    def check(self, contacts: Contacts) -> np.ndarray:
        out = np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)
        rooms = self.walls.room_of[contacts.edge]
        if self.doors == "open":
            out[rooms == self.control.walk[-1]] = Outcome.GOAL
            return out
        if contacts.step == 0:
            self.positions[:] = 0
        new, ok = self.control.advance(self.positions[contacts.rollout], rooms)
        self.positions[contacts.rollout] = new
        out[~ok] = Outcome.FAILED  # left the sequence through a door that should have been closed: never seen
        out[ok & (new == self.control.last)] = Outcome.GOAL
        return out

    def __str__(self) -> str:
        return f"{self.rule.name} rule, doors {self.doors}"


@answer_dataclass("rooms-simulation")
class RoomRuns:
    """Runs of one rule from a start room to a target room (module docstring).

    ``success`` is the share of runs that reached the target within ``max_bounces``; ``bounces`` the bounce
    counts of those runs; ``trapped`` the number of deterministic runs proved caught in a periodic orbit
    (``None`` for the random rule); ``outcomes`` the simulator's counts (``vertex`` / ``tie``: runs stopped
    where the float caster could not call a ray, at a corner).
    """

    rule: str
    walk: tuple[int, ...]
    trials: int
    max_bounces: int
    seed: int | None
    doors: str
    success: float
    bounces: tuple[int, ...]
    outcomes: dict[str, int]
    trapped: int | None
    theta: float | None = None
    theta_tangent: Fraction | None = None
    trajectories: tuple[np.ndarray, ...] = field(default=(), repr=False)
    recommendation: RuleRecommendation | None = None
    theta_mode: str | None = None
    advice: RouteRecommendation | None = None

    @property
    def variant(self) -> str:
        """The rule's name in :data:`RULE_VARIANTS` (the smart rule named by its θ mode)."""
        if self.rule == "smart" and self.theta_mode in ("paper", "per-room"):
            return f"smart-{self.theta_mode}"
        return self.rule

    @property
    def always_arrived(self) -> bool:
        """Every run reached the target (none trapped, none out of budget, none stopped at a corner)."""
        return self.success == 1.0 and not self.trapped

    @property
    def bounces_mean(self) -> float | None:
        return float(np.mean(self.bounces)) if self.bounces else None

    @property
    def bounces_median(self) -> float | None:
        return float(np.median(self.bounces)) if self.bounces else None

    def to_json(self) -> dict:
        out: dict[str, Any] = {
            "kind": "rooms-simulation",
            "rule": self.rule, "from": self.walk[0], "to": self.walk[-1], "rooms": list(self.walk),
            "trials": self.trials, "max_bounces": self.max_bounces, "seed": self.seed, "doors": self.doors,
            "success": self.success, "bounces_mean": self.bounces_mean, "bounces_median": self.bounces_median,
            "bounces_max": max(self.bounces) if self.bounces else None,
            "trapped": self.trapped, "outcomes": self.outcomes,
        }
        if self.theta is not None:
            out["theta"] = self.theta
            out["theta_tangent_exact"] = format_number(self.theta_tangent) if self.theta_tangent is not None else None
            out["theta_mode"] = self.theta_mode
        out["guarantee"] = GUARANTEES.get(self.variant)
        if self.recommendation is not None:
            out.update(_recommendation_json(self.recommendation, self.advice))
        return out

    def row(self) -> str:
        mean = "-" if self.bounces_mean is None else f"{self.bounces_mean:.1f}"
        median = "-" if self.bounces_median is None else f"{self.bounces_median:g}"
        trapped = "-" if self.trapped is None else str(self.trapped)
        flagged = self.outcomes.get("vertex", 0) + self.outcomes.get("tie", 0)
        return f"{self.variant:<15} {self.success:>8.3f} {mean:>10} {median:>8} {trapped:>8} {flagged:>8}"

    def to_text(self, *, width: int = 100) -> str:
        return _table([self], self.walk, self.trials, self.max_bounces, self.seed, self.doors)


def _recommendation_json(rec: RuleRecommendation, advice: RouteRecommendation | None) -> dict:
    out: dict[str, Any] = {"reachability": float(rec.reachability.psi),
                           "reachability_exact": format_number(rec.reachability.psi),
                           "recommended": rec.rule if advice is None else advice.rule,
                           "paper_recommendation": rec.rule}
    if advice is not None:
        out["recommendation"] = advice.to_json()
    return out


NEAR_FASTEST = 1.2
"""A rule that guarantees arrival is preferred to a faster one without a guarantee when its mean is within this
factor of the fastest rule that arrived in every run."""


@dataclass(frozen=True)
class RouteRecommendation:
    """Which rule to use on one route, from simulated bounces per rule (:func:`recommend_from_runs`).

    ``rule`` the recommendation; ``fastest`` the rule with the fewest mean bounces among those that arrived in
    every run (``None`` if none did); ``guaranteed`` the rules that guarantee arrival (:data:`GUARANTEES`);
    ``means`` and ``success`` per rule; ``reason`` one sentence.
    """

    rule: str
    fastest: str | None
    always_arrived: tuple[str, ...]
    guaranteed: tuple[str, ...]
    means: dict[str, float | None]
    success: dict[str, float]
    reason: str

    def to_json(self) -> dict:
        return {"rule": self.rule, "fastest_always_arrived": self.fastest, "always_arrived": list(self.always_arrived),
                "guaranteed": list(self.guaranteed), "bounces_mean": self.means, "success": self.success,
                "guarantees": {name: GUARANTEES.get(name) for name in self.means}, "reason": self.reason}


def recommend_from_runs(runs: dict[str, RoomRuns]) -> RouteRecommendation:
    """The cost-aware recommendation for a route from runs of several rules (the same starts for each).

    Among the rules that arrived in every run, the fastest (fewest mean bounces); a rule that also *guarantees*
    arrival (:data:`~solverplan.rectilinear.rules.GUARANTEES`) is preferred when it is within
    :data:`NEAR_FASTEST` of it. When no rule arrived every time, the rule with the highest success, then the
    fewest bounces. The recommendation is measured, not proved: it holds for the starts simulated.
    """
    if not runs:
        raise InputError("a recommendation needs the runs of at least one rule")
    by_variant = {r.variant: r for r in runs.values()}
    means = {name: r.bounces_mean for name, r in by_variant.items()}
    success = {name: r.success for name, r in by_variant.items()}
    arrived = tuple(name for name, r in by_variant.items() if r.always_arrived and r.bounces_mean is not None)
    guaranteed = tuple(name for name in by_variant if name in GUARANTEED)
    if arrived:
        fastest = min(arrived, key=lambda name: (means[name], name))
        safe = [name for name in arrived if name in GUARANTEED]
        best_safe = min(safe, key=lambda name: (means[name], name)) if safe else None
        if best_safe is not None and means[best_safe] <= NEAR_FASTEST * means[fastest]:  # type: ignore[operator]
            rule = best_safe
            reason = (f"{rule} arrived in every run with {means[rule]:.1f} bounces on average and guarantees arrival"
                      + ("" if rule == fastest else f" (the fastest, {fastest}, {means[fastest]:.1f}, does not)"))
        else:
            rule = fastest
            reason = (f"{rule} arrived in every run with the fewest bounces ({means[rule]:.1f} on average)"
                      + (f"; the fastest rule with a guarantee, {best_safe}, took {means[best_safe]:.1f}"
                         if best_safe is not None else "; no rule with a guarantee arrived every time"))
        return RouteRecommendation(rule, fastest, arrived, guaranteed, means, success, reason)
    rule = max(by_variant, key=lambda name: (success[name], -(means[name] or float("inf")), name))
    return RouteRecommendation(rule, None, (), guaranteed, means, success,
                               f"no rule arrived in every run; {rule} arrived most often ({success[rule]:.3f})")


def _table(runs: Sequence[RoomRuns], walk: tuple[int, ...], trials: int, max_bounces: int, seed: int | None, doors: str) -> str:
    lines = [f"rooms {walk[0]} → {walk[-1]} (through {', '.join(map(str, walk))}), {trials} runs per rule, "
             f"up to {max_bounces} bounces, seed {seed}, doors {doors}",
             f"{'rule':<15} {'success':>8} {'mean':>10} {'median':>8} {'trapped':>8} {'flagged':>8}"]
    lines += [r.row() for r in runs]
    rec = runs[0].recommendation if runs else None
    advice = runs[0].advice if runs else None
    if rec is not None:
        lines.append(f"reachability Ψ = {format_number(rec.reachability.psi)} ≈ {float(rec.reachability.psi):.4g}: "
                     f"the paper's rule {rec.rule}")
    if advice is not None:
        lines.append(f"recommended rule {advice.rule}: {advice.reason}")
    lines.append("mean, median: bounces of the runs that reached the target; trapped: deterministic runs proved "
                 "periodic (exact); flagged: runs stopped at a corner")
    return "\n".join(lines) + "\n"


@answer_dataclass("rooms-rules")
class RuleComparison:
    """The rules side by side (the paper's Table I): ``runs[name]`` for each rule, the same starts for all."""

    runs: dict[str, RoomRuns]

    def to_json(self) -> dict:
        out: dict[str, Any] = {"kind": "rooms-rules", "rules": {name: r.to_json() for name, r in self.runs.items()}}
        first = next(iter(self.runs.values()))
        out["rooms"] = list(first.walk)
        if first.recommendation is not None:
            out.update(_recommendation_json(first.recommendation, first.advice))
        return out

    def to_text(self, *, width: int = 100) -> str:
        first = next(iter(self.runs.values()))
        return _table(list(self.runs.values()), first.walk, first.trials, first.max_bounces, first.seed, first.doors)


def _check_count(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def simulate_rooms(
    dec: Decomposition,
    start: int,
    goal: int,
    *,
    rule: str = "smart",
    trials: int = 100,
    seed: int | None = 0,
    max_bounces: int = DEFAULT_MAX_BOUNCES,
    doors: Doors = "control",
    walk: Sequence[int] | None = None,
    keep: int = 0,
    trapped: bool = True,
    per_room: bool = False,
    theta: str = "safe",
) -> RoomRuns:
    """Run ``trials`` robots of ``rule`` from room ``start`` to room ``goal`` (module docstring).

    Parameters
    ----------
    dec
        A room decomposition (:func:`solverplan.rectilinear.decompose_rooms`).
    start, goal
        Room ids.
    rule
        ``smart``, ``random`` or ``billiard``.
    trials, seed, max_bounces
        Number of robots, the seed of their starts (and of the random rule), the bounce budget of each.
    doors
        ``control`` (the paper's door control for the room sequence) or ``open`` (every door open).
    walk
        The room sequence (default: the tree path from ``start`` to ``goal``; a tour from
        :meth:`Decomposition.tour` makes the target "every room in turn"); it must start at ``start`` and end at
        ``goal``.
    keep
        How many trajectories to keep (their contact points, for pictures).
    trapped
        Replay the deterministic runs that did not arrive, exactly, to find those caught in a periodic orbit.
    per_room
        Give the smart robot the θ of the room it is in (:func:`~solverplan.rectilinear.rules.room_tangents`)
        instead of the least θ of the whole sequence (the same as ``theta="per-room"``).
    theta
        The smart rule's θ mode (:data:`~solverplan.rectilinear.rules.THETA_MODES`): ``safe``, ``paper`` or
        ``per-room``; ``rule`` may also name a variant (``smart-paper``, ``smart-per-room``).

    Returns
    -------
    RoomRuns
        The share of robots that reached ``goal`` within ``max_bounces`` (``success``), their bounce counts, the
        deterministic runs proved trapped in a periodic orbit, and the θ the smart rule used (radians).

    Raises
    ------
    InputError
        Unknown rooms or rule, a walk that does not join ``start`` to ``goal`` through doors, bad counts.

    Examples
    --------
    >>> import solverplan as sp
    >>> rooms = sp.decompose_rooms(sp.load_environment("l_shape"))
    >>> runs = sp.simulate_rooms(rooms, 0, 1, trials=20, seed=1)          # 20 smart robots from room 0 to room 1
    >>> runs.success, runs.outcomes["goal"], runs.theta_tangent, runs.bounces_median
    (1.0, 20, Fraction(1, 5), 3.0)
    """
    trials = _check_count("trials", trials, 1)
    max_bounces = _check_count("max_bounces", max_bounces, 1)
    dec.check_room(start)
    dec.check_room(goal)
    walk = tuple(walk) if walk is not None else dec.path(start, goal)
    if walk[0] != start or walk[-1] != goal:
        raise InputError(f"the room sequence must go from room {start} to room {goal}")
    # the starts, headings and room positions (about 64 bytes a robot) come before the rollouts' own
    # estimate (simulate_policy's 400 bytes a rollout plus 16 a recorded contact): refuse both up front
    recorded = max_bounces + 1 if keep else 2
    refuse_beyond_memory(trials * (464 + 16 * recorded), f"{trials:,} robots of {max_bounces:,} bounces")
    chosen = make_rule(rule, dec, walk, per_room=per_room, theta=theta)
    mode = {"smart-paper": "paper", "smart-per-room": "per-room"}.get(rule, "per-room" if per_room else theta)
    rng = np.random.default_rng(seed)
    world = RoomWorld(dec)
    edges, t, headings = world.starts_in(start, trials, rng)
    policy = RoomPolicy(dec, chosen, walk, headings, doors=doors)
    runs = simulate_policy(dec.env, policy, (edges, t), bounces=max_bounces, trials=trials, seed=rng,
                           record="all" if keep else "ends")
    reached = runs.status == Outcome.GOAL
    kept = tuple(runs.path(k) for k in range(min(keep, trials)))
    n_trapped: int | None = None
    if chosen.deterministic and trapped:
        stuck = np.flatnonzero(runs.status == Outcome.OK)
        n_trapped = sum(_periodic(dec, chosen, walk, doors, int(edges[k]), float(t[k]), float(headings[k]), max_bounces)
                        for k in stuck.tolist())
    smart = chosen if isinstance(chosen, Smart) else None
    tangent = smart.tangent if smart is not None and not smart.per_room else None
    return RoomRuns(rule, walk, trials, max_bounces, seed, doors, float(reached.mean()),
                    tuple(int(b) for b in runs.stop_step[reached]), runs.outcome_counts(), n_trapped,
                    smart.theta if smart is not None else None, tangent, kept,
                    recommend_rule(dec, start, goal, rooms=walk), mode if smart is not None else None)


def compare_rules(dec: Decomposition, start: int, goal: int, *, rules: Sequence[str] = RULES, **options: Any) -> RuleComparison:
    """:func:`simulate_rooms` for each rule with the same seed (so the same starts), side by side.

    Each run carries the cost-aware recommendation made from all of them (:func:`recommend_from_runs`).

    Parameters
    ----------
    dec, start, goal
        The room decomposition and the two room ids, as for :func:`simulate_rooms`.
    rules
        The rules to compare (default the paper's three: ``smart``, ``random``, ``billiard``;
        :data:`~solverplan.rectilinear.rules.RULE_VARIANTS` adds the smart rule's other θ modes).
    **options
        :func:`simulate_rooms`'s keyword arguments (``trials``, ``seed``, ``max_bounces``, ``doors``, ``theta``, ...).

    Returns
    -------
    RuleComparison
        ``runs[rule]``, one :class:`RoomRuns` per rule (the paper's Table I), from the same starts, each with the
        recommendation (``advice``).

    Examples
    --------
    >>> import solverplan as sp
    >>> rooms = sp.decompose_rooms(sp.load_environment("l_shape"))
    >>> table = sp.compare_rules(rooms, 0, 1, trials=20, seed=1)
    >>> {rule: (runs.success, runs.bounces_median) for rule, runs in table.runs.items()}
    {'smart': (1.0, 3.0), 'random': (1.0, 4.5), 'billiard': (1.0, 2.5)}
    >>> table.runs["smart"].advice.rule
    'smart'
    """
    runs = {name: simulate_rooms(dec, start, goal, rule=name, **options) for name in rules}
    advice = recommend_from_runs(runs)
    return RuleComparison({name: replace(r, advice=advice) for name, r in runs.items()})


# ---------------------------------------------------------------------- exact replay: periodic orbits
def _rational_start(world: RoomWorld, wall: int, t: float, heading: float) -> tuple[tuple[Fraction, Fraction], tuple[Fraction, Fraction]]:
    """A rational start near a float one: the point at t rounded to 1e-6 of the wall, the direction's slope
    rounded to 1e-6 (so a billiard orbit keeps a rational slope, the precondition of a periodic one)."""
    room = int(world.room_of[wall])
    edge = world.dec.room_environments[room].edge(wall - int(world.offsets[room]))
    q = Fraction(t).limit_denominator(10**6)
    point = (edge.a[0] + q * (edge.b[0] - edge.a[0]), edge.a[1] + q * (edge.b[1] - edge.a[1]))
    dx, dy = world.directions(np.array([wall]), np.array([heading]))[0].tolist()
    if abs(dx) >= abs(dy):
        return point, (Fraction(1 if dx > 0 else -1), Fraction(dy / abs(dx)).limit_denominator(10**6))
    return point, (Fraction(dx / abs(dy)).limit_denominator(10**6), Fraction(1 if dy > 0 else -1))


def _periodic(dec: Decomposition, rule: Rule, walk: tuple[int, ...], doors: Doors, wall: int, t: float,
              heading: float, max_bounces: int) -> bool:
    world = RoomWorld(dec)
    point, direction = _rational_start(world, wall, t, heading)
    return periodic_orbit(dec, rule, walk, wall, point, direction, max_bounces=max_bounces, doors=doors) is not None


def periodic_orbit(dec: Decomposition, rule: Rule, walk: Sequence[int], wall: int, point: tuple[object, object],
                   direction: tuple[object, object], *, max_bounces: int, doors: Doors = "control") -> int | None:
    """Replay a deterministic rule exactly from ``point`` on wall ``wall`` (a wall of :class:`RoomWorld`) moving
    along ``direction`` (exact numbers); the period in bounces when the state repeats before the end of
    ``walk`` is reached (the robot is trapped for ever), else ``None`` (it arrives, hits a corner, or the
    budget ends first). Door control as in :class:`RoomPolicy`."""
    from solverplan.exact import exact_point

    if not rule.deterministic:
        raise InputError(f"the {rule.name} rule is not deterministic: it has no periodic orbits to find")
    walk = tuple(walk)
    world = RoomWorld(dec)
    control = DoorControl(dec, walk)
    env_of = dec.room_environments
    room = int(world.room_of[wall])
    p = exact_point(point, where="start point")
    d = exact_point(direction, where="start direction")
    smart = rule if isinstance(rule, Smart) else None
    tangents = tuple(smart.exact_tangent(r) for r in range(len(dec.rooms))) if smart else ()
    position = 0
    seen: dict[tuple, int] = {}
    for step in range(1, max_bounces + 1):
        while True:  # one flight: in the room, on through open doors
            hit = cast_rays_exact(env_of[room], [p], [d], skip_invalid=True)[0]
            if hit is None or hit.vertex is not None:
                return None  # a corner: outside the model
            wall = int(world.offsets[room]) + hit.edge
            door = int(world.door_of[wall])
            p = hit.point
            if door < 0 or not (doors == "open" or bool(control.is_open(np.array([position]), np.array([door]))[0])):
                break
            wall = int(world.twin[wall])
            room = int(world.room_of[wall])
        if doors == "open":
            if room == walk[-1]:
                return None
        else:
            new, ok = control.advance(np.array([position]), np.array([room]))
            position = int(new[0])
            if not ok[0] or position == control.last:
                return None
        state = (wall, p, d, position, step % 2 if smart is not None else 0)
        if state in seen:
            return step - seen[state]
        seen[state] = step
        edge = env_of[room].edge(wall - int(world.offsets[room]))
        tangent = (edge.b[0] - edge.a[0], edge.b[1] - edge.a[1])  # axis-parallel: one component is 0
        normal = (-tangent[1], tangent[0])
        if smart is None:  # billiard: the component across the wall changes sign
            d = (-d[0], d[1]) if tangent[0] == 0 else (d[0], -d[1])
        elif step % 2 == 0:
            d = normal
        else:  # π/2 + θ from the wall: the normal turned by θ towards the wall's start
            d = (normal[0] - tangents[room] * tangent[0], normal[1] - tangents[room] * tangent[1])
    return None
