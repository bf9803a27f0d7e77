"""Fuzzing the input files of issue #28: drawings (SVG, DXF), ROS maps (YAML, PNG), plan, answer, certificate and
rooms files, and the options that name paths or addresses.

Every example runs one command through typer's CliRunner. The outcome must be an answer (exit 0), bad input (exit
2 with one stderr line of at most 200 characters) or, for ``verify`` and ``rooms --check``, an invalid file said
in one line (exit 1 with the report on stdout) — never an internal error, a traceback or a hang. Each class of
failure the issue's fuzz found is an explicit ``@example``; tests/test_input_reproducers.py runs the same classes
as real processes under a 2 GiB memory cap (benchmarks/input_reproducers.py).

The default (``ci``) profile runs a few dozen generated examples per test; ``HYPOTHESIS_PROFILE=fuzz`` runs
10,000 each (``FUZZ_EXAMPLES=N`` for another count)::

    HYPOTHESIS_PROFILE=fuzz FUZZ_EXAMPLES=2000 .venv/bin/python -m pytest tests/test_fuzz_input_files.py -q
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from benchmarks.input_reproducers import _LWPOLY as _SQUARE_LINES  # the 4 × 4 square as DXF lines
from benchmarks.input_reproducers import _dxf, _png  # the reproducers' hand-built drawings and pictures
from solverplan.cli import app
from tests.test_fuzz_cli import EXAMPLES, FUZZ, FUZZING, _numbers

MAX_LINE = 200

FUZZ_FEW = settings(FUZZ, max_examples=EXAMPLES if FUZZING else 8)
"""For the tests whose examples take a second or more (plans, reports, checks): fewer in the CI profile."""


def _one_line_or_answer(result, *, invalid_ok: bool = False) -> None:
    """exit 0; or exit 2 (1 for a checked file found invalid) with exactly one stderr line ≤ 200 characters."""
    allowed = (0, 1, 2) if invalid_ok else (0, 2)
    assert result.exit_code in allowed, (result.exit_code, result.stderr[-600:])
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr[-600:]
    if result.exit_code:
        lines = result.stderr.splitlines()
        assert len(lines) == 1 and len(lines[0]) <= MAX_LINE, result.stderr[-600:]


def _run(args: list[str], **kwargs):
    return CliRunner().invoke(app, args, **kwargs)


# ---------------------------------------------------------------------- SVG
_SVG_HEAD = '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100" height="100">'
_RECT = '<rect x="0" y="0" width="10" height="10"/>'
_ATTRIBUTE_VALUES = st.sampled_from(["0", "10", "-5", "a", "", "1e400", "nan", "matrix(1)", "matrix(1 0 0 1 0 0)",
                                     "rotate(", "M 0 0 L", "M 0 0 L 10 0 10 10 Z", "1,2 3", "#a", "#b", "#self",
                                     "url(#a)", "scale(0)", "translate(1e308)"])
_ATTRIBUTES = st.sampled_from(["x", "y", "width", "height", "d", "points", "transform", "href", "xlink:href", "id",
                               "cx", "cy", "r", "rx", "viewBox"])
_TAGS = st.sampled_from(["g", "use", "rect", "path", "polygon", "polyline", "circle", "ellipse", "line", "defs",
                         "symbol", "svg", "text", "clipPath"])


@st.composite
def _svg_elements(draw, depth: int = 0) -> str:
    tag = draw(_TAGS)
    attributes = draw(st.dictionaries(_ATTRIBUTES, _ATTRIBUTE_VALUES, max_size=4))
    text = " ".join(f'{k}="{v}"' for k, v in attributes.items())
    if depth >= 3 or tag not in ("g", "defs", "symbol", "svg", "clipPath"):
        return f"<{tag} {text}/>"
    children = draw(st.lists(_svg_elements(depth + 1), max_size=3))
    return f"<{tag} {text}>{''.join(children)}</{tag}>"


@st.composite
def svg_texts(draw) -> str:
    kind = draw(st.integers(0, 3))
    if kind == 0:  # random trees with ids and references between them
        body = "".join(draw(st.lists(_svg_elements(), min_size=1, max_size=4)))
        return _SVG_HEAD + body + "</svg>"
    if kind == 1:  # deep nesting, possibly past the bound
        n = draw(st.integers(1, 300))
        return _SVG_HEAD + "<g>" * n + _RECT + "</g>" * n + "</svg>"
    if kind == 2:  # <use> fan-out: levels × copies
        levels, fan = draw(st.integers(1, 8)), draw(st.integers(1, 12))
        defs = ['<g id="l0">' + _RECT + "</g>"] + [
            f'<g id="l{i}">' + f'<use href="#l{i - 1}"/>' * fan + "</g>" for i in range(1, levels + 1)]
        return _SVG_HEAD + "<defs>" + "".join(defs) + f'</defs><use href="#l{levels}"/></svg>'
    text = _SVG_HEAD + _RECT + "</svg>"  # a valid drawing cut or changed anywhere
    cut = draw(st.integers(0, len(text)))
    return text[:cut] + draw(st.text(max_size=3)) + text[cut + 1:]


@FUZZ
@given(text=svg_texts())
@example(text=_SVG_HEAD + "<g>" * 1000 + _RECT + "</g>" * 1000 + "</svg>")  # RecursionError in svgelements (#28)
@example(text=_SVG_HEAD + '<g id="a"><use href="#a"/>' + _RECT + "</g></svg>")  # a <use> of its own group
@example(text=_SVG_HEAD + '<g id="a"><use href="#b"/></g><g id="b"><use href="#a"/></g></svg>')  # a <use> cycle
@example(text=_SVG_HEAD + "<defs>" + '<g id="l0">' + _RECT + "</g>" + "".join(
    f'<g id="l{i}">' + f'<use href="#l{i - 1}"/>' * 10 + "</g>" for i in range(1, 10)) + '</defs><use href="#l9"/></svg>')
@example(text=_SVG_HEAD + '<rect x="a" y="b" width="c" height="d" transform="matrix(1)"/></svg>')  # AttributeError
@example(text="<html><body/></html>")  # not an SVG root: AttributeError in svgelements
@example(text='<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;">]>'
              '<svg xmlns="http://www.w3.org/2000/svg"><text>&b;</text></svg>')  # entity expansion
def test_fuzzed_svg_drawings_import_or_refuse_in_one_line(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("svg")
    drawing = folder / "plan.svg"
    drawing.write_text(text)
    _one_line_or_answer(_run(["import", str(drawing), "-o", str(folder / "env.json")]))


# ---------------------------------------------------------------------- DXF


@st.composite
def dxf_texts(draw) -> str:
    kind = draw(st.integers(0, 2))
    if kind == 0:  # random group code / value pairs inside the sections
        pairs = draw(st.lists(st.tuples(st.sampled_from(["0", "2", "8", "10", "20", "11", "21", "70", "90", "42", "x"]),
                                        st.sampled_from(["LINE", "LWPOLYLINE", "INSERT", "B", "0", "4", "1e400", "nan",
                                                         "SECTION", "ENDSEC", "BLOCK", "ENDBLK", "", "-1"])),
                              max_size=30))
        return _dxf("".join(f"{code}\n{value}\n" for code, value in pairs))
    if kind == 1:  # block references, possibly to missing or self-referencing blocks
        name = draw(st.sampled_from(["B", "NOPE", ""]))
        blocks = draw(st.sampled_from(["", "0\nBLOCK\n8\n0\n2\nB\n70\n0\n10\n0\n20\n0\n" + _SQUARE_LINES + "0\nENDBLK\n",
                                       "0\nBLOCK\n8\n0\n2\nB\n70\n0\n10\n0\n20\n0\n0\nINSERT\n8\n0\n2\nB\n10\n1\n20\n0\n0\nENDBLK\n"]))
        return _dxf(f"0\nINSERT\n8\n0\n2\n{name}\n10\n0\n20\n0\n" + _SQUARE_LINES, blocks)
    text = _dxf(_SQUARE_LINES)  # a valid drawing cut or changed anywhere
    cut = draw(st.integers(0, len(text)))
    return text[:cut] + draw(st.text(max_size=3)) + text[cut + 1:]


@FUZZ_FEW  # 12⁶ inserted squares (refused after 200,000, in ~30 s): tests/test_input_reproducers.py (slow)
@given(text=dxf_texts())
@example(text="0\nSECTION\n2\n")  # StopIteration inside ezdxf (#28)
@example(text=_dxf("0\nINSERT\n8\n0\n2\nNOPE\n10\n0\n20\n0\n" + _SQUARE_LINES))  # DXFStructureError: missing block
@example(text="0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n")  # truncated
@example(text="")
def test_fuzzed_dxf_drawings_import_or_refuse_in_one_line(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("dxf")
    drawing = folder / "plan.dxf"
    drawing.write_text(text)
    _one_line_or_answer(_run(["import", str(drawing), "-o", str(folder / "env.json")]))


# ---------------------------------------------------------------------- ROS maps: YAML and images
_LAUGHS = "a: &a [x,x,x,x,x,x,x,x,x]\n" + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{','.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(9))


@st.composite
def map_yaml_texts(draw) -> str:
    kind = draw(st.integers(0, 2))
    if kind == 0:
        lines = {"image": draw(st.sampled_from(["m.png", "", "*a", "[1]", "/dev/zero", "missing.png", "m.png\x00"])),
                 "resolution": draw(st.sampled_from(["0.1", "0", "-1", "abc", "1e400", "*a", ".nan"])),
                 "origin": draw(st.sampled_from(["[0, 0, 0]", "5", "[1e400, 0, 0]", "[*a, 0]", "[]"]))}
        text = "".join(f"{k}: {v}\n" for k, v in lines.items() if draw(st.booleans()) or k == "image")
        return draw(st.sampled_from(["", "x: &a 1\n", _LAUGHS])) + text
    if kind == 1:
        n = draw(st.integers(1, 200))
        return "image: " + "[" * n + "]" * n + "\nresolution: 0.1\norigin: [0, 0, 0]\n"
    return draw(st.text(max_size=60))


@FUZZ_FEW
@given(text=map_yaml_texts(), image=st.sampled_from(["tiny", "truncated", "text", "wide"]))
@example(text=_LAUGHS + "image: m.png\nresolution: 0.1\norigin: *j\n", image="tiny")  # billion laughs (#28)
@example(text="image: " + "[" * 10_000 + "]" * 10_000 + "\n", image="tiny")  # YAML RecursionError (#28)
@example(text="image: &a [*a]\n", image="tiny")
@example(text="image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\n", image="wide")
def test_fuzzed_ros_maps_import_or_refuse_in_one_line(tmp_path_factory, text, image):
    folder = tmp_path_factory.mktemp("map")
    pictures = {"tiny": _png(8, 8), "truncated": _png(50, 50)[:60], "text": b"hello", "wide": _png(50_000, 1_000)}
    (folder / "m.png").write_bytes(pictures[image])
    (folder / "map.yaml").write_text(text)
    _one_line_or_answer(_run(["import", str(folder / "map.yaml"), "-o", str(folder / "env.json")]))


# ---------------------------------------------------------------------- plan, answer, certificate and rooms files
@pytest.fixture(scope="module")
def answer_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("answers")
    plan, cert = folder / "plan.json", folder / "cert.json"
    result = _run(["plan", "square", "--from", "e0", "--to", "e2", "-o", str(plan), "--certificate", str(cert)])
    assert result.exit_code == 0, result.stderr
    rooms = folder / "rooms.json"
    result = _run(["rooms", "warehouse", "-o", str(rooms)])
    assert result.exit_code == 0, result.stderr
    return {"plan": json.loads(plan.read_text()), "cert": json.loads(cert.read_text()),
            "rooms": json.loads(rooms.read_text())}


def _paths(data, prefix=()):
    """Every (path, value) of a JSON value, depth first."""
    yield prefix, data
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _paths(value, (*prefix, key))
    elif isinstance(data, list):
        for k, value in enumerate(data[:4]):
            yield from _paths(value, (*prefix, k))


def _replaced(data, path, value):
    if not path:
        return value
    copy = json.loads(json.dumps(data))
    node = copy
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return copy


_REPLACEMENTS = st.one_of(_numbers, st.sampled_from([2.0, 3.0, 1.5, [], {}, [[]], "x" * 300, {"a": [1, {"b": None}]},
                                                     "e0", "1/0", "0/0", "-1", 10**30]))
_COMMANDS = {
    "simulate": lambda p, folder: ["simulate", "square", str(p), "--trials", "5"],
    "verify": lambda p, folder: ["verify", str(p)],
    "report-plan": lambda p, folder: ["report", "square", "--plan", str(p), "-o", str(folder / "r.html")],
    "report-certificate": lambda p, folder: ["report", "square", "--plan", str(folder / "plan.json"), "--certificate",
                                             str(p), "-o", str(folder / "r.html")],
    "rooms-check": lambda p, folder: ["rooms", "warehouse", "--check", str(p)],
}
_SOURCE = {"simulate": "plan", "verify": "cert", "report-plan": "plan", "report-certificate": "cert",
           "rooms-check": "rooms"}


@FUZZ_FEW
@given(command=st.sampled_from(sorted(_COMMANDS)), data=st.data())
@example(command="verify", data=("version", 2.0))  # "version": 2.0 as a JSON number (#28)
@example(command="verify", data=("version", 3.0))
@example(command="report-certificate", data=("version", 2.0))
@example(command="simulate", data=("version", 2.0))
@example(command="simulate", data=("stages", None))
@example(command="report-plan", data=("status", 5))
@example(command="rooms-check", data=("rooms", None))
@example(command="rooms-check", data=("doors", [{"a": 1}]))
@example(command="rooms-check", data=("", [1]))
@example(command="verify", data=("claims.objective", "fewest-by-magic"))
def test_fuzzed_answer_files_are_read_or_refused_in_one_line(tmp_path_factory, answer_files, command, data):
    folder = tmp_path_factory.mktemp("file")
    source = answer_files[_SOURCE[command]]
    if isinstance(data, tuple):  # the explicit examples: (dotted path, value)
        path = tuple(int(k) if k.isdigit() else k for k in data[0].split(".")) if data[0] else ()
        value = data[1]
    else:
        choices = list(_paths(source))
        path, _old = data.draw(st.sampled_from(choices))
        value = data.draw(_REPLACEMENTS)
    (folder / "plan.json").write_text(json.dumps(answer_files["plan"]))
    target = folder / "input.json"
    target.write_text(json.dumps(_replaced(source, path, value), allow_nan=True, default=str))
    _one_line_or_answer(_run(_COMMANDS[command](target, folder)), invalid_ok=command in ("verify", "rooms-check",
                                                                                         "report-certificate"))


# ---------------------------------------------------------------------- what is not a regular file, and long names
_SPECIAL = {
    "dev-zero": lambda folder, name: _symlink(folder / name, "/dev/zero"),
    "dev-urandom": lambda folder, name: _symlink(folder / name, "/dev/urandom"),
    "fifo": lambda folder, name: os.mkfifo(folder / name),
    "directory": lambda folder, name: (folder / name).mkdir(),
    "sparse": lambda folder, name: os.truncate(_touch(folder / name), 1 << 30),
    "long-name": None,
}


def _symlink(path: Path, target: str) -> None:
    path.symlink_to(target)


def _touch(path: Path) -> Path:
    path.write_bytes(b"")
    return path


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs")
@pytest.mark.parametrize("kind", sorted(_SPECIAL))
@pytest.mark.parametrize("command", ["info", "simulate", "verify", "import-svg", "import-dxf", "import-yaml",
                                     "rooms-check", "report-plan"])
def test_inputs_that_are_not_regular_files_are_refused_at_once(tmp_path, kind, command):
    """/dev/zero, /dev/urandom, a FIFO with no writer (it must not block), a directory, a 1 GiB sparse file and
    a name past the system's limit: one line each (#28: they grew past 4 GiB or blocked for ever)."""
    suffix = {"import-svg": ".svg", "import-dxf": ".dxf", "import-yaml": ".yaml"}.get(command, ".json")
    name = ("n" * 300 if kind == "long-name" else "input") + suffix
    if _SPECIAL[kind] is not None:
        _SPECIAL[kind](tmp_path, name)
    path = str(tmp_path / name)
    args = {"info": ["info", path], "simulate": ["simulate", "square", path, "--trials", "5"], "verify": ["verify", path],
            "rooms-check": ["rooms", "warehouse", "--check", path],
            "report-plan": ["report", "square", "--plan", path, "-o", str(tmp_path / "r.html")]}.get(
        command, ["import", path, "-o", str(tmp_path / "env.json")])
    result = _run(args)
    assert result.exit_code == 2, result.stderr
    _one_line_or_answer(result)


