"""Labels that keep clear of the walls, the vertices and each other: the placer and the id layers.

:class:`LabelPlacer` chooses, for every label, the first of a list of candidate spots (an anchor on the
boundary and an offset in points) that meets no wall, no vertex and no label placed before.
:func:`draw_edge_ids` and :func:`draw_vertex_ids` label edges ``e<i>`` (inside the free space, with an
arrowhead showing the edge's direction) and vertices ``v<i>`` (outside it), like the boundary-set syntax
of ``docs/contract.md``. The geometry helpers here (inward normals, free-space angles) serve the other
layers too.

>>> from solverplan.render import draw_free_space, new_figure
>>> env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]])
>>> fig, ax = new_figure(env)
>>> _ = draw_free_space(ax, env)
>>> [label.get_text() for label in draw_vertex_ids(ax, env)]
['v0', 'v1', 'v2', 'v3']
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.text import Annotation

from solverplan.environment import Environment
from solverplan.render.figure import ARROW_SIZE, EDGE_ID_COLOR, VERTEX_ID_COLOR, _arrow, _figure_of

__all__ = ["LabelPlacer", "draw_edge_ids", "draw_vertex_ids"]


def _font_size(n_labels: int) -> float:
    """Smaller labels when there are many of them."""
    if n_labels <= 40:
        return 8.0
    if n_labels <= 120:
        return 6.5
    return 5.0


def _unit(v: np.ndarray) -> np.ndarray:
    """Unit vectors along the last axis of ``v`` (zero vectors stay zero)."""
    norm = np.hypot(v[..., 0], v[..., 1])[..., None]
    return np.divide(v, norm, out=np.zeros_like(v), where=norm > 0)


def _left_normals(env: Environment) -> np.ndarray:
    """Unit normals of every edge pointing into the free space (the left side), shape (n, 2)."""
    d = _unit(env.edge_end - env.edge_start)
    return np.stack([-d[:, 1], d[:, 0]], axis=1)


def _free_space_angles(env: Environment) -> np.ndarray:
    """The free space's angle at every vertex, in (0, 2π) (π for a collinear vertex, > π reflex), shape (n,)."""
    verts = env.vertices
    back = verts[env.prev_vertex] - verts
    ahead = verts[env.next_vertex] - verts
    cross = ahead[:, 0] * back[:, 1] - ahead[:, 1] * back[:, 0]
    dot = np.einsum("ij,ij->i", ahead, back)
    return np.mod(np.arctan2(cross, dot), 2 * np.pi)


def _inward_at_vertices(env: Environment) -> np.ndarray:
    """Unit directions at every vertex bisecting the free-space angle (into the free space), shape (n, 2)."""
    verts = env.vertices
    ahead = _unit(verts[env.next_vertex] - verts)
    half = 0.5 * _free_space_angles(env)
    c, s = np.cos(half), np.sin(half)
    return np.stack([c * ahead[:, 0] - s * ahead[:, 1], s * ahead[:, 0] + c * ahead[:, 1]], axis=1)


def _edge_label_params(env: Environment) -> np.ndarray:
    """Where along each edge its label (and arrow) goes: the midpoint, moved away from a sharp corner.

    Two edges meeting at an acute corner of the free space would have their labels meet in the
    corner's narrow wedge; sliding each label towards its edge's other end gives them room.
    """
    angles = _free_space_angles(env)
    tail, head = angles, angles[env.next_vertex]
    sharpest = np.minimum(tail, head)
    shift = 0.3 * np.clip(1.0 - sharpest / (np.pi / 2), 0.0, 1.0)
    return np.where(head < tail, 0.5 - shift, 0.5 + shift)


def _label_half_size(text: str, fontsize: float, pad: float = 2.0) -> tuple[float, float]:
    """Approximate half width and half height, in points, of a centred label with ``pad`` around it."""
    return 0.31 * fontsize * len(text) + pad, 0.5 * fontsize + pad


def _clear_distance(direction: np.ndarray, half: tuple[float, float], gap: float) -> float:
    """Distance in points from an anchor to a label's centre, so the label box clears it by ``gap``
    along ``direction`` (a unit vector) whatever the direction's slope."""
    return gap + abs(float(direction[0])) * half[0] + abs(float(direction[1])) * half[1]


def _point_clear_distance(direction: np.ndarray, half: tuple[float, float], gap: float) -> float:
    """Distance in points from an anchor to a label's centre along ``direction`` so the label box
    leaves the anchor ``gap`` points clear along one of the box's axes (whichever comes first)."""
    ux, uy = abs(float(direction[0])), abs(float(direction[1]))
    return min((half[0] + gap) / ux if ux > 1e-9 else np.inf, (half[1] + gap) / uy if uy > 1e-9 else np.inf)


_COMPASS = (np.array([0.0, 1.0]), np.array([0.0, -1.0]), np.array([1.0, 0.0]), np.array([-1.0, 0.0]))


def _rotate(v: np.ndarray, degrees: float) -> np.ndarray:
    """``v`` turned counter-clockwise by ``degrees``."""
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


