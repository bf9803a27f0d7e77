"""Local vector fields in convex cells and the flow-through verifier (Stager and Tanner, §II, Eq. 2 and 3).

**Line field (Eq. 2).** A point q₀, a unit direction d and a gain p (1/length):

    v(q) = d + p (I − d dᵀ)(q₀ − q)

Along the line q₀ + s d the field is d; across it the error e = d^⊥·(q − q₀) obeys ė = −p e (it decays as e^{−pt});
d·v = 1 everywhere, so a robot following v advances at unit rate along d; and v = −∇φ with
φ(q) = −d·(q − q₀) + (p/2)‖(I − d dᵀ)(q − q₀)‖². These are proved in ``solverplan.proofs.line_field``. Here d is
the unit vector of an exact rational vector w = target − q₀, so d = w/|w| is irrational in general.

**Arc field (Eq. 3, missing from the paper's text).** We use, with centre c, radius r, gain p and c_w = +1 for
clockwise (the paper's convention), ρ = |q − c|, r̂ = (q − c)/ρ and t̂ the clockwise unit tangent (r̂ rotated by
−π/2):

    v(q) = c_w t̂ + p (r − ρ) r̂

so ρ̇ = p (r − ρ) (the radial error decays as e^{−pt}) and the robot turns about c at unit speed along the arc.

**Goal field.** In the goal's cell, v = (g − q)/|g − q|: the straight line to g stays in the convex cell.

**Flow-through.** A field *flows through* a cell towards a set of exit sides when every trajectory from every point
of the closed cell leaves it through an exit side in finite time. For a line field this is decided exactly
(:func:`line_flows_through`): n_i·v is affine along side i, so it is positive on the whole closed side iff it is
positive at both end points, and with v strictly inward on every other side no trajectory can cross them, while
d·v = 1 makes every trajectory leave the bounded cell. The sign of n_i·v at a vertex is that of A√L + B with A, B,
L rational (L = |w|²), decided exactly. Other fields are checked by a dense sample (:func:`dense_flows_through`):
trajectories from a grid of the cell and points on its sides, integrated with RK4, must all leave through an exit.

>>> from fractions import Fraction as F
>>> f = LineField((F(0), F(0)), (F(1), F(0)), F(1, 2))
>>> f.velocity(np.array([[0.0, 2.0]])).tolist()
[[1.0, -1.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

import numpy as np

from solverplan.errors import InputError
from solverplan.exact import ExactPoint, format_number
from solverplan.limits import quote
from solverplan.reflection.cells import Cell
from solverplan.verdict import Failure, Verdict

__all__ = ["LineField", "ArcField", "GoalField", "Field", "FlowCheck", "line_flows_through", "dense_flows_through", "fit_line_field",
           "flows_through"]


def _f(p: Sequence[Fraction]) -> np.ndarray:
    return np.array([float(p[0]), float(p[1])])


@dataclass(frozen=True, slots=True)
class LineField:
    """Eq. 2: the line through ``origin`` towards ``target`` (exact points), gain ``gain`` (1/length)."""

    origin: ExactPoint
    target: ExactPoint
    gain: Fraction

    kind = "line"

    def __post_init__(self) -> None:
        if self.origin == self.target:
            raise ValueError("a line field needs a target different from its origin")

    @property
    def direction(self) -> np.ndarray:
        """The unit direction d (floats)."""
        w = _f(self.target) - _f(self.origin)
        return w / np.hypot(*w)

    def velocity(self, points: np.ndarray) -> np.ndarray:
        """v(q) for points of shape (k, 2)."""
        d = self.direction
        a = _f(self.origin)[None, :] - points
        cross_track = a - (a @ d)[:, None] * d[None, :]
        return d[None, :] + float(self.gain) * cross_track

    def potential(self, points: np.ndarray) -> np.ndarray:
        """φ(q) = −d·(q − q₀) + (p/2)‖(I − d dᵀ)(q − q₀)‖² (v = −∇φ)."""
        d = self.direction
        a = points - _f(self.origin)[None, :]
        along = a @ d
        across = a - along[:, None] * d[None, :]
        return -along + 0.5 * float(self.gain) * np.einsum("ij,ij->i", across, across)

    def recentred(self, cell: Cell) -> LineField:
        """The same field (same line, direction and gain) with its origin moved to the point of the line nearest
        the cell's vertex average and its target one |target − origin| further on: v does not change when q₀ slides
        along d, but a fitted field's origin can be thousands of units away (exact)."""
        n = len(cell.vertices)
        c = (sum((v[0] for v in cell.vertices), Fraction(0)) / n, sum((v[1] for v in cell.vertices), Fraction(0)) / n)
        w = (self.target[0] - self.origin[0], self.target[1] - self.origin[1])
        t = ((c[0] - self.origin[0]) * w[0] + (c[1] - self.origin[1]) * w[1]) / (w[0] * w[0] + w[1] * w[1])
        origin = (self.origin[0] + t * w[0], self.origin[1] + t * w[1])
        return LineField(origin, (origin[0] + w[0], origin[1] + w[1]), self.gain)

    def max_speed(self, cell: Cell) -> float:
        """The largest |v| over the cell (at a vertex: |v|² = 1 + p²·dist(q, line)² is convex), length/s per unit
        command; a controller uses v/|v| (the simulator does)."""
        return float(np.hypot(*self.velocity(cell.float_vertices).T).max())

    def to_json(self) -> dict:
        return {"kind": "line", "origin": [float(c) for c in self.origin], "direction": self.direction.tolist(),
                "target": [float(c) for c in self.target], "gain": float(self.gain),
                "gain_exact": format_number(self.gain)}


