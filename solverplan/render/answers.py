"""Contraction answers: patrols (paper Def. 15) and funnel / localisation strategies (paper Fig. 14).

Every reading of the answer objects (:class:`~solverplan.plan.patrols.Patrol`,
:class:`~solverplan.plan.funnels.Funnel`, localisation answers) for drawing sits in this module, through
their public attributes only: ``env``, ``visit``, ``cycle``, ``points``, ``found``, ``status`` and the
objective figures of a patrol; ``start``, ``goal``, ``stages`` (``sources``, ``cones``, ``positions``),
``widths``, ``kind`` and ``epsilon`` of a funnel or localisation answer.

>>> from solverplan.plan.funnels import funnel
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
>>> answer = funnel(env, "e0", "e2:0.4:0.6")
>>> fig = render_answer(answer)
>>> fig.axes[0].get_title().splitlines()[0]
'box: funnel e0 → e2:0.4:0.6'
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from solverplan.environment import Environment
from solverplan.geometry.raycast import cast_from_boundary
from solverplan.render._swept import cone_headings, swept_regions
from solverplan.render.environment import render_environment
from solverplan.render.figure import (
    CONE_COLOR,
    CYCLE_COLOR,
    CYCLE_POINT_COLOR,
    FUNNEL_GOAL_COLOR,
    FUNNEL_START_COLOR,
    PATROL_EDGE_COLOR,
    _piece_lines,
)

__all__ = ["draw_patrol", "draw_position_sets", "draw_answer", "answer_title", "render_answer"]


def _is_patrol(answer) -> bool:
    """A patrol has a cycle of stages; funnel and localisation answers have position stages."""
    return hasattr(answer, "cycle")


def draw_patrol(ax: Axes, patrol, *, linewidth: float = 2.2) -> list:
    """Draw a patrol (:class:`~solverplan.plan.patrols.Patrol`): the required edges (thick, purple), each cycle
    stage's heading interval as a shaded fan of rays from its nominal contact point, and the nominal limit
    cycle (bold, contact points as yellow circles). Returns the artists (gids ``patrol-edges``,
    ``patrol-cone-k``, ``patrol-cycle``, ``patrol-points``)."""
    from matplotlib.patches import Polygon

    env = patrol.env
    artists: list = []
    segs = [env.points_at(np.array([e, e]), np.array([0.0, 1.0])) for e in dict.fromkeys(patrol.visit)]
    if segs:
        lines = LineCollection(segs, colors=PATROL_EDGE_COLOR, linewidths=5.0, alpha=0.55, zorder=3.5,
                               gid="patrol-edges", capstyle="butt")
        ax.add_collection(lines)
        artists.append(lines)
    if not patrol.points:
        return artists
    for k, (st, p) in enumerate(zip(patrol.cycle, patrol.points)):
        hits = cast_from_boundary(env, np.array([st.step.from_edge] * 2), np.array([float(p.t)] * 2),
                                  np.array([st.interval.lo, st.interval.hi]))
        origin = [float(p.point[0]), float(p.point[1])]
        fan = Polygon([origin, [hits.x[0], hits.y[0]], [hits.x[1], hits.y[1]]], closed=True, facecolor=CONE_COLOR,
                      edgecolor=CONE_COLOR, alpha=0.18, linewidth=0.6, zorder=4, gid=f"patrol-cone-{k}")
        ax.add_patch(fan)
        artists.append(fan)
    pts = np.array([[float(p.point[0]), float(p.point[1])] for p in patrol.points])
    closed = np.vstack([pts, pts[:1]])
    (line,) = ax.plot(closed[:, 0], closed[:, 1], color=CYCLE_COLOR if patrol.found else "#6b6b6b", linewidth=linewidth,
                      zorder=6, gid="patrol-cycle")
    artists.append(line)
    artists.append(ax.scatter(pts[:, 0], pts[:, 1], s=60, c=CYCLE_POINT_COLOR, edgecolors=CYCLE_COLOR, linewidths=1.2,
                              zorder=6.5, gid="patrol-points"))
    return artists


def _swept_regions(env: Environment, stage) -> list[np.ndarray | None]:
    """The region each source piece of a position stage sweeps: the hull of the piece and the wall hits of its
    corner rays at the two directions of its exact cone (:func:`~solverplan.render._swept.swept_regions`)."""
    headings = [cone_headings(env, int(p.edge), cone) for p, cone in zip(stage.sources, stage.cones)]
    return swept_regions(env, [int(p.edge) for p in stage.sources], [float(p.t0) for p in stage.sources],
                         [float(p.t1) for p in stage.sources], [h[0] for h in headings], [h[1] for h in headings])


def draw_position_sets(ax: Axes, answer, *, cmap: str = "viridis") -> list:
    """Draw a funnel or localisation strategy: the start set (green), the goal (red), and for every stage the
    region its rays sweep (the hull of the source pieces and their corner hits, shaded) and the exact set of
    positions after it (thick, coloured from the first stage to the last) — the shrinking position sets.
    Returns the artists (gids ``funnel-start``, ``funnel-goal``, ``funnel-swept-k``, ``funnel-positions-k``)."""
    from matplotlib import colormaps
    from matplotlib.patches import Polygon

    env = answer.env
    artists: list = []
    colours = colormaps[cmap]
    n = max(len(answer.stages), 1)

    def pieces(items, colour, width, gid, z):
        if not items:
            return
        lc = LineCollection(_piece_lines(env, items), colors=colour, linewidths=width, zorder=z, gid=gid,
                            capstyle="round")
        ax.add_collection(lc)
        artists.append(lc)

    pieces(answer.start.pieces, FUNNEL_START_COLOR, 6.0, "funnel-start", 3.6)
    if answer.goal is not None:
        pieces(answer.goal.pieces, FUNNEL_GOAL_COLOR, 6.0, "funnel-goal", 3.6)
    for k, st in enumerate(answer.stages):
        colour = colours(0.1 + 0.8 * k / max(n - 1, 1))
        for region in _swept_regions(env, st):
            if region is None:
                continue
            patch = Polygon(region, closed=True, facecolor=colour, edgecolor=colour, alpha=0.3, linewidth=0.8,
                            zorder=4, gid=f"funnel-swept-{k}")
            ax.add_patch(patch)
            artists.append(patch)
        pieces(st.positions, colour, 4.5, f"funnel-positions-{k}", 5.5)
        x, y = _piece_lines(env, st.positions[:1])[0].mean(axis=0)
        label = ax.annotate(str(k + 1), (x, y), xytext=(6, 6), textcoords="offset points", fontsize=8, color="black",
                            zorder=7, gid=f"funnel-label-{k}",
                            bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": colour, "alpha": 0.85})
        artists.append(label)
    return artists


def answer_title(answer) -> str:
    """A two-line figure title for a patrol, funnel or localisation answer: what was asked, then how it went."""
    name = answer.env.name or "environment"
    if _is_patrol(answer):
        seq = "→".join(f"e{e}" for e in answer.visit)
        sub = (f"worst-case contraction {answer.contraction:.3g} per cycle, {answer.rate:.3g} per bounce"
               if answer.found else answer.status)
        return f"{name}: patrol {seq} ({answer.objective})\n{sub}"
    widths = answer.widths
    sub = (f"{len(answer.stages)} bounces; position set {widths[0]:.3g} → {widths[-1]:.3g} long" if answer.stages
           else answer.status)
    target = f"< {answer.epsilon:g}" if answer.kind == "localize" else str(answer.goal)
    return f"{name}: {answer.kind} {answer.start} → {target}\n{sub}"


def draw_answer(ax: Axes, answer) -> list:
    """Draw a patrol (:func:`draw_patrol`) or a funnel / localisation strategy (:func:`draw_position_sets`)."""
    return draw_patrol(ax, answer) if _is_patrol(answer) else draw_position_sets(ax, answer)


def render_answer(answer, *, edge_ids: bool = True) -> Figure:
    """A picture of a patrol, funnel or localisation answer over its environment, with a two-line title."""
    fig = render_environment(answer.env, edge_ids=edge_ids, title=answer_title(answer))
    draw_answer(fig.axes[0], answer)
    return fig
