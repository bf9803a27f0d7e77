"""Views of the other robot models' answers: rooms and doors (Φ per door, the room tree), explorations (views,
viewpoints, path), cut orderings (the cut diagram), pursuit plans (the steps and their shadows), composed fields
(cells, fields, reflection zones, trajectories); and a table view of the kinds without a picture (vertex counts,
simulations, room simulations, imports).

Every view reads the answer's JSON as the CLI wrote it (``solverplan.answers.read_answer`` reads it into its typed
answer); the environment is drawn when it is known, and is required only where the picture is drawn over it.
"""

from __future__ import annotations

import math
import shlex
from typing import Any, Sequence

from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.render.figure import CYCLE_COLOR, PLAN_GOAL_COLOR, PLAN_STAGE_COLORS, PLAN_START_COLOR
from solverplan.render.report._kinds import ANSWER_KINDS, AnswerFile
from solverplan.render.report.bounce import _View
from solverplan.render.report.format import Exact, _e, _num
from solverplan.render.report.page import _environment_rows, _grid, _optimality_rows, _table
from solverplan.render.report.svg import _Canvas, _el, _line

__all__ = ["MODEL_VIEWS"]

_DOOR_COLOR = "#d7301f"
_TREE_COLOR = "#54278f"
_VIEW_COLOR = "#3182bd"
_PATH_COLOR = "#252525"


def _colour(k: int) -> str:
    return PLAN_STAGE_COLORS[k % len(PLAN_STAGE_COLORS)]


def _xy(value: object, where: str) -> tuple[float, float]:
    """A point ``[x, y]`` of the answer (numbers or exact strings) as floats, for drawing."""
    from fractions import Fraction

    if not isinstance(value, list) or len(value) != 2:
        raise MalformedFile(f"{where}: expected [x, y], got {value!r}"[:200])
    try:
        x, y = (float(Fraction(v)) if isinstance(v, str) else float(v) for v in value)
    except (TypeError, ValueError, ZeroDivisionError):
        raise MalformedFile(f"{where}: expected two numbers, got {value!r}"[:200]) from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise MalformedFile(f"{where}: expected finite numbers")
    return x, y


def _bounds(points: Sequence[tuple[float, float]]) -> tuple[float, float, float, float]:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return (min(xs), min(ys), max(xs), max(ys))


