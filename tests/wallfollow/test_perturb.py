"""The symbolic perturbation of --perturb (issue #26): degenerate polygons made general, infinitesimally."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment, load_environment
from solverplan.errors import InvalidEnvironment
from solverplan.exact import orient
from solverplan.generators import rectilinear_polygon
from solverplan.wallfollow.cut import check_general_position, corner_polygon, cut_ordering
from solverplan.wallfollow.perturbation import perturb
from solverplan.wallfollow.pursuit import pursuit_plan

SIMPLE_MODELS = ["comb", "hallway", "two_rooms", "spiral", "warehouse", "three_chambers", "narrow_door", "serpentine"]


@pytest.mark.parametrize("name", SIMPLE_MODELS)
def test_issue26_every_shipped_simple_polygon_gets_a_cut_ordering_with_perturb(name):
    env = load_environment(name)
    with pytest.raises(InvalidEnvironment):
        check_general_position(env)
    p = perturb(env)
    check_general_position(p.env)
    corners = corner_polygon(env)
    assert not p.general and p.env.n_vertices == corners.n_vertices
    assert len(cut_ordering(p.env).labels) == corners.n_vertices + 2 * len(p.env.reflex_vertices)


def test_a_polygon_in_general_position_is_not_moved():
    star = load_environment("star")
    p = perturb(star)
    assert p.general and p.env == star and p.epsilon == 0


def test_holes_are_still_refused():
    with pytest.raises(InvalidEnvironment, match="without holes"):
        perturb(load_environment("one_hole"))


@settings(max_examples=20)
@given(cells=st.integers(2, 14), seed=st.integers(0, 10_000))
def test_simulation_of_simplicity_makes_rectilinear_polygons_general_and_keeps_every_decided_orientation(cells, seed):
    """The perturbation's claim: no three vertices stay collinear, no orientation that was not zero changes sign, and
    the cut ordering no longer depends on ε (the same at ε/1024)."""
    env = corner_polygon(rectilinear_polygon(cells, seed=seed))
    p = perturb(env)
    check_general_position(p.env)
    a, b = env.exact_vertices, p.env.exact_vertices
    n = len(a)
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, min(n, j + 6)):
                before, after = orient(a[i], a[j], a[k]), orient(b[i], b[j], b[k])
                assert after != 0
                if before != 0:
                    assert (before > 0) == (after > 0)
    if not p.general:
        from solverplan.wallfollow.perturbation import _moved

        finer = _moved(env, p.epsilon / 1024)
        assert finer is not None and cut_ordering(finer[0]).labels == cut_ordering(p.env).labels
        assert max(max(abs(d[0]), abs(d[1])) for d in p.displacement) <= Fraction(1, 2**24) * 10**4


SIMPLY_CONNECTED = ["two_rooms", "l_shape", "comb", "spiral", "star", "warehouse", "three_chambers", "hallway",
                    "narrow_door", "worst_case_t4", "three_arms", "serpentine", "square", "triangle", "hexagon",
                    "irregular_convex"]
#: Pursuit plans of these take 30 s of CPU or more with the exact replay (hundreds of event lines per motion); the
#: others 1–4 s, so only the gap sensor runs on those by default.
SLOW = {"spiral", "warehouse"}
SOME = {"comb", "star", "three_chambers", "worst_case_t4", "serpentine", "three_arms"}
PURSUITS = [["--pursuit"], ["--pursuit", "--sensor", "bitangent"], ["--pursuit", "--sensor", "pebble"],
            ["--pursuit", "--sensor", "contact"]]


def _cli(*args):
    from typer.testing import CliRunner

    from solverplan.cli import app

    return CliRunner().invoke(app, list(args))


def _answers_and_verifies(tmp_path, name, mode):
    import json

    cert = tmp_path / "c.json"
    result = _cli("wallfollow", name, "--perturb", *mode, "--certificate", str(cert))
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert "applied" in answer["perturbation"]
    if answer["status"] == "found" and cert.exists():
        verdict = _cli("verify", str(cert))
        assert verdict.exit_code == 0, verdict.output
    return answer


@pytest.mark.parametrize("mode", [["--cut-ordering"], ["--learn"]], ids=["cut-ordering", "learn"])
@pytest.mark.parametrize("name", SIMPLY_CONNECTED)
def test_issue26_every_shipped_simple_model_answers_with_perturb_and_its_certificate_verifies(tmp_path, name, mode):
    answer = _answers_and_verifies(tmp_path, name, mode)
    assert answer["status"] == "found"


@pytest.mark.parametrize("name, mode", [
    pytest.param(m, mode, marks=[pytest.mark.slow] if m in SLOW or (m in SOME and mode != PURSUITS[0]) else [],
                 id=f"{m}-{mode[-1] if len(mode) > 1 else 'gap'}")
    for m in SIMPLY_CONNECTED for mode in PURSUITS])
def test_issue26_every_shipped_simple_model_gets_a_verified_pursuit_answer_with_perturb(tmp_path, name, mode):
    """The exact certificate replay (the gate, then ``verify``) accepts every perturbed plan; Strategy 6 may say
    ``not-found`` (it is not complete), the complete strategies find a plan or prove there is none."""
    answer = _answers_and_verifies(tmp_path, name, mode)
    if answer["status"] == "found":
        assert answer["verified"] is True
    else:
        assert answer["status"] in ("infeasible", "not-found") and (answer["status"] == "infeasible") == \
            (mode != PURSUITS[3])


def test_issue26_the_perturbed_two_rooms_plan_is_the_one_the_exact_replay_confirms():
    """The cause of the refusal: at v3 the line of sight through v12 runs a perturbation's width inside the wall
    v12–v11, so a sliver of the component behind v12 stays hidden (in the perturbed polygon it is a real pocket).
    The ground truth used to drop it (an area tolerance of 10⁻⁹ of the polygon); with exact areas it keeps it,
    like the gap sensor's events and the certificate's replay."""
    p = perturb(load_environment("two_rooms"))
    plan = pursuit_plan(p.env)
    assert plan.actions == ("RFOLLOW", "RFOLLOW", "RFOLLOW", "JUMP") and plan.verified
    assert [sorted(step.labels) for step in plan.check.steps] == [[2, 8, 12, 16], [2], [3, 8, 12], [8, 12], []]
    assert _cli("wallfollow", "two_rooms", "--pursuit").exit_code == 2   # degenerate without --perturb


def test_the_perturbation_does_not_depend_on_how_the_walls_are_written():
    """Vertices of angle π are merged first and the corners are ranked by (x, y): a rotated ring or a split edge
    gives the same perturbed polygon."""
    env = load_environment("two_rooms")
    ring = [tuple(p) for p in env.exact_vertices]
    rotated = Environment.from_coords(ring[5:] + ring[:5])
    a, b = ring[0], ring[1]
    split = Environment.from_coords([a, ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)] + ring[1:])
    points = set(perturb(env).env.exact_vertices)
    assert set(perturb(rotated).env.exact_vertices) == points == set(perturb(split).env.exact_vertices)


@st.composite
def _grid_star(draw):
    """Star-shaped polygons on a small integer grid: collinear triples (and flat vertices) are common."""
    import math

    n = draw(st.integers(5, 9))
    radii = draw(st.lists(st.integers(2, 6), min_size=n, max_size=n))
    ring = [(round(r * math.cos(2 * math.pi * k / n)), round(r * math.sin(2 * math.pi * k / n)))
            for k, r in enumerate(radii)]
    try:
        return Environment.from_coords(ring)
    except (InvalidEnvironment, ValueError):
        from hypothesis import assume

        assume(False)
        raise  # unreachable


def _certified(env):
    from solverplan.certify.gate import checked_answer

    p = perturb(env)
    plan = pursuit_plan(p.env)
    if plan.status.value == "found":
        assert plan.verified
        checked_answer(lambda: plan, env=p.env)   # AnswerNotVerified if the exact replay disagrees
    else:
        assert plan.status.value == "infeasible"
    checked_answer(lambda: cut_ordering(p.env), env=p.env)


@settings(max_examples=6, deadline=None)
@given(cells=st.integers(2, 7), seed=st.integers(0, 10_000))
def test_issue26_perturbed_pursuit_plans_on_random_rectilinear_polygons_pass_the_exact_replay(cells, seed):
    _certified(rectilinear_polygon(cells, seed=seed))


@settings(max_examples=8, deadline=None)
@given(_grid_star())
def test_issue26_perturbed_pursuit_plans_on_polygons_with_collinear_triples_pass_the_exact_replay(env):
    _certified(env)


def test_the_perturbed_pursuit_picture_draws_a_sliver_shadow(tmp_path):
    """On the perturbed two_rooms a shadow component is a sliver a perturbation wide (~1e-7 in area): cleaning it
    gives an empty polygon, and its label must still be placed (it was an internal error from GEOS)."""
    picture = tmp_path / "pursuit.png"
    result = _cli("wallfollow", "two_rooms", "--perturb", "--pursuit", "--picture", str(picture))
    assert result.exit_code == 0, result.output
    assert picture.stat().st_size > 10_000
