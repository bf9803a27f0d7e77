"""Certificates from floating-point planner output.

Planners work in floats: a stage is a heading :class:`~solverplan.interval.Interval` (radians,
measured from the source edge) and the moves it makes (source segment or exact sub-interval → target
segment). :func:`build_certificate` turns that into a :class:`~solverplan.certify.schema.Certificate`
that :func:`~solverplan.certify.check.check_certificate` can verify exactly:

- **Directions.** For each move, each end of the interval becomes an exact direction *in the frame
  of the move's source edge*, chosen inside the interval within ``margin`` (10⁻⁹ rad, or a quarter of
  the width if that is smaller) of the float end, with the simplest rational cotangent there
  (:func:`solverplan.bounce.cones.heading_cone`, inside: the exact cone never claims more than the
  float interval), and scaled to a primitive integer vector.
- **Per-move cones.** A robot executes one heading measured from the edge it is on; for moves whose
  source edges differ, the same heading is a different world direction. So each move carries its own
  world-frame cone (d_lo, d_hi), all built from the one stage interval, and the stage's action
  interval is what their cones have in common, each measured from its own edge.
- **Claims are recomputed from the rational directions**, never copied from the floats: the stage
  ``interval`` is the common cone's enclosure rounded inwards to 16 decimals; ``min_width`` its
  narrowest width, ``tolerance`` half of it, ``sum_width`` the sum; targets, positions (funnels) and the
  return map, fixed point and worst-case contraction (cycles) are exact images of the rational
  directions. A certificate therefore claims only what the checker will find — if the float plan was
  wrong (an interval wider than safe), the certificate says so when checked, it does not hide it.

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.partitions import partition
>>> from solverplan.certify.check import check_certificate
>>> square = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], name="square")
>>> cert = build_certificate(square, partition(square),
...                          [StageSpec(Interval(0.1, 0.7), (MoveSpec(source=0, target=1),))],
...                          start="e0", goal="e1")
>>> cert.stages[0].moves[0].d_lo, cert.stages[0].moves[0].d_hi
((Fraction(74401, 1), Fraction(7465, 1)), (Fraction(25293, 1), Fraction(21304, 1)))
>>> check_certificate(cert).valid
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal, Sequence, Union

from solverplan.interval import Interval
from solverplan.bounce.cones import heading_cone, heading_direction
from solverplan.bounce.partitions import Partition
from solverplan.certify.exact2d import affine_coefficients, line_hit
from solverplan.certify.rational_atan import heading_enclosure
from solverplan.certify.schema import (
    Certificate,
    Claims,
    CycleClaim,
    EnvironmentRecord,
    Move,
    Optimality,
    Piece,
    Point,
    SegmentRecord,
    Stage,
)
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.exact import to_fraction

__all__ = ["MoveSpec", "StageSpec", "CycleSpec", "build_certificate", "DECIMALS"]

DECIMALS = 16
"""Decimal places of the claimed intervals and widths (rounded inwards / downwards)."""

_BITS = 96  # precision of the enclosures behind the claims (≈ 1e-29)

Source = Union[int, BoundaryPiece, tuple[int, object, object]]


@dataclass(frozen=True, slots=True)
class MoveSpec:
    """One move of a stage, as a planner knows it.

    Parameters
    ----------
    source
        A segment id of the partition, or an exact sub-interval of positions: a
        :class:`~solverplan.environment.BoundaryPiece` or ``(edge, t0, t1)`` (numbers read exactly).
    target
        The segment id the move lands on; or leave it ``None`` and give ``target_edge`` when the
        landing set may span several segments of one edge (funnels).
    directions
        Exact world-frame directions ``(d_lo, d_hi)`` to use instead of rationalising the stage's
        interval (e.g. the exactly known parallel direction of a singleton interval).
    """

    source: Source
    target: int | None = None
    target_edge: int | None = None
    directions: tuple[Sequence[object], Sequence[object]] | None = None


@dataclass(frozen=True, slots=True)
class StageSpec:
    """A stage: the heading interval (radians, measured from each move's source edge) and its moves."""

    interval: Interval
    moves: tuple[MoveSpec, ...]


@dataclass(frozen=True, slots=True)
class CycleSpec:
    """The stages ``first_stage ..`` (to the end) repeat forever. ``headings``: the nominal heading of
    each cycle stage (radians; default: the middle of its interval), whose exact return map and fixed
    point the certificate states; ``visits``: edges a patrol must visit in that cyclic order."""

    first_stage: int
    headings: tuple[float, ...] | None = None
    visits: tuple[int, ...] | None = None


# ---------------------------------------------------------------------- directions
def _primitive(v: tuple[Fraction, Fraction]) -> Point:
    """The positive multiple of v with coprime integer coordinates."""
    den = math.lcm(v[0].denominator, v[1].denominator)
    x, y = int(v[0] * den), int(v[1] * den)
    g = math.gcd(x, y) or 1
    return (Fraction(x // g), Fraction(y // g))


def _cone(edge_vector: Point, interval: Interval, margin: float) -> tuple[Point, Point]:
    if interval.is_empty:
        raise InputError("a stage's heading interval is empty: there is nothing to certify")
    lo, hi = float(interval.lo), float(interval.hi)
    if not 0.0 < lo <= hi < math.pi:
        raise InputError(f"heading interval [{lo!r}, {hi!r}] is not inside (0, π)")
    return heading_cone(edge_vector, interval, margin=margin)


# ---------------------------------------------------------------------- decimals
def _ceil_dec(x: Fraction) -> Fraction:
    scale = 10**DECIMALS
    return Fraction(-((-x.numerator * scale) // x.denominator), scale)


def _floor_dec(x: Fraction) -> Fraction:
    scale = 10**DECIMALS
    return Fraction((x.numerator * scale) // x.denominator, scale)


# ---------------------------------------------------------------------- the builder
@dataclass
class _Resolved:
    edge: int
    source: tuple[Fraction, Fraction]
    source_segment: int | None
    target_edge: int
    target_range: tuple[Fraction, Fraction]
    target_segment: int | None
    d_lo: Point
    d_hi: Point
    image: tuple[Fraction, Fraction] | None = None


def build_certificate(
    env: Environment,
    part: Partition,
    stages: Sequence[StageSpec],
    *,
    start: BoundarySet | str | Sequence[int] | Sequence[BoundaryPiece],
    goal: BoundarySet | str | Sequence[int] | Sequence[BoundaryPiece] | None = None,
    kind: Literal["plan", "cycle", "funnel", "localize"] = "plan",
    cycle: CycleSpec | None = None,
    epsilon: object = None,
    objective: str | None = None,
    optimality: Optimality | None = None,
    targets: Literal["segment", "image"] | None = None,
    margin: float = 1e-9,
    producer: str = "solverplan",
) -> Certificate:
    """Build a certificate from a floating-point plan, cycle or funnel (see the module docstring).

    Parameters
    ----------
    env, part
        The environment and its partition P′ (:func:`solverplan.bounce.partitions.partition`).
    stages
        The stages in order, each a heading interval and its moves; none for a plan or funnel whose start set
        lies in its goal set (the checker then checks that inclusion, exactly).
    start, goal
        Boundary sets (``"e3:0.25:0.75,e4"``, a :class:`~solverplan.environment.BoundarySet`, boundary
        pieces, or a list of segment ids); a cycle has no goal.
    kind
        ``plan``, ``funnel`` (stages also claim their exact positions), ``localize`` (a funnel that also
        claims ``epsilon``) or ``cycle`` (give ``cycle``).
    epsilon
        ``localize`` only: the claimed bound on the arc length of the final interval (same unit as the
        coordinates; read exactly: a float by its shortest text, ``0.05`` is 1/20).
    objective, optimality
        Passed through as claims (the checker checks their consistency, not the search behind them).
    targets
        What a move claims as its target: the whole target ``segment`` (default for plans) or the exact
        ``image`` of the move (default for funnels and cycles, whose chaining needs it).
    margin
        Radians cut off each end of an interval before it is made rational.

    Raises
    ------
    InputError
        An unknown segment or edge, an empty interval, an interval outside (0, π).
    SolverFailed
        A cycle whose nominal return map has slope exactly 1 (no fixed point: not a contracting cycle).
    """
    if kind not in ("plan", "cycle", "funnel", "localize"):
        raise InputError(f"unknown certificate kind {kind!r}: use plan, cycle, funnel or localize")
    if (kind == "localize") != (epsilon is not None):
        raise InputError("give epsilon exactly when kind='localize'")
    eps = None
    if epsilon is not None:
        # a float by its shortest text: the ε the user asked for (0.05), not the binary number nearest it
        eps = to_fraction(repr(epsilon) if isinstance(epsilon, float) else epsilon, where="epsilon")
        if eps <= 0:
            raise InputError(f"epsilon {epsilon!r} must be a positive length")
    if not stages and (kind not in ("plan", "funnel") or goal is None):
        raise InputError("a certificate needs at least one stage (only a plan or funnel whose start set lies in its "
                         "goal set has none)")
    if (kind == "cycle") != (cycle is not None):
        raise InputError("give a CycleSpec exactly when kind='cycle'")
    mode = targets or ("segment" if kind == "plan" else "image")
    used: set[int] = set()
    resolved_stages: list[list[_Resolved]] = []
    for k, spec in enumerate(stages):
        if not spec.moves:
            raise InputError(f"stage {k} has no moves")
        resolved_stages.append([_resolve(env, part, spec.interval, move, margin, used) for move in spec.moves])

    out_stages: list[Stage] = []
    widths: list[Fraction] = []
    for k, (spec, moves) in enumerate(zip(stages, resolved_stages)):
        interval, width = _stage_claim(env, moves)
        widths.append(width)
        records = []
        for r in moves:
            target = r.image if (mode == "image" and r.image is not None) else r.target_range
            records.append(
                Move(
                    edge=r.edge,
                    source=r.source,
                    d_lo=r.d_lo,
                    d_hi=r.d_hi,
                    target_edge=r.target_edge,
                    target=target,
                    source_segment=r.source_segment,
                    target_segment=r.target_segment,
                )
            )
        positions = None
        if kind in ("funnel", "localize"):
            if any(r.image is None for r in moves):
                raise InputError(f"stage {k}: a move's corner rays miss its target line, so its image is undefined")
            positions = _union_pieces(part for r in moves if r.image is not None
                                      for part in _on_wall(env, r.target_edge, r.image))
        out_stages.append(Stage(tuple(records), interval, positions))

    # no stages: no interval constrains the heading, so the narrowest is the whole range (0, π), as the planner says
    min_width = min(widths) if widths else Fraction(math.pi)
    claims = Claims(
        bounces=len(out_stages),
        min_width=min_width,
        tolerance=min_width / 2,
        objective=objective,
        sum_width=sum(widths, Fraction(0)),
        optimality=optimality,
        epsilon=eps,
    )
    cycle_claim = _cycle_claim(env, stages, out_stages, cycle) if cycle is not None else None
    segments = tuple(_segment_record(part, i) for i in sorted(used))
    return Certificate(
        kind=kind,
        environment=EnvironmentRecord(env.rings, env.name),
        segments=segments,
        start=_pieces(env, part, start, "start"),
        goal=None if goal is None else _pieces(env, part, goal, "goal"),
        stages=tuple(out_stages),
        claims=claims,
        cycle=cycle_claim,
        producer=producer,
    )


# ---------------------------------------------------------------------- helpers
def _segment(part: Partition, index: object, what: str):
    if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(part.segments):
        raise InputError(f"{what}: unknown segment {index!r} (segments 0..{len(part.segments) - 1})")
    return part.segments[index]


def _segment_record(part: Partition, index: int) -> SegmentRecord:
    s = part.segments[index]
    return SegmentRecord(s.id, s.edge, s.t0, s.t1, s.a, s.b)


def _edge_vector(env: Environment, edge: int) -> tuple[Point, Point]:
    e = env.edge(edge)
    return e.a, (e.b[0] - e.a[0], e.b[1] - e.a[1])


def _segments_ending_at(env: Environment, part: Partition, edge: int, ts: Sequence[Fraction]) -> set[int]:
    """The segments of P′ on the straight wall through ``edge`` that begin or end at the points of parameters ``ts``
    of its line: named in the certificate, they account for the ends of a source that is a run of segments."""
    a, e = _edge_vector(env, edge)
    # an end at a vertex is an end of an edge, which needs no segment to account for it (naming one anyway would be
    # a claim the certificate could drop and stay valid)
    vertices = {v for ring in env.rings for v in ring}
    points = {(a[0] + t * e[0], a[1] + t * e[1]) for t in ts} - vertices

    def on_line(x: Point) -> bool:
        return (x[0] - a[0]) * e[1] - (x[1] - a[1]) * e[0] == 0

    return {s.id for s in part.segments if (s.a in points or s.b in points) and on_line(s.a) and on_line(s.b)}


def _resolve(env: Environment, part: Partition, interval: Interval, spec: MoveSpec, margin: float, used: set[int]) -> _Resolved:
    # source
    if isinstance(spec.source, int) and not isinstance(spec.source, bool):
        seg = _segment(part, spec.source, "move source")
        edge, p, q, source_segment = seg.edge, seg.t0, seg.t1, seg.id
    else:
        if isinstance(spec.source, BoundaryPiece):
            edge, p, q = spec.source.edge, spec.source.t0, spec.source.t1
        else:
            try:
                edge, p_raw, q_raw = spec.source  # type: ignore[misc]
            except (TypeError, ValueError):
                raise InputError(f"move source {spec.source!r}: expected a segment id or (edge, t0, t1)") from None
            p, q = to_fraction(p_raw, where="move source t0"), to_fraction(q_raw, where="move source t1")
        env.edge(edge)  # raises for an unknown edge
        source_segment = next((s.id for s in part.segments if s.edge == edge and s.t0 <= p and q <= s.t1), None)
    if source_segment is not None:
        used.add(source_segment)
    else:  # a run of segments (a patrol leaving from collinear segments): name the segments its ends are ends of
        used.update(_segments_ending_at(env, part, edge, (p, q)))
    # target
    if spec.target is not None:
        seg = _segment(part, spec.target, "move target")
        target_edge, target_range, target_segment = seg.edge, (seg.t0, seg.t1), seg.id
        used.add(seg.id)
    elif spec.target_edge is not None:
        env.edge(spec.target_edge)
        target_edge, target_range, target_segment = spec.target_edge, (Fraction(0), Fraction(1)), None
    else:
        raise InputError("a move needs a target segment or a target edge")
    # directions
    a, e = _edge_vector(env, edge)
    if spec.directions is not None:
        d_lo = _primitive(tuple(to_fraction(x, where="direction") for x in spec.directions[0]))  # type: ignore[arg-type]
        d_hi = _primitive(tuple(to_fraction(x, where="direction") for x in spec.directions[1]))  # type: ignore[arg-type]
    else:
        d_lo, d_hi = _cone(e, interval, margin)
    resolved = _Resolved(edge, (Fraction(p), Fraction(q)), source_segment, target_edge, target_range, target_segment, d_lo, d_hi)
    resolved.image = _image(env, resolved)
    return resolved


def _image(env: Environment, r: _Resolved) -> tuple[Fraction, Fraction] | None:
    """[min τ, max τ] of the four corner rays on the target line, or None if one misses it."""
    a, e = _edge_vector(env, r.edge)
    c, f = _edge_vector(env, r.target_edge)
    taus = []
    for t in r.source:
        origin = (a[0] + t * e[0], a[1] + t * e[1])
        for d in (r.d_lo, r.d_hi):
            hit = line_hit(origin, d, c, f)
            if hit is None or hit[0] < 0:
                return None
            taus.append(hit[1])
    return (min(taus), max(taus))


def _stage_claim(env: Environment, moves: Sequence[_Resolved]) -> tuple[tuple[Fraction, Fraction] | None, Fraction]:
    """The claimed interval (rounded inwards) and width (rounded down) of a stage's common cone."""
    lows, highs = [], []
    for r in moves:
        _, e = _edge_vector(env, r.edge)
        lows.append(heading_enclosure(e, r.d_lo, _BITS))
        highs.append(heading_enclosure(e, r.d_hi, _BITS))
    lo = _ceil_dec(max(u for _, u in lows))
    hi = _floor_dec(min(l for l, _ in highs))
    if lo <= hi:
        return (lo, hi), hi - lo
    width = _floor_dec(min(l for l, _ in highs) - max(u for _, u in lows))
    return None, max(width, Fraction(0))


def _on_wall(env: Environment, edge: int, span: tuple[Fraction, Fraction]) -> list[tuple[int, tuple[Fraction, Fraction]]]:
    """The part ``span`` of ``edge``'s line as pieces of the edges of its straight wall (``edge`` and its
    neighbours on the same line in the same direction: the vertices between them have an angle of exactly π),
    each in its own parameter. An image of a move without a target segment may run on over those neighbours."""
    lo, hi = span
    if 0 <= lo and hi <= 1:
        return [(edge, span)]
    a, e = _edge_vector(env, edge)
    norm = e[0] * e[0] + e[1] * e[1]
    nxt, prv = env.next_vertex, env.prev_vertex
    wall = [(edge, Fraction(0), Fraction(1))]  # (edge, offset, scale): its t maps to offset + scale·t on edge's line
    for step in (nxt, prv):
        j = int(step[edge])
        while j != edge:
            b, f = _edge_vector(env, j)
            if f[0] * e[1] - f[1] * e[0] != 0 or f[0] * e[0] + f[1] * e[1] <= 0:
                break
            offset = Fraction((b[0] - a[0]) * e[0] + (b[1] - a[1]) * e[1]) / norm
            wall.append((j, offset, Fraction(f[0] * e[0] + f[1] * e[1]) / norm))
            j = int(step[j])
    out = []
    for j, offset, scale in wall:
        x0, x1 = max(lo, offset), min(hi, offset + scale)
        if x0 < x1:
            out.append((j, ((x0 - offset) / scale, (x1 - offset) / scale)))
    return out or [(edge, span)]


def _union_pieces(items) -> tuple[Piece, ...]:
    by_edge: dict[int, list[tuple[Fraction, Fraction]]] = {}
    for edge, (lo, hi) in items:
        by_edge.setdefault(edge, []).append((lo, hi))
    pieces: list[Piece] = []
    for edge in sorted(by_edge):
        merged: list[list[Fraction]] = []
        for lo, hi in sorted(by_edge[edge]):
            if merged and lo <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], hi)
            else:
                merged.append([lo, hi])
        pieces.extend(Piece(edge, lo, hi) for lo, hi in merged)
    return tuple(pieces)


def _pieces(env: Environment, part: Partition, value: object, what: str) -> tuple[Piece, ...]:
    if isinstance(value, str):
        value = env.boundary_set(value)
    if isinstance(value, BoundarySet):
        return tuple(Piece(p.edge, p.t0, p.t1) for p in value.pieces)
    out = []
    for item in value:  # type: ignore[attr-defined]
        if isinstance(item, BoundaryPiece):
            out.append(Piece(item.edge, item.t0, item.t1))
        else:
            seg = _segment(part, item, what)
            out.append(Piece(seg.edge, seg.t0, seg.t1))
    if not out:
        raise InputError(f"the {what} set is empty")
    return tuple(out)


def _inside_cone(e: Point, d_lo: Point, d_hi: Point, d: Point) -> bool:
    def cross(u: Point, v: Point) -> Fraction:
        return u[0] * v[1] - u[1] * v[0]

    return cross(e, d) > 0 and cross(d_lo, d) >= 0 and cross(d, d_hi) >= 0


def _cycle_claim(env: Environment, specs: Sequence[StageSpec], stages: Sequence[Stage], cycle: CycleSpec) -> CycleClaim:
    first = cycle.first_stage
    if not 0 <= first < len(stages):
        raise InputError(f"cycle.first_stage {first} is not a stage index (0..{len(stages) - 1})")
    indices = tuple(range(first, len(stages)))
    if cycle.headings is not None and len(cycle.headings) != len(indices):
        raise InputError(f"{len(cycle.headings)} nominal headings for {len(indices)} cycle stages")
    nominal: list[Point] = []
    alpha, beta, worst = Fraction(1), Fraction(0), Fraction(1)
    for idx, k in enumerate(indices):
        if len(stages[k].moves) != 1:
            raise InputError(f"cycle stage {k} has {len(stages[k].moves)} moves: a cycle stage has exactly one")
        move = stages[k].moves[0]
        a, e = _edge_vector(env, move.edge)
        c, f = _edge_vector(env, move.target_edge)
        theta = cycle.headings[idx] if cycle.headings is not None else specs[k].interval.midpoint
        d = heading_direction(e, theta - 1e-12, theta + 1e-12)
        if not _inside_cone(e, move.d_lo, move.d_hi, d):
            d = _primitive((move.d_lo[0] + move.d_hi[0], move.d_lo[1] + move.d_hi[1]))
        nominal.append(d)
        a_k, b_k = affine_coefficients(a, e, c, f, d)
        alpha, beta = a_k * alpha, a_k * beta + b_k
        worst *= max(abs(affine_coefficients(a, e, c, f, move.d_lo)[0]), abs(affine_coefficients(a, e, c, f, move.d_hi)[0]))
    if alpha == 1:
        raise SolverFailed("the cycle's return map has slope 1: no unique fixed point, not a contracting cycle")
    return CycleClaim(
        stages=indices,
        nominal=tuple(nominal),
        alpha=alpha,
        beta=beta,
        fixed_point=beta / (1 - alpha),
        contraction=worst,
        visits=cycle.visits,
    )
