"""Whole pictures: :func:`scene` stacks the layers of an environment picture and what is drawn over it.

A scene is what ``solverplan render`` draws: the environment (free space, walls, reflex vertices, ids),
optionally the partition P′ and the bounce visibility graph, then at most one answer — a plan, the limit
cycle of a constant heading, or a patrol / funnel / localisation answer — and simulated trajectories
(of the plan, of the cycle's constant rule, or of any bounce rule), under a title that says what is shown.

Layers are drawn in a fixed order — graph and safe arcs, partition, plan, trajectories, limit cycles,
answer — each at its own z-order, so a later label layer (the partition's segment ids) keeps clear of the
labels drawn before it.

Every reading of the plan and limit-cycle objects for a scene sits here (the patrol and funnel ones in
:mod:`solverplan.render.answers`), through their public attributes only.

>>> from solverplan.environment import Environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
>>> fig = scene(env, cycle="tan:1/3", trajectories=3, seed=1)
>>> fig.axes[0].get_title().splitlines()[0]
'box: constant heading θ = 0.3218, limit cycle e0 → e1 → e2 → e3 → e0'
>>> sorted({a.get_gid() for a in fig.axes[0].get_children() if (a.get_gid() or "").startswith(("limit-cycle", "traj"))})[:3]
['limit-cycle', 'limit-cycle-arrow-0', 'limit-cycle-arrow-1']
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

from matplotlib.figure import Figure

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.render.answers import answer_title, draw_answer
from solverplan.render.cycles import draw_cycle
from solverplan.render.environment import render_environment
from solverplan.render.graph import draw_graph, draw_safe_arcs
from solverplan.render.partition import draw_partition
from solverplan.render.plans import draw_plan, plan_title
from solverplan.render.trajectories import draw_trajectories

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.dynamics import HeadingSpec
    from solverplan.bounce.rules import BounceRule
    from solverplan.plan.result import Plan

__all__ = ["scene"]

logger = logging.getLogger(__name__)

# The rollouts of a plan are drawn dark and thin over the coloured cones, so both stay readable.
_PLAN_TRAJECTORY_COLOR, _PLAN_TRAJECTORY_WIDTH, _PLAN_TRAJECTORY_ALPHA = "#2b2b2b", 0.4, 0.3


def scene(
    env: Environment,
    *,
    edge_ids: bool = False,
    vertex_ids: bool = False,
    reflex: bool = True,
    partition: bool = False,
    graph: bool = False,
    safe_arcs: bool = False,
    plan: Plan | None = None,
    cycle: HeadingSpec | None = None,
    answer: Any = None,
    trajectories: int = 0,
    rule: BounceRule | str = "specular",
    start: str | None = None,
    bounces: int = 20,
    seed: int = 0,
    title: str | None = None,
) -> Figure:
    """A picture of ``env`` with the requested layers, answer and trajectories (module docstring).

    Parameters
    ----------
    env
        The environment.
    edge_ids, vertex_ids, reflex
        Label edges ``e<i>`` (with direction arrows) and vertices ``v<i>``; mark reflex vertices.
    partition
        Draw the partition P′ of Algorithm 1 (numbered segments, inserted points).
    graph, safe_arcs
        Draw the bounce visibility graph lightly; draw every safe arc as a ray landing on its target.
    plan
        A plan for ``env`` (e.g. :func:`solverplan.plan.load_plan`): its cones per stage, start and goal sets;
        the trajectories then follow the plan (its stages are the bounces).
    cycle
        A constant heading (anything :func:`solverplan.bounce.cycles.limit_cycle` takes, e.g. ``"tan:1/3"``):
        draw its limit cycle, and every other cycle the trajectories reach; the trajectories then follow that
        constant rule from headings equal to it.
    answer
        A patrol, funnel or localisation answer over ``env``: drawn as by :func:`~solverplan.render.render_answer`.
    trajectories
        Simulate and draw this many rollouts (0: none), seeded by ``seed``.
    rule, start, bounces
        The bounce rule (a rule or its spelling, e.g. ``"fixed:pi/3"``), the start set (default: the whole
        boundary) and the bounces per rollout of trajectories that follow neither a plan nor a cycle.
    title
        The Axes title; by default the plan's, the cycle's or the answer's description, else the environment's
        name.

    Returns
    -------
    Figure
        One Axes (``fig.axes[0]``); write it with :func:`~solverplan.render.save_figure`.

    Raises
    ------
    InputError
        A bad rule or start set; a plan together with a cycle, a start set or an answer; a cycle together with
        an answer; a plan made for another environment.
    """
    from solverplan.bounce.rules import Fixed, parse_rule

    bounce_rule: Any = parse_rule(rule) if isinstance(rule, str) else rule
    if start is not None:
        env.boundary_set(start)  # a bad start set is reported before anything is drawn
    if plan is not None and (cycle is not None or start is not None or answer is not None):
        raise InputError("a plan draws its own trajectories from its own start set: give no cycle, start or answer with it")
    if cycle is not None and answer is not None:
        raise InputError("draw either a limit cycle or an answer, not both")
    limit = initial = None
    if plan is not None:
        title = title if title is not None else plan_title(plan)
    if cycle is not None:
        from solverplan.bounce.cycles import limit_cycle

        limit = limit_cycle(env, cycle)
        bounce_rule, initial = Fixed(limit.heading.theta), [limit.heading.theta]
    if answer is not None and title is None:
        title = answer_title(answer)
    figure = render_environment(env, edge_ids=edge_ids, vertex_ids=vertex_ids, reflex=reflex,
                                title=title if title is not None or limit is None else limit.title())
    ax = figure.axes[0]
    from solverplan.bounce.partitions import Partition, partition as partition_boundary

    boundary: Partition | None = None
    if partition or graph or safe_arcs or plan is not None:
        boundary = partition_boundary(env)
    if boundary is not None and (graph or safe_arcs):
        from solverplan.bounce.bvg import safe_bounce_visibility_graph

        bvg = safe_bounce_visibility_graph(boundary)
        if graph:
            draw_graph(ax, bvg)
        if safe_arcs:
            draw_safe_arcs(ax, bvg)
    if boundary is not None and partition:
        draw_partition(ax, boundary)
    runs = None
    if plan is not None and boundary is not None:
        plan.check_environment(env, boundary.n_segments)
        draw_plan(ax, boundary, plan)
        if trajectories and plan.found and plan.stages:
            from solverplan.simulate import simulate_plan

            runs = simulate_plan(env, plan, trials=trajectories, seed=seed, record="all", partition=boundary)
            logger.info("simulated %s", runs.to_text().strip().replace("\n", "; "))
            draw_trajectories(ax, runs, color=_PLAN_TRAJECTORY_COLOR, linewidth=_PLAN_TRAJECTORY_WIDTH,
                              alpha=_PLAN_TRAJECTORY_ALPHA)
    elif trajectories:
        from solverplan.simulate import simulate_rule

        runs = simulate_rule(env, bounce_rule, start, bounces=bounces, trials=trajectories, seed=seed, initial=initial)
        logger.info("simulated %s", runs.to_text().strip().replace("\n", "; "))
        draw_trajectories(ax, runs)
    if limit is not None:
        from solverplan.bounce.cycles import limit_cycles

        ends = list(zip(runs.final_edge.tolist(), runs.final_t.tolist())) if runs is not None else []
        cycles = limit_cycles(env, limit.heading, ends)  # every cycle the trajectories reach
        for each in cycles:
            draw_cycle(ax, each)
        if title is None:
            ax.set_title(cycles[0].title(others=len(cycles) - 1), fontsize=11)
    if answer is not None:
        draw_answer(ax, answer)
    return figure
