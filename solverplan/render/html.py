"""Self-contained HTML reports of answers: ``solverplan report`` (docs/contract.md, "report").

A report is one HTML file that needs nothing else — no network, no CDN, no image files: the environment and
the answer are an inline SVG whose every element (edge, segment of P′, cone, landing segment, position set,
contact point, heatmap cell) carries a ``<title>`` (the browser's tooltip) and ``data-*`` attributes, which a
few lines of inline script show in a details panel and use to highlight one stage in the picture and in the
tables together. Below the picture: the certificate's status, **checked when the report is made** by the
exact checker (:func:`solverplan.certify.check.check_certificate`; nothing the file claims is trusted), the
numbers of the answer, and the command that reproduces it.

Answers come from the JSON the CLI writes (:func:`load_answer`): plans and Pareto fronts (``plan -o``),
patrols (``patrol -o``), funnel and localisation answers (``funnel -o``, ``localize -o``), limit cycles and
constant controllers (``cycle -o``), and studies (``study ... -o`` or the study's ``NAME.json``). Geometry is
recomputed from the environment (the partition P′ of :mod:`solverplan.bounce.partition`, the swept regions
of :mod:`solverplan.render._swept`, the batch ray caster), in floats: the picture illustrates, the checker
decides.

Safety: every piece of text that comes from a file (environment names, boundary sets, reasons, file paths)
is escaped (:func:`html.escape`); the page carries a Content-Security-Policy that forbids every network
request and runs only its own script and style (by their SHA-256), so even an unescaped string could not
load or run anything.

>>> from solverplan.environment import Environment
>>> from solverplan.plan import find_plan
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="<box>")
>>> answer = AnswerFile("plan.json", "plan", find_plan(env, "e0", "e2").to_json())
>>> page = html_report(answer, env, env_label="box.json")
>>> page.kind, "<box>" in page.html, "&lt;box&gt;" in page.html, page.html.count('class="hover cone"') >= 2
('plan', False, True, True)
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
import math
import os
import shlex
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Sequence

import numpy as np

from solverplan._io import atomic_write_text
from solverplan.environment import Environment, read_json
from solverplan.errors import InputError, MalformedFile
from solverplan.limits import quote, read_text_within_limits
from solverplan.render._swept import swept_regions
from solverplan.render.figure import (
    BOUNDARY_COLOR,
    CONE_COLOR,
    CYCLE_COLOR,
    CYCLE_POINT_COLOR,
    EDGE_ID_COLOR,
    FREE_SPACE_COLOR,
    FUNNEL_GOAL_COLOR,
    FUNNEL_START_COLOR,
    PATROL_EDGE_COLOR,
    PLAN_GOAL_COLOR,
    PLAN_STAGE_COLORS,
    PLAN_START_COLOR,
)
from solverplan.result import EnvironmentRecord

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.partition import Partition

__all__ = ["ANSWER_KINDS", "REPORT_OPTIONS", "AnswerFile", "HtmlReport", "SavedReport", "answer_kind", "load_answer",
           "html_report", "write_report"]

ANSWER_KINDS: dict[str, str] = {
    "plan": "a plan (solverplan plan -o)",
    "pareto": "a Pareto front (solverplan plan --pareto -o)",
    "patrol": "a patrol cycle (solverplan patrol -o)",
    "funnel": "a funnel (solverplan funnel -o)",
    "localize": "a localisation strategy (solverplan localize -o)",
    "cycle": "a limit cycle (solverplan cycle -o)",
    "controller": "a constant controller (solverplan cycle --theta auto -o)",
    "study": "a study (solverplan study -o, or the study's NAME.json)",
}
"""The kinds of answer a report can show, and what writes them."""

REPORT_OPTIONS: dict[str, tuple[str, ...]] = {
    "plan": ("plan", "pareto"),
    "patrol": ("patrol",),
    "funnel": ("funnel", "localize"),
    "cycle": ("cycle", "controller"),
    "study": ("study",),
}
"""The ``solverplan report`` option that takes each kind of answer (``--plan`` takes plans and Pareto fronts, ...)."""

_CERTIFICATE_KINDS = {"plan": "plan", "pareto": "plan", "patrol": "cycle", "funnel": "funnel", "localize": "localize"}

_WIDTH, _MAX_HEIGHT, _PAD = 780.0, 600.0, 30.0
_EXACT_CELL = ' class="exact"'  # table cells holding exact numbers: monospace, wrapped anywhere
HOLE_COLOR = "#d9dfe6"  # the holes of the environment (obstacles)


# ====================================================================== reading answers
@dataclass(frozen=True)
class AnswerFile:
    """An answer as the CLI wrote it: where it came from (``path``, for messages and the page), its ``kind``
    (a key of :data:`ANSWER_KINDS`) and its JSON ``data``."""

    path: str
    kind: str
    data: dict


def answer_kind(data: object) -> str | None:
    """The kind of answer ``data`` is (a key of :data:`ANSWER_KINDS`), told by the fields each answer always has;
    ``None`` for anything else (a certificate, an environment, a verify report, ...).

    >>> answer_kind({"status": "found", "objective": "fewest", "stages": []}), answer_kind({"outer": []})
    ('plan', None)
    """
    if not isinstance(data, dict):
        return None
    if isinstance(data.get("study"), dict) and isinstance(data.get("cells"), list):
        return "study"
    if "status" not in data:
        return None
    if isinstance(data.get("cycles"), list) and "tried" in data:
        return "controller"
    if "visit" in data and isinstance(data.get("cycle"), list):
        return "patrol"
    if isinstance(data.get("cycle"), list) and "fixed_point" in data and "theta" in data:
        return "cycle"
    if data.get("kind") in ("funnel", "localize") and isinstance(data.get("stages"), list):
        return str(data["kind"])
    if isinstance(data.get("front"), list) and isinstance(data.get("points"), list):
        return "pareto"
    if isinstance(data.get("stages"), list) and "objective" in data:
        return "plan"
    return None


def load_answer(path: str | os.PathLike[str], *, option: str | None = None) -> AnswerFile:
    """Read an answer file the CLI wrote (or an answer's ``to_json()``), and tell which kind of answer it is.

    Parameters
    ----------
    path
        The answer file (JSON): a plan, Pareto front, patrol, funnel, localisation strategy, limit cycle,
        constant controller or study.
    option
        A key of :data:`REPORT_OPTIONS` (``"plan"``, ``"patrol"``, ...): the answer must be of a kind that
        ``solverplan report`` option takes.

    Returns
    -------
    AnswerFile
        Its ``path``, ``kind`` (a key of :data:`ANSWER_KINDS`) and JSON ``data``.

    Raises
    ------
    MalformedFile
        A missing or unreadable file, bad JSON, a file past the input limits, a file that is no answer, or an
        answer of a kind ``option`` does not take (the message names the option that does).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> plan = sp.find_plan(sp.load_environment("l_shape"), "e5", "e0:0:0.3")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plan.json"
    >>> _ = path.write_text(json.dumps(plan.to_json()))
    >>> sp.load_answer(path).kind
    'plan'
    >>> sp.load_answer(path, option="patrol")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: .../plan.json: is a plan (solverplan plan -o), not what --patrol takes: give it with --plan
    """
    file = Path(path)
    text = read_text_within_limits(file)
    try:
        data = read_json(text, exact=False)
    except json.JSONDecodeError as exc:
        raise MalformedFile(f"{file}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except MalformedFile as exc:
        raise MalformedFile(f"{file}: {exc}") from None
    kind = answer_kind(data)
    if kind is None:
        if isinstance(data, dict) and data.get("schema") == "solverplan-certificate":
            raise MalformedFile(f"{file}: is a certificate, not an answer: give it with --certificate")
        raise MalformedFile(f"{file}: is no answer solverplan writes (a report shows plans, Pareto fronts, patrols, funnels, "
                            "localisation strategies, limit cycles, constant controllers and studies)")
    if option is not None and kind not in REPORT_OPTIONS[option]:
        wanted = next(name for name, kinds in REPORT_OPTIONS.items() if kind in kinds)
        raise MalformedFile(f"{file}: is {ANSWER_KINDS[kind]}, not what --{option} takes: give it with --{wanted}")
    assert isinstance(data, dict)
    return AnswerFile(str(path), kind, data)


# ====================================================================== small helpers
def _e(value: object) -> str:
    """Text (or an attribute value) escaped for HTML and XML: every file-borne string goes through here."""
    return html.escape(str(value), quote=True)


def _num(value: object, digits: int = 6) -> str:
    """A number for people: floats to ``digits`` significant digits, the rest as text."""
    if isinstance(value, bool) or value is None:
        return {True: "yes", False: "no", None: "—"}[value]
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        return f"{value:.{digits}g}"
    return str(value)


def _plain(value: object) -> str:
    """A number for a command line: the shortest text that reads back as the same float (``0.1``, not ``0.1000…01``)."""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _rad(value: object) -> str:
    """An angle in radians with its degrees."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{float(value):.6g} rad ({math.degrees(float(value)):.4g}°)"
    return _num(value)


def _interval(iv: Sequence[float]) -> str:
    return f"[{float(iv[0]):.6g}, {float(iv[1]):.6g}] rad"


def _short_exact(text: object, limit: int = 40) -> str:
    """An exact number's text, cut with … past ``limit`` characters (the whole text stays in the tables)."""
    s = str(text)
    return s if len(s) <= limit else s[: limit - 1] + "…"


def _ints(value: object, where: str) -> list[int]:
    if not isinstance(value, list) or not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in value):
        raise MalformedFile(f"{where}: expected a list of non-negative integers")
    return list(value)


