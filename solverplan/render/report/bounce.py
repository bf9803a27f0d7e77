"""Views of the bouncing robot's answers: plans and Pareto fronts, patrols, funnels and localisation strategies,
limit cycles and constant controllers."""

from __future__ import annotations

import json
import math
import shlex
from functools import cached_property
from typing import TYPE_CHECKING, Sequence

import numpy as np

from solverplan.environment import Environment
from solverplan.errors import InputError, MalformedFile
from solverplan.limits import quote
from solverplan.render._swept import swept_regions
from solverplan.render.figure import (
    BOUNDARY_COLOR,
    CONE_COLOR,
    CYCLE_COLOR,
    CYCLE_POINT_COLOR,
    EDGE_ID_COLOR,
    FREE_SPACE_COLOR,
    FUNNEL_GOAL_COLOR,
    FUNNEL_START_COLOR,
    PATROL_EDGE_COLOR,
    PLAN_GOAL_COLOR,
    PLAN_START_COLOR,
)
from solverplan.result import EnvironmentRecord

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.partitions import Partition
from solverplan.render.report._kinds import AnswerFile, HOLE_COLOR, _EXACT_CELL
from solverplan.render.report.format import Exact, cell_html, _e, _heading_interval, _interval, _num, _plain, _rad, _short_exact
from solverplan.result import finite_number, index_list
from solverplan.render.report.page import _environment_rows, _grid, _optimality_rows, _stats_block, _table
from solverplan.render.report.svg import _Canvas, _el, _line, _stage_colour


