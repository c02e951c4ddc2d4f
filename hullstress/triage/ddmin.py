"""Delta debugging (Zeller and Hildebrandt's ddmin) over the rows of a point set."""

from __future__ import annotations

from collections.abc import Callable, Sequence

__all__ = ["ddmin"]


def _split(items: Sequence[int], n: int) -> list[tuple[int, ...]]:
    """``items`` in ``n`` contiguous chunks of near-equal size (none empty)."""
    k, r = divmod(len(items), n)
    out, start = [], 0
    for i in range(n):
        stop = start + k + (1 if i < r else 0)
        out.append(tuple(items[start:stop]))
        start = stop
    return [c for c in out if c]


def ddmin(n: int, fails: Callable[[tuple[int, ...]], bool], *, min_size: int = 1) -> tuple[int, ...]:
    """A 1-minimal subset of ``range(n)`` on which ``fails`` still holds.

    Parameters
    ----------
    n : int
        Number of rows; ``fails(tuple(range(n)))`` is assumed true.
    fails : callable
        ``fails(indices) -> bool`` for a sorted tuple of row indices.  It may
        raise to stop early (a spent budget); the exception propagates, so
        callers that want the best subset so far should record it inside
        ``fails``.  Results are cached here, so a subset is tried once.
    min_size : int
        Subsets smaller than this are never tried (e.g. a 3D hull needs 4 points).

    Returns
    -------
    tuple of int
        Sorted row indices: removing any single one of them makes ``fails`` false
        (unless stopped early).

    Examples
    --------
    Rows 3 and 7 together trigger the failure:

    >>> ddmin(10, lambda s: 3 in s and 7 in s)
    (3, 7)
    >>> ddmin(1, lambda s: True)
    (0,)
    """
    cache: dict[tuple[int, ...], bool] = {}

    def test(subset: tuple[int, ...]) -> bool:
        if len(subset) < min_size:
            return False
        if subset not in cache:
            cache[subset] = bool(fails(subset))
        return cache[subset]

    items: tuple[int, ...] = tuple(range(n))
    granularity = 2
    while len(items) >= 2:
        chunks = _split(items, min(granularity, len(items)))
        reduced = False
        # Subsets first: when the failure is local, one small chunk reproduces it.
        for chunk in chunks:
            if len(chunks) > 1 and test(chunk):
                items, granularity, reduced = chunk, 2, True
                break
        if not reduced:
            for chunk in chunks:
                removed = set(chunk)
                complement = tuple(i for i in items if i not in removed)
                if complement and test(complement):
                    items, granularity, reduced = complement, max(granularity - 1, 2), True
                    break
        if not reduced:
            if granularity >= len(items):
                break
            granularity = min(len(items), 2 * granularity)
    return items
