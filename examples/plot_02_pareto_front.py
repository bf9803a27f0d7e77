"""
Fewer bounces or more tolerance: the Pareto front
=================================================

Between two boundary sets there is usually a short plan that needs a precise robot and a longer one that
tolerates a sloppier heading. :func:`solverplan.pareto_front` answers every non-dominated pair
(bounces, tolerance) with one plan for each, each optimal for its bounce count.
"""

import matplotlib.pyplot as plt

import solverplan as sp

env = sp.load_environment("two_rooms")
front = sp.pareto_front(env, "e0:0.2:0.8", "e4:0.5:1")
print(front.to_text())

# %%
# Tolerance (radians, ±) against bounces: each point is a plan no other plan beats on both counts.
bounces = [point.bounces for point in front.points]
tolerances = [point.tolerance for point in front.points]
fig, ax = plt.subplots(figsize=(5, 3.2), layout="constrained")
ax.step(bounces, tolerances, where="post", color="0.6")
ax.plot(bounces, tolerances, "o", color="C0")
ax.set_xlabel("stages (bounces)")
ax.set_ylabel("tolerance ± (rad)")
ax.set_title(f"Pareto front on {env.name}")

# %%
# The fewest-bounce end of the front: three stages, but the robot must hold its heading to a quarter degree.
from solverplan.render import scene

shortest = front.points[0].plan
fig = scene(env, plan=shortest, trajectories=40, edge_ids=True)
