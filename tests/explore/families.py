"""The exploration paper's lower-bound families, now in the library (:mod:`solverplan.explore.families`)."""

from solverplan.explore.families import one_hole, spiral

__all__ = ["one_hole", "spiral"]
