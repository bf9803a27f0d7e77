"""The picture: world coordinates to SVG pixels, and SVG elements with escaped attributes and tooltips."""

from __future__ import annotations

from typing import Iterable, Sequence


from solverplan.render.figure import PLAN_STAGE_COLORS

from solverplan.render.report._kinds import _MAX_HEIGHT, _PAD, _WIDTH
from solverplan.render.report.format import _e


class _Canvas:
    """World coordinates → SVG pixels (y up → y down), the bounding box fitted into the picture."""

    def __init__(self, bounds: tuple[float, float, float, float]) -> None:
        xmin, ymin, xmax, ymax = bounds
        w, h = max(xmax - xmin, 1e-12), max(ymax - ymin, 1e-12)
        self.scale = min((_WIDTH - 2 * _PAD) / w, (_MAX_HEIGHT - 2 * _PAD) / h)
        self.width = w * self.scale + 2 * _PAD
        self.height = h * self.scale + 2 * _PAD
        self.xmin, self.ymax = xmin, ymax

    def xy(self, x: float, y: float) -> tuple[float, float]:
        return (_PAD + (float(x) - self.xmin) * self.scale, _PAD + (self.ymax - float(y)) * self.scale)

    def points(self, pts: Iterable[Sequence[float]]) -> str:
        return " ".join("%.2f,%.2f" % self.xy(p[0], p[1]) for p in pts)

    def path(self, rings: Iterable[Iterable[Sequence[float]]]) -> str:
        out = []
        for ring in rings:
            pts = ["%.2f %.2f" % self.xy(p[0], p[1]) for p in ring]
            out.append("M" + " L".join(pts) + " Z")
        return " ".join(out)


def _el(tag: str, attrs: dict[str, object], title: str | None = None, body: str = "") -> str:
    """An SVG element with escaped attributes and an optional ``<title>`` (its tooltip and details text)."""
    text = "".join(f' {k}="{_e(v)}"' for k, v in attrs.items() if v is not None)
    inner = (f"<title>{_e(title)}</title>" if title else "") + body
    return f"<{tag}{text}>{inner}</{tag}>" if inner else f"<{tag}{text}/>"


def _line(c: _Canvas, a: Sequence[float], b: Sequence[float], attrs: dict[str, object], title: str | None = None) -> str:
    (x1, y1), (x2, y2) = c.xy(a[0], a[1]), c.xy(b[0], b[1])
    return _el("line", {"x1": f"{x1:.2f}", "y1": f"{y1:.2f}", "x2": f"{x2:.2f}", "y2": f"{y2:.2f}", **attrs}, title)


def _stage_colour(k: int) -> str:
    return PLAN_STAGE_COLORS[k % len(PLAN_STAGE_COLORS)]

