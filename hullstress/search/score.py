"""The degeneracy score of an input: how close it comes to a degenerate decision, computed exactly.

The search (:mod:`hullstress.search`) keeps an input that raises any part of
this score, in the spirit of Hypothesis's ``target()``: inputs that sit
closer to a degenerate decision are the ones where a float decision of an
algorithm under test can go wrong.  Every part depends on the input alone
(never on an algorithm's output) and only on the *set* of its points: row
order does not change it, and neither does an exact power-of-two scaling
(every part is relative to the coordinates).

``margin_bits``
    The smallest nonzero orientation margin of the hull: over every facet of
    the exact hull (an edge in 2D, a triangle in 3D) and every input point,
    the smallest nonzero ``|orient(facet, point)|`` relative to ``M**d``,
    ``M`` the largest coordinate magnitude, as ``floor(-log2(...))``.  52
    means a decision that depends on about the last bit of the coordinates.
``flat_tuples``
    Exactly coplanar (3D) or collinear (2D) tuples on the hull: summed over
    the facets of a triangulation of the hull of the extreme points, the
    input points exactly on the facet's plane (line) besides its own ``d``
    vertices.  A flat ``k``-gon face of a 3D hull with ``b`` more points on
    it counts ``(k - 2) (k - 3 + b)`` whatever the triangulation.
``duplicates``
    Rows whose coordinates repeat an earlier row's.
``scale_bits``
    ``floor(log2(M / e))``, ``e`` the smallest nonzero extent of the input
    along an axis: large for inputs far from the origin relative to their
    size and for slivers along an axis.

Signs come from the exact predicates of :mod:`hullstress.checker`; the
smallest margin is found with a float value and a rigorous error bound,
then settled with rational arithmetic (:class:`fractions.Fraction`), so the
score is exact.  ``margin_bits`` and ``flat_tuples`` are None when the input
is not full-dimensional or its hull cannot be certified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from ..checker import affine_rank, orient2d, orient3d, qhull_reference
from ..checker.extreme import exact_extreme_2d

__all__ = ["DegeneracyScore", "degeneracy_score", "floor_log2", "SCORE_PARTS"]

#: The parts of a score, in the order they are reported.
SCORE_PARTS = ("margin_bits", "flat_tuples", "duplicates", "scale_bits")

#: Facet x point rows evaluated at once (bounds the memory of one step, whatever n and the facet count).
_CHUNK_ROWS = 1 << 15
#: A bound on the float determinant's relative error, far above Shewchuk's 7 eps of the permanent:
#: a looser bound only sends more rows to the exact evaluation.
_REL_BOUND = 2.0**-40
#: Absolute slack covering products that underflowed.
_ABS_BOUND = 2.0**-900


@dataclass(frozen=True)
class DegeneracyScore:
    """How degenerate an input is; larger is more degenerate in every part (see the module docstring).

    Attributes
    ----------
    margin_bits : int or None
    flat_tuples : int or None
    duplicates : int
    scale_bits : int or None
        None when every point is the same.
    """

    margin_bits: int | None
    flat_tuples: int | None
    duplicates: int
    scale_bits: int | None

    def parts(self) -> dict[str, int]:
        """The parts that have a value, by name."""
        return {name: getattr(self, name) for name in SCORE_PARTS if getattr(self, name) is not None}

    def __str__(self) -> str:
        return " ".join(f"{name}={value}" for name, value in self.parts().items())


def floor_log2(value: Fraction) -> int:
    """``floor(log2(value))`` of a positive rational, exactly.

    Examples
    --------
    >>> floor_log2(Fraction(1)), floor_log2(Fraction(3, 1)), floor_log2(Fraction(1, 3)), floor_log2(Fraction(1, 4))
    (0, 1, -2, -2)
    """
    if value <= 0:
        raise ValueError(f"floor_log2 needs a positive value, got {value}")
    p, q = value.numerator, value.denominator
    k = p.bit_length() - q.bit_length()
    # 2**k <= p/q < 2**(k+1) after at most one correction.
    if k >= 0:
        return k if p >= q << k else k - 1
    return k if p << -k >= q else k - 1


def _exact_det(rows: list[list[float]]) -> Fraction:
    """The orientation determinant of d+1 points (rows of d floats), in rational arithmetic."""
    q = [[Fraction(x) for x in r] for r in rows]
    last = q[-1]
    m = [[a - b for a, b in zip(r, last)] for r in q[:-1]]
    if len(m) == 2:
        return m[0][0] * m[1][1] - m[0][1] * m[1][0]
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _float_det_and_bound(corners: list[np.ndarray], pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Float orientation determinants of each facet (rows of ``corners``) with each point, and an error bound.

    Returns arrays of shape (facets, points).  Non-finite values (overflow)
    get an infinite bound, which sends them to the exact evaluation.
    """
    with np.errstate(all="ignore"):
        diffs = [c[:, None, :] - pts[None, :, :] for c in corners]
        if len(corners) == 2:
            (ax, ay), (bx, by) = ((d[..., 0], d[..., 1]) for d in diffs)
            left, right = ax * by, ay * bx
            det, perm = left - right, np.abs(left) + np.abs(right)
        else:
            (ax, ay, az), (bx, by, bz), (cx, cy, cz) = ((d[..., 0], d[..., 1], d[..., 2]) for d in diffs)
            t1, t2 = bx * cy, cx * by
            t3, t4 = cx * ay, ax * cy
            t5, t6 = ax * by, bx * ay
            det = az * (t1 - t2) + bz * (t3 - t4) + cz * (t5 - t6)
            perm = (np.abs(az) * (np.abs(t1) + np.abs(t2)) + np.abs(bz) * (np.abs(t3) + np.abs(t4))
                    + np.abs(cz) * (np.abs(t5) + np.abs(t6)))
        bound = _REL_BOUND * perm + _ABS_BOUND
        bad = ~(np.isfinite(det) & np.isfinite(bound))
        bound[bad] = np.inf
        det[bad] = 0.0
    return det, bound


