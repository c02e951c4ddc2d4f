"""Exact orientation predicates, vectorised over numpy arrays.

Every function here returns the *exact* sign of a polynomial in float64
inputs, for every finite input (huge, tiny and subnormal included).  Each call
runs four stages on the rows still undecided:

1. **Floating-point filter** (Shewchuk, "Adaptive precision floating-point
   arithmetic and fast robust geometric predicates", 1997): the determinant in
   float64 and his proven error bound ``ccwerrboundA`` / ``o3derrboundA``.
   Shewchuk's bound assumes no underflow and no overflow.  Overflow turns some
   intermediate into inf or NaN, which makes the comparison false (the row is
   undecided).  Underflow can only lose an absolute ``2**-1075`` per product,
   amplified at most by the size of the last factor; a ``2**-1000``-scale
   absolute term covers it (see :func:`_decided`).
2. **Exact-evaluation check**: the same determinant with the error of every
   operation computed by error-free transformations (Knuth's TwoSum, Dekker's
   TwoProduct).  When every error is zero, the float result *is* the exact
   value and its sign (zero included) is final.  This settles integer and
   dyadic lattices, where the filter fails on every coplanar entry, without
   leaving numpy.
3. **Double-double evaluation**: the differences kept exact as hi + lo
   pairs (TwoDiff), the determinant of the hi parts in double-double
   (TwoProduct, TwoSum) plus the first-order tail terms, with an error bound
   of a few hundred eps**2 times the permanent (derived in
   :func:`_dd_eval3`); it settles the nearly-degenerate rows of jittered
   inputs, where the filter fails but the value is not zero.
4. **Integer arithmetic on the mantissas**: each row's coordinates become
   Python integers ``m * 2**(e - e_min)`` with a common per-row exponent, and
   the determinant is evaluated in exact integer arithmetic (numpy object
   arrays, so still one call per operation, not per row).

Sign conventions are Shewchuk's: ``orient2d(a, b, c) > 0`` when a, b, c turn
counter-clockwise; ``orient3d(a, b, c, d) > 0`` when d lies *below* the plane
through a, b, c, "below" being the side opposite to where a, b, c appear
counter-clockwise, i.e. opposite to the normal ``(b - a) x (c - a)``.  So a
point p is strictly *outside* a facet (a, b, c) that is counter-clockwise seen
from outside exactly when ``orient3d(a, b, c, p) < 0``.

The ``*_mean`` variants take the last point as the mean of several points,
exactly (no rounding of the mean): the determinant is affine in that row, so
its sign is the sign of the sum of the determinants with each point.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = [
    "orient2d",
    "orient3d",
    "orient2d_mean",
    "orient3d_mean",
    "collinear3d",
    "orient2d_value",
    "orient3d_value",
    "orient2d_sum_sign",
    "orient3d_sum_sign",
]

_EPS = 2.0**-53  # Shewchuk's epsilon: half an ulp of 1
#: Shewchuk's proven bounds for the plain float evaluation of the determinants.
CCW_ERRBOUND_A = (3.0 + 16.0 * _EPS) * _EPS
O3D_ERRBOUND_A = (7.0 + 56.0 * _EPS) * _EPS
#: Relative slack added to every bound: covers the float evaluation of the bound sums.
_SLACK = 1.0 + 2.0**-40
#: Absolute term that covers the error of a product that underflowed (see module docstring).
_TINY = 2.0**-1000
_SPLITTER = 134217729.0  # 2**27 + 1, Veltkamp's split constant
_SPLIT_MAX = 2.0**995  # beyond this the split can overflow
_PROD_MIN = 2.0**-969  # below this a product's error can fall under the subnormal range


# --------------------------------------------------------------------------- helpers


def _columns(arr: np.ndarray, dim: int) -> list[np.ndarray]:
    return [arr[:, i] for i in range(dim)]


def _prepare(points: Sequence[np.ndarray], dim: int) -> tuple[list[np.ndarray], int]:
    """Broadcast the point arguments to (k, dim) float64 arrays."""
    arrs = [np.asarray(p, dtype=np.float64) for p in points]
    for i, a in enumerate(arrs):
        if a.shape[-1:] != (dim,):
            raise ValueError(f"argument {i} must have shape (k, {dim}) or ({dim},), got {a.shape}")
    shape = np.broadcast_shapes(*(a.shape for a in arrs))
    if len(shape) == 1:
        shape = (1, dim)
    arrs = [np.broadcast_to(a, shape).reshape(-1, dim) for a in arrs]
    return arrs, arrs[0].shape[0]


def _two_diff_err(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Knuth's TwoDiff: ``a - b - x`` exactly, for ``x = fl(a - b)`` (no overflow)."""
    bv = a - x
    av = x + bv
    return (a - av) + (bv - b)


