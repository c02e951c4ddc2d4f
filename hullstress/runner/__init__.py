"""Executing a sweep's tasks: one task is a case with every config to run on it.

Backends share :func:`execute`'s contract: call ``on_row`` once per (case,
config) as results arrive, in any order; the sweep sorts the table afterwards.

* ``workers=0``: in this process, no isolation (debugging); the timeout
  interrupts Python code with SIGALRM but not a hang inside C code.
* ``workers=N``: N isolated worker processes on this machine (the default,
  one per core).  Each call runs under ``timeout``; a hang becomes a
  ``timeout`` row, a dead worker a ``crash`` row naming the signal or exit
  code, and the worker is replaced while the sweep goes on.  Each worker has
  an address-space limit so a runaway allocation fails inside it.
* ``scheduler="tcp://host:8786"``: the same tasks on a Dask cluster, each
  through an isolated worker process on the Dask worker.

Every verdict depends only on the case and the config, never on the backend,
the number of workers or the order tasks finish in.  See
:mod:`hullstress.runner._pool` for the start method and its reasons.
"""

from __future__ import annotations

import atexit
import sys
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from types import TracebackType

from ..case import Case
from ..config import AlgorithmConfig
from ..errors import HullstressError
from ..evaluate import CaseFacts
from ..results import ResultRow
from ._pool import STREAM_PREFETCH, JobFeed, PendingJob, PoolSettings, WorkerPool, start_method
from ._protocol import algorithm_refs, refs_for_configs
from ._serial import CRASH_LOG, crash_log, no_isolation_warning, run_serial
from ._types import DEFAULT_CHECK_TIMEOUT, DEFAULT_MEMORY_LIMIT_MB, ExecutionStats, RunnerOptions, Task

__all__ = [
    "Task",
    "RunnerOptions",
    "ExecutionStats",
    "execute",
    "run_one",
    "CallPool",
    "JobFeed",
    "PendingJob",
    "DEFAULT_MEMORY_LIMIT_MB",
    "DEFAULT_CHECK_TIMEOUT",
    "no_isolation_warning",
    "crash_log",
    "CRASH_LOG",
]


def _platform_notes(options: RunnerOptions) -> list[str]:
    if options.memory_limit_bytes and not sys.platform.startswith("linux"):
        return [f"memory limit {options.memory_limit_mb:g} MB is best effort on {sys.platform} (RLIMIT_AS)"]
    return []


def execute(tasks: Sequence[Task], options: RunnerOptions, on_row: Callable[[ResultRow], None], *,
            on_idle: Callable[[], None] | None = None) -> ExecutionStats:
    """Run every config of every task and hand each row to ``on_row`` as it arrives.

    Parameters
    ----------
    tasks : sequence of Task
        Cases with the configs to run on each.
    options : RunnerOptions
        Backend (``workers``, ``scheduler``), limits and budget.
    on_row : callable
        Called once per finished call, in arrival order.  An exception from it
        (KeyboardInterrupt, a SIGTERM handler's) stops the run and kills the workers.
    on_idle : callable, optional
        With isolated workers on this machine: called once, when every task
        is sent and a worker has nothing left to run while others still work
        (a core is free from then on until the end).  Not called otherwise.

    Returns
    -------
    ExecutionStats
        Backend, wall time, calls, busy times, harness overhead, restarts, budget.

    Raises
    ------
    UsageError
        When an algorithm cannot be sent to workers, or the scheduler is unreachable.

    Examples
    --------
    A task on a degenerate case (three collinear points) with no configs runs nothing:

    >>> from hullstress.case import Case
    >>> task = Task(0, Case.from_points([[0, 0], [1, 1], [2, 2]]), ())
    >>> execute([task], RunnerOptions(workers=0), print).calls_done
    0
    """
    tasks = list(tasks)
    start = time.perf_counter()
    deadline = time.time() + options.time_budget if options.time_budget is not None else None
    if options.scheduler is not None:
        from ._dask import run_dask

        stats = ExecutionStats(backend="dask", start_method=start_method(), notes=_platform_notes(options))
        run_dask(tasks, options, on_row, stats, deadline)
    elif options.workers == 0:
        stats = ExecutionStats(backend="serial", workers=1)
        run_serial(tasks, options, on_row, stats, deadline)
    else:
        settings = PoolSettings(timeout=options.timeout, check_timeout=options.effective_check_timeout,
                                qhull=options.qhull, budget_deadline=deadline, refs=algorithm_refs(tasks),
                                qhull_options=options.qhull_options, on_idle=on_idle)
        pool = WorkerPool(max(1, min(options.workers, len(tasks))), memory_limit_bytes=options.memory_limit_bytes)
        stats = ExecutionStats(backend="local", start_method=start_method(), workers=pool.size,
                               notes=_platform_notes(options))
        try:
            pool.run([PendingJob(t) for t in tasks], settings, on_row, stats)
        finally:
            pool.close()
    return stats.finish(time.perf_counter() - start)


