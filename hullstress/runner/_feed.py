"""A queue of jobs for the worker pool that may grow while the pool runs, most urgent first."""

from __future__ import annotations

import heapq
from collections import deque
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["JobFeed"]


class JobFeed:
    """Jobs for :meth:`WorkerPool.serve` that arrive while it runs, the most urgent (smallest priority) first.

    It offers the part of a deque the pool uses (``popleft``, ``[0]``,
    ``appendleft``, ``extendleft``, truth and length): jobs the pool hands
    back (the rest of a task whose worker died) go first, then the pushed
    ones by priority, ties in the order pushed.

    Examples
    --------
    >>> feed = JobFeed()
    >>> feed.push("late", priority=(2,)); feed.push("early", priority=(1,)); feed.push("early too", priority=(1,))
    >>> [feed.popleft() for _ in range(len(feed))]
    ['early', 'early too', 'late']
    """

    def __init__(self, on_take: Callable[[Any], None] | None = None) -> None:
        self._front: deque[Any] = deque()
        self._heap: list[tuple[Any, int, Any]] = []
        self._pushed = 0
        #: Told of every job the pool takes out (until then its owner may still change it).
        self.on_take = on_take

    def push(self, job: Any, *, priority: Any) -> None:
        """Add ``job`` (a :class:`PendingJob`) with ``priority``."""
        heapq.heappush(self._heap, (priority, self._pushed, job))
        self._pushed += 1

    def __bool__(self) -> bool:
        return bool(self._front or self._heap)

    def __len__(self) -> int:
        return len(self._front) + len(self._heap)

    def __getitem__(self, index: int) -> Any:
        if index != 0 or not self:
            raise IndexError("a job feed shows only its first job")
        return self._front[0] if self._front else self._heap[0][2]

    def popleft(self) -> Any:
        job = self._front.popleft() if self._front else heapq.heappop(self._heap)[2]
        if self.on_take is not None:
            self.on_take(job)
        return job

    def appendleft(self, job: Any) -> None:
        self._front.appendleft(job)

    def extendleft(self, jobs: Iterable[Any]) -> None:
        self._front.extendleft(jobs)
