"""After the sweep: triage, shrinking, failure folders, findings, report.html, JUnit.

``python -m hullstress run`` calls :func:`finalize_run` right after
:func:`hullstress.report.writer.write_report`.  Its time is bounded
(:class:`TriageBudget`; quick / nightly): shrinking 10 s / 300 s in total and
2 s / 30 s per group, pictures 8 s / 120 s, failure folders 25 s / 900 s.  Groups
are handled worst first; past a budget a group keeps its smallest failing
case unshrunk, then gets no picture, then no folder (it stays in the tables).
The report says how many of each.
"""

from __future__ import annotations

import json
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from ..case import Case
from ..results import ResultRow
from ..triage.grouping import FailureGroup, group_failures, groups_frame
from ..triage.oracle import DEFAULT_TIMEOUT
from ..triage.shrink import ShrinkResult, shrink as shrink_case
from .failures import FailureRecord, draw_picture, write_failure_folder
from .findings import findings_markdown, findings_reading, findings_table
from .html import render_html
from .junit import write_junit
from ..files import atomic_write_text

__all__ = ["finalize_run", "TriageBudget", "triage_budget", "shrink_budgets", "MAX_FOLDERS"]

#: At most this many failure folders (worst groups first); the rest are counted in the report.
MAX_FOLDERS = 2000


@dataclass(frozen=True)
class TriageBudget:
    """Time limits of :func:`finalize_run`, in seconds.

    Attributes
    ----------
    shrink_total, shrink_per_group : float
        Shrinking, over all groups and per group.
    pictures : float
        Drawing pictures (groups past it get a folder without a picture).
    total : float
        Everything; groups past it get no folder (they stay in the tables).
    """

    shrink_total: float
    shrink_per_group: float
    pictures: float
    total: float


_BUDGETS = {
    # quick must leave the whole run under a minute on 2 cores (the sweep takes ~20 s)
    "quick": TriageBudget(shrink_total=10.0, shrink_per_group=2.0, pictures=8.0, total=25.0),
    "nightly": TriageBudget(shrink_total=300.0, shrink_per_group=30.0, pictures=120.0, total=900.0),
}


def triage_budget(profile: str | None) -> TriageBudget:
    """The time limits for a profile (quick's for unknown ones)."""
    return _BUDGETS.get(str(profile), _BUDGETS["quick"])


def shrink_budgets(profile: str | None) -> tuple[float, float]:
    """(total seconds, seconds per group) of shrinking for a profile."""
    b = triage_budget(profile)
    return b.shrink_total, b.shrink_per_group


def _unshrunk(case: Case, group: FailureGroup, row: ResultRow | None, note: str) -> ShrinkResult:
    """The group's smallest case as its own "minimal" case, with why it was not shrunk."""
    return ShrinkResult(case=case, original=case, signature=group.signature, original_size=case.n_points,
                        minimal_size=case.n_points, calls=0, seconds=0.0, reproduced=False, row=row, note=note)


def _table_row(table: pd.DataFrame, index: int) -> ResultRow:
    return ResultRow({k: (None if (not isinstance(v, (list, dict)) and pd.isna(v)) else v)
                      for k, v in table.loc[index].items()})


