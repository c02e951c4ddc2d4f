"""The in-process backend (``--workers 0``): no isolation, for debugging.

A segfault ends the run, and the per-call timeout is best effort: a SIGALRM
interrupts Python code (the row is ``timeout``, as in an isolated run) but
not a hang inside C code.  Use it to step through an algorithm in a debugger
or to profile, not to sweep untrusted code.  It runs the same
:func:`~hullstress.runner._protocol.run_job` as the workers, so its rows are
the ones an isolated run gives for every call that returns.
"""

from __future__ import annotations

import faulthandler
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from ..results import ResultRow
from ._protocol import Job, emit_row, run_job
from ._types import ExecutionStats, RunnerOptions, Task

__all__ = ["run_serial", "no_isolation_warning", "crash_log", "CRASH_LOG"]

#: In the run folder of a run without isolation: what Python's faulthandler wrote when the code under
#: test killed the process (SIGSEGV, SIGFPE, SIGABRT, SIGBUS, SIGILL); absent when nothing crashed.
CRASH_LOG = "crash.log"


def no_isolation_warning(run_dir: Path) -> str:
    """The one line a run without isolation starts with: what a crash does, and the command to run after one."""
    from ..report.failures import report_run_command

    return (f"warning: --workers 0 runs the code under test in this process, without isolation: a crash of it "
            f"ends the run (no --memory-limit; a timeout stops only Python code); finished rows stay in "
            f"{Path(run_dir) / 'results.partial.csv'}, and `{report_run_command(run_dir)}` triages them into a report")


@contextmanager
def crash_log(run_dir: Path, *, enabled: bool = True) -> Iterator[None]:
    """While the sweep runs in this process, a fatal signal leaves its traceback in ``run_dir/crash.log``.

    The process still dies (faulthandler re-raises the signal); ``hullstress
    report`` reads the file to say how the run ended.  The file is removed
    when nothing crashed.  A faulthandler enabled before (pytest's) is
    enabled again on ``sys.stderr`` afterwards.
    """
    if not enabled:
        yield
        return
    path = Path(run_dir) / CRASH_LOG
    was_enabled = faulthandler.is_enabled()
    try:
        fh = open(path, "w", encoding="utf-8")
    except OSError:
        yield  # an unwritable run folder is reported by the row stream, not here
        return
    try:
        faulthandler.enable(file=fh, all_threads=False)
        yield
    finally:
        faulthandler.disable()
        fh.close()
        if was_enabled:
            try:
                faulthandler.enable(file=sys.stderr)
            except (ValueError, OSError, AttributeError):
                pass  # stderr without a file descriptor (captured)
        try:
            if os.path.getsize(path) == 0:
                path.unlink()
        except OSError:
            pass


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
