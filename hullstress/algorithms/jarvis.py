"""The Unity tutorial's Jarvis march with collinear points, registered as ``jarvis-march`` (literal) and ``jarvis-march-sorted``.

Seed: ``003_c44ed1a926a0d37c.txt`` ("Gift Wrapping Convex Hull Algorithm With
Unity Implementation", the ``Update()`` method of ``JarvisMarchConvexHull``).
The tutorial does not number its steps; this module numbers them so:

1. Leftmost point: ``leftMostIndex = 0``; for i = 1..n-1, **if**
   ``points[leftMostIndex].x > points[i].x`` then ``leftMostIndex = i``;
   ``result.Add(leftmost)`` -> :func:`_leftmost`.
2. ``collinearPoints = new List`` (created once, *outside* the loop);
   ``current = leftmost``.
3. **while (true)**, the wrap -> :func:`_wrap`:

   a. ``nextTarget = points[0]``; for i = 1..n-1, skipping ``points[i] ==
      current``: ``val = (y2*x1) - (y1*x2)`` with ``x1 = cx - nx``,
      ``x2 = cx - ix``, ``y1 = cy - ny``, ``y2 = cy - iy``;
      **if** ``val > 0``: ``nextTarget = points[i]`` and the collinear list is
      replaced by a new empty one; **else if** ``val == 0``: if
      ``Distance(current, nextTarget) < Distance(current, points[i])`` the
      old ``nextTarget`` joins the collinear list and ``points[i]`` becomes
      ``nextTarget``, otherwise ``points[i]`` joins the list -> :func:`_scan`.
   b. Every point of the collinear list is added to ``result``.
   c. **if** ``nextTarget == leftmost``: break.
   d. ``result.Add(nextTarget)``; ``current = nextTarget``.
4. ``result`` is a ``HashSet`` (adding a member again does nothing) ->
   :func:`jarvis_march` turns it into a polygon (below).

Readings and quirks kept on purpose:

* **Leftmost** is the *first* index with the smallest x; equal x is not broken
  by y.  When that point lies strictly inside a vertical left edge the wrap
  never comes back to it (it jumps from corner to corner past it): see the
  guard below.  NaN in ``points[0].x`` keeps index 0 as "leftmost" (every
  comparison with NaN is false); other NaN x never win.
* **Identity, not coordinates**: ``points[i] == current`` compares Unity
  ``Transform`` objects, i.e. indices here.  ``nextTarget`` starts as
  ``points[0]`` even when that is ``current``; the ``val == 0`` branch then
  moves on (distance 0 is shorter than any other).
* **The collinear list is not cleared between iterations** of the wrap, only
  when a ``val > 0`` candidate appears; left-over entries are already in
  ``result``, so re-adding them changes nothing.  A point collinear with the
  current *candidate* line is collected even if that candidate is later
  replaced by a farther collinear one (the replaced candidate is collected
  too): that is how points between ``current`` and ``nextTarget`` are kept.
* **Arithmetic**: the tutorial's C# ``float`` is read as the input's float64;
  ``val`` is exactly the tutorial's expression (pivot ``current``), distances
  are ``sqrt(dx*dx + dy*dy)`` of ``current - other`` as ``Vector2.Distance``.
* **Tolerance.**  The seed compares ``val`` with 0 twice; here ``val > eps``
  is "left" and ``-eps <= val <= eps`` is "collinear" (``val == 0`` when
  ``eps == 0``).  The distance comparison is not a comparison with zero and
  stays strict.  ``val`` is an area and ``eps`` (scaled policy) a length;
  the project's one eps is used as given, no rescaling is invented.  A NaN
  ``eps`` makes both tests false for every point.
* **Direction and output order.**  The scan replaces ``nextTarget`` by any
  point to its *left*, so the final ``nextTarget`` has every point on its
  right and the wrap runs *clockwise*.  The seed's result is a ``HashSet``,
  and its only order is the one its drawing code (``OnDrawGizmos``) uses: the
  members in insertion order, each joined to the next and the last to the
  first.  That is the polygon ``jarvis-march`` returns: the leftmost point,
  then per iteration the new members of the collinear list *in list order*
  (the order the scan collected them, which is index order among the points
  it met, not their order along the edge), then ``nextTarget`` if new; the
  whole sequence reversed (keeping the leftmost first), because the contract
  wants counter-clockwise.  **This is the seed's weakness, kept**: when an
  edge holds two or more collinear points and the scan meets them out of
  distance order, the polygon zigzags along that edge (the checker reports it
  as not simple).
* **The named variant** ``jarvis-march-sorted`` (an improvement on the seed)
  sorts each iteration's new collinear members by their distance from
  ``current`` (stable for ties) before adding them, so collinear boundary
  points come out in boundary order.  Everything else is shared.
* **Termination guard.**  Step 3.a's result depends on ``current`` only (the
  collinear list is output, never input), so once a ``nextTarget`` that is
  not the leftmost point comes up a second time the wrap would repeat the
  same cycle forever.  That is detected exactly, after at most n + 1
  iterations, and raises :class:`~hullstress.errors.AlgorithmStepLimit`.  It
  is reachable: a leftmost point inside a vertical edge, NaN coordinates, or
  float noise that makes a corner lose to a point it has already passed.
* **Degenerate input.**  No points: step 1 has no ``points[0]`` ->
  ``ValueError``.  One point: ``[0]``.  Collinear points: the wrap goes to
  the far end and back, collecting the middle points (unless the guard
  fires), and the "polygon" runs out and back along the line.

Speed: step 3.a is one sequential scan whose state (``nextTarget``) changes as
it goes.  It is evaluated on windows of points with numpy: every test of the
window is computed against the current ``nextTarget``, the first index where
the seed would change ``nextTarget`` is found with ``argmax``, and the scan
resumes just after it with the new ``nextTarget`` -- the same tests, in the
same order, on the same float values.  Where changes come thick and fast
(points sorted by angle), short stretches run as a plain Python loop instead.
"""

