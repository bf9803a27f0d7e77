"""Trust nothing read back (issue #27), on the command line: whatever the graph cache holds, an answer is the
answer without a cache, or a sound one — never a plan that fails; 8 processes can share one cache folder."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.bounce import _cache
from solverplan.bounce import bvg as bvg_api
from solverplan.certify import gate
from solverplan.certify.check import Failure
from solverplan.environment import load_environment
from tests.bounce.test_cache import TAMPERING, _safe_everywhere, _shifted, _widened
from tests.cache_entries import interval_rows, read_entry, with_sets, write_entry

runner = CliRunner()
QUERY = ["two_rooms", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1"]
ANSWERS = {"fewest": ["--objective", "fewest"], "tolerance": ["--objective", "tolerance"], "pareto": ["--pareto"]}


def answer(result) -> dict:
    """The JSON answer without its timings."""
    assert result.exit_code == 0, (result.exit_code, result.stderr)
    data = json.loads(result.stdout)
    data.pop("stats", None)
    for point in data.get("points", ()):
        point.get("plan", {}).pop("stats", None)
    return data


def run(*args: object, cache: Path | str = "off"):
    bvg_api.clear_graph_cache()  # each command line starts as a new process would: nothing in memory
    _cache._read_here.clear()
    return runner.invoke(cli.app, ["--graph-cache", str(cache), "--graph-cache-min-arcs", "0", *map(str, args)])


@pytest.fixture(scope="module")
def reference() -> dict[str, dict]:
    return {name: answer(run("plan", *QUERY, *extra)) for name, extra in ANSWERS.items()}


@pytest.fixture
def cache(tmp_path):
    folder = tmp_path / "graphs"
    yield folder
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(None)


def populate(cache: Path, extra: list[str]) -> list[Path]:
    first = run("plan", *QUERY, *extra, cache=cache)
    assert first.exit_code == 0, first.stderr
    entries = sorted(cache.glob("*.spg"))
    assert entries
    return entries


# ---------------------------------------------------------------------- an edited entry is a miss
@pytest.mark.parametrize("how", list(TAMPERING))
def test_a_tampered_entry_gives_the_answer_without_cache(reference, cache, how):
    entries = populate(cache, ANSWERS["tolerance"])
    tamper, why = TAMPERING[how]
    bvg_api.set_graph_cache(cache, min_arcs=0)  # for the tampering that builds another polygon's entry
    for entry in entries:
        tamper(entry, cache)
    size = ["--graph-cache-size", str(max(e.stat().st_size for e in entries) - 1)] if how == "a huge file" else []
    bvg_api.clear_graph_cache()
    _cache._read_here.clear()
    result = runner.invoke(cli.app, ["--graph-cache", str(cache), "--graph-cache-min-arcs", "0", *size, "plan", *QUERY,
                                     *ANSWERS["tolerance"], "-v"])
    assert answer(result) == reference["tolerance"]
    assert "graph cache: ignoring" in result.stderr and why in result.stderr
    assert "failed its exact check" not in result.stderr  # the cache's own checks caught it


# ---------------------------------------------------------------------- a resealed entry: the gate's job
def _resealed(edit):
    def tamper(cache: Path) -> None:
        for entry in cache.glob("*.spg"):
            header, arrays = read_entry(entry)
            arrays = edit(arrays)
            header["n_intervals"] = len(arrays["set_lo"])
            write_entry(entry, header, arrays)  # a digest that matches: the cache cannot tell

    return tamper


@pytest.mark.parametrize("kind", ["fewest", "pareto"])
def test_arcs_forged_safe_are_caught_by_the_exact_check_and_the_answer_recomputed(reference, cache, kind):
    """The issue's case, with the digest forged too: the planner takes arcs that are not safe, the exact checker
    refuses the plan, the forged entry is deleted and the answer is the one without a cache."""
    populate(cache, ANSWERS[kind])
    _resealed(_safe_everywhere)(cache)
    result = run("plan", *QUERY, *ANSWERS[kind], "-v", cache=cache)
    assert answer(result) == reference[kind]
    assert "failed its exact check" in result.stderr and "graph cache: deleted" in result.stderr
    again = run("plan", *QUERY, *ANSWERS[kind], "-vv", cache=cache)  # the rewritten entry is sound and read
    assert answer(again) == reference[kind]
    assert "graph cache: read" in again.stderr and "failed its exact check" not in again.stderr


FORGERIES = {
    "arcs made safe": _safe_everywhere,
    "arcs dropped": lambda a: with_sets(a, [rows[:0] if k % 3 == 0 else rows for k, rows in enumerate(interval_rows(a))]),
    "intervals widened": _widened,
    "intervals shifted": _shifted,
}


@pytest.mark.parametrize("how", list(FORGERIES))
@pytest.mark.parametrize("kind", ["fewest", "tolerance"])
def test_a_forged_entry_never_gives_a_plan_that_fails(cache, tmp_path, kind, how):
    """Whatever a forger puts in an entry, a plan that leaves is sound: its certificate verifies against the query
    (a forged entry may still cost optimality or claim "infeasible": docs/contract.md, *Graph cache and size*)."""
    populate(cache, ANSWERS[kind])
    _resealed(FORGERIES[how])(cache)
    cert = tmp_path / "plan.cert.json"
    result = run("plan", *QUERY, *ANSWERS[kind], "--certificate", cert, cache=cache)
    assert result.exit_code == 0, result.stderr
    if json.loads(result.stdout)["status"] == "found":
        check = runner.invoke(cli.app, ["verify", str(cert), "--env", "two_rooms", "--from", QUERY[2], "--to", QUERY[4]])
        assert check.exit_code == 0, check.stderr


def test_an_answer_that_fails_twice_is_never_given(cache, monkeypatch):
    populate(cache, ANSWERS["fewest"])
    bad = gate.check_certificate

    def refuse(cert, **query):
        report = bad(cert, **query)
        return type(report)(False, (Failure("stages[0].interval", "refused by the test"),), report.checked, (), report.kind)

    monkeypatch.setattr(gate, "check_certificate", refuse)
    result = run("plan", *QUERY, *ANSWERS["fewest"], cache=cache)
    assert result.exit_code == 1 and result.stdout == ""
    assert result.stderr.splitlines()[-1] == ("error: the plan failed its exact check, even with freshly built graphs: "
                                              "stages[0].interval: refused by the test")


# ---------------------------------------------------------------------- the gate in the library
def test_checked_answer_answers_again_without_cached_graphs_when_a_query_breaks_on_them(tmp_path):
    from solverplan.plan import find_plan

    env = load_environment("two_rooms")
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(tmp_path, min_arcs=0)
    try:
        find_plan(env, "e0", "e4")  # writes the entry
        bvg_api.clear_graph_cache()
        calls = []

        def compute():
            plan = find_plan(env, "e0", "e4")
            calls.append(plan)
            if len(calls) == 1:
                assert _cache.read_from_disk()
                raise IndexError("a forged graph broke the planner")
            return plan

        checked = gate.checked_answer(compute, env=env, start="e0", goal="e4")
        assert checked.retried and checked.checked == 1 and len(calls) == 2 and checked.certificate is not None
        assert not list(tmp_path.glob("*.spg")) or not _cache.read_from_disk()
        with pytest.raises(IndexError):  # with no graph read from disk, a bug is a bug: no second try
            gate.checked_answer(lambda: [][0], env=env)
    finally:
        bvg_api.clear_graph_cache()
        bvg_api.set_graph_cache(None)


def test_infeasible_answers_are_checked_through_their_certificates():
    """An answer that there is no plan leaves with its infeasibility certificate checked (#22), or unchecked with
    the reason when none can be made."""
    from solverplan.plan import find_plan

    env = load_environment("two_rooms")
    checked = gate.checked_answer(lambda: find_plan(env, "e0", "e4", max_bounces=1), env=env, start="e0", goal="e4")
    assert checked.answer.status.value == "infeasible"
    if checked.certificate is not None:
        assert checked.checked == 1 and checked.certificate.kind == "infeasible" and checked.unchecked is None
    else:
        assert checked.checked == 0 and "margin" in checked.unchecked


def test_an_answer_that_there_is_no_plan_made_with_cached_graphs_is_made_again_with_fresh_ones(tmp_path):
    """A forged entry that drops arcs gives a false "infeasible" that looks like a true one (and a certificate speaks
    of its own class of plans): so an answer that there is no plan never leaves on graphs read from disk alone."""
    from solverplan.plan import find_plan

    env = load_environment("two_rooms")
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(tmp_path, min_arcs=0)
    try:
        find_plan(env, "e0", "e4", max_bounces=1)  # writes the entry
        bvg_api.clear_graph_cache()
        calls = []

        def compute():
            calls.append(1)
            return find_plan(env, "e0", "e4", max_bounces=1)

        checked = gate.checked_answer(compute, env=env, start="e0", goal="e4")
        assert checked.answer.status.value == "infeasible" and checked.retried and len(calls) == 2
        plan = gate.checked_answer(lambda: find_plan(env, "e0", "e4"), env=env, start="e0", goal="e4")
        assert plan.answer.found and not plan.retried  # a plan is checked, not made twice
    finally:
        bvg_api.clear_graph_cache()
        bvg_api.set_graph_cache(None)


# ---------------------------------------------------------------------- many processes, one folder
def test_eight_processes_share_one_cache_folder(reference, tmp_path):
    folder = tmp_path / "shared"
    code = "import sys; from solverplan.cli import main; sys.argv[0] = 'solverplan'; main()"
    env = {**os.environ, "SOLVERPLAN_GRAPH_CACHE": str(folder), "SOLVERPLAN_GRAPH_CACHE_MIN_ARCS": "0"}
    procs = [subprocess.Popen([sys.executable, "-c", code, "plan", *QUERY, *ANSWERS["pareto"]], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(8)]
    outs = [p.communicate(timeout=120) for p in procs]
    assert [p.returncode for p in procs] == [0] * 8, [err for _, err in outs]
    assert all(err == "" for _, err in outs)
    answers = [json.loads(out) for out, _ in outs]
    for a in answers:
        a.pop("stats", None)
        for point in a["points"]:
            point["plan"].pop("stats", None)
    assert all(a == reference["pareto"] for a in answers)
    names = sorted(q.name for q in folder.iterdir())
    assert names and all(n.endswith(".spg") for n in names)  # no temporary file left behind
    again = run("plan", *QUERY, *ANSWERS["pareto"], "-vv", cache=folder)
    assert answer(again) == reference["pareto"] and "graph cache: read" in again.stderr


# ---------------------------------------------------------------------- cache info | clear
def test_cache_info_and_clear(cache):
    populate(cache, ANSWERS["fewest"])
    (cache / "notes.txt").write_text("not the cache's")
    info = run("cache", "info", cache=cache)
    assert info.exit_code == 0 and json.loads(info.stdout)["entries"] >= 1
    cleared = run("cache", "clear", cache=cache)
    assert cleared.exit_code == 0, cleared.stderr
    report = json.loads(cleared.stdout)
    assert report["removed"] >= 1 and report["entries"] == 0 and [q.name for q in cache.iterdir()] == ["notes.txt"]
    off = run("cache", "clear")
    assert off.exit_code == 2 and off.stdout == "" and off.stderr.count("\n") == 1
    assert off.stderr.startswith("error: the graph cache is off")
    bad = runner.invoke(cli.app, ["--graph-cache-size", "lots", "cache", "info"])
    assert bad.exit_code == 2 and "--graph-cache-size" in bad.stderr
