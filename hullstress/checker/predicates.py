"""Exact orientation predicates, vectorised over numpy arrays.

Every function here returns the *exact* sign of a polynomial in float64
inputs, for every finite input (huge, tiny and subnormal included).  Each call
runs these stages on the rows still undecided (when stage 1b leaves at most
:data:`FEW_FOR_INTEGERS` rows, they go straight to stage 4, which is cheaper
for a few rows than the fixed cost of stages 2 and 3):

1. **Floating-point filter** (Shewchuk, "Adaptive precision floating-point
   arithmetic and fast robust geometric predicates", 1997): the determinant in
   float64 and his proven error bound ``ccwerrboundA`` / ``o3derrboundA``
   (in 3D times the product of the rows' L1 norms, an upper bound of his
   permanent that costs fewer operations).
   Shewchuk's bound assumes no underflow and no overflow; a row is decided
   only where both are excluded or covered (issue 33):

   *Overflow.*  Under ``+ - *`` an inf or NaN intermediate never becomes
   finite again, so a finite determinant means that no intermediate of it
   overflowed; every filter here requires ``det`` finite as well as
   ``|det| > bound`` (:func:`_decided`, :func:`filter2_columns`,
   :func:`filter3_columns`, :func:`_orient_mean`).  Comparing alone is not
   enough: the bound is computed along another path (``(tiny x huge) x
   huge``) and stays finite where ``det``'s products overflow, and
   ``|inf| > finite`` once decided rows with the wrong sign (F1, F2).  A
   bound that overflows is inf, and nothing beats it.

   *Underflow.*  A product that underflows has an absolute error of at most
   ``2**-1075`` besides its relative one (sums and differences of floats are
   exact in the subnormal range).  In 2D such an error enters ``det``
   directly; in 3D the xy-products' errors are multiplied by a z difference.
   The bound itself loses at most ``2**-1075`` times the last factor when
   ``|a| * |b|`` (2D: ``|left| + |right|``; 3D: ``norm_a * norm_b``) sinks below
   the normal range.  The absolute term ``2**-1000`` (2D) and
   ``2**-1000 (1 + norm_a + norm_b + norm_c)`` (3D, the rows' L1 norms)
   covers all of these with a factor above ``2**60`` to spare.  The relative
   slack ``1 + 2**-40`` covers the rounding of the bound's own evaluation.

1b. **Row-scaled filter** (:func:`_scaled_filter`): rows stage 1 leaves open
   are filtered again on their differences scaled by a power of two to below
   1.  Nothing can overflow then, and an entry that rounds below the normal
   range moves the determinant by less than the same absolute term.  Mixed
   magnitudes (1e300 with 1e-300, which no exact global scaling can bring
   into range) are settled here instead of in integer arithmetic.
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
   arrays, so still one call per operation, not per row).  When the caller
   labels the rows of :func:`orient3d` by plane (many points against few
   planes), the rows of one plane share one integer normal
   (:func:`_int_signs3_by_plane`).

Sign conventions are Shewchuk's: ``orient2d(a, b, c) > 0`` when a, b, c turn
counter-clockwise; ``orient3d(a, b, c, d) > 0`` when d lies *below* the plane
through a, b, c, "below" being the side opposite to where a, b, c appear
counter-clockwise, i.e. opposite to the normal ``(b - a) x (c - a)``.  So a
point p is strictly *outside* a facet (a, b, c) that is counter-clockwise seen
from outside exactly when ``orient3d(a, b, c, p) < 0``.

The ``*_mean`` variants take the last point as the mean of several points,
exactly (no rounding of the mean): the determinant is affine in that row, so
its sign is the sign of the sum of the determinants with each point.  Their
filter sums the terms' bounds plus ``2 m eps`` times the sum of the terms'
magnitudes (the rounding of an ``m``-term float sum), and decides only when
every term is finite; the rest go to integers.

Stages 2 and 3 decide only finite values inside the ranges their error-free
transformations need (``_two_prod_exact``: no split overflow, products above
``2**-969``; ``_in_dd_range``: differences in ``[2**-300, 2**300]``), and
stage 4 is exact for every finite input.  docs/checker.md lists every float
shortcut of the checker with the argument for its soundness.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction

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
#: Up to this many rows left undecided by the filter go straight to integer arithmetic (stage 4):
#: measured, the exactness check and double-double stages cost about 240 us (3D) and 70 us (2D)
#: whatever the row count below a few hundred, integers 30 us plus about 1 us a row.
FEW_FOR_INTEGERS = 64
_SPLITTER = 134217729.0  # 2**27 + 1, Veltkamp's split constant
_SPLIT_MAX = 2.0**995  # beyond this the split can overflow
_PROD_MIN = 2.0**-969  # below this a product's error can fall under the subnormal range


# --------------------------------------------------------------------------- helpers


def _columns(arr: np.ndarray, dim: int) -> list[np.ndarray]:
    return [arr[:, i] for i in range(dim)]


def _rows(points: Sequence, dim: int) -> tuple[list[np.ndarray], int]:
    """The point arguments as float64 arrays of shape (1, dim) or (k, dim), and k.

    Arguments are broadcast against each other the numpy way; only the row
    count is settled here (the arithmetic broadcasts by itself), so a call
    with one fixed point and k rows costs no copies.
    """
    arrs = []
    for i, p in enumerate(points):
        a = np.asarray(p, dtype=np.float64)
        if a.ndim == 1:
            a = a.reshape(1, -1)
        if a.ndim != 2 or a.shape[1] != dim:
            raise ValueError(f"argument {i} must have shape (k, {dim}) or ({dim},), got {np.shape(p)}")
        arrs.append(a)
    # numpy's rule: counts of 1 stretch to the others, which must agree (0 included: a
    # batch of no rows against one fixed point is empty, issue 33 F8).
    counts = {a.shape[0] for a in arrs} - {1}
    k = counts.pop() if len(counts) == 1 else 1
    if counts:
        raise ValueError(f"arguments must broadcast: got row counts {[a.shape[0] for a in arrs]}")
    return arrs, k


def _take(arr: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``arr[rows]`` for a (k, d) argument, or the one broadcast row repeated."""
    if arr.shape[0] == 1:
        return np.broadcast_to(arr, (len(rows), arr.shape[1]))
    return arr[rows]