from __future__ import annotations

import math

import numpy as np

from .._registry import register_algorithm
from ..errors import AlgorithmStepLimit
from ._predicates2d import as_points_2d, resolve_eps
from ._variant import SeedVariant

__all__ = ["jarvis_march", "jarvis_march_sorted"]

_WINDOW_START = 256  # first numpy window of a scan, doubled while nothing changes
_WINDOW_MAX = 1 << 16
_DENSE = 16  # a change this close to the window start: changes are dense here...
_SCALAR_RUN = 128  # ...so scan this many points in plain Python before trying numpy again


#: The result set in insertion order, as written; and collinear points sorted by distance (the improvement).
LITERAL = SeedVariant("jarvis-march", improved=False)
SORTED = SeedVariant("jarvis-march-sorted", improved=True)


def _leftmost(x: np.ndarray) -> int:
    """Step 1: the seed's strict ``>`` loop -- the first index of the smallest x, NaN never wins."""
    if math.isnan(x[0]):
        return 0
    return int(np.nanargmin(x))


def _scan_python(
    x2: np.ndarray, y2: np.ndarray, dist: np.ndarray, cur: int, eps: float,
    nt: int, coll: list[int], start: int, stop: int,
) -> tuple[int, list[int]]:
    """Step 3.a, literally, for i in [start, stop) (x2 = cx - x, y2 = cy - y)."""
    xs = x2[start:stop].tolist()
    ys = y2[start:stop].tolist()
    ds = dist[start:stop].tolist()
    x1, y1, dn = float(x2[nt]), float(y2[nt]), float(dist[nt])
    for k in range(stop - start):
        i = start + k
        if i == cur:
            continue
        val = (ys[k] * x1) - (y1 * xs[k])
        if val > eps:
            nt, x1, y1, dn = i, xs[k], ys[k], ds[k]
            coll = []
        elif -eps <= val <= eps:
            if dn < ds[k]:
                coll.append(nt)
                nt, x1, y1, dn = i, xs[k], ys[k], ds[k]
            else:
                coll.append(i)
    return nt, coll


def _scan(
    x2: np.ndarray, y2: np.ndarray, dist: np.ndarray, cur: int, eps: float, coll: list[int]
) -> tuple[int, list[int]]:
    """Step 3.a: the final ``nextTarget`` and collinear list of one scan (see the module notes)."""
    n = x2.shape[0]
    nt = 0
    i = 1
    window = _WINDOW_START
    while i < n:
        stop = min(n, i + window)
        x1, y1, dn = x2[nt], y2[nt], dist[nt]
        val = (y2[i:stop] * x1) - (y1 * x2[i:stop])  # the seed's val; x2, y2 precomputed
        left = val > eps
        col = (val >= -eps) & ~left
        far = col & (dn < dist[i:stop])
        if i <= cur < stop:  # "if (points[i] == current) continue"
            left[cur - i] = col[cur - i] = far[cur - i] = False
        change = left | far
        k = int(np.argmax(change))
        if not change[k]:
            coll.extend((np.flatnonzero(col) + i).tolist())
            i = stop
            window = min(2 * window, _WINDOW_MAX)
            continue
        if left[k]:
            coll = []  # "collinearPoints = new List<Transform>()"
        else:
            coll.extend((np.flatnonzero(col[:k]) + i).tolist())
            coll.append(nt)
        nt = i + k
        i = nt + 1
        window = _WINDOW_START
        if k < _DENSE and i < n:
            stop = min(n, i + _SCALAR_RUN)
            nt, coll = _scan_python(x2, y2, dist, cur, eps, nt, coll, i, stop)
            i = stop
    return nt, coll


