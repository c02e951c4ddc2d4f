"""Geometry shared by the checks: exact rescaling, Qhull's DISTround, interior points, distances.

Nothing here decides a verdict on its own: exact decisions are made with
:mod:`.predicates`.  The float distances are for *reporting* magnitudes, and
:func:`inner_radius` is a rigorous lower bound used only as a shortcut.
"""

from __future__ import annotations

import math

from dataclasses import dataclass

import numpy as np

from .predicates import filter2, filter3, orient2d_value, orient3d_value
from .rank import witness_simplex

__all__ = [
    "exact_scale",
    "distround",
    "Interior",
    "point_plane_distance",
    "point_line_distance",
    "inner_radius",
    "surface_interior",
    "cross3",
    "triangle_array",
    "vertex_mean",
    "axis_extents",
]

_EPS52 = 2.0**-52  # Qhull's REALepsilon


#: Inputs whose largest magnitude lies in this range are checked unscaled: no product of
#: three coordinate differences can overflow or sink towards the underflow range there.
_UNSCALED_LOW = 2.0**-100
_UNSCALED_HIGH = 2.0**100


def exact_scale(points: np.ndarray, *, top: float | None = None) -> tuple[np.ndarray, int]:
    """Scale by a power of two so the largest magnitude is in [0.5, 1), when needed and exact.

    Every orientation sign is invariant under a positive scaling, so the checks
    run on the scaled copy: the float filter then never overflows and rarely
    meets underflow.  Inputs whose largest magnitude is already within
    ``[2**-100, 2**100]`` are returned as they are (nothing to gain, one pass
    over the points saved).  When the scaling would round a tiny coordinate
    (an input spanning more than ~2000 binades), the points are returned
    unscaled.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64, finite
    top : float or None
        The largest coordinate magnitude, when the caller knows it.

    Returns
    -------
    scaled : ndarray of shape (n, d), float64
    exponent : int
        ``scaled == points * 2**exponent`` exactly.

    Examples
    --------
    >>> s, k = exact_scale(np.array([[1e300, 0.0], [-3e299, 1.0]]))
    >>> k, float(np.abs(s).max()) < 1.0
    (-997, True)
    >>> exact_scale(np.array([[3.0, 4.0]]))[1]
    0
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.size == 0:
        return pts, 0
    if top is None:
        top = float(max(pts.max(), -pts.min()))
    if top == 0.0 or _UNSCALED_LOW <= top <= _UNSCALED_HIGH:
        return pts, 0
    k = -int(np.frexp(top)[1])
    # Two exact power-of-two factors (one could overflow): as exact as ldexp, and much faster.
    scaled = pts * 2.0 ** (k // 2) * 2.0 ** (k - k // 2)
    if k > 0:  # scaling up below 1 never rounds
        return scaled, k
    # Scaling down rounds only values that fall below the normal range.
    low = np.abs(pts[pts != 0]).min()
    if math.ldexp(float(low), k) >= 2.0**-1022 or np.array_equal(np.ldexp(scaled, -k), pts):
        return scaled, k
    return pts, 0


def axis_extents(points: np.ndarray) -> list[float]:
    """The largest coordinate magnitude along each axis (column by column: numpy's axis-0 reduction is slow)."""
    return [float(np.abs(points[:, j]).max()) for j in range(points.shape[1])] if len(points) else []


def distround(points: np.ndarray, *, extents: list[float] | None = None) -> float:
    """Qhull's DISTround for ``points``: the rounding error of a distance computation.

    ``eps * (d * min(sqrt(d) * MAXabs, MAXsumcoord) * 1.01 + MAXabs)`` with
    ``eps = 2**-52``, MAXabs the largest coordinate magnitude and MAXsumcoord
    the sum over axes of each axis's largest magnitude (Qhull 2020.2,
    ``qh_detroundoff``).

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    extents : list of float or None
        :func:`axis_extents` of ``points``, when the caller has them.

    Returns
    -------
    float
        0.0 for an empty input.

    Examples
    --------
    >>> f"{distround(np.array([[0.5, 0.5, 0.5], [-0.5, -0.5, -0.5]])):.3g}"
    '6.94e-16'
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.size == 0:
        return 0.0
    d = pts.shape[1]
    per_axis = axis_extents(pts) if extents is None else extents
    maxabs = max(per_axis)
    # Near the top of the double range the sums overflow; Qhull's formula is
    # linear in the magnitude, so evaluate it on the scaled-down maxima instead.
    k = math.frexp(maxabs)[1] if maxabs > 0 else 0
    axes = [math.ldexp(v, -k) for v in per_axis]
    a, s = max(axes), sum(axes)  # left to right, as numpy sums three values
    unit = _EPS52 * (d * min(math.sqrt(d) * a, s) * 1.01 + a)
    try:
        return math.ldexp(unit, k)
    except OverflowError:
        return math.inf


@dataclass(frozen=True)
class Interior:
    """A point strictly inside the convex hull of the input, kept exact.

    Attributes
    ----------
    simplex : ndarray of shape (d + 1, d), float64
        Affinely independent input points; the interior point is their
        centroid, never rounded (predicates use the ``*_mean`` forms).
    approx : ndarray of shape (d,), float64
        The centroid rounded to float64: a *candidate* float interior point,
        usable as a plain predicate argument only after it has been verified.
    """

    simplex: np.ndarray
    approx: np.ndarray

    @classmethod
    def from_simplex(cls, simplex: np.ndarray) -> "Interior":
        simplex = np.asarray(simplex, dtype=np.float64)
        # A candidate only, but it must be finite: unscaled inputs near 1e308 overflow the sum.
        return cls(simplex, vertex_mean(simplex))

    @property
    def rows(self) -> list[np.ndarray]:
        return list(self.simplex)


def triangle_array(faces) -> np.ndarray | None:
    """The faces as an (m, 3) index array when every face is a triangle, else None.

    For normalised faces (every face at least three vertices, which the
    checker guarantees) that is exactly when there are ``3 m`` indices: one
    length test instead of ``FaceSet.is_triangles``' pass over the sizes.
    """
    if len(faces.indices) == 3 * faces.n_faces:
        return faces.indices.reshape(-1, 3)
    return None


def vertex_mean(corners: np.ndarray) -> np.ndarray:
    """The float mean of a surface's vertices (one formula, so every check picks the same candidate point).

    Always finite and within the vertices' bounding box: near the top of the
    float range the plain sum overflows (an inf "mean" once made the 2D wrap
    number count 0, issue 33 F3), so the vertices are then divided first and
    the result clamped to the box.  It is only a candidate: every use
    verifies it with exact predicates.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        mean = corners.sum(axis=0) / len(corners)
    if np.isfinite(mean).all():
        return mean
    mean = (corners / len(corners)).sum(axis=0)
    return np.clip(mean, corners.min(axis=0), corners.max(axis=0))


def cross3(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise float cross product of (k, 3) arrays (``np.cross`` costs more in set-up than in arithmetic)."""
    out = np.empty((max(len(u), len(v)), 3))
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out


def surface_interior(points: np.ndarray, vertices: np.ndarray) -> Interior | None:
    """The exact centroid of a non-degenerate simplex of a surface's own vertices.

    A closed convex surface has it strictly below every facet (left of every
    edge in 2D); a surface whose vertices are affinely degenerate (flat, or
    collinear in 2D) has none, and cannot be convex.
    """
    dim = points.shape[1]
    if not len(vertices):
        return None
    simplex = vertices[witness_simplex(points[vertices])]
    return Interior.from_simplex(points[simplex]) if len(simplex) == dim + 1 else None


def point_plane_distance(a: np.ndarray, b: np.ndarray, c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Float signed distance of p above the plane of (a, b, c) (positive on the normal's side).

    For reporting magnitudes only; inf or NaN never escape (0 for a degenerate triangle).
    """
    with np.errstate(all="ignore"):
        n = np.cross(np.asarray(b) - a, np.asarray(c) - a)
        norm = np.sqrt(np.einsum("...i,...i->...", n, n))
        dist = -orient3d_value(a, b, c, p) / norm
    return np.nan_to_num(dist, nan=0.0, posinf=0.0, neginf=0.0)


def point_line_distance(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Float signed distance of p to the left of the directed line a -> b (for reporting)."""
    with np.errstate(all="ignore"):
        u = np.asarray(b) - a
        norm = np.sqrt(np.einsum("...i,...i->...", u, u))
        dist = orient2d_value(a, b, p) / norm
    return np.nan_to_num(dist, nan=0.0, posinf=0.0, neginf=0.0)


def inner_radius(planes: list[np.ndarray], center: np.ndarray) -> float:
    """A rigorous lower bound on the distance from ``center`` to the nearest facet plane.

    Parameters
    ----------
    planes : list of ndarray of shape (m, d), float64
        The facets' defining points: ``[a, b, c]`` (3D) or ``[a, b]`` (2D),
        oriented so that ``center`` is below / left of every one.
    center : ndarray of shape (d,), float64

    Returns
    -------
    float
        ``r >= 0`` such that the ball of radius ``r`` around ``center`` lies
        below every plane.  The numerator uses Shewchuk's bound on the
        determinant (doubled), the denominator an upper bound on the normal's
        length (each component's error at most 8 eps of its terms' magnitudes,
        twice the textbook bound), and the result is shrunk by a further 1e-9.
    """
    eps = 2.0**-53
    with np.errstate(all="ignore"):
        if len(planes) == 3:
            a, b, c = planes
            num, num_err, noise = filter3(a, b, c, np.reshape(center, (1, 3)))
            u, v = b - a, c - a
            n = np.cross(u, v)
            terms = np.abs(np.stack([u[:, 1] * v[:, 2], u[:, 2] * v[:, 1], u[:, 2] * v[:, 0], u[:, 0] * v[:, 2], u[:, 0] * v[:, 1], u[:, 1] * v[:, 0]], axis=1))
            err = 8.0 * eps * (terms[:, 0::2] + terms[:, 1::2]) + 2.0**-1000
        else:
            a, b = planes
            num, num_err = filter2(a, b, np.reshape(center, (1, 2)))
            noise = 2.0**-1000
            u = b - a
            n = np.stack([u[:, 1], -u[:, 0]], axis=1)
            err = 2.0 * eps * np.abs(n) + 2.0**-1000
        num_low = num - (num_err * 2.0 + noise)
        up = np.abs(n) + err
        den_up = np.sqrt(np.einsum("ij,ij->i", up, up)) * (1.0 + 1e-12)
        r = num_low / den_up
        if not len(r) or not np.isfinite(r).all():
            return 0.0
        low = float(r.min())
    return max(low * (1.0 - 1e-9), 0.0)
