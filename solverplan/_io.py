"""Atomic file output: a file is either written whole or left untouched.

Permissions are those of a plain ``open(path, "w")``: a new file gets ``0o666 & ~umask`` (so ``-rw-r--r--``
under the usual umask 022), and overwriting an existing file keeps that file's permission bits. The
temporary file that becomes the output is created private (``mkstemp`` makes it 0600) and given its final
mode before the rename, so no reader ever sees a partial file or a wider mode than intended.
"""

from __future__ import annotations

import os
import stat
import tempfile
import threading
from pathlib import Path

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


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path`` via a temporary file in the same folder and a rename.

    A crash or an exception half-way leaves any previous file intact and no partial file behind. The file's
    permission bits are those of a plain ``open(path, "w")`` (module docstring).
    """
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    mode = _final_mode(target)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
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


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically; see :func:`atomic_write_bytes`."""
    atomic_write_bytes(path, text.encode("utf-8"))
