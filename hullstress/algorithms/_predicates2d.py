"""Shared pieces of the three in-house 2D hulls: input checks, eps, the seeds' float tests.

Everything here is plain floating point, written the way the seed documents
write it.  None of it is exact or robust: these functions are part of the code
under test, and their rounding errors are the weak spots the harness looks for.

* :func:`turn` -- the orientation of three points with the *first* point as
  pivot, ``(bx - ax) * (cy - ay) - (by - ay) * (cx - ax)``: positive for a left
  (counter-clockwise) turn.  This is the formula of the Kettner et al.
  classroom examples; the monotone chain evaluates "right turn" with it.
* :func:`left_normal_lines` / the expression in :func:`line_side` -- the
  Cardiff lecture's sidedness test: the line ``l^t x - d = 0`` with ``l`` the
  unit normal pointing to the left of ``p -> q`` and ``d = l^t p``; ``r`` is
  left when ``l^t r - d`` is positive.  It is not pivoted at ``p``: both dot
  products are taken in absolute coordinates, so large offsets cancel badly.

The tests compare against a tolerance ``eps`` in place of the seeds' zero;
:func:`resolve_eps` turns ``eps=None`` into ``tolerance(points, "scaled")``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..tolerance import tolerance

__all__ = [
    "as_points_2d",
    "resolve_eps",
    "lexicographic_unique",
    "turn",
    "left_normal_lines",
    "line_side",
]


def as_points_2d(points: Any, algorithm: str) -> np.ndarray:
    """Return ``points`` as an (n, 2) float64 array (no copy when already one).

    Raises
    ------
    ValueError
        If the array is not of shape (n, 2).
    """
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"{algorithm}: points must be an (n, 2) float array, got {type(points).__name__}: {exc}"
        ) from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{algorithm}: points must have shape (n, 2), got {arr.shape}")
    return arr


def resolve_eps(points: np.ndarray, eps: float | None, algorithm: str) -> float:
    """The comparison tolerance: ``eps`` itself, or the "scaled" policy when None.

    A NaN ``eps`` (what the scaled policy gives for NaN input) is passed
    through: every comparison against it is false, as it would be in the seeds.

    Raises
    ------
    ValueError
        If ``eps`` is not a real number or is negative.
    """
    if eps is None:
        return tolerance(points, "scaled")
    if isinstance(eps, (bool, np.bool_)):
        raise ValueError(f"{algorithm}: eps must be a float or None, got {eps!r}")
    try:
        value = float(eps)
    except (TypeError, ValueError):
        raise ValueError(f"{algorithm}: eps must be a float or None, got {eps!r}") from None
    if value < 0:
        raise ValueError(f"{algorithm}: eps must be >= 0 or None, got {value!r}")
    return value


def lexicographic_unique(points: np.ndarray) -> np.ndarray:
    """Indices of the distinct points, sorted by x, then y (the lecture's order).

    Of several points with equal coordinates (compared with ``==``, so
    ``-0.0 == 0.0``) the one with the smallest index is kept.  NaN never
    equals anything, so rows holding NaN are all kept (they sort last).

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64

    Returns
    -------
    ndarray of shape (m,), int64
        Row indices in lexicographic order of their points, m <= n.

    Examples
    --------
    >>> lexicographic_unique(np.array([[1.0, 0.0], [0.0, 2.0], [0.0, 1.0], [1.0, 0.0]])).tolist()
    [2, 1, 0]
    """
    x = points[:, 0]
    y = points[:, 1]
    order = np.lexsort((y, x))  # stable: equal points stay in index order
    xs, ys = x[order], y[order]
    keep = np.ones(order.shape[0], dtype=bool)
    keep[1:] = (xs[1:] != xs[:-1]) | (ys[1:] != ys[:-1])
    return order[keep].astype(np.int64, copy=False)


def turn(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    """Orientation of (a, b, c) in float, pivot ``a``: > 0 left turn, < 0 right turn.

    Examples
    --------
    >>> turn(0.0, 0.0, 1.0, 0.0, 1.0, 1.0), turn(0.0, 0.0, 1.0, 1.0, 2.0, 2.0)
    (1.0, 0.0)
    """
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def left_normal_lines(
    px: float, py: float, qx: np.ndarray, qy: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lecture's line ``l^t x - d = 0`` through ``p`` and each ``q``.

    ``l = (-(qy - py), qx - px) / |q - p|`` (orthogonal to ``p -> q``,
    pointing left, unit length so that ``d`` is the line's distance from the
    origin) and ``d = l^t p``.  ``q == p`` gives NaN (0 / 0); the caller must
    silence floating-point warnings.

    Returns
    -------
    lx, ly, d : ndarray of shape (k,), float64
    """
    dx = qx - px
    dy = qy - py
    length = np.sqrt(dx * dx + dy * dy)
    lx = -dy / length
    ly = dx / length
    d = lx * px + ly * py
    return lx, ly, d


def line_side(lx: Any, ly: Any, d: Any, rx: Any, ry: Any) -> Any:
    """``l^t r - d`` (positive: ``r`` left of the line), evaluated as ``(lx*rx + ly*ry) - d``.

    Broadcasts; every caller uses this one expression so that batching the
    work differently never changes a rounding.
    """
    return (lx * rx + ly * ry) - d
