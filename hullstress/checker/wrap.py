"""How many times a closed surface (polygon) wraps around an interior point: a ray-parity count.

Local convexity (no reflex edge, an interior point ``o`` strictly below every
facet) does not rule out a surface that covers the sphere of directions twice
(a branched double cover, or a star polygon such as {7/2}).  The wrap number
settles it: the number of facets whose cone from ``o`` contains a ray from
``o``; a convex surface has exactly one.

The ray runs from ``o`` through a point ``q``.  A count is only valid when
the ray meets no edge, i.e. ``q`` lies on no plane (line, in 2D) through
``o`` and an edge's end points.  Instead of drawing rays until one misses
every edge (which fails silently when ``q`` rounds onto ``o``, as it does at
coordinate scale 1e20), ``q`` is perturbed symbolically (Edelsbrunner and
Mücke's Simulation of Simplicity): ``q' = q + (e, e**2, e**3)`` for an
infinitesimal ``e > 0``.  Where ``q`` itself is on such a plane, the sign for
``q'`` is the sign of the first nonzero coordinate of the plane's normal, an
exact 2D orientation of the projected points.  ``o`` is strictly off every
edge's line, so the normal is never zero and every count is decided.

Soundness: the tie-break signs of :func:`break_ties_2d` come from comparisons
of finite doubles (never ``o - a``, which overflows near 1.7e308); the center
is the finite :func:`._geometry.vertex_mean` or the exact interior point, and
every orientation goes through :mod:`.predicates` (issue 33, F3).
"""

from __future__ import annotations

import functools

import numpy as np

from ..contract import FaceSet
from ._geometry import Interior
from .predicates import orient2d, orient2d_mean, orient3d, orient3d_mean

__all__ = ["wrap_number_3d", "wrap_number_2d", "break_ties_3d", "break_ties_2d", "ray_point"]

#: The projections whose 2D orientations are the x, y and z components of a normal (u - o) x (v - o).
_NORMAL_COMPONENTS = ((1, 2), (2, 0), (0, 1))


@functools.lru_cache(maxsize=64)
def _direction(seed: int, dim: int) -> np.ndarray:
    direction = np.random.default_rng(seed).normal(size=dim)
    direction.setflags(write=False)
    return direction


def ray_point(origin: np.ndarray, extent: float, seed: int) -> np.ndarray:
    """A point ``q`` off ``origin`` in a pseudo-random direction (fixed per seed) at the input's scale.

    ``origin`` itself if that overflows: the symbolic perturbation then gives the ray its direction.
    """
    if extent < 2.0**1000:  # |q| < 2 extent: no overflow
        return origin + _direction(seed, len(origin)) * (extent * 0.0625)
    with np.errstate(all="ignore"):
        q = origin + _direction(seed, len(origin)) * (extent * 0.0625)
    return q if np.isfinite(q).all() else np.array(origin, dtype=np.float64)


def _orient2d_o(center: np.ndarray | None, interior: Interior | None, u: np.ndarray, v: np.ndarray, axes) -> np.ndarray:
    """Exact ``orient2d(o, u, v)`` on the coordinate pair ``axes`` (``o`` the center, or the exact interior)."""
    i, j = axes
    if center is not None:
        return orient2d(center[[i, j]], u[:, [i, j]], v[:, [i, j]])
    return orient2d_mean(u[:, [i, j]], v[:, [i, j]], [r[[i, j]] for r in interior.rows])


def wrap_number_3d(
    points: np.ndarray,
    faces: FaceSet,
    center: np.ndarray | None,
    interior: Interior | None,
    seed: int = 0,
) -> int:
    """Faces whose cone from the interior point strictly contains the (perturbed) ray.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
        A closed surface of convex faces, the interior point strictly below each.
    center : ndarray of shape (3,) or None
        A float point verified strictly below every face (the ray's origin), or None.
    interior : Interior or None
        The exact interior point, the origin when ``center`` is None (one of
        the two must be given).
    seed : int
        Chooses the ray's direction (the count does not depend on it).

    Returns
    -------
    int
    """
    u = points[faces.indices]
    nxt = np.roll(np.arange(len(faces.indices)), -1)
    last = faces.offsets[1:] - 1
    nxt[last] = faces.offsets[:-1]
    v = points[faces.indices[nxt]]
    origin = center if center is not None else interior.approx
    q = ray_point(origin, float(max(u.max(), -u.min())), seed)
    if center is not None:
        s = -orient3d(center, u, v, q)  # > 0: q strictly on the inner side of the plane (o, u, v)
    else:
        s = orient3d_mean(u, v, q, interior.rows)  # orient3d(u, v, q, o) = -orient3d(o, u, v, q)
    break_ties_3d(s, u, v, center, interior)
    inside = np.logical_and.reduceat(s > 0, faces.offsets[:-1])
    return int(inside.sum())


