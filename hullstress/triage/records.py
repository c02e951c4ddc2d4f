"""Triage's plain records: what shrinking produced and what the report writes out.

Kept apart from the code that makes them (:mod:`.shrink`, :mod:`.stage`) so
that the report stage can read them without importing anything that runs an
algorithm.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


from ..case import Case
from ..config import AlgorithmConfig
from ..results import ResultRow
from .grouping import FailureGroup
from .signature import Signature
from .simplify import mantissa_bits

__all__ = ["ShrinkResult", "TriageRecord", "TriageResult"]


@dataclass(frozen=True)
class ShrinkResult:
    """What shrinking one case produced.

    Attributes
    ----------
    case : Case
        The minimal case (the original when nothing could be removed).
    original : Case
    signature : Signature
    original_size, minimal_size : int
        Point counts before and after.
    calls : int
        Judged calls made (cache hits not counted).
    seconds : float
    reproduced : bool
        The original case failed with ``signature`` when re-run.  When False,
        ``case`` is the original and ``note`` says why.
    exhausted : bool
        The time or call budget ran out before the passes finished.
    row : ResultRow or None
        The failing row of ``case`` (its verdict, offending indices, reason).
    steps : tuple of str
        One line per accepted simplification, for the report.
    note : str
        Why shrinking stopped early or did not run, or ``""``.
    """

    case: Case
    original: Case
    signature: Signature
    original_size: int
    minimal_size: int
    calls: int
    seconds: float
    reproduced: bool
    exhausted: bool = False
    row: ResultRow | None = None
    steps: tuple[str, ...] = field(default=())
    note: str = ""

    @property
    def max_mantissa_bits(self) -> int:
        """The most significant bits any coordinate of the minimal case uses."""
        pts = self.case.points
        return int(mantissa_bits(pts).max()) if pts.size else 0


@dataclass(frozen=True)
class TriageRecord:
    """Everything the report needs about one failure group; nothing in it runs code.

    Attributes
    ----------
    signature : Signature
    config : AlgorithmConfig
    group : FailureGroup or None
        The group's counts (None for a failure found outside a sweep: ``shrink``, ``fuzz``).
    shrink : ShrinkResult
        The minimal case, the original, the shrink's calls, steps and note
        (``reproduced=False`` when it was not shrunk, with the reason in ``note``).
    faces : list or None
        The algorithm's output on the minimal case, JSON-ready (None without output).
    faces_note : str
        Why there are no faces, or ``""``.
    storage : {"csv", "npy", "raw"}
        How the minimal case's points are stored (see :func:`.evidence.storage_kind`).
    verified : bool or None
        The failure reproduced from the stored points (None when not checked).
    """

    signature: Signature
    config: AlgorithmConfig
    group: FailureGroup | None
    shrink: ShrinkResult
    faces: Any
    faces_note: str
    storage: str
    verified: bool | None

    @property
    def case(self) -> Case:
        """The minimal case."""
        return self.shrink.case


@dataclass
class TriageResult:
    """The triage stage's output.

    Attributes
    ----------
    groups : list of FailureGroup
        Every failure group of the table, worst first.
    records : list of TriageRecord
        One per group that was triaged, in the same order.
    notes : list of str
        How triage ran: budgets, groups not shrunk or without a record.
    seconds : float
    stopped : bool
        Triage was interrupted before every group was handled.
    """

    groups: list[FailureGroup]
    records: list[TriageRecord] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0
    stopped: bool = False
