"""Certify the common case, a convex closed triangle mesh or polygon, in one batch of exact signs (or decline).

For hulls of tens of points the general checks (:mod:`.topology`,
:mod:`.convexity3d`, :mod:`.containment`) cost their numpy set-up, not their
arithmetic: a dozen predicate calls and a few hundred small array steps.
When the surface is a closed triangle mesh that is in fact a convex hull,
every condition of those checks can be read off one call of the float
filter over stacked rows, with the exact stages only for rows it leaves
open:

* one reflex-test row per edge (the two tests of an edge are the same
  determinant up to an even permutation, see :func:`.convexity3d.check_convexity3d`);
* the vertices' mean ``o`` strictly below every face, which also proves
  every triangle non-degenerate (a collinear triangle has a zero
  determinant with any fourth point);
* one wrap-number row per edge, from ``o`` (the reverse half-edge has the
  opposite sign, its symbolic tie-break included);
* the points that are not vertices against every face, when there are few;
* the signed-volume rows of :mod:`.measure` (float values and bounds only).

The combinatorial conditions of :mod:`.topology` then follow from few facts.
Every directed edge occurs once and its reverse once (``paired``), so the
faces glue into closed orientable surfaces, one per edge-connected piece.
Every face has ``o`` strictly below it and no edge is reflex, so the radial
projection from ``o`` maps each piece onto the whole sphere of directions
with every face keeping its orientation: each piece is crossed at least
once by every ray from ``o``, and a wrap count of exactly one leaves one
piece.  One connected closed orientable surface with V - E + F = 2 is a
sphere whose vertex links are single cycles (with more link cycles than
vertices its Euler characteristic would exceed 2), and two faces on the
same three vertices would pair all their edges with each other, a piece of
two faces.

In 2D (:func:`certify_convex_polygon`) the rows are the turns, the mean
strictly left of every edge, the wrap number, containment and the area.

This path only ever concludes "certified", and then builds exactly the
certificate the general path builds for that surface (same interior point,
same ray, same corner rule); any failed or uncovered condition returns None
and the general path runs, which also reports what failed.

Soundness: :func:`.predicates.filter3_columns` / ``filter2_columns`` return an
infinite bound for any row whose float determinant is not finite, and a bound
with absolute underflow terms otherwise, so ``exact_signs*`` decide in floats
only what Shewchuk's analysis covers; the rest go through the exact stages
(issue 33, F1 and F2).  The mean is :func:`._geometry.vertex_mean`, finite at
any magnitude.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..contract import FaceSet
from ._geometry import triangle_array, vertex_mean
from .certificate import Certificate, corners3
from .containment import _SMALL, check_containment2d, check_containment3d
from .measure import Measure, rotated_to_lowest
from .predicates import exact_signs2, exact_signs3, filter2_columns, filter3_columns
from .topology import half_edges
from .wrap import break_ties_2d, break_ties_3d, ray_point
from ._unique import unique_ints

__all__ = ["certify_closed_mesh", "certify_convex_polygon"]

#: Most (point, face) rows of the batched containment test; beyond, :mod:`.containment`
#: runs (brute force in one matrix product, or the cone strategy for large inputs).
_BATCH_CONTAINMENT = 2_000
_NEXT = np.array([1, 2, 0])
#: Rows filtered at once: the (dim, dim, rows) differences of a 10^6-point sphere's ten million
#: rows would hold 1.4 GB (with their absolute values) at once.
_FILTER_CHUNK = 1 << 20
#: From a half-edge's corner to the corner of the vertex off its edge (c -> c + 2 mod 3).
_BACK = np.array([2, -1, -1])
_EMPTY = np.zeros(0, dtype=np.int64)
_EMPTY.setflags(write=False)


#: The offending kinds of the general checks' certificates, all empty here.
_OFFENDING_KINDS = {
    2: ("containment", "degenerate_edges", "reflex_vertices", "flipped_edges", "manifold_vertices"),
    3: ("containment", "degenerate_faces", "reflex_faces", "flipped_faces", "manifold_faces", "manifold_vertices"),
}


def _certified(
    dim: int, n_faces: int, vertices: np.ndarray, extreme: np.ndarray, boundary: np.ndarray,
    measure: Measure, witness: np.ndarray,
) -> Certificate:
    """The certificate the general checks build for a surface that passes them all."""
    return Certificate(
        dim=dim,
        containment=True,
        convexity=True,
        manifoldness=True,
        n_faces=n_faces,
        hull_vertices=vertices,
        extreme=extreme,
        boundary_nonextreme=boundary,
        outside=_EMPTY,
        n_nonconvex_edges=0,
        n_degenerate_faces=0,
        offending={key: _EMPTY for key in _OFFENDING_KINDS[dim]},
        measure=measure,
        reasons={"containment": [], "convexity": [], "manifoldness": []},
        wraps=1,
        witness=witness,
    )


def _signs_and_measure(
    gather: Callable[[int, int], np.ndarray], dim: int, rows: int, signed: int
) -> tuple[np.ndarray, Measure] | None:
    """One float filter over every row, then the volume (area) from the rows from ``signed`` on
    and exact signs for the rows before; None when the volume is not positive.

    ``gather(start, stop)`` gives the rows ``start:stop`` as an array ``coords`` of shape
    (dim, dim + 1, stop - start): ``coords[c, p]`` is coordinate c of the p-th point of
    every row (the last point is the one subtracted).  Rows are gathered a slab at a
    time, and again only where the filter leaves a sign undecided, so no array of all
    rows' coordinates is ever held (it was 960 MB for a sphere of 10**6 points).
    """
    filter_columns, exact_signs = (filter2_columns, exact_signs2) if dim == 2 else (filter3_columns, exact_signs3)
    with np.errstate(all="ignore"):  # overflow means an undecided row, settled exactly
        det, bound = np.empty(rows), np.empty(rows)

        def run_filter(first: int, last: int) -> None:  # the differences and their magnitudes, a slab at a time
            for start in range(first, last, _FILTER_CHUNK):
                stop = min(start + _FILTER_CHUNK, last)
                coords = gather(start, stop)
                det[start:stop], bound[start:stop] = filter_columns(coords[:, :dim] - coords[:, dim:])

        def gathered(which: np.ndarray, offset: int) -> list[np.ndarray]:  # rows offset + which, as point arguments
            if not len(which):
                return [np.zeros((0, dim))] * (dim + 1)
            lo, hi = int(which[0]), int(which[-1]) + 1
            coords = gather(offset + lo, offset + hi)
            if hi - lo != len(which):  # (which is increasing: equal lengths mean every row)
                coords = coords[:, :, which - lo]
            return [coords[:, j].T for j in range(dim + 1)]

        # The volume rows first: a reversed surface (negative volume) is declined before the rest.
        run_filter(signed, rows)
        measure = Measure(dim, gathered(np.arange(rows - signed), signed), (det[signed:], bound[signed:]))
        if measure.sign <= 0:
            return None
        run_filter(0, signed)
        sign = np.sign(det[:signed]).astype(np.int8)
        open_rows = np.flatnonzero(~(np.abs(det[:signed]) > bound[:signed]))  # NaN: undecided
        if len(open_rows):
            sign[open_rows] = exact_signs(det[open_rows], bound[open_rows], gathered(open_rows, 0))
        return sign, measure


def _sort_with_positions(keys: np.ndarray, limit: int) -> tuple[np.ndarray, np.ndarray]:
    """``(order, keys[order])`` with ``order`` sorting the non-negative ``keys`` (all below ``limit``).

    Where key and position fit in one int64 together, one plain sort of the packed
    values gives both: about three times faster than ``argsort`` on millions of keys.
    """
    shift = max(1, int(len(keys)).bit_length())
    if limit < 2 ** (63 - shift):
        packed = np.sort((keys << shift) | np.arange(len(keys), dtype=np.int64))
        return packed & ((1 << shift) - 1), packed >> shift
    order = np.argsort(keys)
    return order, keys[order]


def _gatherer(points: np.ndarray, idx: np.ndarray, fixed: list[tuple[int, int, int, np.ndarray]]):
    """``gather(start, stop)`` for :func:`_signs_and_measure`: the coordinates of rows ``idx[:, start:stop]``.

    ``fixed``: ``(p, first, last, point)``, the p-th point of rows ``first:last``
    is ``point`` (the mean, the ray point, the volume's reference vertex): it is
    filled in, not gathered (the gather, a random access per coordinate, is the
    batch's largest cost).
    """
    columns = points.T
    dim = points.shape[1]

    def gather(start: int, stop: int) -> np.ndarray:
        coords = np.empty((dim, idx.shape[0], stop - start))  # each coordinate row contiguous
        for p in range(idx.shape[0]):
            cuts = [start, stop]  # the rows of this slab whose p-th point is gathered: between fixed blocks
            for q, first, last, point in fixed:
                lo, hi = max(first, start), min(last, stop)
                if q == p and lo < hi:
                    coords[:, p, lo - start : hi - start] = point[:, None]
                    cuts[-1:] = [lo, hi, stop]
            for lo, hi in zip(cuts[0::2], cuts[1::2]):  # ("clip": unbuffered; every index is in range)
                if lo < hi:
                    np.take(columns, idx[p, lo:hi], axis=1, out=coords[:, p, lo - start : hi - start], mode="clip")
        return coords

    return gather


def certify_closed_mesh(points: np.ndarray, faces: FaceSet, *, seed: int = 0) -> Certificate | None:
    """The certificate of a closed convex triangle mesh, or None when this path cannot give it.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
        All faces triangles.
    seed : int
        The wrap-number ray, as in the general path.

    Returns
    -------
    Certificate or None
    """
    n = len(points)
    tri = triangle_array(faces)
    m = len(tri)
    if m < 4:  # (a triangle repeating a vertex fails the mean-below test below: it is flat)
        return None
    # Half-edge j runs src[j] -> dst[j] in triangle j // 3; its twin runs back.
    src = tri.ravel()
    dst = tri[:, _NEXT].ravel()
    # Every directed edge once and its reverse once means: every undirected edge exactly
    # twice, in opposite directions.  One sort of the undirected keys puts the two side
    # by side (a search of each reverse key in the sorted directed keys cost ten times
    # more on 6 million half-edges: every look-up a cache miss).
    forward = src < dst
    undirected = np.minimum(src, dst) * n + np.maximum(src, dst)
    order, ordered = _sort_with_positions(undirected, n * n)
    first, second = order[0::2], order[1::2]
    if (
        len(order) % 2
        or np.any(ordered[0::2] != ordered[1::2])
        or np.any(ordered[2::2] == ordered[1:-1:2])
        or np.any(forward[first] == forward[second])  # (a loop u -> u is never forward)
    ):
        return None
    partner = np.empty(len(order), dtype=np.int64)
    partner[first], partner[second] = second, first
    half = forward.nonzero()[0]  # one half-edge per edge
    twin = partner[half]
    is_vertex = np.zeros(n, dtype=bool)
    is_vertex[src] = True
    vertices = is_vertex.nonzero()[0]
    e = len(half)
    if len(vertices) - e + m != 2:
        return None

    corners = points[vertices]
    mean = vertex_mean(corners)
    q = ray_point(mean, float(max(corners.max(), -corners.min())), seed)
    candidates = (~is_vertex).nonzero()[0]
    batch_containment = len(candidates) * m <= _BATCH_CONTAINMENT
    k = len(candidates) if batch_containment else 0
    # Rows (as point indices; the mean and the ray point are filled in after the
    # gather): reflex test (e), mean below every face (m), wrap number (e),
    # containment (k m), volume (m).
    signed = 2 * e + m + k * m
    # int32 rows where the indices fit: half the memory of the largest array here.
    idx = np.zeros((4, signed + m), dtype=np.int32 if n < 2**31 else np.int64)
    idx[:3, :e] = tri[half // 3].T
    idx[3, :e] = src[twin + _BACK[twin % 3]]  # the vertex of the twin's triangle off the edge
    idx[:3, e : e + m] = tri.T
    idx[1, e + m : 2 * e + m] = src[half]
    idx[2, e + m : 2 * e + m] = dst[half]
    if k:
        idx[:3, 2 * e + m : signed].reshape(3, k, m)[:] = tri.T[:, None, :]  # every face, for each candidate
        idx[3, 2 * e + m : signed] = np.repeat(candidates, m)
    lowest = rotated_to_lowest(faces).indices.reshape(-1, 3)
    idx[0, signed:], idx[1, signed:], idx[2, signed:], idx[3, signed:] = vertices[0], lowest[:, 1], lowest[:, 0], lowest[:, 2]
    gather = _gatherer(points, idx, [(3, e, e + m, mean), (0, e + m, 2 * e + m, mean), (3, e + m, 2 * e + m, q),
                                     (0, signed, signed + m, points[vertices[0]])])
    batch = _signs_and_measure(gather, 3, signed + m, signed)
    if batch is None:
        return None
    sign, measure = batch
    reflex, below = sign[:e], sign[e : e + m]
    if below.min() <= 0 or reflex.min() < 0 or reflex.max() <= 0 or (k and sign[2 * e + m :].min() < 0):
        return None
    s = -sign[e + m : 2 * e + m]  # > 0: q strictly on the inner side of the plane (mean, u, v)
    break_ties_3d(s, src[half], dst[half], mean, None, points)
    inner = np.empty(3 * m, dtype=bool)
    inner[half] = s > 0
    inner[twin] = s < 0
    if np.count_nonzero(inner[0::3] & inner[1::3] & inner[2::3]) != 1:
        return None
    if not batch_containment:
        he = half_edges(faces, n) if n * m > _SMALL else None
        if not check_containment3d(points, faces, tri, certified=True, center=mean, he=he).ok:
            return None
    sharp_rows = (reflex > 0).nonzero()[0]
    sharp = idx[1:3, e + m + sharp_rows].T.astype(np.int64)  # the edge's end points, from the wrap-number rows
    first_sharp = int(sharp_rows[0])  # a face and a vertex strictly below it: a witness simplex
    extreme = corners3(points, vertices, sharp)
    is_vertex[extreme] = False  # now: vertices that are not corners
    return _certified(3, m, vertices, extreme, vertices[is_vertex[vertices]], measure, idx[:, first_sharp].astype(np.int64))


def certify_convex_polygon(points: np.ndarray, poly: np.ndarray, *, seed: int = 0) -> Certificate | None:
    """The certificate of a convex counter-clockwise polygon, or None when this path cannot give it.

    The conditions of :func:`.polygon2d.check_polygon2d` and
    :func:`.containment.check_containment2d` for a polygon that passes them:
    at least three vertices, no repeated index, every turn left or straight
    and one strictly left, the vertices' mean strictly left of every edge (no
    edge of zero length then), winding once around it, positive area, no
    point strictly right of an edge.  No coordinate repeats then either: every
    edge turns by a positive angle around the mean and they turn once around
    in all, so the vertices lie in distinct directions from it.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    poly : ndarray of shape (k,), int64
    seed : int
        The wrap-number ray, as in the general path.

    Returns
    -------
    Certificate or None
    """
    n, k = len(points), len(poly)
    if k < 3:
        return None
    is_vertex = np.zeros(n, dtype=bool)
    is_vertex[poly] = True
    vertices = is_vertex.nonzero()[0]
    if len(vertices) != k:
        return None
    a = points[poly]
    mean = vertex_mean(a)
    q = ray_point(mean, float(max(a.max(), -a.min())), seed)
    candidates = (~is_vertex).nonzero()[0]
    c = len(candidates) if len(candidates) * k <= _BATCH_CONTAINMENT else 0
    nxt, prev = np.roll(poly, -1), np.roll(poly, 1)
    # Rows (the mean and the ray point filled in after the gather): turns (k), mean
    # left of every edge (k), wrap number (k), containment (c k), area (k).
    signed = 3 * k + c * k
    idx = np.zeros((3, signed + k), dtype=np.int64)
    idx[0, :k], idx[1, :k], idx[2, :k] = prev, poly, nxt
    idx[0, k : 2 * k], idx[1, k : 2 * k] = poly, nxt
    idx[1, 2 * k : 3 * k] = poly
    if c:
        idx[0, 3 * k : signed].reshape(c, k)[:] = poly
        idx[1, 3 * k : signed].reshape(c, k)[:] = nxt
        idx[2, 3 * k : signed] = np.repeat(candidates, k)
    idx[0, signed:], idx[1, signed:], idx[2, signed:] = poly.min(), poly, nxt
    gather = _gatherer(points, idx, [(2, k, 2 * k, mean), (0, 2 * k, 3 * k, mean), (2, 2 * k, 3 * k, q),
                                     (0, signed, signed + k, points[poly.min()])])
    batch = _signs_and_measure(gather, 2, signed + k, signed)
    if batch is None:
        return None
    sign, measure = batch
    turn, left = sign[:k], sign[k : 2 * k]
    if turn.min() < 0 or turn.max() <= 0 or left.min() <= 0 or (c and sign[3 * k :].min() < 0):
        return None
    s = sign[2 * k : 3 * k].copy()
    break_ties_2d(s, a, mean, None)
    if np.count_nonzero((s > 0) & (np.roll(s, -1) < 0)) != 1:
        return None
    if not c and len(candidates):
        cont = check_containment2d(points, poly, certified=True, center=mean)
        if not cont.ok:
            return None
    strict = int(np.argmax(turn > 0))
    return _certified(2, k, vertices, unique_ints(poly[turn > 0]), unique_ints(poly[turn == 0]), measure, idx[:, strict].astype(np.int64))
