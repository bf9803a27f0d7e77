"""Certified negative answers and bounds (issue #22): the invariant over belief states, its exact checker
(solverplan/certify/invariant.py, check.py §10), the planner-side builder (certify/negative.py, build.py) and
what is rejected when any part of an invariant is tampered with."""

from __future__ import annotations

import copy
import math
import random
from fractions import Fraction

import pytest
from hypothesis import given, settings, strategies as st

from solverplan.certify import NothingToCertify, certificate, check_certificate
from solverplan.certify.invariant import Closure, Geometry, TableError
from solverplan.certify.invariant import next_belief
from solverplan.certify.negative import NoBound, bound_claim, refined_table, segment_table, _edges
from solverplan.certify.schema import Certificate, CertificateFormatError, parse_certificate, dumps_certificate
from solverplan.environment import load_environment
from solverplan.plan import find_plan, pareto_front
from solverplan.generators import star_polygon
from tests.certify.cases import MODELS

COMB = load_environment(MODELS / "comb.json")
TWO_ROOMS = load_environment(MODELS / "two_rooms.json")
SETS = ("e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05")  # the sets of the issue's queries


def data_of(cert: Certificate) -> dict:
    return copy.deepcopy(cert.to_json())


def check(data: dict):
    return check_certificate(Certificate.from_json(data))


def assert_rejected(data: dict, claim: str, fragment: str) -> None:
    report = check(data)
    assert not report.valid, "a tampered invariant was accepted"
    first = report.failures[0]
    assert first.claim == claim and fragment in first.message, str(first)


@pytest.fixture(scope="module")
def comb_infeasible() -> Certificate:
    front = pareto_front(COMB, *SETS, max_bounces=4)
    assert not front.points and front.optimality.proved
    return certificate(front, env=COMB)


@pytest.fixture(scope="module")
def fewest_plan():
    plan = find_plan(TWO_ROOMS, "e0:0.2:0.8", "e4:0.5:1")
    assert plan.bounces == 3
    return plan


# ---------------------------------------------------------------------- infeasible answers certify
def test_infeasible_front_on_comb_certifies_and_says_what_it_proves(comb_infeasible):
    cert = comb_infeasible
    assert cert.kind == "infeasible" and cert.stages == () and cert.bound.budget == 4 and cert.bound.threshold == 0
    assert cert.bound.heading_margin == Fraction(1, 1000)
    report = check_certificate(cert)
    assert report.valid, [str(f) for f in report.failures]
    assert report.proved[0].startswith("no plan with at most 4 stages takes the start set to the goal set")
    assert "P′ of the straight walls" in report.proved[0] and "δ = 0.001 rad" in report.proved[0]
    assert dict(report.checked)["bound_beliefs"] > 0 and not report.not_checked
    text = report.to_text()
    assert "certificate (infeasible): VALID" in text and "proved: no plan with at most 4 stages" in text
    assert parse_certificate(dumps_certificate(cert)) == cert  # JSON round trip, version 3


def test_infeasible_plan_within_a_budget_certifies():
    plan = find_plan(TWO_ROOMS, "e0", "e4", max_bounces=2)
    assert plan.status.value == "infeasible"
    cert = certificate(plan, env=TWO_ROOMS)
    assert cert.kind == "infeasible" and cert.bound.budget == 2 and cert.claims.objective == "fewest"
    assert check_certificate(cert).valid
    env = TWO_ROOMS
    pinned = check_certificate(cert, expected_rings=env.rings, expected_start=[(0, Fraction(0), Fraction(1))],
                               expected_goal=[(4, Fraction(0), Fraction(1))])
    assert pinned.valid


