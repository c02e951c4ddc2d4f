"""The report stage: a run's records become its files; nothing here runs code under test.

:func:`write_run_report` reads the results table, the run's metadata and
the triage stage's records (:class:`hullstress.triage.records.TriageResult`)
and writes the run folder: ``results.csv`` / ``.parquet``, ``run.json``,
``failures/<cause>/`` (one folder per cause) with ``failures/index.json``,
``causes.csv``, ``groups.csv``, ``findings.md`` and ``findings.csv``
(:mod:`hullstress.report.findings`, the same files ``python -m hullstress
findings`` writes), ``summary.md`` (one screen), ``report.html``, the baseline
comparison and JUnit XML.

Pictures are drawn for the top causes only (the profile's picture count), so
which folders have one does not depend on the machine's speed; an interrupt
skips the remaining pictures and the notes say so.
"""

from __future__ import annotations

import json
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from collections.abc import Callable, Mapping, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ContextManager

import pandas as pd

from ..files import atomic_write_text
from ..triage.records import TriageResult
from .failures import FailureRecord, draw_picture, write_cause_folder
from .findings import Findings, compute_findings, run_source, write_findings
from .hints import clockwise_hints
from .html import render_html
from .junit import write_junit
from .tables import metamorphic_changes
from .summary import TABLES, causes_frame, groups_table, summary_markdown, write_summary
from .claim import markdown_table as _markdown
from .writer import write_report
from ..records import Origin

__all__ = ["ReportFiles", "write_run_report"]

#: ``progress(done, total, detail)`` while folders are written.
Progress = Callable[[int, int, str], None]