def _prepare(points: Sequence[np.ndarray], dim: int) -> tuple[list[np.ndarray], int]:
    """Broadcast the point arguments to (k, dim) float64 arrays."""
    arrs, k = _rows(points, dim)
    return [a if a.shape[0] == k else np.broadcast_to(a, (k, dim)) for a in arrs], k


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

    A row is decided only when ``det`` is finite (no intermediate overflowed:
    an inf or NaN intermediate never turns finite again under ``+ - *``) and
    exceeds a finite bound.  An infinite ``det`` with a finite bound is *not*
    decided: the bound is computed along another path ((tiny x huge) x huge)
    and can stay finite where the determinant's products overflow (issue 33, F1).
    """
    with np.errstate(invalid="ignore", over="ignore"):
        return np.isfinite(det) & (np.abs(det) > errbound * _SLACK + noise)


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


# --------------------------------------------------------------------------- float filters

def filter2(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shewchuk's float orient2d of (1|k, 2) rows and its error bound ``(det, errbound)``.

    ``det`` is evaluated exactly as in his ``orient2dfast`` (NaN or inf where
    an intermediate overflows); ``errbound`` is ``ccwerrboundA`` times the
    permanent, valid when nothing overflowed or underflowed.
    """
    acx, acy = (a - c).T
    bcx, bcy = (b - c).T
    left = acx * bcy
    right = acy * bcx
    return left - right, CCW_ERRBOUND_A * (np.abs(left) + np.abs(right))