def _wrap(pts: np.ndarray, eps: float, name: str = LITERAL.name) -> tuple[int, list[tuple[int, int, list[int]]]]:
    """Steps 1-3: the leftmost index and, per wrap iteration, (current, nextTarget, collinear list).

    Raises
    ------
    AlgorithmStepLimit
        When the wrap would never return to the leftmost point.
    """
    x = np.ascontiguousarray(pts[:, 0])
    y = np.ascontiguousarray(pts[:, 1])
    lm = _leftmost(x)  # step 1
    coll: list[int] = []  # step 2
    cur = lm
    visited = {lm}
    steps: list[tuple[int, int, list[int]]] = []
    while True:  # step 3; ends by break or by the guard below (at most n + 1 turns)
        x2 = x[cur] - x
        y2 = y[cur] - y
        dist = np.sqrt(x2 * x2 + y2 * y2)  # Vector2.Distance(current, points[i])
        nt, coll = _scan(x2, y2, dist, cur, eps, coll)  # step 3.a
        steps.append((cur, nt, list(coll)))  # step 3.b happens in jarvis_march
        if nt == lm:  # step 3.c
            return lm, steps
        if nt in visited:
            raise AlgorithmStepLimit(
                f"{name}: step 3 (wrap) would never end: point {nt} is nextTarget again after "
                f"{len(steps)} iterations and the wrap never returns to the leftmost point {lm}"
            )
        visited.add(nt)
        cur = nt  # step 3.d


def _polygon(pts: np.ndarray, lm: int, steps: list[tuple[int, int, list[int]]], variant: SeedVariant) -> np.ndarray:
    """Step 3.b-d's additions to the result set, in insertion order, as a counter-clockwise polygon."""
    order = [lm]
    in_result = {lm}
    for cur, nt, coll in steps:
        new = [t for t in dict.fromkeys(coll) if t not in in_result]  # step 3.b, HashSet.Add
        if new and variant.improved:
            d = pts[new] - pts[cur]
            by_distance = np.argsort(np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]), kind="stable")
            new = [new[j] for j in by_distance]
        order.extend(new)
        in_result.update(new)
        if nt != lm and nt not in in_result:  # step 3.d, HashSet.Add
            order.append(nt)
            in_result.add(nt)
    ccw = [order[0]] + order[:0:-1]  # the wrap ran clockwise
    return np.asarray(ccw, dtype=np.int64)


def _run(points: np.ndarray, eps: float | None, variant: SeedVariant) -> np.ndarray:
    """Validate, wrap, and lay the result set out as a polygon."""
    pts = as_points_2d(points, variant.name)
    tol = resolve_eps(pts, eps, variant.name)
    if pts.shape[0] == 0:
        raise ValueError(f"{variant.name}: step 1 (leftmost point) needs at least 1 point, got 0")
    with np.errstate(invalid="ignore", over="ignore"):
        lm, steps = _wrap(pts, tol, variant.name)
        return _polygon(pts, lm, steps, variant)


@register_algorithm(LITERAL.name, dim=2)
def jarvis_march(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """Unity tutorial Jarvis march: wrap from the leftmost point, keeping collinear points, as written.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
        Read-only; never written.
    eps : float or None
        ``val > eps`` is "left", ``|val| <= eps`` is "collinear" (the seed
        compares with 0).  None means ``tolerance(points, "scaled")``.

    Returns
    -------
    ndarray of shape (h,), int64
        The seed's result set in insertion order (the order its drawing code
        joins), reversed to run counter-clockwise, starting at the leftmost
        point; collinear points in the order the scans collected them.

    Raises
    ------
    ValueError
        For a wrong shape, a bad ``eps``, or no points at all.
    AlgorithmStepLimit
        When the wrap would never return to the leftmost point.

    See Also
    --------
    jarvis_march_sorted : the same, with collinear points in boundary order.

    Examples
    --------
    >>> sq = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 0.0], [1.0, 1.0]])
    >>> jarvis_march(sq).tolist()  # keeps 4, the midpoint of the bottom edge
    [0, 4, 1, 2, 3]

    Two points inside the bottom edge, met by the last scan in index order:
    the nearer one to the edge's end ``(3, 0)`` is row 5, but row 4 was added
    first, so the polygon runs 0 -> 5 -> 4 -> 1 and doubles back:

    >>> edge = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0], [1.0, 0.0], [2.0, 0.0]])
    >>> jarvis_march(edge).tolist()
    [0, 5, 4, 1, 2, 3]
    >>> left_edge_middle_first = np.array([[0.0, 1.0], [0.0, 0.0], [0.0, 2.0], [1.0, 0.0], [1.0, 2.0]])
    >>> jarvis_march(left_edge_middle_first)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    hullstress.errors.AlgorithmStepLimit: jarvis-march: step 3 (wrap) would never end: ...
    """
    return _run(points, eps, LITERAL)


@register_algorithm(SORTED.name, dim=2)
def jarvis_march_sorted(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """Jarvis march with each edge's collinear points sorted by distance (a named improvement on the seed).

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
        Read-only; never written.
    eps : float or None
        As for :func:`jarvis_march`.

    Returns
    -------
    ndarray of shape (h,), int64
        The seed's result set, counter-clockwise in boundary order, starting
        at the leftmost point; collinear boundary points included.

    Raises
    ------
    ValueError, AlgorithmStepLimit
        As for :func:`jarvis_march`.

    Examples
    --------
    >>> edge = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0], [1.0, 0.0], [2.0, 0.0]])
    >>> jarvis_march_sorted(edge).tolist()
    [0, 4, 5, 1, 2, 3]
    """
    return _run(points, eps, SORTED)
