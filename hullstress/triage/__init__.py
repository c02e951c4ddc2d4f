"""Triage: failing rows -> failure groups (signatures) -> minimal cases -> causes.

The pipeline's triage stage is :func:`triage_failures` (:mod:`.stage`); it
returns plain records (:mod:`.records`) that the report stage writes out.

* :func:`signature_of` -- a row's :class:`Signature`: config, stage, status,
  failed checks and severity, exception type and frame.
* :func:`group_failures` -- one :class:`FailureGroup` per signature.
* :func:`shrink` -- delete points, then simplify coordinates, keeping the
  signature exactly, on a budget counted in evaluations (:class:`Shrinker`
  is the same as a state machine, for running many in lockstep).
* :func:`canonical_key` -- when two minimal cases are the same input.
* :func:`fails_same_way` -- the shrinker's oracle (isolated through
  ``hullstress.runner.run_one`` when available).
* :func:`fuzz` -- Hypothesis-driven search over the generator families.
"""

from .canonical import canonical_form, canonical_key
from .grouping import FailureGroup, group_failures, groups_frame
from .oracle import IsolationUnavailable, fails_same_way, run_config
from .records import Cause, ShrinkResult, TriageRecord, TriageResult
from .shrink import Shrinker, derive_case, shrink
from .signature import Signature, failed_check, signature_of
from .stage import triage_failures, triage_one

__all__ = [
    "Cause",
    "FailureGroup",
    "IsolationUnavailable",
    "ShrinkResult",
    "Shrinker",
    "Signature",
    "canonical_form",
    "canonical_key",
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
