"""Kenwright's preliminary stage: duplicates, centroid, support mapping, sphere.

Seed: ``002_262f4fc866409e02.txt`` (Ben Kenwright, "Convex Hulls: Surface
Mapping onto a Sphere"), section 4 "A preliminary stage" and Algorithm 1,
lines 1-9.  The stage is implemented once here and used by the harness's
``sphere=on`` variant, for every algorithm (in-house or plug-in), through
:func:`sphere_project`; the harness maps the algorithm's output indices back
with ``original_indices[output]`` (:func:`map_back`).  ``kenwright`` with
``sphere=on`` is therefore the seed's full method, and ``kenwright`` with
``sphere=off`` is its incremental stage alone (lines 10-17).

The mapping of code to Algorithm 1:

==========  ============================================  =====================
Alg. 1      seed text                                     here
==========  ============================================  =====================
line 1      "Remove duplicate points (i.e., within        :func:`remove_duplicates`
            pre-defined distance tolerance)"
line 2      "Calculate Centroid" (Equation 1)             :func:`sphere_centroid`
lines 4-6   "Normal = Centroid to Points(i)",             :func:`support_indices`
            "FindSupportPoint(Normal, Points)"
line 7      "Project surfacepoint onto sphere surface"    :func:`project_onto_sphere`
line 8      "Add supportpoint to spherepoints"            :func:`surface_points`
==========  ============================================  =====================

Readings taken where the seed is silent (each kept on purpose):

* **Duplicate tolerance.**  The "pre-defined distance tolerance" is the
  ``eps`` argument (``None``: ``tolerance(points, "scaled")``).  Points are
  scanned in input order and a point is dropped when its Euclidean distance
  to an already *kept* point is ``<= eps`` (greedy, first occurrence wins),
  so ``eps = 0`` removes exact duplicates only.
* **Centroid.**  Equation 1 over the de-duplicated points (the seed computes
  it after removing duplicates), so a point repeated many times does not
  pull the centroid.
* **Support mapping.**  The direction for point ``i`` is ``p_i - centroid``,
  not normalised (the arg-max does not change under positive scaling); the
  support point is the arg-max of ``dot(direction, point)`` over *all*
  de-duplicated points, as the seed writes it (raw points, not points
  relative to the centroid), with ties going to the lowest input index.  The
  dot product is evaluated elementwise as ``(dx*px + dy*py) + dz*pz`` rather
  than through BLAS so the result is bit-identical on every machine (a Dask
  worker must agree with a local run).  A point that coincides with the
  centroid has no direction and contributes no support point.
* **Surface list.**  A support point found twice is kept once, in
  first-found order (the order of the points whose direction found it).
* **Sphere.**  A *unit* sphere around the centroid, whatever the input's
  scale (Figure 1 (c): "centroid to surface point fixed length"):
  ``centroid + (s - centroid) / |s - centroid|``.

Known weakness of the method, kept: the support mapping only probes the
directions ``centroid -> p_i``.  A hull vertex that is not the farthest point
in any of those directions is culled, so the hull built from the surface list
can miss true vertices and leave input points outside it (on the run of
uniform clouds in docs/findings.md, n = 16..256: 10% of the vertices in 2D, 23% in 3D).
It keeps them all when each point is the farthest along its own direction,
e.g. centrally symmetric points on a sphere.  In 3D that is not enough:
projecting even every true vertex radially onto a sphere changes which of
them span faces.  A sweep records both causes per row
(:mod:`hullstress.sphere_causes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from .contract import FaceSet
from .tolerance import tolerance

__all__ = [
    "SurfacePoints",
    "remove_duplicates",
    "support_indices",
    "surface_points",
    "sphere_project",
    "sphere_centroid",
    "project_onto_sphere",
    "map_back",
]

# Elements of one block of the (directions x points) dot-product matrix; a
# block of ~2 MB keeps the support mapping's memory bounded for any n.
_BLOCK_ELEMENTS = 1 << 18


def _as_points(points: Any, name: str = "points") -> np.ndarray:
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"{name} must have shape (n, 2) or (n, 3), got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ValueError(f"{name} must be finite, got {int(np.sum(~np.isfinite(pts)))} non-finite coordinates")
    return pts


def _resolve_eps(points: np.ndarray, eps: float | None) -> float:
    if eps is None:
        return tolerance(points, "scaled")
    value = float(eps)
    if not (value >= 0.0 and np.isfinite(value)):
        raise ValueError(f"eps must be a finite float >= 0 or None, got {eps!r}")
    return value


def remove_duplicates(points: np.ndarray, eps: float) -> np.ndarray:
    """Indices of the points kept after removing duplicates within ``eps``.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        Finite points.
    eps : float
        Distance tolerance: a point within Euclidean distance ``<= eps`` of an
        earlier kept point is a duplicate.

    Returns
    -------
    ndarray of shape (k,), int64
        Increasing row indices of the kept points (the first of each group).

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [1.0, 1e-20]])
    >>> remove_duplicates(pts, 0.0).tolist()
    [0, 1, 3]
    >>> remove_duplicates(pts, 1e-12).tolist()
    [0, 1]
    """
    n = len(points)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    # Exact duplicates first: np.unique is O(n log n) and leaves one
    # representative per distinct coordinate row, its first occurrence.
    # (+ 0.0 turns -0.0 into 0.0, which np.unique would otherwise keep apart.)
    _, first = np.unique(points + 0.0, axis=0, return_index=True)
    first = np.sort(first).astype(np.int64)
    if eps <= 0.0 or len(first) < 2:
        return first
    # Distinct points within eps are rare (eps is a few ulps of the extent),
    # so the pair list is short; the greedy pass over it is in input order.
    # The k-d tree compares squared distances, which overflow past ~1e154 and
    # underflow below ~1e-154; an exact power-of-two rescale (max |coordinate|
    # in [0.5, 1)) keeps every "distance <= eps" decision unchanged.
    _, exponent = np.frexp(np.abs(points[first]).max())
    reps = np.ldexp(points[first], -int(exponent))
    radius = float(np.ldexp(eps, -int(exponent)))
    pairs = cKDTree(reps).query_pairs(r=radius, output_type="ndarray")
    if len(pairs) == 0:
        return first
    neighbours: dict[int, list[int]] = {}
    for a, b in pairs.tolist():
        lo, hi = (a, b) if a < b else (b, a)
        neighbours.setdefault(hi, []).append(lo)
    kept = np.ones(len(first), dtype=bool)
    for j in sorted(neighbours):
        if any(kept[i] for i in neighbours[j]):
            kept[j] = False
    return first[kept]


def support_indices(points: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Support point of ``points`` in each direction (Kenwright's FindSupportPoint).

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    directions : ndarray of shape (m, d), float64

    Returns
    -------
    ndarray of shape (m,), int64
        For each direction, the row of ``points`` with the largest
        ``dot(direction, point)``; ties go to the lowest row.  A zero
        direction gets row 0 (every dot product ties at zero).

    Notes
    -----
    The full (m, n) matrix is never allocated: directions are processed in
    blocks of about 2**18 dot products.

    Examples
    --------
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    >>> support_indices(square, np.array([[1.0, 0.2], [-1.0, -1.0], [1.0, 1.0]])).tolist()
    [2, 0, 2]
    """
    pts = np.asarray(points, dtype=np.float64)
    dirs = np.asarray(directions, dtype=np.float64)
    n, d = pts.shape
    m = len(dirs)
    out = np.empty(m, dtype=np.int64)
    if m == 0:
        return out
    if n == 0:
        raise ValueError("points must hold at least one point, got shape (0, d)")
    cols = [np.ascontiguousarray(pts[:, j]) for j in range(d)]
    block = max(1, _BLOCK_ELEMENTS // n)
    acc = np.empty((min(block, m), n))
    tmp = np.empty_like(acc)
    # Huge coordinates overflow to inf (and inf - inf to nan); that is the
    # float method's own outcome, not a reason to warn.
    with np.errstate(over="ignore", invalid="ignore"):
        _support_blocks(dirs, cols, out, block, acc, tmp)
    return out


def _support_blocks(
    dirs: np.ndarray, cols: list[np.ndarray], out: np.ndarray, block: int, acc: np.ndarray, tmp: np.ndarray
) -> None:
    d = len(cols)
    for start in range(0, len(dirs), block):
        dblk = dirs[start : start + block]
        a = acc[: len(dblk)]
        t = tmp[: len(dblk)]
        # Fixed left-to-right order, no BLAS: bit-identical everywhere.
        np.multiply(dblk[:, 0:1], cols[0], out=a)
        for j in range(1, d):
            np.multiply(dblk[:, j : j + 1], cols[j], out=t)
            a += t
        out[start : start + len(dblk)] = np.argmax(a, axis=1)  # first max = lowest row


@dataclass(frozen=True)
class SurfacePoints:
    """The output of Kenwright's preliminary stage before the projection.

    Attributes
    ----------
    indices : ndarray of shape (k,), int64
        Input rows of the surface (support) points, in first-found order.
    centroid : ndarray of shape (d,), float64
        Mean of the de-duplicated points.
    kept : ndarray of shape (j,), int64
        Input rows that survived duplicate removal (increasing).
    eps : float
        The duplicate tolerance used.
    """

    indices: np.ndarray
    centroid: np.ndarray
    kept: np.ndarray
    eps: float


def _kept_and_centroid(pts: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Algorithm 1, lines 1-2: the rows kept by duplicate removal and their centroid (NaN if none)."""
    kept = remove_duplicates(pts, tol)
    if len(kept) == 0:
        return kept, np.full(pts.shape[1], np.nan)
    with np.errstate(over="ignore", invalid="ignore"):  # huge input: inf/nan, as floats give
        return kept, pts[kept].mean(axis=0)


def sphere_centroid(points: Any, /, *, eps: float | None = None) -> np.ndarray:
    """The centroid the sphere method projects around (Algorithm 1, lines 1-2).

    The mean of the points left after duplicate removal within ``eps``
    (``None``: ``tolerance(points, "scaled")``); NaN for empty input.

    Examples
    --------
    >>> sphere_centroid(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 0.0], [1.0, 3.0]])).tolist()
    [1.0, 1.0]
    """
    pts = _as_points(points)
    return _kept_and_centroid(pts, _resolve_eps(pts, eps))[1]


def project_onto_sphere(points: Any, rows: Any, centroid: np.ndarray) -> np.ndarray:
    """Algorithm 1, line 7: ``centroid + (p - centroid) / |p - centroid|`` for each of ``points[rows]``.

    Parameters
    ----------
    points : array_like of shape (n, d)
    rows : array_like of int
        The rows to project.
    centroid : ndarray of shape (d,)

    Returns
    -------
    ndarray of shape (len(rows), d), float64, C-contiguous

    Raises
    ------
    ValueError
        When a row's distance from the centroid rounds to zero (no direction
        to project along; e.g. coordinates below ~1e-154, whose squares underflow).
    """
    pts = np.asarray(points, dtype=np.float64)
    idx = np.asarray(rows, dtype=np.int64)
    d = pts.shape[1]
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        rel = pts[idx] - centroid
        length = np.sqrt(sum(rel[:, j] * rel[:, j] for j in range(d)))  # fixed order, no BLAS
        if np.any(length == 0.0):
            row = int(idx[np.argmax(length == 0.0)])
            raise ValueError(
                f"points row {row}: its distance from the centroid rounds to 0 (the point is "
                "at the centroid, or the squares underflow); it cannot be projected"
            )
        projected = centroid + rel / length[:, None]
    return np.ascontiguousarray(projected, dtype=np.float64)


def surface_points(points: Any, /, *, eps: float | None = None) -> SurfacePoints:
    """Run Algorithm 1, lines 1-6 and 8: duplicates, centroid, support points.

    Parameters
    ----------
    points : array_like of shape (n, d), d in {2, 3}
        Finite input points (not modified).
    eps : float or None
        Duplicate tolerance; ``None`` means ``tolerance(points, "scaled")``.

    Returns
    -------
    SurfacePoints
        Surface point rows in first-found order, the centroid, the kept rows.

    Raises
    ------
    ValueError
        If ``points`` has the wrong shape or non-finite values, or ``eps`` is
        negative or non-finite.

    Examples
    --------
    A square with its centre and a duplicated corner: the centre and the
    duplicate never come back as support points.

    >>> pts = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0], [2.0, 0.0]])
    >>> surface_points(pts).indices.tolist()
    [0, 1, 2, 3]
    """
    pts = _as_points(points)
    tol = _resolve_eps(pts, eps)
    kept, centroid = _kept_and_centroid(pts, tol)
    if len(kept) == 0:
        return SurfacePoints(np.zeros(0, np.int64), centroid, kept, tol)
    uniq = pts[kept]
    with np.errstate(over="ignore", invalid="ignore"):  # huge input: inf/nan, as floats give
        directions = uniq - centroid
    # A point at the centroid has no direction ("Normal = Centroid to
    # Points(i)" is the zero vector), so it asks for no support point.
    has_direction = np.any(directions != 0.0, axis=1)
    found = support_indices(uniq, directions[has_direction])
    # First-found order without repeats: np.unique's first occurrences, re-sorted.
    _, first = np.unique(found, return_index=True)
    order = found[np.sort(first)]
    return SurfacePoints(kept[order], centroid, kept, tol)


def sphere_project(points: Any, /, *, eps: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Kenwright's preprocessing: surface points projected onto a unit sphere.

    Parameters
    ----------
    points : array_like of shape (n, d), d in {2, 3}
        Finite input points (not modified).  In 2D the sphere is a circle.
    eps : float or None
        Duplicate tolerance; ``None`` means ``tolerance(points, "scaled")``.

    Returns
    -------
    projected : ndarray of shape (k, d), float64, C-contiguous
        ``centroid + (s - centroid) / |s - centroid|`` for each surface point
        ``s``, in first-found order.
    original_indices : ndarray of shape (k,), int64
        Row ``i`` of ``projected`` comes from input row ``original_indices[i]``.

    Raises
    ------
    ValueError
        On a bad shape, non-finite values, a bad ``eps``, or a surface point
        whose distance from the centroid rounds to zero (no direction to
        project along; e.g. coordinates below ~1e-154, whose squares underflow).

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [2.0, 2.0]])
    >>> q, idx = sphere_project(pts)
    >>> idx.tolist(), np.round(np.hypot(*(q - [2.0, 2.0]).T), 12).tolist()
    ([0, 1, 2, 3], [1.0, 1.0, 1.0, 1.0])

    Collinear input (degenerate) still projects: only the two ends survive.

    >>> sphere_project(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))[1].tolist()
    [0, 2]
    """
    pts = _as_points(points)
    surf = surface_points(pts, eps=eps)
    d = pts.shape[1]
    if len(surf.indices) == 0:
        return np.zeros((0, d), dtype=np.float64), surf.indices
    projected = project_onto_sphere(pts, surf.indices, surf.centroid)
    return projected, surf.indices.astype(np.int64, copy=False)


