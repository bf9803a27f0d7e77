"""Files in and out: one bounded reader for every input, and atomic output.

Input (:func:`read_input_bytes`, :func:`read_input_text`): every file solverplan reads goes through one
reader that takes regular files only (or ``-``, standard input, where a command accepts it), checks the
size before reading and again while reading (it never reads past the limit, so ``/dev/zero``, a file
growing while read or a 1 GiB sparse file cost at most the limit), and refuses FIFOs, devices, sockets
and directories — also through symbolic links — in one line without blocking (the file is opened with
``O_NONBLOCK`` and checked with ``fstat`` before a byte is read).

Output: a file is either written whole or left untouched.

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
from typing import Any, Iterable, Mapping

from solverplan.errors import MalformedFile

__all__ = ["atomic_write_bytes", "atomic_write_text", "read_input_bytes", "read_input_text", "shown_path",
           "MAX_INPUT_BYTES", "reason_of", "cannot_write",
           "MAX_JSON_VALUES", "check_json_values"]

MAX_INPUT_BYTES = 64 * 1024 * 1024
"""Largest input file read (bytes); ``solverplan.limits.MAX_FILE_BYTES`` is this number."""

MAX_SHOWN_PATH = 100
"""Longest file path an error line shows (characters): longer ones keep their start and their file name."""

_READ_CHUNK = 1 << 20


def shown_path(path: object, limit: int = MAX_SHOWN_PATH) -> str:
    """``path`` as an error line shows it: whole up to ``limit`` characters, else its start, ``…`` and its end.

    Examples
    --------
    >>> shown_path("/tmp/plan.json")
    '/tmp/plan.json'
    >>> len(shown_path("/tmp/" + "x" * 5000 + ".json"))
    100
    """
    text = os.fsdecode(path) if isinstance(path, (str, bytes, os.PathLike)) else str(path)
    text = text.replace("\n", "\\n").replace("\r", "\\r")  # one line, whatever the name holds
    if len(text) <= limit:
        return text
    head = limit // 3
    return text[:head] + "…" + text[len(text) - (limit - head - 1):]


_REASONS = {
    errno.ENOENT: "no such file",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.ENAMETOOLONG: "file name too long",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.EISDIR: "is a directory",
    errno.ELOOP: "too many levels of symbolic links",
    errno.EROFS: "read-only file system",
    errno.ENOSPC: "no space left on device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EXDEV: "on another file system",
}


def reason_of(exc: OSError) -> str:
    """A short lower-case reason for an :class:`OSError`, without the path (``permission denied``)."""
    return _REASONS.get(exc.errno or 0) or (exc.strerror or exc.__class__.__name__).lower()


MAX_JSON_VALUES = 4_000_000
"""Most values (numbers, strings, arrays, objects) of one JSON input: counted before parsing, so a 64 MiB file
of ``[0,0,0,…]`` (32 million values, a few GB once parsed) is refused while one of 4 million exact decimals
(about half a gigabyte parsed) is read. An environment needs three values per vertex (100,000 vertices: 300,000)."""


def check_json_values(text: str, name: str) -> None:
    """Refuse JSON ``text`` with more than :data:`MAX_JSON_VALUES` values, counted without parsing.

    Every value but the first follows a ``,`` or opens an array or object (``[``, ``{``): their count bounds
    the values from above (separators inside strings count too: an over-estimate, never an under-estimate).
    """
    values = text.count(",") + text.count("[") + text.count("{") + 1
    if values > MAX_JSON_VALUES:
        where = f"{name}: " if name else ""
        raise MalformedFile(f"{where}JSON of about {values:,} values, more than the limit of {MAX_JSON_VALUES:,}")


def file_format(path: Path, fmt: str | None, suffixes: Mapping[str, str], what: str = "format") -> str:
    """The format of file ``path``: ``fmt`` when given (one of the values of ``suffixes``), else the one its extension
    names in ``suffixes`` (``{".json": "json", ...}``, lower case). Otherwise one line (:class:`MalformedFile`) saying
    what to give, the formats named ``what`` in it.

    >>> file_format(Path("a.JSON"), None, {".json": "json", ".wkt": "wkt"})
    'json'
    >>> file_format(Path("a.txt"), None, {".json": "json", ".wkt": "wkt"})
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: a.txt: cannot tell the format from the extension '.txt': use .json or .wkt, or name the format
    """
    def choices(names: Iterable[str]) -> str:
        *most, last = dict.fromkeys(names)
        return f"{', '.join(most)} or {last}" if most else last

    if fmt:
        if fmt not in suffixes.values():
            raise MalformedFile(f"unknown {what} {fmt!r}: use {choices(suffixes.values())}")
        return fmt
    try:
        return suffixes[path.suffix.lower()]
    except KeyError:
        raise MalformedFile(f"{path}: cannot tell the {what} from the extension {path.suffix!r}: use {choices(suffixes)}, "
                            f"or name the {what}") from None


def cannot_write(path: object, exc: OSError) -> str:
    """The one-line message of a failed write: ``PATH: cannot write (Permission denied)``, the path shortened."""
    return f"{shown_path(path)}: cannot write ({exc.strerror or exc.__class__.__name__})"


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _too_large(name: str, size: int, limit: int, what: str) -> MalformedFile:
    return MalformedFile(f"{name}: {what} is {size:,} bytes, more than the limit of {limit:,}")


def _check_input(status: os.stat_result, name: str, limit: int, what: str) -> None:
    """Refuse an input that is not a regular file, or larger than ``limit`` bytes (:class:`MalformedFile`)."""
    if not stat.S_ISREG(status.st_mode):
        raise MalformedFile(f"{name}: {_kind(status.st_mode)}, not a regular file")
    if status.st_size > limit:
        raise _too_large(name, status.st_size, limit, what)


def read_input_bytes(path: str | os.PathLike[str], *, limit: int = MAX_INPUT_BYTES, what: str = "file",
                     stdin: bool = False) -> bytes:
    """The bytes of the input file ``path``: a regular file of at most ``limit`` bytes (``-`` is standard input
    when ``stdin``).

    The file is checked before it is opened (``stat``), opened without blocking (``O_NONBLOCK``: a FIFO
    with no writer does not hang), checked again on the open descriptor (``fstat``: no race with a
    rename), and read in chunks that stop one byte past ``limit``: nothing past the limit is read, even
    from a file that grows or lies about its size.

    Raises
    ------
    MalformedFile
        One line naming the file: missing, unreadable, not a regular file (a FIFO, a device, a directory,
        also through a symbolic link) or larger than ``limit``.

    Examples
    --------
    >>> read_input_bytes("/dev/zero")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: /dev/zero: a character device, not a regular file
    """
    raw = os.fspath(path)
    name = shown_path(raw)
    if stdin and raw == "-":
        return _read_limited(sys.stdin.buffer, limit, "standard input", what)
    try:
        _check_input(os.stat(raw), name, limit, what)
        fd = os.open(raw, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
                     | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0))
    except (OSError, ValueError) as exc:  # ValueError: a NUL byte in the name
        if isinstance(exc, MalformedFile):
            raise
        reason = reason_of(exc) if isinstance(exc, OSError) else "not a valid file name"
        raise MalformedFile(f"{name}: {reason}") from None
    try:
        _check_input(os.fstat(fd), name, limit, what)
        with os.fdopen(os.dup(fd), "rb", buffering=0) as handle:
            return _read_limited(handle, limit, name, what)
    except OSError as exc:
        raise MalformedFile(f"{name}: {reason_of(exc)}") from None
    finally:
        os.close(fd)


def _read_limited(handle: Any, limit: int, name: str, what: str) -> bytes:
    """Read ``handle`` to its end, but never more than ``limit + 1`` bytes (refused past ``limit``)."""
    parts: list[bytes] = []
    total = 0
    while True:
        chunk = handle.read(min(_READ_CHUNK, limit + 1 - total))
        if not chunk:
            break
        parts.append(chunk)
        total += len(chunk)
        if total > limit:
            raise MalformedFile(f"{name}: {what} is more than the limit of {limit:,} bytes")
    return b"".join(parts)


def read_input_text(path: str | os.PathLike[str], *, limit: int = MAX_INPUT_BYTES, what: str = "file",
                    stdin: bool = False) -> str:
    """The UTF-8 text of the input file ``path``, read by :func:`read_input_bytes` (same limits and errors).

    A leading byte-order mark is dropped. Raises :class:`~solverplan.errors.MalformedFile` when the bytes
    are not UTF-8.
    """
    data = read_input_bytes(path, limit=limit, what=what, stdin=stdin)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        name = "standard input" if stdin and os.fspath(path) == "-" else shown_path(os.fspath(path))
        raise MalformedFile(f"{name}: not UTF-8 text (byte {exc.start})") from None

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


def _may_write(target: Path) -> bool:
    """Whether this process may open the existing file ``target`` for writing, as a shell redirect would."""
    effective = os.access in os.supports_effective_ids
    return os.access(target, os.W_OK, effective_ids=effective)


def _in_place_reason(status: os.stat_result) -> str | None:
    """Why an existing regular file must be rewritten in place instead of replaced by a rename, or None.

    A rename would give the path a new inode: the file's other hard links would keep the old content, and a
    file of another owner (one the user may write, e.g. group-writable) would pass to the writer. A shell
    redirect keeps both, so the file is written through instead.
    """
    if status.st_nlink > 1:
        return "it has other hard links"
    if hasattr(os, "geteuid") and status.st_uid != os.geteuid():
        return "it belongs to another user"
    return None


def _write_in_place(target: Path, chunks: Iterable[bytes]) -> None:
    """Overwrite the existing file ``target`` through its inode (links, owner and mode kept): not atomic."""
    fd = os.open(target, os.O_WRONLY | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0))
    with os.fdopen(fd, "wb") as handle:
        written = 0
        for data in chunks:
            handle.write(data)
            written += len(data)
        handle.truncate(written)
        handle.flush()
        os.fsync(handle.fileno())


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path``; a regular file atomically (:func:`atomic_write_chunks` with one chunk)."""
    atomic_write_chunks(path, (data,))


def atomic_write_chunks(path: str | os.PathLike[str], chunks: Iterable[bytes]) -> None:
    """Write the concatenation of ``chunks`` to ``path``; a regular file atomically, via a temporary file in its folder
    and a rename. The chunks are written as they come, so a large answer never exists whole in memory.

    A crash, an exception or a SIGINT/SIGTERM (as the CLI handles them) half-way leaves any previous
    file intact and no partial file behind. The file's permission bits are those of a plain
    ``open(path, "w")`` (module docstring). Permissions are those of a shell redirect (``> path``):

    - an existing file the user may not write (``0444``, or another user's file in the user's own folder)
      raises :class:`PermissionError` and is left as it is — a rename would replace it all the same;
    - an existing file with other hard links, or of another owner (that the user may write), is rewritten
      in place through its inode, so the links and the owner stay (not atomic: a rename would cut the
      links or take the file from its owner); so is a writable file in a folder the user may not write.

    What is *not* a regular file is never replaced:

    - ``-`` is standard output;
    - a symlink is followed, and its target written atomically as above (the link stays a link);
    - a FIFO, a character or block device (``/dev/null``, a terminal) is opened and written straight
      through, as ``open(path, "w")`` would;
    - a directory raises :class:`IsADirectoryError`.

    Raises
    ------
    OSError
        When the place cannot be written (missing folder, no permission, a directory, a name too long).
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
    if status is not None:
        if not _may_write(target):
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))
        if _in_place_reason(status) is not None:
            _write_in_place(target, chunks)
            return
    folder = target.parent if str(target.parent) else Path(".")
    mode = _final_mode(target)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name[:64]}.", suffix=".tmp", dir=folder)
    except PermissionError:
        if status is None:
            raise
        _write_in_place(target, chunks)  # a writable file in a folder we may not write: as a redirect does
        return
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