def filter3(
    a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shewchuk's float orient3d of (1|k, 3) rows, its error bound and an underflow term.

    ``det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady)``
    evaluated in that order, ``errbound = o3derrboundA * permanent``, and
    ``noise``: an underflowed xy-product loses at most ``2**-1075``, then
    multiplied by a z difference (see the module docstring).  The rows are
    taken apart into coordinate columns once (views, no copies).
    """
    adx, ady, adz = (a - d).T
    bdx, bdy, bdz = (b - d).T
    cdx, cdy, cdz = (c - d).T
    return _det3(adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz)


def filter2_columns(diff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`filter2` from coordinate-major differences, and the full error bound.

    ``diff[c, i]`` is coordinate ``c`` of ``p_i - p_last`` over all rows
    (shape (2, 2, k), each ``diff[c, i]`` contiguous): the same float
    operations as :func:`filter2` on contiguous columns.  Call under
    ``np.errstate(all="ignore")``.
    """
    left = diff[0, 0] * diff[1, 1]
    right = diff[1, 0] * diff[0, 1]
    det = left - right
    bound = CCW_ERRBOUND_A * (np.abs(left) + np.abs(right)) * _SLACK + _TINY
    # inf - finite is inf, and |left| + |right| is then inf too; NaN compares false.  Kept
    # explicit so no later change of the bound can let an overflowed row through.
    return det, np.where(np.isfinite(det), bound, np.inf)


def filter3_columns(diff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`filter3` from coordinate-major differences (shape (3, 3, k)), and the full error bound.

    The same float values as :func:`filter3` (the row norms are summed and
    multiplied in the same order), from a handful of whole-array operations.
    Call under ``np.errstate(all="ignore")``.
    """
    det = _det3_value(*(diff[c, i] for i in range(3) for c in range(3)))
    absolute = np.abs(diff)
    norms = absolute.sum(axis=0)  # (|x| + |y|) + |z| of each row, slab by slab
    noise = _TINY * (((1.0 + norms[0]) + norms[1]) + norms[2])
    bound = O3D_ERRBOUND_A * ((norms[0] * norms[1]) * norms[2]) * _SLACK + noise
    # An overflowed determinant is undecided: its bound must not be beaten by inf (F1).
    return det, np.where(np.isfinite(det), bound, np.inf)


def _det3_value(adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz):
    """Shewchuk's orient3d expression, evaluated in his order."""
    return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady)


def _det3(adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz):
    """The float determinant, its error bound and the underflow term.

    The bound is ``o3derrboundA`` times the product of the rows' L1 norms, an
    upper bound of Shewchuk's permanent (every term of the permanent appears
    in the product's expansion, all terms being nonnegative): a slightly wider
    filter for far fewer operations.
    """
    det = _det3_value(adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz)
    aadz, abdz, acdz = np.abs(adz), np.abs(bdz), np.abs(cdz)
    norm_a = np.abs(adx) + np.abs(ady) + aadz
    norm_b = np.abs(bdx) + np.abs(bdy) + abdz
    norm_c = np.abs(cdx) + np.abs(cdy) + acdz
    # The underflow term covers (see the module docstring) the products that underflow in
    # ``det`` (each at most 2**-1075, then times a z difference) and in the bound itself
    # (``norm_a * norm_b`` sinking below the normal range loses 2**-1075 times ``norm_c``).
    noise = _TINY * (((1.0 + norm_a) + norm_b) + norm_c)
    return det, O3D_ERRBOUND_A * ((norm_a * norm_b) * norm_c), noise


def _scaled_filter(cols: list[np.ndarray], dim: int) -> tuple[np.ndarray, np.ndarray]:
    """The float filter on each row's differences scaled by a power of two to below 1 (stage 1b).

    ``d_i = fl(p_i - p_last)`` are the differences the plain filter uses (one
    rounding each, or inf: such a row is left undecided).  Each row is scaled
    by ``2**-e``, ``e`` the exponent of its largest ``|d_i|``: exact, except
    that an entry falling below the normal range is rounded, by at most
    ``2**-1075`` absolutely.  With every entry below 1 in magnitude, nothing
    can overflow, and a perturbation of ``2**-1075`` in one entry moves the
    determinant by at most that times a cofactor (at most 2), so the whole
    rescaling and every underflowed product stay far below the absolute term
    ``_TINY`` of the bound; the relative part is Shewchuk's, as in stage 1.
    The sign of the scaled determinant is the sign of the original one
    (``2**(-e dim) > 0``).
    """
    with np.errstate(all="ignore"):
        last = cols[dim * dim: dim * (dim + 1)]
        diff = [cols[i * dim + c] - last[c] for i in range(dim) for c in range(dim)]
        top = np.abs(diff[0])
        for d in diff[1:]:
            top = np.maximum(top, np.abs(d))
        # Only rows stage 1 may have failed for their magnitude (products overflowing, or
        # the underflow term dominating): elsewhere scaling changes nothing.
        finite = np.isfinite(top) & ((top > 2.0**300) | ((top < 2.0**-300) & (top > 0)))
        if not finite.any():
            return top, finite
        shift = -np.frexp(np.where(finite, top, 1.0))[1]
        scaled = [np.ldexp(d, shift) for d in diff]
        if dim == 2:
            (ax, ay), (bx, by) = scaled[:2], scaled[2:]
            left, right = ax * by, ay * bx
            det = left - right
            decided = _decided(det, CCW_ERRBOUND_A * (np.abs(left) + np.abs(right)), _TINY)
        else:
            det, errbound, noise = _det3(*scaled)
            decided = _decided(det, errbound, noise)
    return det, decided & finite


def _coincident(args: list[np.ndarray]) -> np.ndarray:
    """Rows where two of the points are equal: the determinant is exactly zero."""
    out = np.zeros(max(len(a) for a in args), dtype=bool)
    for i in range(len(args)):
        for j in range(i + 1, len(args)):
            out |= (args[i] == args[j]).all(axis=1)
    return out


def _settle(sign: np.ndarray, decided: np.ndarray, args: list[np.ndarray], dim: int, stages,
            planes: np.ndarray | None = None) -> np.ndarray:
    """Fill ``sign`` where the filter did not decide: exact zeros, exactness test, double-double, integers.

    Rows with two equal points are exactly zero (common with duplicated
    input points, and otherwise settled only by the integer stage).
    ``stages`` is ``(exact_eval, dd_eval, int_det)``, each taking the undecided
    rows as coordinate columns; the first two return which rows they settled.
    ``planes`` (3D only): a label per row, rows with equal labels sharing
    their first three points (:func:`_int_signs3_by_plane`).
    """
    if decided.all():
        return sign
    rest = np.flatnonzero(~decided)
    taken = [_take(arr, rest) for arr in args]
    zero = _coincident(taken)
    sign[rest[zero]] = 0
    rest = rest[~zero]
    if not rest.size:
        return sign
    cols = [col for arr in taken for col in _columns(arr[~zero], dim)]
    # Rows whose filter overflowed or sank towards underflow (mixed magnitudes such as 1e300
    # with 1e-300): the same filter on row-scaled differences settles most without integers.
    value, ok = _scaled_filter(cols, dim)
    if ok.any():
        sign[rest[ok]] = np.sign(value[ok]).astype(np.int8)
        rest = rest[~ok]
        if not rest.size:
            return sign
        cols = [col[~ok] for col in cols]
    exact_eval, dd_eval, int_det = stages
    if rest.size <= FEW_FOR_INTEGERS:
        # A few rows: integers at once (the float stages' fixed cost of a hundred small
        # array operations is more than integer arithmetic on a few dozen rows).
        sign[rest] = _signs_of_objects(int_det(*_to_ints(cols)))
        return sign
    for stage in (exact_eval, dd_eval):
        value, ok = stage(*cols)
        sign[rest[ok]] = np.sign(value[ok]).astype(np.int8)
        rest = rest[~ok]
        if not rest.size:
            return sign
        cols = [col[~ok] for col in cols]
    shared = _int_signs3_by_plane(cols, planes[rest]) if planes is not None else None
    sign[rest] = shared if shared is not None else _signs_of_objects(int_det(*_to_ints(cols)))
    return sign


