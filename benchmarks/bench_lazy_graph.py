"""The safe BVG built on demand against the whole build, on warehouse maps of several sizes (issue #24).

Run ``python benchmarks/bench_lazy_graph.py [--sizes 12x8,20x10,30x15] [--simplify 0.1]`` from the repository root.
For each size it draws a SLAM-style warehouse (``benchmarks/warehouse_map.py``), imports it (``--simplify`` and
``--rectilinear``; ``--simplify auto``, the default: the import's own defaults, inside the traced free space), and
measures in-process (CPU seconds, ``time.process_time``): the partition P′; the whole
safe BVG (arcs, safe arcs, time; skipped past ``--max-arcs`` estimated arcs); ``reachable_safe_graph`` from the
first edge's segments with budgets of 2 and 4 bounces and without one (arcs kept, sources reached, time); and a
tolerance plan from e0 to the edge half-way round, over each graph (status, width, whether they agree).

This script is not a test (nothing here is named ``test_*``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from warehouse_map import warehouse_map, write_map  # noqa: E402


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def main() -> None:
    from solverplan.bounce import _cache, bvg
    from solverplan.bounce.bvg import estimate_graph, reachable_safe_graph, safe_bounce_visibility_graph
    from solverplan.bounce.partitions import partition
    from solverplan.floorplan import import_floorplan
    from solverplan.plan.search import find_plan

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="12x8,20x10")
    parser.add_argument("--simplify", default="auto")
    parser.add_argument("--max-arcs", type=int, default=20_000_000)
    parser.add_argument("--rectilinear", type=float, default=None)
    options = parser.parse_args()
    folder = Path(tempfile.mkdtemp())
    print("| map (m) | vertices | holes | segments | partition s | whole: arcs / safe / s | budget | on demand: arcs / "
          "sources / s | plan whole (s) | plan on demand (s) | same answer |")
    print("|---|---:|---:|---:|---:|---|---|---|---|---|---|")
    for size in options.sizes.split(","):
        width, height = (float(x) for x in size.split("x"))
        yaml = write_map(folder, f"w{size}", warehouse_map(width, height, seed=1))
        simplify = None if options.simplify == "auto" else float(options.simplify)
        env = import_floorplan(yaml, simplify=simplify, rectilinear=options.rectilinear).environment
        _cache.clear_graph_cache()
        p, t_part = cpu(lambda: partition(env))
        N = len(p.segments)
        estimate = estimate_graph(p)[0]
        whole_text, t_whole = "–", None
        if estimate <= options.max_arcs:
            whole, t_whole = cpu(lambda: safe_bounce_visibility_graph(p))
            whole_text = f"{whole.n_arcs:,} / {whole.n_safe_arcs:,} / {t_whole:.1f}"
        else:
            whole_text = f"≈ {estimate:,} (not built)"
        goal = f"e{len(env.rings[0]) // 2}"
        starts = list(p.edge_segments[0])
        for budget in (2, 4, None):
            lazy, t_lazy = cpu(lambda: reachable_safe_graph(p, starts, max_depth=budget))
            row = (f"| {width:g} × {height:g} | {env.n_vertices:,} | {len(env.holes)} | {N:,} | {t_part:.1f} | "
                   f"{whole_text} | {budget if budget else 'none'} | {lazy.n_arcs:,} / "
                   f"{lazy.stats['reachable_sources']:,} / {t_lazy:.1f} |")
            if budget is None:
                plans = []
                for threshold in (10**12, 0):  # the whole graph (when it was built), then on demand
                    if threshold and t_whole is None:
                        plans.append((None, None))
                        continue
                    bvg.LAZY_MIN_ARCS = threshold
                    _cache.clear_graph_cache()
                    plans.append(cpu(lambda: find_plan(env, "e0", goal, objective="tolerance")))
                bvg.LAZY_MIN_ARCS = 2_000_000
                (pw, tw), (pl, tl) = plans
                same = "–" if pw is None else str(pw.status == pl.status and pw.min_width == pl.min_width)
                row += (f" {'–' if pw is None else f'{pw.status.value} {tw:.1f}'} | {pl.status.value} "
                        f"{pl.min_width if pl.min_width is None else round(pl.min_width, 4)} {tl:.1f} | {same} |")
            else:
                row += " | | |"
            print(row, flush=True)


if __name__ == "__main__":
    main()