# ====================================================================== views of the answers
class _View:
    """What every report of an answer over an environment draws: the environment with edge ids and hover details;
    subclasses add the answer's layers, its numbers and the command that reproduces it."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        self.answer, self.data, self.env, self.env_label = answer, answer.data, env, env_label
        self.canvas = _Canvas(env.bounds)
        self.legend: list[tuple[str, str, str]] = []  # (colour, shape, text)
        self.bounces: int | None = None  # what a certificate must claim
        self.start: str | None = None
        self.goal: str | None = None
        self.contraction: dict[int, float] = {}  # stage → its worst-case contraction coefficient (plans, entries)
        self.check_environment()

    # -- checks
    def check_environment(self) -> None:
        try:
            record = EnvironmentRecord.from_json(self.data.get("environment"), f"{self.answer.path}: environment")
        except ValueError as exc:
            raise MalformedFile(str(exc)) from None
        if record is not None and not record.matches(self.env):
            raise InputError(f"{self.answer.path}: the answer was made in another environment ({record.name or '?'!r}, "
                             f"sha256 {record.sha256[:12]}…), not in {self.env.name!r}")

    def edge_id(self, value: object, where: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < self.env.n_edges:
            raise InputError(f"{self.answer.path}: {where} names edge {quote(value)}, but {self.env.name!r} has edges "
                             f"0..{self.env.n_edges - 1}")
        return value

    @property
    def title(self) -> str:
        return self.env.name or self.env_label

    # -- the picture
    def environment_layer(self) -> str:
        c, env = self.canvas, self.env
        rings = [[(float(x), float(y)) for x, y in ring] for ring in env.rings]
        parts = [_el("path", {"d": c.path(rings), "fill": FREE_SPACE_COLOR, "fill-rule": "evenodd", "stroke": "none",
                              "id": "free-space"})]
        for h, hole in enumerate(rings[1:], start=1):  # obstacles: grey, so they do not read as the outside
            parts.append(_el("path", {"d": c.path([hole]), "fill": HOLE_COLOR, "stroke": "none", "class": "hover hole"},
                             f"hole {h} (an obstacle): edges e{env.ring_offsets[h]}..e{env.ring_offsets[h + 1] - 1}"))
        starts, ends, lengths = env.edge_start, env.edge_end, env.edge_lengths
        ring_of_edge = env.ring_of
        for i in range(env.n_edges):
            a, b = starts[i], ends[i]
            kind = "outer ring" if int(ring_of_edge[i]) == 0 else f"hole {int(ring_of_edge[i])}"
            title = (f"edge e{i} ({kind}): from ({a[0]:.6g}, {a[1]:.6g}) to ({b[0]:.6g}, {b[1]:.6g}), "
                     f"length {lengths[i]:.6g}; t = 0 at the first point")
            parts.append(_line(c, a, b, {"class": "wall", "stroke": BOUNDARY_COLOR, "stroke-width": "2.2",
                                         "stroke-linecap": "round"}))
            parts.append(_line(c, a, b, {"class": "hover hit", "data-edge": i, "stroke-width": "9"}, title))
        return "<g id=\"environment\">" + "".join(parts) + "</g>"

    def edge_labels(self) -> str:
        """``eK`` beside every edge long enough to carry it: outside the free space, or inside when that spot is taken
        (two walls facing each other across a thin gap); left out where both are (the edge's tooltip still names it)."""
        c, env = self.canvas, self.env
        if env.n_edges > 300:
            return ""
        out = []
        taken: list[tuple[float, float, float, float]] = []  # label boxes placed so far (pixels)

        def free(x: float, y: float, half: float) -> bool:
            return all(abs(x - u) > half + h or abs(y - v) > 7.0 for u, v, h, _ in taken)

        for i in range(env.n_edges):
            a, b = env.edge_start[i], env.edge_end[i]
            d = b - a
            length = float(np.hypot(d[0], d[1]))
            if length * c.scale < 18:  # too short to label legibly (door jambs): hover it instead
                continue
            n = np.array([-d[1], d[0]]) / max(length, 1e-300)  # the inward (left) normal
            mx, my = c.xy(*(0.5 * (a + b)))
            half = 3.2 * len(f"e{i}") + 1.0
            for side in (-1.0, 1.0):  # outside the wall first (world y up, pixels down), then inside
                x, y = mx + side * 11 * n[0], my - side * 11 * n[1]
                if free(x, y, half):
                    taken.append((x, y, half, 0.0))
                    out.append(_el("text", {"x": f"{x:.1f}", "y": f"{y:.1f}", "class": "edge-id", "font-size": "10.5",
                                            "fill": EDGE_ID_COLOR, "text-anchor": "middle", "dominant-baseline": "middle"},
                                   body=_e(f"e{i}")))
                    break
        return "<g id=\"edge-ids\">" + "".join(out) + "</g>"

    def pieces_layer(self, spec: str | None, colour: str, gid: str, name: str) -> str:
        if not spec:
            return ""
        pieces = self.env.boundary_set(spec).pieces
        out = []
        for p in pieces:
            a = self.env.point_at(p.edge, float(p.t0))
            b = self.env.point_at(p.edge, float(p.t1))
            out.append(_line(self.canvas, a, b, {"class": "hover", "stroke": colour, "stroke-width": "8",
                                                 "stroke-opacity": "0.55", "stroke-linecap": "butt"},
                             f"{name} set {spec}: e{p.edge}, t ∈ [{p.t0}, {p.t1}]"))
        self.legend.append((colour, "line", f"{name} {spec}"))
        return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"

    def svg(self, layers: Sequence[str]) -> str:
        c = self.canvas
        return (f'<svg id="scene" xmlns="http://www.w3.org/2000/svg" width="{c.width:.0f}" height="{c.height:.0f}" '
                f'viewBox="0 0 {c.width:.2f} {c.height:.2f}" role="img" aria-label="{_e(self.title)}">'
                + "".join(layers) + "</svg>")

    def legend_html(self) -> str:
        items = []
        for colour, shape, text in self.legend:
            mark = (f'<rect x="1" y="3" width="16" height="10" fill="{_e(colour)}" fill-opacity="0.5" stroke="{_e(colour)}"/>'
                    if shape == "area" else
                    f'<circle cx="9" cy="8" r="5" fill="{_e(CYCLE_POINT_COLOR)}" stroke="{_e(colour)}"/>' if shape == "point"
                    else f'<line x1="1" y1="8" x2="17" y2="8" stroke="{_e(colour)}" stroke-width="5"/>')
            items.append(f'<li><svg width="18" height="16" xmlns="http://www.w3.org/2000/svg">{mark}</svg>{_e(text)}</li>')
        return '<ul class="legend" id="legend">' + "".join(items) + "</ul>"

    def picture(self, layers: Sequence[str]) -> str:
        hint = "Hover over the picture (walls, segments, cones, points) or a stage row for details."
        return (f'<section id="picture">{self.svg(layers)}<div id="side"><h2>Details</h2>'
                f'<div id="details" class="empty" aria-live="polite">{_e(hint)}</div>{self.legend_html()}</div></section>')

    # -- the sections
    def render(self, cert_html: str, certificate_path: str | None) -> str:
        layers = [self.environment_layer(), *self.layers(), self.edge_labels()]
        numbers = self.numbers()  # after the layers: drawing the stages measured their contraction
        command = self.command(certificate_path)
        return (self.picture(layers) + cert_html + f'<section id="numbers"><h2>The answer</h2>{numbers}'
                f"{_stats_block(self.data)}</section>"
                f'<section id="reproduce"><h2>Reproduce it</h2><pre><code id="command">{_e(command)}</code></pre>'
                f"<p>Answer file: <code>{_e(self.answer.path)}</code>.</p></section>")

    def layers(self) -> list[str]:  # pragma: no cover - every view draws its own
        raise NotImplementedError

    def numbers(self) -> str:  # pragma: no cover
        raise NotImplementedError

    def command(self, certificate_path: str | None) -> str:  # pragma: no cover
        raise NotImplementedError

    # -- shared drawing of stages that move between segments of P′ (plans, patrol entries)
    @cached_property
    def partition(self) -> Partition:
        """P′ of the environment (Algorithm 1): the segments stage ids refer to, built once per report."""
        from solverplan.bounce.partitions import partition

        return partition(self.env)

    def segment_layer(self) -> str:
        """Every segment of P′ as a hover target (thin ticks at its ends), with its exact coordinates."""
        part = self.partition
        out = []
        for s in part.segments:
            a, b = (float(s.a[0]), float(s.a[1])), (float(s.b[0]), float(s.b[1]))
            title = f"segment {s.id} of P′: on e{s.edge}, t ∈ [{s.t0}, {s.t1}], from ({a[0]:.6g}, {a[1]:.6g}) to ({b[0]:.6g}, {b[1]:.6g})"
            out.append(_line(self.canvas, a, b, {"class": "hover hit", "data-segment": s.id, "stroke-width": "6"}, title))
            x, y = self.canvas.xy(*a)
            out.append(_el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": "1.6", "fill": BOUNDARY_COLOR}))
        return '<g id="segments">' + "".join(out) + "</g>"

    def move_contraction(self, source: int, target: int, lo: float, hi: float) -> tuple[float, str, float] | None:
        """The worst-case contraction coefficient C over [lo, hi] of a move from edge ``source`` to edge ``target``
        (paper Def. 11, Lemma 2: C is monotone in θ, so the worst case is at a known end), its transition and φ;
        None where the paper's C does not apply (the same wall, or parallel walls facing the same way)."""
        from solverplan.bounce.dynamics import edge_transition, worst_case_contraction

        if source == target:
            return None
        try:
            phi, side = edge_transition(self.env, source, target)
        except InputError:
            return None
        c = worst_case_contraction((lo, hi), phi, side)
        return (c, side, phi) if math.isfinite(c) else None

    def check_segments(self, stages: Sequence[dict], where: str) -> None:
        n = self.partition.n_segments
        for k, st in enumerate(stages):
            for key in ("from_segments", "to_segments"):
                for seg in index_list(st.get(key), f"{self.answer.path}: {where}[{k}].{key}"):
                    if seg >= n:
                        raise InputError(f"{self.answer.path}: {where}[{k}] names segment {seg}, but the partition of "
                                         f"{self.env.name!r} has segments 0..{n - 1}: the answer is for another environment")

    def segment_stage_layer(self, stages: Sequence[dict], where: str, gid: str, first: int = 0, label: str = "stage") -> str:
        """Cones (the swept region of every move) and landing segments of stages over segments of P′."""
        part = self.partition
        out: list[str] = []
        moves: list[tuple[int, int, int, float, float]] = []
        for k, st in enumerate(stages):
            lo, hi = _heading_interval(st.get("interval"), f"{self.answer.path}: {where}[{k}].interval")
            raw = st.get("moves")
            pairs = ([(int(m[0]), int(m[1])) for m in raw] if isinstance(raw, list) and
                     all(isinstance(m, list) and len(m) == 2 for m in raw)
                     else [(i, j) for i in st["from_segments"] for j in st["to_segments"][:1]])
            for i, j in pairs:
                if not 0 <= i < part.n_segments or not 0 <= j < part.n_segments:
                    raise InputError(f"{self.answer.path}: {where}[{k}].moves names segment ({i}, {j}) outside 0..{part.n_segments - 1}")
                moves.append((k, i, j, lo, hi))
        seg_edge, seg_t0, seg_t1 = (np.asarray(part.seg_edge), np.asarray(part.seg_t0), np.asarray(part.seg_t1))
        src = np.array([m[1] for m in moves], dtype=np.int64)
        regions = swept_regions(self.env, seg_edge[src], seg_t0[src], seg_t1[src], [m[3] for m in moves],
                                [m[4] for m in moves]) if moves else []
        for (k, i, j, lo, hi), region in zip(moves, regions):
            shrink = self.move_contraction(int(part.segments[i].edge), int(part.segments[j].edge), lo, hi)
            if shrink is not None:
                self.contraction[first + k] = max(self.contraction.get(first + k, 0.0), shrink[0])
            if region is None:
                continue
            colour = _stage_colour(first + k)
            title = (f"{label} {first + k + 1}, move {i} → {j}: heading interval {_interval((lo, hi))}, width {hi - lo:.6g} rad "
                     f"(±{math.degrees((hi - lo) / 2):.4g}°): every point of segment {i} lands on segment {j}"
                     + (f"; worst-case contraction C = {shrink[0]:.6g} ({shrink[1]} transition, φ = {_rad(shrink[2])})"
                        if shrink is not None else ""))
            out.append(_el("polygon", {"points": self.canvas.points(region), "class": "hover cone", "data-stage": first + k,
                                       "fill": colour, "fill-opacity": "0.28", "stroke": colour, "stroke-opacity": "0.9",
                                       "stroke-width": "1"}, title))
        for k, st in enumerate(stages):
            colour = _stage_colour(first + k)
            lo, hi = st["interval"]
            for j in st["to_segments"]:
                s = part.segments[j]
                a, b = (float(s.a[0]), float(s.a[1])), (float(s.b[0]), float(s.b[1]))
                out.append(_line(self.canvas, a, b, {"class": "hover target", "data-stage": first + k, "stroke": colour,
                                                     "stroke-width": "5", "stroke-linecap": "butt"},
                                 f"{label} {first + k + 1} lands on segment {j} (e{s.edge}, t ∈ [{s.t0}, {s.t1}]) from "
                                 f"segments {', '.join(map(str, st['from_segments']))} with headings {_interval((lo, hi))}"))
            if st["to_segments"]:
                s = part.segments[st["to_segments"][0]]
                mx, my = self.canvas.xy(0.5 * (float(s.a[0]) + float(s.b[0])), 0.5 * (float(s.a[1]) + float(s.b[1])))
                d = np.array([float(s.b[0] - s.a[0]), float(s.b[1] - s.a[1])])
                n = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), 1e-300)
                x, y = mx + 12 * n[0], my - 12 * n[1]  # inside the room, beside its landing segment
                out.append(_el("circle", {"cx": f"{x:.1f}", "cy": f"{y:.1f}", "r": "8", "fill": colour,
                                          "class": "hover stage-label", "data-stage": first + k},
                               f"{label} {first + k + 1}: headings {_interval((lo, hi))}"))
                out.append(_el("text", {"x": f"{x:.1f}", "y": f"{y:.1f}", "font-size": "10", "font-weight": "700",
                                        "fill": "#fff", "text-anchor": "middle", "dominant-baseline": "central"},
                               body=_e(first + k + 1)))
        return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"


