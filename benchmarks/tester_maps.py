"""An independent tester's SLAM warehouse maps (issue #24): many kinds of raw Nav2 maps, imported and planned across.

Run ``python benchmarks/tester_maps.py [--maps NAME,...] [--timeout 10] [--limit 60] [--keep DIR]`` from the
repository root (the package importable). Each map below is drawn from scratch here (not with
``warehouse_map.py``): a building outline in metres (rectangle, L, notched or chamfered, turned by any angle, walls
thick or thin), rack layouts (double rows with aisles, L-shaped racks, shelves with gaps, racks touching the walls,
rack interiors left unknown as a lidar sees them), round or square posts, then the lidar's artefacts (salt-and-pepper
specks, ragged wall edges, gaps in the walls through which free space leaks outside, dynamic-obstacle blobs, unknown
patches inside), written as PGM + YAML in trinary, scale or raw mode, optionally ``negate: 1``, with an origin offset
(negative or not) and a resolution of 0.025, 0.05 or 0.1 m.

For each map it runs, as whole processes (wall, user + system CPU and peak resident memory from ``wait4``):

1. ``solverplan import MAP.yaml -o ENV.json`` with the defaults, and with ``--simplify 0 --rectilinear 0`` for the
   traced vertices;
2. ``solverplan --graph-cache off plan ENV.json --from eI --to eJ --objective tolerance`` between the two outer
   walls (of at least a metre) whose midpoints are farthest apart, under ``--timeout LIMIT``; then the same with
   ``--timeout 10`` (the acceptance: within 12 s);
3. once, the first plan under a pseudo-terminal (``script -qc``), checking that a progress bar was drawn.

Each row is checked: exit codes, a traceback, the imported free space inside the traced free space (shapely), the
60 s / 2 GB of the acceptance, the 12 s of ``--timeout 10``. This script is not a test (nothing is named ``test_*``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_maps import CLI, child  # noqa: E402  (the process measurement only; the maps are drawn here)

FREE, OCCUPIED, UNKNOWN = 0, 1, 2


@dataclass(frozen=True)
class MapSpec:
    """What one tester map holds (metres, degrees)."""

    name: str
    width: float = 30.0
    height: float = 30.0
    resolution: float = 0.05
    outline: str = "rect"  # rect, L, notch, chamfer
    turn: float = 0.0  # degrees, the building drawn at an angle in the image
    wall: float = 0.15  # wall thickness
    layout: str = "rows"  # rows, L, gaps, touching, mixed, none
    rack_depth: float = 1.1
    aisle: float = 3.0
    posts: str = "square"  # square, round, none
    post_size: float = 0.3
    unknown_racks: bool = True  # rack interiors unknown (the lidar sees only their faces)
    unknown_patches: int = 3
    specks: float = 0.0005  # share of free cells turned occupied
    free_specks: float = 0.001  # share of unknown cells outside turned free (lidar beams through windows)
    ragged: float = 0.3  # probability a wall-face cell flips
    leaks: int = 2  # gaps in the outer wall leaking a fan of free space outside
    blobs: int = 4  # dynamic obstacles (people, forklifts) left in the map
    mode: str = "trinary"
    negate: int = 0
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    seed: int = 0
    extra: dict = field(default_factory=dict)


def _transform(points: np.ndarray, spec: MapSpec, margin: float) -> np.ndarray:
    """Building coordinates (metres) → image pixels (x right, y down) after the turn about the building's centre."""
    theta = math.radians(spec.turn)
    c, s = math.cos(theta), math.sin(theta)
    centred = points - (spec.width / 2, spec.height / 2)
    turned = centred @ np.array([[c, s], [-s, c]])
    size = _canvas_metres(spec, margin)
    x = (turned[:, 0] + size[0] / 2) / spec.resolution
    y = (size[1] / 2 - turned[:, 1]) / spec.resolution
    return np.column_stack((x, y))


def _canvas_metres(spec: MapSpec, margin: float) -> tuple[float, float]:
    theta = math.radians(spec.turn)
    c, s = abs(math.cos(theta)), abs(math.sin(theta))
    return (spec.width * c + spec.height * s + 2 * margin, spec.width * s + spec.height * c + 2 * margin)


