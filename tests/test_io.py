"""Atomic output files: whole or untouched, with the permissions a plain ``open(path, "w")`` gives."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from solverplan import _io
from solverplan._io import atomic_write_bytes, atomic_write_text

ROOT = Path(__file__).resolve().parent.parent

# Run in a child so that setting the umask cannot disturb this process (pytest may run threads).
_CHILD = r"""
import json, os, stat, sys
from pathlib import Path
from solverplan import _io
from solverplan._io import atomic_write_text, current_umask

os.umask(int(sys.argv[1], 8))
folder = Path(sys.argv[2])
mode = lambda p: stat.S_IMODE(os.stat(p).st_mode)
with open(folder / "plain.txt", "w") as handle:
    handle.write("x")
atomic_write_text(folder / "new.json", "{}")
(folder / "old.json").write_text("old")
os.chmod(folder / "old.json", 0o640)
atomic_write_text(folder / "old.json", "{}")
proc = _io._umask_from_proc()
_io._umask_from_proc = lambda: None  # the portable fallback: set the umask and set it back
fallback = current_umask()
atomic_write_text(folder / "fallback.json", "{}")
print(json.dumps({
    "plain": mode(folder / "plain.txt"), "new": mode(folder / "new.json"), "old": mode(folder / "old.json"),
    "proc": proc, "fallback_umask": fallback, "fallback": mode(folder / "fallback.json"), "umask_after": os.umask(0),
    "leftovers": sorted(p.name for p in folder.iterdir() if p.name.startswith(".")),
}))
"""


@pytest.mark.skipif(os.name != "posix", reason="POSIX permission bits")
@pytest.mark.parametrize("umask,expected", [(0o022, 0o644), (0o077, 0o600)])
def test_new_files_respect_the_umask_and_overwritten_files_keep_their_mode(umask, expected, tmp_path):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-c", _CHILD, f"{umask:o}", str(tmp_path)], capture_output=True, text=True, env=env, check=True
    )
    modes = json.loads(done.stdout)
    assert modes["new"] == modes["plain"] == expected, "a new file gets 0o666 & ~umask, as open() gives"
    assert modes["old"] == 0o640, "overwriting keeps the existing file's permission bits, as open() does"
    if Path("/proc/self/status").exists():
        assert modes["proc"] == umask, "Linux says the umask in /proc/self/status"
    assert modes["fallback_umask"] == umask and modes["fallback"] == expected
    assert modes["umask_after"] == umask, "the fallback restores the umask it read"
    assert modes["leftovers"] == [], "no temporary file is left behind"


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "answer.json"
    atomic_write_text(target, "old")

    def broken_replace(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(_io.os, "replace", broken_replace)
    with pytest.raises(OSError, match="disk full"):
        atomic_write_bytes(target, b"new")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["answer.json"]


def test_a_directory_in_the_way_is_an_error_not_a_lost_directory(tmp_path):
    (tmp_path / "out").mkdir()
    with pytest.raises(OSError):
        atomic_write_text(tmp_path / "out", "{}")
    assert (tmp_path / "out").is_dir() and stat.S_ISDIR(os.stat(tmp_path / "out").st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


# ---------------------------------------------------------------------- what is not a regular file is never replaced
def test_a_symlink_stays_a_link_and_its_target_is_written(tmp_path):
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "answer.json"
    target.write_text("old")
    os.chmod(target, 0o640)
    link = tmp_path / "link.json"
    link.symlink_to(target)
    atomic_write_text(link, "new")
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text() == "new" and stat.S_IMODE(os.stat(target).st_mode) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json", "real"]
    assert [p.name for p in (tmp_path / "real").iterdir()] == ["answer.json"], "the temporary sat next to the target"


def test_a_dangling_symlink_creates_its_target(tmp_path):
    link = tmp_path / "link.json"
    link.symlink_to(tmp_path / "made.json")
    atomic_write_text(link, "{}")
    assert link.is_symlink() and (tmp_path / "made.json").read_text() == "{}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="POSIX FIFOs")
def test_a_fifo_is_written_straight_through(tmp_path):
    import threading

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()), daemon=True)
    reader.start()
    atomic_write_bytes(fifo, b"through the pipe")
    reader.join(timeout=10)
    assert received == [b"through the pipe"]
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["pipe"]


def _null_device(tmp_path: Path) -> Path:
    """A character device like /dev/null inside ``tmp_path`` (root only), so a regression cannot touch /dev/null."""
    if not hasattr(os, "mknod") or os.geteuid() != 0:
        pytest.skip("making a device node needs root")
    device = tmp_path / "null"
    os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # Linux's null device (/dev/null may be a bind mount)
    try:
        with open(device, "wb"):
            pass
    except OSError:
        pytest.skip("device nodes cannot be opened here")
    return device


def test_a_character_device_is_written_through_and_stays_a_device(tmp_path):
    device = _null_device(tmp_path)
    atomic_write_text(device, "discarded")
    assert stat.S_ISCHR(os.stat(device).st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["null"]


def test_cli_graph_onto_a_null_device_leaves_it_a_device(tmp_path):
    from typer.testing import CliRunner

    from solverplan import cli

    device = _null_device(tmp_path)
    result = CliRunner().invoke(cli.app, ["graph", "two_rooms", "-o", str(device)])
    assert result.exit_code == 0, result.stderr
    assert stat.S_ISCHR(os.stat(device).st_mode) and os.stat(device).st_rdev == os.makedev(1, 3)


def test_dash_is_standard_output(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    atomic_write_text("-", "to stdout\n")
    assert capfd.readouterr().out == "to stdout\n"
    assert list(tmp_path.iterdir()) == [], "no file named '-'"


def test_cli_output_dash_and_directory(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from solverplan import cli

    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    result = runner.invoke(cli.app, ["info", "two_rooms", "-o", "-"])
    assert result.exit_code == 0 and json.loads(result.stdout)["name"] == "two_rooms"
    (tmp_path / "out").mkdir()
    result = runner.invoke(cli.app, ["info", "two_rooms", "-o", "out"])
    assert result.exit_code == 2 and result.stderr == "error: out: cannot write (Is a directory)\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


# SIGTERM arrives while the temporary file exists (fsync made slow); the CLI's handler must unwind like SIGINT.
_SIGTERM_CHILD = r"""
import os, sys, time, signal
from solverplan import cli, _io
signal.signal(signal.SIGTERM, cli._terminate)
def slow_fsync(fd):
    print("writing", flush=True)
    time.sleep(30)
