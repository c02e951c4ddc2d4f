"""The report stage: a run's records become its files; nothing here runs code under test.

:func:`write_run_report` reads the results table, the run's metadata and
the triage stage's records (:class:`hullstress.triage.records.TriageResult`)
and writes the run folder: ``results.csv`` / ``.parquet``, ``summary.md``,
``run.json``, ``failures/<signature>/`` with pictures, ``failures/index.json``,
``findings.md`` and ``findings.csv`` (:mod:`hullstress.report.findings`, the same
files ``python -m hullstress findings`` writes), ``report.html``, the baseline
comparison and JUnit XML.
Pictures are bounded by the profile's picture budget; groups past it get a
folder without one, and the report says how many.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from ..files import atomic_write_text
from ..triage.grouping import FailureGroup, groups_frame
from ..triage.records import TriageResult
from .failures import FailureRecord, draw_picture, write_failure_folder
from .findings import Findings, compute_findings, findings_markdown, run_source, write_findings
from .html import render_html
from .junit import write_junit
from .writer import _markdown, write_report

__all__ = ["ReportFiles", "write_run_report"]


@dataclass(frozen=True)
class ReportFiles:
    """What the report stage wrote.

    Attributes
    ----------
    records : list of FailureRecord
        One per failure folder, worst group first.
    notes : list of str
        Triage's and the report's notes (budgets, groups without folders or pictures).
    findings : Findings
        The claims checked against the run (:func:`hullstress.report.findings.compute_findings`).
    html, summary, findings_md, findings_csv, index : Path
    junit : Path or None
    seconds : float
    """

    records: list[FailureRecord]
    notes: list[str]
    findings: Findings
    html: Path
    summary: Path
    findings_md: Path
    findings_csv: Path
    index: Path
    junit: Path | None
    seconds: float


def write_run_report(
    run_dir: str | Path,
    table: pd.DataFrame,
    meta: Mapping[str, Any],
    triage: TriageResult,
    *,
    picture_budget: float,
    plugins: Sequence[str] = (),
    timeout: float | None = None,
    junit_path: str | Path | None = None,
    pictures: bool = True,
    comparison: pd.DataFrame | None = None,
    baseline_label: str | None = None,
    should_stop: Callable[[], bool] | None = None,
) -> ReportFiles:
    """Write every file of the run folder from the run's records.

    Parameters
    ----------
    run_dir : path
        The run folder.
    table : DataFrame
        The results table.
    meta : mapping
        ``run.json``'s content (run id, profile, seed, timings, completeness).
    triage : TriageResult
        The triage stage's groups and records.
    picture_budget : float
        Seconds for drawing pictures.
    plugins : sequence of str
        The run's ``--plugin`` specs (go into reproduce commands of plug-in algorithms).
    timeout : float, optional
        The sweep's per-call timeout (for reproduce commands of timeouts).
    junit_path : path, optional
        Also write JUnit XML there.
    pictures : bool
        Draw pictures (tests may turn them off for speed).
    comparison : DataFrame, optional
        From :func:`hullstress.corpus.baseline.compare_with_baseline`: adds
        ``baseline.csv`` and a section of ``summary.md``.
    baseline_label : str, optional
        What the comparison was made against (for the summary).
    should_stop : callable, optional
        Polled before each picture: when it returns True (an interrupt) the
        remaining groups get no picture and the report is finished at once.

    Returns
    -------
    ReportFiles
    """
    start = time.perf_counter()
    run_dir = Path(run_dir)
    write_report(run_dir, table, meta)
    groups, notes = triage.groups, list(triage.notes)
    records: list[FailureRecord] = []
    picture_seconds = 0.0
    no_picture = 0
    picture_failures: list[str] = []
    for triaged in triage.records:
        sig = triaged.signature
        record = write_failure_folder(
            run_dir / "failures", triaged, plugins=list(plugins) if _origin(sig.algorithm) == "plugin" else [],
            timeout=timeout, picture=False,
        )
        stop = should_stop is not None and should_stop()
        if pictures and picture_seconds < picture_budget and not stop:
            t0 = time.perf_counter()
            try:
                record = draw_picture(record)
            except Exception as exc:  # a picture is a nicety: never lose the report for it
                picture_failures.append(f"{sig.slug}: {type(exc).__name__}: {exc}")
            picture_seconds += time.perf_counter() - t0
        else:
            no_picture += 1
        records.append(record)
    if picture_failures:
        notes.append(f"{len(picture_failures)} pictures could not be drawn (first: {picture_failures[0]}).")
    if pictures and no_picture:
        notes.append(f"{no_picture} groups have no picture: the picture budget ({picture_budget:g} s) was spent"
                     " or the run was interrupted.")

    findings = compute_findings(table, source=run_source(meta))
    findings_md, findings_csv = write_findings(run_dir, findings)
    index = _write_index(run_dir, records, groups)
    summary = _append_summary(run_dir, groups, records, findings, notes)
    if comparison is not None:
        _write_baseline_section(run_dir, comparison, baseline_label or "")
    html_path = run_dir / "report.html"
    atomic_write_text(html_path, render_html(table, meta, records, findings, notes=notes, groups=groups))
    junit = write_junit(junit_path, table, records) if junit_path is not None else None
    return ReportFiles(records=records, notes=notes, findings=findings, html=html_path, summary=summary,
                       findings_md=findings_md, findings_csv=findings_csv, index=index, junit=junit, seconds=time.perf_counter() - start)


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
                    findings: Findings, notes: list[str]) -> Path:
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
    parts += ["", findings_markdown(findings, level=2)]
    atomic_write_text(path, "\n".join(parts).rstrip("\n") + "\n")
    return path


def _write_baseline_section(run_dir: Path, comparison: pd.DataFrame, baseline: str) -> None:
    """``baseline.csv`` and a section of ``summary.md``: new, still-failing and fixed groups."""
    atomic_write_text(run_dir / "baseline.csv", comparison.to_csv(index=False))
    summary = run_dir / "summary.md"
    parts = [summary.read_text(encoding="utf-8").rstrip("\n"), "", f"## Against the baseline `{baseline}`", ""]
    for state in ("new", "still-failing", "fixed"):
        part = comparison[comparison["state"] == state].drop(columns="state")
        parts += [f"### {state} ({len(part)})", "", _markdown(part).rstrip("\n"), ""]
    atomic_write_text(summary, "\n".join(parts))
