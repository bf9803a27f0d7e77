"""The independent exact checker of certificates: claims in, failures out.

This module re-derives every claim of a :class:`~solverplan.certify.schema.Certificate` in rational
arithmetic. It and its two helpers, :mod:`~solverplan.certify.exact2d` (exact predicates) and
:mod:`~solverplan.certify.rational_atan` (rigorous angles), import only the standard library and
:mod:`solverplan.certify.schema`; they use no floats, no planner, no graph builder and no geometry
kernel of solverplan, so a bug there cannot hide a bug here (``tests/certify/test_check.py`` keeps
it so with an ``ast`` test).

What is checked
---------------
1. **Environment.** Each ring has ≥ 3 vertices and no repeated consecutive vertex; the outer ring is
   counter-clockwise and every hole clockwise (exact signed areas), so the free space is on the left
   of every directed edge; no two edges meet except neighbours at their shared vertex (every pair
   of edges, exactly); every hole lies inside the outer ring and outside the other holes.
2. **Segments and sets.** Each named segment lies on its edge (``a``, ``b`` are the points of ``t0``,
   ``t1``); start, goal and position pieces are intervals of existing edges.
3. **Moves** (each stage, each move; a stage has one move per source: a move repeating another's edge and
   source interval is malformed) — with source points P, Q (parameters p < q on edge e, vector E),
   cone d_lo → d_hi, target edge e′ (line L) and target range (segment or edge) τ ∈ [lo, hi]. A source
   without a named segment may run on along the straight wall through e (consecutive collinear edges: the
   vertices between them are no corners), p < 0 or q > 1 on e's line, as a target without a named segment
   may; it then counts as its pieces on the wall's edges (chaining, ends) and the wall's other edges may meet
   the swept region only within [P, Q]:

   - both directions leave e into the free space: cross(E, d) > 0; the cone turns counter-clockwise
     from d_lo to d_hi: cross(d_lo, d_hi) ≥ 0 (with both directions on the left of E, the turn is
     then in [0, π));
   - the four **corner rays** X + s·d (X ∈ {P, Q}, d ∈ {d_lo, d_hi}) meet L at s > 0 strictly
     inside the open target range. A source end that is a vertex of P (p = 0 or q = 1) is not a
     robot position: its rays need only s ≥ 0 and the closed range, since the positions next to it
     land next to its hit, on the inner side (the hit parameter is affine and strictly monotone in
     the source parameter). This is what admits adjacent edges (paper Cor. 1), where the shared
     vertex is its own hit (s = 0);
   - the claimed ``target`` [c, d] is either the whole target range or exactly the image
     [min τ, max τ] of the corner rays (so it holds every landing point, and says nothing more);
   - the **swept region**. All rays from [P, Q] with directions in the cone that stop at L form
     R = (PQ ⊕ cone) ∩ {the side of L facing the source}: a Minkowski sum of a segment and a
     convex cone, cut by a half-plane, hence convex, and equal to the convex hull of P, Q and the
     four corner hits. The move is sound if no boundary point other than those it must touch lies
     in R: every environment edge is clipped exactly against R (Liang–Barsky on the hull's
     half-planes) and
       * the source edge e may meet R only within [P, Q] (R ∩ line(e) = PQ, since R is on the
         left of e), the target edge e′ only within the target range (R ∩ L is the hull of the hits);
       * any other edge must miss R entirely, except that it may touch R in the single point P
         (or Q) when that end is a vertex of P — the neighbour edge of e meeting it there.
     Then the interior of R holds no boundary point; it is connected and, near the middle of PQ, on
     the free side of e, so it is free space; the sides of R from P and Q hold no boundary point
     either, so every trajectory from a robot position in [P, Q] runs through free space and first
     meets the boundary on the open target range. The check is conservative at exact grazing
     contacts (a wall parallel to a cone side through a vertex end, a corner ray through a vertex of
     P): those certificates are rejected, never wrongly accepted.
4. **Chaining.** The rule is *coverage*: the targets of stage k are covered by the union of the
   sources of stage k + 1 on the same edge (closed intervals; a stage may have more sources than the
   previous stage can reach, and one target may be covered by several sources); stage 0's sources
   cover the start set; the last stage's targets lie in the goal set (plans, funnels) or are covered
   by the first cycle stage's sources (cycles: the cycle closes). Every end of a source must be
   accounted for — an end of its edge or of a named segment, an end of the start or goal set (a plan
   may land on the part of a segment between them and leave from it later), an end of a set flowing
   into the stage (the previous stage's targets; for the first cycle stage also the last stage's) or
   of another source of the stage on that edge (a split) — so a source says nothing gratuitous.
   Given the query (``expected_start``, ``expected_goal``), the start and goal sets must be exactly it.
5. **Headings.** A robot executes one heading θ measured from the edge it is on, so a stage's action
   interval is the set of headings common to its moves' cones, each measured from its own source
   edge: [max_j θ(d_lo,j), min_m θ(d_hi,m)]. It must be non-empty (exactly: the sign of a cross
   product); a claimed ``interval`` must lie inside it; ``claims.min_width`` must not exceed any
   stage's width; ``tolerance`` = min_width / 2 exactly; ``bounces`` = number of stages. Decimal
   claims must also be *tight*: within 10⁻⁹ of the exact value, and so must each move's cone be
   to the stage's common cone (a certificate claims what it proves; a loosened or a gratuitously
   widened number is as wrong as an inflated one, and tampering with any single number is caught).
6. **Positions** (funnels): the claimed positions after a stage equal the union of the exact images
   [min τ, max τ] of its moves.
7. **Cycles.** Every cycle stage has one move; the exact affine map of a direction d from source
   parameter t to target parameter τ is τ = α t + β with α = cross(E_s, d) / cross(E_t, d),
   β = cross(A − C, d) / cross(E_t, d) (A, C the first vertices, E_s, E_t the vectors of the source
   and target edges). The composed return map of the nominal directions must equal the claimed
   α, β; the fixed point must be β / (1 − α) and lie in the entry source; the claimed contraction must
   equal the worst case Π_k max(|α_k(d_lo)|, |α_k(d_hi)|) and be < 1. **Why the cone's extremes
   suffice:** every direction of the cone is a positive multiple of d(λ) = (1 − λ) d_lo + λ d_hi,
   λ ∈ [0, 1]; α is homogeneous of degree 0 in d, so α(d(λ)) is a ratio of two functions linear in
   λ; the denominator cross(E_t, d(λ)) vanishes nowhere on [0, 1] (every direction of a sound cone
   meets L) and the numerator cross(E_s, d(λ)) is positive (every direction leaves e into the free
   space). A linear-fractional function with a non-vanishing denominator is monotone on an interval,
   so |α| over the cone is largest at d_lo or d_hi — the exact, trigonometry-free form of the
   monotonicity of the contraction coefficient C(θ, φ) (paper, Lemma 2). Choices at different
   bounces are independent and |α| of a composition is the product, so the worst case of the cycle
   is the product of the per-stage worst cases.
8. **Optimality.** Without a ``bound`` block the bound of a search or LP is not re-derived here (that would
   mean re-running the planner); its consistency with the checked claims is, and the report lists it as not
   checked. With a valid ``bound`` block (10.) it is re-derived: a ``fewest`` plan of k bounces needs K = k − 1,
   w = 0 (then no plan has fewer bounces); a ``tolerance`` / ``constant`` plan needs w ≥ its certified min width
   and K ≥ its bounces (then no plan within K is wider than w: optimal within w − min width, reported).
9. **Localisation** (``localize``): the final position set (the last stage's positions) lies on one
   edge, or on one straight wall (consecutive collinear edges), and the interval from its lowest to its
   highest parameter (along the wall's line) is shorter than ``claims.epsilon`` in arc length:
   (t_hi − t_lo)² · |E|² < ε², exactly (no square root). A version-1 localisation
   certificate has no ε: the report says so and lists the claim as not checked.

10. **Bounds** (``bound`` blocks; ``infeasible`` certificates have nothing else): an inductive invariant over
    belief states proving that no plan exists in a class, with the exact successor relation of
    :mod:`solverplan.certify.invariant` (its docstring has the semantics and why the cells are exact). Checked:
    the table covers every edge exactly once with contiguous straight segments, and each of its groups (if any)
    is a run of ≥ 2 consecutive collinear segments, no segment in two; δ ∈ [0, 3/4), w ≥ 0, K ≥ 0;
    the beliefs are non-empty, ascending, distinct sets of table segments; the first is the start set exactly,
    at depth 0, and the start set does not lie in the goal set (no plan of 0 stages); every successor of a
    belief of depth < K (any depth when K is null) — each source landing on one table segment or anywhere on one
    group, the next belief every segment landed on — contains a listed belief of depth ≤ its depth + 1
    and none is a goal stage (every segment of the next belief meets the goal set). By induction on the stages left, no plan of the
    class with ≤ K stages takes the start set to the goal set; the report states this under ``proved``.

What is certified
-----------------
The report always states what the certificate speaks about, whether or not the query was pinned with
``expected_rings`` / ``expected_start`` / ``expected_goal``: the environment (name, SHA-256 of its exact
rings — the ``environment.sha256`` of the planner's answers —, vertex, edge and hole counts), the start
and goal sets as boundary-set strings (``e0:0.1:0.9``, merged per edge) with their total arc length, the
kind and every claim (bounces, widths, tolerance, the cycle's map and contraction, ε, optimality). A
certificate whose start set was cut down is a true statement about a smaller query: it stays valid,
and the report shows the smaller set.

Exactness
---------
Everything above is rational arithmetic on the certificate's numbers (``fractions.Fraction``) with
the exact predicates of :mod:`solverplan.certify.exact2d` (and integer linear functionals in 10.), except the
angles of 5. and the comparisons of 10. with δ and w. Those are decided
with the rigorous rational arctangent enclosures of :mod:`solverplan.certify.rational_atan`, refined
until each comparison is decided (it always is: see that module).

>>> from solverplan.certify.schema import Certificate, EXAMPLE
>>> report = check_certificate(Certificate.from_json(EXAMPLE))
>>> report.valid, dict(report.checked)["corner_rays"]
(True, 4)
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Callable, Iterable, Sequence

from solverplan.certify.exact2d import (
    affine_coefficients,
    along,
    clip_segment,
    convex_hull,
    cross,
    dot,
    inside_ring,
    line_hit,
    orient,
    segments_meet,
    signed_area2,
    sub,
    uncovered,
    union,
)
from solverplan.certify.rational_atan import (
    MAX_BITS,
    Undecided,
    angle_enclosure,
    compare_angle,
    difference_vector,
    heading_vector,
)
from solverplan.certify.invariant import next_belief, Closure, Geometry, TableError
from solverplan.verdict import Failure, Verdict
from solverplan.certify.schema import (MODEL_KINDS, BoundClaim, Certificate, CycleClaim, EnvironmentRecord, ModelCertificate, Move,
                                       Piece, Point, SegmentRecord, Stage, _terminating_decimal, number_text)

__all__ = ["Failure", "CheckReport", "check_certificate", "certified", "WIDTH_SLACK"]  # Failure: re-exported

WIDTH_SLACK = Fraction(1, 10**9)
"""How far below the exact value a claimed width (or inside the cone a claimed interval end) may be."""

_ZERO = Fraction(0)
_PI_FLOOR = Fraction(314159265358979323846, 10**20)  # π's first 21 digits: below π, above the double nearest it
_ONE = Fraction(1)


# ======================================================================= message formatting
def _approx(x: Fraction, digits: int = 6) -> str:
    """A decimal approximation of x (integer arithmetic), for messages."""
    scaled = round(Fraction(x) * 10**digits)
    minus = "-" if scaled < 0 else ""
    text = str(abs(scaled)).rjust(digits + 1, "0")
    whole, frac = text[:-digits], text[-digits:].rstrip("0")
    return f"{minus}{whole}.{frac}" if frac else f"{minus}{whole}"


def _num(x: Fraction | int) -> str:
    text = number_text(x)
    return text if len(text) <= 18 else "≈" + _approx(Fraction(x), 9)


MAX_FAILURE_LINE = 200
"""Longest failure line (``claim: message``, characters): every message is cut here, in :meth:`_Checker.fail`."""

MAX_QUOTED = 40
"""Longest run of the certificate's own text (a name, a method) a message quotes (characters)."""

