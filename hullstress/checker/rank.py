"""Exact affine rank of a point set, and a witness simplex.

The rank decides the sweep's ``rejected`` rule (docs/design.md: an affinely
degenerate case may be declined) and gives the checker its interior point: the
centroid of a non-degenerate simplex of input points lies strictly inside the
convex hull of the input.
"""

from __future__ import annotations

import numpy as np

from .predicates import orient2d, orient3d

__all__ = ["affine_rank", "witness_simplex"]


def _far_pair(points: np.ndarray) -> tuple[int, int] | None:
    """Two points with different coordinates, far apart on the widest axis (None if all equal)."""
    # Column by column: numpy's reductions along axis 0 of an (n, d) array are slow.
    lows = [int(np.argmin(points[:, a])) for a in range(points.shape[1])]
    highs = [int(np.argmax(points[:, a])) for a in range(points.shape[1])]
    spans = [points[highs[a], a] - points[lows[a], a] for a in range(points.shape[1])]
    axis = int(np.argmax(spans))
    if spans[axis] > 0:
        return lows[axis], highs[axis]
    return None  # every coordinate of every axis is constant: one distinct point


def _off_line(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Exactly: which points are not on the line through a and b (dimension 2 or 3)."""
    if points.shape[1] == 2:
        return orient2d(a, b, points) != 0
    off = np.zeros(len(points), dtype=bool)
    for u, v in ((0, 1), (1, 2), (2, 0)):
        todo = np.flatnonzero(~off)
        if not todo.size:
            break
        off[todo] = orient2d(a[[u, v]], b[[u, v]], points[todo][:, [u, v]]) != 0
    return off


def _pick(exact_test, score: np.ndarray) -> int | None:
    """The best-scoring point that passes ``exact_test``, or None when none does.

    The float score (a distance) is only a heuristic: the highest one is tried
    first, and only if it fails exactly are all points tested exactly.
    """
    score = np.nan_to_num(score, nan=0.0, posinf=1e308)
    best = int(np.argmax(score))
    if exact_test(np.array([best]))[0]:
        return best
    hits = np.flatnonzero(exact_test(np.arange(len(score))))
    if not hits.size:
        return None
    return int(hits[np.argmax(score[hits])])


def witness_simplex(points: np.ndarray) -> np.ndarray:
    """Indices of affinely independent input points spanning the affine hull, exactly.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64, finite, d in (2, 3)

    Returns
    -------
    ndarray of shape (r + 1,), int64
        ``r`` is the affine rank; empty for an empty input.  The choice is
        heuristic (far points first, so the simplex is fat and its centroid
        well inside), the independence exact.

    Examples
    --------
    >>> witness_simplex(np.array([[0.0, 0], [1, 1], [2, 2], [0, 1]])).tolist()
    [0, 2, 3]
    >>> witness_simplex(np.array([[1.0, 1.0], [1.0, 1.0]])).tolist()
    [0]
    """
    pts = np.asarray(points, dtype=np.float64)
    n, d = pts.shape
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    # Scores are only a heuristic for which points to try (each choice is then
    # confirmed exactly), so overflow to inf near the double range is harmless.
    with np.errstate(all="ignore"):
        pair = _far_pair(pts)
    if pair is None:
        return np.array([0], dtype=np.int64)
    i, j = pair
    with np.errstate(all="ignore"):
        u = pts[j] - pts[i]
        rel = pts - pts[i]
        if d == 2:
            score = np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0])
        else:
            score = np.einsum("ij,ij->i", c := np.cross(rel, u), c)
    k = _pick(lambda idx: _off_line(pts[idx], pts[i], pts[j]), score)
    if k is None:
        return np.array([i, j], dtype=np.int64)
    if d == 2:
        return np.array([i, j, k], dtype=np.int64)
    with np.errstate(all="ignore"):
        normal = np.cross(u, pts[k] - pts[i])
        score = np.abs(rel @ normal)
    m = _pick(lambda idx: orient3d(pts[i], pts[j], pts[k], pts[idx]) != 0, score)
    if m is None:
        return np.array([i, j, k], dtype=np.int64)
    return np.array([i, j, k, m], dtype=np.int64)


def affine_rank(points: np.ndarray) -> int:
    """Exact affine rank of a 2D or 3D point set.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64, finite, d in (2, 3)

    Returns
    -------
    int
        -1 for an empty set (the dimension of the empty affine hull), 0 when
        every point is the same, 1 when all are collinear, 2 when all are
        coplanar (in 3D) or the set is full-dimensional in 2D, 3 for a
        full-dimensional 3D set.

    Raises
    ------
    ValueError
        When ``points`` is not an (n, 2) or (n, 3) array of finite values.

    Examples
    --------
    >>> affine_rank(np.array([[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]]))  # collinear
    1
    >>> affine_rank(np.array([[0.0, 0.0], [1.0, 3.0], [0.1, 0.3]]))  # not exactly collinear
    2
    >>> affine_rank(np.zeros((0, 3)))
    -1
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    if not np.isfinite(pts).all():
        raise ValueError("points must be finite, got NaN or inf coordinates")
    return len(witness_simplex(pts)) - 1
