"""The isolated worker process: receives jobs on a pipe, sends protocol messages back.

A worker runs untrusted code, so it is set up to fail in recordable ways:

* an address-space limit (``RLIMIT_AS``) turns a runaway allocation into
  ``MemoryError`` (an ``error`` row naming the limit) or, failing that, into
  the death of this process (a ``crash`` row) instead of the machine swapping
  or the OOM killer picking a victim.  The limit counts what the code under
  test and its check allocate: it is set to the worker's own address space
  once its libraries are loaded (about 0.5 GiB of mappings, most never
  touched) plus ``--memory-limit``.  An address-space limit below what a
  process maps already refuses only new mappings, which a warm worker rarely
  needs: that is why ``--memory-limit 1`` used to change nothing;
* it leads a process group of its own, which the programs it starts
  (``--exec``) share: the pool kills the group, so a hung program dies with
  its worker (:mod:`hullstress.adapters.exec_process`);
* SIGINT is ignored: Ctrl-C in a terminal reaches the whole process group,
  and it is the parent's job to stop the sweep and kill the workers;
* on Linux, ``PR_SET_PDEATHSIG`` kills it when its parent (the fork server)
  goes, so a worker stuck in a hang cannot outlive a killed run;
* BLAS/OpenMP pools are limited to one thread: the parallelism is the workers;
* whatever a call writes on stdout or stderr is captured into its row
  (:func:`hullstress.runner._protocol.captured_output`), so thousands of
  library warnings never reach the terminal.
"""

from __future__ import annotations

import os
import signal
from multiprocessing.connection import Connection

from ..adapters.exec_process import programs_die_with_process_group
from ..forkserver import die_with_parent

__all__ = ["worker_main", "THREAD_ENV", "DEFERRED_MESSAGES"]

#: Messages a worker holds back until the next one, and sends with it in one pipe
#: write: a row (or the case facts) and the start of the next call travel together.
#: Only a few lines of trusted harness code run between such a message and the
#: next one; every message that precedes untrusted or long work (``start``,
#: ``called``, ``facts-start``) and the end of a task (``done``, ``stopped``) is
#: sent at once, so the parent always knows which call a dead or hung worker was in.
DEFERRED_MESSAGES = frozenset({"row", "facts"})

#: Environment that keeps numerical libraries single-threaded inside a worker.
THREAD_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
}


def address_space_bytes() -> int:
    """The address space this process maps now (``/proc/self/statm``), or 0 where that is not known."""
    try:
        with open("/proc/self/statm", encoding="ascii") as fh:
            pages = int(fh.read().split()[0])
        return pages * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        return 0


def _limit_memory(limit_bytes: int | None) -> None:
    """Let this process map ``limit_bytes`` more than it maps now (``RLIMIT_AS``); name the limit in rows."""
    if not limit_bytes:
        return
    try:
        import resource
    except ImportError:  # not POSIX
        return
    from ._protocol import note_memory_limit

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    total = address_space_bytes() + limit_bytes
    if hard != resource.RLIM_INFINITY:
        total = min(total, hard)
    try:
        resource.setrlimit(resource.RLIMIT_AS, (total, hard))
    except (ValueError, OSError):
        return  # e.g. macOS refuses RLIMIT_AS: the run's notes say limits are best effort
    note_memory_limit(limit_bytes)


def worker_main(conn: Connection, limit_bytes: int | None) -> None:
    """Serve jobs from ``conn`` until it sends None or closes.

    Parameters
    ----------
    conn : multiprocessing.connection.Connection
        Receives pickled :class:`~hullstress.runner._protocol.Job` objects (or
        None to stop); protocol messages go back on it, as lists (see
        :data:`DEFERRED_MESSAGES`).
    limit_bytes : int or None
        Address-space limit for this process.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()
    programs_die_with_process_group()
    for key, value in THREAD_ENV.items():
        os.environ.setdefault(key, value)

    from .._registry import load_builtins
    from ._protocol import ensure_algorithm, run_job

    load_builtins()
    _limit_memory(limit_bytes)  # from the address space of a worker with its libraries loaded
    problems: dict[str, str | None] = {}
    while True:
        try:
            job = conn.recv()
        except (EOFError, OSError):
            return  # the parent is gone
        if job is None:
            return
        for ref in job.refs:
            if problems.get(ref.name, "") is not None:  # new, or loaded: (re)syncs options such as clockwise
                problems[ref.name] = ensure_algorithm(ref)
        known = {name: why for name, why in problems.items() if why is not None}
        try:
            held: list[tuple] = []
            for message in run_job(job, known):
                held.append(message)
                if message[0] not in DEFERRED_MESSAGES:
                    conn.send(held)
                    held = []
        except (BrokenPipeError, ConnectionResetError):
            return
