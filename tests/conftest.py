"""Shared test configuration: hypothesis profiles and the shipped models in the doctest namespace.

Profiles (select with HYPOTHESIS_PROFILE or pytest --hypothesis-profile):
- ``ci`` (default): derandomized, no deadline — reproducible, never flaky;
- ``thorough``: 10× the examples, for local runs before a change lands.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# The CLI keeps slow safe BVGs in ~/.cache by default: the suite must not write there (tests of the cache
# give their own folder with --graph-cache or set_graph_cache).
os.environ.setdefault("SOLVERPLAN_GRAPH_CACHE", "off")

# CI must never be flaky: generation-budget health checks depend on machine load (seen with
# concurrent test runs), so they are off; the strategies' rejection rates are kept low by design.
_LOAD_DEPENDENT = [HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large]
settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    print_blob=True,
    suppress_health_check=_LOAD_DEPENDENT,
)
settings.register_profile(
    "thorough",
    max_examples=1000,
    deadline=None,
    print_blob=True,
    suppress_health_check=_LOAD_DEPENDENT,
)
settings.register_profile(  # tests/test_fuzz_cli.py: 10,000 random (not derandomized) inputs per test
    "fuzz",
    max_examples=10_000,
    deadline=None,
    print_blob=True,
    suppress_health_check=_LOAD_DEPENDENT,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

MODELS = Path(__file__).resolve().parent.parent / "solverplan" / "models"


@pytest.fixture
def models_dir() -> Path:
    """The folder of shipped environment files."""
    return MODELS
