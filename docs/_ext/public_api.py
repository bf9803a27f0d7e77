"""Write the API reference page from the public namespace ``import solverplan as sp``.

The names and their sections come from ``_EXPORTS`` in ``solverplan/__init__.py``: each ``# comment`` line there
opens a section, each ``"Name": "module"`` line is a documented name. So the page lists exactly what
``solverplan`` exports, in the order and groups its maintainers chose, with no copy to keep in step.
"""

from __future__ import annotations

import re
from pathlib import Path

import solverplan

_SECTION = re.compile(r"^\s*#\s*(?P<title>.+?)\s*$")
_ENTRY = re.compile(r'^\s*"(?P<name>\w+)"\s*:\s*"(?P<module>[\w.]+)"\s*,?\s*(#.*)?$')


def exported_sections(init_source: str) -> list[tuple[str, list[str]]]:
    """The ``(section title, names)`` pairs of the ``_EXPORTS`` literal, in source order."""
    body = init_source.split("_EXPORTS", 1)[1].split("\n}", 1)[0]
    sections: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if (entry := _ENTRY.match(line)) is not None:
            if not sections:
                sections.append(("Public names", []))
            sections[-1][1].append(entry["name"])
        elif (section := _SECTION.match(line)) is not None:
            sections.append((section["title"], []))
    return [(title, names) for title, names in sections if names]


def api_page(sections: list[tuple[str, list[str]]]) -> str:
    lines = [
        ".. This page is written by docs/_ext/public_api.py on every build: edit solverplan/__init__.py instead.",
        "",
        "API reference",
        "=============",
        "",
        "Everything below is reachable as ``sp.NAME`` after ``import solverplan as sp`` (the names load on first use).",
        "The rendering functions live in :mod:`solverplan.render`, listed at the end.",
        "",
        ".. currentmodule:: solverplan",
        "",
    ]
    for title, names in sections:
        title = title[0].upper() + title[1:]
        lines += [title, "-" * len(title), "", ".. autosummary::", "   :toctree: generated", "", *(f"   {n}" for n in names), ""]
    lines += ["Pictures", "--------", "", ".. currentmodule:: solverplan.render", "", ".. autosummary::",
              "   :toctree: generated", ""]
    import solverplan.render as render

    listed = set(solverplan._EXPORTS)  # e.g. the HTML report's names: documented once, under sp
    lines += [f"   {name}" for name in render.__all__
              if callable(getattr(render, name)) and not name.isupper() and name not in listed]
    lines.append("")
    return "\n".join(lines)


def write_api_page(path: Path) -> None:
    """Write ``api.rst`` when its text changed (an unchanged file keeps Sphinx's incremental build)."""
    source = Path(solverplan.__file__).read_text(encoding="utf-8")
    text = api_page(exported_sections(source))
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
