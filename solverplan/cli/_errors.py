"""Errors to exit codes: one ``error:`` line on stderr, exit 2 for bad input, 1 for failures; -v logging."""

from __future__ import annotations

import logging
import contextlib
import re
import sys
import traceback
from typing import Any, Iterator, Sequence

import typer
from typer.core import TyperGroup

from solverplan._io import reason_of, shown_path
from solverplan.limits import MAX_QUOTED_CHARS
from solverplan.errors import InputError, SolverplanError


def one_line(message: str, limit: int | None = None) -> str:
    """A message on one line. With a ``limit`` (the framework's usage messages, which quote the input whole), the
    quotes of the input are cut like ours (``limits.quote``) and the line to ``limit`` characters."""
    text = " ".join(part.strip() for part in message.splitlines() if part.strip())
    if limit is None or len(text) <= limit:
        return text
    # a quote opens before a non-space and closes before a non-word character: the framework's repr of the input
    text = re.sub(r"(?<!\w)'([^'\s][^']{%d,}?)'(?!\w)" % (MAX_QUOTED_CHARS - 1),
                  lambda m: f"'{m.group(1)[:MAX_QUOTED_CHARS - 3]}…'", text)
    return text if len(text) <= limit else text[: limit - 1] + "…"


MAX_LINE = 200
"""Longest error line (characters, ``error: `` included): the one place every message is shortened."""


def fail(message: str, code: int, suffix: str = "") -> typer.Exit:
    """Write ``error: message suffix`` on one line of at most :data:`MAX_LINE` characters (the message is cut,
    the suffix kept) and return the exit of ``code``."""
    sys.stderr.write(f"error: {one_line(message, limit=MAX_LINE - len('error: ') - len(suffix))}{suffix}\n")
    sys.stderr.flush()
    return typer.Exit(code)


def invalid(what: str, failures: Sequence[Any]) -> typer.Exit:
    """Exit 1 for a check that failed (``verify``, ``rooms --check``): ``error: WHAT invalid: FIRST FAILURE``, and
    how many more failures the report on stdout lists."""
    more = len(failures) - 1
    suffix = f" (and {more} more failure{'s' if more > 1 else ''} in the report)" if more else ""
    return fail(f"{what} invalid: {failures[0]}", 1, suffix)


@contextlib.contextmanager
def stderr_logging(verbose: int) -> Iterator[None]:
    """Log solverplan's messages to stderr while a command runs: -v info, -vv debug."""
    if verbose <= 0:
        yield
        return
    root = logging.getLogger("solverplan")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    old_level = root.level
    root.addHandler(handler)
    root.setLevel(logging.DEBUG if verbose > 1 else logging.INFO)
    try:
        yield
    finally:
        root.removeHandler(handler)
        root.setLevel(old_level)


@contextlib.contextmanager
def exit_codes(verbose: int = 0) -> Iterator[None]:
    """Run a command body, mapping errors to the exit codes of docs/contract.md with one line on stderr.

    :class:`InputError` → 2; any other :class:`SolverplanError` → 1; anything unexpected → 1 with
    ``internal error: ...`` (and the traceback before it when ``verbose``). Also sets up ``-v`` logging.
    """
    with stderr_logging(verbose):
        try:
            yield
        except (typer.Exit, typer.Abort, BrokenPipeError):
            raise
        except InputError as exc:
            raise fail(str(exc) or type(exc).__name__, 2) from None
        except SolverplanError as exc:
            raise fail(str(exc) or type(exc).__name__, 1) from None
        except MemoryError:  # past every up-front estimate: the input asks more memory than the process may use
            raise fail("out of memory: this input needs more memory than the process may use (see --max-memory; "
                       "docs/contract.md, Limits)", 2) from None
        except OSError as exc:  # a file or folder the user named: missing, unwritable, a name too long, ...
            where = f"{shown_path(exc.filename)}: " if exc.filename is not None else ""
            raise fail(f"{where}{reason_of(exc)}", 2) from None
        except Exception as exc:  # a bug: say so in one line, the traceback only on request
            if verbose:
                traceback.print_exc(file=sys.stderr)
                hint = ""
            else:
                hint = " (run with -v for the traceback)"
            raise fail(f"internal error: {type(exc).__name__}: {exc}{hint}", 1) from None


class Shell(TyperGroup):
    """The command group, reporting usage errors (bad option, bad choice) as one ``error:`` line, exit 2."""

    def main(  # type: ignore[override]
        self,
        args: Any = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        try:
            result = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except typer.TyperException as exc:  # the framework's usage errors (vendored click)
            ctx = getattr(exc, "ctx", None)
            if type(exc).__name__ == "NoArgsIsHelpError":  # bare `solverplan`: show the help
                sys.stderr.write(exc.format_message() + "\n")
            else:
                hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
                sys.stderr.write(f"error: {one_line(exc.format_message(), limit=150)}{hint}\n")
            sys.stderr.flush()
            sys.exit(getattr(exc, "exit_code", 2))
        except typer.Abort:
            sys.stderr.write("error: aborted\n")
            sys.exit(1)
        except (typer.Exit, KeyboardInterrupt, SystemExit):
            raise
        except Exception as exc:  # raised outside a command's body (the global options, a parameter's parsing)
            try:
                with exit_codes():
                    raise exc
            except typer.Exit as done:
                sys.exit(done.exit_code)
        # non-standalone mode returns the code of a typer.Exit (commands themselves return None)
        sys.exit(result if isinstance(result, int) else 0)
