"""Prop. 4 made constructive: one constant heading θ under which **every** start converges to a verified
limit cycle of the constant rule b = θ, proved by iterating exact enclosures of the whole boundary.

>>> room = Environment.from_coords([[0, 0], [12, 0], [12, 9], [0, 9]], [[[4, 3], [4, 5], [7, 6], [8, 3]]])
>>> ctrl = constant_controller(room)
>>> ctrl.status.value, ctrl.heading.spec(), [c.edges for c in ctrl.cycles]
('found', 'tan:0.25', [(0, 1, 2, 3)])
>>> ctrl.optimality.method.value, ctrl.optimality.proved
('exact-check', True)
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

from solverplan.bounce._cycle_core import (CycleCore, basins_grid, check_epsilon, cycle_along, edge_sequence_text,
                                           find_cycle_edges, rotation)
from solverplan.bounce.constant_map import GRID_ONE, ConstantMap, merge_grid_intervals
from solverplan.bounce.cycles import LimitCycle, _build
from solverplan.bounce.dynamics import ExactHeading, parse_heading
from solverplan.bounce.partitions import partition
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.interval import DEFAULT_HEADING_MARGIN
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Stats, Status, answer_dataclass

__all__ = ["ConstantController", "constant_controller", "DEFAULT_CONTROLLER_TANGENTS"]

logger = logging.getLogger(__name__)

DEFAULT_CONTROLLER_TANGENTS: tuple[str, ...] = (
    "1/4", "1/3", "1/5", "1/2", "1/6", "1/8", "2/3", "1/10", "1", "1/16", "1/32", "1/64",
    "-1/4", "-1/3", "-1/5", "-1/2", "-1/6", "-1/8", "-2/3", "-1/10", "-1", "-1/16", "-1/32", "-1/64",
)
"""Tangents of the headings :func:`constant_controller` tries, in order: small headings first (the robot
runs close to the walls, where Prop. 4's proof looks for contraction), then their mirror images (θ near π)."""

_ALGORITHM = "exact enclosure of f_θ^k(∂P) on a 2⁻⁹⁶ grid inside verified basins"


@answer_dataclass("controller")
class ConstantController(Answer):
    """A constant heading under which every start converges to a verified limit cycle (Prop. 4), or the
    record of the attempts.

    Attributes
    ----------
    env
        The environment.
    heading
        The exact heading found (None when none was proved).
    cycles
        The verified cycles of ``heading`` (scope ``every-start`` together: every start enters one).
    bounces
        How many bounces the exact enclosure of f_θ^k(∂P) needed to lie inside the cycles' basins.
    tried
        (heading spec, outcome) for every candidate heading, in order (skipped ones too).
    status
        ``found``, or ``not-found``: no candidate was proved — a bounded search, not a proof that no
        constant controller exists.
    optimality
        :attr:`~solverplan.result.Method.EXACT_CHECK` (proved) for a found heading;
        :attr:`~solverplan.result.Method.HEURISTIC` with the ``limits`` hit otherwise.
    stats
        ``seconds_search`` and counts ``headings_tried``, ``enclosure_steps`` (bounces of exact
        enclosures, over all headings tried).
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of ``env``.
    heading_margin
        No candidate within this of 0 or π (radians) was tried.
    """

    env: Environment
    heading: ExactHeading | None
    cycles: tuple[LimitCycle, ...]
    bounces: int | None
    tried: tuple[tuple[str, str], ...]
    status: Status
    optimality: Optimality
    stats: Stats = field(default_factory=Stats)
    environment: EnvironmentRecord | None = None
    heading_margin: float = DEFAULT_HEADING_MARGIN

    @property
    def proved(self) -> bool:
        """True when every start provably enters one of :attr:`cycles` (status ``found``)."""
        return self.status is Status.FOUND

    def to_json(self) -> dict:
        if self.environment is None:
            return replace(self, environment=EnvironmentRecord.of(self.env)).to_json()
        return super().to_json()

    def _fields(self) -> dict:
        return {
            "theta": None if self.heading is None else self.heading.theta,
            "theta_exact": None if self.heading is None else self.heading.spec(),
            "proved": self.proved,
            "bounces": self.bounces,
            "heading_margin": self.heading_margin,
            "cycles": [c.to_json() for c in self.cycles],
            "tried": [{"theta_exact": s, "outcome": o} for s, o in self.tried],
        }

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> ConstantController:
        """Read a constant controller back in ``env`` (required, as for its cycles)."""
        r, env, record = cls._reader_in(data, env, "constant controller")
        heading = parse_heading(r.string("theta_exact")) if r.has("theta_exact") else None
        if heading is not None and not isinstance(heading, ExactHeading):
            raise InputError("controller.theta_exact: expected an exact heading (tan:P/Q or dir:C,S)")
        return cls(env=env, heading=heading, cycles=tuple(LimitCycle.from_json(c.data, env=env) for c in r.items("cycles")),
                   bounces=r.integer("bounces", None),
                   tried=tuple((t.string("theta_exact"), t.string("outcome")) for t in r.items("tried")),
                   status=r.status(), optimality=r.optimality(), stats=r.stats(), environment=record,
                   heading_margin=r.number("heading_margin", DEFAULT_HEADING_MARGIN))

    def to_text(self, *, width: int = 100) -> str:
        head = (f"constant controller θ = {self.heading.theta:.12g} ({self.heading.spec()}): "
                if self.heading is not None else "no constant controller: ")
        lines = [head + (f"every start enters one of {len(self.cycles)} verified cycle(s) within {self.bounces} bounces"
                         if self.proved else "not proved")]
        for c in self.cycles:
            lines.append(f"  cycle {edge_sequence_text(c.edges)}: contraction {c.contraction:.6g}")
        for s, o in self.tried:
            lines.append(f"  tried {s}: {o}")
        lines.append(f"optimality: {self.optimality.to_text()}")
        return "\n".join(lines) + "\n"


@dataclass
class _Proof:
    """The outcome of :func:`_global_proof` for one heading."""

    cores: list[CycleCore]
    proved: bool
    steps: int
    outcome: str
    limit: str | None = None  # the cap that stopped the enclosure, e.g. "max_steps=400"


def _global_proof(env: Environment, cmap: ConstantMap, *, max_steps: int, max_intervals: int) -> _Proof:
    """Iterate an exact enclosure of f_θ^k(∂P), removing what lies in certified basins; discover cycles
    from what is left (see :func:`constant_controller`)."""
    cores: list[CycleCore] = []
    keys: set[tuple] = set()
    basins: dict[int, list[tuple[int, int, int]]] = {}

    def discover(S) -> None:
        # float iteration from the widest parts left: where an unseen cycle most likely attracts
        for e, lo, hi in sorted(S, key=lambda x: x[1] - x[2])[:6]:
            _, cyc, _ = find_cycle_edges(cmap, e, (lo + hi) / (2 * GRID_ONE), 4096)
            if cyc is None:
                continue
            core = cycle_along(env, cmap, cyc, Status.NOT_REALISED)
            if core.status is not Status.FOUND:
                continue
            r = rotation(core)
            key = (core.edges[r:] + core.edges[:r], core.orbit[r])
            if key in keys:
                continue
            keys.add(key)
            cores.append(core)
            for be, items in basins_grid(core.edges, core.orbit, core.radii).items():
                basins.setdefault(be, []).extend(items)

    def subtract(S):
        kept = []
        for e, lo, hi in S:
            parts = [(lo, hi)]
            for b_lo, b_hi, _ in basins.get(e, ()):
                nxt = []
                for a, b in parts:
                    if b < b_lo or a > b_hi:
                        nxt.append((a, b))
                        continue
                    if a < b_lo:
                        nxt.append((a, b_lo))
                    if b > b_hi:
                        nxt.append((b_hi, b))
                parts = nxt
            kept.extend((e, a, b) for a, b in parts)
        return kept

    S = [(e, 0, GRID_ONE) for e in range(env.n_edges)]
    step, discovery = 0, 2
    while True:
        S = subtract(S)
        if S and step >= discovery:
            discover(S)
            discovery = 2 * discovery
            S = subtract(S)
        if not S:
            return _Proof(cores, True, step, f"every start is in a basin after {step} bounces")
        if step == max_steps:
            break
        S = merge_grid_intervals([(e, a, b) for lo_e, lo, hi in S for e, a, b, _ in cmap.grid_image(lo_e, lo, hi)])
        step += 1
        if len(S) > max_intervals:
            return _Proof(cores, False, step, f"the enclosure grew past {max_intervals} intervals",
                          f"max_intervals={max_intervals}")
    measure = sum((hi - lo) / GRID_ONE * float(env.edge_lengths[e]) for e, lo, hi in S)
    return _Proof(cores, False, max_steps, f"after {max_steps} bounces {len(S)} intervals (total length {measure:.3g}) "
                                           "were still outside the basins of the cycles found", f"max_steps={max_steps}")


def _check_margin(heading_margin: object) -> float:
    if isinstance(heading_margin, bool) or not isinstance(heading_margin, (int, float)) \
            or not 0 <= heading_margin < math.pi / 4:
        raise InputError(f"heading_margin must be in [0, π/4) radians, got {heading_margin!r}")
    return float(heading_margin)


def constant_controller(
    env: Environment,
    *,
    tangents: Sequence[str] | None = None,
    max_steps: int = 400,
    max_intervals: int = 20000,
    epsilon: float | None = None,
    heading_margin: float = DEFAULT_HEADING_MARGIN,
) -> ConstantController:
    """Prop. 4 made constructive: a constant heading θ and the cycle(s) it drives **every** start into.

    For each candidate heading (exact, tan θ from ``tangents``, default
    :data:`DEFAULT_CONTROLLER_TANGENTS`) build f_θ exactly and iterate an exact enclosure S_k ⊇ f_θ^k(∂P)
    (unions of intervals on a 2⁻⁹⁶ grid, rounded outward, split at the pieces' ends). Cycles are discovered
    by float iteration from the widest parts of S_k and verified exactly (:func:`~solverplan.bounce.cycles.limit_cycle`'s
    checks, with their basins); the parts of S_k inside a basin are dropped. When S_k is empty every start —
    except the finitely many rays through vertices, outside the model — has entered a basin within k
    bounces and converges to a verified stable cycle: the first heading for which that happens is returned
    with status ``found``.

    **The argument and its limits.** The paper states Prop. 4 per start ("for all points s … a constant
    fixed-angle controller exists"): the heading may depend on s. Its proof picks, per segment of P′, the
    safe contracting headings next to the wall (Prop. 3, Lemma 2) and concludes that one constant heading
    works everywhere; that does not follow — a constant small heading hugs the wall only up to a *reflex*
    vertex, where the ray leaves across the room, and the headings that are safe from different segments
    need not share a value. This function asks for more than the paper (one heading for **every** start)
    and proves it per polygon instead of by a general argument. It can fail for a reason the paper's proof
    misses: two long parallel walls facing each other carry *neutral* period-2 orbits (the two bounces
    compose to the identity, contraction exactly 1), which never converge — in a 50 × 2 corridor every
    heading with tan θ > 2/50 leaves such orbits, and only shallower ones reach the corners (where
    consecutive right transitions contract). A polygon where every candidate fails gets status
    ``not-found`` with the reasons (a bounded search: it proves nothing). Several cycles may share the
    boundary (different starts, different cycles); all are reported.

    Parameters
    ----------
    env
        The environment (any polygon with holes).
    tangents
        Candidate tan θ, exact text (``"1/4"``; negative for θ > π/2), tried in order.
    max_steps, max_intervals
        Per heading: the most bounces of the enclosure, and the most intervals it may hold.
    epsilon
        Also report Cor. 4's cycle counts for this width (arc length) on every cycle.
    heading_margin
        Radians: candidates within this of 0 or π are skipped (recorded in ``tried``), as the planners
        never use headings that graze a wall.

    Returns
    -------
    ConstantController
        ``found`` with the heading, its verified cycles and the bounces after which every start is in their
        basins; or ``not-found`` with every candidate's outcome in ``tried``.

    Raises
    ------
    InputError
        No candidate tangent, a bad ``epsilon`` or ``heading_margin``, or every candidate inside the margin.

    Examples
    --------
    >>> import solverplan as sp
    >>> control = sp.constant_controller(sp.load_environment("l_shape"))
    >>> control.status.value, control.heading.theta         # tan θ = 1/4, radians
    ('found', 0.24497866312686414)
    >>> control.bounces, [cycle.edges for cycle in control.cycles]   # within 4 bounces every start is on its way
    (4, [(0, 1, 2, 5)])
    """
    if epsilon is not None:
        check_epsilon(epsilon)
    margin = _check_margin(heading_margin)
    specs = tuple(tangents) if tangents is not None else DEFAULT_CONTROLLER_TANGENTS
    if not specs:
        raise InputError("constant_controller needs at least one candidate tangent")
    headings = [ExactHeading.from_tangent(spec) for spec in specs]
    if not any(margin <= h.theta <= math.pi - margin for h in headings):
        raise InputError(f"every candidate heading is within heading_margin = {margin:g} rad of a wall: "
                         "use larger tangents or a smaller margin")
    begin = time.perf_counter()
    part = partition(env)
    record = EnvironmentRecord.of(env, part.n_segments)
    tried: list[tuple[str, str]] = []
    limits: list[str] = []
    steps_total = 0

    def stats() -> Stats:
        return Stats(seconds_search=time.perf_counter() - begin,
                     counts={"headings_tried": sum(not o.startswith("skipped") for _, o in tried),
                             "enclosure_steps": steps_total})

    for heading in headings:
        if not margin <= heading.theta <= math.pi - margin:
            tried.append((heading.spec(), f"skipped: θ = {heading.theta:.3g} is within heading_margin = {margin:g} "
                                          "rad of a wall"))
            continue
        cmap = ConstantMap(env, heading)
        proof = _global_proof(env, cmap, max_steps=max_steps, max_intervals=max_intervals)
        steps_total += proof.steps
        tried.append((heading.spec(), proof.outcome))
        logger.info("constant controller %s: %s", heading.spec(), proof.outcome)
        if proof.proved:
            claim = ("every start on the boundary (rays through vertices excepted) converges to one of the "
                     f"{len(proof.cores)} verified cycle(s) of this heading")
            cycles = tuple(
                _build(env, cmap, core, method="iterate", theta=heading.theta, scope="every-start", rotate=True, part=part,
                       algorithm=_ALGORITHM, claim=claim,
                       reason=f"every start converges to one of the {len(proof.cores)} verified cycle(s) of this heading "
                              f"(exact enclosure of all orbits inside their basins after {proof.steps} bounces)")
                .with_epsilon(epsilon)
                for core in proof.cores
            )
            optimality = Optimality(Method.EXACT_CHECK, True, None, scope=claim, algorithm=_ALGORITHM)
            return ConstantController(env, heading, cycles, proof.steps, tuple(tried), Status.FOUND, optimality,
                                      stats(), record, margin)
        if proof.limit is not None and proof.limit not in limits:
            limits.append(proof.limit)
    candidates = ", ".join(spec for spec, outcome in tried if not outcome.startswith("skipped"))
    optimality = Optimality(Method.HEURISTIC, False, None, limits=tuple(limits), algorithm=_ALGORITHM,
                            scope=f"one constant heading among the candidates {candidates} (outside heading_margin = "
                                  f"{margin:g} rad of the walls) driving every start into a verified cycle")
    return ConstantController(env, None, (), None, tuple(tried), Status.NOT_FOUND, optimality, stats(), record, margin)