class _ModelView(_View):
    """A model's answer over its environment (drawn when known), with the answer's scalar numbers in a table."""

    hint = "Hover over the picture or a row for details."

    def __init__(self, answer: AnswerFile, env: Environment | None, env_label: str) -> None:
        self.answer, self.data, self.env_label = answer, answer.data, env_label
        self.env = env  # type: ignore[assignment]  # the models' views draw without an environment too
        self.legend: list[tuple[str, str, str]] = []
        self.bounces = None
        self.start = self.goal = None
        self.contraction: dict[int, float] = {}
        if env is not None and isinstance(self.data.get("environment"), dict):
            self.check_environment()
        points = self.geometry()
        bounds = env.bounds if env is not None else (_bounds(points) if points else (0.0, 0.0, 1.0, 1.0))
        self.canvas = _Canvas(bounds)

    def geometry(self) -> list[tuple[float, float]]:
        """The answer's own points (to frame the picture without an environment)."""
        return []

    @property
    def title(self) -> str:
        name = self.env.name if self.env is not None else str((self.data.get("environment") or {}).get("name", ""))
        return f"{name or 'environment'}: {ANSWER_KINDS[self.answer.kind].split(' (')[0]}, {self.data.get('status', '')}"

    def environment_layer(self) -> str:
        return super().environment_layer() if self.env is not None else ""

    def edge_labels(self) -> str:
        return super().edge_labels() if self.env is not None else ""

    def picture(self, layers: Sequence[str]) -> str:
        if not any(layers):
            return ""
        return (f'<section id="picture">{self.svg(layers)}<div id="side"><h2>Details</h2>'
                f'<div id="details" class="empty" aria-live="polite">{_e(self.hint)}</div>{self.legend_html()}</div></section>')

    def layers(self) -> list[str]:
        return []

    def scalar_rows(self, skip: Sequence[str] = ()) -> list[tuple[str, str]]:
        """The answer's top-level numbers, texts and flags (lists of scalars joined), in the answer's order."""
        rows = []
        for key, value in self.data.items():
            if key in ("kind", "optimality", "stats", "environment", *skip):
                continue
            if isinstance(value, (dict, list)) and not (isinstance(value, list) and all(
                    isinstance(v, (int, float, str)) for v in value) and len(value) <= 60):
                continue
            shown = ", ".join(_num(v, 9) for v in value) if isinstance(value, list) else _num(value, 9)
            rows.append((key, Exact(shown) if key.endswith("_exact") else shown))
        return rows

    def numbers(self) -> str:
        rows = self.scalar_rows() + _optimality_rows(self.data.get("optimality")) + _environment_rows(self.data)
        return _table(rows, table_id="summary", exact=[k for k, _ in rows if k.endswith("_exact")]) + self.tables()

    def tables(self) -> str:
        return ""

    def command(self, certificate_path: str | None) -> str:
        return shlex.join(["solverplan", *self.command_words(), "-o", self.answer.path]
                          + (["--certificate", certificate_path] if certificate_path else []))

    def command_words(self) -> list[str]:
        return [self.answer.kind, self.env_label]

    def polygon(self, ring: Sequence[tuple[float, float]], attrs: dict[str, object], title: str | None = None) -> str:
        return _el("polygon", {"points": self.canvas.points(ring), **attrs}, title)

    def dot(self, p: tuple[float, float], r: float, attrs: dict[str, object], title: str | None = None,
            label: str | None = None) -> str:
        x, y = self.canvas.xy(*p)
        out = _el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": f"{r:.1f}", **attrs}, title)
        if label is not None:
            out += _el("text", {"x": f"{x:.1f}", "y": f"{y:.1f}", "font-size": "9.5", "font-weight": "700", "fill": "#fff",
                                "text-anchor": "middle", "dominant-baseline": "central"}, body=_e(label))
        return out


