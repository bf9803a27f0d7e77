"""Every kind of answer of every model, through the registry (solverplan.answers): build → JSON (kind first, one key
order) → read back (the same JSON) → report (a well-formed page) → certificate → verify → tamper, wherever the
registry's hooks provide it (a kind whose certificate builder raises ``TypeError`` has none yet; this test picks up new
builders by itself)."""

from __future__ import annotations

import json
from html.parser import HTMLParser

import pytest

import solverplan as sp
from solverplan.answers import _SUMMARY_KEYS, KINDS, AnswerSummary, read_answer
from solverplan.errors import MalformedFile
from solverplan.certify.build import NothingToCertify
from solverplan.certify.schema import dumps_certificate, parse_certificate
from solverplan.render.report import AnswerFile, html_report
from solverplan.result import ANSWER_KEY_ORDER, Answer, Status, answer_kinds


def _plan():
    env = sp.load_environment("l_shape")
    return env, sp.find_plan(env, "e0:0.45:0.55", "e3")


def _pareto():
    env = sp.load_environment("l_shape")
    return env, sp.pareto_front(env, "e0:0.45:0.55", "e3", max_bounces=3)


def _patrol():
    env = sp.load_environment("square")
    return env, sp.patrol(env, "e0,e1,e2,e3", tolerance=0.05, epsilon=0.01)


def _funnel():
    env = sp.load_environment("square")
    return env, sp.funnel(env, "e0", "e2:0.4:0.6")


def _localize():
    env = sp.load_environment("l_shape")
    return env, sp.localize(env, epsilon=0.5)


def _cycle():
    env = sp.load_environment("square")
    return env, sp.limit_cycle(env, "tan:1/3", epsilon=0.01)


def _controller():
    env = sp.load_environment("l_shape")
    return env, sp.constant_controller(env)


def _rooms():
    from solverplan.rectilinear import decompose_rooms

    env = sp.load_environment("three_chambers")
    return env, decompose_rooms(env)


def _exploration():
    from solverplan.explore import explore_depth_first

    env = sp.load_environment("l_shape")
    return env, explore_depth_first(env, (1, "1/2"))


def _range_exploration():
    from solverplan.explore import explore_range_limited

    env = sp.load_environment("one_hole")
    return env, explore_range_limited(env, (1, 1), 4)


def _cut_ordering():
    from solverplan.wallfollow.cut import cut_ordering

    env = sp.load_environment("star")
    return env, cut_ordering(env)


def _learned_ordering():
    from solverplan.wallfollow.learning import learn_cut_ordering

    env = sp.load_environment("l_shape")
    return env, learn_cut_ordering(env, None, ("1", "0"), transcript=True)


def _vertex_count():
    from solverplan.wallfollow.filters import count_random_walk

    env = sp.load_environment("star")
    return env, count_random_walk(env, 200, 0)


def _pursuit():
    from solverplan.wallfollow.pursuit import pursuit_plan

    env = sp.load_environment("star")
    return env, pursuit_plan(env)


def _fields():
    from solverplan.reflection.navigation import navigate_fields

    env = sp.load_environment("serpentine")
    return env, navigate_fields(env, (3, "2.25"), (3, "0.25"), scenarios=("reflection",), trials=2, trajectories=1)


def _simulation():
    from solverplan.simulate import simulate_plan

    env, plan = _plan()
    return env, simulate_plan(env, plan, trials=20, seed=1)


def _rooms_runs(rule):
    from solverplan.rectilinear.simulation import compare_rules

    env, dec = _rooms()
    walk = dec.path(0, len(dec.rooms) - 1)
    rules = ("smart", "random", "billiard") if rule == "all" else (rule,)
    answer = compare_rules(dec, walk[0], walk[-1], rules=rules, trials=5, seed=0, max_bounces=200, walk=walk)
    return env, answer if rule == "all" else answer.runs[rule]


BUILDERS = {
    "plan": _plan, "pareto": _pareto, "patrol": _patrol, "funnel": _funnel, "localize": _localize, "cycle": _cycle,
    "controller": _controller, "rooms": _rooms, "exploration": _exploration, "range-exploration": _range_exploration,
    "cut-ordering": _cut_ordering, "learned-ordering": _learned_ordering, "vertex-count": _vertex_count,
    "pursuit": _pursuit, "fields": _fields, "simulation": _simulation,
    "rooms-simulation": lambda: _rooms_runs("smart"), "rooms-rules": lambda: _rooms_runs("all"),
}
# built elsewhere by their own tests (a study runs a pool of environments, an import needs a map file): they are in
# the registry and write their kind too (tests/studies, tests/floorplan)
ELSEWHERE = {"study", "import"}


def test_every_registered_kind_has_hooks_and_a_builder_here():
    assert set(KINDS) == set(answer_kinds())
    assert set(KINDS) == set(BUILDERS) | ELSEWHERE