def finalize_run(
    run_dir: str | Path,
    table: pd.DataFrame,
    cases: Sequence[Case],
    meta: Mapping[str, Any],
    *,
    shrink: bool = True,
    shrink_budget_seconds: float | None = None,
    group_budget_seconds: float | None = None,
    budget: TriageBudget | None = None,
    timeout: float | None = None,
    junit_path: str | Path | None = None,
    plugins: Sequence[str] = (),
    pictures: bool = True,
    max_folders: int = MAX_FOLDERS,
) -> dict[str, Any]:
    """Triage the run's failures and write the human- and CI-facing reports.

    Parameters
    ----------
    run_dir : path
        The run folder (``results.csv``, ``summary.md`` and ``run.json`` already written).
    table : DataFrame
        The results table.
    cases : sequence of Case
        The cases whose ids appear in ``table`` (``SweepResult.cases``).
    meta : mapping
        ``run.json``'s content (``run_id``, ``profile``, ``seed``, timings...).
    shrink : bool
        Shrink each group's smallest failing case (``--no-shrink`` turns it off).
    shrink_budget_seconds, group_budget_seconds : float, optional
        Total and per-group shrink time (override ``budget``).
    budget : TriageBudget, optional
        All time limits (default: :func:`triage_budget` of the profile).
    timeout : float, optional
        The sweep's per-call timeout, reused for shrinking calls.
    junit_path : path, optional
        Write JUnit XML there (``--junit FILE``).
    plugins : sequence of str
        The run's ``--plugin`` specs (go into reproduce commands of plug-in algorithms).
    pictures : bool
        Draw pictures (always on from the CLI; tests may turn them off for speed).
    max_folders : int
        Cap on failure folders.

    Returns
    -------
    dict
        ``groups`` (list of FailureGroup), ``records`` (list of FailureRecord),
        ``notes`` (list of str), ``findings`` (DataFrame), paths ``html``,
        ``summary``, ``findings_csv``, ``index`` and ``junit`` (or None), ``seconds``.
    """
    start = time.perf_counter()
    run_dir = Path(run_dir)
    limits = budget or triage_budget(meta.get("profile"))
    total_budget = limits.shrink_total if shrink_budget_seconds is None else shrink_budget_seconds
    per_group = limits.shrink_per_group if group_budget_seconds is None else group_budget_seconds
    groups = group_failures(table)
    by_id = {c.case_id: c for c in cases}
    records: list[FailureRecord] = []
    notes: list[str] = []
    spent = picture_seconds = 0.0
    not_shrunk = missing = no_picture = 0
    picture_failures: list[str] = []
    out_of_time = False
    for group in groups[:max_folders]:
        if time.perf_counter() - start > limits.total:
            out_of_time = True
            break
        case = by_id.get(group.smallest_case_id)
        if case is None:
            missing += 1
            continue
        row = _table_row(table, group.smallest_index)
        remaining = total_budget - spent
        if not shrink:
            result = _unshrunk(case, group, row, "not shrunk (--no-shrink)")
        elif remaining <= 0.05:
            result = _unshrunk(case, group, row, "not shrunk: the run's shrink budget was spent on earlier groups")
        elif group.signature.check == "timeout" and (timeout or DEFAULT_TIMEOUT) > min(per_group, remaining) / 2:
            # Every failing call lasts the full timeout: ddmin would not get anywhere within the budget.
            result = _unshrunk(case, group, row, f"not shrunk: each call of a hang lasts the "
                               f"{timeout or DEFAULT_TIMEOUT:g} s timeout, too long for the shrink budget")
        else:
            result = shrink_case(case, group.signature.config, group.signature,
                                 budget_seconds=min(per_group, remaining), timeout=timeout)
            spent += result.seconds
            if not result.reproduced:
                result = _unshrunk(case, group, row, result.note)
        if not result.reproduced:
            not_shrunk += 1
        origin = _origin(group.signature.algorithm)
        record = write_failure_folder(
            run_dir / "failures", result, group.signature.config, group=group,
            plugins=list(plugins) if origin == "plugin" else [], timeout=timeout, picture=False,
            # Re-running a hang to verify it would cost a full timeout per group.
            verify=group.signature.check != "timeout",
        )
        if pictures and picture_seconds < limits.pictures:
            t0 = time.perf_counter()
            try:
                record = draw_picture(record)
            except Exception as exc:  # a picture is a nicety: never lose the report for it
                picture_failures.append(f"{group.signature.slug}: {type(exc).__name__}: {exc}")
            picture_seconds += time.perf_counter() - t0
        else:
            no_picture += 1
        records.append(record)
    if picture_failures:
        notes.append(f"{len(picture_failures)} pictures could not be drawn (first: {picture_failures[0]}).")
    if shrink:
        notes.append(f"Shrinking: ddmin over points, then coordinate simplification; budget {total_budget:g} s "
                     f"in total and {per_group:g} s per group, {spent:.1f} s used; "
                     f"{len(records) - not_shrunk} of {len(records)} groups shrunk.")
    else:
        notes.append("Shrinking was turned off (--no-shrink): each group shows its smallest failing case.")
    if pictures and no_picture:
        notes.append(f"{no_picture} groups have no picture: the picture budget ({limits.pictures:g} s) was spent.")
    unfoldered = len(groups) - len(records) - missing
    if unfoldered > 0:
        why = (f"the triage time budget ({limits.total:g} s) was spent" if out_of_time
               else f"of the cap of {max_folders} folders")
        notes.append(f"{unfoldered} more failure groups have no folder because {why}; "
                     "they are listed in the tables here and in summary.md.")
    if missing:
        notes.append(f"{missing} groups had no case object to shrink (their cases were not passed in).")
    unverified = [r for r in records if r.verified is False]
    if unverified:
        notes.append(f"{len(unverified)} groups did not fail again when re-run from the saved points file "
                     "(flaky or state-dependent); their commands may exit 0.")

    findings = findings_table(table)
    reading = findings_reading(findings)
    findings_csv = run_dir / "findings.csv"
    findings.to_csv(findings_csv, index=False)
    index = _write_index(run_dir, records, groups)
    summary = _append_summary(run_dir, groups, records, findings, reading, notes)
    html_path = run_dir / "report.html"
    atomic_write_text(html_path, render_html(table, meta, records, findings, notes=notes, groups=groups))
    junit = write_junit(junit_path, table, records) if junit_path is not None else None
    return {"groups": groups, "records": records, "notes": notes, "findings": findings,
            "html": html_path, "summary": summary, "findings_csv": findings_csv, "index": index,
            "junit": junit, "seconds": time.perf_counter() - start}


