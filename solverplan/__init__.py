"""solverplan."""