@dataclass(frozen=True)
class ReportFiles:
    """What the report stage wrote.

    Attributes
    ----------
    records : list of FailureRecord
        One per cause folder, worst cause first.
    notes : list of str
        Triage's and the report's notes (budgets, groups without folders or pictures).
    findings : Findings
        The claims checked against the run (:func:`hullstress.report.findings.compute_findings`).
    html, summary, findings_md, findings_csv, index : Path
    junit : Path or None
    seconds : float
    hints : list of str
        Remedies the table suggests (:mod:`hullstress.report.hints`), also in the notes.
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
    hints: list[str] = field(default_factory=list)


def write_run_report(
    run_dir: str | Path,
    table: pd.DataFrame,
    meta: Mapping[str, Any],
    triage: TriageResult,
    *,
    pictures: int,
    plugins: Sequence[str] = (),
    timeout: float | None = None,
    junit_path: str | Path | None = None,
    comparison: pd.DataFrame | None = None,
    baseline_label: str | None = None,
    should_stop: Callable[[], bool] | None = None,
    progress: Progress | None = None,
    registration: Sequence[str] = (),
    tables_written: bool = False,
    interruptible: Callable[[], ContextManager[Any]] | None = None,
    workers: int = 1,
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
        The triage stage's groups, records and causes.
    pictures : int
        Draw pictures for this many causes, worst first (0: none).
    plugins : sequence of str
        The run's ``--plugin`` specs (recorded for ``reproduce`` of plug-in algorithms).
    timeout : float, optional
        The sweep's per-call timeout (``reproduce`` uses it).
    junit_path : path, optional
        Also write JUnit XML there.
    comparison : DataFrame, optional
        From :func:`hullstress.corpus.baseline.compare_with_baseline`: adds
        ``baseline.csv`` and a section of ``summary.md``.
    baseline_label : str, optional
        What the comparison was made against (for the summary).
    should_stop : callable, optional
        Polled before each picture: when it returns True (an interrupt) the
        remaining causes get no picture and the report is finished at once.
    progress : callable, optional
        ``progress(done, total, detail)`` as folders are written.
    registration : sequence of str
        The run's ``--exec`` / ``--clockwise`` (and ``--plugin``) arguments,
        recorded for ``reproduce`` of the algorithms that need them.
    tables_written : bool
        ``results.csv`` / ``.parquet`` of this very table are on disk already
        (the pipeline writes them right after the sweep): do not write them again.
    interruptible : callable, optional
        A context (the pipeline's) in which an interrupt raises at once:
        each picture is drawn inside it, so a signal cuts the picture under
        way short (it is skipped) instead of waiting for it.
    workers : int
        Processes the run may keep busy (its ``--workers``): with two or
        more, the findings are computed in another process while this one
        writes the folders and draws the pictures (the same findings: they
        are a function of the table alone).

    Returns
    -------
    ReportFiles
    """
    start = time.perf_counter()
    run_dir = Path(run_dir)
    findings_of_the_table = _findings_beside(table, run_source(meta), workers)
    write_report(run_dir, table, meta, tables=not tables_written)
    notes = list(triage.notes)
    records: list[FailureRecord] = []
    picture_failures: list[str] = []
    skipped_pictures = 0
    causes = list(triage.causes)
    for n, cause in enumerate(causes):
        algorithms = {r.signature.algorithm for r in cause.records}
        needs = any(_needs_registration(a) for a in algorithms)
        record = write_cause_folder(
            run_dir / "failures", cause, timeout=timeout, picture=False,
            plugins=list(plugins) if needs else [], registration=registration if needs else (),
        )
        if n < pictures:
            if should_stop is not None and should_stop():
                skipped_pictures += 1
            else:
                try:
                    with interruptible() if interruptible is not None else nullcontext():
                        record = draw_picture(record)
                except KeyboardInterrupt:  # an interrupt cut this picture short; the rest follow without
                    skipped_pictures += 1
                except Exception as exc:  # a picture is a nicety: never lose the report for it
                    picture_failures.append(f"{cause.slug}: {type(exc).__name__}: {exc}")
        records.append(record)
        if progress is not None:
            progress(n + 1, len(causes), "")
    if picture_failures:
        notes.append(f"{len(picture_failures)} pictures could not be drawn (first: {picture_failures[0]}).")
    if skipped_pictures:
        notes.append(f"{skipped_pictures} of the top causes have no picture: the run was interrupted.")
    if len(causes) > pictures:
        notes.append(f"Pictures are drawn for the top {pictures} causes (the profile's picture count).")

    hints = clockwise_hints(table)
    notes += [f"Hint: {hint}." for hint in hints]
    unreached = meta.get("not_reached") or {}
    if unreached:
        notes.append("Not reached (the run ended early): " + ", ".join(
            f"{family} {count} calls" for family, count in sorted(unreached.items())) + ".")
    if len(table) and (table["transform"].fillna("").astype(str) != "").any():
        changes = metamorphic_changes(table)
        atomic_write_text(run_dir / "metamorphic.csv", changes.to_csv(index=False))
        copies = int((table["transform"].fillna("").astype(str) != "").sum())
        notes.append(f"Metamorphic copies: {len(changes)} of {copies} calls on a transformed copy gave another "
                     "verdict than on the original (metamorphic.csv).")
    folders = {r.cause.slug: r.folder.relative_to(run_dir).as_posix() for r in records}
    findings = findings_of_the_table()
    findings_md, findings_csv = write_findings(run_dir, findings)
    # summary.md fits on a screen: one sentence per claim; findings.md has the rest.
    reading = [f"{claim.title}: {claim.reading[0]}" for claim in findings.claims if claim.reading]
    atomic_write_text(run_dir / TABLES["causes"], causes_frame(causes, folders).to_csv(index=False))
    atomic_write_text(run_dir / TABLES["groups"], groups_table(triage.groups, causes).to_csv(index=False))
    index = _write_index(run_dir, records, len(triage.groups))
    summary = write_summary(run_dir, summary_markdown(
        table, meta, causes=causes, groups=triage.groups, folders=folders, reading=reading, notes=notes))
    if comparison is not None:
        _write_baseline_section(run_dir, comparison, baseline_label or "")
    html_path = run_dir / "report.html"
    atomic_write_text(html_path, render_html(table, meta, records, findings, notes=notes, groups=triage.groups))
    junit = write_junit(junit_path, table, records) if junit_path is not None else None
    return ReportFiles(records=records, notes=notes, findings=findings, html=html_path, summary=summary,
                       findings_md=findings_md, findings_csv=findings_csv, index=index, junit=junit,
                       seconds=time.perf_counter() - start, hints=hints)