def _finite(value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise MalformedFile(f"{where}: expected a finite number, got {quote(value)}")
    return float(value)


def _heading_interval(value: object, where: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise MalformedFile(f"{where}: expected [lo, hi]")
    lo, hi = _finite(value[0], f"{where}[0]"), _finite(value[1], f"{where}[1]")
    if not 0 < lo <= hi < math.pi:
        raise MalformedFile(f"{where}: [{value[0]}, {value[1]}] is not inside (0, π)")
    return lo, hi


class _Canvas:
    """World coordinates → SVG pixels (y up → y down), the bounding box fitted into the picture."""

    def __init__(self, bounds: tuple[float, float, float, float]) -> None:
        xmin, ymin, xmax, ymax = bounds
        w, h = max(xmax - xmin, 1e-12), max(ymax - ymin, 1e-12)
        self.scale = min((_WIDTH - 2 * _PAD) / w, (_MAX_HEIGHT - 2 * _PAD) / h)
        self.width = w * self.scale + 2 * _PAD
        self.height = h * self.scale + 2 * _PAD
        self.xmin, self.ymax = xmin, ymax

    def xy(self, x: float, y: float) -> tuple[float, float]:
        return (_PAD + (float(x) - self.xmin) * self.scale, _PAD + (self.ymax - float(y)) * self.scale)

    def points(self, pts: Iterable[Sequence[float]]) -> str:
        return " ".join("%.2f,%.2f" % self.xy(p[0], p[1]) for p in pts)

    def path(self, rings: Iterable[Iterable[Sequence[float]]]) -> str:
        out = []
        for ring in rings:
            pts = ["%.2f %.2f" % self.xy(p[0], p[1]) for p in ring]
            out.append("M" + " L".join(pts) + " Z")
        return " ".join(out)


def _el(tag: str, attrs: dict[str, object], title: str | None = None, body: str = "") -> str:
    """An SVG element with escaped attributes and an optional ``<title>`` (its tooltip and details text)."""
    text = "".join(f' {k}="{_e(v)}"' for k, v in attrs.items() if v is not None)
    inner = (f"<title>{_e(title)}</title>" if title else "") + body
    return f"<{tag}{text}>{inner}</{tag}>" if inner else f"<{tag}{text}/>"


def _line(c: _Canvas, a: Sequence[float], b: Sequence[float], attrs: dict[str, object], title: str | None = None) -> str:
    (x1, y1), (x2, y2) = c.xy(a[0], a[1]), c.xy(b[0], b[1])
    return _el("line", {"x1": f"{x1:.2f}", "y1": f"{y1:.2f}", "x2": f"{x2:.2f}", "y2": f"{y2:.2f}", **attrs}, title)


def _stage_colour(k: int) -> str:
    return PLAN_STAGE_COLORS[k % len(PLAN_STAGE_COLORS)]


# ====================================================================== the page
@dataclass(frozen=True)
class HtmlReport:
    """A report page: the whole self-contained HTML document, and what it reports on.

    Made by :func:`html_report`; :func:`write_report` writes it.

    Attributes
    ----------
    html
        The whole document (styles, scripts and pictures inline: it opens without a network).
    kind
        The answer's kind (a key of :data:`ANSWER_KINDS`).
    title
        The page's title.
    certificate
        The checker's verdict when a certificate was given (``{"valid", "kind", "failures", "checked",
        "not_checked"}``); ``None`` without one.

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> plan = sp.find_plan(env, "e5", "e0:0:0.3")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plan.json"
    >>> _ = path.write_text(json.dumps(plan.to_json()))
    >>> page = sp.html_report(sp.load_answer(path), env)
    >>> page.kind, page.title, page.certificate
    ('plan', 'l_shape: fewest plan e5 → e0:0:0.3: 1 bounce, tolerance ±0.1452 rad', None)
    >>> page.html.startswith("<!DOCTYPE html>")
    True
    """

    html: str
    kind: str
    title: str
    certificate: dict | None = None

    def to_json(self) -> dict:
        return {"kind": self.kind, "title": self.title, "bytes": len(self.html.encode("utf-8")),
                "certificate": self.certificate}

    def to_text(self, *, width: int = 100) -> str:
        cert = ("no certificate" if self.certificate is None
                else f"certificate {'VALID' if self.certificate['valid'] else 'INVALID'} (checked exactly)")
        return f"report of {ANSWER_KINDS[self.kind]}: {self.title}; {cert}\n"


@dataclass(frozen=True)
class SavedReport:
    """What ``solverplan report`` prints: ``{"written", "kind", "bytes", "certificate"}``."""

    written: str
    report: HtmlReport

    def to_json(self) -> dict:
        return {"written": self.written, "kind": self.report.kind, "bytes": len(self.report.html.encode("utf-8")),
                "certificate": self.report.certificate}

    def to_text(self, *, width: int = 100) -> str:
        return f"wrote {self.written} ({len(self.report.html.encode('utf-8'))} bytes): " + self.report.to_text(width=width)


def write_report(report: HtmlReport, path: str | os.PathLike[str]) -> SavedReport:
    """Write the page atomically (whole or not at all, :mod:`solverplan._io`).

    Parameters
    ----------
    report
        The page (:func:`html_report`).
    path
        The file to write (``.html``); a previous file there is replaced only once the new one is complete.

    Returns
    -------
    SavedReport
        Where the page went and what it reports (what ``solverplan report`` prints).

    Raises
    ------
    InputError
        When the place cannot be written.

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> plan = sp.find_plan(env, "e5", "e0:0:0.3")
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "plan.json").write_text(json.dumps(plan.to_json()))
    >>> page = sp.html_report(sp.load_answer(folder / "plan.json"), env, certificate=sp.certificate(plan, env=env))
    >>> saved = sp.write_report(page, folder / "report.html")
    >>> saved.to_json()["certificate"]["valid"], (folder / "report.html").read_text(encoding="utf-8") == page.html
    (True, True)
    """
    try:
        atomic_write_text(path, report.html)
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror or exc.__class__.__name__})") from None
    return SavedReport(str(path), report)


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
        for a study, or none for the others. A malformed answer is :class:`~solverplan.errors.MalformedFile`.

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
    if env is None:
        raise InputError(f"{answer.path}: {ANSWER_KINDS[kind]} refers to the edges of its environment: give ENV")
    if certificate is not None and kind not in _CERTIFICATE_KINDS:
        raise InputError(f"{answer.path}: {ANSWER_KINDS[kind]} has no certificate (only plans, patrols, funnels and "
                         "localisation strategies do): drop --certificate")
    builder = {"plan": _PlanReport, "pareto": _PlanReport, "patrol": _PatrolReport, "funnel": _FunnelReport,
               "localize": _FunnelReport, "cycle": _CycleReport, "controller": _CycleReport}[kind]
    view = builder(answer, env, env_label or env.name or "ENV")
    verdict = None
    cert_html = _no_certificate(kind, answer.data.get("status") == "found" or kind == "pareto")
    if certificate is not None:
        verdict, cert_html = _certificate_section(answer, env, view, certificate, certificate_path or "CERT.json")
    body = view.render(cert_html, certificate_path)
    return _page(body, kind, view.title, answer, verdict, certificate_path, output, env_label or env.name)


# ---------------------------------------------------------------------- the document around the sections
_STYLE = """
:root{--ink:#1f2a36;--muted:#5b6b7a;--ok:#1b7837;--bad:#b2182b;--warn:#8a6d00;--line:#d5dde6}
*{box-sizing:border-box}
body{margin:0;font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;color:var(--ink);background:#f7f9fb}
header{padding:14px 24px 10px;background:#fff;border-bottom:1px solid var(--line)}
header h1{font-size:19px;margin:0 0 2px}
header p{margin:0;color:var(--muted)}
main{padding:14px 24px 30px;max-width:1400px}
section{background:#fff;border:1px solid var(--line);border-radius:6px;padding:12px 16px;margin:0 0 14px}
section h2{font-size:15px;margin:0 0 8px}
#picture{display:flex;gap:16px;align-items:flex-start;flex-wrap:wrap}
#scene{flex:0 0 auto;max-width:100%;height:auto;background:#fff}
#side{flex:1 1 260px;min-width:240px}
#details{border:1px solid var(--line);border-radius:4px;padding:8px 10px;min-height:86px;background:#fbfcfd;white-space:pre-wrap;font-size:13px}
#details.empty{color:var(--muted)}
.legend{list-style:none;padding:0;margin:10px 0 0;font-size:12.5px}
.legend li{margin:2px 0;display:flex;align-items:center;gap:6px}
.legend svg{flex:0 0 auto}
table{border-collapse:collapse;font-size:13px;margin:4px 0 10px}
th,td{border-bottom:1px solid var(--line);padding:3px 10px 3px 0;text-align:left;vertical-align:top}
th{color:var(--muted);font-weight:600;white-space:nowrap}
td.exact,code{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;font-size:12px;overflow-wrap:anywhere}
tr.hl td{background:#fff3bf}
pre{background:#f1f4f7;border-radius:4px;padding:8px 10px;overflow-x:auto;white-space:pre-wrap;overflow-wrap:anywhere}
.badge{display:inline-block;padding:2px 10px;border-radius:12px;color:#fff;font-weight:700;letter-spacing:.04em}
.valid .badge{background:var(--ok)}.invalid .badge{background:var(--bad)}.none .badge{background:#8795a1}
.failure{color:var(--bad)}
details summary{cursor:pointer;color:var(--muted)}
#scene .hover{cursor:pointer}
#scene .hit{stroke:transparent;fill:none}
#scene .hl{stroke:#ffbf00 !important;stroke-opacity:1 !important}
#scene polygon.hl{fill-opacity:.55 !important}
#scene text{font-family:system-ui,sans-serif;pointer-events:none}
.heat{display:inline-block;margin:0 18px 12px 0;vertical-align:top}
"""