def _int_signs3_by_plane(cols: list[np.ndarray], planes: np.ndarray) -> np.ndarray | None:
    """Exact orient3d signs with one integer normal per plane: ``-N . (d - a)``, ``N = (b - a) x (c - a)``.

    ``orient3d(a, b, c, d) = det[a - d, b - d, c - d] = -((b - a) x (c - a)) . (d - a)``
    (subtract the first row from the others, then expand).  ``N`` is computed
    once per plane from integers with the plane's own common exponent, and
    ``d - a`` per row from integers with the row's; each is the exact value
    times a positive power of two, so their dot product has the exact sign.
    Per row that is six coordinates made integers and eight integer
    operations instead of twelve and twenty-six.

    Returns None (the caller evaluates every row) when the labels do not
    keep their promise, or when there are not at least two rows per plane.
    """
    labels, first, group = np.unique(planes, return_index=True, return_inverse=True)
    if 2 * len(labels) > len(planes):
        return None
    group = group.ravel()
    abc = cols[:9]
    if not all(np.array_equal(col, col[first][group]) for col in abc):
        return None
    ax, ay, az, bx, by, bz, cx, cy, cz = _to_ints([col[first] for col in abc])
    ux, uy, uz, vx, vy, vz = bx - ax, by - ay, bz - az, cx - ax, cy - ay, cz - az
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    rax, ray, raz, dx, dy, dz = _to_ints([cols[0], cols[1], cols[2], cols[9], cols[10], cols[11]])
    return -_signs_of_objects(nx[group] * (dx - rax) + ny[group] * (dy - ray) + nz[group] * (dz - raz))


def exact_signs3(det: np.ndarray, bound: np.ndarray, args: list[np.ndarray]) -> np.ndarray:
    """Exact orient3d signs of rows whose float determinants and bounds are known (:func:`filter3_columns`).

    Call under ``np.errstate(all="ignore")`` (the batched checks hold one for all their steps).
    """
    return _settle(np.sign(det).astype(np.int8), np.abs(det) > bound, args, 3, _STAGES3)


def exact_signs2(det: np.ndarray, bound: np.ndarray, args: list[np.ndarray]) -> np.ndarray:
    """Exact orient2d signs of rows whose float determinants and bounds are known (:func:`filter2_columns`).

    Call under ``np.errstate(all="ignore")``.
    """
    return _settle(np.sign(det).astype(np.int8), np.abs(det) > bound, args, 2, _STAGES2)


# --------------------------------------------------------------------------- orient2d


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


_STAGES2 = (_exact_eval2, _dd_eval2, _int_det2)


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
    args, _ = _rows([a, b, c], 2)
    with np.errstate(all="ignore"):
        det, errbound = filter2(*args)
        sign = np.sign(det).astype(np.int8)
        return _settle(sign, _decided(det, errbound, _TINY), args, 2, _STAGES2)


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


