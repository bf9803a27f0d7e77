"""End to end on hidden-like inputs (issue #23): every model, answer → certificate → verify → tamper → report.

The acceptance test of issue #23, run the way an outside tester runs it: for environments solverplan does not ship
(random polygons with holes, rectilinear rooms, hand-written rings with collinear vertices, clockwise rings, rings
starting anywhere, tiny and huge coordinates, turned by an exact rotation, many vertices), every command that writes
a certificate runs **as a process** with ``-o A.json --certificate C.json``; then

1. the answer must have ``kind`` as its first key, and the command must end with exit code 0 or refuse the input in
   one ``error:`` line with exit code 2 (never a traceback, never an internal error);
2. ``verify C.json`` must exit 0; an answer that certifies nothing (a ``not-found`` plan, a stopped search) writes
   no certificate and says why on stderr (the contract's *Certificates*);
3. single claims of the certificate are tampered (a number nudged, a list element dropped or duplicated, a vertex
   moved, a flag flipped, the kind changed) and ``verify`` must reject each: exit 1 (a failing claim) or 2
   (malformed), in one clear line, no traceback;
4. ``report A.json --certificate C.json`` must write a page that loads in headless Chromium with no console
   message and runs its script (the harness of ``tests/report/test_chromium.py``).

Every run is seeded; a failure is printed with the command that reproduces it, and all results go to a JSON file::

    .venv/bin/python benchmarks/end_to_end.py --runs 4 --out /tmp/e2e          # every model, 4 inputs each
    .venv/bin/python benchmarks/end_to_end.py --model rooms --runs 20 --seed 3  # one model

Not part of the test suite (it takes minutes); its regressions live in ``tests/end_to_end``.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import random
import re
import subprocess
import sys
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from shapely.geometry import Point, Polygon  # noqa: E402

from solverplan import generators  # noqa: E402
from solverplan.environment import Environment, load_environment  # noqa: E402

SOLVERPLAN = str(Path(sys.executable).with_name("solverplan"))
COMMAND_TIMEOUT = 120  # seconds of wall time for one command (the plans also get --timeout)

Ring = list[tuple[Fraction, Fraction]]


# ----------------------------------------------------------------------------------------------- environments
def _decimal(value: Fraction) -> str:
    """Exact decimal text of a fraction whose denominator is 2^a 5^b (every transform below keeps that)."""
    den, twos, fives = value.denominator, 0, 0
    while den % 2 == 0:
        den, twos = den // 2, twos + 1
    while den % 5 == 0:
        den, fives = den // 5, fives + 1
    if den != 1:
        raise ValueError(f"{value} has no finite decimal")
    digits = max(twos, fives)
    scaled = value * 10**digits
    assert scaled.denominator == 1
    sign = "-" if scaled < 0 else ""
    text = str(abs(scaled.numerator)).rjust(digits + 1, "0")
    return sign + (text[:-digits] + "." + text[-digits:] if digits else text)


def env_json(name: str, rings: list[Ring]) -> str:
    """A hand-written environment file: exact decimals as JSON numbers, one ring per line."""
    def ring(r: Ring) -> str:
        return "[" + ", ".join(f"[{_decimal(x)}, {_decimal(y)}]" for x, y in r) + "]"
    holes = ",\n    ".join(ring(h) for h in rings[1:])
    return f'{{"name": {json.dumps(name)},\n "outer": {ring(rings[0])},\n "holes": [{holes}]}}\n'


def _rings(env: Environment) -> list[Ring]:
    return [[(Fraction(x), Fraction(y)) for x, y in ring] for ring in env.rings]


@dataclass
class Shape:
    """A generated environment before the transforms, and whether it is rectilinear (axis-parallel walls)."""

    name: str
    rings: list[Ring]
    rectilinear: bool


def shape(family: str, rng: random.Random, big: bool = False) -> Shape:
    """A random environment of ``family`` (seeded by ``rng``); ``big``: many vertices (200-1,000)."""
    seed = rng.randrange(10**6)
    if family == "star":
        n = rng.randrange(200, 1000) if big else rng.randrange(5, 30)
        env = generators.star_polygon(n, rng.choice([0.0, 0.3, 0.8]), rng.choice([0.0, 0.2, 0.6]), seed=seed,
                                      radius=rng.choice([1.0, 7.5]))
    elif family == "holes":
        env = generators.star_polygon_with_holes(rng.randrange(8, 24) if not big else 300, rng.randrange(1, 4),
                                                 seed=seed, hole_vertices=rng.randrange(3, 7),
                                                 hole_kind=rng.choice(["convex", "star"]))
    elif family == "rooms":
        n_rooms = rng.randrange(2, 7)
        env = generators.rooms_and_corridors(n_rooms, seed=seed, loops=rng.choice([0, 0, 1]) if n_rooms >= 4 else 0)
    elif family == "rectilinear":
        env = generators.rectilinear_floor_plan(rng.randrange(2, 6), seed=seed, pillars=rng.choice([0, 0, 1]))
    elif family == "polyomino":
        env = generators.rectilinear_polygon(rng.randrange(3, 60 if not big else 200), seed=seed)
    elif family == "hand":  # written by hand: a rectangle with a notch, collinear points on purpose
        w, h = rng.randrange(4, 12), rng.randrange(4, 12)
        a = rng.randrange(1, w - 2)
        outer: Ring = [(Fraction(0), Fraction(0)), (Fraction(a), Fraction(0)), (Fraction(w), Fraction(0)),
                       (Fraction(w), Fraction(h)), (Fraction(a + 1), Fraction(h)), (Fraction(a + 1), Fraction(h, 2)),
                       (Fraction(a), Fraction(h, 2)), (Fraction(a), Fraction(h)), (Fraction(0), Fraction(h))]
        return Shape(f"hand notch {w}x{h}", [outer], True)
    elif family == "imported":
        return _imported(rng, seed)
    else:
        raise ValueError(family)
    rect = family in ("rectilinear", "polyomino")
    return Shape(f"{family} {seed}", _rings(env), rect)


def _imported(rng: random.Random, seed: int) -> Shape:
    """A ROS occupancy map drawn at random (a room with boxes, a few lidar specks, ragged walls), through
    ``solverplan import`` as a user would bring one."""
    import tempfile

    w, h = rng.randrange(40, 120), rng.randrange(40, 120)
    free = [[0 < x < w - 1 and 0 < y < h - 1 for x in range(w)] for y in range(h)]
    for _ in range(rng.randrange(0, 6)):  # boxes
        bw, bh = rng.randrange(2, 12), rng.randrange(2, 12)
        x0, y0 = rng.randrange(3, max(4, w - bw - 3)), rng.randrange(3, max(4, h - bh - 3))
        for y in range(y0, min(h - 3, y0 + bh)):
            for x in range(x0, min(w - 3, x0 + bw)):
                free[y][x] = False
    for _ in range(rng.randrange(0, 10)):  # specks and ragged wall cells
        free[rng.randrange(1, h - 1)][rng.randrange(1, w - 1)] = False
    resolution = rng.choice(["0.05", "0.1", "0.025"])
    with tempfile.TemporaryDirectory() as folder:
        pgm = Path(folder) / "map.pgm"
        pgm.write_bytes(f"P5 {w} {h} 255\n".encode() + bytes(254 if c else 0 for row in free for c in row))
        (Path(folder) / "map.yaml").write_text(f"image: map.pgm\nresolution: {resolution}\n"
                                               f"origin: [{rng.randrange(-50, 50)}, {rng.randrange(-50, 50)}, 0]\n")
        out = Path(folder) / "env.json"
        done = subprocess.run([SOLVERPLAN, "import", str(Path(folder) / "map.yaml"), "-o", str(out)],
                              capture_output=True, text=True, timeout=COMMAND_TIMEOUT, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"import exit {done.returncode}: {done.stderr.strip()[-300:]}")
        env = load_environment(out)
    return Shape(f"imported map {seed}", _rings(env), _axis_parallel(env))


def transform(s: Shape, rng: random.Random) -> tuple[list[Ring], list[str]]:
    """The shape as someone else would write it: turned, scaled, shifted, split, listed clockwise, started anywhere.

    Every transform is exact and keeps decimals finite (scales 10^k, the rotation (3/5, 4/5)), so the answer of the
    written file must be the answer of the shape; rectilinear shapes are only turned by right angles.
    """
    rings = [list(r) for r in s.rings]
    done: list[str] = []

    def each(f: Callable[[Fraction, Fraction], tuple[Fraction, Fraction]]) -> None:
        for r in rings:
            r[:] = [f(x, y) for x, y in r]

    if rng.random() < 0.4:
        c, sn = (Fraction(3, 5), Fraction(4, 5)) if not s.rectilinear else (Fraction(0), Fraction(1))
        each(lambda x, y: (c * x - sn * y, sn * x + c * y))
        done.append("rotated")
    if rng.random() < 0.4:
        k = rng.choice([Fraction(1, 1000), Fraction(1, 100), Fraction(100), Fraction(10000)])
        each(lambda x, y: (x * k, y * k))
        done.append(f"scaled {k}")
    if rng.random() < 0.3:
        dx, dy = Fraction(rng.randrange(-5000, 5000)), Fraction(rng.randrange(-5000, 5000))
        each(lambda x, y: (x + dx, y + dy))
        done.append("shifted")
    if rng.random() < 0.5:  # collinear vertices: split some edges at 1/2 or 1/4
        for r in rings:
            out: Ring = []
            for i, (p, q) in enumerate(zip(r, r[1:] + r[:1])):
                out.append(p)
                if rng.random() < 0.3:
                    t = rng.choice([Fraction(1, 2), Fraction(1, 4)])
                    out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
            r[:] = out
        done.append("split")
    if rng.random() < 0.5:
        for r in rings:
            r.reverse()
        done.append("reversed")
    if rng.random() < 0.5:
        for r in rings:
            k = rng.randrange(len(r))
            r[:] = r[k:] + r[:k]
        done.append("restarted")
    return rings, done


# ------------------------------------------------------------------------------------------------- queries
@dataclass
class Case:
    """One command on one written environment file."""

    model: str
    env_file: Path
    env_note: str
    args: list[str]  # after the command name and the environment
    command: str
    expect_exit: tuple[int, ...] = (0,)


def _quantum(poly: Polygon) -> Fraction:
    minx, miny, maxx, maxy = poly.bounds
    size = max(maxx - minx, maxy - miny)
    return Fraction(10) ** (math.floor(math.log10(size)) - 5)


def interior_point(poly: Polygon, rng: random.Random) -> str | None:
    """A point strictly inside the free space, as exact decimal text ``X,Y`` (rounded, then tested)."""
    q = _quantum(poly)
    minx, miny, maxx, maxy = poly.bounds
    inner = poly.buffer(-float(q) * 50)
    for _ in range(200):
        x, y = rng.uniform(minx, maxx), rng.uniform(miny, maxy)
        fx, fy = Fraction(round(Fraction(x) / q)) * q, Fraction(round(Fraction(y) / q)) * q
        if inner.contains(Point(float(fx), float(fy))):
            return f"{_decimal(fx)},{_decimal(fy)}"
    return None


def boundary_set(env: Environment, rng: random.Random, *, whole: bool = False) -> str:
    edge = rng.randrange(env.n_edges)
    if whole or rng.random() < 0.4:
        return f"e{edge}"
    a = Fraction(rng.randrange(0, 8), 10)
    b = a + Fraction(rng.randrange(1, 11 - int(a * 10)), 10)
    return f"e{edge}:{a}:{min(b, Fraction(1))}"


def cases_for(model: str, env_file: Path, note: str, env: Environment, rng: random.Random) -> list[Case]:
    """The commands of ``model`` on ``env`` (queries chosen at random among the valid ones)."""
    poly = env.to_shapely()
    diam = max(poly.bounds[2] - poly.bounds[0], poly.bounds[3] - poly.bounds[1])
    q = _quantum(poly)

    def case(args: list[str], expect: tuple[int, ...] = (0,)) -> Case:
        return Case(model, env_file, note, args, args[0], expect)

    out: list[Case] = []
    if model == "plan":
        objective = rng.choice(["fewest", "tolerance", "sum", "constant", "pareto"])
        args = ["plan", "--from", boundary_set(env, rng), "--to", boundary_set(env, rng, whole=True),
                "--timeout", "30", "--max-bounces", str(rng.choice([2, 3, 4, 6]))]
        args += ["--pareto"] if objective == "pareto" else ["--objective", objective]
        out.append(case(args))
    elif model == "patrol":
        k = rng.choice([2, 2, 3])
        edges = rng.sample(range(env.n_edges), min(k, env.n_edges))
        args = ["patrol", "--visit", ",".join(f"e{e}" for e in edges), "--timeout", "30",
                "--objective", rng.choice(["contraction", "tolerance", "rate"])]
        out.append(case(args))
    elif model == "funnel":
        out.append(case(["funnel", "--from", boundary_set(env, rng), "--to", boundary_set(env, rng),
                         "--timeout", "30", "--max-bounces", str(rng.choice([5, 10, 30]))]))
    elif model == "localize":
        eps = Fraction(round(Fraction(diam) * Fraction(rng.choice([1, 5, 20]), 100) / q)) * q
        out.append(case(["localize", "--epsilon", _decimal(eps), "--timeout", "30",
                         "--max-bounces", str(rng.choice([10, 40]))]))
    elif model == "rooms":
        expect = (0,) if len(env.rings) == 1 and _axis_parallel(env) else (2,)
        out.append(case(["rooms"], expect))
    elif model == "explore":
        start = interior_point(poly, rng)
        if start is None:
            return []
        choice = rng.choice(["first", "random", "far"])
        args = ["explore", "--start", start, "--choice", choice]
        args += ["--seed", str(rng.randrange(100))] if choice == "random" else []
        if rng.random() < 0.5:
            r = Fraction(round(Fraction(diam) * Fraction(rng.choice([5, 20, 20, 60, 60, 150]), 100) / q)) * q
            args += ["--range", _decimal(r)]
        out.append(case(args))
    elif model == "wallfollow":
        mode = rng.choice(["--cut-ordering", "--learn", "--pursuit"])
        args = ["wallfollow", mode] + (["--perturb"] if rng.random() < 0.5 else [])
        if mode == "--pursuit":
            args += ["--sensor", rng.choice(["gap", "bitangent", "pebble", "contact"])]
        if mode == "--learn":
            args += ["--comparisons", rng.choice(["pairwise", "sort"])]
        # holes are unsupported (one line, exit 2); degenerate polygons without --perturb may be refused too
        out.append(case(args, (0, 2)))
    elif model == "fields":
        a, b = interior_point(poly, rng), interior_point(poly, rng)
        if a is None or b is None:
            return []
        args = ["fields", "--from", a, "--to", b, "--trials", "3", "--trajectories", "1",
                "--scenario", rng.choice(["constrained", "unconstrained", "reflection", "all"]),
                "--model", rng.choice(["integrator", "inertial"]), "--seed", str(rng.randrange(100))]
        if rng.random() < 0.3:
            args.append("--arcs")
        if rng.random() < 0.3:
            args += ["--cells", "corners"]
        out.append(case(args, (0, 2)))
    else:
        raise ValueError(model)
    if rng.random() < 0.3:
        out.append(bad_case(model, env, rng, case))
    return out


def bad_case(model: str, env: Environment, rng: random.Random, case: Callable[..., Case]) -> Case:
    """A query that is bad input (exit 2, one ``error:`` line): a point outside, an edge that does not exist,
    an option at an impossible extreme."""
    minx, miny, maxx, maxy = env.to_shapely().bounds
    outside = f"{math.ceil(maxx) + 1},{math.ceil(maxy) + 1}"
    n = env.n_edges
    bad = {
        "plan": [["plan", "--from", f"e{n}", "--to", "e0"], ["plan", "--from", "e0:0.5:0.2", "--to", "e1"],
                 ["plan", "--from", "e0", "--to", "e1", "--max-bounces", "0"]],
        "patrol": [["patrol", "--visit", f"e0,e{n + 3}"], ["patrol", "--visit", "e0,e1", "--tolerance", "-1"]],
        "funnel": [["funnel", "--from", "e0", "--to", "e1", "--tolerance", "4"], ["funnel", "--from", "e-1", "--to", "e1"]],
        "localize": [["localize", "--epsilon", "0"], ["localize", "--epsilon", "-1"], ["localize", "--epsilon", "nan"]],
        "rooms": [["rooms", "--simulate", "--from", "0", "--to", "999"]],
        "explore": [["explore", "--start", outside], ["explore", "--start", "0,0", "--range", "0"],
                    ["explore", "--start", "1,1", "--range", "-2"], ["explore", "--start", "a,b"]],
        "wallfollow": [["wallfollow", "--pursuit", "--from", outside], ["wallfollow", "--learn", "--start", outside]],
        "fields": [["fields", "--from", outside, "--to", outside], ["fields", "--from", "1", "--to", "2,2"],
                   ["fields", "--from", outside, "--to", outside, "--trials", "0"]],
    }[model]
    return case(rng.choice(bad), (2,))


def _axis_parallel(env: Environment) -> bool:
    return all(a[0] == b[0] or a[1] == b[1] for ring in env.rings for a, b in zip(ring, ring[1:] + ring[:1]))


FAMILIES = {  # which environments each model is given
    "plan": ["star", "holes", "rooms", "hand", "polyomino", "imported"],
    "patrol": ["star", "holes", "hand", "polyomino", "imported"],
    "funnel": ["star", "holes", "rooms", "hand", "imported"],
    "localize": ["star", "holes", "hand", "polyomino", "imported"],
    "rooms": ["rectilinear", "polyomino", "hand", "polyomino", "imported"],
    "explore": ["star", "holes", "rooms", "rectilinear", "polyomino", "hand", "imported"],
    "wallfollow": ["star", "polyomino", "hand", "star", "imported"],
    "fields": ["star", "holes", "rooms", "rectilinear", "polyomino", "hand", "imported"],
}


# ------------------------------------------------------------------------------------------------- tampering
def _leaf_paths(node: Any, path: tuple = ()) -> list[tuple]:
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _leaf_paths(v, path + (k,))]
    if isinstance(node, list):
        here = [path] if node else []
        return here + [p for i, v in enumerate(node) for p in _leaf_paths(v, path + (i,))]
    return [path]


def _get(node: Any, path: tuple) -> Any:
    for k in path:
        node = node[k]
    return node


def _set(node: Any, path: tuple, value: Any) -> None:
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def _as_fraction(value: Any) -> Fraction | None:
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, str):
        try:
            return Fraction(value)
        except (ValueError, ZeroDivisionError):
            return None
    if isinstance(value, float):
        return Fraction(value)
    return None


# keys whose change alters no claim (the producer's name, the environment's name) or that the checker reports but
# does not decide (free text)
NOT_CLAIMS = {"producer", "name", "schema", "scope", "note", "table_source", "label", "algorithm", "reason"}


# changes after which the certificate is another true statement (reviewed by hand; verify decides them exactly):
# a line field's origin, target or gain moved a little (another field that also flows through), a cone direction
# nudged by at most one part in a million (still inside the exact safe set), a bound over fewer plans (a larger
# threshold or margin), a smaller start set or a larger goal set (the contract: a true statement about a smaller query),
# a polygon's vertex listed twice in a row (the same polygon), a moved wall of a --perturb certificate (it speaks of
# its own perturbed polygon, which no file pins)
STILL_TRUE = re.compile(r"^claims/policies/\d+/field/(origin|target|gain|centre|radius)|/polygon: duplicated")
WEAKER = re.compile(r"^bound/(threshold|heading_margin): (-?[\d./]+) -> (-?[\d./]+)$")
SET_END = re.compile(r"^(start|goal)/\d+/(t0|t1): (-?[\d./]+) -> (-?[\d./]+)$")
CONE = re.compile(r"^stages/\d+/moves/\d+/d_(lo|hi)/\d: (\S+) -> (\S+)$")
VIEWPOINT = re.compile(r"^claims/(?:views/\d+/viewpoint|start|goal)/\d: (\S+) -> (\S+)$")


def still_true(what: str) -> bool:
    """Is the accepted change ``what`` one of :data:`STILL_TRUE`, or a cone direction nudged by at most 10⁻⁶?"""
    if STILL_TRUE.search(what):
        return True
    weaker = WEAKER.match(what)  # a bound over fewer plans: wider intervals, a larger margin
    if weaker:
        old, new = Fraction(weaker.group(2)), Fraction(weaker.group(3))
        return new > old
    piece = SET_END.match(what)  # a smaller start set or a larger goal set: a true statement about a smaller query
    if piece:
        old, new = Fraction(piece.group(3)), Fraction(piece.group(4))
        smaller = new > old if piece.group(2) == "t0" else new < old
        return smaller == (piece.group(1) == "start")
    if re.match(r"^start: dropped", what):
        return True
    if re.match(r"^bound/groups: dropped", what):
        return True  # a bound over fewer plans (landings inside fewer runs of segments): weaker, still true
    nudged = VIEWPOINT.match(what)  # a viewpoint (its view re-derived) or a field's start/goal point moved by ≤ 10⁻⁴
    if nudged:
        old, new = Fraction(nudged.group(1)), Fraction(nudged.group(2))
        return abs(new - old) <= abs(old) / 10**4
    cone = CONE.match(what)
    if cone:
        old, new = Fraction(cone.group(2)), Fraction(cone.group(3))
        return abs(new - old) <= abs(old) / 10**6
    return False


# lists that are unions of pieces (a boundary set, a position set): a piece listed twice is the same set
UNIONS = {"start", "goal", "positions", "final"}


def tampers(cert: dict, rng: random.Random, count: int) -> list[tuple[str, dict]]:
    """``count`` single changes of ``cert`` (what was changed, the changed certificate)."""
    paths = [p for p in _leaf_paths(cert) if p and not (set(map(str, p)) & NOT_CLAIMS) and p[0] not in ("schema",)]
    out: list[tuple[str, dict]] = []
    kinds = ["plan", "funnel", "localize", "cycle", "infeasible", "rooms", "exploration", "cut-ordering", "pursuit",
             "fields"]
    other = rng.choice([k for k in kinds if k != cert.get("kind")])
    t = copy.deepcopy(cert)
    t["kind"] = other
    out.append((f"kind {cert.get('kind')} -> {other}", t))
    tries = 0
    while len(out) < count and tries < 50 * count:
        tries += 1
        path = rng.choice(paths)
        value = _get(cert, path)
        t = copy.deepcopy(cert)
        where = "/".join(map(str, path))
        if isinstance(value, list):
            if not value:
                continue
            i = rng.randrange(len(value))
            if rng.random() < 0.5 or path[-1] in UNIONS:
                del _get(t, path)[i]
                out.append((f"{where}: dropped [{i}]", t))
            else:
                _get(t, path).insert(i, copy.deepcopy(value[i]))
                out.append((f"{where}: duplicated [{i}]", t))
            continue
        if isinstance(value, bool):
            if path[-1] == "proved" and value:
                continue  # "proved: false" is a weaker claim, still true: no tamper
            _set(t, path, not value)
            out.append((f"{where}: {value} -> {not value}", t))
            continue
        if value is None or path[-1] in ("kind",) and len(path) == 1:
            continue
        if rng.random() < 0.15:  # a value of the wrong type: malformed (exit 2), never a traceback
            bad = rng.choice(["abc", None, [], {}, -1, "1/0", "nan", True])
            _set(t, path, bad)
            out.append((f"{where}: {value!r} -> {bad!r} (malformed)", t))
            continue
        f = _as_fraction(value)
        if f is not None:
            if path[-1] == "version":
                continue
            step = rng.choice([Fraction(1, 10**6), Fraction(1, 1000), Fraction(1, 3), Fraction(1)])
            new = f + step * (abs(f) if f and rng.random() < 0.5 else 1) * rng.choice([-1, 1])
            text: Any = (new.numerator if new.denominator == 1 and isinstance(value, int) else str(new))
            _set(t, path, text)
            out.append((f"{where}: {value} -> {text}", t))
            continue
        if isinstance(value, str):
            swaps = {"l": "r", "r": "l", "left": "right", "right": "left", "RFOLLOW": "LFOLLOW", "LFOLLOW": "RFOLLOW",
                     "JUMP": "RFOLLOW"}
            new_s = swaps.get(value, value + "x")
            _set(t, path, new_s)
            out.append((f"{where}: {value!r} -> {new_s!r}", t))
    return out


# ------------------------------------------------------------------------------------------------- running
@dataclass
class Result:
    model: str
    command: str
    env_note: str
    outcome: str = "ok"  # ok | refused | no-certificate | slow | FAIL
    problems: list[str] = field(default_factory=list)
    accepted_tampers: list[str] = field(default_factory=list)
    unchecked_tampers: list[str] = field(default_factory=list)
    still_true_tampers: list[str] = field(default_factory=list)
    tampers: int = 0
    status: str | None = None
    seconds: float = 0.0


def _run(args: list[str], timeout: float = COMMAND_TIMEOUT) -> tuple[int, str, str, float]:
    t0 = time.monotonic()
    try:
        done = subprocess.run(args, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return -9, "", f"timed out after {timeout} s (wall time; the machine's load counts)", time.monotonic() - t0
    return done.returncode, done.stdout, done.stderr, time.monotonic() - t0


def _clear_line(stderr: str) -> str | None:
    """What is wrong with an error report: a traceback, an internal error, no ``error:`` line (None: it is fine)."""
    if "Traceback" in stderr:
        return "traceback: " + stderr.strip().splitlines()[-1][:300]
    if "internal error" in stderr:
        return stderr.strip().splitlines()[-1][:300]
    lines = [ln for ln in stderr.strip().splitlines() if ln.startswith("error:")]
    if len(lines) != 1:
        return f"not one error line: {stderr.strip()[:300]!r}"
    return None


def run_case(case: Case, work: Path, rng: random.Random, n_tampers: int, browser: Any) -> Result:
    res = Result(case.model, "", case.env_note)
    answer, cert, page = work / "A.json", work / "C.json", work / "R.html"
    for f in (answer, cert, page):
        f.unlink(missing_ok=True)
    argv = [SOLVERPLAN, case.args[0], str(case.env_file), *case.args[1:], "-o", str(answer), "--certificate", str(cert)]
    res.command = " ".join(argv[1:])
    code, _out, err, secs = _run(argv)
    res.seconds = secs
    if code == -9:
        res.outcome = "slow"
        res.problems.append(err)
        return res
    if code not in case.expect_exit or code not in (0, 2):
        res.outcome = "FAIL"
        res.problems.append(f"exit {code}, expected {case.expect_exit}: {err.strip()[-400:]}")
        return res
    if code == 2:
        res.outcome = "refused"
        why = _clear_line(err)
        if why:
            res.outcome = "FAIL"
            res.problems.append(f"exit 2 but {why}")
        else:
            res.problems.append(err.strip().splitlines()[-1][:200])
        return res
    try:
        data = json.loads(answer.read_text())
    except (OSError, ValueError) as exc:
        res.outcome = "FAIL"
        res.problems.append(f"no answer JSON: {exc}")
        return res
    if not isinstance(data, dict) or next(iter(data), None) != "kind":
        res.outcome = "FAIL"
        res.problems.append(f"answer's first key is not kind: {list(data)[:3]}")
        return res
    res.status = data.get("status")
    has_cert = cert.exists()
    if has_cert:
        code, vout, verr, _ = _run([SOLVERPLAN, "verify", str(cert)])
        # --perturb certifies the perturbed polygon (its exact rings are in the certificate): no pin to the file
        perturbed = "--perturb" in case.args
        pcode, _pout, perr, _ = (0, "", "", 0.0) if perturbed else \
            _run([SOLVERPLAN, "verify", str(cert), "--env", str(case.env_file)])
        if code != 0:
            res.outcome = "FAIL"
            res.problems.append(f"verify exit {code}: {(verr or vout).strip()[-400:]}")
        elif pcode != 0:
            res.outcome = "FAIL"
            res.problems.append(f"verify --env ENV exit {pcode}: {perr.strip()[-400:]}")
        else:
            cdata = json.loads(cert.read_text())
            # files that are no certificate: the answer itself, a truncated certificate (exit 2, one line)
            cut = work / "cut.json"
            cut.write_text(cert.read_text()[: rng.randrange(1, max(2, cert.stat().st_size))])
            for wrong in (answer, cut):
                code, _o, werr, _ = _run([SOLVERPLAN, "verify", str(wrong)])
                why = _clear_line(werr)
                if code != 2 or why:
                    res.outcome = "FAIL"
                    res.problems.append(f"verify {wrong.name} (no certificate): exit {code}, {why or werr.strip()[:200]}")
            changed = tampers(cdata, rng, n_tampers)
            for what, t in changed:
                tfile = work / "T.json"
                tfile.write_text(json.dumps(t))
                # a moved wall makes the certificate speak of another environment, true or not: pinning the
                # environment (verify --env) is what rejects it
                pin = ["--env", str(case.env_file)] if what.startswith("environment/") and not perturbed else []
                code, tout, terr, _ = _run([SOLVERPLAN, "verify", str(tfile), *pin])
                res.tampers += 1
                if code == 0:
                    # a claim the verdict itself lists as not re-derived (e.g. which objective was optimised) is
                    # honest, not accepted: the tester reads `not_checked`
                    try:
                        listed = json.loads(tout).get("not_checked", [])
                    except ValueError:
                        listed = []
                    key = ".".join(p for p in what.split(":")[0].split("/") if not p.isdigit())
                    if any(line.startswith(key) for line in listed):
                        res.unchecked_tampers.append(what)
                    elif still_true(what) or (perturbed and what.startswith("environment/")):
                        res.still_true_tampers.append(what)
                    else:
                        res.accepted_tampers.append(what)
                elif code not in (1, 2) or "Traceback" in terr or "internal error" in terr:
                    res.outcome = "FAIL"
                    res.problems.append(f"tamper {what}: verify exit {code}: {terr.strip()[-300:]}")
                elif not terr.strip():
                    res.outcome = "FAIL"
                    res.problems.append(f"tamper {what}: verify exit {code} with nothing on stderr")
    else:
        res.outcome = "no-certificate"
        warn = [ln for ln in err.splitlines() if "certificate" in ln.lower()]
        res.problems.append(f"status {res.status}: {warn[-1][:200] if warn else 'NO WARNING on stderr'}")
        if not warn:
            res.outcome = "FAIL"
    rargs = [SOLVERPLAN, "report", str(answer), "-o", str(page)] + (["--certificate", str(cert)] if has_cert else [])
    if data.get("kind") in ("plan", "pareto", "patrol", "funnel", "localize", "exploration", "range-exploration",
                            "pursuit") and not has_cert or (rng.random() < 0.5 and "--perturb" not in case.args):
        rargs += ["--env", str(case.env_file)]  # the hidden file itself, as written (clockwise, split, ...)
    code, _o, rerr, _ = _run(rargs)
    if code != 0:
        res.outcome = "FAIL"
        res.problems.append(f"report exit {code}: {rerr.strip()[-400:]}")
    elif browser is not None:
        try:
            dom, messages = browser.dom(page)
        except BaseException as exc:  # the harness asserts and fails with pytest's exceptions
            res.outcome = "FAIL"
            res.problems.append(f"chromium: {type(exc).__name__}: {str(exc)[:300]}")
        else:
            if messages:
                res.outcome = "FAIL"
                res.problems.append(f"console: {messages[:3]}")
            if 'data-report-ready="yes"' not in dom:
                res.outcome = "FAIL"
                res.problems.append("the report's script did not run (no data-report-ready)")
    if res.accepted_tampers:
        res.outcome = "FAIL" if res.outcome == "ok" else res.outcome
        res.problems.append(f"accepted tampers: {res.accepted_tampers}")
    return res


def make_browser(work: Path) -> Any:
    from tests.report.test_chromium import Browser, _find

    found = _find()
    if found is None:
        print("chromium not found: reports are written but not loaded", file=sys.stderr)
        return None
    (work / "chromium").mkdir(parents=True, exist_ok=True)
    return Browser(found, work / "chromium")


MODELS = list(FAMILIES)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", action="append", choices=MODELS, help="only this model (repeatable)")
    ap.add_argument("--runs", type=int, default=4, help="inputs per model")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tampers", type=int, default=8, help="tampered certificates per answer")
    ap.add_argument("--big", type=float, default=0.1, help="share of inputs with many vertices (200-1,000)")
    ap.add_argument("--no-browser", action="store_true")
    ap.add_argument("--out", type=Path, default=Path("/tmp/solverplan-e2e"))
    opts = ap.parse_args(argv)
    work = opts.out
    work.mkdir(parents=True, exist_ok=True)
    browser = None if opts.no_browser else make_browser(work)
    results: list[Result] = []
    for model in opts.model or MODELS:
        rng = random.Random(f"{opts.seed}-{model}")
        for run in range(opts.runs):
            family = FAMILIES[model][run % len(FAMILIES[model])]
            big = rng.random() < opts.big and family in ("star", "polyomino", "holes")
            try:
                s = shape(family, rng, big)
            except Exception as exc:  # a generator that gives up is no finding of this driver
                print(f"skip {family}: {exc}", file=sys.stderr)
                continue
            rings, done = transform(s, rng)
            note = f"{s.name} ({', '.join(done) or 'as generated'}; {sum(map(len, rings))} vertices)"
            env_file = work / f"{model}-{run}.json"
            env_file.write_text(env_json(s.name, rings))
            try:
                env = load_environment(env_file)
            except Exception as exc:
                results.append(Result(model, f"load {env_file}", note, "FAIL", [f"load: {exc}"]))
                continue
            for case in cases_for(model, env_file, note, env, rng):
                (work / f"{model}-{run}").mkdir(exist_ok=True)
                res = run_case(case, work / f"{model}-{run}", rng, opts.tampers, browser)
                results.append(res)
                flag = "  " if res.outcome in ("ok", "refused", "no-certificate", "slow") else "!!"
                print(f"{flag} {model:10s} {res.outcome:14s} {res.seconds:6.1f}s {res.status or '':12s} "
                      f"tampers {res.tampers - len(res.accepted_tampers)}/{res.tampers}  {res.command}", flush=True)
                for what in res.unchecked_tampers + res.still_true_tampers:
                    print(f"      accepted, {'listed unchecked' if what in res.unchecked_tampers else 'still true'}: "
                          f"{what[:200]}", flush=True)
                for p in res.problems:
                    print(f"      {p}", flush=True)
                print(f"      input: {note}", flush=True)
    (work / "results.json").write_text(json.dumps([r.__dict__ for r in results], indent=1))
    print("\nmodel      runs  ok refused no-cert slow FAIL | tampers rejected listed-unchecked still-true ACCEPTED")
    for model in opts.model or MODELS:
        rs = [r for r in results if r.model == model]
        count = {o: sum(r.outcome == o for r in rs) for o in ("ok", "refused", "no-certificate", "slow", "FAIL")}
        tt, acc = sum(r.tampers for r in rs), sum(len(r.accepted_tampers) for r in rs)
        unc, true = sum(len(r.unchecked_tampers) for r in rs), sum(len(r.still_true_tampers) for r in rs)
        print(f"{model:10s} {len(rs):4d} {count['ok']:3d} {count['refused']:7d} {count['no-certificate']:7d} "
              f"{count['slow']:4d} {count['FAIL']:4d} | {tt:7d} {tt - acc - unc - true:8d} {unc:16d} {true:10d} {acc:8d}")
    return 1 if any(r.outcome == "FAIL" for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
