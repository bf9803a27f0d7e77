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
