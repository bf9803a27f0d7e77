"""``timeout=``: every search stops at its deadline with a sound answer (its incumbent or not-found), the bound it
had proved, ``proved`` false and the timeout in ``optimality.limits``; bad timeouts are refused; no timeout
changes nothing.

The cuts are made deterministic by a deadline that expires at its n-th check instead of on the clock
(:class:`AfterChecks`), so every search is cut at every stage it can be cut; a few tests use the real clock with
generous bounds (never asserting timings tightly).
"""

from __future__ import annotations

import math
import time

import pytest

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.certify.build import certificate
from solverplan.certify.check import check_certificate
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.models import load as load_model
from solverplan.plan import find_plan, pareto_front
from solverplan.plan._deadline import NEVER, Deadline, check_timeout, deadline_of
from solverplan.plan.funnels import funnel
from solverplan.plan.localization import localize
from solverplan.plan.patrols import patrol
from solverplan.result import Status

EPS = 1e-9


class AfterChecks(Deadline):
    """A deadline that expires at its ``n``-th check (0: at once) and counts the checks made."""

    __slots__ = ("n", "checks")

    def __init__(self, n: float) -> None:
        super().__init__(1.0)  # the seconds its limit text shows
        self.n, self.checks = n, 0

    def expired(self) -> bool:
        self.checks += 1
        if self.checks > self.n:
            self.hit = True
        return self.hit


def _checks(solve) -> int:
    """How many times a search asks its deadline when it is never cut."""
    counter = AfterChecks(math.inf)
    solve(counter)
    return counter.checks


