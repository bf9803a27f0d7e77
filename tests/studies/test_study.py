"""Studies: grids, seeds, tidy tables, reproducible rows, resume after interruption, local pool = serial."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pytest

from solverplan.errors import InputError, SolverFailed
from solverplan.generators import generate
from solverplan.studies import (
    ConnectivityMetric,
    ReachabilityMetric,
    Study,
    StudyInterrupted,
    build_study,
    parse_grid,
    parse_values,
    row_seed,
    run_study,
    run_task,
)
from solverplan.studies.execute import output_paths
from solverplan.studies.store import RowStore

SMALL_GRID = (("n", (8,)), ("irregularity", (0.1, 0.3)), ("spikiness", (0.2, 0.4)))


# ---------------------------------------------------------------------- a cheap metric that counts and can fail
CALLS: list[int] = []


@dataclass(frozen=True)
class CountingMetric:
    """Area and vertex count; records each call's seed in CALLS; raises on the seeds in ``fail_on``."""

    fail_on: tuple[int, ...] = ()
    name: ClassVar[str] = "counting"
    columns: ClassVar[tuple[str, ...]] = ("area", "reflex")
    options: ClassVar[tuple] = ()
    panels: ClassVar[tuple] = (("area", {}),)

    def __call__(self, env: Any, *, seed: int, **options: Any) -> dict:
        if seed in self.fail_on:
            raise RuntimeError("worker died")
        CALLS.append(seed)
        return {"area": float(env.area), "reflex": len(env.reflex_vertices)}

    def spec(self) -> dict:
        return {"metric": self.name}  # fail_on is a test device, not part of the identity


@pytest.fixture(autouse=True)
def _reset_calls():
    CALLS.clear()
    yield
    CALLS.clear()


def counting_study(per_cell: int = 3, fail_on: tuple[int, ...] = (), grid=SMALL_GRID) -> Study:
    return Study(CountingMetric(fail_on), grid=grid, per_cell=per_cell, seed=5)


def without_seconds(rows) -> list[dict]:
    return [{k: v for k, v in r.items() if k != "seconds"} for r in rows]


# ---------------------------------------------------------------------- grids and seeds
@pytest.mark.parametrize(
    "text, values",
    [("20", (20,)), ("0.1:0.4:5", (0.1, 0.175, 0.25, 0.325, 0.4)), ("2:10:5", (2, 4, 6, 8, 10)), ("convex,star", ("convex", "star")),
     ("0.5:0.5:1", (0.5,)), ("-1,2.5", (-1, 2.5))],
)
def test_parse_values(text, values):
    assert parse_values(text) == values


@pytest.mark.parametrize(
    "text, message",
    [("0.1:0.4", r"^x: expected VALUE, V1,V2,\.\.\. or START:STOP:COUNT, got '0.1:0.4'$"),
     ("0.1:0.4:0", r"^x: START:STOP:COUNT needs COUNT >= 1, got '0.1:0.4:0'$"),
     ("1,,2", r"^x: empty value in '1,,2'$"),
     ("1,1", r"^x: repeated value in '1,1'$")],
)
def test_parse_values_errors_are_one_line(text, message):
    with pytest.raises(InputError, match=message):
        parse_values(text, name="x")


def test_parse_grid_replaces_and_extends_axes():
    grid = parse_grid(["spikiness=0.3", "radius=2"], base=SMALL_GRID)
    assert dict(grid) == {"n": (8,), "irregularity": (0.1, 0.3), "spikiness": (0.3,), "radius": (2,)}
    with pytest.raises(InputError, match=r"^grid axis 'spikiness': expected NAME=VALUES"):
        parse_grid(["spikiness"])


def test_study_rejects_unknown_generator_parameters_by_name():
    with pytest.raises(InputError, match=r"^generator 'star' has no parameter 'rooms': use n, irregularity, spikiness"):
        Study(ReachabilityMetric(), grid=(("n", (8,)), ("irregularity", (0.1,)), ("spikiness", (0.1,)), ("rooms", (3,))))
    with pytest.raises(InputError, match=r"^generator 'star' needs a value for 'spikiness'"):
        Study(ReachabilityMetric(), grid=(("n", (8,)), ("irregularity", (0.1,))))
    with pytest.raises(InputError, match=r"^expected per_cell >= 1, got per_cell=0$"):
        Study(ReachabilityMetric(), per_cell=0)