class LabelPlacer:
    """Greedy placement of small labels clear of the boundary, the vertices and each other.

    Works in the Axes' current view, so create it after the limits are set (:func:`draw_free_space`
    sets them) and share one placer between the label layers of a picture. A candidate is an
    anchor (data coordinates) and an offset (points); :meth:`place` returns the first candidate
    whose label box meets no boundary edge, no vertex and no label placed before, and whose centre
    sees its anchor; failing that, the first in sight of its anchor that meets no other label;
    then the first that meets no other label; then the first candidate. Callers list candidates
    best first.
    """

    #: above this many labels, candidates are not searched (the labels are unreadable anyway)
    MAX_SEARCH = 2000

    def __init__(self, ax: Axes, env: Environment, *, vertex_clearance: float = 3.5) -> None:
        import shapely

        ax.apply_aspect()
        figure = _figure_of(ax)
        width_points = ax.get_position().width * figure.get_figwidth() * 72.0
        x0, x1 = ax.get_xlim()
        self.points_per_unit = width_points / abs(x1 - x0)
        self._shapely = shapely
        self._edges = shapely.STRtree(shapely.linestrings(np.stack([env.edge_start, env.edge_end], axis=1)))
        self._search = env.n_edges <= self.MAX_SEARCH
        xmin, ymin, xmax, ymax = env.bounds
        self._cell = max(xmax - xmin, ymax - ymin) / 40 or 1.0
        self._grid: dict[tuple[int, int], list[tuple[float, float, float, float]]] = {}
        r = vertex_clearance / self.points_per_unit
        for x, y in env.vertices:
            self._add((x - r, y - r, x + r, y + r))

    def reserve(self, anchor: np.ndarray, offset: np.ndarray, half: tuple[float, float]) -> None:
        """Keep later labels off a box of half size ``half`` (points) at ``offset`` (points) from ``anchor``."""
        self._add(self._box(anchor, offset, half))

    def _cells(self, box: tuple[float, float, float, float]):
        c = self._cell
        for i in range(int(np.floor(box[0] / c)), int(np.floor(box[2] / c)) + 1):
            for j in range(int(np.floor(box[1] / c)), int(np.floor(box[3] / c)) + 1):
                yield (i, j)

    def _add(self, box: tuple[float, float, float, float]) -> None:
        for cell in self._cells(box):
            self._grid.setdefault(cell, []).append(box)

    def _clear_of_labels(self, box: tuple[float, float, float, float]) -> bool:
        for cell in self._cells(box):
            for other in self._grid.get(cell, ()):
                if box[0] < other[2] and other[0] < box[2] and box[1] < other[3] and other[1] < box[3]:
                    return False
        return True

    def _clear_of_edges(self, box: tuple[float, float, float, float]) -> bool:
        return self._edges.query(self._shapely.box(*box), predicate="intersects").size == 0

    def _box(self, anchor: np.ndarray, offset: np.ndarray, half: tuple[float, float]) -> tuple[float, float, float, float]:
        k = self.points_per_unit
        cx, cy = anchor[0] + offset[0] / k, anchor[1] + offset[1] / k
        return (cx - half[0] / k, cy - half[1] / k, cx + half[0] / k, cy + half[1] / k)

    def _sees(self, anchor: np.ndarray, offset: np.ndarray) -> bool:
        """Does the label's centre see its anchor (no boundary edge in between)?

        Keeps a label in the region of what it labels: never across a thin wall.
        """
        norm = float(np.hypot(offset[0], offset[1]))
        if norm == 0:
            return True
        k = self.points_per_unit
        start = anchor + offset * (0.5 / norm) / k  # half a point off the anchor, which lies on the boundary
        end = anchor + offset / k
        line = self._shapely.linestrings([start, end])
        return self._edges.query(line, predicate="intersects").size == 0

    def place(self, candidates: list[tuple[np.ndarray, np.ndarray]], half: tuple[float, float]) -> int:
        """Index of the candidate ``(anchor, offset)`` chosen for a label of half size ``half`` (points)."""
        chosen = 0
        if self._search:
            boxes = [self._box(anchor, offset, half) for anchor, offset in candidates]
            free_of_labels = [k for k, box in enumerate(boxes) if self._clear_of_labels(box)]
            in_sight = [k for k in free_of_labels if self._sees(*candidates[k])]
            clear = [k for k in in_sight if self._clear_of_edges(boxes[k])]
            # crowded: crossing a line is better than being far from the anchor or hiding another label
            for ranked in (clear, in_sight, free_of_labels):
                if ranked:
                    chosen = ranked[0]
                    break
        anchor, offset = candidates[chosen]
        self._add(self._box(anchor, offset, half))
        return chosen


