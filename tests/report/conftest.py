"""Answers the reports are made of, written once per session by the real commands (``plan -o``, ``patrol -o``, ...)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from solverplan import cli

runner = CliRunner()


def run(*args: object, cwd: Path | None = None):
    """Invoke the CLI in-process (stdout and stderr apart)."""
    return runner.invoke(cli.app, [str(a) for a in args])


# the command of the example, and one small answer of every other kind
ANSWER_COMMANDS: dict[str, list[str]] = {
    "plan": ["plan", "two_rooms", "--from", "e0:0.2:0.8", "--to", "e4:0.5:1", "--objective", "tolerance",
             "-o", "{dir}/plan.json", "--certificate", "{dir}/cert.json"],
    "pareto": ["plan", "l_shape", "--from", "e0:0.45:0.55", "--to", "e3", "--pareto", "--max-bounces", "4",
               "-o", "{dir}/pareto.json", "--certificate", "{dir}/pareto_cert.json"],
    "patrol": ["patrol", "square", "--visit", "e0,e1,e2,e3", "-o", "{dir}/patrol.json",
               "--certificate", "{dir}/patrol_cert.json"],
    "funnel": ["funnel", "square", "--from", "e0", "--to", "e2:0.4:0.6", "-o", "{dir}/funnel.json",
               "--certificate", "{dir}/funnel_cert.json"],
    "localize": ["localize", "l_shape", "--epsilon", "0.5", "-o", "{dir}/localize.json",
                 "--certificate", "{dir}/localize_cert.json"],
    "cycle": ["cycle", "square", "--theta", "tan:1/3", "-o", "{dir}/cycle.json"],
    "controller": ["cycle", "l_shape", "--theta", "auto", "-o", "{dir}/controller.json"],
    "rooms": ["rooms", "three_chambers", "-o", "{dir}/rooms.json"],
    "exploration": ["explore", "l_shape", "--start", "1,1/2", "-o", "{dir}/exploration.json"],
    "range-exploration": ["explore", "one_hole", "--start", "1,1", "--range", "4", "-o", "{dir}/range-exploration.json"],
    "cut-ordering": ["wallfollow", "star", "--cut-ordering", "-o", "{dir}/cut-ordering.json"],
    "learned-ordering": ["wallfollow", "l_shape", "--learn", "-o", "{dir}/learned-ordering.json"],
    "vertex-count": ["wallfollow", "star", "--count", "--steps", "200", "-o", "{dir}/vertex-count.json"],
    "pursuit": ["wallfollow", "star", "--pursuit", "-o", "{dir}/pursuit.json"],
    "fields": ["fields", "serpentine", "--from", "3,2.25", "--to", "3,0.25", "--trials", "2", "--trajectories", "1",
               "--scenario", "reflection", "-o", "{dir}/fields.json"],
    "study": ["study", "reachability", "--grid", "n=8", "--grid", "irregularity=0.1,0.3", "--grid", "spikiness=0.1,0.3",
              "--per-cell", "1", "--workers", "1", "--out-dir", "{dir}/study", "-q", "--no-figure", "-o", "{dir}/study.json"],
}

# the environment each answer was made in (None: a study has none), and the report option that takes it
ENVIRONMENTS = {"plan": "two_rooms", "pareto": "l_shape", "patrol": "square", "funnel": "square", "localize": "l_shape",
                "cycle": "square", "controller": "l_shape", "study": None, "rooms": "three_chambers",
                "exploration": "l_shape", "range-exploration": "one_hole", "cut-ordering": "star", "learned-ordering": "l_shape",
                "vertex-count": "star", "pursuit": "star", "fields": "serpentine"}
OPTIONS = {"plan": "--plan", "pareto": "--plan", "patrol": "--patrol", "funnel": "--funnel", "localize": "--funnel",
           "cycle": "--cycle", "controller": "--cycle", "study": "--study"}
CERTIFICATES = {"plan": "cert.json", "pareto": "pareto_cert.json", "patrol": "patrol_cert.json",
                "funnel": "funnel_cert.json", "localize": "localize_cert.json"}


@pytest.fixture(scope="session")
def answers(tmp_path_factory) -> Path:
    """A folder with every answer of :data:`ANSWER_COMMANDS` (and its certificate) written by the CLI."""
    folder = tmp_path_factory.mktemp("answers")
    for kind, words in ANSWER_COMMANDS.items():
        result = run(*(w.format(dir=folder) for w in words))
        assert result.exit_code == 0, (kind, result.stderr)
    return folder


def report_args(kind: str, folder: Path, out: Path, *, certificate: bool = True) -> list[str]:
    """The ``solverplan report`` arguments for the answer of ``kind`` in ``folder`` (with its certificate if any)."""
    if kind not in OPTIONS:  # the one form every kind takes: report ANSWER.json (its environment found by name)
        return ["report", str(folder / f"{kind}.json"), "-o", str(out)]
    args = ["report"] + ([ENVIRONMENTS[kind]] if ENVIRONMENTS[kind] else [])
    args += [OPTIONS[kind], str(folder / f"{kind}.json")]
    if certificate and kind in CERTIFICATES:
        args += ["--certificate", str(folder / CERTIFICATES[kind])]
    return args + ["-o", str(out)]


@pytest.fixture(scope="session")
def reports(answers, tmp_path_factory) -> dict[str, Path]:
    """Every kind's report page, made by ``solverplan report`` (certified where the answer has a certificate)."""
    folder = tmp_path_factory.mktemp("reports")
    pages = {}
    for kind in ANSWER_COMMANDS:
        out = folder / f"{kind}.html"
        result = run(*report_args(kind, answers, out))
        assert result.exit_code == 0, (kind, result.stderr)
        pages[kind] = out
    return pages
