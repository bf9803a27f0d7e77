"""Composed potential fields with reflection: the convex cells and their fields, and the scenarios' trajectories.

Two panels side by side. Left: the convex cells (thin outlines, ids at the centroids; the cells of the sequence
tinted), each cell's nominal field as arrows on a grid, the reflection zones (the chosen wall side, thick red, with
the reflection field's direction from the inlet midpoint dashed), the start and the goal. Right: the kept
trajectories of every scenario, one colour per scenario, over the same cells.

>>> import solverplan as sp
>>> nav = sp.navigate_fields(sp.load_environment("serpentine"), (3, "2.25"), (3, "0.25"), trials=2, trajectories=1)
>>> fig = render_fields(nav)
>>> len(fig.axes), sorted({a.get_gid() for a in fig.axes[1].lines if a.get_gid()})
(2, ['trajectory-constrained-0', 'trajectory-reflection-0', 'trajectory-unconstrained-0'])
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from solverplan.reflection.compose import FieldPlan
from solverplan.reflection.navigation import FieldNavigation
from solverplan.render.environment import draw_boundary, draw_free_space
from solverplan.render.figure import PLAN_GOAL_COLOR, PLAN_START_COLOR, _style_axes

__all__ = ["render_fields", "draw_cells", "draw_cell_fields", "SCENARIO_COLORS"]

SCENARIO_COLORS = {"constrained": "#1b9e77", "unconstrained": "#7570b3", "reflection": "#d95f02"}
SEQUENCE_TINT = "#fde7c8"
ZONE_COLOR = "#c0392b"
FIELD_COLOR = "#2c5f8a"


def draw_cells(ax: Axes, plan: FieldPlan, *, ids: bool = True) -> None:
    """Cell outlines (gid ``cells``), the sequence's cells tinted (gid ``sequence-<k>``) and the ids."""
    for k, c in enumerate(plan.sequence):
        ax.add_patch(Polygon(plan.cells[c].float_vertices, closed=True, facecolor=SEQUENCE_TINT, edgecolor="none",
                             zorder=0.6, gid=f"sequence-{k}"))
    outlines = [np.vstack([c.float_vertices, c.float_vertices[:1]]) for c in plan.cells]
    ax.add_collection(LineCollection(outlines, colors="#8c96a0", linewidths=0.7, zorder=1.2, gid="cells"))
    if ids:
        for cell in plan.cells:
            x, y = cell.centroid
            ax.annotate(str(cell.id), (x, y), fontsize=7, color="#555555", ha="center", va="center", zorder=1.3)


def draw_cell_fields(ax: Axes, plan: FieldPlan, *, per_cell: int = 4) -> None:
    """Each cell's nominal field as unit arrows on one square grid for the whole picture, ``per_cell`` arrows across
    the narrowest cell but at most ~40 across the picture (gid ``field-<cell>``), and the reflection zones (gid ``zone-<cell>``)."""
    normals, offsets = plan.decomposition.halfplanes
    spacing = min(float(min(c.float_vertices.max(axis=0) - c.float_vertices.min(axis=0))) for c in plan.cells)
    spacing = spacing / per_cell if spacing > 0 else 1.0
    # a sliver cell (a door's diagonal) must not make the grid so fine that the arrows become a hatch: at most
    # about 40 arrows across the picture's longer side
    every = np.concatenate([c.float_vertices for c in plan.cells])
    spacing = max(spacing, float(np.max(every.max(axis=0) - every.min(axis=0))) / 40)
    for c, policy in plan.policies.items():
        verts = plan.cells[c].float_vertices
        lo, hi = verts.min(axis=0), verts.max(axis=0)
        xs = np.arange(np.floor(lo[0] / spacing) - 0.5, np.ceil(hi[0] / spacing) + 1) * spacing
        ys = np.arange(np.floor(lo[1] / spacing) - 0.5, np.ceil(hi[1] / spacing) + 1) * spacing
        grid = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
        inside = np.all(np.einsum("mj,kj->km", normals[c], grid) - offsets[c] > 1e-9 * spacing, axis=1)
        pts = grid[inside]
        if not len(pts):
            continue
        v = policy.field.velocity(pts)
        v = 0.7 * spacing * v / np.maximum(np.hypot(v[:, 0], v[:, 1]), 1e-12)[:, None]
        ax.quiver(pts[:, 0] - v[:, 0] / 2, pts[:, 1] - v[:, 1] / 2, v[:, 0], v[:, 1], angles="xy", scale_units="xy",
                  scale=1, color=FIELD_COLOR, width=0.0022, headwidth=3.5, headlength=4, headaxislength=3.5,
                  zorder=1.5, gid=f"field-{c}")
    for c, zone in plan.zones.items():
        side = plan.cells[c].sides[zone.side]
        a, b = side.a, side.b
        ax.plot([float(a[0]), float(b[0])], [float(a[1]), float(b[1])], color=ZONE_COLOR, linewidth=3.2,
                solid_capstyle="butt", zorder=2.5, gid=f"zone-{c}")
        o, t = zone.field.origin, zone.field.target
        ax.plot([float(o[0]), float(t[0])], [float(o[1]), float(t[1])], color=ZONE_COLOR, linewidth=1.0,
                linestyle="--", zorder=2.4, gid=f"zone-ray-{c}")


def _ends(ax: Axes, plan: FieldPlan) -> None:
    ax.scatter([float(plan.start[0])], [float(plan.start[1])], s=30, c=PLAN_START_COLOR, zorder=6, gid="start")
    ax.scatter([float(plan.goal[0])], [float(plan.goal[1])], s=40, marker="*", c=PLAN_GOAL_COLOR, zorder=6,
               gid="goal")


def render_fields(nav: FieldNavigation, *, title: str | None = None) -> Figure:
    """The cells and fields (left) and the trajectories of every scenario (right) of ``nav``."""
    plan = nav.plan
    env = plan.env
    xmin, ymin, xmax, ymax = env.bounds
    span_x, span_y = max(xmax - xmin, 1e-12), max(ymax - ymin, 1e-12)
    panel_w = 6.5
    panel_h = float(np.clip(panel_w * span_y / span_x, 2.5, 9.0))
    fig = Figure(figsize=(2 * panel_w, panel_h + 0.9))
    FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2)
    name = env.name or "environment"
    _style_axes(left, title or f"{name}: {len(plan.cells)} cells, sequence {'→'.join(map(str, plan.sequence))}")
    times = ", ".join(f"{k} {r.time_mean:.2f} s" for k, r in nav.runs.items() if r.time_mean is not None)
    _style_axes(right, f"{nav.model.kind} robot, {next(iter(nav.runs.values())).trials} trials: {times}")
    pad = 0.04 * max(span_x, span_y)
    for ax in (left, right):
        draw_free_space(ax, env)
        draw_cells(ax, plan, ids=ax is left)
        draw_boundary(ax, env)
        ax.set_xlim(xmin - pad, xmax + pad)
        ax.set_ylim(ymin - pad, ymax + pad)
    draw_cell_fields(left, plan)
    for scenario, run in nav.runs.items():
        color = SCENARIO_COLORS.get(scenario, "#333333")
        for k, path in enumerate(run.trajectories):
            right.plot(path[:, 0], path[:, 1], color=color, linewidth=0.9, alpha=0.75, zorder=3,
                       label=scenario if k == 0 else None, gid=f"trajectory-{scenario}-{k}")
    for ax in (left, right):
        _ends(ax, plan)
    if any(run.trajectories for run in nav.runs.values()):
        right.legend(loc="best", fontsize=7, framealpha=0.85)
    fig.tight_layout()
    return fig
