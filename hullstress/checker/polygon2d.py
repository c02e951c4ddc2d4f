"""Convexity, manifoldness and vertex classification of a 2D hull (a polygon), exactly.

Manifoldness (docs/design.md): a simple closed counter-clockwise polygon without
repeated vertices: at least three vertices, no repeated index, no repeated
coordinates, no two edges meeting except consecutive edges at their shared
vertex (and those not overlapping), positive signed area (exact).

Convexity, the 2D reading of the 3D conditions: no zero-length edge (a
degenerate facet); at every vertex the next vertex is not strictly right of
the previous edge (no reflex vertex); one interior point strictly left of every
edge (the vertices' mean when it passes exactly and some turn is strictly
left, else the exact centroid of a triangle of the polygon's vertices); and
the polygon winds once around it (:func:`.wrap.wrap_number_2d`: a locally
convex polygon that winds twice, like a {7/2} star, fails only this test).

Soundness: every turn and crossing is an exact predicate; "far ends on the same
side" is read from comparisons, not products of differences.  The pairwise
crossing test looks only at edges whose x-extents overlap (a sweep, issue 33).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._geometry import point_line_distance, surface_interior, vertex_mean
from ._unique import unique_ints
from .measure import Measure, surface_measure
from .predicates import orient2d, orient2d_mean
from .wrap import wrap_number_2d

__all__ = ["Polygon2D", "check_polygon2d", "self_intersections"]

_PAIR_CHUNK = 1_000_000


@dataclass
class Polygon2D:
    """What the 2D checks found.

    Attributes
    ----------
    manifold_ok, convex_ok : bool
    bad_vertices : ndarray of int64
        Positions in the polygon where manifoldness breaks (repeats, crossings).
    degenerate_edges : ndarray of int64
        Edge positions ``i`` (from vertex ``i`` to ``i + 1``) of zero length.
    reflex : ndarray of int64
        Vertex positions where the polygon turns right.
    flipped : ndarray of int64
        Edge positions with the interior point not strictly left.
    turn : ndarray of shape (k,), int8
        Exact turn sign at each vertex position.
    center : ndarray of shape (2,) or None
        A float point verified strictly left of every edge.
    magnitudes : dict of str to float
    reasons_manifold, reasons_convex : list of str
    wraps : int or None
        How many times the polygon winds around its interior point (when tested).
    """

    manifold_ok: bool
    convex_ok: bool
    bad_vertices: np.ndarray
    degenerate_edges: np.ndarray
    reflex: np.ndarray
    flipped: np.ndarray
    turn: np.ndarray
    center: np.ndarray | None
    magnitudes: dict[str, float] = field(default_factory=dict)
    reasons_manifold: list[str] = field(default_factory=list)
    reasons_convex: list[str] = field(default_factory=list)
    wraps: int | None = None


def _segments_meet(p1, p2, q1, q2) -> np.ndarray:
    """Exactly: do the closed segments p1p2 and q1q2 share a point?"""
    o1, o2 = orient2d(p1, p2, q1), orient2d(p1, p2, q2)
    o3, o4 = orient2d(q1, q2, p1), orient2d(q1, q2, p2)
    crossing = (o1.astype(np.int16) * o2 <= 0) & (o3.astype(np.int16) * o4 <= 0)
    # All four zero: a zero-length segment is collinear with the other only when it lies
    # on that one's line (testing o1, o2 alone made a point inside the other's box "meet" it).
    collinear = (o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0)
    # Collinear segments meet iff their bounding boxes overlap (exact comparisons).
    overlap = np.all(
        (np.minimum(p1, p2) <= np.maximum(q1, q2)) & (np.minimum(q1, q2) <= np.maximum(p1, p2)), axis=1
    )
    return np.where(collinear, overlap, crossing)


def self_intersections(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Positions of edges that touch a non-adjacent edge or fold back onto the next one.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    poly : ndarray of shape (k,), int64

    Returns
    -------
    ndarray of int64
        Edge positions ``i`` (edge from ``poly[i]`` to ``poly[i + 1]``), sorted.

    Examples
    --------
    >>> pts = np.array([[0.0, 0], [2, 0], [0, 2], [2, 2]])
    >>> self_intersections(pts, np.array([0, 1, 2, 3])).tolist()  # a bow tie
    [1, 3]
    """
    k = len(poly)
    a = points[poly]
    b = points[np.roll(poly, -1)]
    bad = np.zeros(k, dtype=bool)
    if k < 3:
        return np.zeros(0, dtype=np.int64)
    # Consecutive edges fold back when collinear and the far ends lie on the same side.
    c = points[np.roll(poly, -2)]
    col = orient2d(a, b, c) == 0
    # Same side of b on some axis, by comparisons (exact; a product of differences could
    # underflow to 0 or overflow).
    side_a = (a > b).astype(np.int8) - (a < b).astype(np.int8)
    side_c = (c > b).astype(np.int8) - (c < b).astype(np.int8)
    back = col & np.any(side_a * side_c > 0, axis=1)
    bad |= back
    bad[np.flatnonzero(back) + 1 - k] = True
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    for ii, jj in _box_pairs(lo, hi):
        gap = (jj - ii) % k
        keep = (gap > 1) & (gap < k - 1)
        ii, jj = ii[keep], jj[keep]
        boxes = np.all((lo[ii] <= hi[jj]) & (lo[jj] <= hi[ii]), axis=1)
        ii, jj = ii[boxes], jj[boxes]
        if ii.size:
            meet = _segments_meet(a[ii], b[ii], a[jj], b[jj])
            bad[ii[meet]] = True
            bad[jj[meet]] = True
    return np.flatnonzero(bad)


