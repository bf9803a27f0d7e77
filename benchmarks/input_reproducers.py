"""Issue #28's classes of bad input, each run as a real process under a 2 GiB address-space cap and a timeout.

Every case builds its input files in a fresh folder and runs ``solverplan ARGS`` as a child process with
``RLIMIT_AS`` = 2 GiB (so a run that would grow past 2 GiB fails instead of swapping) and a timeout. A case
passes when the process exits 0 or 2, prints no traceback, writes at most one line on stderr of at most 200
characters, does not hang and stays under the cap. The table says, per case, the exit code, the peak RSS
(``ru_maxrss`` of that child), the seconds and the first stderr line; the last line counts them::

    PYTHONPATH=. .venv/bin/python benchmarks/input_reproducers.py            # every case
    PYTHONPATH=. .venv/bin/python benchmarks/input_reproducers.py svg yaml   # cases whose name holds a word

tests/test_input_reproducers.py runs the same cases (marked slow).
"""

from __future__ import annotations

import dataclasses
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib
import struct
from pathlib import Path
from typing import Callable

CAP_BYTES = 2 * 1024**3
TIMEOUT_S = float(os.environ.get("REPRO_TIMEOUT", "60"))
ENTRY = ("import sys; sys.argv[0] = 'solverplan'; from solverplan.cli import main; main()")
# Unprivileged runs: the interpreter lives under /root (not readable by others), so the child imports the CLI
# as root and only then drops to the user's ids, as a setuid wrapper would, before any input is touched.
ENTRY_AS = ("import os, sys, io, contextlib, encodings.ascii, encodings.latin_1; sys.argv[0] = 'solverplan'; from solverplan.cli import app, main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "    try: app(['info', 'square', '-o', os.devnull], standalone_mode=False)  # warm the imports as root\n"
            "    except BaseException: pass\n"
            "os.setgid({gid}); os.setgroups([]); os.setuid({uid}); main()")
SQUARE = {"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}


@dataclasses.dataclass(frozen=True)
class Case:
    name: str
    args: Callable[[Path], list[str]]  # builds the inputs in the folder, returns the command line
    stdin: bytes | None = None
    as_user: bool = False  # run as an unprivileged user (when the runner is root)
    ok_codes: tuple[int, ...] = (0, 2)


@dataclasses.dataclass
class Outcome:
    case: str
    code: int | None
    seconds: float
    peak_mib: float
    first_line: str
    problems: list[str]


# ---------------------------------------------------------------------- input makers
def _write(folder: Path, name: str, data: str | bytes) -> Path:
    path = folder / name
    path.write_bytes(data.encode() if isinstance(data, str) else data)
    return path


def _fifo(folder: Path, name: str) -> Path:
    path = folder / name
    os.mkfifo(path)
    return path


def _link(folder: Path, name: str, target: str) -> Path:
    path = folder / name
    path.symlink_to(target)
    return path


def _sparse(folder: Path, name: str, size: int = 1 << 30) -> Path:
    path = folder / name
    with open(path, "wb") as handle:
        handle.truncate(size)
    return path


def _png(width: int, height: int) -> bytes:
    """A 1-bit grey PNG of ``width × height`` white pixels, built by hand (compresses to ~ pixels / 2,000)."""
    row = b"\x00" + b"\xff" * ((width + 7) // 8)
    raw = zlib.compress(row * height, 9)

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 1, 0, 0, 0, 0))
            + chunk(b"IDAT", raw) + chunk(b"IEND", b""))


def _ros_map(folder: Path, image: str, extra: str = "") -> Path:
    return _write(folder, "map.yaml", f"image: {image}\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                                      f"occupied_thresh: 0.65\nfree_thresh: 0.196\n{extra}")


def _star(n: int) -> dict:
    import math

    pts = []
    for k in range(n):
        r = 10.0 if k % 2 == 0 else 7.0
        a = 2 * math.pi * k / n
        pts.append([round(r * math.cos(a), 9), round(r * math.sin(a), 9)])
    return {"outer": pts}


def _svg(body: str, defs: str = "") -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
            f'width="100" height="100"><defs>{defs}</defs>{body}</svg>')


_RECT = '<rect x="0" y="0" width="10" height="10" fill="none" stroke="black"/>'


def _use_fanout(levels: int = 9, fan: int = 10) -> str:
    defs = ['<g id="l0">' + _RECT + "</g>"]
    for i in range(1, levels + 1):
        defs.append(f'<g id="l{i}">' + "".join(f'<use xlink:href="#l{i - 1}"/>' for _ in range(fan)) + "</g>")
    return _svg(f'<use xlink:href="#l{levels}"/>', "".join(defs))


def _dxf(entities: str, blocks: str = "") -> str:
    head = "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009\n0\nENDSEC\n"
    block_section = f"0\nSECTION\n2\nBLOCKS\n{blocks}0\nENDSEC\n" if blocks else ""
    return head + block_section + f"0\nSECTION\n2\nENTITIES\n{entities}0\nENDSEC\n0\nEOF\n"


