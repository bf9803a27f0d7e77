"""Certificates: the format (:mod:`.schema`), the independent exact checker (:mod:`.check`) and the
writer that turns floating-point planner output into certificates (:mod:`.writer`).

The schema and the checker import only the standard library, so importing this package does not load
the planner or numpy; the writer's names are loaded on first use.
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
    "write_certificate",
]

_WRITER = {"MoveSpec", "StageSpec", "CycleSpec", "build_certificate", "write_certificate"}


def __getattr__(name: str):
    if name in _WRITER:
        from solverplan.certify import writer

        return getattr(writer, name)
    raise AttributeError(f"module 'solverplan.certify' has no attribute {name!r}")
