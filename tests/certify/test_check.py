"""The independent exact checker (solverplan/certify/check.py): valid certificates pass, every kind of
tampering fails naming its claim, and the rational atan enclosures are right."""

from __future__ import annotations

import ast
import copy
import math
import random
from fractions import Fraction
from pathlib import Path

import mpmath
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from solverplan.bounce.partitions import partition
from solverplan.certify import (check, check_exploration, check_fields, check_models, check_rooms, check_wallfollow, exact2d,
                               invariant, rational_atan)
from solverplan.certify.check import check_certificate
from solverplan.certify.exact2d import affine_coefficients
from solverplan.certify.rational_atan import angle_enclosure, atan_enclosure, compare_angle, heading_enclosure, pi_enclosure
from solverplan.certify.schema import Certificate, json_value
from solverplan.environment import load_environment
from tests.certify import cases
from tests.certify.cases import MODELS, tampered


def run(data: dict, **kwargs):
    return check_certificate(Certificate.from_json(data), **kwargs)


def claims_of(report) -> list[str]:
    return [f.claim for f in report.failures]


def assert_fails(data: dict, claim: str, fragment: str, *, first: bool = True):
    report = run(data)
    assert not report.valid
    matching = [f for f in report.failures if f.claim == claim]
    assert matching, f"expected a failure of {claim}, got {[str(f) for f in report.failures]}"
    assert any(fragment in f.message for f in matching), [str(f) for f in matching]
    if first:
        assert report.failures[0].claim == claim, [str(f) for f in report.failures]
    return report


# ---------------------------------------------------------------------- independence
CHECKER_MODULES = [check, exact2d, rational_atan, invariant, check_models, check_rooms, check_exploration, check_wallfollow,
                   check_fields]
"""The independent checker: it must share no code with the planner (only each other and the schema)."""


def _imports(module) -> set[str]:
    tree = ast.parse(Path(module.__file__).read_text())
    names = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    return names | {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}


@pytest.mark.parametrize("module", CHECKER_MODULES, ids=lambda m: m.__name__)
def test_checker_imports_nothing_but_stdlib_and_schema(module):
    checker = {m.__name__ for m in CHECKER_MODULES}
    assert _imports(module) <= {"__future__", "fractions", "dataclasses", "hashlib", "json", "typing", "solverplan.certify.schema",
                                "solverplan.verdict"} | checker


def test_the_verdict_shared_with_the_models_is_standard_library_only():
    """The checker's verdict type lives below every model (:mod:`solverplan.verdict`): it must stay as independent as
    the checker itself, with no float anywhere."""
    from solverplan import verdict

    assert _imports(verdict) <= {"__future__", "dataclasses", "typing", "warnings"}
    tree = ast.parse(Path(verdict.__file__).read_text())
    assert not [n for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, float)]


@pytest.mark.parametrize("module", CHECKER_MODULES, ids=lambda m: m.__name__)
def test_checker_uses_no_floats(module):
    """No float literal, no float() and no math module: every number in the checker is a Fraction or an int."""
    tree = ast.parse(Path(module.__file__).read_text())
    floats = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, float)]
    calls = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id in ("float", "math")]
    assert not floats and not calls, (floats, calls)


def test_schema_imports_only_stdlib_and_errors():
    from solverplan.certify import schema

    tree = ast.parse(Path(schema.__file__).read_text())
    names = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    names |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert names <= {"__future__", "json", "re", "dataclasses", "decimal", "fractions", "pathlib", "sys", "typing", "solverplan.errors",
                     "solverplan._io"}  # the bounded reader: standard library and errors only


# ---------------------------------------------------------------------- the hand-built cases are right
_COORDINATES = st.builds(Fraction, st.integers(-6, 6), st.sampled_from([1, 2, 3]))


@given(points=st.lists(st.tuples(_COORDINATES, _COORDINATES), max_size=12), on_a_line=st.booleans())
@example(points=[(Fraction(0), Fraction(0)), (Fraction(1), Fraction(1)), (Fraction(2), Fraction(2))], on_a_line=False)
def test_checker_hull_by_gift_wrapping_equals_the_planners_monotone_chain(points, on_a_line):
    """The checker's convex hull (gift wrapping) and the planner's (Andrew's monotone chain) are written independently:
    they give the same corners in the same order, collinear points dropped, degenerate inputs included."""
    from solverplan.bounce.transitions import _convex_hull

    if on_a_line:
        points = [(x, 3 * x - 1) for x, _ in points]
    hull = exact2d.convex_hull(points)
    assert hull == _convex_hull(points)
    if len(hull) >= 3:
        turns = [exact2d.orient(hull[i - 2], hull[i - 1], hull[i]) for i in range(len(hull))]
        assert set(turns) == {1}  # counter-clockwise, no collinear corner
        assert all(exact2d.orient(hull[i - 1], hull[i], p) >= 0 for p in points for i in range(len(hull)))