@dataclass(frozen=True, slots=True)
class ArcField:
    """Eq. 3 as we reconstruct it: turn about ``centre`` on the circle of ``radius``; ``clockwise`` is c_w = +1."""

    centre: ExactPoint
    radius: float
    gain: Fraction
    clockwise: bool

    kind = "arc"

    def velocity(self, points: np.ndarray) -> np.ndarray:
        rel = points - _f(self.centre)[None, :]
        rho = np.maximum(np.hypot(rel[:, 0], rel[:, 1]), 1e-12)
        radial = rel / rho[:, None]
        tangent_cw = np.stack([radial[:, 1], -radial[:, 0]], axis=1)
        cw = 1.0 if self.clockwise else -1.0
        return cw * tangent_cw + float(self.gain) * (self.radius - rho)[:, None] * radial

    def to_json(self) -> dict:
        return {"kind": "arc", "centre": [float(c) for c in self.centre], "radius": self.radius,
                "gain": float(self.gain), "gain_exact": format_number(self.gain), "clockwise": self.clockwise}


@dataclass(frozen=True, slots=True)
class GoalField:
    """The goal cell's field: unit speed straight to ``goal`` (zero at the goal)."""

    goal: ExactPoint

    kind = "goal"

    def velocity(self, points: np.ndarray) -> np.ndarray:
        a = _f(self.goal)[None, :] - points
        norm = np.hypot(a[:, 0], a[:, 1])
        return a / np.maximum(norm, 1e-12)[:, None]

    def to_json(self) -> dict:
        return {"kind": "goal", "goal": [float(c) for c in self.goal]}


Field = LineField | ArcField | GoalField