_LWPOLY = "".join(f"0\nLINE\n8\n0\n10\n{a}\n20\n{b}\n11\n{c}\n21\n{d}\n"
                  for a, b, c, d in ((0, 0, 4, 0), (4, 0, 4, 4), (4, 4, 0, 4), (0, 4, 0, 0)))


def _certificate(folder: Path) -> dict:
    out = folder / "cert.json"
    subprocess.run([sys.executable, "-c", ENTRY, "plan", "square", "--from", "e0", "--to", "e2",
                    "--certificate", str(out), "-o", str(folder / "plan.json")], capture_output=True, timeout=120)
    return json.loads(out.read_text())


def _with_certificate(edit: Callable[[dict], None]) -> Callable[[Path], list[str]]:
    def make(folder: Path) -> list[str]:
        data = _certificate(folder)
        edit(data)
        return ["verify", str(_write(folder, "bad.json", json.dumps(data)))]
    return make


def _plan_file(folder: Path) -> dict:
    out = folder / "plan.json"
    subprocess.run([sys.executable, "-c", ENTRY, "plan", "square", "--from", "e0", "--to", "e2", "-o", str(out)],
                   capture_output=True, timeout=120)
    return json.loads(out.read_text())


def _cache_bomb(folder: Path) -> list[str]:
    """A graph-cache folder whose entries are sparse 1.9 GB files (cheap on disk, 1.9 GB if read whole)."""
    cache = folder / "cache"
    cache.mkdir()
    subprocess.run([sys.executable, "-c", ENTRY, "--graph-cache", str(cache), "--graph-cache-min-arcs", "0",
                    "graph", "comb", "--safe", "-o", str(folder / "g.json")], capture_output=True, timeout=120)
    for entry in cache.glob("*.spg"):
        size = entry.stat().st_size
        with open(entry, "r+b") as handle:
            handle.truncate(1_900_000_000 if size < 1_900_000_000 else size)
    return ["--graph-cache", str(cache), "--graph-cache-min-arcs", "0", "graph", "comb", "--safe"]


def _protected(folder: Path, mode: int) -> list[str]:
    target = _write(folder, "protected.json", "keep me\n")
    target.chmod(mode)
    user = _unprivileged()
    if user is not None:  # the user's own read-only file in the user's own folder
        os.chown(folder, *user)
        os.chown(target, *user)
    return ["info", "square", "-o", str(target)]


def _root_owned_in_writable_folder(folder: Path) -> list[str]:
    folder.chmod(0o777)
    target = _write(folder, "root.json", "keep me\n")
    target.chmod(0o644)  # root's file, readable by all, writable by root only
    return ["info", "square", "-o", str(target)]


def _hard_link(folder: Path) -> list[str]:
    target = _write(folder, "answer.json", "old\n")
    os.link(target, folder / "other-name.json")
    user = _unprivileged()
    if user is not None:
        os.chown(folder, *user)
        os.chown(target, *user)
    return ["info", "square", "-o", str(target)]


def _writable_in_readonly_folder(folder: Path) -> list[str]:
    target = _write(folder, "answer.json", "old\n")
    target.chmod(0o666)
    folder.chmod(0o555)
    return ["info", "square", "-o", str(target)]


_LONG = "x" * 5000
_NAME_TOO_LONG = "y" * 300

