"""The fork server every isolated worker process is forked from, started once per run, early.

The fork server is a clean single-threaded process that imports NumPy, SciPy
and hullstress once (:mod:`hullstress.runner._preload`); each worker (and each
helper of the report) is then a cheap fork of it, not a fresh interpreter.
Its imports take about 0.6 s, and no worker can start before they are done.
So ``python -m hullstress run`` starts it first of all, from this module,
which imports nothing heavy: the fork server then loads while the run's own
process imports pandas and builds the cases, instead of after.

Why a fork server and not ``fork``, and how workers find algorithms
registered at run time: :mod:`hullstress.runner._pool`.

The fork server (and so every worker) starts with stdout and stderr on
``/dev/null`` (:func:`get_context`): a worker's own messages are captured per
call into its rows, and what a dying worker or a half-started one (an
interrupt while it is forked) prints outside a call is noise for the
terminal.  ``HULLSTRESS_DEBUG=1`` keeps them.

Workers start with ``PYTHONHASHSEED=0`` (:data:`WORKER_ENV`): string hashing,
and so the iteration order of sets of strings in the code under test, is the
same in every worker, run and backend.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["WORKER_ENV", "current_niceness", "die_with_parent", "get_context", "helper_start", "start_method",
           "take_niceness", "worker_environment"]

#: Environment every worker process starts with (unless the user set these).
#: A fixed hash seed makes ``set``/``dict`` order of strings and bytes the
#: same in every worker, run and backend, so code under test that iterates
#: such a set (Qhull's option list in scipy does) behaves the same everywhere.
WORKER_ENV = {"PYTHONHASHSEED": "0"}

#: What the fork server imports before it forks anything.
_PRELOAD = ["hullstress.runner._preload", "__main__"]
_context_lock = threading.Lock()
_context: Any = None


def start_method() -> str:
    """The multiprocessing start method workers use: ``forkserver`` where available, else ``spawn``.

    The first call starts the fork server (see :func:`get_context`).
    """
    return get_context().get_start_method()


def get_context() -> Any:
    """The multiprocessing context of the workers; the first call starts the fork server, quietly.

    Returns at once: the fork server imports in its own process, and the
    first process forked from it waits until it has.
    """
    global _context
    with _context_lock:
        if _context is None:
            if "forkserver" in multiprocessing.get_all_start_methods():
                ctx = multiprocessing.get_context("forkserver")
                # Takes effect only if the fork server is not running yet;
                # otherwise workers import what they need themselves (slower starts).
                ctx.set_forkserver_preload(_PRELOAD)
                _start_forkserver_quietly()
            else:
                ctx = multiprocessing.get_context("spawn")
            _context = ctx
        return _context


@contextmanager
def worker_environment() -> Iterator[None]:
    """Set :data:`WORKER_ENV` while a child (or the fork server) is spawned; restore afterwards."""
    added = [k for k in WORKER_ENV if k not in os.environ]
    for key in added:
        os.environ[key] = WORKER_ENV[key]
    try:
        yield
    finally:
        for key in added:
            os.environ.pop(key, None)


def _start_forkserver_quietly() -> None:
    """Start the fork server now, with its stdout and stderr (which workers inherit) on /dev/null."""
    if os.environ.get("HULLSTRESS_DEBUG"):
        return
    from multiprocessing import forkserver

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, ValueError, OSError):
            pass
    devnull = os.open(os.devnull, os.O_WRONLY)
    saved = [os.dup(1), os.dup(2)]
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        with worker_environment():
            forkserver.ensure_running()
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (devnull, *saved):
            os.close(fd)


def current_niceness() -> int:
    """This process's ``nice`` value (0 where the platform has none)."""
    try:
        return os.nice(0)
    except (AttributeError, OSError):
        return 0


def take_niceness(niceness: int) -> None:
    """Lower this process's priority to ``niceness`` (never raise it; best effort).

    A process forked from the fork server starts at the fork server's
    priority, not at the run's (``python -m hullstress run`` lowers its own
    once the fork server runs, so that the workers go first).  A helper that
    shares the run's own work, not the workers', takes the run's priority:
    otherwise, in the report, two helpers would leave the run's process,
    which writes the folders, a tenth of a core.
    """
    try:
        now = os.nice(0)
        if niceness > now:
            os.nice(niceness - now)
    except (AttributeError, OSError):
        pass


def die_with_parent() -> None:
    """On Linux, have this process killed (SIGKILL) when its parent dies (``PR_SET_PDEATHSIG``).

    Workers and the report's helpers call it first thing: their parent is
    the fork server, which ends with the run, so none outlives a killed run
    waiting on a pipe or hung in a call.  Best effort elsewhere (the pipe's
    end of file still ends an idle worker).
    """
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, int(signal.SIGKILL), 0, 0, 0)
    except (OSError, AttributeError):
        pass  # best effort: the pipe's EOF still ends an idle worker


def helper_start(niceness: int) -> None:
    """What a helper forked from the fork server does first: its priority, and leaving with the run.

    Every child of the fork server holds the fork server's own lifeline (so
    multiprocessing has it), and the fork server lives until its children
    are gone: a helper must leave by itself when the run is killed, at the
    end of file (or broken pipe) of the pipe it shares with the run.

    Parameters
    ----------
    niceness : int
        The ``nice`` value to take (:func:`take_niceness`).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the run decides when its helpers stop
    take_niceness(niceness)
    die_with_parent()
