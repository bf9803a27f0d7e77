"""Running the command line in-process for the tests, and the one shape of its bad-input answer."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from solverplan import cli

runner = CliRunner()


def run(*args: object):
    """``solverplan ARGS...`` in-process (each argument as its string)."""
    return runner.invoke(cli.app, [str(a) for a in args])


def write(folder: Path, name: str, content: str | dict) -> Path:
    """``content`` (text, or JSON of a dict) written to ``folder / name``."""
    path = folder / name
    path.write_text(content if isinstance(content, str) else json.dumps(content), encoding="utf-8")
    return path


def assert_one_line_error(result, code: int, fragment: str, *, stdout_empty: bool = True) -> str:
    """Exit ``code``, nothing on stdout (unless ``stdout_empty`` is False), exactly one stderr line ``error: ...``
    containing ``fragment`` and no traceback; returns that line."""
    assert result.exit_code == code, (result.exit_code, result.stdout, result.stderr)
    if stdout_empty:
        assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    assert fragment in lines[0], lines[0]
    assert "Traceback" not in result.stderr
    return lines[0]