def _box_pairs(lo: np.ndarray, hi: np.ndarray):
    """Every pair ``(i, j)`` of edges whose x-extents overlap, once, in chunks of at most :data:`_PAIR_CHUNK`.

    A sweep over the edges sorted by their left end: edge ``j`` overlaps
    edge ``i`` in x, with ``j`` after ``i`` in that order, exactly when its
    left end lies in ``[lo_i, hi_i]``, so a binary search gives each edge's
    partners as one contiguous run.  The cost is the number of overlapping
    pairs (a few per edge for a polygon of short edges, such as any hull, or
    any reversal of one), not ``k**2``; the boxes' y-overlap and the exact
    test follow in the caller.
    """
    order = np.argsort(lo[:, 0], kind="stable")
    left = lo[order, 0]
    end = np.searchsorted(left, hi[order, 0], side="right")  # partners of sorted edge t: t+1 .. end-1
    count = np.maximum(end - np.arange(len(order)) - 1, 0)
    total = np.cumsum(count)
    start = 0
    while start < len(order):
        stop = int(np.searchsorted(total, (total[start - 1] if start else 0) + _PAIR_CHUNK, side="right"))
        stop = max(stop, start + 1)
        t = np.arange(start, min(stop, len(order)))
        c = count[t]
        if c.sum():
            first = np.repeat(t, c)
            offset = np.arange(int(c.sum())) - np.repeat(np.cumsum(c) - c, c)
            yield order[first], order[first + 1 + offset]
        start = int(t[-1]) + 1