@pytest.mark.parametrize("model", ["worst_case_t4", "l_shape"])
def test_issue_22_infeasible_answers_that_hold_only_within_the_planners_margins_get_no_certificate(model):
    """Over the exact, margin-free class on P′ refined at the query's set ends a 4-stage plan exists; where the planner
    still says infeasible (worst_case_t4: the margin-free plan is 0.00053 rad wide, below the planner's margins) there
    is nothing a certificate could prove. (l_shape: the planner finds its plan now, by landing units.)"""
    env = load_environment(MODELS / f"{model}.json")
    start, goal = (env.boundary_set(s) for s in SETS)
    with pytest.raises(NoBound, match="a margin-free plan of 4 stages exists"):
        bound_claim(env, start, goal, budget=4, heading_margin=Fraction(1, 1000))
    front = pareto_front(env, *SETS, max_bounces=4)
    if not front.points:  # the planner's own answer, within its margins
        with pytest.raises(NothingToCertify, match=r"infeasible within 4 bounces only within the planner's corner "
                                                   r"clearance, safe margin, corner rule or landing units"):
            certificate(front, env=env)


def test_a_timeout_is_still_nothing_to_certify():
    plan = find_plan(TWO_ROOMS, "e0", "e4", max_bounces=2)
    from dataclasses import replace

    from solverplan.result import Status

    stopped = replace(plan, status=Status.NOT_FOUND)
    with pytest.raises(NothingToCertify, match="not a proof that there is no plan"):
        certificate(stopped, env=TWO_ROOMS)


# ---------------------------------------------------------------------- bounds attached to plans
def test_fewest_plan_carries_a_bound_proving_no_plan_has_fewer_bounces(fewest_plan):
    cert = certificate(fewest_plan, env=TWO_ROOMS)
    assert cert.bound is not None and cert.bound.budget == 2 and cert.bound.threshold == 0
    report = check_certificate(cert)
    assert report.valid, [str(f) for f in report.failures]
    assert report.proved[-1] == "hence every such plan has at least 3 bounces: this plan's 3 is the fewest"
    assert not any("not re-derived" in item for item in report.not_checked)
    stripped = data_of(cert)
    del stripped["bound"]
    plain = check(stripped)
    assert plain.valid and any("not re-derived" in item for item in plain.not_checked)
    assert [p.split(";")[0] for p in plain.proved] == ["from every point of the start set, executing at stage j any heading "
                                                        "inside its interval lands the robot in the goal set after 3 bounces"]


def test_fewest_bound_must_be_below_the_plans_bounces(fewest_plan):
    data = data_of(certificate(fewest_plan, env=TWO_ROOMS))
    data["bound"]["budget"] = 3
    report = check(data)
    assert not report.valid  # the beliefs at depth 2 are not closed, and K = 3 cannot be below 3 anyway
    data["bound"]["threshold"] = "1/100"
    data["bound"]["budget"] = 2
    assert_rejected(data, "bound.threshold", "a bound on the fewest bounces is about every plan")


