"""Issue #28's reproducer classes as real processes: 2 GiB address-space cap, a timeout, one line or an answer.

Each case of benchmarks/input_reproducers.py (special files, outsized inputs, malformed drawings, maps, answer
files, options, paths and permissions) runs ``solverplan`` in a child process under ``RLIMIT_AS`` = 2 GiB; it must
exit 0 or 2 (1 only where a checked file is invalid), print no traceback, write one stderr line of at most 200
characters, finish within the timeout and stay under the cap. Slow (a few minutes for all): run with ``-m slow``.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

import input_reproducers as reproducers  # noqa: E402

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def root():
    reproducers._reap_with_usage()
    folder = Path(tempfile.mkdtemp(prefix="input-repro."))
    folder.chmod(0o755)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@pytest.mark.parametrize("case", reproducers.CASES, ids=lambda case: case.name)
def test_reproducer_answers_or_refuses_in_one_line_within_2_gib(root, case):
    outcome = reproducers.run_case(case, root)
    assert not outcome.problems, (outcome.problems, outcome.code, outcome.first_line)
    assert outcome.peak_mib < reproducers.CAP_BYTES / 2**20
