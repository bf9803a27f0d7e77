"""
A certified plan
================

The most tolerant plan across the corridor of ``two_rooms``.
"""

import matplotlib.pyplot as plt

import solverplan as sp
from solverplan.render import scene

env = sp.load_environment("two_rooms")
plan = sp.find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")
print(plan.status, plan.tolerance)