def test_tolerance_plan_bound_states_its_gap():
    plan = find_plan(TWO_ROOMS, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")
    cert = certificate(plan, env=TWO_ROOMS)
    assert cert.bound is not None and cert.bound.budget is None
    gap = cert.bound.threshold - cert.claims.min_width
    assert 0 < gap < Fraction(1, 1000)
    report = check_certificate(cert)
    assert report.valid, [str(f) for f in report.failures]
    assert "has min width ≤" in report.proved[-1] and "optimal to within 0.0002" in report.proved[-1]
    assert any("re-derived only to within" in item for item in report.not_checked)
    data = data_of(cert)
    data["bound"]["threshold"] = str(cert.claims.min_width - Fraction(1, 10**6))
    report = check(data)  # the plan itself is in the class now: the invariant is not closed (so w is never reached)
    assert not report.valid and report.failures[0].claim.startswith("bound.beliefs[")
    assert "the invariant is not closed" in report.failures[0].message


# ---------------------------------------------------------------------- mutations are rejected
def test_dropping_a_belief_breaks_the_invariant(comb_infeasible):
    data = data_of(comb_infeasible)
    depth1 = [i for i, b in enumerate(data["bound"]["beliefs"]) if b["depth"] == 1]
    assert depth1
    del data["bound"]["beliefs"][depth1[0]]
    assert_rejected(data, "bound.beliefs[0]", "contains no listed belief of depth ≤ 1: the invariant is not closed")


def test_changing_a_depth_breaks_the_invariant(comb_infeasible):
    data = data_of(comb_infeasible)
    for b in data["bound"]["beliefs"]:
        if b["depth"] == 1:
            b["depth"] = 3
    assert_rejected(data, "bound.beliefs[0]", "of depth ≤ 1")
    data = data_of(comb_infeasible)
    data["bound"]["beliefs"][0]["depth"] = 1
    assert_rejected(data, "bound.beliefs[0].depth", "the start belief has depth 1, not 0")


def test_raising_the_budget_breaks_the_invariant(comb_infeasible):
    data = data_of(comb_infeasible)
    data["bound"]["budget"] = 5
    report = check(data)
    assert not report.valid and report.failures[0].claim.startswith("bound.beliefs[")
    data["bound"]["budget"] = None  # unbounded: the listed beliefs are not closed under every successor
    assert not check(data).valid


def test_lowering_the_heading_margin_or_the_threshold_below_zero(comb_infeasible):
    data = data_of(comb_infeasible)
    data["bound"]["threshold"] = "-1/1000"
    assert_rejected(data, "bound.threshold", "< 0")
    data = data_of(comb_infeasible)
    data["bound"]["heading_margin"] = "-0.001"
    assert_rejected(data, "bound.heading_margin", "is not in [0, 3/4)")


def test_a_larger_threshold_or_heading_margin_is_a_weaker_statement_and_stays_true(comb_infeasible):
    """Excluding fewer plans is still a true statement: the checker accepts it, and the report says exactly it."""
    data = data_of(comb_infeasible)
    data["bound"]["heading_margin"] = "0.01"
    data["bound"]["threshold"] = "0.001"
    report = check(data)
    assert report.valid and "width > 0.001 rad" in report.proved[0] and "δ = 0.01 rad" in report.proved[0]


def test_a_smaller_heading_margin_admits_more_stages_and_is_checked():
    """On two_rooms e0 → e4 the invariant of δ = 0.001 is not closed for δ = 0 only if a stage needs the last
    milliradian; either way the checker decides it exactly — here by re-deriving the closure for δ = 0."""
    plan = find_plan(TWO_ROOMS, "e0", "e4", max_bounces=2)
    data = data_of(certificate(plan, env=TWO_ROOMS))
    data["bound"]["heading_margin"] = 0
    env = TWO_ROOMS
    try:
        bound_claim(env, env.boundary_set("e0"), env.boundary_set("e4"), budget=2, heading_margin=Fraction(0))
        closed = True
    except NoBound:
        closed = False
    report = check(data)
    if report.valid:
        assert closed
    else:
        assert report.failures[0].claim.startswith("bound.beliefs[")


def test_changing_the_start_or_the_goal_set(comb_infeasible):
    data = data_of(comb_infeasible)
    data["start"][0]["t0"] = "0.2"
    assert_rejected(data, "bound.beliefs[0].segments", "but the start set is")
    data = data_of(comb_infeasible)
    data["goal"] = [{"edge": 3, "t0": 0, "t1": 1}, {"edge": 4, "t0": 0, "t1": 1}]  # the goal grows over the start
    report = check(data)
    assert not report.valid and report.failures[0].claim in ("start", "bound.beliefs[0]")
    data = data_of(comb_infeasible)
    data["goal"] = [{"edge": e, "t0": 0, "t1": 1} for e in range(COMB.n_edges) if e not in (3, 4)]
    assert_rejected(data, "bound.beliefs[0]", "has a goal stage")


def test_moving_a_segment_end(comb_infeasible):
    data = data_of(comb_infeasible)
    table = data["bound"]["table"]
    k = next(i for i, seg in enumerate(table) if len(seg) == 1 and seg[0][2] != 1)
    table[k][0][2] = str(Fraction(str(table[k][0][2])) + Fraction(1, 1000))
    report = check(data)
    assert not report.valid and report.failures[0].claim == "bound.table" and "overlaps" in report.failures[0].message


def test_table_must_be_contiguous_and_straight():
    env = load_environment(MODELS / "square.json")
    edges, nxt = _edges(env)
    one = Fraction(1)
    with pytest.raises(TableError, match="turn at their shared vertex: a segment is straight"):
        Geometry(edges, nxt, [[(0, Fraction(0), one), (1, Fraction(0), one)], [(2, Fraction(0), one)], [(3, Fraction(0), one)]])
    with pytest.raises(TableError, match="edge 3 is covered only up to t = 1/2"):
        Geometry(edges, nxt, [[(0, Fraction(0), one)], [(1, Fraction(0), one)], [(2, Fraction(0), one)],
                              [(3, Fraction(0), Fraction(1, 2))]])
    with pytest.raises(TableError, match="does not continue piece 0"):
        Geometry(edges, nxt, [[(0, Fraction(0), Fraction(1, 2)), (1, Fraction(0), one)], [(0, Fraction(1, 2), one)],
                              [(2, Fraction(0), one)], [(3, Fraction(0), one)]])
    # across a collinear vertex a segment may run over two edges
    split = load_environment(MODELS / "square.json").__class__.from_coords([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]])
    e2, n2 = _edges(split)
    geo = Geometry(e2, n2, [[(0, Fraction(0), one), (1, Fraction(0), one)], [(2, Fraction(0), one)],
                            [(3, Fraction(0), one)], [(4, Fraction(0), one)]])
    assert geo.segment_of(0, one) == 0 and geo.segment_of(2, Fraction(0)) is None


