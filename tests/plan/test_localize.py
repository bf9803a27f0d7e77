"""Localisation (paper §8.4): one interval shorter than ε after an open-loop strategy; symmetry makes it impossible."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.certify.check import check_certificate
from solverplan.certify.build import certificate
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.plan.localize import localize, rotational_symmetry
from solverplan.result import Method, Status
from solverplan.simulate import StagePolicy, simulate_policy

MODELS = Path(__file__).resolve().parent.parent.parent / "solverplan" / "models"
runner = CliRunner()


def model(name: str) -> Environment:
    return load_environment(MODELS / f"{name}.json")


@pytest.fixture(scope="module")
def triangle_localised():
    return localize(model("triangle"), 0.05)


def test_triangle_is_localised_from_the_whole_boundary(triangle_localised):
    loc = triangle_localised
    env = loc.env
    assert loc.status == "found" and loc.kind == "localize"
    final = loc.stages[-1].positions
    assert len({p.edge for p in final}) == 1
    hull = (max(p.t1 for p in final) - min(p.t0 for p in final)) * env.edge_lengths[final[0].edge]
    assert float(hull) < 0.05
    assert loc.widths[0] == pytest.approx(env.perimeter)
    report = check_certificate(certificate(loc), expected_rings=env.rings)
    assert report.valid, report.failures


def test_ten_thousand_rollouts_from_anywhere_end_in_the_interval(triangle_localised):
    loc = triangle_localised
    stages, targets, goal = loc.rollout_spec()
    runs = simulate_policy(loc.env, StagePolicy(stages, targets, goal=goal), None, bounces=len(stages), trials=10_000,
                           seed=5, ties="exact")
    assert runs.outcome_counts()["goal"] == 10_000
    points = runs.final_points
    spread = np.hypot(*(points.max(axis=0) - points.min(axis=0)))
    assert spread < 0.05


@pytest.mark.parametrize("name,shift", [("square", 1), ("hexagon", 3), ("narrow_door", 6)])
def test_symmetric_environments_cannot_be_localised_from_the_whole_boundary(name, shift):
    env = model(name)
    (c, s), k = rotational_symmetry(env)
    assert k == shift and (c, s) != (1, 0) and c * c + s * s == 1
    loc = localize(env, 0.1)
    assert loc.status is Status.INFEASIBLE and "invariant" in loc.reason and loc.optimality.proved
    assert loc.optimality.method is Method.SYMMETRY and not loc.optimality.limits


def test_asymmetric_models_have_no_rotational_symmetry():
    for name in ("triangle", "irregular_convex", "l_shape", "two_rooms", "one_hole"):
        assert rotational_symmetry(model(name)) is None


def test_a_start_set_breaks_the_symmetry():
    env = model("narrow_door")
    loc = localize(env, 0.05, start="e0")
    assert loc.status == "found"
    assert check_certificate(certificate(loc)).valid


def test_localize_rejects_bad_input():
    env = model("triangle")
    with pytest.raises(InputError, match="epsilon"):
        localize(env, 0)
    with pytest.raises(InputError, match="tolerance"):
        localize(env, 0.1, tolerance=3.0)


def test_cli_localize(tmp_path):
    cert = tmp_path / "loc.json"
    result = runner.invoke(cli.app, ["localize", str(MODELS / "triangle.json"), "--epsilon", "0.05",
                                     "--certificate", str(cert)])
    assert result.exit_code == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["status"] == "found" and answer["kind"] == "localize" and answer["epsilon"] == 0.05
    assert runner.invoke(cli.app, ["verify", str(cert)]).exit_code == 0
    sym = runner.invoke(cli.app, ["localize", str(MODELS / "square.json"), "--epsilon", "0.05"])
    assert sym.exit_code == 0 and json.loads(sym.stdout)["status"] == "infeasible"
