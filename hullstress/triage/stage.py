"""The triage stage: failing rows -> groups -> one minimised, verified case per group.

:func:`triage_failures` reads the results table and the cases, and returns
plain records (:class:`TriageRecord`) that the report stage writes out; it is
the only stage after the sweep that runs code under test.  Its time is
bounded by the profile's :class:`~hullstress.options.TriageBudget`: groups
are handled worst first; past the shrink budget a group keeps its smallest
failing case unshrunk; past the total budget (or the cap on folders) a group
gets no record and stays in the tables only.  :attr:`TriageResult.notes`
says how many of each.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import pandas as pd

from ..case import Case
from ..config import AlgorithmConfig
from ..options import DEFAULTS, TriageBudget
from ..results import ResultRow
from .evidence import output_faces, storage_kind, verify_from_storage
from .grouping import FailureGroup, group_failures
from .oracle import DEFAULT_TIMEOUT
from .records import ShrinkResult, TriageRecord, TriageResult
from .shrink import shrink as shrink_case
from .signature import Signature

__all__ = ["TriageRecord", "TriageResult", "triage_failures", "triage_one"]


def _unshrunk(case: Case, signature: Signature, row: ResultRow | None, note: str) -> ShrinkResult:
    """The group's smallest case as its own "minimal" case, with why it was not shrunk."""
    return ShrinkResult(case=case, original=case, signature=signature, original_size=case.n_points,
                        minimal_size=case.n_points, calls=0, seconds=0.0, reproduced=False, row=row, note=note)


def _table_row(table: pd.DataFrame, index: int) -> ResultRow:
    return ResultRow({k: (None if (not isinstance(v, (list, dict)) and pd.isna(v)) else v)
                      for k, v in table.loc[index].items()})


def triage_one(result: ShrinkResult, config: AlgorithmConfig, *, group: FailureGroup | None = None,
               timeout: float | None = None, verify: bool = True, qhull_options: str | None = None) -> TriageRecord:
    """Gather a shrink result's evidence: the output faces, the storage form, the verification.

    Parameters
    ----------
    result : ShrinkResult
        From :func:`hullstress.triage.shrink` (or an unshrunk stand-in).
    config : AlgorithmConfig
    group : FailureGroup, optional
    timeout : float, optional
        Per-call timeout for the verification run.
    verify : bool
        Re-run the case from its stored form (skipped for hangs: a full timeout each).
    qhull_options : str, optional
        The run's ``--qhull-options`` (the verification's reference uses them).
    """
    sig = result.signature
    dangerous = sig.check in ("timeout", "crash")
    kind = storage_kind(result.case.points)
    faces, note = output_faces(result.case, config, sig) if not dangerous else (None, f"no output: {sig.check}")
    verified = verify_from_storage(result.case, kind, config, sig, timeout, qhull_options) if verify else None
    return TriageRecord(signature=sig, config=config, group=group, shrink=result, faces=faces,
                        faces_note=note, storage=kind, verified=verified)


def triage_failures(
    table: pd.DataFrame,
    cases: Sequence[Case],
    *,
    budget: TriageBudget,
    shrink: bool = True,
    timeout: float | None = None,
    max_records: int = DEFAULTS.max_folders,
    should_stop: Callable[[], bool] | None = None,
    qhull_options: str | None = None,
) -> TriageResult:
    """Group the table's failures and minimise and verify one case per group, within ``budget``.

    Parameters
    ----------
    table : DataFrame
        The results table.
    cases : sequence of Case
        The cases whose ids appear in ``table``.
    budget : TriageBudget
        Time limits (the profile's).
    shrink : bool
        Shrink each group's smallest failing case (``--no-shrink`` turns it off).
    timeout : float, optional
        The sweep's per-call timeout, reused for shrinking calls.
    max_records : int
        Cap on triaged groups (worst first).
    should_stop : callable, optional
        Polled between groups and by the shrinker between calls; when it
        returns True triage ends early (an interrupt).
    qhull_options : str, optional
        The run's ``--qhull-options``, for every re-run's reference.

    Returns
    -------
    TriageResult
    """
    start = time.perf_counter()
    groups = group_failures(table)
    by_id = {c.case_id: c for c in cases}
    records: list[TriageRecord] = []
    spent = 0.0
    not_shrunk = missing = 0
    out_of_time = stopped = False
    call_timeout = timeout or DEFAULT_TIMEOUT
    for group in groups[:max_records]:
        try:
            if should_stop is not None and should_stop():
                stopped = True
                break
            if time.perf_counter() - start > budget.total:
                out_of_time = True
                break
            case = by_id.get(group.smallest_case_id)
            if case is None:
                missing += 1
                continue
            row = _table_row(table, group.smallest_index)
            remaining = budget.shrink_total - spent
            sig = group.signature
            if not shrink:
                result = _unshrunk(case, sig, row, "not shrunk (--no-shrink)")
            elif remaining <= 0.05:
                result = _unshrunk(case, sig, row, "not shrunk: the run's shrink budget was spent on earlier groups")
            elif sig.check == "timeout" and call_timeout > min(budget.shrink_per_group, remaining) / 2:
                # Every failing call lasts the full timeout: ddmin would not get anywhere within the budget.
                result = _unshrunk(case, sig, row, f"not shrunk: each call of a hang lasts the "
                                   f"{call_timeout:g} s timeout, too long for the shrink budget")
            else:
                result = shrink_case(case, sig.config, sig, budget_seconds=min(budget.shrink_per_group, remaining),
                                     timeout=timeout, qhull_options=qhull_options)
                spent += result.seconds
                if not result.reproduced:
                    result = _unshrunk(case, sig, row, result.note)
            if not result.reproduced:
                not_shrunk += 1
            # Re-running a hang to verify it would cost a full timeout per group.
            records.append(triage_one(result, sig.config, group=group, timeout=timeout, verify=sig.check != "timeout",
                                      qhull_options=qhull_options))
        except KeyboardInterrupt:
            # An interrupt (the pipeline's signal handler) ends triage; the groups done so far stay.
            stopped = True
            break
    notes: list[str] = []
    if shrink:
        notes.append(f"Shrinking: ddmin over points, then coordinate simplification; budget "
                     f"{budget.shrink_total:g} s in total and {budget.shrink_per_group:g} s per group, "
                     f"{spent:.1f} s used; {len(records) - not_shrunk} of {len(records)} groups shrunk.")
    else:
        notes.append("Shrinking was turned off (--no-shrink): each group shows its smallest failing case.")
    untriaged = len(groups) - len(records) - missing
    if untriaged > 0:
        why = ("triage was interrupted" if stopped
               else f"the triage time budget ({budget.total:g} s) was spent" if out_of_time
               else f"of the cap of {max_records} folders")
        notes.append(f"{untriaged} more failure groups have no folder because {why}; "
                     "they are listed in the tables here and in summary.md.")
    if missing:
        notes.append(f"{missing} groups had no case object to shrink (their cases were not passed in).")
    unverified = [r for r in records if r.verified is False]
    if unverified:
        notes.append(f"{len(unverified)} groups did not fail again when re-run from the saved points file "
                     "(flaky or state-dependent); their commands may exit 0.")
    return TriageResult(groups=groups, records=records, notes=notes, seconds=time.perf_counter() - start,
                        stopped=stopped)