def test_a_malformed_bound_block_is_a_format_error(comb_infeasible):
    from solverplan.certify.schema import CertificateFormatError

    data = data_of(comb_infeasible)
    data["bound"]["table"][0][0] = [0, 0]
    with pytest.raises(CertificateFormatError, match=r"^bound\.table\[0\]\[0\]: expected a piece \[edge, t0, t1\]"):
        Certificate.from_json(data)
    data = data_of(comb_infeasible)
    del data["bound"]
    with pytest.raises(CertificateFormatError, match="an infeasible certificate needs the bound block"):
        Certificate.from_json(data)
    data = data_of(comb_infeasible)
    data["version"] = 2
    with pytest.raises(CertificateFormatError, match="unknown field 'bound'"):
        Certificate.from_json(data)


# ---------------------------------------------------------------------- the engine against ground truths
def _cast(edges, o, d):
    best = (math.inf, None, None)
    for i, (p, q) in enumerate(edges):
        f = (q[0] - p[0], q[1] - p[1])
        den = d[0] * f[1] - d[1] * f[0]
        if abs(den) < 1e-15:
            continue
        pm = (p[0] - o[0], p[1] - o[1])
        mu, u = (pm[0] * f[1] - pm[1] * f[0]) / den, (pm[0] * d[1] - pm[1] * d[0]) / den
        if mu > 1e-9 and -1e-12 <= u <= 1 + 1e-12 and mu < best[0]:
            best = (mu, i, u)
    return best


def _sampled_landings(env, table, groups=(), *, samples: int, margin: float, seed: int):
    """For every single-segment successor of the exact engine: (its runs, the table segments float rays from
    ``samples`` sampled positions and headings land on, None at a segment end). Positions stay ``margin`` (a fraction)
    inside the source, headings 2 % inside the successor's interval."""
    edges, nxt = _edges(env)
    geo = Geometry(edges, nxt, table, groups)
    closure = Closure(geo, Fraction(1, 1000), Fraction(0))
    fedges = [((float(a[0]), float(a[1])), (float(b[0]), float(b[1]))) for a, b in edges]
    rng = random.Random(seed)
    out = []
    for s in range(len(table)):
        a, b = geo.ends[s]
        A, B = (float(a[0]), float(a[1])), (float(b[0]), float(b[1]))
        E = (B[0] - A[0], B[1] - A[1])
        L = math.hypot(*E)
        for (targets, (lo, hi)) in closure.successors((s,)):
            l, h = math.atan2(lo[1], lo[0]), math.atan2(hi[1], hi[0])
            met = []
            for _ in range(samples):
                lam, th = rng.uniform(margin, 1 - margin), rng.uniform(l + 0.02 * (h - l), h - 0.02 * (h - l))
                o = (A[0] + lam * E[0], A[1] + lam * E[1])
                d = ((E[0] * math.cos(th) - E[1] * math.sin(th)) / L, (E[0] * math.sin(th) + E[1] * math.cos(th)) / L)
                _, e, u = _cast(fedges, o, d)
                assert e is not None
                met.append(geo.segment_of(e, Fraction(u).limit_denominator(10**9)))
            out.append((targets, met))
    return out


