"""Data flows one way: each layer imports only from layers to its left.

environment → geometry kernel → the rollout engine → model structures (bounce, rectilinear, …, each with its own
simulation) → planners → results (simulate, studies, certificates) → renderings / descriptions → CLI.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "solverplan"

# rank of each top-level part of the package; a module may import lower ranks or its own part
LAYERS = {
    "errors": 0,
    "_docstrings": 0,  # docstring fragments shared by public functions (no imports)
    "_io": 0.25,  # files in (bounded) and out (atomic): raises errors (0)
    "_arrays": 0,
    "progress": 0,
    "verdict": 0,  # the one verdict shape of every check (standard library only): the checker and the models share it  # what long loops report, and where a timeout stops them (no imports)
    "runtime": 0.25,  # the run-time settings (graph cache, memory limit) read where they apply
    "limits": 0.5,
    "choices": 0.5,  # the named options of the library's functions (enumerations; raise errors: after it)  # the documented input limits every reader checks (raise errors: after it)
    "_shipped": 0,  # where the shipped model files are: environment accepts a model's name
    "interval": 1,
    "exact": 1,
    "environment": 2,
    "result": 3,
    "geometry": 3,
    "rollout": 3.5,  # the rollout engine (policies ask, one batch of rays per bounce): below every model that simulates
    "floorplan": 3.5,  # floor plans in (ROS maps, DXF, SVG): they make environments (2) and answer like results (3)
    "models": 3,
    "generators": 4.5,  # seeded random environments, valid by construction (spiked combs keep the wall-following model's general position, 4)  # the shipped environments by name: they load through environment (2)
    "bounce": 4,
    "rectilinear": 4,
    "wallfollow": 4,
    "explore": 4,
    "reflection": 4,
    "plan": 5,
    "proofs": 5,  # sympy proofs; one checks the exact safe set of bounce (4); only the CLI imports them
    "simulate": 6,  # the bouncing robot's policies (rules, plans) on the rollout engine (3.5)
    "studies": 7,  # studies run simulations (simulate, 6; each model's own, 4) and feed render (7, via plain arrays)
    "certify": 6,
    "describe": 7,
    "render": 7,
    "answers": 7.5,  # the registry of answer kinds: every answer class (layers 4–7) and its hooks (certify, render)
    "cli": 8,
    "__init__": 9,
    "__main__": 9,
}


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        yield path, path.relative_to(PACKAGE).parts[0].removesuffix(".py")


def _imported_parts(tree: ast.AST, path: Path) -> set[str]:
    parts: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative import: resolve against the module's package
                base = path.relative_to(PACKAGE).parts[: -node.level]
                names = [".".join(("solverplan", *base, node.module or ""))]
            else:
                names = [node.module or ""]
        else:
            continue
        for name in names:
            bits = name.split(".")
            if bits[0] == "solverplan" and len(bits) > 1 and bits[1]:
                parts.add(bits[1])
    return parts


@pytest.mark.parametrize("path,part", list(_modules()), ids=lambda v: str(v) if isinstance(v, str) else v.name)
def test_modules_import_only_from_layers_to_their_left(path, part):
    assert part in LAYERS, f"{part} has no layer: add it to LAYERS in {__file__}"
    tree = ast.parse(path.read_text())
    for imported in _imported_parts(tree, path):
        assert imported in LAYERS, f"{path.name} imports unknown part {imported}"
        assert imported == part or LAYERS[imported] < LAYERS[part], (
            f"{path.relative_to(PACKAGE)} (layer {part}) imports solverplan.{imported}, a layer to its right"
        )


def test_library_modules_never_print():
    """stdout belongs to the CLI (answers are JSON on stdout): a stray print corrupts JSON output."""
    for path, part in _modules():
        if part in ("cli", "__main__"):
            continue
        tree = ast.parse(path.read_text())
        calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "print"]
        assert not calls, f"{path.relative_to(PACKAGE)} calls print() on line {calls[0].lineno}"


def test_no_module_is_named_like_a_function_it_defines():
    """``solverplan.plan.patrols`` is the module and ``patrol`` its function: a package that re-exports a function
    named like one of its modules makes ``package.name`` mean the module or the function by import order."""
    for path, _part in _modules():
        rel = str(path.relative_to(PACKAGE))
        tree = ast.parse(path.read_text())
        defined = {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
        assert path.stem not in defined, f"{rel} defines {path.stem}(): name the module for what it holds"


def test_every_command_fits_one_screen():
    """The CLI only parses, calls and emits: a command function (options one a line, through Annotated aliases)
    longer than a screen is doing the library's work."""
    for path in sorted((PACKAGE / "cli").glob("*.py")):
        tree = ast.parse(path.read_text())
        for node in tree.body:
            if isinstance(node, ast.FunctionDef) and node.decorator_list:
                lines = node.end_lineno - node.lineno + 1 + len(node.decorator_list)  # type: ignore[operator]
                assert lines <= 50, f"cli/{path.name}:{node.name} is {lines} lines: delegate its work (at most 50)"