# ---------------------------------------------------------------------- rooms and doors
class _RoomsView(_ModelView):
    """Rooms coloured and numbered, doors in red with Φ from each side, the room tree joining the rooms' centres."""

    hint = "Hover over a room, a door or a branch of the room tree."

    def __init__(self, answer: AnswerFile, env: Environment | None, env_label: str) -> None:
        d = answer.data
        self.rooms = [(r.get("id"), [_xy(p, f"{answer.path}: rooms[{k}].polygon") for p in r.get("polygon") or []], r)
                      for k, r in enumerate(d.get("rooms") or []) if isinstance(r, dict)]
        self.doors = [x for x in d.get("doors") or [] if isinstance(x, dict)]
        super().__init__(answer, env, env_label)

    def geometry(self) -> list[tuple[float, float]]:
        return [p for _, ring, _ in self.rooms for p in ring]

    def centre(self, room: int) -> tuple[float, float] | None:
        for rid, ring, _ in self.rooms:
            if rid == room and ring:
                return (sum(p[0] for p in ring) / len(ring), sum(p[1] for p in ring) / len(ring))
        return None

    def layers(self) -> list[str]:
        out = []
        for k, (rid, ring, raw) in enumerate(self.rooms):
            out.append(self.polygon(ring, {"class": "hover room", "fill": _colour(k), "fill-opacity": "0.25",
                                           "stroke": _colour(k), "stroke-width": "1", "data-room": rid},
                                    f"room {rid}: area {raw.get('area_exact', raw.get('area'))}, doors "
                                    f"{', '.join(map(str, raw.get('doors') or [])) or 'none'}"))
        for k, door in enumerate(self.doors):
            a, b = _xy(door.get("a"), f"doors[{k}].a"), _xy(door.get("b"), f"doors[{k}].b")
            rooms = door.get("rooms") or ["?", "?"]
            phis = door.get("escapability_by_room_exact") or door.get("escapability_by_room") or []
            by_room = "; ".join(f"Φ leaving room {r} = {phi}" for r, phi in zip(rooms, phis))
            out.append(_line(self.canvas, a, b, {"class": "hover door", "stroke": _DOOR_COLOR, "stroke-width": "3.2",
                                                 "data-door": door.get("id")},
                             f"door {door.get('id')} between rooms {rooms[0]} and {rooms[-1]}: length {_num(door.get('length'))}; "
                             f"{by_room}; the door's Φ {door.get('escapability_exact', door.get('escapability'))}"))
        for i, j in (pair for pair in self.data.get("tree") or [] if isinstance(pair, list) and len(pair) == 2):
            p, q = self.centre(i), self.centre(j)
            if p is not None and q is not None:
                out.append(_line(self.canvas, p, q, {"class": "hover tree", "stroke": _TREE_COLOR, "stroke-width": "1.6",
                                                     "stroke-dasharray": "5 3"}, f"room tree: {i} — {j}"))
        for rid, ring, _ in self.rooms:
            c = self.centre(rid) if isinstance(rid, int) else None
            if c is not None:
                out.append(self.dot(c, 8, {"fill": _TREE_COLOR, "class": "hover room-id"}, f"room {rid}", str(rid)))
        self.legend += [(_colour(0), "area", "rooms (numbered)"), (_DOOR_COLOR, "line", "doors"),
                        (_TREE_COLOR, "line", "room tree (one branch per door)")]
        return ['<g id="rooms">' + "".join(out) + "</g>"]

    def numbers(self) -> str:
        rows = [("status", str(self.data.get("status"))), ("rooms", str(len(self.rooms))), ("doors", str(len(self.doors))),
                ("dropped segments", str(len(self.data.get("dropped") or [])))]
        rows += _optimality_rows(self.data.get("optimality")) + _environment_rows(self.data)
        return _table(rows, table_id="summary") + self.tables()

    def tables(self) -> str:
        rooms = [[str(rid), Exact(str(raw.get("area_exact", raw.get("area")))), str(len(ring)),
                  ", ".join(map(str, raw.get("doors") or []))] for rid, ring, raw in self.rooms]
        doors = []
        for door in self.doors:
            rooms_of = door.get("rooms") or []
            phis = door.get("escapability_by_room_exact") or door.get("escapability_by_room") or []
            doors.append([str(door.get("id")), " – ".join(map(str, rooms_of)), _num(door.get("length")),
                          Exact(str(phis[0])) if phis else "—", Exact(str(phis[1])) if len(phis) > 1 else "—",
                          Exact(str(door.get("escapability_exact", door.get("escapability"))))])
        tree = [[f"{i} — {j}"] for i, j in (p for p in self.data.get("tree") or [] if isinstance(p, list) and len(p) == 2)]
        return ("<h2>Rooms</h2>" + _grid(["room", "area", "vertices", "doors"], rooms, table_id="rooms")
                + "<h2>Doors (Φ = |door| / |wall it lies on|, from each side)</h2>"
                + _grid(["door", "rooms i – j", "length", "Φ leaving i", "Φ leaving j", "door's Φ"], doors, table_id="doors")
                + "<h2>Room tree</h2>" + _grid(["branch"], tree, table_id="tree"))

    def command_words(self) -> list[str]:
        return ["rooms", self.env_label]


