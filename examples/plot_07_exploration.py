"""
Exploring an unknown polygon with few views
===========================================

Ghosh, Burdick, Bhattacharya and Sarkar's Algorithm A: a robot that sees only where it stops moves to a point on
a *constructed edge* of its current view (the edge a ray grazing a reflex vertex cuts through free space), and
backtracks when no such edge leads anywhere new. Their Theorem 1: it needs at most r + 1 views, r the reflex
vertices of the free space (a hole's convex corners count). :func:`solverplan.explore_depth_first` runs it with
exact views.
"""

import solverplan as sp
from solverplan.render import render_exploration

env = sp.load_environment("spiral")
run = sp.explore_depth_first(env, (1, 1))
print(run.to_text())

# %%
# The bound of Theorem 1 holds, and the union of the views is the whole free space.
print(f"{len(run.views)} views for r = {run.reflex} reflex vertices (bound r + 1 = {run.bound}); "
      f"covered {run.covered_fraction:.6f} of the area")

fig = render_exploration(run, env)
