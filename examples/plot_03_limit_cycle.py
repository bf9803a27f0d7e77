"""
A limit cycle in a convex polygon (Theorem 1)
=============================================

In a convex polygon a robot that always leaves the wall at one small constant heading θ visits the edges in
counter-clockwise order forever, and every start converges to one period-n cycle (the paper's Lemma 3 and
Theorem 1). :func:`solverplan.limit_cycle` finds that cycle and proves it in exact arithmetic: the return map of a
lap is affine with rational coefficients, its contraction is ``|α|`` and its fixed point is ``β / (1 − α)``.
A heading given as ``tan:P/Q`` is exact.
"""

import solverplan as sp
from solverplan.render import scene

env = sp.load_environment("irregular_convex")
cycle = sp.limit_cycle(env, "tan:1/4", epsilon=0.01)
print(cycle.to_text())
# tan(θ) = 1/4 lies inside Lemma 3's range, so the cycle attracts every start (scope ``every-start``); try
# ``tan:1/3``, just above it: the cycle still exists and contracts, but only the starts in its basins reach it.

# %%
# The contraction per lap, exact and as a float, and where the cycle touches each edge.
print("contraction per lap:", cycle.contraction_exact, "≈", float(cycle.contraction))
print("contact points (edge, t):", [(p.edge, str(p.t)) for p in cycle.points])

# %%
# Twenty rollouts of the same constant rule from random starts, and the cycle they converge to (bold).
fig = scene(env, cycle="tan:1/4", trajectories=20, rule="fixed:" + str(cycle.theta), bounces=30, edge_ids=True)
