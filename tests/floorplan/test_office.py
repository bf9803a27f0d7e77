"""The shipped example: models/office.yaml is what its script writes, imports as the README says, and plans."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
from PIL import Image

from solverplan.floorplan import import_floorplan
from solverplan.plan.search import find_plan

MODELS = Path(__file__).resolve().parents[2] / "models"


def test_the_office_map_is_what_its_script_writes():
    spec = importlib.util.spec_from_file_location("make_office_map", MODELS / "make_office_map.py")
    assert spec is not None and spec.loader is not None
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    shipped = np.asarray(Image.open(MODELS / "office.pgm"))
    assert np.array_equal(script.office_map(), shipped)


def test_the_readme_tutorial_imports_and_plans_through_the_door(tmp_path):
    done = import_floorplan(MODELS / "office.yaml", output=tmp_path / "office.json", simplify=0.15, rectilinear=10)
    env = done.environment
    assert (done.outer_vertices, done.holes, env.n_vertices) == (14, 2, 23)
    assert 52.5 < done.area < 54.5  # 10 m × 6 m less the wall, desk, table and shelf (54.2 m²) less ragged edges
    # e8 is the left room's far wall, e0 the right room's: the README's edge ids
    assert {float(x) for x, _ in (env.edge(8).a, env.edge(8).b)} == {0.025}
    assert {round(float(x), 1) for x, _ in (env.edge(0).a, env.edge(0).b)} == {10.0}
    plan = find_plan(env, "e8", "e0")
    assert plan.status.answered and plan.bounces >= 2  # no straight line joins the two walls: through the door


def test_a_fine_import_advises_the_simplification_that_planning_needs(tmp_path):
    # half a cell, as traced (the defaults simplify within the walls' noise: 69 vertices)
    fine = import_floorplan(MODELS / "office.yaml", output=tmp_path / "fine.json", simplify=0.025, rectilinear=0)
    assert fine.environment.n_vertices > 150 and "--simplify 0.1 (two cells)" in fine.to_json()["advice"]
    assert "advice:" in fine.to_text()
    coarse = import_floorplan(MODELS / "office.yaml", output=tmp_path / "coarse.json", simplify=0.1, rectilinear=10)
    assert coarse.advice is None and "advice" not in coarse.to_json()