def _findings_beside(table: pd.DataFrame, source: str, workers: int) -> Callable[[], Findings]:
    """Start :func:`compute_findings` of ``table``; call the result for the findings.

    With ``workers >= 2`` they are computed in a process of their own (forked
    from the run's fork server, so it starts with pandas loaded) while the
    caller writes the cause folders and pictures; otherwise, or if that
    process cannot start or dies, here, when asked for.  Either way the
    same function of the same table: the same findings.
    """
    def here() -> Findings:
        return compute_findings(table, source=source)

    if workers < 2 or "forkserver" not in multiprocessing.get_all_start_methods():
        return here
    try:
        # The fork server, not fork: the run's own process may hold threads (a progress bar).
        executor = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("forkserver"))
        future = executor.submit(compute_findings, table, source=source)
    except (OSError, RuntimeError):
        return here

    def collected() -> Findings:
        try:
            return future.result()
        except (BrokenProcessPool, OSError):  # the helper died (an interrupt reached it): compute them here
            return here()
        finally:
            executor.shutdown(wait=False, cancel_futures=True)

    return collected


def _needs_registration(algorithm: str) -> bool:
    """Whether ``reproduce`` must register again what the run registered for ``algorithm``."""
    from .._registry import ALGORITHMS

    try:
        spec = ALGORITHMS.get(algorithm)
    except Exception:  # unknown here: keep the registration, to be safe
        return True
    return spec.origin in (Origin.PLUGIN, Origin.EXECUTABLE) or spec.clockwise


def _write_index(run_dir: Path, records: Sequence[FailureRecord], n_groups: int) -> Path:
    """``failures/index.json``: every cause folder, worst first (no timings: identical runs write the same)."""
    folder = run_dir / "failures"
    folder.mkdir(exist_ok=True)
    entries = [{"slug": r.cause.slug, "cause": r.cause.headline, **r.signature.as_dict(),
                "failures": r.cause.failures, "groups": [m.signature.slug for m in r.cause.records],
                "configs": list(r.cause.configs), "families": dict(r.cause.families),
                "original_size": r.original_size, "minimal_size": r.minimal_size, "minimised": r.shrunk,
                "verified": r.verified, "picture": r.picture is not None} for r in records]
    path = folder / "index.json"
    atomic_write_text(path, json.dumps({"groups": n_groups, "causes": len(records), "folders": entries},
                                       indent=2) + "\n")
    return path


def _write_baseline_section(run_dir: Path, comparison: pd.DataFrame, baseline: str) -> None:
    """``baseline.csv`` and a short section of ``summary.md``: counts, and the first new groups."""
    atomic_write_text(run_dir / "baseline.csv", comparison.to_csv(index=False))
    summary = run_dir / "summary.md"
    counts = comparison["state"].value_counts()
    parts = [summary.read_text(encoding="utf-8").rstrip("\n"), "", f"## Against the baseline `{baseline}`", "",
             ", ".join(f"{int(counts.get(s, 0))} {s}" for s in ("new", "still-failing", "fixed"))
             + " failure groups; every one in [baseline.csv](baseline.csv).", ""]
    new = comparison[comparison["state"] == "new"].drop(columns="state")
    if len(new):
        parts += ["New:", "", _markdown(new.head(10)).rstrip("\n")]
        if len(new) > 10:
            parts += ["", f"... and {len(new) - 10} more new groups."]
    atomic_write_text(summary, "\n".join(parts).rstrip("\n") + "\n")