@pytest.mark.parametrize("model", ["square", "l_shape", "one_hole"])
def test_cases_use_the_shipped_models_normalised_rings(model):
    env = load_environment(MODELS / f"{model}.json")
    assert tuple(tuple((Fraction(x), Fraction(y)) for x, y in ring) for ring in cases.rings_of(model)) == env.rings


@pytest.mark.parametrize(
    "model,segments",
    [("square", {s["id"]: s for s in cases.SQUARE_SEGMENTS}), ("l_shape", cases.L_SEGMENTS), ("one_hole", cases.ONE_HOLE_SEGMENTS)],
)
def test_cases_name_the_segments_of_algorithm_1(model, segments):
    part = partition(load_environment(MODELS / f"{model}.json"))
    for sid, record in segments.items():
        seg = part.segments[sid]
        assert (seg.edge, seg.t0, seg.t1) == (record["edge"], Fraction(record["t0"]), Fraction(record["t1"]))
        assert seg.a == tuple(Fraction(x) for x in record["a"]) and seg.b == tuple(Fraction(x) for x in record["b"])


# ---------------------------------------------------------------------- valid certificates
@pytest.mark.parametrize("name", list(cases.ALL_VALID))
def test_hand_built_certificates_are_valid(name):
    data = cases.ALL_VALID[name]()
    report = run(data)
    assert report.valid, [str(f) for f in report.failures]
    assert report.failures == ()
    counts = dict(report.checked)
    n_moves = sum(len(s["moves"]) for s in data["stages"])
    n_edges = sum(len(r) for r in data["environment"]["rings"])
    assert counts["moves"] == n_moves
    assert counts["corner_rays"] == 4 * n_moves
    assert counts["edge_tests"] == n_moves * n_edges  # every environment edge, against every move
    assert counts["links"] >= len(data["stages"])


@pytest.mark.parametrize("name", ["square_up", "l_shape_plan", "one_hole_plan"])
def test_valid_certificate_matches_its_environment_file(name):
    data = cases.ALL_VALID[name]()
    env = load_environment(MODELS / f"{data['environment']['name']}.json")
    assert run(data, expected_rings=env.rings).valid


def test_certificate_for_another_environment_is_rejected():
    other = load_environment(MODELS / "l_shape.json")
    report = run(cases.square_up(), expected_rings=other.rings)
    assert claims_of(report)[0] == "environment.rings[0]"
    assert "the given environment's ring has 6" in report.failures[0].message


def test_report_json_and_text():
    report = run(cases.square_up())
    data = report.to_json()
    assert data["valid"] is True and data["kind"] == "plan" and data["failures"] == []
    assert data["checked"]["corner_rays"] == 4
    assert data["version"] == 4 and data["start"] == {"set": "e0:0.1:0.9", "length": "8", "length_exact": True}
    assert data["goal"]["set"] == "e2" and data["claims"]["bounces"] == 1
    lines = report.to_text().splitlines()
    assert lines[0] == "certificate (plan): VALID"
    assert lines[1].startswith("environment: 'square', sha256 ") and lines[1].endswith("4 vertices, 4 edges, 0 holes")
    assert lines[2:4] == ["start: e0:0.1:0.9 (length 8)", "goal: e2 (length 10)"]
    assert lines[4].startswith("scope: a point robot in this environment that moves straight between bounces")
    assert lines[5].startswith("claims: bounces 1, min_width 0.0999")
    assert lines[6].startswith("checked exactly: 1 stages")
    assert lines[7].startswith("proved: from every point of the start set, executing at stage j any heading inside its "
                               "interval lands the robot in the goal set after 1 bounce")


# ---------------------------------------------------------------------- tampering: one claim at a time
def test_nudged_corner_direction_misses_the_target():
    data = tampered(cases.square_up(), "stages.0.moves.0.d_hi", [-1, 2])
    report = assert_fails(data, "stages[0].moves[0].d_hi", "outside segment 2")
    assert "corner ray from (1, 0) (t = 0.1 of edge 0) along (-1, 2) hits the line of edge 2 at (-4, 10) (t = 1.4)" in report.failures[0].message


def test_swept_region_crossing_the_hole_is_rejected():
    assert_fails(cases.one_hole_through_the_hole(), "stages[0].moves[0].swept", "edge 4 runs through the swept region from (4, 3) to (4, 5)")


def test_swept_region_around_the_reflex_corner_is_rejected():
    assert_fails(cases.l_shape_around_the_corner(), "stages[0].moves[0].swept", "edge 2 runs through the swept region from (4.2, 4) to (4, 4)")


def test_direction_pointing_into_the_wall():
    data = tampered(cases.square_up(), "stages.0.moves.0.d_lo", [1, -20])
    assert_fails(data, "stages[0].moves[0].d_lo", "points into the wall")


