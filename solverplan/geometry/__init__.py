"""The geometry kernel: exact predicates with float filters, ray casting, visibility.

Imports only :mod:`solverplan.exact`, :mod:`solverplan.environment` and :mod:`solverplan.errors`.
"""
