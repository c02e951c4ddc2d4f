"""Exact geometry oracles for the algorithm tests, independent of hullstress.checker (the checker is itself under test)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

_EPS = float(np.finfo(np.float64).eps)
_ORIENT_ERRBOUND = (7.0 + 56.0 * _EPS) * _EPS  # Shewchuk's orient3d errboundA


def exact_orient(a, b, c, d) -> int:
    """Sign of det[a-d, b-d, c-d] in exact rational arithmetic."""
    rows = [[Fraction(float(x)) - Fraction(float(y)) for x, y in zip(p, d)] for p in (a, b, c)]
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = rows
    det = ax * (by * cz - bz * cy) + bx * (cy * az - cz * ay) + cx * (ay * bz - az * by)
    return (det > 0) - (det < 0)


def orient_sign(points: np.ndarray, tri: np.ndarray, queries: np.ndarray | None = None) -> np.ndarray:
    """Exact sign of det[a-q, b-q, c-q] for every (triangle, query): shape (m, k).

    ``queries`` defaults to ``points``.  Negative means the query is strictly
    above (outside) the counter-clockwise triangle.  A float filter with
    Shewchuk's bound decides most entries; the rest are computed exactly.
    """
    queries = points if queries is None else queries
    q = queries[None, :, :]
    a = points[tri[:, 0]][:, None, :] - q
    b = points[tri[:, 1]][:, None, :] - q
    c = points[tri[:, 2]][:, None, :] - q
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    bx, by, bz = b[..., 0], b[..., 1], b[..., 2]
    cx, cy, cz = c[..., 0], c[..., 1], c[..., 2]
    det = ax * (by * cz - bz * cy) + bx * (cy * az - cz * ay) + cx * (ay * bz - az * by)
    perm = (
        np.abs(ax) * (np.abs(by * cz) + np.abs(bz * cy))
        + np.abs(bx) * (np.abs(cy * az) + np.abs(cz * ay))
        + np.abs(cx) * (np.abs(ay * bz) + np.abs(az * by))
    )
    sign = np.sign(det).astype(np.int64)
    for f, k in zip(*np.nonzero(np.abs(det) <= _ORIENT_ERRBOUND * perm)):
        t = tri[f]
        sign[f, k] = exact_orient(points[t[0]], points[t[1]], points[t[2]], queries[k])
    return sign


def random_cloud(seed: int, n: int, kind: str) -> np.ndarray:
    """n points uniform in the unit ball, uniform in the cube [-1, 1]^3, or standard Gaussian.

    Built from the generator's draws with elementwise + - * and comparisons
    only (the ball by rejection from the cube), never ``**``, ``exp``, ``sin``
    or BLAS, whose last bits numpy may take from a CPU-specific path: the same
    seed gives the same bytes on every machine.
    """
    rng = np.random.default_rng(seed)
    if kind == "ball":
        kept = np.zeros((0, 3))
        while len(kept) < n:
            x = rng.random((2 * n + 8, 3)) * 2 - 1
            kept = np.vstack([kept, x[x[:, 0] * x[:, 0] + x[:, 1] * x[:, 1] + x[:, 2] * x[:, 2] <= 1.0]])
        return kept[:n].copy()
    if kind == "cube":
        return rng.random((n, 3)) * 2 - 1
    return rng.standard_normal((n, 3))


def qhull_outward(points: np.ndarray) -> np.ndarray:
    """Qhull's triangles (scipy), each turned to face outward: a correct 3D hull of a random cloud.

    For tests that need an algorithm to be right, so that what fails is something else.
    """
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    faces = hull.simplices.copy()
    a, b, c = (points[faces[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    faces[inward] = faces[inward][:, ::-1]
    return faces