def _hull_facets(distinct: np.ndarray, dim: int) -> np.ndarray | None:
    """Facets (index tuples into ``distinct``) of a triangulation of the hull of its extreme points, or None.

    2D: the edges of the exact extreme cycle.  3D: Qhull's triangulation of the
    exact extreme points; it is accepted only after the exact checks in
    :func:`degeneracy_score` (every point on one side of each facet, no flat
    facet, ``2 h - 4`` triangles using every extreme point).
    """
    if dim == 2:
        cycle = exact_extreme_2d(distinct)
        if len(cycle) < 3:
            return None
        return np.stack([cycle, np.roll(cycle, -1)], axis=1)
    ref = qhull_reference(distinct)
    extreme = ref.extreme
    if extreme is None or len(extreme) < 4:
        return None
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(distinct[extreme], qhull_options="Qt")
    except (QhullError, ValueError):
        return None
    tri = extreme[np.asarray(hull.simplices, dtype=np.int64)]
    if len(tri) != 2 * len(extreme) - 4 or len(np.unique(tri)) != len(extreme):
        return None
    return tri


def _distinct_rows(pts: np.ndarray) -> np.ndarray:
    """One row per distinct coordinate tuple, in lexicographic order (so the result ignores row order)."""
    return np.unique(pts + 0.0, axis=0)  # + 0.0 folds -0.0 into 0.0