def test_direction_along_the_wall_is_not_into_the_free_space():
    data = tampered(cases.square_up(), "stages.0.moves.0.d_lo", [1, 0])
    assert_fails(data, "stages[0].moves[0].d_lo", "cross(edge, d) = 0 ≤ 0")


def test_claimed_min_width_larger_than_true():
    data = cases.square_up()
    data["claims"].update(min_width="0.2", tolerance="0.1")
    assert_fails(data, "claims.min_width", "more than the width 0.099916791443 of stages[0].interval")


def test_claimed_min_width_larger_than_the_exact_cone_without_intervals():
    data = cases.with_claims(cases.square_up(), intervals=False)
    del data["stages"][0]["interval"]
    true_width = 2 * math.atan(1 / 20)  # 0.09991679144388552
    data["claims"].update(min_width="0.0999167914438856", tolerance="0.0499583957219428")
    assert Fraction("0.0999167914438856") > Fraction(true_width)  # 1e-16 too much: still caught
    assert_fails(data, "claims.min_width", "but stages[0] is only 0.099917 wide")


def test_broken_chaining():
    data = tampered(cases.square_adjacent(), "stages.1.moves.0.source", ["1/2", 1])
    assert_fails(data, "stages[1].moves", "no move leaves t in (0, 0.5) of edge 1, where stages[0].moves[0] may land")


def test_wrong_fixed_point():
    data = tampered(cases.square_cycle(), "cycle.fixed_point", "1/12")
    report = assert_fails(data, "cycle.fixed_point", "claims 1/12, but β / (1 − α) = 1/11")
    assert claims_of(report) == ["cycle.fixed_point"]


def test_cycle_claimed_contracting_that_is_not():
    report = assert_fails(cases.square_neutral_cycle("1/2"), "cycle.contraction", "the worst case of |α| over the cones is 1", first=False)
    assert "cycle.fixed_point" in claims_of(report)  # α = 1: no unique fixed point either


def test_cycle_honestly_claiming_no_contraction_is_still_not_a_certificate():
    assert_fails(cases.square_neutral_cycle("1"), "cycle.contraction", "the cycle does not contract", first=False)


# ---------------------------------------------------------------------- tampering: more claims
def test_reversed_cone():
    data = cases.square_up()
    move = data["stages"][0]["moves"][0]
    move["d_lo"], move["d_hi"] = move["d_hi"], move["d_lo"]
    assert_fails(data, "stages[0].moves[0].d_hi", "clockwise of d_lo")


def test_start_not_covered_by_the_first_stage():
    data = tampered(cases.square_up(), "start.0.t1", 1)
    assert_fails(data, "stages[0].moves", "no move leaves t in (0.9, 1) of edge 0, part of start[0]")


def test_last_targets_outside_the_goal():
    data = tampered(cases.square_up(), "goal.0.t1", "1/2")
    assert_fails(data, "stages[0].moves[0].target", "is not within the goal set: t in (0.5, 1) is outside it")


def test_claimed_target_must_hold_the_corner_hits():
    data = tampered(cases.square_up(), "stages.0.moves.0.target", [0, "1/2"])
    assert_fails(data, "stages[0].moves[0].target", "lands at t = 0.85 of edge 2, outside the claimed target [0, 0.5]")


def test_segment_record_off_its_edge():
    data = tampered(cases.square_up(), "segments.0.b", [10, 1])
    assert_fails(data, "segments[0].b", "is not the point t1 = 1 of edge 0")


def test_source_segment_on_another_edge():
    data = tampered(cases.square_up(), "stages.0.moves.0.source_segment", 2)
    assert_fails(data, "stages[0].moves[0].source_segment", "lies on edge 2, not on the source edge 0")


def test_source_not_an_interval():
    data = tampered(cases.square_up(), "stages.0.moves.0.source", ["9/10", "1/10"])
    assert_fails(data, "stages[0].moves[0].source", "is not an interval")


def test_target_segment_interior_is_open():
    """A corner hit exactly on a partition point of the target is not strictly inside it."""
    data = cases.l_shape_plan()
    data["stages"][0]["moves"][0]["source"] = [0, "7/20"]  # from the vertex (0, 0) up-left: hits x = -1/4
    data["start"][0]["t0"] = 0
    assert_fails(data, "stages[0].moves[0].d_hi", "outside segment 6 (t in [0, 1])")


def test_stage_interval_leaving_the_cone():
    data = cases.square_up()
    lo = Fraction(data["stages"][0]["interval"][0])
    data["stages"][0]["interval"][0] = str(lo - Fraction(1, 100))
    assert_fails(data, "stages[0].interval.lo", "but the cone of moves[0] starts at heading 1.520838")


def test_stage_interval_must_be_tight():
    data = cases.square_up()
    hi = Fraction(data["stages"][0]["interval"][1])
    data["stages"][0]["interval"][1] = str(hi - Fraction(1, 100))
    assert_fails(data, "stages[0].interval.hi", "more than 1e-9 inside the common cone", first=False)


