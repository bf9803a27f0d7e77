"""The bounce visibility graph and the safe BVG (paper §4–5: Def. 5, Prop. 1, Prop. 3, Prop. 5).

References: the exact predicate :func:`~solverplan.geometry.visibility.segments_see_each_other`
(open segments, no grazing) for the arcs, :func:`~solverplan.bounce.safe.safe_set` for the labels.
"""

from __future__ import annotations

import json
import re
import math
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import solverplan.bounce._sweep as sweep_module
from solverplan import cli
from solverplan.bounce.bvg import SafeBVG, bounce_visibility_graph, safe_bounce_visibility_graph
from solverplan.interval import Interval
from solverplan.bounce.partitions import partition
from solverplan.limits import reset_memory_limit, set_memory_limit
from solverplan.bounce.safe import safe_set
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.geometry.visibility import segments_see_each_other
from solverplan.generators import worst_case_polygon
from tests.strategies import polygons_with_holes, simple_polygons

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"
SQUARE = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]], name="square")
ELL = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], name="L")

# Prop. 1 on the paper's worst-case family n = 4t + 2 (§4.0.1): (t, n, segments of P′, BVG arcs, safe arcs)
WORST_CASE_COUNTS = [
    (2, 10, 22, 282, 154),
    (3, 14, 42, 914, 470),
    (4, 18, 70, 2190, 1090),
    (5, 22, 94, 4066, 1982),
    (6, 26, 134, 7754, 3742),
    (7, 30, 182, 13398, 6414),
    (8, 34, 238, 21434, 10306),
]