def _stage_rows(stages: Sequence[dict], contraction: dict[int, float], first: int = 0) -> list[list[str]]:
    rows = []
    for k, st in enumerate(stages):
        lo, hi = st["interval"]
        c = contraction.get(first + k)
        rows.append([str(first + k + 1), ", ".join(map(str, st.get("from_segments", []))),
                     ", ".join(map(str, st.get("to_segments", []))), f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}",
                     f"±{math.degrees((hi - lo) / 2):.4g}°", "—" if c is None else f"{c:.6g}"])
    return rows


_STAGE_HEADER = ["stage", "from segments", "to segments", "lo (rad)", "hi (rad)", "width (rad)", "tolerance",
                 "worst-case contraction C"]


class _PlanReport(_View):
    """A plan, or a Pareto front (drawn: its most tolerant plan; the front as a table)."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        from solverplan.plan.result import parse_plan

        data = self.data
        self.front = None
        if answer.kind == "pareto":
            points = data.get("points")
            if not isinstance(points, list) or not all(isinstance(p, dict) and isinstance(p.get("plan"), dict) for p in points):
                raise MalformedFile(f"{answer.path}: points: expected a list of {{bounces, min_width, tolerance, plan}}")
            self.front = points
            best = max(points, key=lambda p: finite_number(p.get("tolerance"), f"{answer.path}: points[].tolerance"), default=None)
            plan_data = best["plan"] if best is not None else {"status": "infeasible", "stages": [],
                                                               "objective": "tolerance", "reason": data.get("reason")}
        else:
            plan_data = data
        self.plan = parse_plan(plan_data, answer.path)
        self.plan_data = plan_data
        self.plan.check_environment(env, self.partition.n_segments)  # a Pareto point's plan records it too
        self.stages = plan_data.get("stages", []) if self.plan.found else []
        self.check_segments(self.stages, "stages")
        self.bounces = self.plan.bounces
        self.start, self.goal = self.plan.start, self.plan.goal

    @property
    def title(self) -> str:
        p = self.plan
        name = self.env.name or self.env_label
        if not p.found:
            return f"{name}: {p.objective} plan {p.start} → {p.goal}: {p.status.value}"
        return (f"{name}: {p.objective} plan {p.start} → {p.goal}: {p.bounces} bounce{'s' if p.bounces != 1 else ''}, "
                f"tolerance ±{(p.tolerance or 0.0):.4g} rad")

    def layers(self) -> list[str]:
        out = [self.segment_layer(), self.segment_stage_layer(self.stages, "stages", "plan-stages")]
        for k, _ in enumerate(self.stages):
            self.legend.append((_stage_colour(k), "area", f"stage {k + 1}: {_interval(self.stages[k]['interval'])}"))
        out.append(self.pieces_layer(self.plan.start, PLAN_START_COLOR, "start-set", "start"))
        out.append(self.pieces_layer(self.plan.goal, PLAN_GOAL_COLOR, "goal-set", "goal"))
        return out

    def numbers(self) -> str:
        p, d = self.plan, self.plan_data
        rows = [("status", p.status.value), ("objective", p.objective), ("start", str(p.start)), ("goal", str(p.goal))]
        if p.found:
            rows += [("bounces", str(p.bounces)), ("min_width", _rad(p.min_width)), ("tolerance", _rad(p.tolerance)),
                     ("sum_width", _rad(p.sum_width))]
        else:
            rows.append(("reason", str(p.reason or d.get("reason") or "")))
        if p.max_bounces is not None:
            rows.append(("max_bounces", str(p.max_bounces)))
        rows += _optimality_rows(d.get("optimality"))
        margins = d.get("margins")
        if isinstance(margins, dict) and margins:
            rows.append(("margins", ", ".join(f"{k} {_num(v)}" for k, v in margins.items())))
        rows += _environment_rows(self.data)
        out = _table(rows, table_id="summary", exact=("environment sha256",))
        if self.front is not None:
            out += "<h2>Pareto front (bounces ↔ tolerance)</h2>" + _grid(
                ["bounces", "min_width (rad)", "tolerance (rad)", "proved"],
                [[str(q.get("bounces")), _num(q.get("min_width"), 9), _num(q.get("tolerance"), 9),
                  _num((q["plan"].get("optimality") or {}).get("proved"))] for q in self.front], table_id="front")
            out += "<p>The picture and the stages below are the front's most tolerant plan.</p>"
        if self.stages:
            out += "<h2>Stages</h2>" + _grid(_STAGE_HEADER, _stage_rows(self.stages, self.contraction), table_id="stages",
                                             stage_rows=True)
            out += ("<p>C is the worst case over the interval of the contraction coefficient of the stage's moves "
                    "(the paper's Def. 11): how much a set of positions may stretch (C &gt; 1) or shrink (C &lt; 1).</p>")
        return out

    def command(self, certificate_path: str | None) -> str:
        from solverplan.plan.margins import default_corner_clearance

        p, d = self.plan, self.data
        words = ["solverplan", "plan", self.env_label, "--from", str(p.start), "--to", str(p.goal)]
        if self.answer.kind == "pareto":
            words.append("--pareto")
        else:
            words += ["--objective", p.objective]
        budget = d.get("max_bounces")
        if isinstance(budget, int) and not isinstance(budget, bool):
            words += ["--max-bounces", str(budget)]
        margins = self.plan_data.get("margins") or {}
        heading = margins.get("heading")
        if isinstance(heading, (int, float)) and abs(float(heading) - 1e-3) > 1e-15:
            words += ["--heading-margin", repr(float(heading))]
        clearance = margins.get("corner_clearance")
        if isinstance(clearance, (int, float)) and not math.isclose(float(clearance), default_corner_clearance(self.env),
                                                                    rel_tol=1e-9):
            words += ["--corner-clearance", repr(float(clearance))]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


class _PatrolReport(_View):
    """A patrol: the edges to visit, the entry stages, each cycle stage's fan of headings from its contact point,
    the nominal limit cycle and its contact points."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        self.entry = d.get("entry") or []
        self.cycle = d.get("cycle") or []
        if not isinstance(self.entry, list) or not isinstance(self.cycle, list):
            raise MalformedFile(f"{answer.path}: entry and cycle must be lists of stages")
        self.check_segments(self.entry, "entry")
        self.check_segments(self.cycle, "cycle")
        for k, st in enumerate(self.cycle):
            _heading_interval(st.get("interval"), f"{answer.path}: cycle[{k}].interval")
            self.edge_id(st.get("from_edge"), f"cycle[{k}].from_edge")
        self.points = _fixed_points(self, d.get("fixed_point") or [])
        visit = d.get("visit") or []
        if not isinstance(visit, list):
            raise MalformedFile(f"{answer.path}: visit: expected a list of edges like 'e3'")
        self.visit = [self.edge_id(_edge_number(v), f"visit[{k}]") for k, v in enumerate(visit)]
        self.start = d.get("start") if isinstance(d.get("start"), str) else None
        if self.cycle:
            self.bounces = len(self.entry) + len(self.cycle)

    @property
    def title(self) -> str:
        d = self.data
        seq = " → ".join(f"e{e}" for e in self.visit)
        tail = (f"worst-case contraction {_num(d.get('contraction'), 4)} per cycle" if d.get("status") == "found"
                else str(d.get("status")))
        return f"{self.env.name or self.env_label}: patrol {seq} ({d.get('objective')}): {tail}"

    def layers(self) -> list[str]:
        c, env = self.canvas, self.env
        out = [self.segment_layer()]
        vis = []
        for e in dict.fromkeys(self.visit):
            vis.append(_line(c, env.edge_start[e], env.edge_end[e], {"class": "hover", "stroke": PATROL_EDGE_COLOR,
                                                                     "stroke-width": "7", "stroke-opacity": "0.5"},
                             f"required edge e{e} (visited {self.visit.count(e)}× per pass)"))
        out.append('<g id="patrol-edges">' + "".join(vis) + "</g>")
        self.legend.append((PATROL_EDGE_COLOR, "line", "edges to visit: " + ", ".join(f"e{e}" for e in self.visit)))
        if self.entry:
            out.append(self.segment_stage_layer(self.entry, "entry", "patrol-entry", label="entry stage"))
            self.legend.append((_stage_colour(0), "area", f"entry: {len(self.entry)} stage(s) into the cycle"))
        out.append(_cycle_layers(self, self.cycle, self.points, first=len(self.entry), fans=True))
        out.append(self.pieces_layer(self.start, PLAN_START_COLOR, "start-set", "start"))
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status")))]
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("visit", "objective", "tolerance", "max_between", "start", "bounces", "periods", "contraction",
                    "contraction_exact", "rate", "attractor_width"):
            if key in d:
                v = d[key]
                rows.append((key, ", ".join(map(str, v)) if isinstance(v, list) else _num(v, 9)))
        rm = d.get("return_map")
        if isinstance(rm, dict):
            rows.append(("return map", f"on e{rm.get('edge')}: t ↦ {rm.get('alpha')} · t + {rm.get('beta')}"))
            rows.append(("nominal contraction", _num(rm.get("nominal_contraction"), 9)))
        rows += _optimality_rows(d.get("optimality"))
        if "bound_all_classes" in d:
            rows.append(("bound_all_classes", _num(d.get("bound_all_classes"), 9)))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("contraction_exact", "return map", "environment sha256"))
        out += _cycle_tables(self.entry, self.cycle, self.points, self.contraction)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        words = ["solverplan", "patrol", self.env_label, "--visit", ",".join(f"e{e}" for e in self.visit)]
        if self.start:
            words += ["--from", self.start]
        objective = str(d.get("objective") or "contraction")
        words += ["--objective", objective]
        if objective != "tolerance" and isinstance(d.get("tolerance"), (int, float)):
            words += ["--tolerance", repr(float(d["tolerance"]))]
        if isinstance(d.get("max_between"), int):
            words += ["--max-between", str(d["max_between"])]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


