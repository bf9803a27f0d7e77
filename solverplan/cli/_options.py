"""Options and small parsers shared by several commands."""

from __future__ import annotations

import contextlib
import functools
import inspect
import logging
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Callable, ContextManager, Iterator

import typer

from solverplan._io import cannot_write
from solverplan.choices import RoomRule, ScenarioName, or_all
from solverplan.cli._app import EnvFormatOpt, FormatOpt, OutOpt, VerboseOpt, load_env, loaded
from solverplan.cli._errors import exit_codes
from solverplan.cli._output import EnvFormat, OutputFormat, emit
from solverplan.errors import InputError

logger = logging.getLogger(__name__)

# The choices of the options that also take ``all`` (every member at once): enums made at run time, which a type
# checker sees as the base ``Choice``.
if TYPE_CHECKING:
    from solverplan.choices import Choice as RoomRuleOrAll, Choice as ScenarioOrAll
    from solverplan.environment import Environment
else:
    RoomRuleOrAll = or_all(RoomRule)
    ScenarioOrAll = or_all(ScenarioName)

CertificateOpt = Annotated[
    Path | None,
    typer.Option("--certificate", metavar="FILE", help="Also write a certificate of the answer (check it with 'solverplan verify').", show_default=False),
]
PictureOpt = Annotated[
    Path | None,
    typer.Option("--picture", metavar="FIG", help="Also draw the answer to a .png or .svg file.", show_default=False),
]
PositionToleranceOpt = Annotated[
    float | None,
    typer.Option("--tolerance", metavar="E", help="Heading tolerance ε (radians): every interval is 2ε wide (default 0.005).", show_default=False),
]
HeadingMarginOpt = Annotated[
    float, typer.Option("--heading-margin", metavar="D", help="Keep every heading this far (radians) from the walls (0 and π).")
]
TimeoutOpt = Annotated[
    float | None,
    typer.Option("--timeout", metavar="SECONDS", help="Answer within about this many seconds of the command's start: "
                 "the best found so far, not proved optimal, with the bound proved so far (plan also cuts the "
                 "partition and the graph build; the other commands build theirs whole first).", show_default=False),
]


def _process_age() -> float:
    """Seconds since this process started (Linux ``/proc``), or since this module was imported elsewhere."""
    try:
        import os

        with open("/proc/self/stat", encoding="ascii") as stat:
            start_ticks = int(stat.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime", encoding="ascii") as uptime:
            up = float(uptime.read().split()[0])
        return max(0.0, up - start_ticks / os.sysconf("SC_CLK_TCK"))
    except (OSError, ValueError, IndexError):
        return time.monotonic() - _IMPORTED


_IMPORTED = time.monotonic()
_STARTED = _IMPORTED - _process_age()
_COMMANDS = 0


def start_command_clock() -> None:
    """Called as each command line starts: the first in a process counts from the process's start (its start-up is
    part of the user's wait); a later one in the same process (tests, a notebook calling ``app``) from now."""
    global _STARTED, _COMMANDS
    if _COMMANDS:
        _STARTED = time.monotonic()
    _COMMANDS += 1
_ANSWER_RESERVE = 0.3
"""Seconds of a --timeout kept at least for what follows the search: the exact check of the answer and writing it."""
_ANSWER_RESERVE_SHARE = 0.1
"""The share of a --timeout kept for the same when it is more: an anytime search (a patrol's bisection, a plan's
incumbent) uses all the time it is given, and on large maps the exact check takes seconds (a 401-vertex patrol:
0.8 s), so with a fixed 0.3 s the check was always stopped and no certificate written."""
_WRITE_RESERVE = 0.1
"""Seconds of a --timeout kept for writing the answer after its exact check (:func:`command_stop`)."""


def _command_end(seconds: float) -> float:
    """The :func:`time.monotonic` time at which a ``--timeout`` of ``seconds`` ends: counted from the command's start
    (:func:`start_command_clock`), so that start-up and reading the input count."""
    return _STARTED + seconds


def command_timeout(timeout: float | None) -> Any:
    """``--timeout`` as a running deadline for the library (a :class:`~solverplan.plan._deadline.Deadline` whose limit
    reads as the user's seconds): the process's start-up and reading the input count, and a little is kept for
    checking and writing the answer (a tenth of it, at least 0.3 s), so that the whole command ends near ``timeout``."""
    from solverplan.plan._deadline import Deadline, check_timeout

    seconds = check_timeout(timeout)
    if seconds is None:
        return None
    reserve = max(_ANSWER_RESERVE, _ANSWER_RESERVE_SHARE * seconds)
    deadline = Deadline(max(1e-3, _command_end(seconds) - time.monotonic() - reserve))
    deadline.seconds = seconds  # the answer's limits name the user's timeout
    return deadline


def command_stop(timeout: float | None) -> float | None:
    """The :func:`time.monotonic` time at which a command with ``--timeout`` must stop checking its answer (the
    exact gate's ``stop_at``): the end of the user's limit less :data:`_WRITE_RESERVE`; ``None`` without one."""
    from solverplan.plan._deadline import check_timeout

    seconds = check_timeout(timeout)
    return None if seconds is None else _command_end(seconds) - _WRITE_RESERVE


CornerClearanceOpt = Annotated[
    float | None,
    typer.Option("--corner-clearance", metavar="K", help="Keep every landing point this far (a length) from segment ends, "
                 "but the corner a stage's segments share (default: 1e-4 of the environment's diameter).", show_default=False),
]

def parse_xy(text: str, option: str) -> tuple:
    """``X,Y`` as an exact point; bad text is one line naming the option."""
    from solverplan.exact import to_fraction

    parts = text.split(",")
    if len(parts) != 2:
        raise InputError(f"{option} {text!r}: expected X,Y (two numbers separated by a comma)")
    return tuple(to_fraction(part.strip(), where=option) for part in parts)

def parse_pair(text: str | None, name: str) -> tuple[str, str] | None:
    """``"X,Y"`` → two number strings (read exactly by the library), or ``None``."""
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise InputError(f"{name} must be two numbers X,Y, got {text!r}")
    return parts[0].strip(), parts[1].strip()

@contextlib.contextmanager
def progress_bar(description: str, quiet: bool) -> Iterator[Any]:
    """A rich progress bar on stderr (never stdout), or None when quiet or stderr is not a terminal."""
    if quiet or not sys.stderr.isatty():
        yield None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True)) as bar:
        task = bar.add_task(description, total=None)
        yield lambda done, total: bar.update(task, completed=done, total=total)