def _outline(spec: MapSpec) -> list[tuple[float, float]]:
    w, h = spec.width, spec.height
    if spec.outline == "L":
        return [(0, 0), (w, 0), (w, h * 0.55), (w * 0.6, h * 0.55), (w * 0.6, h), (0, h)]
    if spec.outline == "notch":  # a loading dock cut into the bottom wall and an office block out of a corner
        return [(0, 0), (w * 0.3, 0), (w * 0.3, 1.5), (w * 0.55, 1.5), (w * 0.55, 0), (w, 0), (w, h * 0.8),
                (w * 0.8, h * 0.8), (w * 0.8, h), (0, h)]
    if spec.outline == "chamfer":  # two corners cut at 45° and one wall slanted
        cut = min(w, h) * 0.15
        return [(cut, 0), (w - cut, 0), (w, cut), (w, h), (w * 0.3, h), (0, h - cut * 2)]
    return [(0, 0), (w, 0), (w, h), (0, h)]


def _racks(spec: MapSpec, rng: np.random.Generator) -> list[list[tuple[float, float]]]:
    """Rack footprints (polygons in building metres) for the layout, inside the outline with room to walk."""
    w, h = spec.width, spec.height
    racks: list[list[tuple[float, float]]] = []
    d, aisle = spec.rack_depth, spec.aisle
    layout = spec.layout
    if layout == "none":
        return racks
    inset = 0.0 if layout == "touching" else 2.5
    x0, x1 = inset + spec.wall, w * (0.6 if spec.outline == "L" else 1.0) - inset - spec.wall
    y = 3.0
    top = h * (0.8 if spec.outline in ("notch",) else 1.0) - 3.0
    if spec.outline == "chamfer":
        top = h - min(w, h) * 0.3 - 2.0
    row = 0
    while y + 2 * d < top:
        kind = layout if layout != "mixed" else ("rows", "gaps", "L", "rows")[row % 4]
        if kind == "L":
            length = (x1 - x0) * 0.5
            racks.append([(x0 + 1, y), (x0 + 1 + length, y), (x0 + 1 + length, y + 2 * d), (x0 + 1 + 2 * d, y + 2 * d),
                          (x0 + 1 + 2 * d, y + 2 * d + 2.0), (x0 + 1, y + 2 * d + 2.0)])
            racks.append([(x0 + 3 + length, y), (x1 - 1, y), (x1 - 1, y + 2 * d), (x0 + 3 + length, y + 2 * d)])
            y += 2 * d + 2.0 + aisle
        elif kind == "gaps":
            x = x0 + 0.5
            while x < x1 - 2:
                bay = float(rng.uniform(2.0, 5.0))
                end = min(x + bay, x1 - 0.5)
                racks.append([(x, y), (end, y), (end, y + 2 * d), (x, y + 2 * d)])
                x = end + float(rng.uniform(0.3, 1.2))
            y += 2 * d + aisle
        else:  # rows: a double rack with a cross aisle in the middle
            mid = (x0 + x1) / 2
            racks.append([(x0, y), (mid - 1.5, y), (mid - 1.5, y + 2 * d), (x0, y + 2 * d)])
            racks.append([(mid + 1.5, y), (x1, y), (x1, y + 2 * d), (mid + 1.5, y + 2 * d)])
            y += 2 * d + aisle
        row += 1
    return racks


def _posts(spec: MapSpec, racks: list) -> list[tuple[float, float]]:
    if spec.posts == "none":
        return []
    w, h = spec.width, spec.height
    centres = []
    for px in np.arange(6.0, w - 3.0, 9.0):
        for py in np.arange(1.8, h - 1.0, 12.0):
            centres.append((float(px), float(py)))
    return centres


