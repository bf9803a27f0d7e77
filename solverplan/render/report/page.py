"""The page around the sections: the document, its style and script (hover details, zoom and pan), tables,
and writing it."""

from __future__ import annotations

import base64
import hashlib
import json
import os
import shlex
from dataclasses import dataclass
from typing import Sequence


from solverplan._io import atomic_write_text, cannot_write
from solverplan.errors import InputError

from solverplan.render.report._kinds import ANSWER_KINDS, AnswerFile, _EXACT_CELL
from solverplan.render.report.format import Exact, _e, _num, cell_html


# ====================================================================== the page
@dataclass(frozen=True)
class HtmlReport:
    """A report page: the whole self-contained HTML document, and what it reports on.

    Made by :func:`~solverplan.render.report.html_report`; :func:`write_report` writes it.

    Attributes
    ----------
    html
        The whole document (styles, scripts and pictures inline: it opens without a network).
    kind
        The answer's kind (a key of :data:`~solverplan.render.report._kinds.ANSWER_KINDS`).
    title
        The page's title.
    certificate
        The checker's verdict when a certificate was given (:meth:`~solverplan.verdict.Verdict.verdict_json`:
        ``{"valid", "kind", "failures": [{"claim", "message"}], "checked", "not_checked", "proved", "scope"}``);
        ``None`` without one.

    Examples
    --------
    An answer in memory, as if read from ``plan.json``:

    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> page = sp.html_report(AnswerFile("plan.json", "plan", sp.find_plan(env, "e5", "e0:0:0.3").to_json()), env)
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
        The page (:func:`~solverplan.render.report.html_report`).
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
    >>> import pathlib, tempfile
    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> plan = sp.find_plan(env, "e5", "e0:0:0.3")
    >>> page = sp.html_report(AnswerFile("plan.json", "plan", plan.to_json()), env, certificate=sp.certificate(plan, env=env))
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "report.html"
    >>> saved = sp.write_report(page, path)
    >>> saved.to_json()["certificate"]["valid"], path.read_text(encoding="utf-8") == page.html
    (True, True)
    """
    try:
        atomic_write_text(path, report.html)
    except OSError as exc:
        raise InputError(cannot_write(path, exc)) from None
    return SavedReport(str(path), report)


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
.exact-number{border-bottom:1px dotted var(--muted);cursor:help}
#zoom{display:flex;gap:4px;margin:0 0 -10px;flex:0 0 100%}
#zoom button{font:inherit;padding:1px 9px;border:1px solid var(--line);border-radius:4px;background:#fff;cursor:pointer}
#scene.panning{cursor:grabbing}
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
  // zoom (wheel, buttons) and pan (drag) of the picture, through its viewBox: large maps stay readable
  var scene = document.getElementById('scene');
  if (scene && scene.viewBox && scene.viewBox.baseVal) {
    var base = scene.viewBox.baseVal;
    var home = [base.x, base.y, base.width, base.height];
    var view = home.slice();
    var apply = function () { scene.setAttribute('viewBox', view.join(' ')); };
    var zoom = function (factor, cx, cy) {
      var w = Math.min(home[2] * 4, Math.max(home[2] / 200, view[2] * factor));
      var h = w * home[3] / home[2];
      view = [cx - (cx - view[0]) * w / view[2], cy - (cy - view[1]) * h / view[3], w, h];
      apply();
    };
    var toView = function (ev) {
      var r = scene.getBoundingClientRect();
      return [view[0] + (ev.clientX - r.left) / r.width * view[2], view[1] + (ev.clientY - r.top) / r.height * view[3]];
    };
    scene.addEventListener('wheel', function (ev) {
      ev.preventDefault();
      var p = toView(ev);
      zoom(ev.deltaY > 0 ? 1.2 : 1 / 1.2, p[0], p[1]);
    }, {passive: false});
    var drag = null;
    scene.addEventListener('mousedown', function (ev) { drag = [ev.clientX, ev.clientY, view[0], view[1]]; scene.classList.add('panning'); });
    document.addEventListener('mouseup', function () { drag = null; scene.classList.remove('panning'); });
    document.addEventListener('mousemove', function (ev) {
      if (!drag) { return; }
      var r = scene.getBoundingClientRect();
      view[0] = drag[2] - (ev.clientX - drag[0]) / r.width * view[2];
      view[1] = drag[3] - (ev.clientY - drag[1]) / r.height * view[3];
      apply();
    });
    var bar = document.createElement('div');
    bar.id = 'zoom';
    [['+', function () { zoom(1 / 1.5, view[0] + view[2] / 2, view[1] + view[3] / 2); }],
     ['\u2212', function () { zoom(1.5, view[0] + view[2] / 2, view[1] + view[3] / 2); }],
     ['reset', function () { view = home.slice(); apply(); }]].forEach(function (b) {
      var button = document.createElement('button');
      button.type = 'button';
      button.textContent = b[0];
      button.className = 'zoom-' + (b[0] === 'reset' ? 'reset' : (b[0] === '+' ? 'in' : 'out'));
      button.addEventListener('click', b[1]);
      bar.appendChild(button);
    });
    scene.parentNode.insertBefore(bar, scene);
  }
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
    """The command that made the page: ``solverplan report ANSWER [--env ENV] [--certificate C] -o OUT``."""
    words = ["solverplan", "report", answer.path]
    if env_label:
        words += ["--env", env_label]
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
    cells = "".join(f"<tr><th>{_e(k)}</th><td{_EXACT_CELL if k in exact else ''}>"
                    f"{cell_html(Exact(v) if k in exact else v)}</td></tr>" for k, v in rows)
    return f"<table{attrs}>{cells}</table>"


def _grid(header: Sequence[str], rows: Sequence[Sequence[str]], *, table_id: str, stage_rows: bool = False) -> str:
    """A table with a header row; with ``stage_rows`` row k carries ``data-stage="k"`` (highlighted with the picture)."""
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = []
    for k, row in enumerate(rows):
        attr = f' data-stage="{k}"' if stage_rows else ""
        body.append(f"<tr{attr}>" + "".join(f"<td>{cell_html(v)}</td>" for v in row) + "</tr>")
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

