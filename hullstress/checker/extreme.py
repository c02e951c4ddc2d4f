"""Exact extreme points without a certified hull, and coordinate-set helpers.

:func:`exact_extreme_2d` is Andrew's monotone chain with an exact scalar
orientation test: used as the 2D reference when Qhull's own hull fails the
exact checks.  The coordinate helpers compare vertex sets by coordinates,
because duplicated input points make index sets ambiguous.

Soundness of :func:`_orient_scalar`'s filter: Shewchuk's bound plus 1e-300 for
underflowed products; an infinite ``det`` has an infinite bound (``|det| <=
|left| + |right|``) and NaN compares false, so only finite values are decided.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from ._unique import unique_ints

__all__ = ["exact_extreme_2d", "first_of_each", "rows_in", "Coordinates"]

#: Shewchuk's ccwerrboundA, with a relative slack of 2**-40 for the float evaluation of the bound.
_ERRBOUND = (3.0 + 16.0 * 2.0**-53) * 2.0**-53 * (1.0 + 2.0**-40)


def _orient_scalar(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> int:
    """Exact orient2d on Python floats: Shewchuk's filter, then rationals."""
    left = (ax - cx) * (by - cy)
    right = (ay - cy) * (bx - cx)
    det = left - right
    bound = _ERRBOUND * (abs(left) + abs(right))
    # The 1e-300 floor keeps the filter honest where products underflow.  A NaN det fails
    # the test, and so does an infinite one (|det| <= |left| + |right|: its bound is infinite).
    if abs(det) > bound + 1e-300:
        return 1 if det > 0 else -1
    fa = [Fraction(v) for v in (ax, ay, bx, by, cx, cy)]
    exact = (fa[0] - fa[4]) * (fa[3] - fa[5]) - (fa[1] - fa[5]) * (fa[2] - fa[4])
    return (exact > 0) - (exact < 0)


def exact_extreme_2d(points: np.ndarray) -> np.ndarray:
    """Indices of the extreme points of a 2D point set, exactly, counter-clockwise.

    Duplicated coordinates appear once (the lowest index).  Points on an edge
    of the hull but not corners are excluded.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64, finite

    Returns
    -------
    ndarray of shape (h,), int64
        Counter-clockwise from the lexicographically smallest point; a single
        point for a one-point set, two for a collinear set.

    Examples
    --------
    >>> pts = np.array([[0.0, 0], [1, 0], [2, 0], [1, 1], [1, 0.5], [0, 0]])
    >>> exact_extreme_2d(pts).tolist()  # (1, 0) lies on an edge
    [0, 2, 3]
    >>> exact_extreme_2d(np.array([[0.0, 0], [1, 1], [3, 3]])).tolist()
    [0, 2]
    """
    pts = np.asarray(points, dtype=np.float64)
    if not len(pts):
        return np.zeros(0, dtype=np.int64)
    uniq, first = np.unique(pts + 0.0, axis=0, return_index=True)  # lexicographic; -0.0 folded into 0.0
    if len(uniq) <= 2:
        return first.astype(np.int64)
    xy = uniq.tolist()

    def chain(order):
        hull: list[int] = []
        for i in order:
            while len(hull) >= 2:
                a, b = xy[hull[-2]], xy[hull[-1]]
                if _orient_scalar(a[0], a[1], b[0], b[1], xy[i][0], xy[i][1]) > 0:
                    break
                hull.pop()
            hull.append(i)
        return hull

    lower = chain(range(len(xy)))
    upper = chain(range(len(xy) - 1, -1, -1))
    ring = lower[:-1] + upper[:-1]
    if len(ring) < 3:  # collinear input: the two ends
        ring = [0, len(xy) - 1]
    return first[ring].astype(np.int64)


def _keys(rows: np.ndarray) -> np.ndarray:
    """One opaque key per row, equal exactly when the rows are equal by value (-0.0 == 0.0)."""
    arr = np.ascontiguousarray(np.asarray(rows, dtype=np.float64) + 0.0)
    return arr.view(np.dtype((np.void, 8 * arr.shape[1]))).ravel()


def first_of_each(points: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """The indices of ``idx`` whose coordinates appear first, one per distinct coordinate (sorted)."""
    idx = np.asarray(idx, dtype=np.int64)
    if not len(idx):
        return idx
    _, first = np.unique(_keys(points[idx]), return_index=True)
    return np.sort(idx[first])


class Coordinates:
    """Which points of a subset share coordinates: one integer id per distinct coordinate.

    Built once per verdict over the indices it will compare (hull vertices,
    extreme points, Qhull's vertices), so that every set operation after it
    is on small integers instead of rows of floats compared byte by byte.

    Examples
    --------
    >>> pts = np.array([[0.0, 1], [2, 3], [0, 1], [-0.0, 1]])
    >>> ids = Coordinates(pts, np.array([0, 1, 2, 3]))
    >>> ids.distinct(np.array([0, 2, 3])), ids.first_of_each(np.array([3, 2, 1])).tolist()
    (1, [1, 3])
    """

    def __init__(self, points: np.ndarray, *index_arrays: np.ndarray):
        idx = unique_ints(np.concatenate([np.asarray(i, dtype=np.int64) for i in index_arrays]))
        rows = points[idx]  # sorted and compared by value: -0.0 and 0.0 are the same coordinate
        order = np.lexsort(rows.T[::-1])
        srt = rows[order]
        new = np.ones(len(idx), dtype=bool)  # the first row starts a group
        np.any(srt[1:] != srt[:-1], axis=1, out=new[1:])
        self._id = np.full(len(points), -1, dtype=np.int64)
        self._id[idx[order]] = np.cumsum(new) - 1
        self.count = int(new.sum())

    def groups(self, idx: np.ndarray) -> np.ndarray:
        """The distinct coordinate ids of ``points[idx]`` (sorted)."""
        return unique_ints(self._id[idx])

    def distinct(self, idx: np.ndarray) -> int:
        """How many distinct coordinates ``points[idx]`` holds."""
        return len(self.groups(idx))

    def first_of_each(self, idx: np.ndarray) -> np.ndarray:
        """The indices of ``idx`` whose coordinates appear first, one per distinct coordinate (sorted)."""
        idx = np.asarray(idx, dtype=np.int64)
        _, first = np.unique(self._id[idx], return_index=True)
        return np.sort(idx[first])

    def within(self, idx: np.ndarray, groups: np.ndarray) -> np.ndarray:
        """For each of ``idx``, whether its coordinate is among ``groups`` (ids from :meth:`groups`)."""
        mark = np.zeros(self.count, dtype=bool)
        mark[groups] = True
        return mark[self._id[idx]]


def rows_in(rows: np.ndarray, table: np.ndarray) -> np.ndarray:
    """For each row of ``rows``, whether it equals some row of ``table`` (exact float equality).

    Parameters
    ----------
    rows : ndarray of shape (k, d)
    table : ndarray of shape (t, d)

    Returns
    -------
    ndarray of shape (k,), bool
    """
    if not len(rows) or not len(table):
        return np.zeros(len(rows), dtype=bool)
    return np.isin(_keys(rows), _keys(table))
