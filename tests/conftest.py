"""Shared pytest configuration: Hypothesis profiles and common fixtures.

Profiles (select with ``HYPOTHESIS_PROFILE=...`` or ``--hypothesis-profile``):
``dev`` (default, quick), ``ci`` (what .ci/run uses: deterministic, no deadline),
``nightly`` (many more examples, for the slow nightly suite).
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

settings.register_profile("dev", max_examples=30, deadline=None)
settings.register_profile(
    "ci",
    max_examples=30,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "nightly",
    max_examples=1000,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "dev"))
