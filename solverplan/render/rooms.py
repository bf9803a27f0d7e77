"""Rooms and doors (the rooms paper's Algorithm 1): rooms filled in distinct colours and numbered, doors as
bold red segments labelled with their escapability Φ from each side, the room tree (room centre → door middle →
room centre, dashed), segments Algorithm 1 dropped dotted, and trajectories of the bounce rules on top.

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear import decompose_rooms
>>> fig = render_rooms(decompose_rooms(load_environment("three_chambers")))
>>> sorted({a.get_gid() for a in fig.axes[0].patches})[:2], len([t for t in fig.axes[0].texts if t.get_gid().startswith("room-id-")])
(['room-0', 'room-1'], 5)
>>> [t.get_text() for t in fig.axes[0].texts if t.get_gid() == "door-phi-0"]
['Φ 1/30 | 1']
"""

from __future__ import annotations

from typing import Mapping

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from solverplan.rectilinear.decomposition import Decomposition
from solverplan.render.environment import draw_boundary
from solverplan.render.figure import BOUNDARY_COLOR, _style_axes, new_figure

__all__ = ["ROOM_COLORS", "RULE_COLORS", "draw_rooms", "draw_doors", "draw_room_tree", "draw_room_paths", "render_rooms"]

ROOM_COLORS = ("#cfe3f3", "#f9dcc4", "#d8ecd0", "#eadcf0", "#f6efc6", "#d3eeee", "#f3d3dc", "#e2e2e2")
"""Pale fills, so trajectories and doors stay readable; neighbouring rooms get different ones where possible."""
DOOR_COLOR = "#c0392b"
DROPPED_COLORS = {"diagonal": "#2e8b57", "chain": "#1f5fbf", "crossing": "#8e44ad"}  # the paper's Fig. 2: green, blue
RULE_COLORS = {"smart": "#08306b", "smart-paper": "#2171b5", "smart-per-room": "#6baed6", "random": "#d95f02",
               "billiard": "#7570b3"}
TREE_COLOR = "#555555"


def _colouring(dec: Decomposition) -> list[int]:
    """A colour per room, different from its neighbours' (a tree; the palette is larger than any need):
    room i tries colour i first, so rooms far apart in the tree still differ."""
    n = len(ROOM_COLORS)
    colour: dict[int, int] = {}
    for room in dec.rooms:
        used = {colour[other] for other, _ in dec.neighbours[room.id] if other in colour}
        colour[room.id] = next((k % n for k in range(room.id, room.id + n) if k % n not in used), room.id % n)
    return [colour[room.id] for room in dec.rooms]


def draw_rooms(ax: Axes, dec: Decomposition, *, labels: bool = True) -> list:
    """Fill each room (gid ``room-<id>``) and, with ``labels``, write its id at its centre (gid ``room-id-<id>``)."""
    import shapely

    artists: list = []
    colours = _colouring(dec)
    for room in dec.rooms:
        xy = np.array([[float(x), float(y)] for x, y in room.polygon])
        patch = Polygon(xy, closed=True, facecolor=ROOM_COLORS[colours[room.id]], edgecolor="none", zorder=0.5,
                        gid=f"room-{room.id}")
        ax.add_patch(patch)
        artists.append(patch)
        if labels:
            spot = shapely.Polygon(xy).point_on_surface()
            artists.append(ax.text(spot.x, spot.y, str(room.id), ha="center", va="center", fontsize=9, color=BOUNDARY_COLOR,
                                   zorder=6, gid=f"room-id-{room.id}"))
    return artists


def draw_doors(ax: Axes, dec: Decomposition, *, dropped: bool = True) -> list:
    """Doors as bold red segments (gid ``doors``); with ``dropped``, the segments Algorithm 1 dropped, dotted
    (gid ``dropped-<reason>``: green diagonal, blue chain, purple crossing)."""
    artists: list = []
    if dec.doors:
        segments = [[(float(d.a[0]), float(d.a[1])), (float(d.b[0]), float(d.b[1]))] for d in dec.doors]
        lines = LineCollection(segments, colors=DOOR_COLOR, linewidths=2.6, zorder=3, gid="doors")
        ax.add_collection(lines)
        artists.append(lines)
    if dropped:
        for reason, colour in DROPPED_COLORS.items():
            segments = [[(float(a[0]), float(a[1])), (float(b[0]), float(b[1]))] for a, b, r in dec.dropped if r == reason]
            if segments:
                lines = LineCollection(segments, colors=colour, linewidths=1.4, linestyles="dotted", zorder=2.5,
                                       gid=f"dropped-{reason}")
                ax.add_collection(lines)
                artists.append(lines)
    return artists


