"""The view of a study: heatmaps per metric over the axes that vary, and the table of cells."""

from __future__ import annotations

import json
import math
import shlex
from dataclasses import dataclass, field
from typing import Any, Sequence


from solverplan.errors import MalformedFile

from solverplan.render.report._kinds import AnswerFile
from solverplan.render.report.format import _e, _num, _plain
from solverplan.render.report.page import _grid, _table
from solverplan.render.report.svg import _el


# ====================================================================== studies
@dataclass
class _Study:
    """A study: its identity, the means, a heatmap per metric over the (first two) axes that vary, the cells."""

    answer: AnswerFile
    notes: list[str] = field(default_factory=list)

    def render(self) -> str:
        d = self.answer.data
        ident = d["study"]
        if not isinstance(ident, dict):
            raise MalformedFile(f"{self.answer.path}: study: expected the study's identity object")
        cells = [c for c in d["cells"] if isinstance(c, dict)]
        grid: dict = ident["grid"] if isinstance(ident.get("grid"), dict) else {}
        axes = [str(a) for a in ident.get("axes", [])] if isinstance(ident.get("axes"), list) else []
        varying = [a for a in axes if isinstance(grid.get(a), list) and len(grid[a]) > 1]
        metrics = self.metrics(cells, set(axes))
        rows = [("study", str(ident.get("study"))), ("generator", str(ident.get("generator"))),
                ("seed", str(ident.get("seed"))), ("metric", json.dumps(ident.get("metric"), ensure_ascii=False)),
                ("grid", "; ".join(f"{a} = {', '.join(_num(v) for v in grid.get(a, []))}" for a in axes)),
                ("per cell", str(ident.get("per_cell"))), ("cells", str(len(cells))), ("rows", str(ident.get("rows")))]
        means = d.get("means")
        if isinstance(means, dict):
            rows += [(f"mean {k}", _num(v)) for k, v in means.items() if not isinstance(v, (dict, list))]
        heat = "".join(self.heatmap(cells, m, varying, grid) for m in metrics)
        if not heat:
            heat = "<p>No metric varies over two axes or one: see the table of cells.</p>"
        header = ["cell", *axes, *metrics]
        body = [[str(c.get("cell"))] + [_num(c.get(a)) for a in axes] + [_num(self.value(c, m)) for m in metrics]
                for c in cells]
        title = f"{ident.get('study')} study over {ident.get('generator')} environments"
        return (f'<section id="picture"><div id="heatmaps"><h2>{_e(title)}</h2>{heat}</div><div id="side"><h2>Details</h2>'
                '<div id="details" class="empty" aria-live="polite">Hover over a cell for its parameters and values.</div>'
                f'{"".join(f"<p>{_e(n)}</p>" for n in self.notes)}</div></section>'
                f'<section id="numbers"><h2>The study</h2>{_table(rows, table_id="summary", exact=("metric",))}'
                f'<h2>Cells</h2>{_grid(header, body, table_id="cells")}</section>'
                f'<section id="reproduce"><h2>Reproduce it</h2><pre><code id="command">{_e(self.command(ident, axes, grid))}'
                f"</code></pre><p>Answer file: <code>{_e(self.answer.path)}</code>.</p></section>")

    @staticmethod
    def value(cell: dict, metric: str) -> object:
        """A cell's value of a metric: a number (the study's answer) or the mean of its statistics (NAME.json)."""
        v = cell.get(metric)
        if isinstance(v, dict):
            return v.get("mean")
        return v

    def metrics(self, cells: Sequence[dict], axes: set[str]) -> list[str]:
        skip = axes | {"cell", "rows", "replicate", "seed", "seconds"}
        names: list[str] = []
        for c in cells:
            for k in c:
                v = self.value(c, k)
                if k not in skip and k not in names and isinstance(v, (int, float)) and not isinstance(v, bool):
                    names.append(k)
        return names

    def heatmap(self, cells: Sequence[dict], metric: str, varying: Sequence[str], grid: dict) -> str:
        if not varying:
            return ""
        ax_x = varying[-1]
        ax_y = varying[-2] if len(varying) > 1 else None
        # the axes' values in the grid's order (numbers, or the rule families of a rules study)
        xs: list[Any] = [v for v in grid[ax_x] if isinstance(v, (int, float, str))]
        ys: list[Any] = [v for v in grid[ax_y] if isinstance(v, (int, float, str))] if ax_y else [None]
        if not xs or not ys:
            return ""
        table: dict[tuple[object, object], list[float]] = {}
        for c in cells:
            v = self.value(c, metric)
            if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(float(v)):
                table.setdefault((c.get(ax_x), c.get(ax_y) if ax_y else None), []).append(float(v))
        if not table:
            return ""
        if len(varying) > 2 and not self.notes:
            self.notes.append(f"Heatmaps average the cells over {', '.join(varying[:-2])} (they vary too).")
        values = [sum(v) / len(v) for v in table.values()]
        vmin, vmax = min(values), max(values)
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        cw, ch, left, top = 56.0, 30.0, 70.0, 26.0
        # wide enough for the metric's name too (about 7 px a character at 12 px bold)
        width, height = max(left + cw * len(xs) + 10, left + 7.5 * len(metric) + 10), top + ch * len(ys) + 34
        parts = [_el("text", {"x": f"{left:.0f}", "y": "16", "font-size": "12", "font-weight": "700"}, body=_e(metric))]
        for iy, yv in enumerate(reversed(ys)):
            for ix, xv in enumerate(xs):
                vals = table.get((xv, yv))
                if not vals:
                    continue
                v = sum(vals) / len(vals)
                r, g, b, _ = cmap(0.5 if vmax == vmin else (v - vmin) / (vmax - vmin))
                colour = "#%02x%02x%02x" % (round(r * 255), round(g * 255), round(b * 255))
                where = f"{ax_x} = {_num(xv)}" + (f", {ax_y} = {_num(yv)}" if ax_y else "")
                x, y = left + cw * ix, top + ch * iy
                parts.append(_el("rect", {"x": f"{x:.0f}", "y": f"{y:.0f}", "width": f"{cw - 1:.0f}", "height": f"{ch - 1:.0f}",
                                          "fill": colour, "class": "hover cell"},
                                 f"{metric} = {v:.6g} at {where} (mean of {len(vals)} cell(s))"))
                ink = "#fff" if (r * 0.3 + g * 0.59 + b * 0.11) < 0.5 else "#000"
                parts.append(_el("text", {"x": f"{x + cw / 2:.0f}", "y": f"{y + ch / 2 + 4:.0f}", "font-size": "10",
                                          "text-anchor": "middle", "fill": ink}, body=_e(f"{v:.3g}")))
        for ix, xv in enumerate(xs):
            parts.append(_el("text", {"x": f"{left + cw * ix + cw / 2:.0f}", "y": f"{top + ch * len(ys) + 14:.0f}",
                                      "font-size": "10", "text-anchor": "middle"}, body=_e(_num(xv, 4))))
        parts.append(_el("text", {"x": f"{left + cw * len(xs) / 2:.0f}", "y": f"{top + ch * len(ys) + 29:.0f}",
                                  "font-size": "11", "text-anchor": "middle"}, body=_e(ax_x)))
        if ax_y:
            for iy, yv in enumerate(reversed(ys)):
                parts.append(_el("text", {"x": f"{left - 6:.0f}", "y": f"{top + ch * iy + ch / 2 + 4:.0f}",
                                          "font-size": "10", "text-anchor": "end"}, body=_e(_num(yv, 4))))
            parts.append(_el("text", {"x": "12", "y": f"{top + ch * len(ys) / 2:.0f}", "font-size": "11",
                                      "text-anchor": "middle", "transform": f"rotate(-90 12 {top + ch * len(ys) / 2:.0f})"},
                             body=_e(ax_y)))
        return (f'<svg class="heat" xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
                f'viewBox="0 0 {width:.0f} {height:.0f}" role="img" aria-label="{_e(metric)}">' + "".join(parts) + "</svg>")

    def command(self, ident: dict, axes: Sequence[str], grid: dict) -> str:
        words = ["solverplan", "study", str(ident.get("study")), "--generator", str(ident.get("generator")),
                 "--seed", str(ident.get("seed"))]
        for a in axes:
            values = grid.get(a)
            if isinstance(values, list) and values:
                if ident.get("study") == "rules" and a == "rule":  # the rule families are an option, not a grid axis
                    words += ["--rules", ",".join(map(str, values))]
                else:
                    words += ["--grid", f"{a}={','.join(_plain(v) for v in values)}"]
        if ident.get("per_cell") is not None:
            words += ["--per-cell", str(ident["per_cell"])]
        metric = ident.get("metric")
        if isinstance(metric, dict):
            for key, flag in (("family_size", "--family-size"), ("trials", "--trials"), ("bounces", "--bounces")):
                if metric.get(key) is not None:
                    v = metric[key]
                    words += [flag, ",".join(map(str, v)) if isinstance(v, list) else str(v)]
        return shlex.join(words)

