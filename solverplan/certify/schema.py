"""The certificate format (version 4; versions 1, 2 and 3 are still read): frozen dataclasses, and JSON in and out.

A certificate is a self-contained statement that :mod:`solverplan.certify.check` re-derives in exact
rational arithmetic: the environment, the partition segments it names, the start and goal sets, and
per stage the moves the robot may make, each with an action cone given by two rational direction
vectors. Nothing in it is trusted: angles, widths, images and return maps are recomputed.

Numbers
-------
Every exact number is written as a JSON integer or a string: ``"3/7"`` or an exact decimal ``"0.25"``
(:func:`json_value` picks the shortest). When reading, JSON numbers with a fraction part are taken
at their decimal text (``0.1`` is 1/10, never the binary float near it); Python floats handed to
:meth:`Certificate.from_json` are refused, since their binary value is not what anybody wrote.

Conventions
-----------
- ``environment.rings``: outer ring counter-clockwise, holes clockwise (free space on the left of
  every directed edge); edge ``i`` goes from vertex ``i`` to the next vertex of its ring, the outer
  ring's edges first, then each hole's.
- A boundary parameter ``t`` ∈ [0, 1] runs along a directed edge (t = 0 at its first vertex).
- A **move** leaves the source interval ``source = [p, q]`` of edge ``edge`` with any direction in
  the cone from ``d_lo`` counter-clockwise to ``d_hi`` (world frame, rational vectors, any length)
  and lands on edge ``target_edge`` within ``target = [c, d]`` (parameters on that edge); it may name
  the partition segments involved (``source_segment``, ``target_segment``).
- A **stage** is one bounce: a list of moves, one per possible source (belief-state plans: the robot
  does not know which source it is on). The robot executes a heading θ measured from the edge it is
  on, so the stage's action interval is the set of headings common to all its moves' cones, each
  measured from its own source edge; ``interval`` (optional, radians) claims a part of it.
  ``positions`` (funnels) claims the exact set of positions after the stage.
- ``kind``: ``plan`` (start → goal), ``infeasible`` (no plan from start to goal within the ``bound`` block's
  budget: no stages, the proof is the bound block), ``funnel`` (a plan whose stages carry ``positions``),
  ``localize`` (a funnel whose final positions lie in one interval of one edge shorter than
  ``claims.epsilon``, arc length) or ``cycle`` (``stages[cycle.stages[0]:]`` repeat forever; the block
  claims the exact affine return map of the nominal directions, its fixed point and the worst-case
  contraction over the cones).

Bounds (version 3)
------------------
A ``bound`` block proves that **no plan exists** in a stated class, by an inductive invariant over belief
states (:mod:`solverplan.certify.invariant` has the semantics): ``table`` partitions the boundary into straight
segments (each a list of consecutive pieces ``[edge, t0, t1]`` of the edges, exact), ``heading_margin`` δ and
``threshold`` w (radians, exact) and ``budget`` K (stages; ``null``: any number) state the class — plans of at
most K stages, every stage's interval wider than w inside [δ, π − δ], every stage landing inside one table
segment or anywhere on one group (``groups``, optional: lists of consecutive collinear table segments, each a
segment of P′ cut at the query's set ends) — and ``beliefs`` lists the invariant: sets of table segments (``segments``, ascending ids = indices
into ``table``) with their ``depth``, the first being the start belief at depth 0. An ``infeasible``
certificate has the block and no stages (w = 0); a ``plan`` certificate may carry one as the proof of its
optimality bound (``fewest`` with k bounces: K = k − 1, w = 0; ``tolerance``: no plan wider than w).

Model certificates (version 4)
------------------------------
The other robot models' answers are certified by :class:`ModelCertificate`: ``{"schema", "version": 4, "kind",
"producer", "environment", "claims"}`` with ``kind`` one of :data:`MODEL_KINDS` — ``rooms`` (doors, rooms, the
room tree, areas, escapability Φ and reachability Ψ), ``exploration`` (views, viewpoints, the bound), ``cut-ordering``
(cut end points and their boundary order), ``pursuit`` (a pursuit plan's motions and its shadow labels) and
``fields`` (cells, their fields and outlets). ``claims`` is the kind's own block, exact numbers written as in a
bounce certificate; its fields are documented with each kind's checker (:mod:`solverplan.certify.check_models`)
and in ``docs/contract.md``. The block is read as data here: the checker reads it field by field, and a
missing or malformed field there is a failed claim naming it.

Versions
--------
Version 4 (written) added the model kinds; its bounce certificates are those of version 3. Version 3 added the ``infeasible`` kind and the ``bound`` block. Version 2 added the ``localize`` kind and its ``claims.epsilon``. Version 1 (still read) had
neither: a localisation strategy was a ``funnel`` whose ``claims.objective`` starts with ``localize``; it
is read as a ``localize`` certificate without an ε claim (``claims.epsilon`` is ``None``,
:attr:`Certificate.version` is 1) and written back as version 1, unchanged.

>>> cert = Certificate.from_json(EXAMPLE)
>>> cert.kind, len(cert.stages), cert.stages[0].moves[0].d_lo
('plan', 1, (Fraction(1, 1), Fraction(20, 1)))
>>> Certificate.from_json(cert.to_json()) == cert
True
>>> parse_certificate('{"schema": "solverplan-certificate", "version": 5}')
Traceback (most recent call last):
...
solverplan.certify.schema.CertificateFormatError: certificate version 5 is not supported (this solverplan reads versions 1 to 4)
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from pathlib import Path
from typing import Any, Literal

from solverplan._io import check_json_values, read_input_text, shown_path  # the one bounded reader (standard library only)
from solverplan.errors import MalformedFile

__all__ = [
    "SCHEMA",
    "VERSION",
    "READ_VERSIONS",
    "KINDS",
    "Point",
    "CertificateFormatError",
    "EnvironmentRecord",
    "SegmentRecord",
    "Piece",
    "Move",
    "Stage",
    "Optimality",
    "Claims",
    "CycleClaim",
    "BeliefRecord",
    "BoundClaim",
    "Certificate",
    "ModelCertificate",
    "MODEL_KINDS",
    "parse_number",
    "json_value",
    "number_text",
    "point_text",
    "parse_certificate",
    "load_certificate",
    "dumps_certificate",
    "EXAMPLE",
]


def _q(value: object, limit: int = 40) -> str:
    """``repr(value)`` cut to ``limit`` characters with ``…``: messages quote the input but stay one short line."""
    if isinstance(value, int) and value.bit_length() > 13_000:  # repr would hit Python's digit guard
        return f"(an integer of about {int(value.bit_length() * 0.30103):,} digits)"
    text = str(value) if type(value).__name__ == "Decimal" else repr(value)  # a JSON number as it was written
    return text if len(text) <= limit else text[: limit - 1] + "…"

SCHEMA = "solverplan-certificate"
VERSION = 4
"""The version this solverplan writes."""
READ_VERSIONS = (1, 2, 3, 4)
"""The versions this solverplan reads."""
KINDS = ("plan", "cycle", "funnel", "localize", "infeasible")
MODEL_KINDS = ("rooms", "exploration", "cut-ordering", "pursuit", "fields")
"""The kinds of :class:`ModelCertificate` (version 4): certificates of the other robot models' answers."""
_KINDS_V1 = ("plan", "cycle", "funnel")
_KINDS_V2 = ("plan", "cycle", "funnel", "localize")

