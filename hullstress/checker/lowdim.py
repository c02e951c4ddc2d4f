"""The exact judge of answers for lower-dimensional input: a point, a segment, a flat polygon.

When the input's exact affine rank is below its dimension (all points equal,
collinear in 2D or 3D, coplanar in 3D, fewer than d+1 distinct points), its
convex hull is a point, a segment or a flat polygon, and no closed surface of
positive volume is right.  docs/lower-dimensional.md states which
outputs are correct; this module decides them exactly:

* **The exact answer.**  Rank 0: the one point.  Rank 1: the two extreme
  endpoints, found by lexicographic order (on a line, lexicographic order of
  the coordinates is the order along the line, so this is exact).  Rank 2 in
  3D: the points are projected onto a coordinate plane along an axis that is
  not parallel to their plane (chosen with an exact ``orient2d`` of a witness
  triangle), an affine bijection of the plane, so extreme points, collinearity
  and convexity are unchanged; the extreme cycle is
  :func:`~hullstress.checker.extreme.exact_extreme_2d` of the projection.
* **Identical points are one point.**  Every index is replaced by the first
  index with the same coordinates before judging.
* **A walk around the hull.**  A 2D answer, or one 3D face for rank <= 1, is a
  cycle of vertices.  It is right when it holds every extreme point once, no
  point twice, and between consecutive extreme points only points on the hull
  edge joining them, strictly in order along it (tested with exact
  ``orient2d`` and lexicographic comparisons).  For a segment the cycle runs
  from one endpoint to the other and back: ``[a, b]`` in either order, and
  ``[a, m, b]`` with m between them.  In 3D a face and its reverse (a
  two-sided answer) count as that face.
* **A flat surface** (rank 2 in 3D): faces must be convex and non-degenerate
  in the plane.  Faces are split by their orientation in the projection into
  the two sides; each non-empty side must tile the hull polygon exactly once.
  Because every face of a side has the same orientation, it tiles the polygon
  exactly when the side's boundary chain (directed edges, each counted minus
  its reverse) is one cycle walking once around the hull as above: the number
  of faces covering a point is then the winding number of that cycle, 1
  inside, 0 outside.  One side (a polygon, or a triangulated polygon) and two
  sides (the polygon with its reverse, or a closed "pillow" of flat triangles)
  are both right.

Each verdict's reason cites the exact answer (the endpoints, the extreme
cycle), never Qhull's: Qhull builds no hull for such input, so
``qhull_agreement`` is left unknown.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

import numpy as np

from ..contract import FaceSet, normalize_output, require_face_size
from ..errors import ContractViolation
from ..verdict import Verdict
from ._geometry import distround, exact_scale
from ._unique import unique_ints
from .extreme import _keys, exact_extreme_2d
from .predicates import orient2d, orient3d
from .rank import witness_simplex
from .severity import relative_magnitudes, severity

__all__ = ["LowerHull", "lower_dimensional_hull", "full_dimensional", "judge_lower_dimensional", "verdict_if_degenerate"]

#: At most this many indices of a hull are quoted in a reason.
_QUOTE = 12


@dataclass(frozen=True)
class LowerHull:
    """The exact convex hull of a lower-dimensional point set.

    Attributes
    ----------
    rank : int
        Exact affine rank: -1 (no points), 0 (one point), 1 (a segment), 2 (a flat polygon in 3D).
    extreme : ndarray of shape (k,), int64
        The extreme points, one index per distinct point (the first with its
        coordinates): the point; the two endpoints, lexicographically smaller
        first; the polygon's corners counter-clockwise in the projection.
    axes : tuple of int
        The coordinates the judge works in: both for 2D input, the two kept
        by the projection for 3D input.
    """

    rank: int
    extreme: np.ndarray
    axes: tuple[int, ...]

    def describe(self, points: np.ndarray) -> str:
        """The exact answer in words, with indices (and coordinates for a point or segment)."""
        ex = self.extreme.tolist()
        if self.rank < 0:
            return "no points: the hull is empty"
        if self.rank == 0:
            return f"all points are one point: the hull is point {ex[0]} {_coords(points, ex[0])}"
        if self.rank == 1:
            return (f"collinear input: the hull is the segment from point {ex[0]} {_coords(points, ex[0])} "
                    f"to point {ex[1]} {_coords(points, ex[1])}")
        shown = ", ".join(map(str, ex[:_QUOTE])) + (", ..." if len(ex) > _QUOTE else "")
        return f"coplanar input: the hull is the flat polygon with extreme points {shown} ({len(ex)}, in order)"


def _coords(points: np.ndarray, i: int) -> str:
    return "(" + ", ".join(repr(float(x)) for x in points[i]) + ")"


def _representatives(points: np.ndarray) -> np.ndarray:
    """For each row, the first row with the same coordinates (-0.0 == 0.0)."""
    if not len(points):
        return np.zeros(0, dtype=np.int64)
    _, first, inverse = np.unique(_keys(points), return_index=True, return_inverse=True)
    return first[inverse.ravel()].astype(np.int64)


def _lex_rank(points: np.ndarray) -> np.ndarray:
    """Dense rank of every row in lexicographic order (equal rows share a rank)."""
    pts = points + 0.0
    order = np.lexsort(pts.T[::-1])
    srt = pts[order]
    new = np.ones(len(pts), dtype=bool)
    new[1:] = np.any(srt[1:] != srt[:-1], axis=1)
    rank = np.empty(len(pts), dtype=np.int64)
    rank[order] = np.cumsum(new) - 1
    return rank


def full_dimensional(points: np.ndarray) -> bool:
    """A cheap exact certificate of full rank: some d+1 of the axis-extreme points are independent.

    False means "not certified" (the caller then computes the rank), not "degenerate".
    """
    n, d = points.shape
    if n <= d:
        return False
    cand = unique_ints(np.concatenate([[0], np.argmin(points, axis=0), np.argmax(points, axis=0)]))
    groups = np.array(list(combinations(cand.tolist(), d + 1)), dtype=np.int64)
    if not len(groups):
        return False
    p = points[groups]
    if d == 2:
        return bool(np.any(orient2d(p[:, 0], p[:, 1], p[:, 2]) != 0))
    return bool(np.any(orient3d(p[:, 0], p[:, 1], p[:, 2], p[:, 3]) != 0))


def lower_dimensional_hull(points: np.ndarray, simplex: np.ndarray | None = None) -> LowerHull:
    """The exact hull of a point set whose affine rank is below its dimension.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64, finite, d in (2, 3)
    simplex : ndarray of int, optional
        A witness simplex (:func:`~hullstress.checker.witness_simplex`), computed when not given.

    Returns
    -------
    LowerHull

    Raises
    ------
    ValueError
        When the points are full-dimensional.

    Examples
    --------
    >>> pts = np.array([[2.0, 2.0], [0.0, 0.0], [1.0, 1.0], [0.0, 0.0]])
    >>> h = lower_dimensional_hull(pts)
    >>> h.rank, h.extreme.tolist()
    (1, [1, 0])
    >>> pts3 = np.array([[0.0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [0.5, 0.5, 1]])
    >>> lower_dimensional_hull(pts3).extreme.tolist()
    [0, 1, 2, 3]
    """
    n, d = points.shape
    if simplex is None:
        simplex = witness_simplex(points)
    rank = len(simplex) - 1
    if rank >= d:
        raise ValueError(f"points are full-dimensional (rank {rank} in {d}D)")
    if rank < 0:
        return LowerHull(-1, np.zeros(0, dtype=np.int64), tuple(range(d)))
    rep = _representatives(points)
    if rank == 0:
        return LowerHull(0, np.array([rep[0]], dtype=np.int64), tuple(range(d)))
    if rank == 1:
        order = np.lexsort((points + 0.0).T[::-1])
        ends = np.array([rep[order[0]], rep[order[-1]]], dtype=np.int64)
        return LowerHull(1, ends, tuple(range(d)))
    tri = points[np.asarray(simplex[:3])]
    for axes in ((0, 1), (1, 2), (0, 2)):
        if orient2d(tri[0, axes], tri[1, axes], tri[2, axes])[0] != 0:
            break
    else:  # pragma: no cover - a rank-2 witness triangle is not collinear in every projection
        raise AssertionError("no projection keeps the witness triangle non-degenerate")
    extreme = exact_extreme_2d(points[:, axes])
    return LowerHull(2, rep[extreme].astype(np.int64), axes)


@dataclass
class _Findings:
    """Problems found so far, by check, with offending indices and violation sizes."""

    containment: list[str] = field(default_factory=list)
    convexity: list[str] = field(default_factory=list)
    manifoldness: list[str] = field(default_factory=list)
    offending: dict[str, list[int]] = field(default_factory=dict)
    missing: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    n_outside: int = 0
    n_misordered: int = 0
    n_bad_faces: int = 0

    def add(self, key: str, values: Any) -> None:
        self.offending.setdefault(key, []).extend(int(v) for v in np.asarray(values).ravel())

    @property
    def ok(self) -> bool:
        return not (self.containment or self.convexity or self.manifoldness)


def _walk_problems(walk: np.ndarray, hull: LowerHull, plane: np.ndarray, lex: np.ndarray) -> tuple[str, np.ndarray]:
    """Why ``walk`` (distinct points holding every extreme point) is not a walk around the hull.

    Returns a reason ("" when it is one) and the points at fault.
    """
    ext = hull.extreme
    pos = np.full(len(lex), -1, dtype=np.int64)
    pos[walk] = np.arange(len(walk))
    at = pos[ext]
    walk = np.roll(walk, -int(at[0]))
    at = (at - at[0]) % len(walk)
    if len(ext) > 2 and np.any(np.diff(at) <= 0):
        return "the extreme points are not in order around the polygon (or the face runs the other way)", ext
    # Segment id of every walk position: which hull edge (ext[s] -> ext[s+1]) it lies on.
    seg = np.cumsum(np.isin(np.arange(len(walk)), at)) - 1
    nxt = np.roll(walk, -1)
    start, end = ext[seg], ext[(seg + 1) % len(ext)]
    direction = np.sign(lex[end] - lex[start])
    bad = np.sign(lex[nxt] - lex[walk]) != direction
    if hull.rank == 2:
        inner = ~np.isin(np.arange(len(walk)), at)
        off = np.zeros(len(walk), dtype=bool)
        if inner.any():
            off[inner] = orient2d(plane[start[inner]], plane[end[inner]], plane[walk[inner]]) != 0
        if off.any():
            return "points " + _quote(walk[off]) + " of the walk are not on the hull edge they sit between", walk[off]
    if len(ext) > 1 and bad.any():
        return "the vertices do not run in order along the hull's edges (" + _quote(walk[bad]) + ")", walk[bad]
    return "", np.zeros(0, dtype=np.int64)


def _quote(idx: np.ndarray) -> str:
    values = np.asarray(idx).tolist()
    return ", ".join(map(str, values[:_QUOTE])) + (", ..." if len(values) > _QUOTE else "")


def _judge_cycle(cycle: np.ndarray, hull: LowerHull, plane: np.ndarray, lex: np.ndarray, found: _Findings) -> None:
    """Judge one vertex cycle (representative indices) against the exact hull."""
    if hull.rank < 0:
        return
    if not len(cycle):
        found.containment.append("the answer has no vertices")
        found.missing = hull.extreme
        return
    values, counts = np.unique(cycle, return_counts=True)
    if np.any(counts > 1):
        rep = values[counts > 1]
        found.manifoldness.append(f"point {_quote(rep)} appears more than once")
        found.add("repeated_vertices", rep)
    missing = hull.extreme[~np.isin(hull.extreme, cycle)]
    if len(missing):
        found.containment.append(f"extreme point {_quote(missing)} missing")
        found.missing = missing
    if np.any(counts > 1) or len(missing):
        return
    reason, at = _walk_problems(cycle, hull, plane, lex)
    if reason:
        found.convexity.append(reason)
        found.n_misordered = len(at)
        found.add("misordered_vertices", at)


def _face_table(faces: FaceSet, rep: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per vertex position: its representative, the previous and the next one in its face."""
    idx = rep[faces.indices]
    sizes = faces.sizes
    face_of = np.repeat(np.arange(faces.n_faces, dtype=np.int64), sizes)
    local = np.arange(len(idx), dtype=np.int64) - faces.offsets[:-1][face_of]
    base = faces.offsets[:-1][face_of]
    prev = idx[base + (local - 1) % sizes[face_of]]
    nxt = idx[base + (local + 1) % sizes[face_of]]
    return idx, prev, nxt


def _face_orientations(faces: FaceSet, idx, prev, nxt, plane: np.ndarray, lex: np.ndarray, found: _Findings) -> np.ndarray:
    """+1 / -1 per face (counter-clockwise / clockwise in the projection), 0 for a bad face."""
    m = faces.n_faces
    sizes = faces.sizes
    face_of = np.repeat(np.arange(m, dtype=np.int64), sizes)
    turn = orient2d(plane[prev], plane[idx], plane[nxt]).astype(np.int64)
    pos = np.bincount(face_of, weights=turn > 0, minlength=m) > 0
    neg = np.bincount(face_of, weights=turn < 0, minlength=m) > 0
    # A zero turn must go straight on (a point on the edge), not back (a spike).
    straight = (np.sign(lex[idx] - lex[prev]) == np.sign(lex[nxt] - lex[idx]))
    spike = np.bincount(face_of, weights=(turn == 0) & ~straight, minlength=m) > 0
    # A convex polygon's lexicographic direction changes exactly twice (it winds once).
    step = np.sign(lex[nxt] - lex[idx])
    first = faces.offsets[:-1]
    before = np.empty_like(step)
    before[1:] = step[:-1]
    before[first] = step[faces.offsets[1:] - 1]
    changes = np.bincount(face_of, weights=step != before, minlength=m)
    # A face repeats a point when it has fewer distinct (face, point) pairs than vertices.
    pairs = unique_ints(face_of * (int(idx.max()) + 1) + idx)
    repeated = np.bincount(pairs // (int(idx.max()) + 1), minlength=m) < sizes
    degenerate = ~pos & ~neg & ~repeated
    nonconvex = ((pos & neg) | spike | (changes != 2)) & ~degenerate & ~repeated
    if repeated.any():
        found.manifoldness.append(f"face {_quote(np.flatnonzero(repeated))} repeats a point")
        found.add("manifold_faces", np.flatnonzero(repeated))
    if degenerate.any():
        found.convexity.append(f"face {_quote(np.flatnonzero(degenerate))} has no area (collinear vertices)")
        found.add("degenerate_faces", np.flatnonzero(degenerate))
    if nonconvex.any():
        found.convexity.append(f"face {_quote(np.flatnonzero(nonconvex))} is not a convex polygon")
        found.add("nonconvex_faces", np.flatnonzero(nonconvex))
    found.n_bad_faces = int((degenerate | nonconvex | repeated).sum())
    orient = np.where(pos, 1, -1)
    orient[degenerate | nonconvex | repeated] = 0
    return orient


def _boundary_cycle(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray | None, str]:
    """The boundary chain of a set of faces' directed edges as one cycle, or why it is not one."""
    lo, hi = np.minimum(src, dst), np.maximum(src, dst)
    sign = np.where(src < dst, 1, -1)
    keys, inverse = np.unique(np.stack([lo, hi], axis=1), axis=0, return_inverse=True)
    net = np.bincount(inverse.ravel(), weights=sign, minlength=len(keys)).astype(np.int64)
    if np.any(np.abs(net) > 1):
        return None, "its faces overlap (an edge is crossed twice the same way)"
    keep = net != 0
    a = np.where(net[keep] > 0, keys[keep, 0], keys[keep, 1])
    b = np.where(net[keep] > 0, keys[keep, 1], keys[keep, 0])
    if not len(a):
        return None, "its faces have no boundary (they cover the plane an even number of times)"
    if len(unique_ints(a)) != len(a) or len(unique_ints(b)) != len(b):
        return None, "its boundary is not a simple cycle (faces overlap or leave a hole)"
    succ = dict(zip(a.tolist(), b.tolist()))
    start = int(a[0])
    walk = [start]
    while len(walk) <= len(a):
        nxt = succ.get(walk[-1])
        if nxt is None:
            return None, "its boundary does not close (a face is missing)"
        if nxt == start:
            break
        walk.append(nxt)
    if len(walk) != len(a):
        return None, "its boundary is more than one cycle (faces overlap or leave a hole)"
    return np.array(walk, dtype=np.int64), ""


#: Most (vertex, boundary edge) pairs :func:`_t_junction` examines: it only words a reason.
_JUNCTION_PAIRS = 1_000_000


def _t_junction(src: np.ndarray, dst: np.ndarray, plane: np.ndarray, lex: np.ndarray) -> tuple[int, int, int] | None:
    """A face vertex strictly inside an uncancelled edge of the side's boundary, if any (exact).

    Faces that cover the polygon once but meet at a T-junction leave the split
    edge uncancelled (README "Lower-dimensional input": the boundary rule); the
    reason then names the junction instead of a generic overlap.  Collinearity
    is an exact orientation in the plane's coordinates; "strictly inside" is
    the lexicographic rank (the order along any line).
    """
    lo, hi = np.minimum(src, dst), np.maximum(src, dst)
    sign = np.where(src < dst, 1, -1)
    keys, inverse = np.unique(np.stack([lo, hi], axis=1), axis=0, return_inverse=True)
    net = np.bincount(inverse.ravel(), weights=sign, minlength=len(keys)) != 0
    edges = keys[net]
    verts = unique_ints(src)
    if not len(edges) or len(edges) * len(verts) > _JUNCTION_PAIRS:
        return None
    e = np.repeat(np.arange(len(edges)), len(verts))
    v = np.tile(verts, len(edges))
    a, b = edges[e, 0], edges[e, 1]
    first, last = np.minimum(lex[a], lex[b]), np.maximum(lex[a], lex[b])
    inside = (lex[v] > first) & (lex[v] < last)
    rows = np.flatnonzero(inside)
    if not rows.size:
        return None
    on = orient2d(plane[a[rows]], plane[b[rows]], plane[v[rows]]) == 0
    if not on.any():
        return None
    r = rows[np.argmax(on)]
    return int(v[r]), int(a[r]), int(b[r])


def _judge_flat(faces: FaceSet, hull: LowerHull, rep: np.ndarray, plane: np.ndarray, lex: np.ndarray, found: _Findings) -> None:
    """Judge faces of a coplanar 3D input: each non-empty side must tile the hull polygon once."""
    used = unique_ints(rep[faces.indices])
    missing = hull.extreme[~np.isin(hull.extreme, used)]
    if len(missing):
        found.containment.append(f"extreme point {_quote(missing)} missing")
        found.missing = missing
    if faces.n_faces == 0:
        if not len(missing):
            found.containment.append("the answer has no faces")
        return
    idx, prev, nxt = _face_table(faces, rep)
    orient = _face_orientations(faces, idx, prev, nxt, plane, lex, found)
    if np.any(orient == 0) or len(missing):
        return
    face_of = np.repeat(np.arange(faces.n_faces, dtype=np.int64), faces.sizes)
    for side, name in ((1, "counter-clockwise"), (-1, "clockwise")):
        sel = orient[face_of] == side
        if not sel.any():
            continue
        # A clockwise side is read reversed, so that a tiling walks counter-clockwise.
        src, dst = (idx[sel], nxt[sel]) if side == 1 else (nxt[sel], idx[sel])
        walk, why = _boundary_cycle(src, dst)
        if walk is None:
            junction = _t_junction(src, dst, plane, lex)
            if junction is not None:
                why = (f"point {junction[0]} lies inside the edge {junction[1]}-{junction[2]} of another face "
                       "(a T-junction: faces must meet edge to edge)")
            found.manifoldness.append(f"the {name} faces do not tile the polygon: {why}")
            found.add("manifold_faces", np.flatnonzero(orient == side))
            continue
        on_hull = np.isin(hull.extreme, walk)
        if not on_hull.all():
            found.manifoldness.append(f"the {name} faces do not tile the polygon: their boundary misses extreme "
                                      f"point {_quote(hull.extreme[~on_hull])} (a hole)")
            found.add("manifold_faces", np.flatnonzero(orient == side))
            continue
        reason, at = _walk_problems(walk, hull, plane, lex)
        if reason:
            found.manifoldness.append(f"the {name} faces do not tile the polygon: their boundary: {reason}")
            found.n_misordered += len(at)
            found.add("misordered_vertices", at)


def _outside_segment(lex: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Rows of a collinear set beyond the extent of the answer's points."""
    if not len(used):
        return np.arange(len(lex), dtype=np.int64)
    lo, hi = lex[used].min(), lex[used].max()
    return np.flatnonzero((lex < lo) | (lex > hi))


def _outside_polygon(plane: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Rows of a planar set strictly outside the convex hull of ``used`` (exact, O(n log h))."""
    if not len(used):
        return np.arange(len(plane), dtype=np.int64)
    ring = used[exact_extreme_2d(plane[used])]
    if len(ring) < 3:
        a, b = plane[ring[0]], plane[ring[-1]]
        lex = _lex_rank(plane)
        lo, hi = sorted((lex[ring[0]], lex[ring[-1]]))
        return np.flatnonzero((orient2d(a, b, plane) != 0) | (lex < lo) | (lex > hi))
    # Fan from ring[0]: binary search for the wedge (ring[k], ring[k+1]) holding each point.
    o = plane[ring[0]]
    lo = np.ones(len(plane), dtype=np.int64)
    hi = np.full(len(plane), len(ring) - 1, dtype=np.int64)
    while np.any(hi - lo > 1):
        mid = (lo + hi) // 2
        left = orient2d(o, plane[ring[mid]], plane) >= 0
        lo = np.where(left & (hi - lo > 1), mid, lo)
        hi = np.where(~left & (hi - lo > 1), mid, hi)
    outside = (orient2d(o, plane[ring[1]], plane) < 0) | (orient2d(o, plane[ring[-1]], plane) > 0)
    outside |= orient2d(plane[ring[lo]], plane[ring[hi]], plane) < 0
    return np.flatnonzero(outside)


def judge_lower_dimensional(
    points: np.ndarray,
    faces: Any,
    *,
    simplex: np.ndarray | None = None,
    reference: Any = None,
    max_offending: int = 20,
) -> Verdict:
    """The verdict on an answer for a lower-dimensional point set.

    Parameters
    ----------
    points : ndarray of shape (n, 2) or (n, 3), float64, finite
        Affinely degenerate: rank below the dimension.
    faces : sequence of int (2D); list of polygons, (m, 3) array or FaceSet (3D)
        The answer.  In 3D, faces of one or two vertices are allowed for a
        rank 0 or 1 input (one point, a segment).
    simplex : ndarray of int, optional
        A witness simplex of ``points`` (computed when not given).
    reference : QhullReference, optional
        Only recorded (options, Qhull's own health); Qhull is not a witness here.
    max_offending : int
        At most this many indices per kind in ``offending``.

    Returns
    -------
    Verdict
        ``qhull_agreement`` is None; ``volume`` is 0.0; ``offending`` keys:
        ``missing_extreme``, ``containment`` (points outside the answer),
        ``repeated_vertices``, ``misordered_vertices`` (point indices),
        ``degenerate_faces``, ``nonconvex_faces``, ``manifold_faces`` (face indices).

    Raises
    ------
    ValueError
        When ``points`` is full-dimensional.
    ContractViolation
        When ``faces`` breaks the output contract (in 3D, a face of fewer
        than three vertices for an input of rank 2).

    Examples
    --------
    >>> line = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    >>> judge_lower_dimensional(line, [2, 0]).ok, judge_lower_dimensional(line, [0, 1, 2]).ok
    (True, True)
    >>> v = judge_lower_dimensional(line, [0, 1])
    >>> v.ok, v.detail
    (False, 'collinear input: the hull is the segment from point 0 (0.0, 0.0) to point 2 (2.0, 2.0); containment: extreme point 2 missing')
    """
    pts = np.asarray(points, dtype=np.float64)
    n, dim = pts.shape
    hull = lower_dimensional_hull(pts, simplex)
    if isinstance(faces, FaceSet) and dim != 3:
        raise ContractViolation("a FaceSet describes a 3D surface, got 2D points")
    answer: np.ndarray | FaceSet = normalize_output(faces, n, dim, min_face_size=1)  # FaceSets too (F6)
    if isinstance(answer, FaceSet) and hull.rank >= 2:
        require_face_size(answer)
    rep = _representatives(pts)
    lex = _lex_rank(pts)
    plane = pts[:, list(hull.axes)]
    found = _Findings()
    if isinstance(answer, FaceSet) and hull.rank >= 2:
        _judge_flat(answer, hull, rep, plane, lex, found)
    elif isinstance(answer, FaceSet):
        _judge_faces_of_a_point_or_segment(answer, hull, rep, plane, lex, found)
    else:
        _judge_cycle(rep[answer], hull, plane, lex, found)
    used = unique_ints(rep[answer.indices if isinstance(answer, FaceSet) else answer])
    n_faces = answer.n_faces if isinstance(answer, FaceSet) else (len(answer) if len(answer) > 1 else 0)
    return _verdict(pts, hull, lex, found, used, n_faces, reference, max_offending)


def _judge_faces_of_a_point_or_segment(answer: FaceSet, hull: LowerHull, rep: np.ndarray, plane: np.ndarray,
                                       lex: np.ndarray, found: _Findings) -> None:
    """One face (or a face and its reverse) whose cycle is the point's or the segment's walk."""
    polys = [rep[f] for f in answer.polygons()]
    two_sided = len(polys) == 2 and _same_cycle(polys[0], polys[1][::-1])
    if len(polys) > 1 and not two_sided:
        found.manifoldness.append(f"{len(polys)} faces; a point or a segment is one face (or one face and its reverse)")
        found.add("manifold_faces", np.arange(1, len(polys)))
    _judge_cycle(polys[0] if polys else np.zeros(0, dtype=np.int64), hull, plane, lex, found)


def _verdict(pts: np.ndarray, hull: LowerHull, lex: np.ndarray, found: _Findings, used: np.ndarray, n_faces: int,
             reference: Any, max_offending: int) -> Verdict:
    """The findings as a Verdict: counts, the points left outside and how far, the reason."""
    magnitudes: dict[str, float] = {}
    scaled, _ = exact_scale(pts)
    if len(found.missing):
        plane = pts[:, list(hull.axes)]
        outside = _outside_segment(lex, used) if hull.rank <= 1 else _outside_polygon(plane, used)
        found.n_outside = len(outside)
        found.add("containment", outside)
        found.add("missing_extreme", found.missing)
        if len(used):
            from scipy.spatial import cKDTree

            # The distance to the nearest point of the answer: an upper bound on the distance to its hull.
            gap, _ = cKDTree(scaled[used]).query(scaled[found.missing])
            magnitudes["outside"] = float(np.max(gap))
        else:
            magnitudes["outside"] = float("inf")  # no answer at all: nothing of the hull is there
    rel = relative_magnitudes(magnitudes, distround(scaled))
    sev, worst = severity(rel, failed=not found.ok, topological=bool(found.manifoldness))
    parts = [f"{name}: {'; '.join(msgs)}" for name, msgs in
             (("containment", found.containment), ("convexity", found.convexity), ("manifoldness", found.manifoldness))
             if msgs]
    detail = ("ok: " if found.ok else "") + hull.describe(pts) + ("; " + "; ".join(parts) if parts else "")
    n_extreme, n_missing = len(hull.extreme), len(found.missing)
    return Verdict(
        convexity=not found.convexity,
        containment=not found.containment,
        manifoldness=not found.manifoldness,
        qhull_agreement=None,
        severity=sev,
        max_violation=float(worst),
        distround=distround(pts),
        n_faces=int(n_faces),
        n_hull_vertices=len(used),
        n_extreme=n_extreme,
        n_missing_extreme=n_missing,
        n_boundary_nonextreme=int(len(used) - (n_extreme - n_missing)),
        n_outside=found.n_outside,
        n_nonconvex_edges=found.n_misordered,
        n_degenerate_faces=found.n_bad_faces,
        volume=0.0,
        qhull_volume=None if reference is None else reference.volume,
        qhull_options=None if reference is None else reference.options,
        qhull_ok=None if reference is None else reference.qhull_ok,
        affine_rank=hull.rank,
        offending={k: tuple(sorted(dict.fromkeys(v)))[:max_offending] for k, v in sorted(found.offending.items()) if v},
        detail=detail,
    )


def _same_cycle(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two vertex sequences are the same cycle (up to rotation)."""
    if len(a) != len(b):
        return False
    if not len(a):
        return True
    hits = np.flatnonzero(b == a[0])
    return any(np.array_equal(np.roll(b, -int(h)), a) for h in hits)


def verdict_if_degenerate(points: np.ndarray, faces: Any, *, reference: Any = None, max_offending: int = 20) -> Verdict | None:
    """The lower-dimensional verdict when ``points`` is degenerate, else None (the full check applies).

    The rank comes from ``reference``'s witness simplex when there is one,
    else from a cheap exact certificate of full rank, else from
    :func:`~hullstress.checker.witness_simplex`.
    """
    pts = np.asarray(points, dtype=np.float64)
    dim = pts.shape[1]
    simplex = getattr(reference, "simplex", None)
    if simplex is None:
        if full_dimensional(pts):
            return None
        simplex = witness_simplex(pts)
    if len(simplex) - 1 >= dim:
        return None
    return judge_lower_dimensional(pts, faces, simplex=np.asarray(simplex), reference=reference,
                                   max_offending=max_offending)

