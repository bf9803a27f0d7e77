"""Fuzzing the public entry points of ``import solverplan as sp`` with hostile arguments.

The Python API's counterpart of the CLI's "an answer or one line, exit 2": every call returns a result or raises
:class:`solverplan.errors.InputError` (a ``ValueError``) whose message is one line under 200 characters — never
another exception type from deep inside (``KeyError``, ``OverflowError``, ``RecursionError``, numpy errors), never a
hang. Profiles as in ``tests/test_fuzz_cli.py`` (``HYPOTHESIS_PROFILE=fuzz`` for the long run).
"""

from __future__ import annotations

import math
import signal
from fractions import Fraction

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import solverplan as sp
from solverplan.errors import InputError
from tests.test_fuzz_cli import FUZZ, _numbers, _sets

_square = [[0, 0], [4, 0], [4, 4], [0, 4]]
_models: dict[str, sp.Environment] = {}


def _model(name: str) -> sp.Environment:
    if name not in _models:
        _models[name] = sp.load_environment(name)
    return _models[name]


def _answer_or_input_error(call, *args, seconds: int = 120, **kwargs):
    """Call; an :class:`InputError` must be one short line, anything else raised fails; a hang fails."""

    def _hang(signum, frame):  # pragma: no cover - only on a hang
        raise AssertionError(f"no answer within {seconds} s")

    previous = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(seconds)
    try:
        return call(*args, **kwargs)
    except InputError as error:
        message = str(error)
        assert "\n" not in message and 0 < len(message) < 200, message
        return None
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


_coordinates = st.one_of(_numbers, st.fractions(), st.decimals(allow_nan=True, allow_infinity=True).map(str),
                         st.sampled_from(["1e-999999", "1e999999", "0.1", "-0", "1/3", Fraction(1, 3)]))
_rings = st.lists(st.one_of(st.lists(_coordinates, min_size=0, max_size=3), _coordinates,
                            st.fixed_dictionaries({"x": _coordinates, "y": _coordinates})), max_size=7)


@FUZZ
@given(outer=st.one_of(_rings, st.just(_square).flatmap(
    lambda sq: st.tuples(st.integers(0, 3), st.integers(0, 1), _coordinates).map(
        lambda c: [[c[2] if (i, j) == c[:2] else v for j, v in enumerate(p)] for i, p in enumerate(sq)]))),
    holes=st.one_of(st.none(), st.lists(_rings, max_size=2)))
@example(outer=[[0, 0], [10**5000, 0], [0, 1]], holes=None)
@example(outer=[[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]], holes=None)
@example(outer=[[0, 0], ["1e-999999", 0], [1, 1]], holes=None)
def test_fuzzed_coordinates_give_an_environment_or_one_line(outer, holes):
    env = _answer_or_input_error(sp.Environment.from_coords, outer, holes)
    if env is not None:  # a valid polygon: it is one and its numbers are finite
        assert env.n_edges >= 3
        assert all(math.isfinite(float(c)) for ring in env.rings for point in ring for c in point)


_floats = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0, -1, 1e-300, 1e300, 2, 0.5]),
                    st.integers(-10**20, 10**20))


@FUZZ
@given(model=st.sampled_from(["triangle", "square", "l_shape"]), start=_sets, goal=_sets,
       objective=st.sampled_from(["fewest", "tolerance", "sum", "constant", "nope"]),
       max_bounces=st.one_of(st.none(), st.integers(-3, 6), st.just(10**30)),
       heading_margin=st.one_of(st.just(1e-3), _floats), corner_clearance=st.one_of(st.none(), _floats))
@example(model="triangle", start="e0:0:1,e1:0:1,e2", goal="e0:0:1,e1:0:1,e2", objective="sum", max_bounces=10**30,
         heading_margin=1e-3, corner_clearance=None).via("found by the fuzz profile: a hang")
def test_fuzzed_plan_queries_answer_or_refuse_in_one_line(model, start, goal, objective, max_bounces, heading_margin,
                                                          corner_clearance):
    plan = _answer_or_input_error(sp.find_plan, _model(model), start, goal, objective=objective,
                                  max_bounces=max_bounces, heading_margin=heading_margin,
                                  corner_clearance=corner_clearance)
    if plan is not None:
        assert isinstance(plan.status, sp.Status)


@FUZZ
@given(model=st.sampled_from(["triangle", "square", "hexagon"]), theta=_floats,
       edges=st.one_of(st.none(), st.sampled_from(["e0,e1", "e9", "", "x"]), st.lists(st.integers(-2, 8), max_size=3)),
       epsilon=st.one_of(st.none(), _floats), max_bounces=st.one_of(st.just(200), st.integers(-2, 10)))
def test_fuzzed_limit_cycles_answer_or_refuse_in_one_line(model, theta, edges, epsilon, max_bounces):
    cycle = _answer_or_input_error(sp.limit_cycle, _model(model), theta, edges=edges, epsilon=epsilon,
                                   max_bounces=max_bounces)
    if cycle is not None:
        assert isinstance(cycle.status, sp.Status)


@FUZZ
@given(model=st.sampled_from(["triangle", "square"]), epsilon=_floats, start=st.one_of(st.none(), _sets),
       tolerance=st.one_of(st.none(), _floats), max_bounces=st.integers(-2, 6), which=st.sampled_from(["localize",
                                                                                                     "funnel"]))
def test_fuzzed_position_searches_answer_or_refuse_in_one_line(model, epsilon, start, tolerance, max_bounces, which):
    env = _model(model)
    if which == "localize":
        answer = _answer_or_input_error(sp.localize, env, epsilon, start=start, tolerance=tolerance,
                                        max_bounces=max_bounces)
    else:
        answer = _answer_or_input_error(sp.funnel, env, start or "e0", "e1", tolerance=tolerance,
                                        max_bounces=max_bounces)
    if answer is not None:
        assert isinstance(answer.status, sp.Status)


@FUZZ
@given(visit=st.one_of(_sets, st.lists(st.integers(-2, 6), max_size=4)), tolerance=st.one_of(st.none(), _floats),
       max_between=st.one_of(st.none(), st.integers(-1, 3)),
       objective=st.sampled_from(["contraction", "robust", "tolerance", "nope"]))
def test_fuzzed_patrols_answer_or_refuse_in_one_line(visit, tolerance, max_between, objective):
    answer = _answer_or_input_error(sp.patrol, _model("square"), visit, tolerance=tolerance, max_between=max_between,
                                    objective=objective)
    if answer is not None:
        assert isinstance(answer.status, sp.Status)


@pytest.mark.parametrize("trials", [0, -1, 10**30, 2.5, float("nan")])
def test_rollout_counts_are_checked(trials):
    plan = sp.find_plan(_model("square"), "e0", "e2")
    assert _answer_or_input_error(sp.simulate_plan, _model("square"), plan, trials=trials) is None
