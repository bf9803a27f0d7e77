"""How JSON answers are laid out: indented when small, compact when large, ``--indent N``/``--compact`` to force.

Whatever the layout, the text parses to the same value; NaN and infinities are refused as before.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from solverplan import cli
from solverplan.cli import _output  # noqa: F401  (cli._output: the layout switches)
from tests.cli_runs import run

runner = CliRunner()

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


class _Fixed:
    """A stand-in answer with a given ``to_json()``."""

    def __init__(self, value):
        self.value = value

    def to_json(self) -> dict:
        return self.value

    def to_text(self, *, width: int = 100) -> str:
        return "fixed\n"


def test_small_answer_is_indented_by_two_spaces():
    result = run("info", MODELS / "square.json")
    assert result.exit_code == 0, result.stderr
    value = json.loads(result.stdout)
    assert result.stdout == json.dumps(value, ensure_ascii=False, indent=2) + "\n"
    assert result.stdout.startswith('{\n  "name": "square",\n')


def test_large_answer_is_compact_and_the_same_value(monkeypatch):
    small = run("graph", MODELS / "two_rooms.json", "--safe")
    assert small.exit_code == 0, small.stderr
    assert len(small.stdout) < cli.JSON_INDENT_LIMIT and small.stdout.count("\n") > 100
    monkeypatch.setattr(cli._output, "JSON_INDENT_LIMIT", 1000)
    large = run("graph", MODELS / "two_rooms.json", "--safe")
    assert large.exit_code == 0, large.stderr
    assert large.stdout.count("\n") == 1 and large.stdout.endswith("}\n")
    assert ", " not in large.stdout and '": ' not in large.stdout  # no spaces after separators
    assert json.loads(large.stdout) == json.loads(small.stdout)


def test_compact_forces_one_line_and_indent_forces_indentation(tmp_path, monkeypatch):
    compact = run("--compact", "info", MODELS / "square.json")
    assert compact.exit_code == 0, compact.stderr
    assert compact.stdout.count("\n") == 1 and compact.stdout.startswith('{"name":"square",')
    monkeypatch.setattr(cli._output, "JSON_INDENT_LIMIT", 10)  # would be compact by size
    out = tmp_path / "info.json"
    wide = run("--indent", 4, "info", MODELS / "square.json", "-o", out)
    assert wide.exit_code == 0 and wide.stdout == ""
    text = out.read_text(encoding="utf-8")
    assert text.startswith('{\n    "name": "square",\n')
    assert json.loads(text) == json.loads(compact.stdout)


def test_layout_option_lasts_one_command_only():
    assert run("--compact", "info", MODELS / "square.json").exit_code == 0
    assert cli._output.json_indent() is None
    again = run("info", MODELS / "square.json")
    assert again.stdout.startswith('{\n  "name"')


def test_text_format_ignores_the_json_layout():
    plain = run("info", MODELS / "square.json", "--format", "text")
    forced = run("--compact", "info", MODELS / "square.json", "--format", "text")
    assert plain.exit_code == forced.exit_code == 0
    assert forced.stdout == plain.stdout and not plain.stdout.lstrip().startswith("{")


@pytest.mark.parametrize(
    ("args", "fragment"),
    [(["--compact", "--indent", "2"], "not both"), (["--indent", "-1"], "--indent"), (["--indent", "x"], "--indent")],
)
def test_bad_layout_options_are_usage_errors(args, fragment):
    result = run(*args, "info", MODELS / "square.json")
    assert result.exit_code == 2 and result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and fragment in lines[0]


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
@pytest.mark.parametrize("layout", [[], ["--compact"], ["--indent", "2"]])
def test_non_finite_numbers_are_refused_in_every_layout(monkeypatch, bad, layout):
    monkeypatch.setattr("solverplan.describe.describe_environment", lambda env: _Fixed({"area": bad}))
    result = run(*layout, "info", MODELS / "square.json")
    assert result.exit_code == 1 and result.stdout == ""
    assert "not JSON compliant" in result.stderr and len(result.stderr.splitlines()) == 1


def test_emit_outside_the_command_keeps_unicode_and_chooses_by_size(capsys, monkeypatch):
    cli.emit(_Fixed({"name": "P′", "x": [1, 2]}), cli.OutputFormat.JSON, None)
    assert capsys.readouterr().out == '{\n  "name": "P′",\n  "x": [\n    1,\n    2\n  ]\n}\n'
    monkeypatch.setattr(cli._output, "JSON_INDENT_LIMIT", 5)
    cli.emit(_Fixed({"name": "P′", "x": [1, 2]}), cli.OutputFormat.JSON, None)
    assert capsys.readouterr().out == '{"name":"P′","x":[1,2]}\n'


@pytest.mark.parametrize("args", [["explore", "two_holes", "--start", "1,1"], ["info", "square"],
                                  ["wallfollow", "star", "--pursuit"], ["rooms", "l_shape"]])
def test_text_answers_end_with_a_newline(args):
    # explore's report ended without one: the shell prompt followed on its last line
    result = runner.invoke(cli.app, [*args, "--format", "text"])
    assert result.exit_code == 0 and result.stdout.endswith("\n") and not result.stdout.endswith("\n\n\n")
