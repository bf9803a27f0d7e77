"""Numbers and text for people: escaping, significant digits, angles, and exact numbers shortened for display
(the whole exact value stays in a tooltip)."""

from __future__ import annotations

import html
import re
from fractions import Fraction
import math
from typing import Sequence


from solverplan.errors import MalformedFile
from solverplan.result import finite_number


# ====================================================================== small helpers
def _e(value: object) -> str:
    """Text (or an attribute value) escaped for HTML and XML: every file-borne string goes through here."""
    return html.escape(str(value), quote=True)


def _num(value: object, digits: int = 6) -> str:
    """A number for people: floats to ``digits`` significant digits, the rest as text."""
    if isinstance(value, bool) or value is None:
        return {True: "yes", False: "no", None: "—"}[value]
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        return f"{value:.{digits}g}"
    return str(value)


def _plain(value: object) -> str:
    """A number for a command line: the shortest text that reads back as the same float (``0.1``, not ``0.1000…01``)."""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _rad(value: object) -> str:
    """An angle in radians with its degrees."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{float(value):.6g} rad ({math.degrees(float(value)):.4g}°)"
    return _num(value)


def _interval(iv: Sequence[float]) -> str:
    return f"[{float(iv[0]):.6g}, {float(iv[1]):.6g}] rad"


def _short_exact(text: object, limit: int = 40) -> str:
    """An exact number's text, cut with … past ``limit`` characters (the whole text stays in the tables)."""
    s = str(text)
    return s if len(s) <= limit else s[: limit - 1] + "…"


def _heading_interval(value: object, where: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise MalformedFile(f"{where}: expected [lo, hi]")
    lo, hi = finite_number(value[0], f"{where}[0]"), finite_number(value[1], f"{where}[1]")
    if not 0 < lo <= hi < math.pi:
        raise MalformedFile(f"{where}: [{value[0]}, {value[1]}] is not inside (0, π)")
    return lo, hi


class Exact(str):
    """Text holding exact numbers (``"280190461600097/905779590829372"``, ``"t ↦ -1/2 · t + 3/4"``): tables show it
    shortened (:func:`shorten_exact`) with the whole text as the cell's tooltip."""


_RATIONAL = re.compile(r"-?\d+(?:\.\d+)?(?:/\d+)?")


def shorten_exact(text: str, limit: int = 14) -> str:
    """Every exact number in ``text`` longer than ``limit`` characters as a decimal of 9 significant digits (≈).

    >>> shorten_exact("1/3"), shorten_exact("280190461600097/905779590829372")
    ('1/3', '≈0.30933625')
    """
    def short(m: re.Match[str]) -> str:
        token = m.group(0)
        if len(token) <= limit:
            return token
        value = Fraction(token)
        return f"≈{float(value):.9g}"

    return _RATIONAL.sub(short, text)


def cell_html(value: object) -> str:
    """A table cell's content: escaped text, or for :class:`Exact` text its short form with the whole text as tooltip."""
    if isinstance(value, Exact):
        short = shorten_exact(str(value))
        if short != value:
            return f'<span class="exact-number" title="{_e(value)}">{_e(short)}</span>'
    return _e(value)
