"""Environments many tests share (small, exact, with edges numbered as the comments say)."""

from __future__ import annotations

from solverplan.environment import Environment

SQUARE = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
"""The 4 × 4 square: e0 floor (→ +x), e1 right wall (→ +y), e2 ceiling (→ −x), e3 left wall (→ −y)."""