@pytest.mark.parametrize("model", ["l_shape", "comb", "one_hole"])
def test_successors_agree_with_float_ray_casting(model):
    """Every successor the exact engine reports is confirmed by float rays from sampled positions and headings
    (away from the run's ends): each lands on the claimed segment."""
    env = load_environment(MODELS / f"{model}.json")
    table = segment_table(env, env.boundary_set("e1"), env.boundary_set("e3"))
    found = _sampled_landings(env, table, samples=8, margin=0.02, seed=7)
    for (run,), met in found:
        assert set(met) <= {*run, None}
    assert sum(len(met) for _, met in found) > 100


@st.composite
def small_queries(draw):
    """Spiky star polygons (6–10 vertices, many reflex), whole edges as start and goal, budgets 1–2: about a third
    of these queries are infeasible."""
    n = draw(st.integers(6, 10))
    env = star_polygon(n, 0.6, 0.7, radius=10.0, seed=draw(st.integers(0, 10**6)), decimals=2)
    s = draw(st.integers(0, n - 1))
    g = (s + draw(st.integers(1, n - 1))) % n
    return env, f"e{s}", f"e{g}", draw(st.integers(1, 2))


@settings(max_examples=40)
@given(small_queries())
def test_infeasibility_certificate_agrees_with_exhaustive_search(query):
    """Soundness of the negative certificates: whenever the exact invariant proves that no plan within K stages
    exists, the planner's exhaustive search with every margin but δ switched off (its plans are a subclass: the
    start and goal are whole edges, so the tables agree) finds none either; and the certificate verifies."""
    env, start, goal, budget = query
    try:
        bound = bound_claim(env, env.boundary_set(start), env.boundary_set(goal), budget=budget,
                            heading_margin=Fraction(1, 1000))
    except NoBound:
        return
    plan = find_plan(env, start, goal, max_bounces=budget, safe_margin=0.0, corner_clearance=0.0)
    assert plan.status.value == "infeasible", f"the invariant excludes a plan the planner found: {plan.stages}"
    cert = certificate(plan, env=env)
    assert cert.bound == bound
    assert check_certificate(cert).valid


def test_lowering_a_tolerance_threshold_breaks_the_invariant():
    """two_holes e1 → e11 within 4 bounces: the margin-free class has a plan wider than the planner's W* + 2·end
    margin (the price of the corner clearance), so the bound's threshold sits higher; lowered, it is not closed."""
    env = load_environment(MODELS / "two_holes.json")
    plan = find_plan(env, "e1", "e11", objective="tolerance", max_bounces=4)
    cert = certificate(plan, env=env)
    assert cert.bound is not None and cert.bound.threshold - cert.claims.min_width > Fraction(1, 100)
    assert check_certificate(cert).valid
    data = data_of(cert)
    data["bound"]["threshold"] = str(cert.claims.min_width + Fraction(3, 10000))
    report = check(data)
    assert not report.valid and report.failures[0].claim.startswith("bound.beliefs[")


# ---------------------------------------------------------------------- landing units: the table's groups
@pytest.fixture(scope="module")
def l_shape_fewest():
    """l_shape with the issue's sets: the fewest-bounce plan (4) needs a landing on part of a segment (the part of e3
    above the goal set's end); its bound block ranges over the landing units (groups)."""
    env = load_environment(MODELS / "l_shape.json")
    plan = find_plan(env, *SETS, objective="fewest", max_bounces=4)
    assert plan.bounces == 4 and any(stage.sources for stage in plan.stages[1:])
    return certificate(plan, env=env)


def test_bounds_range_over_the_landing_units(l_shape_fewest):
    cert = l_shape_fewest
    assert cert.bound is not None and cert.bound.groups == ((1, 2, 3), (4, 5, 6))
    report = check_certificate(cert)
    assert report.valid, [str(f) for f in report.failures]
    assert ("or inside one of its 2 groups (segments of P′ cut at the query's set ends into table segments; the next "
            "belief holds the run of the group's consecutive segments that the landings meet)" in report.proved[1])
    assert report.proved[-1] == "hence every such plan has at least 4 bounces: this plan's 4 is the fewest"
    assert parse_certificate(dumps_certificate(cert)) == cert  # the groups survive the JSON round trip