def _edge_number(name: object) -> object:
    """The number of an edge named ``eK`` (or given as K); anything else unchanged, for the caller to refuse."""
    if isinstance(name, str) and name[:1] == "e" and name[1:].isdigit():
        return int(name[1:])
    return name


def _fixed_points(view: _View, raw: object) -> list[dict]:
    if not isinstance(raw, list):
        raise MalformedFile(f"{view.answer.path}: fixed_point: expected a list of {{edge, t, point}}")
    points = []
    for k, p in enumerate(raw):
        where = f"fixed_point[{k}]"
        if not isinstance(p, dict) or not isinstance(p.get("point"), list) or len(p["point"]) != 2:
            raise MalformedFile(f"{view.answer.path}: {where}: expected {{edge, t, point: [x, y]}}")
        view.edge_id(p.get("edge"), where)
        finite_number(p.get("t"), f"{view.answer.path}: {where}.t")
        finite_number(p["point"][0], f"{view.answer.path}: {where}.point[0]")
        finite_number(p["point"][1], f"{view.answer.path}: {where}.point[1]")
        points.append(p)
    return points


def _cycle_layers(view: _View, cycle: Sequence[dict], points: Sequence[dict], *, first: int, fans: bool,
                  colour: str = CYCLE_COLOR, gid: str = "cycle", label: str = "cycle stage") -> str:
    """The nominal cycle through its contact points (bold), each stage's fan of headings from its contact point
    (``fans``), and the contact points with their exact parameters."""
    from solverplan.geometry.raycast import cast_from_boundary

    c, env = view.canvas, view.env
    out: list[str] = []
    if fans and cycle and len(points) == len(cycle):
        edges = np.array([int(st["from_edge"]) for st in cycle for _ in (0, 1)], dtype=np.int64)
        ts = np.array([float(p["t"]) for p in points for _ in (0, 1)])
        heads = np.array([h for st in cycle for h in (float(st["interval"][0]), float(st["interval"][1]))])
        hits = cast_from_boundary(env, edges, ts, heads)
        for k, (st, p) in enumerate(zip(cycle, points)):
            lo, hi = float(st["interval"][0]), float(st["interval"][1])
            h0, h1 = hits.points[2 * k], hits.points[2 * k + 1]
            if not (np.all(np.isfinite(h0)) and np.all(np.isfinite(h1))):
                continue
            extra = "; ".join(f"{key} {_short_exact(st[key]) if key != 'phi' else _rad(st[key])}"
                              for key in ("transition", "phi", "contraction") if key in st)
            mp: dict = st["map"] if isinstance(st.get("map"), dict) else {}
            title = (f"{label} {first + k + 1}: e{st.get('from_edge')} → e{st.get('to_edge')}, headings {_interval((lo, hi))} "
                     f"(width {hi - lo:.6g} rad); {extra}; exact map t ↦ {_short_exact(mp.get('alpha'))} · t + "
                     f"{_short_exact(mp.get('beta'))}")
            out.append(_el("polygon", {"points": c.points([p["point"], h0, h1]), "class": "hover cone fan",
                                       "data-stage": first + k, "fill": CONE_COLOR, "fill-opacity": "0.2",
                                       "stroke": CONE_COLOR, "stroke-opacity": "0.8", "stroke-width": "0.8"}, title))
    if points:
        closed = [p["point"] for p in points] + [points[0]["point"]]
        out.append(_el("polyline", {"points": c.points(closed), "fill": "none", "stroke": colour, "stroke-width": "2.6",
                                    "stroke-linejoin": "round", "class": "cycle-path"}))
        for k, p in enumerate(points):
            x, y = c.xy(p["point"][0], p["point"][1])
            bits = [f"contact point {k + 1} on e{p['edge']}: t = {p.get('t_exact', p['t'])} (≈ {float(p['t']):.9g}), "
                    f"at ({float(p['point'][0]):.6g}, {float(p['point'][1]):.6g})"]
            if "segment" in p:
                bits.append(f"segment {p['segment']}")
            if isinstance(p.get("basin"), list):
                bits.append(f"basin t ∈ [{_num(p['basin'][0])}, {_num(p['basin'][1])}]")
            if p.get("cycles_to_epsilon") is not None:
                bits.append(f"{p['cycles_to_epsilon']} cycles to ε")
            out.append(_el("circle", {"cx": f"{x:.2f}", "cy": f"{y:.2f}", "r": "5.5", "fill": CYCLE_POINT_COLOR,
                                      "stroke": colour, "stroke-width": "1.4", "class": "hover contact",
                                      "data-stage": first + k if k < len(cycle) else None}, "; ".join(bits)))
        view.legend.append((colour, "line", f"limit cycle ({len(points)} contact points)"))
        view.legend.append((colour, "point", "contact points (fixed points of the return map)"))
    if fans and cycle:
        view.legend.append((CONE_COLOR, "area", "heading interval of each cycle stage"))
    return f'<g id="{_e(gid)}">' + "".join(out) + "</g>"


