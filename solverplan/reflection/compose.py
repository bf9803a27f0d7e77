"""Sequential composition of the cell fields, with the reflection zones of §III (Stager and Tanner).

:func:`compose_fields` builds the whole policy for a start and a goal point:

1. the convex cells (:func:`~solverplan.reflection.cells.decompose_free_space`) and the cell sequence from the
   start's cell to the goal's cell (shortest path in the adjacency graph);
2. for **every** cell that can reach the goal, an outlet — the facet to its next cell on a shortest path to the
   goal's cell (so a robot knocked off the sequence still converges) — and a field that provably flows through
   it (:mod:`~solverplan.reflection.fields`). Candidates, first verified wins: in ``arcs`` mode an arc field when
   inlet and outlet meet at a vertex (dense-sample check); the paper's line field from the inlet midpoint (the start
   point in the start cell, the vertex average off the sequence) to the outlet midpoint; the line field through the
   outlet midpoint along the outlet's outward normal. Each at the gain given, then 2×, ½×, 4×, ¼×, 8×, ⅛× of it;
   failing those, any line field found by a linear program over its offset and gain for 15 directions about the
   outlet's normal, then finer sweeps (:func:`~solverplan.reflection.fields.fit_line_field`, checked exactly);
   then the line from the vertex average to the outlet midpoint at ever smaller gains. A cell still without a
   field is cut into a triangle on its outlet and the rest (:func:`~solverplan.reflection.cells.cut_at_sides`)
   and the composition starts again (at worst the cells become triangles, where the last candidate works);
3. the goal cell's field, straight to the goal;
4. the reflection zones of the candidate cells of the sequence (:mod:`~solverplan.reflection.zones`).

Convergence. Every cell's nominal field flows through its outlet into a cell one step closer (in the shortest-path
tree) to the goal's cell, whose field ends at the goal: by induction every start converges (sequential composition).
The hybrid controller of a reflection cell runs the reflection field until the robot hits a wall, then the nominal
field; it is armed at most once per cell and run (the first entry), so after finitely many switches only nominal
fields act and the argument above applies unchanged. ``flow_through`` is true when every cell's field was verified.

>>> import solverplan as sp
>>> plan = compose_fields(sp.load_environment("serpentine"), (3, "2.25"), (3, "0.25"))
>>> plan.sequence, plan.reflection_cells, plan.flow_through
((4, 2, 1, 0, 3, 7, 6, 5, 8), (2, 0, 7, 5), True)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, exact_point, format_number, to_fraction
from solverplan.reflection.cells import Cell, CellDecomposition, cut_at_sides, decompose_free_space
from solverplan.reflection.fields import (Field, FlowCheck, GoalField, LineField, arc_turn, fit_line_field,
                                          flows_through)
from solverplan.reflection.zones import ReflectionZone, RejectedZone, select_zone_recorded

__all__ = ["CellPolicy", "FieldPlan", "compose_fields", "field_kinds", "GAIN_STEPS", "mean_width", "default_gains",
           "resolve_gains", "REFERENCE_WIDTH"]

#: Multiples of the given gain tried, in order, until a field verifies.
GAIN_STEPS = (Fraction(1), Fraction(2), Fraction(1, 2), Fraction(4), Fraction(1, 4), Fraction(8), Fraction(1, 8))

REFERENCE_WIDTH = Fraction("0.4422")
"""The mean width (:func:`mean_width`) of the shipped ``serpentine``, the corridor the default gains (3 and 1, the
default robot's goal radius 0.1) were tuned for: defaults scale with an environment's mean width against it."""


def mean_width(env: Environment) -> Fraction:
    """The environment's mean width 2A/P (area over half the perimeter of all its rings: the width of a long
    corridor), rounded to 4 significant digits as an exact decimal, so that it scales exactly with decimal
    coordinates and does not depend on how the walls are written. The length unit of the fields' defaults.

    Examples
    --------
    >>> import solverplan as sp
    >>> mean_width(sp.load_environment("square")), mean_width(sp.load_environment("serpentine")) == REFERENCE_WIDTH
    (Fraction(5, 1), True)
    """
    width = 2 * float(env.area) / env.perimeter
    return Fraction(f"{width:.4g}")


def default_gains(env: Environment) -> tuple[Fraction, Fraction]:
    """The default gains (line, arc) of ``env``, 1/length: 3 and 1 in a corridor as wide as the shipped
    ``serpentine``'s, inversely proportional to the mean width (:func:`mean_width`) elsewhere, so that p·w — what
    decides whether a field flows through — does not depend on the scale of the coordinates.

    Examples
    --------
    >>> import solverplan as sp
    >>> default_gains(sp.load_environment("serpentine"))
    (Fraction(3, 1), Fraction(1, 1))
    >>> default_gains(sp.load_environment("square"))          # mean width 5
    (Fraction(6633, 25000), Fraction(2211, 25000))
    """
    w = mean_width(env)
    return 3 * REFERENCE_WIDTH / w, REFERENCE_WIDTH / w


@dataclass(frozen=True, slots=True)
class CellPolicy:
    """A cell's nominal field, where it leads (``outlet_side``/``next_cell``; ``None`` in the goal cell), its
    ``inlet_side`` on the sequence (``None`` off it and in the start cell) and its flow-through ``check``."""

    cell: int
    field: Field
    check: FlowCheck
    next_cell: int | None
    outlet_side: int | None
    inlet_side: int | None

    def to_json(self) -> dict:
        return {"cell": self.cell, "next": self.next_cell, "inlet_side": self.inlet_side,
                "outlet_side": self.outlet_side, "field": self.field.to_json(), "flow": self.check.to_json()}


@dataclass(frozen=True)
class FieldPlan:
    """The composed policy: cells, sequence, one :class:`CellPolicy` per cell that reaches the goal (``policies``,
    by cell id) and the reflection zones (``zones``, by cell id)."""

    decomposition: CellDecomposition
    start: ExactPoint
    goal: ExactPoint
    sequence: tuple[int, ...]
    policies: dict[int, CellPolicy]
    zones: dict[int, ReflectionZone]
    rejected: tuple[RejectedZone, ...] = ()

    def without_zones(self, cells: Sequence[int], rejected: Sequence[RejectedZone] = ()) -> FieldPlan:
        """The plan with the reflection zones of ``cells`` dropped and ``rejected`` added to the record."""
        drop = set(cells)
        return FieldPlan(self.decomposition, self.start, self.goal, self.sequence, self.policies,
                         {c: z for c, z in self.zones.items() if c not in drop}, self.rejected + tuple(rejected))

    def export(self) -> dict:
        """The composed field for a controller (``solverplan fields --export``): for every cell its half-planes
        (exact inward normals n and offsets n·a; q is in the cell iff n·q ≥ offset for all), its nominal field, the
        next cell, and the reflection zone's field and wall when one is planned. Command u = s·v(q)/|v(q)| with
        the cell's field v (line: v = d + p(I − ddᵀ)(q₀ − q); goal: towards the goal; arc: as in the field's
        record) and s the speed; in a reflection cell use the zone's field from the first entry until a wall is
        hit, then the nominal one (once per cell and run)."""
        cells = []
        for cell in self.cells:
            policy = self.policies.get(cell.id)
            zone = self.zones.get(cell.id)
            cells.append({
                "id": cell.id,
                "polygon": [[float(x), float(y)] for x, y in cell.vertices],
                "halfplanes": [{"normal": [float(sd.normal[0]), float(sd.normal[1])],
                                "offset": float(sd.normal[0] * sd.a[0] + sd.normal[1] * sd.a[1]),
                                "normal_exact": [format_number(sd.normal[0]), format_number(sd.normal[1])],
                                "offset_exact": format_number(sd.normal[0] * sd.a[0] + sd.normal[1] * sd.a[1]),
                                "neighbour": sd.neighbour} for sd in cell.sides],
                "field": None if policy is None else policy.field.to_json(),
                "max_speed": None if policy is None else _max_speed(policy.field, cell),
                "next": None if policy is None else policy.next_cell,
                "reflection": None if zone is None else {"side": zone.side, "field": zone.field.to_json(),
                                                          "max_speed": zone.field.max_speed(cell)},
            })
        return {"format": "solverplan composed field 1", "start": [float(c) for c in self.start],
                "goal": [float(c) for c in self.goal], "sequence": list(self.sequence),
                "command": "u = speed * v / |v|; reflection field from the first entry into a reflection cell until a "
                           "wall is hit, then the nominal field", "cells": cells}

    @property
    def env(self) -> Environment:
        return self.decomposition.env

    @property
    def cells(self) -> tuple[Cell, ...]:
        return self.decomposition.cells

    @property
    def reflection_cells(self) -> tuple[int, ...]:
        """The cells of the sequence with a reflection zone, in sequence order."""
        return tuple(c for c in self.sequence if c in self.zones)

    @property
    def flow_through(self) -> bool:
        """Every cell's nominal field is verified to flow through (the composition converges)."""
        return all(p.check.valid for p in self.policies.values())

    @property
    def proved(self) -> bool:
        """Verified exactly (no dense-sample check among the fields)."""
        return self.flow_through and all(p.check.method == "exact" for p in self.policies.values())

    @property
    def goal_cell(self) -> int:
        return self.sequence[-1]