PROVING_METHODS = ("search-exhausted", "lp-duality", "milp", "bisection", "exact-check", "symmetry")
"""The optimality methods that can prove what they claim (``solverplan.result.Method``; a test keeps them equal)."""

METHODS = (*PROVING_METHODS, "heuristic", "none")
"""Every optimality method a certificate may name: ``heuristic`` and ``none`` prove nothing."""

PLAN_OBJECTIVES = ("fewest", "tolerance", "sum", "constant")
"""What a plan optimises (``solverplan.choices.Objective``; a test keeps them equal)."""

PATROL_OBJECTIVES = ("contraction", "tolerance", "rate")
"""What a patrol optimises (``solverplan.choices.PatrolObjective``; a test keeps them equal)."""

OBJECTIVES: dict[str, tuple[str, ...]] = {
    "plan": PLAN_OBJECTIVES,
    "infeasible": PLAN_OBJECTIVES,  # the objective the query asked for
    "funnel": ("funnel-fewest", "localize-fewest"),  # version 1 wrote a localisation as a funnel
    "localize": ("localize-fewest",),
    "cycle": (*(f"patrol-{o}" for o in PATROL_OBJECTIVES), "contraction"),  # contraction: a cycle's own, bound checked
}
"""The ``claims.objective`` each kind of certificate may name: any other string is an unknown objective (a
failure); a known one is confirmed only by a re-derived bound, else listed as not checked."""


def _quote(text: object) -> str:
    """``repr(text)`` cut to :data:`MAX_QUOTED` characters with ``…``."""
    shown = repr(text)
    return shown if len(shown) <= MAX_QUOTED else shown[: MAX_QUOTED - 1] + "…"


def _shorten(text: str, limit: int) -> str:
    """``text`` on one line of at most ``limit`` characters (cut with ``…``)."""
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: max(limit - 1, 0)] + "…"


def _pt(p: Point) -> str:
    return f"({_num(p[0])}, {_num(p[1])})"


def _heading_value(v: Point) -> Fraction:
    lo, hi = angle_enclosure(v, 40)
    return (lo + hi) / 2


def _heading(v: Point) -> str:
    """The angle of v (radians), to 6 decimals, for messages."""
    return _approx(_heading_value(v), 6)


# ======================================================================= the report
@dataclass(frozen=True, slots=True)
class CheckReport(Verdict):
    """The verdict of :func:`check_certificate`, for a certificate of any kind.

    The :class:`~solverplan.verdict.Verdict` every check gives, with what the certificate speaks about: ``version``,
    ``environment``, ``start``, ``goal`` and ``claims`` (see :func:`certified`), always, so that a verdict never
    hides which query it answers.

    Parameters
    ----------
    valid
        True iff there are no ``failures``.
    failures
        Every claim that does not hold (:class:`~solverplan.verdict.Failure`: its path in the certificate and what
        was found).
    checked
        What was re-derived exactly, as ``(name, count)`` pairs: stages, moves, corner rays, edge-against-region
        tests, chaining links, angle decisions (a model certificate: its own, e.g. doors, rooms, views).
    not_checked
        Claims taken on trust, in words (the optimality bound of a search without a ``bound`` block, for instance).
    kind
        The certificate's kind (``plan``, ``funnel``, ``cycle``, ``infeasible``, ``rooms``, ``pursuit``, ...).
    version
        The certificate format's version.
    environment
        Its environment: name, SHA-256 of the exact rings, vertex, edge and hole counts.
    start, goal
        A bounce certificate's start and goal sets (``{"set", "length", "length_exact"}``); ``None`` for the models'.
    claims
        Every claim, as the report states them.
    proved
        What a valid certificate proves, in words.
    scope
        What the statements speak about, in words.

    Examples
    --------
    >>> import solverplan as sp
    >>> env = sp.load_environment("square")
    >>> report = sp.check_certificate(sp.certificate(sp.find_plan(env, "e0:0.1:0.9", "e2"), env=env))
    >>> isinstance(report, sp.Verdict), report.valid, report.kind, report.start["set"], report.failures
    (True, True, 'plan', 'e0:0.1:0.9', ())
    >>> print(report.to_text().splitlines()[0])
    certificate (plan): VALID
    """

    valid: bool
    failures: tuple[Failure, ...]
    checked: tuple[tuple[str, int], ...]
    not_checked: tuple[str, ...]
    kind: str
    version: int = 0
    environment: dict[str, Any] = field(default_factory=dict)
    start: dict[str, Any] | None = None
    goal: dict[str, Any] | None = None
    claims: dict[str, Any] = field(default_factory=dict)
    proved: tuple[str, ...] = ()
    scope: str = ""
    """What the statements speak about, in words."""

    @property
    def title(self) -> str:
        return f"certificate ({self.kind})"

    def subject_json(self) -> dict[str, Any]:
        return {"version": self.version, "environment": dict(self.environment), "start": self.start,
                "goal": self.goal, "claims": dict(self.claims)}

    def subject_lines(self) -> list[str]:
        lines = []
        env = self.environment
        if env:
            name = repr(env["name"]) if env["name"] else "(unnamed)"
            lines.append(f"environment: {name}, sha256 {env['sha256']}, {env['vertices']} vertices, "
                         f"{env['edges']} edges, {env['holes']} hole{'' if env['holes'] == 1 else 's'}")
        if self.kind not in MODEL_KINDS:  # a bounce certificate speaks about a start and a goal set
            lines.append(f"start: {_set_line(self.start)}")
            lines.append(f"goal: {_set_line(self.goal) if self.goal is not None else 'none (a cycle: the cycle is the goal)'}")
        return lines

    def claim_lines(self) -> list[str]:
        if self.kind in MODEL_KINDS:  # a model certificate: its claims in words
            return ["claims: " + (", ".join(f"{k.replace('_', ' ')} {_short_claim(v)}" for k, v in self.claims.items())
                                  or "none")]
        return _claim_lines(self.claims)


_BOUNCE_SCOPE = ("a point robot in this environment that moves straight between bounces and, at each bounce, executes "
                 "one heading measured from the edge it is on; the start and goal sets above")


def _short_claim(value: Any) -> str:
    if isinstance(value, str) and ("/" in value or "." in value) and value.replace("/", "").replace(".", "").lstrip("-").isdigit():
        return _short(value)
    return str(value)


def _set_line(summary: dict[str, Any] | None) -> str:
    if summary is None:
        return "none"
    approx = "" if summary["length_exact"] else "≈ "
    return f"{summary['set']} (length {approx}{summary['length']})"


def _short(text: object) -> str:
    """An exact number's text, or ≈ its 9-decimal approximation when longer than 18 characters."""
    text = str(text)
    return text if len(text) <= 18 else "≈" + _approx(Fraction(text), 9)


def _claim_lines(claims: dict[str, Any]) -> list[str]:
    """The claims of :attr:`CheckReport.claims` as text lines (``claims: bounces 2, min_width …``)."""
    main = [f"{key} {claims[key] if key == 'objective' else _short(claims[key])}"
            for key in ("bounces", "min_width", "tolerance", "sum_width", "objective") if key in claims]
    lines = ["claims: " + (", ".join(main) or "none")]
    if "bound" in claims:
        b = claims["bound"]
        budget = "any number of stages" if b["budget"] is None else f"at most {b['budget']} stages"
        lines.append(f"bound: no plan with {budget}, every interval wider than {_short(b['threshold'])} rad inside "
                     f"[δ, π − δ], δ = {_short(b['heading_margin'])} rad (table of {b['table_segments']} segments"
                     f"{': ' + b['table_source'] if b.get('table_source') else ''}; invariant of {b['beliefs']} beliefs)")
    if "cycle" in claims:
        c = claims["cycle"]
        visits = f", visits {c['visits']}" if "visits" in c else ""
        lines.append(f"cycle: stages {c['stages']}, return map t -> {_short(c['alpha'])} t + {_short(c['beta'])}, "
                     f"fixed point {_short(c['fixed_point'])}, contraction {_short(c['contraction'])} < 1{visits}")
    if "epsilon" in claims:
        eps = claims["epsilon"]
        if eps is None:
            lines.append("epsilon: none (a version-1 localisation certificate carries no ε claim)")
        else:
            final = claims.get("final")
            where = f": the final positions {_set_line(final)} lie in one interval shorter than ε" if final else ""
            lines.append(f"epsilon: {_short(eps)}{where}")
    if "optimality" in claims:
        o = claims["optimality"]
        bound = "no bound" if o["bound"] is None else f"bound {_short(o['bound'])}"
        lines.append(f"optimality: {o['method']}, {'proved' if o['proved'] else 'not proved'}, {bound} (consistency only)")
    return lines


@dataclass
class _Edge:
    id: int
    ring: int
    a: Point
    b: Point

    @property
    def vector(self) -> Point:
        return sub(self.b, self.a)


@dataclass
class _MoveResult:
    """What the move checks learnt, for the stage, chaining, position and cycle checks."""

    move: Move
    edge_vector: Point
    w_lo: Point  # d_lo in the source edge's frame (its angle is the heading)
    w_hi: Point
    image: tuple[Fraction, Fraction] | None = None  # [min τ, max τ] on the target edge, when sound
    sound: bool = False


# ======================================================================= the checker
Query = Sequence[tuple[int, Fraction, Fraction]]
"""A start or goal set as (edge, t0, t1) pieces, to compare a certificate's own with."""