CASES: list[Case] = [
    # ------------------------------------------------------------------ unbounded reads
    Case("read/symlink-dev-zero-env", lambda d: ["info", str(_link(d, "env.json", "/dev/zero"))]),
    Case("read/symlink-dev-urandom-env", lambda d: ["partition", str(_link(d, "env.json", "/dev/urandom"))]),
    Case("read/dev-zero-plan-simulate", lambda d: ["simulate", "square", "/dev/zero", "--trials", "10"]),
    Case("read/symlink-dev-zero-cert", lambda d: ["verify", str(_link(d, "c.json", "/dev/zero"))]),
    Case("read/symlink-dev-zero-png", lambda d: ["import", str(_ros_map(d, str(_link(d, "m.pgm", "/dev/zero")))),
                                                "-o", str(d / "o.json")]),
    Case("read/symlink-dev-zero-yaml", lambda d: ["import", str(_link(d, "m.yaml", "/dev/zero")), "-o", str(d / "o.json")]),
    Case("read/symlink-dev-zero-svg", lambda d: ["import", str(_link(d, "m.svg", "/dev/urandom")), "-o", str(d / "o.json")]),
    Case("read/symlink-dev-zero-dxf", lambda d: ["import", str(_link(d, "m.dxf", "/dev/zero")), "-o", str(d / "o.json")]),
    Case("read/dev-zero-rooms-check", lambda d: ["rooms", "warehouse", "--check", "/dev/zero"]),
    Case("read/dev-zero-report-plan", lambda d: ["report", "square", "--plan", "/dev/zero", "-o", str(d / "r.html")]),
    Case("read/dev-zero-report-study", lambda d: ["report", "--study", "/dev/zero", "-o", str(d / "r.html")]),
    Case("read/fifo-env", lambda d: ["info", str(_fifo(d, "env.json"))]),
    Case("read/fifo-plan", lambda d: ["simulate", "square", str(_fifo(d, "p.json")), "--trials", "10"]),
    Case("read/fifo-cert", lambda d: ["verify", str(_fifo(d, "c.json"))]),
    Case("read/fifo-yaml", lambda d: ["import", str(_fifo(d, "m.yaml")), "-o", str(d / "o.json")]),
    Case("read/fifo-svg", lambda d: ["import", str(_fifo(d, "m.svg")), "-o", str(d / "o.json")]),
    Case("read/fifo-dxf", lambda d: ["import", str(_fifo(d, "m.dxf")), "-o", str(d / "o.json")]),
    Case("read/fifo-png", lambda d: ["import", str(_ros_map(d, str(_fifo(d, "m.png")))), "-o", str(d / "o.json")]),
    Case("read/fifo-rooms-check", lambda d: ["rooms", "warehouse", "--check", str(_fifo(d, "r.json"))]),
    Case("read/fifo-report-plan", lambda d: ["report", "square", "--plan", str(_fifo(d, "p.json")), "-o", str(d / "r.html")]),
    Case("read/fifo-verify-env", lambda d: ["verify", str(_write(d, "c.json", json.dumps(_certificate(d)))),
                                            "--env", str(_fifo(d, "e.json"))]),
    Case("read/sparse-1g-plan", lambda d: ["simulate", "square", str(_sparse(d, "p.json")), "--trials", "10"]),
    Case("read/sparse-1g-cert", lambda d: ["verify", str(_sparse(d, "c.json"))]),
    Case("read/sparse-1g-env", lambda d: ["info", str(_sparse(d, "e.json"))]),
    Case("read/sparse-1g-svg", lambda d: ["import", str(_sparse(d, "m.svg")), "-o", str(d / "o.json")]),
    Case("read/sparse-1g-dxf", lambda d: ["import", str(_sparse(d, "m.dxf")), "-o", str(d / "o.json")]),
    Case("read/sparse-1g-png", lambda d: ["import", str(_ros_map(d, str(_sparse(d, "m.png")))), "-o", str(d / "o.json")]),
    Case("read/sparse-1g-yaml", lambda d: ["import", str(_sparse(d, "m.yaml")), "-o", str(d / "o.json")]),
    Case("read/sparse-1g-rooms-check", lambda d: ["rooms", "warehouse", "--check", str(_sparse(d, "r.json"))]),
    Case("read/sparse-1g-report", lambda d: ["report", "square", "--plan", str(_sparse(d, "p.json")), "-o", str(d / "r.html")]),
    Case("read/directory-env", lambda d: ["info", str(d)]),
    Case("read/directory-plan", lambda d: ["simulate", "square", str(d), "--trials", "10"]),
    Case("read/directory-cert", lambda d: ["verify", str(d)]),
    Case("read/stdin-zero-env", lambda d: ["info", "-"], stdin=b"\0" * 1000),
    # ------------------------------------------------------------------ memory beyond the input
    Case("memory/png-1e8-pixels", lambda d: ["import", str(_ros_map(d, str(_write(d, "m.png", _png(10_000, 10_000))))),
                                             "-o", str(d / "o.json")]),
    Case("memory/png-huge-header", lambda d: ["import", str(_ros_map(d, str(_write(d, "m.png", _png(100_000, 50))))),
                                              "-o", str(d / "o.json")]),
    Case("memory/yaml-billion-laughs", lambda d: ["import", str(_write(d, "m.yaml", "a: &a [x,x,x,x,x,x,x,x,x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [{','.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(9)))), "-o", str(d / "o.json")]),
    Case("memory/yaml-billion-laughs-image", lambda d: ["import", str(_write(d, "m.yaml", "a: &a [x,x,x,x,x,x,x,x,x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [{','.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(9)) + "image: *j\n")),
        "-o", str(d / "o.json")]),
    Case("memory/svg-use-fanout", lambda d: ["import", str(_write(d, "m.svg", _use_fanout())), "-o", str(d / "o.json")]),
    Case("memory/svg-use-fanout-wide", lambda d: ["import", str(_write(d, "m.svg", _use_fanout(6, 30))), "-o", str(d / "o.json")]),
    Case("memory/dxf-insert-fanout", lambda d: ["import", str(_write(d, "m.dxf", _dxf(
        "0\nINSERT\n8\n0\n2\nB6\n10\n0\n20\n0\n",
        "0\nBLOCK\n8\n0\n2\nB0\n70\n0\n10\n0\n20\n0\n" + _LWPOLY + "0\nENDBLK\n" + "".join(
            f"0\nBLOCK\n8\n0\n2\nB{i}\n70\n0\n10\n0\n20\n0\n" + "".join(
                f"0\nINSERT\n8\n0\n2\nB{i - 1}\n10\n{k}\n20\n0\n" for k in range(12)) + "0\nENDBLK\n" for i in range(1, 7))))),
        "-o", str(d / "o.json")]),
    Case("memory/study-grid-10001", lambda d: ["study", "reachability", "--grid", "n=10001", "--per-cell", "1",
                                               "--out-dir", str(d / "s"), "--workers", "1", "-q"]),
    Case("memory/study-grid-cells", lambda d: ["study", "reachability", "--grid", "n=3:10000:100000",
                                               "--out-dir", str(d / "s"), "--workers", "1", "-q"]),
    Case("memory/study-grid-per-cell", lambda d: ["study", "reachability", "--grid", "n=3:1000:10000", "--per-cell",
                                                  "100000", "--out-dir", str(d / "s"), "--workers", "1", "-q"]),
    Case("memory/rooms-simulate-huge", lambda d: ["rooms", "warehouse", "--simulate", "--from", "0", "--to", "1",
                                                  "--trials", "100000000", "--max-bounces", "10000000"]),
    Case("memory/rooms-simulate-all-rules", lambda d: ["rooms", "warehouse", "--simulate", "--from", "0", "--to", "1",
                                                       "--rule", "all", "--trials", "50000000", "--max-bounces", "1000"]),
    Case("memory/polygon-20k-plan", lambda d: ["plan", str(_write(d, "e.json", json.dumps(_star(20_000)))),
                                               "--from", "e0", "--to", "e10"]),
    Case("memory/polygon-100k-graph", lambda d: ["graph", str(_write(d, "e.json", json.dumps(_star(100_000))))]),
    Case("memory/polygon-50k-partition", lambda d: ["partition", str(_write(d, "e.json", json.dumps(_star(50_000))))]),
    Case("memory/polygon-100k-info", lambda d: ["info", str(_write(d, "e.json", json.dumps(_star(100_000))))]),
    Case("memory/polygon-20k-cycle", lambda d: ["cycle", str(_write(d, "e.json", json.dumps(_star(20_000))))]),
    Case("memory/polygon-10k-render", lambda d: ["render", str(_write(d, "e.json", json.dumps(_star(10_000)))),
                                                 "-o", str(d / "p.png")]),
    Case("memory/env-long-digits", lambda d: ["info", str(_write(d, "e.json", json.dumps({"outer": [
        [f"{k}.{'1' * 90}", f"{(k * k) % 9973}.{'3' * 90}"] for k in range(60_000)]})))]),
    Case("memory/cache-entry-bomb", _cache_bomb),
    Case("memory/png-36e6-pixels", lambda d: ["import", str(_ros_map(d, str(_write(d, "m.png", _png(6_000, 6_000))))),
                                              "-o", str(d / "o.json")]),
    Case("memory/env-60mb-short-numbers", lambda d: ["info", str(_write(d, "e.json", '{"outer": [' + ",".join(
        ["[0.1,0.2]"] * 6_000_000) + "]}"))]),
    Case("memory/env-30mb-decimals", lambda d: ["info", str(_write(d, "e.json", '{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], '
        '"extra": [' + ",".join(["1234567.12345678"] * 1_800_000) + "]}"))]),
    Case("memory/env-60mb-empty-objects", lambda d: ["info", str(_write(d, "e.json", "[" + ",".join(["{}"] * 20_000_000) + "]"))]),
    Case("memory/plan-60mb-numbers", lambda d: ["simulate", "square", str(_write(d, "p.json", "[" + ",".join(
        ["0.5"] * 15_000_000) + "]")), "--trials", "10"]),
    Case("memory/cert-60mb-numbers", lambda d: ["verify", str(_write(d, "c.json", '{"x": [' + ",".join(
        ["0.5"] * 15_000_000) + "]}"))]),
    Case("memory/cert-3.9m-decimals", lambda d: ["verify", str(_write(d, "c.json", '{"x": [' + ",".join(
        ["0.123456789012"] * 3_900_000) + "]}"))]),
    # ------------------------------------------------------------------ internal errors: import
    Case("import/svg-nested-g-1000", lambda d: ["import", str(_write(d, "m.svg", _svg("<g>" * 1000 + _RECT + "</g>" * 1000))),
                                                "-o", str(d / "o.json")]),
    Case("import/svg-nested-g-100000", lambda d: ["import", str(_write(d, "m.svg", _svg("<g>" * 100_000 + _RECT + "</g>" * 100_000))),
                                                  "-o", str(d / "o.json")]),
    Case("import/svg-self-use", lambda d: ["import", str(_write(d, "m.svg", _svg('<g id="a"><use xlink:href="#a"/>' + _RECT + "</g>"))),
                                           "-o", str(d / "o.json")]),
    Case("import/svg-use-cycle", lambda d: ["import", str(_write(d, "m.svg", _svg(
        '<g id="a"><use href="#b"/></g><g id="b"><use href="#a"/>' + _RECT + "</g>"))), "-o", str(d / "o.json")]),
    Case("import/svg-bad-attribute", lambda d: ["import", str(_write(d, "m.svg", _svg(
        '<rect x="a" y="b" width="c" height="d" transform="matrix(1)"/><path d="M 0 0 L"/><polygon points="1"/>'))),
        "-o", str(d / "o.json")]),
    Case("import/svg-empty-use", lambda d: ["import", str(_write(d, "m.svg", _svg('<use href="#nothing"/><use/>' + _RECT))),
                                            "-o", str(d / "o.json")]),
    Case("import/svg-not-svg", lambda d: ["import", str(_write(d, "m.svg", "<html><body/></html>")), "-o", str(d / "o.json")]),
    Case("import/svg-text-root", lambda d: ["import", str(_write(d, "m.svg", "just text")), "-o", str(d / "o.json")]),
    Case("import/svg-entity-bomb", lambda d: ["import", str(_write(d, "m.svg",
        '<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa">' + "".join(
            f'<!ENTITY {chr(98 + i)} "{("&" + chr(97 + i) + ";") * 10}">' for i in range(8)) + ']><svg xmlns="http://www.w3.org/2000/svg"><text>&i;</text></svg>')),
        "-o", str(d / "o.json")]),
    Case("import/dxf-truncated", lambda d: ["import", str(_write(d, "m.dxf", "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n")),
                                            "-o", str(d / "o.json")]),
    Case("import/dxf-odd-lines", lambda d: ["import", str(_write(d, "m.dxf", "0\nSECTION\n2\n")), "-o", str(d / "o.json")]),
    Case("import/dxf-empty", lambda d: ["import", str(_write(d, "m.dxf", "")), "-o", str(d / "o.json")]),
    Case("import/dxf-missing-block", lambda d: ["import", str(_write(d, "m.dxf", _dxf("0\nINSERT\n8\n0\n2\nNOPE\n10\n0\n20\n0\n" + _LWPOLY))),
                                                "-o", str(d / "o.json")]),
    Case("import/dxf-self-insert", lambda d: ["import", str(_write(d, "m.dxf", _dxf(
        "0\nINSERT\n8\n0\n2\nB\n10\n0\n20\n0\n" + _LWPOLY,
        "0\nBLOCK\n8\n0\n2\nB\n70\n0\n10\n0\n20\n0\n0\nINSERT\n8\n0\n2\nB\n10\n1\n20\n0\n0\nENDBLK\n"))), "-o", str(d / "o.json")]),
    Case("import/dxf-bad-number", lambda d: ["import", str(_write(d, "m.dxf", _dxf(_LWPOLY.replace("11\n4\n", "11\nfour\n", 1)))),
                                             "-o", str(d / "o.json")]),
    Case("import/dxf-binary-garbage", lambda d: ["import", str(_write(d, "m.dxf", b"AutoCAD Binary DXF\r\n\x1a\x00" + random.Random(28).randbytes(200))),
                                                 "-o", str(d / "o.json")]),
    *(Case(f"import/dxf-binary-garbage-{seed}", lambda d, seed=seed: ["import", str(_write(d, "m.dxf", b"AutoCAD Binary DXF\r\n\x1a\x00"
        + random.Random(seed).randbytes(20 + 40 * seed))), "-o", str(d / "o.json")]) for seed in range(1, 6)),
    Case("import/dxf-huge-vertex-count", lambda d: ["import", str(_write(d, "m.dxf", _dxf(
        "0\nLWPOLYLINE\n8\n0\n90\n999999999\n70\n1\n10\n0\n20\n0\n10\n4\n20\n0\n10\n4\n20\n4\n"))), "-o", str(d / "o.json")]),
    Case("import/yaml-deep-nesting", lambda d: ["import", str(_write(d, "m.yaml", "image: " + "[" * 10_000 + "]" * 10_000 + "\n")),
                                                "-o", str(d / "o.json")]),
    Case("import/yaml-deep-mapping", lambda d: ["import", str(_write(d, "m.yaml", "a: " + "{b: " * 5000 + "1" + "}" * 5000 + "\n")),
                                                "-o", str(d / "o.json")]),
    Case("import/yaml-recursive-alias", lambda d: ["import", str(_write(d, "m.yaml", "image: &a [*a]\n")), "-o", str(d / "o.json")]),
    Case("import/yaml-not-mapping", lambda d: ["import", str(_write(d, "m.yaml", "- 1\n- 2\n")), "-o", str(d / "o.json")]),
    Case("import/yaml-bad-types", lambda d: ["import", str(_write(d, "m.yaml", "image: [1]\nresolution: abc\norigin: 5\n")),
                                             "-o", str(d / "o.json")]),
    Case("import/yaml-python-tag", lambda d: ["import", str(_write(d, "m.yaml", "image: !!python/object/apply:os.system ['true']\n")),
                                              "-o", str(d / "o.json")]),
    Case("import/png-truncated", lambda d: ["import", str(_ros_map(d, str(_write(d, "m.png", _png(100, 100)[:60])))),
                                            "-o", str(d / "o.json")]),
    Case("import/png-not-image", lambda d: ["import", str(_ros_map(d, str(_write(d, "m.png", "hello")))), "-o", str(d / "o.json")]),
    Case("import/yaml-image-long-path", lambda d: ["import", str(_ros_map(d, "/" + "a" * 5000 + ".png")), "-o", str(d / "o.json")]),
    # ------------------------------------------------------------------ internal errors: plan, answer and certificate files
    Case("files/cert-version-float", _with_certificate(lambda c: c.__setitem__("version", 2.0))),
    Case("files/cert-version-string", _with_certificate(lambda c: c.__setitem__("version", "3"))),
    Case("files/cert-version-huge", _with_certificate(lambda c: c.__setitem__("version", 10**30))),
    Case("files/cert-version-bool", _with_certificate(lambda c: c.__setitem__("version", True))),
    Case("files/cert-stages-null", _with_certificate(lambda c: c.__setitem__("stages", None))),
    Case("files/cert-stages-dict", _with_certificate(lambda c: c.__setitem__("stages", {"a": 1}))),
    Case("files/cert-claims-list", _with_certificate(lambda c: c.__setitem__("claims", [1, 2]))),
    Case("files/cert-env-number", _with_certificate(lambda c: c.__setitem__("environment", 3))),
    Case("files/cert-objective-wrong", _with_certificate(lambda c: c["claims"].__setitem__("objective", 12345)),
         ok_codes=(1, 2)),
    Case("files/cert-long-string", _with_certificate(lambda c: c.__setitem__("kind", "k" * 10_000))),
    Case("files/cert-not-object", lambda d: ["verify", str(_write(d, "c.json", "[1, 2, 3]"))]),
    Case("files/cert-deep", lambda d: ["verify", str(_write(d, "c.json", "[" * 100_000))]),
    Case("files/cert-huge-exponent", lambda d: ["verify", str(_write(d, "c.json", '{"version": 1e999999999}'))]),
    Case("files/cert-long-int", lambda d: ["verify", str(_write(d, "c.json", '{"version": ' + "9" * 5000 + "}"))]),
    Case("files/plan-version-float", lambda d: ["simulate", "square", str(_write(d, "p.json", json.dumps(
        {**_plan_file(d), "version": 2.0}))), "--trials", "10"]),
    Case("files/plan-stages-null", lambda d: ["simulate", "square", str(_write(d, "p.json", json.dumps(
        {**_plan_file(d), "stages": None}))), "--trials", "10"]),
    Case("files/plan-stages-strings", lambda d: ["simulate", "square", str(_write(d, "p.json", json.dumps(
        {**_plan_file(d), "stages": ["a", "b"]}))), "--trials", "10"]),
    Case("files/plan-empty-object", lambda d: ["simulate", "square", str(_write(d, "p.json", "{}")), "--trials", "10"]),
    Case("files/plan-list", lambda d: ["simulate", "square", str(_write(d, "p.json", "[]")), "--trials", "10"]),
    Case("files/plan-not-utf8", lambda d: ["simulate", "square", str(_write(d, "p.json", b"\xff\xfe\x00")), "--trials", "10"]),
    Case("files/report-plan-garbage", lambda d: ["report", "square", "--plan", str(_write(d, "p.json", '{"status": 5}')),
                                                 "-o", str(d / "r.html")]),
    Case("files/report-study-garbage", lambda d: ["report", "--study", str(_write(d, "s.json", '{"rows": 5, "name": []}')),
                                                  "-o", str(d / "r.html")]),
    Case("files/report-cycle-garbage", lambda d: ["report", "square", "--cycle", str(_write(d, "c.json", '{"cycle": "x"}')),
                                                  "-o", str(d / "r.html")]),
    Case("files/report-funnel-garbage", lambda d: ["report", "square", "--funnel", str(_write(d, "f.json", '{"stages": [1]}')),
                                                   "-o", str(d / "r.html")]),
    Case("files/report-patrol-garbage", lambda d: ["report", "square", "--patrol", str(_write(d, "f.json", '{"cycle": {"a": 1}}')),
                                                   "-o", str(d / "r.html")]),
    Case("files/report-cert-garbage", lambda d: ["report", "square", "--certificate", str(_write(d, "c.json", '{"version": 2.0}')),
                                                 "-o", str(d / "r.html")]),
    # ------------------------------------------------------------------ rooms --check
    Case("rooms/check-empty-object", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json", "{}"))], ok_codes=(1, 2)),
    Case("rooms/check-list", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json", "[1]"))], ok_codes=(1, 2)),
    Case("rooms/check-rooms-null", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json", '{"rooms": null, "doors": 3}'))],
         ok_codes=(1, 2)),
    Case("rooms/check-rooms-strings", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json",
        '{"rooms": ["a"], "doors": [{"a": 1}]}'))], ok_codes=(1, 2)),
    Case("rooms/check-rooms-bad-rect", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json",
        '{"rooms": [{"id": 0, "rect": [1]}], "doors": [[0, 1, "x"]]}'))], ok_codes=(1, 2)),
    Case("rooms/check-deep", lambda d: ["rooms", "warehouse", "--check", str(_write(d, "r.json", "[" * 100_000))], ok_codes=(1, 2)),
    Case("rooms/check-not-rectilinear", lambda d: ["rooms", "square", "--check", str(_write(d, "r.json", "{}"))], ok_codes=(1, 2)),
    # ------------------------------------------------------------------ numbers and options
    Case("options/explore-range-tiny", lambda d: ["explore", "square", "--start", "1,1", "--range", "1e-309"]),
    Case("options/explore-range-huge", lambda d: ["explore", "square", "--start", "1,1", "--range", "1e309"]),
    Case("options/explore-range-nan", lambda d: ["explore", "square", "--start", "1,1", "--range", "nan"]),
    Case("options/explore-start-huge", lambda d: ["explore", "square", "--start", "1e309,1"]),
    Case("options/indent-huge", lambda d: ["--indent", "999999999999", "info", "square"]),
    Case("options/indent-large", lambda d: ["--indent", "100000000", "info", "square"]),
    Case("options/max-memory-huge", lambda d: ["--max-memory", "9" * 400, "info", "square"]),
    Case("options/graph-cache-size-huge", lambda d: ["--graph-cache-size", "1e999", "info", "square"]),
    Case("options/long-env-path", lambda d: ["info", "/tmp/" + _LONG + ".json"]),
    Case("options/long-name-component", lambda d: ["info", str(d / (_NAME_TOO_LONG + ".json"))]),
    Case("options/long-output-path", lambda d: ["info", "square", "-o", str(d / (_NAME_TOO_LONG + ".json"))]),
    Case("options/long-output-path-total", lambda d: ["info", "square", "-o", "/tmp/" + "/".join(["z" * 200] * 30) + ".json"]),
    Case("options/long-cache-path", lambda d: ["--graph-cache", str(d / _NAME_TOO_LONG), "--graph-cache-min-arcs", "0",
                                               "graph", "square", "--safe"]),
    Case("options/long-cache-path-total", lambda d: ["--graph-cache", "/tmp/" + "/".join(["c" * 250] * 20),
                                                     "--graph-cache-min-arcs", "0", "graph", "square", "--safe"]),
    Case("options/long-cache-info", lambda d: ["--graph-cache", str(d / _NAME_TOO_LONG), "cache", "info"]),
    Case("options/long-certificate-path", lambda d: ["plan", "square", "--from", "e0", "--to", "e2", "--certificate",
                                                     str(d / (_NAME_TOO_LONG + ".json"))]),
    Case("options/long-picture-path", lambda d: ["info", "square", "--picture", str(d / (_NAME_TOO_LONG + ".png"))]),
    Case("options/long-study-out-dir", lambda d: ["study", "reachability", "--grid", "n=6", "--per-cell", "1",
                                                  "--out-dir", str(d / _NAME_TOO_LONG), "--workers", "1", "-q"]),
    Case("options/long-import-path", lambda d: ["import", "/tmp/" + _LONG + ".svg", "-o", str(d / "o.json")]),
    Case("options/long-verify-path", lambda d: ["verify", str(d / (_NAME_TOO_LONG + ".json"))]),
    Case("options/long-from-set", lambda d: ["plan", "square", "--from", "e0," * 3000 + "e1", "--to", "e2"]),
    Case("options/scheduler-garbage", lambda d: ["study", "reachability", "--grid", "n=6", "--per-cell", "1",
                                                 "--scheduler", "not a :: address", "--out-dir", str(d / "s"), "-q"]),
    Case("options/scheduler-bad-port", lambda d: ["study", "reachability", "--grid", "n=6", "--per-cell", "1",
                                                  "--scheduler", "tcp://127.0.0.1:99999", "--out-dir", str(d / "s"), "-q"]),
    Case("options/scheduler-bad-scheme", lambda d: ["study", "reachability", "--grid", "n=6", "--per-cell", "1",
                                                    "--scheduler", "http://[::1", "--out-dir", str(d / "s"), "-q"]),
    Case("options/scheduler-closed-port", lambda d: ["study", "reachability", "--grid", "n=6", "--per-cell", "1",
                                                     "--scheduler", "tcp://127.0.0.1:1", "--out-dir", str(d / "s"), "-q"]),
    Case("options/grid-bad", lambda d: ["study", "reachability", "--grid", "n=1e309", "--out-dir", str(d / "s"), "-q"]),
    Case("options/grid-range-huge", lambda d: ["study", "reachability", "--grid", "n=3:5:99999999999", "--out-dir", str(d / "s"), "-q"]),
    # ------------------------------------------------------------------ -o and permissions
    Case("write/readonly-0444", lambda d: _protected(d, 0o444), as_user=True, ok_codes=(2,)),
    Case("write/root-owned-in-writable-folder", _root_owned_in_writable_folder, as_user=True, ok_codes=(2,)),
    Case("write/readonly-folder", lambda d: (d.chmod(0o555), ["info", "square", "-o", str(d / "new.json")])[1],
         as_user=True, ok_codes=(2,)),
    Case("write/hard-link-kept", _hard_link, ok_codes=(0,)),
    Case("write/hard-link-kept-as-user", _hard_link, as_user=True, ok_codes=(0,)),
    Case("write/writable-file-in-readonly-folder", _writable_in_readonly_folder, as_user=True, ok_codes=(0,)),
    Case("write/into-directory", lambda d: ["info", "square", "-o", str(d)], ok_codes=(2,)),
    Case("write/into-missing-folder", lambda d: ["info", "square", "-o", str(d / "no" / "x.json")], ok_codes=(2,)),
]


# ---------------------------------------------------------------------- running
def _unprivileged() -> tuple[int, int] | None:
    if os.geteuid() != 0:
        return None
    import pwd

    try:
        entry = pwd.getpwnam("nobody")
    except KeyError:
        return None
    return entry.pw_uid, entry.pw_gid


def _limits() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (CAP_BYTES, CAP_BYTES))
    os.setsid()


def run_case(case: Case, root: Path) -> Outcome:
    folder = Path(tempfile.mkdtemp(prefix="repro.", dir=root))
    folder.chmod(0o755)
    try:
        args = case.args(folder)
    except Exception as exc:  # the runner could not build the input
        return Outcome(case.name, None, 0.0, 0.0, f"setup failed: {exc!r}", ["setup"])
    user = _unprivileged() if case.as_user else None
    env = dict(os.environ, COLUMNS="120", PYTHONFAULTHANDLER="")
    env.setdefault("XDG_CACHE_HOME", str(root / "xdg"))
    start = time.monotonic()
    entry = ENTRY if user is None else ENTRY_AS.format(uid=user[0], gid=user[1])
    proc = subprocess.Popen([sys.executable, "-c", entry, *args], stdin=subprocess.PIPE if case.stdin is not None
                            else subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=folder, env=env,
                            preexec_fn=_limits)
    problems: list[str] = []
    try:
        out, err = proc.communicate(case.stdin, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        problems.append("hang")
    seconds = time.monotonic() - start
    peak = _peaks.pop(proc.pid, 0.0)
    text = err.decode("utf-8", "replace")
    lines = text.splitlines()
    if proc.returncode not in case.ok_codes and "hang" not in problems:
        problems.append(f"exit {proc.returncode}")
    if "Traceback" in text:
        problems.append("traceback")
    if "MemoryError" in text or peak > CAP_BYTES / 2**20:
        problems.append("memory")
    if proc.returncode in (1, 2) and (len(lines) != 1 or len(lines[0]) > 200):
        problems.append(f"{len(lines)} stderr lines, longest {max(map(len, lines), default=0)}")
    if case.as_user and user is None and os.geteuid() == 0:
        problems.append("not run unprivileged")
    if case.name.startswith("write/") and (folder / "protected.json").exists():
        if (folder / "protected.json").read_text() != "keep me\n":
            problems.append("protected file replaced")
    if case.name.startswith("write/") and (folder / "root.json").exists():
        if (folder / "root.json").read_text() != "keep me\n" or (folder / "root.json").stat().st_uid != 0:
            problems.append("root's file replaced")
    if case.name.startswith("write/hard-link") and proc.returncode == 0:
        linked = folder / "other-name.json"
        if linked.read_text() != (folder / "answer.json").read_text() or linked.stat().st_nlink != 2:
            problems.append("hard link broken")
    if case.name.startswith("write/writable-file") and proc.returncode == 0:
        if (folder / "answer.json").read_text() == "old\n":
            problems.append("not written")
    folder.chmod(0o755)
    shutil.rmtree(folder, ignore_errors=True)
    return Outcome(case.name, proc.returncode, seconds, peak, lines[0][:160] if lines else "", problems)


_peaks: dict[int, float] = {}


def _reap_with_usage() -> None:
    """Make subprocess's wait record each child's own peak RSS (``os.wait4``) before it is reaped."""
    original = subprocess.Popen._try_wait  # type: ignore[attr-defined]

    def try_wait(self, wait_flags):  # noqa: ANN001
        try:
            pid, status, usage = os.wait4(self.pid, wait_flags)
        except ChildProcessError:
            return original(self, wait_flags)
        if pid:
            _peaks[pid] = usage.ru_maxrss / 1024
        return pid, status

    subprocess.Popen._try_wait = try_wait  # type: ignore[attr-defined]


def run(cases: list[Case]) -> list[Outcome]:
    _reap_with_usage()
    root = Path(tempfile.mkdtemp(prefix="input-repro."))
    root.chmod(0o755)
    outcomes = []
    try:
        for case in cases:
            outcome = run_case(case, root)
            outcomes.append(outcome)
            mark = "ok  " if not outcome.problems else "FAIL"
            print(f"{mark} {outcome.case:42s} exit={outcome.code!s:4s} {outcome.seconds:6.1f}s {outcome.peak_mib:7.0f}MiB "
                  f"{';'.join(outcome.problems):20s} {outcome.first_line[:110]}", flush=True)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    return outcomes


def summary(outcomes: list[Outcome]) -> str:
    def count(word: str) -> int:
        return sum(any(p.startswith(word) for p in o.problems) for o in outcomes)

    return (f"{len(outcomes)} cases: {sum(not o.problems for o in outcomes)} clean, {count('exit 1')} exit-1, "
            f"{count('traceback')} tracebacks, {count('hang')} hangs, {count('memory')} over 2 GiB, "
            f"{sum(bool(o.problems) for o in outcomes)} failing; peak {max((o.peak_mib for o in outcomes), default=0):.0f} MiB")


if __name__ == "__main__":
    words = sys.argv[1:]
    chosen = [c for c in CASES if not words or any(w in c.name for w in words)]
    results = run(chosen)
    print(summary(results))
    sys.exit(0 if all(not o.problems for o in results) else 1)
