"""
From an occupancy map to a certified plan
=========================================

A mobile robot's map comes from SLAM as a ROS ``map_server`` map: a YAML file and an occupancy image. This script
writes a small one (two rooms joined by a door, 5 cm cells, a ragged wall and stray returns), reads it back with
:func:`solverplan.import_floorplan` — the free component is traced into an outer ring with holes in world
coordinates, simplified within 10 cm and snapped to the axes — and plans through the door.
"""

import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

import solverplan as sp
from solverplan.render import scene

FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # the values ROS's map_saver writes
rng = np.random.default_rng(7)
image = np.full((80, 140), UNKNOWN, np.uint8)  # 80 rows × 140 columns of 5 cm: 7 m × 4 m
image[10:70, 10:130] = OCCUPIED  # the building's walls ...
image[13:67, 13:68] = FREE  # ... the left room ...
image[13:67, 72:127] = FREE  # ... the right room ...
image[35:50, 68:72] = FREE  # ... and the door between them
image[30:40, 30:40] = OCCUPIED  # a cupboard in the left room
ragged = rng.random(image.shape) < 0.02  # sensor noise: stray cells flipped along the free space
image[ragged & (image == FREE)] = OCCUPIED

folder = Path(tempfile.mkdtemp())
Image.fromarray(image).save(folder / "rooms.pgm")
(folder / "rooms.yaml").write_text("image: rooms.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                                   "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
# every obstacle down to 2.5 cm is kept by default (posts, table legs); the stray returns here are 5 cm cells
# (one or two at a time), so --min-obstacle 0.12 leaves them out — each one listed in ``imported.features`` with where it was
imported = sp.import_floorplan(folder / "rooms.yaml", simplify=0.1, rectilinear=10, min_obstacle=0.12)
print(imported.to_text())
specks = [f for f in imported.features if f.kind == "speckle"]
print(len(specks), "stray cells left out, the first at", specks[0].at, "m")
env = imported.environment

# %%
# A plan from the left room's far wall to the right room's far wall: the outer ring's vertex 0 is where the trace
# starts, so the walls are found by position rather than by number.
mid_x = (env.edge_start[:, 0] + env.edge_end[:, 0]) / 2  # metres
outer = [i for i in range(env.n_edges) if env.ring_of[i] == 0]
far_left, far_right = min(outer, key=lambda i: mid_x[i]), max(outer, key=lambda i: mid_x[i])
plan = sp.find_plan(env, f"e{far_left}", f"e{far_right}")
print(plan.to_text())

fig = scene(env, plan=plan, edge_ids=True)