_SCRIPT = """
(function () {
  'use strict';
  var panel = document.getElementById('details');
  var hint = panel ? panel.textContent : '';
  function titleOf(el) {
    for (var c = el.firstChild; c; c = c.nextSibling) {
      if (c.nodeName && c.nodeName.toLowerCase() === 'title') { return c.textContent; }
    }
    return el.getAttribute('data-info') || '';
  }
  function mark(stage, on) {
    if (stage === null) { return; }
    var nodes = document.querySelectorAll('[data-stage="' + stage + '"]');
    for (var i = 0; i < nodes.length; i++) { nodes[i].classList.toggle('hl', on); }
  }
  function target(ev) {
    var el = ev.target;
    return el && el.closest ? el.closest('.hover, tr[data-stage]') : null;
  }
  document.addEventListener('mouseover', function (ev) {
    var el = target(ev);
    if (!el) { return; }
    mark(el.getAttribute('data-stage'), true);
    var text = titleOf(el);
    if (panel && text) { panel.textContent = text; panel.classList.remove('empty'); }
  });
  document.addEventListener('mouseout', function (ev) {
    var el = target(ev);
    if (!el) { return; }
    mark(el.getAttribute('data-stage'), false);
  });
  document.addEventListener('mouseleave', function () {
    if (panel) { panel.textContent = hint; panel.classList.add('empty'); }
  });
  document.documentElement.setAttribute('data-report-ready', 'yes');
})();
"""


def _csp_hash(text: str) -> str:
    return "sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii")


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("solverplan")
    except PackageNotFoundError:
        return "(source tree)"


def _report_command(answer: AnswerFile, certificate_path: str | None, output: str | None, env_label: str | None) -> str:
    option = next(name for name, kinds in REPORT_OPTIONS.items() if answer.kind in kinds)
    words = ["solverplan", "report"] + ([env_label] if env_label else []) + [f"--{option}", answer.path]
    if certificate_path:
        words += ["--certificate", certificate_path]
    words += ["-o", output or "REPORT.html"]
    return shlex.join(words)


def _page(body: str, kind: str, title: str, answer: AnswerFile, verdict: dict | None, certificate_path: str | None,
          output: str | None, env_label: str | None) -> HtmlReport:
    heading = f"solverplan report: {ANSWER_KINDS[kind].split(' (')[0]}"
    full_title = f"{heading}{' — ' + title if title else ''}"
    csp = (f"default-src 'none'; style-src '{_csp_hash(_STYLE)}'; script-src '{_csp_hash(_SCRIPT)}'; img-src data:; "
           "base-uri 'none'; form-action 'none'")
    made = _report_command(answer, certificate_path, output, env_label)
    doc = (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<meta http-equiv=\"Content-Security-Policy\" content=\"{_e(csp)}\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        f"<meta name=\"generator\" content=\"solverplan {_e(_version())}\">\n"
        f"<title>{_e(full_title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
        f"<header><h1 id=\"report-title\">{_e(heading)}</h1><p>{_e(title)}</p></header>\n<main>\n{body}\n"
        f"<footer><p>Made by solverplan {_e(_version())} with <code id=\"made-with\">{_e(made)}</code>. "
        "Everything on this page is in this one file"
        f"{'; the certificate was checked exactly when the page was made' if verdict is not None else ''}.</p>"
        "</footer>\n</main>\n"
        f"<script>{_SCRIPT}</script>\n</body>\n</html>\n"
    )
    return HtmlReport(doc, kind, title or heading, verdict)


def _table(rows: Sequence[tuple[str, str]], *, table_id: str | None = None, exact: Sequence[str] = ()) -> str:
    """A two-column table of (name, already formatted value) pairs, both escaped here."""
    attrs = f' id="{_e(table_id)}"' if table_id else ""
    cells = "".join(f"<tr><th>{_e(k)}</th><td{_EXACT_CELL if k in exact else ''}>{_e(v)}</td></tr>" for k, v in rows)
    return f"<table{attrs}>{cells}</table>"


def _grid(header: Sequence[str], rows: Sequence[Sequence[str]], *, table_id: str, stage_rows: bool = False) -> str:
    """A table with a header row; with ``stage_rows`` row k carries ``data-stage="k"`` (highlighted with the picture)."""
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = []
    for k, row in enumerate(rows):
        attr = f' data-stage="{k}"' if stage_rows else ""
        body.append(f"<tr{attr}>" + "".join(f"<td>{_e(v)}</td>" for v in row) + "</tr>")
    return f'<table id="{_e(table_id)}"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


def _optimality_rows(opt: object) -> list[tuple[str, str]]:
    if not isinstance(opt, dict):
        return []
    rows = [("optimality method", _num(opt.get("method"))), ("optimality proved", _num(opt.get("proved"))),
            ("optimality bound", _num(opt.get("bound"))), ("optimality gap", _num(opt.get("gap")))]
    for key in ("scope", "algorithm"):
        if opt.get(key):
            rows.append((key, str(opt[key])))
    if opt.get("limits"):
        rows.append(("limits", ", ".join(str(x) for x in opt["limits"])))
    return rows


def _environment_rows(data: dict) -> list[tuple[str, str]]:
    record = data.get("environment")
    if not isinstance(record, dict):
        return []
    rows = [("environment", str(record.get("name", ""))), ("environment sha256", str(record.get("sha256", "")))]
    if record.get("n_segments") is not None:
        rows.append(("segments of P′", str(record["n_segments"])))
    return rows


def _stats_block(data: dict) -> str:
    stats = data.get("stats")
    if not isinstance(stats, dict) or not stats:
        return ""
    rows = [(str(k), _num(v) if not isinstance(v, (dict, list)) else json.dumps(v)[:200]) for k, v in stats.items()]
    return f"<details><summary>search statistics (recorded, not part of the answer)</summary>{_table(rows)}</details>"


def _no_certificate(kind: str, answered: bool = True) -> str:
    if kind in ("plan", "pareto") and not answered:
        why = ("No certificate was given: an infeasible plan's certificate (--certificate FILE when solving) proves "
               "that there is no plan; without it, what the answer proves rests on its search (see optimality below).")
    elif kind in _CERTIFICATE_KINDS and not answered:
        why = ("An answer that found no strategy has no certificate: what it proves rests on its search "
               "(see optimality below).")
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
    verdict = {"valid": report.valid, "kind": report.kind, "failures": [str(f) for f in report.failures],
               "checked": dict(report.checked), "not_checked": list(report.not_checked)}
    state = "valid" if report.valid else "invalid"
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
    rows.append(("checked exactly", ", ".join(f"{v} {k.replace('_', ' ')}" for k, v in report.checked)))
    rows.extend(("proved", statement) for statement in report.proved)
    failures = "".join(f'<li class="failure">{_e(f)}</li>' for f in report.failures)
    trusted = "".join(f"<li>{_e(item)}</li>" for item in report.not_checked)
    body = (f'<section id="certificate" class="{state}"><h2>Certificate</h2>'
            f'<p><span class="badge" id="certificate-status">{state.upper()}</span> checked now, in exact rational '
            "arithmetic, by solverplan's independent checker (solverplan.certify.check), against this environment and "
            "this answer's query; nothing the certificate claims was taken on trust but what is listed below.</p>"
            + _table(rows, table_id="certificate-claims", exact=("claims.min_width", "claims.tolerance", "claims.sum_width",
                                                                  "claims.cycle", "environment"))
            + (f"<p>Failures:</p><ul id=\"certificate-failures\">{failures}</ul>" if failures else "")
            + (f"<p>Not re-derived:</p><ul>{trusted}</ul>" if trusted else "") + "</section>")
    return verdict, body


