"""Strategy 6 (contact and pebble sensors only) against Strategy 2 (gap sensor, complete) on random simple polygons
(issue #26): how often the contact-only pursuer finds a plan when one exists, and that every plan it finds is
confirmed by the geometric ground-truth checker.

    PYTHONPATH=. python benchmarks/strategy6.py [--polygons 200] [--vertices 6] [--seed 1]
"""

from __future__ import annotations

import argparse
import random

import shapely

from solverplan.environment import Environment
from solverplan.errors import InvalidEnvironment
from solverplan.wallfollow import cuts
from solverplan.wallfollow.pursuit import pursuit_plan


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--polygons", type=int, default=200)
    parser.add_argument("--vertices", type=int, default=6)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    tried = solvable = solved = verified = 0
    by_length: dict[int, list[int]] = {}
    while tried < args.polygons:
        ring = [(rng.randint(0, 1000), rng.randint(0, 1000)) for _ in range(args.vertices)]
        if not shapely.Polygon(ring).is_valid:
            continue
        try:
            env = Environment.from_coords(ring)
            cuts(env)
        except InvalidEnvironment:
            continue
        if not env.reflex_vertices:
            continue
        tried += 1
        gap = pursuit_plan(env, sensor="gap")
        if gap.status.value != "found":
            continue
        solvable += 1
        row = by_length.setdefault(len(gap.actions), [0, 0])
        row[0] += 1
        contact = pursuit_plan(env, sensor="contact")
        if contact.status.value == "found":
            solved += 1
            row[1] += 1
            verified += bool(contact.check is not None and contact.check.valid)
    print(f"{tried} polygons with {args.vertices} vertices: {solvable} have a plan (gap sensor); Strategy 6 finds "
          f"{solved} ({verified} confirmed by the geometric checker)")
    for length in sorted(by_length):
        total, found = by_length[length]
        print(f"  shortest plan {length} actions: {found}/{total} found by Strategy 6")


if __name__ == "__main__":
    main()