@dataclass(frozen=True, slots=True)
class FlowCheck(Verdict):
    """The verdict of a flow-through check: does every trajectory of a cell's field leave it through an exit?

    A :class:`~solverplan.verdict.Verdict`, as every check of solverplan gives.

    Parameters
    ----------
    valid
        True when the field was found to flow through.
    method
        ``exact`` (line and goal fields: decided in exact arithmetic) or ``dense-sample`` (RK4 trajectories from a
        grid of the cell and points on its sides: a sample, not a proof).
    failing_side
        The first side the field fails on (not an exit): ``None`` when valid, for a goal outside the cell, or for a
        sampled trajectory that never left.
    samples
        Trajectories sampled (``dense-sample``).
    exits
        The exit sides, ascending.
    decided
        Exact sign decisions made (``exact``: n·v at side ends; a goal field: 1, the goal in the cell).
    field_kind
        The kind of field checked: ``line``, ``arc`` or ``goal``.

    Attributes
    ----------
    kind
        ``flow-through``.
    failures
        The failing side (``sides[i]``), the goal outside the cell (``goal``) or a sampled trajectory that never
        left (``exits``), as :class:`~solverplan.verdict.Failure` records.
    checked
        The exact decisions: ``side_ends`` or ``goal_in_cell``; nothing for a sample.
    not_checked
        For a sample: that it is one, with its size.
    proved
        When valid and exact: every trajectory from the closed cell leaves through an exit (or reaches the goal).
    scope
        The trajectories the verdict speaks about, in words.

    Examples
    --------
    A kite whose side 1 is the exit: the fitted line field is checked exactly, and the same field with side 2 as
    the exit fails on side 1.

    >>> import solverplan as sp
    >>> kite = sp.decompose_free_space(sp.Environment.from_coords([(0, 0), (4, 0), (5, 3), (0, 1)])).cells[0]
    >>> field, check = fit_line_field(kite, {1})
    >>> check.valid, check.method, check.checked, check.proved[0]
    (True, 'exact', (('side_ends', 6),), 'every trajectory of the line field from every point of the closed cell leaves it through side 1 in finite time')
    >>> print(sp.flows_through(field, kite, {2}).failures[0])
    sides[1]: n·v ≤ 0 at an end of side 1: the field does not point into the cell there, and side 1 is no exit
    """

    valid: bool
    method: str
    failing_side: int | None = None
    samples: int = 0
    exits: tuple[int, ...] = ()
    decided: int = 0
    field_kind: str = "line"

    kind = "flow-through"

    @property
    def failures(self) -> tuple[Failure, ...]:
        if self.valid:
            return ()
        side = self.failing_side
        if self.field_kind == "goal":
            return (Failure("goal", "the goal is not in the closed cell"),)
        if side is None:
            return (Failure("exits", "a sampled trajectory is still in the cell after 10 diameters of travel"),)
        if self.method == "exact":
            return (Failure(f"sides[{side}]", f"n·v ≤ 0 at an end of side {side}: the field does not point into the "
                                              f"cell there, and side {side} is no exit"),)
        return (Failure(f"sides[{side}]", f"a sampled trajectory leaves the cell through side {side}, which is no exit"),)

    @property
    def checked(self) -> tuple[tuple[str, int], ...]:
        if self.method != "exact":
            return ()
        return (("goal_in_cell" if self.field_kind == "goal" else "side_ends", self.decided),)

    @property
    def not_checked(self) -> tuple[str, ...]:
        if self.method == "exact":
            return ()
        return (f"flow-through of the {self.field_kind} field: judged on {self.samples} trajectories integrated by "
                f"RK4 from a grid of the cell and points on its sides (a sample, not a proof)",)

    @property
    def proved(self) -> tuple[str, ...]:
        if not self.valid or self.method != "exact":
            return ()
        if self.field_kind == "goal":
            return ("the goal is in the closed convex cell: the straight line to it from every point of the cell stays "
                    "in the cell",)
        sides = ", ".join(map(str, self.exits))
        return (f"every trajectory of the {self.field_kind} field from every point of the closed cell leaves it "
                f"through side{'s' if len(self.exits) != 1 else ''} {sides} in finite time",)

    @property
    def scope(self) -> str:
        return (f"the trajectories of the cell's {self.field_kind} field from every point of the closed convex cell; "
                f"exits: {'sides ' + ', '.join(map(str, self.exits)) if self.exits else 'none (the goal)'}")

    @property
    def title(self) -> str:
        return f"flow-through of a {self.field_kind} field ({self.method})"

    def subject_json(self) -> dict[str, Any]:
        return {"method": self.method, "failing_side": self.failing_side, "samples": self.samples,
                "exits": list(self.exits), "field": self.field_kind}


def _sign_a_sqrt_l_plus_b(a: Fraction, b: Fraction, l: Fraction) -> int:
    """The exact sign of a·√l + b (l > 0)."""
    sa = (a > 0) - (a < 0)
    sb = (b > 0) - (b < 0)
    if sa == sb or sb == 0:
        return sa if sa else sb
    if sa == 0:
        return sb
    lhs, rhs = a * a * l, b * b
    return sa if lhs > rhs else sb if lhs < rhs else 0


