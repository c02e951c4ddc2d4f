"""The flow of one run, in one place: generate -> execute -> check -> triage -> report.

=========  =====================================================  ==========================
stage      what it does                                           where
=========  =====================================================  ==========================
generate   families x variants x sizes x seeds (and points        :func:`hullstress.sweep.build_tasks`,
           files) become cases; cases x configs become tasks      ``generators/``
execute    each task runs in an isolated worker: preprocessing,   :func:`hullstress.sweep.run_sweep`,
           the algorithm call, the output contract                ``runner/``, ``evaluate.py``
check      in the same worker, the exact checker turns the        ``checker/``, ``evaluate.judge``
           output into a verdict row
triage     failing rows grouped by signature, one case per        :func:`hullstress.triage.triage_failures`
           group shrunk (in parallel, on a budget counted in
           evaluations), groups merged into causes
report     tables, summary, failure folders, HTML, JUnit;         :func:`hullstress.report.stage.write_run_report`
           reads records, runs nothing
=========  =====================================================  ==========================

:func:`run` chains them for ``python -m hullstress run``; other entry points
(``replay``, the pytest plug-in, ``fuzz``) call a single stage.  Each stage
consumes plain records and knows nothing of the stages after it.

Interruption is handled here, once: the first SIGINT or SIGTERM stops the
phase under way (the sweep's workers are killed, triage keeps the groups it
finished), every finished row is kept, the report is written from what
there is and marked incomplete and interrupted, and :attr:`Run.exit_status`
is 130 (SIGINT) or 143 (SIGTERM).  A second signal during the report aborts
it.
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from .case import Case
from .errors import UsageError
from .results import ResultRow, to_frame
from .runner import ExecutionStats, Task
from .sweep import SweepOptions, build_tasks, run_sweep, sort_table

__all__ = ["RunOptions", "Run", "Interrupted", "Plan", "plan", "run", "EXIT_FOR_SIGNAL"]

#: Exit status after an interrupt, by signal (the shell's 128 + signal number).
EXIT_FOR_SIGNAL = {signal.SIGINT: 130, signal.SIGTERM: 143}


class Interrupted(KeyboardInterrupt):
    """A SIGINT or SIGTERM arrived while a stage was running (it stops the stage)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


@dataclass(frozen=True)
class RunOptions:
    """Everything a run needs: what to sweep, and what to do with the results.

    Attributes
    ----------
    sweep : SweepOptions
        Which cases and configs (decides the results table).
    out : str
        Folder under which the run folder is created.
    shrink : bool
        Minimise each failure group's case (``--no-shrink`` turns it off).
    junit : str or None
        Also write JUnit XML there.
    baseline : str or None
        An earlier run or a corpus: the exit status counts only new failure groups.
    save_corpus : str or None
        Add the minimised new failures to this corpus folder.
    plugins : tuple of str
        The ``--plugin`` specs (reproduce commands of plug-in algorithms repeat them).
    arguments : mapping
        The command line's arguments, recorded in ``run.json``.
    pictures : bool
        Draw pictures of failures.
    """

    sweep: SweepOptions = field(default_factory=SweepOptions)
    out: str = "reports"
    shrink: bool = True
    junit: str | None = None
    baseline: str | None = None
    save_corpus: str | None = None
    plugins: tuple[str, ...] = ()
    arguments: Mapping[str, Any] = field(default_factory=dict)
    pictures: bool = True


@dataclass(frozen=True)
class Plan:
    """The generate stage's output: tasks (cases x configs) and what was not generated."""

    tasks: list[Task]
    cases: list[Case]
    skipped: list[str]

    @property
    def n_calls(self) -> int:
        return sum(len(t.configs) for t in self.tasks)


@dataclass
class Run:
    """What a run produced, stage by stage.

    Attributes
    ----------
    run_dir : Path
    plan : Plan
    table : DataFrame
        One row per finished call, sorted (case order, then config).
    stats : ExecutionStats or None
        The runner's accounting (None when the sweep was interrupted before it returned).
    meta : dict
        ``run.json``'s content.
    triage : TriageResult or None
    report : ReportFiles or None
    comparison : DataFrame or None
        Failure groups against the baseline (``state``: new, still-failing, fixed).
    corpus_saved : list of (Path, bool)
        Corpus entries written (True) or already there (False).
    signal : int or None
        The signal that interrupted the run.
    complete : bool
        Every planned call ran (not interrupted, time budget not exhausted).
    seconds : dict of str to float
        Wall time per phase.
    """

    run_dir: Path
    plan: Plan
    table: pd.DataFrame
    stats: ExecutionStats | None = None
    meta: dict[str, Any] = field(default_factory=dict)
    triage: Any = None
    report: Any = None
    comparison: pd.DataFrame | None = None
    corpus_saved: list[tuple[Path, bool]] = field(default_factory=list)
    signal: int | None = None
    complete: bool = True
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def interrupted(self) -> bool:
        return self.signal is not None

    @property
    def n_failed(self) -> int:
        from .triage.signature import FAILED_STATUSES

        return int(self.table["status"].isin(FAILED_STATUSES).sum()) if len(self.table) else 0

    @property
    def exit_status(self) -> int:
        """130/143 interrupted; with a baseline 1 only for new failure groups; else 1 for any failure."""
        if self.signal is not None:
            return EXIT_FOR_SIGNAL.get(self.signal, 130)
        if self.comparison is not None:
            return 1 if bool((self.comparison["state"] == "new").any()) else 0
        return 1 if self.n_failed else 0


