"""Triage: group failing rows by signature, shrink each group's smallest case, fuzz.

* :func:`group_failures` -- one :class:`FailureGroup` per :class:`Signature`.
* :func:`shrink` -- ddmin over points, then coordinate simplification.
* :func:`fails_same_way` -- the shrinker's oracle (isolated through
  ``hullstress.runner.run_one`` when available).
* :func:`fuzz` -- Hypothesis-driven search over the generator families.
"""

from .grouping import FailureGroup, group_failures, groups_frame
from .oracle import IsolationUnavailable, fails_same_way, run_config
from .shrink import ShrinkResult, derive_case, shrink
from .signature import Signature, failed_check, signature_of

__all__ = [
    "FailureGroup",
    "IsolationUnavailable",
    "ShrinkResult",
    "Signature",
    "derive_case",
    "failed_check",
    "fails_same_way",
    "group_failures",
    "groups_frame",
    "run_config",
    "shrink",
    "signature_of",
]


def __getattr__(name: str):  # fuzz pulls in Hypothesis: load it only when asked for
    if name in ("fuzz", "FuzzResult"):
        from . import fuzzing as _fuzz

        return getattr(_fuzz, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
