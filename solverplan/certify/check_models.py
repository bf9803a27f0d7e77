"""The exact checks of model certificates (version 4): one entry, one verdict shape, one reading of the claims.

:func:`check_model_certificate` validates the environment exactly (the checks of a bounce certificate's
environment: rings, orientation, simplicity, holes) and hands the ``claims`` block to its kind's checker:

- ``rooms`` — :mod:`solverplan.certify.check_rooms`;
- ``exploration`` — :mod:`solverplan.certify.check_exploration`;
- ``cut-ordering`` and ``pursuit`` — :mod:`solverplan.certify.check_wallfollow`;
- ``fields`` — :mod:`solverplan.certify.check_fields`.

Each returns the :class:`~solverplan.certify.check.CheckReport` every certificate gets: ``valid``, the failures (each
naming its claim, e.g. ``claims.doors[2].escapability[0]``), the counts of what was re-derived, what was not checked
(and why), the statements ``proved`` and, for these kinds, ``scope``: what the statements speak about, in words.

Like the rest of the checker, these modules import only the standard library and each other: a claim is read with
:class:`Reader` (a missing or malformed field is a failed claim, never a crash) and decided in rational arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable

from solverplan.certify.check import CheckReport, Failure, _Checker, _environment_summary
from solverplan.certify.exact2d import cross, dot, inside_ring as _inside, on_closed_segment, orient, sub, uncovered
from solverplan.certify.schema import ModelCertificate, Point, number_text, parse_number

__all__ = ["check_model_certificate", "Malformed", "Reader", "ModelChecker", "Env", "inside_open", "box", "apart", "param_on"]


class Malformed(Exception):
    """A claim that cannot be read (missing field, wrong type, not a number): reported as a failure of ``claim``."""

    def __init__(self, claim: str, message: str) -> None:
        super().__init__(f"{claim}: {message}")
        self.claim = claim
        self.message = message


class Reader:
    """Typed reads of JSON claims that raise :class:`Malformed` naming the place."""

    @staticmethod
    def of_type(value: Any, kind: type, where: str, what: str) -> Any:
        """``value`` when it is a ``kind``; otherwise :class:`Malformed` saying ``expected`` ``what``."""
        if not isinstance(value, kind):
            raise Malformed(where, f"expected {what}")
        return value

    @staticmethod
    def obj(value: Any, where: str) -> dict:
        return Reader.of_type(value, dict, where, "a JSON object")

    @staticmethod
    def lst(value: Any, where: str) -> list:
        return Reader.of_type(value, list, where, "a list")

    @staticmethod
    def field(obj: dict, key: str, where: str) -> Any:
        if key not in obj:
            raise Malformed(f"{where}.{key}", "missing")
        return obj[key]

    @staticmethod
    def integer(value: Any, where: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise Malformed(where, f"expected an integer, got {str(value)[:40]!r}")
        return value

    @staticmethod
    def number(value: Any, where: str) -> Fraction:
        try:
            return parse_number(value, where)
        except ValueError as exc:
            raise Malformed(where, str(exc).split(": ", 1)[-1]) from None

    @staticmethod
    def point(value: Any, where: str) -> Point:
        if not isinstance(value, list) or len(value) != 2:
            raise Malformed(where, "expected a point [x, y]")
        return (Reader.number(value[0], where), Reader.number(value[1], where))

    @staticmethod
    def ring(value: Any, where: str) -> list[Point]:
        return [Reader.point(p, f"{where}[{i}]") for i, p in enumerate(Reader.lst(value, where))]

    @staticmethod
    def text(value: Any, where: str) -> str:
        return Reader.of_type(value, str, where, "a string")


@dataclass
class Env:
    """The validated environment: ``rings`` (outer CCW, holes CW), ``edges`` as (a, b) with their ring, in edge order."""

    rings: list[list[Point]]
    edges: list[tuple[Point, Point]]
    ring_of: list[int]

    @property
    def outer(self) -> list[Point]:
        return self.rings[0]

    @property
    def vertices(self) -> list[Point]:
        return [p for ring in self.rings for p in ring]

    def area2(self) -> Fraction:
        """Twice the area of the free space (outer minus holes), exactly."""
        total = Fraction(0)
        for ring in self.rings:
            n = len(ring)
            total += sum((cross(ring[i], ring[(i + 1) % n]) for i in range(n)), Fraction(0))
        return total

    def reflex(self) -> list[int]:
        """Vertex ids (over all rings, in edge order) whose interior angle exceeds π (a right turn)."""
        out, base = [], 0
        for ring in self.rings:
            n = len(ring)
            for i in range(n):
                if orient(ring[i - 1], ring[i], ring[(i + 1) % n]) < 0:
                    out.append(base + i)
            base += n
        return out

    def on_boundary(self, p: Point) -> bool:
        x, y = p
        return any(min(a[0], b[0]) <= x <= max(a[0], b[0]) and min(a[1], b[1]) <= y <= max(a[1], b[1])
                   and on_closed_segment(p, a, b) for a, b in self.edges)

    def on_wall(self, a: Point, b: Point) -> bool:
        """Does the segment ab lie on the boundary: covered by the edges on its line? A straight wall may be written
        as several collinear edges (vertices of angle π), and a side of a cell or a view may run along all of them."""
        d = sub(b, a)
        dd = dot(d, d)
        spans = []
        for u, w in self.edges:
            if orient(a, b, u) == 0 and orient(a, b, w) == 0:
                s, t = dot(sub(u, a), d) / dd, dot(sub(w, a), d) / dd
                spans.append((min(s, t), max(s, t)))
        return uncovered(Fraction(0), Fraction(1), spans) is None

    def locate(self, p: Point) -> int:
        """1 strictly inside the free space, 0 on the boundary, −1 outside (exact)."""
        if self.on_boundary(p):
            return 0
        if not _inside(p, self.rings[0]):
            return -1
        return -1 if any(_inside(p, hole) for hole in self.rings[1:]) else 1


def inside_open(p: Point, ring: list[Point]) -> bool:
    """Is p strictly inside the simple ring, or (when on it) wherever the crossing number puts it? Callers decide
    points on the ring first (exact crossing number)."""
    return _inside(p, ring)


def box(points) -> tuple[Fraction, Fraction, Fraction, Fraction]:
    """The bounding box (x_min, y_min, x_max, y_max) of exact points."""
    return (min(p[0] for p in points), min(p[1] for p in points), max(p[0] for p in points), max(p[1] for p in points))


def apart(s: tuple, t: tuple) -> bool:
    """Are two bounding boxes disjoint (so the exact tests between what they bound can be skipped)?"""
    return s[2] < t[0] or t[2] < s[0] or s[3] < t[1] or t[3] < s[1]


def param_on(a: Point, d: Point, v: Point) -> Fraction:
    """The parameter of v on the line a + s·d (v on that line, d ≠ 0)."""
    return (v[0] - a[0]) / d[0] if d[0] != 0 else (v[1] - a[1]) / d[1]


class ModelChecker:
    """What every model check shares: failures, counts, statements and the validated environment."""

    def __init__(self, cert: ModelCertificate, *, partial: bool = False) -> None:
        self.cert = cert
        self.partial = partial  # an answer file checked as claims: exact numbers it does not state are skipped
        self.failures: list[Failure] = []
        self.counts: dict[str, int] = {}
        self.not_checked: list[str] = []
        self.proved: list[str] = []
        self.summary: dict[str, Any] = {}
        self.scope = ""
        self.env: Env | None = None

    def fail(self, claim: str, message: str) -> None:
        self.failures.append(Failure(claim, message))

    def optional(self, obj: dict, key: str, where: str) -> Any:
        """``obj[key]``; when checking an answer (``partial``), ``None`` if the answer does not state it."""
        if self.partial and key not in obj:
            return None
        return Reader.field(obj, key, where)

    def count(self, name: str, k: int = 1) -> None:
        self.counts[name] = self.counts.get(name, 0) + k

    def check_environment(self) -> bool:
        inner = _Checker(self.cert)  # type: ignore[arg-type]  # it reads only the environment
        ok = inner.check_environment()
        self.failures.extend(inner.failures)
        if ok:
            rings = [list(r) for r in self.cert.environment.rings]
            edges: list[tuple[Point, Point]] = []
            ring_of: list[int] = []
            for r, ring in enumerate(rings):
                for i in range(len(ring)):
                    edges.append((ring[i], ring[(i + 1) % len(ring)]))
                    ring_of.append(r)
            self.env = Env(rings, edges, ring_of)
            self.count("edges", len(edges))
        return ok

    def report(self) -> CheckReport:
        valid = not self.failures
        return CheckReport(
            valid=valid,
            failures=tuple(self.failures),
            checked=tuple(self.counts.items()),
            not_checked=tuple(self.not_checked),
            kind=self.cert.kind,
            version=self.cert.version,
            environment=_environment_summary(self.cert.environment),
            start=None,
            goal=None,
            claims=dict(self.summary),
            proved=tuple(self.proved) if valid else (),
            scope=self.scope,
        )


def check_model_certificate(cert: ModelCertificate, *, expected_rings: Any = None, partial: bool = False) -> CheckReport:
    """Check a model certificate exactly (module docstring); ``expected_rings`` pins its environment. ``partial``:
    the claims are an answer file's (:func:`solverplan.certify.rooms_answer.check_rooms_answer`), which may leave exact numbers
    unstated (they are then listed as not checked); a certificate states them all."""
    from solverplan.certify.check_exploration import check as exploration
    from solverplan.certify.check_fields import check as fields
    from solverplan.certify.check_rooms import check as rooms
    from solverplan.certify.check_wallfollow import check_cut_ordering, check_pursuit

    checks: dict[str, Callable[[ModelChecker], None]] = {
        "rooms": rooms,
        "exploration": exploration,
        "cut-ordering": check_cut_ordering,
        "pursuit": check_pursuit,
        "fields": fields,
    }
    checker = ModelChecker(cert, partial=partial)
    if expected_rings is not None:
        inner = _Checker(cert)  # type: ignore[arg-type]
        inner.check_expected(expected_rings)
        checker.failures.extend(inner.failures)
    if checker.check_environment():
        try:
            checks[cert.kind](checker)
        except Malformed as exc:
            checker.fail(exc.claim, exc.message)
    return checker.report()


# ---------------------------------------------------------------------- shared exact geometry
def segment_crosses_open(p: Point, q: Point, a: Point, b: Point) -> bool:
    """Does the closed segment ab meet the open segment pq in a point other than p and q, *crossing* or *touching
    from one side* it (not merely lying along it)? Exact. Used to decide that nothing of the boundary lies on an
    open line of sight or door."""
    o1, o2 = orient(p, q, a), orient(p, q, b)
    if o1 == 0 and o2 == 0:
        return False  # collinear: handled by the caller (overlaps)
    o3, o4 = orient(a, b, p), orient(a, b, q)
    if o1 * o2 > 0 or o3 * o4 > 0:
        return False
    if o1 != 0 and o2 != 0 and o3 != 0 and o4 != 0:
        return True  # proper crossing
    for x in (a, b):  # an end of ab on the open pq
        if orient(p, q, x) == 0 and x not in (p, q) and on_closed_segment(x, p, q):
            return True
    # p or q on the open ab, or an end of ab at p or q: touching at an end of pq only
    return False


def text(x: Fraction | int) -> str:
    return number_text(Fraction(x))


def pt(p: Point) -> str:
    return f"({text(p[0])}, {text(p[1])})"


def area2(ring: list[Point]) -> Fraction:
    n = len(ring)
    return sum((cross(ring[i], ring[(i + 1) % n]) for i in range(n)), Fraction(0))


def dist2(p: Point, q: Point) -> Fraction:
    d = sub(p, q)
    return dot(d, d)
