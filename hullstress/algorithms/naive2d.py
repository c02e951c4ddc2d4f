"""The Cardiff lecture's naive O(n^3) hull, registered as ``naive-2d``.

Seed: ``004_3607bf1c5abd6a5b.txt`` (Sun and Langbein, CM0304 Graphics, II.7,
slides "Naive Approach" and "Algorithm Details").  Map from the seed's steps
to the code:

0. "Assume all points are distinct (otherwise sort and remove duplicates)"
   (slide "Computational Problem") -> :func:`lexicographic_unique`; of equal
   points the smallest index is kept.  The remaining points are then visited
   in index order.
1. **For** all pairs (p, q) of points -> :func:`_accepted_targets` is called for
   every p and decides every q at once (ordered pairs: p -> q and q -> p are
   different directed lines).
1.A-i. **For** all r in P - {p, q}: **if** r lies to the left of the directed
   line p -> q, reject the pair.  "Algorithm Details": the line is
   ``l^t x - d = 0`` with ``l`` orthogonal to p -> q pointing left and ``d``
   the line's distance from the origin, and r is left if ``l^t r - d > 0``
   (:func:`~._predicates2d.left_normal_lines`, :func:`~._predicates2d.line_side`).
1.B. Otherwise add (p, q) to E -> :func:`accepted_edges` lists E in the order
   the loops would add it: p ascending, then q ascending.
3. "Order edges in E to form the boundary", "Sort them by concatenating edges
   with common vertices" -> :func:`_walk`.

Readings and quirks kept on purpose:

* **The side test** is the lecture's, in float64: ``l`` is normalised (that is
  what makes ``d`` a distance), ``d = l^t p``, and ``l^t r - d`` is evaluated
  as ``(lx*rx + ly*ry) - d`` in absolute coordinates -- no pivot, so large
  coordinates cancel badly.  The early exit "go to 2" only saves time; the
  accepted set E does not depend on the order in which the r are tried.
* **Tolerance.**  r is "left" when ``l^t r - d > eps`` (the seed compares with
  0).  With a unit ``l`` the left side is a signed distance, so ``eps`` (a
  length) is compared with a length; points within ``eps`` of the line count
  as on it, like Nathan's "counted as on the negative side".  Larger eps
  accepts more edges.
* **Orientation.**  An accepted edge has no point to its left, so E runs
  clockwise (the lecture "seeks the points of H(P) in clockwise order").  The
  contract wants counter-clockwise: the walk's result is reversed.
* **Step 3, the natural assembly.**  Start at the first edge of E; from each
  vertex follow the *first* edge of E that starts there (E's order above);
  stop on returning to the start.  Edges the walk never uses are ignored:
  with a boundary point b between corners a and c, E holds a->b, b->c *and*
  a->c, and the walk keeps b or not depending on whether b's index is smaller
  than c's.  If a vertex has no outgoing edge, or the walk comes back to a
  vertex other than the start (the edges do not close into one cycle through
  it), step 3 raises ``ValueError`` naming the vertex.  The walk visits each
  vertex at most once, so it cannot loop forever (no iteration guard needed).
* **Degenerate input.**  Fewer than two distinct points: E is empty ->
  ``ValueError``.  All points collinear: every ordered pair has nothing to
  its left, E holds both directions, and the walk returns a two-vertex
  polygon (first point, its first partner).  NaN coordinates make every test
  involving them false, so such points are never "left" of anything and every
  pair through them is accepted; the result is whatever the walk gives.

Speed: the r-loop (1.A) is vectorised, over the pairs of many sources p at
once (in cache-sized chunks).  Every pair is first tried against a
few points that are extreme in fixed directions (most non-edges have one of
them on their left), survivors against all points; a pair is rejected only
after an actual float evaluation ``l^t r - d > eps`` of the seed's formula, so
the result is identical to the triple loop, only faster.  This reorders the
r-loop and nothing else: E, the walk and every float value are the seed's.
It does not change the seed's worst case, O(n^3) ("Algorithm Analysis"):
on points in convex position on a flat arc the probe directions find only the
arc's ends and middle, so about n^2/4 ordered pairs reach the full O(n) test
(and in arc order the seed's own "go to 2", trying r in index order, runs
about min(i, j) tests for the pair (i, j) before it may stop).
``benchmarks/bench_algorithms.py`` measures that input as naive-2d's worst
case; on uniform random points, where the probes reject almost every pair,
the growth is near n^2.
"""

