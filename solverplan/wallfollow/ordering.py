"""The cut ordering: the cyclic order of vertices and cut end points along the boundary (§V-A of the paper).

With n vertices, m of them reflex, the set M holds the n vertices and the 2m cut end points (ℓ_i, r_i for
each reflex v_i, see :mod:`solverplan.wallfollow.cut`). The **cut ordering** is M in counter-clockwise order
along the boundary. It is written as a list of names — ``vK`` vertex K, ``lK`` / ``rK`` the end point of the
left / right cut of reflex vertex K — starting at ``v0``; vertices appear as v0, v1, …, v_{n−1} in that order,
and every reflex vertex K has exactly one ``lK`` and one ``rK``.

The vertex numbering is arbitrary (any vertex may be called v0): two orderings are **equivalent** when one
becomes the other by renaming v_k as v_{k+s} (mod n) for one shift s. :meth:`CutOrdering.canonical` picks the
lexicographically least of the n renamings, so equivalent orderings have equal canonical forms.

A cut is a chord between its vertex and its end point. **Prop. 4**: two cuts whose four end points are
distinct cross (in the interior of the polygon) exactly when their end points alternate along the boundary —
:meth:`CutOrdering.cuts_cross` decides it from the ordering alone.

>>> order = CutOrdering.from_labels(["v0", "v1", "v2", "l4", "r1", "v3", "v4", "v5", "l1", "r4"])
>>> order.n, order.reflex
(6, (1, 4))
>>> order.relabel(-2).labels             # v2 renamed v0 and so on: the paper's Eqs. (12) and (13)
('v0', 'l2', 'r5', 'v1', 'v2', 'v3', 'l5', 'r2', 'v4', 'v5')
>>> order.equivalent(order.relabel(-2)), order.cuts_cross("l1", "r4"), order.cuts_cross("l1", "l4")
(True, True, False)
"""

from __future__ import annotations

import re
from dataclasses import field
from typing import Any, Iterable, Sequence

from solverplan.errors import InputError
from solverplan.result import Construction, EnvironmentRecord, Method, Optimality, Reader, Stats, answer_dataclass

__all__ = ["CutOrdering", "parse_label"]

_LABEL = re.compile(r"([vlr])(0|[1-9][0-9]*)")
_KIND_RANK = {"v": 0, "l": 1, "r": 2}


def parse_label(label: str) -> tuple[str, int]:
    """``"l4"`` → ``("l", 4)``; raises :class:`~solverplan.errors.InputError` for anything else."""
    match = _LABEL.fullmatch(label) if isinstance(label, str) else None
    if match is None:
        raise InputError(f"cut ordering: {label!r} is not a point name (vK, lK or rK with K a vertex number)")
    return match.group(1), int(match.group(2))


