"""The gallery's scripts (examples/plot_*.py) run, draw a figure, and say what their docstrings promise.

Each script runs in this process with runpy (the Agg backend, no window), as the docs build runs it; its globals
are then checked: every script leaves at least one matplotlib figure, and the main answer of each has the property
the script's text claims (a valid certificate, a front of several points, a proved cycle, ...).
"""

from __future__ import annotations

import runpy
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SCRIPTS = sorted(EXAMPLES.glob("plot_*.py"))


def _certified_plan(ns):
    assert ns["plan"].status.value == "found" and ns["plan"].optimality.proved
    assert ns["report"].valid
    assert ns["runs"].success_rate == 1.0


def _pareto_front(ns):
    assert len(ns["front"].points) >= 2
    assert ns["bounces"] == sorted(ns["bounces"]) and ns["tolerances"] == sorted(ns["tolerances"])


def _limit_cycle(ns):
    cycle = ns["cycle"]
    assert cycle.status.value == "found" and cycle.optimality.proved
    assert cycle.scope == "every-start"  # tan θ = 1/4 is inside Lemma 3's range, as the script says
    assert 0 < cycle.contraction_exact < 1


def _patrol(ns):
    tightest, widest = ns["tightest"], ns["widest"]
    assert tightest.status.value == widest.status.value == "found"
    assert tightest.contraction < widest.contraction < 1  # both contract; the wider intervals contract less
    assert widest.tolerance > tightest.tolerance


def _funnel_localize(ns):
    funnel = ns["funnel"]
    assert funnel.status.value == "found"
    assert funnel.widths[-1] < funnel.widths[0]  # the position set shrank
    assert ns["where"].status.value == "found"


def _rooms_and_doors(ns):
    dec = ns["dec"]
    assert len(dec.rooms) == len(dec.doors) + 1  # Remark 5: the rooms form a tree
    assert set(ns["comparison"].runs) == {"smart", "random", "billiard"}


def _exploration(ns):
    run = ns["run"]
    assert len(run.views) <= run.bound  # Theorem 1: at most r + 1 views
    assert run.covered_fraction > 1 - 1e-9


def _wall_following(ns):
    assert ns["learned"].matches_geometry
    assert len(ns["ordering"].labels) == ns["env"].n_vertices + 2 * len(ns["ordering"].reflex)


def _reflection_fields(ns):
    runs = ns["nav"].runs
    assert all(run.success == 1.0 for run in runs.values())  # every rollout reached the goal
    assert runs["reflection"].time_mean < runs["unconstrained"].time_mean < runs["constrained"].time_mean


def _floorplan_import(ns):
    assert ns["imported"].holes == 1  # the cupboard; the speckle was left out, and listed
    specks = [f for f in ns["imported"].features if f.kind == "speckle"]
    assert specks and all(f.size < 0.12 for f in specks)
    assert ns["plan"].status.value == "found"


def _pursuit(ns):
    assert ns["plan"].status.value == "found" and ns["replay"].valid
    assert len(ns["weaker"].actions) == len(ns["plan"].actions) == 5  # Prop. 10: the same length as Strategy 2


CHECKS = {
    "plot_01_certified_plan.py": _certified_plan,
    "plot_02_pareto_front.py": _pareto_front,
    "plot_03_limit_cycle.py": _limit_cycle,
    "plot_04_patrol.py": _patrol,
    "plot_05_funnel_localize.py": _funnel_localize,
    "plot_06_rooms_and_doors.py": _rooms_and_doors,
    "plot_07_exploration.py": _exploration,
    "plot_08_wall_following.py": _wall_following,
    "plot_09_reflection_fields.py": _reflection_fields,
    "plot_10_floorplan_import.py": _floorplan_import,
    "plot_11_pursuit.py": _pursuit,
}


def test_every_example_is_checked():
    assert {script.name for script in SCRIPTS} == set(CHECKS)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_example_runs_and_draws(script, capsys):
    text = script.read_text(encoding="utf-8")
    assert text.startswith('"""\n') and "\n===" in text.split('"""')[1], "sphinx-gallery needs a docstring title"
    try:
        ns = runpy.run_path(str(script), run_name="__main__")
        figures = [value for value in ns.values() if isinstance(value, Figure)]
        assert figures, f"{script.name} draws no figure"
        for fig in figures:
            assert fig.axes and all(ax.has_data() or ax.images or ax.patches for ax in fig.axes)
        CHECKS[script.name](ns)
    finally:
        plt.close("all")
    assert capsys.readouterr().out.strip(), f"{script.name} printed nothing"
