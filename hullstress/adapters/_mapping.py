"""Map coordinates a library returns back to row indices of the input.

Libraries such as GEOS (shapely) and CGAL return hull *points*, not indices.
Both copy the input doubles unchanged into their results, so an exact
coordinate match recovers the index.  When several input rows share the same
coordinates the lowest row index is used: the rows are the same point, and
choosing the first makes the mapping deterministic.  ``-0.0`` and ``0.0``
compare equal and therefore map to the same row, which is right for a point
set.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

__all__ = ["coordinate_table", "indices_of"]


def coordinate_table(points: np.ndarray) -> dict[tuple[float, ...], int]:
    """Return a mapping from each distinct coordinate row to its lowest row index.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64

    Returns
    -------
    dict of tuple of float to int

    Examples
    --------
    >>> import numpy as np
    >>> coordinate_table(np.array([[0.0, 1.0], [2.0, 3.0], [0.0, 1.0]]))
    {(0.0, 1.0): 0, (2.0, 3.0): 1}
    """
    table: dict[tuple[float, ...], int] = {}
    for i, row in enumerate(np.asarray(points).tolist()):
        table.setdefault(tuple(row), i)
    return table


def indices_of(
    coordinates: Iterable[Sequence[float]],
    table: dict[tuple[float, ...], int],
    *,
    library: str,
) -> list[int]:
    """Look up the input index of every returned coordinate tuple.

    Parameters
    ----------
    coordinates : iterable of sequences of float
        Points as the library returned them.
    table : dict
        From :func:`coordinate_table` on the input.
    library : str
        Named in the error message.

    Returns
    -------
    list of int

    Raises
    ------
    RuntimeError
        When the library returned a point that is not an input point (the
        adapter cannot express such a result under the output contract).

    Examples
    --------
    >>> table = {(0.0, 1.0): 0, (2.0, 3.0): 1}
    >>> indices_of([(2.0, 3.0), (0.0, 1.0)], table, library="demo")
    [1, 0]
    """
    out = []
    for c in coordinates:
        key = tuple(float(x) for x in c)
        try:
            out.append(table[key])
        except KeyError:
            raise RuntimeError(
                f"{library} returned the point {key}, which is not one of the input points"
            ) from None
    return out