@answer_dataclass("cut-ordering")
class CutOrdering(Construction):
    """A cut ordering, as names in counter-clockwise order starting at ``v0`` (module docstring).

    Build one with :meth:`from_labels` (validated) or :func:`solverplan.wallfollow.cut_ordering` (from a
    polygon). It is also an answer of the result protocol: ``status``, ``optimality``, ``stats``,
    ``environment``, ``to_json()``, ``to_text()``.

    Attributes
    ----------
    labels
        The names of the n + 2m points, ``labels[0] == "v0"``.
    environment
        The environment it was computed in, when it was (``None`` for a learned or hand-written ordering).
    optimality
        How it was obtained; the default claims nothing.
    stats
        Counts of the computation that made it.

    Examples
    --------
    >>> import solverplan as sp
    >>> ordering = sp.cut_ordering(sp.load_environment("l_shape"))
    >>> ordering.labels, ordering.status.value, ordering.optimality.proved
    (('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3'), 'found', True)
    >>> sp.CutOrdering.from_labels(ordering.labels) == sp.CutOrdering(ordering.labels)   # validated, by hand
    True
    """

    labels: tuple[str, ...]
    environment: EnvironmentRecord | None = None
    optimality: Optimality = field(default_factory=lambda: Optimality(Method.NONE, False, None))
    stats: Stats = field(default_factory=Stats)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_labels(cls, labels: Iterable[str], **fields: Any) -> CutOrdering:
        """Validate names in cyclic counter-clockwise order (any starting point) and rotate them to start at v0.

        Raises
        ------
        InputError
            For a malformed name, a repeated point, vertices out of order, a missing vertex, or a reflex vertex
            without exactly its two cut end points.
        """
        items = list(labels)
        parsed = [parse_label(x) for x in items]
        if len(set(items)) != len(items):
            dup = next(x for x in items if items.count(x) > 1)
            raise InputError(f"cut ordering: {dup} appears more than once")
        vertices = [k for kind, k in parsed if kind == "v"]
        n = len(vertices)
        if n < 3 or sorted(vertices) != list(range(n)):
            raise InputError(f"cut ordering: the vertices must be v0 .. v{max(n - 1, 0)} with none missing "
                             f"(got {n} vertices{'' if n >= 3 else ', at least 3 needed'})")
        start = items.index("v0")
        items = items[start:] + items[:start]
        order = [k for kind, k in (parse_label(x) for x in items) if kind == "v"]
        if order != list(range(n)):
            raise InputError("cut ordering: the vertices must appear as v0, v1, v2, ... counter-clockwise")
        ends = {(kind, k) for kind, k in parsed if kind != "v"}
        for kind, k in ends:
            if k >= n:
                raise InputError(f"cut ordering: {kind}{k} names vertex {k}, but there are {n} vertices")
            other = "r" if kind == "l" else "l"
            if (other, k) not in ends:
                raise InputError(f"cut ordering: {kind}{k} without {other}{k} (a reflex vertex has both cuts)")
        return cls(tuple(items), **fields)

    # ------------------------------------------------------------------ structure
    @property
    def n(self) -> int:
        """Number of vertices."""
        return sum(1 for x in self.labels if x[0] == "v")

    @property
    def reflex(self) -> tuple[int, ...]:
        """The reflex vertices (those with cuts), ascending."""
        return tuple(sorted(k for kind, k in map(parse_label, self.labels) if kind == "l"))

    def index(self, label: str) -> int:
        """Position of ``label`` in :attr:`labels`; :class:`~solverplan.errors.InputError` if it is not there."""
        try:
            return self.labels.index(label)
        except ValueError:
            raise InputError(f"cut ordering has no point {label!r}") from None

    def edge_of(self, label: str) -> int:
        """The edge a point lies on: the last vertex at or before it (a vertex K lies at the start of edge K)."""
        i = self.index(label)
        while self.labels[i][0] != "v":
            i -= 1
        return parse_label(self.labels[i])[1]

    def between(self, start: str, end: str, label: str) -> bool:
        """Does ``label`` lie in the open counter-clockwise interval (start, end) of the boundary?"""
        a, b, x = self.index(start), self.index(end), self.index(label)
        size = len(self.labels)
        return 0 < (x - a) % size < (b - a) % size

    def cuts_cross(self, first: str, second: str) -> bool:
        """Prop. 4: do the cuts ending at ``first`` and ``second`` (``"l3"``, ``"r5"``) cross?

        Two cuts with four distinct end points cross iff the end points alternate along the boundary. The two
        cuts of one vertex share that vertex and do not cross (False).
        """
        (k1, i), (k2, j) = parse_label(first), parse_label(second)
        if k1 == "v" or k2 == "v":
            raise InputError(f"cuts_cross takes cut end points (lK or rK), got {first!r} and {second!r}")
        if i == j:
            return False
        a, b = f"v{i}", first
        return self.between(a, b, f"v{j}") != self.between(a, b, second)

    # ------------------------------------------------------------------ relabelling
    def relabel(self, shift: int) -> CutOrdering:
        """Rename vertex k as k + ``shift`` (mod n), cut names with it, and start again at v0."""
        n = self.n
        renamed = [f"{kind}{(k + shift) % n}" for kind, k in map(parse_label, self.labels)]
        start = renamed.index("v0")
        return CutOrdering(tuple(renamed[start:] + renamed[:start]), self.environment, self.optimality, self.stats)

    def _key(self) -> tuple[tuple[int, int], ...]:
        return tuple((_KIND_RANK[kind], k) for kind, k in map(parse_label, self.labels))

    def canonical(self) -> CutOrdering:
        """The lexicographically least renaming (kinds ordered v < l < r, then by number): equal for equivalent
        orderings."""
        return min((self.relabel(s) for s in range(self.n)), key=CutOrdering._key)

    def equivalent(self, other: CutOrdering | Sequence[str]) -> bool:
        """Are the two orderings the same up to renaming the vertices (a cyclic shift of their numbers)?"""
        if not isinstance(other, CutOrdering):
            other = CutOrdering.from_labels(other)
        return self.n == other.n and self.canonical().labels == other.canonical().labels

    # ------------------------------------------------------------------ result protocol

    def _fields(self) -> dict:
        return {"cut_ordering": list(self.labels), "n": self.n, "reflex": list(self.reflex)}

    @classmethod
    def from_json(cls, data: Any, *, env: Any = None) -> CutOrdering:
        """Read a cut ordering answer back (validated by :meth:`from_labels`; ``env`` is not needed)."""
        r = Reader(data, "cut_ordering")
        return cls.from_labels(r.texts("cut_ordering"), environment=r.environment(), optimality=r.optimality(),
                               stats=r.stats())

    def to_text(self, *, width: int = 100) -> str:
        head = f"cut ordering: {self.n} vertices, {len(self.reflex)} reflex ({len(self.labels)} points)"
        lines, line = [head], " "
        for i, label in enumerate(self.labels):
            piece = f" {label}" + ("," if i + 1 < len(self.labels) else "")
            if len(line) + len(piece) > width:
                lines.append(line)
                line = " "
            line += piece
        lines.append(line)
        return "\n".join(lines) + "\n"
