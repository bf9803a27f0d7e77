"""One verdict for every check (issue #23): every checker of every model answers with :class:`solverplan.Verdict`.

The checks: the exact checker of certificates (bounce kinds and every model's), the rooms answer check, the
ground-truth replay of pursuit plans and the flow-through test of a cell's field — each valid and each invalid.
Every one must expose the same protocol (``valid``, ``failures``, ``checked``, ``not_checked``, ``proved``,
``scope``, ``kind``), the same JSON key order and the same text layout.
"""

from __future__ import annotations

import copy
import json
import warnings
from fractions import Fraction

import pytest

import solverplan as sp
from solverplan.certify.schema import ModelCertificate, dumps_certificate, parse_certificate
from solverplan.verdict import VERDICT_KEYS, Failure, Verdict

ROOM = [[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]]  # a wall juts in from the right


def _centre(cell) -> tuple[Fraction, Fraction]:
    v = cell.vertices
    return (sum((p[0] for p in v), Fraction(0)) / len(v), sum((p[1] for p in v), Fraction(0)) / len(v))


def _tampered(cert: ModelCertificate, change) -> ModelCertificate:
    data = json.loads(dumps_certificate(cert))
    change(data["claims"])
    return parse_certificate(json.dumps(data))


def _plan(valid: bool) -> Verdict:
    env = sp.load_environment("l_shape")
    cert = sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env)
    return sp.check_certificate(cert) if valid else sp.check_certificate(cert, expected_goal=[(0, Fraction(0), Fraction(1, 5))])


def _bounce(kind: str, valid: bool) -> Verdict:
    """A funnel, localisation, patrol (cycle) or infeasibility certificate; checked against another environment when
    invalid."""
    env = sp.load_environment({"infeasible": "comb", "localize": "l_shape"}.get(kind, "square"))
    answer = {"funnel": lambda: sp.funnel(env, "e0", "e2"), "cycle": lambda: sp.patrol(env, [0, 2]),
              "localize": lambda: sp.localize(env, epsilon=1.0),
              "infeasible": lambda: sp.find_plan(env, "e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05", max_bounces=2)}[kind]()
    cert = sp.certificate(answer, env=env)
    assert cert.kind == kind
    other = sp.load_environment("square" if kind == "localize" else "l_shape")
    return sp.check_certificate(cert) if valid else sp.check_certificate(cert, expected_rings=other.rings)


def _model(kind: str, valid: bool) -> Verdict:
    from solverplan.explore import explore_depth_first
    from solverplan.wallfollow import cut_ordering, pursuit_plan

    if kind == "rooms":
        cert, change = sp.certificate(sp.decompose_rooms(sp.load_environment("three_chambers"))), \
            lambda c: c["doors"][0].update(length=str(Fraction(c["doors"][0]["length"]) + 1))
    elif kind == "exploration":
        env = sp.load_environment("two_holes")
        cert = sp.certificate(explore_depth_first(env, _centre(sp.decompose_free_space(env).cells[0])), env=env)
        change = lambda c: c.update(bound=c["bound"] - 1)  # noqa: E731
    elif kind == "cut-ordering":
        env = sp.load_environment("star")
        cert, change = sp.certificate(cut_ordering(env), env=env), lambda c: c["ordering"].reverse()
    elif kind == "pursuit":
        env = sp.Environment.from_coords(ROOM)
        cert, change = sp.certificate(pursuit_plan(env), env=env), lambda c: c.update(cleared_after=0)
    else:
        env = sp.load_environment("l_shape")
        cells = sp.decompose_free_space(env).cells
        cert = sp.certificate(sp.compose_fields(env, _centre(cells[0]), _centre(cells[-1])))
        change = lambda c: c["policies"][0].update(flows_through=not c["policies"][0].get("flows_through", True))  # noqa: E731
    assert isinstance(cert, ModelCertificate) and cert.kind == kind
    return sp.check_certificate(cert if valid else _tampered(cert, change))


def _rooms_answer(valid: bool) -> Verdict:
    from solverplan.certify.rooms_answer import check_rooms_answer

    env = sp.load_environment("three_chambers")
    answer = json.loads(json.dumps(sp.decompose_rooms(env).to_json()))
    if not valid:
        answer = copy.deepcopy(answer)
        answer["rooms"][0]["area_exact"] = "901"
    return check_rooms_answer(env, answer)


def _replay(valid: bool) -> Verdict:
    return sp.check_pursuit(sp.Environment.from_coords(ROOM), ["LFOLLOW" if valid else "RFOLLOW"])


def _square_cell():
    return sp.decompose_free_space(sp.load_environment("square")).cells[0]  # sides 0 … 3 from the bottom


def _line_flow(valid: bool, dense: bool = False) -> Verdict:
    from solverplan.reflection.fields import LineField, dense_flows_through

    cell = _square_cell()
    up = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, Fraction(3, 10))
    exits = {2} if valid else {3}
    return dense_flows_through(up, cell, exits, grid=6, per_side=6) if dense else sp.flows_through(up, cell, exits)


def _arc_flow(valid: bool) -> Verdict:
    from solverplan.reflection.fields import arc_turn

    cell = _square_cell()
    arc = arc_turn(cell, 0, 1, Fraction(1))
    assert arc is not None
    return sp.flows_through(arc, cell, {1} if valid else {3})


def _goal_flow(valid: bool) -> Verdict:
    from solverplan.reflection.fields import GoalField

    cell = _square_cell()
    return sp.flows_through(GoalField(_centre(cell) if valid else (Fraction(-1), Fraction(-1))), cell, set())


