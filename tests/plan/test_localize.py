"""Localisation (paper §8.4): one interval shorter than ε after an open-loop strategy; symmetry makes it impossible."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.certify.check import check_certificate
from solverplan.certify.build import certificate
from solverplan.bounce.transitions import transition_set
from solverplan.environment import BoundaryPiece, BoundarySet, Environment, load_environment
from solverplan.errors import InputError
from solverplan.plan.funnels import funnel
from solverplan.plan.localization import localize, rotational_symmetry
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


@pytest.fixture(scope="module", params=["l_shape", "two_rooms"])
def non_convex_localised(request):
    return localize(model(request.param), 0.1)


def test_non_convex_rooms_are_localised_from_the_whole_boundary(non_convex_localised):
    """The L-shaped room (one reflex vertex) and the two rooms (seven): a strategy from every boundary point."""
    loc = non_convex_localised
    env = loc.env
    assert loc.status == "found" and loc.stages
    assert loc.start.pieces == tuple(BoundaryPiece(e, Fraction(0), Fraction(1)) for e in range(env.n_edges))
    # the positions, recomputed stage by stage in exact arithmetic from the stages' own cones
    current = loc.start.pieces
    for stage in loc.stages:
        assert tuple(stage.sources) == tuple(current)
        images = []
        for piece, cone in zip(stage.sources, stage.cones):
            image = transition_set(env, piece, cone)
            assert len(image) == 1  # every piece lands whole on one edge
            images.extend(image)
        current = BoundarySet(tuple(images)).merged().pieces
        assert current == tuple(stage.positions)
    assert len({p.edge for p in current}) == 1
    assert float(max(p.t1 for p in current) - min(p.t0 for p in current)) * float(env.edge_lengths[current[0].edge]) < 0.1
    report = check_certificate(certificate(loc), expected_rings=env.rings)
    assert report.valid, report.failures
    stages, targets, goal = loc.rollout_spec()
    runs = simulate_policy(env, StagePolicy(stages, targets, goal=goal), None, bounces=len(stages), trials=2_000,
                           seed=11, ties="exact")
    assert runs.outcome_counts()["goal"] == 2_000


def test_a_room_where_every_first_stage_splits_an_edge_says_so():
    """The hallway's long walls face several edges across its alcoves: no heading carries a whole wall onto one
    edge, so the search stops at the first bounce and says why (not a proof: nothing is claimed)."""
    loc = localize(model("hallway"), 0.1)
    assert loc.status == "not-found" and not loc.optimality.proved and loc.status.incomplete
    assert loc.optimality.limits[-1] == "cut=exhausted"
    assert "no candidate heading carried every piece whole onto one edge" in loc.reason
    assert "splits a piece over several edges" in loc.reason


def test_the_work_budget_cuts_the_search_and_is_named():
    loc = localize(model("comb"), 0.1, max_rows=2_000)
    assert loc.status == "not-found" and not loc.optimality.proved
    assert "max_rows=2000" in loc.optimality.limits and loc.optimality.limits[-1] == "cut=max_rows"
    assert loc.reason.startswith("work budget reached at bounce ")


def test_localize_rejects_bad_input():
    env = model("triangle")
    with pytest.raises(InputError, match="epsilon"):
        localize(env, 0)
    with pytest.raises(InputError, match="tolerance"):
        localize(env, 0.1, tolerance=3.0)


@pytest.mark.parametrize("search", [lambda **kw: localize(model("square"), 0.5, **kw),
                                    lambda **kw: funnel(model("square"), "e0", "e1:0.4:0.6", **kw)],
                         ids=["localize", "funnel"])
@pytest.mark.parametrize("bounds, message", [
    ({"max_bounces": 0}, r"^max_bounces must be an integer in \[1, 10,000,000\], got 0$"),
    ({"max_bounces": 2.5}, r"^max_bounces must be an integer in \[1, 10,000,000\], got 2\.5$"),
    ({"n_headings": 0}, r"^n_headings must be an integer in \[1, 100,000\], got 0$"),
    ({"beam": True}, r"^beam must be an integer in \[1, 100,000\], got True$"),
    ({"max_rows": -1}, r"^max_rows must be a non-negative integer or None \(no budget\), got -1$"),
])
def test_funnel_and_localize_check_their_search_bounds_alike(search, bounds, message):
    # one SearchBounds for both planners: localisation used to run with max_bounces=0 or -3 and to raise
    # IndexError/TypeError on n_headings=0 or 2.5 bounces; checked before any work (the square's symmetry
    # answer included)
    with pytest.raises(InputError, match=message):
        search(**bounds)


def test_cli_localize_two_rooms_certificate_verifies(tmp_path):
    cert = tmp_path / "two_rooms.cert.json"
    result = runner.invoke(cli.app, ["localize", "two_rooms", "--epsilon", "0.1", "--certificate", str(cert)])
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["status"] == "found"
    checked = runner.invoke(cli.app, ["verify", str(cert)])
    assert checked.exit_code == 0, checked.stderr
    assert json.loads(checked.stdout)["claims"]["epsilon"] == "0.1"


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


# ---------------------------------------------------------------------- certificates claim ε
def _certificate_file(tmp_path: Path, loc) -> Path:
    from solverplan.certify.schema import dumps_certificate

    path = tmp_path / "loc.cert.json"
    path.write_text(dumps_certificate(certificate(loc)), encoding="utf-8")
    return path


def test_localisation_certificate_claims_epsilon_and_verify_prints_it(triangle_localised, tmp_path):
    from fractions import Fraction

    cert = certificate(triangle_localised)
    assert cert.kind == "localize" and cert.version == 4 and cert.claims.epsilon == Fraction(1, 20)
    path = _certificate_file(tmp_path, triangle_localised)
    data = json.loads(path.read_text())
    assert data["version"] == 4 and data["kind"] == "localize" and data["claims"]["epsilon"] == "0.05"
    result = runner.invoke(cli.app, ["verify", str(path)])
    assert result.exit_code == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["kind"] == "localize" and report["claims"]["epsilon"] == "0.05"
    final = report["claims"]["final"]
    assert final["set"].startswith("e1:") and not final["length_exact"] and float(final["length"]) < 0.05
    text = runner.invoke(cli.app, ["verify", str(path), "--format", "text"]).stdout
    assert f"epsilon: 0.05: the final positions {final['set']} (length ≈ {final['length']}) lie in one interval shorter than ε" in text


def test_an_epsilon_below_the_final_length_fails_naming_the_claim(triangle_localised, tmp_path):
    path = _certificate_file(tmp_path, triangle_localised)
    data = json.loads(path.read_text())
    final = triangle_localised.stages[-1].positions
    length = float((max(p.t1 for p in final) - min(p.t0 for p in final)) * triangle_localised.env.edge_lengths[final[0].edge])
    data["claims"]["epsilon"] = "0.005"  # the final interval is ≈ 0.0058 long
    assert 0.005 < length < 0.05
    path.write_text(json.dumps(data), encoding="utf-8")
    result = runner.invoke(cli.app, ["verify", str(path)])
    assert result.exit_code == 1
    assert result.stderr.startswith("error: certificate invalid: claims.epsilon: claims ε = 0.005, but the final position set e1:[")
    assert "long: not shorter" in result.stderr  # the line is cut at its end when the numbers are long
    assert [f["claim"] for f in json.loads(result.stdout)["failures"]] == ["claims.epsilon"]


def test_a_version_1_localisation_certificate_is_read_without_an_epsilon_claim(triangle_localised, tmp_path):
    from solverplan.certify.schema import dumps_certificate, load_certificate

    path = _certificate_file(tmp_path, triangle_localised)
    data = json.loads(path.read_text())
    data.update(version=1, kind="funnel")  # as version 1 wrote it: a funnel, objective localize-fewest, no ε
    del data["claims"]["epsilon"]
    path.write_text(json.dumps(data), encoding="utf-8")
    old = load_certificate(path)
    assert old.kind == "localize" and old.version == 1 and old.claims.epsilon is None
    assert json.loads(dumps_certificate(old)) == data  # written back as it was
    result = runner.invoke(cli.app, ["verify", str(path)])
    assert result.exit_code == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["version"] == 1 and report["kind"] == "localize" and report["claims"]["epsilon"] is None
    assert any(item.startswith("claims.epsilon: a version-1 localisation certificate carries no ε claim") for item in report["not_checked"])
    text = runner.invoke(cli.app, ["verify", str(path), "--format", "text"]).stdout
    assert "epsilon: none (a version-1 localisation certificate carries no ε claim)" in text
    data["claims"]["epsilon"] = "0.05"  # version 1 had no such field
    path.write_text(json.dumps(data), encoding="utf-8")
    bad = runner.invoke(cli.app, ["verify", str(path)])
    assert bad.exit_code == 2 and "claims: unknown field 'epsilon'" in bad.stderr
