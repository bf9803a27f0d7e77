"""
Rooms and doors: three bounce rules compared
=============================================

Çağırıcı, Bahoo and LaValle split a rectilinear polygon into rooms joined by doors (their Algorithm 1) and send a
sensorless robot from room to room, comparing three bounce rules: *billiard* (angle in = angle out), *random* and
their *smart* rule, which alternates between the inward normal and a tilt θ chosen so that each crossing of a room
advances sideways by one door width. :func:`solverplan.decompose_rooms` makes the rooms (exact doors, the room
adjacency a tree); :func:`solverplan.compare_rules` simulates the rules from one room to another with the doors on
the way opened by a controller.
"""

import solverplan as sp
from solverplan.render import render_rooms

env = sp.load_environment("warehouse")
dec = sp.decompose_rooms(env)
print(f"{len(dec.rooms)} rooms, {len(dec.doors)} doors")

# %%
# From room 0 to room 14 (see the numbers in the picture), 60 trials of each rule, one trajectory kept per rule.
comparison = sp.compare_rules(dec, 0, 14, trials=60, seed=1, keep=1)
print(comparison.to_text())

fig = render_rooms(dec, {name: runs.trajectories[0] for name, runs in comparison.runs.items() if runs.trajectories})