from __future__ import annotations

import numpy as np

from .._registry import register_algorithm
from ._predicates2d import (
    as_points_2d,
    left_normal_lines,
    lexicographic_unique,
    line_side,
    resolve_eps,
)

__all__ = ["naive_2d", "accepted_edges"]

_NAME = "naive-2d"
# Witness stages: support points of 8, then 64, evenly spaced directions.
_WITNESS_DIRECTIONS = (8, 64)
# Side tests evaluated at once (elements): small enough for the temporaries to stay in cache.
_CHUNK = 1 << 15
# Lines p -> q held at once (three float64 arrays of this many elements).
_LINES = 1 << 15


def _support_points(x: np.ndarray, y: np.ndarray, k: int) -> np.ndarray:
    """Indices of the points extreme in ``k`` evenly spaced directions (an evaluation order only)."""
    ang = np.arange(k) * (2.0 * np.pi / k)
    proj = np.cos(ang)[:, None] * x[None, :] + np.sin(ang)[:, None] * y[None, :]
    return np.unique(np.argmax(proj, axis=1))


def _witness_stages(x: np.ndarray, y: np.ndarray) -> list[np.ndarray]:
    stages: list[np.ndarray] = []
    seen = np.zeros(0, dtype=np.int64)
    for k in _WITNESS_DIRECTIONS:
        w = np.setdiff1d(_support_points(x, y, k), seen)
        if w.size:
            stages.append(w)
            seen = np.union1d(seen, w)
    return stages