# ====================================================================== views of the answers
class _View:
    """What every report of an answer over an environment draws: the environment with edge ids and hover details;
    subclasses add the answer's layers, its numbers and the command that reproduces it."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        self.answer, self.data, self.env, self.env_label = answer, answer.data, env, env_label
        self.canvas = _Canvas(env.bounds)
        self.legend: list[tuple[str, str, str]] = []  # (colour, shape, text)
        self.bounces: int | None = None  # what a certificate must claim
        self.start: str | None = None
        self.goal: str | None = None
        self.contraction: dict[int, float] = {}  # stage → its worst-case contraction coefficient (plans, entries)
        self.check_environment()

    # -- checks
    def check_environment(self) -> None:
        try:
            record = EnvironmentRecord.from_json(self.data.get("environment"), f"{self.answer.path}: environment")
        except ValueError as exc:
            raise MalformedFile(str(exc)) from None
        if record is not None and not record.matches(self.env):
            raise InputError(f"{self.answer.path}: the answer was made in another environment ({record.name or '?'!r}, "
                             f"sha256 {record.sha256[:12]}…), not in {self.env.name!r}")

    def edge_id(self, value: object, where: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < self.env.n_edges:
            raise InputError(f"{self.answer.path}: {where} names edge {quote(value)}, but {self.env.name!r} has edges "
                             f"0..{self.env.n_edges - 1}")
        return value

    @property
    def title(self) -> str:
        return self.env.name or self.env_label

    # -- the picture
    def environment_layer(self) -> str:
        c, env = self.canvas, self.env
        rings = [[(float(x), float(y)) for x, y in ring] for ring in env.rings]
        parts = [_el("path", {"d": c.path(rings), "fill": FREE_SPACE_COLOR, "fill-rule": "evenodd", "stroke": "none",
                              "id": "free-space"})]
        for h, hole in enumerate(rings[1:], start=1):  # obstacles: grey, so they do not read as the outside
            parts.append(_el("path", {"d": c.path([hole]), "fill": HOLE_COLOR, "stroke": "none", "class": "hover hole"},
                             f"hole {h} (an obstacle): edges e{env.ring_offsets[h]}..e{env.ring_offsets[h + 1] - 1}"))
        starts, ends, lengths = env.edge_start, env.edge_end, env.edge_lengths
        ring_of_edge = env.ring_of
        for i in range(env.n_edges):
            a, b = starts[i], ends[i]
            kind = "outer ring" if int(ring_of_edge[i]) == 0 else f"hole {int(ring_of_edge[i])}"
            title = (f"edge e{i} ({kind}): from ({a[0]:.6g}, {a[1]:.6g}) to ({b[0]:.6g}, {b[1]:.6g}), "
                     f"length {lengths[i]:.6g}; t = 0 at the first point")
            parts.append(_line(c, a, b, {"class": "wall", "stroke": BOUNDARY_COLOR, "stroke-width": "2.2",
                                         "stroke-linecap": "round"}))
            parts.append(_line(c, a, b, {"class": "hover hit", "data-edge": i, "stroke-width": "9"}, title))
        return "<g id=\"environment\">" + "".join(parts) + "</g>"

    def edge_labels(self) -> str:
        """``eK`` beside every edge long enough to carry it: outside the free space, or inside when that spot is taken
        (two walls facing each other across a thin gap); left out where both are (the edge's tooltip still names it)."""
        c, env = self.canvas, self.env
        if env.n_edges > 300:
            return ""
        out = []
        taken: list[tuple[float, float, float, float]] = []  # label boxes placed so far (pixels)

        def free(x: float, y: float, half: float) -> bool:
            return all(abs(x - u) > half + h or abs(y - v) > 7.0 for u, v, h, _ in taken)

        for i in range(env.n_edges):
            a, b = env.edge_start[i], env.edge_end[i]
            d = b - a
            length = float(np.hypot(d[0], d[1]))
            if length * c.scale < 18:  # too short to label legibly (door jambs): hover it instead
                continue
            n = np.array([-d[1], d[0]]) / max(length, 1e-300)  # the inward (left) normal
            mx, my = c.xy(*(0.5 * (a + b)))
            half = 3.2 * len(f"e{i}") + 1.0
            for side in (-1.0, 1.0):  # outside the wall first (world y up, pixels down), then inside
                x, y = mx + side * 11 * n[0], my - side * 11 * n[1]
                if free(x, y, half):
                    taken.append((x, y, half, 0.0))
                    out.append(_el("text", {"x": f"{x:.1f}", "y": f"{y:.1f}", "class": "edge-id", "font-size": "10.5",
                                            "fill": EDGE_ID_COLOR, "text-anchor": "middle", "dominant-baseline": "middle"},
                                   body=_e(f"e{i}")))
                    break
        return "<g id=\"edge-ids\">" + "".join(out) + "</g>"

    def pieces_layer(self, spec: str | None, colour: str, gid: str, name: str) -> str:
        if not spec:
            return ""
        pieces = self.env.boundary_set(spec).pieces
        out = []
        for p in pieces:
            a = self.env.point_at(p.edge, float(p.t0))
            b = self.env.point_at(p.edge, float(p.t1))
            out.append(_line(self.canvas, a, b, {"class": "hover", "stroke": colour, "stroke-width": "8",
                                                 "stroke-opacity": "0.55", "stroke-linecap": "butt"},
                             f"{name} set {spec}: e{p.edge}, t ∈ [{p.t0}, {p.t1}]"))
        self.legend.append((colour, "line", f"{name} {spec}"))
        return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"

    def svg(self, layers: Sequence[str]) -> str:
        c = self.canvas
        return (f'<svg id="scene" xmlns="http://www.w3.org/2000/svg" width="{c.width:.0f}" height="{c.height:.0f}" '
                f'viewBox="0 0 {c.width:.2f} {c.height:.2f}" role="img" aria-label="{_e(self.title)}">'
                + "".join(layers) + "</svg>")

    def legend_html(self) -> str:
        items = []
        for colour, shape, text in self.legend:
            mark = (f'<rect x="1" y="3" width="16" height="10" fill="{_e(colour)}" fill-opacity="0.5" stroke="{_e(colour)}"/>'
                    if shape == "area" else
                    f'<circle cx="9" cy="8" r="5" fill="{_e(CYCLE_POINT_COLOR)}" stroke="{_e(colour)}"/>' if shape == "point"
                    else f'<line x1="1" y1="8" x2="17" y2="8" stroke="{_e(colour)}" stroke-width="5"/>')
            items.append(f'<li><svg width="18" height="16" xmlns="http://www.w3.org/2000/svg">{mark}</svg>{_e(text)}</li>')
        return '<ul class="legend" id="legend">' + "".join(items) + "</ul>"

    def picture(self, layers: Sequence[str]) -> str:
        hint = "Hover over the picture (walls, segments, cones, points) or a stage row for details."
        return (f'<section id="picture">{self.svg(layers)}<div id="side"><h2>Details</h2>'
                f'<div id="details" class="empty" aria-live="polite">{_e(hint)}</div>{self.legend_html()}</div></section>')

    # -- the sections
    def render(self, cert_html: str, certificate_path: str | None) -> str:
        layers = [self.environment_layer(), *self.layers(), self.edge_labels()]
        numbers = self.numbers()  # after the layers: drawing the stages measured their contraction
        command = self.command(certificate_path)
        return (self.picture(layers) + cert_html + f'<section id="numbers"><h2>The answer</h2>{numbers}'
                f"{_stats_block(self.data)}</section>"
                f'<section id="reproduce"><h2>Reproduce it</h2><pre><code id="command">{_e(command)}</code></pre>'
                f"<p>Answer file: <code>{_e(self.answer.path)}</code>.</p></section>")

    def layers(self) -> list[str]:  # pragma: no cover - every view draws its own
        raise NotImplementedError

    def numbers(self) -> str:  # pragma: no cover
        raise NotImplementedError

    def command(self, certificate_path: str | None) -> str:  # pragma: no cover
        raise NotImplementedError

    # -- shared drawing of stages that move between segments of P′ (plans, patrol entries)
    @cached_property
    def partition(self) -> Partition:
        """P′ of the environment (Algorithm 1): the segments stage ids refer to, built once per report."""
        from solverplan.bounce.partition import partition

        return partition(self.env)

    def segment_layer(self) -> str:
        """Every segment of P′ as a hover target (thin ticks at its ends), with its exact coordinates."""
        part = self.partition
        out = []
        for s in part.segments:
            a, b = (float(s.a[0]), float(s.a[1])), (float(s.b[0]), float(s.b[1]))
            title = f"segment {s.id} of P′: on e{s.edge}, t ∈ [{s.t0}, {s.t1}], from ({a[0]:.6g}, {a[1]:.6g}) to ({b[0]:.6g}, {b[1]:.6g})"
            out.append(_line(self.canvas, a, b, {"class": "hover hit", "data-segment": s.id, "stroke-width": "6"}, title))
            x, y = self.canvas.xy(*a)
            out.append(_el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": "1.6", "fill": BOUNDARY_COLOR}))
        return '<g id="segments">' + "".join(out) + "</g>"

    def move_contraction(self, source: int, target: int, lo: float, hi: float) -> tuple[float, str, float] | None:
        """The worst-case contraction coefficient C over [lo, hi] of a move from edge ``source`` to edge ``target``
        (paper Def. 11, Lemma 2: C is monotone in θ, so the worst case is at a known end), its transition and φ;
        None where the paper's C does not apply (the same wall, or parallel walls facing the same way)."""
        from solverplan.bounce.dynamics import edge_transition, worst_case_contraction

        if source == target:
            return None
        try:
            phi, side = edge_transition(self.env, source, target)
        except InputError:
            return None
        c = worst_case_contraction((lo, hi), phi, side)
        return (c, side, phi) if math.isfinite(c) else None

    def check_segments(self, stages: Sequence[dict], where: str) -> None:
        n = self.partition.n_segments
        for k, st in enumerate(stages):
            for key in ("from_segments", "to_segments"):
                for seg in _ints(st.get(key), f"{self.answer.path}: {where}[{k}].{key}"):
                    if seg >= n:
                        raise InputError(f"{self.answer.path}: {where}[{k}] names segment {seg}, but the partition of "
                                         f"{self.env.name!r} has segments 0..{n - 1}: the answer is for another environment")

    def segment_stage_layer(self, stages: Sequence[dict], where: str, gid: str, first: int = 0, label: str = "stage") -> str:
        """Cones (the swept region of every move) and landing segments of stages over segments of P′."""
        part = self.partition
        out: list[str] = []
        moves: list[tuple[int, int, int, float, float]] = []
        for k, st in enumerate(stages):
            lo, hi = _heading_interval(st.get("interval"), f"{self.answer.path}: {where}[{k}].interval")
            raw = st.get("moves")
            pairs = ([(int(m[0]), int(m[1])) for m in raw] if isinstance(raw, list) and
                     all(isinstance(m, list) and len(m) == 2 for m in raw)
                     else [(i, j) for i in st["from_segments"] for j in st["to_segments"][:1]])
            for i, j in pairs:
                if not 0 <= i < part.n_segments or not 0 <= j < part.n_segments:
                    raise InputError(f"{self.answer.path}: {where}[{k}].moves names segment ({i}, {j}) outside 0..{part.n_segments - 1}")
                moves.append((k, i, j, lo, hi))
        seg_edge, seg_t0, seg_t1 = (np.asarray(part.seg_edge), np.asarray(part.seg_t0), np.asarray(part.seg_t1))
        src = np.array([m[1] for m in moves], dtype=np.int64)
        regions = swept_regions(self.env, seg_edge[src], seg_t0[src], seg_t1[src], [m[3] for m in moves],
                                [m[4] for m in moves]) if moves else []
        for (k, i, j, lo, hi), region in zip(moves, regions):
            shrink = self.move_contraction(int(part.segments[i].edge), int(part.segments[j].edge), lo, hi)
            if shrink is not None:
                self.contraction[first + k] = max(self.contraction.get(first + k, 0.0), shrink[0])
            if region is None:
                continue
            colour = _stage_colour(first + k)
            title = (f"{label} {first + k + 1}, move {i} → {j}: heading interval {_interval((lo, hi))}, width {hi - lo:.6g} rad "
                     f"(±{math.degrees((hi - lo) / 2):.4g}°): every point of segment {i} lands on segment {j}"
                     + (f"; worst-case contraction C = {shrink[0]:.6g} ({shrink[1]} transition, φ = {_rad(shrink[2])})"
                        if shrink is not None else ""))
            out.append(_el("polygon", {"points": self.canvas.points(region), "class": "hover cone", "data-stage": first + k,
                                       "fill": colour, "fill-opacity": "0.28", "stroke": colour, "stroke-opacity": "0.9",
                                       "stroke-width": "1"}, title))
        for k, st in enumerate(stages):
            colour = _stage_colour(first + k)
            lo, hi = st["interval"]
            for j in st["to_segments"]:
                s = part.segments[j]
                a, b = (float(s.a[0]), float(s.a[1])), (float(s.b[0]), float(s.b[1]))
                out.append(_line(self.canvas, a, b, {"class": "hover target", "data-stage": first + k, "stroke": colour,
                                                     "stroke-width": "5", "stroke-linecap": "butt"},
                                 f"{label} {first + k + 1} lands on segment {j} (e{s.edge}, t ∈ [{s.t0}, {s.t1}]) from "
                                 f"segments {', '.join(map(str, st['from_segments']))} with headings {_interval((lo, hi))}"))
            if st["to_segments"]:
                s = part.segments[st["to_segments"][0]]
                mx, my = self.canvas.xy(0.5 * (float(s.a[0]) + float(s.b[0])), 0.5 * (float(s.a[1]) + float(s.b[1])))
                d = np.array([float(s.b[0] - s.a[0]), float(s.b[1] - s.a[1])])
                n = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), 1e-300)
                x, y = mx + 12 * n[0], my - 12 * n[1]  # inside the room, beside its landing segment
                out.append(_el("circle", {"cx": f"{x:.1f}", "cy": f"{y:.1f}", "r": "8", "fill": colour,
                                          "class": "hover stage-label", "data-stage": first + k},
                               f"{label} {first + k + 1}: headings {_interval((lo, hi))}"))
                out.append(_el("text", {"x": f"{x:.1f}", "y": f"{y:.1f}", "font-size": "10", "font-weight": "700",
                                        "fill": "#fff", "text-anchor": "middle", "dominant-baseline": "central"},
                               body=_e(first + k + 1)))
        return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"