def test_a_group_across_a_partition_point_breaks_the_invariant(l_shape_fewest):
    """Joining two table segments at a point of P′ (not a set end) into a group lets more stages land: the invariant
    is not closed."""
    data = data_of(l_shape_fewest)
    data["bound"]["groups"].append([7, 8])
    assert_rejected(data, "bound.beliefs[0]", "3→7+8")


def test_dropping_the_groups_is_a_weaker_statement_and_stays_true(l_shape_fewest):
    data = data_of(l_shape_fewest)
    del data["bound"]["groups"]
    report = check(data)
    assert report.valid and "groups" not in report.proved[1] and "at least 4 bounces" in report.proved[-1]


def test_groups_must_be_runs_of_consecutive_collinear_segments(l_shape_fewest):
    env = load_environment(MODELS / "l_shape.json")
    edges, nxt = _edges(env)
    table = [list(seg) for seg in l_shape_fewest.bound.table]
    Geometry(edges, nxt, table, [(1, 2, 3), (4, 5, 6)])
    for groups, message in (([(1,)], "a group joins at least two segments"),
                            ([(1, 2), (2, 3)], "segment 2 is already in group 0"),
                            ([(1, 3)], "segment 3 does not follow segment 1 along the boundary"),
                            ([(3, 4)], "segments 3 and 4 turn where they meet: a group is straight"),
                            ([(13, 14)], "segment 14 is not in the table")):
        with pytest.raises(TableError, match=message):
            Geometry(edges, nxt, table, groups)
    data = data_of(l_shape_fewest)
    data["bound"]["groups"] = [[1, 3]]
    assert_rejected(data, "bound.groups[0]", "does not follow segment 1")
    data["bound"]["groups"] = [[1, "two"]]
    with pytest.raises(CertificateFormatError, match=r"^bound\.groups\[0\]"):
        Certificate.from_json(data)


def test_landings_on_runs_agree_with_float_ray_casting():
    """With the issue's sets on l_shape (cut segments on e3 and e4): every successor's landing unit (a run of
    consecutive segments of one group) holds the float landing points of sampled positions and headings, and some
    landings on a run of several segments meet several of them."""
    env = load_environment(MODELS / "l_shape.json")
    table, groups = refined_table(env, *(env.boundary_set(s) for s in SETS))
    runs = several = 0
    for targets, met in _sampled_landings(env, table, groups, samples=40, margin=0.001, seed=3):
        (run,) = targets
        assert next_belief(targets) == frozenset(run) and set(met) <= {*run, None}
        if len(run) > 1:
            runs += 1
            assert any(run == group[i:i + len(run)] for group in ((1, 2, 3), (4, 5, 6)) for i in range(len(group)))
            several += len(set(met) - {None}) > 1  # a run may hull cells that meet one of its segments each
    assert runs > 0 and several > 0


# ---------------------------------------------------------------------- the class holds the planner's plans (#22, dom)
def _plan_and_lowered_bound(env, start: str, goal: str, budget: int):
    """The planner's most tolerant plan, and bound_claim just below its min width W* (a claim there is false)."""
    plan = find_plan(env, start, goal, objective="tolerance", max_bounces=budget)
    assert plan.found
    threshold = Fraction(plan.min_width) - Fraction(1, 10**6)
    return plan, lambda: bound_claim(env, env.boundary_set(start), env.boundary_set(goal), budget=budget,
                                     threshold=threshold, heading_margin=Fraction(1, 1000))