def test_min_width_must_be_tight():
    data = cases.square_up()
    data["claims"].update(min_width="0.05", tolerance="0.025")
    assert_fails(data, "claims.min_width", "claims must be tight")


def test_tolerance_is_half_the_min_width():
    data = tampered(cases.square_up(), "claims.tolerance", "0.05")
    assert_fails(data, "claims.tolerance", "but min_width / 2 = ")


def test_bounces_count_the_stages():
    data = tampered(cases.square_adjacent(), "claims.bounces", 1)
    assert_fails(data, "claims.bounces", "claims 1, the certificate has 2 stages")


def test_sum_width():
    data = cases.square_adjacent()
    widths = [2 * (math.atan(9 / 10) - math.atan(1 / 10))]  # the two stages have the same cone
    assert_fails(tampered(data, "claims.sum_width", "1.7"), "claims.sum_width", "add up to")
    assert_fails(tampered(data, "claims.sum_width", "1.2"), "claims.sum_width", "claims must be tight")
    ok = tampered(data, "claims.sum_width", str(Fraction(widths[0]) - Fraction(1, 10**12)))
    assert run(ok).valid


def test_funnel_positions_are_the_exact_image():
    data = tampered(cases.funnel_square(), "stages.0.positions.0.t1", "9/10")
    assert_fails(data, "stages[0].positions", "the exact image of the stage is e2:[0.05, 0.95]")


def test_cones_of_a_stage_must_share_a_heading():
    data = cases.square_up()
    extra = cases.move(0, ["1/10", "9/10"], (10, 1), (10, 9), 1, [0, 1])
    data["stages"][0]["moves"].append(extra)
    data["goal"].append({"edge": 1, "t0": 0, "t1": 1})
    assert_fails(data, "stages[0]", "the moves' cones share no heading", first=False)


def test_belief_stage_interval_is_common_to_all_edges():
    """square_belief's moves leave two different edges with the same *relative* cone: its claimed
    interval is measured from each source edge, and a world-frame slip on one edge is caught."""
    data = tampered(cases.square_belief(), "stages.0.moves.1.d_hi", [8, -10])  # narrower on edge 3 only
    report = assert_fails(data, "stages[0].interval.hi", "but the cone of moves[1] ends at heading 0.674741", first=False)
    assert report.failures[0].claim == "stages[0].moves[0].d_hi"  # the cones no longer agree
    # a cone wider than the stage's common interval claims headings the robot never uses
    wider = tampered(cases.square_belief(), "stages.0.moves.1.d_lo", [1, -11])
    assert_fails(wider, "stages[0].moves[1].d_lo", "more than 1e-9 before the stage's common cone")


def test_target_is_the_segment_or_the_exact_image():
    data = tampered(cases.square_adjacent(), "stages.0.moves.0.target", [0, "19/20"])
    assert_fails(data, "stages[0].moves[0].target", "neither all of segment 1 ([0, 1]) nor the exact image [0, 0.9]")


def test_source_ends_are_accounted_for():
    data = tampered(cases.square_adjacent(), "stages.1.moves.0.source", [0, "99/100"])
    assert_fails(data, "stages[1].moves[0].source", "its end q = 0.99 of edge 1 is not accounted for")


def test_query_pins_start_and_goal():
    # square_adjacent leaves the whole bottom edge: a smaller start set is a true statement about
    # another query, which only the query itself can tell apart
    data = tampered(cases.square_adjacent(), "start.0.t0", "0.2")
    assert run(data).valid
    query = {"expected_start": [(0, Fraction(0), Fraction(1))], "expected_goal": [(2, Fraction(0), Fraction(1))]}
    assert run(cases.square_adjacent(), **query).valid
    report = run(data, **query)
    assert [str(f) for f in report.failures] == ["start: is e0:[0.2, 1], but the query's start set is e0:[0, 1]"]
    wider_goal = tampered(cases.square_adjacent(), "goal", [{"edge": 2, "t0": 0, "t1": 1}, {"edge": 1, "t0": 0, "t1": 1}])
    assert run(wider_goal).valid
    assert claims_of(run(wider_goal, **query)) == ["goal"]


def test_shrunk_start_under_a_partial_source_is_caught_without_the_query():
    data = tampered(cases.square_up(), "start.0.t0", "0.2")
    assert_fails(data, "stages[0].moves[0].source", "its end p = 0.1 of edge 0 is not accounted for")


def test_invalid_environment_is_rejected_first():
    data = cases.square_up()
    data["environment"]["rings"][0] = data["environment"]["rings"][0][::-1]  # clockwise outer ring
    report = assert_fails(data, "environment.rings[0]", "must be counter-clockwise")
    assert len(report.failures) == 1


def test_self_intersecting_environment_is_rejected():
    data = cases.square_up()
    data["environment"]["rings"] = [[[0, 0], [10, 0], [10, 10], [0, 10]], [[2, 2], [2, 12], [4, 12], [4, 2]]]
    assert_fails(data, "environment", "meets edge")


