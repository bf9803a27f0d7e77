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
from solverplan.wallfollow.cut import check_general_position, cut_ordering
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
    assert not p.general and p.env.n_vertices == env.n_vertices
    assert len(cut_ordering(p.env).labels) == env.n_vertices + 2 * len(p.env.reflex_vertices)


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
    env = rectilinear_polygon(cells, seed=seed)
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


@pytest.mark.xfail(strict=True, reason="#26: on the perturbed two_rooms the exact certificate replay and the float "
                   "ground-truth checker disagree (step 3 contaminates shadows [8] or [8, 12]): the gate refuses the "
                   "plan (exit 1, one line); which of the two is right is open")
def test_issue26_perturbed_answers_carry_the_perturbation_and_plans_are_verified():
    from typer.testing import CliRunner
    import json

    from solverplan.cli import app

    result = CliRunner().invoke(app, ["wallfollow", "two_rooms", "--perturb", "--pursuit"])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert answer["perturbation"]["applied"] is True and answer["status"] == "found" and answer["verified"] is True
    assert pursuit_plan(perturb(load_environment("two_rooms")).env).check.verified
    refused = CliRunner().invoke(app, ["wallfollow", "two_rooms", "--pursuit"])
    assert refused.exit_code == 2
