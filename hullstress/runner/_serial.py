"""The in-process backend (``--workers 0``): no isolation, for debugging.

A segfault ends the run, and the per-call timeout is best effort: a SIGALRM
interrupts Python code (the row is ``timeout``, as in an isolated run) but
not a hang inside C code.  Use it to step through an algorithm in a debugger
or to profile, not to sweep untrusted code.  It runs the same
:func:`~hullstress.runner._protocol.run_job` as the workers, so its rows are
the ones an isolated run gives for every call that returns.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from ..results import ResultRow
from ._protocol import Job, emit_row, run_job
from ._types import ExecutionStats, RunnerOptions, Task

__all__ = ["run_serial"]


def run_serial(
    tasks: Sequence[Task],
    options: RunnerOptions,
    on_row: Callable[[ResultRow], None],
    stats: ExecutionStats,
    budget_deadline: float | None,
) -> None:
    """Run every task here, in order, updating ``stats``; stop starting calls at ``budget_deadline``."""
    for task in tasks:
        if budget_deadline is not None and time.time() >= budget_deadline:
            stats.budget_exhausted = True
            return
        job = Job(task=task, qhull=options.qhull, budget_deadline=budget_deadline, qhull_options=options.qhull_options)
        for message in run_job(job, alarm_after=options.timeout):
            kind = message[0]
            if kind == "row":
                emit_row(message[2], on_row, stats)
            elif kind == "start":
                stats.calls_started += 1
            elif kind == "facts":
                stats.facts_seconds += message[3]
            elif kind == "stopped":
                stats.budget_exhausted = True
