"""
A patrol that shrinks its own uncertainty
=========================================

A patrol visits a given sequence of walls in cyclic order forever (the paper's Def. 15). With non-deterministic
headings the robot's position is a set; if the cycle's return map contracts, that set shrinks every lap, so the
robot ends up on a narrow limit cycle whatever its precision within ``tolerance``. :func:`solverplan.patrol`
finds the cycle through the floor and the ceiling of ``square`` with the least worst-case contraction per lap.
"""

import solverplan as sp
from solverplan.render import scene

env = sp.load_environment("square")
patrol = sp.patrol(env, "e0,e2", tolerance=0.01, epsilon=0.05)
print(patrol.to_text())

# %%
# Contraction per lap below 1 is the proof that uncertainty shrinks; its value is a worst case over every heading
# in the intervals.
print(f"{patrol.status.value}: contraction {patrol.contraction:.4g} per lap, {len(patrol.cycle)} bounces per lap")

fig = scene(env, answer=patrol, edge_ids=True)
