"""
Funnels and localisation: contraction as a sensor
=================================================

A robot that knows only that it is *somewhere* on a wall can still reach a narrow doorway: each bounce into a
corner that contracts shrinks the set of its possible positions (the paper's Fig. 14, a plan its own planner
could not find). :func:`solverplan.funnel` tracks that set exactly, stage by stage, until it fits inside the goal;
:func:`solverplan.localize` asks only that it ends narrower than ε.
"""

import matplotlib.pyplot as plt

import solverplan as sp
from solverplan.render import scene

square = sp.load_environment("square")
funnel = sp.funnel(square, "e0", "e2:0.45:0.55", tolerance=0.005)
print(funnel.to_text())

# %%
# The arc length of the possible positions before the first stage and after each one.
fig, ax = plt.subplots(figsize=(5, 3), layout="constrained")
ax.semilogy(range(len(funnel.widths)), funnel.widths, "o-")
ax.set_xlabel("stage")
ax.set_ylabel("width of the position set")
ax.set_title("funnel in square: from all of e0 into 10 % of e2")

# %%
# The stages and their position sets on the walls.
fig = scene(square, answer=funnel, edge_ids=True)

# %%
# Localisation from anywhere on the triangle's base: the final position set is narrower than 0.05.
triangle = sp.load_environment("triangle")
where = sp.localize(triangle, 0.05, start="e0", tolerance=0.002)
print(where.status.value, "final positions:", where.goal, "after", len(where.stages), "bounces")
