"""Triage's plain records: what shrinking produced and what the report writes out.

* :class:`ShrinkResult` -- one shrink: the minimal case and how it was reached.
* :class:`TriageRecord` -- one failure group triaged: its shrink and the evidence.
* :class:`Cause` -- failure groups whose minimal inputs coincide (up to
  translation, power-of-two scaling, row and axis order): one bug, reported
  once, with every config and family it covers.
* :class:`TriageResult` -- the stage's output.

Kept apart from the code that makes them (:mod:`.shrink`, :mod:`.stage`) so
that the report stage can read them without importing anything that runs an
algorithm.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..case import Case
from ..config import AlgorithmConfig
from ..results import ResultRow
from .grouping import FailureGroup
from .signature import Signature
from .simplify import mantissa_bits

__all__ = ["ShrinkResult", "TriageRecord", "Cause", "TriageResult", "merge_family_counts"]


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
        The evaluation budget (or the wall-clock safety net) ran out before the passes finished.
    row : ResultRow or None
        The failing row of ``case`` (its verdict, offending indices, reason).
    steps : tuple of str
        One line per accepted simplification, for the report.
    note : str
        Why shrinking stopped early or did not run, or ``""``.
    adopted : bool
        The shrink started from another group's minimal case, not from its own.
    verified : bool or None
        The minimal case, re-run at the end, failed with the signature again
        (False: flaky; None: not re-run).
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
    adopted: bool = False
    verified: bool | None = None

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

    @property
    def families(self) -> tuple[tuple[str, int], ...]:
        """Failing calls per family (the group's; the case's own family outside a sweep)."""
        if self.group is not None and self.group.families:
            return self.group.families
        return ((self.shrink.original.family, 1),)

    @property
    def failures(self) -> int:
        """Failing calls of the group (1 outside a sweep)."""
        return self.group.count if self.group is not None else 1


def merge_family_counts(parts: Sequence[tuple[tuple[str, int], ...]]) -> tuple[tuple[str, int], ...]:
    """Add up per-family counts; most first, ties by name.

    Examples
    --------
    >>> merge_family_counts([(("a", 2), ("b", 1)), (("b", 3),)])
    (('b', 4), ('a', 2))
    """
    total: dict[str, int] = {}
    for part in parts:
        for family, n in part:
            total[family] = total.get(family, 0) + int(n)
    return tuple(sorted(total.items(), key=lambda fn: (-fn[1], fn[0])))


@dataclass(frozen=True)
class Cause:
    """Failure groups whose minimal inputs coincide: one bug, whatever the configs and families.

    Attributes
    ----------
    key : str
        :func:`~.canonical.canonical_key` of the minimal input shared by the
        members (for a group that was not minimised: its own, unmerged).
    records : tuple of TriageRecord
        The members, worst group first; the first is the representative whose
        minimal case the cause's folder holds.
    """

    key: str
    records: tuple[TriageRecord, ...]

    @property
    def representative(self) -> TriageRecord:
        return self.records[0]

    @property
    def signature(self) -> Signature:
        return self.representative.signature

    @property
    def slug(self) -> str:
        """The cause's folder name: its representative's signature slug."""
        return self.signature.slug

    @property
    def failures(self) -> int:
        """Failing calls over every member group."""
        return sum(r.failures for r in self.records)

    @property
    def families(self) -> tuple[tuple[str, int], ...]:
        """Failing calls per family over every member, most first."""
        return merge_family_counts([r.families for r in self.records])

    @property
    def configs(self) -> tuple[str, ...]:
        """Config labels of the members, in member order, without repeats."""
        return tuple(dict.fromkeys(r.config.label for r in self.records))

    @property
    def minimal_size(self) -> int:
        return self.representative.shrink.minimal_size

    @property
    def headline(self) -> str:
        """One line: the representative's label, and how many more configs fail the same way.

        Examples
        --------
        ``gift-wrap-3d[sphere=off,eps=scaled] fail containment (gross (31 x DISTround)) (+3 configs)``
        """
        more = len(self.configs) - 1
        label = self.signature.label
        sig, row = self.signature, self.representative.shrink.row
        if sig.severity and row is not None and f"({sig.severity})" in label:
            from ..checker.severity import describe_severity

            # The grade alone reads as a contradiction next to a small distance: say why (gross: an orientation).
            shown = describe_severity(sig.severity, row.get("max_violation"), manifoldness=row.get("manifoldness"),
                                      detail=str(row.get("reason") or ""))
            label = label.replace(f"({sig.severity})", f"({shown})")
        return label + (f" (+{more} config{'s' if more > 1 else ''})" if more > 0 else "")

    @property
    def minimised(self) -> bool:
        """The representative's case was shrunk (not merely the smallest failing case as found)."""
        return self.representative.shrink.reproduced


@dataclass
class TriageResult:
    """The triage stage's output.

    Attributes
    ----------
    groups : list of FailureGroup
        Every failure group of the table, worst first.
    records : list of TriageRecord
        One per group that was triaged, in the same order.
    causes : list of Cause
        The records merged by coinciding minimal input, worst first (most
        failing calls; ties in group order).  Every record is in exactly one.
    notes : list of str
        How triage ran: budgets, groups not shrunk or without a record.
    seconds : float
    stopped : bool
        Triage was interrupted before every group was handled.
    calls : int
        Evaluations the shrinks asked for (the unit of the budget; cross-checks included).
    reused : int
        Of those, the ones answered by an identical earlier call (same points,
        config and reference) instead of a new one.
    safety_net : bool
        The wall-clock safety net stopped triage: what it produced may differ between runs.
    """

    groups: list[FailureGroup]
    records: list[TriageRecord] = field(default_factory=list)
    causes: list[Cause] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0
    stopped: bool = False
    calls: int = 0
    safety_net: bool = False
    reused: int = 0