def test_a_landing_inside_the_goal_across_a_start_cut_is_a_goal_stage():
    """square e0:0.55:1 → e3:0.9:1,e0:0:0.75: the last stage lands inside the goal piece e0:[0, 0.75] across the start
    set's end at 0.55 (two table segments of the group of e0, which also holds the non-goal [0.75, 1]); the landing
    unit is the run of the two, a goal stage, so no bound is claimed below the plan's width."""
    env = load_environment(MODELS / "square.json")
    plan, claim = _plan_and_lowered_bound(env, "e0:0.55:1", "e3:0.9:1,e0:0:0.75", 5)
    with pytest.raises(NoBound, match="a margin-free plan of"):
        claim()
    cert = certificate(plan, env=env)
    assert cert.bound is not None and cert.bound.threshold >= cert.claims.min_width
    assert check_certificate(cert).valid


def test_a_ray_through_a_joint_lands_on_the_later_segment_of_the_group():
    """one_hole e7:0.3:0.7 → e2:0.35:1,e3:0:0.7: the middle ray of a cell of e7's piece meets e3 exactly at the joint
    t = 0.7 of its group; the joint belongs to the later segment (it was dropped, and with it the cell the planner's
    first stage needs)."""
    env = load_environment(MODELS / "one_hole.json")
    start, goal = "e7:0.3:0.7", "e2:0.35:1,e3:0:0.7"
    table, groups = refined_table(env, env.boundary_set(start), env.boundary_set(goal))
    edges, nxt = _edges(env)
    geo = Geometry(edges, nxt, table, groups)
    before, after = geo.segment_of(3, Fraction(69, 100)), geo.segment_of(3, Fraction(71, 100))
    assert before != after and (before, after) in groups
    assert geo._segment_at(3, 7, 10, joints=True) == after and geo.segment_of(3, Fraction(7, 10)) is None
    _, claim = _plan_and_lowered_bound(env, start, goal, 5)
    with pytest.raises(NoBound):
        claim()


@st.composite
def cut_queries(draw):
    """Star polygons (6–9 vertices) with start and goal sets that end inside edges — one piece, or a piece over a
    vertex into the next edge — so that the table's groups matter; budgets 2–4."""
    n = draw(st.integers(6, 9))
    env = star_polygon(n, 0.3, 0.3, radius=10.0, seed=draw(st.integers(0, 10**6)), decimals=2)

    def a_set() -> str:
        e = draw(st.integers(0, n - 1))
        a, b = sorted(draw(st.lists(st.integers(1, 19), min_size=2, max_size=2, unique=True)))
        if draw(st.booleans()):
            return f"e{e}:{a / 20}:1,e{(e + 1) % n}:0:{b / 20}"
        return f"e{e}:{a / 20}:{b / 20}"
    return env, a_set(), a_set(), draw(st.integers(2, 4))


@settings(max_examples=25, deadline=None)
@given(cut_queries())
def test_piece_monotonicity_the_closure_holds_every_plan_of_the_planner(query):
    """proofs/piece_monotonicity, for the bounds: the class of a bound block holds every plan of the planner (each
    stage's landing unit, the run of table segments the landings meet, lies inside the planner's unit, and a smaller
    belief has every plan of a larger one) — so the exact closure never proves "no plan wider than w" for a w below
    the min width of a plan the planner found."""
    env, start, goal, budget = query
    try:
        plan = find_plan(env, start, goal, objective="tolerance", max_bounces=budget, timeout=30)
    except ValueError:
        return  # the start set lies in the goal set, or similar: no query
    if not plan.found:
        return
    threshold = Fraction(plan.min_width) - Fraction(1, 10**6)
    with pytest.raises(NoBound):
        bound_claim(env, env.boundary_set(start), env.boundary_set(goal), budget=budget, threshold=threshold,
                    heading_margin=Fraction(1, 1000))


@pytest.mark.parametrize("objective,valid", [("tolerance", True), ("tolerancex", False), ("funnel-fewest", False)])
def test_an_infeasible_certificates_objective_is_one_the_query_could_ask(comb_infeasible, objective, valid):
    """End-to-end seed 12: an infeasible certificate's objective 'tolerance' -> 'tolerancex' verified."""
    data = copy.deepcopy(comb_infeasible.to_json())
    data["claims"]["objective"] = objective
    report = check_certificate(Certificate.from_json(data))
    assert report.valid is valid
    if not valid:
        assert report.failures[0].claim == "claims.objective" and "an infeasible certificate" in str(report.failures[0])
