"""What a worker does with one task, as a stream of messages, shared by every backend.

:func:`run_job` is the only place a task is executed: the serial backend
iterates it in-process, an isolated worker sends each message up its pipe, so
rows are identical by construction.  Messages (tuples, first item the kind):

``("facts-start", t)``
    computing case facts began (``t``: ``time.monotonic()`` in the worker).
``("facts", degenerate, invalid_input, seconds)``
    case facts are known.
``("start", k, t)``
    the call of config ``k`` began: the per-call timeout runs from ``t``.
``("called", k, t, seconds)``
    the call returned (or raised); the checker's own limit runs from ``t``.
``("row", k, row)``
    config ``k``'s :class:`~hullstress.results.ResultRow`.
``("stopped", k)``
    the time budget ran out before config ``k``: the rest of the task is not run.
``("done",)``
    the task is finished.

``time.monotonic()`` is system-wide on Linux and macOS, so the parent can
compare a worker's timestamps with its own clock.  An isolated worker sends
the messages in lists, a ``row`` (or ``facts``) with the ``start`` that
follows it (:data:`hullstress.runner._worker.DEFERRED_MESSAGES`): one pipe
write per call fewer, the same information at the same moments.

Each call's own output (a library's warnings and messages on stdout or
stderr, at the file-descriptor level, so C code's too; an executable's
stderr) is captured around the call (:func:`captured_output`) and kept in
the row's ``call_output`` column, never written to the terminal.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import pickle
import re
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from .._registry import ALGORITHMS, AlgorithmSpec, get_algorithm, set_clockwise, set_contract
from ..config import AlgorithmConfig
from ..errors import UsageError, one_line
from ..evaluate import CaseFacts, call_algorithm, case_facts, judge
from ..records import Stage, Status
from ..results import ResultRow, make_row
from ._types import ExecutionStats, Task

__all__ = [
    "AlgorithmRef",
    "Job",
    "algorithm_refs",
    "refs_for_configs",
    "ensure_algorithm",
    "run_job",
    "death_reason",
    "emit_row",
    "one_line",
    "row_for",
    "captured_output",
    "CALL_OUTPUT_CHARS",
]

#: Characters of a call's captured output kept in its row (the tail).
CALL_OUTPUT_CHARS = 2000
# Qhull prints a random run id with its messages; the table must not depend on it.
_RUN_ID = re.compile(r"run-id \d+")


def death_reason(exitcode: int | None) -> str:
    """Describe how a process ended from its exit code.

    Examples
    --------
    >>> death_reason(-11)
    'killed by signal 11 (SIGSEGV)'
    >>> death_reason(3)
    'exited with code 3'
    >>> death_reason(None)
    'died (exit status unknown)'
    """
    if exitcode is None:
        return "died (exit status unknown)"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = "unknown signal"
        return f"killed by signal {-exitcode} ({name})"
    return f"exited with code {exitcode}"


@dataclass(frozen=True)
class AlgorithmRef:
    """How a worker process finds an algorithm registered in the parent.

    Built-in algorithms are registered in every process; plug-ins and
    algorithms registered from user code are not.  The worker imports the
    module that defines the function (a ``--plugin`` file through
    :func:`hullstress.plugins.load_plugin`, which gives it the same module
    name as in the parent) and, if importing did not register the name,
    registers the unpickled spec itself.

    Attributes
    ----------
    name, origin : str
        Registry name and origin (``in-house``, ``adapter``, ``plugin``).
    module : str
        ``__module__`` of the function.
    file : str or None
        The module's file, for modules that are not importable by name.
    spec_pickle : bytes
        The pickled :class:`~hullstress.AlgorithmSpec` (the function by reference).
    clockwise : bool
        The parent's ``clockwise`` flag (``run --clockwise NAME`` sets it on built-ins too).
    contract : str
        The parent's declared contract, as its label (``run --contract NAME=...`` sets it on any algorithm).
    """

    name: str
    origin: str
    module: str
    file: str | None
    spec_pickle: bytes
    clockwise: bool = False
    contract: str = "lenient"


def _ref(spec: AlgorithmSpec) -> AlgorithmRef:
    module = spec.module
    mod = sys.modules.get(module)
    file = getattr(mod, "__file__", None)
    try:
        blob = pickle.dumps(spec)
    except Exception as exc:  # lambdas, closures, functions defined inside functions
        raise UsageError(
            f"algorithm {spec.name!r} ({module}.{getattr(spec.func, '__qualname__', spec.func)}) cannot be sent "
            f"to worker processes ({one_line(exc)}): define it at module level in an importable module or "
            "a --plugin file, or run with --workers 0"
        ) from None
    return AlgorithmRef(name=spec.name, origin=spec.origin, module=module, file=file, spec_pickle=blob,
                        clockwise=spec.clockwise, contract=spec.contract.label)


def algorithm_refs(tasks: list[Task] | tuple[Task, ...]) -> dict[str, AlgorithmRef]:
    """One :class:`AlgorithmRef` per algorithm the tasks use, by name.

    Raises
    ------
    UsageError
        When an algorithm's function cannot be pickled by reference.
    """
    return refs_for_configs([c for t in tasks for c in t.configs])


def refs_for_configs(configs: Iterable[AlgorithmConfig]) -> dict[str, AlgorithmRef]:
    """One :class:`AlgorithmRef` per algorithm of ``configs``, by name (see :func:`algorithm_refs`)."""
    names = sorted({c.algorithm for c in configs})
    return {name: _ref(get_algorithm(name)) for name in names}


def _import_file(module: str, file: str) -> None:
    spec = importlib.util.spec_from_file_location(module, file)
    if spec is None or spec.loader is None:
        raise ImportError(f"{file!r} is not an importable Python file")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[module] = mod
    try:
        spec.loader.exec_module(mod)
    except BaseException:
        del sys.modules[module]
        raise


def _sync_options(ref: AlgorithmRef) -> None:
    """Give this process's registration the parent's ``clockwise`` flag and declared contract."""
    if ALGORITHMS.get(ref.name).clockwise != ref.clockwise:
        set_clockwise(ref.name, ref.clockwise)
    if ALGORITHMS.get(ref.name).contract.label != ref.contract:
        set_contract(ref.name, ref.contract + ",orientation=" + ("cw" if ref.clockwise else "ccw"))


def ensure_algorithm(ref: AlgorithmRef) -> str | None:
    """Make ``ref`` resolvable by name in this process; return None, or why it cannot be.

    Examples
    --------
    A built-in is already there (nothing to do):

    >>> from hullstress.runner._protocol import ensure_algorithm  # doctest: +SKIP
    >>> ensure_algorithm(ref_of_a_builtin) is None  # doctest: +SKIP
    True
    """
    if ref.name in ALGORITHMS:
        _sync_options(ref)
        return None
    try:
        if ref.module not in sys.modules:
            if ref.module.startswith("hullstress_plugin_") and ref.file:
                from ..plugins import load_plugin

                load_plugin(ref.file)
            else:
                try:
                    importlib.import_module(ref.module)
                except ImportError:
                    if not ref.file:
                        raise
                    _import_file(ref.module, ref.file)
        if ref.name not in ALGORITHMS:
            ALGORITHMS.add(pickle.loads(ref.spec_pickle))
        _sync_options(ref)
    except Exception as exc:
        return f"cannot load algorithm {ref.name!r} from {ref.file or ref.module} in the worker: {one_line(exc)}"
    return None


@dataclass(frozen=True)
class Job:
    """A task as sent to a worker: where to resume, and what the worker needs to know.

    Attributes
    ----------
    task : Task
    start_at : int
        Index of the first config to run (earlier ones already have rows).
    qhull : bool
        Compute the Qhull reference with the case facts.
    facts : CaseFacts or None
        Precomputed facts (skips computing them), or None.
    refs : tuple of AlgorithmRef
        For the algorithms of ``task``'s configs (empty in-process).
    budget_deadline : float or None
        ``time.time()`` after which no new call starts.
    qhull_options : str or None
        Qhull options tried first for the reference hull.
    """

    task: Task
    start_at: int = 0
    qhull: bool = True
    facts: CaseFacts | None = None
    refs: tuple[AlgorithmRef, ...] = ()
    budget_deadline: float | None = None
    qhull_options: str | None = None


def _exit_code(exc: SystemExit) -> int:
    code = exc.code
    if code is None:
        return 0
    return code if isinstance(code, int) else 1


class _CallTimedOut(BaseException):
    """Raised by SIGALRM inside a call (in-process runs); a BaseException so the code under test cannot catch it as an error."""


@contextmanager
def _alarm(seconds: float | None) -> Iterator[None]:
    """Interrupt Python code still running after ``seconds`` (main thread, POSIX; C code is not interrupted)."""
    usable = (seconds is not None and hasattr(signal, "setitimer")
              and threading.current_thread() is threading.main_thread())
    if not usable:
        yield
        return

    def _expired(signum: int, frame: Any) -> None:
        raise _CallTimedOut()

    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


class _Capture:
    """What every captured call reuses: the capture file, Python's streams on fds 1 and 2, C's fflush.

    Set up once per process (a worker captures thousands of calls; opening
    them per call cost more than a small algorithm call).
    """

    def __init__(self) -> None:
        import atexit
        import tempfile

        self.file = tempfile.TemporaryFile()
        atexit.register(self.file.close)
        self.streams: list[Any] = [None, None]
        self.fflush: Any = None
        try:
            import ctypes

            self.fflush = ctypes.CDLL(None).fflush
        except (OSError, AttributeError):
            pass

    def ours(self) -> list[Any]:
        """Text streams writing to fds 1 and 2 (reopened if the code under test closed one)."""
        for i, fd in enumerate((1, 2)):
            if self.streams[i] is None or self.streams[i].closed:
                self.streams[i] = open(fd, "w", encoding="utf-8", errors="replace", closefd=False)
        return self.streams

    def flush_c_stdio(self) -> None:
        """Flush C's stdio buffers, so what a C library printf'd lands in the capture, not later on the terminal."""
        if self.fflush is not None:
            try:
                self.fflush(None)
            except (OSError, AttributeError):
                pass


_capture: _Capture | None = None


@contextmanager
def captured_output() -> Iterator[list[str]]:
    """Capture what is written on file descriptors 1 and 2 in the block; the list receives the text.

    At the descriptor level, so a C library's messages (Qhull's ``QH...``
    warnings) and a child program's stderr are captured too, not only
    Python's ``sys.stderr``.  The text is the tail (:data:`CALL_OUTPUT_CHARS`),
    with Qhull's random run ids blanked.

    Examples
    --------
    >>> with captured_output() as out:
    ...     _ = os.write(2, b"QH7088 warning, run-id 123\\n")
    >>> out
    ['QH7088 warning, run-id <n>']
    """
    global _capture
    if _capture is None:
        _capture = _Capture()
    capture = _capture.file
    result: list[str] = []
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, ValueError, OSError):
            pass
    capture.seek(0)
    capture.truncate()
    saved = [os.dup(1), os.dup(2)]
    # sys.stdout may not write to fd 1 (pytest's capture, a notebook): point Python's streams there too.
    saved_streams = (sys.stdout, sys.stderr)
    ours = _capture.ours()
    try:
        os.dup2(capture.fileno(), 1)
        os.dup2(capture.fileno(), 2)
        sys.stdout, sys.stderr = ours
        yield result
    finally:
        for stream in (sys.stdout, sys.stderr, *ours):
            try:
                stream.flush()
            except (AttributeError, ValueError, OSError):
                pass
        sys.stdout, sys.stderr = saved_streams
        _capture.flush_c_stdio()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved:
            os.close(fd)
        size = capture.seek(0, os.SEEK_END)
        text = ""
        if size:
            capture.seek(max(0, size - 4 * CALL_OUTPUT_CHARS))
            text = capture.read().decode("utf-8", errors="replace").strip()
        result.append(_RUN_ID.sub("run-id <n>", text)[-CALL_OUTPUT_CHARS:] if text else "")


#: The ``--memory-limit`` of this worker process in bytes (set by the worker; None: no limit).
_memory_limit_bytes: int | None = None


def note_memory_limit(limit_bytes: int | None) -> None:
    """Record this process's memory limit, so that a ``MemoryError`` row names it."""
    global _memory_limit_bytes
    _memory_limit_bytes = limit_bytes


