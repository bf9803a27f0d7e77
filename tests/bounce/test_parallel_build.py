"""Large jobs split over worker processes (the setting ``jobs``): the same answers as in one process, bit for bit."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import solverplan as sp
from solverplan import _arrays
from solverplan.bounce import partitions
from solverplan.bounce.bvg import _build, build, safe_bounce_visibility_graph, serialise
from solverplan.bounce.partitions import _partition, partition
from solverplan.environment import load_environment
from solverplan.errors import InputError
from solverplan.generators import star_polygon
from solverplan.progress import Stopped, watching
from solverplan.runtime import parallel_map
from tests.bounce.test_bvg import examples
from tests.strategies import polygons_with_holes

COLUMNS = ("source", "target", "lo", "hi", "n_intervals", "set_offsets", "set_lo", "set_hi", "transition", "phi")


def assert_same_graph(a, b) -> None:
    """Equal arrays, dtype for dtype (NaN where NaN)."""
    assert a.n_arcs == b.n_arcs
    for name in COLUMNS:
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype, name
        np.testing.assert_array_equal(x, y, err_msg=name)
    for x, y in zip(a._set_ends, b._set_ends):
        assert x.dtype == y.dtype
        np.testing.assert_array_equal(x, y)


@given(env=polygons_with_holes(max_vertices=8, max_holes=2), batches=st.integers(1, 12))
@settings(max_examples=examples(20), deadline=None)
@example(env=load_environment("two_holes"), batches=5)
@example(env=load_environment("warehouse"), batches=7)
def test_the_safe_bvg_built_in_batches_of_sources_equals_the_whole_build(env, batches):
    """Every arc's row needs only the sweeps at its source's ends; the arcs only their targets' sweeps meet are the
    reverses no batch built: the batches joined are the whole build, array for array (in this process: jobs=1)."""
    p = partition(env)
    assert_same_graph(build._build_split(p, 1, batches), _build(p))


def test_worker_processes_build_the_same_graph_as_one_process(monkeypatch):
    """Through safe_bounce_visibility_graph, with the size thresholds forced low: two forked workers, equal arrays."""
    monkeypatch.setattr(build, "SPLIT_MIN_SEGMENTS", 1)
    monkeypatch.setattr(build, "SPLIT_MIN_ARCS", 1)
    env = star_polygon(40, 0.2, 0.3, seed=3)
    with sp.config(graph_cache=None, jobs=1):
        one = _build(partition(env))
    with sp.config(graph_cache=None, jobs=2):
        two = safe_bounce_visibility_graph(partition(env))
    if _arrays.can_fork():
        assert two.stats["jobs"] == 2 and two.stats["batches"] >= 8
    assert_same_graph(two, one)


def test_small_graphs_are_built_in_this_process():
    with sp.config(graph_cache=None, jobs=2):
        g = safe_bounce_visibility_graph(load_environment("warehouse"))
    assert "jobs" not in g.stats


def test_the_partition_made_by_worker_processes_is_the_same(monkeypatch):
    monkeypatch.setattr(partitions, "SPLIT_MIN_PAIRS", 0)
    for env in (star_polygon(60, 0.2, 0.3, seed=1), load_environment("two_holes")):
        with sp.config(jobs=1):
            one = _partition(env)
        with sp.config(jobs=2):
            two = _partition(env)
        assert two == one and two.inserted == one.inserted


def test_the_json_encoded_by_worker_processes_is_the_same_bytes(monkeypatch):
    g = safe_bounce_visibility_graph(load_environment("warehouse"))
    monkeypatch.setattr(serialise, "SPLIT_MIN_ARCS", 1)
    monkeypatch.setattr(serialise, "SPLIT_ARCS_PER_RUN", 1000)
    for labelled in (True, False):
        view = g.select(safe=labelled)
        with sp.config(jobs=1):
            one = bytes(view.json_bytes(end=b"\n", arcs_per_chunk=500))
        with sp.config(jobs=2):
            two = bytes(view.json_bytes(end=b"\n", arcs_per_chunk=500))
        assert two == one


def test_process_map_keeps_the_order_and_raises_a_workers_exception():
    assert list(_arrays.process_map(lambda x: x * x, range(7), 2)) == [x * x for x in range(7)]

    def fails(x: int) -> int:
        if x == 3:
            raise InputError(f"bad item {x}")
        return x

    with pytest.raises(InputError, match="bad item 3"):
        list(_arrays.process_map(fails, range(6), 2))


@pytest.mark.skipif(not _arrays.can_fork(), reason="no worker processes here")
def test_a_killed_worker_is_an_error_not_a_wait():
    import os
    import signal

    def killed(x: int) -> int:
        if x == 2:
            os.kill(os.getpid(), signal.SIGKILL)  # as the out-of-memory killer would
        return x

    with pytest.raises(MemoryError, match="worker process was killed"):
        list(_arrays.process_map(killed, range(6), 2))


def test_a_worker_that_passes_the_stop_time_stops_the_job_with_its_task():
    def slow(x: int) -> int:
        from solverplan.progress import step

        step("counting", x, 4)
        return x

    with sp.config(jobs=2), watching(stop_at=time.monotonic() - 1), pytest.raises(Stopped) as stop:
        list(parallel_map(slow, range(4)))
    assert stop.value.task == "counting" and stop.value.total == 4


def test_jobs_must_be_a_whole_number_of_processes():
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(InputError, match="jobs"):
            with sp.config(jobs=bad):
                pass
    with sp.config(jobs=3) as now:
        assert now.jobs == 3