def test_cycle_alpha_beta_nominal_and_visits():
    good = cases.square_cycle()
    assert_fails(tampered(good, "cycle.alpha", "1/1000"), "cycle.alpha", "has α = 0.0001")
    assert_fails(tampered(good, "cycle.beta", 0), "cycle.beta", "has β = ")
    assert_fails(tampered(good, "cycle.nominal.1", [-5, 10]), "cycle.nominal[1]", "is not inside the cone")
    assert_fails(tampered(good, "cycle.visits", [0, 2, 1]), "cycle.visits", "does not visit [0, 2, 1]")
    assert run(tampered(good, "cycle.visits", [2, 3, 0])).valid  # cyclic order
    assert_fails(tampered(good, "cycle.contraction", "27/1000"), "cycle.contraction", "is 0.0081")


def test_cycle_stages_must_be_the_tail():
    assert_fails(tampered(cases.square_cycle(), "cycle.stages", [0, 1, 2]), "cycle.stages", "must be the last stages")


def test_optimality_is_checked_for_consistency_and_listed_as_not_checked():
    data = cases.square_adjacent()
    data["claims"]["objective"] = "fewest"
    data["claims"]["optimality"] = {"method": "search-exhausted", "proved": True, "bound": 2}
    report = run(data)
    assert report.valid
    assert report.not_checked and "search-exhausted" in report.not_checked[0]
    data["claims"]["optimality"]["bound"] = 3
    assert_fails(data, "claims.optimality.bound", "a lower bound of 3 bounces exceeds")
    data["claims"]["optimality"] = {"method": "search-exhausted", "proved": True}
    assert_fails(data, "claims.optimality.bound", "must state its bound")


def test_zero_width_stage_is_an_exact_tie():
    """The neutral cycle's cones are single directions: min_width 0 is exact, not 'undecided'."""
    report = run(cases.square_neutral_cycle("1"))
    assert not any(f.claim.startswith("claims") for f in report.failures), [str(f) for f in report.failures]


def test_every_single_number_tampered_is_caught():
    """Issue 5's acceptance: change any one number of a certificate and verify rejects it."""
    base = cases.square_adjacent()
    base["claims"]["sum_width"] = str(Fraction(2 * (math.atan(9 / 10) - math.atan(1 / 10))) - Fraction(1, 10**12))
    assert run(base).valid
    rng = random.Random(5)
    paths = []

    def walk(node, path):
        if isinstance(node, dict):
            for k, v in node.items():
                if k not in ("schema", "version", "kind", "name"):
                    walk(v, [*path, k])
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, [*path, str(i)])
        elif isinstance(node, (int, str)) and not isinstance(node, bool):
            paths.append(".".join(path))

    walk(base, [])
    assert len(paths) > 60
    env = load_environment(MODELS / "square.json")
    start, goal = [(0, Fraction(0), Fraction(1))], [(2, Fraction(0), Fraction(1))]
    assert run(base, expected_rings=env.rings, expected_start=start, expected_goal=goal).valid
    for path in paths:
        value = Fraction(str(eval_path(base, path)))
        for delta in (Fraction(1, 7), -Fraction(rng.randint(1, 5), 3)):
            changed = tampered(base, path, json_value(value + delta))
            try:
                report = run(changed, expected_rings=env.rings, expected_start=start, expected_goal=goal)
            except ValueError:
                continue  # a format error (e.g. a negative id): rejected before checking
            assert not report.valid, f"{path} changed to {value + delta} went unnoticed"


def eval_path(data, path):
    node = data
    for key in path.split("."):
        node = node[int(key)] if isinstance(node, list) else node[key]
    return node


# ---------------------------------------------------------------------- affine maps
def test_affine_map_agrees_with_the_transition_module():
    """Two independent derivations of t ↦ α t + β (bounce/transitions.py and the checker's)."""
    from solverplan.bounce.transitions import affine_map

    env = load_environment(MODELS / "one_hole.json")
    for edge, target, d in [(0, 2, (1, 30)), (0, 1, (3, 1)), (1, 2, (-2, 3)), (2, 3, (-1, -1)), (0, 4, (1, 3))]:
        src, tgt = env.edge(edge), env.edge(target)
        mine = affine_coefficients(src.a, (src.b[0] - src.a[0], src.b[1] - src.a[1]), tgt.a, (tgt.b[0] - tgt.a[0], tgt.b[1] - tgt.a[1]), d)
        theirs = affine_map(env, edge, d, target)
        assert mine == (theirs.alpha, theirs.beta)


# ---------------------------------------------------------------------- the rational atan
def _mp(x: Fraction) -> mpmath.mpf:
    return mpmath.mpf(x.numerator) / x.denominator