def _exact_eval3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Float orient3d with a flag saying the float value is exact.

    Every operation is checked with an error-free transformation, except that
    a term whose z difference is exactly zero is exactly zero whatever its
    xy-minor rounded to: points on a plane parallel to two axes (a cube's
    faces, ``z = 0``) are settled here instead of in integer arithmetic.
    """

    def sub(p, q):
        r = p - q
        return r, _two_diff_err(p, q, r) == 0

    def term(z, z_ok, p, q, r, t, parts_ok):  # z (p q - r t)
        pq, rt = p * q, r * t
        minor = pq - rt
        value = z * minor
        exact = _two_prod_exact(p, q, pq) & _two_prod_exact(r, t, rt) & (_two_diff_err(pq, rt, minor) == 0)
        exact &= _two_prod_exact(z, minor, value) & parts_ok
        return value, z_ok & ((z == 0) | exact)

    (adx, adx_ok), (bdx, bdx_ok), (cdx, cdx_ok) = sub(ax, dx), sub(bx, dx), sub(cx, dx)
    (ady, ady_ok), (bdy, bdy_ok), (cdy, cdy_ok) = sub(ay, dy), sub(by, dy), sub(cy, dy)
    (adz, adz_ok), (bdz, bdz_ok), (cdz, cdz_ok) = sub(az, dz), sub(bz, dz), sub(cz, dz)
    t1, ok1 = term(adz, adz_ok, bdx, cdy, cdx, bdy, bdx_ok & cdy_ok & cdx_ok & bdy_ok)
    t2, ok2 = term(bdz, bdz_ok, cdx, ady, adx, cdy, cdx_ok & ady_ok & adx_ok & cdy_ok)
    t3, ok3 = term(cdz, cdz_ok, adx, bdy, bdx, ady, adx_ok & bdy_ok & bdx_ok & ady_ok)
    s12 = t1 + t2
    det = s12 + t3
    ok = ok1 & ok2 & ok3 & (_two_sum_err(t1, t2, s12) == 0) & (_two_sum_err(s12, t3, det) == 0)
    return det, ok & np.isfinite(det)


def _int_det3(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    adx, bdx, cdx = ax - dx, bx - dx, cx - dx
    ady, bdy, cdy = ay - dy, by - dy, cy - dy
    adz, bdz, cdz = az - dz, bz - dz, cz - dz
    return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady)


_STAGES3 = (_exact_eval3, _dd_eval3, _int_det3)


def orient3d(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray, *,
             planes: np.ndarray | None = None) -> np.ndarray:
    """Exact sign of the 3D orientation of (a, b, c, d).

    Parameters
    ----------
    a, b, c, d : ndarray of shape (k, 3) or (3,), float64
        Broadcast against each other.
    planes : ndarray of shape (k,), int, optional
        A label per row; rows with equal labels have equal ``a``, ``b`` and
        ``c`` (many points against few planes).  Only a speed hint: the rows
        the float stages leave share one exact normal per plane.  A label
        that breaks the promise is detected, and then ignored.

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
    args, k = _rows([a, b, c, d], 3)
    if planes is not None:
        planes = np.asarray(planes)
        if planes.shape != (k,):
            raise ValueError(f"planes must have shape ({k},), got {planes.shape}")
    with np.errstate(all="ignore"):
        det, errbound, noise = filter3(*args)
        sign = np.sign(det).astype(np.int8)
        return _settle(sign, _decided(det, errbound, noise), args, 3, _STAGES3, planes)


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