def write_certificate_file(answer: Any, path: Path, env: Any = None, checked: Any = None) -> None:
    """--certificate: the answer's certificate, checked exactly, then written (a warning, and no file, for an
    answer with nothing to certify; exit 1 if the check fails). ``checked``: the certificate, already checked."""
    from solverplan.certify.build import NothingToCertify, certificate, write_certificate

    try:
        cert = checked if checked is not None else certificate(answer, env=env)
    except NothingToCertify as exc:
        sys.stderr.write(f"warning: no certificate written to {path}: {exc.why}\n")
        return
    try:
        write_certificate(cert, path, check=checked is None)
    except OSError as exc:
        raise InputError(cannot_write(path, exc)) from None
    logger.info("wrote certificate %s (verified)", path)


def save_picture(picture: Path | None, renderer: str, *args: Any) -> None:
    """--picture: ``solverplan.render.MODULE.FUNCTION(*args)`` (``renderer`` is ``"MODULE.FUNCTION"``) saved to
    ``picture``; ``renderer`` ``""``: the picture hook of the answer ``args[0]``'s kind (:data:`solverplan.answers.KINDS`).
    The renderer is imported only when a picture is asked (matplotlib costs ≈ 0.3 s of a start)."""
    if picture is None:
        return
    import importlib

    from solverplan.render import save_figure

    if renderer:
        module, name = renderer.rsplit(".", 1)
        draw = getattr(importlib.import_module(f"solverplan.render.{module}"), name)
    else:
        from solverplan.answers import KINDS

        draw = KINDS[args[0].kind].picture
    save_figure(draw(*args), picture)


_COMMON: dict[str, tuple[Any, Any]] = {
    "heading_margin": (HeadingMarginOpt, 1e-3),
    "corner_clearance": (CornerClearanceOpt, None),
    "timeout": (TimeoutOpt, None),
    "certificate": (CertificateOpt, None),
    "picture": (PictureOpt, None),
    "env_format": (EnvFormatOpt, None),
    "fmt": (FormatOpt, OutputFormat.JSON),
    "out": (OutOpt, None),
    "verbose": (VerboseOpt, 0),
}
"""The options commands end with: name → (annotated type, default), in the order ``--help`` lists them."""