def _cycle_tables(entry: Sequence[dict], cycle: Sequence[dict], points: Sequence[dict],
                  contraction: dict[int, float] | None = None) -> str:
    contraction = contraction or {}
    out = ""
    if entry:
        out += "<h2>Entry stages</h2>" + _grid(_STAGE_HEADER, _stage_rows(entry, contraction), table_id="entry-stages",
                                               stage_rows=True)
    if cycle:
        header = ["stage", "edges", "lo (rad)", "hi (rad)", "width (rad)", "transition", "contraction", "map t ↦ α t + β"]
        rows = []
        for st in cycle:
            lo, hi = st["interval"]
            mp: dict = st["map"] if isinstance(st.get("map"), dict) else {}
            rows.append([f"e{st.get('from_edge')} → e{st.get('to_edge')}", f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}",
                         str(st.get("transition", "")), _num(st.get("contraction"), 9),
                         f"α = {mp.get('alpha')}, β = {mp.get('beta')}"])
        body = "".join(f'<tr data-stage="{len(entry) + k}"><td>{len(entry) + k + 1}</td>'
                       + "".join(f"<td{_EXACT_CELL if j == len(r) - 1 else ''}>{cell_html(Exact(v) if j == len(r) - 1 else v)}</td>"
                                 for j, v in enumerate(r))
                       + "</tr>" for k, r in enumerate(rows))
        out += ('<h2>Cycle stages</h2><table id="cycle-stages"><thead><tr>' + "".join(f"<th>{_e(h)}</th>" for h in header)
                + f"</tr></thead><tbody>{body}</tbody></table>")
    if points:
        rows2 = [[str(k + 1), f"e{p['edge']}", Exact(str(p.get("t_exact", p["t"]))), f"{float(p['t']):.9g}",
                  f"({float(p['point'][0]):.6g}, {float(p['point'][1]):.6g})"] for k, p in enumerate(points)]
        out += "<h2>Fixed points</h2>" + _grid(["point", "edge", "t (exact)", "t", "(x, y)"], rows2, table_id="fixed-points")
    return out


