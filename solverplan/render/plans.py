"""Plans (paper Figs. 12–13): per stage the cones a robot may sweep, the segments it lands on, start and goal.

The cone of a move i → j is the region swept by the rays leaving source segment i at the stage's
heading interval: the convex hull of the segment and the first wall hits of its four corner rays
(segment ends × interval ends), cast by the geometry kernel (:func:`solverplan.geometry.cast_from_boundary`).

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.partitions import partition
>>> from solverplan.plan import find_plan
>>> from solverplan.render import render_environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
>>> plan = find_plan(env, "e0", "e2")
>>> fig = render_environment(env, title=plan_title(plan))
>>> plan.bounces, [a.get_gid() for a in draw_plan(fig.axes[0], partition(env), plan)][:4]
(2, ['plan-cone-0-0', 'plan-cone-outline-0-0', 'plan-targets-0', 'plan-stage-label-0'])
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from solverplan.bounce.partitions import Partition
from solverplan.render._swept import swept_regions
from solverplan.render.figure import PLAN_GOAL_COLOR, PLAN_STAGE_COLORS, PLAN_START_COLOR, _piece_lines
from solverplan.render.labels import _left_normals

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.plan.result import Plan

__all__ = ["draw_plan", "plan_title"]

def _plan_cones(partition: Partition, plan: Plan) -> list[list[np.ndarray | None]]:
    """The swept region of every move of every stage: ``cones[k][m]`` holds the corners of the region of move
    ``plan.stages[k].moves[m]`` (floats, for drawing), or None when it is degenerate."""
    moves = [(k, i, stage.interval) for k, stage in enumerate(plan.stages) for i, _ in stage.moves]
    source = np.array([i for _, i, _ in moves], dtype=np.int64)
    regions = swept_regions(partition.env, np.asarray(partition.seg_edge)[source], np.asarray(partition.seg_t0)[source],
                            np.asarray(partition.seg_t1)[source], [h.lo for _, _, h in moves], [h.hi for _, _, h in moves])
    cones: list[list[np.ndarray | None]] = [[] for _ in plan.stages]
    for (k, _, _), region in zip(moves, regions):
        cones[k].append(region)
    return cones


def draw_plan(
    ax: Axes,
    partition: Partition,
    plan: Plan,
    *,
    colors: tuple[str, ...] = PLAN_STAGE_COLORS,
    alpha: float = 0.3,
    legend: bool = True,
) -> list:
    """Draw a plan (:class:`~solverplan.plan.Plan`) as the paper's Figs. 12–13: for every stage and every
    possible source segment, the **cone** the robot may sweep — the region between the source segment
    and the four landing points of its corner rays at the two ends of the stage's interval — filled in
    the stage's colour; the segments a stage lands on drawn bold in that colour and numbered with the
    stage; the start set (green) and the goal set (magenta) drawn along the walls; and a legend with each
    stage's interval and width. Draw after :func:`draw_free_space`; draw trajectories on top
    (:func:`draw_trajectories` with rollouts of :func:`solverplan.simulate.simulate_plan`).

    Returns the artists: the cones (gid ``plan-cone-<stage>-<source>``, filled, under the trajectories, and
    ``plan-cone-outline-<stage>-<source>``, their outlines above them), the landing segments
    (``plan-targets-<stage>``), their stage numbers (``plan-stage-label-<stage>``), the start and goal
    sets (``plan-start``, ``plan-goal``) and the legend (``plan-legend``).
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon

    env = partition.env
    artists: list = []
    handles = []
    normals = _left_normals(env)
    cones = _plan_cones(partition, plan)
    for k, stage in enumerate(plan.stages):
        colour = colors[k % len(colors)]
        lo, hi = stage.interval.lo, stage.interval.hi
        for (i, _), cone in zip(stage.moves, cones[k]):
            if cone is None:
                continue
            patch = Polygon(cone, closed=True, facecolor=colour, edgecolor="none", alpha=alpha, zorder=1.3,
                            gid=f"plan-cone-{k}-{i}")
            outline = Polygon(cone, closed=True, fill=False, edgecolor=colour, alpha=0.9, linewidth=0.9, zorder=1.7,
                              gid=f"plan-cone-outline-{k}-{i}")
            ax.add_patch(patch)
            ax.add_patch(outline)
            artists.extend([patch, outline])
        segs = np.stack([partition.seg_start[list(stage.to_segments)], partition.seg_end[list(stage.to_segments)]], axis=1)
        lines = LineCollection(list(segs), colors=colour, linewidths=4.0, capstyle="butt", zorder=3.2, gid=f"plan-targets-{k}")
        ax.add_collection(lines)
        artists.append(lines)
        for s in stage.to_segments[:1]:
            mid = 0.5 * (np.asarray(partition.seg_start[s]) + np.asarray(partition.seg_end[s]))
            normal = normals[int(partition.seg_edge[s])]
            label = ax.annotate(
                str(k + 1), xy=(float(mid[0]), float(mid[1])), xytext=(float(-normal[0] * 9), float(-normal[1] * 9)),
                textcoords="offset points", ha="center", va="center", fontsize=8, fontweight="bold", color="white",
                bbox=dict(boxstyle="circle,pad=0.18", facecolor=colour, edgecolor="none"), zorder=6.8,
                annotation_clip=False,
            )
            label.set_gid(f"plan-stage-label-{k}")
            artists.append(label)
        handles.append(Line2D([], [], color=colour, linewidth=6, alpha=0.6,
                              label=f"{k + 1}: [{lo:.4f}, {hi:.4f}]  width {hi - lo:.4f}"))
    for spec, colour, gid, name in ((plan.start, PLAN_START_COLOR, "plan-start", "start"),
                                   (plan.goal, PLAN_GOAL_COLOR, "plan-goal", "goal")):
        if not spec:
            continue
        lines = LineCollection(list(_piece_lines(env, env.boundary_set(spec).pieces)), colors=colour, linewidths=7.0, alpha=0.55,
                               capstyle="butt", zorder=2.9, gid=gid)
        ax.add_collection(lines)
        artists.append(lines)
        handles.append(Line2D([], [], color=colour, linewidth=6, alpha=0.55, label=f"{name} {spec}"))
    if legend and handles:
        box = ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5, frameon=False,
                        title="stage: heading interval (rad)", title_fontsize=8, handlelength=1.6, borderaxespad=0.0)
        box.set_gid("plan-legend")
        box._legend_box.align = "left"  # type: ignore[attr-defined]  # matplotlib has no public way to left-align a legend title
        artists.append(box)
    return artists


def plan_title(plan: Plan) -> str:
    """A one-line description of a plan for a figure title."""
    env = plan.environment.name if plan.environment is not None else ""
    head = f"{env}: " if env else ""
    if not plan.found:
        return f"{head}{plan.objective} plan from {plan.start} to {plan.goal}: infeasible"
    tol = plan.tolerance or 0.0
    return (f"{head}{plan.objective} plan {plan.start} → {plan.goal}: {plan.bounces} bounce"
            f"{'s' if plan.bounces != 1 else ''}, tolerance ±{tol:.4f} rad (±{np.degrees(tol):.2f}°)")