def _spot(room) -> tuple[float, float]:
    import shapely

    spot = shapely.Polygon([[float(x), float(y)] for x, y in room.polygon]).point_on_surface()
    return spot.x, spot.y


def draw_room_tree(ax: Axes, dec: Decomposition, *, phi: bool = True) -> list:
    """The room tree (Remark 5): a dashed path from each room's label through the middle of each of its doors
    (gid ``room-tree``); with ``phi``, each door's escapability from its two rooms, "Φ a | b" for rooms
    (door.rooms[0], door.rooms[1]) (gid ``door-phi-<id>``, exact fractions)."""
    from solverplan.exact import format_number

    artists: list = []
    segments = []
    for door in dec.doors:
        mid = ((float(door.a[0]) + float(door.b[0])) / 2, (float(door.a[1]) + float(door.b[1])) / 2)
        for room in door.rooms:
            segments.append([_spot(dec.rooms[room]), mid])
        if phi:
            a, b = (format_number(door.escapability(r)) for r in door.rooms)
            # at one end of the door, alternating ends so that the labels of a doorway's two doors do not overlap
            top = door.id % 2 == 0
            ends = sorted([(float(door.a[0]), float(door.a[1])), (float(door.b[0]), float(door.b[1]))],
                          key=lambda q: (q[1], q[0]))
            where = ends[1] if top else ends[0]
            artists.append(ax.text(where[0], where[1], f"Φ {a} | {b}", fontsize=6, color=DOOR_COLOR, ha="center",
                                   va="bottom" if top else "top", zorder=7, gid=f"door-phi-{door.id}",
                                   bbox={"boxstyle": "round,pad=0.1", "facecolor": "white", "alpha": 0.7,
                                         "edgecolor": "none"}))
    if segments:
        lines = LineCollection(segments, colors=TREE_COLOR, linewidths=0.8, linestyles="dashed", zorder=2.8,
                               gid="room-tree")
        ax.add_collection(lines)
        artists.append(lines)
    return artists


def draw_room_paths(ax: Axes, paths: Mapping[str, np.ndarray], *, linewidth: float = 0.9) -> list:
    """One trajectory per rule: ``paths[rule]`` the contact points (n, 2), drawn in the rule's colour with a
    legend (gid ``path-<rule>``); its start is a dot."""
    artists: list = []
    for name, path in paths.items():
        path = np.asarray(path, dtype=float)
        path = path[np.isfinite(path).all(axis=1)]
        if len(path) == 0:
            continue
        colour = RULE_COLORS.get(name, "#333333")
        (line,) = ax.plot(path[:, 0], path[:, 1], color=colour, linewidth=linewidth, alpha=0.85, zorder=4,
                          label=f"{name} ({len(path) - 1} bounces)", gid=f"path-{name}")
        artists.append(line)
        artists.append(ax.scatter(path[:1, 0], path[:1, 1], s=16, c=colour, zorder=5, gid=f"path-start-{name}"))
    if artists:
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85)
    return artists


def _panel(ax: Axes, dec: Decomposition) -> None:
    xmin, ymin, xmax, ymax = dec.env.bounds
    pad = 0.05 * max(xmax - xmin, ymax - ymin)
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    draw_rooms(ax, dec)
    draw_boundary(ax, dec.env)
    draw_doors(ax, dec)
    draw_room_tree(ax, dec)


def render_rooms(dec: Decomposition, paths: Mapping[str, np.ndarray] | None = None, *, title: str | None = None) -> Figure:
    """The rooms, walls and doors (and the dropped segments); with ``paths``, one panel per rule with its
    trajectory on top (:func:`draw_room_paths`)."""
    heading = title or f"{dec.env.name or 'rooms'}: {len(dec.rooms)} rooms, {len(dec.doors)} doors"
    fig, ax = new_figure(dec.env, title=heading)
    if not paths:
        _panel(ax, dec)
        return fig
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    width, height = fig.get_size_inches()
    panels = Figure(figsize=(width, height * len(paths) + 0.3))
    FigureCanvasAgg(panels)
    for k, (name, path) in enumerate(paths.items()):
        ax = panels.add_subplot(len(paths), 1, k + 1)
        _style_axes(ax, f"{heading} — {name} rule" if k == 0 else f"{name} rule")
        _panel(ax, dec)
        draw_room_paths(ax, {name: path})
    panels.tight_layout()
    return panels
