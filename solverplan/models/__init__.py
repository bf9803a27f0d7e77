"""The environments shipped with solverplan, by name.

Each model is a JSON environment file in this package (``square``, ``two_rooms``, ``one_hole``, …; the
table in this folder's README.md says what each is for). Wherever solverplan expects an environment
file, in :func:`solverplan.environment.load_environment` and on the command line, a model's name
works too; a file of that name in the working directory wins.

>>> from solverplan import models
>>> "two_rooms" in models.names()
True
>>> models.path("square").name
'square.json'
>>> env = models.load("l_shape")
>>> env.name, env.n_vertices, len(env.reflex_vertices)
('l_shape', 6, 1)
>>> models.load("no_such_model")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
solverplan.errors.InputError: unknown model 'no_such_model': the shipped models are comb, degenerate, ...
"""

from __future__ import annotations

from pathlib import Path

from solverplan._shipped import model_file, model_names
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError

__all__ = ["names", "path", "load"]


def names() -> list[str]:
    """The names of the shipped models, sorted (each is the stem of its file)."""
    return model_names()


def path(name: str) -> Path:
    """The file of the shipped model ``name`` (``"two_rooms"`` or ``"two_rooms.json"``).

    Raises
    ------
    InputError
        If no shipped model has that name; the message lists the known names.
    """
    file = model_file(name)
    if file is None:
        raise InputError(f"unknown model {name!r}: the shipped models are {', '.join(model_names())}")
    return file


def load(name: str) -> Environment:
    """The shipped model ``name`` as an :class:`~solverplan.environment.Environment` (its name is the model's)."""
    return load_environment(path(name))