def _stage_rows(stages: Sequence[dict], contraction: dict[int, float], first: int = 0) -> list[list[str]]:
    rows = []
    for k, st in enumerate(stages):
        lo, hi = st["interval"]
        c = contraction.get(first + k)
        rows.append([str(first + k + 1), ", ".join(map(str, st.get("from_segments", []))),
                     ", ".join(map(str, st.get("to_segments", []))), f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}",
                     f"±{math.degrees((hi - lo) / 2):.4g}°", "—" if c is None else f"{c:.6g}"])
    return rows


_STAGE_HEADER = ["stage", "from segments", "to segments", "lo (rad)", "hi (rad)", "width (rad)", "tolerance",
                 "worst-case contraction C"]


class _PlanReport(_View):
    """A plan, or a Pareto front (drawn: its most tolerant plan; the front as a table)."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        from solverplan.plan.result import parse_plan

        data = self.data
        self.front = None
        if answer.kind == "pareto":
            points = data.get("points")
            if not isinstance(points, list) or not all(isinstance(p, dict) and isinstance(p.get("plan"), dict) for p in points):
                raise MalformedFile(f"{answer.path}: points: expected a list of {{bounces, min_width, tolerance, plan}}")
            self.front = points
            best = max(points, key=lambda p: _finite(p.get("tolerance"), f"{answer.path}: points[].tolerance"), default=None)
            plan_data = best["plan"] if best is not None else {"status": "infeasible", "stages": [],
                                                               "objective": "tolerance", "reason": data.get("reason")}
        else:
            plan_data = data
        self.plan = parse_plan(plan_data, answer.path)
        self.plan_data = plan_data
        self.plan.check_environment(env, self.partition.n_segments)  # a Pareto point's plan records it too
        self.stages = plan_data.get("stages", []) if self.plan.found else []
        self.check_segments(self.stages, "stages")
        self.bounces = self.plan.bounces
        self.start, self.goal = self.plan.start, self.plan.goal

    @property
    def title(self) -> str:
        p = self.plan
        name = self.env.name or self.env_label
        if not p.found:
            return f"{name}: {p.objective} plan {p.start} → {p.goal}: {p.status.value}"
        return (f"{name}: {p.objective} plan {p.start} → {p.goal}: {p.bounces} bounce{'s' if p.bounces != 1 else ''}, "
                f"tolerance ±{(p.tolerance or 0.0):.4g} rad")

    def layers(self) -> list[str]:
        out = [self.segment_layer(), self.segment_stage_layer(self.stages, "stages", "plan-stages")]
        for k, _ in enumerate(self.stages):
            self.legend.append((_stage_colour(k), "area", f"stage {k + 1}: {_interval(self.stages[k]['interval'])}"))
        out.append(self.pieces_layer(self.plan.start, PLAN_START_COLOR, "start-set", "start"))
        out.append(self.pieces_layer(self.plan.goal, PLAN_GOAL_COLOR, "goal-set", "goal"))
        return out

    def numbers(self) -> str:
        p, d = self.plan, self.plan_data
        rows = [("status", p.status.value), ("objective", p.objective), ("start", str(p.start)), ("goal", str(p.goal))]
        if p.found:
            rows += [("bounces", str(p.bounces)), ("min_width", _rad(p.min_width)), ("tolerance", _rad(p.tolerance)),
                     ("sum_width", _rad(p.sum_width))]
        else:
            rows.append(("reason", str(p.reason or d.get("reason") or "")))
        if p.max_bounces is not None:
            rows.append(("max_bounces", str(p.max_bounces)))
        rows += _optimality_rows(d.get("optimality"))
        margins = d.get("margins")
        if isinstance(margins, dict) and margins:
            rows.append(("margins", ", ".join(f"{k} {_num(v)}" for k, v in margins.items())))
        rows += _environment_rows(self.data)
        out = _table(rows, table_id="summary", exact=("environment sha256",))
        if self.front is not None:
            out += "<h2>Pareto front (bounces ↔ tolerance)</h2>" + _grid(
                ["bounces", "min_width (rad)", "tolerance (rad)", "proved"],
                [[str(q.get("bounces")), _num(q.get("min_width"), 9), _num(q.get("tolerance"), 9),
                  _num((q["plan"].get("optimality") or {}).get("proved"))] for q in self.front], table_id="front")
            out += "<p>The picture and the stages below are the front's most tolerant plan.</p>"
        if self.stages:
            out += "<h2>Stages</h2>" + _grid(_STAGE_HEADER, _stage_rows(self.stages, self.contraction), table_id="stages",
                                             stage_rows=True)
            out += ("<p>C is the worst case over the interval of the contraction coefficient of the stage's moves "
                    "(the paper's Def. 11): how much a set of positions may stretch (C &gt; 1) or shrink (C &lt; 1).</p>")
        return out

    def command(self, certificate_path: str | None) -> str:
        from solverplan.plan.margins import default_corner_clearance

        p, d = self.plan, self.data
        words = ["solverplan", "plan", self.env_label, "--from", str(p.start), "--to", str(p.goal)]
        if self.answer.kind == "pareto":
            words.append("--pareto")
        else:
            words += ["--objective", p.objective]
        budget = d.get("max_bounces")
        if isinstance(budget, int) and not isinstance(budget, bool):
            words += ["--max-bounces", str(budget)]
        margins = self.plan_data.get("margins") or {}
        heading = margins.get("heading")
        if isinstance(heading, (int, float)) and abs(float(heading) - 1e-3) > 1e-15:
            words += ["--heading-margin", repr(float(heading))]
        clearance = margins.get("corner_clearance")
        if isinstance(clearance, (int, float)) and not math.isclose(float(clearance), default_corner_clearance(self.env),
                                                                    rel_tol=1e-9):
            words += ["--corner-clearance", repr(float(clearance))]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


class _PatrolReport(_View):
    """A patrol: the edges to visit, the entry stages, each cycle stage's fan of headings from its contact point,
    the nominal limit cycle and its contact points."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        self.entry = d.get("entry") or []
        self.cycle = d.get("cycle") or []
        if not isinstance(self.entry, list) or not isinstance(self.cycle, list):
            raise MalformedFile(f"{answer.path}: entry and cycle must be lists of stages")
        self.check_segments(self.entry, "entry")
        self.check_segments(self.cycle, "cycle")
        for k, st in enumerate(self.cycle):
            _heading_interval(st.get("interval"), f"{answer.path}: cycle[{k}].interval")
            self.edge_id(st.get("from_edge"), f"cycle[{k}].from_edge")
        self.points = _fixed_points(self, d.get("fixed_point") or [])
        visit = d.get("visit") or []
        if not isinstance(visit, list):
            raise MalformedFile(f"{answer.path}: visit: expected a list of edges like 'e3'")
        self.visit = [self.edge_id(_edge_number(v), f"visit[{k}]") for k, v in enumerate(visit)]
        self.start = d.get("start") if isinstance(d.get("start"), str) else None
        if self.cycle:
            self.bounces = len(self.entry) + len(self.cycle)

    @property
    def title(self) -> str:
        d = self.data
        seq = " → ".join(f"e{e}" for e in self.visit)
        tail = (f"worst-case contraction {_num(d.get('contraction'), 4)} per cycle" if d.get("status") == "found"
                else str(d.get("status")))
        return f"{self.env.name or self.env_label}: patrol {seq} ({d.get('objective')}): {tail}"

    def layers(self) -> list[str]:
        c, env = self.canvas, self.env
        out = [self.segment_layer()]
        vis = []
        for e in dict.fromkeys(self.visit):
            vis.append(_line(c, env.edge_start[e], env.edge_end[e], {"class": "hover", "stroke": PATROL_EDGE_COLOR,
                                                                     "stroke-width": "7", "stroke-opacity": "0.5"},
                             f"required edge e{e} (visited {self.visit.count(e)}× per pass)"))
        out.append('<g id="patrol-edges">' + "".join(vis) + "</g>")
        self.legend.append((PATROL_EDGE_COLOR, "line", "edges to visit: " + ", ".join(f"e{e}" for e in self.visit)))
        if self.entry:
            out.append(self.segment_stage_layer(self.entry, "entry", "patrol-entry", label="entry stage"))
            self.legend.append((_stage_colour(0), "area", f"entry: {len(self.entry)} stage(s) into the cycle"))
        out.append(_cycle_layers(self, self.cycle, self.points, first=len(self.entry), fans=True))
        out.append(self.pieces_layer(self.start, PLAN_START_COLOR, "start-set", "start"))
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status")))]
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("visit", "objective", "tolerance", "max_between", "start", "bounces", "periods", "contraction",
                    "contraction_exact", "rate", "attractor_width"):
            if key in d:
                v = d[key]
                rows.append((key, ", ".join(map(str, v)) if isinstance(v, list) else _num(v, 9)))
        rm = d.get("return_map")
        if isinstance(rm, dict):
            rows.append(("return map", f"on e{rm.get('edge')}: t ↦ {rm.get('alpha')} · t + {rm.get('beta')}"))
            rows.append(("nominal contraction", _num(rm.get("nominal_contraction"), 9)))
        rows += _optimality_rows(d.get("optimality"))
        if "bound_all_classes" in d:
            rows.append(("bound_all_classes", _num(d.get("bound_all_classes"), 9)))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("contraction_exact", "return map", "environment sha256"))
        out += _cycle_tables(self.entry, self.cycle, self.points, self.contraction)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        words = ["solverplan", "patrol", self.env_label, "--visit", ",".join(f"e{e}" for e in self.visit)]
        if self.start:
            words += ["--from", self.start]
        objective = str(d.get("objective") or "contraction")
        words += ["--objective", objective]
        if objective != "tolerance" and isinstance(d.get("tolerance"), (int, float)):
            words += ["--tolerance", repr(float(d["tolerance"]))]
        if isinstance(d.get("max_between"), int):
            words += ["--max-between", str(d["max_between"])]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