@dataclass(frozen=True)
class CommonOptions:
    """The options a command ends with (:func:`common_options`), given to it as one value: the searches' heading margin,
    corner clearance and --timeout, the answer's --certificate and --picture (where the command has them), the
    environment file's --env-format, the answer's --format and -o file, -v.

    Its methods are the steps the commands share: load the environment, map errors to exit codes, emit."""

    heading_margin: float = 1e-3
    corner_clearance: float | None = None
    timeout: float | None = None
    certificate: Path | None = None
    picture: Path | None = None
    env_format: EnvFormat | None = None
    fmt: Any = OutputFormat.JSON
    out: Path | None = None
    verbose: int = 0

    def search(self) -> dict[str, Any]:
        """A search's keywords of these options: ``heading_margin``, ``corner_clearance`` and ``timeout`` (the
        running deadline of :func:`command_timeout`)."""
        return {"heading_margin": self.heading_margin, "corner_clearance": self.corner_clearance,
                "timeout": command_timeout(self.timeout)}

    def exit_codes(self) -> ContextManager[None]:
        """The command body's errors as one line and an exit code (:func:`~solverplan.cli._errors.exit_codes`)."""
        return exit_codes(self.verbose)

    def loaded(self, env: Path) -> ContextManager[Environment]:
        """The environment ``env`` loaded inside :meth:`exit_codes` (a bad --picture path refused first)."""
        return loaded(env, self.env_format, self.picture, verbose=self.verbose)

    def load(self, env: Path) -> Environment:
        """The environment ``env`` (a bad --picture path refused first), inside a body already under :meth:`exit_codes`."""
        return load_env(env, self.env_format, self.picture)

    def emit(self, answer: Any) -> None:
        """The answer in the --format asked, on stdout or to the -o file."""
        emit(answer, self.fmt, self.out)

    def emit_checked(self, checked: Any, *, env: Any = None, certificate: Path | None = None, draw_picture: bool = True,
                     renderer: str = "", draw: tuple = ()) -> None:
        """The end of a command whose answer passed the exact gate (:func:`~solverplan.certify.gate.checked_answer`):
        its --certificate (the certificate the gate checked; ``certificate``: a command's own option instead), its
        --picture unless ``draw_picture`` is false (``renderer(answer, *draw)``, by default the picture of its kind:
        see :func:`save_picture`), then the answer itself."""
        answer = checked.answer
        certificate = certificate if certificate is not None else self.certificate
        if certificate is not None and checked.stopped:
            sys.stderr.write(f"warning: no certificate written to {certificate}: {checked.unchecked}\n")
        elif certificate is not None:
            write_certificate_file(answer, certificate, env, checked.certificate)
        save_picture(self.picture if draw_picture else None, renderer, answer, *draw)
        self.emit(answer)


def common_options(*names: str, **own: tuple[Any, Any]) -> Callable[[Callable[..., Any]], Callable[..., None]]:
    """Decorate a command that takes the common options ``names`` (keys of :data:`_COMMON`; ``own``: a name given
    another annotated type and default, e.g. graph's ``--format``) as one keyword ``common`` (:class:`CommonOptions`).

    typer reads a command's options from its signature: the decorated command's signature is the command's own
    parameters followed by these options, in the order of :data:`_COMMON`, so ``--help`` lists them last as
    before, and each is written once here instead of at the end of every command."""
    if not set(names) <= set(_COMMON) or not set(own) <= set(names):
        raise ValueError(f"common options are among {list(_COMMON)} and own types are for names given: {names}, {list(own)}")
    chosen = {name: own.get(name, _COMMON[name]) for name in _COMMON if name in names}
    return lambda command: _WithCommonOptions(command, chosen)


class _WithCommonOptions:
    """A command of :func:`common_options`: called with its own options and the common ones, it calls the command
    with its own and one :class:`CommonOptions`.

    What typer reads of it — its signature, with the command's annotations evaluated (they are strings, ``from
    __future__``), and its annotations — is made when typer first asks: a process builds one command
    (cli/_startup.py), and evaluating every command's option annotations would cost every start ≈ 20 ms."""

    def __init__(self, command: Callable[..., Any], chosen: dict[str, tuple[Any, Any]]) -> None:
        self.__wrapped__ = command
        self.__module__, self.__name__ = command.__module__, command.__name__
        self.__qualname__, self.__doc__ = command.__qualname__, command.__doc__
        self._chosen = chosen

    def __call__(self, **values: Any) -> None:
        common = CommonOptions(**{name: values.pop(name) for name in self._chosen})
        self.__wrapped__(**values, common=common)

    @functools.cached_property
    def __signature__(self) -> inspect.Signature:
        command = self.__wrapped__
        namespace = inspect.unwrap(command).__globals__
        parameters = [p.replace(annotation=eval(p.annotation, namespace)) if isinstance(p.annotation, str) else p
                      for p in inspect.signature(command).parameters.values() if p.name != "common"]
        for name, (annotation, default) in self._chosen.items():
            parameters.append(inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=default,
                                                annotation=annotation))
        # the return annotation is left out: it may name a class imported for type checkers only (generate's)
        return inspect.Signature(parameters, return_annotation=None)

    @functools.cached_property
    def __annotations__(self) -> dict[str, Any]:  # type: ignore[override]
        return {p.name: p.annotation for p in self.__signature__.parameters.values()} | {"return": None}
