"""Result building blocks shared by patrol, funnel and localisation answers (private).

Stages and optimality claims are the shared :class:`solverplan.result.Stage` and
:class:`solverplan.result.Optimality`. :class:`PositionStrategy` is what funnels and localisation strategies
have in common: stages that carry the exact ``positions`` after them, the exact source pieces, and the exact
cones (rational world directions) they were computed with; :func:`heading_cone` makes those cones.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from solverplan.bounce.cones import heading_cone
from solverplan.bounce.partitions import Partition
from solverplan.environment import BoundarySet, Environment
from solverplan.interval import Interval
from solverplan.result import Answer, EnvironmentRecord, Optimality, Reader, Stage, Stats, Status, piece_json

__all__ = ["OnPartition", "PositionStrategy", "heading_cone"]


class OnPartition:
    """What the answers computed in a partition P′ share (patrols, funnels, localisation strategies): ``status``
    read as a :class:`~solverplan.result.Status`, ``env`` from the partition they keep for rollouts and
    certificates, ``found``. A mixin of frozen dataclasses with fields ``status`` and ``partition``."""

    status: Status
    partition: Partition

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", Status(self.status))

    @property
    def env(self) -> Environment:
        """The environment (of ``partition``)."""
        return self.partition.env


@dataclass(frozen=True, kw_only=True)
class PositionStrategy(OnPartition, Answer):
    """An open-loop strategy over exact position sets (a funnel or a localisation strategy), or why there is none.

    Attributes
    ----------
    status, reason
        A :class:`~solverplan.result.Status` and why (empty when found).
    optimality
        How the answer was found (a heuristic search: never proved optimal; a capped search that found nothing
        lists its caps in ``limits``).
    environment
        The :class:`~solverplan.result.EnvironmentRecord` of the environment.
    start, goal
        The start set and the goal set every start ends in (for localisation: the final interval, ``None``
        when there is none).
    tolerance
        ε, radians: every heading interval is 2ε wide.
    stages
        :class:`~solverplan.result.Stage` s with ``positions`` (the exact pieces the robot may be on after the
        stage), ``sources`` (before it), ``cones`` (the exact world-frame directions (d_lo, d_hi) each source
        was pushed through) and ``target_edges``.
    stats
        Search statistics (recorded, never asserted).
    partition
        The partition P′ of the environment (not serialised): for rollouts and certificates.
    """

    status: Status
    optimality: Optimality
    environment: EnvironmentRecord
    start: BoundarySet
    tolerance: float
    partition: Partition = field(repr=False, compare=False)
    stages: tuple[Stage, ...] = ()
    goal: BoundarySet | None = None
    reason: str = ""
    stats: Stats = field(default_factory=Stats, compare=False)


    @property
    def bounces(self) -> int:
        return len(self.stages)

    @property
    def widths(self) -> list[float]:
        """Arc length of the position set before the first stage and after each stage."""
        lengths = self.env.edge_lengths
        out = [sum(float(p.t1 - p.t0) * float(lengths[p.edge]) for p in self.start.pieces)]
        out += [sum(float(p.t1 - p.t0) * float(lengths[p.edge]) for p in st.positions) for st in self.stages]
        return out

    @property
    def intervals(self) -> tuple[Interval, ...]:
        return tuple(st.interval for st in self.stages)

    def rollout_spec(self):
        """``(stages, targets, goal)`` for :class:`solverplan.simulate.StagePolicy`: each stage must land in its
        exact positions; after the last one the robot must be in the goal (the final positions for localisation)."""
        targets = tuple(st.positions for st in self.stages)
        goal = self.goal if self.goal is not None else BoundarySet(self.stages[-1].positions)
        return self.intervals, targets, goal

    def _fields(self) -> dict:
        out: dict[str, Any] = {
            "reason": self.reason,
            "start": str(self.start),
            "goal": None if self.goal is None else str(self.goal),
            "tolerance": self.tolerance,
            "objective": "fewest",
            "bounces": len(self.stages),
            "min_width": 2 * self.tolerance if self.stages else None,
            "stages": [st.to_json() for st in self.stages],
            "position_widths": self.widths,
            "final_positions": [piece_json(p) for p in (self.stages[-1].positions if self.stages else ())],
        }
        out.update(self._extra_json())
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> PositionStrategy:
        """Read a funnel or localisation answer back in ``env`` (required: its positions are pieces of its edges)."""
        from solverplan.bounce.partitions import partition

        r, env, record = cls._reader_in(data, env, cls.kind)
        goal = r.string("goal", None)
        return cls(status=r.status(), optimality=r.optimality(), environment=record or EnvironmentRecord.of(env),
                   start=env.boundary_set(r.string("start")), tolerance=r.number("tolerance"), partition=partition(env),
                   stages=tuple(Stage.from_json(st.data, st.where) for st in r.items("stages")),
                   goal=None if goal is None else env.boundary_set(goal), reason=r.string("reason", ""),
                   stats=r.stats(), **cls._extra_from_json(r))

    @classmethod
    def _extra_from_json(cls, r: Reader) -> dict:
        return {}

    def _extra_json(self) -> dict:
        return {}

    def _head(self) -> str:
        return f"{self.kind} in {self.environment.name or 'the environment'} from {self.start}"

    def to_text(self, *, width: int = 100) -> str:
        lines = [f"{self._head()}: {self.status.value}"]
        if self.reason:
            lines.append(f"reason: {self.reason}")
        lines += self._extra_text()
        widths = self.widths
        lines.append(f"start: {self.start} (length {widths[0]:.6g})")
        for k, st in enumerate(self.stages):
            where = ", ".join(f"e{p.edge}:[{float(p.t0):.6g}, {float(p.t1):.6g}]" for p in st.positions)
            lines.append(f"  {k}: θ ∈ [{st.interval.lo:.6f}, {st.interval.hi:.6f}] → {where}  (length {widths[k + 1]:.3g})")
        lines.append(f"optimality: {self.optimality.to_text()}")
        return "\n".join(lines) + "\n"

    def _extra_text(self) -> list[str]:
        return []
