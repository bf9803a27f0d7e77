"""The smart rule's θ modes against random and billiard bouncing on generated rectilinear floors (issue #26).

For each floor, a route between the two rooms farthest apart in the room tree: every rule of
``RULE_VARIANTS`` is simulated with seed 0 (the recommendation is made from these runs), then again with seed 1
(an independent check). Printed per route: mean bounces and success of each rule (seed 1), the recommended
rule, the fastest rule that arrived in every seed-1 run, and the ratio recommended / fastest (the acceptance
of #26 asks for at most 1.5).

    PYTHONPATH=. python benchmarks/rooms_rules.py [--trials 60] [--floors 8] [--seed 100]

``--seed`` is the first floor's generator seed (floor k uses seed + k) and shifts the simulation seeds (seed − 100
and seed − 99): a fresh value gives fresh floors and fresh runs.
"""

from __future__ import annotations

import argparse
import time

import networkx as nx

from solverplan.rectilinear import decompose_rooms
from solverplan.generators import generate
from solverplan.rectilinear.simulation import RULE_VARIANTS, compare_rules


def _far_route(dec) -> tuple[int, int]:
    tree = nx.Graph([tuple(pair) for pair in dec.tree])
    tree.add_nodes_from(range(len(dec.rooms)))
    a = max(nx.single_source_shortest_path_length(tree, 0).items(), key=lambda kv: (kv[1], -kv[0]))[0]
    b = max(nx.single_source_shortest_path_length(tree, a).items(), key=lambda kv: (kv[1], -kv[0]))[0]
    return a, b


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--trials", type=int, default=60)
    parser.add_argument("--floors", type=int, default=8)
    parser.add_argument("--seed", type=int, default=100)
    args = parser.parse_args()
    sim = args.seed - 100
    floors = []
    for k in range(args.floors):
        if k % 2 == 0:
            floors.append(generate("rectilinear", seed=args.seed + k, n_rooms=4 + k))
        else:
            floors.append(generate("polyomino", seed=args.seed + k, n_cells=6 + 2 * k))
    worst = 0.0
    began = time.perf_counter()
    for env in floors:
        dec = decompose_rooms(env)
        if len(dec.rooms) < 2:
            continue
        a, b = _far_route(dec)
        made = compare_rules(dec, a, b, rules=RULE_VARIANTS, trials=args.trials, seed=sim)
        check = compare_rules(dec, a, b, rules=RULE_VARIANTS, trials=args.trials, seed=sim + 1)
        rec = made.runs["smart"].advice
        assert rec is not None
        rows = {name: r for name, r in check.runs.items()}
        arrived = [n for n, r in rows.items() if r.always_arrived]
        fastest = min(arrived, key=lambda n: rows[n].bounces_mean) if arrived else None
        ratio = (rows[rec.rule].bounces_mean or float("inf")) / rows[fastest].bounces_mean if fastest else float("nan")
        worst = max(worst, ratio) if fastest else worst
        cells = "  ".join(f"{n} {r.bounces_mean or float('nan'):.0f}/{r.success:.2f}" for n, r in rows.items())
        print(f"{env.name[:40]:<40} rooms {len(dec.rooms):>2} route {a}->{b}: {cells}")
        print(f"    recommended {rec.rule}, fastest always-arriving (seed 1) {fastest}, ratio {ratio:.2f}")
    print(f"worst ratio {worst:.2f}; {time.perf_counter() - began:.0f} s")


if __name__ == "__main__":
    main()