Kind = Literal["plan", "cycle", "funnel", "localize", "infeasible"]
Point = tuple[Fraction, Fraction]
"""An exact point or direction vector."""


class CertificateFormatError(MalformedFile):
    """The certificate is not a readable certificate (wrong schema or version, bad number, missing field):
    bad input, exit code 2. Messages name the place, e.g. ``stages[1].moves[0].d_lo: 'x' is not a number``."""


# ---------------------------------------------------------------------- numbers
_RATIO = re.compile(r"^\s*([+-]?\d+)\s*/\s*(\d+)\s*$")

MAX_DIGITS = 200_000
"""Most digits of one integer read from a certificate. The exact products along a long patrol cycle have tens of
thousands of digits, past Python's 4,300-digit guard for parsing untrusted text; this bound keeps a hostile file
from costing minutes of quadratic conversion (200,000 digits read in about 0.05 s)."""


_PIECE_DIGITS = 4000
"""Most digits one ``int()`` call converts here: under Python's 4,300-digit guard, which is never lifted (it is a
setting of the whole process, protecting other threads' parsing of untrusted text)."""


def _int_of(text: str, where: str = "certificate") -> int:
    """``int(text)`` (an optional sign, then digits) for up to :data:`MAX_DIGITS` digits, refusing longer runs in
    one line. Longer than :data:`_PIECE_DIGITS`, the digits are read half by half: high·10**k + low."""
    if len(text) > MAX_DIGITS + 1:
        raise CertificateFormatError(f"{where}: an integer of {len(text):,} digits (at most {MAX_DIGITS:,} are read)")
    if len(text) <= _PIECE_DIGITS:
        return int(text)
    if text[0] in "+-":
        return -_int_of(text[1:], where) if text[0] == "-" else _int_of(text[1:], where)
    k = len(text) // 2
    return _int_of(text[:-k], where) * 10**k + _int_of(text[-k:], where)


def _text_of(n: int, width: int = 0) -> str:
    """``str(n)`` for integers of any length (see :data:`MAX_DIGITS`), zero-padded to ``width`` digits. Past
    13,000 bits (3,914 digits) n is written half by half: divmod(n, 10**k) gives the high digits and the k low
    ones, so every ``str()`` call stays under Python's digit guard."""
    if n < 0:
        return "-" + _text_of(-n, width)
    if n.bit_length() < 13_000:
        return str(n).rjust(width, "0")
    k = n.bit_length() * 3 // 20  # about half of its digits: log10(2) > 3/10
    high, low = divmod(n, 10**k)
    return _text_of(high, width - k) + _text_of(low, k)


def parse_number(value: object, where: str) -> Fraction:
    """An exact number from JSON: an int, a ``"p/q"`` or decimal string, or a :class:`~decimal.Decimal`
    (a JSON number read with ``parse_float=Decimal``). Binary floats, booleans and non-finite values
    are refused with :class:`CertificateFormatError` naming ``where``."""
    if isinstance(value, bool):
        raise CertificateFormatError(f"{where}: {_q(value)} is not a number")
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, Fraction):
        return value
    if isinstance(value, float):
        raise CertificateFormatError(
            f"{where}: {_q(value)} is a binary float; write exact numbers as integers or strings (\"1/3\", \"0.25\")"
        )
    if isinstance(value, Decimal):
        if not value.is_finite():
            raise CertificateFormatError(f"{where}: {value} is not finite")
        return Fraction(value)
    if isinstance(value, str):
        match = _RATIO.match(value)
        if match:
            num, den = _int_of(match.group(1), where), _int_of(match.group(2), where)
            if den == 0:
                raise CertificateFormatError(f"{where}: {_q(value)} divides by zero")
            return Fraction(num, den)
        try:
            number = Decimal(value.strip())
        except InvalidOperation:
            raise CertificateFormatError(f"{where}: {_q(value)} is not a number") from None
        if not number.is_finite():
            raise CertificateFormatError(f"{where}: {_q(value)} is not finite")
        return Fraction(number)
    raise CertificateFormatError(f"{where}: {_q(value)} is not a number")