def check_certificate(
    cert: Certificate | ModelCertificate,
    *,
    expected_rings: Sequence[Sequence[Point]] | None = None,
    expected_start: Query | None = None,
    expected_goal: Query | None = None,
    stop: Callable[[], bool] | None = None,
) -> CheckReport:
    """Check every claim of ``cert`` in exact arithmetic; see the module docstring for what and how.

    Parameters
    ----------
    cert
        A parsed certificate.
    expected_rings
        If given, the certificate's environment must have exactly these (normalised) rings, e.g.
        ``load_environment(path).rings``: the certificate then speaks about that environment.
    expected_start, expected_goal
        If given, the query the certificate must answer: its start (goal) set must be this union of
        pieces, exactly. Without them, a certificate with a smaller start or a larger goal than asked
        for is a true statement about another query, and valid.
    stop
        Asked now and then (a caller's deadline, e.g. ``--timeout``): once it returns true the check stops with
        :class:`CheckStopped` instead of a verdict; ``None``: no limit. Certificates of the other robot models are
        checked without it.

    Returns
    -------
    CheckReport
        ``valid`` with no failures, or every failure found, each naming its claim.

    Raises
    ------
    CheckStopped
        ``stop()`` returned true before the check decided.

    Examples
    --------
    >>> import solverplan as sp
    >>> from fractions import Fraction
    >>> env = sp.load_environment("l_shape")
    >>> cert = sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env)
    >>> report = sp.check_certificate(cert, expected_rings=env.rings)
    >>> report.valid, report.kind, report.claims["bounces"]
    (True, 'plan', 1)

    Checked against another query, the same certificate is rejected, and the failure names the claim:

    >>> report = sp.check_certificate(cert, expected_goal=[(0, Fraction(0), Fraction(1, 5))])
    >>> report.valid, report.failures[0].claim, report.failures[0].message
    (False, 'goal', "is e0:[0, 0.3], but the query's goal set is e0:[0, 0.2]")
    """
    if isinstance(cert, ModelCertificate):  # the other robot models (version 4): their own claims, the same verdict
        from solverplan.certify.check_models import check_model_certificate

        report = check_model_certificate(cert, expected_rings=expected_rings)
        if expected_start is None and expected_goal is None:
            return report
        wrong = Failure("start" if expected_start is not None else "goal", f"a {cert.kind} certificate has no start or goal set")
        return replace(report, valid=False, failures=(wrong, *report.failures), proved=())
    checker = _Checker(cert, stop)
    checker.run(expected_rings)
    if expected_start is not None:
        checker.check_query("start", cert.start, expected_start)
    if expected_goal is not None:
        checker.check_query("goal", cert.goal or (), expected_goal)
    return checker.report()


def _a(word: str) -> str:
    """``word`` with its indefinite article (an infeasible, a plan)."""
    return f"{'an' if word[:1] in 'aeiou' else 'a'} {word}"


class CheckStopped(Exception):
    """The check was told to stop (``stop``, :func:`check_certificate`) before deciding: no verdict at all."""