# ---------------------------------------------------------------------- explorations
class _ExplorationView(_ModelView):
    """The views (visibility polygons, recomputed exactly from the viewpoints; range discs for range-limited
    views), the numbered viewpoints and the robot's path."""

    hint = "Hover over a viewpoint, its view or a leg of the path."

    def layers(self) -> list[str]:
        from fractions import Fraction

        from solverplan.geometry.visibility import visibility_polygon

        assert self.env is not None
        d = self.data
        points = [_xy(p, f"{self.answer.path}: viewpoints[{k}]") for k, p in enumerate(d.get("viewpoints") or [])]
        exact = d.get("viewpoints_exact") if isinstance(d.get("viewpoints_exact"), list) else None
        radius = d.get("range") if isinstance(d.get("range"), (int, float)) else None
        views = []
        for k, p in enumerate(points):
            try:
                where = (tuple(Fraction(v) for v in exact[k]) if exact else (Fraction(p[0]), Fraction(p[1])))
                ring = [(float(x), float(y)) for x, y in visibility_polygon(self.env, where).ring]
            except (InputError, ValueError, TypeError, IndexError):
                continue  # a viewpoint the float text puts a hair outside the free space: its view is not drawn
            views.append(self.polygon(ring, {"class": "hover view", "data-stage": k, "fill": _VIEW_COLOR,
                                             "fill-opacity": "0.12", "stroke": _VIEW_COLOR, "stroke-opacity": "0.5",
                                             "stroke-width": "0.8", "stroke-dasharray": "4 2"},
                                     f"view {k + 1}: the visibility polygon of p{k + 1}"))
            if radius is not None:
                x, y = self.canvas.xy(*p)
                views.append(_el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": f"{radius * self.canvas.scale:.2f}",
                                            "fill": "none", "stroke": _VIEW_COLOR, "stroke-width": "0.8",
                                            "class": "range"}))
        path = [_xy(p, f"{self.answer.path}: path[{k}]") for k, p in enumerate(d.get("path") or [])]
        legs = "".join(_line(self.canvas, a, b, {"class": "hover leg", "stroke": _PATH_COLOR, "stroke-width": "1.6"},
                             f"leg {k + 1}: ({a[0]:.6g}, {a[1]:.6g}) → ({b[0]:.6g}, {b[1]:.6g})")
                       for k, (a, b) in enumerate(zip(path, path[1:])))
        parents = d.get("parents") or []
        phases = d.get("phases") or []
        dots = "".join(self.dot(p, 7.5, {"fill": _colour(k), "class": "hover viewpoint", "data-stage": k},
                                f"p{k + 1} = ({p[0]:.6g}, {p[1]:.6g})"
                                + (f", on a window of p{parents[k] + 1}" if k < len(parents) and isinstance(parents[k], int)
                                   and parents[k] >= 0 else "") + (f" ({phases[k]})" if k < len(phases) else ""),
                                str(k + 1)) for k, p in enumerate(points))
        self.legend += [(_VIEW_COLOR, "area", f"views ({len(points)})"), (_PATH_COLOR, "line", "the robot's path"),
                        (_colour(0), "point", "viewpoints, in the order visited")]
        return ['<g id="views">' + "".join(views) + "</g>", '<g id="path">' + legs + "</g>",
                '<g id="viewpoints">' + dots + "</g>"]

    def numbers(self) -> str:
        rows = self.scalar_rows(skip=("viewpoints", "parents", "phases", "path", "arcs"))
        rows += _optimality_rows(self.data.get("optimality")) + _environment_rows(self.data)
        points = self.data.get("viewpoints") or []
        parents = self.data.get("parents") or []
        body = [[f"p{k + 1}", f"({_num(p[0], 9)}, {_num(p[1], 9)})" if isinstance(p, list) and len(p) == 2 else "?",
                 f"p{parents[k] + 1}" if k < len(parents) and isinstance(parents[k], int) and parents[k] >= 0 else "—"]
                for k, p in enumerate(points)]
        return (_table(rows, table_id="summary") + "<h2>Viewpoints</h2>"
                + _grid(["viewpoint", "(x, y)", "lies in the view of"], body, table_id="viewpoints", stage_rows=True))

    def command_words(self) -> list[str]:
        start = (self.data.get("viewpoints") or [[0, 0]])[0]
        words = ["explore", self.env_label, "--start", f"{_num(start[0], 17)},{_num(start[1], 17)}"]
        if isinstance(self.data.get("range"), (int, float)):
            words += ["--range", _num(self.data["range"], 17)]
        if self.data.get("choice") not in (None, "first"):
            words += ["--choice", str(self.data["choice"])]
        return words