def naming_memory_limit(row: ResultRow) -> ResultRow:
    """A row whose reason is a ``MemoryError``, with the limit that refused the allocation.

    Examples
    --------
    >>> from hullstress.results import ResultRow
    >>> note_memory_limit(64 * 2**20)
    >>> naming_memory_limit(ResultRow({"reason": "MemoryError"}))["reason"]
    'MemoryError: an allocation went over --memory-limit 64 MiB'
    >>> note_memory_limit(None)
    """
    reason = str(row.get("reason") or "")
    if _memory_limit_bytes is None or "MemoryError" not in reason or "--memory-limit" in reason:
        return row
    limit = f"an allocation went over --memory-limit {_memory_limit_bytes / 2**20:g} MiB"
    head, sep, rest = reason.partition("MemoryError")
    rest = rest.lstrip(":").strip()
    named = f"{head}MemoryError: {limit}" + (f" ({rest})" if rest else "")
    return ResultRow({**row.values, "reason": named})


def _with_output(row: ResultRow, output: list[str]) -> ResultRow:
    return ResultRow({**row.values, "call_output": output[0]}) if output and output[0] else row


def run_job(job: Job, problems: Mapping[str, str] | None = None, *,
            alarm_after: float | None = None) -> Iterator[tuple[Any, ...]]:
    """Execute ``job`` and yield the protocol messages (see the module docstring).

    Parameters
    ----------
    job : Job
    problems : mapping of str to str, optional
        Algorithms that could not be loaded here, with why: their configs get
        an ``error`` row starting with ``internal:`` instead of a call.
    alarm_after : float, optional
        In-process runs only: interrupt a call still running Python code after
        this many seconds and record it as ``timeout`` (a hang inside C code
        is not interrupted; isolated workers are killed by the parent instead).

    Yields
    ------
    tuple
        Messages, in order; the last one is ``("done",)``.
    """
    task = job.task
    case = task.case
    configs = task.configs
    problems = problems or {}
    facts = job.facts
    if facts is None:
        yield ("facts-start", time.monotonic())
        t0 = time.perf_counter()
        try:
            facts = case_facts(case, qhull=job.qhull, qhull_options=job.qhull_options)
        except Exception as exc:  # trusted code failing must still leave one row per config
            for k in range(job.start_at, len(configs)):
                yield ("row", k, make_row(case, configs[k], status=Status.ERROR, stage=Stage.CHECK,
                                          reason=f"internal: case facts raised {one_line(exc)}"))
            yield ("done",)
            return
        yield ("facts", facts.degenerate, facts.invalid_input, time.perf_counter() - t0)
    else:
        yield ("facts", facts.degenerate, facts.invalid_input, 0.0)
    for k in range(job.start_at, len(configs)):
        if job.budget_deadline is not None and time.time() >= job.budget_deadline:
            yield ("stopped", k)
            break
        config = configs[k]
        problem = problems.get(config.algorithm)
        if problem is not None:
            yield ("row", k, make_row(case, config, status=Status.ERROR, reason=f"internal: {problem}",
                                      degenerate=facts.degenerate, invalid_input=facts.invalid_input))
            continue
        started = time.monotonic()
        yield ("start", k, started)
        output: list[str] = []
        try:
            with captured_output() as output, _alarm(alarm_after):
                outcome = call_algorithm(case, config)
        except _CallTimedOut:
            yield ("row", k, _with_output(make_row(
                case, config, status=Status.TIMEOUT, reason=f"exceeded {float(alarm_after or 0)} s",
                seconds=time.monotonic() - started, degenerate=facts.degenerate,
                invalid_input=facts.invalid_input), output))
            continue
        except SystemExit as exc:
            # sys.exit() inside the code under test: the same row as a worker
            # that exits with that code (os._exit), but this process lives on.
            yield ("row", k, _with_output(make_row(
                case, config, status=Status.CRASH, reason=death_reason(_exit_code(exc)),
                degenerate=facts.degenerate, invalid_input=facts.invalid_input), output))
            continue
        yield ("called", k, time.monotonic(), outcome.seconds)
        try:
            row = judge(case, config, outcome, facts)
        except Exception as exc:
            row = make_row(case, config, status=Status.ERROR, stage=Stage.CHECK,
                           reason=f"internal: judging raised {one_line(exc)}",
                           seconds=outcome.seconds, eps_value=outcome.eps_value,
                           degenerate=facts.degenerate, invalid_input=facts.invalid_input)
        yield ("row", k, _with_output(naming_memory_limit(row), output))
    yield ("done",)


def row_for(task: Task, k: int, *, status: str, reason: str, origin: str | None,
            facts_info: tuple[bool | None, str | None], seconds: float = 0.0,
            check_seconds: float = 0.0, stage: Stage = Stage.ALGORITHM, contract: str | None = None) -> ResultRow:
    """A row the parent builds itself (timeout, crash, limits), with the facts the worker reported.

    ``stage`` is ``check`` when the harness's own part (facts, checker) ran out
    of time or died; a call that hangs or dies is the algorithm's.
    """
    degenerate, invalid = facts_info
    return make_row(task.case, task.configs[k], status=status, stage=stage, reason=reason, seconds=seconds,
                    check_seconds=check_seconds, degenerate=degenerate, invalid_input=invalid, origin=origin,
                    contract=contract)


def emit_row(row: ResultRow, on_row: Callable[[ResultRow], None], stats: ExecutionStats) -> None:
    """Count ``row`` and its busy time in ``stats``, then hand it to ``on_row``."""
    stats.calls_done += 1
    stats.algorithm_seconds += float(row["seconds"] or 0.0)
    stats.check_seconds += float(row["check_seconds"] or 0.0)
    on_row(row)
