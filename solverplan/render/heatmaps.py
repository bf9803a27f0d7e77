"""Study heatmaps (paper Figs. 15–16): one panel per table of means, panels of one value on one colour scale.

>>> from types import SimpleNamespace
>>> panel = SimpleNamespace(title="reachability", value="unreached", x_name="n", x_values=[10, 20],
...                         y_name="spikiness", y_values=[0.2, 0.5], mean=[[0.1, 0.2], [0.3, float("nan")]],
...                         count=[[2, 2], [2, 0]])
>>> fig = render_heatmaps([panel])
>>> sorted(t.get_text() for t in fig.axes[0].texts)
['0.1', '0.2', '0.3']
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from solverplan.errors import InputError
from solverplan.render.figure import HEATMAP_CMAP

__all__ = ["draw_heatmap", "render_heatmaps"]


def draw_heatmap(
    ax: Axes,
    heatmap,
    *,
    cmap: str = HEATMAP_CMAP,
    vmin: float | None = None,
    vmax: float | None = None,
    annotate: bool = True,
):
    """Draw one study heatmap (paper Figs. 15–16): a cell per (x, y) coloured by its mean, annotated.

    ``heatmap`` is a :class:`solverplan.studies.study.Heatmap` (any object with ``title``, ``x_name``,
    ``x_values``, ``y_name``, ``y_values``, ``mean`` (rows = y, columns = x, NaN = no rows) and
    ``count``). y grows upwards. Returns the :class:`~matplotlib.image.AxesImage` (gid ``heatmap``).
    """
    mean = np.asarray(heatmap.mean, dtype=float)
    finite = mean[np.isfinite(mean)]
    lo = vmin if vmin is not None else (float(finite.min()) if finite.size else 0.0)
    hi = vmax if vmax is not None else (float(finite.max()) if finite.size else 1.0)
    if hi <= lo:
        hi = lo + (abs(lo) * 0.01 or 1.0)
    image = ax.imshow(mean, origin="lower", cmap=cmap, vmin=lo, vmax=hi, aspect="auto", interpolation="nearest")
    image.set_gid("heatmap")
    ax.set_xticks(range(len(heatmap.x_values)), [f"{v:g}" if isinstance(v, float) else str(v) for v in heatmap.x_values])
    ax.set_yticks(range(len(heatmap.y_values)), [f"{v:g}" if isinstance(v, float) else str(v) for v in heatmap.y_values])
    ax.set_xlabel(heatmap.x_name, fontsize=9)
    ax.set_ylabel(heatmap.y_name, fontsize=9)
    ax.tick_params(labelsize=8)
    ax.set_title(heatmap.title, fontsize=10)
    if annotate:
        from matplotlib import colormaps

        colours = colormaps[cmap]
        size = 8 if mean.size <= 36 else 6
        for i in range(mean.shape[0]):
            for j in range(mean.shape[1]):
                value = mean[i, j]
                if not np.isfinite(value):
                    continue
                level = (value - lo) / (hi - lo)
                r, g, b, _ = colours(float(np.clip(level, 0, 1)))
                ink = "white" if 0.299 * r + 0.587 * g + 0.114 * b < 0.5 else "black"
                text = f"{value:.3g}" if abs(value) >= 0.01 or value == 0 else f"{value:.1e}"
                ax.text(j, i, text, ha="center", va="center", fontsize=size, color=ink, gid=f"heatmap-value-{i}-{j}")
    return image


def render_heatmaps(heatmaps, *, title: str | None = None, columns: int | None = None, cmap: str = HEATMAP_CMAP) -> Figure:
    """A figure of study heatmaps in a grid (``columns`` per row; default: all in one row up to 5).

    Panels showing the same ``value`` share one colour scale (so families or options compare
    directly); each scale has a colour bar beside the last panel using it.
    """
    panels = list(heatmaps)
    if not panels:
        raise InputError("no heatmap to draw")
    ncols = columns or min(len(panels), 5)
    nrows = -(-len(panels) // ncols)
    fig = Figure(figsize=(3.9 * ncols + 0.6, 3.4 * nrows + (0.5 if title else 0.1)))
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    scales: dict[str, tuple[float, float]] = {}
    for h in panels:
        finite = np.asarray(h.mean, dtype=float)[np.isfinite(h.mean)]
        if finite.size:
            lo, hi = scales.get(h.value, (float("inf"), float("-inf")))
            scales[h.value] = (min(lo, float(finite.min())), max(hi, float(finite.max())))
    last = {h.value: k for k, h in enumerate(panels)}
    for k, h in enumerate(panels):
        ax = axes[k // ncols][k % ncols]
        lo, hi = scales.get(h.value, (0.0, 1.0))
        image = draw_heatmap(ax, h, cmap=cmap, vmin=lo, vmax=hi)
        if last[h.value] == k:
            fig.colorbar(image, ax=ax, fraction=0.046, pad=0.03).ax.tick_params(labelsize=7)
    for k in range(len(panels), nrows * ncols):
        axes[k // ncols][k % ncols].set_visible(False)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig
