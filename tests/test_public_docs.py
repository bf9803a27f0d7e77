"""Every name of ``solverplan.__all__`` has a numpydoc docstring with runnable Examples.

What each kind of name must document (modules are exempt: their page is their module docstring):

- a one-line summary, and an ``Examples`` section with at least one ``>>>`` line;
- functions: ``Parameters`` naming exactly the parameters of the signature (``Other Parameters`` count too),
  and ``Returns`` or ``Yields`` (a function annotated ``-> None`` returns nothing to describe);
- classes: ``Attributes`` or ``Parameters``; a ``Parameters`` section names exactly the constructor's
  parameters, and every name under ``Attributes`` is an attribute of the class (no stale names);
- exceptions: ``Examples`` only (showing when one is raised).

The examples run in the suite through the project's doctest collection (``--doctest-modules`` over the
``solverplan`` package, pyproject.toml): the last test checks that each public name's examples are found there,
under the module that defines it, so ``pytest`` runs them.
"""

from __future__ import annotations

import ast
import dataclasses
import doctest
import enum
import inspect
import sys
import textwrap
import tomllib
import warnings
from pathlib import Path

import pytest

import solverplan

try:
    from numpydoc import docscrape
except ImportError:  # the docs extra; the doctest collection below is still checked without it
    docscrape = None

ROOT = Path(__file__).resolve().parent.parent
NAMES = [name for name in solverplan.__all__ if not inspect.ismodule(getattr(solverplan, name))]


def _kind(obj) -> str:
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    return "function"


def _parse(name: str, obj):
    text = inspect.getdoc(obj)
    assert text and obj.__doc__, f"{name} has no docstring"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an unknown or misspelt section heading is a failure, not a warning
        return docscrape.NumpyDocString(text)


def _documented(entries) -> list[str]:
    """The names of a numpydoc parameter list: ``start, goal`` documents two, ``**changes`` one."""
    return [part.strip().lstrip("*") for entry in entries for part in entry.name.split(",") if part.strip()]


def _signature_names(obj) -> list[str]:
    return list(inspect.signature(obj).parameters)


def _attribute_names(cls) -> set[str]:
    """Class attributes, properties, fields, and the instance attributes its methods assign (``self.x = ...``)."""
    names = {name for klass in cls.__mro__ for name in vars(klass)}  # dir() of an enum hides its properties
    if dataclasses.is_dataclass(cls):
        names |= {f.name for f in dataclasses.fields(cls)}
    for klass in cls.__mro__:
        names |= set(getattr(klass, "__annotations__", {}))
        names |= set(getattr(klass, "__slots__", ()))
        if klass.__module__.startswith("solverplan."):
            tree = ast.parse(textwrap.dedent(inspect.getsource(klass)))
            names |= {node.attr for node in ast.walk(tree) if isinstance(node, ast.Attribute)
                      and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == "self"}
    return names


@pytest.mark.skipif(docscrape is None, reason="numpydoc is not installed (pip install '.[docs]'): public docstrings "
                                               "not parsed")
@pytest.mark.parametrize("name", NAMES)
def test_public_name_has_a_numpydoc_docstring(name):
    obj = getattr(solverplan, name)
    kind = _kind(obj)
    doc = _parse(name, obj)

    summary = doc["Summary"]
    assert len(summary) == 1 and summary[0].strip(), f"{name}: the summary is not one line: {summary}"
    assert any(line.lstrip().startswith(">>>") for line in doc["Examples"]), f"{name}: no Examples with >>>"
    if kind == "exception":
        return

    documented = _documented([*doc["Parameters"], *doc["Other Parameters"]])
    assert len(documented) == len(set(documented)), f"{name}: a parameter documented twice: {documented}"
    if kind == "function":
        signature = _signature_names(obj)
        if signature:
            assert documented, f"{name}: no Parameters section for {signature}"
        assert sorted(documented) == sorted(signature), (
            f"{name}: Parameters {documented} do not match the signature {signature}")
        if inspect.signature(obj).return_annotation not in (None, "None"):
            assert doc["Returns"] or doc["Yields"], f"{name}: no Returns or Yields section"
        return

    attributes = _documented(doc["Attributes"])
    assert documented or attributes, f"{name}: a class needs Attributes or Parameters"
    if documented:
        signature = _signature_names(obj)
        assert sorted(documented) == sorted(signature), (
            f"{name}: Parameters {documented} do not match the constructor {signature}")
    known = _attribute_names(obj)
    if issubclass(obj, enum.Enum):
        known |= set(obj.__members__)
    stale = [a for a in attributes if a not in known]
    assert not stale, f"{name}: Attributes names no attribute of the class: {stale}"


def test_doctests_are_collected_by_the_suite():
    options = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["pytest"]["ini_options"]
    assert "--doctest-modules" in options["addopts"].split() and "solverplan" in options["testpaths"]


@pytest.mark.parametrize("name", NAMES)
def test_examples_are_found_by_the_doctest_collection(name):
    """``pytest --doctest-modules`` collects a module's docstrings only for the objects it defines."""
    obj = getattr(solverplan, name)
    module = sys.modules[obj.__module__]
    qualified = f"{module.__name__}.{obj.__qualname__}"
    tests = {test.name: test for test in doctest.DocTestFinder().find(module) if test.examples}
    assert qualified in tests, f"{name}: its examples are not collected from {module.__name__}"
