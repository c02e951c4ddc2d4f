"""Shared helpers for the generator families.

Argument checks with one-line messages, exact lattice builders, random
rotations, ulp arithmetic on float64 bit patterns, power-of-two rescaling and
exact (filtered, then rational) orientation signs.  Everything here is
vectorised; the only randomness is the ``numpy.random.Generator`` passed in.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import numpy as np


__all__ = [
    "GeneratorValueError",
    "check_dim",
    "check_n",
    "check_choice",
    "check_positive",
    "check_int",
    "check_bool",
    "declare_min_size",
    "MIN_SIZE_RULES",
    "finish",
    "random_rotation",
    "row_dot",
    "apply_matrix",
    "combine",
    "row_norms",
    "lattice",
    "lattice_side",
    "pow2_at_least",
    "fit_unit_pow2",
    "ulp_shift",
    "ulp_distance",
    "random_ulp_offsets",
    "uniform_ball",
    "on_sphere",
    "cube_surface",
    "box_points",
    "sector_polygon",
    "orient_sign",
    "orient_exact",
    "affine_rank_exact",
    "round_to_float32",
]

_F64 = np.float64
_INT64_MIN = np.int64(np.iinfo(np.int64).min)
#: Ordered-integer image of +inf; anything beyond it is NaN territory.
_ORDERED_INF = np.int64(np.array(np.inf).view(np.int64))


# Defined with the rest of the exception tree; re-exported here for the families.
from hullstress.errors import GeneratorValueError  # noqa: E402,F401


# ---------------------------------------------------------------------------
# argument checks


def check_dim(family: str, dim: Any, dims: Sequence[int]) -> int:
    """Return ``dim`` as int or raise naming the family and the valid dims."""
    if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or int(dim) not in dims:
        raise GeneratorValueError(f"{family}: dim must be one of {tuple(dims)}, got {dim!r}")
    return int(dim)


def check_n(family: str, n: Any, minimum: int = 1, why: str = "") -> int:
    """Return ``n`` as int or raise ``n must be an integer >= minimum``."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or int(n) < minimum:
        reason = f" ({why})" if why else ""
        raise GeneratorValueError(f"{family}: n must be an integer >= {minimum}{reason}, got {n!r}")
    return int(n)


def check_choice(family: str, name: str, value: Any, choices: Sequence[Any]) -> Any:
    """Return ``value`` if it is one of ``choices``, else raise naming the parameter."""
    if value not in choices:
        raise GeneratorValueError(
            f"{family}: {name} must be one of {', '.join(repr(c) for c in choices)}, got {value!r}"
        )
    return value


