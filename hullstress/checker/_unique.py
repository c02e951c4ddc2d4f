"""Sorted distinct values of an integer array, by sorting.

numpy 2.3 and later answer a plain ``np.unique(a)`` through a hash table and
then sort the result; on the index arrays the checker handles (10**5 to 10**7
entries, most of them distinct) that costs about ten times a sort followed by
a comparison of neighbours.  :func:`unique_ints` is that sort: the same values
in the same order and dtype, for integer (and boolean) arrays only, where
equality is plain and there is no NaN to fold.
"""

from __future__ import annotations

import numpy as np

__all__ = ["unique_ints"]


def unique_ints(values: np.ndarray) -> np.ndarray:
    """The sorted distinct entries of an integer array (flattened), as ``np.unique`` gives them.

    Parameters
    ----------
    values : array_like of int or bool

    Returns
    -------
    ndarray of shape (k,)
        Same dtype as ``values``.

    Examples
    --------
    >>> unique_ints(np.array([[3, 1], [3, 2]]))
    array([1, 2, 3])
    """
    flat = np.sort(np.asarray(values).ravel())
    if flat.dtype.kind not in "iub":
        raise TypeError(f"unique_ints needs an integer array, got dtype {flat.dtype}")
    if len(flat) < 2:
        return flat
    keep = np.empty(len(flat), dtype=bool)
    keep[0] = True
    np.not_equal(flat[1:], flat[:-1], out=keep[1:])
    return flat[keep]