# -- one isolated call at a time (the shrinker's oracle) ----------------------

_solo_lock = threading.Lock()
_solo: WorkerPool | None = None


def _solo_pool(limit_bytes: int | None) -> WorkerPool:
    global _solo
    if _solo is not None and _solo.memory_limit_bytes != limit_bytes:
        _solo.close()
        _solo = None
    if _solo is None:
        _solo = WorkerPool(1, memory_limit_bytes=limit_bytes)
    return _solo


@atexit.register
def _close_solo() -> None:
    global _solo
    with _solo_lock:
        if _solo is not None:
            _solo.close()
            _solo = None


def run_one(
    case: Case,
    config: AlgorithmConfig,
    *,
    timeout: float,
    facts: CaseFacts | None = None,
    memory_limit_mb: float | None = DEFAULT_MEMORY_LIMIT_MB,
    qhull: bool = True,
    check_timeout: float | None = None,
    qhull_options: str | None = None,
) -> ResultRow:
    """Run and judge one config on one case in an isolated worker process.

    One persistent worker serves every call (replaced when a call kills it or
    times out), so a call costs a round trip and the work itself, not a new
    process: the shrinker calls this hundreds of times.  Calls from several
    threads are serialised.

    Parameters
    ----------
    case : Case
    config : AlgorithmConfig
    timeout : float
        Limit on the call in seconds; beyond it the row is ``timeout``.
    facts : CaseFacts, optional
        Precomputed facts for ``case`` (skips recomputing validity, rank and the Qhull reference).
    memory_limit_mb : float or None
        Address-space limit of the worker in MiB (None or 0: none).
    qhull : bool
        Compute the Qhull reference when ``facts`` is not given.
    check_timeout : float, optional
        Limit on the checker; default ``max(60, 10 * timeout)``.
    qhull_options : str, optional
        Qhull options tried first for the reference hull (when ``facts`` is not given).

    Returns
    -------
    ResultRow
        With any status, ``timeout`` and ``crash`` included; never raises for
        what the algorithm does.

    Examples
    --------
    >>> from hullstress import AlgorithmConfig, Case  # doctest: +SKIP
    >>> square = Case.from_points([[0, 0], [1, 0], [1, 1], [0, 1], [0, 1]])  # doctest: +SKIP
    >>> run_one(square, AlgorithmConfig("monotone-chain"), timeout=5.0).status  # doctest: +SKIP
    'pass'
    """
    options = RunnerOptions(workers=1, timeout=timeout, qhull=qhull, memory_limit_mb=memory_limit_mb,
                            check_timeout=check_timeout)
    task = Task(0, case, (config,))
    settings = PoolSettings(timeout=options.timeout, check_timeout=options.effective_check_timeout,
                            qhull=qhull, refs=algorithm_refs([task]), qhull_options=qhull_options)
    rows: list[ResultRow] = []
    with _solo_lock:
        pool = _solo_pool(options.memory_limit_bytes)
        pool.run([PendingJob(task, facts=facts)], settings, rows.append, ExecutionStats(backend="local"))
    if len(rows) != 1:
        raise HullstressError(f"internal: run_one expected 1 row for {config.label}, got {len(rows)}")
    return rows[0]


# -- many isolated calls at a time (parallel triage) --------------------------