# ---------------------------------------------------------------------- the wall-following robot
def _cut_diagram(labels: Sequence[str], positions: Sequence[str] = (), shadows: Sequence[Sequence[str]] = ()) -> str:
    """The cut diagram: the points of the cut ordering around a circle (counter-clockwise from v0 at the right),
    each reflex vertex joined to its two cut end points (two chords cross exactly when the cuts do); with
    ``positions``, the pursuer's steps as numbered arrows between the points."""
    n = len(labels)
    size, r = 460.0, 180.0
    cx = cy = size / 2
    at = {}
    out = []
    for k, label in enumerate(labels):
        turn = 2 * math.pi * k / max(n, 1)
        at[label] = (cx + r * math.cos(turn), cy - r * math.sin(turn))
    for label, (px, py) in at.items():
        x, y = px, py
        if label.startswith("v"):
            for kind, colour in (("l", "#2b8cbe"), ("r", "#e6550d")):
                end = at.get(kind + label[1:])
                if end is not None:
                    out.append(f'<line x1="{x:.1f}" y1="{y:.1f}" x2="{end[0]:.1f}" y2="{end[1]:.1f}" stroke="{colour}" '
                               f'stroke-width="1.6" class="hover chord"><title>{_e(f"{kind}-cut of reflex vertex {label}: {label} — {kind}{label[1:]}")}</title></line>')
    for k, (first, second) in enumerate(zip(positions, positions[1:])):
        if first in at and second in at:
            (x1, y1), (x2, y2) = at[first], at[second]
            out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" stroke="{CYCLE_COLOR}" '
                       f'stroke-width="2.4" stroke-opacity="0.7" class="hover step" data-stage="{k}">'
                       f'<title>{_e(f"step {k + 1}: {first} → {second}")}</title></line>')
    for label, (px, py) in at.items():
        x, y = px, py
        fill = "#252525" if label.startswith("v") else "#fff"
        out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4.5" fill="{fill}" stroke="#252525" class="hover point">'
                   f'<title>{_e(label)}</title></circle>')
        angle = math.atan2(cy - y, x - cx)
        tx, ty = cx + (r + 18) * math.cos(angle), cy - (r + 18) * math.sin(angle)
        out.append(f'<text x="{tx:.1f}" y="{ty:.1f}" font-size="10" text-anchor="middle" dominant-baseline="central">'
                   f"{_e(label)}</text>")
    return (f'<svg id="scene" xmlns="http://www.w3.org/2000/svg" width="{size:.0f}" height="{size:.0f}" '
            f'viewBox="0 0 {size:.0f} {size:.0f}" role="img" aria-label="cut diagram">' + "".join(out) + "</svg>")


