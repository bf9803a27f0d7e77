"""
Potential fields that bounce on purpose
=======================================

Stager and Tanner's robot follows a composed vector field through convex cells of the free space, and in turning
cells it may aim at a wall and let the collision turn it (the *reflection* scenario). On the shipped corridor
``serpentine`` (four turns cut at 45°), :func:`solverplan.navigate_fields` decomposes the free space, composes the
line fields cell by cell, verifies that each cell's field flows out through its outlet, and runs 25 noisy rollouts
of an inertial robot in each scenario: slow nominal fields (constrained), fast ones (unconstrained) and fast ones
that reflect. Every rollout reaches the goal; reflection is the fastest, as in the paper's Table I.
"""

import solverplan as sp
from solverplan.render.fields import render_fields

env = sp.load_environment("serpentine")
nav = sp.navigate_fields(env, (3, 2.25), (3, 0.25), trials=25, seed=0, trajectories=5)
print(nav.to_text())

# %%
# Mean time to goal per scenario (seconds), and the share of rollouts that arrived.
times = {name: round(s.time_mean, 3) for name, s in nav.runs.items()}
print(times, {name: s.success for name, s in nav.runs.items()})

fig = render_fields(nav)
