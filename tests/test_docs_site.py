"""The documentation site's generated pages cover what they claim to (the build itself is ``make docs``)."""

from __future__ import annotations

import sys
from pathlib import Path

import solverplan

DOCS = Path(__file__).resolve().parent.parent / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

from public_api import api_page, exported_sections  # noqa: E402  (docs/_ext is not a package)


def test_api_page_lists_exactly_the_public_namespace():
    sections = exported_sections(Path(solverplan.__file__).read_text(encoding="utf-8"))
    names = [name for _, group in sections for name in group]
    assert sorted(names) == sorted(solverplan._EXPORTS)  # every export once, nothing else
    assert len(sections) > 5 and all(title and group for title, group in sections)
    page = api_page(sections)
    for name in names:
        assert f"\n   {name}\n" in page


def test_cli_reference_walks_every_command():
    import typer.main

    from solverplan.cli import app

    root = typer.main.get_command(app)
    sys.path.insert(0, str(DOCS / "_ext"))
    import cli_reference

    assert cli_reference.command.name == root.name
    assert set(cli_reference.command.commands) == set(root.commands) and len(root.commands) > 10


def test_tutorial_python_section_runs(tmp_path, monkeypatch):
    """The tutorial's "same from Python" block is real code: it runs and answers what the commands above it do."""
    import matplotlib

    matplotlib.use("Agg")
    text = (DOCS / "tutorial" / "index.md").read_text(encoding="utf-8")
    code = text.split("## 6. The same from Python", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    office = DOCS / "tutorial" / "office.json"
    code = code.replace('"docs/tutorial/office.json"', repr(str(office)))
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(code, "tutorial", "exec"), namespace)
    assert namespace["plan"].status.value == "found" and len(namespace["plan"].stages) == 6
    assert namespace["runs"].success_rate == 1.0
    assert (tmp_path / "certificate.json").is_file() and (tmp_path / "plan.png").stat().st_size > 10_000