def degeneracy_score(points: Any) -> DegeneracyScore:
    """The exact degeneracy score of an input (see the module docstring for each part).

    Parameters
    ----------
    points : array_like of shape (n, 2) or (n, 3), finite float64

    Returns
    -------
    DegeneracyScore

    Raises
    ------
    ValueError
        When ``points`` is not an (n, 2) or (n, 3) array of finite numbers with n >= 1.

    Examples
    --------
    A square with a point on one edge and a duplicated corner: one collinear
    tuple, one duplicate, and a margin of ``0.5**2 / 1**2`` (a quarter: 2 bits):

    >>> s = degeneracy_score([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0], [0, 0], [0.5, 0.5]])
    >>> s.flat_tuples, s.duplicates, s.margin_bits, s.scale_bits
    (1, 1, 1, 0)
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3) or len(pts) < 1:
        raise ValueError(f"points must have shape (n, 2) or (n, 3) with n >= 1, got {pts.shape}")
    if not np.isfinite(pts).all():
        raise ValueError("points must be finite, got NaN or infinity")
    dim = pts.shape[1]
    distinct = _distinct_rows(pts)
    duplicates = len(pts) - len(distinct)
    top = float(np.abs(pts).max())
    extents = [Fraction(float(distinct[:, k].max())) - Fraction(float(distinct[:, k].min())) for k in range(dim)]
    nonzero = [e for e in extents if e > 0]
    scale_bits = floor_log2(Fraction(top) / min(nonzero)) if nonzero else None
    if affine_rank(distinct) < dim:
        return DegeneracyScore(None, None, duplicates, scale_bits)
    facets = _hull_facets(distinct, dim)
    if facets is None:
        return DegeneracyScore(None, None, duplicates, scale_bits)
    margin, flat = _margin_and_flat(distinct, facets, dim)
    if margin is None or flat is None:
        return DegeneracyScore(None, None, duplicates, scale_bits)
    margin_bits = floor_log2(Fraction(top) ** dim / margin) if margin > 0 else None
    return DegeneracyScore(margin_bits, flat, duplicates, scale_bits)


def _margin_and_flat(distinct: np.ndarray, facets: np.ndarray, dim: int) -> tuple[Fraction | None, int | None]:
    """The smallest nonzero |orientation| over facets x points (0 when none) and the flat count; (None, None) when a facet is not supporting."""
    orient = orient2d if dim == 2 else orient3d
    n = len(distinct)
    per_chunk = max(1, _CHUNK_ROWS // n)
    flat = 0
    best_upper = math.inf
    candidates: list[tuple[float, int, int]] = []  # (lower bound, facet, point) that may hold the minimum
    for start in range(0, len(facets), per_chunk):
        chunk = facets[start:start + per_chunk]
        rows = np.repeat(np.arange(len(chunk)), n)
        cols = np.tile(np.arange(n), len(chunk))
        corners = [distinct[chunk[rows, k]] for k in range(dim)]
        signs = orient(*corners, distinct[cols]).reshape(len(chunk), n)
        if ((signs > 0).any(axis=1) & (signs < 0).any(axis=1)).any():
            return None, None  # points on both sides: not a facet of the hull
        on = (signs == 0).sum(axis=1)
        if (on == n).any():
            return None, None  # a flat facet
        flat += int((on - dim).sum())
        det, bound = _float_det_and_bound([distinct[chunk[:, k]] for k in range(dim)], distinct)
        lower = np.where(signs != 0, np.abs(det) - bound, np.inf)
        upper = np.where(signs != 0, np.abs(det) + bound, np.inf)
        best_upper = min(best_upper, float(upper.min()))
        f_idx, p_idx = np.nonzero(lower <= best_upper)
        candidates.extend(zip(lower[f_idx, p_idx].tolist(), (f_idx + start).tolist(), p_idx.tolist()))
    if not math.isfinite(best_upper):
        return Fraction(0), flat  # every point on every facet's plane cannot happen for a full-dimensional set
    best: Fraction | None = None
    for _, f, p in (c for c in candidates if c[0] <= best_upper):
        rows = [distinct[i].tolist() for i in facets[f]] + [distinct[p].tolist()]
        value = abs(_exact_det(rows))
        if value and (best is None or value < best):
            best = value
    return (best if best is not None else Fraction(0)), flat