@pytest.mark.parametrize("args", [
    ["explore", "square", "--start", "1,1", "--range", "1e-309"],  # ZeroDivisionError (#28)
    ["explore", "square", "--start", "1,1", "--range", "1e309"],  # OverflowError (#28)
    ["explore", "square", "--start", "1e309,1"],
    ["--indent", "999999999999", "info", "square"],  # MemoryError (#28)
    ["study", "reachability", "--grid", "n=10001", "--per-cell", "1", "--workers", "1", "-q"],  # generate's limit
    ["study", "reachability", "--grid", "n=3:10000:100000", "--workers", "1", "-q"],
    ["study", "reachability", "--grid", "n=" + "9" * 5000, "--workers", "1", "-q"],
    ["study", "reachability", "--grid", "n=6", "--per-cell", "1", "--scheduler", "not a :: address", "-q"],  # 40 s (#28)
    ["study", "reachability", "--grid", "n=6", "--per-cell", "1", "--scheduler", "tcp://127.0.0.1:99999", "-q"],
    ["study", "reachability", "--grid", "n=6", "--per-cell", "1", "--scheduler", "http://[::1", "-q"],
    ["rooms", "warehouse", "--simulate", "--from", "0", "--to", "1", "--trials", "100000000", "--max-bounces", "10000000"],
    ["plan", "square", "--from", "e0," * 3000 + "e1", "--to", "e2"],
])
def test_options_of_the_issue_are_refused_in_one_line(tmp_path, args):
    if args[0] == "study":
        args = [*args, "--out-dir", str(tmp_path / "s")]
    result = _run(["--max-memory", "1G", *args])
    _one_line_or_answer(result)  # refused (2), or answered (0: 3,000 copies of e0 are one piece)