class _CutOrderingView(_ModelView):
    """The cut diagram of a cut ordering (exact, or learned by Strategy 1), with the polygon when it is known."""

    hint = "Hover over a chord (a cut) or a point of the ordering."

    def labels(self) -> list[str]:
        labels = self.data.get("cut_ordering")
        if not isinstance(labels, list) or not all(isinstance(x, str) for x in labels):
            raise MalformedFile(f"{self.answer.path}: cut_ordering: expected a list of names like 'v0', 'l3', 'r3'")
        return labels

    def picture(self, layers: Sequence[str]) -> str:
        self.legend += [("#2b8cbe", "line", "left cut (reflex vertex — lK)"), ("#e6550d", "line", "right cut (reflex vertex — rK)")]
        return (f'<section id="picture">{self.diagram()}<div id="side"><h2>Details</h2>'
                f'<div id="details" class="empty" aria-live="polite">{_e(self.hint)}</div>{self.legend_html()}</div></section>')

    def diagram(self) -> str:
        return _cut_diagram(self.labels())

    def tables(self) -> str:
        labels = self.labels()
        return "<h2>Cut ordering (counter-clockwise from v0)</h2>" + _grid(
            ["#", "point"], [[str(k), x] for k, x in enumerate(labels)], table_id="ordering")

    def numbers(self) -> str:
        rows = self.scalar_rows(skip=("cut_ordering", "transcript")) + _optimality_rows(self.data.get("optimality"))
        return _table(rows + _environment_rows(self.data), table_id="summary") + self.tables()

    def command_words(self) -> list[str]:
        return ["wallfollow", self.env_label, "--learn" if self.answer.kind == "learned-ordering" else "--cut-ordering"]


class _PursuitView(_CutOrderingView):
    """A pursuit plan: its steps on the cut diagram and, per step, the shadow components that may hold the evader."""

    hint = "Hover over a step of the plan (arrows on the cut diagram, rows of the table)."

    def diagram(self) -> str:
        return _cut_diagram(self.labels(), [str(p) for p in self.data.get("positions") or []])

    def tables(self) -> str:
        actions = [str(a) for a in self.data.get("plan") or []]
        positions = [str(p) for p in self.data.get("positions") or []]
        shadows = self.data.get("shadow_labels") or []
        rows = [["start", "", positions[0] if positions else "", ", ".join(shadows[0]) if shadows else "—"]]
        for k, action in enumerate(actions):
            rows.append([str(k + 1), action, positions[k + 1] if k + 1 < len(positions) else "",
                         ", ".join(shadows[k + 1]) if k + 1 < len(shadows) and shadows[k + 1] else "none"])
        return ("<h2>Pursuit steps</h2>" + _grid(["step", "action", "at", "shadows labelled 1 (may hold the evader)"], rows,
                                                table_id="steps")
                + "<p>A shadow component is named by the reflex vertex its window starts at; every label 0 after the last "
                  "step means no evader can be hiding.</p>" + _replay_verdict(self.data.get("verdict")))

    def command_words(self) -> list[str]:
        return ["wallfollow", self.env_label, "--pursuit", "--sensor", str(self.data.get("sensor", "gap")),
                "--from", str(self.data.get("start", "v0"))]


