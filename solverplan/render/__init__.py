"""Pictures: environments, partitions, graphs, trajectories, cycles, plans, answers and study heatmaps.

All plotting in solverplan lives in this package, one module per layer: :mod:`~solverplan.render.figure`
(figures, palette, PNG/SVG output), :mod:`~solverplan.render.labels` (label placement, edge and vertex
ids), :mod:`~solverplan.render.environment`, :mod:`~solverplan.render.partition`,
:mod:`~solverplan.render.graph`, :mod:`~solverplan.render.trajectories`, :mod:`~solverplan.render.cycles`,
:mod:`~solverplan.render.plans`, :mod:`~solverplan.render.answers`, :mod:`~solverplan.render.heatmaps`,
:mod:`~solverplan.render.rooms` (rooms and doors of rectilinear polygons), :mod:`~solverplan.render.explore`
(explorations with discrete views), :mod:`~solverplan.render.fields` (convex cells, composed fields and reflection
trajectories), :mod:`~solverplan.render.wallfollow` (the wall-following robot's cuts and cut
diagram, pursuit plans),
and :mod:`~solverplan.render.scenes`, whose :func:`scene` stacks the layers into a whole picture (what
``solverplan render`` draws). :mod:`~solverplan.render.report` writes self-contained HTML reports of answers (inline
SVG with hover details; ``solverplan report``). Each ``draw_*`` layer takes an Axes and returns the artists it added; every
artist has a ``gid`` that becomes its ``id`` in SVG output.

>>> from solverplan.environment import Environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
>>> fig = scene(env, partition=True, edge_ids=True)
>>> fig.axes[0].get_title(), len([t for t in fig.axes[0].texts if t.get_gid().startswith("edge-id-")])
('box', 4)
"""

from solverplan.render.answers import answer_title, draw_answer, draw_patrol, draw_position_sets, render_answer
from solverplan.render.cycles import draw_cycle
from solverplan.render.environment import (
    draw_boundary,
    draw_edge_directions,
    draw_free_space,
    draw_reflex_vertices,
    render_environment,
)
from solverplan.render.explore import render_exploration
from solverplan.render.floorplan import FEATURE_STYLES, render_import
from solverplan.render.fields import SCENARIO_COLORS, draw_cell_fields, draw_cells, render_fields
from solverplan.render.figure import FigureFormat, SavedFigure, figure_bytes, figure_format, new_figure, save_figure
from solverplan.render.graph import draw_graph, draw_safe_arcs
from solverplan.render.heatmaps import draw_heatmap, render_heatmaps
from solverplan.render.report import (ANSWER_KINDS, REPORT_OPTIONS, AnswerFile, HtmlReport, SavedReport,
                                      detect_answer_kind, html_report, load_answer, make_report, report_environment,
                                      write_report)
from solverplan.render.labels import LabelPlacer, draw_edge_ids, draw_vertex_ids
from solverplan.render.partition import draw_partition
from solverplan.render.plans import draw_plan, plan_title
from solverplan.render.rooms import (ROOM_COLORS, RULE_COLORS, draw_doors, draw_room_paths, draw_room_tree, draw_rooms,
                                     render_rooms)
from solverplan.render.scenes import scene
from solverplan.render.trajectories import draw_trajectories
from solverplan.render.wallfollow import (CUT_COLORS, SHADOW_COLORS, draw_cut_diagram, draw_cuts, render_cuts,
                                          render_pursuit)

__all__ = [
    "render_import",
    "FEATURE_STYLES",
    "render_exploration",
    "render_fields",
    "draw_cells",
    "draw_cell_fields",
    "SCENARIO_COLORS",
    "FigureFormat",
    "new_figure",
    "draw_free_space",
    "draw_boundary",
    "draw_edge_directions",
    "draw_edge_ids",
    "draw_vertex_ids",
    "LabelPlacer",
    "draw_reflex_vertices",
    "draw_partition",
    "draw_graph",
    "draw_safe_arcs",
    "draw_trajectories",
    "draw_cycle",
    "draw_plan",
    "plan_title",
    "draw_patrol",
    "draw_position_sets",
    "draw_answer",
    "answer_title",
    "render_answer",
    "render_environment",
    "scene",
    "figure_format",
    "figure_bytes",
    "save_figure",
    "SavedFigure",
    "draw_heatmap",
    "render_heatmaps",
    "ROOM_COLORS",
    "RULE_COLORS",
    "draw_rooms",
    "draw_doors",
    "draw_room_paths",
    "draw_room_tree",
    "render_rooms",
    "CUT_COLORS",
    "draw_cuts",
    "draw_cut_diagram",
    "render_cuts",
    "ANSWER_KINDS",
    "REPORT_OPTIONS",
    "AnswerFile",
    "HtmlReport",
    "SavedReport",
    "detect_answer_kind",
    "html_report",
    "load_answer",
    "write_report",
    "make_report",
    "report_environment",
    "SHADOW_COLORS",
    "render_pursuit",
]
