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
phase under way (the sweep's workers are killed, a call in progress
included; triage keeps the groups it finished and its shrinker stops between
calls), every finished row is kept, the report is written from what there is
and marked incomplete and interrupted (with the signal), and
:attr:`Run.exit_status` is 130 (SIGINT) or 143 (SIGTERM).  The signal raises
only while code under test runs (the sweep, triage, saving to the corpus);
while files are written it is noted and honoured at the next step, so a
report is never left half-written by the first signal.  A second signal
during the report aborts it.

The environment is handled here too: output folders (``--out``,
``--save-corpus``, the folder of ``--junit``) are checked before any work; a
write refused later (a full disk) stops the run where it is, keeps every file
already written (``results.partial.csv`` included) and sets
:attr:`Run.environment_errors` (exit status 4).
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import pandas as pd

from .case import Case
from .errors import CorpusError, EnvironmentFailure, ExitStatus, Interrupted, UsageError, is_environment_error
from .results import ResultRow, to_frame
from .runner import ExecutionStats, Task
from .qhull_format import check_qhull_options
from .sweep import SweepOptions, build_tasks, run_sweep, sort_table

if TYPE_CHECKING:  # the report's modules load when the run gets there
    from .report.picture_helper import PictureDrawer
    from .report.stage import FindingsBeside

__all__ = ["RunOptions", "Run", "Interrupted", "Plan", "plan", "run", "report_rows", "EXIT_FOR_SIGNAL", "Executor",
           "YIELD_NICENESS", "yield_cpu_to_workers", "RUNNING"]

#: Exit status after an interrupt, by signal (the shell's 128 + signal number).
EXIT_FOR_SIGNAL = {signal.SIGINT: int(ExitStatus.SIGINT), signal.SIGTERM: int(ExitStatus.SIGTERM)}


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
    registration : tuple of str
        The command line's ``--plugin``/``--exec``/``--clockwise`` arguments (repeated in
        the reproduce commands of the algorithms that need them).
    last_failed : {None, "only", "first"}
        ``--last-failed``: run only the calls that failed in the latest run in
        ``out``; ``--failed-first``: run their cases first.
    executor : Executor or None
        The execute stage when it is not the sweep (``hullstress search``).
    yield_cpu : bool
        Once the fork server of the worker processes runs, lower this
        process's CPU priority (``nice`` +10; workers keep theirs): it only
        feeds the workers and collects their rows, so with as many workers as
        cores it takes a core only when they leave one free.  The command line
        sets it; a library caller (the pytest plug-in, a script) keeps its priority.
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
    registration: tuple[str, ...] = ()
    last_failed: str | None = None
    executor: "Executor | None" = None
    yield_cpu: bool = False