# ---------------------------------------------------------------------- composed fields
class _FieldsView(_ModelView):
    """The convex cells (the sequence highlighted, reflection cells red), each cell's field direction, the reflection
    zones, and the kept trajectories of every scenario."""

    hint = "Hover over a cell, a field arrow, a reflection zone or a trajectory."

    def __init__(self, answer: AnswerFile, env: Environment | None, env_label: str) -> None:
        d = answer.data
        self.cells = [(c.get("id"), [_xy(p, f"{answer.path}: cells[{k}].polygon") for p in c.get("polygon") or []])
                      for k, c in enumerate(d.get("cells") or []) if isinstance(c, dict)]
        super().__init__(answer, env, env_label)

    def geometry(self) -> list[tuple[float, float]]:
        return [p for _, ring in self.cells for p in ring]

    def layers(self) -> list[str]:
        d = self.data
        sequence = set(x for x in d.get("sequence") or [] if isinstance(x, int))
        reflecting = set(x for x in d.get("reflection_cells") or [] if isinstance(x, int))
        fields = {f.get("cell"): f for f in d.get("fields") or [] if isinstance(f, dict)}
        out = []
        for cid, ring in self.cells:
            colour = "#d7301f" if cid in reflecting else ("#74a9cf" if cid in sequence else "#d9d9d9")
            f = fields.get(cid, {})
            flow = f.get("flow") or {}
            out.append(self.polygon(ring, {"class": "hover cell", "fill": colour, "fill-opacity": "0.25", "stroke": "#636363",
                                           "stroke-width": "0.8"},
                                    f"cell {cid}: next {f.get('next')}, field {(f.get('field') or {}).get('kind')}, flow-through "
                                    f"{'verified' if _flow_valid(flow) else 'not verified'} ({flow.get('method')})"
                                    + ("; a reflection cell" if cid in reflecting else "")))
            if ring and isinstance(f.get("next"), int):
                nxt = dict(self.cells).get(f["next"])
                if nxt:
                    a = (sum(p[0] for p in ring) / len(ring), sum(p[1] for p in ring) / len(ring))
                    b = (sum(p[0] for p in nxt) / len(nxt), sum(p[1] for p in nxt) / len(nxt))
                    m = (a[0] + 0.45 * (b[0] - a[0]), a[1] + 0.45 * (b[1] - a[1]))
                    out.append(_line(self.canvas, a, m, {"class": "hover field", "stroke": "#08519c", "stroke-width": "1.8",
                                                         "stroke-linecap": "round"},
                                     f"cell {cid}'s field leaves through its outlet towards cell {f['next']}"))
                    out.append(self.dot(m, 2.6, {"fill": "#08519c"}))
        for z in d.get("reflection_zones") or []:
            if isinstance(z, dict) and isinstance(z.get("point"), list):
                p = _xy(z["point"], f"{self.answer.path}: reflection_zones[].point")
                out.append(self.dot(p, 5, {"fill": "#d7301f", "class": "hover zone"},
                                    f"reflection zone of cell {z.get('cell')}: α = {_num(z.get('alpha'))} rad, cost "
                                    f"{z.get('cost_exact', z.get('cost'))}"))
        trajectories = []
        for s, (name, run) in enumerate((d.get("scenarios") or {}).items()):
            if not isinstance(run, dict):
                continue
            for t, path in enumerate(run.get("trajectories") or []):
                pts = [_xy(p, f"{self.answer.path}: scenarios.{name}.trajectories[{t}]") for p in path]
                if len(pts) > 1:
                    trajectories.append(_el("polyline", {"points": self.canvas.points(pts), "fill": "none",
                                                         "stroke": _colour(s), "stroke-width": "1.1", "stroke-opacity": "0.8",
                                                         "class": "hover trajectory"},
                                            f"{name} scenario, trajectory {t + 1} ({len(pts)} control ticks)"))
            self.legend.append((_colour(s), "line", f"{name} trajectories"))
        for key, colour in (("start", PLAN_START_COLOR), ("goal", PLAN_GOAL_COLOR)):
            if isinstance(d.get(key), list):
                p = _xy(d[key], f"{self.answer.path}: {key}")
                out.append(self.dot(p, 6, {"fill": colour, "class": "hover"}, f"{key} ({p[0]:.6g}, {p[1]:.6g})"))
        self.legend += [("#74a9cf", "area", "cells of the sequence"), ("#d7301f", "area", "reflection cells and zones"),
                        ("#08519c", "line", "field direction (towards the next cell)")]
        return ['<g id="cells">' + "".join(out) + "</g>", '<g id="trajectories">' + "".join(trajectories) + "</g>"]

    def tables(self) -> str:
        rows = []
        for name, run in (self.data.get("scenarios") or {}).items():
            if isinstance(run, dict):
                rows.append([name, _num(run.get("trials")), _num(run.get("success")), _num(run.get("time_mean")),
                             _num(run.get("time_var")), _num(run.get("collisions_mean"))])
        fields = [[str(f.get("cell")), str(f.get("next")), str((f.get("field") or {}).get("kind")),
                   _num(_flow_valid(f.get("flow"))), str((f.get("flow") or {}).get("method"))]
                  for f in self.data.get("fields") or [] if isinstance(f, dict)]
        return ("<h2>Scenarios</h2>" + _grid(["scenario", "trials", "success", "time mean (s)", "time var", "collisions"],
                                            rows, table_id="scenarios")
                + "<h2>Fields</h2>" + _grid(["cell", "next", "field", "flows through", "verdict"], fields, table_id="fields"))

    def numbers(self) -> str:
        rows = self.scalar_rows(skip=("adjacency",)) + _optimality_rows(self.data.get("optimality"))
        return _table(rows + _environment_rows(self.data), table_id="summary") + self.tables()

    def command_words(self) -> list[str]:
        d = self.data
        words = ["fields", self.env_label]
        for key, flag in (("start", "--from"), ("goal", "--to")):
            if isinstance(d.get(key), list) and len(d[key]) == 2:
                words += [flag, f"{_num(d[key][0], 17)},{_num(d[key][1], 17)}"]
        if d.get("seed") is not None:
            words += ["--seed", str(d["seed"])]
        return words