def break_ties_3d(
    s: np.ndarray, u: np.ndarray, v: np.ndarray, center: np.ndarray | None, interior: Interior | None,
    points: np.ndarray | None = None,
) -> None:
    """Replace the zeros of ``s = -orient3d(o, u, v, q)`` by the signs for the perturbed ``q``, in place.

    ``s(q + d) = s(q) + n . d`` with ``n = (u - o) x (v - o)`` and ``d = (e, e**2, e**3)``:
    the first nonzero component of ``n`` decides.  ``u`` and ``v`` are points,
    or indices into ``points`` when that is given (gathered only where ties are).
    """
    tie = np.flatnonzero(s == 0)
    if not tie.size:
        return
    if points is not None:
        u, v = points[u[tie]], points[v[tie]]
        tie_rows = np.arange(len(tie))
    else:
        u, v, tie_rows = u[tie], v[tie], np.arange(len(tie))
    for axes in _NORMAL_COMPONENTS:
        if not tie.size:
            return
        comp = _orient2d_o(center, interior, u[tie_rows], v[tie_rows], axes)
        s[tie] = comp
        tie, tie_rows = tie[comp == 0], tie_rows[comp == 0]
    if tie.size:  # o on an edge's line: impossible below every face, but never count it silently
        raise ValueError(f"the wrap number is undecidable: the interior point is on the line of {tie.size} edges")


def wrap_number_2d(
    points: np.ndarray,
    poly: np.ndarray,
    center: np.ndarray | None,
    interior: Interior | None,
    seed: int = 0,
) -> int:
    """Edges of a polygon whose cone from the interior point contains the (perturbed) ray.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    poly : ndarray of shape (k,), int64
        A closed polygon with the interior point strictly left of every edge.
    center, interior, seed
        As in :func:`wrap_number_3d`.

    Returns
    -------
    int
    """
    a = points[poly]
    origin = center if center is not None else interior.approx
    q = ray_point(origin, float(max(a.max(), -a.min())), seed)
    if center is not None:
        s = orient2d(center, a, q)
    else:
        s = orient2d_mean(a, q, interior.rows)  # orient2d(a, q, o) = orient2d(o, a, q)
    break_ties_2d(s, a, center, interior)
    # Edge i (a_i -> a_i+1) holds the ray when it is left of o -> a_i and right of o -> a_i+1.
    return int(np.count_nonzero((s > 0) & (np.roll(s, -1) < 0)))


def break_ties_2d(s: np.ndarray, a: np.ndarray, center: np.ndarray | None, interior: Interior | None) -> None:
    """Replace the zeros of ``s = orient2d(o, a, q)`` by the signs for the perturbed ``q``, in place.

    ``s(q + (e, e**2)) = s(q) + e (o_y - a_y) + e**2 (a_x - o_x)``; ``o`` is
    never a vertex ``a`` (it is strictly left of every edge).
    """
    tie = np.flatnonzero(s == 0)
    if not tie.size:
        return
    t = a[tie]
    if center is not None:
        # Comparisons, not differences: exact for every finite float (no rounding, no overflow).
        first = (center[1] > t[:, 1]).astype(np.int8) - (center[1] < t[:, 1]).astype(np.int8)
        second = (t[:, 0] > center[0]).astype(np.int8) - (t[:, 0] < center[0]).astype(np.int8)
    else:
        ones = np.ones(len(t))
        rows = interior.rows
        first = orient2d_mean(np.c_[0 * ones, t[:, 1]], np.c_[ones, t[:, 1]], rows)  # o_y - a_y
        second = orient2d_mean(np.c_[t[:, 0], 0 * ones], np.c_[t[:, 0], ones], rows)  # a_x - o_x
    s[tie] = np.where(first != 0, first, second)
    if np.any(s[tie] == 0):
        raise ValueError("the wrap number is undecidable: the interior point is a polygon vertex")
