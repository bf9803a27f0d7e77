"""``explore``: online exploration with discrete views (Algorithms A and B)."""

from __future__ import annotations

from typing import Annotated

import typer

from solverplan.choices import ViewChoice
from solverplan.limits import MAX_SEED
from solverplan.cli._app import EnvArg, app
from solverplan.cli._options import CommonOptions, common_options, parse_xy


@app.command(name="explore")
@common_options("certificate", "picture", "env_format", "fmt", "out", "verbose")
def explore_command(
    env: EnvArg,
    start: Annotated[str, typer.Option("--start", metavar="X,Y", help="The robot's start p1, a point of the free space.")],
    choice: Annotated[ViewChoice, typer.Option("--choice", help="Which unexplored constructed edge the next view is taken on: first, random (with --seed) or far.")] = ViewChoice.FIRST,
    seed: Annotated[int | None, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Seed of --choice random (default 0).", show_default=False)] = None,
    range_: Annotated[str | None, typer.Option("--range", metavar="R", help="Sensing range R > 0: range-limited views and Algorithm B (Algorithm A when R reaches across the polygon).", show_default=False)] = None,
    *,
    common: CommonOptions,
) -> None:
    """Explore an unknown polygon with discrete views (Ghosh et al.): Algorithm A (at most r + 1 views), or with
    --range R Algorithm B (at most Lemma 4's bound)."""
    from solverplan.certify.gate import checked_answer
    from solverplan.explore import Exploration, RangeExploration, explore_depth_first, explore_range_limited

    with common.loaded(env) as environment:
        point = parse_xy(start, "--start")

        def solve() -> Exploration | RangeExploration:
            if range_ is None:
                return explore_depth_first(environment, point, choice=choice.value, seed=seed)
            return explore_range_limited(environment, point, range_, choice=choice.value, seed=seed)

        checked = checked_answer(solve, env=environment)  # the views checked exactly before the answer leaves
        common.emit_checked(checked, env=environment, renderer="explore.render_exploration", draw=(environment,))
