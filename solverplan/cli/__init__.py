"""The ``solverplan`` command: a thin shell over the public API (docs/contract.md).

Every command parses its arguments, calls the library, and emits the answer's ``to_json()``
(default) or ``to_text()`` (``--format text``) on stdout, or writes it atomically to ``-o FILE``.
No geometry, planning or JSON shaping happens here: if a command needs some, the API lacks it.

Exit codes: 0 answered; 1 internal failure; 2 bad input — one line on stderr
(``error: <message>``), no traceback, nothing written. :func:`exit_codes` maps library errors;
the :class:`Shell` group does the same for usage errors (unknown option, bad choice).

Adding a command (its own options one a line through ``Annotated`` aliases; the options commands end with, such as
--env-format, --format, -o and -v, added by :func:`~solverplan.cli._options.common_options` and given to it as one
value)::

    @app.command(name="partition")
    @common_options("env_format", "fmt", "out", "verbose")
    def partition_command(env: EnvArg, *, common: CommonOptions) -> None:
        \"\"\"The partition P′ of Algorithm 1.\"\"\"
        with common.loaded(env) as environment:
            common.emit(partition_boundary(environment))
"""

from __future__ import annotations

import gc
import signal
import sys
from typing import Any

# the command modules register their commands on ``app`` when imported
from solverplan.cli import (  # noqa: F401
    bounce,
    cache,
    explore,
    export,
    fields,
    floorplan,
    generate,
    geometry,
    proofs,
    report,
    rooms,
    study,
    wallfollow,
)
from solverplan.cli._app import app
from solverplan.cli._startup import command_for
from solverplan.cli._errors import exit_codes
from solverplan.cli._output import JSON_INDENT_LIMIT, EnvFormat, OutputFormat, emit

__all__ = ["app", "main", "exit_codes", "emit", "OutputFormat", "EnvFormat", "JSON_INDENT_LIMIT"]


def _terminate(signum: int, frame: Any) -> None:
    """SIGTERM unwinds like SIGINT, so output files half-written are removed (exit 128 + 15)."""
    raise SystemExit(128 + signum)



def main() -> None:
    """Console-script entry point (``solverplan = "solverplan.cli:main"``)."""
    signal.signal(signal.SIGTERM, _terminate)
    # A command builds large acyclic structures (10⁵–10⁶ arcs, their answers) and exits: with the default
    # thresholds the cyclic collector rescans the growing heap again and again (≈ 40 % of a big graph's build).
    # Collect young objects rarely; the structures have no cycles, and the process is short-lived.
    gc.freeze()
    gc.set_threshold(200_000, 50, 50)
    command_for(app, sys.argv[1:])()  # this command line's command only (cli/_startup.py: ≈ 0.15 s less start-up)