_io.os.fsync = slow_fsync
_io.atomic_write_text(sys.argv[1], "x" * 1000)
"""


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_sigterm_during_a_write_leaves_no_temporary(tmp_path):
    import signal

    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    target = tmp_path / "answer.json"
    child = subprocess.Popen([sys.executable, "-c", _SIGTERM_CHILD, str(target)], stdout=subprocess.PIPE, text=True, env=env)
    try:
        assert child.stdout.readline() == "writing\n"
        assert len(list(tmp_path.iterdir())) == 1, "the temporary exists while the write runs"
        child.send_signal(signal.SIGTERM)
        assert child.wait(timeout=20) == 128 + signal.SIGTERM
    finally:
        if child.poll() is None:
            child.kill()
    assert list(tmp_path.iterdir()) == []


def test_main_installs_the_sigterm_handler(monkeypatch):
    import signal

    from solverplan import cli

    installed = {}
    monkeypatch.setattr(cli.signal, "signal", lambda sig, handler: installed.setdefault(sig, handler))
    monkeypatch.setattr(cli, "command_for", lambda app, argv: lambda: None)  # no command is run
    cli.main()
    assert installed == {signal.SIGTERM: cli._terminate}
    with pytest.raises(SystemExit) as exit_info:
        cli._terminate(signal.SIGTERM, None)
    assert exit_info.value.code == 143


# ---------------------------------------------------------------------- permissions like a shell redirect (#28)
def _as_nobody(code: str, *paths: Path) -> subprocess.CompletedProcess | None:
    """Run ``code`` (with solverplan imported as root first) as the user ``nobody``; None where that cannot be done."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        return None
    import pwd

    try:
        nobody = pwd.getpwnam("nobody")
    except KeyError:
        return None
    script = ("import os, sys, encodings.ascii; from solverplan._io import atomic_write_text\n"
              f"os.setgid({nobody.pw_gid}); os.setgroups([]); os.setuid({nobody.pw_uid})\n" + code)
    return subprocess.run([sys.executable, "-c", script, *map(str, paths)], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}, timeout=60)


def test_a_read_only_file_is_never_replaced(tmp_path, monkeypatch):
    """0444: a shell redirect says Permission denied; so does the writer, though the folder allows a rename."""
    target = tmp_path / "answer.json"
    target.write_text("keep\n")
    target.chmod(0o444)
    monkeypatch.setattr(_io, "_may_write", lambda path: False)  # the logic, also where the tests run as root
    with pytest.raises(PermissionError):
        atomic_write_text(target, "new\n")
    assert target.read_text() == "keep\n" and stat.S_IMODE(target.stat().st_mode) == 0o444
    assert sorted(p.name for p in tmp_path.iterdir()) == ["answer.json"]


