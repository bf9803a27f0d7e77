"""Rows of a study on disk, written as they come, so an interrupted study resumes where it stopped.

``DIR/NAME.jsonl`` (JSON lines). The first line is the header, every other line one row::

    {"format": "solverplan-study-rows", "version": 1, "identity": {...Study.identity()...}}
    {"cell": 0, "replicate": 0, "seed": 3359378886, "n": 20, "irregularity": 0.1, ..., "seconds": 0.021}
    ...

Each row is written with one ``write`` of a whole line and flushed at once, so a study killed at any
moment (SIGINT, SIGTERM, SIGKILL, a crash) leaves every finished row on disk and at most one partial
last line. On resume (:meth:`RowStore.open`) the header must match the study's identity (generator,
base seed, metric parameters, axis names: the things a row depends on besides its own cell), rows are
recognised by their cell's parameters and replicate, and a row is kept only if it is complete (every
column) and its seed is the one the study derives for it. A damaged file (partial last line, a line
that is not JSON, a stale row) is rewritten atomically with the good rows before appending resumes.
Rows of cells no longer in the grid are kept in the file (a later, larger grid may use them) but left
out of the tables. The file is locked while a study writes it (two runs cannot interleave rows).
Rows are flushed, not fsync'ed: they survive the process, not a power cut.
"""

from __future__ import annotations

import json
import logging
import os
from pathlib import Path
from typing import IO, Any

from solverplan._io import atomic_write_text, cannot_write
from solverplan.errors import InputError
from solverplan.limits import quote
from solverplan.studies.study import Study, row_seed

__all__ = ["RowStore", "FORMAT", "VERSION"]

logger = logging.getLogger(__name__)

FORMAT = "solverplan-study-rows"
VERSION = 1


class RowStore:
    """The JSON-lines file of a study's rows (module docstring). Use :meth:`open`, then :meth:`append`."""

    def __init__(self, path: str | os.PathLike[str], study: Study) -> None:
        self.path = Path(path)
        self.study = study
        self.rows: dict[str, dict] = {}
        self.dropped = 0
        self._handle: IO[str] | None = None

    # ------------------------------------------------------------------ reading
    def _header(self) -> str:
        return json.dumps({"format": FORMAT, "version": VERSION, "identity": self.study.identity()}) + "\n"

    def _check_header(self, line: str) -> None:
        try:
            header = json.loads(line)
        except (ValueError, RecursionError):  # not JSON, a number past the digit guard, nested too deep
            header = None
        if not isinstance(header, dict) or header.get("format") != FORMAT:
            raise InputError(f"{self.path}: not a solverplan study rows file; delete it, or use --fresh or another --out-dir")
        if header.get("version") != VERSION:
            raise InputError(f"{self.path}: rows file version {quote(header.get('version'))}, this solverplan writes "
                             f"{VERSION}; use --fresh")
        old, new = header.get("identity"), self.study.identity()
        old = old if isinstance(old, dict) else {}
        for k in new:
            if old.get(k) != new[k]:
                raise InputError(
                    f"{self.path} holds rows of another study ({k}: {quote(old.get(k))} there, {quote(new[k])} here); "
                    "use --fresh to start over, or another --out-dir"
                )

    def _row_key(self, row: Any) -> str | None:
        """The key of a complete, consistent row; None for anything else."""
        if not isinstance(row, dict):
            return None
        gen = [k for k, _ in self.study.grid]
        if any(c not in row for c in self.study.columns if c != "cell"):
            return None
        replicate = row["replicate"]
        if isinstance(replicate, bool) or not isinstance(replicate, int) or replicate < 0:
            return None
        if row["seed"] != row_seed(self.study.seed, self.study.generator, {k: row[k] for k in gen}, replicate):
            return None
        return self.study.key_of(row)

    def _load(self) -> bool:
        """Read the file into :attr:`rows`; True when it must be rewritten (damaged lines)."""
        text = self.path.read_text(encoding="utf-8", errors="replace")
        lines = text.split("\n")
        self._check_header(lines[0])
        damaged = not text.endswith("\n")
        body = lines[1:-1] if not damaged else lines[1:]
        for line in body:
            if not line.strip():
                continue
            try:
                row = json.loads(line)
                key = self._row_key(row)
            except (ValueError, RecursionError, TypeError):  # a damaged or foreign line is dropped and rewritten
                row, key = None, None
            if key is None or key in self.rows:
                self.dropped += 1
                continue
            self.rows[key] = row
        return damaged or self.dropped > 0

    # ------------------------------------------------------------------ writing
    def open(self, *, resume: bool = True) -> dict[str, dict]:
        """Open for appending (creating the folder and file); return the finished rows by key.

        ``resume=False`` starts over (the old file is replaced). Raises :class:`InputError` for a file
        of another study or one that another run is writing.
        """
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            rewrite = True
            if resume and self.path.exists() and self.path.stat().st_size > 0:
                rewrite = self._load()
                if self.dropped:
                    logger.warning("%s: dropped %d damaged or stale line(s)", self.path, self.dropped)
            if rewrite:
                body = "".join(json.dumps(r) + "\n" for r in self.rows.values())
                atomic_write_text(self.path, self._header() + body)
            self._handle = open(self.path, "a", encoding="utf-8")
        except OSError as exc:
            raise InputError(cannot_write(self.path, exc)) from None
        self._lock()
        return dict(self.rows)

    def _lock(self) -> None:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not on POSIX
            return
        assert self._handle is not None
        try:
            fcntl.flock(self._handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._handle.close()
            self._handle = None
            raise InputError(f"{self.path}: another study is writing this file") from None

    def append(self, row: dict) -> None:
        """Write one row as one line and flush it."""
        if self._handle is None:
            raise RuntimeError("RowStore.append before open")
        self._handle.write(json.dumps(row) + "\n")
        self._handle.flush()
        key = self._row_key(row)
        if key is not None:
            self.rows[key] = row

    def saved_count(self) -> int:
        """Rows whose line is complete on disk (what a re-run will reuse).

        Read back from the file rather than counted in memory: an interrupt can land between a row's
        write and its bookkeeping, and the file is what the next run sees.
        """
        if self._handle is not None:
            self._handle.flush()
        lines = self.path.read_text(encoding="utf-8").split("\n")[1:]  # after the header
        return sum(1 for line in lines[:-1] if line.strip())  # the last piece has no newline: incomplete

    def close(self) -> None:
        if self._handle is not None:
            self._handle.close()
            self._handle = None

    def __enter__(self) -> RowStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
