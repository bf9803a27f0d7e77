"""Negative certificates and certified bounds, planner side: the invariant of :mod:`solverplan.certify.invariant`.

The planner answers ``infeasible`` and optimality claims (fewest bounces, widest tolerance) by exhausting its
search. This module turns such answers into proofs the exact checker re-derives: a ``bound`` block (schema
version 3) whose invariant says that **no plan exists** in a stated class —

- an ``infeasible`` answer (any objective, budget K or none): no plan with ≤ K stages (of positive width);
- a ``fewest`` plan with k bounces: no plan with ≤ k − 1 stages;
- a ``tolerance`` (or ``constant``) plan of min width W* within budget K: no plan with ≤ K stages whose every
  interval is wider than w ≥ W*: first w = W* + 2·end margin + 10⁻⁹ (the planner's intervals lie ``end_margin``
  inside the exact safe sets at both ends, the checker's cells do not); when the margin-free class still has a
  wider plan (the corner clearance can cut far more than the end margin off an interval near a corner, and the
  planner takes no two consecutive arcs into one corner), w rises just above that plan's narrowest stage, until
  no plan is wider (:func:`tolerance_bound`). The checker states the gap w − W*.

The class is over the **segment table** P′ of the environment's straight walls (collinear vertices merged, as
the planner searches), refined at the ends of the query's start and goal sets (so that both are unions of whole
segments), with the **groups** of the pieces each segment of P′ was cut into: a stage may land on one piece or
anywhere on one group — the planner's landing units and its whole segments (:mod:`solverplan.plan._problem`) — and
the heading margin δ of the query; *margin-free* otherwise: no safe
margin, no corner clearance, no ban on consecutive arcs into one corner. Those margins only remove options, and a
belief of the planner is a union of table segments the invariant's beliefs split into pieces (each piece of a
unit lands where the unit does), so the class contains every plan the planner considers, and the statement
proved is stronger than the planner's.

The invariant is computed with the checker's own exact successor relation (:class:`~.invariant.Closure`):
breadth-first over beliefs from the start belief, up to depth K. There are therefore no float-versus-exact
disagreements to repair; the price is that the builder does the checker's work once more. When the exact
closure reaches the goal although the planner said there is no plan, the planner's answer holds only within its
margins: :class:`~solverplan.certify.build.NothingToCertify` says so, with the stage count the margin-free class
needs.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from solverplan.bounce.partitions import partition as make_partition
from solverplan.certify.invariant import Closure, Geometry, next_belief
from solverplan.certify.schema import BeliefRecord, BoundClaim, Point
from solverplan.environment import BoundaryPiece, BoundarySet, Environment
from solverplan.plan._walls import PartitionedWalls
from solverplan.plan.margins import DEFAULT_HEADING_MARGIN, Margins

__all__ = ["NoBound", "segment_table", "refined_table", "bound_claim", "TABLE_SOURCE", "tolerance_threshold", "tolerance_bound",
           "heading_margin_of", "ceil12"]

TABLE_SOURCE = ("P′ of the straight walls (collinear vertices merged) refined at the query's set ends, grouped by "
                "segment of P′")

MAX_BELIEFS = 20_000
"""Most beliefs an invariant may list before the builder gives up (the certificate would be unreadable)."""

MAX_PROOF_SEGMENTS = 1_000
"""Largest table (segments of P′) over which the builder tries an exact closure at all. Each source segment whose
exact runs the closure needs costs work proportional to the table (about 0.4 ms of CPU per segment of the table
here: 2 s per source on a raw warehouse map of 5,140 segments, where one proof ran for over 6 minutes), so on
larger tables the answer goes without a bound block (its optimality claim stays the search's, not certified)."""

MAX_PROOF_WORK = 30_000
"""Most work (source segments whose exact runs were computed × segments of the table) the closures of one bound may
take, all rounds of :func:`tolerance_bound` together, before the builder gives up. Checked before each belief's
successors (whose new sources are counted first: one belief of a warehouse map holds hundreds), so it is never
overrun: about 11 s of CPU at the rate measured on a tester's map (1.1·10⁻⁴ s per unit), and the checker redoes about
a third of it; tables up to 316 segments never reach it in one round."""


class NoBound(Exception):
    """No invariant proves the bound: ``why`` says why in a few words (the margin-free class has a plan).
    ``width``: the narrowest stage width of that plan (radians, a float within 10⁻¹² of the exact value), when
    one was found."""

    def __init__(self, why: str, width: float | None = None) -> None:
        super().__init__(why)
        self.why = why
        self.width = width


def _stage_width(lo: tuple[int, int], hi: tuple[int, int], delta: float) -> float:
    """The width of [lo, hi] ∩ [δ, π − δ] (heading vectors), in floats."""
    a, b = math.atan2(lo[1], lo[0]), math.atan2(hi[1], hi[0])
    return min(b, math.pi - delta) - max(a, delta)


Piece3 = tuple[int, Fraction, Fraction]


def _edges(env: Environment) -> tuple[list[tuple[Point, Point]], list[int]]:
    edges: list[tuple[Point, Point]] = []
    nxt: list[int] = []
    for ring in env.rings:
        first = len(edges)
        for i in range(len(ring)):
            a, b = ring[i], ring[(i + 1) % len(ring)]
            edges.append(((Fraction(a[0]), Fraction(a[1])), (Fraction(b[0]), Fraction(b[1]))))
            nxt.append(first + (i + 1) % len(ring))
    return edges, nxt


def segment_table(env: Environment, start: BoundarySet, goal: BoundarySet) -> list[list[Piece3]]:
    """The table of the certificates: P′ of the straight walls of ``env`` (:mod:`solverplan.plan._walls`), each
    segment as pieces of the user's edges, cut at every end of the start and goal sets' pieces."""
    return refined_table(env, start, goal)[0]


def refined_table(env: Environment, start: BoundarySet, goal: BoundarySet) -> tuple[list[list[Piece3]], list[tuple[int, ...]]]:
    """:func:`segment_table` and its groups: for every segment of P′ the set ends cut, the table segments it was cut
    into (the planner lands on one of them or anywhere on the whole, :mod:`solverplan.plan._problem`)."""
    walls = PartitionedWalls(env)  # every collinear vertex merged; the set ends are cut below (at joints too)
    part = make_partition(walls.merged)
    table: list[list[Piece3]] = []
    for seg in part.segments:
        user = walls.to_user([BoundaryPiece(seg.edge, seg.t0, seg.t1)])
        table.append([(p.edge, Fraction(p.t0), Fraction(p.t1)) for p in user])
    cuts: dict[int, set[Fraction]] = {}
    for bset in (start, goal):
        for p in bset.merged().pieces:
            cuts.setdefault(p.edge, set()).update((Fraction(p.t0), Fraction(p.t1)))
    out: list[list[Piece3]] = []
    groups: list[tuple[int, ...]] = []
    for seg_pieces in table:
        first = len(out)
        current: list[Piece3] = []
        for edge, t0, t1 in seg_pieces:
            if current and (t0 in cuts.get(edge, ()) or current[-1][2] in cuts.get(current[-1][0], ())):
                out.append(current)  # a set ends at the collinear vertex between two pieces of the segment
                current = []
            lo = t0
            for c in sorted(x for x in cuts.get(edge, ()) if t0 < x < t1):
                current.append((edge, lo, c))
                out.append(current)
                current, lo = [], c
            current.append((edge, lo, t1))
        out.append(current)
        if len(out) - first > 1:
            groups.append(tuple(range(first, len(out))))
    return out, groups


def heading_margin_of(margins: dict | None, scope: str | None = None) -> Fraction:
    """The query's heading margin δ as an exact rational (its shortest decimal text): from an answer's ``margins``,
    else from the text of its optimality scope, else the default."""
    value: float | None = None
    if margins and "heading" in margins:
        value = float(margins["heading"])
    elif scope:
        found = re.search(r"heading margin ([0-9.eE+-]+) rad", scope)
        if found:
            value = float(found.group(1))
    return Fraction(repr(value if value is not None else DEFAULT_HEADING_MARGIN))


def ceil12(x: Fraction | float) -> Fraction:
    """x rounded up to 12 decimals (exact)."""
    q = Fraction(x)
    scale = 10**12
    return Fraction(-((-q.numerator * scale) // q.denominator), scale)


def tolerance_bound(env: Environment, start: BoundarySet, goal: BoundarySet, *, width: float, floor: Fraction,
                    margins: dict | None, budget: int | None, heading_margin: Fraction,
                    max_rounds: int = 40) -> BoundClaim:
    """The smallest threshold this builder can prove for a most-tolerant plan of min width ``width``: first
    :func:`tolerance_threshold` (at least ``floor``, the certified min width); while the exact margin-free closure
    still finds a plan wider than the threshold, the threshold rises just above that plan's narrowest stage (so
    each round excludes the plan found) — the answer's gap is then the price of the planner's margins, stated by
    the checker. Raises :class:`NoBound` after ``max_rounds`` rounds."""
    w = max(tolerance_threshold(env, width, margins), floor)
    spent = [0]  # the rounds share MAX_PROOF_WORK
    for _ in range(max_rounds):
        try:
            return bound_claim(env, start, goal, budget=budget, threshold=w, heading_margin=heading_margin, spent=spent)
        except NoBound as exc:
            if exc.width is None or not math.isfinite(exc.width):
                raise
            w = max(w + Fraction(1, 10**12), ceil12(exc.width + 1e-9))
    raise NoBound(f"no threshold proved in {max_rounds} rounds (the last tried: {float(w):.12g} rad)")


def tolerance_threshold(env: Environment, width: float, margins: dict | None) -> Fraction:
    """w = W* + 2·end margin + 10⁻⁹, rounded up to 12 decimals: what the margin-free class can prove about a plan
    of min width W* found with the margins of ``margins`` (see the module docstring)."""
    if margins and "end" in margins:  # answers that record the end margin as applied
        end = float(margins["end"])
    else:
        end = Margins.for_environment(env, heading_margin=float((margins or {}).get("heading", DEFAULT_HEADING_MARGIN)),
                                      safe_margin=float((margins or {}).get("safe", 1e-9)),
                                      corner_clearance=(margins or {}).get("corner_clearance")).end_margin
    return ceil12(Fraction(width) + 2 * Fraction(end) + Fraction(1, 10**9))


def bound_claim(env: Environment, start: BoundarySet, goal: BoundarySet, *, budget: int | None,
                threshold: Fraction = Fraction(0), heading_margin: Fraction, spent: list[int] | None = None) -> BoundClaim:
    """The invariant proving that no plan of the class (module docstring) with ≤ ``budget`` stages (None: any
    number) whose intervals are wider than ``threshold`` takes ``start`` to ``goal``.

    Raises :class:`NoBound` when the exact closure reaches the goal (naming the stage count), lists more than
    :data:`MAX_BELIEFS` beliefs, or would take more work than :data:`MAX_PROOF_SEGMENTS` and :data:`MAX_PROOF_WORK`
    allow (``spent``: the work of earlier rounds, in units of the table's segments; this round's is added)."""
    table, groups = refined_table(env, start, goal)
    if len(table) > MAX_PROOF_SEGMENTS:
        raise NoBound(f"the exact closure over a table of {len(table):,} segments is not tried (at most "
                      f"{MAX_PROOF_SEGMENTS:,}: its work grows as the square of the table)")
    edges, nxt = _edges(env)
    geo = Geometry(edges, nxt, table, groups)
    start_pieces = [(p.edge, Fraction(p.t0), Fraction(p.t1)) for p in start.merged().pieces]
    goal_pieces = [(p.edge, Fraction(p.t0), Fraction(p.t1)) for p in goal.merged().pieces]
    start_belief = tuple(sorted(geo.overlapping(start_pieces)))
    goal_set = geo.overlapping(goal_pieces)
    if all(any(lo <= p[1] and p[2] <= hi for e, lo, hi in goal_pieces if e == p[0]) for p in start_pieces):
        raise NoBound("the start set lies in the goal set")
    closure = Closure(geo, heading_margin, threshold)
    depth_of: dict[tuple[int, ...], int] = {start_belief: 0}
    narrowest: dict[tuple[int, ...], float] = {start_belief: math.inf}  # along the path that reached the belief
    frontier = [start_belief]
    depth = 0
    delta = float(heading_margin)
    done = spent[0] if spent is not None else 0
    try:
        while frontier and (budget is None or depth < budget):
            nxt_frontier = []
            for belief in frontier:
                fresh = sum(1 for s in set(belief) if s not in closure._runs)  # sources whose runs this belief computes
                if (len(closure._runs) + fresh) * len(table) + done > MAX_PROOF_WORK:
                    raise NoBound(f"the exact closure would take more than {MAX_PROOF_WORK:,} units of work (sources × "
                                  f"table segments; {len(table):,} segments)")
                for targets, (lo, hi) in closure.successors(belief):
                    nb = tuple(sorted(next_belief(targets)))
                    width = min(narrowest[belief], _stage_width(lo, hi, delta))
                    if set(nb) <= goal_set:
                        stages = depth + 1
                        wider = "" if threshold == 0 else f" with every interval wider than {float(threshold):.12g} rad"
                        raise NoBound(f"a margin-free plan of {stages} stage{'s' if stages > 1 else ''} exists (the exact "
                                      f"closure over the table reaches the goal{wider})", width)
                    if nb not in depth_of:
                        depth_of[nb] = depth + 1
                        narrowest[nb] = width
                        nxt_frontier.append(nb)
                        if len(depth_of) > MAX_BELIEFS:
                            raise NoBound(f"the invariant would list more than {MAX_BELIEFS:,} beliefs")
            frontier = nxt_frontier
            depth += 1
    finally:
        if spent is not None:
            spent[0] += len(closure._runs) * len(table)
    beliefs = tuple(BeliefRecord(b, d) for b, d in depth_of.items())
    return BoundClaim(tuple(tuple(p) for p in table), heading_margin, threshold, budget, beliefs, TABLE_SOURCE,
                      tuple(groups))