class _Checker:
    def __init__(self, cert: Certificate, stop: Callable[[], bool] | None = None) -> None:
        self.cert = cert
        self.stop = stop
        self.failures: list[Failure] = []
        self.not_checked: list[str] = []
        self.counts = {
            "stages": 0,
            "moves": 0,
            "corner_rays": 0,
            "edge_tests": 0,
            "links": 0,
            "angle_decisions": 0,
        }
        self.edges: list[_Edge] = []
        self.segments: dict[int, SegmentRecord] = {}
        self.proved: list[str] = []
        self.optimality_rederived = False
        self.bound_ok = False

    def tick(self) -> None:
        """Stop (:class:`CheckStopped`) once ``stop()`` says so: asked once per move, angle comparison and bound
        belief, each far shorter than the time a caller's deadline leaves."""
        if self.stop is not None and self.stop():
            raise CheckStopped(f"the exact check was stopped at its time limit after {dict(self.counts)}")

    def fail(self, claim: str, message: str) -> None:
        claim = _shorten(claim, 60)
        self.failures.append(Failure(claim, _shorten(message, MAX_FAILURE_LINE - len(claim) - 2)))

    def report(self) -> CheckReport:
        summary = certified(self.cert)
        return CheckReport(
            valid=not self.failures,
            failures=tuple(self.failures),
            checked=tuple((k, v) for k, v in self.counts.items()
                          if self.cert.kind != "infeasible" or k.startswith("bound_") or k == "angle_decisions"),
            not_checked=tuple(self.not_checked),
            kind=self.cert.kind,
            version=self.cert.version,
            environment=summary["environment"],
            start=summary["start"],
            goal=summary["goal"],
            claims=summary["claims"],
            proved=tuple(self._main_statement() + self.proved) if not self.failures else (),
            scope=_BOUNCE_SCOPE,
        )

    def _main_statement(self) -> list[str]:
        """What a valid plan, funnel, localisation or cycle certificate proves, in words (``verify`` prints it)."""
        cert = self.cert
        if cert.kind == "infeasible":
            return []
        k, width = cert.claims.bounces, _num(cert.claims.min_width)
        if cert.kind == "cycle" and cert.cycle is not None:
            return [f"executing the entry stages once and then the {len(cert.cycle.stages)} cycle stages forever, with "
                    f"any heading inside each stage's interval, the robot never leaves the cycle's segments and converges "
                    f"to the fixed point t = {_num(cert.cycle.fixed_point)}, by at least the factor "
                    f"{_num(cert.cycle.contraction)} < 1 per cycle; every interval is at least {width} rad wide"]
        if not cert.stages:
            return ["the start set lies in the goal set: the robot is there with no bounce (a plan of 0 stages)"]
        out = [f"from every point of the start set, executing at stage j any heading inside its interval lands the robot "
               f"in the goal set after {k} bounce{'s' if k != 1 else ''}; every interval is at least {width} rad wide"]
        if cert.kind in ("funnel", "localize"):
            out.append("after every stage the robot is within the claimed positions")
        if cert.kind == "localize" and cert.claims.epsilon is not None:
            out.append(f"the final positions lie in one interval shorter than ε = {_num(cert.claims.epsilon)}")
        return out

    # ------------------------------------------------------------------ the run
    def run(self, expected_rings: Sequence[Sequence[Point]] | None) -> None:
        cert = self.cert
        if expected_rings is not None:
            self.check_expected(expected_rings)
        if not self.check_environment():
            return  # nothing else means anything on an invalid environment
        self.check_segments()
        self.check_pieces(cert.start, "start")
        if cert.goal is not None:
            self.check_pieces(cert.goal, "goal")
        if cert.bound is not None:
            self.check_bound(cert.bound)
        if cert.kind == "infeasible":
            self.check_objective(self.bound_ok)  # the objective the query asked for: a known one, at least
            return
        if not cert.stages:
            self.check_no_stages()
            return
        results: list[list[_MoveResult | None]] = []
        for k, stage in enumerate(cert.stages):
            self.counts["stages"] += 1
            self.check_one_move_per_source(k, stage)
            results.append([self.check_move(f"stages[{k}].moves[{m}]", move) for m, move in enumerate(stage.moves)])
        widths = [self.check_stage_headings(k, stage, results[k]) for k, stage in enumerate(cert.stages)]
        self.check_chaining(results)
        self.check_source_ends()
        for k, stage in enumerate(cert.stages):
            if stage.positions is not None:
                self.check_positions(k, stage, results[k])
        self.check_claims(widths)
        if cert.cycle is not None:
            self.check_cycle(cert.cycle, results)
        if cert.kind == "localize":
            self.check_epsilon()

    def check_no_stages(self) -> None:
        """A plan or funnel of no stages: its start set lies in its goal set (exactly), it claims 0 bounces and a
        width no wider than the whole heading range (0, π)."""
        cert = self.cert
        goal = _merged((p.edge, p.t0, p.t1) for p in (cert.goal or ()))
        for i, piece in enumerate(cert.start):
            self.counts["links"] += 1
            gap = uncovered(piece.t0, piece.t1, goal.get(piece.edge, []))
            if gap is not None:
                self.fail("stages", f"none, but t in ({_num(gap[0])}, {_num(gap[1])}) of edge {piece.edge} (part of "
                                    f"start[{i}]) is not in the goal set")
        self.check_claims([])

    # ------------------------------------------------------------------ environment
    def check_expected(self, expected: Sequence[Sequence[Point]]) -> None:
        rings = self.cert.environment.rings
        if len(rings) != len(expected):
            self.fail("environment", f"has {len(rings)} rings, the given environment has {len(expected)}")
            return
        for r, (mine, theirs) in enumerate(zip(rings, expected)):
            if len(mine) != len(theirs):
                self.fail(f"environment.rings[{r}]", f"has {len(mine)} vertices, the given environment's ring has {len(theirs)}")
                return
            for i, (p, q) in enumerate(zip(mine, theirs)):
                if (Fraction(p[0]), Fraction(p[1])) != (Fraction(q[0]), Fraction(q[1])):
                    self.fail(f"environment.rings[{r}][{i}]", f"is {_pt(p)}, the given environment has {_pt(q)}")
                    return

    def check_query(self, where: str, mine: Sequence[Piece], expected: Query) -> None:
        have = _merged((p.edge, p.t0, p.t1) for p in mine)
        want = _merged(expected)
        if have != want:
            self.fail(where, f"is {self._pieces_text(have)}, but the query's {where} set is {self._pieces_text(want)}")

    def check_environment(self) -> bool:
        rings = self.cert.environment.rings
        before = len(self.failures)
        for r, ring in enumerate(rings):
            where = f"environment.rings[{r}]"
            if len(ring) < 3:
                self.fail(where, f"has {len(ring)} vertices; a ring needs at least 3")
                continue
            for i in range(len(ring)):
                if ring[i] == ring[(i + 1) % len(ring)]:
                    self.fail(where, f"repeats vertex {i} {_pt(ring[i])}")
                    break
            else:
                area2 = signed_area2(ring)
                if r == 0 and area2 <= 0:
                    self.fail(where, f"the outer ring must be counter-clockwise (free space on the left); its signed area is {_num(area2 / 2)}")
                elif r > 0 and area2 >= 0:
                    self.fail(where, f"a hole must be clockwise (free space on the left); its signed area is {_num(area2 / 2)}")
        if len(self.failures) > before:
            return False
        edges: list[_Edge] = []
        nxt: list[int] = []
        for r, ring in enumerate(rings):
            first = len(edges)
            for i in range(len(ring)):
                edges.append(_Edge(len(edges), r, ring[i], ring[(i + 1) % len(ring)]))
                nxt.append(first + (i + 1) % len(ring))
        # every pair of edges, pruned exactly by x-extent
        order = sorted(range(len(edges)), key=lambda i: min(edges[i].a[0], edges[i].b[0]))
        for pos, i in enumerate(order):
            ei = edges[i]
            x_max = max(ei.a[0], ei.b[0])
            y_lo, y_hi = min(ei.a[1], ei.b[1]), max(ei.a[1], ei.b[1])
            for j in order[pos + 1 :]:
                ej = edges[j]
                if min(ej.a[0], ej.b[0]) > x_max:
                    break
                if max(ej.a[1], ej.b[1]) < y_lo or min(ej.a[1], ej.b[1]) > y_hi:
                    continue
                if nxt[i] == j or nxt[j] == i:
                    e_in, e_out = (ei, ej) if nxt[i] == j else (ej, ei)
                    v = e_in.b  # the shared vertex: they may meet only there
                    if orient(e_in.a, v, e_out.b) == 0 and dot(sub(e_in.a, v), sub(e_out.b, v)) > 0:
                        self.fail("environment", f"edges {e_in.id} and {e_out.id} fold back onto each other at {_pt(v)}")
                        return False
                    continue
                if segments_meet(ei.a, ei.b, ej.a, ej.b):
                    lo, hi = sorted((i, j))
                    self.fail("environment", f"edge {lo} meets edge {hi}: the boundary is not simple")
                    return False
        for h in range(1, len(rings)):
            if not inside_ring(rings[h][0], rings[0]):
                self.fail(f"environment.rings[{h}]", "the hole lies outside the outer ring")
                return False
            for g in range(1, len(rings)):
                if g != h and inside_ring(rings[h][0], rings[g]):
                    self.fail(f"environment.rings[{h}]", f"the hole lies inside hole ring {g}")
                    return False
        self.edges = edges
        self.nxt = nxt
        self._find_walls(nxt)
        return True

    def _find_walls(self, nxt: Sequence[int]) -> None:
        """The straight walls: maximal chains of consecutive edges of a ring on one line, in one direction (a
        vertex with an angle of exactly π between them is no corner). For every edge e, ``wall[e]`` = (w, o, s):
        the first edge w of its chain and the affine map t ↦ o + s·t from e's parameter to the parameter along
        w's line (exact); ``wall_end[w]``: the parameter of the chain's last point on that line."""
        n = len(self.edges)
        prev = [0] * n
        for i, j in enumerate(nxt):
            prev[j] = i

        def straight(i: int, j: int) -> bool:
            u, v = self.edges[i].vector, self.edges[j].vector
            return cross(u, v) == 0 and dot(u, v) > 0

        self.wall: list[tuple[int, Fraction, Fraction]] = [(i, _ZERO, _ONE) for i in range(n)]
        self.wall_end: dict[int, Fraction] = {i: _ONE for i in range(n)}
        for w in range(n):
            if straight(prev[w], w) or not straight(w, nxt[w]):
                continue  # not the first edge of a chain of two or more
            base, vec = self.edges[w].a, self.edges[w].vector
            norm = dot(vec, vec)
            j = w
            while True:
                e = self.edges[j]
                offset, scale = dot(sub(e.a, base), vec) / norm, dot(e.vector, vec) / norm
                self.wall[j] = (w, offset, scale)
                self.wall_end[w] = offset + scale
                if not straight(j, nxt[j]):
                    break
                j = nxt[j]

    def wall_range(self, edge: int) -> tuple[Fraction, Fraction]:
        """The straight wall through ``edge`` in ``edge``'s own parameter ([0, 1] when it has no collinear
        neighbour; beyond it the line runs on over the neighbours)."""
        w, offset, scale = self.wall[edge]
        return (-offset / scale, (self.wall_end[w] - offset) / scale)

    def on_walls(self, edge: int, a: Fraction, b: Fraction) -> list[tuple[int, Fraction, Fraction]]:
        """The part [a, b] of ``edge``'s line (within its straight wall) as pieces of the wall's edges, each
        in its own parameter (pieces of positive length; a single point stays on ``edge``)."""
        if _ZERO <= a and b <= _ONE:
            return [(edge, a, b)]
        w, offset, scale = self.wall[edge]
        lo, hi = offset + scale * a, offset + scale * b
        out = []
        for j in range(len(self.edges)):
            wj, oj, sj = self.wall[j]
            if wj != w:
                continue
            x0, x1 = max(lo, oj), min(hi, oj + sj)
            if x0 < x1:
                out.append((j, (x0 - oj) / sj, (x1 - oj) / sj))
        return out or [(edge, a, b)]

    # ------------------------------------------------------------------ records
    def point_at(self, edge: int, t: Fraction) -> Point:
        e = self.edges[edge]
        return along(e.a, e.vector, t)

    def check_segments(self) -> None:
        n = len(self.edges)
        for i, seg in enumerate(self.cert.segments):
            where = f"segments[{i}]"
            if seg.id in self.segments:
                self.fail(f"{where}.id", f"segment id {seg.id} appears twice")
                continue
            if not 0 <= seg.edge < n:
                self.fail(f"{where}.edge", f"edge {seg.edge} does not exist (edges 0..{n - 1})")
                continue
            if not 0 <= seg.t0 < seg.t1 <= 1:
                self.fail(where, f"[t0, t1] = [{_num(seg.t0)}, {_num(seg.t1)}] is not an interval 0 ≤ t0 < t1 ≤ 1")
                continue
            if seg.a != self.point_at(seg.edge, seg.t0):
                self.fail(f"{where}.a", f"{_pt(seg.a)} is not the point t0 = {_num(seg.t0)} of edge {seg.edge}, {_pt(self.point_at(seg.edge, seg.t0))}")
                continue
            if seg.b != self.point_at(seg.edge, seg.t1):
                self.fail(f"{where}.b", f"{_pt(seg.b)} is not the point t1 = {_num(seg.t1)} of edge {seg.edge}, {_pt(self.point_at(seg.edge, seg.t1))}")
                continue
            self.segments[seg.id] = seg

    def check_pieces(self, pieces: Sequence[Piece], where: str) -> None:
        n = len(self.edges)
        for i, piece in enumerate(pieces):
            if not 0 <= piece.edge < n:
                self.fail(f"{where}[{i}].edge", f"edge {piece.edge} does not exist (edges 0..{n - 1})")
            elif not 0 <= piece.t0 < piece.t1 <= 1:
                self.fail(f"{where}[{i}]", f"[t0, t1] = [{_num(piece.t0)}, {_num(piece.t1)}] is not an interval 0 ≤ t0 < t1 ≤ 1")

    # ------------------------------------------------------------------ one move
    def check_one_move_per_source(self, k: int, stage: Stage) -> None:
        """A stage says once what happens to the robots on each source: a move repeated (same edge and source
        interval) is malformed, even though the statement it repeats may hold."""
        first: dict[tuple[int, tuple[Fraction, Fraction]], int] = {}
        for m, move in enumerate(stage.moves):
            j = first.setdefault((move.edge, move.source), m)
            if j != m:
                self.fail(f"stages[{k}].moves[{m}]", f"repeats the source e{move.edge}:[{_num(move.source[0])}, "
                                                     f"{_num(move.source[1])}] of moves[{j}]: a stage has one move per source")

    def check_move(self, path: str, move: Move) -> _MoveResult | None:
        self.tick()
        self.counts["moves"] += 1
        n = len(self.edges)
        if not 0 <= move.edge < n:
            self.fail(f"{path}.edge", f"edge {move.edge} does not exist (edges 0..{n - 1})")
            return None
        if not 0 <= move.target_edge < n:
            self.fail(f"{path}.target_edge", f"edge {move.target_edge} does not exist (edges 0..{n - 1})")
            return None
        if self.wall[move.target_edge][0] == self.wall[move.edge][0]:
            self.fail(f"{path}.target_edge", f"edge {move.target_edge} lies on the source edge {move.edge}'s line: no ray "
                                             "leaving an edge into the free space comes back to its line")
            return None
        p, q = move.source
        w_lo, w_hi = (_ZERO, _ONE) if move.source_segment is not None else self.wall_range(move.edge)
        if not w_lo <= p < q <= w_hi:
            where = (f"edge {move.edge}" if (w_lo, w_hi) == (_ZERO, _ONE) else
                     f"the straight wall through edge {move.edge} (t in [{_num(w_lo)}, {_num(w_hi)}])")
            self.fail(f"{path}.source", f"[{_num(p)}, {_num(q)}] is not an interval p < q of {where}")
            return None
        sound = True
        if move.source_segment is not None:
            seg = self.segments.get(move.source_segment)
            if seg is None:
                self.fail(f"{path}.source_segment", f"segment {move.source_segment} is not among the certificate's (valid) segments")
                sound = False
            elif seg.edge != move.edge:
                self.fail(f"{path}.source_segment", f"segment {seg.id} lies on edge {seg.edge}, not on the source edge {move.edge}")
                sound = False
            elif not (seg.t0 <= p and q <= seg.t1):
                self.fail(f"{path}.source", f"[{_num(p)}, {_num(q)}] is not within segment {seg.id} ([{_num(seg.t0)}, {_num(seg.t1)}] of edge {seg.edge})")
                sound = False
        # Without a named segment a move may land anywhere on the straight wall through its target edge: the
        # vertices between collinear edges are no corners (t < 0 and t > 1 run on over the neighbours)
        t_lo, t_hi = self.wall_range(move.target_edge)
        label = f"edge {move.target_edge}" if (t_lo, t_hi) == (_ZERO, _ONE) else f"the straight wall through edge {move.target_edge}"
        if move.target_segment is not None:
            seg = self.segments.get(move.target_segment)
            if seg is None:
                self.fail(f"{path}.target_segment", f"segment {move.target_segment} is not among the certificate's (valid) segments")
                return None
            if seg.edge != move.target_edge:
                self.fail(f"{path}.target_segment", f"segment {seg.id} lies on edge {seg.edge}, not on the target edge {move.target_edge}")
                return None
            t_lo, t_hi, label = seg.t0, seg.t1, f"segment {seg.id}"
        c, d = move.target
        if not t_lo <= c <= d <= t_hi:
            self.fail(f"{path}.target", f"[{_num(c)}, {_num(d)}] is not within {label} (t in [{_num(t_lo)}, {_num(t_hi)}] of edge {move.target_edge})")
            sound = False

        # ---- directions and the cone
        src = self.edges[move.edge]
        e_vec = src.vector
        directions = (("d_lo", move.d_lo), ("d_hi", move.d_hi))
        cone_ok = True
        for name, vec in directions:
            if vec[0] == 0 and vec[1] == 0:
                self.fail(f"{path}.{name}", "is the zero vector, not a direction")
                cone_ok = False
            elif cross(e_vec, vec) <= 0:
                self.fail(
                    f"{path}.{name}",
                    f"{_pt(vec)} points into the wall: it does not leave edge {move.edge} (along {_pt(e_vec)}) into the "
                    f"free space on its left (cross(edge, d) = {_num(cross(e_vec, vec))} ≤ 0)",
                )
                cone_ok = False
        if not cone_ok:
            return None
        if cross(move.d_lo, move.d_hi) < 0:
            self.fail(f"{path}.d_hi", f"{_pt(move.d_hi)} lies clockwise of d_lo {_pt(move.d_lo)}: the cone must turn counter-clockwise from d_lo to d_hi")
            return None
        result = _MoveResult(move, e_vec, heading_vector(e_vec, move.d_lo), heading_vector(e_vec, move.d_hi))

        # ---- corner rays
        tgt = self.edges[move.target_edge]
        c_pt, t_vec = tgt.a, tgt.vector
        ends = (("p", p, self.point_at(move.edge, p)), ("q", q, self.point_at(move.edge, q)))
        taus: list[Fraction] = []
        hits: list[Point] = []
        corners_ok = True
        for end, t, origin in ends:
            vertex = t == 0 or t == 1 or t == w_lo or t == w_hi
            for name, vec in directions:
                self.counts["corner_rays"] += 1
                where = f"corner ray from {_pt(origin)} (t = {_num(t)} of edge {move.edge}) along {_pt(vec)}"
                hit = line_hit(origin, vec, c_pt, t_vec)
                if hit is None:
                    self.fail(f"{path}.{name}", f"{where} runs parallel to edge {move.target_edge} and never reaches it")
                    corners_ok = False
                    continue
                s, tau = hit
                point = along(c_pt, t_vec, tau)
                if s < 0 or (s == 0 and not vertex):
                    self.fail(f"{path}.{name}", f"{where} meets the line of edge {move.target_edge} behind its start, at {_pt(point)}")
                    corners_ok = False
                    continue
                inside = (t_lo <= tau <= t_hi) if vertex else (t_lo < tau < t_hi)
                if not inside:
                    self.fail(
                        f"{path}.{name}",
                        f"{where} hits the line of edge {move.target_edge} at {_pt(point)} (t = {_num(tau)}), "
                        f"outside {label} (t in {'[' if vertex else '('}{_num(t_lo)}, {_num(t_hi)}{']' if vertex else ')'})",
                    )
                    corners_ok = False
                    continue
                if not c <= tau <= d:
                    self.fail(f"{path}.target", f"{where} lands at t = {_num(tau)} of edge {move.target_edge}, outside the claimed target [{_num(c)}, {_num(d)}]")
                    sound = False
                taus.append(tau)
                hits.append(point)
        if not corners_ok:
            return result
        result.image = (min(taus), max(taus))
        if sound and (c, d) not in ((t_lo, t_hi), result.image):
            self.fail(
                f"{path}.target",
                f"claims [{_num(c)}, {_num(d)}], neither all of {label} ([{_num(t_lo)}, {_num(t_hi)}]) nor the exact image "
                f"[{_num(result.image[0])}, {_num(result.image[1])}] of the move",
            )
            sound = False

        # ---- the swept region
        allowed = {origin for _, t, origin in ends if t == 0 or t == 1 or t == w_lo or t == w_hi}
        swept_ok = self.check_swept(path, move, (ends[0][2], ends[1][2], *hits), allowed, (t_lo, t_hi))
        result.sound = sound and swept_ok
        return result

    def check_swept(self, path: str, move: Move, points: Sequence[Point], allowed: set[Point], target_range: tuple[Fraction, Fraction]) -> bool:
        hull = convex_hull(points)
        if len(hull) < 3:
            self.fail(f"{path}.swept", "the swept region is degenerate (its corners are collinear)")
            return False
        xs = [h[0] for h in hull]
        ys = [h[1] for h in hull]
        x_lo, x_hi, y_lo, y_hi = min(xs), max(xs), min(ys), max(ys)
        p, q = move.source
        for edge in self.edges:
            self.counts["edge_tests"] += 1
            a, b = edge.a, edge.b
            if max(a[0], b[0]) < x_lo or min(a[0], b[0]) > x_hi or max(a[1], b[1]) < y_lo or min(a[1], b[1]) > y_hi:
                continue  # bounding boxes apart (exact)
            clip = clip_segment(a, b, hull)
            if clip is None:
                continue
            l0, l1 = clip
            if edge.id == move.edge:
                if p <= l0 and l1 <= q:
                    continue
            elif move.source_segment is None and self.wall[edge.id][0] == self.wall[move.edge][0]:
                # another edge of the straight wall the source runs on: within the source only
                _, o_e, s_e = self.wall[edge.id]
                _, o_s, s_s = self.wall[move.edge]
                m0, m1 = sorted(((o_e + s_e * l - o_s) / s_s for l in (l0, l1)))
                if p <= m0 and m1 <= q:
                    continue
            elif edge.id == move.target_edge:
                if target_range[0] <= l0 and l1 <= target_range[1]:
                    continue
            elif move.target_segment is None and self.wall[edge.id][0] == self.wall[move.target_edge][0]:
                # another edge of the straight wall the move may land on: within the target range only
                w, o_e, s_e = self.wall[edge.id]
                _, o_t, s_t = self.wall[move.target_edge]
                m0, m1 = sorted(((o_e + s_e * l - o_t) / s_t for l in (l0, l1)))
                if target_range[0] <= m0 and m1 <= target_range[1]:
                    continue
            elif l0 == l1 and along(a, edge.vector, l0) in allowed:
                continue  # a neighbour of the source edge touching it at a vertex end of the source
            x0, x1 = along(a, edge.vector, l0), along(a, edge.vector, l1)
            if l0 == l1:
                what = f"vertex {_pt(x0)} of edge {edge.id}" if l0 in (0, 1) else f"edge {edge.id} at {_pt(x0)}"
                self.fail(f"{path}.swept", f"{what} lies in the swept region (the hull of the source and the corner hits)")
            else:
                self.fail(f"{path}.swept", f"edge {edge.id} runs through the swept region from {_pt(x0)} to {_pt(x1)}")
            return False
        return True

    # ------------------------------------------------------------------ headings of a stage
    def _compare(self, v: Point, r: Fraction, claim: str) -> int | None:
        self.tick()
        self.counts["angle_decisions"] += 1
        try:
            return compare_angle(v, r)
        except Undecided as exc:
            self.fail(claim, f"cannot decide a heading comparison: {exc}")
            return None

    def check_stage_headings(self, k: int, stage: Stage, results: Sequence[_MoveResult | None]) -> list[Point] | None:
        """Checks of 5. for one stage; returns the vectors whose angles are the stage's width (the angle from the
        latest cone start d_lo to the earliest cone end d_hi over its moves: the least of all the pairwise widths
        angle(d_hi of m) − angle(d_lo of j)), or ``None`` if the cones are unusable.

        Headings of different moves are angles measured from their own source edges, in [0, π]: they compare
        exactly through the sign of their difference vector, so the extremes take one pass (not every pair)."""
        if any(r is None for r in results):
            return None
        moves = [r for r in results if r is not None]
        if not moves:
            return []
        latest = earliest = 0  # the move whose cone starts last, the one whose cone ends first
        for m, r in enumerate(moves):
            self.tick()
            if difference_vector(moves[latest].w_lo, r.w_lo)[1] > 0:
                latest = m
            if difference_vector(moves[earliest].w_hi, r.w_hi)[1] < 0:
                earliest = m
        rm, rj = moves[earliest], moves[latest]
        width = difference_vector(rj.w_lo, rm.w_hi)
        if width[1] < 0:
            self.fail(
                f"stages[{k}]",
                f"the moves' cones share no heading: moves[{earliest}] ends (d_hi) at heading {_heading(rm.w_hi)} before "
                f"moves[{latest}] starts (d_lo) at {_heading(rj.w_lo)} (each measured from its source edge)",
            )
            return None
        for m, r in enumerate(moves):
            if m != latest and self._compare(difference_vector(rj.w_lo, r.w_lo), -WIDTH_SLACK,
                                             f"stages[{k}].moves[{m}].d_lo") == -1:
                self.fail(
                    f"stages[{k}].moves[{m}].d_lo",
                    f"the cone starts at heading {_heading(r.w_lo)}, more than 1e-9 before the stage's common cone "
                    f"(moves[{latest}] starts at {_heading(rj.w_lo)}): a move's cone must be the stage's action interval",
                )
            if m != earliest and self._compare(difference_vector(rm.w_hi, r.w_hi), WIDTH_SLACK,
                                               f"stages[{k}].moves[{m}].d_hi") == 1:
                self.fail(
                    f"stages[{k}].moves[{m}].d_hi",
                    f"the cone ends at heading {_heading(r.w_hi)}, more than 1e-9 after the stage's common cone "
                    f"(moves[{earliest}] ends at {_heading(rm.w_hi)}): a move's cone must be the stage's action interval",
                )
        diffs = [width]
        if stage.interval is not None:
            lo, hi = stage.interval
            if lo > hi:
                self.fail(f"stages[{k}].interval", f"[{_num(lo)}, {_num(hi)}] is reversed")
                return None
            for j, r in enumerate(moves):
                if self._compare(r.w_lo, lo, f"stages[{k}].interval.lo") == 1:
                    self.fail(f"stages[{k}].interval.lo", f"claims {_num(lo)}, but the cone of moves[{j}] starts at heading {_heading(r.w_lo)} (d_lo {_pt(r.move.d_lo)} from edge {r.move.edge})")
                    return None
                if self._compare(r.w_hi, hi, f"stages[{k}].interval.hi") == -1:
                    self.fail(f"stages[{k}].interval.hi", f"claims {_num(hi)}, but the cone of moves[{j}] ends at heading {_heading(r.w_hi)} (d_hi {_pt(r.move.d_hi)} from edge {r.move.edge})")
                    return None
            if not any(self._compare(r.w_lo, lo - WIDTH_SLACK, f"stages[{k}].interval.lo") in (1, None) for r in moves):
                self.fail(f"stages[{k}].interval.lo", f"claims {_num(lo)}, more than 1e-9 inside the common cone, which starts at heading {_approx(max(_heading_value(r.w_lo) for r in moves), 6)}")
            if not any(self._compare(r.w_hi, hi + WIDTH_SLACK, f"stages[{k}].interval.hi") in (-1, None) for r in moves):
                self.fail(f"stages[{k}].interval.hi", f"claims {_num(hi)}, more than 1e-9 inside the common cone, which ends at heading {_approx(min(_heading_value(r.w_hi) for r in moves), 6)}")
        return diffs

    # ------------------------------------------------------------------ chaining
    def check_chaining(self, results: Sequence[Sequence[_MoveResult | None]]) -> None:
        cert = self.cert
        stages = cert.stages
        # start: covered by the sources of stage 0
        sources0 = self._sources(stages[0])
        for i, piece in enumerate(cert.start):
            if not (0 <= piece.edge < len(self.edges) and piece.t0 < piece.t1):
                continue
            self.counts["links"] += 1
            gap = uncovered(piece.t0, piece.t1, sources0.get(piece.edge, []))
            if gap is not None:
                self.fail("stages[0].moves", f"no move leaves t in ({_num(gap[0])}, {_num(gap[1])}) of edge {piece.edge}, part of start[{i}]")
        links = [(k, k + 1) for k in range(len(stages) - 1)]
        if cert.cycle is not None and 0 <= cert.cycle.stages[0] < len(stages):
            links.append((len(stages) - 1, cert.cycle.stages[0]))
        for k_from, k_to in links:
            sources = self._sources(stages[k_to])
            for m, move in enumerate(stages[k_from].moves):
                landing = self._uncovered_landing(move, sources)
                if landing is not None:
                    edge, gap = landing
                    c, d = move.target
                    wrap = " (the cycle returns to its first stage)" if k_to <= k_from else ""
                    self.fail(
                        f"stages[{k_to}].moves",
                        f"no move leaves t in ({_num(gap[0])}, {_num(gap[1])}) of edge {edge}, where "
                        f"stages[{k_from}].moves[{m}] may land (its target is [{_num(c)}, {_num(d)}]"
                        f"{'' if edge == move.target_edge else f' of edge {move.target_edge}'}){wrap}",
                    )
        if cert.goal is not None:
            goal: dict[int, list[tuple[Fraction, Fraction]]] = {}
            for piece in cert.goal:
                goal.setdefault(piece.edge, []).append((piece.t0, piece.t1))
            last = len(stages) - 1
            for m, move in enumerate(stages[last].moves):
                landing = self._uncovered_landing(move, goal)
                if landing is not None:
                    edge, gap = landing
                    c, d = move.target
                    self.fail(
                        f"stages[{last}].moves[{m}].target",
                        f"[{_num(c)}, {_num(d)}] of edge {move.target_edge} is not within the goal set: "
                        f"t in ({_num(gap[0])}, {_num(gap[1])}){'' if edge == move.target_edge else f' of edge {edge}'} "
                        "is outside it",
                    )

    def _uncovered_landing(self, move: Move, cover: dict[int, list[tuple[Fraction, Fraction]]]
                           ) -> tuple[int, tuple[Fraction, Fraction]] | None:
        """One link checked: the first edge and gap of the target of ``move`` (on the walls it runs over) that the
        pieces ``cover`` (by edge) leave uncovered, or ``None``."""
        self.counts["links"] += 1
        c, d = move.target
        for edge, a, b in self.on_walls(move.target_edge, c, d):
            gap = uncovered(a, b, cover.get(edge, []))
            if gap is not None:
                return edge, gap
        return None

    def check_source_ends(self) -> None:
        """Every end of a source is accounted for: an end of the edge or of a named segment, an end of the start or
        goal set, an end of a set flowing into the stage (the previous stage's targets), or an end of another
        source of the same stage on that edge (a split). A certificate claims nothing gratuitous."""
        cert = self.cert
        stages = cert.stages
        n = len(stages)
        segment_ends: dict[int, set[Fraction]] = {}
        for seg in self.segments.values():
            segment_ends.setdefault(seg.edge, set()).update((seg.t0, seg.t1))
        # the ends of the query's sets: a plan may land on the part of a segment between them and leave from it later
        for piece in (*cert.start, *(cert.goal or ())):
            segment_ends.setdefault(piece.edge, set()).update((piece.t0, piece.t1))
        for k, stage in enumerate(stages):
            inflow: dict[int, set[Fraction]] = {}
            feeding: list[tuple[int, Fraction, Fraction]] = []
            if k == 0:
                feeding += [(piece.edge, piece.t0, piece.t1) for piece in cert.start]
            else:
                feeding += [p for m in stages[k - 1].moves for p in self.on_walls(m.target_edge, *m.target)]
            if cert.cycle is not None and k == cert.cycle.stages[0]:
                feeding += [p for m in stages[n - 1].moves for p in self.on_walls(m.target_edge, *m.target)]
            for edge, a, b in feeding:
                inflow.setdefault(edge, set()).update((a, b))
            pieces = [self._source_pieces(move) for move in stage.moves]
            for m, move in enumerate(stage.moves):
                # the ends of the source, each on the edge that holds it (a source on a straight wall runs on)
                ends = ((pieces[m][0][0], pieces[m][0][1]), (pieces[m][-1][0], pieces[m][-1][2]))
                for name, (edge, t) in zip(("p", "q"), ends):
                    others = {x for j, ps in enumerate(pieces) if j != m for e, a, b in ps if e == edge for x in (a, b)}
                    known = {_ZERO, _ONE} | segment_ends.get(edge, set()) | inflow.get(edge, set()) | others
                    if t not in known:
                        flowing = "the start set" if k == 0 else f"stages[{k - 1}]'s targets"
                        self.fail(
                            f"stages[{k}].moves[{m}].source",
                            f"its end {name} = {_num(t)} of edge {move.edge} is not accounted for: not an end of the edge, of a "
                            f"named segment, of the start or goal set, of {flowing} or of another source of the stage",
                        )
                        break

    def _sources(self, stage: Stage) -> dict[int, list[tuple[Fraction, Fraction]]]:
        """The sources of a stage per edge (a source on a straight wall as its pieces on the wall's edges)."""
        out: dict[int, list[tuple[Fraction, Fraction]]] = {}
        for move in stage.moves:
            for edge, a, b in self._source_pieces(move):
                out.setdefault(edge, []).append((a, b))
        return out

    def _source_pieces(self, move: Move) -> list[tuple[int, Fraction, Fraction]]:
        """A move's source as pieces of edges: itself, or its pieces on the edges of its straight wall, in order
        along the wall."""
        if not 0 <= move.edge < len(self.edges):
            return [(move.edge, *move.source)]
        return sorted(self.on_walls(move.edge, *move.source), key=lambda piece: self.wall[piece[0]][1])

    # ------------------------------------------------------------------ positions
    def check_positions(self, k: int, stage: Stage, results: Sequence[_MoveResult | None]) -> None:
        assert stage.positions is not None
        where = f"stages[{k}].positions"
        before = len(self.failures)
        self.check_pieces(stage.positions, where)
        if len(self.failures) > before or any(r is None or r.image is None for r in results):
            return
        exact_u = _merged(p for r in results for p in self.on_walls(r.move.target_edge, *r.image))  # type: ignore[union-attr, misc]
        claimed_u = _merged((piece.edge, piece.t0, piece.t1) for piece in stage.positions)
        if exact_u != claimed_u:
            self.fail(where, f"claims {self._pieces_text(claimed_u)}, but the exact image of the stage is {self._pieces_text(exact_u)}")

    @staticmethod
    def _pieces_text(pieces: dict[int, list[tuple[Fraction, Fraction]]]) -> str:
        parts = [f"e{e}:[{_num(a)}, {_num(b)}]" for e in sorted(pieces) for a, b in pieces[e]]
        return ", ".join(parts) if parts else "nothing"

    # ------------------------------------------------------------------ bounds (negative certificates)
    def check_bound(self, bound: BoundClaim) -> None:
        """10.: the invariant of a ``bound`` block (schema *Bounds*; semantics in :mod:`.invariant`)."""
        before = len(self.failures)
        delta, w, budget = bound.heading_margin, bound.threshold, bound.budget
        if not _ZERO <= delta < Fraction(3, 4):
            self.fail("bound.heading_margin", f"δ = {_num(delta)} is not in [0, 3/4) radians")
        if w < 0:
            self.fail("bound.threshold", f"w = {_num(w)} < 0")
        if budget is not None and budget < 0:
            self.fail("bound.budget", f"K = {budget} < 0")
        if len(self.failures) > before:
            return
        try:
            geo = Geometry([(e.a, e.b) for e in self.edges], self.nxt, bound.table, bound.groups)
        except TableError as exc:
            self.fail(exc.claim, exc.message)
            return
        m = len(bound.table)
        seen: dict[tuple[int, ...], int] = {}
        for i, rec in enumerate(bound.beliefs):
            self.tick()
            where = f"bound.beliefs[{i}]"
            segs = rec.segments
            if not segs:
                self.fail(f"{where}.segments", "a belief has at least one segment")
                return
            if any(not 0 <= k < m for k in segs):
                bad = next(k for k in segs if not 0 <= k < m)
                self.fail(f"{where}.segments", f"segment {bad} is not in the table (segments 0..{m - 1})")
                return
            if any(x >= y for x, y in zip(segs, segs[1:])):
                self.fail(f"{where}.segments", f"{list(segs)} is not strictly ascending")
                return
            if segs in seen:
                self.fail(f"{where}.segments", f"{list(segs)} is listed twice (also beliefs[{seen[segs]}])")
                return
            seen[segs] = i
        # the start belief is the start set, exactly; the start set is not inside the goal (no 0-stage plan)
        first = bound.beliefs[0]
        if first.depth != 0:
            self.fail("bound.beliefs[0].depth", f"the start belief has depth {first.depth}, not 0")
            return
        have = geo.pieces_of(first.segments)
        want = _merged((p.edge, p.t0, p.t1) for p in self.cert.start)
        if have != want:
            self.fail("bound.beliefs[0].segments", f"the start belief's segments make up {self._pieces_text(have)}, but the "
                                                   f"start set is {self._pieces_text(want)}")
            return
        goal_pieces = [(p.edge, p.t0, p.t1) for p in (self.cert.goal or ())]
        goal_by_edge = _merged(goal_pieces)
        if all(uncovered(p.t0, p.t1, goal_by_edge.get(p.edge, [])) is None for p in self.cert.start):
            self.fail("start", "the start set lies in the goal set: the plan with no stages reaches it")
            return
        goal = geo.overlapping(goal_pieces)
        closure = Closure(geo, delta, w)
        by_depth = sorted(range(len(bound.beliefs)), key=lambda j: bound.beliefs[j].depth)
        listed = [(frozenset(bound.beliefs[j].segments), bound.beliefs[j].depth, j) for j in by_depth]
        checked = 0
        for i, rec in enumerate(bound.beliefs):
            self.tick()
            if budget is not None and rec.depth >= budget:
                continue
            checked += 1
            for targets, (lo, hi) in closure.successors(rec.segments):
                nxt = next_belief(targets)
                if nxt <= goal:
                    moves = _run_moves(rec.segments, targets)
                    self.fail(f"bound.beliefs[{i}]", f"has a goal stage: headings {self._heading_range(lo, hi)} take its "
                                                     f"segments into goal segments ({moves}) at depth {rec.depth}")
                    return
                limit = None if budget is None else rec.depth + 1
                exact = seen.get(tuple(sorted(nxt)))
                if exact is not None and (limit is None or bound.beliefs[exact].depth <= limit):
                    continue
                if not any(seg <= nxt and (limit is None or depth <= limit) for seg, depth, _ in listed):
                    moves = _run_moves(rec.segments, targets)
                    depth_text = "" if limit is None else f" of depth ≤ {limit}"
                    self.fail(f"bound.beliefs[{i}]", f"its successor {sorted(nxt)} (headings {self._heading_range(lo, hi)}: "
                                                     f"{moves}) contains no listed belief{depth_text}: the invariant is not closed")
                    return
        for key in ("sources", "cells", "region_tests", "successors"):
            self.counts[f"bound_{key}"] = closure.counts[key]
        self.counts["bound_beliefs"] = checked
        self.counts["angle_decisions"] += closure.counts["angle_decisions"]
        self.bound_ok = True
        budget_text = "any number of stages" if budget is None else f"at most {budget} stage{'s' if budget != 1 else ''}"
        width_text = "positive width" if w == 0 else f"width > {_num(w)} rad"
        units = ("" if not geo.groups else
                 f" or inside one of its {len(geo.groups)} groups (segments of P′ cut at the query's set ends into table "
                 f"segments; the next belief holds the run of the group's consecutive segments that the landings meet)")
        self.proved.append(
            f"no plan with {budget_text} takes the start set to the goal set, among plans whose every stage is one "
            f"heading interval of {width_text} inside [δ, π − δ] (δ = {_num(delta)} rad) and lands, from every "
            f"possible segment, inside one segment of the certificate's table ({m} segments"
            f"{': ' + bound.table_source if bound.table_source else ''}){units}; goal segments are the {len(goal)} "
            f"table segments that meet the goal set")

    @staticmethod
    def _heading_range(lo: tuple[int, int], hi: tuple[int, int]) -> str:
        def one(h: tuple[int, int]) -> str:
            return _heading((Fraction(h[0]), Fraction(h[1])))
        return f"[{one(lo)}, {one(hi)}] rad"

    # ------------------------------------------------------------------ claims
    def check_claims(self, widths: Sequence[list[Point] | None]) -> None:
        cert = self.cert
        claims = cert.claims
        if claims.bounces != len(cert.stages):
            self.fail("claims.bounces", f"claims {claims.bounces}, the certificate has {len(cert.stages)} stages")
        if claims.tolerance * 2 != claims.min_width:
            self.fail("claims.tolerance", f"claims {_num(claims.tolerance)}, but min_width / 2 = {_num(claims.min_width / 2)}")
        usable = all(w is not None for w in widths)
        if not cert.stages:  # no stage constrains the heading: a width up to the whole range (0, π), nothing to add
            if not 0 <= claims.min_width < _PI_FLOOR:
                self.fail("claims.min_width", f"claims {_num(claims.min_width)}, outside [0, π) (the width of headings "
                                              f"no stage constrains)")
            if claims.sum_width not in (None, 0):
                self.fail("claims.sum_width", f"claims {_num(claims.sum_width)}, but there are no stages to add up")
        else:
            if claims.min_width < 0:
                self.fail("claims.min_width", f"claims {_num(claims.min_width)} < 0")
            elif usable:
                self.check_min_width(claims.min_width, widths)  # type: ignore[arg-type]
            if claims.sum_width is not None and usable:
                self.check_sum_width(claims.sum_width, widths)  # type: ignore[arg-type]
        self.check_optimality()
        self.check_objective(self.optimality_rederived)

    def check_min_width(self, claimed: Fraction, widths: Sequence[list[Point]]) -> None:
        for k, diffs in enumerate(widths):
            interval = self.cert.stages[k].interval
            if interval is not None and claimed > interval[1] - interval[0]:
                self.fail("claims.min_width", f"claims {_num(claimed)}, more than the width {_num(interval[1] - interval[0])} of stages[{k}].interval")
                return
            for v in diffs:
                if self._compare(v, claimed, "claims.min_width") == -1:
                    self.fail("claims.min_width", f"claims {_num(claimed)}, but stages[{k}] is only {_heading(v)} wide (its common cone, measured exactly)")
                    return
        tight = any(self._compare(v, claimed + WIDTH_SLACK, "claims.min_width") in (-1, 0, None) for diffs in widths for v in diffs)
        if not tight:
            narrowest = _approx(min(_heading_value(v) for diffs in widths for v in diffs), 9)
            self.fail("claims.min_width", f"claims {_num(claimed)}, more than 1e-9 below the narrowest stage's width {narrowest}: claims must be tight")

    def check_sum_width(self, claimed: Fraction, widths: Sequence[list[Point]]) -> None:
        slack = WIDTH_SLACK * len(widths)
        bits = 64
        while True:
            lo_sum = hi_sum = _ZERO
            for diffs in widths:
                enclosures = [angle_enclosure(v, bits) for v in diffs]
                lo_sum += min(e[0] for e in enclosures)
                hi_sum += min(e[1] for e in enclosures)
            self.counts["angle_decisions"] += 1
            if hi_sum < claimed:
                self.fail("claims.sum_width", f"claims {_num(claimed)}, more than the stages' widths add up to (exactly, "
                                              f"at most {_approx(hi_sum, 20)}; the claim exceeds it by ≥ {_approx(claimed - hi_sum, 20)})")
                return
            if lo_sum > claimed + slack:
                self.fail("claims.sum_width", f"claims {_num(claimed)}, more than {_num(slack)} below the sum of the widths {_approx(lo_sum, 9)}: claims must be tight")
                return
            if lo_sum >= claimed and hi_sum <= claimed + slack:
                return
            if bits >= MAX_BITS:
                self.fail("claims.sum_width", f"cannot decide {_num(claimed)} against the sum of the widths within 2^-{bits}")
                return
            bits *= 2

    def check_bound_claim(self, bound: BoundClaim) -> bool:
        """What a valid bound block proves about this plan's objective (10.); ``True`` if it re-derives the
        optimality claim (fully, or within a stated gap)."""
        claims = self.cert.claims
        objective, k = claims.objective, claims.bounces
        budget, w = bound.budget, bound.threshold
        opt = claims.optimality
        if objective == "fewest":
            if w != 0:
                self.fail("bound.threshold", f"w = {_num(w)}: a bound on the fewest bounces is about every plan (w = 0)")
            elif budget is None or budget >= k:
                self.fail("bound.budget", f"K = {budget}: this plan itself has {k} stages, so no invariant can exclude every "
                                          f"plan with at most K stages (a fewest-bounces bound has K < {k})")
            else:
                tight = budget + 1 == k
                self.proved.append(f"hence every such plan has at least {budget + 1} bounces"
                                   + (f": this plan's {k} is the fewest" if tight else f" (this plan has {k})"))
                if not tight and opt is not None and opt.proved:
                    self.not_checked.append(f"claims.optimality: the bound block proves only ≥ {budget + 1} bounces, "
                                            f"not the {k} claimed optimal")
                return True
            return False
        if objective in ("tolerance", "constant"):
            if w < claims.min_width:
                self.fail("bound.threshold", f"w = {_num(w)} is below this plan's certified min_width {_num(claims.min_width)}: "
                                             "the plan itself is wider than the bound")
            elif budget is not None and budget < k:
                self.fail("bound.budget", f"K = {budget} < this plan's {k} stages: the bound is not about a class of plans "
                                          "that holds this plan")
            else:
                gap = w - claims.min_width
                within = "" if budget is None else f" with at most {budget} stages"
                self.proved.append(f"hence every such plan{within} has min width ≤ {_num(w)} rad; this plan's certified "
                                   f"min width is {_num(claims.min_width)} rad: optimal to within {_approx(gap, 9)} rad")
                if opt is not None and opt.proved and gap > WIDTH_SLACK:
                    self.not_checked.append(f"claims.optimality: optimality within 1e-9 (the planner's, over its margins) is "
                                            f"re-derived only to within {_approx(gap, 9)} rad: the checker's cells are "
                                            "margin-free, the planner's intervals are not")
                return True
            return False
        self.fail("bound", f"a bound block proves optimality for the objectives fewest, tolerance and constant, not {_quote(objective)}")
        return False

    def check_objective(self, rederived: bool) -> None:
        """``claims.objective`` is checked where the certificate can speak for it, else listed as not checked."""
        claims = self.cert.claims
        objective = claims.objective
        if objective is None:
            return
        kind = self.cert.kind
        if objective not in OBJECTIVES.get(kind, ()):
            others = sorted({k for k, known in OBJECTIVES.items() if objective in known} - {"infeasible"})
            self.fail("claims.objective", f"{_quote(objective)} is an objective of {', '.join(others)} certificates, not of "
                                          f"{_a(kind)} certificate" if others else
                      f"unknown objective {_quote(objective)}: {_a(kind)} certificate names one of "
                      f"{', '.join(OBJECTIVES.get(kind, ()))}")
        elif objective == "sum" and claims.sum_width is None and kind == "plan":
            self.fail("claims.objective", "the objective is the sum of widths, but claims.sum_width is missing")
        elif not rederived:
            self.not_checked.append(f"claims.objective: {_quote(objective)} names what the planner optimised; only a "
                                    "re-derived optimality bound could confirm it")

    def check_optimality(self) -> None:
        claims = self.cert.claims
        opt = claims.optimality
        rederived = False
        if self.cert.bound is not None and self.bound_ok:
            rederived = self.check_bound_claim(self.cert.bound)
        self.optimality_rederived = rederived
        if opt is None:
            return
        if opt.method not in METHODS:
            self.fail("claims.optimality.method", f"unknown method {_quote(opt.method)}: one of {', '.join(METHODS)}")
            return
        if opt.proved and opt.method not in PROVING_METHODS:
            self.fail("claims.optimality.proved", f"true, but the method {opt.method!r} proves nothing (a bounded search "
                                                  "or no claim)")
            return
        if not rederived:
            self.not_checked.append(
                f"claims.optimality: the bound of method {opt.method!r} is not re-derived (only its consistency with the checked claims)"
            )
        if opt.proved and opt.bound is None:
            self.fail("claims.optimality.bound", "a proved optimality claim must state its bound")
            return
        if opt.bound is None:
            return
        bound = opt.bound
        objective = claims.objective
        if objective == "fewest":
            if bound > claims.bounces:
                self.fail("claims.optimality.bound", f"a lower bound of {_num(bound)} bounces exceeds this plan's {claims.bounces}")
            elif opt.proved and bound != claims.bounces:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} differs from the {claims.bounces} bounces")
        elif objective in ("tolerance", "constant"):
            if bound < claims.min_width:
                self.fail("claims.optimality.bound", f"an upper bound {_num(bound)} below the certified min_width {_num(claims.min_width)}")
            elif opt.proved and bound - claims.min_width > WIDTH_SLACK:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} exceeds min_width {_num(claims.min_width)} by more than 1e-9")
        elif objective == "sum":
            if claims.sum_width is None:
                self.fail("claims.sum_width", "the objective is the sum of widths: claim it")
            elif bound < claims.sum_width:
                self.fail("claims.optimality.bound", f"an upper bound {_num(bound)} below the certified sum_width {_num(claims.sum_width)}")
            elif opt.proved and bound - claims.sum_width > WIDTH_SLACK * len(self.cert.stages):
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} exceeds sum_width {_num(claims.sum_width)}")
        elif objective == "contraction" and self.cert.cycle is not None:
            contraction = self.cert.cycle.contraction
            if bound > contraction:
                self.fail("claims.optimality.bound", f"a lower bound {_num(bound)} above the certified contraction {_num(contraction)}")
            elif opt.proved and contraction - bound > WIDTH_SLACK:
                self.fail("claims.optimality.bound", f"proved optimal, yet the bound {_num(bound)} is below the contraction {_num(contraction)}")

    # ------------------------------------------------------------------ localisation
    def check_epsilon(self) -> None:
        """9.: the final positions lie in one interval of one edge shorter than ε (arc length), exactly."""
        cert = self.cert
        eps = cert.claims.epsilon
        if eps is None:
            if cert.version >= 2:
                self.fail("claims.epsilon", "a localize certificate must claim ε (the final interval is shorter than it)")
            else:
                self.not_checked.append("claims.epsilon: a version-1 localisation certificate carries no ε claim "
                                        "(only its positions are checked, not that they are localised)")
            return
        if eps <= 0:
            self.fail("claims.epsilon", f"claims ε = {_num(eps)}, not a positive length")
            return
        final = cert.stages[-1].positions
        if final is None:
            self.fail(f"stages[{len(cert.stages) - 1}].positions", "a localize certificate claims the final positions")
            return
        edges = sorted({piece.edge for piece in final})
        if not all(0 <= e < len(self.edges) for e in edges):
            return  # reported by the positions check
        if len(edges) == 1:
            edge = edges[0]
            lo, hi = min(p.t0 for p in final), max(p.t1 for p in final)
            v = self.edges[edge].vector
            where = f"e{edge}:[{_num(lo)}, {_num(hi)}]"
        elif len({self.wall[e][0] for e in edges}) == 1:
            # one interval of one straight wall (collinear edges): measured along the wall's line
            w = self.wall[edges[0]][0]
            lo = min(self.wall[p.edge][1] + self.wall[p.edge][2] * p.t0 for p in final)
            hi = max(self.wall[p.edge][1] + self.wall[p.edge][2] * p.t1 for p in final)
            v = self.edges[w].vector
            where = f"[{_num(lo)}, {_num(hi)}] of the straight wall through edges {', '.join(map(str, edges))} (in edge {w}'s parameter)"
        else:
            self.fail("claims.epsilon", f"the final position set lies on edges {', '.join(map(str, edges))}, not in one interval of one edge")
            return
        squared = (hi - lo) ** 2 * (v[0] ** 2 + v[1] ** 2)
        if not squared < eps**2:
            length, exact = _sqrt_text(squared)
            self.fail(
                "claims.epsilon",
                f"claims ε = {_num(eps)}, but the final position set {where} is "
                f"{'' if exact else '≈ '}{length} long: not shorter than ε",
            )

    # ------------------------------------------------------------------ cycles
    def check_cycle(self, cycle: CycleClaim, results: Sequence[Sequence[_MoveResult | None]]) -> None:
        stages = self.cert.stages
        n = len(stages)
        first = cycle.stages[0]
        if list(cycle.stages) != list(range(first, n)) or not 0 <= first < n:
            self.fail("cycle.stages", f"{list(cycle.stages)} must be the last stages in order ({first}..{n - 1}): the cycle repeats the tail of the stage list")
            return
        if len(cycle.nominal) != len(cycle.stages):
            self.fail("cycle.nominal", f"gives {len(cycle.nominal)} directions for {len(cycle.stages)} cycle stages")
            return
        for i in cycle.stages:
            if len(stages[i].moves) != 1:
                self.fail(f"stages[{i}].moves", f"a cycle stage has exactly one move (found {len(stages[i].moves)}): its return map is one affine map")
                return
        moves = [results[i][0] for i in cycle.stages]
        if any(r is None or not r.sound or r.image is None for r in moves):
            return  # the move's own failures are reported already
        for idx, i in enumerate(cycle.stages):
            nxt = cycle.stages[(idx + 1) % len(cycle.stages)]
            here, there = stages[i].moves[0], stages[nxt].moves[0]
            if here.target_edge != there.edge:
                self.fail("cycle.stages", f"stages[{i}] lands on edge {here.target_edge} but stages[{nxt}] leaves from edge {there.edge}")
                return
        alpha, beta, worst = _ONE, _ZERO, _ONE
        for idx, i in enumerate(cycle.stages):
            move = stages[i].moves[0]
            src, tgt = self.edges[move.edge], self.edges[move.target_edge]
            d = cycle.nominal[idx]
            if not (cross(src.vector, d) > 0 and cross(move.d_lo, d) >= 0 and cross(d, move.d_hi) >= 0):
                self.fail(f"cycle.nominal[{idx}]", f"{_pt(d)} is not inside the cone {_pt(move.d_lo)} → {_pt(move.d_hi)} of stages[{i}].moves[0]")
                return
            a_k, b_k = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, d)
            alpha, beta = a_k * alpha, a_k * beta + b_k
            a_lo = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, move.d_lo)[0]
            a_hi = affine_coefficients(src.a, src.vector, tgt.a, tgt.vector, move.d_hi)[0]
            worst *= max(abs(a_lo), abs(a_hi))
        entry = stages[first].moves[0]
        if cycle.alpha != alpha:
            self.fail("cycle.alpha", f"claims {_num(cycle.alpha)}, the return map of the nominal directions on edge {entry.edge} has α = {_num(alpha)}")
        if cycle.beta != beta:
            self.fail("cycle.beta", f"claims {_num(cycle.beta)}, the return map of the nominal directions on edge {entry.edge} has β = {_num(beta)}")
        if alpha == 1:
            self.fail("cycle.fixed_point", "the return map has α = 1: no unique fixed point")
        else:
            fixed = beta / (1 - alpha)
            if cycle.fixed_point != fixed:
                self.fail("cycle.fixed_point", f"claims {_num(cycle.fixed_point)}, but β / (1 − α) = {_num(fixed)}")
            elif not entry.source[0] <= fixed <= entry.source[1]:
                self.fail("cycle.fixed_point", f"t* = {_num(fixed)} lies outside the entry source [{_num(entry.source[0])}, {_num(entry.source[1])}] of edge {entry.edge}")
        if cycle.contraction != worst:
            self.fail("cycle.contraction", f"claims {_num(cycle.contraction)}, but the worst case of |α| over the cones is {_num(worst)}")
        elif worst >= 1:
            self.fail("cycle.contraction", f"the cycle does not contract: the worst case of |α| over the cones is {_num(worst)} ≥ 1")
        if cycle.visits is not None:
            # a stage visits the edge it leaves from; one leaving from a run over a straight wall visits no one edge
            visited = [m.edge if _ZERO <= m.source[0] and m.source[1] <= _ONE else None
                       for m in (stages[i].moves[0] for i in cycle.stages)]
            if not any(_is_subsequence(cycle.visits, visited[s:] + visited[:s]) for s in range(len(visited))):
                self.fail("cycle.visits", f"the cycle bounces on edges {visited} (cyclically), which does not visit {list(cycle.visits)} in that order")