def check_polygon2d(
    points: np.ndarray, poly: np.ndarray, *, seed: int = 0, measure: Measure | None = None
) -> Polygon2D:
    """Run the 2D manifoldness and convexity checks on one polygon.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    poly : ndarray of shape (k,), int64
        Vertex indices in the order given (counter-clockwise expected).
    seed : int
        For the ray of the wrap-number test (the verdict does not depend on it).
    measure : Measure or None
        The polygon's signed area (:func:`~.measure.surface_measure`), when
        the caller has it already; its exact sign decides the orientation.

    Returns
    -------
    Polygon2D

    Examples
    --------
    >>> pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0]])
    >>> res = check_polygon2d(pts, np.array([0, 4, 1, 2, 3]))
    >>> res.manifold_ok, res.convex_ok, res.turn.tolist()  # 4 is on an edge: allowed
    (True, True, [1, 0, 1, 1, 1])
    """
    k = len(poly)
    mags: dict[str, float] = {}
    rm: list[str] = []
    rc: list[str] = []
    bad_vertices: list[np.ndarray] = []
    if k < 3:
        rm.append(f"{k} vertices: a polygon needs at least 3")
        rc.append(f"{k} vertices: a polygon needs at least 3")
        empty = np.zeros(0, np.int64)
        return Polygon2D(False, False, np.arange(k), empty, empty, empty, np.zeros(k, np.int8), None, mags, rm, rc)
    a = points[poly]
    b = points[np.roll(poly, -1)]
    prev = points[np.roll(poly, 1)]

    # Convexity.
    degenerate = np.flatnonzero(np.all(a == b, axis=1))
    if degenerate.size:
        rc.append(f"{degenerate.size} zero-length edges")
        mags["degenerate"] = 0.0
    turn = orient2d(prev, a, b)
    reflex = np.flatnonzero(turn < 0)
    if reflex.size:
        rc.append(f"{reflex.size} reflex vertices")
        mags["reflex"] = float(np.max(-point_line_distance(prev[reflex], a[reflex], b[reflex])))
    center = None
    interior = None
    flipped = np.zeros(0, np.int64)
    degree = None
    real = np.setdiff1d(np.arange(k), degenerate)
    # The vertices' mean first (a strict left turn proves the vertices are not collinear);
    # the exact centroid of a triangle of the vertices when that fails or the polygon
    # already failed, so that the edges it is not left of are named.
    mean = vertex_mean(a)
    if not rc and (turn > 0).any() and bool(np.all(orient2d(a, b, mean) > 0)):
        center = mean
    else:
        interior = surface_interior(points, unique_ints(poly))
        if interior is None:
            rc.append("no interior point: the polygon's vertices are collinear")
        else:
            left = orient2d_mean(a[real], b[real], interior.rows) > 0
            flipped = real[~left]
            if flipped.size:
                rc.append(f"{flipped.size} edges with the interior point not strictly left")
                mags["flipped"] = float(np.max(-point_line_distance(a[flipped], b[flipped], interior.approx), initial=0.0))
            for candidate in (mean, interior.approx):
                if real.size and bool(np.all(orient2d(a[real], b[real], candidate) > 0)):
                    center = np.asarray(candidate, dtype=np.float64)
                    break
    if not rc:
        degree = wrap_number_2d(points, poly, center, interior, seed)
        if degree != 1:
            rc.append(f"the polygon winds {degree} times around the interior point")

    # Manifoldness.
    _, first, counts = np.unique(poly, return_index=True, return_counts=True)
    if np.any(counts > 1):
        rep = np.flatnonzero(np.isin(poly, unique_ints(poly)[counts > 1]))
        rm.append(f"{int((counts > 1).sum())} repeated vertex indices")
        bad_vertices.append(rep)
    _, inv, ccount = np.unique(a, axis=0, return_inverse=True, return_counts=True)
    dup_coord = np.flatnonzero(ccount[inv.ravel()] > 1)
    if dup_coord.size and not np.any(counts > 1):
        rm.append(f"{dup_coord.size} vertices at repeated coordinates")
    bad_vertices.append(dup_coord)
    if rc:
        # Not certified convex: simplicity needs the pairwise test.
        crossing = self_intersections(points, poly)
        if crossing.size:
            rm.append(f"{crossing.size} edges touching or crossing another edge")
            bad_vertices.append(crossing)
    if not rm:
        sign = (measure if measure is not None else surface_measure(points, poly)).sign
        if sign <= 0:
            rm.append("clockwise orientation (signed area negative)" if sign < 0 else "zero signed area")
    bad = np.unique(np.concatenate(bad_vertices)).astype(np.int64) if bad_vertices else np.zeros(0, np.int64)
    return Polygon2D(
        manifold_ok=not rm,
        convex_ok=not rc,
        bad_vertices=bad,
        degenerate_edges=degenerate,
        reflex=reflex,
        flipped=flipped,
        turn=turn,
        center=center,
        magnitudes=mags,
        reasons_manifold=rm,
        reasons_convex=rc,
        wraps=degree,
    )
