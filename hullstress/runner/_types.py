"""The runner's records: what to run (:class:`Task`), how (:class:`RunnerOptions`), what it cost (:class:`ExecutionStats`)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from ..case import Case
from ..config import AlgorithmConfig
from ..errors import UsageError
from ..options import DEFAULTS

__all__ = ["Task", "RunnerOptions", "ExecutionStats", "DEFAULT_MEMORY_LIMIT_MB", "DEFAULT_CHECK_TIMEOUT"]

#: Address-space limit per isolated worker, in MiB (see :class:`hullstress.options.Defaults`).
DEFAULT_MEMORY_LIMIT_MB = DEFAULTS.memory_limit_mb
#: Floor of the limit on trusted work in a worker (case facts, the exact checker), in seconds.
DEFAULT_CHECK_TIMEOUT = DEFAULTS.check_timeout_floor


@dataclass(frozen=True)
class Task:
    """A case and the configs to run on it (the points travel to a worker once per task).

    Attributes
    ----------
    index : int
        Position in the sweep (for bookkeeping only; tables are sorted afterwards).
    case : Case
    configs : tuple of AlgorithmConfig
    """

    index: int
    case: Case
    configs: tuple[AlgorithmConfig, ...]


@dataclass(frozen=True)
class RunnerOptions:
    """How to execute: backend, parallelism, isolation limits, budget.

    Attributes
    ----------
    workers : int
        0 runs in this process without isolation (debugging; the timeout
        interrupts Python code only); N >= 1 uses N isolated worker processes
        on this machine.
    timeout : float
        Per-call timeout in seconds (the algorithm call, preprocessing and
        output contract; not the checker).
    time_budget : float or None
        Stop starting new calls after this many seconds; calls under way finish.
    qhull : bool
        Compute Qhull references (needed for the agreement check).
    memory_limit_mb : float or None
        What the code under test and its check may allocate in an isolated
        worker, in MiB, beyond the worker's address space once its libraries
        are loaded (enforced with ``RLIMIT_AS``); None or 0 for no limit, else at
        least ``DEFAULTS.min_memory_limit_mb``.  Ignored with ``workers=0``.
    check_timeout : float or None
        Limit on trusted work per step in a worker (case facts, one check);
        None means ``max(60, 10 * timeout)``.  Exceeding it is an ``error``
        row whose reason starts with ``internal:``.
    scheduler : str or None
        A Dask scheduler address (``tcp://host:8786``): run on that cluster
        instead of locally; ``workers`` is then ignored.
    qhull_options : str or None
        Qhull options tried first for each case's reference hull (``--qhull-options``).

    Examples
    --------
    >>> RunnerOptions(workers=2, timeout=5.0).effective_check_timeout
    60.0
    >>> RunnerOptions(workers=-1)
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: workers must be 0 or more, got -1
    """

    workers: int = 0
    timeout: float = DEFAULTS.call_timeout
    time_budget: float | None = None
    qhull: bool = True
    memory_limit_mb: float | None = DEFAULT_MEMORY_LIMIT_MB
    check_timeout: float | None = None
    scheduler: str | None = None
    qhull_options: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.workers, int) or self.workers < 0:
            raise UsageError(f"workers must be 0 or more, got {self.workers!r}")
        if not self.timeout > 0:
            raise UsageError(f"timeout must be positive, got {self.timeout!r}")
        if self.time_budget is not None and not self.time_budget > 0:
            raise UsageError(f"time_budget must be positive, got {self.time_budget!r}")
        if self.memory_limit_mb is not None and not self.memory_limit_mb >= 0:
            raise UsageError(f"memory_limit_mb must be 0 (no limit) or positive, got {self.memory_limit_mb!r}")
        if self.memory_limit_mb and self.memory_limit_mb < DEFAULTS.min_memory_limit_mb:
            raise UsageError(f"memory_limit_mb {self.memory_limit_mb:g} is below the minimum of "
                             f"{DEFAULTS.min_memory_limit_mb:g} MiB that a worker needs beyond its libraries")
        if self.check_timeout is not None and not self.check_timeout > 0:
            raise UsageError(f"check_timeout must be positive, got {self.check_timeout!r}")

    @property
    def effective_check_timeout(self) -> float:
        """The limit on trusted work per step, in seconds."""
        if self.check_timeout is not None:
            return float(self.check_timeout)
        return max(DEFAULT_CHECK_TIMEOUT, 10.0 * float(self.timeout))

    @property
    def memory_limit_bytes(self) -> int | None:
        """The per-worker address-space limit in bytes, or None for none."""
        if not self.memory_limit_mb:
            return None
        return int(self.memory_limit_mb * 2**20)


@dataclass
class ExecutionStats:
    """What a backend measured.

    Attributes
    ----------
    backend : {"serial", "local", "dask"}
    start_method : str
        How local worker processes start (``forkserver``, ``spawn``), or ``""``.
    workers : int
        Parallel slots used: local worker processes, Dask threads, 1 for serial.
    wall_seconds : float
        Wall time of the whole execution, worker start-up included.
    budget_exhausted : bool
        The time budget stopped the sweep before every call ran.
    calls_started, calls_done : int
        Algorithm calls begun; rows delivered.
    algorithm_seconds, check_seconds, facts_seconds : float
        Time inside algorithm calls (with preprocessing), inside the checker,
        and computing case facts (validity, affine rank, Qhull reference), summed over workers.
    harness_overhead_seconds : float
        Wall time not spent inside algorithms or checks:
        ``wall - (algorithm + check + facts) / workers``, at least 0.  It
        includes worker start-up, messaging, result handling and idle workers at the end.
    harness_overhead_fraction : float
        ``harness_overhead_seconds / wall_seconds``.
    worker_restarts : int
        Worker processes replaced after a crash, a timeout or a stall.
    notes : list of str
        Anything the run should mention (e.g. memory limits unsupported here).
    """

    backend: str = "serial"
    start_method: str = ""
    workers: int = 1
    wall_seconds: float = 0.0
    budget_exhausted: bool = False
    calls_started: int = 0
    calls_done: int = 0
    algorithm_seconds: float = 0.0
    check_seconds: float = 0.0
    facts_seconds: float = 0.0
    harness_overhead_seconds: float = 0.0
    harness_overhead_fraction: float = 0.0
    worker_restarts: int = 0
    notes: list[str] = field(default_factory=list)

    def finish(self, wall_seconds: float) -> "ExecutionStats":
        """Record the wall time and derive the harness overhead from it; returns self."""
        self.wall_seconds = float(wall_seconds)
        busy = self.algorithm_seconds + self.check_seconds + self.facts_seconds
        self.harness_overhead_seconds = max(0.0, self.wall_seconds - busy / max(1, self.workers))
        self.harness_overhead_fraction = (
            self.harness_overhead_seconds / self.wall_seconds if self.wall_seconds > 0 else 0.0
        )
        return self

    def merge_counts(self, other: "ExecutionStats") -> None:
        """Add another tally's counters and busy times (used to fold in per-task tallies from Dask)."""
        self.budget_exhausted |= other.budget_exhausted
        self.calls_started += other.calls_started
        self.facts_seconds += other.facts_seconds
        self.worker_restarts += other.worker_restarts
        for note in other.notes:
            if note not in self.notes:
                self.notes.append(note)

    def as_dict(self) -> dict[str, Any]:
        """Plain values for ``run.json`` (seconds rounded to the millisecond)."""
        out = asdict(self)
        for key, value in out.items():
            if isinstance(value, float):
                out[key] = round(value, 4 if key.endswith("fraction") else 3)
        return out
