"""Ben Kenwright's incremental hull: a tetrahedron grown point by point, in input order.

Seed: ``002_262f4fc866409e02.txt`` ("Convex Hulls: Surface Mapping onto a
Sphere"), section 4 and Algorithm 1.  Registered as ``kenwright`` (3D).

The seed's method has two stages, and the project splits them.  The issue
reads: "sphere: Kenwright's preprocessing (support mapping, projection onto a
unit sphere around the centroid; a circle in 2D) implemented once as a
wrapper that applies to any algorithm, in-house or plug-in, with indices
mapped back to the original points.  Kenwright's algorithm with sphere off is
the same incremental hull without the projection."  So:

* Algorithm 1, lines 1-9 (duplicate removal, centroid, support mapping, and
  line 7, "Project surfacepoint onto sphere surface") are the harness's
  ``sphere=on`` variant, :func:`hullstress.sphere.sphere_project`, applied
  to every algorithm alike before the call, with the output mapped back.
* Algorithm 1, lines 10-17 are this module, run over *all* input rows in
  input order, with no preliminary stage of its own:

  - line 11, "Construct a tetrahedron using spherepoints (e.g., first four
    points)": :func:`_start_tetrahedron`;
  - lines 12-17, "for i=4 to num spherepoints": :func:`_grow` -- for each
    remaining row in input order the faces it sees are removed and the
    removed faces' edges that occur once ("shared (count > 1) are thrown
    away") are joined to the point.

``kenwright`` with ``sphere=off`` is therefore a plain incremental hull: an
interior point or a duplicate sees no face and is skipped, as in any
incremental hull.  With ``sphere=on`` the harness runs ``sphere_project``
and then this function on the projected surface points, which is the seed's
full method, support mapping included.  The support mapping's known flaw (it
culls true hull vertices that are not the farthest point along any probed
direction, see :mod:`hullstress.sphere`) belongs to that variant.

Readings taken where the seed is silent or loose:

* **Starting tetrahedron.**  The seed takes "the first four" points.  When
  those are degenerate we scan the rows in order: the first row, the next
  row farther than ``eps`` from it, the next row farther than ``eps`` from
  their line, the next row farther than ``eps`` from their plane.  When the
  first four are a proper tetrahedron this is exactly the seed's choice.  If
  no such four exist a ``ValueError`` is raised (coplanar within ``eps``).
* **Visibility.**  "front facing if n.p > n.v" with the tolerance added and
  the normal ``n = (b - a) x (c - a)`` made unit length, so that ``eps`` is a
  distance: a face is visible when ``n.p - n.a > eps``.  A face whose normal
  has zero length (Figure 10 (b)) is never visible.
* **Order.**  Points are inserted in input order (the seed's "for i=4 to num
  spherepoints"), not farthest-first.  Runs of points that see no face are
  tested in blocks; the block's dot products are the same elementwise
  operations as one point's, so the first visible point and everything after
  it is exactly what the one-at-a-time loop would get.

Quirks kept on purpose: no face merging, no special handling of coplanar
faces (a point on a face's plane within ``eps`` does not see it, so such
points are skipped and coplanar facets stay split into triangles), no
re-check that the visible region is a disc (the edge count rule is applied as
written), and floating-point predicates throughout (overflow and underflow
give whatever inf/nan outcome the arithmetic gives, without warnings).
"""

from __future__ import annotations

from collections import Counter
from typing import Any

import numpy as np

from .._registry import register_algorithm
from ..errors import AlgorithmStepLimit
from ..tolerance import tolerance

__all__ = ["kenwright_hull"]

NAME = "kenwright"

# Iteration guard: a valid hull of n points has at most 2n - 4 triangles, so a
# face list past FACE_LIMIT_PER_POINT * n + FACE_LIMIT_BASE has run away.
FACE_LIMIT_PER_POINT = 16
FACE_LIMIT_BASE = 64

# Up to this many removed faces, the horizon is found in plain Python.
_FEW_FACES = 64
# Points that see no face are tested in blocks of at most this many
# (points x faces) comparisons (~2 MB of float64), so memory stays bounded.
_BLOCK_ELEMENTS = 1 << 18


def _dot(rows: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise dot products summed left to right (no BLAS: bit-identical on every machine)."""
    return rows[:, 0] * v[..., 0] + rows[:, 1] * v[..., 1] + rows[:, 2] * v[..., 2]


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise ``u x v``: each component two products and one difference (numpy.cross's operations, without its set-up)."""
    return np.stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],
                     u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                     u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]], axis=1)


