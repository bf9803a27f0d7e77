"""The certificate section: the certificate checked exactly, pinned to the answer's environment and query."""

from __future__ import annotations

import json
from fractions import Fraction
from typing import Any, Iterable, Sequence


from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.result import EnvironmentRecord

from solverplan.render.report._kinds import ANSWER_KINDS, AnswerFile, _CERTIFICATE_KINDS
from solverplan.render.report.bounce import _View
from solverplan.render.report.format import _e
from solverplan.render.report.page import _table


def _no_certificate(kind: str, answered: bool = True) -> str:
    if kind in ("plan", "pareto") and not answered:
        why = ("No certificate was given: an infeasible plan's certificate (--certificate FILE when solving) proves "
               "that there is no plan; without it, what the answer proves rests on its search (see optimality below).")
    elif kind in _CERTIFICATE_KINDS and not answered:
        why = ("An answer that found no strategy has no certificate: what it proves rests on its search "
               "(see optimality below).")
    elif kind in _MODEL_CERTIFICATE_KINDS and answered:
        why = "No certificate was given (make one with --certificate FILE when solving, and pass it to the report)."
    elif kind in _CERTIFICATE_KINDS:
        why = "No certificate was given (make one with --certificate FILE when solving, and pass it to the report)."
    else:
        why = ("This kind of answer has no certificate file; a limit cycle's claims are verified exactly by "
               "'solverplan cycle' itself (see optimality below).")
    return (f'<section id="certificate" class="none"><h2>Certificate</h2><p><span class="badge" id="certificate-status">'
            f"NOT CERTIFIED</span> {_e(why)}</p></section>")


def _merged(pieces: Iterable[tuple[int, Fraction, Fraction]]) -> dict[int, list[tuple[Fraction, Fraction]]]:
    out: dict[int, list[tuple[Fraction, Fraction]]] = {}
    for edge, lo, hi in sorted(pieces):
        spans = out.setdefault(edge, [])
        if spans and lo <= spans[-1][1]:
            spans[-1] = (spans[-1][0], max(spans[-1][1], hi))
        else:
            spans.append((lo, hi))
    return out


def _certificate_section(answer: AnswerFile, env: Environment, view: _View, cert: Any, cert_path: str) -> tuple[dict, str]:
    """Check ``cert`` exactly, pinned to ``env`` and to the answer's query; refuse a certificate of something else."""
    from solverplan.certify.check import certified, check_certificate

    said = certified(cert)
    mine = EnvironmentRecord.of(env).sha256
    if said["environment"]["sha256"] != mine:
        raise InputError(f"{cert_path}: the certificate is about another environment ({said['environment']['name']!r}, "
                         f"sha256 {said['environment']['sha256'][:12]}…), not {env.name!r} (sha256 {mine[:12]}…)")
    wanted = _CERTIFICATE_KINDS[answer.kind]
    if wanted == "plan" and answer.data.get("status") == "infeasible":
        wanted = "infeasible"  # a proof that there is no plan (issue #22)
    have = cert.kind
    if have != wanted and not (wanted == "localize" and have == "funnel" and str(cert.claims.objective or "").startswith("localize")):
        raise InputError(f"{cert_path}: a {have} certificate does not certify {ANSWER_KINDS[answer.kind]}")
    if have != "infeasible" and view.bounces is not None and cert.claims.bounces != view.bounces:
        raise InputError(f"{cert_path}: the certificate claims {cert.claims.bounces} bounces, the answer has {view.bounces}: "
                         "it certifies another answer")
    query: dict[str, Any] = {}
    for key, spec in (("start", view.start), ("goal", view.goal)):
        if spec is None:
            continue
        pieces = [(p.edge, Fraction(p.t0), Fraction(p.t1)) for p in env.boundary_set(spec).pieces]
        theirs = cert.start if key == "start" else (cert.goal or ())
        if _merged(pieces) != _merged((p.edge, p.t0, p.t1) for p in theirs):
            shown = said[key]["set"] if said.get(key) else "none"
            raise InputError(f"{cert_path}: the certificate's {key} set is {shown}, the answer's is {spec}: it certifies "
                             "another query")
        query[f"expected_{key}"] = pieces
    report = check_certificate(cert, expected_rings=env.rings, **query)
    verdict = report.verdict_json()  # the verdict every check gives (solverplan.verdict)
    rows = [("file", cert_path), ("kind", f"{report.kind} (version {report.version})"),
            ("environment", f"{said['environment']['name']} (sha256 {said['environment']['sha256']})")]
    if said.get("start"):
        rows.append(("start", f"{said['start']['set']} (length {said['start']['length']})"))
    if said.get("goal"):
        rows.append(("goal", f"{said['goal']['set']} (length {said['goal']['length']})"))
    claims = said["claims"]
    for key in ("bounces", "min_width", "tolerance", "sum_width", "objective", "epsilon"):
        if claims.get(key) is not None:
            rows.append((f"claims.{key}", str(claims[key])))
    if "cycle" in claims:
        c = claims["cycle"]
        rows.append(("claims.cycle", f"return map t ↦ {c['alpha']} t + {c['beta']}; fixed point {c['fixed_point']}; "
                                     f"contraction {c['contraction']}"))
    body = _section(report, rows, ", against this environment and this answer's query; nothing the certificate claims "
                    "was taken on trust but what is listed below.",
                    exact=("claims.min_width", "claims.tolerance", "claims.sum_width", "claims.cycle", "environment"))
    return verdict, body


