"""The Cardiff lecture's incremental hull (Andrew's monotone chain), registered as ``monotone-chain``.

Seed: ``004_3607bf1c5abd6a5b.txt`` (Sun and Langbein, CM0304 Graphics, II.7
"Convex Hull Finding Algorithms", slides "Incremental Convex Hull Algorithm",
"Correct?" and "Colinear Points").  Map from the seed's steps to the code:

0. "Assume all points are distinct (otherwise sort and remove duplicates)"
   (slide "Computational Problem") -> :func:`lexicographic_unique`: points with
   equal coordinates are merged, the smallest index is kept.
1. "Sort P by x coordinates" with the fix of slide "Correct?": *lexicographic
   order*, x first, then y for equal x -> the same ``lexicographic_unique``.
2.-3. ``L_upper = (p1, p2)``; for i = 3..n append p_i, then **while** the list
   holds more than two points **and** its last three points do not make a
   right turn, delete the middle one -> the first ``for``/``while`` loop.
4.-5. ``L_lower = (p_n, p_{n-1})``; for i = n-2 down to 1 the same -> the
   second loop.
6. Remove the first and last point of ``L_lower`` (they repeat p_n and p_1).
7. "Concatenate L_lower and L_upper" -> ``L_lower[1:-1] + L_upper``.  The
   lecture seeks the hull in *clockwise* order (the upper chain runs left to
   right); the contract wants counter-clockwise, so the result is reversed.

Readings and quirks kept on purpose:

* **Turn test.**  The lecture gives no formula for "right turn"; the natural
  one is the orientation of the last three points (a, b, c) with the first,
  ``a``, as pivot: :func:`~._predicates2d.turn`, the Kettner et al. formula,
  in plain float64.  Nearly collinear points are misjudged ("Our approach:
  sweep it under the carpet").
* **Collinear rule.**  "Three points which lie on a straight line have to be
  treated as if they make a left turn", so a collinear middle point is deleted
  and never appears in the output; the while condition is ``not right_turn``.
* **Tolerance.**  The lecture compares with zero.  Here "right turn" means
  ``turn(a, b, c) < -eps``: the tolerance widens the collinear band, and by the
  collinear rule a nearly collinear middle point is deleted.  ``eps`` is a
  length (the scaled policy) compared with an area-valued orientation, as the
  project's single eps applies to every algorithm; no rescaling is invented.
  A NaN ``eps`` makes every turn "not right", so the chains collapse.
* **Degenerate input.**  Fewer than two distinct points: step 2 cannot build
  ``(p1, p2)`` -> ``ValueError``.  Two distinct points, or all points
  collinear, give a two-vertex "polygon" ``[p_n, p_1]`` (steps 6-7 leave only
  the ends) -- returned, not raised.  NaN coordinates sort last and make every
  turn test false; the result is whatever the chains leave.
* **Termination.**  Every loop is a ``for`` over the points or a ``while`` that
  deletes a point per turn, so no iteration guard is needed.
"""

from __future__ import annotations

import numpy as np

from .._registry import register_algorithm
from ._predicates2d import as_points_2d, lexicographic_unique, resolve_eps, turn

__all__ = ["monotone_chain"]

_NAME = "monotone-chain"


def _chain(xs: list[float], ys: list[float], start: list[int], rest: range, eps: float) -> list[int]:
    """Steps 2-3 (or 4-5): grow one chain, deleting middles that do not turn right."""
    chain = list(start)
    for i in rest:
        chain.append(i)  # step 3.A
        while len(chain) > 2:  # step 3.B
            a, b = chain[-3], chain[-2]
            if turn(xs[a], ys[a], xs[b], ys[b], xs[i], ys[i]) < -eps:  # a right turn: keep the middle
                break
            del chain[-2]  # step 3.B.i: left turn or collinear (the collinear rule)
    return chain


@register_algorithm(_NAME, dim=2)
def monotone_chain(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """Cardiff lecture incremental hull: lexicographic sort, upper and lower chains.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
        Read-only; never written.
    eps : float or None
        A turn counts as "right" only when its float orientation is below
        ``-eps``.  None means ``tolerance(points, "scaled")``.

    Returns
    -------
    ndarray of shape (h,), int64
        Hull vertex indices, counter-clockwise; no collinear boundary points.

    Raises
    ------
    ValueError
        For a wrong shape, a bad ``eps``, or fewer than two distinct points.

    Examples
    --------
    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5]])
    >>> monotone_chain(sq).tolist()  # the collinear point 4 is dropped
    [2, 3, 0, 1]
    >>> monotone_chain(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0]])).tolist()  # collinear: the two ends
    [1, 0]
    """
    pts = as_points_2d(points, _NAME)
    tol = resolve_eps(pts, eps, _NAME)
    order = lexicographic_unique(pts)  # steps 0-1
    n = int(order.shape[0])
    if n < 2:
        raise ValueError(f"{_NAME}: step 2 needs at least 2 distinct points, got {n}")
    xs = pts[order, 0].tolist()
    ys = pts[order, 1].tolist()
    upper = _chain(xs, ys, [0, 1], range(2, n), tol)  # steps 2-3
    lower = _chain(xs, ys, [n - 1, n - 2], range(n - 3, -1, -1), tol)  # steps 4-5
    clockwise = lower[1:-1] + upper  # steps 6-7
    ccw = clockwise[::-1]
    return order[np.asarray(ccw, dtype=np.int64)]