def _face_planes(pts: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (zero for degenerate faces) and offsets ``n . a`` of ``faces``."""
    a, b, c = pts[faces[:, 0]], pts[faces[:, 1]], pts[faces[:, 2]]
    normals = _cross(b - a, c - a)
    length = np.sqrt(_dot(normals, normals))
    ok = length > 0.0
    normals[ok] /= length[ok, None]
    normals[~ok] = 0.0
    return normals, _dot(normals, a)


def _start_tetrahedron(pts: np.ndarray, eps: float) -> tuple[list[int], np.ndarray]:
    """The first four rows (in input order) that span a tetrahedron.

    Returns the four rows of ``pts`` used and the tetrahedron's faces,
    counter-clockwise seen from outside.  Raises ValueError when the points
    are coplanar within ``eps``.
    """
    n = len(pts)
    if n < 4:
        raise ValueError(f"{NAME}: need at least 4 points for a tetrahedron, got {n}")
    p0 = pts[0]
    rel = pts - p0
    dist0 = np.sqrt(_dot(rel, rel))
    far = np.flatnonzero(dist0 > eps)
    if len(far) == 0:
        raise ValueError(f"{NAME}: all {n} points are within eps={eps!r} of one point")
    i1 = int(far[0])
    axis = rel[i1] / dist0[i1]
    off_line = np.cross(rel, axis)
    line_dist = np.sqrt(_dot(off_line, off_line))
    line_dist[[0, i1]] = 0.0  # their own rounding residue must not pick them again
    far = np.flatnonzero(line_dist > eps)
    if len(far) == 0:
        raise ValueError(f"{NAME}: the {n} points are collinear within eps={eps!r}")
    i2 = int(far[0])
    normal = np.cross(rel[i1], rel[i2])
    length = float(np.sqrt(_dot(normal[None, :], normal))[0])
    if length == 0.0:  # the cross product underflowed: no usable plane
        raise ValueError(f"{NAME}: the {n} points are collinear within eps={eps!r}")
    normal /= length
    plane_dist = _dot(rel, normal)
    plane_dist[[0, i1, i2]] = 0.0
    far = np.flatnonzero(np.abs(plane_dist) > eps)
    if len(far) == 0:
        raise ValueError(f"{NAME}: the {n} points are coplanar within eps={eps!r}")
    i3 = int(far[0])
    first = [0, i1, i2, i3]
    faces = np.array([[0, i1, i2], [0, i3, i1], [i1, i3, i2], [i2, i3, 0]], dtype=np.int64)
    if plane_dist[i3] > 0.0:  # i3 above face (0, i1, i2): every face is inward
        faces = faces[:, ::-1].copy()
    return first, faces


def _horizon(removed: np.ndarray, n: int) -> np.ndarray:
    """Directed edges of ``removed`` faces whose undirected edge occurs once, in the faces' order."""
    if len(removed) <= _FEW_FACES:
        # A few faces (each insertion on a small hull): plain Python beats np.unique's set-up.
        edges = [(a, b) for u, v, w in removed.tolist() for a, b in ((u, v), (v, w), (w, u))]
        seen = Counter((a, b) if a < b else (b, a) for a, b in edges)
        once = [(a, b) for a, b in edges if seen[(a, b) if a < b else (b, a)] == 1]
        return np.array(once, dtype=np.int64).reshape(-1, 2)
    edges = removed[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    # One int64 key per undirected edge (rows < n, so lo * n + hi is unique).
    keys = np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(edges[:, 0], edges[:, 1])
    _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    return edges[counts[inverse] == 1]


def _as_points(points: Any) -> np.ndarray:
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3), got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        bad = int(np.sum(~np.isfinite(pts)))
        raise ValueError(f"points must be finite, got {bad} non-finite coordinates")
    return pts


def _resolve_eps(points: np.ndarray, eps: float | None) -> float:
    if eps is None:
        # Not validated: huge input gives an inf/nan tolerance, the float method's own outcome.
        return tolerance(points, "scaled")
    value = float(eps)
    if not (value >= 0.0 and np.isfinite(value)):
        raise ValueError(f"eps must be a finite float >= 0 or None, got {eps!r}")
    return value


@register_algorithm(NAME, dim=3)
def kenwright_hull(points: Any, /, *, eps: float | None = None) -> np.ndarray:
    """Kenwright's incremental hull: a tetrahedron grown by every point in input order.

    Algorithm 1, lines 10-17 of seed 002 over all input rows; the seed's
    preliminary stage (duplicates, support mapping, sphere projection) is
    the harness's ``sphere=on`` variant, :func:`hullstress.sphere.sphere_project`.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
        Input points (read-only; not modified).
    eps : float or None
        Tolerance of the point-plane test and of the starting tetrahedron's
        scan; ``None`` means ``hullstress.tolerance.tolerance(points, "scaled")``.

    Returns
    -------
    ndarray of shape (m, 3), int64
        Triangles, counter-clockwise seen from outside, as rows of
        ``points``.  Interior points and duplicates see no face and are
        never used; coplanar facets stay split into triangles.

    Raises
    ------
    ValueError
        On a bad shape, non-finite input, a negative or non-finite ``eps``,
        fewer than four points, or points that are coplanar within ``eps``.
    hullstress.errors.AlgorithmStepLimit
        When the face list grows past ``16 n + 64`` for ``n`` points (a valid
        hull has at most ``2 n - 4``): the growth has run away.

    Examples
    --------
    >>> cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    >>> faces = kenwright_hull(np.vstack([[[0.5, 0.5, 0.5]], cube]))
    >>> faces.shape, sorted(set(faces.ravel().tolist()))
    ((12, 3), [1, 2, 3, 4, 5, 6, 7, 8])

    A flat 3 x 3 grid (degenerate): the scan finds no fourth point off the
    plane of the first three, so all nine points are declined:

    >>> grid = np.array([[x, y, 0.0] for x in (-1.0, 0.0, 1.0) for y in (-1.0, 0.0, 1.0)])
    >>> kenwright_hull(grid)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: kenwright: the 9 points are coplanar within eps=3.14...e-16
    """
    pts = _as_points(points)
    tol = _resolve_eps(pts, eps)
    # Huge or tiny coordinates overflow or underflow in the cross and dot
    # products; the float method's inf/nan outcome is kept, without warnings.
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        return _grow(pts, tol)


def _visible(normals: np.ndarray, offsets: np.ndarray, queries: np.ndarray, tol: float) -> np.ndarray:
    """``n . q - n . a > tol`` for every (query, face): shape (q, m).

    The same elementwise operations, in the same order, as ``_dot(normals,
    q) - offsets`` for one query, so a block agrees bit for bit with the
    one-point-at-a-time loop.
    """
    dots = (
        queries[:, 0:1] * normals[:, 0] + queries[:, 1:2] * normals[:, 1] + queries[:, 2:3] * normals[:, 2]
    )
    return dots - offsets > tol


def _grow(pts: np.ndarray, tol: float) -> np.ndarray:
    """Algorithm 1, lines 10-17, over all rows of ``pts`` in order; faces index ``pts``."""
    n = len(pts)
    first, faces = _start_tetrahedron(pts, tol)
    normals, offsets = _face_planes(pts, faces)
    limit = FACE_LIMIT_PER_POINT * n + FACE_LIMIT_BASE
    used = np.zeros(n, dtype=bool)
    used[first] = True
    rest = np.flatnonzero(~used)  # "for i=4 to num spherepoints", in input order
    pos = 0
    block = 1
    while pos < len(rest):
        # Test the next `block` points at once; the hull only changes at the
        # first of them that sees a face, so the ones before it are skipped
        # exactly as the sequential loop would skip them.
        rows = rest[pos : pos + block]
        vis = _visible(normals, offsets, pts[rows], tol)
        seen = vis.any(axis=1)
        if not seen.any():
            pos += len(rows)
            # Misses get likelier as the hull grows: widen, within the memory cap.
            block = min(2 * block, max(1, _BLOCK_ELEMENTS // len(faces)))
            continue
        j = int(np.argmax(seen))
        step, i = pos + j, int(rows[j])
        visible = vis[j]
        new = _horizon(faces[visible], n)
        new = np.column_stack([new, np.full(len(new), i, dtype=np.int64)])
        new_normals, new_offsets = _face_planes(pts, new)
        keep = ~visible
        faces = np.concatenate([faces[keep], new])
        normals = np.concatenate([normals[keep], new_normals])
        offsets = np.concatenate([offsets[keep], new_offsets])
        if len(faces) > limit:
            raise AlgorithmStepLimit(
                f"{NAME}: insertion step {step} (input row {i}) left "
                f"{len(faces)} faces, over the limit {limit} for {n} points"
            )
        pos = step + 1
        block = max(1, block // 2)
    return faces
