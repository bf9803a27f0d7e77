"""Atomic file output: a file is either written whole or left untouched.

Permissions are those of a plain ``open(path, "w")``: a new file gets ``0o666 & ~umask`` (so ``-rw-r--r--``
under the usual umask 022), and overwriting an existing file keeps that file's permission bits. The
temporary file that becomes the output is created private (``mkstemp`` makes it 0600) and given its final
mode before the rename, so no reader ever sees a partial file or a wider mode than intended.
"""

from __future__ import annotations

import errno
import os
import stat
import sys
import tempfile
import threading
from pathlib import Path
from typing import Iterable

__all__ = ["atomic_write_bytes", "atomic_write_text"]

_UMASK_LOCK = threading.Lock()


def _umask_from_proc() -> int | None:
    """The process's umask as Linux reports it (``Umask:`` in /proc/self/status, Linux ≥ 4.7), else None."""
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    return None


def current_umask() -> int:
    """The process's umask, read without changing it where the system allows.

    Where /proc does not say, the umask is read the only portable way, by setting it and setting it
    back. The lock keeps two writers here from interleaving that; another thread creating a file at that
    instant elsewhere would see the temporary umask 077, so its file would be private, never too open.
    """
    found = _umask_from_proc()
    if found is not None:
        return found
    with _UMASK_LOCK:
        found = os.umask(0o077)
        os.umask(found)
    return found


def _final_mode(target: Path) -> int:
    """The permission bits ``open(target, "w")`` would leave: the existing file's, else 0o666 & ~umask."""
    try:
        existing = os.stat(target)
    except OSError:  # no such file (or no access to it: the write will say so)
        return 0o666 & ~current_umask()
    if stat.S_ISREG(existing.st_mode):
        return stat.S_IMODE(existing.st_mode)
    return 0o666 & ~current_umask()


def _destination(path: str | os.PathLike[str]) -> tuple[Path, os.stat_result | None]:
    """Where a write to ``path`` lands: a symlink's final target, with its status (None if it does not exist)."""
    target = Path(path)
    if target.is_symlink():
        # replacing the link would cut it: write what it points to, next to that file
        target = Path(os.path.realpath(target))
    try:
        return target, os.stat(target)
    except FileNotFoundError:
        return target, None


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path``; a regular file atomically (:func:`atomic_write_chunks` with one chunk)."""
    atomic_write_chunks(path, (data,))


def atomic_write_chunks(path: str | os.PathLike[str], chunks: Iterable[bytes]) -> None:
    """Write the concatenation of ``chunks`` to ``path``; a regular file atomically, via a temporary file in its folder
    and a rename. The chunks are written as they come, so a large answer never exists whole in memory.

    A crash, an exception or a SIGINT/SIGTERM (as the CLI handles them) half-way leaves any previous
    file intact and no partial file behind. The file's permission bits are those of a plain
    ``open(path, "w")`` (module docstring). What is *not* a regular file is never replaced:

    - ``-`` is standard output;
    - a symlink is followed, and its target written atomically as above (the link stays a link);
    - a FIFO, a character or block device (``/dev/null``, a terminal) is opened and written straight
      through, as ``open(path, "w")`` would;
    - a directory raises :class:`IsADirectoryError`.

    Raises
    ------
    OSError
        When the place cannot be written (missing folder, no permission, a directory).
    """
    if os.fspath(path) == "-":
        for data in chunks:
            _write_stdout(data)
        return
    target, status = _destination(path)
    if status is not None and stat.S_ISDIR(status.st_mode):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(path))
    if status is not None and not stat.S_ISREG(status.st_mode):
        with open(target, "wb") as handle:  # FIFO or device: no rename could stand in for it
            for data in chunks:
                handle.write(data)
        return
    folder = target.parent if str(target.parent) else Path(".")
    mode = _final_mode(target)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            for data in chunks:
                handle.write(data)
            handle.flush()
            if hasattr(os, "fchmod"):
                os.fchmod(handle.fileno(), mode)
            else:  # Windows before Python 3.13: only the read-only bit means anything there
                os.chmod(tmp, mode)
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def _write_stdout(data: bytes) -> None:
    out = sys.stdout
    buffer = getattr(out, "buffer", None)
    out.flush()
    if buffer is not None:
        buffer.write(data)
        buffer.flush()
    else:  # a text-only stream (a test's capture): it takes text
        out.write(data.decode("utf-8"))
        out.flush()


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically; see :func:`atomic_write_bytes`."""
    atomic_write_bytes(path, text.encode("utf-8"))