def line_inward_sign(field: LineField, normal: ExactPoint, q: ExactPoint) -> int:
    """The exact sign of n·v(q) for the line field (n any positive multiple of a side's inward normal).

    n·v·|w|² = (n·w)|w| + p(|w|² n·(q₀ − q) − (n·w)(w·(q₀ − q))), w = target − q₀.
    """
    wx, wy = field.target[0] - field.origin[0], field.target[1] - field.origin[1]
    ax, ay = field.origin[0] - q[0], field.origin[1] - q[1]
    nw = normal[0] * wx + normal[1] * wy
    l2 = wx * wx + wy * wy
    b = field.gain * (l2 * (normal[0] * ax + normal[1] * ay) - nw * (wx * ax + wy * ay))
    return _sign_a_sqrt_l_plus_b(nw, b, l2)


def line_flows_through(field: LineField, cell: Cell, exits: set[int] | frozenset[int]) -> FlowCheck:
    """Exact flow-through of a line field: strictly inward at both ends of every side not in ``exits``.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> from solverplan.environment import load_environment
    >>> from solverplan.reflection.cells import decompose_free_space
    >>> cell = decompose_free_space(load_environment("square")).cells[0]
    >>> [s.midpoint for s in cell.sides][:1]
    [(Fraction(5, 1), Fraction(0, 1))]
    >>> f = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, F(3, 10))
    >>> line_flows_through(f, cell, {2}).valid, line_flows_through(f, cell, {1}).valid
    (True, False)
    """
    if not isinstance(field, LineField):
        raise TypeError(f"line_flows_through checks line fields; use dense_flows_through for {field.kind} fields")
    decided = 0
    ends = tuple(sorted(exits))
    for i, side in enumerate(cell.sides):
        if i in exits:
            continue
        for q in (side.a, side.b):
            decided += 1
            if line_inward_sign(field, side.normal, q) <= 0:
                return FlowCheck(False, "exact", i, exits=ends, decided=decided)
    return FlowCheck(True, "exact", exits=ends, decided=decided)


def dense_flows_through(field: Field, cell: Cell, exits: set[int] | frozenset[int], *, grid: int = 24,
                        per_side: int = 24) -> FlowCheck:
    """Flow-through by a dense sample: trajectories of ``v`` (RK4, step 1/400 of the cell's diameter) from a ``grid`` × ``grid`` lattice of the cell and ``per_side`` points on each side must all
    leave through a side of ``exits`` (the crossed side is the first whose half-plane the last step leaves). The
    step is at most 1/(4p) for a field of gain p (RK4 is accurate there), for up to 10 diameters of travel.

    Examples
    --------
    >>> import solverplan as sp
    >>> from fractions import Fraction
    >>> cell = sp.decompose_free_space(sp.load_environment("square")).cells[0]    # sides 0 … 3 from the bottom
    >>> bottom_to_top = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, Fraction(3, 10))
    >>> check = dense_flows_through(bottom_to_top, cell, {2})
    >>> check.valid, check.checked, check.proved, check.not_checked[0][:45]
    (True, (), (), 'flow-through of the line field: judged on 672')
    """
    verts = cell.float_vertices
    normals = np.array([s.unit_normal() for s in cell.sides])
    offsets = np.array([normals[i] @ _f(s.a) for i, s in enumerate(cell.sides)])
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    diameter = float(np.hypot(*(hi - lo)))
    xs = np.linspace(0, 1, grid + 2)[1:-1]
    pts = np.stack(np.meshgrid(lo[0] + xs * (hi[0] - lo[0]), lo[1] + xs * (hi[1] - lo[1])), axis=-1).reshape(-1, 2)
    pts = pts[np.all(pts @ normals.T - offsets >= 0, axis=1)]
    ts = np.linspace(0, 1, per_side + 2)[1:-1]
    on_sides = [(1 - t) * _f(s.a) + t * _f(s.b) for s in cell.sides for t in ts]
    pts = np.vstack([pts, np.array(on_sides)])
    n = len(pts)
    gain = float(getattr(field, "gain", 0))
    h = min(diameter / 400, 0.25 / gain) if gain > 0 else diameter / 400  # RK4 stays accurate for stiff gains
    q = pts.copy()
    alive = np.ones(n, dtype=bool)
    crossed = np.full(n, -1)

    def v(x: np.ndarray) -> np.ndarray:
        return field.velocity(x)

    for _ in range(int(np.ceil(10 * diameter / h))):
        idx = np.flatnonzero(alive)
        if not len(idx):
            break
        x = q[idx]
        k1 = v(x)
        k2 = v(x + 0.5 * h * k1)
        k3 = v(x + 0.5 * h * k2)
        k4 = v(x + h * k3)
        new = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        before = x @ normals.T - offsets
        after = new @ normals.T - offsets
        out = np.any(after < -1e-12 * diameter, axis=1)
        if out.any():
            b, a = before[out], after[out]
            with np.errstate(divide="ignore", invalid="ignore"):
                lam = np.where(a < 0, np.clip(b, 0, None) / (np.clip(b, 0, None) - a), np.inf)
            crossed[idx[out]] = np.argmin(lam, axis=1)
            alive[idx[out]] = False
        q[idx] = new
    ends, kind = tuple(sorted(exits)), field.kind
    if alive.any():
        return FlowCheck(False, "dense-sample", None, n, ends, field_kind=kind)
    bad = np.flatnonzero(~np.isin(crossed, sorted(exits)))
    if len(bad):
        return FlowCheck(False, "dense-sample", int(crossed[bad[0]]), n, ends, field_kind=kind)
    return FlowCheck(True, "dense-sample", None, n, ends, field_kind=kind)


