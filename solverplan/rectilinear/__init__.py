"""Rooms and doors of rectilinear polygons (Çağırıcı, Bahoo and LaValle, "Bouncing robots in rectilinear polygons").

- :mod:`~solverplan.rectilinear.decomposition` — Algorithm 1: bottleneck segments from reflex vertices become
  virtual doors, the polygon splits into rooms along them, and rooms and doors form a tree (Remark 5).
"""

from solverplan.rectilinear.decomposition import Decomposition, Door, Room, decompose

__all__ = ["Decomposition", "Door", "Room", "decompose"]