def _edge_number(name: object) -> object:
    """The number of an edge named ``eK`` (or given as K); anything else unchanged, for the caller to refuse."""
    if isinstance(name, str) and name[:1] == "e" and name[1:].isdigit():
        return int(name[1:])
    return name


def _fixed_points(view: _View, raw: object) -> list[dict]:
    if not isinstance(raw, list):
        raise MalformedFile(f"{view.answer.path}: fixed_point: expected a list of {{edge, t, point}}")
    points = []
    for k, p in enumerate(raw):
        where = f"fixed_point[{k}]"
        if not isinstance(p, dict) or not isinstance(p.get("point"), list) or len(p["point"]) != 2:
            raise MalformedFile(f"{view.answer.path}: {where}: expected {{edge, t, point: [x, y]}}")
        view.edge_id(p.get("edge"), where)
        _finite(p.get("t"), f"{view.answer.path}: {where}.t")
        _finite(p["point"][0], f"{view.answer.path}: {where}.point[0]")
        _finite(p["point"][1], f"{view.answer.path}: {where}.point[1]")
        points.append(p)
    return points


def _cycle_layers(view: _View, cycle: Sequence[dict], points: Sequence[dict], *, first: int, fans: bool,
                  colour: str = CYCLE_COLOR, gid: str = "cycle", label: str = "cycle stage") -> str:
    """The nominal cycle through its contact points (bold), each stage's fan of headings from its contact point
    (``fans``), and the contact points with their exact parameters."""
    from solverplan.geometry.raycast import cast_from_boundary

    c, env = view.canvas, view.env
    out: list[str] = []
    if fans and cycle and len(points) == len(cycle):
        edges = np.array([int(st["from_edge"]) for st in cycle for _ in (0, 1)], dtype=np.int64)
        ts = np.array([float(p["t"]) for p in points for _ in (0, 1)])
        heads = np.array([h for st in cycle for h in (float(st["interval"][0]), float(st["interval"][1]))])
        hits = cast_from_boundary(env, edges, ts, heads)
        for k, (st, p) in enumerate(zip(cycle, points)):
            lo, hi = float(st["interval"][0]), float(st["interval"][1])
            h0, h1 = hits.points[2 * k], hits.points[2 * k + 1]
            if not (np.all(np.isfinite(h0)) and np.all(np.isfinite(h1))):
                continue
            extra = "; ".join(f"{key} {_short_exact(st[key]) if key != 'phi' else _rad(st[key])}"
                              for key in ("transition", "phi", "contraction") if key in st)
            mp: dict = st["map"] if isinstance(st.get("map"), dict) else {}
            title = (f"{label} {first + k + 1}: e{st.get('from_edge')} → e{st.get('to_edge')}, headings {_interval((lo, hi))} "
                     f"(width {hi - lo:.6g} rad); {extra}; exact map t ↦ {_short_exact(mp.get('alpha'))} · t + "
                     f"{_short_exact(mp.get('beta'))}")
            out.append(_el("polygon", {"points": c.points([p["point"], h0, h1]), "class": "hover cone fan",
                                       "data-stage": first + k, "fill": CONE_COLOR, "fill-opacity": "0.2",
                                       "stroke": CONE_COLOR, "stroke-opacity": "0.8", "stroke-width": "0.8"}, title))
    if points:
        closed = [p["point"] for p in points] + [points[0]["point"]]
        out.append(_el("polyline", {"points": c.points(closed), "fill": "none", "stroke": colour, "stroke-width": "2.6",
                                    "stroke-linejoin": "round", "class": "cycle-path"}))
        for k, p in enumerate(points):
            x, y = c.xy(p["point"][0], p["point"][1])
            bits = [f"contact point {k + 1} on e{p['edge']}: t = {p.get('t_exact', p['t'])} (≈ {float(p['t']):.9g}), "
                    f"at ({float(p['point'][0]):.6g}, {float(p['point'][1]):.6g})"]
            if "segment" in p:
                bits.append(f"segment {p['segment']}")
            if isinstance(p.get("basin"), list):
                bits.append(f"basin t ∈ [{_num(p['basin'][0])}, {_num(p['basin'][1])}]")
            if p.get("cycles_to_epsilon") is not None:
                bits.append(f"{p['cycles_to_epsilon']} cycles to ε")
            out.append(_el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": "5.5", "fill": CYCLE_POINT_COLOR,
                                      "stroke": colour, "stroke-width": "1.4", "class": "hover contact",
                                      "data-stage": first + k if k < len(cycle) else None}, "; ".join(bits)))
        view.legend.append((colour, "line", f"limit cycle ({len(points)} contact points)"))
        view.legend.append((colour, "point", "contact points (fixed points of the return map)"))
    if fans and cycle:
        view.legend.append((CONE_COLOR, "area", "heading interval of each cycle stage"))
    return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"


def _cycle_tables(entry: Sequence[dict], cycle: Sequence[dict], points: Sequence[dict],
                  contraction: dict[int, float] | None = None) -> str:
    contraction = contraction or {}
    out = ""
    if entry:
        out += "<h2>Entry stages</h2>" + _grid(_STAGE_HEADER, _stage_rows(entry, contraction), table_id="entry-stages",
                                               stage_rows=True)
    if cycle:
        header = ["stage", "edges", "lo (rad)", "hi (rad)", "width (rad)", "transition", "contraction", "map t ↦ α t + β"]
        rows = []
        for st in cycle:
            lo, hi = st["interval"]
            mp: dict = st["map"] if isinstance(st.get("map"), dict) else {}
            rows.append([f"e{st.get('from_edge')} → e{st.get('to_edge')}", f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}",
                         str(st.get("transition", "")), _num(st.get("contraction"), 9),
                         f"α = {mp.get('alpha')}, β = {mp.get('beta')}"])
        body = "".join(f'<tr data-stage="{len(entry) + k}"><td>{len(entry) + k + 1}</td>'
                       + "".join(f"<td{_EXACT_CELL if j == len(r) - 1 else ''}>{_e(v)}</td>" for j, v in enumerate(r))
                       + "</tr>" for k, r in enumerate(rows))
        out += ('<h2>Cycle stages</h2><table id="cycle-stages"><thead><tr>' + "".join(f"<th>{_e(h)}</th>" for h in header)
                + f"</tr></thead><tbody>{body}</tbody></table>")
    if points:
        rows2 = [[str(k + 1), f"e{p['edge']}", str(p.get("t_exact", p["t"])), f"{float(p['t']):.9g}",
                  f"({float(p['point'][0]):.6g}, {float(p['point'][1]):.6g})"] for k, p in enumerate(points)]
        out += "<h2>Fixed points</h2>" + _grid(["point", "edge", "t (exact)", "t", "(x, y)"], rows2, table_id="fixed-points")
    return out


