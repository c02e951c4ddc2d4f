"""The triage stage's questions on their way to the worker pool: who waits on which call.

A running shrink waits on one question (:class:`Asking`); questions become
calls on the pool (:class:`InFlight`), each (case, config) once at a time, so
that a row is told apart by its case and config alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..case import Case
from ..config import AlgorithmConfig
from ..results import ResultRow
from .shrink import Question, Shrinker

if TYPE_CHECKING:
    from ..runner import JobFeed, PendingJob

__all__ = ["Asking", "InFlight"]


@dataclass
class Asking:
    """A running shrink, its chain, and the question it waits on, asked in round ``round``."""

    shrinker: Shrinker
    chain: int
    round: int
    question: Question


class InFlight:
    """The calls under way or queued, each once, and which groups wait on each.

    A question is a case and a config, judged with or without the Qhull
    reference.  Shrinks asking the same question share one call (unless one
    of them re-runs a case on purpose: that is always a call of its own).
    Questions about one case judged the same way go to the pool as one job
    while it is still queued, so the case facts are computed once for all
    of them.  A question about a case and config under way the other way
    (with the reference, say, while it runs without), or re-run on purpose,
    waits for that call to end: every row is then told apart by its case
    and config.
    """

    def __init__(self) -> None:
        self._calls: dict[tuple[str, str], tuple[bool, list[int]]] = {}
        self._later: dict[tuple[str, str], list[tuple[int, Case, AlgorithmConfig, bool, bool, bool]]] = {}
        self._queued: dict[tuple[str, bool], "PendingJob"] = {}  # jobs not taken by the pool yet
        self.calls = 0

    def taken(self, job: "PendingJob") -> None:
        """The pool took ``job`` out of the feed: it no longer takes more configs."""
        key = (job.task.case.case_id, bool(job.qhull))
        if self._queued.get(key) is job:
            del self._queued[key]

    def add(self, i: int, case: Case, config: AlgorithmConfig, qhull: bool, *, fresh: bool = False,
            alone: bool = False) -> "PendingJob | None":
        """Group ``i`` asks: a new job to push, or None when a queued job or a call under way answers it.

        ``fresh`` re-runs the case on purpose (a call of its own); ``alone``
        runs the call as a job of its own in a worker that has run nothing
        before it (a crash is judged so: whether native code dies can depend
        on what its process did before).
        """
        from ..runner import PendingJob, Task

        key = (case.case_id, config.label)
        under_way = self._calls.get(key)
        if under_way is not None:
            if under_way[0] == qhull and not fresh:
                under_way[1].append(i)
            else:
                self._later.setdefault(key, []).append((i, case, config, qhull, fresh, alone))
            return None
        self._calls[key] = (qhull, [i])
        self.calls += 1
        if alone:
            return PendingJob(Task(0, case, (config,)), qhull=qhull, fresh_worker=True)
        queued = self._queued.get((case.case_id, qhull))
        if queued is not None:
            queued.task = Task(queued.task.index, case, queued.task.configs + (config,))
            queued.wire = None
            return None
        job = PendingJob(Task(0, case, (config,)), qhull=qhull)
        self._queued[(case.case_id, qhull)] = job
        return job

    def answer(self, row: ResultRow, timeout: float, feed: "JobFeed") -> list[tuple[int, tuple]]:
        """The groups ``row`` answers, with its key for reuse; queues the questions that waited for it."""
        key = (str(row["case_id"]), str(row["config"]))
        qhull, groups = self._calls.pop(key)
        for k, (i, case, config, other, fresh, alone) in enumerate(self._later.pop(key, [])):
            job = self.add(i, case, config, other, fresh=fresh, alone=alone)
            if job is not None:
                feed.push(job, priority=(-1, k))  # they waited a whole call already: first
        return [(i, (key[0], key[1], qhull, timeout)) for i in groups]
