"""``wallfollow``: the wall-following robot (cut ordering, Strategy 1, counting, pursuit-evasion)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from solverplan.choices import Comparisons, Sensor
from solverplan.limits import MAX_SEED
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, app
from solverplan.cli._options import CommonOptions, common_options, parse_pair, save_picture, write_certificate_file


@app.command(name="wallfollow")
@common_options("certificate", "picture", "env_format", "fmt", "out", "verbose")
def wallfollow_command(
    env: EnvArg,
    cut_ordering: Annotated[bool, typer.Option("--cut-ordering", help="The exact geometric cut ordering (the default).")] = False,
    learn: Annotated[bool, typer.Option("--learn", help="The cut ordering learned by Strategy 1 from sensing alone, with its action and memory counts.")] = False,
    count: Annotated[bool, typer.Option("--count", help="n and the winding number by the counting filter, from a seeded random walk.")] = False,
    start: Annotated[str | None, typer.Option("--start", metavar="X,Y", help="The robot's start point (default vertex 0).", show_default=False)] = None,
    heading: Annotated[str | None, typer.Option("--heading", metavar="DX,DY", help="Direction INIT drives in from an interior start (default 1,0).", show_default=False)] = None,
    comparisons: Annotated[Comparisons, typer.Option("--comparisons", help="With --learn: compare every pair of end points on an edge (the paper) or merge-sort them.")] = Comparisons.PAIRWISE,
    transcript: Annotated[bool, typer.Option("--transcript", help="With --learn: include every action and observation.")] = False,
    steps: Annotated[int, typer.Option("--steps", min=0, max=10_000_000, metavar="K", help="With --count: follows of the random walk (at most 10,000,000).")] = 1000,
    seed: Annotated[int, typer.Option("--seed", min=0, max=MAX_SEED, metavar="S", help="With --count: seed of the random walk.")] = 0,
    pursuit: Annotated[bool, typer.Option("--pursuit", help="A shortest pursuit-evasion plan, replayed by the geometric ground-truth checker.")] = False,
    sensor: Annotated[Sensor, typer.Option("--sensor", help="With --pursuit: the pursuer's extra sensor (gap: Strategy 2; bitangent: Strategy 3; pebble: Strategies 4–5, pebble visibility; contact: Strategy 6, touch and pebble only).")] = Sensor.GAP,
    origin: Annotated[str, typer.Option("--from", metavar="POINT", help="With --pursuit: the pursuer's start, a point of the cut ordering (v0, r3).")] = "v0",
    max_states: Annotated[int, typer.Option("--max-states", min=1, max=10_000_000, metavar="N", help="With --pursuit: cap on the derived I-states searched.")] = 200_000,
    perturb: Annotated[bool, typer.Option("--perturb", help="Make a degenerate polygon general by an infinitesimal symbolic perturbation (simulation of simplicity): grazing JUMPs pass one fixed side, coinciding cut end points are ordered one fixed way.")] = False,
    *,
    common: CommonOptions,
) -> None:
    """The wall-following robot (Yershova et al.): cut ordering, Strategy 1, vertex counting, pursuit-evasion."""
    with common.exit_codes():
        _check_modes(cut_ordering, learn, count, pursuit, pursuit_options=(sensor, origin, max_states),
                     learn_options=(transcript, comparisons), place=(start, heading), walk=(steps, seed),
                     certificate=common.certificate)
        environment = common.load(env)
        perturbation = None
        if perturb:
            from solverplan.wallfollow.perturbation import perturb as make_general

            perturbation = make_general(environment)
            environment = perturbation.env
        where, towards = parse_pair(start, "--start"), parse_pair(heading or "1,0", "--heading")
        assert towards is not None
        mode = "learn" if learn else "count" if count else "pursuit" if pursuit else "cut-ordering"
        answer = _answer(environment, mode, where, towards, comparisons=comparisons, transcript=transcript,
                         steps=steps, seed=seed, sensor=sensor, origin=origin, max_states=max_states)
        _check_and_draw(environment, answer, mode, common)
        if perturbation is not None:
            from solverplan.wallfollow.perturbation import PerturbedAnswer

            answer = PerturbedAnswer(answer, perturbation)
        common.emit(answer)


def _check_modes(cut_ordering: bool, learn: bool, count: bool, pursuit: bool, *, pursuit_options: tuple,
                 learn_options: tuple, place: tuple, walk: tuple, certificate: Any) -> None:
    """One line for options that belong to another mode than the one chosen."""
    if cut_ordering + learn + count + pursuit > 1:
        raise InputError("choose one of --cut-ordering, --learn, --count and --pursuit")
    if not pursuit and pursuit_options != (Sensor.GAP, "v0", 200_000):
        raise InputError("--sensor, --from and --max-states belong to --pursuit")
    if not learn and learn_options != (False, Comparisons.PAIRWISE):
        raise InputError("--comparisons and --transcript belong to --learn")
    if not (learn or count) and place != (None, None):
        raise InputError("--start and --heading place the robot of --learn or --count")
    if not count and walk != (1000, 0):
        raise InputError("--steps and --seed belong to --count")
    if count and certificate is not None:
        raise InputError("--certificate certifies a cut ordering or a pursuit plan: --count is a random walk's estimate")


def _answer(environment: Any, mode: str, where: Any, towards: Any, *, comparisons: Comparisons, transcript: bool,
            steps: int, seed: int, sensor: Sensor, origin: str, max_states: int) -> Any:
    """The library's answer for the mode chosen."""
    if mode == "learn":
        from solverplan.wallfollow.learning import learn_cut_ordering

        return learn_cut_ordering(environment, where, towards, comparisons=comparisons.value, transcript=transcript)
    if mode == "count":
        from solverplan.wallfollow.filters import count_random_walk

        return count_random_walk(environment, steps, seed, where, towards)
    if mode == "pursuit":
        from solverplan.wallfollow.pursuit import pursuit_plan

        return pursuit_plan(environment, sensor=sensor.value, start=origin, max_states=max_states)
    from solverplan.wallfollow.cut import cut_ordering

    return cut_ordering(environment)


def _check_and_draw(environment: Any, answer: Any, mode: str, common: CommonOptions) -> None:
    """The exact check before the answer leaves (a learned ordering: in the true numbering), the --certificate and
    the --picture."""
    learned = answer.ordering.relabel(answer.pebble_vertex) if mode == "learn" else None
    if mode != "count":
        from solverplan.certify.gate import checked_answer

        certified = learned if learned is not None else answer
        checked = checked_answer(lambda: certified, env=environment)
        if common.certificate is not None:
            write_certificate_file(certified, common.certificate, environment, checked.certificate)
    if mode == "pursuit":
        save_picture(common.picture, "wallfollow.render_pursuit", environment, answer)
    else:
        save_picture(common.picture, "wallfollow.render_cuts", environment, learned)