def check_positive(family: str, name: str, value: Any, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a finite float > 0 (or >= 0), else raise."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    ok = math.isfinite(v) and (v >= 0 if allow_zero else v > 0)
    if isinstance(value, bool) or not ok:
        what = "a finite float >= 0" if allow_zero else "a finite float > 0"
        raise GeneratorValueError(f"{family}: {name} must be {what}, got {value!r}")
    return v


def check_int(family: str, name: str, value: Any, lo: int, hi: int | None = None) -> int:
    """Return ``value`` as an int in ``[lo, hi]``, else raise."""
    ok = not isinstance(value, bool) and isinstance(value, (int, np.integer))
    if ok:
        ok = int(value) >= lo and (hi is None or int(value) <= hi)
    if not ok:
        rng = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise GeneratorValueError(f"{family}: {name} must be an integer {rng}, got {value!r}")
    return int(value)


def check_bool(family: str, name: str, value: Any) -> bool:
    """Return ``value`` if it is a bool (numpy's included), else raise naming the parameter."""
    if not isinstance(value, (bool, np.bool_)):
        raise GeneratorValueError(f"{family}: {name} must be True or False, got {value!r}")
    return bool(value)


#: family name -> rule(dim, **params) -> smallest n the family accepts.
MIN_SIZE_RULES: dict[str, Callable[..., int]] = {}


def declare_min_size(family: str, rule: Callable[..., int]) -> None:
    """Record the smallest ``n`` a family accepts (read by :func:`generators.min_size`)."""
    MIN_SIZE_RULES[family] = rule


def finish(points: np.ndarray) -> np.ndarray:
    """Return ``points`` as a fresh C-contiguous float64 array (the output contract)."""
    return np.ascontiguousarray(points, dtype=_F64).copy()


# ---------------------------------------------------------------------------
# geometry builders


def random_rotation(rng: np.random.Generator, dim: int) -> np.ndarray:
    """A random proper rotation matrix of shape (dim, dim), uniformly (Haar) distributed.

    2D: the normalised Gaussian pair (cos, sin); 3D: the matrix of a
    normalised Gaussian unit quaternion.  Only +, *, / and sqrt are used (no
    LAPACK, no trigonometry), so the bytes do not depend on the BLAS build.
    """
    g = [float(x) for x in rng.standard_normal(2 if dim == 2 else 4)]
    norm = math.sqrt(sum(x * x for x in g)) or 1.0
    g = [x / norm for x in g]
    if dim == 2:
        c, s = g
        return np.array([[c, -s], [s, c]])
    w, x, y, z = g
    return np.array(
        [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
            [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
            [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
        ]
    )


def row_dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot products ``a @ b`` for a of shape (n, d) and b of shape (d,), left to right.

    Written with elementwise ufuncs instead of BLAS so that the rounding (and
    hence the generated bytes) does not depend on the BLAS build, its kernels
    or its thread count.
    """
    out = a[:, 0] * b[0]
    for k in range(1, a.shape[1]):
        out = out + a[:, k] * b[k]
    return out


def apply_matrix(points: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """``points @ matrix.T`` without BLAS (see :func:`row_dot`)."""
    return np.column_stack([row_dot(points, matrix[j]) for j in range(matrix.shape[0])])


def combine(weights: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Weighted sums of vertices, left to right, without BLAS.

    ``weights`` (n, k) with ``verts`` (k, d) gives ``weights @ verts``; with
    ``verts`` (n, k, d) row i uses its own vertices ``verts[i]``.
    """
    per_row = verts.ndim == 3
    out = weights[:, :1] * (verts[:, 0, :] if per_row else verts[0])
    for i in range(1, weights.shape[1]):
        out = out + weights[:, i : i + 1] * (verts[:, i, :] if per_row else verts[i])
    return out


def row_norms(x: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of x, summed left to right (no BLAS)."""
    return np.sqrt(row_dot(x * x, np.ones(x.shape[1])))


def lattice_side(n: int, dim: int) -> int:
    """Smallest integer side s with s**dim >= n (exact, no float roots)."""
    s = max(1, int(round(n ** (1.0 / dim))))
    while s**dim < n:
        s += 1
    while s > 1 and (s - 1) ** dim >= n:
        s -= 1
    return s


def lattice(side: int, dim: int) -> np.ndarray:
    """All points of ``{0..side-1}**dim`` as int64 rows, last axis fastest."""
    grids = np.indices((side,) * dim).reshape(dim, -1).T
    return np.ascontiguousarray(grids, dtype=np.int64)


def pow2_at_least(x: float) -> float:
    """The smallest power of two >= x (x > 0), as a float."""
    m, e = math.frexp(x)  # x = m * 2**e, 0.5 <= m < 1
    return math.ldexp(1.0, e - 1) if m == 0.5 else math.ldexp(1.0, e)


def fit_unit_pow2(points: np.ndarray) -> np.ndarray:
    """Scale by a power of two (exactly) so that max |coordinate| lies in (1/2, 1]."""
    peak = float(np.max(np.abs(points))) if points.size else 0.0
    if peak == 0.0:
        return points.astype(_F64)
    return points.astype(_F64) / pow2_at_least(peak)


def uniform_ball(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """n points uniform in the unit ball (direction from a Gaussian, radius u**(1/dim))."""
    g = rng.standard_normal((n, dim))
    norm = row_norms(g)[:, None]
    norm[norm == 0] = 1.0  # probability zero, but never divide by zero
    r = rng.random((n, 1)) ** (1.0 / dim)
    return g / norm * r


def on_sphere(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """n points on the unit sphere (normalised Gaussians; |p| = 1 within a few ulps)."""
    g = rng.standard_normal((n, dim))
    norm = row_norms(g)[:, None]
    g[norm[:, 0] == 0] = 1.0
    norm[norm == 0] = math.sqrt(dim)
    return g / norm


def cube_surface(rng: np.random.Generator, n: int, dim: int, width: float = 0.0) -> np.ndarray:
    """rbox ``W<width>``: points of [-1, 1]**dim pushed to within ``width`` of a face.

    One random axis j per point becomes ``±(1 - |u_j| * width)`` (sign of the
    original coordinate), exactly ``±1`` when ``width == 0`` (rbox ``W0``).
    """
    pts = rng.uniform(-1.0, 1.0, (n, dim))
    axis = rng.integers(0, dim, n)
    rows = np.arange(n)
    u = pts[rows, axis]
    sign = np.where(u < 0, -1.0, 1.0)
    pts[rows, axis] = sign * (1.0 - np.abs(u) * width)
    return pts


def box_points(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """The 2**dim corners of [-1, 1]**dim, then n - 2**dim points exactly on its faces (rbox W0)."""
    corners = (lattice(2, dim) * 2 - 1).astype(_F64)
    return np.concatenate([corners, cube_surface(rng, n - len(corners), dim, 0.0)])


def sector_polygon(rng: np.random.Generator, k: int, *, wobble: bool) -> np.ndarray:
    """k points around the origin, counter-clockwise, one per sector of angle 2 pi / k.

    Each angle lies in the middle 40% of its sector, so consecutive points
    turn by less than pi and the origin is strictly inside the polygon.
    Radius 1 (cocircular up to rounding), or uniform in [0.5, 1] with
    ``wobble`` (a star-shaped, usually non-convex polygon).
    """
    angles = 2.0 * math.pi * (np.arange(k) + rng.uniform(0.3, 0.7, k)) / k
    r = rng.uniform(0.5, 1.0, k) if wobble else np.ones(k)
    return np.column_stack([r * np.cos(angles), r * np.sin(angles)])


# ---------------------------------------------------------------------------
# ulp arithmetic on the ordered integer image of float64


def _ordered(x: np.ndarray) -> np.ndarray:
    """Map float64 to int64 so that consecutive doubles map to consecutive integers."""
    a = np.array(x, dtype=_F64, ndmin=1)  # a fresh contiguous copy, at least 1-D
    i = a.view(np.int64)
    # Negative doubles have the sign bit set, i = INT64_MIN + magnitude; mirror
    # them to -magnitude so that -0.0 and +0.0 both map to 0 and order holds.
    # Only the negative entries are touched: INT64_MIN - i cannot overflow there.
    neg = i < 0
    i[neg] = _INT64_MIN - i[neg]
    return i.reshape(np.shape(x))


def _from_ordered(o: np.ndarray) -> np.ndarray:
    bits = np.array(o, dtype=np.int64, ndmin=1)
    neg = bits < 0
    bits[neg] = _INT64_MIN - bits[neg]
    return bits.view(_F64).reshape(np.shape(o))


def ulp_shift(x: np.ndarray | float, k: np.ndarray | int) -> np.ndarray:
    """Move each float64 in ``x`` by ``k`` representable steps (k < 0: downwards).

    Equivalent to applying ``math.nextafter`` |k| times, vectorised.  Crossing
    zero is allowed (-0.0 and +0.0 count as one value); reaching inf raises.

    Examples
    --------
    >>> float(ulp_shift(1.0, 1)) == math.nextafter(1.0, 2.0)
    True
    >>> float(ulp_shift(0.0, -1))
    -5e-324
    """
    xa = np.asarray(x, dtype=_F64)
    if not np.all(np.isfinite(xa)):
        raise GeneratorValueError("ulp_shift: x must be finite, got a NaN or infinity")
    ka = np.asarray(k, dtype=np.int64)
    o = _ordered(xa) + ka
    if np.any(np.abs(o) >= _ORDERED_INF):
        raise GeneratorValueError("ulp_shift: shift overflows to infinity")
    # k == 0 returns x itself (keeps the sign of -0.0, which the map folds into +0.0).
    return np.where(ka == 0, xa, _from_ordered(o))


def ulp_distance(a: np.ndarray | float, b: np.ndarray | float) -> np.ndarray:
    """Signed number of representable doubles from ``a`` to ``b`` (int64, elementwise)."""
    return _ordered(np.asarray(b, dtype=_F64)) - _ordered(np.asarray(a, dtype=_F64))


def random_ulp_offsets(
    rng: np.random.Generator, shape: tuple[int, ...], ulps: int, *, nonzero_rows: bool
) -> np.ndarray:
    """Integer offsets in [-ulps, ulps]; with ``nonzero_rows`` no row is all zero."""
    k = rng.integers(-ulps, ulps + 1, shape, dtype=np.int64)
    if nonzero_rows and ulps > 0 and len(shape) == 2 and shape[0] > 0:
        zero = ~k.any(axis=1)
        # A row that drew no offset gets +1 ulp on a random axis: still within
        # ``ulps`` and guaranteed distinct from its source.
        axis = rng.integers(0, shape[1], shape[0])
        k[zero, axis[zero]] = 1
    return k


_F32_MAX = float(np.finfo(np.float32).max)


def round_to_float32(points: np.ndarray, family: str = "float32") -> np.ndarray:
    """Round every coordinate to the nearest float32 (ties to even) and return it as float64.

    This is what happens to data that passes through a C/C++/Rust ``float``:
    the result holds only values exactly representable in float32 (24
    significant bits, spacing 2**-23 relative), so ``x == float(np.float32(x))``
    for every entry.  Finite values beyond float32's range raise instead of
    silently becoming infinities.

    Examples
    --------
    >>> round_to_float32(np.array([[0.1, 1.0]])).tolist()
    [[0.10000000149011612, 1.0]]
    """
    p = np.asarray(points, dtype=_F64)
    if p.size and float(np.max(np.abs(p))) > _F32_MAX:
        raise GeneratorValueError(
            f"{family}: coordinates up to {float(np.max(np.abs(p))):.3g} overflow float32 (max {_F32_MAX:.4g})"
        )
    return p.astype(np.float32).astype(_F64)


# ---------------------------------------------------------------------------
# exact orientation (used to certify interior points and by the tests)

_EPS = 2.0**-53  # unit roundoff
# Shewchuk's static bounds (ccwerrboundA, o3derrboundA): they cover the
# rounding of the coordinate differences as well as of the products.
_BOUND = {2: (3.0 + 16.0 * _EPS) * _EPS, 3: (7.0 + 56.0 * _EPS) * _EPS}
_TINY = 2.0**-900  # below this the products may have underflowed: go exact


def orient_exact(rows: Sequence[Sequence[float]]) -> int:
    """Exact sign of det[p1 - p0, ..., pd - p0] for d+1 points of dimension d.

    Uses :class:`fractions.Fraction`, so it is exact for any finite doubles.

    Examples
    --------
    >>> orient_exact([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])
    1
    >>> orient_exact([(0.5, 0.5), (12.0, 12.0), (24.0, 24.0)])  # Kettner's collinear triple
    0
    """
    pts = [[Fraction(float(c)) for c in p] for p in rows]
    d = len(pts) - 1
    m = [[pts[i + 1][j] - pts[0][j] for j in range(d)] for i in range(d)]
    if d == 2:
        det = m[0][0] * m[1][1] - m[0][1] * m[1][0]
    elif d == 3:
        det = (
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        )
    elif d == 1:
        det = m[0][0]
    else:
        raise GeneratorValueError(f"orient_exact: need 2, 3 or 4 points of matching dimension, got {len(pts)}")
    return (det > 0) - (det < 0)


def affine_rank_exact(rows: Sequence[Sequence[float]]) -> int:
    """Exact affine rank of a few points (-1 for none, 0 for one distinct point, 1 collinear...).

    Rational Gaussian elimination on the differences to the first point;
    meant for the handful of points of a small case, not for clouds.

    Examples
    --------
    >>> affine_rank_exact([(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)])
    1
    >>> affine_rank_exact([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1e-300)])
    3
    """
    pts = [[Fraction(float(c)) for c in p] for p in rows]
    if not pts:
        return -1
    mat = [[a - b for a, b in zip(p, pts[0])] for p in pts[1:]]
    rank = 0
    for col in range(len(pts[0])):
        pivot = next((i for i in range(rank, len(mat)) if mat[i][col] != 0), None)
        if pivot is None:
            continue
        mat[rank], mat[pivot] = mat[pivot], mat[rank]
        for i in range(rank + 1, len(mat)):
            f = mat[i][col] / mat[rank][col]
            if f:
                mat[i] = [a - f * b for a, b in zip(mat[i], mat[rank])]
        rank += 1
    return rank


def orient_sign(simplices: np.ndarray) -> np.ndarray:
    """Exact orientation signs of many simplices, shape (m, d+1, d) -> (m,) int8.

    A floating-point filter with Shewchuk's static error bound decides most
    signs; the rest (and anything that overflowed or may have underflowed)
    are decided exactly by :func:`orient_exact`.
    """
    s = np.asarray(simplices, dtype=_F64)
    m, k, d = s.shape
    if k != d + 1 or d not in (2, 3):
        raise GeneratorValueError(f"orient_sign: simplices must have shape (m, d+1, d) with d in (2, 3), got {s.shape}")
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        v = s[:, 1:, :] - s[:, :1, :]
        if d == 2:
            t1 = v[:, 0, 0] * v[:, 1, 1]
            t2 = v[:, 0, 1] * v[:, 1, 0]
            det = t1 - t2
            perm = np.abs(t1) + np.abs(t2)
        else:
            c0 = v[:, 1, 1] * v[:, 2, 2] - v[:, 1, 2] * v[:, 2, 1]
            c1 = v[:, 1, 0] * v[:, 2, 2] - v[:, 1, 2] * v[:, 2, 0]
            c2 = v[:, 1, 0] * v[:, 2, 1] - v[:, 1, 1] * v[:, 2, 0]
            det = v[:, 0, 0] * c0 - v[:, 0, 1] * c1 + v[:, 0, 2] * c2
            p0 = np.abs(v[:, 1, 1] * v[:, 2, 2]) + np.abs(v[:, 1, 2] * v[:, 2, 1])
            p1 = np.abs(v[:, 1, 0] * v[:, 2, 2]) + np.abs(v[:, 1, 2] * v[:, 2, 0])
            p2 = np.abs(v[:, 1, 0] * v[:, 2, 1]) + np.abs(v[:, 1, 1] * v[:, 2, 0])
            perm = np.abs(v[:, 0, 0]) * p0 + np.abs(v[:, 0, 1]) * p1 + np.abs(v[:, 0, 2]) * p2
        bound = _BOUND[d] * perm
        sure = np.isfinite(det) & np.isfinite(perm) & (perm > _TINY) & (np.abs(det) > bound)
    out = np.where(sure, np.sign(det), 0).astype(np.int8)
    for i in np.flatnonzero(~sure):
        out[i] = orient_exact(s[i])
    return out