def _max_speed(field: Field, cell: Cell) -> float:
    """The largest |v| of ``field`` over ``cell`` (sampled at the vertices and the vertex average)."""
    import numpy as np

    points = np.vstack([cell.float_vertices, cell.float_vertices.mean(axis=0)])
    return float(np.hypot(*field.velocity(points).T).max())


def _vertex_average(cell: Cell) -> ExactPoint:
    n = len(cell.vertices)
    return (sum((v[0] for v in cell.vertices), Fraction(0)) / n, sum((v[1] for v in cell.vertices), Fraction(0)) / n)


def _nominal(cell: Cell, origin: ExactPoint, inlet: int | None, outlet: int, gain_line: Fraction,
             gain_arc: Fraction, arcs: bool) -> tuple[Field, FlowCheck]:
    exits = frozenset({outlet})
    out_side = cell.sides[outlet]
    mid = out_side.midpoint
    normal_target = (mid[0] - out_side.normal[0], mid[1] - out_side.normal[1])  # outward through the outlet
    makers: list = []
    if arcs and inlet is not None and arc_turn(cell, inlet, outlet, gain_arc) is not None:
        makers.append(lambda g: arc_turn(cell, inlet, outlet, gain_arc * g))
    if origin != mid:
        makers.append(lambda g: LineField(origin, mid, gain_line * g))
    makers.append(lambda g: LineField(mid, normal_target, gain_line * g))
    first: tuple[Field, FlowCheck] | None = None
    for make in makers:
        for step in GAIN_STEPS:
            field = make(step)
            check = flows_through(field, cell, exits)
            if check.valid:
                return field, check
            first = first or (field, check)
    fitted = fit_line_field(cell, exits)  # any line (direction, offset, gain) that works: an LP per direction
    if fitted is not None:
        return fitted
    average = _vertex_average(cell)  # in a triangle the median to the outlet, bent ever more gently, works
    for k in range(3, 40, 3):
        field = LineField(average, mid, gain_line / 2**k)
        check = flows_through(field, cell, exits)
        if check.valid:
            return field, check
    assert first is not None
    return first