def examples(k: int) -> int:
    """k examples in the default profile, 10 k in the thorough one."""
    return max(k, settings.default.max_examples * k // 100)


def model(name: str) -> Environment:
    return load_environment(MODELS / f"{name}.json")


def arcs_of(g: SafeBVG) -> set[tuple[int, int]]:
    return set(zip(g.source.tolist(), g.target.tolist()))


# ---------------------------------------------------------------------------------------------
# acceptance and small cases
# ---------------------------------------------------------------------------------------------
def test_square_has_four_segments_and_safe_arcs_both_ways():
    g = safe_bounce_visibility_graph(SQUARE)
    assert g.n_segments == 4
    assert arcs_of(g) == {(i, j) for i in range(4) for j in range(4) if i != j}
    assert g.n_safe_arcs == 12  # Cor. 1: the adjacent sides too, in both directions
    assert g.transitions[g.arc_index(0, 1)] == "right" and g.transitions[g.arc_index(1, 0)] == "left"
    assert g.transitions[g.arc_index(0, 2)] == "parallel" and g.phi[g.arc_index(0, 2)] == 0.0
    assert g.phi[g.arc_index(0, 1)] == pytest.approx(math.pi / 2)


def test_arcs_need_open_segments_to_see_each_other_not_just_an_end_point():
    """In an L, the right wall's lower part and the top of the left arm see each other only along
    the line grazing the reflex vertex: no arc, although an end point of each is visible from the other."""
    p = partition(ELL)
    g = safe_bounce_visibility_graph(p)
    wall = p.segment_at(1, 0.5)  # (4, 0)–(4, 2)
    top = p.segment_at(4, 0.5)  # (2, 4)–(0, 4)
    assert (wall, top) not in arcs_of(g) and (top, wall) not in arcs_of(g)
    s, t = p.segments[wall], p.segments[top]
    assert not segments_see_each_other(ELL, (s.a, s.b), (t.a, t.b))


def test_no_self_loops_no_arcs_within_an_edge_and_symmetric():
    for name in ("two_rooms", "degenerate", "two_holes"):
        p = partition(model(name))
        g = safe_bounce_visibility_graph(p)
        arcs = arcs_of(g)
        assert all(i != j for i, j in arcs)
        assert all(p.segments[i].edge != p.segments[j].edge for i, j in arcs)  # collinear pieces of one edge
        assert all((j, i) in arcs for i, j in arcs)  # visibility is symmetric
        assert np.all(np.diff(g.source * g.n_segments + g.target) > 0)  # sorted, no duplicates


def test_no_arc_between_the_segments_at_a_reflex_vertex():
    p = partition(ELL)
    g = safe_bounce_visibility_graph(p)
    r = ELL.reflex_vertices[0]
    after = p.segment_at(r, 0)
    before = int(p.prev_segment[after])
    assert (before, after) not in arcs_of(g) and (after, before) not in arcs_of(g)


def test_bounce_visibility_graph_is_a_networkx_digraph():
    p = partition(model("l_shape"))
    g = bounce_visibility_graph(p)
    safe = safe_bounce_visibility_graph(p)
    assert isinstance(g, nx.DiGraph)
    assert set(g.nodes) == set(range(len(p)))
    assert set(g.edges) == arcs_of(safe)
    assert all(data["transition"] in ("left", "right", "parallel") for _, _, data in g.edges(data=True))
    h = safe.to_networkx()
    assert set(h.edges) == set(g.edges)
    for i, j, data in h.edges(data=True):
        assert data["safe"] == safe.interval(i, j)
        assert data["safe_set"] == tuple(piece.interval for piece in safe.safe_set(i, j).intervals)
    only = safe.to_networkx(safe_only=True)
    assert only.number_of_edges() == safe.n_safe_arcs
    assert all(not data["safe"].is_empty for _, _, data in only.edges(data=True))


# ---------------------------------------------------------------------------------------------
# Def. 5 against the exact reference
# ---------------------------------------------------------------------------------------------
def check_arcs_against_reference(env: Environment) -> None:
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    arcs = arcs_of(g)
    segs = p.segments
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            sees = segments_see_each_other(env, (segs[i].a, segs[i].b), (segs[j].a, segs[j].b))
            assert sees == ((i, j) in arcs) == ((j, i) in arcs), (i, j, sees)


@given(env=polygons_with_holes(max_vertices=7, max_holes=2))
@settings(max_examples=examples(8))
def test_def5_arcs_equal_the_exact_reference_with_holes(env):
    check_arcs_against_reference(env)


@given(env=simple_polygons(max_vertices=10))
@settings(max_examples=examples(10))
def test_def5_arcs_equal_the_exact_reference_without_holes(env):
    check_arcs_against_reference(env)


@pytest.mark.parametrize("name", ["degenerate", "l_shape", "comb"])
def test_def5_arcs_equal_the_exact_reference_on_models(name):
    """The degenerate model: collinear vertices, parallel edges, inserted points on lines through
    vertices — exact ties, decided without epsilons."""
    check_arcs_against_reference(model(name))


@pytest.mark.parametrize("name", ["degenerate", "two_holes", "worst_case_t4", "spiral"])
def test_exact_fallbacks_agree_with_the_float_path(monkeypatch, name):
    """Force the decisions through the exact fallbacks (huge tolerances make every float answer
    uncertain; every sector is cast exactly): the graph and its safe sets must not change."""
    import solverplan.bounce.bvg as bvg_module

    env = model(name)
    want = safe_bounce_visibility_graph(env)
    monkeypatch.setattr(sweep_module, "ANGLE_REL", 1e3)
    monkeypatch.setattr(sweep_module, "CROSS_REL", 1e3)
    monkeypatch.setattr(sweep_module, "_THIN", 10.0)
    monkeypatch.setattr(bvg_module.tolerances, "SAT_REL", 1e3)
    bvg_module.clear_graph_cache()  # a rebuild, not the graph kept from the first call
    got = safe_bounce_visibility_graph(env)
    bvg_module.clear_graph_cache()  # nor keep this one for the other tests
    assert got.stats["exact_casts"] > 0 and got.stats["exact_checks"] > 5 * want.stats["exact_checks"]
    assert arcs_of(got) == arcs_of(want)
    assert np.array_equal(got.n_intervals, want.n_intervals)
    assert np.allclose(got.set_lo, want.set_lo, atol=1e-12) and np.allclose(got.set_hi, want.set_hi, atol=1e-12)
    assert np.array_equal(got.transition, want.transition)


# ---------------------------------------------------------------------------------------------
# Prop. 1: sizes
# ---------------------------------------------------------------------------------------------
def test_prop1_arc_counts_on_the_worst_case_family():
    rows = []
    for t, n, segments, arcs, safe in WORST_CASE_COUNTS:
        env = worst_case_polygon(t)
        p = partition(env)
        g = safe_bounce_visibility_graph(p)
        assert (env.n_vertices, len(p), g.n_arcs, g.n_safe_arcs) == (n, segments, arcs, safe), t
        rows.append((n, segments, arcs))
    n, segments, arcs = (np.array(col, dtype=float) for col in zip(*rows))
    assert np.all(np.diff(arcs) > 0) and np.all(np.diff(segments) > 0)
    assert np.all(arcs <= segments * (segments - 1))
    # |P′| = O(n²) and |arcs| = O(n⁴): fitted exponents on this range (the asymptote is reached slowly)
    seg_slope = np.polyfit(np.log(n), np.log(segments), 1)[0]
    arc_slope = np.polyfit(np.log(n), np.log(arcs), 1)[0]
    assert 1.5 < seg_slope <= 2.2 and 3.0 < arc_slope <= 4.2
    assert arcs[-1] / n[-1] ** 4 > arcs[0] / n[0] ** 4 * 0.5  # no collapse below n⁴ growth


# ---------------------------------------------------------------------------------------------
# Prop. 3 and Prop. 5
# ---------------------------------------------------------------------------------------------
def check_prop3(env: Environment) -> None:
    """Every segment has a safe action (0, θ_l] and one [θ_r, π) (paper Prop. 3, both kinds)."""
    g = safe_bounce_visibility_graph(env)
    right = np.zeros(g.n_segments, dtype=bool)
    left = np.zeros(g.n_segments, dtype=bool)
    for k in np.flatnonzero(g.safe).tolist():
        pieces = g.safe_set(int(g.source[k]), int(g.target[k])).intervals
        right[g.source[k]] |= pieces[0].lo == 0.0
        left[g.source[k]] |= pieces[-1].hi == math.pi
    assert right.all() and left.all(), (np.flatnonzero(~right).tolist(), np.flatnonzero(~left).tolist())
    assert np.all(np.bincount(g.source[g.safe], minlength=g.n_segments) >= 2)


@pytest.mark.parametrize("name", ["square", "triangle", "l_shape", "two_rooms", "comb", "spiral", "one_hole",
                                  "two_holes", "warehouse", "degenerate", "worst_case_t4"])
def test_prop3_every_segment_has_two_safe_outgoing_intervals_on_models(name):
    check_prop3(model(name))


@given(env=st.one_of(simple_polygons(max_vertices=14), polygons_with_holes(max_vertices=10, max_holes=3)))
@settings(max_examples=examples(30))
def test_prop3_every_segment_has_two_safe_outgoing_intervals(env):
    check_prop3(env)


def test_prop5_a_segment_without_safe_incoming_arcs():
    """Paper Prop. 5 (Fig. 10): planning in BVG_safe is incomplete. In the two-rooms model one segment
    of P′ is reached by no safe action — checked against the exact reference from every other segment;
    its two ends are reflex or inserted points, as the paper's proof says they must be."""
    env = model("two_rooms")
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    reached = np.zeros(g.n_segments, dtype=bool)
    reached[g.target[g.safe]] = True
    unreached = np.flatnonzero(~reached).tolist()
    assert unreached
    j = unreached[0]
    target = p.segments[j]
    for i, source in enumerate(p.segments):
        if i != j:
            assert safe_set(env, (source.a, source.b), (target.a, target.b)).is_empty
    assert g.n_intervals[g.target == j].sum() == 0 and (g.target == j).any()  # seen, never safely reached
    reflex = {env.exact_vertices[v] for v in env.reflex_vertices}
    inserted = {q.point for q in p.inserted}
    assert target.a in reflex | inserted and target.b in reflex | inserted


# ---------------------------------------------------------------------------------------------
# output formats
# ---------------------------------------------------------------------------------------------
def test_contract_json_of_the_safe_graph():
    g = safe_bounce_visibility_graph(model("two_rooms"))
    data = g.to_json()
    assert data["n_arcs"] == len(data["arcs"]) == g.n_arcs and data["n_safe_arcs"] == g.n_safe_arcs
    json.dumps(data, allow_nan=False)  # no NaN leaks into JSON
    for arc in data["arcs"]:
        assert set(arc) == {"from", "to", "safe", "transition", "phi", "safe_set"}
        assert arc["transition"] in ("left", "right", "parallel")
        if arc["safe"] is None:
            assert arc["safe_set"] == []
        else:
            lo, hi = arc["safe"]
            assert 0.0 <= lo <= hi <= math.pi and [lo, hi] in arc["safe_set"]
    plain = g.to_json(safe=False)
    assert all(set(arc) == {"from", "to", "transition"} for arc in plain["arcs"])


def test_graphml_dot_and_text_exports():
    g = safe_bounce_visibility_graph(model("l_shape"))
    back = nx.parse_graphml(g.to_graphml(), node_type=int)
    assert set(back.edges) == arcs_of(g)
    k = int(np.flatnonzero(g.safe)[0])
    i, j = int(g.source[k]), int(g.target[k])
    assert back.edges[i, j]["safe_lo"] == g.lo[k] and json.loads(back.edges[i, j]["safe_set"]) == [[g.lo[k], g.hi[k]]]
    dot = g.to_dot()
    assert dot.startswith('digraph "bvg l_shape"') and dot.count("->") == g.n_arcs and dot.rstrip().endswith("}")
    text = g.to_text(width=80)
    assert text.splitlines()[1].split() == ["segments:", str(g.n_segments), "arcs:", str(g.n_arcs), "safe", "arcs:", str(g.n_safe_arcs)]
    assert all(len(line) <= 80 for line in text.splitlines())


def test_lookup_errors_name_the_segment():
    g = safe_bounce_visibility_graph(SQUARE)
    with pytest.raises(InvalidBoundarySet, match=r"^unknown segment 7: segments are 0\.\.3$"):
        g.safe_set(0, 7)
    with pytest.raises(InvalidBoundarySet, match=r"^unknown segment -1: segments are 0\.\.3$"):
        g.successors(-1)
    assert g.interval(0, 0) is Interval.EMPTY and g.arc_index(0, 0) is None
    with pytest.raises(InputError, match="expected a Partition or an Environment"):
        safe_bounce_visibility_graph("square.json")


# ---------------------------------------------------------------------------------------------
# CLI
# ---------------------------------------------------------------------------------------------
runner = CliRunner()


def test_cli_graph_safe_json():
    result = runner.invoke(cli.app, ["graph", str(MODELS / "two_rooms.json"), "--safe"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    g = safe_bounce_visibility_graph(model("two_rooms"))
    assert data["n_arcs"] == g.n_arcs and data["arcs"][0]["safe_set"] is not None


def test_cli_graph_plain_and_formats(tmp_path):
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json")])
    assert result.exit_code == 0
    assert all(set(arc) == {"from", "to", "transition"} for arc in json.loads(result.stdout)["arcs"])
    out = tmp_path / "g.graphml"
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json"), "--safe", "--format", "graphml", "-o", str(out)])
    assert result.exit_code == 0 and result.stdout == ""
    assert nx.read_graphml(out).number_of_edges() == 12
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json"), "--format", "dot"])
    assert result.exit_code == 0 and result.stdout.startswith("digraph")
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json"), "--safe", "--format", "text"])
    assert result.exit_code == 0 and "safe arcs: 12" in result.stdout


def test_cli_graph_filters_by_segment_and_heading():
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json"), "--safe", "--from", "0", "--heading", "0.5"])
    assert result.exit_code == 0, result.output
    arcs = json.loads(result.stdout)["arcs"]
    assert [(a["from"], a["to"]) for a in arcs] == [(0, 1)]  # bottom side: only (0, π/4] holds 0.5


@pytest.mark.parametrize(
    "args, message",
    [
        (["--from", "9"], "error: unknown segment 9: segments are 0..3"),
        (["--heading", "3.5"], "error: heading 3.5 is not inside (0, π)"),
        (["--heading", "0"], "error: heading 0 is not inside (0, π)"),
    ],
)
def test_cli_graph_bad_input_is_one_line_exit_2(args, message):
    result = runner.invoke(cli.app, ["graph", str(MODELS / "square.json"), "--safe", *args])
    assert result.exit_code == 2
    assert result.stdout == ""
    assert result.stderr.splitlines() == [message]


# ---------------------------------------------------------------------------------------------
# rendering layers
# ---------------------------------------------------------------------------------------------
def test_render_layers_draw_every_pair_once_and_safe_arcs_as_landing_rays(tmp_path):
    from solverplan.render import draw_graph, draw_partition, draw_safe_arcs, render_environment, save_figure

    env = model("two_rooms")
    p = partition(env)
    g = safe_bounce_visibility_graph(p)
    fig = render_environment(env)
    ax = fig.axes[0]
    (lines,) = draw_graph(ax, g)
    assert lines.get_gid() == "bvg-arcs" and len(lines.get_segments()) == g.n_arcs // 2
    (rays,) = draw_safe_arcs(ax, g)
    segments = np.array(rays.get_segments())
    assert rays.get_gid() == "safe-arcs" and len(segments) == g.n_safe_arcs
    # every ray starts at the middle of its source segment and ends on its target segment
    rows = np.flatnonzero(g.safe)
    start, end = np.asarray(p.seg_start), np.asarray(p.seg_end)
    i, j = g.source[rows], g.target[rows]
    assert np.allclose(segments[:, 0], 0.5 * (start[i] + end[i]))
    d = end[j] - start[j]
    w = segments[:, 1] - start[j]
    along = (w * d).sum(axis=1) / (d * d).sum(axis=1)
    off = np.abs(w[:, 0] * d[:, 1] - w[:, 1] * d[:, 0]) / np.hypot(d[:, 0], d[:, 1])
    assert np.all(off < 1e-9) and np.all((along > -1e-9) & (along < 1 + 1e-9))
    draw_partition(ax, p)
    saved = save_figure(fig, tmp_path / "graph.svg")
    svg = (tmp_path / "graph.svg").read_text()
    assert saved.format == "svg" and 'id="bvg-arcs"' in svg and 'id="safe-arcs"' in svg


def test_cli_render_partition_graph(tmp_path):
    out = tmp_path / "g.png"
    result = runner.invoke(cli.app, ["render", str(MODELS / "l_shape.json"), "--partition", "--graph", "--safe-arcs", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["written"] == str(out) and out.stat().st_size > 1000


# ---------------------------------------------------------------------------------------------
# memory and time that follow the output: pruning, chunked JSON, the graph cache, the size check
# ---------------------------------------------------------------------------------------------
from solverplan.bounce import bvg as bvg_api  # noqa: E402
from solverplan.generators import star_polygon, star_polygon_with_holes  # noqa: E402


@pytest.fixture
def no_cache():
    """No graph kept between the calls of a test, none left for the others."""
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(None)
    yield
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(None)
    reset_memory_limit()


def graph_arrays(g: SafeBVG) -> dict[str, np.ndarray]:
    names = ("source", "target", "lo", "hi", "n_intervals", "set_offsets", "set_lo", "set_hi", "transition", "phi")
    out = {k: getattr(g, k) for k in names}
    out.update({f"end{i}": a for i, a in enumerate(g._set_ends)})
    return out


def assert_same_graph(got: SafeBVG, want: SafeBVG) -> None:
    a, b = graph_arrays(got), graph_arrays(want)
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=True), k


@pytest.mark.parametrize(("env", "prunes"), [(star_polygon(60, 0.2, 0.3, seed=3), True),
                                             (star_polygon_with_holes(40, 3, seed=2), True), (model("two_holes"), False)],
                         ids=["star60", "star40+holes", "two_holes"])
def test_occlusion_pruning_changes_no_sweep_entry(monkeypatch, env, prunes):
    """The occluder pruning of the hit search skips tests, never answers: with chunks too wide to
    ever be spanned (no pruning) the sweeps are the same, and pruning did skip tests."""
    p = partition(env)
    pruned = sweep_module.build_sweeps(p)
    ctx = sweep_module.SweepContext(p)
    monkeypatch.setattr(sweep_module, "SweepContext", lambda partition: ctx)
    sweep_module.build_sweeps(p)
    assert (ctx.depth_tested < ctx.depth_pairs) == prunes  # the stars' hidden spikes are skipped
    monkeypatch.setattr(sweep_module, "_CHUNK", 1 << 30)
    ctx.depth_pairs = ctx.depth_tested = 0
    full = sweep_module.build_sweeps(p)
    assert ctx.depth_tested == ctx.depth_pairs  # every (sector, covering edge) pair tested
    for name in ("sweep", "seg", "lo_to", "hi_to", "lo", "hi", "lo_err", "hi_err"):
        assert np.array_equal(getattr(pruned, name), getattr(full, name)), name


def test_json_bytes_are_the_bytes_of_to_json(no_cache):
    import orjson

    g = safe_bounce_visibility_graph(star_polygon_with_holes(12, 4, hole_kind="star", hole_vertices=6, hole_radius=0.06, seed=3))
    assert (g.n_intervals > 1).any()  # unions of intervals are in the answer
    for view in (g, g.select(safe=False), g.select(source=3)):
        want = orjson.dumps(view.to_json())
        assert bytes(view.json_bytes(arcs_per_chunk=7)) == want
        assert bytes(view.json_bytes(end=b"\n")) == want + b"\n"
        for safe in (True, False):  # the columnar encoder against the dicts, one arc per chunk too
            want = orjson.dumps(view.to_json(safe=safe))
            assert bytes(view.json_bytes(safe=safe, arcs_per_chunk=1)) == want
            assert bytes(view.json_bytes(safe=safe, arcs_per_chunk=1000)) == want
    empty = g.select(source=0, heading=3.1)
    assert bytes(empty.json_bytes()) == orjson.dumps(empty.to_json())


def test_memory_cache_reuses_the_graph_for_equal_rings(no_cache):
    env = star_polygon(30, 0.2, 0.3, seed=5)
    first = safe_bounce_visibility_graph(env)
    again = safe_bounce_visibility_graph(env)
    assert again is first
    with pytest.raises(ValueError):  # shared arrays are read-only
        first.lo[0] = 0.0
    renamed = Environment.from_coords([[float(x), float(y)] for x, y in env.outer], name="renamed")
    other = safe_bounce_visibility_graph(renamed)  # same rings, another name: the same arrays, its own name
    assert other.partition.env is renamed and other.to_json()["name"] == "renamed"
    assert other.lo is first.lo
    p = partition(env)
    mine = safe_bounce_visibility_graph(p)  # an equal partition: answered for that partition object
    assert mine.partition is p and mine.source is first.source


def test_disk_cache_round_trip(no_cache, tmp_path):
    """A graph read back from disk is the graph built (tampering and its misses: tests/bounce/test_cache.py)."""
    env = star_polygon(25, 0.2, 0.3, seed=7)
    bvg_api.set_graph_cache(tmp_path, min_arcs=0)
    built = safe_bounce_visibility_graph(env)
    (entry,) = tmp_path.glob("*.spg")
    assert not list(tmp_path.glob(".*.tmp"))  # written atomically, nothing left behind
    bvg_api.clear_graph_cache()
    read = safe_bounce_visibility_graph(env)
    assert read.stats.get("cached") is True and read is not built
    assert_same_graph(read, built)
    assert read.to_json() == built.to_json()
    with pytest.raises(ValueError):  # read-only, like every shared graph
        read.lo[0] = 0.0


def test_size_estimate_and_refusal_up_front(no_cache):
    env = star_polygon(80, 0.2, 0.3, seed=1)
    p = partition(env)
    arcs, need = bvg_api.estimate_graph(p)
    g = safe_bounce_visibility_graph(p)
    assert abs(arcs - g.n_arcs) <= 0.1 * g.n_arcs
    assert need > bvg_api.BYTES_PER_ARC * arcs
    bvg_api.clear_graph_cache()
    set_memory_limit(bvg_api.BASE_BYTES + (need - bvg_api.BASE_BYTES) // 2)  # half the graph's own bytes fit
    with pytest.raises(bvg_api.GraphTooLarge, match=r"would need ≈ .* arcs, 629 segments\), more than the memory limit") as info:
        safe_bounce_visibility_graph(p)
    assert "\n" not in str(info.value) and len(str(info.value)) < 200
    # the refusal names the simplification that would fit, and that simplification leaves the vertices it says
    hint = re.search(r"--simplify ([0-9.e-]+) at import would fit \(≈ ([0-9,]+) vertices\)", str(info.value))
    assert hint is not None, str(info.value)
    import shapely
    simple = shapely.simplify(env.to_shapely(), float(hint[1]), preserve_topology=True)
    assert len(simple.exterior.coords) - 1 == int(hint[2].replace(",", "")) < env.n_vertices
    set_memory_limit(need * 2)
    assert safe_bounce_visibility_graph(p).n_arcs == g.n_arcs
    with pytest.raises(InputError, match="positive number of bytes"):
        set_memory_limit(0)


def test_cli_max_memory_refuses_in_one_line_and_graph_cache_option(tmp_path):
    runner = CliRunner()
    src = tmp_path / "star.json"
    src.write_text(json.dumps(star_polygon(80, 0.2, 0.3, seed=1).to_dict()))
    out = tmp_path / "g.json"
    r = runner.invoke(cli.app, ["--graph-cache", "off", "--max-memory", "1M", "graph", str(src), "--safe", "-o", str(out)])
    assert r.exit_code == 2 and not out.exists()
    assert r.stderr.count("\n") == 1 and "would need ≈" in r.stderr and "1 MB" in r.stderr
    r = runner.invoke(cli.app, ["--max-memory", "lots", "graph", str(src)])
    assert r.exit_code == 2 and "--max-memory" in r.stderr
    cache = tmp_path / "cache"
    r1 = runner.invoke(cli.app, ["--graph-cache", str(cache), "graph", str(src), "--safe", "-o", str(out)])
    assert r1.exit_code == 0, r1.stderr
    bvg_api.clear_graph_cache()
    bvg_api.set_graph_cache(None)
    assert bvg_api.graph_cache_directory() is None  # the option lasted one command line
    plain = runner.invoke(cli.app, ["--graph-cache", "off", "--compact", "graph", str(src), "--safe"])
    assert plain.exit_code == 0 and out.read_text() == plain.stdout  # the chunked encoder wrote the same bytes


def test_point_vectors_are_accurate_far_from_zero():
    """Differences of P′ points 1e12 from 0 (rounded there to 1.2e-4) are accurate to rounding of the
    difference itself, and the plain path is the float difference where that is already accurate."""
    from fractions import Fraction as F

    from solverplan.bounce.partitions import partition

    off = 10**12
    env = Environment.from_coords([[off, off], [off + 10, off], [off + F(10, 3), off + F(1, 7)]])
    p = partition(env)
    frm, to = np.array([0, 1, 2]), np.array([1, 2, 0])
    exact = [(float(p.segments[t].a[0] - p.segments[f].a[0]), float(p.segments[t].a[1] - p.segments[f].a[1]))
             for f, t in zip(frm, to)]
    np.testing.assert_allclose(p.point_vectors(frm, to), exact, rtol=1e-15, atol=0)
    near = partition(Environment.from_coords([[0, 0], [10, 0], [F(10, 3), F(1, 7)]]))
    assert np.array_equal(near.point_vectors(frm, to), near.seg_start[to] - near.seg_start[frm])


def test_translated_star_keeps_arcs_and_float_angles():
    """A random star moved by 1e12: the same arcs and every float answer within 1e-12 of the untranslated one."""
    from solverplan.generators import star_polygon

    base = star_polygon(12, 0.2, 0.3, seed=3)
    moved = Environment.from_coords([[x + 10**12, y - 10**12] for x, y in base.outer])
    a, b = safe_bounce_visibility_graph(base), safe_bounce_visibility_graph(moved)
    assert np.array_equal(a.source, b.source) and np.array_equal(a.target, b.target)
    assert np.array_equal(a.set_offsets, b.set_offsets)
    for x, y in [(a.set_lo, b.set_lo), (a.set_hi, b.set_hi), (a.phi, b.phi)]:
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-12)