# ---------------------------------------------------------------------- kinds without a picture
class _TableView(_ModelView):
    """The answer's numbers (vertex counts, simulations, room simulations, imports): no picture of its own; the
    environment is drawn when it is known."""

    def tables(self) -> str:
        out = ""
        for key, value in self.data.items():
            if isinstance(value, dict) and key not in ("optimality", "stats", "environment") and value:
                rows = [(str(k), _num(v, 9) if not isinstance(v, (dict, list)) else str(v)[:300]) for k, v in value.items()]
                out += f"<h2>{_e(key)}</h2>" + _table(rows, table_id=f"table-{key}")
        return out

    def command_words(self) -> list[str]:
        return {"vertex-count": ["wallfollow", self.env_label, "--count"],
                "simulation": ["simulate", self.env_label, "PLAN.json"],
                "rooms-simulation": ["rooms", self.env_label, "--simulate"],
                "rooms-rules": ["rooms", self.env_label, "--simulate", "--rule", "all"],
                "import": ["import", str(self.data.get("source", "FILE"))]}.get(self.answer.kind, [self.answer.kind])


MODEL_VIEWS: dict[str, Any] = {
    "rooms": _RoomsView,
    "exploration": _ExplorationView,
    "range-exploration": _ExplorationView,
    "cut-ordering": _CutOrderingView,
    "learned-ordering": _CutOrderingView,
    "pursuit": _PursuitView,
    "fields": _FieldsView,
    "vertex-count": _TableView,
    "simulation": _TableView,
    "rooms-simulation": _TableView,
    "rooms-rules": _TableView,
    "import": _TableView,
}
"""The view of every answer kind that is not the bouncing robot's (those are in :mod:`.bounce`) or a study."""


def _flow_valid(flow: Any) -> Any:
    """A cell's flow-through verdict: ``valid`` (the verdict every check gives), ``verified`` in earlier answers."""
    return flow.get("valid", flow.get("verified")) if isinstance(flow, dict) else None


def _replay_verdict(verdict: Any) -> str:
    """The ground-truth replay's verdict (the answer's ``verdict``) in its words: valid or not, what it proves, every
    failure and what it did not check."""
    if not isinstance(verdict, dict):
        return ""
    items = [f"<li>proved: {_e(p)}</li>" for p in verdict.get("proved") or [] if isinstance(p, str)]
    items += [f'<li class="failure">FAIL {_e(f.get("claim"))}: {_e(f.get("message"))}</li>'
              for f in verdict.get("failures") or [] if isinstance(f, dict)]
    items += [f"<li>not checked: {_e(n)}</li>" for n in verdict.get("not_checked") or [] if isinstance(n, str)]
    state = "VALID" if verdict.get("valid") is True else "INVALID"
    return (f'<h2>Ground-truth replay</h2><p id="replay-verdict"><span class="badge">{state}</span> '
            f"{_e(verdict.get('scope', ''))}</p><ul>{''.join(items)}</ul>")
