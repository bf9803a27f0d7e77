"""Whole-process times of the ``solverplan`` command, as a user waits for them.

Run ``python benchmarks/bench_cli.py`` from the repository root (package installed in that
Python's environment). It writes its inputs to a temporary folder —

- the 80-vertex star ``solverplan generate star --n 80 --irregularity 0.2 --spikiness 0.3 --seed 1``
  (629 segments, 73,248 arcs; the same polygon as ``benchmarks/bench_bvg.py``'s n = 80 row),
- the paper's worst case for Algorithm 1 at t = 16, ``worst_case_polygon(16)`` (n = 4t + 2 = 66
  vertices; the command line has no generator for this family, so the library writes it),

then times, as subprocesses, ``solverplan info models/two_rooms.json`` (start-up: interpreter,
imports, one small answer) and ``solverplan graph ENV --safe`` for both polygons, once written with
``-o FILE`` and once to stdout redirected to ``/dev/null``. Each command runs once untimed (so the
bytecode cache is warm, as for an installed package) and then ``--repeat`` times; the table gives
the median wall time and the 1-minute load average when the command's runs started. It prints a
markdown table and the machine (cores, CPU model, Python); the recorded results are in
``benchmarks/README.md``, "Whole-process CLI times".

``--large`` times the scale targets instead: partition + safe BVG of the 640- and 1,000-vertex stars
and of a 26 × 22 room with 30 aligned unit-square pillars, as whole processes (wall and CPU seconds,
peak resident memory), with the full JSON answer and with a one-segment answer (the build alone), a
second run reading the graph from the disk cache, and the 2,000-vertex star built and refused under
``--max-memory 1G``.

The machine is shared: ``--wait-load L`` waits (at most ``--max-wait`` seconds) until the 1-minute
load average is below L before starting. This script is not a test: pytest collects only
``tests/``, ``solverplan/`` and ``proofs/``, and nothing here is named ``test_*``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Seconds the reference implementation takes for the same two graphs (quoted in the project's
#: performance requirements; not measured here).
REFERENCE_SECONDS = {"star80": 65.0, "worst_case_t16": 147.0}


def solverplan_command() -> list[str]:
    """The installed console script next to this Python, else the CLI through ``-c``."""
    script = Path(sys.executable).with_name("solverplan")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "from solverplan.cli import main; main()"]


def child_environment(cache: Path) -> dict[str, str]:
    """The caller's environment with bytecode caching on (kept in ``cache``, outside the tree)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(cache)
    return env


def run(args: list[str], env: dict[str, str]) -> float:
    """Wall seconds of one run of ``args`` with stdout to ``/dev/null``; stops the script if it fails."""
    with open(os.devnull, "wb") as sink:
        start = time.perf_counter()
        done = subprocess.run(args, stdout=sink, stderr=subprocess.PIPE, env=env, check=False)
        seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(args)} exited {done.returncode}: {done.stderr.decode(errors='replace').strip()}")
    return seconds