def draw_map(spec: MapSpec) -> np.ndarray:
    """The map's cells (FREE, OCCUPIED, UNKNOWN), image rows top to bottom."""
    from PIL import Image, ImageDraw

    rng = np.random.default_rng(spec.seed)
    margin = 1.0 + spec.wall
    cw, ch = _canvas_metres(spec, margin)
    width_px, height_px = int(math.ceil(cw / spec.resolution)), int(math.ceil(ch / spec.resolution))
    canvas = Image.new("L", (width_px, height_px), UNKNOWN)
    pen = ImageDraw.Draw(canvas)

    def poly(points: list, value: int) -> None:
        pts = _transform(np.asarray(points, float), spec, margin)
        pen.polygon([tuple(p) for p in pts.tolist()], fill=value)

    def band(a: tuple[float, float], b: tuple[float, float], thick: float, value: int) -> None:
        a_, b_ = np.asarray(a, float), np.asarray(b, float)
        direction = (b_ - a_) / max(np.linalg.norm(b_ - a_), 1e-9)
        normal = np.array([-direction[1], direction[0]]) * thick / 2
        a_ -= direction * thick / 2
        b_ += direction * thick / 2
        poly([a_ + normal, b_ + normal, b_ - normal, a_ - normal], value)

    outline = _outline(spec)
    poly(outline, FREE)
    for k, a in enumerate(outline):
        band(a, outline[(k + 1) % len(outline)], spec.wall, OCCUPIED)
    racks = _racks(spec, rng)
    for rack in racks:
        poly(rack, OCCUPIED)
    cells = np.array(canvas, np.uint8)
    if spec.unknown_racks:  # the lidar sees a rack's faces; its inside stays unknown
        inner = Image.new("L", (width_px, height_px), 0)
        inner_pen = ImageDraw.Draw(inner)
        for rack in racks:
            pts = np.asarray(rack, float)
            centre = pts.mean(axis=0)
            shrunk = centre + (pts - centre) * 0.8
            inner_pen.polygon([tuple(p) for p in _transform(shrunk, spec, margin).tolist()], fill=1)
        cells[np.array(inner, bool) & (cells == OCCUPIED)] = UNKNOWN
    canvas = Image.fromarray(cells)
    pen = ImageDraw.Draw(canvas)
    for (px, py) in _posts(spec, racks):
        r = spec.post_size / 2
        if spec.posts == "round":
            centre = _transform(np.array([[px, py]]), spec, margin)[0]
            rp = r / spec.resolution
            pen.ellipse([centre[0] - rp, centre[1] - rp, centre[0] + rp, centre[1] + rp], fill=OCCUPIED)
        else:
            poly([(px - r, py - r), (px + r, py - r), (px + r, py + r), (px - r, py + r)], OCCUPIED)
    # dynamic obstacles: irregular blobs in the aisles (a person, a pallet truck caught mid-scan)
    for _ in range(spec.blobs):
        bx, by = float(rng.uniform(2, spec.width - 2)), float(rng.uniform(2, spec.height - 2))
        sizes = rng.uniform(0.2, 0.8, size=7)
        angles = np.sort(rng.uniform(0, 2 * math.pi, size=7))
        poly([(bx + s * math.cos(t), by + s * math.sin(t)) for s, t in zip(sizes, angles)], OCCUPIED)
    cells = np.array(canvas, np.uint8)
    # unknown patches inside (shadows behind clutter the scan never saw)
    for _ in range(spec.unknown_patches):
        cx, cy = int(rng.integers(0, cells.shape[1])), int(rng.integers(0, cells.shape[0]))
        rw, rh = int(rng.integers(4, 30)), int(rng.integers(4, 30))
        patch = cells[cy:cy + rh, cx:cx + rw]
        patch[patch == FREE] = UNKNOWN
    # ragged edges: every free cell next to an occupied one flips with probability ragged (both ways)
    occ = cells == OCCUPIED
    near = np.zeros_like(occ)
    near[1:] |= occ[:-1]
    near[:-1] |= occ[1:]
    near[:, 1:] |= occ[:, :-1]
    near[:, :-1] |= occ[:, 1:]
    face = near & (cells == FREE)
    flips = face & (rng.random(cells.shape) < spec.ragged)
    cells[flips] = OCCUPIED
    inner_face = occ & np.roll(cells == FREE, 1, axis=0) & (rng.random(cells.shape) < spec.ragged / 3)
    cells[inner_face] = FREE
    # leaks: gaps in the outer wall, with a fan of free cells outside (the lidar's beams through a door left open)
    for _ in range(spec.leaks):
        k = int(rng.integers(0, len(outline)))
        a, b = np.asarray(outline[k], float), np.asarray(outline[(k + 1) % len(outline)], float)
        t = float(rng.uniform(0.2, 0.8))
        at = a + t * (b - a)
        direction = (b - a) / np.linalg.norm(b - a)
        outward = np.array([direction[1], -direction[0]])  # the outline runs counter-clockwise
        gap = float(rng.uniform(0.1, 0.4))
        fan = [at - direction * gap / 2 - outward * spec.wall, at + direction * gap / 2 - outward * spec.wall,
               at + direction * (gap / 2 + 0.6) + outward * (spec.wall + 0.8),
               at - direction * (gap / 2 + 0.6) + outward * (spec.wall + 0.8)]
        pts = _transform(np.asarray(fan), spec, margin)
        leak = Image.new("L", (width_px, height_px), 0)
        ImageDraw.Draw(leak).polygon([tuple(p) for p in pts.tolist()], fill=1)
        cells[np.array(leak, bool)] = FREE
    # salt and pepper
    free = cells == FREE
    cells[free & (rng.random(cells.shape) < spec.specks)] = OCCUPIED
    unknown = cells == UNKNOWN
    cells[unknown & (rng.random(cells.shape) < spec.free_specks)] = FREE
    return cells


