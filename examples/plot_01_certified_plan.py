"""
A plan, its certificate, and an independent check
=================================================

The most tolerant plan across the corridor of the shipped model ``two_rooms``: from the middle of the left
room's floor to the right half of the right room's floor. The start set spans four segments of the partition
P′, so one plan must work from all of them. The plan's claims are then written as exact rationals (a
certificate) and checked again in exact arithmetic by a checker that shares no code with the planner, and
10⁴ adversarial rollouts replay it in floating point.
"""

import solverplan as sp
from solverplan.render import scene

env = sp.load_environment("two_rooms")
plan = sp.find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")
print(plan.to_text())

# %%
# The certificate holds every stage's interval and landing segment as rationals; the check recomputes them.
cert = sp.certificate(plan, env=env)
report = sp.check_certificate(cert)
print("certificate valid:", report.valid)

runs = sp.simulate_plan(env, plan, trials=10_000, seed=1, sampling="endpoints")
print("rollouts that reached the goal:", runs.success_rate)

# %%
# Each stage's cone of headings, and 60 rollouts with headings drawn inside the intervals.
fig = scene(env, plan=plan, trajectories=60, edge_ids=True)
