"""solverplan.render: the environment layers, label placement, PNG/SVG output, and whole scenes."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import shapely
from matplotlib.figure import Figure

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.render import (
    answer_title,
    draw_edge_directions,
    figure_bytes,
    figure_format,
    new_figure,
    plan_title,
    render_answer,
    render_environment,
    save_figure,
    scene,
)

PILLAR = Environment.from_coords(
    [[0, 0], [10, 0], [10, 6], [6, 6], [6, 4], [0, 4]], [[[2, 1], [4, 1], [4, 2.5], [2, 2.5]]], name="pillar"
)
STAR = Environment.from_coords(
    [
        [round(r * math.cos(math.pi * k / 8), 3), round(r * math.sin(math.pi * k / 8), 3)]
        for k, r in zip(range(16), [10, 5] * 8)
    ],
    [[[-1, -1], [1.5, -0.5], [0, 1.5]]],
    name="star",
)


def by_gid(artists, prefix: str) -> list:
    return [a for a in artists if (a.get_gid() or "").startswith(prefix)]


def test_plain_render_has_free_space_boundary_and_reflex_marks():
    fig = render_environment(PILLAR)
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    assert ax.get_title() == "pillar"
    assert ax.get_aspect() == 1.0
    (boundary,) = by_gid(ax.collections, "boundary")
    assert len(boundary.get_segments()) == PILLAR.n_edges
    (reflex,) = by_gid(ax.collections, "reflex-vertices")
    assert sorted(map(tuple, reflex.get_offsets().tolist())) == sorted(
        map(tuple, PILLAR.vertices[list(PILLAR.reflex_vertices)].tolist())
    )
    assert by_gid(ax.texts, "edge-id-") == [] and by_gid(ax.texts, "vertex-id-") == []


def test_free_space_is_filled_with_the_hole_cut_out():
    fig = render_environment(PILLAR, reflex=False)
    ax = fig.axes[0]
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba())

    def colour(x: float, y: float) -> tuple[int, ...]:
        px, py = ax.transData.transform((x, y))
        return tuple(pixels[pixels.shape[0] - 1 - int(round(py)), int(round(px)), :3])

    free = colour(1, 1)
    assert free != (255, 255, 255)
    assert colour(8, 5) == free
    assert colour(3, 1.75) == (255, 255, 255)  # inside the pillar
    assert colour(3, 5) == (255, 255, 255)  # outside the L


def test_without_reflex_marks():
    fig = render_environment(PILLAR, reflex=False)
    assert by_gid(fig.axes[0].collections, "reflex-vertices") == []


@pytest.mark.parametrize("env", [PILLAR, STAR], ids=["pillar", "star"])
def test_one_edge_label_and_arrow_per_edge_one_vertex_label_per_vertex(env):
    fig = render_environment(env, edge_ids=True, vertex_ids=True)
    ax = fig.axes[0]
    edge_labels = by_gid(ax.texts, "edge-id-")
    assert [t.get_text() for t in edge_labels] == [f"e{i}" for i in range(env.n_edges)]
    arrows = by_gid(ax.texts, "edge-arrow-")
    assert len(arrows) == env.n_edges
    vertex_labels = by_gid(ax.texts, "vertex-id-")
    assert [t.get_text() for t in vertex_labels] == [f"v{i}" for i in range(env.n_vertices)]


def _display_boxes(fig, texts):
    renderer = fig.canvas.get_renderer()
    return [t.get_window_extent(renderer) for t in texts]


@pytest.mark.parametrize("env", [PILLAR, STAR], ids=["pillar", "star"])
def test_edge_labels_sit_in_the_free_space_clear_of_the_boundary_and_of_each_other(env):
    fig = render_environment(env, edge_ids=True, vertex_ids=True)
    ax = fig.axes[0]
    fig.canvas.draw()
    to_data = ax.transData.inverted()
    free = env.to_shapely()
    edges_display = ax.transData.transform(np.stack([env.edge_start, env.edge_end], axis=1).reshape(-1, 2))
    edges_display = shapely.linestrings(edges_display.reshape(-1, 2, 2))
    labels = by_gid(ax.texts, "edge-id-") + by_gid(ax.texts, "vertex-id-")
    boxes = [shapely.box(b.x0, b.y0, b.x1, b.y1) for b in _display_boxes(fig, labels)]
    for label, box in zip(labels, boxes):
        assert not shapely.intersects(box, edges_display).any(), f"{label.get_text()} overlaps the boundary"
    for i, box in enumerate(boxes):
        others = boxes[:i] + boxes[i + 1 :]
        assert not shapely.intersects(box, np.array(others)).any(), f"{labels[i].get_text()} overlaps a label"
    n = env.n_edges
    for label, box in zip(labels[:n], boxes[:n]):
        centre = to_data.transform(np.array(box.centroid.coords[0]))
        assert free.contains(shapely.Point(centre)), f"{label.get_text()} is outside the free space"


def test_edge_arrows_point_along_their_edges():
    fig, ax = new_figure(PILLAR)
    arrows = draw_edge_directions(ax, PILLAR, t=np.full(PILLAR.n_edges, 0.5))
    for i, arrow in enumerate(arrows):
        tip = np.array(arrow.xy)
        np.testing.assert_allclose(tip, (PILLAR.edge_start[i] + PILLAR.edge_end[i]) / 2)
        tail_offset = np.array(arrow.xyann)  # points, behind the tip
        direction = PILLAR.edge_end[i] - PILLAR.edge_start[i]
        assert np.dot(-tail_offset, direction) > 0
        cross = tail_offset[0] * direction[1] - tail_offset[1] * direction[0]
        assert abs(cross) < 1e-9 * np.linalg.norm(direction) * np.linalg.norm(tail_offset)


def test_render_into_given_axes():
    fig, ax = new_figure(PILLAR, title="mine")
    assert render_environment(PILLAR, ax=ax, edge_ids=True) is fig
    assert ax.get_title() == "mine"
    assert len(by_gid(ax.texts, "edge-id-")) == PILLAR.n_edges


def test_save_png_and_svg(tmp_path):
    fig = render_environment(PILLAR, edge_ids=True)
    png = save_figure(fig, tmp_path / "p.png")
    data = (tmp_path / "p.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert (png.format, png.size) == ("png", len(data))
    svg = save_figure(fig, tmp_path / "p.SVG")
    text = (tmp_path / "p.SVG").read_text()
    assert svg.format == "svg" and "<svg" in text and 'id="edge-id-3"' in text
    assert svg.to_json() == {"written": str(tmp_path / "p.SVG"), "format": "svg", "bytes": len(text.encode())}


def test_svg_output_is_reproducible():
    first = figure_bytes(render_environment(STAR, edge_ids=True), "svg")
    second = figure_bytes(render_environment(STAR, edge_ids=True), "svg")
    assert first == second


@pytest.mark.parametrize(
    "name, message",
    [
        ("p.pdf", "p.pdf: unknown picture format '.pdf': use a .png or .svg file name"),
        ("p", "p: unknown picture format (no extension): use a .png or .svg file name"),
    ],
)
def test_unknown_picture_format_is_input_error_and_writes_nothing(tmp_path, name, message):
    with pytest.raises(InputError, match=f"^{re.escape(message)}$"):
        figure_format(name)
    fig = render_environment(PILLAR)
    with pytest.raises(InputError):
        save_figure(fig, tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_unwritable_path_is_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot write"):
        save_figure(render_environment(PILLAR), tmp_path / "missing" / "p.png")


# ---------------------------------------------------------------------------------------------
# scene(): whole pictures, as `solverplan render` draws them
# ---------------------------------------------------------------------------------------------
BOX = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")


def gids(fig) -> set[str]:
    return {a.get_gid() for a in fig.axes[0].get_children() if a.get_gid()}


def test_scene_of_a_bare_environment_draws_only_the_environment_layers():
    fig = scene(PILLAR)
    ax = fig.axes[0]
    assert ax.get_title() == "pillar"
    assert {"free-space", "boundary", "reflex-vertices"} <= gids(fig)
    assert not any(g.startswith(("partition", "bvg", "safe-arcs", "plan-", "trajector", "limit-cycle", "edge-id"))
                   for g in gids(fig))
    assert scene(PILLAR, reflex=False, title="mine").axes[0].get_title() == "mine"
    assert "reflex-vertices" not in gids(scene(PILLAR, reflex=False))


def test_scene_stacks_graph_and_safe_arcs_under_the_partition():
    from solverplan.bounce.partitions import partition

    fig = scene(PILLAR, partition=True, graph=True, safe_arcs=True, edge_ids=True)
    ax = fig.axes[0]
    (arcs,) = by_gid(ax.collections, "bvg-arcs")
    (safe,) = by_gid(ax.collections, "safe-arcs")
    (segments,) = by_gid(ax.collections, "partition-segments")
    assert arcs.get_zorder() < safe.get_zorder() < segments.get_zorder()
    n = partition(PILLAR).n_segments
    assert len(segments.get_segments()) == n and len(by_gid(ax.texts, "segment-id-")) == n
    assert len(by_gid(ax.texts, "edge-id-")) == PILLAR.n_edges


def test_scene_of_a_plan_draws_its_cones_on_the_target_segments_and_its_rollouts():
    from solverplan.bounce.partitions import partition
    from solverplan.bounce.transitions import transition_set
    from solverplan.plan import find_plan

    plan = find_plan(PILLAR, "e0", "e3")
    assert plan.found
    fig = scene(PILLAR, plan=plan, trajectories=20, seed=2)
    ax = fig.axes[0]
    assert ax.get_title() == plan_title(plan)
    assert {"plan-start", "plan-goal", "plan-legend", "trajectories"} <= gids(fig)
    (paths,) = by_gid(ax.collections, "trajectories")
    assert len(paths.get_segments()) == 20 * plan.bounces
    p = partition(PILLAR)
    free = PILLAR.to_shapely().buffer(1e-9)
    for k, stage in enumerate(plan.stages):
        assert len(by_gid(ax.collections, f"plan-targets-{k}")) == 1
        for i, j in stage.moves:
            (cone,) = by_gid(ax.patches, f"plan-cone-{k}-{i}")
            polygon = shapely.Polygon(cone.get_xy())
            # the swept region lies in the free space, holds the source segment and reaches the target segment
            assert free.contains(polygon)
            source = shapely.LineString([p.seg_start[i], p.seg_end[i]])
            target = shapely.LineString([p.seg_start[j], p.seg_end[j]])
            assert polygon.buffer(1e-9).contains(source)
            assert polygon.intersection(target.buffer(1e-9)).area > 0
            # and it holds the exact landing set of the move: every point the stage's rays reach
            segment = p.segments[i]
            for piece in transition_set(PILLAR, (segment.edge, segment.t0, segment.t1), stage.interval):
                ends = PILLAR.points_at(np.array([piece.edge] * 2), np.array([float(piece.t0), float(piece.t1)]))
                assert polygon.buffer(1e-6).contains(shapely.LineString(ends))


def test_scene_of_a_cycle_draws_the_cycle_over_rollouts_of_its_constant_heading():
    fig = scene(BOX, cycle="tan:1/3", trajectories=4, seed=0)
    ax = fig.axes[0]
    assert ax.get_title().startswith("box: constant heading θ = 0.3218, limit cycle e0 → e1 → e2 → e3 → e0")
    (line,) = by_gid(ax.lines, "limit-cycle")
    assert len(line.get_xydata()) == 5  # four contacts, closed
    assert len(by_gid(ax.texts, "limit-cycle-arrow-")) == 4
    (paths,) = by_gid(ax.collections, "trajectories")
    assert len(paths.get_segments()) == 4 * 20  # the default 20 bounces per rollout
    assert line.get_zorder() > paths.get_zorder()


def test_scene_of_a_funnel_answer_has_its_title_and_swept_regions_holding_the_positions():
    from solverplan.plan.funnels import funnel

    answer = funnel(BOX, "e0", "e2:0.4:0.6")
    assert answer.found
    fig = scene(BOX, answer=answer)
    ax = fig.axes[0]
    assert ax.get_title() == answer_title(answer) and ax.get_title().startswith("box: funnel e0 → e2:0.4:0.6\n")
    assert {"funnel-start", "funnel-goal"} <= gids(fig)
    for k, stage in enumerate(answer.stages):
        regions = shapely.union_all([shapely.Polygon(patch.get_xy()) for patch in by_gid(ax.patches, f"funnel-swept-{k}")])
        for piece in stage.positions:  # the positions after a stage are where its rays land: on the regions' rims
            a, b = BOX.points_at(np.array([piece.edge] * 2), np.array([float(piece.t0), float(piece.t1)]))
            assert regions.buffer(1e-6).contains(shapely.LineString([a, b]))


def test_scene_draws_what_render_answer_draws():
    from solverplan.plan.funnels import funnel

    answer = funnel(BOX, "e0", "e2:0.4:0.6")
    assert figure_bytes(scene(BOX, answer=answer, edge_ids=True), "svg") == figure_bytes(render_answer(answer), "svg")


@pytest.mark.parametrize(
    "options, message",
    [
        ({"rule": "bouncy"}, "unknown bounce rule 'bouncy'"),
        ({"start": "e9"}, "e9"),
        ({"plan": "PLAN", "cycle": 0.3}, "a plan draws its own trajectories"),
        ({"plan": "PLAN", "start": "e0"}, "a plan draws its own trajectories"),
        ({"cycle": 0.3, "answer": object()}, "either a limit cycle or an answer"),
    ],
)
def test_scene_rejects_bad_or_conflicting_options(options, message):
    from solverplan.plan import find_plan

    if options.get("plan") == "PLAN":
        options = {**options, "plan": find_plan(BOX, "e0", "e2")}
    with pytest.raises(InputError, match=re.escape(message)):
        scene(BOX, **options)


def test_scene_rejects_a_plan_made_in_another_environment():
    from solverplan.plan import find_plan

    with pytest.raises(InputError, match="another environment"):
        scene(PILLAR, plan=find_plan(BOX, "e0", "e2"))


def test_cli_render_writes_the_scene(tmp_path):
    from typer.testing import CliRunner

    from solverplan import cli

    out = tmp_path / "cycle.svg"
    model = tmp_path / "box.json"
    model.write_text('{"name": "box", "outer": [[0, 0], [4, 0], [4, 3], [0, 3]]}')
    result = CliRunner().invoke(cli.app, ["render", str(model), "--cycle", "--theta", "tan:1/3", "--trajectories", "4",
                                          "--edge-ids", "-o", str(out)])
    assert result.exit_code == 0, result.output
    env = load_environment(model)
    expected = figure_bytes(scene(env, cycle="tan:1/3", trajectories=4, edge_ids=True), "svg")
    assert out.read_bytes() == expected


def test_render_package_exports_every_public_name_and_no_name_hides_a_submodule():
    import pkgutil

    import solverplan.render as render

    submodules = {m.name for m in pkgutil.iter_modules(render.__path__)}
    assert {"figure", "labels", "environment", "partition", "graph", "trajectories", "cycles", "plans", "answers",
            "heatmaps", "scenes"} <= submodules
    assert not submodules & set(render.__all__)
    for name in submodules - {"_swept"}:
        module = __import__(f"solverplan.render.{name}", fromlist=["__all__"])
        assert set(module.__all__) <= set(render.__all__), name
        assert all(getattr(render, n) is getattr(module, n) for n in module.__all__)
