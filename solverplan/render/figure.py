"""Figures and their output: the Agg figure sized to an environment, the palette, PNG/SVG bytes and files.

Figures are built on the Agg canvas without pyplot, so no window opens, no global figure list grows, and
nothing depends on the user's matplotlib backend. Every layer module draws into an Axes made by
:func:`new_figure` and takes its colours from the palette here, so one picture reads as one style.

>>> figure_format("plan.SVG")
'svg'
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, cast

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Annotation

from solverplan._io import atomic_write_bytes, cannot_write
from solverplan.environment import Environment
from solverplan.errors import InputError

__all__ = ["FigureFormat", "new_figure", "figure_format", "figure_bytes", "SavedFigure", "save_figure"]

FigureFormat = Literal["png", "svg"]
_FORMATS: dict[str, FigureFormat] = {".png": "png", ".svg": "svg"}

# Palette: light free space, dark walls, hole interiors left white; ids in muted colours.
FREE_SPACE_COLOR = "#e8f0f8"
BOUNDARY_COLOR = "#1f2a36"
EDGE_ID_COLOR = "#1a5fa8"
VERTEX_ID_COLOR = "#5a5a5a"
REFLEX_COLOR = "#d1495b"
PARTITION_COLORS = ("#e07a1f", "#2a9d8f", "#7b5ea7")  # alternate along each ring; the third closes odd rings
INSERTED_COLOR = "#1f2a36"
GRAPH_COLOR = "#6b7b8c"  # the BVG's arcs: light grey-blue lines under everything else
SAFE_ARC_COLOR = "#2c7fb8"  # safe arcs: rays that really land, a little stronger
TRAJECTORY_COLOR = "#d95f02"  # warm, against the pale free space and the dark walls
TRAJECTORY_START_COLOR = "#1b7837"
TRAJECTORY_FLAG_COLOR = "#b2182b"
CYCLE_COLOR = "#08306b"  # a limit cycle: bold dark blue over the warm trajectories
CYCLE_POINT_COLOR = "#ffd92f"  # its contact points: yellow circles, as in the paper's Fig. 9
PLAN_STAGE_COLORS = ("#1b9e77", "#d95f02", "#7570b3", "#1f78b4", "#66a61e", "#e6ab02", "#a6761d", "#17becf")
PLAN_START_COLOR = "#1b7837"  # the start set: green, like the trajectories' start dots
PLAN_GOAL_COLOR = "#c51b7d"  # the goal set: magenta, distinct from every stage colour
PATROL_EDGE_COLOR = "#7b3294"  # the edges a patrol must visit
CONE_COLOR = "#2c7fb8"  # the heading interval of a stage, as a fan of rays
FUNNEL_START_COLOR = "#1b7837"
FUNNEL_GOAL_COLOR = "#b2182b"
HEATMAP_CMAP = "viridis"

PNG_DPI = 150
ARROW_SIZE = 14.0  # points: the arrowheads showing edge directions


def new_figure(env: Environment, *, width: float | None = None, title: str | None = None) -> tuple[Figure, Axes]:
    """A fresh figure with one Axes sized to ``env``'s aspect ratio (height clamped).

    ``width`` is in inches; by default 7, growing with the number of edges and for long thin
    environments (up to 16) so that labels keep room. The figure is attached to an Agg canvas (no screen needed) and is not
    registered with pyplot.
    """
    if width is None:
        width = float(np.clip(7.0 * np.sqrt(env.n_edges / 30), 7.0, 16.0))
    xmin, ymin, xmax, ymax = env.bounds
    span_x, span_y = max(xmax - xmin, 1e-12), max(ymax - ymin, 1e-12)
    if span_x > 3 * span_y:  # long and thin (hallways): wider, so the labels fit across
        width = float(min(16.0, width * np.sqrt(span_x / (3 * span_y))))
    height = min(max(width * span_y / span_x, 3.0), width * 10 / 7)
    if span_y > span_x:  # tall environments: keep the height, narrow the figure
        width = min(max(height * span_x / span_y, 3.0), width)
    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    _style_axes(ax, title)
    return fig, ax


def _figure_of(ax: Axes) -> Figure:
    """The figure holding ``ax`` (the figures here are never sub-figures)."""
    return cast(Figure, ax.get_figure())


def _style_axes(ax: Axes, title: str | None) -> None:
    ax.set_aspect("equal", adjustable="box")
    ax.tick_params(labelsize=7, colors="#777777")
    for spine in ax.spines.values():
        spine.set_color("#cccccc")
    if title:
        ax.set_title(title, fontsize=11)


def _arrow(ax: Axes, at: np.ndarray, direction: np.ndarray, *, color: str, size: float, gid: str) -> Annotation:
    """An arrowhead of ``size`` points with its tip at ``at`` (data coordinates), pointing along the unit ``direction``."""
    tail = (-float(direction[0]) * size, -float(direction[1]) * size)
    arrow = ax.annotate(
        "",
        xy=(float(at[0]), float(at[1])),
        xytext=tail,
        textcoords="offset points",
        arrowprops=dict(
            arrowstyle="-|>,head_length=0.5,head_width=0.22",
            color=color,
            lw=0,
            shrinkA=0,
            shrinkB=0,
            mutation_scale=size,
        ),
        zorder=3,
        annotation_clip=False,
    )
    arrow.set_gid(gid)
    return arrow


def _ink_alpha(
    ax: Axes, env: Environment, segments: np.ndarray, linewidth: float, coverage_goal: float, *,
    lo: float = 0.01, hi: float = 0.6,
) -> float:
    """Opacity (clipped to [lo, hi]) so that the ink of all lines, spread evenly, would cover ``coverage_goal``
    of the free space: a few lines stay clearly visible, dense ones do not saturate, and where many lines agree
    (a limit cycle) the picture still darkens. ``segments`` is (m, 2, 2) in data units, ``linewidth`` in points."""
    if len(segments) == 0:
        return 0.8
    ax.apply_aspect()
    x0, x1 = ax.get_xlim()
    width_points = ax.get_position().width * _figure_of(ax).get_figwidth() * 72.0
    line_width = linewidth / (width_points / abs(x1 - x0))  # in data units
    ink = float(np.hypot(*(segments[:, 1] - segments[:, 0]).T).sum()) * line_width
    coverage = ink / max(float(env.area), 1e-300)
    return float(np.clip(coverage_goal / max(coverage, 1e-12), lo, hi))


def _piece_lines(env: Environment, pieces) -> np.ndarray:
    """Boundary pieces (anything with ``edge``, ``t0``, ``t1``; exact or float) as (m, 2, 2) line segments."""
    edges = np.array([int(p.edge) for p in pieces], dtype=np.int64)
    a = env.points_at(edges, np.array([float(p.t0) for p in pieces]))
    b = env.points_at(edges, np.array([float(p.t1) for p in pieces]))
    return np.stack([a, b], axis=1).reshape(-1, 2, 2)


def figure_format(path: str | os.PathLike[str]) -> FigureFormat:
    """The picture format for ``path``, from its extension (``.png`` or ``.svg``).

    >>> figure_format("plan.SVG")
    'svg'
    >>> figure_format("plan.pdf")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: plan.pdf: unknown picture format '.pdf': use a .png or .svg file name
    """
    suffix = Path(path).suffix.lower()
    try:
        return _FORMATS[suffix]
    except KeyError:
        shown = repr(suffix) if suffix else "(no extension)"
        raise InputError(f"{path}: unknown picture format {shown}: use a .png or .svg file name") from None


def figure_bytes(fig: Figure, fmt: FigureFormat) -> bytes:
    """Render ``fig`` in memory as PNG or SVG bytes (reproducible: no dates or random ids in SVG)."""
    from matplotlib import rc_context

    buffer = io.BytesIO()
    metadata = {"Date": None} if fmt == "svg" else {"Software": None}
    with rc_context({"svg.hashsalt": "solverplan", "svg.fonttype": "none"}):
        fig.savefig(buffer, format=fmt, dpi=PNG_DPI, bbox_inches="tight", pad_inches=0.1, metadata=metadata)
    return buffer.getvalue()


@dataclass(frozen=True, slots=True)
class SavedFigure:
    """What :func:`save_figure` wrote: the file, its format and its size in bytes."""

    path: Path
    format: FigureFormat
    size: int

    def to_json(self) -> dict:
        return {"written": str(self.path), "format": self.format, "bytes": self.size}

    def to_text(self, *, width: int = 100) -> str:
        return f"wrote {self.path} ({self.format.upper()}, {self.size} bytes)\n"


def save_figure(fig: Figure, path: str | os.PathLike[str]) -> SavedFigure:
    """Write ``fig`` to ``path`` atomically, as PNG or SVG by the extension.

    The picture is rendered in memory first, so a failure leaves no partial file behind.

    Raises
    ------
    InputError
        For an extension other than ``.png`` / ``.svg``, or a path that cannot be written
        (missing folder, no permission); nothing is written.
    """
    fmt = figure_format(path)
    data = figure_bytes(fig, fmt)
    try:
        atomic_write_bytes(path, data)
    except OSError as exc:
        raise InputError(cannot_write(path, exc)) from None
    return SavedFigure(Path(path), fmt, len(data))