def map_back(output: Any, original_indices: np.ndarray) -> Any:
    """Map an algorithm's output indices (into the projected set) to input rows.

    Parameters
    ----------
    output : array_like of int, sequence of sequences of int, or FaceSet
        A 2D vertex list, an (m, 3) triangle array, a list of polygons, or
        normalised faces (:class:`~hullstress.contract.FaceSet`).
    original_indices : ndarray of shape (k,), int64
        The second value returned by :func:`sphere_project`.

    Returns
    -------
    ndarray of int64, list of ndarray, or FaceSet
        The same structure with every index ``i`` replaced by
        ``original_indices[i]``: an array for regular input, a list of
        arrays for polygons of different sizes, a FaceSet for a FaceSet
        (face ``k`` stays face ``k``).

    Examples
    --------
    >>> map_back([[0, 1, 2]], np.array([5, 7, 9])).tolist()
    [[5, 7, 9]]
    >>> [p.tolist() for p in map_back([[0, 1, 2, 1], [2, 0]], np.array([5, 7, 9]))]
    [[5, 7, 9, 7], [9, 5]]
    """
    idx = np.asarray(original_indices, dtype=np.int64)
    if isinstance(output, FaceSet):
        return FaceSet(idx[output.indices], output.offsets.copy())
    try:
        regular = np.asarray(output, dtype=np.int64)
    except ValueError:  # ragged: polygons of different sizes
        return [idx[np.asarray(p, dtype=np.int64)] for p in output]
    return idx[regular]
