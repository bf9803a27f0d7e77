"""Reflection-aware navigation with composed local potential fields (Stager and Tanner, "Composition of local
potential functions with reflection").

- :mod:`~solverplan.reflection.cells` — convex cells of the free space (exact), adjacency, cell sequences.
"""

from solverplan.reflection.cells import Cell, Decomposition, Side, decompose_free_space

__all__ = ["Cell", "Decomposition", "Side", "decompose_free_space"]