# ======================================================================= what is certified
def certified(cert: Certificate) -> dict[str, Any]:
    """What ``cert`` speaks about, as JSON data: ``environment`` (name, sha256, vertices, edges, holes),
    ``start`` and ``goal`` (``{"set", "length", "length_exact"}``: a boundary-set string and its total arc
    length, exact text or a 9-decimal approximation; ``goal`` is ``None`` for cycles) and ``claims`` (every
    claim in exact text; ``epsilon`` and the ``final`` positions for localisation; ``None`` for an ε that a
    version-1 certificate does not carry). Computed from the certificate alone, valid or not.

    The sha256 is that of the planner's answers (``environment.sha256``): SHA-256 of the compact JSON of the
    rings with every coordinate as exact text (``3``, ``0.25``, ``1/3``).
    """
    rings = cert.environment.rings
    environment = _environment_summary(cert.environment)
    squared = _squared_lengths(rings)
    claims: dict[str, Any] = {} if cert.kind == "infeasible" else {
        "bounces": cert.claims.bounces, "min_width": number_text(cert.claims.min_width),
        "tolerance": number_text(cert.claims.tolerance)}
    if cert.claims.sum_width is not None:
        claims["sum_width"] = number_text(cert.claims.sum_width)
    if cert.claims.objective is not None:
        claims["objective"] = cert.claims.objective
    if cert.cycle is not None:
        c = cert.cycle
        cycle: dict[str, Any] = {"stages": list(c.stages), "alpha": number_text(c.alpha), "beta": number_text(c.beta),
                                 "fixed_point": number_text(c.fixed_point), "contraction": number_text(c.contraction)}
        if c.visits is not None:
            cycle["visits"] = list(c.visits)
        claims["cycle"] = cycle
    if cert.kind == "localize":
        claims["epsilon"] = None if cert.claims.epsilon is None else number_text(cert.claims.epsilon)
        final = cert.stages[-1].positions
        if final is not None:
            claims["final"] = _set_summary(final, squared)
    if cert.claims.optimality is not None:
        o = cert.claims.optimality
        claims["optimality"] = {"method": str(o.method), "proved": o.proved, "bound": None if o.bound is None else number_text(o.bound)}
    if cert.bound is not None:
        b = cert.bound
        claims["bound"] = {"budget": b.budget, "threshold": number_text(b.threshold), "heading_margin": number_text(b.heading_margin),
                           "table_segments": len(b.table), "beliefs": len(b.beliefs), "table_source": b.table_source}
    return {
        "environment": environment,
        "start": _set_summary(cert.start, squared),
        "goal": None if cert.goal is None else _set_summary(cert.goal, squared),
        "claims": claims,
    }


