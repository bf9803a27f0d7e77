"""The wall-following robot's cuts and cut diagram (Yershova et al., Figs. 3–5).

Left: the polygon with every cut drawn from its reflex vertex to its end point (left cuts dashed blue, right cuts
solid orange), vertices and end points labelled. Right: the **cut diagram** — the n + 2m points of the cut
ordering placed around a circle in their cyclic order, each reflex vertex joined by a chord to its two cut end
points; by Prop. 4 two chords cross exactly when the cuts cross in the polygon.

>>> from solverplan.environment import Environment
>>> from solverplan.wallfollow import cut_ordering
>>> room = Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
>>> fig = render_cuts(room)
>>> sorted(a.get_gid() for a in fig.axes[1].lines if a.get_gid().startswith("chord"))
['chord-l3', 'chord-r3']
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from solverplan.environment import Environment
from solverplan.render.environment import draw_boundary, draw_free_space, draw_reflex_vertices
from solverplan.render.figure import (BOUNDARY_COLOR, TRAJECTORY_COLOR, TRAJECTORY_START_COLOR, _style_axes,
                                      new_figure)
from solverplan.wallfollow.cut import Cut, cut_ordering, cuts
from solverplan.wallfollow.ordering import CutOrdering

__all__ = ["CUT_COLORS", "SHADOW_COLORS", "draw_cuts", "draw_cut_diagram", "render_cuts", "render_pursuit"]

CUT_COLORS = {"l": "#1f5fbf", "r": "#d95f02"}
_STYLES = {"l": "--", "r": "-"}


def draw_cuts(ax: Axes, env: Environment, all_cuts: tuple[Cut, ...] | None = None, *, labels: bool = True) -> list:
    """Each cut as a segment (gid ``cut-l3``) and, with ``labels``, its end point's name (gid ``cut-label-l3``)."""
    artists: list = []
    pts = env.vertices
    span = max(env.bounds[2] - env.bounds[0], env.bounds[3] - env.bounds[1])
    for cut in all_cuts if all_cuts is not None else cuts(env):
        a, b = pts[cut.vertex], np.array([float(cut.point[0]), float(cut.point[1])])
        (line,) = ax.plot([a[0], b[0]], [a[1], b[1]], _STYLES[cut.side], color=CUT_COLORS[cut.side], linewidth=1.0,
                          zorder=3, gid=f"cut-{cut.label}")
        artists.append(line)
        if labels:
            d = (b - a) / max(float(np.hypot(*(b - a))), 1e-300)
            spot = b - 0.03 * span * d
            artists.append(ax.text(spot[0], spot[1], cut.label, fontsize=7, color=CUT_COLORS[cut.side],
                                   ha="center", va="center", zorder=6, gid=f"cut-label-{cut.label}"))
    if labels:
        inward = np.mean(pts, axis=0)
        for k, p in enumerate(pts):
            d = p - inward
            spot = p + 0.04 * span * d / max(float(np.hypot(*d)), 1e-300)
            artists.append(ax.text(spot[0], spot[1], f"v{k}", fontsize=7, color=BOUNDARY_COLOR, ha="center",
                                   va="center", zorder=6, gid=f"vertex-label-{k}"))
    return artists


def draw_cut_diagram(ax: Axes, ordering: CutOrdering) -> list:
    """The cut diagram: points of the ordering counter-clockwise on the unit circle from ``v0`` at the top,
    reflex vertices as red dots, chords to their end points (gid ``chord-l3``)."""
    artists: list = []
    size = len(ordering.labels)
    angle = np.pi / 2 + 2 * np.pi * np.arange(size) / size
    xy = np.column_stack([np.cos(angle), np.sin(angle)])
    where = {label: xy[i] for i, label in enumerate(ordering.labels)}
    circle = np.linspace(0, 2 * np.pi, 200)
    artists += ax.plot(np.cos(circle), np.sin(circle), color="#bbbbbb", linewidth=0.8, zorder=1, gid="diagram-circle")
    reflex = set(ordering.reflex)
    for k in sorted(reflex):
        for side in ("l", "r"):
            a, b = where[f"v{k}"], where[f"{side}{k}"]
            artists += ax.plot([a[0], b[0]], [a[1], b[1]], _STYLES[side], color=CUT_COLORS[side], linewidth=1.0,
                               zorder=2, gid=f"chord-{side}{k}")
    for i, label in enumerate(ordering.labels):
        kind, k = label[0], int(label[1:])
        color = "#c0392b" if kind == "v" and k in reflex else BOUNDARY_COLOR if kind == "v" else CUT_COLORS[kind]
        artists.append(ax.scatter([xy[i, 0]], [xy[i, 1]], s=14, color=color, zorder=3, gid=f"diagram-point-{label}"))
        artists.append(ax.text(1.12 * xy[i, 0], 1.12 * xy[i, 1], label, fontsize=7, color=color, ha="center",
                               va="center", zorder=4, gid=f"diagram-label-{label}"))
    ax.set_xlim(-1.3, 1.3)
    ax.set_ylim(-1.3, 1.3)
    ax.set_xticks([])
    ax.set_yticks([])
    return artists