def resolve_gains(env: Environment, gain_line: object, gain_arc: object) -> tuple[Fraction, Fraction]:
    """The gains (line, arc) as given (read exactly), or :func:`default_gains` for those given as ``None``."""
    line, arc = default_gains(env)
    return (line if gain_line is None else to_fraction(gain_line, where="gain_line"),
            arc if gain_arc is None else to_fraction(gain_arc, where="gain_arc"))


def _policies(dec: CellDecomposition, s: ExactPoint, g: ExactPoint, p_line: Fraction, p_arc: Fraction,
              arcs: bool) -> tuple[tuple[int, ...], dict[int, CellPolicy]]:
    """The cell sequence from ``s``'s cell to ``g``'s and every cell's policy (its verdict may be a failure)."""
    start_cell = dec.locate(s, where="start")
    goal_cell = dec.locate(g, where="goal")
    sequence = dec.sequence(start_cell, goal_cell)
    successors = dec.successors(goal_cell)
    inlets = {c: dec.cells[c].facet_to(prev) for prev, c in zip(sequence, sequence[1:])}
    policies: dict[int, CellPolicy] = {}
    for cell in dec.cells:
        nxt = successors[cell.id]
        if cell.id == goal_cell:
            goal_field = GoalField(g)
            policies[cell.id] = CellPolicy(cell.id, goal_field, flows_through(goal_field, cell, frozenset()), None,
                                           None, inlets.get(cell.id))
            continue
        if nxt is None:
            continue  # cannot reach the goal (another component): no policy
        outlet = cell.facet_to(nxt)
        on_sequence = cell.id in sequence and sequence.index(cell.id) < len(sequence) - 1 and \
            sequence[sequence.index(cell.id) + 1] == nxt
        inlet = inlets.get(cell.id) if on_sequence else None
        if cell.id == start_cell:
            origin = s
        elif inlet is not None:
            origin = cell.sides[inlet].midpoint
        else:
            origin = _vertex_average(cell)
        field, check = _nominal(cell, origin, inlet, outlet, p_line, p_arc, arcs)
        policies[cell.id] = CellPolicy(cell.id, field, check, nxt, outlet, inlet)
    return sequence, policies