def _rationals(n: int, seed: int):
    rng = random.Random(seed)
    out = [Fraction(0), Fraction(1), Fraction(-1), Fraction(1, 2), Fraction(1, 16), Fraction(17, 16), Fraction(10**30, 3)]
    for _ in range(n):
        den = rng.randint(1, 10 ** rng.randint(1, 15))
        num = rng.randint(-(10 ** rng.randint(0, 16)), 10 ** rng.randint(0, 16))
        out.append(Fraction(num, den))
    return out


def test_atan_enclosure_contains_math_atan_and_is_narrow():
    for x in _rationals(2000, seed=1):
        lo, hi = atan_enclosure(x)
        assert hi - lo < Fraction(1, 10**15)
        # math.atan(float(x)) is the float nearest atan(float(x)): within a few ulps of atan(x)
        ref = Fraction(math.atan(float(x)))
        slack = Fraction(4 * math.ulp(max(abs(math.atan(float(x))), 1e-300))) + abs(Fraction(float(x)) - x)
        assert lo - slack <= ref <= hi + slack, x


def test_atan_enclosure_is_rigorous_at_high_precision():
    mpmath.mp.prec = 1400
    try:
        for bits in (64, 200, 1000):
            lo, hi = pi_enclosure(bits)
            assert _mp(lo) <= mpmath.pi <= _mp(hi) and hi - lo <= Fraction(1, 2**bits)
            for x in _rationals(60, seed=bits):
                lo, hi = atan_enclosure(x, bits)
                assert _mp(lo) <= mpmath.atan(_mp(x)) <= _mp(hi), (x, bits)
                assert hi - lo <= Fraction(4, 2**bits)
    finally:
        mpmath.mp.prec = 53


def test_angle_enclosure_quadrants():
    for v, expected in [((1, 0), 0), ((0, 1), math.pi / 2), ((-1, 0), math.pi), ((0, -1), -math.pi / 2), ((-1, -1), -3 * math.pi / 4), ((3, -4), math.atan2(-4, 3))]:
        lo, hi = angle_enclosure((Fraction(v[0]), Fraction(v[1])))
        assert float(lo) == pytest.approx(expected, abs=1e-15) and float(hi) == pytest.approx(expected, abs=1e-15)
    lo, hi = heading_enclosure((Fraction(0), Fraction(-10)), (Fraction(9), Fraction(-10)))  # edge 3 of the square
    assert float(lo) == pytest.approx(math.atan(9 / 10))


def test_compare_angle_refines_until_decided():
    v = (Fraction(3), Fraction(7))
    lo, hi = angle_enclosure(v, 400)  # a rational within 2^-400 of the angle, on either side
    assert compare_angle(v, lo) == 1 and compare_angle(v, hi) == -1
    assert compare_angle((Fraction(5), Fraction(0)), Fraction(0)) == 0  # the one exact tie


# ---------------------------------------------------------------------- soundness against exact ray casting
def _random_move(env, part, rng):
    """A random move aimed from the middle of a source piece at two points of a target segment."""
    from solverplan.certify.schema import Move

    s, g = rng.choice(part.segments), rng.choice(part.segments)
    if s.edge == g.edge:
        return None
    if rng.random() < 0.3:
        p, q = s.t0, s.t1  # whole segments: vertex ends and adjacent targets
    else:
        a, b = sorted(Fraction(rng.randint(0, 1000), 1000) for _ in range(2))
        if a == b:
            return None
        p, q = s.t0 + a * (s.t1 - s.t0), s.t0 + b * (s.t1 - s.t0)
    src, tgt = env.edge(s.edge), env.edge(g.edge)
    e = (src.b[0] - src.a[0], src.b[1] - src.a[1])
    f = (tgt.b[0] - tgt.a[0], tgt.b[1] - tgt.a[1])
    mid = (src.a[0] + (p + q) / 2 * e[0], src.a[1] + (p + q) / 2 * e[1])
    aims = []
    for w in sorted(Fraction(rng.randint(1, 999), 1000) for _ in range(2)):
        tau = g.t0 + w * (g.t1 - g.t0)
        aims.append((tgt.a[0] + tau * f[0] - mid[0], tgt.a[1] + tau * f[1] - mid[1]))
    d1, d2 = aims
    if e[0] * d1[1] - e[1] * d1[0] <= 0 or e[0] * d2[1] - e[1] * d2[0] <= 0:
        return None
    if d1[0] * d2[1] - d1[1] * d2[0] < 0:
        d1, d2 = d2, d1
    return Move(s.edge, (p, q), d1, d2, g.edge, (g.t0, g.t1), s.id, g.id), s, g


