"""Start-up of a ``solverplan`` process: build only the command its command line names, and coerce plain parameter
values without pydantic.

typer builds a click command for every registered command before it parses a command line — inspecting every
parameter of every command, ≈ 50 ms for the thirty commands — and (since 0.29) coerces every parameter's value through
a pydantic ``TypeAdapter``, importing pydantic and building a schema per parameter: ≈ 0.1 s of every start. A process
runs one command, so :func:`command_for`

- builds the command the command line names in full, and every other command as its *outline*: its name and its
  help (all that the listing of ``solverplan --help`` or an unknown command's message shows of it);
- coerces the values of parameters of plain types (``str``, ``bool``, ``int``, ``float``, ``Path``, enums, lists of ``str``)
  directly, giving the values typer's coercion gives; a value it is not sure of (a malformed number, a choice not
  spelled as listed, a number out of its range) goes to typer's own coercion, so every error reads as before.

Nothing here changes what a command does; ``tests/test_cli_startup.py`` compares the outputs with typer's usual
build. A typer without these internals gets its usual build (:func:`command_for` falls back to it).
"""

from __future__ import annotations

import copy
import functools
import re
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any, Callable, get_args, get_origin

import typer
import typer.main

__all__ = ["command_for"]


def command_for(app: typer.Typer, argv: list[str]) -> Any:
    """The click command that runs ``app`` on the arguments ``argv`` (without the program name): the command they
    name built in full, the others outlined, plain values coerced directly (module docstring)."""
    if not _typer_as_known():
        return typer.main.get_command(app)
    group = typer.main.get_group(_outline(app))
    name = _command_name(group, argv)
    if name is not None:
        group.commands[name] = _full_command(app, name, group)
    _coerce_directly(group)
    return group


def _typer_as_known() -> bool:
    """Does the installed typer build commands and coerce values as this module expects (typer 0.29)?"""
    try:
        from typer._coercion import RuntimeParam, build_runtime_param  # noqa: F401
        from typer._param_types import coerce_cli_choice, coerce_cli_path  # noqa: F401
        from typer.core import TyperCommand, TyperOption, _TyperParameter  # noqa: F401
    except ImportError:
        return False
    return (hasattr(_TyperParameter, "get_runtime_param") and hasattr(TyperCommand, "get_help_option")
            and all(hasattr(typer.main, f) for f in ("get_group", "get_command_from_info", "get_group_from_info",
                                                     "get_command_name")))


# ------------------------------------------------------------------ outlines
def _outline(app: typer.Typer) -> typer.Typer:
    """A shallow copy of ``app`` whose commands (and those of its sub-apps) take no parameters."""
    out = copy.copy(app)
    out.registered_commands = [_outline_command(info) for info in app.registered_commands]
    groups = []
    for info in app.registered_groups:
        group = copy.copy(info)
        group.typer_instance = _outline(info.typer_instance) if info.typer_instance is not None else None
        groups.append(group)
    out.registered_groups = groups
    return out


def _outline_command(info: Any) -> Any:
    callback = info.callback

    def outline() -> None:  # pragma: no cover - command_for builds the named command in full
        raise RuntimeError(f"the outline of command {callback.__name__!r} was run")

    outline.__name__ = callback.__name__
    outline.__qualname__ = callback.__qualname__
    outline.__doc__ = callback.__doc__
    out = copy.copy(info)
    out.callback = outline
    return out


def _command_name(group: Any, argv: list[str]) -> str | None:
    """The command ``argv`` names, parsed as the group parses it (its options before the command, those that take a
    value with their value), or None when it names none of the group's commands."""
    from typer.core import TyperOption

    takes_value = {opt for p in group.params if isinstance(p, TyperOption) and not p.is_flag and not p.count
                   for opt in p.opts + p.secondary_opts}
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg == "--":
            i += 1
            break
        if not arg.startswith("-") or arg == "-":
            break
        i += 2 if arg in takes_value else 1
    if i < len(argv) and argv[i] in group.commands:
        return argv[i]
    return None


def _full_command(app: typer.Typer, name: str, outline: Any) -> Any:
    """The command ``name`` of ``app`` built as typer builds it."""
    short, markup = app.pretty_exceptions_short, app.rich_markup_mode
    for info in app.registered_commands:
        if info.callback is not None and (info.name or typer.main.get_command_name(info.callback.__name__)) == name:
            return typer.main.get_command_from_info(info, pretty_exceptions_short=short, rich_markup_mode=markup)
    for group in app.registered_groups:
        if group.name == name:
            return typer.main.get_group_from_info(group, pretty_exceptions_short=short, rich_markup_mode=markup,
                                                  suggest_commands=app.suggest_commands)
    return outline.commands[name]


