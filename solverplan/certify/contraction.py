"""Certificates for contraction-based answers: patrol cycles, funnels and localisation strategies.

Turns the results of :mod:`solverplan.plan.patrol`, :mod:`solverplan.plan.funnel` and
:mod:`solverplan.plan.localize` into :class:`~solverplan.certify.schema.Certificate` s with the writer
(:func:`~solverplan.certify.writer.build_certificate`), for the independent exact checker:

- a **patrol** is a ``cycle`` certificate: the entry stages (belief stages of the safe BVG: one move per possible
  segment), then the cycle's stages, one move each from its whole source segment; the cycle block claims the
  exact return map of the nominal headings, its fixed point, the worst-case contraction (< 1) and the visits;
- a **funnel** or a **localisation** strategy is a ``funnel`` certificate: every stage moves exact position
  pieces with the *exact cones the planner used* (rational directions, ``MoveSpec.directions``), so the images
  the checker recomputes are the positions the planner tracked, and each stage claims them.
"""

from __future__ import annotations

import math
from fractions import Fraction

from solverplan.certify.schema import Certificate, Optimality
from solverplan.certify.writer import CycleSpec, MoveSpec, StageSpec, build_certificate
from solverplan.environment import BoundaryPiece
from solverplan.errors import InputError

__all__ = ["patrol_certificate", "funnel_certificate"]


def _optimality(opt) -> Optimality | None:
    if opt is None or opt.method == "none" or opt.bound is None or not math.isfinite(opt.bound):
        return None
    bound = None if opt.bound is None else Fraction(opt.bound)
    return Optimality(opt.method, bool(opt.proved), bound)


def patrol_certificate(result) -> Certificate:
    """A ``cycle`` certificate of a found :class:`~solverplan.plan.patrol.Patrol`."""
    if not result.found:
        raise InputError(f"the patrol has status {result.status!r}: there is no cycle to certify")
    part = result.partition
    stages: list[StageSpec] = []
    for st in result.entry:
        stages.append(StageSpec(st.interval, tuple(MoveSpec(source=s, target=t) for s, t in st.moves)))
    for st in result.cycle:
        stages.append(StageSpec(st.interval, (MoveSpec(source=st.from_segment, target=st.to_segment),)))
    start = result.start if result.start is not None else [result.cycle[0].from_segment]
    return build_certificate(
        result.env, part, stages, start=start, kind="cycle",
        cycle=CycleSpec(len(result.entry), headings=tuple(s.affine.heading for s in result.cycle), visits=result.visit),
        objective=f"patrol-{result.objective}", optimality=_optimality(result.optimality),
    )


def funnel_certificate(result) -> Certificate:
    """A ``funnel`` certificate of a found :class:`~solverplan.plan.funnel.Funnel` (or localisation strategy):
    each stage's moves leave the exact position pieces with the planner's exact cones."""
    if not result.found:
        raise InputError(f"the answer has status {result.status!r}: there is no strategy to certify")
    stages: list[StageSpec] = []
    for st in result.stages:
        if st.sources is None or st.cones is None:
            raise InputError("a funnel stage without exact sources and cones cannot be certified")
        moves = []
        for piece, (d_lo, d_hi), target in zip(st.sources, st.cones, st.target_edges):
            moves.append(MoveSpec(source=BoundaryPiece(piece.edge, piece.t0, piece.t1), target_edge=target,
                                  directions=(d_lo, d_hi)))
        stages.append(StageSpec(st.interval, tuple(moves)))
    return build_certificate(result.env, result.partition, stages, start=result.start, goal=result.goal, kind="funnel",
                             objective=f"{result.kind}-fewest", optimality=_optimality(result.optimality))
