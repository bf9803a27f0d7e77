"""Batch ray casting speed: rays per second of :class:`solverplan.geometry.RayCaster`.

Run ``python benchmarks/bench_raycast.py`` (from the repository root, with the package installed):
it prints a markdown table (edges, holes, rays, seconds, rays/s) for polygons of 10, 100, 1,000
and 10,000 edges with holes, each hit by 10^5 rays from random boundary points at random headings
(float batch caster), then a table of exact casting (Algorithm 1's rays through reflex vertices,
batch ``cast_exact`` against the scalar ``cast_ray``). Results are recorded in ``benchmarks/README.md``.

The polygons are made here: a star-shaped outer ring (integer coordinates, radii alternating
in and out) around a square grid of small square holes.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from solverplan.environment import Environment
from solverplan.geometry.raycast import RayCaster, cast_ray


def star_with_holes(outer_vertices: int, holes_per_side: int, *, radius: int = 1_000_000, seed: int = 0) -> Environment:
    """A star-shaped ring of ``outer_vertices`` integer vertices with ``holes_per_side``² square holes.

    Vertex k sits at angle 2πk/n with radius alternating between ~R and ~0.75 R (plus jitter), so
    half the vertices are reflex; the holes fill a square of half-side 0.45 R, well inside.
    """
    rng = np.random.default_rng(seed)
    outer = []
    for k in range(outer_vertices):
        angle = 2 * math.pi * k / outer_vertices
        r = radius * ((1.0 if k % 2 == 0 else 0.75) + 0.05 * rng.uniform(-1, 1))
        outer.append((round(r * math.cos(angle)), round(r * math.sin(angle))))
    holes = []
    if holes_per_side:
        half = 0.45 * radius
        spacing = 2 * half / holes_per_side
        side = spacing / 3
        for i in range(holes_per_side):
            for j in range(holes_per_side):
                cx = -half + (i + 0.5) * spacing
                cy = -half + (j + 0.5) * spacing
                x0, y0 = round(cx - side / 2), round(cy - side / 2)
                x1, y1 = round(cx + side / 2), round(cy + side / 2)
                holes.append([(x0, y0), (x0, y1), (x1, y1), (x1, y0)])
    return Environment.from_coords(outer, holes, name=f"star{outer_vertices}+{len(holes)}holes")


# (outer vertices, holes per side): 10, 100, 1,000 and 10,000 edges (4 per hole)
SIZES = [(6, 1), (64, 3), (600, 10), (5904, 32)]


def run(rays: int, seed: int, sizes=SIZES, repeat: int = 3) -> list[dict]:
    rows = []
    for outer_vertices, per_side in sizes:
        t0 = time.perf_counter()
        env = star_with_holes(outer_vertices, per_side, seed=seed)
        validate = time.perf_counter() - t0
        t0 = time.perf_counter()
        caster = RayCaster(env)
        build = time.perf_counter() - t0
        rng = np.random.default_rng(seed)
        edges = rng.integers(0, env.n_edges, rays)
        t = rng.uniform(0.0, 1.0, rays)
        headings = rng.uniform(0.0, math.pi, rays)
        headings = np.clip(headings, 1e-9, math.pi - 1e-9)
        seconds = math.inf
        for _ in range(repeat):  # best of `repeat`: the machine may be busy with something else
            t0 = time.perf_counter()
            hits = caster.cast_from_boundary(edges, t, headings)
            seconds = min(seconds, time.perf_counter() - t0)
        rows.append(
            {
                "edges": env.n_edges,
                "holes": len(env.holes),
                "rays": rays,
                "seconds": seconds,
                "rays/s": rays / seconds,
                "uncertain": int(hits.uncertain.sum()),
                "grid": "×".join(map(str, caster.grid_shape)) if not caster.brute_force else "brute force",
                "index build (s)": build,
                "validation (s)": validate,
            }
        )
    return rows


def run_exact(rays: int, seed: int, sizes=SIZES, scalar_rays: int = 1000) -> list[dict]:
    """Exact casting: rays from every reflex vertex away from random vertices (Algorithm 1's rays,
    all through a vertex), by the batch exact caster and by the scalar one."""
    rows = []
    for outer_vertices, per_side in sizes:
        env = star_with_holes(outer_vertices, per_side, seed=seed)
        caster = RayCaster(env)
        rng = np.random.default_rng(seed)
        reflex = np.array(env.reflex_vertices)
        r = reflex[rng.integers(0, len(reflex), rays)]
        v = rng.integers(0, env.n_vertices, rays)
        v = np.where(v == r, (v + 1) % env.n_vertices, v)
        verts = env.exact_vertices
        origins = [verts[i] for i in r.tolist()]
        directions = [(verts[i][0] - verts[j][0], verts[i][1] - verts[j][1]) for i, j in zip(r.tolist(), v.tolist())]
        t0 = time.perf_counter()
        hits = caster.cast_exact(origins, directions, through_vertices=True, skip_invalid=True)
        batch = time.perf_counter() - t0
        t0 = time.perf_counter()
        for origin, direction in zip(origins[:scalar_rays], directions[:scalar_rays]):
            try:
                cast_ray(env, origin, direction, through_vertices=True)
            except ValueError:
                pass
        scalar = (time.perf_counter() - t0) / min(rays, scalar_rays)
        rows.append(
            {
                "edges": env.n_edges,
                "rays": rays,
                "valid": sum(hit is not None for hit in hits),
                "cast_exact (s)": batch,
                "cast_exact rays/s": rays / batch,
                "cast_ray rays/s": 1 / scalar,
            }
        )
    return rows


def markdown(rows: list[dict]) -> str:
    head = list(rows[0])
    lines = ["| " + " | ".join(head) + " |", "|" + "---:|" * len(head)]
    for row in rows:
        cells = []
        for key in head:
            value = row[key]
            if key.endswith("rays/s"):
                cells.append(f"{value:,.0f}")
            elif isinstance(value, float):
                cells.append(f"{value:.3f}")
            elif isinstance(value, int):
                cells.append(f"{value:,}")
            else:
                cells.append(str(value))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=3, help="report the best of this many runs")
    parser.add_argument("--exact-rays", type=int, default=10_000, help="rays for the exact table (0: skip)")
    args = parser.parse_args()
    print(markdown(run(args.rays, args.seed, repeat=args.repeat)))
    if args.exact_rays:
        print()
        print(markdown(run_exact(args.exact_rays, args.seed)))


if __name__ == "__main__":
    main()
