"""Reflections only where they pay (issue #26): the reflection scenario against the unconstrained controller on
generated corridors (square corners, 45° cuts, zigzags; two widths; corner cells), planned zones after the
payoff tests against every zone the geometry allows.

    PYTHONPATH=. python benchmarks/fields_payoff.py [--trials 25] [--seeds 2] [--first-seed 0]

Corridor seeds run from ``--first-seed`` (``--seeds`` of them); the simulations use 100 + the corridor's seed.
"""

from __future__ import annotations

import argparse
import time

from solverplan.reflection.navigation import navigate_fields
from tests.reflection.corridors import KINDS, corridor


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--trials", type=int, default=25)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--starts", default="fixed")
    parser.add_argument("--first-seed", type=int, default=0)
    args = parser.parse_args()
    worst = -1e9
    began = time.perf_counter()
    for kind in KINDS:
        for width in (0.4, 0.8):
            for seed in range(args.first_seed, args.first_seed + args.seeds):
                env, s, g = corridor(kind, 3, width, seed=seed)
                row = []
                for mode in ("payoff", "all"):
                    nav = navigate_fields(env, s, g, scenarios=("unconstrained", "reflection"), trials=args.trials,
                                          seed=100 + seed, cells="corners", reflections=mode, starts=args.starts)
                    u, r = nav.runs["unconstrained"].time_mean, nav.runs["reflection"].time_mean
                    cost = 100 * (r - u) / u
                    row.append((mode, nav.plan.reflection_cells, u, r, cost))
                    if mode == "payoff":
                        worst = max(worst, cost)
                text = "  ".join(f"{m}: zones {list(z)} refl {r:.3f} ({c:+.2f} %)" for m, z, u, r, c in row)
                print(f"{kind:<7} w={width} seed={seed}  unconstrained {row[0][2]:.3f}  {text}")
    print(f"worst cost of planned reflections: {worst:+.2f} %; {time.perf_counter() - began:.0f} s")


if __name__ == "__main__":
    main()
