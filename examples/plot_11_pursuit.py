"""
Finding an evader with a wall-following robot
=============================================

Yershova et al.'s pursuer can only follow walls and jump past reflex vertices, yet it can guarantee to see an
evader who moves arbitrarily fast. :func:`solverplan.pursuit_plan` searches the derived information states (the
pursuer's place in the cut ordering and a 0/1 label per shadow component: may the evader be there?) for a shortest
plan that clears every label (Strategy 2, the gap sensor), and :func:`solverplan.check_pursuit` replays the plan
geometrically — exact shadow components along every motion, labels carried by overlap — independently of the
search. On the shipped ``three_arms`` five actions are enough.
"""

import solverplan as sp
from solverplan.render import render_pursuit

env = sp.load_environment("three_arms")
plan = sp.pursuit_plan(env, sensor="gap")
print(plan.to_text())

# %%
# The same plan found with the weaker bitangent sensor (Strategy 3 is complete too), and the independent replay.
weaker = sp.pursuit_plan(env, sensor="bitangent")
replay = sp.check_pursuit(env, plan.actions)
print("bitangent sensor:", " ".join(weaker.actions), "| verified by the geometric replay:", replay.valid)

# %%
# Weaker still: a pebble-visibility sensor. Strategy 4 first learns the bitangents by dropping the pebble and
# looking for it; Strategy 5 then runs Strategy 3's search on what it learned.
learned = sp.learn_bitangents(env)
weakest = sp.pursuit_plan(env, sensor="pebble")
print(f"pebble sensor: {' '.join(weakest.actions)} after {learned.actions} learning actions "
      f"({len(learned.bitangents)} bitangents)")

fig = render_pursuit(env, plan)