def test_row_seeds_depend_on_generator_parameters_and_replicate_only():
    params = {"n": 20, "irregularity": 0.1, "spikiness": 0.3}
    seeds = {row_seed(0, "star", params, k) for k in range(100)}
    assert len(seeds) == 100
    assert row_seed(0, "star", params, 3) == row_seed(0, "star", dict(reversed(params.items())), 3)
    assert row_seed(1, "star", params, 3) != row_seed(0, "star", params, 3)
    study = build_study("rules", per_cell=2, families=["fixed", "specular"], grid=["irregularity=0.1", "spikiness=0.2"])
    by_rule = {}
    for task in study.tasks():
        by_rule.setdefault(dict(task.options)["rule"], []).append(task.seed)
    assert by_rule["fixed"] == by_rule["specular"]  # the families see the same polygons


# ---------------------------------------------------------------------- tables
def test_table_has_one_row_per_cell_and_seed_with_the_declared_columns(tmp_path):
    study = Study(ReachabilityMetric(), grid=SMALL_GRID, per_cell=2)
    result = run_study(study, tmp_path, workers=1)
    rows = result.table.rows
    assert len(rows) == study.n_cells * study.per_cell == 8
    assert [(r["cell"], r["replicate"]) for r in rows] == [(c, k) for c in range(4) for k in range(2)]
    assert all(tuple(r) == study.columns for r in rows)
    assert study.columns == ("cell", "replicate", "seed", "n", "irregularity", "spikiness", "vertices", "holes",
                             "segments", "arcs", "safe_arcs", "unreachable_segments", "unreachable",
                             "unreachable_nonadjacent", "seconds")
    for r in rows:
        assert 0 <= r["unreachable_nonadjacent"] <= 1 and 0 <= r["unreachable"] <= r["unreachable_nonadjacent"]
        assert r["safe_arcs"] <= r["arcs"] and r["vertices"] == 8
    # the files: CSV and JSON tables equal to the in-memory table
    paths = output_paths(study, tmp_path)
    with open(paths["csv"], newline="") as handle:
        csv_rows = list(csv.DictReader(handle))
    assert [tuple(r) for r in csv_rows][0] == study.columns
    assert [float(r["unreachable"]) for r in csv_rows] == [r["unreachable"] for r in rows]
    data = json.loads(paths["json"].read_text())
    assert data["columns"] == list(study.columns) and data["rows"] == [dict(r) for r in rows]
    assert [c["rows"] for c in data["cells"]] == [2] * 4
    mean0 = np.mean([r["unreachable"] for r in rows if r["cell"] == 0])
    assert data["cells"][0]["unreachable"]["mean"] == pytest.approx(mean0)


def test_rows_are_reproducible_from_their_seed():
    study = Study(ConnectivityMetric(), grid=SMALL_GRID, per_cell=2)
    table = run_study(study, workers=1).table
    for row in table.rows[::3]:
        env = generate("star", seed=row["seed"], n=row["n"], irregularity=row["irregularity"], spikiness=row["spikiness"])
        again = ConnectivityMetric()(env, seed=row["seed"])
        assert {c: row[c] for c in ConnectivityMetric.columns} == again


def test_heatmap_means_cells_over_the_last_two_axes():
    study = counting_study(per_cell=2)
    table = run_study(study, workers=1).table
    heat = table.heatmap("area")
    assert (heat.y_name, heat.y_values, heat.x_name, heat.x_values) == ("irregularity", (0.1, 0.3), "spikiness", (0.2, 0.4))
    for i, irr in enumerate(heat.y_values):
        for j, spk in enumerate(heat.x_values):
            values = [r["area"] for r in table.rows if r["irregularity"] == irr and r["spikiness"] == spk]
            assert heat.mean[i, j] == pytest.approx(np.mean(values)) and heat.count[i, j] == 2
    assert heat.overall == pytest.approx(np.mean(table.column("area")))


