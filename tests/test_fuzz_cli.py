"""Fuzzing the input boundary: malformed environment files, boundary sets and plan files on every reading command.

Each example writes one generated file and runs one command through typer's CliRunner. The outcome must be an
answer (exit 0) or bad input (exit 2 with exactly one stderr line under 200 characters, nothing on stdout and no
output file) — never an internal error (exit 1), a traceback or a partial file.

The default (``ci``) profile runs a few dozen examples per test; ``HYPOTHESIS_PROFILE=fuzz`` runs 10,000 each
(``FUZZ_EXAMPLES=N`` for another count), random rather than derandomized::

    HYPOTHESIS_PROFILE=fuzz .venv/bin/python -m pytest tests/test_fuzz_cli.py -p no:cacheprovider -q
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from solverplan.cli import app

FUZZING = os.environ.get("HYPOTHESIS_PROFILE") == "fuzz"
EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "10000")) if FUZZING else 40
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=not FUZZING,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

_numbers = st.one_of(
    st.integers(-10**6, 10**6), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, 1, -1, 1e308, 1e-308, 1e-300, 10**400, 0.1, 2.5]),
    st.text(max_size=8), st.none(), st.booleans(),
)
_points = st.one_of(
    st.lists(_numbers, min_size=0, max_size=3),
    st.fixed_dictionaries({"x": _numbers, "y": _numbers}),
    _numbers,
)
_rings = st.one_of(st.lists(_points, max_size=8), _numbers, st.dictionaries(st.text(max_size=4), _numbers, max_size=2))
_square = [[0, 0], [4, 0], [4, 4], [0, 4]]


@st.composite
def environment_texts(draw) -> str:
    """JSON texts around the environment format: valid squares with one field broken, random structures, and
    broken JSON."""
    kind = draw(st.integers(0, 3))
    if kind == 0:  # a valid polygon with one coordinate replaced
        outer = [list(p) for p in _square]
        i, j = draw(st.integers(0, 3)), draw(st.integers(0, 1))
        outer[i][j] = draw(_numbers)
        return json.dumps({"outer": outer}, allow_nan=True)
    if kind == 1:  # random structure in the right shape
        data: dict = {"outer": draw(_rings)}
        if draw(st.booleans()):
            data["holes"] = draw(st.lists(_rings, max_size=2))
        if draw(st.booleans()):
            data["name"] = draw(_numbers)
        return json.dumps(data, allow_nan=True, default=str)
    if kind == 2:  # a valid text cut anywhere, or with a byte changed
        text = json.dumps({"outer": _square, "holes": [[[1, 1], [1, 2], [2, 2], [2, 1]]]})
        cut = draw(st.integers(0, len(text)))
        if draw(st.booleans()):
            return text[:cut]
        return text[:cut] + draw(st.characters(codec="utf-8")) + text[cut + 1:]
    return draw(st.text(max_size=60))


_sets = st.one_of(
    st.sampled_from(["e0", "e1:0.25:0.75", "e0,e2", "e9", "e0:1:0", "e0:0.5:0.5", "e-1", "x", "", "e0:", "e0:0:2",
                     "e99999999999999999999", "e0:1e-999999:1", "e0:0:1,e1:0:1,e2"]),
    st.text(alphabet="e0123456789:,.-", max_size=12),
)


def _assert_answer_or_one_line(result, out_file=None) -> None:
    assert result.exit_code in (0, 2), (result.exit_code, result.stderr[-400:])
    if result.exit_code == 2:
        lines = result.stderr.splitlines()
        assert len(lines) == 1 and len(lines[0]) < 200 and lines[0].startswith(("error:", "Usage", "Try")) or \
            "Usage:" in result.stderr, result.stderr
        assert result.stdout == ""
        if out_file is not None:
            assert not out_file.exists()


@FUZZ
@given(text=environment_texts(), command=st.sampled_from(["info", "partition", "graph"]))
@example(text='{"outer": [[0, 0], [1e400, 0], [0, 1]]}', command="info")
@example(text="[" * 100_000, command="graph")
@example(text='{"outer": [[0, 0], [18446744073709551616, 0], [4, 4], [0, 4]]}', command="info")  # found by fuzzing
@example(text='{"outer": [[0, 0], [4, 0], [-1.401298464324817e-45, 4], [0, 4]]}', command="info")  # found by fuzzing
def test_fuzzed_environment_files_are_answered_or_refused_in_one_line(tmp_path_factory, text, command):
    folder = tmp_path_factory.mktemp("fuzz")
    env, out = folder / "env.json", folder / "answer.json"
    env.write_text(text)
    _assert_answer_or_one_line(CliRunner().invoke(app, [command, str(env), "-o", str(out)]), out)


@FUZZ
@given(start=_sets, goal=_sets, objective=st.sampled_from(["fewest", "tolerance", "sum", "constant", "best"]),
       budget=st.one_of(st.none(), st.integers(-2, 5)))
def test_fuzzed_boundary_sets_and_options_are_answered_or_refused_in_one_line(start, goal, objective, budget):
    args = ["plan", "square", "--from", start, "--to", goal, "--objective", objective]
    if budget is not None:
        args += ["--max-bounces", str(budget)]
    _assert_answer_or_one_line(CliRunner().invoke(app, args))


@FUZZ
@given(text=st.one_of(st.text(max_size=40), st.builds(json.dumps, st.dictionaries(
    st.sampled_from(["status", "stages", "objective", "bounces", "environment", "optimality"]), _numbers, max_size=4))))
def test_fuzzed_plan_and_certificate_files_are_refused_in_one_line(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("fuzz")
    path = folder / "file.json"
    path.write_text(text)
    for args in (["simulate", "square", str(path), "--trials", "10"], ["verify", str(path)]):
        result = CliRunner().invoke(app, args)
        if args[0] == "verify" and result.exit_code == 1:  # an invalid certificate: verify's own answer
            assert "INVALID" in result.stdout or '"valid": false' in result.stdout
            continue
        _assert_answer_or_one_line(result)


@pytest.mark.parametrize("flag", ["--trials", "--seed"])
def test_huge_integer_options_are_refused_in_one_line(flag):
    result = CliRunner().invoke(app, ["simulate", "square", "nope.json", flag, str(2**64)])
    _assert_answer_or_one_line(result)


# Every command with a valid base invocation on small models, and each of its value options. A fuzzed option value
# replaces the default (or the base's value); the rest of the invocation stays valid, so the refusal (or answer) is
# the option's.
_BASE = {
    "info": ["info", "square"],
    "partition": ["partition", "l_shape"],
    "graph": ["graph", "triangle", "--safe"],
    "cycle": ["cycle", "square", "--theta", "0.3"],
    "patrol": ["patrol", "square", "--visit", "e0,e2"],
    "funnel": ["funnel", "square", "--from", "e0", "--to", "e2"],
    "localize": ["localize", "triangle", "--epsilon", "0.5"],
    "plan": ["plan", "triangle", "--from", "e0", "--to", "e1"],
    "render": ["render", "square"],
    "simulate": ["simulate", "square", "PLAN"],
    "verify": ["verify", "CERT"],
    "prove": ["prove", "--only", "lemma2_contraction"],
    "explore": ["explore", "l_shape", "--start", "1,1"],
    "wallfollow": ["wallfollow", "star", "--pursuit"],
    "fields": ["fields", "serpentine", "--from", "3,2.25", "--to", "3,0.25", "--trials", "2"],
    "import": ["import", "OFFICE"],
    "report": ["report", "square", "--plan", "PLAN"],
}
_OPTIONS = {
    "graph": ["--from", "--heading"],
    "cycle": ["--theta", "--edges", "--epsilon", "--method", "--start", "--max-bounces", "--heading-margin"],
    "patrol": ["--visit", "--from", "--tolerance", "--objective", "--max-between", "--epsilon", "--heading-margin",
               "--corner-clearance"],
    "funnel": ["--from", "--to", "--tolerance", "--max-bounces", "--heading-margin", "--corner-clearance"],
    "localize": ["--epsilon", "--from", "--tolerance", "--max-bounces", "--heading-margin", "--corner-clearance"],
    "plan": ["--from", "--to", "--objective", "--max-bounces", "--pareto", "--method", "--heading-margin",
             "--corner-clearance"],
    "render": ["--trajectories", "--rule", "--from", "--bounces", "--seed", "--theta"],
    "simulate": ["--trials", "--seed", "--sampling", "--ties"],
    "verify": ["--from", "--to"],
    "prove": ["--only"],
    "info": ["--env-format", "--format"],
    "partition": ["--env-format", "--format"],
    "explore": ["--start", "--range", "--choice", "--seed"],
    "wallfollow": ["--sensor", "--from", "--max-states"],
    "fields": ["--from", "--to", "--trials", "--seed", "--trajectories", "--fast", "--slow", "--scenario", "--model"],
    "import": ["--seed-point", "--simplify", "--min-hole-area", "--spur-width", "--rectilinear", "--tolerance"],
    "report": ["--plan", "--certificate"],
}
_VALUES = st.one_of(
    st.sampled_from(["0", "-0", "-1", "1", "2", "0.3", "1e-300", "5e-324", "1e300", "1e400", "nan", "inf", "-inf",
                     "18446744073709551616", "1e-999999", "1e999999", "abc", "", " ", "0x10", "1_000", "1/3",
                     "e0", "e0:0:1", "e0,e1", "e5", "fixed:1.0", "specular", "relative:1.0±0.1", "fewest",
                     "1e7", "10000000", "-1e-300", "٣"]),
    st.text(max_size=10),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**25, 10**25).map(str),
)


@pytest.fixture(scope="module")
def plan_and_certificate(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz-files")
    plan, cert = folder / "plan.json", folder / "cert.json"
    result = CliRunner().invoke(app, ["plan", "square", "--from", "e0", "--to", "e2", "-o", str(plan),
                                      "--certificate", str(cert)])
    assert result.exit_code == 0, result.stderr
    return str(plan), str(cert)


def _invoke_bounded(args, seconds: int = 120):
    """Run one CLI invocation; a case that runs longer than ``seconds`` fails the test (a hang)."""
    import signal

    def _hang(signum, frame):  # pragma: no cover - only on a hang
        raise AssertionError(f"no answer within {seconds} s: {args}")

    previous = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(seconds)
    try:
        return CliRunner().invoke(app, args, catch_exceptions=False)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.parametrize("value", ["00\U000114da\U00012544\U00018d09\U00018d09\U0001fbcb\U0002ebe1", "x" * 300])
def test_a_long_bad_choice_is_quoted_short(value):  # found by the fuzz profile: the choice's repr made 226 characters
    _assert_answer_or_one_line(CliRunner().invoke(app, ["cycle", "square", "--theta", "0.3", "--method", value]))


@FUZZ
@given(command=st.sampled_from(sorted(_OPTIONS)), data=st.data())
@example(command="localize", data=None).via("found by fuzzing: ten million bounces, ε below float resolution (a hang)")
@example(command="wallfollow", data=None).via("found by fuzzing: a bad --from listed the whole cut ordering (250 chars)")
@example(command="import", data=None).via("found by fuzzing: --spur-width 16 ran scipy out of memory")
def test_fuzzed_option_values_are_answered_or_refused_in_one_line(tmp_path_factory, plan_and_certificate, command,
                                                                  data):
    folder = tmp_path_factory.mktemp("fuzz")
    out = folder / "answer.json"
    office = str(Path(__file__).resolve().parent.parent / "models" / "office.yaml")
    files = {"PLAN": plan_and_certificate[0], "CERT": plan_and_certificate[1], "OFFICE": office}
    args = [files.get(a, a) for a in _BASE[command]]
    if data is None:  # the explicit examples found by fuzzing
        pairs = {"wallfollow": [("--from", "\U00018cd6\U0002ebe1\U0002fa1e")],
                 "import": [("--spur-width", "16")]}.get(command, [("--max-bounces", "10000000"), ("--epsilon", "1e-300")])
    else:
        options = data.draw(st.lists(st.sampled_from(_OPTIONS[command]), min_size=1, max_size=2, unique=True))
        pairs = [(option, data.draw(_VALUES)) for option in options]
    for option, value in pairs:
        if option in args:  # replace the base's value
            args[args.index(option) + 1] = value
        else:
            args += [option, value]
    if command in ("render", "report"):
        out = folder / ("picture.png" if command == "render" else "report.html")
        args += ["-o", str(out)]
    elif command != "verify":
        args += ["-o", str(out)]
    result = _invoke_bounded(args)
    if command == "verify" and result.exit_code == 1:  # a certificate that does not hold for the pinned sets
        assert "INVALID" in result.stdout or '"valid": false' in result.stdout or result.stdout == "", result.stdout
        return
    _assert_answer_or_one_line(result, out)
