"""Executing a sweep's tasks: one task is a case with every config to run on it.

Backends share :func:`execute`'s contract: call ``on_row`` once per (case,
config) as results arrive, in any order; the sweep sorts the table afterwards.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from ..case import Case
from ..config import AlgorithmConfig
from ..evaluate import call_algorithm, case_facts, judge
from ..results import ResultRow

__all__ = ["Task", "RunnerOptions", "ExecutionStats", "execute"]


@dataclass(frozen=True)
class Task:
    """A case and the configs to run on it (the points travel to a worker once per task)."""

    index: int
    case: Case
    configs: tuple[AlgorithmConfig, ...]


@dataclass(frozen=True)
class RunnerOptions:
    """How to execute: parallelism, isolation limits, budget.

    Attributes
    ----------
    workers : int
        0 runs in this process without isolation (debugging); N >= 1 uses N workers.
    timeout : float
        Per-call timeout in seconds.
    time_budget : float or None
        Stop starting new calls after this many seconds.
    qhull : bool
        Compute Qhull references (needed for the agreement check).
    """

    workers: int = 0
    timeout: float = 10.0
    time_budget: float | None = None
    qhull: bool = True


@dataclass
class ExecutionStats:
    """What the backend measured: wall time, and whether the budget cut the sweep short."""

    wall_seconds: float = 0.0
    budget_exhausted: bool = False
    calls_started: int = 0
    notes: list[str] = field(default_factory=list)


def execute(tasks: Sequence[Task], options: RunnerOptions, on_row: Callable[[ResultRow], None]) -> ExecutionStats:
    """Run every task in this process, in order (no isolation, no timeout)."""
    stats = ExecutionStats()
    start = time.perf_counter()
    for task in tasks:
        if options.time_budget is not None and time.perf_counter() - start > options.time_budget:
            stats.budget_exhausted = True
            break
        facts = case_facts(task.case, qhull=options.qhull)
        for config in task.configs:
            stats.calls_started += 1
            on_row(judge(task.case, config, call_algorithm(task.case, config), facts))
    stats.wall_seconds = time.perf_counter() - start
    return stats