# ---------------------------------------------------------------------- resume
def test_resume_computes_only_the_missing_rows_after_a_worker_fails(tmp_path):
    full = run_study(counting_study(), None, workers=1).table  # uninterrupted reference
    reference_calls = list(CALLS)
    CALLS.clear()
    fail_at = reference_calls[7]  # the 8th row raises: 7 rows are finished and saved
    with pytest.raises(SolverFailed, match=r"^row cell 2 \(n=8, irregularity=0\.3, spikiness=0\.2\), replicate 1, seed \d+ "
                                           r"failed: RuntimeError: worker died$"):
        run_study(counting_study(fail_on=(fail_at,)), tmp_path, workers=1)
    assert CALLS == reference_calls[:7]
    CALLS.clear()
    result = run_study(counting_study(), tmp_path, workers=1)
    assert CALLS == reference_calls[7:]  # only the missing rows, each once
    assert (result.computed, result.reused) == (5, 7)
    assert without_seconds(result.table.rows) == without_seconds(full.rows)


def test_resume_after_a_partial_last_line_and_deleted_rows(tmp_path):
    study = counting_study()
    first = run_study(study, tmp_path, workers=1)
    path = output_paths(study, tmp_path)["rows"]
    lines = path.read_text().splitlines(keepends=True)
    assert len(lines) == 1 + 12
    # delete rows 3 and 4 (the 2nd and 3rd rows), and cut the last row mid-line (a kill while writing)
    damaged = lines[:2] + lines[4:-1] + [lines[-1][: len(lines[-1]) // 2]]
    path.write_text("".join(damaged))
    CALLS.clear()
    again = run_study(study, tmp_path, workers=1)
    missing = {first.table.rows[k]["seed"] for k in (1, 2, 11)}
    assert sorted(CALLS) == sorted(missing)
    assert again.computed == 3 and again.reused == 9
    assert without_seconds(again.table.rows) == without_seconds(first.table.rows)
    # the rows file was repaired: a header and 12 complete rows, every line JSON
    lines = path.read_text().splitlines()
    assert len(lines) == 13 and all(json.loads(line) for line in lines)


@pytest.mark.parametrize("hostile", ["[" * 100_000, '{"replicate": ' + "9" * 5000 + "}", '{"replicate": [1]}',
                                     '[1, 2]', '{"seed": {"a": 1}, "replicate": 0, "n": [], "cell": 1}'])
def test_hostile_rows_are_dropped_and_recomputed(tmp_path, hostile):
    study = counting_study(per_cell=1)
    run_study(study, tmp_path, workers=1)
    path = output_paths(study, tmp_path)["rows"]
    lines = path.read_text().splitlines(keepends=True)
    path.write_text(lines[0] + hostile + "\n" + "".join(lines[2:]))
    again = run_study(study, tmp_path, workers=1)
    assert (again.computed, again.reused) == (1, len(lines) - 2)


@pytest.mark.parametrize("header", ["[" * 100_000, '{"format": "solverplan-study-rows", "version": ' + "9" * 5000 + "}",
                                    '{"format": "solverplan-study-rows", "version": 1, "identity": [1]}'])
def test_a_hostile_header_is_one_line(tmp_path, header):
    study = counting_study(per_cell=1)
    run_study(study, tmp_path, workers=1)
    path = output_paths(study, tmp_path)["rows"]
    lines = path.read_text().splitlines(keepends=True)
    path.write_text(header + "\n" + "".join(lines[1:]))
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path, workers=1)
    assert "\n" not in str(info.value) and len(str(info.value)) < 200 + len(str(path))


def test_a_finished_study_recomputes_nothing_and_a_larger_one_reuses_its_rows(tmp_path):
    run_study(counting_study(per_cell=2), tmp_path, workers=1)
    CALLS.clear()
    assert run_study(counting_study(per_cell=2), tmp_path, workers=1).computed == 0
    assert CALLS == []
    bigger = counting_study(per_cell=3, grid=(("n", (8,)), ("irregularity", (0.1, 0.3, 0.5)), ("spikiness", (0.2, 0.4))))
    result = run_study(bigger, tmp_path, workers=1)
    assert (result.reused, result.computed) == (8, 10) and len(CALLS) == 10
    assert len(result.table.rows) == 18


def test_fresh_starts_over(tmp_path):
    run_study(counting_study(per_cell=1), tmp_path, workers=1)
    CALLS.clear()
    assert run_study(counting_study(per_cell=1), tmp_path, workers=1, resume=False).computed == 4
    assert len(CALLS) == 4


def test_rows_of_another_study_are_refused(tmp_path):
    run_study(counting_study(per_cell=1), tmp_path, workers=1)
    other = Study(CountingMetric(), grid=SMALL_GRID, per_cell=1, seed=6)
    path = output_paths(other, tmp_path)["rows"]
    with pytest.raises(InputError, match=rf"^{path} holds rows of another study \(seed: 5 there, 6 here\); use --fresh"):
        run_study(other, tmp_path, workers=1)


def test_two_runs_cannot_write_one_rows_file(tmp_path):
    study = counting_study(per_cell=1)
    store = RowStore(output_paths(study, tmp_path)["rows"], study)
    store.open()
    try:
        with pytest.raises(InputError, match=r"another study is writing this file$"):
            run_study(study, tmp_path, workers=1)
    finally:
        store.close()


def test_interrupt_keeps_finished_rows(tmp_path):
    study = counting_study()
    seen = []

    def progress(done: int, total: int) -> None:
        seen.append(done)
        if done == 5:
            raise KeyboardInterrupt

    with pytest.raises(StudyInterrupted, match=r"^study counting interrupted after 5 of 12 rows; its rows are in .*: run it again"):
        run_study(study, tmp_path, workers=1, progress=progress)
    assert seen == [0, 1, 2, 3, 4, 5]
    CALLS.clear()
    assert run_study(study, tmp_path, workers=1).computed == 7 and len(CALLS) == 7


def test_bad_generator_parameters_in_a_row_are_input_errors():
    study = Study(CountingMetric(), grid=(("n", (8,)), ("irregularity", (1.5,)), ("spikiness", (0.2,))), per_cell=1)
    with pytest.raises(InputError, match=r"^cell \(n=8, irregularity=1\.5, spikiness=0\.2\): "
                                         r"expected irregularity in \[0, 1\], got irregularity=1\.5$"):
        run_study(study, workers=1)


# ---------------------------------------------------------------------- engines agree
def test_local_pool_gives_the_serial_table(tmp_path):
    study = Study(ReachabilityMetric(), grid=SMALL_GRID, per_cell=3)
    serial = run_study(study, workers=1)
    pooled = run_study(study, tmp_path, workers=2)
    assert pooled.engine == {"engine": "local", "workers": 2}
    assert without_seconds(pooled.table.rows) == without_seconds(serial.table.rows)


def test_run_task_row_layout():
    task = counting_study(per_cell=1).tasks()[1]
    row = run_task(task)
    assert list(row) == list(counting_study().columns)
    assert (row["cell"], row["replicate"], row["seed"], row["spikiness"]) == (1, 0, task.seed, 0.4)


def test_summary_json_and_text():
    result = run_study(counting_study(per_cell=2), workers=1)
    data = result.to_json()
    assert data["rows"] == 8 and data["computed"] == 8 and data["study"]["cells"] == 4
    assert data["means"]["area"] == pytest.approx(np.mean(result.table.column("area")))
    assert [c["area"] for c in data["cells"]] == pytest.approx(list(result.table.heatmap("area").mean.ravel()))
    text = result.to_text()
    assert text.splitlines()[0] == "study counting: star polygons, 4 cells x 2 seeds = 8 rows (8 computed, 0 reused) in " + \
        f"{result.seconds:.1f} s"
    assert text.splitlines()[1].split() == ["irregularity", "spikiness", "area"]
    assert json.loads(json.dumps(data)) == data
    from solverplan.answers import AnswerSummary, read_answer

    back = read_answer(json.loads(json.dumps(data)))  # a study summary reads back as what it is
    assert isinstance(back, AnswerSummary) and back.kind == "study" and back.to_json() == json.loads(json.dumps(data))


@pytest.mark.slow
def test_full_paper_grid_reachability_and_connectivity(tmp_path):
    """The paper's grid (5 × 5 cells × 10 star polygons, n = 20) with the defaults."""
    for name in ("reachability", "connectivity"):
        result = run_study(build_study(name), tmp_path)
        assert len(result.table.rows) == 250
        means = result.table.means()
        if name == "reachability":
            assert means["unreachable"] < 0.05  # the paper: on average at least 95 % reachable
        else:
            assert means["wcc"] < 1.5 < means["scc"]
            heat = result.table.heatmap("scc")
            assert heat.mean[:, -1].mean() > heat.mean[:, 0].mean()  # strong components grow with spikiness