def _filter(dim: int, args: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The float determinant and a bound on its error (underflow included)."""
    if dim == 2:
        det, errbound = filter2(*args)
        return det, errbound * _SLACK + _TINY
    det, errbound, noise = filter3(*args)
    return det, errbound * _SLACK + noise


def _orient_mean(dim: int, fixed: list, ds: Sequence[np.ndarray]) -> np.ndarray:
    ds = list(ds)
    if not ds:
        raise ValueError("the mean needs at least one point, got an empty sequence")
    arrs, k = _rows(fixed + ds, dim)
    fixed_arrs, mean_arrs = arrs[:dim], arrs[dim:]
    with np.errstate(all="ignore"):
        total = np.zeros(k)
        bound = np.zeros(k)
        magnitude = np.zeros(k)
        for d in mean_arrs:
            det, err = _filter(dim, fixed_arrs + [d])
            total = total + det
            bound = bound + err
            magnitude = magnitude + np.abs(det)
        # Summing m terms in float adds at most (m - 1) * eps relative to the sum of magnitudes.
        bound = bound + (len(ds) * 2.0 * _EPS) * magnitude
        # Every term must be finite: an overflowed term makes ``total`` inf or NaN (F1).
        bound = np.where(np.isfinite(magnitude), bound, np.inf)
        sign = np.sign(total).astype(np.int8)
        todo = np.flatnonzero(~_decided(total, bound, 0.0))
    if todo.size:
        all_cols = [col for arr in arrs for col in _columns(_take(arr, todo), dim)]
        ints = _to_ints(all_cols)
        m = len(ds)
        fixed_ints = [m * v for v in ints[: dim * dim]]
        summed = [sum(ints[dim * dim + j * dim + i] for j in range(m)) for i in range(dim)]
        det_fn = _int_det2 if dim == 2 else _int_det3
        sign[todo] = _signs_of_objects(det_fn(*fixed_ints, *summed))
    return sign


#: The three coordinate projections of a 3D point, as column pairs.
_PROJECTIONS = np.array([[0, 1], [1, 2], [2, 0]])


def collinear3d(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Exactly whether three 3D points are collinear (a degenerate triangle).

    Three points are collinear iff their projections on the xy, yz and zx
    planes are all collinear.  The three projections go through one float
    filter; only rows it leaves open in all three are decided exactly.

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
    # (3k, 2): the xy projections of every row, then yz, then zx.
    pa2, pb2, pc2 = (x[:, _PROJECTIONS].transpose(1, 0, 2).reshape(3 * k, 2) for x in (pa, pb, pc))
    with np.errstate(all="ignore"):
        det, errbound = filter2(pa2, pb2, pc2)
        off = _decided(det, errbound, _TINY).reshape(3, k).any(axis=0)
    out = ~off
    for p in range(3):
        todo = np.flatnonzero(out)
        if not todo.size:
            break
        rows = p * k + todo
        out[todo[orient2d(pa2[rows], pb2[rows], pc2[rows]) != 0]] = False
    return out


# --------------------------------------------------------------------------- float values (reporting)


def orient2d_value(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Float value of the 2D orientation determinant (twice the signed area); for magnitudes only."""
    args, _ = _rows([a, b, c], 2)
    with np.errstate(all="ignore"):
        return filter2(*args)[0]


def orient3d_value(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Float value of the 3D orientation determinant (six times the signed volume); for magnitudes only."""
    args, _ = _rows([a, b, c, d], 3)
    with np.errstate(all="ignore"):
        return filter3(*args)[0]


# --------------------------------------------------------------------------- sums of determinants


def float_det_sum(dim: int, points: Sequence[np.ndarray]) -> tuple[float, float]:
    """Float sum of the orientation determinants over rows, and a rigorous bound on its error.

    The sum is ``math.fsum`` of the float determinants (correctly rounded, so
    it does not depend on the order of the rows).  Returns ``(nan, inf)``
    when a determinant, its bound or the sum overflows: then only
    :func:`exact_det_sum` can say.
    """
    args, k = _rows(points, dim)
    if k == 0:
        return 0.0, 0.0
    with np.errstate(all="ignore"):
        det, err = _filter(dim, args)
    return sum_with_bound(det, err)


def sum_with_bound(det: np.ndarray, err: np.ndarray) -> tuple[float, float]:
    """``math.fsum(det)`` and a bound on its distance to the exact sum of the values ``det`` stand for.

    ``err`` bounds each term's error.  ``(nan, inf)`` when anything is not
    finite or fsum's partial sums overflow (mixed magnitudes).
    """
    try:
        total = math.fsum(det.tolist())
        bound = math.fsum(err.tolist())
    except (OverflowError, ValueError):  # partial sums overflow on mixed magnitudes; inf - inf
        return math.nan, math.inf
    if not (math.isfinite(total) and math.isfinite(bound)):
        return math.nan, math.inf
    # fsum rounds once (eps |total|); the bound's own rounding is covered by the slack.
    return total, bound * (1.0 + 2.0**-30) + abs(total) * 2.0 * _EPS


def exact_det_sum(dim: int, points: Sequence[np.ndarray]) -> Fraction:
    """The exact sum over rows of the orientation determinants, as a Fraction (integer arithmetic).

    Examples
    --------
    >>> exact_det_sum(2, [np.array([[0.0, 0], [1, 0]]), np.array([[1.0, 0], [1, 1]]), np.array([0.0, 1])])
    Fraction(2, 1)
    """
    arrs, k = _prepare(points, dim)
    if k == 0:
        return Fraction(0)
    cols = [col for arr in arrs for col in _columns(arr, dim)]
    ints, emin = _to_ints(cols, exponents=True)
    dets = (_int_det2 if dim == 2 else _int_det3)(*ints)
    # Each row's determinant is homogeneous of degree ``dim`` in its scaled values.
    low = int(emin.min())
    scale = (emin - low) * dim
    total = sum(int(v) << int(sh) for v, sh in zip(dets, scale.tolist()))
    return Fraction(total) * Fraction(2) ** (dim * low)


def _sum_sign(dim: int, points: list) -> int:
    total, error = float_det_sum(dim, points)
    if abs(total) > error:  # false for NaN
        return 1 if total > 0 else -1
    exact = exact_det_sum(dim, points)
    return (exact > 0) - (exact < 0)


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