def test_an_unprivileged_user_cannot_replace_a_read_only_or_a_root_owned_file(tmp_path):
    """As the user nobody (root runs the test): their own 0444 file, and root's file in their writable folder."""
    tmp_path.chmod(0o777)
    own, roots = tmp_path / "own.json", tmp_path / "roots.json"
    own.write_text("keep\n")
    roots.write_text("keep\n")
    code = ("import sys\nfor path in sys.argv[1:]:\n    try:\n        atomic_write_text(path, 'new')\n        print('written')\n"
            "    except PermissionError as exc:\n        print(exc.strerror)\n")
    probe = _as_nobody("pass")
    if probe is None or probe.returncode != 0:
        pytest.skip("needs root and a user 'nobody' who can run this interpreter")
    import pwd

    nobody = pwd.getpwnam("nobody")
    os.chown(own, nobody.pw_uid, nobody.pw_gid)
    own.chmod(0o444)
    roots.chmod(0o644)
    result = _as_nobody(code, own, roots)
    assert result is not None and result.stdout.split("\n")[:2] == ["Permission denied", "Permission denied"], result
    assert own.read_text() == roots.read_text() == "keep\n" and roots.stat().st_uid == 0


def test_hard_links_are_kept_by_writing_in_place(tmp_path):
    target, other = tmp_path / "answer.json", tmp_path / "same-file.json"
    target.write_text("old old old\n")
    os.link(target, other)
    atomic_write_text(target, "new\n")
    assert other.read_text() == "new\n" and target.stat().st_ino == other.stat().st_ino and target.stat().st_nlink == 2


def test_another_owners_writable_file_keeps_its_owner(tmp_path, monkeypatch):
    target = tmp_path / "answer.json"
    target.write_text("old\n")
    inode = target.stat().st_ino
    monkeypatch.setattr(os, "geteuid", lambda: target.stat().st_uid + 1)  # someone else's (group-writable) file
    atomic_write_text(target, "new\n")
    assert target.read_text() == "new\n" and target.stat().st_ino == inode


def test_a_writable_file_in_a_folder_we_cannot_write_is_written_in_place(tmp_path, monkeypatch):
    target = tmp_path / "answer.json"
    target.write_text("old\n")

    def no_temporary(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(_io.tempfile, "mkstemp", no_temporary)
    atomic_write_text(target, "new\n")
    assert target.read_text() == "new\n"
    with pytest.raises(PermissionError):  # a new file there cannot be made at all, as with a redirect
        atomic_write_text(tmp_path / "new.json", "x")


# ---------------------------------------------------------------------- the bounded reader (#28)
@pytest.mark.parametrize("kind", ["dev-zero", "fifo", "directory", "sparse", "missing", "long-name", "nul"])
def test_the_bounded_reader_refuses_what_is_not_a_small_regular_file_at_once(tmp_path, kind):
    from solverplan._io import read_input_bytes
    from solverplan.errors import MalformedFile

    path = {"dev-zero": "/dev/zero", "long-name": str(tmp_path / ("n" * 300)), "nul": "a\0b"}.get(kind, str(tmp_path / "f"))
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "directory":
        os.mkdir(path)
    elif kind == "sparse":
        with open(path, "wb") as handle:
            handle.truncate(1 << 30)
    reasons = {"dev-zero": "a character device, not a regular file", "fifo": "a FIFO, not a regular file",
               "directory": "a directory, not a regular file", "sparse": "more than the limit",
               "missing": "no such file", "long-name": "file name too long", "nul": "not a valid file name"}
    with pytest.raises(MalformedFile, match=reasons[kind]) as caught:
        read_input_bytes(path)
    assert len(str(caught.value)) <= 200


def test_the_bounded_reader_never_reads_past_the_limit(tmp_path, monkeypatch):
    """A file that grows after its size was checked is cut at limit + 1 bytes and refused."""
    from solverplan._io import _read_limited
    from solverplan.errors import MalformedFile

    class Endless:
        asked = 0

        def read(self, n):
            Endless.asked += n
            return b"x" * n

    with pytest.raises(MalformedFile, match="more than the limit of 1,000 bytes"):
        _read_limited(Endless(), 1000, "f", "file")
    assert Endless.asked == 1001