def _environment_summary(record: EnvironmentRecord) -> dict[str, Any]:
    """Name, SHA-256 of the exact rings (the planner answers' ``environment.sha256``), vertex, edge and hole counts."""
    rings = record.rings
    texts = [[[_canonical(x), _canonical(y)] for x, y in ring] for ring in rings]
    digest = hashlib.sha256(json.dumps(texts, separators=(",", ":")).encode()).hexdigest()
    n = sum(len(ring) for ring in rings)
    return {"name": record.name, "sha256": digest, "vertices": n, "edges": n, "holes": max(len(rings) - 1, 0)}


def _canonical(x: Fraction) -> str:
    """The exact text of the environment hash: an integer, a terminating decimal in full, else ``p/q``."""
    x = Fraction(x)
    if x.denominator == 1:
        return str(x.numerator)
    return _terminating_decimal(x) or f"{x.numerator}/{x.denominator}"


def _squared_lengths(rings: Sequence[Sequence[Point]]) -> list[Fraction]:
    out = []
    for ring in rings:
        for i in range(len(ring)):
            a, b = ring[i], ring[(i + 1) % len(ring)]
            out.append((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2)
    return out


def _set_summary(pieces: Sequence[Piece], squared: Sequence[Fraction]) -> dict[str, Any]:
    """A set of pieces as a boundary-set string (merged per edge) and its total arc length."""
    merged = _merged((p.edge, p.t0, p.t1) for p in pieces)
    parts, roots, exact_total = [], [], _ZERO
    exact = True
    for e in sorted(merged):
        for a, b in merged[e]:
            parts.append(f"e{e}" if (a, b) == (_ZERO, _ONE) else f"e{e}:{_canonical(a)}:{_canonical(b)}")
            if 0 <= e < len(squared):
                root = _rational_sqrt(squared[e])
                if root is None:
                    exact = False
                    roots.append((b - a) ** 2 * squared[e])
                else:
                    exact_total += (b - a) * root
    if exact:
        length, is_exact = number_text(exact_total), True
    else:
        total = exact_total + sum((_sqrt_fraction(q) for q in roots), _ZERO)
        length, is_exact = _approx(total, 9), False
    return {"set": ",".join(parts), "length": length, "length_exact": is_exact}


def _isqrt(n: int) -> int:
    """⌊√n⌋ of an integer n ≥ 0 (Newton's iteration on integers: no floats in the checker)."""
    if n < 2:
        return n
    x = 1 << ((n.bit_length() + 1) // 2)  # ≥ √n
    while True:
        y = (x + n // x) // 2
        if y >= x:
            return x
        x = y


def _rational_sqrt(q: Fraction) -> Fraction | None:
    """√q if it is rational, else ``None``."""
    if q < 0:
        return None
    n, d = _isqrt(q.numerator), _isqrt(q.denominator)
    return Fraction(n, d) if n * n == q.numerator and d * d == q.denominator else None


def _sqrt_fraction(q: Fraction, digits: int = 12) -> Fraction:
    """√q to within 10⁻ᵈⁱᵍⁱᵗˢ (integer square root), for lengths shown in reports."""
    scale = 10 ** (2 * digits)
    return Fraction(_isqrt(q.numerator * scale // q.denominator), 10**digits)


def _sqrt_text(q: Fraction) -> tuple[str, bool]:
    """√q as exact text, or as a 9-decimal approximation (and whether it is exact)."""
    root = _rational_sqrt(q)
    return (number_text(root), True) if root is not None else (_approx(_sqrt_fraction(q), 9), False)


def _merged(pieces: Iterable[tuple[int, Fraction, Fraction]]) -> dict[int, list[tuple[Fraction, Fraction]]]:
    """(edge, t0, t1) pieces as the union of their intervals on each edge (numbers read exactly)."""
    by_edge: dict[int, list[tuple[Fraction, Fraction]]] = {}
    for edge, a, b in pieces:
        by_edge.setdefault(int(edge), []).append((Fraction(a), Fraction(b)))
    return {e: union(v) for e, v in by_edge.items()}


def _is_subsequence(needle: Sequence[int], haystack: Sequence[int | None]) -> bool:
    it = iter(haystack)
    return all(any(x == y for y in it) for x in needle)


def _run_moves(sources: Sequence[int], targets: Sequence[Sequence[int]]) -> str:
    """A successor's moves as text: ``3→5``, or ``3→5+6`` for a landing anywhere on a group."""
    return ", ".join(f"{s}→{'+'.join(map(str, t))}" for s, t in zip(sources, targets))
