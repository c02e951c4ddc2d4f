"""Volume (area in 2D) of a checked surface: independent of face order, exact where it matters.

The signed volume of a 3D surface is the sum over its faces of
``orient3d(a, b, c, r) / 6``, each face fanned from its lowest vertex index
and ``r`` the surface's lowest-index vertex; in 2D the area is the sum over
edges of ``orient2d(a, b, r) / 2``.  Each determinant is evaluated with a
face vertex as the point subtracted (``orient3d(r, b, a, c)``, the same
value), so its error bound is proportional to the face's size: the float
sum of a hull of thousands of small faces stays within ~1e-15 of exact.  Two numbers come out of it:

* an **estimate**: ``math.fsum`` of the per-face float determinants.  fsum
  rounds the exact sum of its terms once, so the estimate depends on neither
  the order of the faces nor the vertex a face is listed from (the fan and
  ``r`` are fixed by the indices alone).  A rigorous error bound (Shewchuk's
  per-determinant bound, summed) comes with it;
* the **exact value**, a :class:`fractions.Fraction` from integer arithmetic
  on the mantissas, computed only when asked: when the estimate cannot decide
  a comparison (thin hulls, where every determinant is mostly rounding
  error), or when the float sum overflows (mixed magnitudes, where fsum
  raises).

So a comparison of two volumes (:func:`compare`) is exact, and the recorded
volume (:meth:`Measure.value`) is a function of the face set alone.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..contract import FaceSet
from ._geometry import cross3, triangle_array
from .predicates import exact_det_sum, float_det_sum, sum_with_bound

__all__ = ["Measure", "surface_measure", "surface_area", "compare", "rotated_to_lowest", "triangle_keys", "canonical_triangles", "to_float", "measure_rows"]

#: The recorded value is the float estimate when its error bound is this small relative to it.
_ACCURATE = 2.0**-44


def triangle_keys(tri: np.ndarray, n: int) -> np.ndarray:
    """One integer per oriented triangle, the same for its three rotations: ``(a n + b) n + c``
    of the lexicographically smallest rotation ``(a, b, c)``.  ``n`` exceeds every index
    and ``n**3 < 2**63``."""
    a, b, c = tri.T
    return np.minimum(np.minimum((a * n + b) * n + c, (b * n + c) * n + a), (c * n + a) * n + b)


def canonical_triangles(tri: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Triangles rotated to their smallest rotation, and their keys (:func:`triangle_keys`), in one pass."""
    key = triangle_keys(tri, n)
    out = np.empty_like(tri)
    out[:, 0], rest = np.divmod(key, n * n)
    out[:, 1], out[:, 2] = np.divmod(rest, n)
    return out, key


def rotated_to_lowest(faces: FaceSet) -> FaceSet:
    """Each face's cycle rotated to start at its lowest vertex index (orientation kept).

    ``faces`` must be normalised (every face at least three vertices).  A
    face that repeats its lowest index (a degenerate one) starts at the
    occurrence giving the smallest sequence (triangles) or at the first
    (larger polygons): either way a function of the face, not of how it was
    listed.

    Examples
    --------
    >>> rotated_to_lowest(FaceSet.from_polygons([[5, 2, 7], [9, 8, 3, 4]])).to_python()
    [[2, 7, 5], [3, 4, 9, 8]]
    """
    idx = faces.indices
    if not len(idx):
        return faces
    tri = triangle_array(faces)
    if tri is not None:
        a, b, c = tri.T
        if (a < b).all() and (a < c).all():  # already so (Qhull's faces are stored that way)
            return faces
        n = int(idx.max()) + 1
        if n < 2**21:
            out, _ = canonical_triangles(tri, n)
        else:
            from_b = (b < a) & (b <= c)
            from_c = (c <= a) & (c < b)  # (X, Y, X) starts at its second X: (X, X, Y) is the smallest
            out = tri.copy()
            out[from_b] = tri[from_b][:, [1, 2, 0]]
            out[from_c] = tri[from_c][:, [2, 0, 1]]
        return FaceSet(out.ravel(), faces.offsets)
    sizes = faces.sizes
    starts = faces.offsets[:-1]
    base = np.repeat(starts, sizes)
    within = np.arange(len(idx)) - base
    lowest = np.repeat(np.minimum.reduceat(idx, starts), sizes)
    # The first position of each face's lowest index (a face may repeat it).
    shift = np.minimum.reduceat(np.where(idx == lowest, within, len(idx)), starts)
    rotated = idx[base + (within + np.repeat(shift, sizes)) % np.repeat(sizes, sizes)]
    return FaceSet(rotated, faces.offsets)


