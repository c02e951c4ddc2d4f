"""A pool of isolated worker processes with per-call timeouts, replaced one by one when they die.

Why not ``concurrent.futures``: a process pool there cannot kill one hung
worker, and a dead worker breaks the whole pool.  Here every worker is a
``multiprocessing.Process`` with its own duplex pipe; the parent waits on all
pipes and process sentinels at once, kills a worker whose call overruns, and
starts a fresh one for the rest of that worker's tasks.

Start method: ``forkserver`` (``spawn`` where it does not exist).  Plain
``fork`` would be faster to set up and would inherit every registered
plug-in, but it copies the parent mid-flight: the parent may run threads (a
Dask worker's event loop, a progress bar, BLAS pools), and a child forked
while another thread holds a lock can deadlock (Python 3.12 warns about
exactly this).  The fork server is a clean single-threaded process that has
imported NumPy, SciPy and hullstress once (``_preload``), so a new worker is
a cheap fork of it.  The price is that workers do not inherit algorithms
registered at run time: each job carries an :class:`AlgorithmRef` per
algorithm, and the worker imports the defining module (``--plugin`` files by
path) or unpickles the spec.  As with any ``spawn``/``forkserver`` program, a
script that runs a sweep must guard its entry point with
``if __name__ == "__main__":`` (workers import the main module).

The fork server itself (started early, quietly, with a fixed hash seed for
every worker) lives in :mod:`hullstress.forkserver`.

Messages and their meaning are in :mod:`hullstress.runner._protocol`.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import pickle
import select
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from contextlib import contextmanager
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from typing import Any, Iterator

from ..evaluate import CaseFacts
from ..forkserver import get_context as _get_context, start_method, worker_environment as _worker_environment
from ..results import ResultRow
from ..records import Stage, Status
from ._feed import JobFeed
from ._protocol import AlgorithmRef, Job, death_reason, emit_row, row_for
from ._types import ExecutionStats, Task
from ._worker import worker_main

__all__ = ["WorkerPool", "PoolSettings", "PendingJob", "JobFeed", "start_method", "STREAM_PREFETCH"]

#: Jobs waiting in a busy worker's pipe (prefetch) take at most this many bytes
#: together: they fit the socket buffer, so sending one never blocks the parent.
#: A larger job waits until a worker is idle.
PREFETCH_MAX_BYTES = 32 * 1024
#: Jobs queued per worker by default: the one running plus one waiting in its pipe.
PREFETCH_DEPTH = 2
#: Jobs queued per worker when a caller streams one-call jobs (:meth:`CallPool.stream`, parallel
#: triage): such a job lasts milliseconds, and the parent, which decides the next jobs from the
#: answers and runs at a lower priority than its workers, is not always scheduled before a worker
#: ends two of them.  Measured on the quick profile's triage, 2 workers on 2 cores: idle CPU
#: 1.65 core-seconds with 2 jobs per worker, 1.17 with 3, 0.95 with 4, 0.79 with 6, 0.60 with 8.
STREAM_PREFETCH = 8
#: A task whose worker dies this often outside any call is given up on.
MAX_DEATHS_OUTSIDE_CALLS = 2

_HAVE_POLL = hasattr(select, "poll")
# Starting a child flips the (process-wide) daemon flag in a daemonic parent; serialise starts.
_start_lock = threading.Lock()


def _kill_group(proc: Any) -> None:
    """Kill a worker and the programs it started (``--exec``): they share its process group.

    A worker leads its own group from its first instructions
    (:func:`hullstress.adapters.exec_process.programs_die_with_process_group`); one
    killed before that has no group yet, and started no program.
    """
    try:
        if proc.pid is not None and os.getpgid(proc.pid) == proc.pid:
            os.killpg(proc.pid, signal.SIGKILL)
            return
    except (OSError, AttributeError):  # no such group yet, or no process groups here
        pass
    proc.kill()


@contextmanager
def _children_allowed() -> Iterator[None]:
    """Let a daemonic process (a Dask nanny's worker) start worker processes.

    multiprocessing refuses children of daemonic processes so that they cannot
    be orphaned.  Ours are daemonic themselves, exit at EOF on their pipe and
    (on Linux) are killed with their parent, so they cannot outlive this process.
    """
    me = multiprocessing.current_process()
    if not me.daemon:
        yield
        return
    me.daemon = False
    try:
        yield
    finally:
        me.daemon = True


@dataclass(frozen=True)
class PoolSettings:
    """Per-run limits and context the pool needs to build jobs and rows.

    Attributes
    ----------
    timeout : float
        Per-call limit in seconds.
    check_timeout : float
        Limit on each trusted step (facts, one check) and on a worker's silence between steps.
    qhull : bool
    qhull_options : str or None
        Qhull options tried first for the reference hull.
    budget_deadline : float or None
        ``time.time()`` after which no new call starts.
    refs : mapping of str to AlgorithmRef
        For every algorithm the tasks use.
    prefetch : int
        Jobs queued per worker: the one running and ``prefetch - 1`` waiting
        in its pipe (within :data:`PREFETCH_MAX_BYTES`), so that a worker
        that ends a job starts the next one without waiting for the parent.
    on_idle : callable or None
        Called once, the first time a worker has nothing left to run while
        others still work (every job is sent: the run's tail), so that the
        caller can start work of its own on the core that frees.
    """

    timeout: float
    check_timeout: float
    qhull: bool = True
    budget_deadline: float | None = None
    refs: dict[str, AlgorithmRef] = field(default_factory=dict)
    qhull_options: str | None = None
    prefetch: int = PREFETCH_DEPTH
    on_idle: Callable[[], None] | None = None

    def budget_over(self) -> bool:
        return self.budget_deadline is not None and time.time() >= self.budget_deadline


@dataclass
class PendingJob:
    """A task the parent still owes rows for, and where to resume it."""

    task: Task
    start_at: int = 0
    facts: CaseFacts | None = None
    deaths: int = 0
    #: Compute the Qhull reference with the case facts (None: the run's ``PoolSettings.qhull``).
    qhull: bool | None = None
    #: Run only in a worker that has run nothing else since it started: whether native code
    #: dies can depend on what its process did before (memory left by earlier calls), and a
    #: crash is then judged the same way on every run and with any number of workers.
    fresh_worker: bool = False
    # The pickled job for ``start_at`` (a job that waits for an idle worker is looked at many times).
    wire: tuple[int, bytes] | None = field(default=None, repr=False)

    @property
    def finished(self) -> bool:
        return self.start_at >= len(self.task.configs)


def _ready(fds: list[int], timeout: float) -> set[int]:
    """The descriptors of ``fds`` that are readable or closed, after waiting at most ``timeout`` seconds.

    ``poll(2)`` with a fresh poller: the parent waits once or twice per call,
    and ``multiprocessing.connection.wait`` (and ``Connection.poll``, which
    goes through it) builds a Python selector each time, most of the parent's
    own time per call.  Where ``poll`` is missing, that portable wait.
    """
    if not _HAVE_POLL:
        return set(wait(fds, timeout))
    poller = select.poll()
    for fd in fds:
        poller.register(fd, select.POLLIN)
    # Rounded up: waking before the deadline would only spin.
    return {fd for fd, _ in poller.poll(math.ceil(timeout * 1000) if timeout > 0 else 0)}


class _Start:
    """A worker process being started in a background thread, and what came of it."""

    def __init__(self, thread: threading.Thread) -> None:
        self.thread = thread
        self.result: tuple[Any, Connection] | BaseException | None = None


class _Slot:
    """One worker process and what the parent knows about its progress."""

    def __init__(self, index: int) -> None:
        self.index = index
        self.proc: Any = None
        self.conn: Connection | None = None
        self.jobs: deque[PendingJob] = deque()
        #: Jobs sent to the current worker since it started (0: a fresh worker).
        self.served = 0
        #: A worker being started in the background for this slot (see WorkerPool._begin_start).
        self.starting: _Start | None = None
        self.reset_state()

    def reset_state(self) -> None:
        # phase: "idle" (no job), "setup" (job sent, nothing heard), "facts",
        # "between" (between steps), "call", "check"
        self.phase = "idle"
        self.k = -1
        self.t0 = time.monotonic()
        self.call_seconds = 0.0
        self.facts_info: tuple[bool | None, str | None] = (None, None)

    @property
    def alive(self) -> bool:
        return self.proc is not None


class WorkerPool:
    """Isolated worker processes that run tasks and survive whatever the code under test does.

    Parameters
    ----------
    size : int
        Number of worker processes (started on first use, replaced when they die).
    memory_limit_bytes : int or None
        Address-space limit for each worker.

    Notes
    -----
    A pool can be reused across :meth:`run` calls (the single-call runner and
    the Dask backend keep one alive); :meth:`close` stops its workers.  If
    :meth:`run` is interrupted (Ctrl-C, SIGTERM) every worker is killed, so
    no call keeps running after the sweep stopped.
    """

    def __init__(self, size: int, *, memory_limit_bytes: int | None = None) -> None:
        if size < 1:
            raise ValueError(f"size must be at least 1, got {size}")
        self.memory_limit_bytes = memory_limit_bytes
        self._slots = [_Slot(i) for i in range(size)]
        self.restarts = 0
        # Written by a background start when its worker is up, to wake the loop waiting on its workers
        # (made when first needed, closed with the pool).
        self._wake: tuple[int, int] | None = None
        self._fresh_waiting: deque[PendingJob] = deque()  # jobs for a fresh worker, stepped aside
        self._held: int | None = None  # the slot kept free of other jobs to be retired for them
        self._on_idle: Callable[[], None] | None = None  # settings.on_idle until it is called

    @property
    def size(self) -> int:
        return len(self._slots)

    # -- worker processes -------------------------------------------------

    def _new_worker(self, index: int) -> tuple[Any, Connection]:
        """Start a worker process (blocks until the fork server reports it): the process and its pipe."""
        ctx = _get_context()
        parent_end, child_end = ctx.Pipe(duplex=True)
        proc = ctx.Process(target=worker_main, args=(child_end, self.memory_limit_bytes),
                           name=f"hullstress-worker-{index}", daemon=True)
        with _start_lock, _children_allowed(), _worker_environment():
            proc.start()
        child_end.close()
        return proc, parent_end

    def _wake_pipe(self) -> tuple[int, int]:
        """The (read, write) ends of the wake-up pipe of background starts."""
        if self._wake is None:
            read, write = os.pipe()
            os.set_blocking(read, False)
            self._wake = (read, write)
        return self._wake

    def _begin_start(self, slot: _Slot) -> None:
        """Start ``slot``'s worker in a background thread; :meth:`_adopt_started` takes it in.

        Starting a worker waits for the fork server to fork (2 to 15 ms, more on
        a busy machine); done in the loop, that wait stopped the other workers'
        rows and jobs too, after every crash and timeout.
        """
        _get_context()  # the fork server starts (with its output redirected) here, never in a thread
        wake = self._wake_pipe()[1]

        def run() -> None:
            try:
                start.result = self._new_worker(slot.index)
            except BaseException as exc:  # given to the loop, which raises it
                start.result = exc
            finally:
                try:
                    os.write(wake, b"!")
                except OSError:
                    pass  # the pool is closed

        start = _Start(threading.Thread(target=run, name=f"hullstress-start-{slot.index}", daemon=True))
        slot.starting = start
        start.thread.start()

    def _adopt_started(self, *, wait: bool = False) -> None:
        """Take in the workers whose background start has ended (waiting for them with ``wait``)."""
        if self._wake is not None:
            try:
                while os.read(self._wake[0], 4096):
                    pass
            except (BlockingIOError, OSError):
                pass
        for slot in self._slots:
            start = slot.starting
            # Done when it has a result (set before its wake-up byte; the thread may still be ending).
            if start is None or (start.result is None and not wait):
                continue
            start.thread.join()
            slot.starting = None
            if isinstance(start.result, BaseException):
                raise start.result
            assert start.result is not None
            slot.proc, slot.conn = start.result
            slot.served = 0
            slot.reset_state()

    def _kill(self, slot: _Slot) -> int | None:
        """Kill (if still running) and reap ``slot``'s worker; return its exit code."""
        proc = slot.proc
        if proc is None:
            return None
        if proc.is_alive():
            _kill_group(proc)
        proc.join(5.0)
        code = proc.exitcode
        if slot.conn is not None:
            slot.conn.close()
        try:
            proc.close()
        except ValueError:
            pass  # still running after SIGKILL and 5 s: leave it to the OS
        slot.proc, slot.conn = None, None
        return code

    def close(self) -> None:
        """Stop every worker (politely, then by force)."""
        self._adopt_quietly()
        for slot in self._slots:
            if slot.proc is None:
                continue
            try:
                assert slot.conn is not None
                slot.conn.send(None)
            except (OSError, ValueError):
                pass
        deadline = time.monotonic() + 1.0
        for slot in self._slots:
            if slot.proc is not None:
                slot.proc.join(max(0.0, deadline - time.monotonic()))
                self._kill(slot)
            slot.jobs.clear()
            slot.reset_state()
        if self._wake is not None:
            for fd in self._wake:
                os.close(fd)
            self._wake = None

    def _adopt_quietly(self) -> None:
        """Wait for background starts and take their workers in (to stop them); a failed start is moot now."""
        try:
            self._adopt_started(wait=True)
        except BaseException:
            for slot in self._slots:
                slot.starting = None

    def kill_all(self) -> None:
        """Kill every worker at once (interruption)."""
        self._adopt_quietly()
        for slot in self._slots:
            if slot.proc is not None and slot.proc.is_alive():
                _kill_group(slot.proc)
        for slot in self._slots:
            self._kill(slot)
            slot.jobs.clear()
            slot.reset_state()

    # -- running ----------------------------------------------------------

    def run(
        self,
        jobs: Iterable[PendingJob],
        settings: PoolSettings,
        on_row: Callable[[ResultRow], None],
        stats: ExecutionStats,
    ) -> None:
        """Run ``jobs`` to completion (or until the budget), calling ``on_row`` per row as it arrives.

        Parameters
        ----------
        jobs : iterable of PendingJob
        settings : PoolSettings
        on_row : callable
            Receives every row; may raise (e.g. KeyboardInterrupt) to stop the run.
        stats : ExecutionStats
            Updated in place: calls, busy times, restarts, budget.
        """
        self.serve(deque(j for j in jobs if not j.finished), settings, on_row, stats)

    def serve(self, queue: "deque[PendingJob] | JobFeed", settings: PoolSettings,
              on_row: Callable[[ResultRow], None], stats: ExecutionStats) -> None:
        """Run the jobs of ``queue`` until it is empty and every worker idle, as :meth:`run` does.

        ``queue`` may grow while it runs: ``on_row`` may add jobs to it (a
        :class:`JobFeed`, most urgent first), and they are sent as workers
        have room, so a caller that decides its next jobs from the rows it
        gets never waits for a whole batch.
        """
        self._fresh_waiting.clear()
        self._held = None
        self._on_idle = settings.on_idle
        try:
            self._loop(queue, settings, on_row, stats)
        except BaseException:
            self.kill_all()
            raise

    def _loop(self, queue: deque[PendingJob], settings: PoolSettings,
              on_row: Callable[[ResultRow], None], stats: ExecutionStats) -> None:
        while True:
            self._adopt_started()
            self._fill(queue, settings, stats)
            busy = [s for s in self._slots if s.jobs]
            unsent = bool(queue) or bool(self._fresh_waiting)
            starting = unsent and any(s.starting is not None for s in self._slots)
            if not busy and not starting:
                if unsent:  # only the budget leaves work unsent
                    stats.budget_exhausted = True
                return
            if self._on_idle is not None and not unsent and len(busy) < len(self._slots):
                idle, self._on_idle = self._on_idle, None
                idle()
            now = time.monotonic()
            next_deadline = min((s.t0 + self._limit(s, settings) for s in busy), default=now + settings.check_timeout)
            fds = [fd for s in busy for fd in (s.conn.fileno(), s.proc.sentinel)]
            ready = _ready(fds + [self._wake_pipe()[0]] if starting else fds, max(0.0, next_deadline - now))
            for s in busy:
                message, dead = s.conn.fileno() in ready, s.proc.sentinel in ready
                if not (message or dead):
                    continue
                # Read everything the worker sent before looking at how it ended:
                # the last "start" names the call that was running when it died.
                if not self._drain(s, settings, on_row, stats) or dead:
                    self._on_death(s, queue, settings, on_row, stats, kill_reason=None)
            now = time.monotonic()
            for s in busy:
                if s.jobs and s.alive and now - s.t0 > self._limit(s, settings):
                    # Messages may be waiting that end the overrun step: read them first.
                    if not self._drain(s, settings, on_row, stats):
                        self._on_death(s, queue, settings, on_row, stats, kill_reason=None)
                    elif s.jobs and time.monotonic() - s.t0 > self._limit(s, settings):
                        self._on_death(s, queue, settings, on_row, stats, kill_reason="limit")

    @staticmethod
    def _limit(slot: _Slot, settings: PoolSettings) -> float:
        return settings.timeout if slot.phase == "call" else settings.check_timeout

    def _fill(self, queue: deque[PendingJob], settings: PoolSettings, stats: ExecutionStats) -> None:
        """Send jobs to workers with room, least loaded first; a job for a fresh worker to a fresh one."""
        broken: set[int] = set()
        while True:
            # A job that needs a fresh worker steps aside, so that the others keep flowing
            # while a worker is retired and restarted for it.
            while queue and queue[0].fresh_worker:
                self._fresh_waiting.append(queue.popleft())
            if not queue and not self._fresh_waiting:
                return
            if settings.budget_over():
                stats.budget_exhausted = True
                return
            for s in self._slots:
                if not s.alive and s.starting is None:
                    self._begin_start(s)
            open_slots = [s for s in self._slots if s.alive and s.index not in broken]
            if not open_slots:
                return
            held = None
            if self._fresh_waiting:
                fresh, held = self._fresh_target(open_slots)
                if fresh is not None:
                    self._send(fresh, self._fresh_waiting, settings, stats, broken)
                    continue
            others = [s for s in open_slots if s is not held and s.alive]  # (one may have been retired)
            if not queue or not others:
                return
            slot = min(others, key=lambda s: len(s.jobs))
            if len(slot.jobs) >= max(1, settings.prefetch):
                return
            if slot.jobs and self._waiting_bytes(slot, settings) + len(self._payload(queue[0], settings)) \
                    > PREFETCH_MAX_BYTES:
                return  # it waits until a worker has room, so the send cannot block
            self._send(slot, queue, settings, stats, broken)

    def _waiting_bytes(self, slot: _Slot, settings: PoolSettings) -> int:
        """Bytes of the jobs sent to ``slot`` behind the one it runs (still in its pipe)."""
        return sum(len(self._payload(job, settings)) for job in list(slot.jobs)[1:])

    def _send(self, slot: _Slot, queue: deque[PendingJob], settings: PoolSettings, stats: ExecutionStats,
              broken: set[int]) -> None:
        """Send the first job of ``queue`` to ``slot``; if the worker is gone, the job goes back to ``queue``."""
        job = queue.popleft()
        assert slot.conn is not None
        try:
            slot.conn.send_bytes(self._payload(job, settings))
        except OSError:
            # The worker is gone; nothing of this job ran.
            queue.appendleft(job)
            if slot.jobs:
                # It died during an earlier job: the main loop reads what it
                # sent and records the call it died in before replacing it.
                broken.add(slot.index)
            else:
                self._restart_after_death(slot, stats)
            return
        if not slot.jobs:
            slot.phase, slot.t0 = "setup", time.monotonic()
        slot.jobs.append(job)
        slot.served += 1

    def _fresh_target(self, open_slots: list[_Slot]) -> tuple[_Slot | None, _Slot | None]:
        """For the next job that needs a fresh worker: (an idle one that has run nothing, a slot held back).

        Without an idle fresh worker, and none starting, one worker is held
        back from other jobs until it is idle, then retired (not counted as
        a restart) and started again in the background; the loop wakes when
        it is up.
        """
        fresh = next((s for s in open_slots if not s.jobs and s.served == 0), None)
        if fresh is not None:
            return fresh, None
        if any(s.starting is not None for s in self._slots):
            return None, None  # a fresh worker is on its way
        held = self._slots[self._held] if self._held is not None else None
        if held is None or not held.alive:
            held = min(open_slots, key=lambda s: (len(s.jobs), s.index))
            self._held = held.index
        if held.jobs:
            return None, held
        self._kill(held)
        held.reset_state()
        self._held = None
        self._begin_start(held)
        return None, None

    @staticmethod
    def _payload(job: PendingJob, settings: PoolSettings) -> bytes:
        if job.wire is not None and job.wire[0] == job.start_at:
            return job.wire[1]
        names = dict.fromkeys(c.algorithm for c in job.task.configs[job.start_at:])
        refs = tuple(settings.refs[n] for n in names if n in settings.refs)
        qhull = settings.qhull if job.qhull is None else job.qhull
        wire = Job(task=job.task, start_at=job.start_at, qhull=qhull, facts=job.facts,
                   refs=refs, budget_deadline=settings.budget_deadline, qhull_options=settings.qhull_options)
        payload = pickle.dumps(wire, protocol=pickle.HIGHEST_PROTOCOL)
        job.wire = (job.start_at, payload)
        return payload

    def _drain(self, slot: _Slot, settings: PoolSettings, on_row: Callable[[ResultRow], None],
               stats: ExecutionStats) -> bool:
        """Handle every message waiting from ``slot``; False when the worker is gone."""
        conn = slot.conn
        assert conn is not None
        try:
            while conn.fileno() in _ready([conn.fileno()], 0.0):
                batch = conn.recv()  # a list: a row and the next call's start arrive together
                if not isinstance(batch, list):
                    raise pickle.UnpicklingError(f"unexpected worker message {type(batch).__name__}")
                for msg in batch:
                    self._handle(slot, msg, settings, on_row, stats)
        except (EOFError, OSError, pickle.UnpicklingError):
            return False
        return True

    def _handle(self, slot: _Slot, msg: tuple[Any, ...], settings: PoolSettings,
                on_row: Callable[[ResultRow], None], stats: ExecutionStats) -> None:
        kind = msg[0]
        job = slot.jobs[0]
        if kind == "start":
            slot.phase, slot.k, slot.t0 = "call", msg[1], msg[2]
            stats.calls_started += 1
        elif kind == "called":
            slot.phase, slot.t0, slot.call_seconds = "check", msg[2], msg[3]
        elif kind == "row":
            slot.phase, slot.t0 = "between", time.monotonic()
            job.start_at = msg[1] + 1
            emit_row(msg[2], on_row, stats)
        elif kind == "facts-start":
            slot.phase, slot.t0 = "facts", msg[1]
        elif kind == "facts":
            slot.phase, slot.t0 = "between", time.monotonic()
            slot.facts_info = (msg[1], msg[2])
            stats.facts_seconds += msg[3]
        elif kind == "stopped":
            stats.budget_exhausted = True
            job.start_at = len(job.task.configs)
        elif kind == "done":
            slot.jobs.popleft()
            slot.reset_state()
            if slot.jobs:
                slot.phase = "setup"
        else:
            raise pickle.UnpicklingError(f"unknown worker message {kind!r}")

    def _on_death(self, slot: _Slot, queue: deque[PendingJob], settings: PoolSettings,
                  on_row: Callable[[ResultRow], None], stats: ExecutionStats, *, kill_reason: str | None) -> None:
        """Record what the worker was doing when it died (or was killed), requeue the rest, replace it."""
        phase, k, t0, facts_info = slot.phase, slot.k, slot.t0, slot.facts_info
        call_seconds = slot.call_seconds
        limit = self._limit(slot, settings)
        jobs = list(slot.jobs)
        elapsed = time.monotonic() - t0
        code = self._kill(slot)
        how = death_reason(code)
        if jobs:
            job = jobs[0]
            task, n = job.task, len(job.task.configs)
            origin = self._origin(task, k, settings) if 0 <= k < n else None
            contract = self._contract(task, k, settings) if 0 <= k < n else None
            if phase == "call":
                if kill_reason:
                    row = row_for(task, k, status=Status.TIMEOUT, reason=f"exceeded {float(settings.timeout)} s",
                                  origin=origin, facts_info=facts_info, seconds=elapsed, contract=contract)
                else:
                    row = row_for(task, k, status=Status.CRASH, reason=how, origin=origin,
                                  facts_info=facts_info, seconds=elapsed, contract=contract)
                job.start_at = k + 1
                emit_row(row, on_row, stats)
            elif phase == "check":
                why = f"exceeded {limit:g} s" if kill_reason else f"crashed ({how})"
                emit_row(row_for(task, k, status=Status.ERROR, reason=f"internal: checker {why}", origin=origin,
                              facts_info=facts_info, seconds=call_seconds, check_seconds=elapsed,
                              stage=Stage.CHECK, contract=contract), on_row, stats)
                job.start_at = k + 1
            elif phase == "facts":
                why = f"exceeded {limit:g} s" if kill_reason else f"crashed ({how})"
                self._give_up(job, f"internal: case facts {why}", settings, on_row, stats)
            else:
                job.deaths += 1
                if job.deaths >= MAX_DEATHS_OUTSIDE_CALLS:
                    why = f"stalled for {limit:g} s" if kill_reason else f"died ({how})"
                    self._give_up(job, f"internal: worker {why} outside any call, {job.deaths} times",
                                  settings, on_row, stats)
            if job.finished:
                jobs = jobs[1:]
            # The rest goes first to the next free worker (which recomputes the case facts).
            queue.extendleft(reversed(jobs))
        self._restart_after_death(slot, stats)

    def _restart_after_death(self, slot: _Slot, stats: ExecutionStats) -> None:
        if slot.proc is not None:
            self._kill(slot)
        slot.jobs.clear()
        slot.reset_state()
        self.restarts += 1
        stats.worker_restarts += 1
        # The replacement starts when the next job needs a worker (_fill), in the background.

    @staticmethod
    def _origin(task: Task, k: int, settings: PoolSettings) -> str | None:
        ref = settings.refs.get(task.configs[k].algorithm)
        return ref.origin if ref is not None else None

    @staticmethod
    def _contract(task: Task, k: int, settings: PoolSettings) -> str | None:
        ref = settings.refs.get(task.configs[k].algorithm)
        return ref.contract if ref is not None else None

    def _give_up(self, job: PendingJob, reason: str, settings: PoolSettings,
                 on_row: Callable[[ResultRow], None], stats: ExecutionStats) -> None:
        for k in range(job.start_at, len(job.task.configs)):
            emit_row(row_for(job.task, k, status=Status.ERROR, reason=reason, origin=self._origin(job.task, k, settings),
                          facts_info=(None, None), stage=Stage.CHECK,
                          contract=self._contract(job.task, k, settings)), on_row, stats)
        job.start_at = len(job.task.configs)
