"""certificate(result) and write_certificate (solverplan/certify/build.py): one call per answer type, a clear
error when there is nothing to certify, and nothing written unless the exact checker accepts."""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass, fields, replace
from fractions import Fraction

import pytest

from solverplan.certify import CertificateRejected, NothingToCertify, certificate, check_certificate, write_certificate
from solverplan.certify.schema import load_certificate
from solverplan.environment import load_environment
from solverplan.errors import InputError, SolverplanError
from solverplan.plan import find_plan, pareto_front
from solverplan.plan.funnels import Funnel, funnel
from solverplan.plan.patrols import patrol
from solverplan.result import Status
from tests.certify.cases import MODELS

SQUARE = load_environment(MODELS / "square.json")
TWO_ROOMS = load_environment(MODELS / "two_rooms.json")


@pytest.fixture(scope="module")
def plan():
    return find_plan(TWO_ROOMS, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")


@pytest.fixture(scope="module")
def square_funnel():
    return funnel(SQUARE, "e0", "e2:0.3:0.7")


def assert_valid(cert):
    report = check_certificate(cert)
    assert report.valid, [str(f) for f in report.failures]


# ---------------------------------------------------------------------- dispatch on the answer's type
def test_a_plan_needs_its_environment_and_gives_a_plan_certificate(plan):
    cert = certificate(plan, env=TWO_ROOMS)
    assert cert.kind == "plan" and cert.claims.bounces == plan.bounces and cert.claims.objective == "tolerance"
    assert_valid(cert)
    with pytest.raises(TypeError, match=r"call certificate\(plan, env=...\)"):
        certificate(plan)
    with pytest.raises(InputError, match="another environment"):
        certificate(plan, env=SQUARE)


def test_a_pareto_front_gives_the_certificate_of_its_most_tolerant_plan():
    front = pareto_front(TWO_ROOMS, "e0", "e4")
    cert = certificate(front, env=TWO_ROOMS)
    assert cert.claims.bounces == front.best().plan.bounces
    assert abs(float(cert.claims.min_width) - front.best().plan.min_width) < 1e-9
    assert_valid(cert)


def test_a_patrol_gives_a_cycle_certificate():
    p = patrol(SQUARE, "e0,e1,e2,e3", start="e2", tolerance=0.02)
    cert = certificate(p)
    assert cert.kind == "cycle" and cert.cycle.visits == p.visit and cert.cycle.contraction < 1
    assert_valid(cert)
    assert certificate(p, env=SQUARE) == cert  # its own environment, given again
    with pytest.raises(InputError, match="another environment"):
        certificate(p, env=TWO_ROOMS)


def test_a_funnel_gives_a_funnel_certificate_and_subclasses_dispatch_like_their_base(square_funnel):
    assert square_funnel.found
    cert = certificate(square_funnel)
    assert cert.kind == "funnel" and all(stage.positions for stage in cert.stages)
    assert_valid(cert)

    @dataclass(frozen=True, kw_only=True)
    class Strategy(Funnel):  # a future result class derived from Funnel needs no new entry
        pass

    derived = Strategy(**{f.name: getattr(square_funnel, f.name) for f in fields(square_funnel)})
    assert certificate(derived) == cert


def test_answers_with_nothing_to_certify_raise_a_clear_input_error():
    infeasible = find_plan(TWO_ROOMS, "e0", "e4", max_bounces=2)  # proved infeasible: certified (test_negative.py)
    assert certificate(infeasible, env=TWO_ROOMS).kind == "infeasible"
    assert certificate(pareto_front(TWO_ROOMS, "e0", "e4", max_bounces=2), env=TWO_ROOMS).kind == "infeasible"
    stopped = replace(infeasible, status=Status.NOT_FOUND)
    with pytest.raises(NothingToCertify, match="not a proof that there is no plan") as caught:
        certificate(stopped, env=TWO_ROOMS)
    assert isinstance(caught.value, InputError) and caught.value.why.startswith("the answer has status 'not-found'")
    not_found = patrol(load_environment(MODELS / "narrow_door.json"), "e0,e4")
    assert not not_found.found
    with pytest.raises(NothingToCertify, match="there is no cycle to certify"):
        certificate(not_found)


def test_other_objects_are_a_type_error():
    with pytest.raises(TypeError, match="cannot certify a str"):
        certificate("e0")


# ---------------------------------------------------------------------- the checked, atomic write
def test_write_certificate_checks_then_writes_atomically(tmp_path, plan):
    cert = certificate(plan, env=TWO_ROOMS)
    path = tmp_path / "plan.cert.json"
    write_certificate(cert, path)
    assert load_certificate(path) == cert and os.listdir(tmp_path) == ["plan.cert.json"]


def test_a_tampered_certificate_is_refused_and_nothing_is_written(tmp_path, plan):
    cert = certificate(plan, env=TWO_ROOMS)
    wider = cert.claims.min_width + Fraction(1, 1000)
    bad = replace(cert, claims=replace(cert.claims, min_width=wider, tolerance=wider / 2))
    with pytest.raises(CertificateRejected, match=r"^the plan's certificate does not verify: claims\.min_width: claims ") as caught:
        write_certificate(bad, tmp_path / "bad.json")
    assert isinstance(caught.value, SolverplanError) and not isinstance(caught.value, InputError)
    assert caught.value.failure.claim == "claims.min_width" and not caught.value.report.valid
    assert os.listdir(tmp_path) == []
    good = tmp_path / "good.json"  # a refused write leaves a previous file as it was
    write_certificate(cert, good)
    before = good.read_bytes()
    with pytest.raises(CertificateRejected):
        write_certificate(bad, good)
    assert good.read_bytes() == before and os.listdir(tmp_path) == ["good.json"]
    write_certificate(bad, good, check=False)  # unchecked, on request: what `verify` is then for
    assert load_certificate(good) == bad


def test_a_missing_folder_is_an_os_error_and_leaves_nothing(tmp_path, plan):
    with pytest.raises(FileNotFoundError):
        write_certificate(certificate(plan, env=TWO_ROOMS), tmp_path / "missing" / "x.json")
    assert os.listdir(tmp_path) == []


# ---------------------------------------------------------------------- the package stays light
def test_importing_the_checker_does_not_import_numpy_or_the_planner():
    code = ("import sys; import solverplan.certify as c; from solverplan.certify import check_certificate, "
            "load_certificate; print(sorted(m for m in ('numpy', 'solverplan.plan', 'solverplan.certify.build') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert out.stdout.strip() == "[]", out.stdout + out.stderr
