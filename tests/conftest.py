"""Shared pytest configuration: Hypothesis profiles and common fixtures.

Profiles (select with ``HYPOTHESIS_PROFILE=...`` or ``--hypothesis-profile``):

``ci`` (the default, whatever the environment says)
    Deterministic and database-free: the same examples on every run and every
    machine, nothing read from or written to ``.hypothesis/``.  The README's
    test command and ``.ci/run`` use it without setting anything.
``nightly``
    Fresh random seeds and many more examples, for the nightly workflow.  A
    failure it finds prints its minimal example; add that as an explicit
    ``@example`` to the test so the ``ci`` profile replays it forever.
``dev``
    Random seeds with the local example database, for exploring at a desk.
``mutation``
    Like ``ci`` with fewer examples: the mutation run (``tools/mutation.sh``)
    runs the checker's tests once per mutant.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

_DETERMINISTIC = dict(deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])

settings.register_profile("ci", max_examples=30, **_DETERMINISTIC)
settings.register_profile("mutation", max_examples=10, **_DETERMINISTIC)
settings.register_profile("dev", max_examples=30, deadline=None)
settings.register_profile(
    "nightly",
    max_examples=1000,
    deadline=None,
    derandomize=False,
    database=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
