"""``python -m solverplan.cli``: the same as the ``solverplan`` command."""

from solverplan.cli import main

main()
