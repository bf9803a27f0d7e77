"""``study``: batch studies over random environments."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from solverplan.choices import StudyGenerator as GeneratorName
from solverplan.limits import MAX_BOUNCES, MAX_COUNT, MAX_SEED, MAX_TRIALS
from solverplan.cli._app import app
from solverplan.cli._errors import Shell, fail
from solverplan.cli._options import CommonOptions, common_options, progress_bar


study_app = typer.Typer(
    rich_markup_mode=None,  # plain help: typer's rich help imports rich and markdown-it (≈ 0.1 s of every start)
    name="study", cls=Shell, no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
    help="Batch studies over random environments (paper §7.3-7.4, §8.2): tables (CSV, JSON) and heatmaps; resumable.",
)
app.add_typer(study_app, name="study")



GeneratorOpt = Annotated[GeneratorName, typer.Option("--generator", help="The random environments.")]
GridOpt = Annotated[
    list[str] | None,
    typer.Option("--grid", metavar="NAME=VALUES", show_default=False,
                 help="A generator parameter: one value (20), a list (0.1,0.3) or START:STOP:COUNT (0.1:0.4:5); repeatable. "
                      "Default for star: the paper's n=20, irregularity=0.1:0.4:5, spikiness=0.1:0.5:5."),
]
PerCellOpt = Annotated[int, typer.Option("--per-cell", min=1, max=MAX_COUNT, metavar="N", help="Environments per grid cell.")]
StudySeedOpt = Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="Base seed (each row's seed derives from it).")]
OutDirOpt = Annotated[
    Path | None,
    typer.Option("--out-dir", metavar="DIR", show_default=False,
                 help="Folder of NAME.jsonl (rows, written as they finish), NAME.csv, NAME.json, NAME.png (default ./NAME-study)."),
]
WorkersOpt = Annotated[
    int | None, typer.Option("--workers", min=1, max=MAX_COUNT, metavar="N", show_default=False, help="Local worker processes (default: the CPU count).")
]
SchedulerOpt = Annotated[
    str | None, typer.Option("--scheduler", metavar="ADDRESS", show_default=False, help="Run on this Dask scheduler (tcp://host:8786).")
]
FreshOpt = Annotated[bool, typer.Option("--fresh", help="Start over instead of resuming the rows already in --out-dir.")]
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar (there is none when stderr is not a terminal).")]
FigureOpt = Annotated[bool, typer.Option("--figure/--no-figure", help="Draw the heatmaps to DIR/NAME.png.")]


def _study(name: str, generator: GeneratorName, grid: list[str] | None, per_cell: int, seed: int, out_dir: Path | None,
           workers: int | None, scheduler: str | None, fresh: bool, quiet: bool, figure: bool, common: CommonOptions,
           **options: Any) -> None:
    from solverplan.studies import StudyInterrupted, build_study, run_study
    from solverplan.studies.execute import output_paths

    with common.exit_codes():
        study = build_study(name, generator=generator.value, grid=grid or (), per_cell=per_cell, seed=seed, **options)
        folder = out_dir if out_dir is not None else Path(f"{study.name}-study")
        try:
            with progress_bar(f"study {study.name}", quiet) as progress:
                result = run_study(study, folder, workers=workers, scheduler=scheduler, resume=not fresh, progress=progress)
        except StudyInterrupted as exc:
            raise fail(str(exc), 130) from None
        if figure:
            from solverplan.render import render_heatmaps, save_figure

            path = output_paths(study, folder)["figure"]
            save_figure(render_heatmaps(result.table.heatmaps(), title=result.figure_title(),
                                        columns=result.table.panel_columns()), path)
            result = result.with_file("figure", path)
        common.emit(result)


def _shared_options_study(name: str, summary: str) -> None:
    """Register ``study NAME``: a study that takes the options every study shares, and no others."""
    @common_options("fmt", "out", "verbose")
    def command(
        generator: GeneratorOpt = GeneratorName.STAR, grid: GridOpt = None, per_cell: PerCellOpt = 10, seed: StudySeedOpt = 0,
        out_dir: OutDirOpt = None, workers: WorkersOpt = None, scheduler: SchedulerOpt = None, fresh: FreshOpt = False,
        quiet: QuietOpt = False, figure: FigureOpt = True, *, common: CommonOptions,
    ) -> None:
        _study(name, generator, grid, per_cell, seed, out_dir, workers, scheduler, fresh, quiet, figure, common)

    command.__doc__, command.__name__ = summary, f"study_{name}"
    study_app.command(name)(command)


for _name, _summary in (
    ("reachability", "Share of the boundary no safe action reaches (safe-BVG nodes without incoming arcs; paper Figure 15)."),
    ("connectivity", "Strongly and weakly connected components of the safe BVG (paper Figure 16)."),
):
    _shared_options_study(_name, _summary)


@study_app.command("rules")
@common_options("fmt", "out", "verbose")
def study_rules(
    rules: Annotated[str, typer.Option("--rules", metavar="F1,F2,...", help="Rule families: any, fixed, monotone, relative, specular, or one rule such as fixed:pi/4.")] = "any,fixed,monotone,relative,specular",
    family_size: Annotated[int, typer.Option("--family-size", min=1, max=MAX_COUNT, metavar="M", help="Parameters per family: θ = kπ/(M+1).")] = 5,
    trials: Annotated[int, typer.Option("--trials", min=1, max=MAX_TRIALS, metavar="K", help="Simulated robots per environment and family.")] = 200,
    bounces: Annotated[int, typer.Option("--bounces", min=2, max=MAX_BOUNCES, metavar="B", help="Bounces per simulated robot.")] = 50,
    generator: GeneratorOpt = GeneratorName.STAR, grid: GridOpt = None, per_cell: PerCellOpt = 10, seed: StudySeedOpt = 0,
    out_dir: OutDirOpt = None, workers: WorkersOpt = None, scheduler: SchedulerOpt = None, fresh: FreshOpt = False,
    quiet: QuietOpt = False, figure: FigureOpt = True, *, common: CommonOptions,
) -> None:
    """Compare bounce-rule families by the reachability of the systems they induce (paper §8.2; see rule_systems)."""
    families = [f for f in (part.strip() for part in rules.split(",")) if f]
    _study("rules", generator, grid, per_cell, seed, out_dir, workers, scheduler, fresh, quiet, figure, common,
           families=families, family_size=family_size, trials=trials, bounces=bounces)