def _origin(algorithm: str) -> str:
    from .._registry import ALGORITHMS

    try:
        return ALGORITHMS.get(algorithm).origin
    except Exception:  # unknown here: keep the plug-ins in the command, to be safe
        return "plugin"


def _write_index(run_dir: Path, records: Sequence[FailureRecord], groups: Sequence[FailureGroup]) -> Path:
    folder = run_dir / "failures"
    folder.mkdir(exist_ok=True)
    entries = [{"slug": r.signature.slug, **r.signature.as_dict(),
                "failures": r.group.count if r.group else None, "calls": r.group.calls if r.group else None,
                "original_size": r.original_size, "minimal_size": r.minimal_size, "shrunk": r.shrunk,
                "verified": r.verified, "reproduce": r.command} for r in records]
    path = folder / "index.json"
    atomic_write_text(path, json.dumps({"groups": len(groups), "folders": entries}, indent=2) + "\n")
    return path


def _append_summary(run_dir: Path, groups: Sequence[FailureGroup], records: Sequence[FailureRecord],
                    findings: pd.DataFrame, reading: list[str], notes: list[str]) -> Path:
    from .writer import _markdown

    path = run_dir / "summary.md"
    text = path.read_text(encoding="utf-8") if path.exists() else "# hullstress run\n"
    sizes = {r.signature.slug: r for r in records}
    frame = groups_frame(list(groups))
    if len(frame):
        frame["minimal_n_points"] = [sizes[s].minimal_size if s in sizes else pd.NA for s in frame["slug"]]
        frame = frame[["algorithm", "sphere", "eps", "check", "family", "failures", "calls", "rate",
                       "smallest_n_points", "minimal_n_points", "slug"]]
    parts = [text.rstrip("\n"), "", f"## Failure groups ({len(groups)})", ""]
    parts += [f"{line}" for line in notes] + [""]
    parts.append(_markdown(frame).rstrip("\n"))
    if records:
        parts += ["", "### Reproduce", ""]
        for r in records:
            parts.append(f"- `{r.signature.slug}` ({r.original_size} -> {r.minimal_size} points): `{r.command}`")
    parts += ["", "## Findings: the seeds' claims against this run", "", findings_markdown(findings, reading)]
    atomic_write_text(path, "\n".join(parts).rstrip("\n") + "\n")
    return path
