"""A test plug-in: an exactly-correct 2D hull in rational arithmetic, registered as ``exact-rational-2d``.

Andrew's monotone chain on :class:`fractions.Fraction` coordinates, so every
orientation test is exact.  It returns the lower-dimensional answers of docs/lower-dimensional.md
("Lower-dimensional input"): ``[]`` for no points, one index for a set of
identical points, the two extreme endpoints for a collinear set; and it
raises ``ValueError`` on what has no hull (NaN, infinity, a wrong shape).  It
is a positive control: a sweep must find nothing wrong with it.

Load it with ``--plugin tests/exact_hull_plugin.py`` (or ``load_plugin``).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from hullstress import register_algorithm


def _turn(o: tuple[Fraction, Fraction], a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction]) -> Fraction:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _chain(keys: list[tuple[Fraction, Fraction]]) -> list[tuple[Fraction, Fraction]]:
    chain: list[tuple[Fraction, Fraction]] = []
    for k in keys:
        while len(chain) >= 2 and _turn(chain[-2], chain[-1], k) <= 0:
            chain.pop()
        chain.append(k)
    return chain


@register_algorithm("exact-rational-2d", dim=2)
def exact_rational_2d(points: np.ndarray, /) -> list[int]:
    """Exact monotone chain in rationals: the extreme points counter-clockwise (a test plug-in).

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64

    Returns
    -------
    list of int
        The extreme points counter-clockwise from the lexicographically
        smallest; for lower-dimensional input the answer of docs/lower-dimensional.md.

    Raises
    ------
    ValueError
        On a wrong shape or a non-finite coordinate.

    Examples
    --------
    >>> exact_rational_2d(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0], [0.0, 0.0]]))
    [0, 1]
    """
    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got {pts.shape}")
    if not np.isfinite(pts).all():
        raise ValueError("points must be finite")
    first: dict[tuple[Fraction, Fraction], int] = {}
    for i, (x, y) in enumerate(pts.tolist()):
        first.setdefault((Fraction(x), Fraction(y)), i)  # Fraction(-0.0) == 0: one point
    keys = sorted(first)
    if len(keys) <= 2:
        return [first[k] for k in keys]
    ring = _chain(keys)[:-1] + _chain(keys[::-1])[:-1]
    if len(ring) < 3:  # collinear: the chains meet at the two ends
        return [first[keys[0]], first[keys[-1]]]
    return [first[k] for k in ring]