def render_cuts(env: Environment, ordering: CutOrdering | None = None, *, title: str | None = None) -> Figure:
    """Two panels: the polygon with its cuts, and the cut diagram of ``ordering`` (default: the geometric one)."""
    ordering = ordering if ordering is not None else cut_ordering(env)
    fig, ax = new_figure(env, title=title or f"{env.name or 'polygon'}: {len(ordering.reflex)} reflex vertices, "
                                             f"{2 * len(ordering.reflex)} cuts")
    width, height = fig.get_size_inches()
    fig.set_size_inches(width + max(height, 4.0), max(height, 4.0))
    ax.remove()
    left = fig.add_subplot(1, 2, 1)
    _style_axes(left, title or f"{env.name or 'polygon'}: {2 * len(ordering.reflex)} cuts")
    draw_free_space(left, env)
    draw_boundary(left, env)
    draw_reflex_vertices(left, env)
    draw_cuts(left, env)
    right = fig.add_subplot(1, 2, 2)
    _style_axes(right, "cut diagram")
    draw_cut_diagram(right, ordering)
    fig.tight_layout()
    return fig


# ---------------------------------------------------------------------- pursuit plans (Yershova et al., Figs. 14–15)
SHADOW_COLORS = {1: "#d1495b", 0: "#9aa5b1"}  #: label 1 (the evader may be there): red; label 0: grey


def _pursuit_panel(ax: Axes, env: Environment, check, upto: int) -> None:
    """The polygon, the path up to step ``upto``, the pursuer there, its shadow components shaded by label."""
    from matplotlib.patches import Polygon as Patch

    step = check.steps[upto]
    draw_free_space(ax, env)
    for g, ring in sorted(step.components.items()):
        label = 1 if g in step.labels else 0
        xy = np.array([[float(x), float(y)] for x, y in ring])
        ax.add_patch(Patch(xy, closed=True, facecolor=SHADOW_COLORS[label], alpha=0.55 if label else 0.4,
                           edgecolor=SHADOW_COLORS[label], linewidth=0.6, zorder=2, gid=f"shadow-v{g}-{label}"))
        from shapely.geometry import Polygon as Shape

        shape = Shape(xy).buffer(0)  # a sliver (a perturbation's width, ~1e-7 in area) may clean to nothing
        x, y = (shape.representative_point().coords[0] if not shape.is_empty else xy.mean(axis=0))
        ax.text(x, y, str(label), fontsize=8, color="#222222", ha="center", va="center", zorder=7,
                gid=f"shadow-label-v{g}")
    draw_boundary(ax, env)
    path = [check.steps[0].point] + [s.point for s in check.steps[1:upto + 1]]
    for k, (a, b) in enumerate(zip(path, path[1:]), start=1):
        jump = check.steps[k].action is not None and check.steps[k].action.value == "JUMP"
        ax.plot([float(a[0]), float(b[0])], [float(a[1]), float(b[1])], ":" if jump else "-", color=TRAJECTORY_COLOR,
                linewidth=2.0, zorder=4, gid=f"path-{k}")
    start, here = path[0], path[-1]
    ax.scatter([float(start[0])], [float(start[1])], s=30, color=TRAJECTORY_START_COLOR, zorder=5, gid="start")
    ax.scatter([float(here[0])], [float(here[1])], s=45, marker="*", color="#111111", zorder=6, gid="pursuer")
    action = "start" if upto == 0 else f"step {upto}: {check.steps[upto].action}"
    ax.set_title(f"{action} → {step.label}\n{len(step.labels)} of {len(step.components)} shadow(s) labelled 1",
                 fontsize=8)


MAX_PURSUIT_PANELS = 36
"""A pursuit picture shows every step up to this many; a longer plan shows this many, evenly spaced (the first and
the last always), and says so in the title."""


def render_pursuit(env: Environment, plan, *, panels: int | None = None, columns: int = 4,
                   title: str | None = None) -> Figure:
    """A pursuit plan as a grid of snapshots, one per step (the start, then after each action), ``columns`` wide:
    the path so far (follows solid, JUMPs dotted), the pursuer (star) and its shadow components, red when labelled
    1 (the evader may be there), grey when 0, by the ground-truth checker. Panels are ~3 inches square, so the
    picture stays readable however long the plan (a strip of every step was 4,000 px wide).

    ``plan`` is a :class:`~solverplan.wallfollow.pursuit.PursuitPlan` (with its check) or a
    :class:`~solverplan.wallfollow.pursuit_check.PursuitCheck`; ``panels`` caps the snapshots (default every step,
    at most :data:`MAX_PURSUIT_PANELS`).
    """
    check = getattr(plan, "check", plan)
    if check is None:
        why = f" ({plan.status.value}, {plan.sensor} sensor)" if hasattr(plan, "sensor") else ""
        fig, ax = new_figure(env, title=title or f"{env.name or 'polygon'}: no pursuit plan{why}")
        draw_free_space(ax, env)
        draw_boundary(ax, env)
        return fig
    last = len(check.steps) - 1
    cap = MAX_PURSUIT_PANELS if panels is None else max(1, panels)
    count = min(cap, last + 1)
    picks = sorted({round(k * last / max(count - 1, 1)) for k in range(count)})
    cols = max(1, min(columns, len(picks)))
    rows = -(-len(picks) // cols)
    xmin, ymin, xmax, ymax = env.bounds
    aspect = (ymax - ymin) / max(xmax - xmin, 1e-12)
    size = 3.0
    fig = Figure(figsize=(size * cols, size * min(max(aspect, 0.4), 2.5) * rows + 0.6))
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    verdict = "verified" if check.valid else "NOT verified"
    shown = "every step" if len(picks) == last + 1 else f"{len(picks)} of {last + 1} steps"
    fig.suptitle(title or f"{env.name or 'polygon'}: pursuit plan of {len(check.actions)} actions from {check.start} "
                          f"({verdict} by the ground-truth checker; {shown})", fontsize=10)
    for k, upto in enumerate(picks, start=1):
        panel = fig.add_subplot(rows, cols, k)
        _style_axes(panel, None)
        _pursuit_panel(panel, env, check, upto)
        panel.set_aspect("equal")
    fig.tight_layout()
    return fig