class _FunnelReport(_View):
    """A funnel or localisation strategy: the start and goal sets, and per stage the region its rays sweep and the
    exact set of possible positions after it."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        self.stages = d.get("stages") or [] if d.get("status") == "found" else []
        if not isinstance(self.stages, list):
            raise MalformedFile(f"{answer.path}: stages must be a list")
        self.start = d.get("start") if isinstance(d.get("start"), str) else None
        self.goal = d.get("goal") if isinstance(d.get("goal"), str) and answer.kind == "funnel" else None
        if self.start is not None:
            env.boundary_set(self.start)  # a start set of edges env lacks is another environment's
        self.positions: list[list[dict]] = []
        for k, st in enumerate(self.stages):
            where = f"stages[{k}]"
            if not isinstance(st, dict):
                raise MalformedFile(f"{answer.path}: {where}: expected a stage object")
            _heading_interval(st.get("interval"), f"{answer.path}: {where}.interval")
            pieces = st.get("positions")
            if not isinstance(pieces, list) or not pieces:
                raise MalformedFile(f"{answer.path}: {where}.positions: expected a list of {{edge, t0, t1}}")
            for m, p in enumerate(pieces):
                if not isinstance(p, dict):
                    raise MalformedFile(f"{answer.path}: {where}.positions[{m}]: expected {{edge, t0, t1}}")
                self.edge_id(p.get("edge"), f"{where}.positions[{m}]")
                t0 = finite_number(p.get("t0"), f"{answer.path}: {where}.positions[{m}].t0")
                t1 = finite_number(p.get("t1"), f"{answer.path}: {where}.positions[{m}].t1")
                if not 0 <= t0 <= t1 <= 1:
                    raise MalformedFile(f"{answer.path}: {where}.positions[{m}]: [t0, t1] = [{t0}, {t1}] is not inside [0, 1]")
            self.positions.append(pieces)
        if d.get("status") == "found":
            self.bounces = len(self.stages)

    @property
    def title(self) -> str:
        d = self.data
        target = f"< {d.get('epsilon')}" if self.answer.kind == "localize" else str(d.get("goal"))
        tail = (f"{len(self.stages)} bounces; position set {_num((d.get('position_widths') or [0])[0], 4)} → "
                f"{_num((d.get('position_widths') or [0])[-1], 4)} long" if self.stages else str(d.get("status")))
        return f"{self.env.name or self.env_label}: {self.answer.kind} {d.get('start')} → {target}: {tail}"

    def layers(self) -> list[str]:
        env, c = self.env, self.canvas
        out = [self.pieces_layer(self.start, FUNNEL_START_COLOR, "start-set", "start"),
               self.pieces_layer(self.goal, FUNNEL_GOAL_COLOR, "goal-set", "goal")]
        sources = ([{"edge": p.edge, "t0": float(p.t0), "t1": float(p.t1)} for p in env.boundary_set(self.start).pieces]
                   if self.start else [])
        n = max(len(self.stages), 1)
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        swept: list[str] = []
        lines: list[str] = []
        for k, st in enumerate(self.stages):
            r, g, b, _ = cmap(0.1 + 0.8 * k / max(n - 1, 1))
            colour = "#%02x%02x%02x" % (round(r * 255), round(g * 255), round(b * 255))
            lo, hi = st["interval"]
            if sources:
                regions = swept_regions(env, [int(p["edge"]) for p in sources], [float(p["t0"]) for p in sources],
                                        [float(p["t1"]) for p in sources], [lo] * len(sources), [hi] * len(sources))
                for region in regions:
                    if region is None:
                        continue
                    swept.append(_el("polygon", {"points": c.points(region), "class": "hover cone", "data-stage": k,
                                                 "fill": colour, "fill-opacity": "0.25", "stroke": colour,
                                                 "stroke-width": "0.8"},
                                     f"stage {k + 1}: headings {_interval((lo, hi))} (width {hi - lo:.6g} rad) sweep this "
                                     "region from the possible positions before it"))
            for p in self.positions[k]:
                a, b2 = env.point_at(int(p["edge"]), float(p["t0"])), env.point_at(int(p["edge"]), float(p["t1"]))
                length = float(env.edge_lengths[int(p["edge"])]) * (float(p["t1"]) - float(p["t0"]))
                lines.append(_line(c, a, b2, {"class": "hover positions", "data-stage": k, "stroke": colour,
                                              "stroke-width": "5", "stroke-linecap": "round"},
                                   f"positions after stage {k + 1}: e{p['edge']}, t ∈ [{p.get('t0_exact', p['t0'])}, "
                                   f"{p.get('t1_exact', p['t1'])}] (length {length:.6g})"))
            self.legend.append((colour, "area", f"stage {k + 1}: {_interval((lo, hi))}"))
            sources = self.positions[k]
        out.insert(0, '<g id="funnel-swept">' + "".join(swept) + "</g>")
        out.append('<g id="funnel-positions">' + "".join(lines) + "</g>")
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status"))), ("kind", str(d.get("kind")))]
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("start", "goal", "epsilon", "tolerance", "bounces", "min_width", "safe_plan_exists"):
            if key in d:
                rows.append((key, _num(d[key], 9)))
        widths = d.get("position_widths")
        if isinstance(widths, list):
            rows.append(("position widths", " → ".join(_num(w, 6) for w in widths)))
        rows += _optimality_rows(d.get("optimality"))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("environment sha256",))
        if self.stages:
            header = ["stage", "lo (rad)", "hi (rad)", "width (rad)", "positions after (exact)"]
            body = []
            for k, st in enumerate(self.stages):
                lo, hi = st["interval"]
                pos = Exact("; ".join(f"e{p['edge']} [{p.get('t0_exact', p['t0'])}, {p.get('t1_exact', p['t1'])}]"
                                      for p in self.positions[k]))
                body.append([str(k + 1), f"{lo:.9g}", f"{hi:.9g}", f"{hi - lo:.6g}", pos])
            out += "<h2>Stages</h2>" + _grid(header, body, table_id="stages", stage_rows=True)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        if self.answer.kind == "localize":
            words = ["solverplan", "localize", self.env_label, "--epsilon", _plain(d.get("epsilon"))]
            if self.start:
                words += ["--from", self.start]
        else:
            words = ["solverplan", "funnel", self.env_label, "--from", str(d.get("start")), "--to", str(d.get("goal"))]
        if isinstance(d.get("tolerance"), (int, float)):
            words += ["--tolerance", repr(float(d["tolerance"]))]
        words += ["-o", self.answer.path]
        if certificate_path:
            words += ["--certificate", certificate_path]
        return shlex.join(words)


class _CycleReport(_View):
    """A limit cycle of a constant heading (``cycle``), or a constant controller (``cycle --theta auto``: each of
    its cycles)."""

    def __init__(self, answer: AnswerFile, env: Environment, env_label: str) -> None:
        super().__init__(answer, env, env_label)
        d = self.data
        raw = d.get("cycles") if answer.kind == "controller" else [d]
        if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
            raise MalformedFile(f"{answer.path}: cycles: expected a list of cycle answers")
        self.cycles = []
        for i, cyc in enumerate(raw):
            stages = cyc.get("cycle") or []
            entry = cyc.get("entry") or []
            if not isinstance(stages, list) or not isinstance(entry, list):
                raise MalformedFile(f"{answer.path}: cycle and entry must be lists of stages")
            for k, st in enumerate(stages):
                if not isinstance(st, dict):
                    raise MalformedFile(f"{answer.path}: cycle[{k}]: expected a stage object")
                _heading_interval(st.get("interval"), f"{answer.path}: cycle[{k}].interval")
                self.edge_id(st.get("from_edge"), f"cycle[{k}].from_edge")
            self.cycles.append((cyc, entry, stages, _fixed_points(self, cyc.get("fixed_point") or [])))

    @property
    def title(self) -> str:
        d = self.data
        head = f"{self.env.name or self.env_label}: constant heading θ = {d.get('theta_exact') or _num(d.get('theta'))}"
        if self.answer.kind == "controller":
            return f"{head}: {len(self.cycles)} limit cycle(s), {d.get('status')}"
        return f"{head}: limit cycle of period {d.get('period')}, contraction {_num(d.get('contraction'), 4)}, {d.get('status')}"

    def layers(self) -> list[str]:
        out = []
        colours = (CYCLE_COLOR, "#b2182b", "#1b7837", "#7b3294", "#e08214")
        first = 0
        for i, (cyc, _entry, stages, points) in enumerate(self.cycles):
            out.append(_cycle_layers(self, stages, points, first=first, fans=False, colour=colours[i % len(colours)],
                                     gid=f"cycle-{i}", label=f"cycle {i + 1} stage"))
            first += len(stages)
        return out

    def numbers(self) -> str:
        d = self.data
        rows = [("status", str(d.get("status")))]
        keys = (("theta", "theta_exact", "proved", "bounces", "heading_margin") if self.answer.kind == "controller" else
                ("theta", "theta_exact", "theta_used", "method", "edges", "period", "contraction", "contraction_exact",
                 "scope", "start", "epsilon", "cycles_to_epsilon"))
        for key in keys:
            if key in d:
                v = d[key]
                rows.append((key, ", ".join(map(str, v)) if isinstance(v, list) else _num(v, 9)))
        if d.get("reason"):
            rows.append(("reason", str(d["reason"])))
        for key in ("lemma3", "theorem1"):
            if isinstance(d.get(key), (dict, list)):
                rows.append((key, json.dumps(d[key], ensure_ascii=False)))
        rows += _optimality_rows(d.get("optimality"))
        rows += _environment_rows(d)
        out = _table(rows, table_id="summary", exact=("contraction_exact", "environment sha256", "lemma3", "theorem1"))
        if self.answer.kind == "controller" and isinstance(d.get("tried"), list):
            out += "<h2>Headings tried</h2>" + _grid(["θ (exact)", "outcome"], [[str(t.get("theta_exact")), str(t.get("outcome"))]
                                                                             for t in d["tried"] if isinstance(t, dict)],
                                                     table_id="tried")
        for i, (cyc, entry, stages, points) in enumerate(self.cycles):
            if len(self.cycles) > 1:
                out += f"<h2>Cycle {i + 1}: contraction {_e(_num(cyc.get('contraction'), 6))}</h2>"
            out += _cycle_tables(entry, stages, points)
        return out

    def command(self, certificate_path: str | None) -> str:
        d = self.data
        if self.answer.kind == "controller":
            words = ["solverplan", "cycle", self.env_label, "--theta", "auto"]
            margin = d.get("heading_margin")
            if isinstance(margin, (int, float)) and abs(float(margin) - 1e-3) > 1e-15:
                words += ["--heading-margin", repr(float(margin))]
            if d.get("epsilon") is not None:
                words += ["--epsilon", _plain(d.get("epsilon"))]
        else:
            theta = d.get("theta_exact") or repr(d.get("theta"))
            words = ["solverplan", "cycle", self.env_label, "--theta", str(theta)]
            method = d.get("method")
            if method in ("theorem1", "iterate", "edges"):
                words += ["--method", str(method)]
            if method == "edges" and isinstance(d.get("edges"), list):
                words += ["--edges", ",".join(f"e{e}" for e in d["edges"])]
            if isinstance(d.get("start"), str):
                words += ["--start", d["start"]]
            if d.get("epsilon") is not None:
                words += ["--epsilon", _plain(d.get("epsilon"))]
        words += ["-o", self.answer.path]
        return shlex.join(words)