@pytest.mark.parametrize("where", ["env", "output", "certificate", "picture", "graph-cache", "out-dir"])
def test_names_past_the_system_limit_are_refused_in_one_line(tmp_path, where):
    """ENAMETOOLONG anywhere a path is named (#28: an internal error)."""
    long_name = str(tmp_path / ("n" * 300))
    args = {
        "env": ["info", long_name + ".json"],
        "output": ["info", "square", "-o", long_name + ".json"],
        "certificate": ["plan", "square", "--from", "e0", "--to", "e2", "--certificate", long_name + ".json"],
        "picture": ["info", "square", "--picture", long_name + ".png"],
        "graph-cache": ["--graph-cache", long_name, "--graph-cache-min-arcs", "0", "graph", "square", "--safe"],
        "out-dir": ["study", "reachability", "--grid", "n=6", "--per-cell", "1", "--workers", "1", "-q",
                    "--out-dir", long_name],
    }[where]
    _one_line_or_answer(_run(args))


@FUZZ_FEW
@given(body=st.binary(max_size=300))
@example(body=__import__("random").Random(3).randbytes(140))  # struct.error inside ezdxf's binary loader (#28)
def test_fuzzed_binary_dxf_import_or_refuse_in_one_line(tmp_path_factory, body):
    folder = tmp_path_factory.mktemp("bdxf")
    drawing = folder / "plan.dxf"
    drawing.write_bytes(b"AutoCAD Binary DXF\r\n\x1a\x00" + body)
    _one_line_or_answer(_run(["import", str(drawing), "-o", str(folder / "env.json")]))