def _section(report: Any, rows: list[tuple[str, str]], against: str, *, exact: Sequence[str] = ()) -> str:
    """The certificate section of either shape of certificate: the verdict's badge, what the checker checked it
    against (``against`` ends the sentence), the table of ``rows`` with the verdict's scope, what it checked exactly
    and what it proved, then its failures and what it did not re-derive."""
    state = "valid" if report.valid else "invalid"
    rows = [*rows, ("scope", report.scope),
            ("checked exactly", ", ".join(f"{v} {k.replace('_', ' ')}" for k, v in report.checked)),
            *(("proved", statement) for statement in report.proved)]
    return (f'<section id="certificate" class="{state}"><h2>Certificate</h2>'
            f'<p><span class="badge" id="certificate-status">{state.upper()}</span> checked now, in exact rational '
            "arithmetic, by solverplan's independent checker (solverplan.certify.check)" + against + "</p>"
            + _table(rows, table_id="certificate-claims", exact=exact)
            + _failures_and_trusted(report) + "</section>")


def _failures_and_trusted(report: Any) -> str:
    """The verdict's failures and what it did not re-derive, as the section's two lists (none when empty)."""
    failures = "".join(f'<li class="failure">{_e(f)}</li>' for f in report.failures)
    trusted = "".join(f"<li>{_e(item)}</li>" for item in report.not_checked)
    return ((f"<p>Failures:</p><ul id=\"certificate-failures\">{failures}</ul>" if failures else "")
            + (f"<p>Not re-derived:</p><ul>{trusted}</ul>" if trusted else ""))


_MODEL_CERTIFICATE_KINDS: dict[str, str] = {
    "rooms": "rooms", "exploration": "exploration", "range-exploration": "exploration", "cut-ordering": "cut-ordering",
    "learned-ordering": "cut-ordering", "pursuit": "pursuit", "fields": "fields"}
"""The certificate kind that certifies each answer kind of the other robot models."""


def _model_certificate_section(answer: AnswerFile, env: Environment | None, cert: Any, cert_path: str) -> tuple[dict, str]:
    """Check the certificate of a rooms, exploration, cut-ordering, pursuit or fields answer exactly (its environment
    pinned to ``env`` when known); refuse a certificate of another kind of answer."""
    from solverplan.certify.check import check_certificate

    wanted = _MODEL_CERTIFICATE_KINDS.get(answer.kind)
    have = getattr(cert, "kind", None)
    if wanted is None:
        raise InputError(f"{answer.path}: {ANSWER_KINDS[answer.kind]} has no certificate: drop --certificate")
    if have != wanted:
        raise InputError(f"{cert_path}: a {have} certificate does not certify {ANSWER_KINDS[answer.kind]}")
    report = check_certificate(cert, expected_rings=env.rings) if env is not None else check_certificate(cert)
    verdict = report.verdict_json()  # the verdict every check gives (solverplan.verdict)
    rows = [("file", cert_path), ("kind", f"{report.kind} (version {report.version})")]
    said = report.to_json() if hasattr(report, "to_json") else {}
    claims = said.get("claims") if isinstance(said, dict) else None
    if isinstance(claims, dict):
        rows += [(f"claims.{k}", json.dumps(v, ensure_ascii=False)[:300] if isinstance(v, (dict, list)) else str(v))
                 for k, v in claims.items()]
    body = _section(report, rows, (", against this environment" if env is not None else "") + ".")
    return verdict, body