def _two_sum_err(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Knuth's TwoSum: ``a + b - x`` exactly, for ``x = fl(a + b)`` (no overflow)."""
    bv = x - a
    av = x - bv
    return (a - av) + (b - bv)


def _two_prod_exact(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """True where ``x = fl(a * b)`` is provably the exact product.

    Dekker's TwoProduct gives the rounding error exactly when the split cannot
    overflow and the product is far enough from the underflow range (Boldo's
    conditions); outside that range the row is left to the integer stage.
    """
    c = _SPLITTER * a
    ahi = c - (c - a)
    alo = a - ahi
    c = _SPLITTER * b
    bhi = c - (c - b)
    blo = b - bhi
    err = alo * blo - (((x - ahi * bhi) - alo * bhi) - ahi * blo)
    ax = np.abs(x)
    valid = (np.abs(a) < _SPLIT_MAX) & (np.abs(b) < _SPLIT_MAX) & (
        (ax >= _PROD_MIN) | ((a == 0) | (b == 0))
    )
    return valid & (err == 0) & np.isfinite(x)


def _two_prod(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Dekker's TwoProduct: ``a * b = hi + lo`` exactly (no overflow, no underflow)."""
    hi = a * b
    c = _SPLITTER * a
    ahi = c - (c - a)
    alo = a - ahi
    c = _SPLITTER * b
    bhi = c - (c - b)
    blo = b - bhi
    lo = alo * blo - (((hi - ahi * bhi) - alo * bhi) - ahi * blo)
    return hi, lo


def _in_dd_range(*diffs: np.ndarray) -> np.ndarray:
    """Rows whose nonzero differences lie in [2**-300, 2**300]: products of three stay normal."""
    ok = np.ones(diffs[0].shape, dtype=bool)
    for x in diffs:
        ax = np.abs(x)
        ok &= (ax == 0) | ((ax >= 2.0**-300) & (ax <= 2.0**300))
    return ok


def _dd_eval2(ax, ay, bx, by, cx, cy) -> tuple[np.ndarray, np.ndarray]:
    """orient2d to about 2**-100 of its permanent: differences kept exact as hi + lo pairs.

    With exact differences ``x = x1 + x2`` (|x2| <= eps |x1|), the determinant
    is the double-double value of the hi parts, plus the first-order tail
    terms in float, plus second-order terms below 2 eps**2 P (P the permanent
    of the hi parts).  Adding up the rounding of every step gives less than
    35 eps**2 P; rows are decided beyond 128 eps**2 P (+ 2**-700, covering any
    underflow of tail products).
    """
    x1, y1, z1, w1 = ax - cx, by - cy, ay - cy, bx - cx
    x2 = _two_diff_err(ax, cx, x1)
    y2 = _two_diff_err(by, cy, y1)
    z2 = _two_diff_err(ay, cy, z1)
    w2 = _two_diff_err(bx, cx, w1)
    ph, pl = _two_prod(x1, y1)
    qh, ql = _two_prod(z1, w1)
    sh = ph - qh
    sl = _two_diff_err(ph, qh, sh)
    tail = (x2 * y1 + x1 * y2) - (z2 * w1 + z1 * w2)
    low = ((sl + pl) - ql) + tail
    det = sh + low
    perm = np.abs(ph) + np.abs(qh)
    decided = (np.abs(det) > 128.0 * _EPS * _EPS * perm * _SLACK + 2.0**-700) & _in_dd_range(x1, y1, z1, w1)
    return det, decided & np.isfinite(det) & np.isfinite(perm)


def _dd_eval3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz) -> tuple[np.ndarray, np.ndarray]:
    """orient3d to about 2**-98 of its permanent, as :func:`_dd_eval2` (bound 256 eps**2 P).

    The three 2x2 minors of the hi parts are double-doubles (TwoProduct,
    TwoDiff), each times its z difference by TwoProduct, summed by TwoSum; all
    low parts, the minors' low parts times z, and the first-order tail terms
    go into one float sum.  The error analysis gives under 110 eps**2 P.
    """
    cols = {}
    for name, (p, q) in {
        "adx": (ax, dx), "bdx": (bx, dx), "cdx": (cx, dx),
        "ady": (ay, dy), "bdy": (by, dy), "cdy": (cy, dy),
        "adz": (az, dz), "bdz": (bz, dz), "cdz": (cz, dz),
    }.items():
        hi = p - q
        cols[name] = (hi, _two_diff_err(p, q, hi))
    (adx, adx2), (bdx, bdx2), (cdx, cdx2) = cols["adx"], cols["bdx"], cols["cdx"]
    (ady, ady2), (bdy, bdy2), (cdy, cdy2) = cols["ady"], cols["bdy"], cols["cdy"]
    (adz, adz2), (bdz, bdz2), (cdz, cdz2) = cols["adz"], cols["bdz"], cols["cdz"]

    def minor(p, q, r, s):  # p*q - r*s as hi + lo, and |p q| + |r s|
        ph, pl = _two_prod(p, q)
        qh, ql = _two_prod(r, s)
        sh = ph - qh
        sl = _two_diff_err(ph, qh, sh)
        return sh, (sl + pl) - ql, np.abs(ph) + np.abs(qh)

    m1h, m1l, p1 = minor(bdx, cdy, cdx, bdy)
    m2h, m2l, p2 = minor(cdx, ady, adx, cdy)
    m3h, m3l, p3 = minor(adx, bdy, bdx, ady)
    t1h, t1l = _two_prod(adz, m1h)
    t2h, t2l = _two_prod(bdz, m2h)
    t3h, t3l = _two_prod(cdz, m3h)
    s1 = t1h + t2h
    s1l = _two_sum_err(t1h, t2h, s1)
    s2 = s1 + t3h
    s2l = _two_sum_err(s1, t3h, s2)
    # First-order tails: each tail once, with the hi parts of the other two factors.
    tail = (
        adz2 * m1h + bdz2 * m2h + cdz2 * m3h
        + adz * ((bdx2 * cdy + bdx * cdy2) - (cdx2 * bdy + cdx * bdy2))
        + bdz * ((cdx2 * ady + cdx * ady2) - (adx2 * cdy + adx * cdy2))
        + cdz * ((adx2 * bdy + adx * bdy2) - (bdx2 * ady + bdx * ady2))
    )
    low = (s1l + s2l) + (t1l + t2l + t3l) + (adz * m1l + bdz * m2l + cdz * m3l) + tail
    det = s2 + low
    perm = np.abs(adz) * p1 + np.abs(bdz) * p2 + np.abs(cdz) * p3
    in_range = _in_dd_range(adx, bdx, cdx, ady, bdy, cdy, adz, bdz, cdz)
    decided = (np.abs(det) > 256.0 * _EPS * _EPS * perm * _SLACK + 2.0**-700) & in_range
    return det, decided & np.isfinite(det) & np.isfinite(perm)


def _decided(det: np.ndarray, errbound: np.ndarray, noise: np.ndarray | float) -> np.ndarray:
    """Rows whose float determinant has a certain sign.

    NaN and inf (overflow) compare false, so such rows stay undecided.
    """
    with np.errstate(invalid="ignore", over="ignore"):
        return np.abs(det) > errbound * _SLACK + noise


def _to_ints(cols: list[np.ndarray], *, exponents: bool = False):
    """Exact integer images of float columns, with a common power-of-two scale per row.

    Each float is ``m * 2**e`` with an integer mantissa ``|m| < 2**53``; the
    row's smallest exponent ``e_min`` is factored out, so every value becomes
    the Python int ``m << (e - e_min)``.  A polynomial that is homogeneous in
    the row's values keeps its sign.  Subnormals are handled by frexp.
    """
    mat = np.stack(cols, axis=1)
    mant, ex = np.frexp(mat)
    m = (mant * 2.0**53).astype(np.int64)  # exact: mant has at most 53 significant bits
    e = ex.astype(np.int64)
    nz = m != 0
    big = np.iinfo(np.int64).max
    emin = np.where(nz, e, big).min(axis=1)
    emin[emin == big] = 0
    shift = np.where(nz, e - emin[:, None], 0)
    obj = m.astype(object) << shift.astype(object)
    out = [obj[:, i] for i in range(mat.shape[1])]
    if exponents:
        return out, emin - 53  # row value = int * 2**(emin - 53)
    return out


def _signs_of_objects(values: np.ndarray) -> np.ndarray:
    return np.fromiter(((v > 0) - (v < 0) for v in values), dtype=np.int8, count=len(values))


# --------------------------------------------------------------------------- orient2d


def _filter2(ax, ay, bx, by, cx, cy):
    acx = ax - cx
    bcx = bx - cx
    acy = ay - cy
    bcy = by - cy
    left = acx * bcy
    right = acy * bcx
    det = left - right
    errbound = CCW_ERRBOUND_A * (np.abs(left) + np.abs(right))
    return det, errbound


def _exact_eval2(ax, ay, bx, by, cx, cy) -> tuple[np.ndarray, np.ndarray]:
    """Float orient2d with a flag saying every operation was exact."""
    acx = ax - cx
    bcx = bx - cx
    acy = ay - cy
    bcy = by - cy
    left = acx * bcy
    right = acy * bcx
    det = left - right
    ok = (
        (_two_diff_err(ax, cx, acx) == 0)
        & (_two_diff_err(bx, cx, bcx) == 0)
        & (_two_diff_err(ay, cy, acy) == 0)
        & (_two_diff_err(by, cy, bcy) == 0)
        & _two_prod_exact(acx, bcy, left)
        & _two_prod_exact(acy, bcx, right)
        & (_two_diff_err(left, right, det) == 0)
        & np.isfinite(det)
    )
    return det, ok


def _int_det2(ax, ay, bx, by, cx, cy):
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


def _cascade(cols, det, decided, exact_eval, dd_eval, int_det) -> np.ndarray:
    """Signs of ``det`` where the filter ``decided``; the later stages settle the rest.

    Undecided entries go through the exactness test (``exact_eval``), then
    double-double arithmetic (``dd_eval``), then integer arithmetic on the
    mantissas (``int_det``); each stage returns which entries it settled.
    """
    sign = np.sign(det).astype(np.int8)
    rest = np.flatnonzero(~decided)
    for stage in (exact_eval, dd_eval):
        if not rest.size:
            return sign
        value, ok = stage(*[col[rest] for col in cols])
        sign[rest[ok]] = np.sign(value[ok]).astype(np.int8)
        rest = rest[~ok]
    if rest.size:
        sign[rest] = _signs_of_objects(int_det(*_to_ints([col[rest] for col in cols])))
    return sign


def orient2d(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Exact sign of the 2D orientation of (a, b, c).

    Parameters
    ----------
    a, b, c : ndarray of shape (k, 2) or (2,), float64
        Broadcast against each other.

    Returns
    -------
    ndarray of shape (k,), int8
        +1 counter-clockwise, -1 clockwise, 0 collinear (exactly).

    Examples
    --------
    >>> orient2d([0.0, 0.0], [1.0, 0.0], [[0.5, 1e-300], [0.5, 0.0], [0.5, -5e-324]]).tolist()
    [1, 0, -1]
    >>> orient2d([0.0, 0.0], [1.0, 3.0], [0.1, 0.3]).tolist()  # the double 0.3 < 3 * (double 0.1)
    [-1]
    """
    (pa, pb, pc), k = _prepare([a, b, c], 2)
    cols = _columns(pa, 2) + _columns(pb, 2) + _columns(pc, 2)
    with np.errstate(all="ignore"):
        det, errbound = _filter2(*cols)
        return _cascade(cols, det, _decided(det, errbound, _TINY), _exact_eval2, _dd_eval2, _int_det2)


def orient2d_mean(a: np.ndarray, b: np.ndarray, cs: Sequence[np.ndarray]) -> np.ndarray:
    """Exact sign of ``orient2d(a, b, mean(cs))``, without rounding the mean.

    Parameters
    ----------
    a, b : ndarray of shape (k, 2) or (2,), float64
    cs : sequence of ndarray of shape (k, 2) or (2,)
        The points whose centroid is the third argument.

    Returns
    -------
    ndarray of shape (k,), int8

    Examples
    --------
    >>> tri = [np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.array([0.0, 1.0])]
    >>> orient2d_mean([0.0, 0.0], [1.0, 0.0], tri).tolist()  # centroid (1/3, 1/3) is left
    [1]
    """
    return _orient_mean(2, [a, b], cs)


# --------------------------------------------------------------------------- orient3d


def _filter3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    adz = az - dz
    bdz = bz - dz
    cdz = cz - dz
    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    cdxady = cdx * ady
    adxcdy = adx * cdy
    adxbdy = adx * bdy
    bdxady = bdx * ady
    det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady)
    aadz, abdz, acdz = np.abs(adz), np.abs(bdz), np.abs(cdz)
    permanent = (
        (np.abs(bdxcdy) + np.abs(cdxbdy)) * aadz
        + (np.abs(cdxady) + np.abs(adxcdy)) * abdz
        + (np.abs(adxbdy) + np.abs(bdxady)) * acdz
    )
    # An underflowed xy-product loses at most 2**-1075, then multiplied by a z difference.
    noise = _TINY * (1.0 + aadz + abdz + acdz)
    return det, O3D_ERRBOUND_A * permanent, noise


def _exact_eval3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Float orient3d with a flag saying every operation was exact."""
    ok = np.ones(ax.shape, dtype=bool)

    def sub(p, q):
        nonlocal ok
        r = p - q
        ok &= _two_diff_err(p, q, r) == 0
        return r

    def mul(p, q):
        nonlocal ok
        r = p * q
        ok &= _two_prod_exact(p, q, r)
        return r

    def add(p, q):
        nonlocal ok
        r = p + q
        ok &= _two_sum_err(p, q, r) == 0
        return r

    adx, bdx, cdx = sub(ax, dx), sub(bx, dx), sub(cx, dx)
    ady, bdy, cdy = sub(ay, dy), sub(by, dy), sub(cy, dy)
    adz, bdz, cdz = sub(az, dz), sub(bz, dz), sub(cz, dz)
    t1 = mul(adz, sub(mul(bdx, cdy), mul(cdx, bdy)))
    t2 = mul(bdz, sub(mul(cdx, ady), mul(adx, cdy)))
    t3 = mul(cdz, sub(mul(adx, bdy), mul(bdx, ady)))
    det = add(add(t1, t2), t3)
    return det, ok & np.isfinite(det)


def _int_det3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    adx, bdx, cdx = ax - dx, bx - dx, cx - dx
    ady, bdy, cdy = ay - dy, by - dy, cy - dy
    adz, bdz, cdz = az - dz, bz - dz, cz - dz
    return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady)


def orient3d(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Exact sign of the 3D orientation of (a, b, c, d).

    Parameters
    ----------
    a, b, c, d : ndarray of shape (k, 3) or (3,), float64
        Broadcast against each other.

    Returns
    -------
    ndarray of shape (k,), int8
        +1 when d is below the plane of a, b, c (opposite to the normal
        ``(b - a) x (c - a)``), -1 above, 0 coplanar (exactly).

    Examples
    --------
    >>> o = np.zeros(3); x = np.array([1.0, 0, 0]); y = np.array([0, 1.0, 0])
    >>> orient3d(o, x, y, [[0, 0, -1.0], [0.3, 0.3, 0.0], [0, 0, 5e-324]]).tolist()
    [1, 0, -1]
    """
    (pa, pb, pc, pd), k = _prepare([a, b, c, d], 3)
    cols = _columns(pa, 3) + _columns(pb, 3) + _columns(pc, 3) + _columns(pd, 3)
    with np.errstate(all="ignore"):
        det, errbound, noise = _filter3(*cols)
        return _cascade(cols, det, _decided(det, errbound, noise), _exact_eval3, _dd_eval3, _int_det3)


def orient3d_mean(a: np.ndarray, b: np.ndarray, c: np.ndarray, ds: Sequence[np.ndarray]) -> np.ndarray:
    """Exact sign of ``orient3d(a, b, c, mean(ds))``, without rounding the mean.

    Parameters
    ----------
    a, b, c : ndarray of shape (k, 3) or (3,), float64
    ds : sequence of ndarray of shape (k, 3) or (3,)

    Returns
    -------
    ndarray of shape (k,), int8

    Examples
    --------
    >>> o = np.zeros(3); x = np.array([1.0, 0, 0]); y = np.array([0, 1.0, 0])
    >>> orient3d_mean(o, x, y, [np.array([0, 0, 1e-300]), np.array([0, 0, -2e-300])]).tolist()
    [1]
    """
    return _orient_mean(3, [a, b, c], ds)


def _orient_mean(dim: int, fixed: list, ds: Sequence[np.ndarray]) -> np.ndarray:
    ds = list(ds)
    if not ds:
        raise ValueError("the mean needs at least one point, got an empty sequence")
    arrs, k = _prepare(fixed + ds, dim)
    fixed_cols = [col for arr in arrs[:dim] for col in _columns(arr, dim)]
    mean_cols = [_columns(arr, dim) for arr in arrs[dim:]]
    filt = _filter2 if dim == 2 else _filter3
    with np.errstate(all="ignore"):
        total = np.zeros(k)
        bound = np.zeros(k)
        magnitude = np.zeros(k)
        for cols in mean_cols:
            out = filt(*fixed_cols, *cols)
            det, errbound = out[0], out[1]
            noise = out[2] if dim == 3 else _TINY
            total = total + det
            bound = bound + errbound * _SLACK + noise
            magnitude = magnitude + np.abs(det)
        # Summing m terms in float adds at most (m - 1) * eps relative to the sum of magnitudes.
        bound = bound + (len(ds) * 2.0 * _EPS) * magnitude
        sign = np.sign(total).astype(np.int8)
        todo = np.flatnonzero(~_decided(total, bound, 0.0))
    if todo.size:
        all_cols = [col[todo] for col in fixed_cols] + [col[todo] for cols in mean_cols for col in cols]
        ints = _to_ints(all_cols)
        m = len(ds)
        fixed_ints = [m * v for v in ints[: dim * dim]]
        summed = [sum(ints[dim * dim + j * dim + i] for j in range(m)) for i in range(dim)]
        det_fn = _int_det2 if dim == 2 else _int_det3
        sign[todo] = _signs_of_objects(det_fn(*fixed_ints, *summed))
    return sign


def collinear3d(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Exactly whether three 3D points are collinear (a degenerate triangle).

    Three points are collinear iff their projections on the xy, yz and zx
    planes are all collinear.

    Parameters
    ----------
    a, b, c : ndarray of shape (k, 3) or (3,), float64

    Returns
    -------
    ndarray of shape (k,), bool

    Examples
    --------
    >>> collinear3d([0, 0, 0.0], [1, 1, 1.0], [[2, 2, 2.0], [2, 2, 2.0000000000000004]]).tolist()
    [True, False]
    """
    (pa, pb, pc), k = _prepare([a, b, c], 3)
    out = np.ones(k, dtype=bool)
    for i, j in ((0, 1), (1, 2), (2, 0)):
        todo = np.flatnonzero(out)
        if not todo.size:
            break
        s = orient2d(pa[todo][:, [i, j]], pb[todo][:, [i, j]], pc[todo][:, [i, j]])
        out[todo[s != 0]] = False
    return out


# --------------------------------------------------------------------------- float values (reporting)


def orient2d_value(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Float value of the 2D orientation determinant (twice the signed area); for magnitudes only."""
    (pa, pb, pc), _ = _prepare([a, b, c], 2)
    with np.errstate(all="ignore"):
        return _filter2(*_columns(pa, 2), *_columns(pb, 2), *_columns(pc, 2))[0]


def orient3d_value(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Float value of the 3D orientation determinant (six times the signed volume); for magnitudes only."""
    (pa, pb, pc, pd), _ = _prepare([a, b, c, d], 3)
    with np.errstate(all="ignore"):
        return _filter3(*_columns(pa, 3), *_columns(pb, 3), *_columns(pc, 3), *_columns(pd, 3))[0]


# --------------------------------------------------------------------------- signs of sums


def _sum_sign(dim: int, points: list) -> int:
    arrs, k = _prepare(points, dim)
    if k == 0:
        return 0
    cols = [col for arr in arrs for col in _columns(arr, dim)]
    with np.errstate(all="ignore"):
        out = (_filter2 if dim == 2 else _filter3)(*cols)
        det, errbound = out[0], out[1]
        noise = out[2] if dim == 3 else _TINY
        bounds = errbound * _SLACK + noise
        if np.isfinite(det).all() and np.isfinite(bounds).all():
            total = math.fsum(det.tolist())  # correctly rounded sum of the float terms
            bound = math.fsum(bounds.tolist())
            # fsum rounds once (eps * |total|); the bound's own rounding is covered by the slack.
            if math.isfinite(total) and abs(total) > (bound * (1.0 + 2.0**-30) + abs(total) * 2.0 * _EPS):
                return 1 if total > 0 else -1
    ints, emin = _to_ints(cols, exponents=True)
    dets = (_int_det2 if dim == 2 else _int_det3)(*ints)
    # Each row's determinant is homogeneous of degree ``dim`` in its scaled values.
    scale = (emin - emin.min()) * dim
    total = sum(int(v) << int(sh) for v, sh in zip(dets, scale.tolist()))
    return (total > 0) - (total < 0)


def orient2d_sum_sign(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> int:
    """Exact sign of the sum over rows of the 2D orientation determinants.

    With ``c`` fixed and (a, b) the edges of a closed polygon, this is the sign
    of its signed area.

    Parameters
    ----------
    a, b, c : ndarray of shape (k, 2) or (2,), float64

    Returns
    -------
    int
        -1, 0 or +1.

    Examples
    --------
    >>> sq = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    >>> orient2d_sum_sign(sq, np.roll(sq, -1, axis=0), sq[0])  # counter-clockwise square
    1
    """
    return _sum_sign(2, [a, b, c])


def orient3d_sum_sign(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> int:
    """Exact sign of the sum over rows of the 3D orientation determinants.

    With ``d`` fixed and (a, b, c) the triangles of a closed surface, this is
    the sign of its signed volume (positive when the triangles are
    counter-clockwise seen from outside).

    Parameters
    ----------
    a, b, c, d : ndarray of shape (k, 3) or (3,), float64

    Returns
    -------
    int
        -1, 0 or +1.

    Examples
    --------
    >>> p = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> orient3d_sum_sign(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]], p[0])
    1
    """
    return _sum_sign(3, [a, b, c, d])