class _FunnelReport(_View):
    """A funnel or localisation strategy: the start and goal sets, and per stage the region its rays sweep and the
    exact set of possible positions after it."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        self.stages = d.get("stages") or [] if d.get("status") == "found" else []
        if not isinstance(self.stages, list):
            raise MalformedFile(f"{answer.path}: stages must be a list")
        self.start = d.get("start") if isinstance(d.get("start"), str) else None
        self.goal = d.get("goal") if isinstance(d.get("goal"), str) and answer.kind == "funnel" else None
        if self.start is not None:
            env.boundary_set(self.start)  # a start set of edges env lacks is another environment's
        self.positions: list[list[dict]] = []
        for k, st in enumerate(self.stages):
            where = f"stages[{k}]"
            if not isinstance(st, dict):
                raise MalformedFile(f"{answer.path}: {where}: expected a stage object")
            _heading_interval(st.get("interval"), f"{answer.path}: {where}.interval")
            pieces = st.get("positions")
            if not isinstance(pieces, list) or not pieces:
                raise MalformedFile(f"{answer.path}: {where}.positions: expected a list of {{edge, t0, t1}}")
            for m, p in enumerate(pieces):
                if not isinstance(p, dict):
                    raise MalformedFile(f"{answer.path}: {where}.positions[{m}]: expected {{edge, t0, t1}}")
                self.edge_id(p.get("edge"), f"{where}.positions[{m}]")
                t0 = _finite(p.get("t0"), f"{answer.path}: {where}.positions[{m}].t0")
                t1 = _finite(p.get("t1"), f"{answer.path}: {where}.positions[{m}].t1")
                if not 0 <= t0 <= t1 <= 1:
                    raise MalformedFile(f"{answer.path}: {where}.positions[{m}]: [t0, t1] = [{t0}, {t1}] is not inside [0, 1]")
            self.positions.append(pieces)
        if d.get("status") == "found":
            self.bounces = len(self.stages)

    @property
    def title(self) -> str:
        d = self.data
        target = f"< {d.get('epsilon')}" if self.answer.kind == "localize" else str(d.get("goal"))
        tail = (f"{len(self.stages)} bounces; position set {_num((d.get('position_widths') or [0])[0], 4)} → "
                f"{_num((d.get('position_widths') or [0])[-1], 4)} long" if self.stages else str(d.get("status")))
        return f"{self.env.name or self.env_label}: {self.answer.kind} {d.get('start')} → {target}: {tail}"

    def layers(self) -> list[str]:
        env, c = self.env, self.canvas
        out = [self.pieces_layer(self.start, FUNNEL_START_COLOR, "start-set", "start"),
               self.pieces_layer(self.goal, FUNNEL_GOAL_COLOR, "goal-set", "goal")]
        sources = ([{"edge": p.edge, "t0": float(p.t0), "t1": float(p.t1)} for p in env.boundary_set(self.start).pieces]
                   if self.start else [])
        n = max(len(self.stages), 1)
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        swept: list[str] = []
        lines: list[str] = []
        for k, st in enumerate(self.stages):
            r, g, b, _ = cmap(0.1 + 0.8 * k / max(n - 1, 1))
            colour = "#%02x%02x%02x" % (round(r * 255), round(g * 255), round(b * 255))
            lo, hi = st["interval"]
            if sources:
                regions = swept_regions(env, [int(p["edge"]) for p in sources], [float(p["t0"]) for p in sources],
                                        [float(p["t1"]) for p in sources], [lo] * len(sources), [hi] * len(sources))
                for region in regions:
                    if region is None:
                        continue
                    swept.append(_el("polygon", {"points": c.points(region), "class": "hover cone", "data-stage": k,
                                                 "fill": colour, "fill-opacity": "0.25", "stroke": colour,
                                                 "stroke-width": "0.8"},
                                     f"stage {k + 1}: headings {_interval((lo, hi))} (width {hi - lo:.6g} rad) sweep this "
                                     "region from the possible positions before it"))
            for p in self.positions[k]:
                a, b2 = env.point_at(int(p["edge"]), float(p["t0"])), env.point_at(int(p["edge"]), float(p["t1"]))
                length = float(env.edge_lengths[int(p["edge"])]) * (float(p["t1"]) - float(p["t0"]))
                lines.append(_line(c, a, b2, {"class": "hover positions", "data-stage": k, "stroke": colour,
                                              "stroke-width": "5", "stroke-linecap": "round"},
                                   f"positions after stage {k + 1}: e{p['edge']}, t ∈ [{p.get('t0_exact', p['t0'])}, "
                                   f"{p.get('t1_exact', p['t1'])}] (length {length:.6g})"))
            self.legend.append((colour, "area", f"stage {k + 1}: {_interval((lo, hi))}"))
            sources = self.positions[k]
        out.insert(0, '<g id="funnel-swept">' + "".join(swept) + "</g>")
        out.append('<g id="funnel-positions">' + "".join(lines) + "</g>")
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status"))), ("kind", str(d.get("kind")))]
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("start", "goal", "epsilon", "tolerance", "bounces", "min_width", "safe_plan_exists"):
            if key in d:
                rows.append((key, _num(d[key], 9)))
        widths = d.get("position_widths")
        if isinstance(widths, list):
            rows.append(("position widths", " → ".join(_num(w, 6) for w in widths)))
        rows += _optimality_rows(d.get("optimality"))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("environment sha256",))
        if self.stages:
            header = ["stage", "lo (rad)", "hi (rad)", "width (rad)", "positions after (exact)"]
            body = []
            for k, st in enumerate(self.stages):
                lo, hi = st["interval"]
                pos = "; ".join(f"e{p['edge']} [{p.get('t0_exact', p['t0'])}, {p.get('t1_exact', p['t1'])}]"
                                for p in self.positions[k])
                body.append([str(k + 1), f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}", pos])
            out += "<h2>Stages</h2>" + _grid(header, body, table_id="stages", stage_rows=True)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        if self.answer.kind == "localize":
            words = ["solverplan", "localize", self.env_label, "--epsilon", _plain(d.get("epsilon"))]
            if self.start:
                words += ["--from", self.start]
        else:
            words = ["solverplan", "funnel", self.env_label, "--from", str(d.get("start")), "--to", str(d.get("goal"))]
        if isinstance(d.get("tolerance"), (int, float)):
            words += ["--tolerance", repr(float(d["tolerance"]))]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


class _CycleReport(_View):
    """A limit cycle of a constant heading (``cycle``), or a constant controller (``cycle --theta auto``: each of
    its cycles)."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        raw = d.get("cycles") if answer.kind == "controller" else [d]
        if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
            raise MalformedFile(f"{answer.path}: cycles: expected a list of cycle answers")
        self.cycles = []
        for i, cyc in enumerate(raw):
            stages = cyc.get("cycle") or []
            entry = cyc.get("entry") or []
            if not isinstance(stages, list) or not isinstance(entry, list):
                raise MalformedFile(f"{answer.path}: cycle and entry must be lists of stages")
            for k, st in enumerate(stages):
                if not isinstance(st, dict):
                    raise MalformedFile(f"{answer.path}: cycle[{k}]: expected a stage object")
                _heading_interval(st.get("interval"), f"{answer.path}: cycle[{k}].interval")
                self.edge_id(st.get("from_edge"), f"cycle[{k}].from_edge")
            self.cycles.append((cyc, entry, stages, _fixed_points(self, cyc.get("fixed_point") or [])))

    @property
    def title(self) -> str:
        d = self.data
        head = f"{self.env.name or self.env_label}: constant heading θ = {d.get('theta_exact') or _num(d.get('theta'))}"
        if self.answer.kind == "controller":
            return f"{head}: {len(self.cycles)} limit cycle(s), {d.get('status')}"
        return f"{head}: limit cycle of period {d.get('period')}, contraction {_num(d.get('contraction'), 4)}, {d.get('status')}"

    def layers(self) -> list[str]:
        out = []
        colours = (CYCLE_COLOR, "#b2182b", "#1b7837", "#7b3294", "#e08214")
        first = 0
        for i, (cyc, _entry, stages, points) in enumerate(self.cycles):
            out.append(_cycle_layers(self, stages, points, first=first, fans=False, colour=colours[i % len(colours)],
                                     gid=f"cycle-{i}", label=f"cycle {i + 1} stage"))
            first += len(stages)
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status")))]
        keys = (("theta", "theta_exact", "proved", "bounces", "heading_margin") if self.answer.kind == "controller" else
                ("theta", "theta_exact", "theta_used", "method", "edges", "period", "contraction", "contraction_exact",
                 "scope", "start", "epsilon", "cycles_to_epsilon"))
        for key in keys:
            if key in d:
                v = d[key]
                rows.append((key, ", ".join(map(str, v)) if isinstance(v, list) else _num(v, 9)))
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("lemma3", "theorem1"):
            if isinstance(d.get(key), (dict, list)):
                rows.append((key, json.dumps(d[key], ensure_ascii=False)))
        rows += _optimality_rows(d.get("optimality"))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("contraction_exact", "environment sha256", "lemma3", "theorem1"))
        if self.answer.kind == "controller" and isinstance(d.get("tried"), list):
            out += "<h2>Headings tried</h2>" + _grid(["θ (exact)", "outcome"], [[str(t.get("theta_exact")), str(t.get("outcome"))]
                                                                             for t in d["tried"] if isinstance(t, dict)],
                                                     table_id="tried")
        for i, (cyc, entry, stages, points) in enumerate(self.cycles):
            if len(self.cycles) > 1:
                out += f"<h2>Cycle {i + 1}: contraction {_e(_num(cyc.get('contraction'), 6))}</h2>"
            out += _cycle_tables(entry, stages, points)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        if self.answer.kind == "controller":
            words = ["solverplan", "cycle", self.env_label, "--theta", "auto"]
            margin = d.get("heading_margin")
            if isinstance(margin, (int, float)) and abs(float(margin) - 1e-3) > 1e-15:
                words += ["--heading-margin", repr(float(margin))]
            if d.get("epsilon") is not None:
                words += ["--epsilon", _plain(d.get("epsilon"))]
        else:
            theta = d.get("theta_exact") or repr(d.get("theta"))
            words = ["solverplan", "cycle", self.env_label, "--theta", str(theta)]
            method = d.get("method")
            if method in ("theorem1", "iterate", "edges"):
                words += ["--method", str(method)]
            if method == "edges" and isinstance(d.get("edges"), list):
                words += ["--edges", ",".join(f"e{e}" for e in d["edges"])]
            if isinstance(d.get("start"), str):
                words += ["--start", d["start"]]
            if d.get("epsilon") is not None:
                words += ["--epsilon", _plain(d.get("epsilon"))]
        words += ["-o", self.answer.path]
        return shlex.join(words)


