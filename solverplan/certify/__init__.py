"""Certificates: the format (:mod:`.schema`), the independent exact checker (:mod:`.check`, with its
exact predicates :mod:`.exact2d`, rigorous angles :mod:`.rational_atan` and the exact belief-state
successors of negative certificates :mod:`.invariant`), the writer that turns floating-point planner output
into certificates (:mod:`.writer`), the invariants of infeasible answers and optimality bounds
(:mod:`.negative`) and the one call from a planner's answer to a checked certificate file (:mod:`.build`:
:func:`certificate`, :func:`write_certificate`).

The schema and the checker import only the standard library, so importing this package does not load
the planner or numpy; the names of the writer and of :mod:`.build` are loaded on first use.
"""

from solverplan.certify.check import CheckReport, Failure, check_certificate
from solverplan.certify.schema import (
    SCHEMA,
    VERSION,
    Certificate,
    CertificateFormatError,
    dumps_certificate,
    load_certificate,
    parse_certificate,
)

__all__ = [
    "SCHEMA",
    "VERSION",
    "Certificate",
    "CertificateFormatError",
    "CheckReport",
    "Failure",
    "check_certificate",
    "load_certificate",
    "parse_certificate",
    "dumps_certificate",
    "MoveSpec",
    "StageSpec",
    "CycleSpec",
    "build_certificate",
    "certificate",
    "write_certificate",
    "NothingToCertify",
    "CertificateRejected",
]

_LAZY = {
    "MoveSpec": "writer",
    "StageSpec": "writer",
    "CycleSpec": "writer",
    "build_certificate": "writer",
    "certificate": "build",
    "write_certificate": "build",
    "NothingToCertify": "build",
    "CertificateRejected": "build",
}
"""Names whose modules load the planner (and numpy): imported on first use."""


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f"solverplan.certify.{_LAZY[name]}"), name)
    raise AttributeError(f"module 'solverplan.certify' has no attribute {name!r}")
