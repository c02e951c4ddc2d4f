"""Triage: group failing rows by signature, shrink each group's smallest case, fuzz.

The pipeline's triage stage is :func:`triage_failures` (:mod:`.stage`); it
returns plain records (:mod:`.records`) that the report stage writes out.

* :func:`group_failures` -- one :class:`FailureGroup` per :class:`Signature`.
* :func:`shrink` -- ddmin over points, then coordinate simplification.
* :func:`fails_same_way` -- the shrinker's oracle (isolated through
  ``hullstress.runner.run_one`` when available).
* :func:`fuzz` -- Hypothesis-driven search over the generator families.
"""

from .grouping import FailureGroup, group_failures, groups_frame
from .oracle import IsolationUnavailable, fails_same_way, run_config
from .records import ShrinkResult, TriageRecord, TriageResult
from .shrink import derive_case, shrink
from .signature import Signature, failed_check, signature_of
from .stage import triage_failures, triage_one

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
    "TriageRecord",
    "TriageResult",
    "triage_failures",
    "triage_one",
]


def __getattr__(name: str):  # fuzz pulls in Hypothesis: load it only when asked for
    if name in ("fuzz", "FuzzResult"):
        from . import fuzzing as _fuzz

        return getattr(_fuzz, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
