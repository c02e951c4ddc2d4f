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

import dataclasses
import json
import multiprocessing
import time
from collections.abc import Callable, Mapping, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ContextManager

import pandas as pd

from ..files import atomic_write_text
from ..forkserver import helper_start
from ..triage.records import Cause, TriageResult
from .failures import FailureRecord, draw_picture, with_picture, write_cause_folder
from .picture_helper import PictureDrawer
from .findings import Findings, compute_findings, run_source, write_findings
from .hints import clockwise_hints
from .html import render_html
from .junit import write_junit
from .tables import metamorphic_changes
from .summary import TABLES, causes_frame, groups_table, summary_markdown, write_summary
from .claim import markdown_table as _markdown
from .writer import write_report
from ..records import Origin

__all__ = ["ReportFiles", "write_run_report", "FindingsBeside"]

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
    drawer: PictureDrawer | None = None,
    findings_beside: FindingsBeside | None = None,
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
        writes the folders, and the pictures in a third (the same findings
        and pictures: functions of the table and the folders alone).
    drawer : PictureDrawer, optional
        Where the pictures are drawn: the run's, made when it began
        (:func:`~.writer.prepare_report`) and begun during the sweep, so
        that matplotlib is loaded by now.  By default one is started here
        for ``workers``.  Either way it is closed before this returns.
    findings_beside : FindingsBeside, optional
        The findings of ``table``, started by the pipeline as soon as the
        table was final; by default started here for ``workers``.

    Returns
    -------
    ReportFiles
    """
    start = time.perf_counter()
    run_dir = Path(run_dir)
    notes = list(triage.notes)
    causes = list(triage.causes)
    if findings_beside is None:
        findings_beside = FindingsBeside(table, workers)
    if drawer is None:
        drawer = PictureDrawer.start(pictures=pictures > 0, workers=workers)
    with findings_beside, drawer:
        write_report(run_dir, table, meta, tables=not tables_written)
        records, done = _write_folders(run_dir, causes, drawer, pictures=pictures, timeout=timeout, plugins=plugins,
                                       registration=registration, should_stop=should_stop, progress=progress)
        # What does not depend on the pictures, while a helper draws them.
        hints = clockwise_hints(table)
        later = [f"Hint: {hint}." for hint in hints]
        unreached = meta.get("not_reached") or {}
        if unreached:
            later.append("Not reached (the run ended early): " + ", ".join(
                f"{family} {count} calls" for family, count in sorted(unreached.items())) + ".")
        transformed = table["transform"].fillna("").astype(str) != "" if len(table) else None
        if transformed is not None and transformed.any():
            changes = metamorphic_changes(table)
            atomic_write_text(run_dir / "metamorphic.csv", changes.to_csv(index=False))
            copies = int(transformed.sum())
            later.append(f"Metamorphic copies: {len(changes)} of {copies} calls on a transformed copy gave "
                         "another verdict than on the original (metamorphic.csv).")
        folders = {r.cause.slug: r.folder.relative_to(run_dir).as_posix() for r in records}
        findings = findings_beside.result(run_source(meta))
        findings_md, findings_csv = write_findings(run_dir, findings)
        atomic_write_text(run_dir / TABLES["causes"], causes_frame(causes, folders).to_csv(index=False))
        atomic_write_text(run_dir / TABLES["groups"], groups_table(triage.groups, causes).to_csv(index=False))
        picture_failures, skipped_pictures = _collect_pictures(
            records, causes, drawer, pictures=pictures, done=done, should_stop=should_stop, progress=progress,
            interruptible=interruptible)
    if picture_failures:
        notes.append(f"{len(picture_failures)} pictures could not be drawn (first: {picture_failures[0]}).")
    if skipped_pictures:
        notes.append(f"{skipped_pictures} of the top causes have no picture: the run was interrupted.")
    if len(causes) > pictures:
        notes.append(f"Pictures are drawn for the top {pictures} causes (the profile's picture count).")
    notes += later
    # summary.md fits on a screen: one sentence per claim; findings.md has the rest.
    reading = [f"{claim.title}: {claim.reading[0]}" for claim in findings.claims if claim.reading]
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


def _write_folders(
    run_dir: Path, causes: list[Cause], drawer: PictureDrawer, *, pictures: int, timeout: float | None,
    plugins: Sequence[str], registration: Sequence[str], should_stop: Callable[[], bool] | None,
    progress: Progress | None,
) -> tuple[list[FailureRecord], int]:
    """Write every cause's folder, and ask ``drawer`` for the pictures of the first ``pictures``.

    The pictured causes come first in ``causes``: their pictures are drawn
    (by the drawer's helper, when it has one) while the other folders and
    the report's tables are written.  A folder counts as done for
    ``progress`` once it has its picture; returns the records and the
    folders done so far.
    """
    records: list[FailureRecord] = []
    done = 0
    for n, cause in enumerate(causes):
        algorithms = {r.signature.algorithm for r in cause.records}
        needs = any(_needs_registration(a) for a in algorithms)
        record = write_cause_folder(
            run_dir / "failures", cause, timeout=timeout, picture=False,
            plugins=list(plugins) if needs else [], registration=registration if needs else (),
        )
        records.append(record)
        if n < pictures:
            if should_stop is None or not should_stop():
                drawer.request(record)
        elif progress is not None:
            done += 1
            progress(done, len(causes), "")
    return records, done


def _collect_pictures(
    records: list[FailureRecord], causes: list[Cause], drawer: PictureDrawer, *, pictures: int, done: int,
    should_stop: Callable[[], bool] | None, progress: Progress | None,
    interruptible: Callable[[], ContextManager[Any]] | None,
) -> tuple[list[str], int]:
    """Put the first ``pictures`` records' pictures in their folders (and ``records``): the helper's, or drawn here.

    Returns the pictures that could not be drawn (``slug: error``) and how
    many an interrupt skipped.
    """
    picture_failures: list[str] = []
    skipped = 0
    for n in range(min(pictures, len(records))):
        if should_stop is not None and should_stop():
            skipped += 1
        else:
            try:
                with interruptible() if interruptible is not None else nullcontext():
                    png = drawer.drawn(records[n])
                    records[n] = with_picture(records[n], png) if png is not None else draw_picture(records[n])
            except KeyboardInterrupt:  # an interrupt cut this picture short; the rest follow without
                skipped += 1
            except Exception as exc:  # a picture is a nicety: never lose the report for it
                picture_failures.append(f"{causes[n].slug}: {type(exc).__name__}: {exc}")
        if progress is not None:
            done += 1
            progress(done, len(causes), "")
    return picture_failures, skipped

#: The ``nice`` value of the process that computes the findings while triage runs.
_LOWEST_PRIORITY = 19


class FindingsBeside:
    """The findings of a results table (:func:`compute_findings`), computed beside the run.

    With ``workers >= 2`` they are computed in a process of their own,
    forked from the run's fork server (so it starts with pandas loaded) at
    the lowest priority, from the moment the table is final (the pipeline
    starts it when the sweep ends: it takes what triage leaves idle of the
    cores); otherwise, or if that process cannot start or dies, here, when
    asked for.  Either way the same function of the same table: the same
    findings.  The process sends them on a pipe and leaves; if the run is
    killed first, that send fails and it leaves all the same.

    Parameters
    ----------
    table : DataFrame
        The run's final results table.
    workers : int
        Processes the run may keep busy (its ``--workers``).
    """

    def __init__(self, table: pd.DataFrame, workers: int) -> None:
        self._table = table
        self._process: Any = None
        self._conn: Any = None
        if workers < 2 or "forkserver" not in multiprocessing.get_all_start_methods():
            return
        try:
            # The fork server, not fork: the run's own process may hold threads (a progress bar).
            context = multiprocessing.get_context("forkserver")
            self._conn, theirs = context.Pipe(duplex=False)
            self._process = context.Process(target=_findings_in_helper, args=(theirs, table), daemon=True,
                                            name="hullstress-findings")
            try:
                self._process.start()
            finally:
                theirs.close()  # this process's copy: the helper's death then reads as end of file here
        except (OSError, RuntimeError, ValueError):
            self.close()

    @property
    def helped(self) -> bool:
        """Whether a helper process computes the findings."""
        return self._process is not None

    def result(self, source: str) -> Findings:
        """The findings, headed ``source`` (:func:`run_source`: known only when the report is written)."""
        found: Findings | None = None
        if self._conn is not None:
            try:
                found = self._conn.recv()
            except (EOFError, OSError):  # the helper died, or was closed: here then
                found = None
            finally:
                self.close()
        if found is None:
            found = compute_findings(self._table)
        return dataclasses.replace(found, source=source)

    def close(self) -> None:
        """End the helper process (its work is dropped if it is not done)."""
        if self._process is not None:
            self._process.kill()
            self._process.join()
            self._process = None
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def __enter__(self) -> FindingsBeside:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _findings_in_helper(conn: Any, table: pd.DataFrame) -> None:
    """The findings helper: compute them, send them, leave (the send fails if the run is gone)."""
    helper_start(_LOWEST_PRIORITY)  # it runs while triage leaves a core idle, never before the run's process
    try:
        conn.send(compute_findings(table))
    except Exception:  # the run is gone, or the findings failed: the run computes them itself
        pass


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
    from ..corpus.baseline import STATES

    counts = comparison["state"].value_counts()
    parts = [summary.read_text(encoding="utf-8").rstrip("\n"), "", f"## Against the baseline `{baseline}`", "",
             ", ".join(f"{int(counts.get(s, 0))} {s}" for s in STATES)
             + " failure groups; every one in [baseline.csv](baseline.csv).", ""]
    new = comparison.loc[comparison["state"] == "new", ["label", "failures", "families"]]
    if len(new):
        parts += ["New:", "", _markdown(new.head(10)).rstrip("\n")]
        if len(new) > 10:
            parts += ["", f"... and {len(new) - 10} more new groups."]
    atomic_write_text(summary, "\n".join(parts).rstrip("\n") + "\n")
