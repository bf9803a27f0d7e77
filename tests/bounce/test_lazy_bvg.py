"""The safe BVG built on demand (reachable_safe_graph) against the whole build: the same safe arcs, equal arrays."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from solverplan.bounce import _cache
from solverplan.bounce.bvg import _build, reachable_safe_graph, safe_bounce_visibility_graph
from solverplan.bounce.partitions import partition
from solverplan.environment import Environment, load_environment
from solverplan.errors import InvalidBoundarySet
from tests.bounce.test_bvg import examples
from tests.strategies import polygons_with_holes

COLUMNS = ("source", "target", "lo", "hi", "n_intervals", "set_offsets", "set_lo", "set_hi", "transition", "phi")


def safe_rows(g, sources) -> dict[str, np.ndarray]:
    """The whole graph's rows of ``sources`` with a safe heading, as the columns a lazy graph has."""
    keep = np.flatnonzero(np.isin(g.source, sources) & (g.n_intervals > 0))
    counts = g.n_intervals[keep]
    take = np.repeat(g.set_offsets[keep], counts) + np.concatenate([np.arange(c) for c in counts] or [np.zeros(0, int)])
    out = {name: getattr(g, name)[keep] for name in ("source", "target", "lo", "hi", "n_intervals", "transition", "phi")}
    out["set_offsets"] = np.concatenate([[0], np.cumsum(counts)])
    out["set_lo"], out["set_hi"] = g.set_lo[take], g.set_hi[take]
    ends = tuple(a[take] for a in g._set_ends)
    return out | {"ends": ends}


def assert_same_rows(lazy, whole_rows) -> None:
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(lazy, name), whole_rows[name], err_msg=name)
    for a, b in zip(lazy._set_ends, whole_rows["ends"]):
        np.testing.assert_array_equal(a, b)


def reachable(g, start, depth=None) -> np.ndarray:
    seen, frontier, d = set(start), set(start), 0
    while frontier and (depth is None or d < depth):
        nxt = set()
        for s in frontier:
            nxt |= set(g.target[(g.source == s) & (g.n_intervals > 0)].tolist())
        frontier = nxt - seen
        seen |= frontier
        d += 1
    return np.array(sorted(seen), dtype=np.int64)


@given(env=polygons_with_holes(max_vertices=8, max_holes=2), data=st.data())
@settings(max_examples=examples(15), deadline=None)
@example(env=load_environment("two_holes"), data=None)
def test_lazy_rows_equal_the_whole_safe_bvg_with_holes(env, data):
    """Per source: the safe arcs built from its two end sweeps alone are the whole build's, value for value."""
    p = partition(env)
    whole = _build(p)
    N = len(p.segments)
    sources = (np.array(sorted(data.draw(st.sets(st.integers(0, N - 1), min_size=1, max_size=N))), dtype=np.int64)
               if data is not None else np.arange(0, N, 3))
    assert_same_rows(_build(p, sources), safe_rows(whole, sources))


@given(env=polygons_with_holes(max_vertices=8, max_holes=2), start=st.integers(0, 10**6),
       depth=st.one_of(st.none(), st.integers(1, 3)))
@settings(max_examples=examples(15), deadline=None)
def test_reachable_safe_graph_holds_every_safe_arc_a_search_from_the_start_can_use(env, start, depth):
    p = partition(env)
    whole = _build(p)
    s = start % len(p.segments)
    lazy = reachable_safe_graph(p, [s], max_depth=depth)
    sources = reachable(whole, [s], depth)
    if depth is not None:  # the sources at depths below the budget
        sources = reachable(whole, [s], depth - 1)
    assert_same_rows(lazy, safe_rows(whole, sources))
    assert lazy.stats["reachable_sources"] >= len(sources)


def test_a_frontier_wider_than_a_batch_is_built_once_source_by_source():
    """The batch size adapts as the layer is built (the first is 64 sources): every source of a wide frontier is
    built exactly once — neither overlapping chunks (arcs listed twice) nor skipped ones (arcs missing)."""
    p = partition(load_environment("warehouse"))
    whole = _build(p)
    sources = np.arange(len(p.segments), dtype=np.int64)
    assert len(sources) > 3 * 64
    lazy = reachable_safe_graph(p, sources, max_depth=1)
    assert_same_rows(lazy, safe_rows(whole, sources))


def test_the_planner_answers_alike_on_the_lazy_and_the_whole_graph(monkeypatch):
    """find_plan over the reachable part (forced by a zero threshold) gives the whole graph's answer."""
    import solverplan as sp
    import solverplan.bounce.bvg as bvg

    for name, start, goal in (("two_holes", "e0", "e5"), ("warehouse", "e0", "e30"), ("star", "e0", "e9")):
        env = load_environment(name)
        _cache.clear_graph_cache()
        whole = sp.find_plan(env, start, goal, objective="tolerance")
        monkeypatch.setattr(bvg, "LAZY_MIN_ARCS", 0)
        _cache.clear_graph_cache()
        lazy = sp.find_plan(env, start, goal, objective="tolerance")
        monkeypatch.setattr(bvg, "LAZY_MIN_ARCS", 2_000_000)
        assert lazy.status == whole.status
        assert lazy.min_width == whole.min_width and lazy.bounces == whole.bounces
        assert [s.moves for s in lazy.stages] == [s.moves for s in whole.stages]


def test_start_segments_out_of_range_are_refused():
    with pytest.raises(InvalidBoundarySet, match="start segments"):
        reachable_safe_graph(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]]), [7])


def test_a_reachable_part_beyond_the_memory_limit_is_refused_with_a_simplification(monkeypatch):
    """The graph built on demand checks its growth against the memory limit and names what would fit."""
    import solverplan.bounce.bvg as bvg
    from solverplan.generators import star_polygon
    from solverplan.limits import reset_memory_limit, set_memory_limit

    env = star_polygon(60, 0.2, 0.3, seed=4)
    p = partition(env)
    set_memory_limit(bvg.BASE_BYTES + 1000 * bvg.PLANNED_BYTES_PER_ARC)  # room for 1,000 arcs
    try:
        with pytest.raises(bvg.GraphTooLarge, match=r"outgrew the memory limit .* after [0-9,]+ arcs from") as info:
            reachable_safe_graph(p, [0])
        assert "\n" not in str(info.value) and len(str(info.value)) < 200
        set_memory_limit(None)
        assert reachable_safe_graph(p, [0]).n_arcs > 1000
    finally:
        reset_memory_limit()


def test_a_query_without_budget_is_refused_up_front_when_the_whole_graph_would_not_fit(monkeypatch):
    """Without --max-bounces the on-demand build would reach nearly everything: refused before it starts."""
    import solverplan as sp
    import solverplan.bounce.bvg as bvg
    from solverplan.generators import star_polygon
    from solverplan.limits import reset_memory_limit, set_memory_limit

    env = star_polygon(60, 0.2, 0.3, seed=6)
    monkeypatch.setattr(bvg, "LAZY_MIN_ARCS", 0)
    monkeypatch.setattr(bvg, "reachable_safe_graph", lambda *a, **k: pytest.fail("built before refusing"))
    _cache.clear_graph_cache()
    set_memory_limit(bvg.BASE_BYTES + 1000)
    try:
        with pytest.raises(bvg.GraphTooLarge, match="would need"):
            sp.find_plan(env, "e0", "e30", objective="tolerance")
    finally:
        reset_memory_limit()