def compose_fields(env: Environment, start: Sequence[object], goal: Sequence[object], *,
                   gain_line: object = None, gain_arc: object = None, arcs: bool = False,
                   reflection: bool = True, decomposition: CellDecomposition | None = None,
                   cells: str = "convex") -> FieldPlan:
    """The composed field policy from ``start`` to ``goal`` (points of the open free space, exact or decimal).

    Parameters
    ----------
    env
        The environment.
    start, goal
        Points (x, y); read exactly (``"0.1"`` is 1/10).
    gain_line, gain_arc
        The gains p of line and arc fields (1/length of the environment's units). The paper's 0.3 and 0.03 are for
        its (unstated) workspace units. ``None`` (default): :func:`default_gains`, 3 and 1 in corridors as wide as
        the shipped ``serpentine``'s (mean width 0.4422), inversely proportional to the mean width elsewhere, so
        the composition of a scaled environment is the scaled composition.
    arcs
        Try an arc field in cells whose inlet and outlet meet at a vertex (the paper's "linear/arc" configuration).
    reflection
        Select the reflection zones of the sequence's candidate cells.
    decomposition
        Reuse a decomposition of ``env``.
    cells
        ``convex`` or ``corners`` (:func:`~solverplan.reflection.cells.decompose_free_space`): with ``corners``
        the turns of corridors get corner cells, the reflection candidates.

    Returns
    -------
    FieldPlan
        The cells, the cell sequence from the start's cell to the goal's, one verified field per cell of the
        sequence (``policies``, by cell id; ``flow_through`` says every line field carries its cell into its
        outlet, checked exactly) and the reflection zones (``zones``).

    Raises
    ------
    InputError
        A point outside the free space or on a wall, a non-positive gain, or a goal that cannot be reached.

    Examples
    --------
    >>> import solverplan as sp
    >>> plan = compose_fields(sp.load_environment("l_shape"), (8, 2), (2, 8))
    >>> plan.sequence, sorted(plan.policies), plan.policies[plan.goal_cell].field.kind
    ((0, 1), [0, 1], 'goal')
    """
    dec = decomposition or decompose_free_space(env, cells)
    p_line, p_arc = resolve_gains(env, gain_line, gain_arc)
    if p_line <= 0 or p_arc <= 0:
        raise InputError(f"gains must be positive, got line {p_line} and arc {p_arc}")
    s = exact_point(start, where="start")
    g = exact_point(goal, where="goal")
    while True:  # cut cells no line field leaves through their outlets, down to triangles at worst
        sequence, policies = _policies(dec, s, g, p_line, p_arc, arcs)
        stuck = {c: p.outlet_side for c, p in policies.items()
                 if not p.check.valid and p.outlet_side is not None and len(dec.cells[c].vertices) > 3}
        if not stuck:
            break
        dec = cut_at_sides(dec, stuck)
    zones: dict[int, ReflectionZone] = {}
    rejected: list[RejectedZone] = []
    if reflection:
        for k in range(1, len(sequence) - 1):
            c = sequence[k]
            policy = policies[c]
            if policy.inlet_side is None or policy.outlet_side is None:
                continue
            zone, passed_over = select_zone_recorded(dec.cells[c], policy.inlet_side, policy.outlet_side,
                                                     tuple(p_line * step for step in GAIN_STEPS))
            rejected.extend(passed_over)
            if zone is not None:
                zones[c] = zone
    return FieldPlan(dec, s, g, sequence, policies, zones, tuple(rejected))


def field_kinds(plan: FieldPlan) -> dict[int, str]:
    """The kind of each cell's nominal field (``line``, ``arc``, ``goal``)."""
    return {c: p.field.kind for c, p in plan.policies.items()}

