"""
The wall-following robot: cut ordering, exact and learned
=========================================================

Yershova, Tovar, Katsev, Ghrist and LaValle's robot only follows walls, jumps off reflex vertices along the
edge it arrived on, and drops or grabs a pebble. Everything it can ever learn about the polygon is the *cut
ordering*: the counter-clockwise order of the vertices and of the end points of the cuts (each reflex vertex's two
edges continued to the boundary). :func:`solverplan.cut_ordering` computes it exactly from the geometry;
:func:`solverplan.learn_cut_ordering` runs their Strategy 1 in a simulator and learns the same ordering from the
robot's sensors alone.
"""

import solverplan as sp
from solverplan.render import render_cuts

env = sp.load_environment("star")
ordering = sp.cut_ordering(env)
print(" ".join(ordering.labels))

# %%
# Strategy 1 (INIT, DROP, follow, JUMP, compare end points with the pebble): the learned ordering, renamed by the
# vertex where the pebble was dropped, equals the exact one.
learned = sp.learn_cut_ordering(env)
print(learned.to_text())

fig = render_cuts(env, ordering)
