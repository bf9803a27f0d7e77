"""Docstring fragments: parameters several public functions share, described once.

A function whose docstring holds a line ``%(name)s`` (alone, at the indentation of a parameter name) is decorated
with :func:`fill_doc`; the line becomes the fragment, indented like it. The docstring is complete at import
time, so ``help()``, Sphinx and the doctests read the whole text; only the source holds the placeholder.

>>> @fill_doc(seed="seed\\n    The seed of the random draws.")
... def draw(seed=None):
...     '''Draw.
...
...     Parameters
...     ----------
...     %(seed)s
...     '''
>>> import inspect
>>> print(inspect.getdoc(draw))
Draw.
<BLANKLINE>
Parameters
----------
seed
    The seed of the random draws.
"""

from __future__ import annotations

import re
import textwrap
from typing import Callable, TypeVar

__all__ = ["fill_doc"]

F = TypeVar("F", bound=Callable)


def fill_doc(**fragments: str) -> Callable[[F], F]:
    """Decorator: replace each line ``%(name)s`` of the docstring by ``fragments[name]`` at that line's indentation.

    A placeholder with no fragment, or a fragment with no placeholder, is a :class:`ValueError` at import time (so
    a renamed fragment cannot leave a docstring incomplete).
    """
    def fill(func: F) -> F:
        doc = func.__doc__ or ""
        for name, text in fragments.items():
            pattern = re.compile(rf"^( *)%\({re.escape(name)}\)s$", re.MULTILINE)
            if not pattern.search(doc):
                raise ValueError(f"{func.__qualname__}: no line %({name})s in the docstring")
            doc = pattern.sub(lambda m: textwrap.indent(text.strip("\n"), m.group(1)), doc)
        left = re.search(r"%\((\w+)\)s", doc)
        if left:
            raise ValueError(f"{func.__qualname__}: no fragment for %({left.group(1)})s in the docstring")
        func.__doc__ = doc
        return func
    return fill