# ====================================================================== studies
@dataclass
class _Study:
    """A study: its identity, the means, a heatmap per metric over the (first two) axes that vary, the cells."""

    answer: AnswerFile
    notes: list[str] = field(default_factory=list)

    def render(self) -> str:
        d = self.answer.data
        ident = d["study"]
        if not isinstance(ident, dict):
            raise MalformedFile(f"{self.answer.path}: study: expected the study's identity object")
        cells = [c for c in d["cells"] if isinstance(c, dict)]
        grid: dict = ident["grid"] if isinstance(ident.get("grid"), dict) else {}
        axes = [str(a) for a in ident.get("axes", [])] if isinstance(ident.get("axes"), list) else []
        varying = [a for a in axes if isinstance(grid.get(a), list) and len(grid[a]) > 1]
        metrics = self.metrics(cells, set(axes))
        rows = [("study", str(ident.get("study"))), ("generator", str(ident.get("generator"))),
                ("seed", str(ident.get("seed"))), ("metric", json.dumps(ident.get("metric"), ensure_ascii=False)),
                ("grid", "; ".join(f"{a} = {', '.join(_num(v) for v in grid.get(a, []))}" for a in axes)),
                ("per cell", str(ident.get("per_cell"))), ("cells", str(len(cells))), ("rows", str(ident.get("rows")))]
        means = d.get("means")
        if isinstance(means, dict):
            rows += [(f"mean {k}", _num(v)) for k, v in means.items() if not isinstance(v, (dict, list))]
        heat = "".join(self.heatmap(cells, m, varying, grid) for m in metrics)
        if not heat:
            heat = "<p>No metric varies over two axes or one: see the table of cells.</p>"
        header = ["cell", *axes, *metrics]
        body = [[str(c.get("cell"))] + [_num(c.get(a)) for a in axes] + [_num(self.value(c, m)) for m in metrics]
                for c in cells]
        title = f"{ident.get('study')} study over {ident.get('generator')} environments"
        return (f'<section id="picture"><div id="heatmaps"><h2>{_e(title)}</h2>{heat}</div><div id="side"><h2>Details</h2>'
                '<div id="details" class="empty" aria-live="polite">Hover over a cell for its parameters and values.</div>'
                f'{"".join(f"<p>{_e(n)}</p>" for n in self.notes)}</div></section>'
                f'<section id="numbers"><h2>The study</h2>{_table(rows, table_id="summary", exact=("metric",))}'
                f'<h2>Cells</h2>{_grid(header, body, table_id="cells")}</section>'
                f'<section id="reproduce"><h2>Reproduce it</h2><pre><code id="command">{_e(self.command(ident, axes, grid))}'
                f"</code></pre><p>Answer file: <code>{_e(self.answer.path)}</code>.</p></section>")

    @staticmethod
    def value(cell: dict, metric: str) -> object:
        """A cell's value of a metric: a number (the study's answer) or the mean of its statistics (NAME.json)."""
        v = cell.get(metric)
        if isinstance(v, dict):
            return v.get("mean")
        return v

    def metrics(self, cells: Sequence[dict], axes: set[str]) -> list[str]:
        skip = axes | {"cell", "rows", "replicate", "seed", "seconds"}
        names: list[str] = []
        for c in cells:
            for k in c:
                v = self.value(c, k)
                if k not in skip and k not in names and isinstance(v, (int, float)) and not isinstance(v, bool):
                    names.append(k)
        return names

    def heatmap(self, cells: Sequence[dict], metric: str, varying: Sequence[str], grid: dict) -> str:
        if not varying:
            return ""
        ax_x = varying[-1]
        ax_y = varying[-2] if len(varying) > 1 else None
        # the axes' values in the grid's order (numbers, or the rule families of a rules study)
        xs: list[Any] = [v for v in grid[ax_x] if isinstance(v, (int, float, str))]
        ys: list[Any] = [v for v in grid[ax_y] if isinstance(v, (int, float, str))] if ax_y else [None]
        if not xs or not ys:
            return ""
        table: dict[tuple[object, object], list[float]] = {}
        for c in cells:
            v = self.value(c, metric)
            if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(float(v)):
                table.setdefault((c.get(ax_x), c.get(ax_y) if ax_y else None), []).append(float(v))
        if not table:
            return ""
        if len(varying) > 2 and not self.notes:
            self.notes.append(f"Heatmaps average the cells over {', '.join(varying[:-2])} (they vary too).")
        values = [sum(v) / len(v) for v in table.values()]
        vmin, vmax = min(values), max(values)
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        cw, ch, left, top = 56.0, 30.0, 70.0, 26.0
        # wide enough for the metric's name too (about 7 px a character at 12 px bold)
        width, height = max(left + cw * len(xs) + 10, left + 7.5 * len(metric) + 10), top + ch * len(ys) + 34
        parts = [_el("text", {"x": f"{left:.0f}", "y": "16", "font-size": "12", "font-weight": "700"}, body=_e(metric))]
        for iy, yv in enumerate(reversed(ys)):
            for ix, xv in enumerate(xs):
                vals = table.get((xv, yv))
                if not vals:
                    continue
                v = sum(vals) / len(vals)
                r, g, b, _ = cmap(0.5 if vmax == vmin else (v - vmin) / (vmax - vmin))
                colour = "#%02x%02x%02x" % (round(r * 255), round(g * 255), round(b * 255))
                where = f"{ax_x} = {_num(xv)}" + (f", {ax_y} = {_num(yv)}" if ax_y else "")
                x, y = left + cw * ix, top + ch * iy
                parts.append(_el("rect", {"x": f"{x:.0f}", "y": f"{y:.0f}", "width": f"{cw - 1:.0f}", "height": f"{ch - 1:.0f}",
                                          "fill": colour, "class": "hover cell"},
                                 f"{metric} = {v:.6g} at {where} (mean of {len(vals)} cell(s))"))
                ink = "#fff" if (r * 0.3 + g * 0.59 + b * 0.11) < 0.5 else "#000"
                parts.append(_el("text", {"x": f"{x + cw / 2:.0f}", "y": f"{y + ch / 2 + 4:.0f}", "font-size": "10",
                                          "text-anchor": "middle", "fill": ink}, body=_e(f"{v:.3g}")))
        for ix, xv in enumerate(xs):
            parts.append(_el("text", {"x": f"{left + cw * ix + cw / 2:.0f}", "y": f"{top + ch * len(ys) + 14:.0f}",
                                      "font-size": "10", "text-anchor": "middle"}, body=_e(_num(xv, 4))))
        parts.append(_el("text", {"x": f"{left + cw * len(xs) / 2:.0f}", "y": f"{top + ch * len(ys) + 29:.0f}",
                                  "font-size": "11", "text-anchor": "middle"}, body=_e(ax_x)))
        if ax_y:
            for iy, yv in enumerate(reversed(ys)):
                parts.append(_el("text", {"x": f"{left - 6:.0f}", "y": f"{top + ch * iy + ch / 2 + 4:.0f}",
                                          "font-size": "10", "text-anchor": "end"}, body=_e(_num(yv, 4))))
            parts.append(_el("text", {"x": "12", "y": f"{top + ch * len(ys) / 2:.0f}", "font-size": "11",
                                      "text-anchor": "middle", "transform": f"rotate(-90 12 {top + ch * len(ys) / 2:.0f})"},
                             body=_e(ax_y)))
        return (f'<svg class="heat" xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
                f'viewBox="0 0 {width:.0f} {height:.0f}" role="img" aria-label="{_e(metric)}">' + "".join(parts) + "</svg>")

    def command(self, ident: dict, axes: Sequence[str], grid: dict) -> str:
        words = ["solverplan", "study", str(ident.get("study")), "--generator", str(ident.get("generator")),
                 "--seed", str(ident.get("seed"))]
        for a in axes:
            values = grid.get(a)
            if isinstance(values, list) and values:
                if ident.get("study") == "rules" and a == "rule":  # the rule families are an option, not a grid axis
                    words += ["--rules", ",".join(map(str, values))]
                else:
                    words += ["--grid", f"{a}={','.join(_plain(v) for v in values)}"]
        if ident.get("per_cell") is not None:
            words += ["--per-cell", str(ident["per_cell"])]
        metric = ident.get("metric")
        if isinstance(metric, dict):
            for key, flag in (("family_size", "--family-size"), ("trials", "--trials"), ("bounces", "--bounces")):
                if metric.get(key) is not None:
                    v = metric[key]
                    words += [flag, ",".join(map(str, v)) if isinstance(v, list) else str(v)]
        return shlex.join(words)