def run_measured(args: list[str], env: dict[str, str] | None = None) -> tuple[float, float, int, str]:
    """(wall s, CPU s of the child, peak RSS in MiB of the largest child so far, stdout) of one run of ``args``;
    stops the script if it fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(args, capture_output=True, text=True, env=env, check=False)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(args)} exited {done.returncode}: {done.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, after.ru_maxrss // 1024, done.stdout


def wait_for_load(limit: float | None, max_wait: float) -> None:
    if limit is None:
        return
    deadline = time.monotonic() + max_wait
    while os.getloadavg()[0] >= limit and time.monotonic() < deadline:
        time.sleep(5)


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def make_inputs(folder: Path, cli: list[str], env: dict[str, str]) -> dict[str, Path]:
    from solverplan.environment import save_environment
    from solverplan.generators import worst_case_polygon

    star = folder / "star80.json"
    subprocess.run([*cli, "generate", "star", "--n", "80", "--irregularity", "0.2", "--spikiness", "0.3",
                    "--seed", "1", "-o", str(star)], env=env, check=True)
    worst = folder / "worst_case_t16.json"
    save_environment(worst_case_polygon(16), worst)
    return {"star80": star, "worst_case_t16": worst}


def measure(args: list[str], env: dict[str, str]) -> tuple[float, float, float, int]:
    """(wall s, CPU s = user + system, peak resident MB, exit code) of one run, stdout to /dev/null."""
    with open(os.devnull, "wb") as sink:
        start = time.perf_counter()
        child = subprocess.Popen(args, stdout=sink, stderr=subprocess.DEVNULL, env=env)
        _, status, usage = os.wait4(child.pid, 0)
        seconds = time.perf_counter() - start
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status)


def pillar_room() -> object:
    """A 26 × 22 room with 30 unit-square pillars on an aligned 6 × 5 grid (1,584 segments of P′)."""
    from solverplan.environment import Environment

    holes = [[[x, y], [x, y + 1], [x + 1, y + 1], [x + 1, y]] for x in range(3, 24, 4) for y in range(3, 20, 4)]
    return Environment.from_coords([[0, 0], [26, 0], [26, 22], [0, 22]], holes, name="pillars30")


def large(opts: argparse.Namespace) -> None:
    """The scale targets: partition + safe BVG of the 640- and 1,000-vertex stars and the 30-pillar room
    as whole processes (the full JSON answer, and a one-segment answer: the build alone), the reuse of a
    cached graph, and the 2,000-vertex star with and without a memory limit."""
    from solverplan.environment import save_environment

    cli = solverplan_command()
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        folder = Path(tmp)
        env = child_environment(folder / "pycache")
        inputs = {}
        for n in (640, 1000, 2000):
            inputs[f"star{n}"] = folder / f"star{n}.json"
            subprocess.run([*cli, "generate", "star", "--n", str(n), "--irregularity", "0.2", "--spikiness", "0.3",
                            "--seed", "1", "-o", str(inputs[f"star{n}"])], env=env, check=True)
        inputs["pillars30"] = folder / "pillars30.json"
        save_environment(pillar_room(), inputs["pillars30"])
        cache = folder / "graphs"
        out = str(folder / "g.json")
        cases = []
        for name in ("star640", "star1000", "pillars30"):
            path = str(inputs[name])
            cases += [(name, "graph --safe -o FILE", ["--graph-cache", "off", "graph", path, "--safe", "-o", out]),
                      (name, "graph --safe --from 0 (build only)", ["--graph-cache", "off", "graph", path, "--safe", "--from", "0", "-o", out]),
                      (name, "… again, graph cached on disk", ["--graph-cache", str(cache), "graph", path, "--safe", "--from", "0", "-o", out])]
        path = str(inputs["star2000"])
        cases += [("star2000", "graph --safe --from 0 (build only)", ["--graph-cache", "off", "graph", path, "--safe", "--from", "0", "-o", out]),
                  ("star2000", "--max-memory 1G: refused", ["--graph-cache", "off", "--max-memory", "1G", "graph", path, "--safe"])]
        subprocess.run([*cli, "info", str(inputs["star640"])], env=env, check=True, capture_output=True)  # warm bytecode
        rows = []
        for name, label, args in cases:
            if label.startswith("…"):  # the first run fills the cache
                measure([*cli, *args], env)
            wait_for_load(opts.wait_load, opts.max_wait)
            load = os.getloadavg()[0]
            runs = [measure([*cli, *args], env) for _ in range(opts.repeat)]
            best = min(runs, key=lambda r: r[1])
            rows.append((name, label, *best, load))
    print(f"machine: {os.cpu_count()} cores, {cpu_model()}, Python {platform.python_version()}; best of {opts.repeat} by CPU time")
    print()
    print("| environment | command | wall s | CPU s | peak MB | exit | load (1 min) |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for name, label, wall, cpu, rss, code, load in rows:
        print(f"| {name} | `{label}` | {wall:.2f} | {cpu:.2f} | {rss:,.0f} | {code} | {load:.2f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per command (median reported)")
    parser.add_argument("--wait-load", type=float, default=None, metavar="L",
                        help="wait until the 1-minute load average is below L before each command")
    parser.add_argument("--max-wait", type=float, default=300.0, metavar="S", help="give up waiting after S seconds")
    parser.add_argument("--large", action="store_true", help="the scale targets instead (stars of 640, 1,000, 2,000 vertices, 30 pillars)")
    opts = parser.parse_args()
    if opts.large:
        large(opts)
        return

    cli = solverplan_command()
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        folder = Path(tmp)
        env = child_environment(folder / "pycache")
        inputs = make_inputs(folder, cli, env)
        small = ROOT / "solverplan" / "models" / "two_rooms.json"
        cases = [("info", "two_rooms", small, ["info", str(small)], False)]
        for name, path in inputs.items():
            cases.append(("graph --safe -o FILE", name, path, ["graph", str(path), "--safe", "-o", str(folder / "g.json")], False))
            cases.append(("graph --safe > /dev/null", name, path, ["graph", str(path), "--safe"], True))

        rows = []
        counts: dict[str, tuple[int, int]] = {}  # environment → (segments, arcs), from its -o answer
        for label, name, path, args, to_null in cases:
            run([*cli, *args], env)  # warm-up: bytecode cache, page cache
            wait_for_load(opts.wait_load, opts.max_wait)
            load = os.getloadavg()[0]
            times = [run([*cli, *args], env) for _ in range(opts.repeat)]
            described = subprocess.run([*cli, "info", str(path)], env=env, check=True, capture_output=True)
            vertices = json.loads(described.stdout)["n_vertices"]
            if label.startswith("graph") and not to_null:
                graph = json.loads((folder / "g.json").read_text(encoding="utf-8"))
                counts[name] = (graph["n_segments"], graph["n_arcs"])
            segments, arcs = counts.get(name, (None, None))
            rows.append((label, name, vertices, segments, arcs, statistics.median(times), len(times), load,
                         REFERENCE_SECONDS.get(name) if label.startswith("graph") else None))

    def num(value: object, fmt: str = ",") -> str:
        return "—" if value is None else format(value, fmt)

    print(f"machine: {os.cpu_count()} cores, {cpu_model()}, Python {platform.python_version()}; command: {' '.join(cli)}")
    print()
    print("| command | environment | vertices | segments | arcs | seconds (median) | runs | load (1 min) | reference s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for label, name, n, segments, arcs, seconds, runs, load, ref in rows:
        print(f"| `{label}` | {name} | {n} | {num(segments)} | {num(arcs)} | {seconds:.2f} | {runs} | {load:.2f} | {num(ref, '.0f')} |")


if __name__ == "__main__":
    main()