CHECKS = {
    "plan-certificate": _plan,
    **{f"{kind}-certificate": (lambda kind: lambda valid: _bounce(kind, valid))(kind)
       for kind in ("funnel", "localize", "cycle", "infeasible")},
    **{f"{kind}-certificate": (lambda kind: lambda valid: _model(kind, valid))(kind)
       for kind in ("rooms", "exploration", "cut-ordering", "pursuit", "fields")},
    "rooms-answer": _rooms_answer,
    "pursuit-replay": _replay,
    "line-flow-exact": _line_flow,
    "line-flow-sampled": lambda valid: _line_flow(valid, dense=True),
    "arc-flow": _arc_flow,
    "goal-flow": _goal_flow,
}


@pytest.mark.parametrize("valid", [True, False], ids=["valid", "invalid"])
@pytest.mark.parametrize("name", list(CHECKS))
def test_every_check_of_every_model_gives_the_one_verdict(name, valid):
    verdict = CHECKS[name](valid)
    assert isinstance(verdict, Verdict)
    assert verdict.valid is valid and verdict.valid == (not verdict.failures), [str(f) for f in verdict.failures]
    assert isinstance(verdict.kind, str) and verdict.kind and isinstance(verdict.scope, str) and verdict.scope
    assert all(isinstance(f, Failure) and f.claim and f.message for f in verdict.failures)
    assert all(isinstance(name, str) and isinstance(k, int) and k >= 0 for name, k in verdict.checked)
    assert all(isinstance(item, str) and item for item in (*verdict.not_checked, *verdict.proved))
    assert valid or not verdict.proved, "an invalid verdict proves nothing"

    data = json.loads(json.dumps(verdict.to_json()))  # plain JSON
    keys = list(data)
    assert keys[:2] == ["valid", "kind"] and keys[-5:] == list(VERDICT_KEYS[2:]), keys
    assert data["valid"] is valid and data["kind"] == verdict.kind and data["scope"] == verdict.scope
    assert data["failures"] == [{"claim": f.claim, "message": f.message} for f in verdict.failures]
    assert data["checked"] == dict(verdict.checked) and data["not_checked"] == list(verdict.not_checked)
    assert data["proved"] == list(verdict.proved)
    assert list(verdict.verdict_json()) == list(VERDICT_KEYS)
    assert verdict.verdict_json() == {key: data[key] for key in VERDICT_KEYS}

    lines = verdict.to_text().splitlines()
    assert lines[0] == f"{verdict.title}: {'VALID' if valid else 'INVALID'}"
    starts = [next(i for i, line in enumerate(lines) if line.startswith(prefix))
              for prefix in ("scope: ", "checked exactly: ")]
    assert starts[0] < starts[1] and lines[starts[0]] == f"scope: {verdict.scope}"
    tail = lines[starts[1] + 1:]  # proved, then FAIL, then not checked: nothing else
    expected = ([f"proved: {p}" for p in verdict.proved] + [f"FAIL {f}" for f in verdict.failures]
                + [f"not checked: {item}" for item in verdict.not_checked])
    assert tail == expected


def test_a_sampled_flow_through_is_never_stated_as_proved():
    check = _line_flow(True, dense=True)
    assert check.valid and check.method == "dense-sample" and not check.proved and not check.checked
    assert "a sample, not a proof" in check.not_checked[0]
    exact = _line_flow(True)
    assert exact.proved and dict(exact.checked)["side_ends"] == 6 and not exact.not_checked


def test_the_answers_carry_their_checks_verdicts():
    from solverplan.reflection.navigation import navigate_fields

    chase = sp.pursuit_plan(sp.Environment.from_coords(ROOM))
    assert chase.to_json()["verdict"] == chase.check.verdict_json() and chase.verified is chase.check.valid
    assert "pursuit replay from v0, 1 action: VALID" in chase.to_text()
    env = sp.load_environment("l_shape")
    cells = sp.decompose_free_space(env).cells
    answer = navigate_fields(env, _centre(cells[0]), _centre(cells[-1]), trials=1, scenarios=("constrained",))
    for entry in answer.to_json()["fields"]:
        assert list(entry["flow"])[:2] == ["valid", "kind"] and list(entry["flow"])[-5:] == list(VERDICT_KEYS[2:])


def test_verified_is_a_deprecated_name_of_valid():
    replay, flow = _replay(True), _line_flow(False)
    for check in (replay, flow):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert check.verified is check.valid
        assert caught and issubclass(caught[0].category, DeprecationWarning) and ".valid" in str(caught[0].message)


@pytest.mark.parametrize("args,fragment", [
    ((1, "cell", {1}), "checks a LineField, ArcField or GoalField, not int"),
    (("line", "cell", {1}), "not str"),
    (("field", None, {1}), "checks a convex Cell"),
    (("field", "cell", 2), "exits must be a set of side indices, not int"),
    (("field", "cell", {4}), "exit side 4 is not a side of cell 0 (sides 0 … 3)"),
    (("field", "cell", {True}), "exit side True is not a side"),
    (("field", "cell", {10**5000}), "exit side (an integer of about 5,000 digits)"),
])
def test_flows_through_says_in_one_line_what_it_cannot_check(args, fragment):
    from solverplan.reflection.fields import LineField

    cell = _square_cell()
    up = LineField(cell.sides[0].midpoint, cell.sides[2].midpoint, Fraction(3, 10))
    field, where, exits = args
    field = up if field == "field" else field
    where = cell if where == "cell" else where
    with pytest.raises(sp.InputError) as raised:
        sp.flows_through(field, where, exits)
    message = str(raised.value)
    assert fragment in message and "\n" not in message and len(message) < 200
