"""The process start-up of cli/_startup.py changes nothing a command line gives: the same output, errors and exit codes
as typer's usual build (every command built, pydantic coercion), and values coerced as pydantic coerces them."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
import typer.testing
from typer.testing import CliRunner

from solverplan import cli
from solverplan.cli import _startup

runner = CliRunner()

COMMAND_LINES = [
    [], ["--help"], ["--version"], ["info", "--help"], ["info", "square"], ["info", "square", "--format", "text"],
    ["--indent", "0", "info", "square"], ["--indent=3", "info", "square"], ["--compact", "info", "square"],
    ["--graph-cache", "off", "--max-memory", "1G", "info", "square"], ["--", "info", "square"],
    ["--indent", "x", "info", "square"], ["--indent", "99", "info", "square"], ["--indent", "-1", "info", "square"],
    ["--indent", "007", "info", "square"], ["--compact", "--indent", "2", "info", "square"],
    ["info", "square", "--format", "bogus"], ["info", "square", "--format", "TEXT"], ["info", "nosuchmodel"],
    ["info", "square", "--no-such-option"], ["info"], ["nosuch"], ["inf", "square"], ["--no-such-root-option"],
    ["graph", "l_shape", "--safe", "--from", "2"], ["graph", "l_shape", "--heading", "0.5"],
    ["graph", "l_shape", "--heading", "1e-1"], ["graph", "l_shape", "--heading", "abc"],
    ["graph", "l_shape", "--heading", "nan"], ["graph", "l_shape", "--from", "-3"], ["graph", "l_shape", "--from", "2.0"],
    ["generate", "--help"], ["generate", "star", "--help"], ["generate", "star", "--n", "7", "--seed", "3"],
    ["generate", "nosuch"], ["cache", "--help"], ["--graph-cache", "off", "cache", "info"],
    ["partition", "square", "--env-format", "json"], ["partition", "square", "--env-format", "JSON"],
]


@pytest.mark.parametrize("args", COMMAND_LINES, ids=lambda a: " ".join(a) or "(none)")
def test_the_startup_build_answers_as_typer_does(monkeypatch, args):
    usual = runner.invoke(cli.app, args)
    monkeypatch.setattr(typer.testing, "_get_command", lambda app: _startup.command_for(app, args))
    fast = runner.invoke(cli.app, args)
    assert (fast.exit_code, fast.stdout, fast.stderr) == (usual.exit_code, usual.stdout, usual.stderr)


def test_a_command_line_builds_one_command_and_imports_no_pydantic(tmp_path):
    assert _startup._typer_as_known()  # the installed typer gets the start-up build, not the fallback
    group = _startup.command_for(cli.app, ["info", "square"])
    assert group.commands["info"].params and not group.commands["plan"].params  # the others: name and help only
    code = ("import sys\nfrom solverplan.cli import main\nsys.argv = ['solverplan', 'info', 'square']\n"
            "try:\n    main()\nfinally:\n    print('pydantic' in sys.modules, file=sys.stderr)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and '"n_vertices": 4' in done.stdout
    assert done.stderr.strip().splitlines()[-1] == "False"


@pytest.mark.parametrize("kind", [int, float])
def test_numbers_are_coerced_as_pydantic_coerces_them(kind):
    from pydantic import TypeAdapter, ValidationError

    adapter = TypeAdapter(kind)
    texts = ["0", "-0", "7", "-12", "007", "1.5", "-2.25", "1e3", "1E-3", "2.5e+10", "3.0", "123456789012345678",
             "1234567890123456789012", "0.1", "4.9e-324", "1e308", " 5", "5 ", "+5", "1_000", ".5", "5.", "inf",
             "nan", "0x10", "", "1e400", "٣"]
    for text in texts:
        got = _startup._number(kind, text, None, None)
        if got is _startup._UNSURE:
            continue
        want = adapter.validate_python(text)
        assert type(got) is type(want) and got == want and math.copysign(1, got) == math.copysign(1, want), text
    for value in (3, 0, -4, 2.5, True):
        got = _startup._number(kind, value, None, None)
        if got is not _startup._UNSURE:
            assert got == adapter.validate_python(value) and type(got) is kind
    assert _startup._number(int, "5", 0, 4) is _startup._UNSURE  # out of range: typer's own words
    with pytest.raises(ValidationError):
        adapter.validate_python("x")


def test_the_command_line_imports_no_numpy_before_a_command_needs_it():
    """``solverplan --help`` stays a tenth of a second: the CLI package (and what its options import, such as the
    runtime settings) must not import numpy (≈ 0.1 s) at start-up."""
    import subprocess
    import sys

    code = "import sys, solverplan.cli; print(sorted(m for m in ('numpy', 'shapely', 'pydantic', 'rich') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"