def _cuts(total: int, most: int = 12) -> list[int]:
    step = max(1, total // most)
    return sorted({*range(0, total, step), total - 1}) if total else [0]


def _same(a, b) -> bool:
    ja, jb = a.to_json(), b.to_json()
    ja.pop("stats", None)
    jb.pop("stats", None)
    return ja == jb


ELL = Environment.from_coords([[0, 0], [8, 0], [8, 4], [4, 4], [4, 8], [0, 8]], name="ell")


@pytest.fixture(scope="module")
def ell_graph():
    return safe_bounce_visibility_graph(ELL)


@pytest.fixture(scope="module")
def rooms():
    env = load_model("two_rooms")
    return env, safe_bounce_visibility_graph(env)


# ---------------------------------------------------------------------- the deadline itself
@pytest.mark.parametrize("bad", [0, 0.0, -1, -1e-9, math.nan, math.inf, -math.inf, True, "1", [1], 10**400])
def test_bad_timeouts_are_refused_in_one_line(bad):
    with pytest.raises(InputError, match="timeout") as info:
        check_timeout(bad)
    assert "\n" not in str(info.value) and len(str(info.value)) < 200


def test_good_timeouts_and_none():
    assert check_timeout(None) is None and check_timeout(2) == 2.0 and check_timeout(1e-6) == 1e-6
    assert deadline_of(None) is NEVER and not NEVER.expired() and NEVER.remaining() is None
    d = deadline_of(60)
    assert not d.expired() and 0 < d.remaining() <= 60 and deadline_of(d) is d


def test_a_deadline_stays_expired():
    d = Deadline(1e-4)
    time.sleep(0.002)
    assert d.expired() and d.hit and d.expired() and d.remaining() == 0.0
    assert d.limit("3 beliefs") == "timeout 0.0001 s reached after 3 beliefs"


@pytest.mark.parametrize("call", [
    lambda t: find_plan(ELL, "e5", "e0", timeout=t),
    lambda t: pareto_front(ELL, "e5", "e0", timeout=t),
    lambda t: patrol(ELL, "e0,e1", timeout=t),
    lambda t: funnel(ELL, "e0", "e2", timeout=t),
    lambda t: localize(ELL, 0.5, timeout=t),
], ids=["find_plan", "pareto_front", "patrol", "funnel", "localize"])
@pytest.mark.parametrize("bad", [0, -2.5, math.nan])
def test_every_entry_point_refuses_bad_timeouts(call, bad):
    with pytest.raises(InputError, match="timeout"):
        call(bad)


# ---------------------------------------------------------------------- no timeout changes nothing
@pytest.mark.parametrize("objective,k", [("fewest", None), ("tolerance", None), ("tolerance", 6), ("sum", 4),
                                         ("constant", None)])
def test_a_generous_timeout_changes_nothing(ell_graph, objective, k):
    plain = find_plan(ELL, "e5", "e0:0:0.3", objective=objective, max_bounces=k, graph=ell_graph)
    timed = find_plan(ELL, "e5", "e0:0:0.3", objective=objective, max_bounces=k, graph=ell_graph, timeout=600)
    assert plain.found and _same(plain, timed) and timed.optimality.proved and not timed.optimality.limits


def test_a_generous_timeout_changes_nothing_for_the_others(ell_graph):
    assert _same(pareto_front(ELL, "e5", "e0:0:0.3", graph=ell_graph),
                 pareto_front(ELL, "e5", "e0:0:0.3", graph=ell_graph, timeout=600))
    sq = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
    assert _same(patrol(sq, "e0,e1,e2,e3", tolerance=0.05), patrol(sq, "e0,e1,e2,e3", tolerance=0.05, timeout=600))
    assert _same(funnel(sq, "e0", "e2:0.45:0.55", tolerance=0.005),
                 funnel(sq, "e0", "e2:0.45:0.55", tolerance=0.005, timeout=600))


# ---------------------------------------------------------------------- every cut is sound
def _check_cut(plan, full, env, graph):
    """A cut plan: not proved, the timeout named, a sound incumbent or not-found, a bound the optimum obeys."""
    opt = plan.optimality
    assert not opt.proved and opt.limits and opt.limits[-1].startswith("timeout 1 s reached after")
    best = full.value
    if plan.found:
        assert plan.status is Status.FOUND
        assert check_certificate(certificate(plan, env=env, partition=graph.partition)).valid
        if plan.objective == "fewest":
            assert plan.value >= best
        else:
            assert plan.value <= best + EPS
    else:
        assert plan.status is Status.NOT_FOUND and "timeout" in plan.reason and "not a proof" in plan.reason
    if opt.bound is not None:
        if plan.objective == "fewest":
            assert opt.bound <= best  # a lower bound on the bounces
        else:
            assert opt.bound >= best - EPS  # an upper bound on the width or the sum
        if plan.found:
            assert opt.gap == pytest.approx(abs(plan.value - opt.bound))


QUERIES = [
    ("ell", "e5", "e0:0:0.3", "fewest", None),
    ("ell", "e5", "e0:0:0.3", "tolerance", None),
    ("ell", "e5", "e0:0:0.3", "tolerance", 6),
    ("ell", "e5", "e0:0:0.3", "sum", 4),
    ("ell", "e5", "e0:0:0.3", "constant", None),
    ("rooms", "e0", "e4", "fewest", None),  # the start spans several segments: belief searches (A*, bounds)
    ("rooms", "e0", "e4", "tolerance", None),
    ("rooms", "e0", "e4", "tolerance", 8),
    ("rooms", "e0", "e4", "constant", None),
]


@pytest.mark.parametrize("where,start,goal,objective,k", QUERIES, ids=[f"{q[0]}-{q[3]}-{q[4]}" for q in QUERIES])
def test_every_cut_of_every_search_is_sound(where, start, goal, objective, k, ell_graph, rooms):
    env, graph = (ELL, ell_graph) if where == "ell" else rooms
    full = find_plan(env, start, goal, objective=objective, max_bounces=k, graph=graph)
    assert full.found and full.optimality.proved

    def solve(deadline):
        return find_plan(env, start, goal, objective=objective, max_bounces=k, graph=graph, timeout=deadline)

    total = _checks(solve)
    assert total >= 1
    outcomes = set()
    for n in _cuts(total):
        plan = solve(AfterChecks(n))
        _check_cut(plan, full, env, graph)
        outcomes.add(plan.status)
    assert Status.NOT_FOUND in outcomes  # the first cut has nothing yet
    assert _same(solve(AfterChecks(total)), full)  # a deadline never reached changes nothing


def test_a_cut_tolerance_search_answers_its_incumbent(ell_graph):
    """The L-shape's front is 1 bounce at 0.29 rad, 5 bounces at 0.46: a cut after the first point answers it."""
    def solve(deadline):
        return find_plan(ELL, "e5", "e0:0:0.3", objective="tolerance", max_bounces=6, graph=ell_graph, timeout=deadline)

    total = _checks(solve)
    incumbents = [p for p in (solve(AfterChecks(n)) for n in range(total)) if p.found]
    assert incumbents, "some cut comes after the one-bounce plan"
    one = incumbents[0]
    assert one.bounces == 1 and one.min_width == pytest.approx(0.2903, abs=1e-4)
    assert one.optimality.bound >= 0.4625 and not one.optimality.proved


def test_a_cut_pareto_front_keeps_its_exact_points(ell_graph):
    full = pareto_front(ELL, "e5", "e0:0:0.3", graph=ell_graph)

    def solve(deadline):
        return pareto_front(ELL, "e5", "e0:0:0.3", graph=ell_graph, timeout=deadline)

    total = _checks(solve)
    seen_partial = False
    for n in range(total):
        front = solve(AfterChecks(n))
        opt = front.optimality
        assert not opt.proved and opt.limits[0].startswith("timeout")
        assert [(p.bounces, p.min_width) for p in front.points] == [(p.bounces, p.min_width)
                                                                    for p in full.points[:len(front.points)]]
        assert all(p.plan.optimality.proved for p in front.points)  # each point is still the best within its k
        assert front.status is (Status.FOUND if front.points else Status.NOT_FOUND)
        if opt.bound is not None:
            assert opt.bound >= full.points[-1].min_width - EPS
        seen_partial |= 0 < len(front.points) < len(full.points)
    assert seen_partial


# ---------------------------------------------------------------------- the other searches
def test_a_cut_patrol_is_not_proved(rooms):
    env, graph = rooms
    full = patrol(env, "e0,e4", start="e2", objective="tolerance", graph=graph)
    assert full.found and full.optimality.proved

    def solve(deadline):
        return patrol(env, "e0,e4", start="e2", objective="tolerance", graph=graph, timeout=deadline)

    total = _checks(solve)
    for n in _cuts(total, 8):
        p = solve(AfterChecks(n))
        assert not p.optimality.proved and any(x.startswith("timeout") for x in p.optimality.limits)
        assert p.status in (Status.FOUND, Status.NOT_FOUND)
        if p.found:  # the bracket reached: its feasible end is a tolerance that works, its upper end a bound
            assert p.tolerance <= full.optimality.bound + EPS
            assert p.optimality.bound >= full.tolerance - EPS
            assert check_certificate(certificate(p, env=env, partition=graph.partition)).valid


@pytest.mark.parametrize("which", ["funnel", "localize"])
def test_a_cut_position_search_is_not_found(which):
    sq = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
    tri = Environment.from_coords([[0, 0], [10, 0], [3, 7]], name="triangle")

    def solve(deadline):
        if which == "funnel":
            return funnel(sq, "e0", "e2:0.45:0.55", tolerance=0.005, timeout=deadline)
        return localize(tri, 0.05, start="e0", tolerance=0.002, timeout=deadline)

    full = solve(None)
    assert full.found
    total = _checks(solve)
    assert total > 3
    for n in _cuts(total, 6):
        r = solve(AfterChecks(n))
        assert r.status is Status.NOT_FOUND and "timeout" in r.reason
        assert r.optimality.limits[-1].startswith("timeout") and not r.optimality.proved
    assert _same(solve(AfterChecks(total)), full)


# ---------------------------------------------------------------------- the real clock
def test_a_real_timeout_returns_soon_with_an_honest_answer():
    """The 100-vertex star of the benchmarks, a belief tolerance query: the graph build alone takes longer than
    the timeout, so the search stops at once; whatever the machine, the answer comes back within seconds."""
    from solverplan.generators import star_polygon

    env = star_polygon(100, 0.2, 0.3, seed=1)
    t0 = time.monotonic()
    plan = find_plan(env, "e45,e94", "e88", objective="tolerance", timeout=0.02)
    assert time.monotonic() - t0 < 30
    assert plan.status is Status.NOT_FOUND and not plan.optimality.proved
    (limit,) = plan.optimality.limits  # cut inside the build (#24), or after it when the graph was cached
    assert limit.startswith("timeout 0.02 s reached after ")
    assert limit.endswith(", while building the query's graph") or limit.endswith("building the safe BVG and the query")


def test_a_real_timeout_cuts_a_long_localisation():
    """Localisation from the whole boundary of the two-room model searches for many seconds without a timeout."""
    env, graph = load_model("two_rooms"), None
    t0 = time.monotonic()
    loc = localize(env, 0.05, timeout=0.5, graph=graph)
    elapsed = time.monotonic() - t0
    assert elapsed < 30
    if loc.optimality.limits and loc.optimality.limits[-1].startswith("timeout"):
        assert loc.status is Status.NOT_FOUND and not loc.optimality.proved
    else:  # the search ended by itself first: then it obeys its other caps
        assert loc.status in (Status.FOUND, Status.NOT_FOUND, Status.INFEASIBLE)


# ---------------------------------------------------------------------- the timeout covers the graph build (#24)
def test_a_timeout_during_the_partition_answers_not_found_not_proved():
    """The deadline stops the partition of the boundary between reflex vertices: the query answers at once."""
    import time

    from solverplan.bounce import _cache
    from solverplan.generators import star_polygon
    from solverplan.plan.search import find_plan, pareto_front

    env = star_polygon(400, 0.3, 0.3, seed=11)
    _cache.clear_graph_cache()
    started = time.monotonic()
    plan = find_plan(env, "e0", "e200", objective="tolerance", timeout=0.05)
    front = pareto_front(env, "e0", "e200", timeout=0.05)
    assert time.monotonic() - started < 5.0  # the whole partition of 400 vertices takes longer than this
    for answer in (plan, front):
        assert answer.optimality.proved is False
        assert any("while building the query's graph" in limit for limit in answer.optimality.limits)
    assert plan.status.value == "not-found" and plan.stages == ()
    assert "before any plan was found: not a proof" in plan.reason
    assert front.points == () and "timeout 0.05 s" in front.reason


def test_the_cli_timeout_counts_from_the_process_start():
    """--timeout is the whole command's: the library's deadline is what is left of it, named as the user gave it."""
    from solverplan.cli._options import _ANSWER_RESERVE, _STARTED, command_timeout

    budget = 3600.0
    deadline = command_timeout(budget)
    assert deadline.seconds == budget  # the answer's limit names the user's timeout
    left = deadline.remaining()
    assert left is not None and 0 < left <= budget - _ANSWER_RESERVE - time_since(_STARTED)
    assert command_timeout(1e-6).remaining() <= 1e-3  # a test process older than the timeout: stop at once
    assert command_timeout(None) is None


def time_since(moment: float) -> float:
    import time

    return time.monotonic() - moment - 0.01  # the clock moved on between the two reads