def _terminating_decimal(value: Fraction) -> str | None:
    """``value`` (not an integer) written out in full as a decimal, or ``None`` if its expansion does not end.

    In lowest terms p/q has a decimal of k digits exactly when q divides 10**k, and k is the least such power.
    Such a k exists exactly when q divides 10**b for b = q.bit_length(), since q = 2**i 5**j c holds each of the
    primes 2 and 5 fewer than b times. As q | 10**k implies q | 10**(k + 1), the least k is found by bisection
    (on residues ``pow(10, k, q)``, never on the large powers themselves).
    """
    den = value.denominator
    high = den.bit_length()  # q | 10**high if any power of ten at all
    if pow(10, high, den) != 0:
        return None
    low = 0  # q ∤ 10**low: q > 1 here
    while high - low > 1:
        middle = (low + high) // 2
        if pow(10, middle, den) == 0:
            high = middle
        else:
            low = middle
    digits = high
    scaled = abs(value.numerator) * (10**digits // value.denominator)
    text = _text_of(scaled).rjust(digits + 1, "0")
    sign = "-" if value < 0 else ""
    return f"{sign}{text[:-digits]}.{text[-digits:]}"


def number_text(value: Fraction | int) -> str:
    """Exact text of a number: ``3``, ``-0.25``, ``1/3`` (a terminating decimal when shorter)."""
    value = Fraction(value)
    if value.denominator == 1:
        return _text_of(value.numerator)
    ratio = f"{_text_of(value.numerator)}/{_text_of(value.denominator)}"
    decimal = _terminating_decimal(value)
    return decimal if decimal is not None and len(decimal) <= len(ratio) + 4 else ratio


def json_value(value: Fraction | int) -> int | str:
    """An exact number as JSON: an integer, or the string of :func:`number_text`."""
    value = Fraction(value)
    if value.denominator == 1 and value.numerator.bit_length() < 13_000:
        return int(value.numerator)
    return number_text(value)  # integers past Python's digit guard, too: JSON encoders refuse to print them


def point_text(p: tuple[Fraction | int, Fraction | int]) -> str:
    """``(x, y)`` with :func:`number_text` coordinates, for messages."""
    return f"({number_text(p[0])}, {number_text(p[1])})"


# ---------------------------------------------------------------------- records
@dataclass(frozen=True, slots=True)
class EnvironmentRecord:
    """The environment: ``rings[0]`` the outer ring (CCW), then the holes (CW); exact points."""

    rings: tuple[tuple[Point, ...], ...]
    name: str = ""


@dataclass(frozen=True, slots=True)
class SegmentRecord:
    """A segment of P′ named by the certificate: t ∈ [t0, t1] of ``edge``, from ``a`` to ``b``."""

    id: int
    edge: int
    t0: Fraction
    t1: Fraction
    a: Point
    b: Point


@dataclass(frozen=True, slots=True)
class Piece:
    """The part t ∈ [t0, t1] of edge ``edge`` (closed; t0 < t1)."""

    edge: int
    t0: Fraction
    t1: Fraction


@dataclass(frozen=True, slots=True)
class Move:
    """From ``source`` = [p, q] on ``edge``, any direction from ``d_lo`` CCW to ``d_hi``, onto
    ``target`` = [c, d] on ``target_edge`` (see the module docstring)."""

    edge: int
    source: tuple[Fraction, Fraction]
    d_lo: Point
    d_hi: Point
    target_edge: int
    target: tuple[Fraction, Fraction]
    source_segment: int | None = None
    target_segment: int | None = None


@dataclass(frozen=True, slots=True)
class Stage:
    """One bounce: its moves, optionally the claimed heading ``interval`` (radians, measured from each
    move's source edge) and the claimed exact ``positions`` after the stage."""

    moves: tuple[Move, ...]
    interval: tuple[Fraction, Fraction] | None = None
    positions: tuple[Piece, ...] | None = None


@dataclass(frozen=True, slots=True)
class Optimality:
    """How optimality was established: ``method`` (e.g. ``search-exhausted``, ``lp-duality``,
    ``heuristic``), whether it is ``proved``, and the ``bound`` (best objective any plan could reach)."""

    method: str
    proved: bool
    bound: Fraction | None = None


@dataclass(frozen=True, slots=True)
class Claims:
    """The numbers a certificate claims (all re-derived by the checker).

    ``min_width`` is a lower bound on the narrowest stage's angular width (radians), within 1e-9 of
    it; ``tolerance`` = min_width / 2; ``sum_width`` (optional) a lower bound on the sum of the widths;
    ``epsilon`` (``localize`` certificates of version 2; same unit as the coordinates): the final
    position set lies in one interval of one edge whose arc length is less than ε.
    """

    bounces: int
    min_width: Fraction
    tolerance: Fraction
    objective: str | None = None
    sum_width: Fraction | None = None
    optimality: Optimality | None = None
    epsilon: Fraction | None = None


@dataclass(frozen=True, slots=True)
class CycleClaim:
    """A limit cycle: ``stages`` (the tail of the stage list that repeats), one ``nominal`` direction
    per cycle stage (inside that stage's cone), the exact return map t ↦ ``alpha`` t + ``beta`` of the
    nominal directions on the entry edge, its ``fixed_point`` β / (1 − α), and ``contraction``: the
    worst case of |α| over all directions in the cones (must be < 1). ``visits``: edges the cycle
    visits in this cyclic order (patrolling)."""

    stages: tuple[int, ...]
    nominal: tuple[Point, ...]
    alpha: Fraction
    beta: Fraction
    fixed_point: Fraction
    contraction: Fraction
    visits: tuple[int, ...] | None = None


@dataclass(frozen=True, slots=True)
class BeliefRecord:
    """One belief of a bound's invariant: table segment ids (ascending) and its depth (stages from the start)."""

    segments: tuple[int, ...]
    depth: int


@dataclass(frozen=True, slots=True)
class BoundClaim:
    """A proof that no plan exists in a class (module docstring, *Bounds*): the segment ``table`` (per segment,
    its pieces ``(edge, t0, t1)``), ``heading_margin`` δ, ``threshold`` w (radians), ``budget`` K (None: any
    number of stages) and the invariant's ``beliefs`` (the first is the start belief, depth 0)."""

    table: tuple[tuple[tuple[int, Fraction, Fraction], ...], ...]
    heading_margin: Fraction
    threshold: Fraction
    budget: int | None
    beliefs: tuple[BeliefRecord, ...]
    table_source: str = ""
    """What the table is, in words (``P′ of the straight walls refined at the query's set ends``): stated by the
    producer, not checked (the statement proved is about this table, whatever its origin)."""
    groups: tuple[tuple[int, ...], ...] = ()
    """Runs of consecutive, collinear table segments (each a segment of P′ cut at the query's set ends) that a stage
    may land anywhere on, as on one segment (:mod:`solverplan.certify.invariant`); checked."""


@dataclass(frozen=True, slots=True)
class Certificate:
    """A certificate; see the module docstring. Build with :mod:`solverplan.certify.writer` or
    :meth:`from_json`; check with :func:`solverplan.certify.check.check_certificate`. ``version``: the
    format version it was read as (and is written as): :data:`VERSION` for new certificates."""

    kind: Kind
    environment: EnvironmentRecord
    segments: tuple[SegmentRecord, ...]
    start: tuple[Piece, ...]
    goal: tuple[Piece, ...] | None
    stages: tuple[Stage, ...]
    claims: Claims
    cycle: CycleClaim | None = None
    producer: str = ""
    version: int = VERSION
    bound: BoundClaim | None = None

    # ------------------------------------------------------------------ JSON out
    def to_json(self) -> dict:
        """The certificate as JSON data (exact numbers as ints or strings)."""
        # version 1 spelled a localisation certificate as a funnel (its objective says localize)
        kind = "funnel" if self.version == 1 and self.kind == "localize" else self.kind
        data = _head_json(kind, self.version, self.producer, self.environment)
        data["segments"] = [
            {"id": s.id, "edge": s.edge, "t0": json_value(s.t0), "t1": json_value(s.t1), "a": _point_json(s.a), "b": _point_json(s.b)}
            for s in self.segments
        ]
        data["start"] = [_piece_json(p) for p in self.start]
        data["goal"] = None if self.goal is None else [_piece_json(p) for p in self.goal]
        data["stages"] = [_stage_json(s) for s in self.stages]
        claims: dict[str, Any] = {} if self.kind == "infeasible" else {
            "bounces": self.claims.bounces,
            "min_width": json_value(self.claims.min_width),
            "tolerance": json_value(self.claims.tolerance),
        }
        if self.claims.objective is not None:
            claims["objective"] = self.claims.objective
        if self.claims.sum_width is not None:
            claims["sum_width"] = json_value(self.claims.sum_width)
        if self.claims.optimality is not None:
            opt = self.claims.optimality
            claims["optimality"] = {
                "method": opt.method,
                "proved": opt.proved,
                "bound": None if opt.bound is None else json_value(opt.bound),
            }
        if self.claims.epsilon is not None:
            claims["epsilon"] = json_value(self.claims.epsilon)
        data["claims"] = claims
        if self.cycle is not None:
            c = self.cycle
            cycle: dict[str, Any] = {
                "stages": list(c.stages),
                "nominal": [_point_json(d) for d in c.nominal],
                "alpha": json_value(c.alpha),
                "beta": json_value(c.beta),
                "fixed_point": json_value(c.fixed_point),
                "contraction": json_value(c.contraction),
            }
            if c.visits is not None:
                cycle["visits"] = list(c.visits)
            data["cycle"] = cycle
        if self.bound is not None:
            data["bound"] = _bound_json(self.bound)
        return data

    # ------------------------------------------------------------------ JSON in
    @classmethod
    def from_json(cls, data: object) -> Certificate:
        """Read JSON data (as from ``json.loads(text, parse_float=Decimal)``).

        Raises
        ------
        CertificateFormatError
            Wrong schema or version, a missing or unknown field, a bad number; the message names the
            place (``stages[0].moves[1].target``). Semantic problems (a ray missing its target, an
            unknown segment id) are not format errors: the checker reports them.
        """
        top, version = _head(data)
        kind = _field(top, "kind", "certificate")
        if version >= 4 and kind in MODEL_KINDS:
            raise CertificateFormatError(f"kind: {_q(kind)} is a model certificate: read it with parse_certificate")
        fields = {"schema", "version", "kind", "producer", "environment", "segments", "start", "goal", "stages", "claims", "cycle"}
        _known(top, fields | {"bound"} if version >= 3 else fields, "certificate")
        kinds = KINDS if version >= 3 else _KINDS_V2 if version == 2 else _KINDS_V1
        if kind not in kinds:
            raise CertificateFormatError(f"kind: {_q(kind)} is not one of {', '.join(kinds)}")
        producer = top.get("producer", "")
        if not isinstance(producer, str):
            raise CertificateFormatError(f"producer: expected a string, got {_q(producer)}")
        environment = _environment(_field(top, "environment", "certificate"))
        segments = tuple(_segment(s, f"segments[{i}]") for i, s in enumerate(_list(_field(top, "segments", "certificate"), "segments")))
        start = _pieces(_field(top, "start", "certificate"), "start")
        if not start:
            raise CertificateFormatError("start: the start set is empty")
        goal_raw = top.get("goal")
        goal = None if goal_raw is None else _pieces(goal_raw, "goal")
        stages_raw = _list(_field(top, "stages", "certificate"), "stages")
        if kind == "infeasible":
            if stages_raw:
                raise CertificateFormatError("stages: an infeasible certificate has no stages (its proof is the bound block)")
        elif not stages_raw and kind not in ("plan", "funnel"):
            # (a plan or funnel of no stages claims that its start set lies in its goal set: checked exactly)
            raise CertificateFormatError(f"stages: a {kind} certificate has at least one stage")
        stages = tuple(_stage(s, f"stages[{i}]") for i, s in enumerate(stages_raw))
        claims = _claims(_field(top, "claims", "certificate"), version, infeasible=kind == "infeasible")
        bound_raw = top.get("bound")
        bound = None if bound_raw is None else _bound(bound_raw)
        if kind == "infeasible" and bound is None:
            raise CertificateFormatError("bound: an infeasible certificate needs the bound block (its proof)")
        if bound is not None and kind not in ("plan", "infeasible"):
            raise CertificateFormatError(f"bound: a {kind} certificate has no bound block (only plan and infeasible ones)")
        if version == 1 and kind == "funnel" and (claims.objective or "").startswith("localize"):
            kind = "localize"  # a version-1 localisation strategy: read as what it is, without an ε claim
        elif kind == "localize" and claims.epsilon is None:
            raise CertificateFormatError("claims.epsilon: a localize certificate claims ε (the final interval is shorter than it)")
        elif kind != "localize" and claims.epsilon is not None:
            raise CertificateFormatError(f"claims.epsilon: only a localize certificate claims ε, not a {kind} certificate")
        cycle_raw = top.get("cycle")
        cycle = None if cycle_raw is None else _cycle(cycle_raw)
        if kind == "cycle":
            if cycle is None:
                raise CertificateFormatError("cycle: a cycle certificate needs the cycle block")
            if goal is not None:
                raise CertificateFormatError("goal: a cycle certificate has no goal (its cycle is the goal): use null")
        else:
            if cycle is not None:
                raise CertificateFormatError(f"cycle: a {kind} certificate has no cycle block")
            if goal is None or not goal:
                raise CertificateFormatError(f"goal: a {kind} certificate needs a non-empty goal set")
        if kind in ("funnel", "localize"):
            for i, stage in enumerate(stages):
                if stage.positions is None:
                    raise CertificateFormatError(f"stages[{i}].positions: a {kind} certificate claims the positions after every stage")
        return cls(kind, environment, segments, start, goal, stages, claims, cycle, producer, version, bound)


@dataclass(frozen=True)
class ModelCertificate:
    """A certificate of another robot model's answer (version 4; module docstring, *Model certificates*).

    ``claims`` is the kind's block as JSON data (exact numbers as ints, strings or :class:`~decimal.Decimal`);
    :func:`solverplan.certify.check.check_certificate` reads and re-derives it. Build with
    :func:`solverplan.certify.build.certificate`.

    >>> cert = ModelCertificate("cut-ordering", EnvironmentRecord((((0, 0), (1, 0), (0, 1)),)),
    ...                         {"cuts": [], "ordering": ["v0", "v1", "v2"]})
    >>> ModelCertificate.from_json(cert.to_json()) == cert
    True
    """

    kind: str
    environment: EnvironmentRecord
    claims: dict
    producer: str = ""
    version: int = VERSION

    def to_json(self) -> dict:
        """The certificate as JSON data."""
        data = _head_json(self.kind, self.version, self.producer, self.environment)
        data["claims"] = _plain(self.claims)
        return data

    @classmethod
    def from_json(cls, data: object) -> ModelCertificate:
        """Read JSON data; :class:`CertificateFormatError` for a wrong schema, version or kind or a missing field."""
        top, version = _head(data)
        kind = _field(top, "kind", "certificate")
        if kind not in MODEL_KINDS or version < 4:
            raise CertificateFormatError(f"kind: {_q(kind)} is not a model certificate kind of version {version}")
        _known(top, {"schema", "version", "kind", "producer", "environment", "claims"}, "certificate")
        producer = top.get("producer", "")
        if not isinstance(producer, str):
            raise CertificateFormatError(f"producer: expected a string, got {_q(producer)}")
        environment = _environment(_field(top, "environment", "certificate"))
        claims = _object(_field(top, "claims", "certificate"), "claims")
        return cls(kind, environment, claims, producer, version)


def _head(data: object) -> tuple[dict, int]:
    """The top object and its version, once the schema and version are known (:class:`CertificateFormatError`)."""
    top = _object(data, "certificate")
    if top.get("schema") != SCHEMA:
        raise CertificateFormatError(f"not a solverplan certificate: schema is {_q(top.get('schema'))}, expected {_q(SCHEMA)}")
    version = top.get("version")
    if not isinstance(version, int) or isinstance(version, bool):  # 2.0 (a JSON decimal) is no version number
        raise CertificateFormatError(f"certificate version {_q(version)}: expected an integer (1 to 4)")
    if version not in READ_VERSIONS:
        raise CertificateFormatError(f"certificate version {_q(version)} is not supported (this solverplan reads versions 1 to 4)")
    return top, version


def _head_json(kind: str, version: int, producer: str, environment: EnvironmentRecord) -> dict[str, Any]:
    """What every certificate starts with: schema, version, kind, producer (if any) and the environment."""
    data: dict[str, Any] = {"schema": SCHEMA, "version": version, "kind": kind}
    if producer:
        data["producer"] = producer
    env: dict[str, Any] = {}
    if environment.name:
        env["name"] = environment.name
    env["rings"] = [[_point_json(p) for p in ring] for ring in environment.rings]
    data["environment"] = env
    return data


def _plain(value: Any) -> Any:
    """JSON data with exact numbers (Fractions, Decimals) as :func:`json_value` text."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, (int, Fraction, Decimal)):
        return json_value(Fraction(value))
    raise TypeError(f"a model certificate holds exact numbers, not {type(value).__name__}")


# ---------------------------------------------------------------------- text in and out
def parse_certificate(text: str, *, source: str = "certificate") -> Certificate | ModelCertificate:
    """Parse certificate JSON text (decimals read exactly); :class:`CertificateFormatError` if malformed."""
    try:
        check_json_values(text, source)  # before parsing: memory in proportion to the file
    except MalformedFile as exc:
        raise CertificateFormatError(str(exc)) from None
    try:
        data = json.loads(text, parse_float=Decimal, parse_int=_int_of, parse_constant=_reject_constant)
    except json.JSONDecodeError as exc:
        raise CertificateFormatError(f"{source}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except CertificateFormatError as exc:
        raise CertificateFormatError(f"{source}: {exc}") from None
    except RecursionError:
        raise CertificateFormatError(f"{source}: JSON nested too deeply") from None
    except ValueError as exc:  # a decimal of a huge exponent, or another number Python cannot read
        raise CertificateFormatError(f"{source}: a number cannot be read ({str(exc)[:60]})") from None
    if isinstance(data, dict) and data.get("kind") in MODEL_KINDS:
        return ModelCertificate.from_json(data)
    return Certificate.from_json(data)


def load_certificate(path: str | Path) -> Certificate | ModelCertificate:
    """Read a certificate file; :class:`CertificateFormatError` (naming the file) if it is unreadable or malformed.

    Parameters
    ----------
    path
        A certificate file (JSON) written by :func:`~solverplan.certify.build.write_certificate` or
        ``solverplan plan --certificate``.

    Returns
    -------
    Certificate or ModelCertificate
        The parsed certificate, exact (numbers as fractions); not yet checked (a :class:`ModelCertificate` for the
        other models' kinds, :data:`MODEL_KINDS`).

    Raises
    ------
    CertificateFormatError
        A missing or unreadable file, invalid JSON, or a field of the wrong shape (a
        :class:`~solverplan.errors.MalformedFile`).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "certificate.json"
    >>> sp.write_certificate(sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env), path)
    >>> cert = sp.load_certificate(path)
    >>> cert.kind, sp.check_certificate(cert).valid
    ('plan', True)
    >>> _ = path.write_text("{")
    >>> sp.load_certificate(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    solverplan.certify.schema.CertificateFormatError: .../certificate.json: not valid JSON (Expecting property name enclosed in double quotes at line 1 column 2)
    """
    path = Path(path)
    name = shown_path(path)
    try:
        text = read_input_text(path)  # regular files only, never read past the limit (solverplan._io)
    except MalformedFile as exc:
        raise CertificateFormatError(str(exc)) from None
    try:
        return parse_certificate(text, source=name)
    except CertificateFormatError as exc:
        message = str(exc)
        raise CertificateFormatError(message if message.startswith(f"{name}:") else f"{name}: {message}") from None


def dumps_certificate(cert: Certificate | ModelCertificate) -> str:
    """The certificate as JSON text (two-space indent, small arrays on one line), ending in a newline."""
    return _layout(cert.to_json(), "") + "\n"


def _layout(value: Any, indent: str) -> str:
    flat = json.dumps(value, ensure_ascii=False)
    if not isinstance(value, (dict, list)) or len(flat) + len(indent) <= 100 and _shallow(value):
        return flat
    step = indent + "  "
    if isinstance(value, dict):
        body = ",\n".join(f"{step}{json.dumps(k)}: {_layout(v, step)}" for k, v in value.items())
        return "{\n" + body + "\n" + indent + "}"
    body = ",\n".join(step + _layout(v, step) for v in value)
    return "[\n" + body + "\n" + indent + "]"


def _shallow(value: Any, depth: int = 0) -> bool:
    if isinstance(value, dict):
        return depth < 2 and all(_shallow(v, depth + 1) for v in value.values())
    if isinstance(value, list):
        return depth < 3 and all(_shallow(v, depth + 1) for v in value)
    return True


def _reject_constant(name: str) -> None:
    raise CertificateFormatError(f"non-finite number {name}")


# ---------------------------------------------------------------------- JSON helpers (out)
def _point_json(p: Point) -> list:
    return [json_value(p[0]), json_value(p[1])]


def _piece_json(p: Piece) -> dict:
    return {"edge": p.edge, "t0": json_value(p.t0), "t1": json_value(p.t1)}


def _move_json(m: Move) -> dict:
    data: dict[str, Any] = {}
    if m.source_segment is not None:
        data["source_segment"] = m.source_segment
    data["edge"] = m.edge
    data["source"] = [json_value(m.source[0]), json_value(m.source[1])]
    data["d_lo"] = _point_json(m.d_lo)
    data["d_hi"] = _point_json(m.d_hi)
    if m.target_segment is not None:
        data["target_segment"] = m.target_segment
    data["target_edge"] = m.target_edge
    data["target"] = [json_value(m.target[0]), json_value(m.target[1])]
    return data


def _stage_json(s: Stage) -> dict:
    data: dict[str, Any] = {}
    if s.interval is not None:
        data["interval"] = [json_value(s.interval[0]), json_value(s.interval[1])]
    data["moves"] = [_move_json(m) for m in s.moves]
    if s.positions is not None:
        data["positions"] = [_piece_json(p) for p in s.positions]
    return data


# ---------------------------------------------------------------------- JSON helpers (in)
def _object(value: object, where: str) -> dict:
    if not isinstance(value, dict):
        raise CertificateFormatError(f"{where}: expected a JSON object, got {_kind_of(value)}")
    return value


def _list(value: object, where: str) -> list:
    if not isinstance(value, list):
        raise CertificateFormatError(f"{where}: expected a list, got {_kind_of(value)}")
    return value


def _kind_of(value: object) -> str:
    names = {dict: "an object", list: "a list", str: "a string", bool: "a boolean", type(None): "null"}
    for kind, name in names.items():
        if isinstance(value, kind):
            return name
    return "a number" if isinstance(value, (int, float, Decimal)) else type(value).__name__


def _field(obj: dict, key: str, where: str) -> Any:
    if key not in obj:
        raise CertificateFormatError(f"{where}: missing field {_q(key)}")
    return obj[key]


def _known(obj: dict, keys: set[str], where: str) -> None:
    unknown = sorted(set(obj) - keys)
    if unknown:
        raise CertificateFormatError(f"{where}: unknown field {_q(unknown[0])}")


def _integer(value: object, where: str, *, minimum: int | None = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise CertificateFormatError(f"{where}: expected an integer, got {_q(value)}")
    if minimum is not None and value < minimum:
        raise CertificateFormatError(f"{where}: expected an integer ≥ {minimum}, got {value}")
    return value


def _point(value: object, where: str) -> Point:
    if not isinstance(value, list) or len(value) != 2:
        raise CertificateFormatError(f"{where}: expected a pair [x, y], got {_q(value)}")
    return (parse_number(value[0], where), parse_number(value[1], where))


def _pair(value: object, where: str) -> tuple[Fraction, Fraction]:
    if not isinstance(value, list) or len(value) != 2:
        raise CertificateFormatError(f"{where}: expected a pair [lo, hi], got {_q(value)}")
    return (parse_number(value[0], where), parse_number(value[1], where))


def _environment(value: object) -> EnvironmentRecord:
    obj = _object(value, "environment")
    _known(obj, {"name", "rings"}, "environment")
    name = obj.get("name", "")
    if not isinstance(name, str):
        raise CertificateFormatError(f"environment.name: expected a string, got {_q(name)}")
    rings_raw = _list(_field(obj, "rings", "environment"), "environment.rings")
    if not rings_raw:
        raise CertificateFormatError("environment.rings: no outer ring")
    rings = []
    for r, ring in enumerate(rings_raw):
        where = f"environment.rings[{r}]"
        rings.append(tuple(_point(p, f"{where}[{k}]") for k, p in enumerate(_list(ring, where))))
    return EnvironmentRecord(tuple(rings), name)


def _segment(value: object, where: str) -> SegmentRecord:
    obj = _object(value, where)
    _known(obj, {"id", "edge", "t0", "t1", "a", "b"}, where)
    return SegmentRecord(
        _integer(_field(obj, "id", where), f"{where}.id"),
        _integer(_field(obj, "edge", where), f"{where}.edge"),
        parse_number(_field(obj, "t0", where), f"{where}.t0"),
        parse_number(_field(obj, "t1", where), f"{where}.t1"),
        _point(_field(obj, "a", where), f"{where}.a"),
        _point(_field(obj, "b", where), f"{where}.b"),
    )


def _piece(value: object, where: str) -> Piece:
    obj = _object(value, where)
    _known(obj, {"edge", "t0", "t1"}, where)
    return Piece(
        _integer(_field(obj, "edge", where), f"{where}.edge"),
        parse_number(_field(obj, "t0", where), f"{where}.t0"),
        parse_number(_field(obj, "t1", where), f"{where}.t1"),
    )


def _pieces(value: object, where: str) -> tuple[Piece, ...]:
    return tuple(_piece(p, f"{where}[{i}]") for i, p in enumerate(_list(value, where)))


def _move(value: object, where: str) -> Move:
    obj = _object(value, where)
    _known(obj, {"source_segment", "edge", "source", "d_lo", "d_hi", "target_segment", "target_edge", "target"}, where)
    source_segment = obj.get("source_segment")
    target_segment = obj.get("target_segment")
    return Move(
        edge=_integer(_field(obj, "edge", where), f"{where}.edge"),
        source=_pair(_field(obj, "source", where), f"{where}.source"),
        d_lo=_point(_field(obj, "d_lo", where), f"{where}.d_lo"),
        d_hi=_point(_field(obj, "d_hi", where), f"{where}.d_hi"),
        target_edge=_integer(_field(obj, "target_edge", where), f"{where}.target_edge"),
        target=_pair(_field(obj, "target", where), f"{where}.target"),
        source_segment=None if source_segment is None else _integer(source_segment, f"{where}.source_segment"),
        target_segment=None if target_segment is None else _integer(target_segment, f"{where}.target_segment"),
    )


def _stage(value: object, where: str) -> Stage:
    obj = _object(value, where)
    _known(obj, {"interval", "moves", "positions"}, where)
    moves_raw = _list(_field(obj, "moves", where), f"{where}.moves")
    if not moves_raw:
        raise CertificateFormatError(f"{where}.moves: a stage has at least one move")
    moves = tuple(_move(m, f"{where}.moves[{i}]") for i, m in enumerate(moves_raw))
    interval_raw = obj.get("interval")
    interval = None if interval_raw is None else _pair(interval_raw, f"{where}.interval")
    positions_raw = obj.get("positions")
    positions = None if positions_raw is None else _pieces(positions_raw, f"{where}.positions")
    return Stage(moves, interval, positions)


def _claims(value: object, version: int = VERSION, *, infeasible: bool = False) -> Claims:
    where = "claims"
    obj = _object(value, where)
    if infeasible:  # no plan: nothing but the objective asked for
        _known(obj, {"objective"}, where)
        objective = obj.get("objective")
        if objective is not None and not isinstance(objective, str):
            raise CertificateFormatError(f"claims.objective: expected a string, got {_q(objective)}")
        return Claims(bounces=0, min_width=Fraction(0), tolerance=Fraction(0), objective=objective)
    keys = {"bounces", "min_width", "tolerance", "objective", "sum_width", "optimality"}
    _known(obj, keys | {"epsilon"} if version >= 2 else keys, where)
    epsilon_raw = obj.get("epsilon")
    objective = obj.get("objective")
    if objective is not None and not isinstance(objective, str):
        raise CertificateFormatError(f"claims.objective: expected a string, got {_q(objective)}")
    sum_raw = obj.get("sum_width")
    optimality = None
    if obj.get("optimality") is not None:
        opt = _object(obj["optimality"], "claims.optimality")
        _known(opt, {"method", "proved", "bound"}, "claims.optimality")
        method = _field(opt, "method", "claims.optimality")
        if not isinstance(method, str) or not method:
            raise CertificateFormatError(f"claims.optimality.method: expected a non-empty string, got {_q(method)}")
        proved = _field(opt, "proved", "claims.optimality")
        if not isinstance(proved, bool):
            raise CertificateFormatError(f"claims.optimality.proved: expected true or false, got {_q(proved)}")
        bound_raw = opt.get("bound")
        bound = None if bound_raw is None else parse_number(bound_raw, "claims.optimality.bound")
        optimality = Optimality(method, proved, bound)
    return Claims(
        bounces=_integer(_field(obj, "bounces", where), "claims.bounces"),
        min_width=parse_number(_field(obj, "min_width", where), "claims.min_width"),
        tolerance=parse_number(_field(obj, "tolerance", where), "claims.tolerance"),
        objective=objective,
        sum_width=None if sum_raw is None else parse_number(sum_raw, "claims.sum_width"),
        optimality=optimality,
        epsilon=None if epsilon_raw is None else parse_number(epsilon_raw, "claims.epsilon"),
    )


def _cycle(value: object) -> CycleClaim:
    where = "cycle"
    obj = _object(value, where)
    _known(obj, {"stages", "nominal", "alpha", "beta", "fixed_point", "contraction", "visits"}, where)
    stages = tuple(_integer(s, f"cycle.stages[{i}]") for i, s in enumerate(_list(_field(obj, "stages", where), "cycle.stages")))
    if not stages:
        raise CertificateFormatError("cycle.stages: a cycle has at least one stage")
    nominal = tuple(_point(d, f"cycle.nominal[{i}]") for i, d in enumerate(_list(_field(obj, "nominal", where), "cycle.nominal")))
    visits_raw = obj.get("visits")
    visits = None
    if visits_raw is not None:
        visits = tuple(_integer(e, f"cycle.visits[{i}]") for i, e in enumerate(_list(visits_raw, "cycle.visits")))
    return CycleClaim(
        stages=stages,
        nominal=nominal,
        alpha=parse_number(_field(obj, "alpha", where), "cycle.alpha"),
        beta=parse_number(_field(obj, "beta", where), "cycle.beta"),
        fixed_point=parse_number(_field(obj, "fixed_point", where), "cycle.fixed_point"),
        contraction=parse_number(_field(obj, "contraction", where), "cycle.contraction"),
        visits=visits,
    )


def _bound(value: object) -> BoundClaim:
    where = "bound"
    obj = _object(value, where)
    _known(obj, {"budget", "threshold", "heading_margin", "table_source", "table", "beliefs", "groups"}, where)
    source = obj.get("table_source", "")
    if not isinstance(source, str):
        raise CertificateFormatError(f"bound.table_source: expected a string, got {_q(source)}")
    budget_raw = _field(obj, "budget", where)
    budget = None if budget_raw is None else _integer(budget_raw, "bound.budget")
    threshold = parse_number(_field(obj, "threshold", where), "bound.threshold")
    delta = parse_number(_field(obj, "heading_margin", where), "bound.heading_margin")
    table = []
    for k, seg in enumerate(_list(_field(obj, "table", where), "bound.table")):
        pieces = []
        for i, piece in enumerate(_list(seg, f"bound.table[{k}]")):
            w = f"bound.table[{k}][{i}]"
            if not isinstance(piece, list) or len(piece) != 3:
                raise CertificateFormatError(f"{w}: expected a piece [edge, t0, t1], got {_q(piece)}")
            pieces.append((_integer(piece[0], w), parse_number(piece[1], w), parse_number(piece[2], w)))
        table.append(tuple(pieces))
    beliefs = []
    for i, item in enumerate(_list(_field(obj, "beliefs", where), "bound.beliefs")):
        w = f"bound.beliefs[{i}]"
        b = _object(item, w)
        _known(b, {"depth", "segments"}, w)
        segs = tuple(_integer(x, f"{w}.segments") for x in _list(_field(b, "segments", w), f"{w}.segments"))
        beliefs.append(BeliefRecord(segs, _integer(_field(b, "depth", w), f"{w}.depth")))
    if not beliefs:
        raise CertificateFormatError("bound.beliefs: the invariant lists at least the start belief")
    groups = tuple(tuple(_integer(x, f"bound.groups[{i}]") for x in _list(item, f"bound.groups[{i}]"))
                   for i, item in enumerate(_list(obj.get("groups", []), "bound.groups")))
    return BoundClaim(tuple(table), delta, threshold, budget, tuple(beliefs), source, groups)


def _bound_json(b: BoundClaim) -> dict:
    return {
        "budget": b.budget,
        "threshold": json_value(b.threshold),
        "heading_margin": json_value(b.heading_margin),
        **({"table_source": b.table_source} if b.table_source else {}),
        "beliefs": [{"depth": r.depth, "segments": list(r.segments)} for r in b.beliefs],
        "table": [[[e, json_value(t0), json_value(t1)] for e, t0, t1 in seg] for seg in b.table],
        **({"groups": [list(g) for g in b.groups]} if b.groups else {}),
    }


EXAMPLE: dict = {
    "schema": SCHEMA,
    "version": VERSION,
    "kind": "plan",
    "producer": "hand-written example: square, bottom to top",
    "environment": {"name": "square", "rings": [[[0, 0], [10, 0], [10, 10], [0, 10]]]},
    "segments": [
        {"id": 0, "edge": 0, "t0": 0, "t1": 1, "a": [0, 0], "b": [10, 0]},
        {"id": 2, "edge": 2, "t0": 0, "t1": 1, "a": [10, 10], "b": [0, 10]},
    ],
    "start": [{"edge": 0, "t0": "0.1", "t1": "0.9"}],
    "goal": [{"edge": 2, "t0": 0, "t1": 1}],
    "stages": [
        {
            "interval": ["1.5208379310729539", "1.6207547225168393"],
            "moves": [
                {"source_segment": 0, "edge": 0, "source": ["0.1", "0.9"], "d_lo": [1, 20], "d_hi": [-1, 20],
                 "target_segment": 2, "target_edge": 2, "target": [0, 1]}
            ],
        }
    ],
    "claims": {"bounces": 1, "min_width": "0.0999167914438854", "tolerance": "0.0499583957219427"},
}
"""A small valid certificate (one stage in the 10 × 10 square, from the middle of the bottom edge
straight up, headings π/2 ± atan(1/20)): the shape every certificate has."""
