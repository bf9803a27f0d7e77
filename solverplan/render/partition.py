"""The partition P′ of the boundary (paper Algorithm 1, Figs. 3–4): coloured segments, inserted points, ids.

>>> from solverplan.environment import Environment
>>> from solverplan.bounce.partitions import partition
>>> from solverplan.render import render_environment
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
>>> fig = render_environment(env)
>>> artists = draw_partition(fig.axes[0], partition(env))
>>> [a.get_gid() for a in artists[:2]], len(artists) - 2 == partition(env).n_segments
(['partition-segments', 'partition-inserted'], True)
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from solverplan.bounce.partitions import Partition
from solverplan.render.figure import INSERTED_COLOR, PARTITION_COLORS
from solverplan.render.labels import (
    LabelPlacer,
    _clear_distance,
    _font_size,
    _label_half_size,
    _left_normals,
    _offset_label,
    _reserve_labels,
)

__all__ = ["draw_partition"]


def draw_partition(
    ax: Axes,
    partition: Partition,
    *,
    segment_ids: bool = True,
    placer: LabelPlacer | None = None,
    colors: tuple[str, ...] = PARTITION_COLORS,
    fontsize: float | None = None,
) -> list:
    """Draw the partition P′ (paper Algorithm 1, as in the paper's Figs. 3 and 4).

    Segments are drawn over the boundary in colours alternating along each ring (a third colour
    closes a ring with an odd number of segments, so neighbours always differ); inserted points are
    white dots ringed in dark; with ``segment_ids`` each segment is labelled with its id beside its
    middle, in the free space, in the segment's colour.

    Returns the artists added: the segments' :class:`~matplotlib.collections.LineCollection` (gid
    ``partition-segments``), the inserted points' ``PathCollection`` (gid ``partition-inserted``),
    then the labels (gid ``segment-id-<k>``).
    """
    env = partition.env
    m = partition.n_segments
    colour_of = []
    for k in range(len(partition.ring_offsets) - 1):
        count = partition.ring_offsets[k + 1] - partition.ring_offsets[k]
        ring_colours = [colors[j % 2] for j in range(count)]
        if count % 2 and count > 1:
            ring_colours[-1] = colors[2 % len(colors)]
        colour_of.extend(ring_colours)
    starts, ends = partition.seg_start, partition.seg_end
    lines = LineCollection(
        list(np.stack([starts, ends], axis=1)), colors=colour_of, linewidths=3.2, capstyle="butt", zorder=2.5,
        gid="partition-segments",
    )
    ax.add_collection(lines)
    pts = np.array([[float(q.point[0]), float(q.point[1])] for q in partition.inserted]).reshape(-1, 2)
    dots = ax.scatter(
        pts[:, 0], pts[:, 1], s=16, c="white", edgecolors=INSERTED_COLOR, linewidths=0.9, zorder=5.5,
        gid="partition-inserted",
    )
    artists: list = [lines, dots]
    if not segment_ids:
        return artists
    size = fontsize or _font_size(m)
    if placer is None:
        placer = LabelPlacer(ax, env)
        _reserve_labels(placer, ax)
    normals = _left_normals(env)
    for k in range(m):
        text = str(k)
        half = _label_half_size(text, size, pad=1.0)
        normal = normals[int(partition.seg_edge[k])]
        base = _clear_distance(normal, half, gap=3.0)
        candidates = [
            (starts[k] + f * (ends[k] - starts[k]), normal * base * stretch)
            for stretch in (1.0, 1.7, 2.5, 3.5)
            for f in (0.5, 0.35, 0.65, 0.2, 0.8)
        ]
        anchor, offset = candidates[placer.place(candidates, half)]
        label = _offset_label(ax, text, anchor, offset, size=size, color=colour_of[k], gid=f"segment-id-{k}",
                              fontweight="bold")
        artists.append(label)
    return artists
