"""The Dask engine: a study on a LocalCluster gives exactly the local table (timings aside)."""

from __future__ import annotations

import pytest

distributed = pytest.importorskip("distributed")

from solverplan.studies import ReachabilityMetric, Study, build_study, run_study  # noqa: E402
from solverplan.studies.execute import output_paths  # noqa: E402

GRID = (("n", (10,)), ("irregularity", (0.1, 0.4)), ("spikiness", (0.2, 0.5)))


def metric_rows(table):
    return [{k: v for k, v in row.items() if k != "seconds"} for row in table.rows]


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as c:
        yield c


def test_dask_local_cluster_gives_the_local_table(cluster, tmp_path):
    study = Study(ReachabilityMetric(), grid=GRID, per_cell=3)
    local = run_study(study, workers=1)
    remote = run_study(study, tmp_path, scheduler=cluster.scheduler_address)
    assert remote.engine == {"engine": "dask", "scheduler": cluster.scheduler_address}
    assert metric_rows(remote.table) == metric_rows(local.table)
    assert output_paths(study, tmp_path)["csv"].read_text().count("\n") == 1 + 12


def test_dask_client_resumes_a_local_run(cluster, tmp_path):
    """Rows computed locally are reused on the cluster; the rules study (sampled) agrees exactly too."""
    study = build_study("rules", per_cell=2, families=["fixed", "specular"], trials=20, bounces=10,
                        grid=["n=10", "irregularity=0.3", "spikiness=0.2,0.5"])
    local = run_study(study, workers=1)
    half = Study(study.metric, grid=(("n", (10,)), ("irregularity", (0.3,)), ("spikiness", (0.2,))), per_cell=2)
    run_study(half, tmp_path, workers=1)
    with distributed.Client(cluster, set_as_default=False) as client:
        remote = run_study(study, tmp_path, scheduler=client)
    assert (remote.reused, remote.computed) == (4, 4)
    assert metric_rows(remote.table) == metric_rows(local.table)


def test_a_finished_study_on_the_cluster_computes_nothing(cluster, tmp_path):
    study = Study(ReachabilityMetric(), grid=GRID, per_cell=1)
    run_study(study, tmp_path, workers=1)
    result = run_study(study, tmp_path, scheduler=cluster.scheduler_address)
    assert (result.computed, result.reused) == (0, 4)
