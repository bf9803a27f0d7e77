"""
A patrol that shrinks its own uncertainty
=========================================

A patrol visits a given sequence of walls in cyclic order forever (the paper's Def. 15). With non-deterministic
headings the robot's position is a set; if the cycle's return map contracts, that set shrinks every lap, so the
robot ends up on a narrow limit cycle however imprecise it is within the tolerance. :func:`solverplan.patrol`
finds such cycles through the floor ``e0`` and the ceiling ``e2`` of ``square``, optimal for one of two objectives.
"""

import solverplan as sp
from solverplan.render import scene

env = sp.load_environment("square")

# %%
# ``contraction``: for a heading tolerance of ±0.01 rad, the cycle whose worst-case contraction per lap is least.
# It runs into the corners at shallow angles, where each bounce contracts most.
tightest = sp.patrol(env, "e0,e2", tolerance=0.01)
print(tightest.to_text())

# %%
# ``tolerance``: the widest heading intervals with which the cycle still contracts: the sloppiest robot that
# can patrol these walls at all. Its contraction per lap is just below 1.
widest = sp.patrol(env, "e0,e2", objective="tolerance")
print(f"{widest.status.value}: tolerance ±{widest.tolerance:.4f} rad, contraction {widest.contraction:.4f} per lap")

fig = scene(env, answer=widest, edge_ids=True)
