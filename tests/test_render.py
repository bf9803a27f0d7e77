"""render.py: the environment layers, label placement, and PNG/SVG output."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import shapely
from matplotlib.figure import Figure

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.render import (
    draw_edge_directions,
    figure_bytes,
    figure_format,
    new_figure,
    render_environment,
    save_figure,
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