def flows_through(field: Field, cell: Cell, exits: set[int] | frozenset[int]) -> FlowCheck:
    """Does every trajectory of ``field`` from the closed ``cell`` leave it through an exit side?

    Line fields are decided exactly (:func:`line_flows_through`); a goal field flows to its goal when the goal is in
    the closed cell (exact: the segment to it stays in the convex cell); other fields (arcs) are judged on a dense
    sample (:func:`dense_flows_through`), which the verdict lists under ``not_checked``.

    Parameters
    ----------
    field
        A :class:`LineField`, :class:`ArcField` or :class:`GoalField`.
    cell
        A convex cell (:func:`~solverplan.reflection.cells.decompose_free_space`).
    exits
        The sides (indices, counter-clockwise from the cell's first vertex) trajectories may leave through.

    Returns
    -------
    FlowCheck
        The verdict (:class:`~solverplan.verdict.Verdict`): ``valid``, ``failures`` naming the side that fails,
        what was decided exactly and what was only sampled.

    Examples
    --------
    >>> import solverplan as sp
    >>> from fractions import Fraction
    >>> cell = sp.decompose_free_space(sp.load_environment("square")).cells[0]
    >>> up = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, Fraction(3, 10))
    >>> [(check.valid, check.method) for check in (sp.flows_through(up, cell, {2}), sp.flows_through(up, cell, {3}))]
    [(True, 'exact'), (False, 'exact')]
    >>> sp.flows_through(GoalField(cell.sides[0].midpoint), cell, set()).proved[0][:34]
    'the goal is in the closed convex c'
    >>> sp.flows_through(up, cell, {4})
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: exit side 4 is not a side of cell 0 (sides 0 … 3)
    """
    _check_flow_question(field, cell, exits)
    if isinstance(field, LineField):
        return line_flows_through(field, cell, exits)
    if isinstance(field, GoalField):
        return FlowCheck(cell.contains(field.goal), "exact", decided=1, field_kind="goal")
    return dense_flows_through(field, cell, exits)


def _check_flow_question(field: object, cell: object, exits: object) -> None:
    """One line for a question :func:`flows_through` cannot answer: not a field, not a cell, exits not side indices."""
    if not isinstance(field, (LineField, ArcField, GoalField)):
        raise InputError(f"flows_through checks a LineField, ArcField or GoalField, not {type(field).__name__}")
    if not isinstance(cell, Cell):
        raise InputError(f"flows_through checks a convex Cell (decompose_free_space), not {type(cell).__name__}")
    if not isinstance(exits, (set, frozenset, list, tuple)):
        raise InputError(f"exits must be a set of side indices, not {type(exits).__name__}")
    m = len(cell.sides)
    for side in exits:
        if isinstance(side, bool) or not isinstance(side, int) or not 0 <= side < m:
            raise InputError(f"exit side {quote(side)} is not a side of cell {cell.id} (sides 0 … {m - 1})")