@dataclass(frozen=True)
class Plan:
    """The generate stage's output: tasks (cases x configs) and what was not generated.

    Attributes
    ----------
    tasks : list of Task
        In the order they run (``--failed-first`` puts earlier failures first).
    cases : list of Case
        The cases of ``tasks`` in generation order (the results table's order).
    skipped : list of str
    notes : list of str
        What the terminal should say about the selection (``--last-failed``).
    """

    tasks: list[Task]
    cases: list[Case]
    skipped: list[str]
    notes: list[str] = field(default_factory=list)

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
        None when the run stopped before its report (a refused write).
    comparison : DataFrame or None
        Failure groups against the baseline (:func:`hullstress.corpus.baseline.compare_with_baseline`;
        ``state``: new, still-failing, fixed, not-reached).
    corpus_saved : list of (Path, bool, Signature)
        Corpus entries written (True) or already there (False).
    signal : int or None
        The signal that interrupted the run.
    complete : bool
        Every planned call ran (not interrupted, time budget not exhausted).
    seconds : dict of str to float
        Wall time per phase.
    environment_errors : list of str
        Writes the environment refused (a full disk, an unwritable path), one line each.
    """

    run_dir: Path
    plan: Plan
    table: pd.DataFrame
    stats: ExecutionStats | None = None
    meta: dict[str, Any] = field(default_factory=dict)
    triage: Any = None
    report: Any = None
    comparison: pd.DataFrame | None = None
    corpus_saved: list[tuple[Path, bool, Any]] = field(default_factory=list)
    baseline_note: str = ""
    signal: int | None = None
    complete: bool = True
    seconds: dict[str, float] = field(default_factory=dict)
    environment_errors: list[str] = field(default_factory=list)
    #: How the sweep ended when ``hullstress report`` reports it afterwards (``run.json``'s state then:
    #: crashed, interrupted, ...); None for a run reported by itself.
    ended: str | None = None
    #: ``run.json``'s ``crash``: the first lines of ``crash.log`` when the code under test killed the process.
    crash: str | None = None

    @property
    def interrupted(self) -> bool:
        return self.signal is not None

    @property
    def n_failed(self) -> int:
        from .triage.signature import FAILED_STATUSES

        return int(self.table["status"].isin(FAILED_STATUSES).sum()) if len(self.table) else 0

    @property
    def exit_status(self) -> int:
        """130/143 interrupted; 4 a write refused; 5 no call ran; with a baseline 1 only for new groups; else 1 for any failure."""
        if self.signal is not None:
            return EXIT_FOR_SIGNAL.get(self.signal, int(ExitStatus.SIGINT))
        if self.environment_errors:
            return int(ExitStatus.ENVIRONMENT)
        if not len(self.table):
            return int(ExitStatus.NO_WORK)
        if self.comparison is not None:
            return int(ExitStatus.FAILURES if bool((self.comparison["state"] == "new").any()) else ExitStatus.OK)
        return int(ExitStatus.FAILURES if self.n_failed else ExitStatus.OK)


class _Signals:
    """SIGINT/SIGTERM for the duration of a run: remember the signal; stop the code under test.

    The handler raises :class:`Interrupted` only inside :meth:`raising`
    regions (where code under test runs), at most once per region; elsewhere
    the first signal is only recorded (:meth:`stop_requested`) and a second
    one aborts.
    """

    def __init__(self) -> None:
        self.signum: int | None = None
        self._raising = False

    def handler(self, signum: int, frame: Any) -> None:
        first = self.signum is None
        if first:
            self.signum = signum
        if self._raising:
            self._raising = False  # the region's clean-up runs undisturbed
            raise Interrupted(signum)
        if not first:
            raise Interrupted(signum)

    def stop_requested(self) -> bool:
        return self.signum is not None

    @contextmanager
    def raising(self) -> Iterator[None]:
        """A region where the first signal raises at once (unless one arrived already: then it raises now)."""
        if self.signum is not None:
            raise Interrupted(self.signum)
        self._raising = True
        try:
            yield
        finally:
            self._raising = False

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


class Executor(Protocol):
    """An execute stage other than the sweep (:mod:`hullstress.search`): it makes the cases it runs.

    Called with the generate stage's plan, it may run other cases than the
    plan's: it rewrites ``plan.tasks`` and ``plan.cases`` to what it ran, each
    case appended before its first row reaches ``on_row`` (so an interrupt
    leaves a plan that lists every row's case), and returns the runner's
    accounting (``budget_exhausted`` when a time budget cut it short).
    """

    def planned_calls(self, plan: "Plan") -> int:
        """The calls it expects to make (the progress bar's total)."""

    def __call__(self, plan: "Plan", on_row: Callable[[ResultRow], None]) -> ExecutionStats:
        """Run, handing each row to ``on_row``."""


def plan(options: SweepOptions, *, out: str | None = None, last_failed: str | None = None) -> Plan:
    """The generate stage: build every case and cross it with its dimension's configs.

    Parameters
    ----------
    options : SweepOptions
    out : str, optional
        The output folder whose latest run ``last_failed`` reads.
    last_failed : {None, "only", "first"}
        ``--last-failed`` / ``--failed-first`` (see :mod:`hullstress.previous`).

    Raises
    ------
    UsageError
        When no case matches the selected algorithms' dimensions (nothing to
        run), a size would not fit in memory, or ``--qhull-options`` are not
        Qhull options; nothing has been generated then.
    """
    check_qhull_options(options.qhull_options)
    tasks, cases, _, skipped = build_tasks(options)
    if not tasks:
        raise UsageError("nothing to run: no case matches the selected algorithms' dimensions")
    notes: list[str] = []
    if last_failed is not None:
        from .previous import select_previous_failures

        tasks, note = select_previous_failures(tasks, out or ".", last_failed)
        notes.append(note)
        kept = {t.case.case_id for t in tasks}
        cases = [c for c in cases if c.case_id in kept]
    return Plan(tasks=tasks, cases=cases, skipped=skipped, notes=notes)


def _run_name(options: RunOptions) -> str:
    kind = options.sweep.profile if options.executor is None else "search"
    return f"{time.strftime('%Y%m%d-%H%M%S')}-{kind}-seed{options.sweep.seed}"


def _refusal(exc: BaseException) -> str | None:
    """The one-line message of a write the environment refused, or None for any other error."""
    if isinstance(exc, EnvironmentFailure):
        return str(exc)
    if is_environment_error(exc):
        assert isinstance(exc, OSError)
        return f"cannot write {str(exc.filename or 'a file')!r}: {exc.strerror or exc}"
    return None


@contextmanager
def _noting_refusals(the_run: Run) -> Iterator[None]:
    """Record a write the environment refused in ``the_run.environment_errors`` and go on; re-raise anything else."""
    try:
        yield
    except (EnvironmentFailure, OSError) as exc:
        message = _refusal(exc)
        if message is None:
            raise
        the_run.environment_errors.append(message)


def _check_output_folders(options: RunOptions) -> None:
    """Refuse unwritable output folders before any work is done (exit status 4, or 2 for a bad path)."""
    from .files import writable_folder

    if options.save_corpus:
        writable_folder(options.save_corpus, "--save-corpus")
        from .corpus.store import held_groups

        try:  # which groups it holds decides what is saved: an unreadable entry is found now, not after the sweep
            held_groups(options.save_corpus)
        except CorpusError as exc:
            raise UsageError(f"--save-corpus: {exc}") from None
    if options.junit:
        junit = Path(options.junit)
        if junit.is_dir():
            raise UsageError(f"--junit {options.junit!r} is a folder, expected a file name")
        writable_folder(junit.parent, "--junit")


#: How much this process lowers its priority under ``RunOptions.yield_cpu``.
YIELD_NICENESS = 10


def yield_cpu_to_workers() -> None:
    """``nice`` this process by :data:`YIELD_NICENESS` (workers forked from the running fork server keep theirs).

    Measured on 2 cores, the quick sweep with 2 workers: 9.3-9.5 s -> 8.9 s.
    Where the platform has no ``nice`` or refuses it, nothing changes.
    """
    try:
        os.nice(YIELD_NICENESS)
    except (AttributeError, OSError):
        pass


def run(
    options: RunOptions,
    *,
    on_row: Callable[[ResultRow], None] | None = None,
    echo: Callable[[str], None] | None = None,
    progress: bool = False,
    warn: Callable[[str], None] | None = None,
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
    warn : callable, optional
        Receives the lines the user must see even with ``--quiet`` (the
        warning of a run without isolation).

    Returns
    -------
    Run
        Never raises for what the code under test does; an interrupt ends the
        run early with :attr:`Run.signal` set, a refused write with
        :attr:`Run.environment_errors`.

    Raises
    ------
    UsageError
        Bad options, an unreadable baseline, a path that cannot be a folder,
        an unreachable scheduler (then no run folder is left behind).
    EnvironmentFailure
        An output folder that is read-only or not writable, found before any work.
    """
    from .corpus.baseline import load_baseline
    from .progress import PhaseProgress, ProgressBar
    from .report.writer import OutputLog, RowStream, new_run_dir, prepare_report

    began = time.perf_counter()
    say = echo or (lambda line: None)
    sweep = options.sweep
    if sweep.runner_options().workers >= 1:
        from .runner import start_method

        # Start the fork server that every isolated worker is forked from now: it imports NumPy, SciPy
        # and hullstress (about half a second) in its own process while this one builds the cases,
        # instead of while the sweep's first workers wait for it.
        start_method()
        if options.yield_cpu:
            yield_cpu_to_workers()
    baseline = None
    if options.baseline:  # fails before the sweep; the folder --save-corpus creates may not exist yet (night 1)
        baseline = load_baseline(options.baseline, may_be_created=_same_path(options.baseline, options.save_corpus))
    the_plan = plan(sweep, out=options.out, last_failed=options.last_failed)
    _check_output_folders(options)
    run_dir = new_run_dir(options.out, _run_name(options))
    say(f"hullstress: {len(the_plan.tasks)} cases x configs = {the_plan.n_calls} calls -> {run_dir}")
    the_run = Run(run_dir=run_dir, plan=the_plan, table=to_frame([]), baseline_note=baseline.note if baseline else "")
    # run.json at once, state "running": a run killed before its end (a crash without isolation, SIGKILL)
    # still says what it was, and `hullstress report` rebuilds its cases from the arguments recorded here.
    _write_tables(the_run, options, started=True)
    if the_run.environment_errors:
        return the_run
    isolated = sweep.runner_options().workers >= 1 or sweep.scheduler is not None
    if not isolated and warn is not None:
        from .runner import no_isolation_warning

        warn(no_isolation_warning(run_dir))
    signals = _Signals()
    rows: list[ResultRow] = []
    stream = RowStream(run_dir)
    log = OutputLog(run_dir)
    total = the_plan.n_calls if options.executor is None else options.executor.planned_calls(the_plan)
    bar = ProgressBar(total, enabled=progress)
    # Without a terminal (CI logs), a line per quarter of the sweep instead of the bar.
    quarters = PhaseProgress("sweep", "calls", live=False, enabled=echo is not None and not progress)

    def collect(row: ResultRow) -> None:
        rows.append(row)
        stream(row)
        log(row)
        bar.update(row)
        quarters(len(rows), total)
        if on_row is not None:
            on_row(row)

    # The report's imports now (matplotlib too, in a thread, with one worker: see prepare_report).
    report_workers = max(1, sweep.runner_options().workers)  # processes the report's helpers may keep busy
    drawer = prepare_report(pictures=options.pictures, workers=report_workers)
    started = time.perf_counter()
    the_run.seconds["generate"] = started - began  # the cases, the output folder, the report's imports
    with signals.installed(), drawer, ExitStack() as helpers:
        # execute + check: the sweep.
        try:
            with signals.raising():
                if options.executor is None:
                    from .runner import crash_log

                    # The picture drawers warm up on the first core the sweep's tail leaves idle.
                    with crash_log(run_dir, enabled=not isolated):
                        result = run_sweep(sweep, on_row=collect, tasks=the_plan.tasks, on_idle=drawer.begin)
                    the_run.table, the_run.stats = result.table, result.stats
                else:
                    the_run.stats = options.executor(the_plan, collect)
                    the_run.table = sort_table(to_frame(rows), [c.case_id for c in the_plan.cases])
            the_run.complete = not the_run.stats.budget_exhausted
        except KeyboardInterrupt:
            the_run.complete = False
        except UsageError:
            # e.g. an unreachable --scheduler: nothing ran, so leave no empty run folder behind.
            stream.close(remove=True)
            if not rows:
                import shutil

                shutil.rmtree(run_dir, ignore_errors=True)
            raise
        except (EnvironmentFailure, OSError) as exc:
            if _refusal(exc) is None:
                raise
            the_run.environment_errors.append(str(_refusal(exc)))  # a full disk: the sweep stops here
            the_run.complete = False
        finally:
            bar.close()
            log.close()
        if not the_run.complete and len(the_run.table) != len(rows):
            the_run.table = sort_table(to_frame(rows), [c.case_id for c in the_plan.cases])
        the_run.seconds["sweep"] = time.perf_counter() - started
        the_run.signal = signals.signum
        # The table is final: with workers to spare, a helper computes the findings (a function of the
        # table alone) now, in the core this process leaves idle while it writes the tables and groups
        # the failures, and in what triage leaves idle.  The picture drawers began warming up when the
        # sweep's tail first left a core idle (begun here if it never did).
        from .report.stage import FindingsBeside

        findings = helpers.enter_context(FindingsBeside(the_run.table, report_workers))
        drawer.begin()
        _write_tables(the_run, options)  # the table is safe on disk before triage
        stream.close(remove=not the_run.environment_errors)
        if the_run.environment_errors:
            return the_run  # a full disk: stop here, keeping what is written

        # triage.
        t0 = time.perf_counter()
        if signals.signum is None:
            say("triage: grouping failures by signature, shrinking one case per group, merging groups into causes")
        the_run.triage = _triage_with_progress(the_run, options, signals, echo=echo, progress=progress)
        the_run.seconds["triage"] = time.perf_counter() - t0
        if the_run.signal is None:
            say(f"triage: {len(the_run.triage.groups)} failure groups -> {len(the_run.triage.causes)} causes "
                f"in {the_run.seconds['triage']:.1f} s ({the_run.triage.calls} evaluations)")
        the_run.signal = signals.signum
        if the_run.signal is None and baseline is not None:
            the_run.comparison = _compare(the_run, options, baseline, signals)
        if options.save_corpus and the_run.signal is None:
            the_run.corpus_saved = _save_corpus(options, the_run, signals)
        the_run.signal = signals.signum

        # report: a first signal from here on cuts the picture under way short and skips the
        # others; the rest of the report is written.  A second signal aborts it.
        say(f"report: writing {run_dir}")
        report_bar = PhaseProgress("report", "cause folders", live=progress, enabled=echo is not None)
        try:
            _report(the_run, options, signals, started, report_bar, drawer, findings)
        finally:
            report_bar.close()
    return the_run


def report_rows(
    run_dir: Path,
    options: RunOptions,
    table: pd.DataFrame,
    the_plan: Plan,
    *,
    ended: str,
    complete: bool = False,
    crash: str | None = None,
    sweep_seconds: float = 0.0,
    echo: Callable[[str], None] | None = None,
    progress: bool = False,
) -> Run:
    """Triage the rows of an existing run folder and write its report there (``hullstress report``).

    The flow of :func:`run` from the sweep's end: the tables, triage, the
    report; nothing is compared with a baseline nor saved to a corpus.

    Parameters
    ----------
    run_dir : Path
        The run folder (``results.csv`` and the report go there).
    options : RunOptions
        The run's options, as its ``run.json`` recorded them.
    table : DataFrame
        The rows the run finished (``results.partial.csv`` of a run that died).
    the_plan : Plan
        The run's plan, rebuilt from its options: every row's case is in it.
    ended : str
        How the sweep ended (``run.json``'s state): ``crashed``, ``interrupted``, ``complete`` ...
    complete : bool
        Every planned call ran.
    crash : str or None
        What killed the process, from ``crash.log``.
    sweep_seconds : float
        The sweep's wall time, when the run recorded it.
    echo, progress
        As for :func:`run`.

    Returns
    -------
    Run
        Never interrupted by the run's own signal: a signal now stops this
        triage (exit status 130/143 then).
    """
    from .progress import PhaseProgress

    say = echo or (lambda line: None)
    the_run = Run(run_dir=Path(run_dir), plan=the_plan, table=sort_table(table, [c.case_id for c in the_plan.cases]),
                  complete=complete, ended=ended, crash=crash)
    the_run.seconds["sweep"] = sweep_seconds
    signals = _Signals()
    started = time.perf_counter()
    with signals.installed():
        _write_tables(the_run, options)
        if the_run.environment_errors:
            return the_run
        say(f"triage: {the_run.n_failed} failed calls of {len(the_run.table)}: grouping by signature, shrinking "
            "one case per group, merging groups into causes")
        the_run.triage = _triage_with_progress(the_run, options, signals, echo=echo, progress=progress)
        the_run.seconds["triage"] = time.perf_counter() - started
        the_run.signal = signals.signum
        say(f"report: writing {run_dir}")
        report_bar = PhaseProgress("report", "cause folders", live=progress, enabled=echo is not None)
        try:
            _report(the_run, options, signals, started, report_bar)
        finally:
            report_bar.close()
    return the_run


def _write_tables(the_run: Run, options: RunOptions, *, started: bool = False) -> None:
    """``results.csv`` (+ Parquet), ``summary.md`` and ``run.json`` as the run stands; a refused write is recorded.

    With ``started``, only ``run.json`` in the state ``running``, before the sweep.
    """
    from .report.writer import run_metadata, write_report, write_run_json

    the_run.meta = _metadata(the_run, options, run_metadata)
    if started:
        the_run.meta["state"] = RUNNING
        with _noting_refusals(the_run):
            write_run_json(the_run.run_dir, the_run.meta)
        return
    refused = len(the_run.environment_errors)
    with _noting_refusals(the_run):
        write_report(the_run.run_dir, the_run.table, the_run.meta)
    if len(the_run.environment_errors) > refused:
        # A full disk may still take the small run.json, which says what happened.
        the_run.meta = _metadata(the_run, options, run_metadata)
        with _noting_refusals(the_run):
            write_run_json(the_run.run_dir, the_run.meta)


def _triage_with_progress(the_run: Run, options: RunOptions, signals: _Signals, *,
                          echo: Callable[[str], None] | None, progress: bool) -> Any:
    """The triage phase with its progress bar (shown when the run echoes), for :func:`run` and :func:`report_rows`."""
    from .progress import PhaseProgress

    triage_bar = PhaseProgress("triage", "groups", live=progress, enabled=echo is not None)
    try:
        return _triage(the_run, options, signals, triage_bar)
    finally:
        triage_bar.close()


def _triage(the_run: Run, options: RunOptions, signals: _Signals, progress: Any = None) -> Any:
    from .triage.records import TriageResult
    from .triage.stage import triage_failures

    sweep = options.sweep
    t0 = time.perf_counter()
    try:
        with signals.raising():
            runner = sweep.runner_options()
            return triage_failures(
                the_run.table, the_run.plan.cases, budget=sweep.profile_spec.triage,
                shrink=options.shrink and signals.signum is None, timeout=runner.timeout,
                workers=max(1, runner.workers), qhull=runner.qhull, memory_limit_mb=runner.memory_limit_mb,
                should_stop=signals.stop_requested, progress=progress, qhull_options=sweep.qhull_options,
            )
    except KeyboardInterrupt:  # between groups or while grouping: nothing triaged is lost but this step
        return TriageResult(groups=[], notes=["Triage was interrupted before it grouped the failures."],
                            seconds=time.perf_counter() - t0, stopped=True)


def _report(the_run: Run, options: RunOptions, signals: _Signals, started: float, progress: Any = None,
            drawer: PictureDrawer | None = None, findings: FindingsBeside | None = None) -> None:
    from .report.stage import write_run_report
    from .report.writer import run_metadata, write_run_json

    sweep = options.sweep
    t0 = time.perf_counter()
    the_run.seconds["total_before_report"] = time.perf_counter() - started
    the_run.meta = _metadata(the_run, options, run_metadata)
    try:
        with _noting_refusals(the_run):
            the_run.report = write_run_report(
                the_run.run_dir, the_run.table, the_run.meta, the_run.triage,
                pictures=sweep.profile_spec.triage.pictures if options.pictures else 0, plugins=options.plugins,
                timeout=sweep.runner_options().timeout, junit_path=options.junit, progress=progress,
                comparison=the_run.comparison, baseline_label=options.baseline,
                should_stop=signals.stop_requested, registration=options.registration,
                tables_written=not the_run.environment_errors, interruptible=signals.raising,
                workers=max(1, sweep.runner_options().workers), drawer=drawer, findings_beside=findings,
            )
    except KeyboardInterrupt:
        pass  # a second signal: the report stays as far as it got; run.json says why below
    the_run.seconds["report"] = time.perf_counter() - t0
    if the_run.signal is None or the_run.report is None:
        # run.json again: with the report's own time, and saying so when a signal interrupted the report
        # or it failed.  (A run interrupted earlier wrote it already and stops at once.)
        the_run.signal = signals.signum
        the_run.meta = _metadata(the_run, options, run_metadata)
        with _noting_refusals(the_run):
            write_run_json(the_run.run_dir, the_run.meta)


def _metadata(the_run: Run, options: RunOptions, run_metadata: Callable[..., dict[str, Any]]) -> dict[str, Any]:
    stats = the_run.stats
    wall = sum(v for k, v in the_run.seconds.items() if k in ("sweep", "triage", "report"))
    return run_metadata(
        run_id=the_run.run_dir.name, arguments=dict(options.arguments) or {
            "profile": options.sweep.profile, "seed": options.sweep.seed}, df=the_run.table,
        wall_seconds=the_run.seconds.get("sweep", wall), complete=the_run.complete and not the_run.interrupted,
        skipped=the_run.plan.skipped,
        extra={"state": _state(the_run),
               "interrupted": the_run.interrupted,
               "signal": None if the_run.signal is None else signal.Signals(the_run.signal).name,
               "environment_errors": list(the_run.environment_errors),
               "selection": list(the_run.plan.notes),
               "calls_planned": the_run.plan.n_calls,
               "budget_exhausted": bool(stats.budget_exhausted) if stats else False,
               "runner": stats.as_dict() if stats else None,
               "phase_seconds": {k: round(v, 3) for k, v in the_run.seconds.items()},
               "cwd": os.getcwd(),
               **({"crash": the_run.crash} if the_run.crash else {}),
               "not_reached": _not_reached(the_run),
               "triage": None if the_run.triage is None else {
                   "groups": len(the_run.triage.groups), "causes": len(the_run.triage.causes),
                   "evaluations": the_run.triage.calls, "reused": the_run.triage.reused,
                   "stopped": the_run.triage.stopped,
                   "safety_net": the_run.triage.safety_net}},
    )


def _not_reached(the_run: Run) -> dict[str, int]:
    """Planned calls that did not run, per family (a time budget or an interrupt ended the sweep)."""
    planned: dict[str, int] = {}
    for task in the_run.plan.tasks:
        planned[task.case.family] = planned.get(task.case.family, 0) + len(task.configs)
    done = the_run.table["generator"].value_counts().to_dict() if len(the_run.table) else {}
    return {family: n - int(done.get(family, 0)) for family, n in planned.items() if n > done.get(family, 0)}


#: ``run.json``'s state while the run runs: still there afterwards, the process died before its end.
RUNNING = "running"


def _state(the_run: Run) -> str:
    """``run.json``'s one-word state: interrupted, environment-failure, incomplete (budget) or complete.

    (``running`` until the sweep ends; ``hullstress report`` records ``crashed`` for a run that died then.)
    """
    if the_run.ended is not None:
        return the_run.ended
    if the_run.interrupted:
        return "interrupted"
    if the_run.environment_errors:
        return "environment-failure"
    return "complete" if the_run.complete else "incomplete"


def _same_path(a: str | None, b: str | None) -> bool:
    """``--baseline`` and ``--save-corpus`` name one folder (the nightly loop's command line)."""
    return bool(a and b) and os.path.abspath(a) == os.path.abspath(b)  # type: ignore[arg-type]


def _planned_calls(the_plan: Plan) -> dict[str, int]:
    """Calls the plan holds per config label."""
    planned: dict[str, int] = {}
    for task in the_plan.tasks:
        for config in task.configs:
            planned[config.label] = planned.get(config.label, 0) + 1
    return planned


def _compare(the_run: Run, options: RunOptions, baseline: Any, signals: _Signals) -> pd.DataFrame | None:
    """The run's failure groups against the baseline; a known group the sweep did not meet is re-run on its case."""
    from .corpus.baseline import compare_with_baseline
    from .corpus.replay import recheck_groups

    runner = options.sweep.runner_options()
    groups = the_run.triage.groups if the_run.triage is not None and not the_run.triage.stopped else None
    try:
        with signals.raising():  # re-running a corpus case runs code under test
            return compare_with_baseline(the_run.table, baseline, _planned_calls(the_run.plan), groups=groups,
                                         recheck=lambda entries: recheck_groups(entries, runner))
    except KeyboardInterrupt:
        return None


def _save_corpus(options: RunOptions, the_run: Run, signals: _Signals) -> list[tuple[Path, bool, Any]]:
    """Every failure group the corpus does not hold yet becomes an entry (its minimal case)."""
    from .corpus.save import save_new_groups
    from .triage.grouping import group_failures

    groups = the_run.triage.groups if the_run.triage is not None and not the_run.triage.stopped else None
    runner = options.sweep.runner_options()
    try:
        with _noting_refusals(the_run), signals.raising():  # recording expectations runs every config
            return save_new_groups(
                options.save_corpus, groups if groups is not None else group_failures(the_run.table),  # type: ignore[arg-type]
                the_run.triage.records if the_run.triage is not None else [], the_run.plan.cases,
                workers=runner.workers, timeout=runner.timeout, found_by=f"hullstress run {the_run.run_dir.name}",
            )
    except KeyboardInterrupt:
        pass
    except CorpusError as exc:  # an unreadable entry: name it, save nothing rather than a second copy of a group
        the_run.environment_errors.append(f"--save-corpus: {exc}")
    return []
