"""Self-contained HTML reports of answers of every kind: ``solverplan report ANSWER.json`` (docs/contract.md, "report").

A report is one HTML file that needs nothing else — no network, no CDN, no image files: the environment and the
answer are an inline SVG whose every element carries a ``<title>`` (the browser's tooltip) and ``data-*``
attributes, which a few lines of inline script show in a details panel, use to highlight one stage in the picture
and the tables together, and to zoom (wheel, buttons) and pan (drag) large maps. Below the picture: the
certificate's status, **checked when the report is made** by the exact checker (nothing the file claims is
trusted), the numbers of the answer (exact numbers shortened for display, the whole value in their tooltip), and
the command that reproduces it.

The package has one module per concern: :mod:`._kinds` (which answers there are, reading answer files by their
``kind``), :mod:`.format` (numbers and text for people), :mod:`.svg` (the picture's coordinates and elements),
:mod:`.page` (the document, style, script, tables), :mod:`.certificate` (the checked certificate), and the views
of the answers: :mod:`.bounce` (plans, fronts, patrols, funnels, localisation, cycles, controllers),
:mod:`.models` (rooms, exploration, cut orderings, pursuit, fields, and a table view of the other kinds) and
:mod:`.study`. Geometry is recomputed from the environment in floats: the picture illustrates, the checker decides.

>>> from solverplan.environment import Environment
>>> from solverplan.plan import find_plan
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="<box>")
>>> answer = AnswerFile("plan.json", "plan", find_plan(env, "e0", "e2").to_json())
>>> page = html_report(answer, env, env_label="box.json")
>>> page.kind, "<box>" in page.html, "&lt;box&gt;" in page.html, page.html.count('class="hover cone"') >= 2
('plan', False, True, True)
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.render.report._kinds import (ANSWER_KINDS, NEEDS_ENVIRONMENT, REPORT_OPTIONS, AnswerFile, _CERTIFICATE_KINDS,
                                             detect_answer_kind, load_answer)
from solverplan.render.report.bounce import _CycleReport, _FunnelReport, _PatrolReport, _PlanReport
from solverplan.render.report.certificate import _certificate_section, _model_certificate_section, _no_certificate
from solverplan.render.report.models import MODEL_VIEWS
from solverplan.render.report.page import HtmlReport, SavedReport, _page, write_report
from solverplan.render.report.study import _Study
from solverplan.result import EnvironmentRecord

__all__ = ["ANSWER_KINDS", "REPORT_OPTIONS", "AnswerFile", "HtmlReport", "SavedReport", "detect_answer_kind",
           "load_answer", "html_report", "write_report", "report_environment", "make_report"]

_BOUNCE_VIEWS = {"plan": _PlanReport, "pareto": _PlanReport, "patrol": _PatrolReport, "funnel": _FunnelReport,
                 "localize": _FunnelReport, "cycle": _CycleReport, "controller": _CycleReport}


def report_environment(answer: AnswerFile, certificate_path: str | Path | None = None) -> Environment | None:
    """The environment an answer was made in, when the answer file alone does not say where it is: the exact rings
    of its certificate (every certificate carries them), else the shipped model its ``environment.name`` names
    when the SHA-256 matches; ``None`` when neither is there (the caller then asks for ``--env``).

    Raises
    ------
    MalformedFile
        An unreadable certificate file.
    """
    record = answer.data.get("environment")
    sha = record.get("sha256") if isinstance(record, dict) else None
    if certificate_path is not None:
        from solverplan.limits import read_text_within_limits

        from solverplan._io import check_json_values

        text = read_text_within_limits(Path(certificate_path))
        check_json_values(text, str(certificate_path))  # before parsing: memory in proportion to the file
        try:
            raw = json.loads(text)
        except (ValueError, RecursionError):
            raise MalformedFile(f"{certificate_path}: not valid JSON") from None
        env_block = raw.get("environment") if isinstance(raw, dict) else None
        rings = env_block.get("rings") if isinstance(env_block, dict) else None
        if isinstance(env_block, dict) and isinstance(rings, list) and rings:
            try:
                env = Environment.from_coords(rings[0], rings[1:], name=str(env_block.get("name") or "environment"))
            except (InputError, TypeError, ValueError):
                env = None
            if env is not None and (sha is None or EnvironmentRecord.of(env).sha256 == sha):
                return env
    name = record.get("name") if isinstance(record, dict) else (record if isinstance(record, str) else None)
    if isinstance(name, str) and name:
        from solverplan import models

        if name in models.names():
            env = models.load(name)
            if sha is None or EnvironmentRecord.of(env).sha256 == sha:
                return env
    return None


def html_report(
    answer: AnswerFile,
    env: Environment | None = None,
    *,
    certificate: Any = None,
    certificate_path: str | None = None,
    env_label: str | None = None,
    output: str | None = None,
) -> HtmlReport:
    """The self-contained HTML report of ``answer`` in ``env`` (module docstring).

    Parameters
    ----------
    answer
        The answer (:func:`load_answer`).
    env
        The environment the answer was made in; required for every kind but ``study`` (which has none, and
        refuses one).
    certificate
        A parsed certificate of the answer (:func:`solverplan.certify.schema.load_certificate`): checked here,
        exactly, with its environment pinned to ``env`` and its start and goal sets to the answer's.
    certificate_path, env_label, output
        How the certificate, the environment and the report were named on the command line: they go into the
        command that reproduces the answer and the one that made the page (default: the environment's name).

    Returns
    -------
    HtmlReport
        The page (``html``), its ``kind`` and ``title``, and the certificate's verdict when one was given.

    Raises
    ------
    InputError
        The answer was made in another environment (its SHA-256 differs, or it names segments or edges ``env``
        lacks); the certificate is of another kind of answer, another environment, another start or goal set or
        another number of bounces; a certificate for an answer that has none (cycles, studies); an environment
        for a study, or none for the kinds drawn over their environment. A malformed answer is
        :class:`~solverplan.errors.MalformedFile`.

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> plan = sp.find_plan(env, "e5", "e0:0:0.3")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plan.json"
    >>> _ = path.write_text(json.dumps(plan.to_json()))
    >>> page = sp.html_report(sp.load_answer(path), env, certificate=sp.certificate(plan, env=env))
    >>> print(page.to_text(), end="")
    report of a plan (solverplan plan -o): l_shape: fewest plan e5 → e0:0:0.3: 1 bounce, tolerance ±0.1452 rad; certificate VALID (checked exactly)
    >>> sp.html_report(sp.load_answer(path), sp.load_environment("square"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: .../plan.json: the answer was made in another environment ('l_shape', sha256 7da40167f198…), not in 'square'
    """
    kind = answer.kind
    if kind == "study":
        if env is not None:
            raise InputError(f"{answer.path}: a study runs over random environments: give no ENV with --study")
        if certificate is not None:
            raise InputError(f"{answer.path}: a study has no certificate: drop --certificate")
        body = _Study(answer).render()
        return _page(body, kind, "", answer, None, None, output, env_label)
    if env is None and kind in NEEDS_ENVIRONMENT:
        raise InputError(f"{answer.path}: {ANSWER_KINDS[kind]} refers to the edges of its environment: give it (--env ENV)")
    label = env_label or (env.name if env is not None else None) or "ENV"
    if kind in _BOUNCE_VIEWS:
        assert env is not None
        if certificate is not None and kind not in _CERTIFICATE_KINDS:
            raise InputError(f"{answer.path}: {ANSWER_KINDS[kind]} has no certificate (only plans, patrols, funnels and "
                             "localisation strategies do): drop --certificate")
        view = _BOUNCE_VIEWS[kind](answer, env, label)
        verdict = None
        cert_html = _no_certificate(kind, answer.data.get("status") == "found" or kind == "pareto")
        if certificate is not None:
            verdict, cert_html = _certificate_section(answer, env, view, certificate, certificate_path or "CERT.json")
        body = view.render(cert_html, certificate_path)
        return _page(body, kind, view.title, answer, verdict, certificate_path, output, env_label or env.name)
    model_view = MODEL_VIEWS[kind](answer, env, label)
    verdict = None
    cert_html = _no_certificate(kind, answer.data.get("status", "found") == "found")
    if certificate is not None:
        verdict, cert_html = _model_certificate_section(answer, env, certificate, certificate_path or "CERT.json")
    body = model_view.render(cert_html, certificate_path)
    return _page(body, kind, model_view.title, answer, verdict, certificate_path, output, env_label)


def make_report(answer_path: str | Path, output: str | Path, *, env: Environment | None = None, env_label: str | None = None,
                certificate_path: str | Path | None = None, option: str | None = None) -> SavedReport:
    """The report of an answer file of any kind, written atomically: what ``solverplan report ANSWER.json`` does.

    It reads the answer (its ``kind`` says what it is), finds its environment, checks its certificate exactly and
    writes the page.

    Parameters
    ----------
    answer_path
        The answer's JSON file, as a command wrote it with ``-o``.
    output
        The page to write (``.html`` or ``.htm``).
    env, env_label
        The environment the answer was made in and how it was named; without it, the certificate's rings or the
        shipped model the answer names (:func:`report_environment`).
    certificate_path
        The answer's certificate, checked exactly now.
    option
        The older form ``report ENV --plan P.json``: the option the answer was given with (it must take that kind).

    Returns
    -------
    SavedReport
        What was written; ``report.certificate`` holds the checker's verdict (``None`` without a certificate).

    Raises
    ------
    InputError
        A name not ending in .html, a malformed or foreign answer or certificate, an answer whose environment
        cannot be found (give ``env``).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> from solverplan.rectilinear import decompose_rooms
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rooms = decompose_rooms(sp.load_environment("three_chambers"))
    >>> _ = (folder / "rooms.json").write_text(json.dumps(rooms.to_json()))
    >>> saved = sp.make_report(folder / "rooms.json", folder / "rooms.html")   # the shipped model, found by name
    >>> saved.to_json()["kind"], "Φ leaving i" in (folder / "rooms.html").read_text(encoding="utf-8")
    ('rooms', True)
    """
    if Path(output).suffix.lower() not in (".html", ".htm"):
        raise InputError(f"-o {output}: a report is an .html file: give -o REPORT.html")
    if not Path(answer_path).exists() and option is None:
        from solverplan import models

        if Path(answer_path).stem in models.names():
            raise InputError(f"{answer_path} is an environment, not an answer: solverplan report ANSWER.json (the file a "
                             "command wrote with -o)")
    answer = load_answer(answer_path, option=option)
    if env is None and answer.kind != "study":
        env = report_environment(answer, certificate_path)
        if env is not None and env_label is None:
            env_label = env.name
    cert = None
    if certificate_path is not None:
        from solverplan.certify.schema import load_certificate

        cert = load_certificate(certificate_path)
    page = html_report(answer, env, certificate=cert, certificate_path=None if certificate_path is None else str(certificate_path),
                       env_label=env_label, output=str(output))
    return write_report(page, output)