def write_map(folder: Path, spec: MapSpec, cells: np.ndarray) -> Path:
    """Write ``cells`` as PGM + YAML in the spec's mode; returns the YAML's path."""
    from PIL import Image

    rng = np.random.default_rng(spec.seed + 1)
    if spec.mode == "raw":  # occupancy in percent: 0 free, 100 occupied, 255 unknown
        values = np.where(cells == FREE, 0, np.where(cells == OCCUPIED, 100, 255)).astype(np.uint8)
        thresholds = "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    elif spec.mode == "scale":  # grey levels as a map_saver in scale mode writes them: noisy probabilities
        free_v = 255 - rng.integers(0, 30, size=cells.shape)
        occ_v = rng.integers(0, 60, size=cells.shape)
        unk_v = rng.integers(120, 150, size=cells.shape)
        values = np.where(cells == FREE, free_v, np.where(cells == OCCUPIED, occ_v, unk_v)).astype(np.uint8)
        thresholds = "occupied_thresh: 0.65\nfree_thresh: 0.25\n"
    else:
        values = np.where(cells == FREE, 254, np.where(cells == OCCUPIED, 0, 205)).astype(np.uint8)
        thresholds = "occupied_thresh: 0.65\nfree_thresh: 0.25\n"
    if spec.negate:
        if spec.mode == "raw":
            raise ValueError("negate is not read in raw mode")
        values = 255 - values
    Image.fromarray(values).save(folder / f"{spec.name}.pgm")
    ox, oy, yaw = spec.origin
    yaml = folder / f"{spec.name}.yaml"
    yaml.write_text(f"image: {spec.name}.pgm\nmode: {spec.mode}\nresolution: {spec.resolution}\n"
                    f"origin: [{ox}, {oy}, {yaw}]\nnegate: {spec.negate}\n{thresholds}")
    return yaml


