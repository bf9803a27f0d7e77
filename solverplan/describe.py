"""A description of an environment: what ``solverplan info`` answers (docs/contract.md).

:func:`describe_environment` gathers the facts — vertices in global numbering, rings, directed
edges, reflex vertices, exact area, perimeter, and notes on how the input was normalised — into
an :class:`EnvironmentInfo`. Its :meth:`~EnvironmentInfo.to_json` is the only place they become
a dict; :meth:`~EnvironmentInfo.to_text` renders readable tables for a person.

Exact numbers travel as JSON numbers when their decimal text is exact (``3``, ``0.25``) and as
strings otherwise (``"1/3"``, or a decimal with more digits than a float keeps), so a script
reading the answer with ``parse_float=Decimal`` gets the exact input coordinates back.

>>> env = Environment.from_coords([[0, 0], [0, 3], [3, 3], [3, 0]], [[[1, 1], [2, 1], [1, 2]]], name="demo")
>>> info = describe_environment(env)
>>> info.notes
('outer ring was clockwise: vertex order reversed', 'hole 0 was counter-clockwise: vertex order reversed')
>>> data = info.to_json()
>>> data["vertices"][0]
[[0, 0], [3, 0], [3, 3], [0, 3]]
>>> data["rings"][1]
{'index': 1, 'kind': 'hole', 'vertices': [4, 5, 6], 'reoriented': True}
>>> data["edges"][4]
{'id': 4, 'ring': 1, 'vertices': [4, 5], 'a': [1, 1], 'b': [1, 2], 'length': 1.0}
>>> data["reflex"], data["area"], data["area_exact"]
([4, 5, 6], 8.5, '8.5')
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

from solverplan.environment import Environment
from solverplan.exact import ExactPoint, format_number, json_point

__all__ = [
    "EdgeInfo",
    "EnvironmentInfo",
    "RingInfo",
    "describe_environment",
]


@dataclass(frozen=True, slots=True)
class RingInfo:
    """One ring of the normalised environment.

    ``vertices`` are global vertex ids in boundary order (free space on the left);
    ``reoriented`` says whether the input listed this ring in the opposite orientation.
    """

    index: int
    kind: Literal["outer", "hole"]
    vertices: tuple[int, ...]
    reoriented: bool

    def to_json(self) -> dict:
        return {"index": self.index, "kind": self.kind, "vertices": list(self.vertices), "reoriented": self.reoriented}


@dataclass(frozen=True, slots=True)
class EdgeInfo:
    """Directed edge ``id`` of ring ``ring``, from vertex ``tail`` at ``a`` to vertex ``head`` at ``b``.

    ``length`` is the Euclidean length (float; generally irrational).
    """

    id: int
    ring: int
    tail: int
    head: int
    a: ExactPoint
    b: ExactPoint
    length: float

    def to_json(self) -> dict:
        return {
            "id": self.id,
            "ring": self.ring,
            "vertices": [self.tail, self.head],
            "a": json_point(self.a),
            "b": json_point(self.b),
            "length": self.length,
        }


@dataclass(frozen=True, slots=True)
class EnvironmentInfo:
    """Facts about a normalised environment, as ``solverplan info`` reports them.

    Attributes
    ----------
    name
        The environment's name (the file's stem when the file gives none).
    points
        Every vertex, exact, in global numbering (vertex ``i`` starts edge ``i``).
    rings, edges
        See :class:`RingInfo` and :class:`EdgeInfo`.
    reflex
        Global ids of the vertices whose free-space angle exceeds π (convex corners of holes count).
    area
        Exact area of the free space (outer ring minus holes).
    perimeter
        Total length of all rings (float).
    bounds
        ``(xmin, ymin, xmax, ymax)`` of the outer ring (floats).
    notes
        How the input was changed on load, e.g. ``outer ring was clockwise: vertex order reversed``.
    """

    name: str
    points: tuple[ExactPoint, ...]
    rings: tuple[RingInfo, ...]
    edges: tuple[EdgeInfo, ...]
    reflex: tuple[int, ...]
    area: Fraction
    perimeter: float
    bounds: tuple[float, float, float, float]
    notes: tuple[str, ...]

    def to_json(self) -> dict:
        """The answer as a JSON-ready dict (field names of docs/contract.md)."""
        return {
            "name": self.name,
            "n_vertices": len(self.points),
            "n_edges": len(self.edges),
            "n_holes": len(self.rings) - 1,
            "notes": list(self.notes),
            "vertices": [[json_point(self.points[v]) for v in ring.vertices] for ring in self.rings],
            "rings": [ring.to_json() for ring in self.rings],
            "edges": [edge.to_json() for edge in self.edges],
            "reflex": list(self.reflex),
            "area": float(self.area),
            "area_exact": format_number(self.area),
            "perimeter": self.perimeter,
            "bounds": list(self.bounds),
        }

    def to_text(self, *, width: int = 100) -> str:
        """Readable tables (summary, notes, rings, vertices, edges) as plain text ``width`` columns wide."""
        from rich import box
        from rich.console import Console
        from rich.table import Table

        buffer = io.StringIO()
        console = Console(file=buffer, width=width, color_system=None, force_terminal=False, highlight=False)

        console.print(f"environment {self.name!r}")
        summary = Table(box=box.SIMPLE, show_header=False)
        summary.add_column("field", style="bold")
        summary.add_column("value")
        summary.add_row("vertices", str(len(self.points)))
        summary.add_row("edges", str(len(self.edges)))
        summary.add_row("holes", str(len(self.rings) - 1))
        summary.add_row("reflex", ", ".join(map(str, self.reflex)) or "none")
        area_text = format_number(self.area)
        if area_text != _short_float(float(self.area)):
            area_text += f" ≈ {_short_float(float(self.area))}"
        summary.add_row("area", area_text)
        summary.add_row("perimeter", _short_float(self.perimeter))
        xmin, ymin, xmax, ymax = self.bounds
        summary.add_row("bounds", f"x ∈ [{_short_float(xmin)}, {_short_float(xmax)}], y ∈ [{_short_float(ymin)}, {_short_float(ymax)}]")
        for note in self.notes:
            summary.add_row("note", note)
        console.print(summary)

        console.print("rings (free space on the left of every edge)")
        rings = Table(box=box.SIMPLE_HEAD)
        for column in ("ring", "kind", "vertices", "reoriented"):
            rings.add_column(column, justify="right" if column == "ring" else "left")
        for ring in self.rings:
            rings.add_row(str(ring.index), ring.kind, _id_range(ring.vertices), "yes" if ring.reoriented else "no")
        console.print(rings)

        reflex = set(self.reflex)
        ring_of = {v: ring.index for ring in self.rings for v in ring.vertices}
        console.print("vertices")
        vertices = Table(box=box.SIMPLE_HEAD)
        for column in ("id", "ring", "x", "y", "reflex"):
            vertices.add_column(column, justify="left" if column == "reflex" else "right")
        for v, (x, y) in enumerate(self.points):
            vertices.add_row(str(v), str(ring_of[v]), format_number(x), format_number(y), "reflex" if v in reflex else "")
        console.print(vertices)

        console.print("edges (edge i goes from vertex i to the next vertex of its ring)")
        edges = Table(box=box.SIMPLE_HEAD)
        for column in ("id", "ring", "from", "to", "a", "b", "length"):
            edges.add_column(column, justify="left" if column in ("a", "b") else "right")
        for e in self.edges:
            edges.add_row(
                str(e.id), str(e.ring), str(e.tail), str(e.head), _point_text(e.a), _point_text(e.b), _short_float(e.length)
            )
        console.print(edges)
        return "\n".join(line.rstrip() for line in buffer.getvalue().rstrip().splitlines()) + "\n"


def _short_float(x: float) -> str:
    """A float for people: integers without ``.0``, otherwise up to 6 significant digits."""
    if math.isfinite(x) and x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return f"{x:.6g}"


def _point_text(p: ExactPoint) -> str:
    return f"({format_number(p[0])}, {format_number(p[1])})"


def _id_range(ids: tuple[int, ...]) -> str:
    """``4..7`` for consecutive ids (always the case for rings), else a comma list."""
    if len(ids) > 2 and list(ids) == list(range(ids[0], ids[0] + len(ids))):
        return f"{ids[0]}..{ids[-1]}"
    return ", ".join(map(str, ids))


def describe_environment(env: Environment) -> EnvironmentInfo:
    """Gather the facts ``solverplan info`` reports about ``env`` (see :class:`EnvironmentInfo`)."""
    offsets = env.ring_offsets
    rings = tuple(
        RingInfo(
            index=k,
            kind="outer" if k == 0 else "hole",
            vertices=tuple(range(offsets[k], offsets[k + 1])),
            reoriented=bool(env.reoriented[k]),
        )
        for k in range(len(env.rings))
    )
    points = env.exact_vertices
    nxt = env.next_vertex
    lengths = env.edge_lengths
    edges = tuple(
        EdgeInfo(
            id=i,
            ring=int(env.ring_of[i]),
            tail=i,
            head=int(nxt[i]),
            a=points[i],
            b=points[int(nxt[i])],
            length=float(lengths[i]),
        )
        for i in range(env.n_edges)
    )
    notes = []
    for ring in rings:
        if ring.reoriented:
            if ring.kind == "outer":
                notes.append("outer ring was clockwise: vertex order reversed")
            else:
                notes.append(f"hole {ring.index - 1} was counter-clockwise: vertex order reversed")
    return EnvironmentInfo(
        name=env.name,
        points=points,
        rings=rings,
        edges=edges,
        reflex=tuple(int(v) for v in env.reflex_vertices),
        area=env.area,
        perimeter=float(env.perimeter),
        bounds=tuple(float(b) for b in env.bounds),  # type: ignore[arg-type]
        notes=tuple(notes),
    )
