"""The Dask distributed backend (``--scheduler tcp://host:8786``).

One Dask future per task (a case with all its configs).  On the Dask worker
the task does not run in the Dask worker process itself: it goes through the
same isolated worker process as a local run (one persistent
:class:`~hullstress.runner._pool.WorkerPool` of size 1 per Dask thread), so
a segfault or a hang in the code under test costs one isolated process, not
the Dask worker, and is recorded as the same ``crash`` or ``timeout`` row a
local run records.  That is what makes the table identical to a local run's.

Requirements on the cluster: hullstress and the libraries it uses installed
in the workers' environment, and every ``--plugin`` file at the same path on
every worker machine (a module plug-in must be importable there).  A running
call cannot be cancelled from the client: after Ctrl-C, calls already on a
Dask worker finish (each bounded by ``--timeout``) and their rows are dropped.
"""

from __future__ import annotations

import atexit
import threading
import time
import uuid
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import UsageError
from ..records import Stage, Status
from ..results import ResultRow, make_row
from ._pool import PendingJob, PoolSettings, WorkerPool
from ._protocol import algorithm_refs, emit_row, one_line
from ._types import ExecutionStats, RunnerOptions, Task

__all__ = ["run_dask", "run_task_on_dask_worker"]

#: Futures in flight per Dask thread: enough to keep every thread busy, few
#: enough that the time budget can stop the sweep promptly.
IN_FLIGHT_PER_THREAD = 2
#: How long to wait for the cluster to have at least one worker.
WORKER_WAIT_SECONDS = 60.0

# On a Dask worker: idle isolated pools, keyed by memory limit (one per Dask thread at most).
_idle_pools: dict[int | None, list[WorkerPool]] = {}
_idle_lock = threading.Lock()


def _acquire_pool(limit_bytes: int | None) -> WorkerPool:
    with _idle_lock:
        pools = _idle_pools.setdefault(limit_bytes, [])
        if pools:
            return pools.pop()
    return WorkerPool(1, memory_limit_bytes=limit_bytes)


def _release_pool(pool: WorkerPool) -> None:
    with _idle_lock:
        _idle_pools.setdefault(pool.memory_limit_bytes, []).append(pool)


@atexit.register
def _close_idle_pools() -> None:
    with _idle_lock:
        pools = [p for ps in _idle_pools.values() for p in ps]
        _idle_pools.clear()
    for pool in pools:
        pool.close()


def run_task_on_dask_worker(
    task: Task, settings: PoolSettings, limit_bytes: int | None
) -> tuple[list[ResultRow], ExecutionStats]:
    """Run one task on this Dask worker through an isolated worker process.

    Returns
    -------
    rows : list of ResultRow
    tally : ExecutionStats
        Calls started, facts time, restarts and the budget flag, for the client to add up.
    """
    pool = _acquire_pool(limit_bytes)
    rows: list[ResultRow] = []
    tally = ExecutionStats(backend="dask")
    try:
        pool.run([PendingJob(task)], settings, rows.append, tally)
    finally:
        _release_pool(pool)
    return rows, tally


def _connect(address: str) -> Any:
    try:
        from distributed import Client
    except ImportError:
        raise UsageError(
            f"--scheduler {address!r} needs the optional dependency 'distributed' "
            "(pip install 'hullstress[distributed]')"
        ) from None
    try:
        client = Client(address, timeout="30s", set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise UsageError(f"--scheduler {address!r}: cannot connect: {one_line(exc)}") from None
    try:
        client.wait_for_workers(1, timeout=WORKER_WAIT_SECONDS)
    except (OSError, TimeoutError):
        client.close()
        raise UsageError(
            f"--scheduler {address!r}: no worker joined within {WORKER_WAIT_SECONDS:g} s"
        ) from None
    return client


def run_dask(
    tasks: Sequence[Task],
    options: RunnerOptions,
    on_row: Callable[[ResultRow], None],
    stats: ExecutionStats,
    budget_deadline: float | None,
) -> None:
    """Run ``tasks`` on the Dask cluster at ``options.scheduler``, streaming rows as tasks finish."""
    from distributed import as_completed

    assert options.scheduler is not None
    refs = algorithm_refs(list(tasks))
    settings = PoolSettings(timeout=options.timeout, check_timeout=options.effective_check_timeout,
                            qhull=options.qhull, budget_deadline=budget_deadline, refs=refs,
                            qhull_options=options.qhull_options)
    client = _connect(options.scheduler)
    futures: dict[Any, Task] = {}
    try:
        threads = max(1, sum(client.nthreads().values()))
        stats.workers = threads
        run_token = uuid.uuid4().hex[:12]
        pending = iter(tasks)
        completed = as_completed(loop=client.loop)

        def submit_next() -> bool:
            task = next(pending, None)
            if task is None:
                return False
            if budget_deadline is not None and time.time() >= budget_deadline:
                stats.budget_exhausted = True
                return False
            future = client.submit(run_task_on_dask_worker, task, settings, options.memory_limit_bytes,
                                   key=f"hullstress-{run_token}-{task.index}", retries=0)
            futures[future] = task
            completed.add(future)
            return True

        for _ in range(IN_FLIGHT_PER_THREAD * threads):
            if not submit_next():
                break
        for future in completed:
            task = futures.pop(future)
            try:
                rows, tally = future.result()
            except Exception as exc:  # the Dask worker died or the task could not run there
                reason = f"internal: dask task failed: {one_line(exc)}"
                rows = [make_row(task.case, c, status=Status.ERROR, stage=Stage.CHECK, reason=reason,
                                 origin=refs[c.algorithm].origin, contract=refs[c.algorithm].contract)
                        for c in task.configs]
                tally = ExecutionStats(backend="dask")
            for row in rows:
                emit_row(row, on_row, stats)
            stats.merge_counts(tally)
            submit_next()
    finally:
        if futures:
            client.cancel(list(futures))
        client.close()