@pytest.mark.parametrize("model", ["one_hole", "two_holes", "degenerate", "comb"])
def test_accepted_moves_agree_with_exact_ray_casting(model):
    """Soundness: whenever the checker accepts a move, exact rays from its source (ends and random
    interior points, never a vertex of P) along directions of its cone (ends and random positive
    combinations) first meet the boundary strictly inside the target segment (geometry.raycast)."""
    from solverplan.certify.schema import Certificate as Cert, Claims, EnvironmentRecord, Piece, SegmentRecord, Stage
    from solverplan.geometry.raycast import cast_ray

    env = load_environment(MODELS / f"{model}.json")
    part = partition(env)
    rng = random.Random(model)
    accepted = rays = 0
    for _ in range(150):
        made = _random_move(env, part, rng)
        if made is None:
            continue
        move, s, g = made
        records = {r.id: SegmentRecord(r.id, r.edge, r.t0, r.t1, r.a, r.b) for r in (s, g)}
        cert = Cert("plan", EnvironmentRecord(env.rings), tuple(records.values()), (Piece(s.edge, *move.source),),
                    (Piece(g.edge, g.t0, g.t1),), (Stage((move,)),), Claims(1, Fraction(0), Fraction(0)))
        if any(f.claim.startswith("stages[0].moves[0]") for f in check_certificate(cert).failures):
            continue
        accepted += 1
        src = env.edge(s.edge)
        for _ in range(12):
            t = rng.choice([move.source[0], move.source[1], None])
            if t is None:
                t = move.source[0] + Fraction(rng.randint(1, 999), 1000) * (move.source[1] - move.source[0])
            if t in (0, 1):
                continue
            origin = (src.a[0] + t * (src.b[0] - src.a[0]), src.a[1] + t * (src.b[1] - src.a[1]))
            a, b = Fraction(rng.randint(0, 20)), Fraction(rng.randint(0, 20))
            a = a or (Fraction(1) if b == 0 else a)
            d = (a * move.d_lo[0] + b * move.d_hi[0], a * move.d_lo[1] + b * move.d_hi[1])
            hit = cast_ray(env, origin, d)
            rays += 1
            assert hit.vertex is None and hit.edge == g.edge and g.t0 < hit.t < g.t1, (move, t, d, hit)
    assert accepted >= 15 and rays >= 100  # the test is not vacuous


# ---------------------------------------------------------------------- localisation: ε
def test_localisation_epsilon_is_checked_exactly():
    report = run(cases.localize_square("19/2"))
    assert report.valid, [str(f) for f in report.failures]
    assert report.claims["epsilon"] == "9.5" and report.claims["final"] == {"set": "e2:0.05:0.95", "length": "9", "length_exact": True}
    # the final interval is exactly 9 long: ε = 9 is not larger, and ε just above 9 is
    assert_fails(cases.localize_square("9"), "claims.epsilon", "claims ε = 9, but the final position set e2:[0.05, 0.95] is 9 long: not shorter than ε")
    assert run(cases.localize_square("9.000000000000000000001")).valid
    assert_fails(cases.localize_square("0"), "claims.epsilon", "not a positive length")


def test_reported_set_lengths_are_exact_or_a_9_decimal_approximation():
    """Edges of rational length give exact lengths; the hypotenuse of a unit right triangle (√2) does not."""
    tri = check.certified(Certificate.from_json({**cases.localize_square(), "environment": {"name": "t", "rings": [[[0, 0], [1, 0], [0, 1]]]}}))
    assert tri["start"] == {"set": "e0:0.1:0.9", "length": "0.8", "length_exact": True}
    assert tri["goal"] == {"set": "e2", "length": "1", "length_exact": True}
    slanted = check.certified(Certificate.from_json({**cases.localize_square(), "start": [{"edge": 1, "t0": 0, "t1": "1/2"}],
                                                     "environment": {"name": "t", "rings": [[[0, 0], [1, 0], [0, 1]]]}}))
    assert slanted["start"] == {"set": "e1:0:0.5", "length": "0.707106781", "length_exact": False}


def test_localisation_final_positions_on_two_edges_fail():
    data = cases.localize_square()
    data["goal"] = [{"edge": 1, "t0": 0, "t1": 1}, {"edge": 2, "t0": 0, "t1": 1}]
    data["stages"][0]["positions"] = [{"edge": 1, "t0": 0, "t1": "1/2"}, {"edge": 2, "t0": "1/20", "t1": "19/20"}]
    report = run(data)
    assert "claims.epsilon" in claims_of(report)
    assert any(str(f) == "claims.epsilon: the final position set lies on edges 1, 2, not in one interval of one edge" for f in report.failures)


def test_a_constructed_version_2_localisation_without_epsilon_fails():
    import dataclasses

    cert = Certificate.from_json(cases.localize_square())
    bare = dataclasses.replace(cert, claims=dataclasses.replace(cert.claims, epsilon=None))
    report = check_certificate(bare)
    assert not report.valid and report.failures[0].claim == "claims.epsilon"