def _offset_label(ax: Axes, text: str, anchor, offset, *, size: float, color, gid: str, **style) -> Annotation:
    """A label centred ``offset`` points away from the data point ``anchor`` (placed by :class:`LabelPlacer`)."""
    label = ax.annotate(
        text,
        xy=(float(anchor[0]), float(anchor[1])),
        xytext=(float(offset[0]), float(offset[1])),
        textcoords="offset points",
        ha="center",
        va="center",
        fontsize=size,
        color=color,
        zorder=4,
        annotation_clip=False,
        **style,
    )
    label.set_gid(gid)
    return label


def draw_edge_ids(
    ax: Axes,
    env: Environment,
    *,
    arrows: bool = True,
    placer: LabelPlacer | None = None,
    color: str = EDGE_ID_COLOR,
    fontsize: float | None = None,
) -> list[Annotation]:
    """Label every edge ``e<i>`` beside it in the free space, with an arrowhead showing its direction.

    Each label sits near its edge's middle, moved along the edge or further from it when that
    spot is taken (by another label, a vertex or an edge). Returns the labels (gid ``edge-id-<i>``);
    the arrows (gid ``edge-arrow-<i>``) are added to the Axes beside them.
    """
    size = fontsize or _font_size(env.n_edges)
    placer = placer or LabelPlacer(ax, env)
    preferred = _edge_label_params(env)
    normals = _left_normals(env)
    dirs = _unit(env.edge_end - env.edge_start)
    labels = []
    for i in range(env.n_edges):
        text = f"e{i}"
        half = _label_half_size(text, size)
        base = _clear_distance(normals[i], half, gap=3.5)
        params = list(dict.fromkeys([float(preferred[i]), 0.5, 0.35, 0.65, 0.2, 0.8]))
        candidates = [
            (env.points_at(np.array([i]), np.array([t]))[0], normals[i] * base * stretch)
            for stretch in (1.0, 1.6, 2.4)
            for t in params
        ]
        chosen = placer.place(candidates, half)
        anchor, offset = candidates[chosen]
        label = _offset_label(ax, text, anchor, offset, size=size, color=color, gid=f"edge-id-{i}",
                              bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.8))
        labels.append(label)
        if arrows:
            _arrow(ax, anchor, dirs[i], color=color, size=ARROW_SIZE, gid=f"edge-arrow-{i}")
            head = 0.5 * ARROW_SIZE  # head_length of the arrow style, in points
            placer.reserve(anchor, -dirs[i] * head / 2, (abs(dirs[i][0]) * head / 2 + 3, abs(dirs[i][1]) * head / 2 + 3))
    return labels


def draw_vertex_ids(
    ax: Axes,
    env: Environment,
    *,
    placer: LabelPlacer | None = None,
    color: str = VERTEX_ID_COLOR,
    fontsize: float | None = None,
) -> list[Annotation]:
    """Label every vertex ``v<i>``, preferably outside the free space (beyond the outer ring, inside holes).

    Each label goes on the bisector of the angle outside the free space, or turned from it when
    that spot is taken.

    Returns the labels (gid ``vertex-id-<i>``).
    """
    size = fontsize or _font_size(env.n_vertices)
    placer = placer or LabelPlacer(ax, env)
    outward = -_inward_at_vertices(env)
    labels = []
    for i in range(env.n_vertices):
        text = f"v{i}"
        half = _label_half_size(text, size, pad=0.5)  # no box behind vertex labels
        anchor = env.vertices[i]
        candidates: list[tuple[np.ndarray, np.ndarray]] = []
        for turn, stretches in ((0, (1.0, 1.6, 2.4)), (25, (1.0, 1.6)), (-25, (1.0, 1.6)), (60, (1.0,)), (-60, (1.0,)),
                                (100, (1.0,)), (-100, (1.0,)), (145, (1.0,)), (-145, (1.0,)), (180, (1.0,))):
            direction = _rotate(outward[i], turn)
            base = _point_clear_distance(direction, half, gap=4.0)
            candidates.extend((anchor, direction * base * stretch) for stretch in stretches)
        for direction in _COMPASS:  # last resorts in crowded corners: straight up, down, left, right
            base = _point_clear_distance(direction, half, gap=4.0)
            candidates.extend((anchor, direction * base * stretch) for stretch in (1.0, 2.0, 3.0))
        chosen = placer.place(candidates, half)
        _, offset = candidates[chosen]
        label = _offset_label(ax, text, anchor, offset, size=size, color=color, gid=f"vertex-id-{i}")
        labels.append(label)
    return labels


def _reserve_labels(placer: LabelPlacer, ax: Axes) -> None:
    """Keep new labels off the labels already on ``ax`` (annotations placed with an offset in points)."""
    for text in ax.texts:
        if not isinstance(text, Annotation) or text.anncoords != "offset points":
            continue
        anchor, offset = np.asarray(text.xy, dtype=float), np.asarray(text.xyann, dtype=float)
        label = text.get_text()
        if label:
            placer.reserve(anchor, offset, _label_half_size(label, float(text.get_fontsize())))
        else:  # an arrow drawn from `offset` to its anchor: keep its shaft and head clear
            placer.reserve(anchor, offset / 2, (abs(offset[0]) / 2 + 3, abs(offset[1]) / 2 + 3))
