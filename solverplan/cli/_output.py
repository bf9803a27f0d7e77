"""Answers out: JSON (indented when small, compact when large) or text, on stdout or atomically to a file."""

from __future__ import annotations

import gc
import json
import logging
import shutil
import sys
from enum import StrEnum
from pathlib import Path
from typing import Any, Iterable, Protocol

import orjson

from solverplan.choices import EnvironmentFormat
from solverplan._io import atomic_write_chunks, cannot_write
from solverplan.errors import InputError

logger = logging.getLogger(__name__)


class Answer(Protocol):
    """What a command emits: every result type of the library has these two methods."""

    def to_json(self) -> dict: ...

    def to_text(self, *, width: int = ...) -> str: ...


class OutputFormat(StrEnum):
    JSON = "json"
    TEXT = "text"


EnvFormat = EnvironmentFormat  # the environment file formats (--env-format), the library's


def text_width(out: Path | None) -> int:
    if out is None and sys.stdout.isatty():
        return max(shutil.get_terminal_size().columns, 60)
    return 100


#: Answers whose compact JSON is longer than this (characters, about bytes) are printed compact
#: unless ``--indent`` asks otherwise: the standard library indents in pure Python, about five
#: times slower than its compact C encoder (≈ 0.15 s per MB of compact text on the project's
#: machine), and a reader does not page through megabytes anyway. The compact text is made first
#: in any case, so measuring it costs nothing extra.
JSON_INDENT_LIMIT = 512 * 1024

#: ``None``: choose by size (:data:`JSON_INDENT_LIMIT`); ``-1``: compact; ``n >= 0``: ``indent=n``.
#: Set by the global ``--indent``/``--compact`` options for the duration of one command.
_json_indent: int | None = None


def set_json_indent(indent: int | None) -> None:
    """Set the JSON layout of this command line (the global ``--indent``/``--compact``; ``None`` resets it)."""
    global _json_indent
    _json_indent = indent


def json_indent() -> int | None:
    """The JSON layout of this command line: ``None`` by size, ``-1`` compact, ``n`` spaces."""
    return _json_indent


def json_text(value: Any, indent: int | None = None) -> str:
    """``value`` as JSON text (no trailing newline): indented by two spaces when small, compact otherwise.

    ``indent`` is ``None`` to choose by the size of the compact text, ``-1`` for compact, or the
    number of spaces per level. Answers up to :data:`JSON_INDENT_LIMIT` go through the standard
    encoder, which refuses NaN and infinities (``ValueError``), as strict JSON readers do: results
    carry exact or non-finite numbers as strings or null. Larger answers (graphs of 10⁵ arcs) are
    encoded by orjson, ten times faster — the encoder was most of a big answer's time; it writes the
    same text but does not re-check finiteness (the answers' own ``to_json`` map non-finite floats to
    null).
    """
    try:
        fast = orjson.dumps(value)
    except orjson.JSONEncodeError:  # e.g. an exact integer beyond 64 bits: the standard encoder writes it
        fast = b""
    if len(fast) > JSON_INDENT_LIMIT:
        if indent is None or indent < 0:
            return fast.decode()
        if indent == 2:
            return orjson.dumps(value, option=orjson.OPT_INDENT_2).decode()
        return json.dumps(value, ensure_ascii=False, allow_nan=False, indent=indent)
    if indent is not None and indent < 0:
        return json.dumps(value, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    return json.dumps(value, ensure_ascii=False, allow_nan=False, indent=2 if indent is None else indent)


def emit(answer: Answer, fmt: OutputFormat, out: Path | None) -> None:
    """Print ``answer`` as JSON or text on stdout, or write it atomically to ``out``.

    JSON is indented for small answers and compact for large ones (:data:`JSON_INDENT_LIMIT`),
    unless the global ``--indent N`` or ``--compact`` option says which.
    """
    if fmt is OutputFormat.JSON:
        # A large answer is hundreds of thousands of fresh dicts and lists, none of them in a
        # reference cycle: without the collector pausing, its repeated full scans of the growing
        # heap made building a 250,000-arc graph answer ≈ 4× slower.
        collecting = gc.isenabled()
        gc.disable()
        try:
            text = json_text(answer.to_json(), _json_indent) + "\n"
        finally:
            if collecting:
                gc.enable()
    else:
        text = answer.to_text(width=text_width(out))
        if not text.endswith("\n"):  # a report is whole lines: the shell prompt must not follow on the last one
            text += "\n"
    emit_string(text, out)


def emit_string(text: str, out: Path | None) -> None:
    """Write ready-made text (GraphML, DOT, an answer's JSON) to stdout or atomically to ``out``."""
    emit_chunks((text.encode("utf-8"),), out)


def emit_chunks(chunks: Iterable[bytes], out: Path | None) -> None:
    """Write the concatenation of ``chunks`` (UTF-8) to stdout, or atomically to ``out``, as they come: a large
    answer never exists whole in memory. A file that cannot be written is bad input (one line, exit 2)."""
    if out is None:
        atomic_write_chunks("-", chunks)  # "-": stdout
        return
    try:
        atomic_write_chunks(out, chunks)
    except OSError as exc:
        raise InputError(cannot_write(out, exc)) from None
    logger.info("wrote %s", out)