class _Signals:
    """SIGINT/SIGTERM for the duration of a run: stop the running stage, remember the signal."""

    def __init__(self) -> None:
        self.signum: int | None = None
        self.raising = True  # during the report the first signal only asks it to hurry

    def handler(self, signum: int, frame: Any) -> None:
        first = self.signum is None
        if first:
            self.signum = signum
        if self.raising or not first:
            raise Interrupted(signum)

    def stop_requested(self) -> bool:
        return self.signum is not None

    @contextmanager
    def installed(self) -> Iterator["_Signals"]:
        if threading.current_thread() is not threading.main_thread():
            yield self  # signals reach the main thread only; a caller there handles them
            return
        previous = {s: signal.signal(s, self.handler) for s in EXIT_FOR_SIGNAL}
        try:
            yield self
        finally:
            for s, h in previous.items():
                signal.signal(s, h)


def plan(options: SweepOptions) -> Plan:
    """The generate stage: build every case and cross it with its dimension's configs.

    Raises
    ------
    UsageError
        When no case matches the selected algorithms' dimensions (nothing to run).
    """
    tasks, cases, _, skipped = build_tasks(options)
    if not tasks:
        raise UsageError("nothing to run: no case matches the selected algorithms' dimensions")
    return Plan(tasks=tasks, cases=cases, skipped=skipped)


def _run_name(options: RunOptions) -> str:
    return f"{time.strftime('%Y%m%d-%H%M%S')}-{options.sweep.profile}-seed{options.sweep.seed}"


def run(
    options: RunOptions,
    *,
    on_row: Callable[[ResultRow], None] | None = None,
    echo: Callable[[str], None] | None = None,
    progress: bool = False,
) -> Run:
    """Run the whole flow and write the run folder.

    Parameters
    ----------
    options : RunOptions
    on_row : callable, optional
        Called with each row as it arrives.
    echo : callable, optional
        Receives one line per phase for the terminal.
    progress : bool
        Draw a progress bar on stderr during the sweep.

    Returns
    -------
    Run
        Never raises for what the code under test does; an interrupt ends the
        run early with :attr:`Run.signal` set.

    Raises
    ------
    UsageError
        Bad options, an unreadable baseline, an unwritable ``--out``, an
        unreachable scheduler (then no run folder is left behind).
    """
    from .corpus.baseline import compare_with_baseline, load_baseline
    from .progress import PhaseProgress, ProgressBar
    from .report.stage import write_run_report
    from .report.writer import RowStream, new_run_dir, run_metadata, write_report, write_run_json
    from .triage.stage import triage_failures

    say = echo or (lambda line: None)
    sweep = options.sweep
    profile = sweep.profile_spec
    baseline = load_baseline(options.baseline) if options.baseline else None  # fails before the sweep
    the_plan = plan(sweep)
    run_dir = new_run_dir(options.out, _run_name(options))
    say(f"hullstress: {len(the_plan.tasks)} cases x configs = {the_plan.n_calls} calls -> {run_dir}")
    timeout = sweep.runner_options().timeout
    the_run = Run(run_dir=run_dir, plan=the_plan, table=to_frame([]))
    signals = _Signals()
    rows: list[ResultRow] = []
    stream = RowStream(run_dir)
    bar = ProgressBar(the_plan.n_calls, enabled=progress)
    # Without a terminal (CI logs), a line per quarter of the sweep instead of the bar.
    quarters = PhaseProgress("sweep", "calls", live=False, enabled=echo is not None and not progress)

    def collect(row: ResultRow) -> None:
        rows.append(row)
        stream(row)
        bar.update(row)
        quarters(len(rows), the_plan.n_calls)
        if on_row is not None:
            on_row(row)

    started = time.perf_counter()
    with signals.installed():
        # execute + check: the sweep.
        try:
            result = run_sweep(sweep, on_row=collect, tasks=the_plan.tasks)
            the_run.table, the_run.stats = result.table, result.stats
            the_run.complete = not result.stats.budget_exhausted
        except KeyboardInterrupt:
            the_run.complete = False
            the_run.table = sort_table(to_frame(rows), [c.case_id for c in the_plan.cases])
        except UsageError:
            # e.g. an unreachable --scheduler: nothing ran, so leave no empty run folder behind.
            stream.close(remove=True)
            if not rows:
                import shutil

                shutil.rmtree(run_dir, ignore_errors=True)
            raise
        finally:
            bar.close()
        the_run.seconds["sweep"] = time.perf_counter() - started
        the_run.signal = signals.signum
        the_run.meta = _metadata(the_run, options, run_metadata)
        write_report(run_dir, the_run.table, the_run.meta)  # the table is safe on disk before triage
        stream.close(remove=True)

        # triage.
        t0 = time.perf_counter()
        if the_run.signal is None:
            say("triage: grouping failures by signature, shrinking one case per group, merging groups into causes")
        runner = sweep.runner_options()
        triage_bar = PhaseProgress("triage", "groups", live=progress, enabled=echo is not None)
        try:
            the_run.triage = triage_failures(
                the_run.table, the_plan.cases, budget=profile.triage,
                shrink=options.shrink and not the_run.interrupted, timeout=timeout, workers=max(1, runner.workers),
                qhull=runner.qhull, memory_limit_mb=runner.memory_limit_mb, should_stop=signals.stop_requested,
                progress=triage_bar,
            )
        finally:
            triage_bar.close()
        the_run.seconds["triage"] = time.perf_counter() - t0
        if the_run.signal is None:
            say(f"triage: {len(the_run.triage.groups)} failure groups -> {len(the_run.triage.causes)} causes "
                f"in {the_run.seconds['triage']:.1f} s ({the_run.triage.calls} evaluations)")
        the_run.signal = signals.signum
        if the_run.signal is None and baseline is not None:
            the_run.comparison = compare_with_baseline(the_run.table, baseline)
        if options.save_corpus and the_run.signal is None:
            the_run.corpus_saved = _save_corpus(options, the_run, timeout)
        the_run.signal = signals.signum

        # report: the first signal from here on only skips the remaining pictures.
        signals.raising = False
        t0 = time.perf_counter()
        the_run.seconds["total_before_report"] = time.perf_counter() - started
        the_run.meta = _metadata(the_run, options, run_metadata)
        report_bar = PhaseProgress("report", "cause folders", live=progress, enabled=echo is not None)
        try:
            the_run.report = write_run_report(
                run_dir, the_run.table, the_run.meta, the_run.triage,
                pictures=profile.triage.pictures if options.pictures else 0, plugins=options.plugins,
                timeout=timeout, junit_path=options.junit, comparison=the_run.comparison,
                baseline_label=options.baseline, should_stop=signals.stop_requested, progress=report_bar,
            )
        finally:
            report_bar.close()
        the_run.seconds["report"] = time.perf_counter() - t0
        the_run.seconds["total"] = time.perf_counter() - started
        the_run.meta = _metadata(the_run, options, run_metadata)
        write_run_json(run_dir, the_run.meta)
        if signals.signum is not None and the_run.signal is None:
            # Interrupted while the report was being written: it is complete, but say so.
            the_run.signal = signals.signum
            the_run.meta = _metadata(the_run, options, run_metadata)
            write_report(run_dir, the_run.table, the_run.meta)
    return the_run