def _accepted_targets(
    ps: np.ndarray, x: np.ndarray, y: np.ndarray, eps: float, stages: list[np.ndarray]
) -> list[np.ndarray]:
    """Steps 1.A-1.B for the sources ``ps``: per p, the q (ascending) with no r strictly left of p -> q.

    The pairs (p, q) of all the sources are tested together, in chunks of at
    most ``_CHUNK`` side tests; every line and every side test is the same
    elementwise float expression as for one pair, so batching changes no
    rounding.
    """
    m = x.shape[0]
    k = ps.size
    lx, ly, d = left_normal_lines(x[ps, None], y[ps, None], x[None, :], y[None, :])  # (k, m): line p -> q
    # Pair (ps[i], q) at flat index i * m + q.
    lx, ly, d = lx.ravel(), ly.ravel(), d.ravel()
    alive = np.ones(k * m, dtype=bool)
    alive[np.arange(k) * m + ps] = False
    for w in (*stages, None):  # the witness stages, then every point (None)
        pair = np.flatnonzero(alive)  # q ascending within each p
        if pair.size == 0:
            break
        src, q = np.divmod(pair, m)
        rx, ry = (x, y) if w is None else (x[w], y[w])
        # r ranges over P - {p, q}: the column of p and of q, where the stage holds them.
        col = np.arange(m) if w is None else np.full(m, -1, dtype=np.int64)
        if w is not None:
            col[w] = np.arange(w.size)
        rejected = np.zeros(q.size, dtype=bool)
        step = max(1, _CHUNK // rx.size)
        for start in range(0, q.size, step):
            at, s, c = pair[start : start + step], src[start : start + step], q[start : start + step]
            left = line_side(lx[at, None], ly[at, None], d[at, None], rx[None, :], ry[None, :]) > eps
            for own in (ps[s], c):
                rows = np.flatnonzero(col[own] >= 0)
                left[rows, col[own[rows]]] = False
            rejected[start : start + step] = left.any(axis=1)
        alive[pair[rejected]] = False
    src, q = np.divmod(np.flatnonzero(alive), m)
    return np.split(q, np.cumsum(np.bincount(src, minlength=k))[:-1])


def _edges_by_source(pts: np.ndarray, eps: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """Steps 0-2: the distinct points' indices (ascending) and, per point, its accepted targets."""
    uniq = np.sort(lexicographic_unique(pts))  # step 0, then visit in index order
    x = np.ascontiguousarray(pts[uniq, 0])
    y = np.ascontiguousarray(pts[uniq, 1])
    m = x.size
    targets: list[np.ndarray] = []
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        stages = _witness_stages(x, y) if m else []
        per_block = max(1, _LINES // max(m, 1))  # sources whose lines p -> q are held at once
        for start in range(0, m, per_block):  # step 1
            targets.extend(_accepted_targets(np.arange(start, min(m, start + per_block)), x, y, eps, stages))
    return uniq, targets


def accepted_edges(points: np.ndarray, *, eps: float | None = None) -> np.ndarray:
    """The lecture's edge set E (steps 0-2): directed pairs with no point to their left.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    eps : float or None
        A point is "left" of p -> q when ``l^t r - d > eps``; None means
        ``tolerance(points, "scaled")``.

    Returns
    -------
    ndarray of shape (k, 2), int64
        Rows ``(p, q)`` as indices of the input, in the order the seed's loops
        add them (p ascending, then q ascending).  Clockwise edges.

    Examples
    --------
    >>> tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0]])
    >>> accepted_edges(tri).tolist()  # 3 lies on edge 1 -> 0: E has 1->0, 1->3 and 3->0
    [[0, 2], [1, 0], [1, 3], [2, 1], [3, 0]]
    """
    pts = as_points_2d(points, _NAME)
    tol = resolve_eps(pts, eps, _NAME)
    uniq, targets = _edges_by_source(pts, tol)
    rows = [np.column_stack([np.full(t.size, uniq[p]), uniq[t]]) for p, t in enumerate(targets) if t.size]
    if not rows:
        return np.zeros((0, 2), dtype=np.int64)
    edges = np.concatenate(rows).astype(np.int64, copy=False)
    return edges[np.lexsort((edges[:, 1], edges[:, 0]))]


def _walk(first_out: np.ndarray, start: int, labels: np.ndarray) -> list[int]:
    """Step 3: follow the first outgoing edge from each vertex until back at ``start``."""
    cycle = [start]
    seen = {start}
    v = int(first_out[start])
    while v != start:
        if v < 0:
            raise ValueError(
                f"{_NAME}: step 3 (order edges): vertex {labels[cycle[-1]]} has no accepted "
                f"outgoing edge, so the edges do not close into a cycle"
            )
        if v in seen:
            raise ValueError(
                f"{_NAME}: step 3 (order edges): the walk from vertex {labels[start]} came back "
                f"to vertex {labels[v]}, so the edges do not form one cycle through the start"
            )
        cycle.append(v)
        seen.add(v)
        v = int(first_out[v])
    return cycle


@register_algorithm(_NAME, dim=2)
def naive_2d(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """Cardiff lecture naive hull: keep every directed pair with no point to its left.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
        Read-only; never written.
    eps : float or None
        A point is "left" of p -> q when its signed distance ``l^t r - d``
        exceeds ``eps``.  None means ``tolerance(points, "scaled")``.

    Returns
    -------
    ndarray of shape (h,), int64
        Vertex indices, counter-clockwise, assembled from the accepted edges
        by following, from each vertex, its first accepted edge.

    Raises
    ------
    ValueError
        For a wrong shape or bad ``eps``; when no edge is accepted (fewer
        than two distinct points); when the accepted edges do not close into
        a cycle through the first edge's start.

    Examples
    --------
    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    >>> naive_2d(sq).tolist()
    [0, 1, 2, 3]
    >>> naive_2d(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])).tolist()  # collinear: a 2-gon
    [0, 1]
    """
    pts = as_points_2d(points, _NAME)
    tol = resolve_eps(pts, eps, _NAME)
    uniq, targets = _edges_by_source(pts, tol)
    first_out = np.array([int(t[0]) if t.size else -1 for t in targets], dtype=np.int64)
    sources = np.flatnonzero(first_out >= 0)
    if sources.size == 0:
        raise ValueError(
            f"{_NAME}: step 3 (order edges): no edge was accepted among {uniq.size} distinct "
            f"points; need at least 2"
        )
    clockwise = _walk(first_out, int(sources[0]), uniq)
    ccw = [clockwise[0]] + clockwise[:0:-1]
    return uniq[np.asarray(ccw, dtype=np.int64)]