def arc_turn(cell: Cell, inlet: int, outlet: int, gain: Fraction) -> ArcField | None:
    """The arc field of a turning cell whose inlet and outlet sides meet at a vertex: centre that vertex, radius
    the mean distance to the two midpoints, turning from the inlet to the outlet; ``None`` when they do not meet."""
    m = len(cell.sides)
    if (inlet + 1) % m == outlet:
        centre = cell.sides[inlet].b
    elif (outlet + 1) % m == inlet:
        centre = cell.sides[outlet].b
    else:
        return None
    c = _f(centre)
    p_in, p_out = cell.sides[inlet].float_midpoint(), cell.sides[outlet].float_midpoint()
    radius = 0.5 * (math.hypot(*(p_in - c)) + math.hypot(*(p_out - c)))
    turn = (p_in - c)[0] * (p_out - c)[1] - (p_in - c)[1] * (p_out - c)[0]  # > 0: counter-clockwise from in to out
    return ArcField(centre, radius, gain, clockwise=bool(turn < 0))


_CROSS_SPEED = 2.0
"""Fitted line fields first try lines with |p·offset| ≤ this from the cell's centroid (cross-track speed, per unit
along-track speed): a field whose line is far from its cell commands huge speeds (issue #26: ~224)."""


def fit_line_field(cell: Cell, exits: set[int] | frozenset[int], *, directions: int = 15,
                   gain_range: tuple[float, float] = (0.05, 1e4)) -> tuple[LineField, FlowCheck] | None:
    """A line field that flows through ``cell`` towards ``exits``, found by linear programming, or ``None``.

    The search is made in the cell's own units — lengths divided by R, the largest distance from the cell's
    centroid to a vertex, gains multiplied by R — so it does not depend on the scale of the coordinates: the fit
    in the cell scaled by s (and moved, and turned) is the image of the fit in the cell (up to float rounding; the
    exact check decides). For a fixed direction d, write the line's point as q₀ = c d^⊥ (the centroid as origin)
    and r = p c, dimensionless: the condition "n_i·v > 0 at both ends of every other side" reads
    (n_i·d) + r (n_i·d^⊥) − p (n_i·(I − d dᵀ) q) > 0, linear in (r, p). For ``directions`` directions spread over
    ±79° about the outward normal of the first exit side, the LP maximising the smallest margin (scipy's HiGHS)
    gives the most robust (r, p) with p·R in ``gain_range`` (dimensionless); when no direction has a margin, sweeps
    of 4·``directions`` + 1 directions over ±88° and 16·``directions`` + 1 over ±89° follow (a narrow outlet
    can leave a window of directions a few degrees wide). The best direction's field is rounded
    to rationals (in units of R, from the cell's exact vertex average) and checked exactly
    (:func:`line_flows_through`), so the answer never relies on the LP's floats.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> from solverplan.environment import Environment
    >>> from solverplan.reflection.cells import decompose_free_space
    >>> kite = decompose_free_space(Environment.from_coords([(0, 0), (4, 0), (5, 3), (0, 1)])).cells[0]
    >>> field, check = fit_line_field(kite, {1})
    >>> check.valid, check.method
    (True, 'exact')
    >>> tiny = decompose_free_space(Environment.from_coords([(0, 0), ("4e-4", 0), ("5e-4", "3e-4"), (0, "1e-4")]))
    >>> small, _ = fit_line_field(tiny.cells[0], {1})
    >>> small.gain == field.gain * 10_000, small.origin == (field.origin[0] / 10_000, field.origin[1] / 10_000)
    (True, True)
    """
    from scipy.optimize import linprog

    if not exits:
        return None
    centre = cell.centroid
    unit = cell_unit(cell)  # R rounded to an exact decimal: the fit scales with the cell exactly
    verts = (cell.float_vertices - centre) / float(unit)
    others = [i for i in range(len(cell.sides)) if i not in exits]
    normals = [cell.sides[i].unit_normal() for i in others]
    ends = [(verts[i], verts[(i + 1) % len(verts)]) for i in others]
    outward = -cell.sides[min(exits)].unit_normal()
    base = math.atan2(outward[1], outward[0])
    lo, hi = gain_range
    best: tuple[float, np.ndarray, float, float, np.ndarray, np.ndarray] | None = None
    for count, spread in ((directions, 0.44), (4 * directions + 1, 0.49), (16 * directions + 1, 0.495)):
        for j in range(count):  # ±79° first; then ever finer sweeps to within 1° of the side's line
            angle = base + (j - count // 2) * (spread * math.pi / max(count // 2, 1))
            found = _direction_lp(angle, normals, ends, lo, hi)
            if found is not None and (best is None or found[0] > best[0]):
                best = found
        if best is not None:
            break
    if best is None:
        return None
    margin, d, r, p, rows_best, rhs_best = best
    # the gentlest gain keeping half the best margin: a stiff field is as sound but makes robots chatter
    r_bound = _CROSS_SPEED if abs(r) <= _CROSS_SPEED * (1 + 1e-9) else hi
    gentle = linprog(c=[0.0, 1.0, 0.0], A_ub=rows_best, b_ub=rhs_best,
                     bounds=[(-r_bound, r_bound), (lo, hi), (margin / 2, 1.0)], method="highs")
    if gentle.status == 0:
        r, p = float(gentle.x[0]), float(gentle.x[1])
    # in units of R from the exact vertex average a: q₀ = a + R·(centroid − a + (r/p) d^⊥)/R, target q₀ + R·d
    k = len(cell.vertices)
    average = (sum((v[0] for v in cell.vertices), Fraction(0)) / k, sum((v[1] for v in cell.vertices), Fraction(0)) / k)
    q0 = (centre - _f(average)) / float(unit) + (r / p) * np.array([-d[1], d[0]])

    def rational(x: float) -> Fraction:
        return Fraction(x).limit_denominator(10**6)

    origin = (average[0] + unit * rational(q0[0]), average[1] + unit * rational(q0[1]))
    target = (origin[0] + unit * rational(d[0]), origin[1] + unit * rational(d[1]))
    field = LineField(origin, target, Fraction(p).limit_denominator(10**4) / unit).recentred(cell)
    check = line_flows_through(field, cell, exits)
    return (field, check) if check.valid else None


def _direction_lp(angle: float, normals: list[np.ndarray], ends: list[tuple[np.ndarray, np.ndarray]], lo: float,
                  hi: float) -> tuple[float, np.ndarray, float, float, np.ndarray, np.ndarray] | None:
    """The LP of :func:`fit_line_field` for one direction: (margin, d, r, p, rows, rhs) or ``None`` (no margin)."""
    from scipy.optimize import linprog

    d = np.array([math.cos(angle), math.sin(angle)])
    d_perp = np.array([-d[1], d[0]])
    rows, rhs = [], []
    for n, (a, b) in zip(normals, ends):
        for q in (a, b):
            across = q - (q @ d) * d
            # a + u r + w p ≥ t  ⇔  −u r − w p + t ≤ a
            rows.append([-(n @ d_perp), n @ across, 1.0])
            rhs.append(n @ d)
    for r_bound in (_CROSS_SPEED, hi):  # a line through the cell first (bounded speed), then any (|c| ≲ R)
        res = linprog(c=[0.0, 0.0, -1.0], A_ub=np.array(rows), b_ub=np.array(rhs),
                      bounds=[(-r_bound, r_bound), (lo, hi), (None, 1.0)], method="highs")
        if res.status == 0 and res.x[2] > 1e-6:
            return float(res.x[2]), d, float(res.x[0]), float(res.x[1]), np.array(rows), np.array(rhs)
    return None


def cell_unit(cell: Cell) -> Fraction:
    """The cell's length unit: the largest distance from its centroid to a vertex, rounded to 6 significant
    digits as an exact decimal (so that it scales exactly with decimal coordinates).

    Examples
    --------
    >>> import solverplan as sp
    >>> cell_unit(sp.decompose_free_space(sp.load_environment("square")).cells[0])
    Fraction(707107, 100000)
    """
    radius = float(np.hypot(*(cell.float_vertices - cell.centroid).T).max())
    return Fraction(f"{radius:.6g}")