# ---------------------------------------------------------------------- every printed claim checked or listed (#28)
@pytest.mark.parametrize("method,proved,claim,message", [
    ("by-magic", True, "claims.optimality.method", "unknown method 'by-magic'"),
    ("heuristic", True, "claims.optimality.proved", "proves nothing"),
    ("none", True, "claims.optimality.proved", "proves nothing"),
])
def test_an_optimality_method_that_cannot_prove_fails_a_proved_claim(method, proved, claim, message):
    data = cases.square_adjacent()
    data["claims"]["objective"] = "fewest"
    data["claims"]["optimality"] = {"method": method, "proved": proved, "bound": 2}
    assert_fails(data, claim, message)


def test_the_checkers_optimality_methods_are_the_planners():
    from solverplan.result import Method

    assert set(check.METHODS) == {m.value for m in Method}
    assert set(check.PROVING_METHODS) == {m.value for m in Method} - {"heuristic", "none"}


@pytest.mark.parametrize("objective", ["fewest", "tolerance", "constant"])
def test_an_objective_is_listed_as_not_checked_unless_a_bound_block_confirms_it(objective):
    data = cases.square_adjacent()
    data["claims"]["objective"] = objective
    report = run(data)
    assert report.valid
    listed = [line for line in report.not_checked if line.startswith("claims.objective")]
    assert len(listed) == 1 and len(listed[0]) <= 200


@pytest.mark.parametrize("objective,fragment", [
    ("anything at all", "unknown objective 'anything at all': a plan certificate names one of fewest, tolerance, sum, constant"),
    ("fewestx", "unknown objective 'fewestx'"),
    ("x" * 500, "unknown objective 'xxxxxxxx"),
    ("funnel-fewest", "'funnel-fewest' is an objective of funnel certificates, not of a plan certificate"),
    ("patrol-rate", "is an objective of cycle certificates, not of a plan certificate"),
])
def test_an_unknown_objective_or_another_kinds_is_a_failure(objective, fragment):
    """pipe's finding 3: a tampered objective (``funnel-fewest`` → ``funnel-fewestx``, a funnel relabelled a plan) was
    only listed as not checked; an objective no certificate of the kind can have is a failure."""
    data = cases.square_adjacent()
    data["claims"]["objective"] = objective
    report = assert_fails(data, "claims.objective", fragment)
    assert all(len(str(f)) <= check.MAX_FAILURE_LINE for f in report.failures)


def test_the_checkers_objectives_are_the_planners():
    from solverplan.choices import Objective, PatrolObjective

    assert check.PLAN_OBJECTIVES == tuple(o.value for o in Objective)
    assert check.PATROL_OBJECTIVES == tuple(o.value for o in PatrolObjective)


def test_a_move_repeated_in_a_stage_is_malformed():
    """pipe's finding 2: a stage listing one move twice said nothing false, but says it twice: one failure naming the
    repeat (the certificate is otherwise as checked)."""
    data = cases.square_adjacent()
    moves = data["stages"][0]["moves"]
    moves.append(copy.deepcopy(moves[0]))
    report = assert_fails(data, f"stages[0].moves[{len(moves) - 1}]", "of moves[0]: a stage has one move per source")
    assert [f.claim for f in report.failures] == [f"stages[0].moves[{len(moves) - 1}]"]


def test_a_sum_objective_needs_its_sum_width():
    data = cases.square_adjacent()
    data["claims"]["objective"] = "sum"
    data["claims"].pop("sum_width", None)
    assert_fails(data, "claims.objective", "sum_width is missing")


def test_sum_width_is_decided_exactly_above_the_exact_sum():
    """A claimed sum a hair (10⁻³⁰) above the exact sum of the widths fails; the exact sum's lower end passes."""
    data = cases.square_adjacent()
    report = run(data)
    cert = Certificate.from_json(data)
    widths = []
    original = check._Checker.check_sum_width

    def spy(self, claimed, diffs):
        widths.append(diffs)
        return original(self, claimed, diffs)

    check._Checker.check_sum_width = spy
    try:
        data["claims"]["sum_width"] = json_value(cert.claims.min_width)
        run(data)
    finally:
        check._Checker.check_sum_width = original
    assert report.valid and widths
    exact_low = sum(min(angle_enclosure(v, 512)[0] for v in d) for d in widths[0])
    data["claims"]["sum_width"] = json_value(exact_low + Fraction(1, 10**30))
    assert_fails(data, "claims.sum_width", "more than the stages' widths add up to")
    data["claims"]["sum_width"] = json_value(exact_low)
    assert run(data).valid


def test_failure_lines_are_cut_to_200_characters_in_one_place():
    data = cases.square_adjacent()
    data["claims"]["objective"] = "fewest"
    data["claims"]["optimality"] = {"method": "m" * 1000, "proved": True, "bound": 2}
    report = run(data)
    assert not report.valid
    assert all(len(str(f)) <= check.MAX_FAILURE_LINE for f in report.failures)
    assert "'mmm" in str(report.failures[0]) and "m" * 50 not in str(report.failures[0])