# ------------------------------------------------------------------ direct coercion
_UNSURE = object()
_INT = re.compile(r"-?(?:0|[1-9][0-9]{0,17})")
_FLOAT = re.compile(r"-?[0-9]{1,20}(?:\.[0-9]{1,20})?(?:[eE][-+]?[0-9]{1,3})?")


def _coerce_directly(command: Any) -> None:
    """Give every parameter of plain type of ``command`` (and of its subcommands) the direct coercion, the
    ``--help`` flag too (made when a context first asks for it)."""
    for param in command.params:
        _give_direct(param)
    help_option = command.get_help_option

    def get_help_option(ctx: Any) -> Any:
        return _give_direct(help_option(ctx))

    command.get_help_option = get_help_option
    for sub in getattr(command, "commands", {}).values():
        _coerce_directly(sub)


def _give_direct(param: Any) -> Any:
    if getattr(param, "_runtime_param", _UNSURE) is None:
        direct = _direct(param.type_descriptor)
        if direct is not None:
            param._runtime_param = direct
    return param


def _direct(descriptor: Any) -> Any:
    """The direct coercion of a parameter, or None to leave it to typer."""
    from typer._param_types import coerce_cli_choice, coerce_cli_path

    info, annotation = descriptor.parameter_info, descriptor.annotation
    if descriptor.file_annotation is not None or info.parser is not None or getattr(info, "click_type", None) is not None:
        return None
    convert: Callable[[Any, Any, Any], Any]
    if annotation is str or annotation is bool:  # a flag's value is a bool already (None: no value)
        def convert(value: Any, param: Any, ctx: Any) -> Any:
            return value if type(value) is annotation else _UNSURE
    elif annotation is int or annotation is float:
        def convert(value: Any, param: Any, ctx: Any) -> Any:
            return _number(annotation, value, info.min, info.max)
    elif isinstance(annotation, type) and issubclass(annotation, Enum):
        choices = tuple(annotation)

        def convert(value: Any, param: Any, ctx: Any) -> Any:
            return coerce_cli_choice(value, choices=choices, case_sensitive=info.case_sensitive, ctx=ctx)
    elif annotation is Path and info.path_type is None:
        def convert(value: Any, param: Any, ctx: Any) -> Any:
            if isinstance(value, str) and value and "\0" not in value:
                value = Path(value)
            if not isinstance(value, Path):
                return _UNSURE
            return coerce_cli_path(value, info, path_type=Path, param=param, ctx=ctx)
    elif get_origin(annotation) is list and get_args(annotation) == (str,):
        def convert(value: Any, param: Any, ctx: Any) -> Any:
            items = value if isinstance(value, (list, tuple)) else [value]
            return list(items) if all(isinstance(v, str) for v in items) else _UNSURE
    else:
        return None
    return _direct_class()(parameter_info=info, annotation=annotation, convert=convert, descriptor=descriptor)


@functools.cache
def _direct_class() -> type:
    """typer's runtime coercion with a direct conversion first (one class, made once: typer's base class is imported
    only where it exists)."""
    from typer._coercion import RuntimeParam, build_runtime_param

    @dataclass(frozen=True)
    class Direct(RuntimeParam):
        convert: Callable[[Any, Any, Any], Any]
        descriptor: Any

        def _coerce_value(self, value: Any, param: Any, ctx: Any) -> Any:
            try:
                out = self.convert(value, param, ctx)
            except Exception:  # typer's own coercion says what is wrong, in its words
                out = _UNSURE
            if out is _UNSURE:
                return build_runtime_param(self.descriptor)._coerce_value(value, param=param, ctx=ctx)
            return out

    return Direct


def _number(kind: type[int] | type[float], value: Any, lo: float | None, hi: float | None) -> Any:
    """``value`` as an int or a float when it is plainly one within [lo, hi]; else unsure."""
    out: int | float
    if type(value) is kind or (kind is float and type(value) is int):
        out = kind(value)
    elif type(value) is str and (_INT if kind is int else _FLOAT).fullmatch(value):
        out = kind(value)
    else:
        return _UNSURE
    if kind is float and not -1e300 < out < 1e300:
        return _UNSURE
    if (lo is not None and out < lo) or (hi is not None and out > hi):
        return _UNSURE
    return out