MAPS = [
    MapSpec("rows_30x30", 30, 30),
    MapSpec("thin_20x20_0025", 20, 20, resolution=0.025, wall=0.08, posts="round", origin=(-10.0, -10.0, 0.0)),
    MapSpec("turned17_30x40", 30, 40, turn=17, layout="gaps", seed=3),
    MapSpec("L_40x40_scale", 40, 40, outline="L", layout="L", mode="scale", seed=4, origin=(-12.5, 3.25, 0.0)),
    MapSpec("notch_40x30_negate", 40, 30, outline="notch", layout="touching", negate=1, seed=5, wall=0.3),
    MapSpec("chamfer_30x30_raw", 30, 30, outline="chamfer", layout="mixed", mode="raw", seed=6, posts="round"),
    MapSpec("coarse_60x50_01", 60, 50, resolution=0.1, layout="mixed", seed=7, wall=0.3),
    MapSpec("big_60x50", 60, 50, layout="rows", seed=8, specks=0.0002),
    MapSpec("turned33_40x30", 40, 30, turn=33, layout="mixed", seed=9, posts="round", origin=(-5.5, -7.25, 0.0)),
    MapSpec("yaw_30x30", 30, 30, layout="gaps", seed=10, origin=(2.0, -3.0, 0.3)),
    MapSpec("fine_60x50_0025", 60, 50, resolution=0.025, layout="rows", seed=11, wall=0.2, specks=0.0002),
    MapSpec("thick_25x20_turned5", 25, 20, turn=5, wall=0.6, layout="touching", posts="round", post_size=0.5,
            seed=12, blobs=8, leaks=4, origin=(-100.25, -40.5, 0.0)),
]


def measured(args: list[str], timeout: float, tty: bool = False) -> tuple[float, float, float, int, str, str]:
    """(wall s, CPU s, peak MB, exit code, stdout, stderr) of one command as a whole process, alone in a helper
    process (``bench_maps.child``); ``tty``: under a pseudo-terminal (``script``), as a user at a terminal runs it."""
    if tty:
        args = ["script", "-qefc", " ".join(map(str, args)), "/dev/null"]
    w, c, m, done = child(args, timeout)
    return w, c, m, done.returncode, done.stdout, done.stderr


def far_walls(env_file: Path) -> tuple[str, str]:
    """Two outer edges of at least a metre (else the longest) whose midpoints are farthest apart."""
    data = json.loads(env_file.read_text())
    outer = np.asarray([[float(v) for v in p] for p in data["outer"]], float)
    nxt = np.roll(outer, -1, axis=0)
    length = np.linalg.norm(nxt - outer, axis=1)
    mids = (outer + nxt) / 2
    ok = np.flatnonzero(length >= min(1.0, float(length.max())))
    d = np.linalg.norm(mids[ok, None] - mids[None, ok], axis=2)
    i, j = np.unravel_index(int(np.argmax(d)), d.shape)
    return f"e{ok[i]}", f"e{ok[j]}"