class Measure:
    """The signed volume (area in 2D) of one surface: a float estimate, its error bound, the exact value.

    Attributes
    ----------
    dim : int
    estimate : float
        Sum of the float determinants (``nan`` when it overflows), *not*
        divided by ``dim!``: see :meth:`value`.
    error : float
        ``|exact sum - estimate| <= error`` (``inf`` when unknown).
    """

    __slots__ = ("dim", "estimate", "error", "_rows", "_exact")

    def __init__(self, dim: int, rows: list[np.ndarray], filtered: tuple[np.ndarray, np.ndarray] | None = None):
        """``rows``: the determinants' point arguments; ``filtered``: their float values and bounds, if known."""
        self.dim = dim
        self._rows = rows
        self._exact: Fraction | None = None
        if not len(rows[0]):
            self.estimate, self.error = 0.0, 0.0
        elif filtered is not None:
            self.estimate, self.error = sum_with_bound(*filtered)
        else:
            self.estimate, self.error = float_det_sum(dim, rows)

    @property
    def denominator(self) -> int:
        """``dim!``: the determinant sum over this is the volume (area)."""
        return 6 if self.dim == 3 else 2

    def exact_sum(self) -> Fraction:
        """The exact sum of the determinants (computed once, in integers)."""
        if self._exact is None:
            self._exact = exact_det_sum(self.dim, self._rows) if len(self._rows[0]) else Fraction(0)
        return self._exact

    @property
    def sign(self) -> int:
        """Exact sign of the volume (area)."""
        if abs(self.estimate) > self.error:  # false for nan
            return 1 if self.estimate > 0 else -1
        exact = self.exact_sum()
        return (exact > 0) - (exact < 0)

    def value(self) -> float:
        """The volume (area) as a float: the estimate where it is accurate, else the exact value rounded.

        Either way a function of the face set only (never of face order);
        ``inf`` when the volume is beyond the double range.
        """
        if self.error <= _ACCURATE * abs(self.estimate):
            return self.estimate / self.denominator
        return to_float(self.exact_sum() / self.denominator)


def to_float(x: Fraction) -> float:
    """``x`` rounded to the nearest double, +-inf beyond the double range."""
    try:
        return float(x)
    except OverflowError:
        return math.inf if x > 0 else -math.inf


def measure_rows(points: np.ndarray, faces: FaceSet) -> list[np.ndarray]:
    """The orient3d arguments whose sum is six times the volume of a 3D surface (see the module docstring)."""
    lowest = rotated_to_lowest(faces)
    tri = triangle_array(lowest)
    if tri is None:
        tri = lowest.fan_triangles()[0]
    if not len(tri):
        return [np.zeros((0, 3))] * 4
    r = points[faces.indices.min()]
    # orient3d(r, b, a, c) = orient3d(a, b, c, r), with a face vertex as the point subtracted:
    # the error bound then scales with the face's size, not with its distance from r.
    return [r, points[tri[:, 1]], points[tri[:, 0]], points[tri[:, 2]]]


def surface_measure(points: np.ndarray, faces: np.ndarray | FaceSet) -> Measure:
    """The :class:`Measure` of a polygon (2D vertex cycle) or a FaceSet (3D).

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    faces : ndarray of shape (k,), int64 (2D) or FaceSet (3D)

    Examples
    --------
    >>> sq = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    >>> surface_measure(sq, np.array([2, 3, 0, 1])).value()
    1.0
    """
    dim = points.shape[1]
    if dim == 2:
        poly = np.asarray(faces, dtype=np.int64)
        if len(poly) < 3:
            return Measure(2, [np.zeros((0, 2))] * 3)
        r = points[poly.min()]
        # orient2d(r, a, b) = orient2d(a, b, r), with an edge's end point subtracted (see measure_rows).
        return Measure(2, [r, points[poly], points[np.roll(poly, -1)]])
    return Measure(3, measure_rows(points, faces))


def surface_area(points: np.ndarray, faces: np.ndarray | FaceSet) -> float:
    """Float surface area (perimeter in 2D), summed with fsum: independent of face order.

    For tolerances and reporting only (inf where it overflows).
    """
    with np.errstate(all="ignore"):
        if points.shape[1] == 2:
            poly = np.asarray(faces)
            parts = np.linalg.norm(points[np.roll(poly, -1)] - points[poly], axis=1)
        else:
            lowest = rotated_to_lowest(faces)
            tri = triangle_array(lowest)
            if tri is None:
                tri = lowest.fan_triangles()[0]
            a = points[tri[:, 0]]
            n = cross3(points[tri[:, 1]] - a, points[tri[:, 2]] - a)
            parts = np.sqrt(np.einsum("ij,ij->i", n, n)) / 2.0
    if not np.isfinite(parts).all():
        return math.inf
    try:
        return math.fsum(parts.tolist())
    except OverflowError:
        return math.inf


def compare(a: Measure, b: Measure, tol: Fraction | float) -> tuple[bool, Fraction]:
    """Exactly whether ``|volume(a) - volume(b)| <= tol``, and that difference.

    The float estimates decide when their error bounds show the difference
    within ``tol``; otherwise the exact values decide, and the returned
    difference is then exact, so a severity graded from it does not depend on
    rounding either.

    Examples
    --------
    >>> sq = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
    >>> compare(surface_measure(sq, np.arange(4)), surface_measure(sq, np.array([0, 1, 4])), 0.1)
    (False, Fraction(3, 4))
    """
    den = a.denominator
    tol = Fraction(tol)
    with np.errstate(all="ignore"):
        diff = a.estimate - b.estimate
        bound = (a.error + b.error) * (1.0 + 2.0**-30) + 2.0**-52 * abs(diff)
        if math.isfinite(diff) and math.isfinite(bound) and abs(diff) + bound < to_float(tol) * den * (1.0 - 2.0**-50):
            return True, Fraction(abs(diff)) / den
    exact = abs(a.exact_sum() - b.exact_sum()) / den
    return exact <= tol, exact