def _metadata(the_run: Run, options: RunOptions, run_metadata: Callable[..., dict[str, Any]]) -> dict[str, Any]:
    stats = the_run.stats
    wall = sum(v for k, v in the_run.seconds.items() if k in ("sweep", "triage", "report"))
    return run_metadata(
        run_id=the_run.run_dir.name, arguments=dict(options.arguments) or {
            "profile": options.sweep.profile, "seed": options.sweep.seed}, df=the_run.table,
        wall_seconds=the_run.seconds.get("sweep", wall), complete=the_run.complete and not the_run.interrupted,
        skipped=the_run.plan.skipped,
        extra={"interrupted": the_run.interrupted,
               "signal": None if the_run.signal is None else signal.Signals(the_run.signal).name,
               "calls_planned": the_run.plan.n_calls,
               "budget_exhausted": bool(stats.budget_exhausted) if stats else False,
               "runner": stats.as_dict() if stats else None,
               "phase_seconds": {k: round(v, 3) for k, v in the_run.seconds.items()},
               "triage": None if the_run.triage is None else {
                   "groups": len(the_run.triage.groups), "causes": len(the_run.triage.causes),
                   "evaluations": the_run.triage.calls, "stopped": the_run.triage.stopped,
                   "safety_net": the_run.triage.safety_net}},
    )


def _save_corpus(options: RunOptions, the_run: Run, timeout: float) -> list[tuple[Path, bool]]:
    """The minimised new failures become corpus entries (only new groups when there is a baseline)."""
    from .corpus.save import save_minimised_failures

    new_groups = None
    if the_run.comparison is not None:
        new = the_run.comparison[the_run.comparison["state"] == "new"]
        new_groups = set(map(tuple, new[["algorithm", "sphere", "eps", "generator", "signature"]].astype(str).values))
    return save_minimised_failures(
        options.save_corpus, the_run.triage.records, the_run.plan.cases, new_groups=new_groups,
        workers=options.sweep.runner_options().workers, timeout=timeout,
        found_by=f"hullstress run {the_run.run_dir.name}",
    )