def check_inside(yaml: Path, env_file: Path, min_obstacle: float = 0.06) -> str:
    """'ok' when the imported free space lies inside the traced free space (shapely, 1 µm slack), else how far out.

    The traced free space here is the free cells with the lidar specks the import drops by default filled in
    (obstacles of 8-connected non-free cells whose bounding box is below ``min_obstacle``: each is listed by the
    import); everything else the import adds to the free space is an error.
    """
    import shapely
    from scipy import ndimage

    from solverplan.environment import load_environment
    from solverplan.floorplan.occupancy import cells_to_polygons, read_occupancy_map

    grid = read_occupancy_map(yaml)
    env = load_environment(env_file)
    imported = shapely.Polygon([(float(x), float(y)) for x, y in env.outer],
                               [[(float(x), float(y)) for x, y in h] for h in env.holes])
    blobs, _ = ndimage.label(~grid.free, structure=np.ones((3, 3), bool))
    filled = grid.free.copy()
    for label, box in enumerate(ndimage.find_objects(blobs), start=1):
        extent = max(box[0].stop - box[0].start, box[1].stop - box[1].start) * float(grid.resolution)
        if extent < min_obstacle:
            filled[box] |= blobs[box] == label
    free = cells_to_polygons(grid, filled)
    outside = imported.difference(free.buffer(1e-6))
    return "ok" if outside.area < 1e-9 else f"{outside.area:.4f} m² outside"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", default=",".join(m.name for m in MAPS))
    parser.add_argument("--limit", type=float, default=60.0, help="--timeout of the full plan (s)")
    parser.add_argument("--timeout", type=float, default=10.0, help="the short --timeout to check (s)")
    parser.add_argument("--keep", type=Path, help="write the maps and environments here")
    parser.add_argument("--no-plan", action="store_true")
    parser.add_argument("--tty", action="store_true", help="run the full plan under a pseudo-terminal too")
    options = parser.parse_args()
    folder = options.keep or Path(tempfile.mkdtemp())
    folder.mkdir(parents=True, exist_ok=True)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores", flush=True)
    print("| map | size (m) | res (m) | traced vertices | imported | holes | inside | P′ segments | plan | "
          "wall / CPU s | peak MB | --timeout 10: wall / CPU s | problems |")
    print("|---|---|---:|---:|---:|---:|---|---:|---|---:|---:|---:|---|", flush=True)
    chosen = {name for name in options.maps.split(",")}
    for spec in MAPS:
        if spec.name not in chosen:
            continue
        problems = []
        cells = draw_map(spec)
        yaml = write_map(folder, spec, cells)
        env_file = folder / f"{spec.name}.json"
        w, c, m, rc, out, err = measured(CLI + ["import", str(yaml), "-o", str(env_file)], 300)
        if rc != 0 or "Traceback" in err:
            print(f"| {spec.name} | import failed (exit {rc}): {err.strip()[-300:]} |", flush=True)
            continue
        info = json.loads(out)
        _, _, _, rc2, out2, err2 = measured(CLI + ["import", str(yaml), "-o", str(folder / f"{spec.name}_raw.json"),
                                                   "--simplify", "0", "--rectilinear", "0", "--min-obstacle", "0"], 300)
        traced = json.loads(out2)["vertices"] if rc2 == 0 else f"exit {rc2}"
        inside = check_inside(yaml, env_file)
        if inside != "ok":
            problems.append("imported outside traced")
        start, goal = far_walls(env_file)
        row = (f"| {spec.name} | {spec.width:g} × {spec.height:g}{' turned %g°' % spec.turn if spec.turn else ''} | "
               f"{spec.resolution:g} | {traced} | {info.get('vertices')} | {info.get('holes')} | {inside} |")
        if options.no_plan:
            print(row + f" – | – | – | – | – | {'; '.join(problems)} |", flush=True)
            continue
        plan = CLI + ["--graph-cache", "off", "plan", str(env_file), "--from", start, "--to", goal,
                      "--objective", "tolerance"]
        w, c, m, rc, out, err = measured(plan + ["--timeout", str(options.limit)], options.limit * 4)
        try:
            answer = json.loads(out)
            status = answer["status"]
            stats = answer.get("stats", {})
            if answer.get("optimality", {}).get("limits"):
                status += " (timeout)"
        except (json.JSONDecodeError, KeyError):
            status, stats = f"exit {rc}: {err.strip()[-160:]}", {}
            problems.append("plan failed")
        if "Traceback" in err:
            problems.append("traceback")
        if w > 60:
            problems.append("> 60 s")
        if m > 2048:
            problems.append("> 2 GB")
        tw, tc, _, trc, tout, terr = measured(plan + ["--timeout", str(options.timeout)], 120)
        if tw > options.timeout + 2:
            problems.append(f"--timeout {options.timeout:g} took {tw:.1f} s")
        if trc not in (0, 1) or "Traceback" in terr:
            problems.append(f"--timeout run exit {trc}: {terr.strip()[-120:]}")
        if options.tty:
            _, _, _, _, tty_out, _ = measured(plan + ["--timeout", str(options.limit), "-o", str(folder / "p.json")],
                                             options.limit * 4, tty=True)
            if not re.search(r"[━█▏▎▍▌▋▊▉]|\d+%", tty_out):
                problems.append("no progress bar on a terminal")
        print(row + f" {stats.get('graph_segments', '–')} | {status} | {w:.1f} / {c:.1f} | {m:.0f} | {tw:.1f} / {tc:.1f} | "
              f"{'; '.join(problems) or 'none'} |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} at the end; files in {folder}")


if __name__ == "__main__":
    main()
