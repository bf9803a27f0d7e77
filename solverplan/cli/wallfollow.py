"""``wallfollow``: the wall-following robot (cut ordering, Strategy 1, counting, pursuit-evasion)."""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Any

import typer

from solverplan.limits import MAX_SEED
from solverplan.errors import InputError
from solverplan.cli._app import EnvArg, EnvFormatOpt, FormatOpt, OutOpt, VerboseOpt, app, load_env
from solverplan.cli._errors import exit_codes
from solverplan.cli._options import CertificateOpt, PictureOpt, parse_pair, save_picture, write_certificate_file
from solverplan.cli._output import OutputFormat, emit


class Comparisons(StrEnum):
    PAIRWISE = "pairwise"
    SORT = "sort"


class PursuitSensor(StrEnum):
    GAP = "gap"
    BITANGENT = "bitangent"
    PEBBLE = "pebble"
    CONTACT = "contact"


@app.command(name="wallfollow")
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
    sensor: Annotated[PursuitSensor, typer.Option("--sensor", help="With --pursuit: the pursuer's extra sensor (gap: Strategy 2; bitangent: Strategy 3; pebble: Strategies 4–5, pebble visibility; contact: Strategy 6, touch and pebble only).")] = PursuitSensor.GAP,
    origin: Annotated[str, typer.Option("--from", metavar="POINT", help="With --pursuit: the pursuer's start, a point of the cut ordering (v0, r3).")] = "v0",
    max_states: Annotated[int, typer.Option("--max-states", min=1, max=10_000_000, metavar="N", help="With --pursuit: cap on the derived I-states searched.")] = 200_000,
    perturb: Annotated[bool, typer.Option("--perturb", help="Make a degenerate polygon general by an infinitesimal symbolic perturbation (simulation of simplicity): grazing JUMPs pass one fixed side, coinciding cut end points are ordered one fixed way.")] = False,
    certificate: CertificateOpt = None,
    picture: PictureOpt = None,
    env_format: EnvFormatOpt = None,
    fmt: FormatOpt = OutputFormat.JSON,
    out: OutOpt = None,
    verbose: VerboseOpt = 0,
) -> None:
    """The wall-following robot (Yershova et al.): cut ordering, Strategy 1, vertex counting, pursuit-evasion."""
    from solverplan.wallfollow.cut import cut_ordering as exact_cut_ordering
    from solverplan.wallfollow.filters import count_random_walk
    from solverplan.wallfollow.learning import learn_cut_ordering

    with exit_codes(verbose):
        if cut_ordering + learn + count + pursuit > 1:
            raise InputError("choose one of --cut-ordering, --learn, --count and --pursuit")
        if not pursuit and (sensor is not PursuitSensor.GAP or origin != "v0" or max_states != 200_000):
            raise InputError("--sensor, --from and --max-states belong to --pursuit")
        if not learn and (transcript or comparisons is not Comparisons.PAIRWISE):
            raise InputError("--comparisons and --transcript belong to --learn")
        if not (learn or count) and (start is not None or heading is not None):
            raise InputError("--start and --heading place the robot of --learn or --count")
        if not count and (steps != 1000 or seed != 0):
            raise InputError("--steps and --seed belong to --count")
        if count and certificate is not None:
            raise InputError("--certificate certifies a cut ordering or a pursuit plan: --count is a random walk's estimate")
        environment = load_env(env, env_format, picture)
        perturbation = None
        if perturb:
            from solverplan.wallfollow.perturbation import PerturbedAnswer, perturb as make_general

            perturbation = make_general(environment)
            environment = perturbation.env
        where, towards = parse_pair(start, "--start"), parse_pair(heading or "1,0", "--heading")
        assert towards is not None
        if learn:
            answer: Any = learn_cut_ordering(environment, where, towards, comparisons=comparisons.value,
                                             transcript=transcript)
        elif count:
            answer = count_random_walk(environment, steps, seed, where, towards)
        elif pursuit:
            from solverplan.wallfollow.pursuit import pursuit_plan

            answer = pursuit_plan(environment, sensor=sensor.value, start=origin, max_states=max_states)
        else:
            answer = exact_cut_ordering(environment)
        if not count:  # the exact check before the answer leaves (a learned ordering: in the true numbering)
            from solverplan.certify.gate import checked_answer

            certified = answer.ordering.relabel(answer.pebble_vertex) if learn else answer
            checked = checked_answer(lambda: certified, env=environment)
            if certificate is not None:
                write_certificate_file(certified, certificate, environment, checked.certificate)
        if pursuit:
            save_picture(picture, "wallfollow.render_pursuit", environment, answer)
        else:
            save_picture(picture, "wallfollow.render_cuts", environment,
                         answer.ordering.relabel(answer.pebble_vertex) if learn else None)
        emit(answer if perturbation is None else PerturbedAnswer(answer, perturbation), fmt, out)