class CallPool:
    """A multi-worker :func:`run_one`: isolated worker processes kept alive for many small batches.

    Triage runs hundreds of rounds of a few dozen calls each (shrink
    candidates, cross-checks); starting workers per round would cost more
    than the calls.  A pool keeps ``workers`` worker processes, runs each
    batch on all of them at once, replaces a worker that crashes or hangs
    (its call becomes a ``crash`` or ``timeout`` row, as in a sweep) and
    returns every row in task order.

    Parameters
    ----------
    workers : int
        Worker processes (at least 1; started on first use).
    memory_limit_mb : float or None
        Address-space limit per worker in MiB (None or 0: none).

    Examples
    --------
    >>> from hullstress import AlgorithmConfig, Case  # doctest: +SKIP
    >>> square = Case.from_points([[0, 0], [1, 0], [1, 1], [0, 1]])  # doctest: +SKIP
    >>> with CallPool(2) as pool:  # doctest: +SKIP
    ...     rows = pool.run([Task(0, square, (AlgorithmConfig("monotone-chain", eps="scaled"),))], timeout=5.0)
    >>> rows[0][0].status  # doctest: +SKIP
    'pass'
    """

    def __init__(self, workers: int, *, memory_limit_mb: float | None = DEFAULT_MEMORY_LIMIT_MB) -> None:
        options = RunnerOptions(workers=max(1, int(workers)), memory_limit_mb=memory_limit_mb)
        self._pool = WorkerPool(options.workers, memory_limit_bytes=options.memory_limit_bytes)
        self.stats = ExecutionStats(backend="local", start_method=start_method(), workers=options.workers)

    @property
    def workers(self) -> int:
        return self._pool.size

    def run(self, tasks: Sequence[Task], *, timeout: float, qhull: bool | Mapping[str, bool] = True,
            check_timeout: float | None = None, qhull_options: str | None = None,
            alone: Sequence[bool] | None = None) -> list[list[ResultRow]]:
        """Run every config of every task; rows per task, in config order.

        Parameters
        ----------
        tasks : sequence of Task
            Tasks with the same case (same ``case_id``) get the same rows.
        timeout : float
            Per-call limit in seconds; beyond it the row is ``timeout``.
        qhull : bool or mapping of str to bool
            Compute the Qhull reference with the case facts: for every task,
            or per case id (cases missing from the mapping get none).  One
            batch can so mix cases judged with and without a reference.
        check_timeout : float, optional
            Limit on the checker; default ``max(60, 10 * timeout)``.
        qhull_options : str, optional
            Qhull options tried first for the reference (the run's ``--qhull-options``).
        alone : sequence of bool, optional
            Per task: run it as a job of its own in a worker that has run
            nothing before it (:attr:`PendingJob.fresh_worker`), not merged
            with the other tasks of its case.

        Raises
        ------
        KeyboardInterrupt
            Passed on from the pool (its workers are killed first).
        """
        tasks = list(tasks)
        if not tasks:
            return []
        per_case = qhull if isinstance(qhull, Mapping) else None
        options = RunnerOptions(workers=self.workers, timeout=timeout, qhull=per_case is not None or bool(qhull),
                                check_timeout=check_timeout)
        settings = PoolSettings(timeout=options.timeout, check_timeout=options.effective_check_timeout,
                                qhull=options.qhull, refs=algorithm_refs(tasks), qhull_options=qhull_options)
        found: dict[tuple[str, str], ResultRow] = {}

        def keep(row: ResultRow) -> None:
            found[(str(row["case_id"]), str(row["config"]))] = row

        # One job per case, with the union of its configs: its facts are computed once.
        merged: dict[str, Task] = {}
        separate: list[Task] = []
        for n, t in enumerate(tasks):
            if alone is not None and alone[n]:
                separate.append(t)
                continue
            first = merged.get(t.case.case_id)
            configs = t.configs if first is None else tuple(dict.fromkeys(first.configs + t.configs))
            merged[t.case.case_id] = Task(t.index if first is None else first.index, t.case, configs)

        def reference(t: Task) -> bool | None:
            return None if per_case is None else bool(per_case.get(t.case.case_id, False))

        jobs = [PendingJob(t, qhull=reference(t)) for t in merged.values()]
        jobs += [PendingJob(t, qhull=reference(t), fresh_worker=True) for t in separate]
        self._pool.run(jobs, settings, keep, self.stats)
        out = []
        for t in tasks:
            rows = [found.get((t.case.case_id, c.label)) for c in t.configs]
            missing = [c.label for c, r in zip(t.configs, rows) if r is None]
            if missing:
                raise HullstressError(f"internal: the call pool returned no row for {missing[0]} on case "
                                      f"{t.case.case_id}")
            out.append(rows)
        return out

    def stream(self, feed: JobFeed, on_row: Callable[[ResultRow], None], *, configs: Sequence[AlgorithmConfig],
               timeout: float, check_timeout: float | None = None, qhull_options: str | None = None) -> None:
        """Run the jobs of ``feed`` as workers have room, including those ``on_row`` adds, until none is left.

        Where :meth:`run` takes a batch and returns its rows, this hands each
        row to ``on_row`` as it arrives, and ``on_row`` may push new jobs
        (:class:`~hullstress.runner._pool.PendingJob`, with their own
        ``qhull``) into ``feed``: a caller that decides its next calls from
        the answers (parallel triage) never waits for the slowest call of a
        batch.  Isolation is :meth:`run`'s: a crash or hang is a row.

        Parameters
        ----------
        feed : JobFeed
            The jobs, most urgent first; it may grow while this runs.
        on_row : callable
            Receives every row; may push jobs, or raise to stop (the workers are killed first).
        configs : sequence of AlgorithmConfig
            Every config the jobs may use (their algorithms are made known to the workers).
        timeout : float
            Per-call limit in seconds; beyond it the row is ``timeout``.
        check_timeout : float, optional
            Limit on the checker; default ``max(60, 10 * timeout)``.
        qhull_options : str, optional
            Qhull options tried first for the reference.
        """
        options = RunnerOptions(workers=self.workers, timeout=timeout, check_timeout=check_timeout)
        settings = PoolSettings(timeout=options.timeout, check_timeout=options.effective_check_timeout,
                                qhull=False, refs=refs_for_configs(configs), qhull_options=qhull_options,
                                prefetch=STREAM_PREFETCH)
        self._pool.serve(feed, settings, on_row, self.stats)

    def close(self) -> None:
        """Stop the workers."""
        self._pool.close()

    def __enter__(self) -> "CallPool":
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()