class _Parser(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        for k, v in attrs:
            if k == "id" and v:
                self.ids.add(v)


@pytest.fixture(scope="module")
def built():
    cache = {}

    def get(kind):
        if kind not in cache:
            cache[kind] = BUILDERS[kind]()
        return cache[kind]

    return get


@pytest.mark.parametrize("kind", sorted(BUILDERS))
def test_answer_round_trip_report_and_certificate(kind, built, tmp_path):
    env, answer = built(kind)
    data = json.loads(json.dumps(answer.to_json()))  # what a file holds
    # the kind first, then the one key order: status next, the protocol's closing fields last
    keys = list(data)
    assert keys[0] == "kind" and data["kind"] == kind
    if "status" in data:
        assert keys[1] == "status"
    closing = [k for k in ANSWER_KEY_ORDER[-3:] if k in data and isinstance(data[k], dict)]
    if closing:
        assert keys[-len(closing):] == closing
    entry = KINDS[kind]
    if isinstance(answer, Answer):  # the protocol's one test of success, on every answer
        assert answer.found is (Status(answer.status) is Status.FOUND)
    # read back: the same JSON
    back = read_answer(data, env=env)
    if isinstance(back, AnswerSummary):  # a summary kind: the JSON, checked, under the class that wrote it
        assert back.kind == kind and back.source is type(answer)
        broken = {k: v for k, v in data.items() if k != list(_SUMMARY_KEYS[kind])[0]}
        with pytest.raises(MalformedFile, match=f"^{kind}: no "):
            read_answer(broken, env=env)
    else:
        assert type(back) is type(answer)
    assert json.loads(json.dumps(back.to_json())) == data
    # the report: a whole page with the picture or the numbers, made from the file's JSON
    page = html_report(AnswerFile(f"{kind}.json", kind, data), env, env_label=env.name)
    parser = _Parser()
    parser.feed(page.html)
    assert page.kind == kind and {"numbers", "reproduce"} <= parser.ids
    # the certificate, where the registry's builder makes one
    try:
        cert = entry.certificate(answer, env=env)
    except (TypeError, NothingToCertify):
        return
    report = entry.check(cert, expected_rings=env.rings)
    assert report.valid, report.failures
    text = dumps_certificate(cert)
    tampered = _tamper(json.loads(text))
    if tampered is not None:
        assert not entry.check(parse_certificate(json.dumps(tampered)), expected_rings=env.rings).valid


def _tamper(cert: dict) -> dict | None:
    """One claim changed: the first number the certificate claims (level by level through its claims) moved a little,
    or, where the claims hold no number, the first two names of a list swapped (an ordering)."""
    from fractions import Fraction

    def walk(node):
        items = list(node.items()) if isinstance(node, dict) else list(enumerate(node))
        for key, value in items:  # this level's numbers first, then deeper
            if isinstance(value, bool) or key in ("optimality", "objective", "method"):
                continue
            if isinstance(value, int):
                node[key] = value + 1
                return True
            if isinstance(value, str):
                try:
                    node[key] = str(Fraction(value) * Fraction(101, 100) + Fraction(1, 1000))
                    return True
                except (ValueError, ZeroDivisionError):
                    continue
        if any(isinstance(value, (dict, list)) and walk(value) for _, value in items):
            return True
        strings = [v for v in items if isinstance(v[1], str)]
        if isinstance(node, list) and len(strings) >= 2 and strings[0][1] != strings[1][1]:
            node[0], node[1] = node[1], node[0]
            return True
        return False

    claims = cert.get("claims")
    return cert if isinstance(claims, dict) and walk(claims) else None


def test_a_file_without_kind_or_of_an_unknown_kind_is_refused():
    from solverplan.errors import MalformedFile

    with pytest.raises(MalformedFile, match="expected a JSON object whose 'kind' says what it is"):
        read_answer({"status": "found"})
    with pytest.raises(MalformedFile, match="unknown answer kind 'teleport'"):
        read_answer({"kind": "teleport"})
    with pytest.raises(MalformedFile, match="^simulation: no 'environment'"):
        read_answer({"kind": "simulation"})


def test_kinds_that_name_edges_need_their_environment(built):
    from solverplan.errors import InputError

    _env, patrol = built("patrol")
    with pytest.raises(InputError, match="read back in its environment"):
        read_answer(patrol.to_json())
    with pytest.raises(InputError, match="another environment"):
        read_answer(patrol.to_json(), env=sp.load_environment("l_shape"))


def test_a_fields_answer_of_the_former_flow_shape_reads_back():
    """Answers written before the one verdict shape carried ``"verified"`` in each cell's ``flow``: they read back."""
    env, answer = _fields()
    data = json.loads(json.dumps(answer.to_json()))

    def old_shape(value):
        if isinstance(value, list):
            return [old_shape(v) for v in value]
        if isinstance(value, dict):
            return {k: ({"verified": v["valid"], "method": "exact"} if k == "flow" else old_shape(v))
                    for k, v in value.items()}
        return value

    old = old_shape(data)
    assert "verified" in json.dumps(old["fields"])
    back = read_answer(old, env=env)
    assert back.kind == "fields" and back.status == answer.status
