"""The exact orientation predicates, pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/predicates.py``
that survived the rest of the fast suite (``tools/mutation.sh
'hullstress.checker.predicates.*'``, docs/testing.md "Mutation testing").  Every expected
sign or value is derived by hand from the geometry (points on a known plane or
line, whose determinant is a known multiple of one coordinate) or computed
independently with ``fractions.Fraction`` from the doubles given; never copied
from the predicates' own output.  The stages are also tested one by one against
what their docstrings promise: the exactness check claims only exact values and
settles dyadic lattices, the double-double stage is accurate to 256 eps**2 of the
permanent and decides every row beyond that, the filters compute Shewchuk's
bounds.  A row only reaches the exactness-check and double-double stages when the
float filter leaves more than ``FEW_FOR_INTEGERS`` rows open, so the tests that
aim at those stages through the public functions either use more rows than that
or set it to 0.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

import hullstress.checker.predicates as P
from hullstress.checker.predicates import (
    FEW_FOR_INTEGERS,
    collinear3d,
    exact_det_sum,
    exact_signs2,
    exact_signs3,
    filter2,
    filter2_columns,
    filter3,
    filter3_columns,
    float_det_sum,
    orient2d,
    orient2d_mean,
    orient2d_sum_sign,
    orient2d_value,
    orient3d,
    orient3d_mean,
    orient3d_sum_sign,
    orient3d_value,
    sum_with_bound,
)

EPS = 2.0**-53

# --------------------------------------------------------------------------- exact references


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def _rows_of(*points) -> list[list[list[Fraction]]]:
    """Per row, the points as lists of Fractions (the exact values of the doubles)."""
    arrs = np.broadcast_arrays(*(np.atleast_2d(np.asarray(p, dtype=np.float64)) for p in points))
    return [[[Fraction(v) for v in p] for p in row] for row in zip(*(a.tolist() for a in arrs))]


def _det3(a, b, c, d) -> Fraction:
    ad, bd, cd = ([p[i] - d[i] for i in range(3)] for p in (a, b, c))
    return (ad[2] * (bd[0] * cd[1] - cd[0] * bd[1]) + bd[2] * (cd[0] * ad[1] - ad[0] * cd[1])
            + cd[2] * (ad[0] * bd[1] - bd[0] * ad[1]))


def _det2(a, b, c) -> Fraction:
    return (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])


def exact3(a, b, c, d) -> list[Fraction]:
    return [_det3(*row) for row in _rows_of(a, b, c, d)]


def exact2(a, b, c) -> list[Fraction]:
    return [_det2(*row) for row in _rows_of(a, b, c)]


def signs(values: list[Fraction]) -> np.ndarray:
    return np.array([_sign(v) for v in values], dtype=np.int8)


# --------------------------------------------------------------------------- hard rows


def _ulps(x: np.ndarray, k: np.ndarray) -> np.ndarray:
    """x moved by k ulps (k small integers), exactly."""
    out = x.copy()
    for _ in range(int(np.abs(k).max(initial=0))):
        step = k != 0
        out[step] = np.nextafter(out[step], np.where(k[step] > 0, np.inf, -np.inf))
        k = k - np.sign(k)
    return out


def rows3(kind: str, k: int = 96, seed: int = 0) -> tuple[np.ndarray, ...]:
    """k rows (a, b, c, d) of one kind of hard orient3d input."""
    rng = np.random.default_rng(seed)
    if kind == "lattice":  # dyadic, every operation exact; half of them coplanar
        a, b, c = (rng.integers(-8, 9, (k, 3)) * 0.125 for _ in range(3))
        d = a + rng.integers(-2, 3, (k, 1)) * (b - a) + rng.integers(-2, 3, (k, 1)) * (c - a)
        d[::2] = rng.integers(-8, 9, (k - k // 2, 3)) * 0.125
        return a, b, c, d
    if kind == "tilted":  # on the plane z = x (a determinant with two equal columns), half nudged off
        a, b, c, d = (rng.random((k, 3)) for _ in range(4))
        for p in (a, b, c, d):
            p[:, 2] = p[:, 0]
        d[::2, 2] = _ulps(d[::2, 2], rng.integers(-2, 3, k - k // 2))
        return a, b, c, d
    if kind == "jitter":  # rounded affine combinations, a few ulps off
        a, b, c = (rng.random((k, 3)) * 10 for _ in range(3))
        d = a + rng.random((k, 1)) * (b - a) + rng.random((k, 1)) * (c - a)
        return a, b, c, _ulps(d, rng.integers(-2, 3, d.shape))
    if kind == "flat":  # on z = 0.3, non-dyadic x, y; every other d one ulp above or below
        a, b, c, d = (np.c_[rng.random((k, 2)), np.full(k, 0.3)] for _ in range(4))
        d[::2, 2] = _ulps(d[::2, 2], rng.choice([-1, 1], k - k // 2))
        return a, b, c, d
    if kind == "subnormal":  # multiples of the smallest subnormal
        a, b, c = (rng.integers(-8, 9, (k, 3)) * 5e-324 for _ in range(3))
        return a, b, c, a + rng.integers(-1, 2, (k, 3)) * 5e-324
    if kind == "tiny":  # products underflow
        a, b, c, d = (x * 2.0**-540 for x in rows3("jitter", k, seed))
        return a, b, c, d
    if kind == "huge":  # products overflow
        a, b, c, d = (x * 2.0**990 for x in rows3("jitter", k, seed))
        return a, b, c, d
    if kind == "wide":  # one difference at the edges of the double-double range or beyond, the others near 1
        a, b, c, d = (x.copy() for x in rows3("jitter", k, seed))
        for j in range(k):
            p, i = (a, b, c)[j % 9 // 3], j % 3
            d[j, i] = 0.0
            p[j, i] = (-1.0) ** j * _EDGES[j // 9 % len(_EDGES)]
        return a, b, c, d
    if kind == "tilted-axis":  # on z = x with one y difference zero: the permanent's terms are unequal
        a, b, c, d = (x.copy() for x in rows3("tilted", k, seed))
        for p in (a, b, c):
            p[:] = d + (p - d) * 2.0 ** rng.integers(-20, 20, (k, 1))
            p[:, 2] = p[:, 0]
        which = rng.integers(0, 3, k)
        for j, p in enumerate((a, b, c)):
            p[which == j, 1] = d[which == j, 1]
        return a, b, c, d
    if kind == "tilted-small":  # the same far down (differences near 2**-200, permanents below 2**-600)
        return tuple(x * 2.0**-200 for x in rows3("tilted-axis", k, seed))
    if kind == "one-inexact":  # a permuted unit matrix with one entry made an inexact difference
        rows = []
        for perm in ([0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [2, 1, 0], [1, 0, 2]):
            for pos in range(9):
                m = np.eye(3)[perm] * [1.0, 2.0, 4.0]
                m[pos // 3, pos % 3] = np.nan  # replaced below: 0.1 - 1 (rounded) or 3 * 0.1 (rounded)
                rows.append((m, pos))
        out = np.zeros((4, len(rows), 3))
        for j, (m, pos) in enumerate(rows):
            d = np.ones(3)
            pts = d + np.nan_to_num(m, nan=0.0)
            pts[pos // 3, pos % 3] = 0.1 if j % 2 else 1.0 + 0.1 * 3  # a difference -0.9 or 0.3, both rounded
            out[:3, j], out[3, j] = pts, d
        return tuple(out[i] for i in range(4))
    raise ValueError(kind)


#: Difference magnitudes just inside and just outside the double-double range [2**-300, 2**300], and far out.
_EDGES = [2.0**-300, 2.0**300, 2.0**-301, 2.0**301, 2.0**-400, 2.0**400]

KINDS3 = ["lattice", "tilted", "jitter", "flat", "subnormal", "tiny", "huge", "wide", "tilted-axis",
          "tilted-small", "one-inexact"]


def rows2(kind: str, k: int = 96, seed: int = 0) -> tuple[np.ndarray, ...]:
    """k rows (a, b, c) of one kind of hard orient2d input."""
    rng = np.random.default_rng(seed)
    if kind == "lattice":
        a, b = (rng.integers(-8, 9, (k, 2)) * 0.125 for _ in range(2))
        c = a + rng.integers(-3, 4, (k, 1)) * (b - a)
        c[::2] = rng.integers(-8, 9, (k - k // 2, 2)) * 0.125
        return a, b, c
    if kind == "tilted":  # on y = x, half nudged off
        a, b, c = (np.repeat(rng.random((k, 1)), 2, axis=1) for _ in range(3))
        c[::2, 1] = _ulps(c[::2, 1], rng.integers(-2, 3, k - k // 2))
        return a, b, c
    if kind == "jitter":
        a, b = (rng.random((k, 2)) * 10 for _ in range(2))
        c = a + rng.random((k, 1)) * (b - a)
        return a, b, _ulps(c, rng.integers(-2, 3, c.shape))
    if kind == "subnormal":
        a, b = (rng.integers(-8, 9, (k, 2)) * 5e-324 for _ in range(2))
        return a, b, a + rng.integers(-1, 2, (k, 2)) * 5e-324
    if kind == "tiny":
        return tuple(x * 2.0**-540 for x in rows2("jitter", k, seed))
    if kind == "huge":
        return tuple(x * 2.0**990 for x in rows2("jitter", k, seed))
    if kind == "wide":
        a, b, c = (x.copy() for x in rows2("jitter", k, seed))
        for j in range(k):
            p, i = (a, b)[j % 4 // 2], j % 2
            c[j, i] = 0.0
            p[j, i] = (-1.0) ** j * _EDGES[j // 4 % len(_EDGES)]
        return a, b, c
    raise ValueError(kind)


KINDS2 = ["lattice", "tilted", "jitter", "subnormal", "tiny", "huge", "wide"]


def cols(*points) -> list[np.ndarray]:
    return [p[:, i] for p in points for i in range(p.shape[1])]


# --------------------------------------------------------------------------- whole predicates


@pytest.mark.parametrize("few", [0, FEW_FOR_INTEGERS], ids=["float-stages", "default"])
@pytest.mark.parametrize("kind", KINDS3)
def test_orient3d_gives_the_exact_sign_on_every_kind_of_hard_row(monkeypatch, kind, few):
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", few)
    a, b, c, d = rows3(kind)
    assert np.array_equal(orient3d(a, b, c, d), signs(exact3(a, b, c, d)))


@pytest.mark.parametrize("few", [0, FEW_FOR_INTEGERS], ids=["float-stages", "default"])
@pytest.mark.parametrize("kind", KINDS2)
def test_orient2d_gives_the_exact_sign_on_every_kind_of_hard_row(monkeypatch, kind, few):
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", few)
    a, b, c = rows2(kind)
    assert np.array_equal(orient2d(a, b, c), signs(exact2(a, b, c)))


def test_points_off_a_coordinate_plane_by_tiny_heights_through_every_stage():
    # a, b, c span the plane z = 0 with (b - a) x (c - a) = +z, so the determinant of
    # (a, b, c, d) is exactly -d_z whatever d_x, d_y: the sign is -sign(d_z) (docstring:
    # +1 when d is below the plane).  Heights far below the filter's bound leave every row
    # open; lattice abscissas are settled by the exactness check, 0.1-multiples by the
    # double-double stage, heights below its precision by integers.
    k = 3 * (FEW_FOR_INTEGERS + 1)
    rng = np.random.default_rng(5)
    xy = np.r_[rng.integers(-9, 10, (k // 3, 2)) * 1.0, rng.integers(-9, 10, (2 * k // 3, 2)) * 0.1]
    heights = rng.integers(-3, 4, k) * np.r_[np.full(2 * k // 3, 2.0**-60), np.full(k - 2 * k // 3, 2.0**-120)]
    d = np.c_[xy, heights]
    a, b, c = np.zeros(3), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    assert np.array_equal(orient3d(a, b, c, d), -np.sign(heights).astype(np.int8))


# --------------------------------------------------------------------------- the stages one by one


def _hi3(a, b, c, d) -> list[np.ndarray]:
    """The float differences (IEEE subtraction) adx, ady, adz, bdx, ..., cdz."""
    return [(p - d)[:, i] for p in (a, b, c) for i in range(3)]


def _perm3(h: list[float]) -> Fraction:
    """The permanent of the hi parts, |adz| (|bdx cdy| + |cdx bdy|) + ..., exactly."""
    adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz = (abs(Fraction(v)) for v in h)
    return adz * (bdx * cdy + cdx * bdy) + bdz * (cdx * ady + adx * cdy) + cdz * (adx * bdy + bdx * ady)


def _in_range(h: list[float]) -> bool:
    """The double-double stages' domain: every nonzero difference in [2**-300, 2**300]."""
    return all(v == 0 or 2.0**-300 <= abs(v) <= 2.0**300 for v in h)


KINDS3_DD = KINDS3 + ["small", "large"]


def _rows3_dd(kind: str) -> tuple[np.ndarray, ...]:
    if kind == "small":  # jittered rows at 2**-280: inside the double-double range
        return tuple(x * 2.0**-280 for x in rows3("jitter", seed=1))
    if kind == "large":
        return tuple(x * 2.0**280 for x in rows3("tilted", seed=1))
    return rows3(kind)


@pytest.mark.parametrize("kind", KINDS3)
def test_the_exactness_check_claims_only_exact_values_in_3d(kind):
    # "_exact_eval3: a flag saying the float value is exact": where it says so the value is
    # the exact determinant; dyadic lattices and points on one plane parallel to two axes are
    # always settled (module docstring, stage 2).
    a, b, c, d = rows3(kind)
    with np.errstate(all="ignore"):  # as _settle calls it
        value, ok = P._exact_eval3(*cols(a, b, c, d))
    exact = exact3(a, b, c, d)
    for v, o, e in zip(value.tolist(), ok.tolist(), exact):
        if o:
            assert Fraction(v) == e
    if kind == "lattice":
        assert ok.all()
    if kind == "flat":
        assert ok[1::2].all()  # every z difference is zero: the value is 0 whatever the xy-minors
        assert not value[1::2].any()


@pytest.mark.parametrize("kind", KINDS2)
def test_the_exactness_check_claims_only_exact_values_in_2d(kind):
    a, b, c = rows2(kind)
    with np.errstate(all="ignore"):
        value, ok = P._exact_eval2(*cols(a, b, c))
    exact = exact2(a, b, c)
    for v, o, e in zip(value.tolist(), ok.tolist(), exact):
        if o:
            assert Fraction(v) == e
    if kind == "lattice":
        assert ok.all()


@pytest.mark.parametrize("kind", KINDS3_DD)
def test_the_double_double_stage_is_accurate_and_decides_beyond_its_bound_in_3d(kind):
    # _dd_eval3: "orient3d to about 2**-98 of its permanent ... (bound 256 eps**2 P)", the
    # error analysis giving under 110 eps**2 P, on rows whose differences lie in the range
    # where products of three stay normal.  So: a decided row has the exact sign; every
    # in-range value is within 256 eps**2 P (+ 2**-700 for underflowed tails, + half an ulp
    # of the value: the double returned is rounded once more) of the exact determinant; a
    # row beyond twice that is decided; no row outside the range is.
    a, b, c, d = _rows3_dd(kind)
    with np.errstate(all="ignore"):
        value, decided = P._dd_eval3(*cols(a, b, c, d))
    exact = exact3(a, b, c, d)
    hi = np.stack(_hi3(a, b, c, d), axis=1).tolist()
    tol = 256 * Fraction(EPS) ** 2
    for v, dec, e, h in zip(value.tolist(), decided.tolist(), exact, hi):
        if dec:
            assert math.isfinite(v) and _sign(Fraction(v)) == _sign(e)
        if not _in_range(h):
            assert not dec
            continue
        perm = _perm3(h)
        assert abs(Fraction(v) - e) <= tol * perm + Fraction(2.0**-700) + Fraction(EPS) * abs(Fraction(v))
        if abs(e) > 2 * tol * perm + Fraction(2.0**-699):
            assert dec


def _rows2_dd(kind: str) -> tuple[np.ndarray, ...]:
    if kind == "small":
        return tuple(x * 2.0**-280 for x in rows2("jitter", seed=1))
    if kind == "large":
        return tuple(x * 2.0**280 for x in rows2("tilted", seed=1))
    return rows2(kind)


@pytest.mark.parametrize("kind", KINDS2 + ["small", "large"])
def test_the_double_double_stage_is_accurate_and_decides_beyond_its_bound_in_2d(kind):
    # _dd_eval2: error under 35 eps**2 P, rows decided beyond 128 eps**2 P (+ 2**-700), P the
    # permanent |x1 y1| + |z1 w1| of the hi parts of the differences (the returned double
    # rounded once more).  As in 3D.
    a, b, c = _rows2_dd(kind)
    with np.errstate(all="ignore"):
        value, decided = P._dd_eval2(*cols(a, b, c))
    exact = exact2(a, b, c)
    tol = 128 * Fraction(EPS) ** 2
    for v, dec, e, pa, pb, pc in zip(value.tolist(), decided.tolist(), exact, a.tolist(), b.tolist(), c.tolist()):
        if dec:
            assert math.isfinite(v) and _sign(Fraction(v)) == _sign(e)
        h = [pa[0] - pc[0], pb[1] - pc[1], pa[1] - pc[1], pb[0] - pc[0]]  # x1, y1, z1, w1 (IEEE)
        if not _in_range(h):
            assert not dec
            continue
        x1, y1, z1, w1 = (Fraction(t) for t in h)
        perm = abs(x1 * y1) + abs(z1 * w1)
        assert abs(Fraction(v) - e) <= tol * perm + Fraction(2.0**-700) + Fraction(EPS) * abs(Fraction(v))
        if abs(e) > 2 * tol * perm + Fraction(2.0**-699):
            assert dec


# --------------------------------------------------------------------------- the filters


def test_filter3_bound_is_shewchuks_constant_times_the_product_of_l1_norms():
    # o3derrboundA = (7 + 56 eps) eps (Shewchuk 1997) times the product of the rows' L1
    # norms; on these rows every norm and the determinant are exact in float.
    a, b, c, d = (np.array(p, dtype=np.float64) for p in ([[1.0, 0, 0]], [[0, 2.0, 0]], [[0, 0, 4.0]], [[0, 0, 0.0]]))
    det, errbound, noise = filter3(a, b, c, d)
    assert det.tolist() == [8.0] and _sign(Fraction(8)) == _sign(exact3(a, b, c, d)[0])
    assert Fraction(P.O3D_ERRBOUND_A) == (7 + 56 * Fraction(EPS)) * Fraction(EPS)
    assert errbound.tolist() == [P.O3D_ERRBOUND_A * 8.0]
    a2 = np.array([[3.0, 0.0]])
    det2, bound2 = filter2(a2, np.array([[0.0, 5.0]]), np.zeros((1, 2)))
    assert Fraction(P.CCW_ERRBOUND_A) == (3 + 16 * Fraction(EPS)) * Fraction(EPS)
    assert det2.tolist() == [15.0] and bound2.tolist() == [P.CCW_ERRBOUND_A * 15.0]


def _amplified(k: int = 96, seed: int = 0) -> tuple[np.ndarray, ...]:
    """Rows whose xy-products underflow while a z difference is huge: only the filter's
    underflow term (2**-1000 times the z differences) keeps the lost bits covered."""
    rng = np.random.default_rng(seed)
    a, b, c, d = (np.c_[rng.integers(-8, 9, (k, 2)) * 2.0**-540, np.zeros(k)] for _ in range(4))
    which = rng.integers(0, 3, k)
    for j, p in enumerate((a, b, c)):
        p[which == j, 2] = rng.choice([-1.0, 1.0], (which == j).sum()) * 2.0**500
    return a, b, c, d


@pytest.mark.parametrize("few", [0, FEW_FOR_INTEGERS], ids=["float-stages", "default"])
def test_orient3d_when_xy_products_underflow_under_a_huge_height(monkeypatch, few):
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", few)
    a, b, c, d = _amplified()
    exact = signs(exact3(a, b, c, d))
    assert exact.any()  # not vacuous: the lost products decide the sign
    assert np.array_equal(orient3d(a, b, c, d), exact)


@pytest.mark.parametrize("kind", KINDS3 + ["amplified"])
def test_filter3_columns_gives_filter3s_values_and_full_bound(kind):
    # filter3_columns: "The same float values as filter3 ... and the full error bound"
    # (errbound with the slack, plus the underflow term), from coordinate-major differences.
    a, b, c, d = _amplified() if kind == "amplified" else rows3(kind)
    with np.errstate(all="ignore"):
        det, errbound, noise = filter3(a, b, c, d)
        diff = np.stack([a - d, b - d, c - d]).transpose(2, 0, 1).copy()  # diff[c, i] = coord c of p_i - d
        det_c, bound_c = filter3_columns(diff)
    np.testing.assert_array_equal(det_c, det)
    np.testing.assert_array_equal(bound_c, errbound * P._SLACK + noise)
    # exact_signs3 settles every row from these: the exact signs.
    with np.errstate(all="ignore"):
        got = exact_signs3(det_c, bound_c, [a, b, c, d])
    assert got.dtype == np.int8 and np.array_equal(got, signs(exact3(a, b, c, d)))


@pytest.mark.parametrize("kind", KINDS2)
def test_filter2_columns_gives_filter2s_values_and_full_bound(kind):
    a, b, c = rows2(kind)
    with np.errstate(all="ignore"):
        det, errbound = filter2(a, b, c)
        diff = np.stack([a - c, b - c]).transpose(2, 0, 1).copy()
        det_c, bound_c = filter2_columns(diff)
    np.testing.assert_array_equal(det_c, det)
    np.testing.assert_array_equal(bound_c, errbound * P._SLACK + P._TINY)
    with np.errstate(all="ignore"):
        got = exact_signs2(det_c, bound_c, [a, b, c])
    assert got.dtype == np.int8 and np.array_equal(got, signs(exact2(a, b, c)))


def test_float_values_overflow_silently():
    # orient*_value: the float determinant, for magnitudes only: an overflow is inf (here
    # the exact values are 1e600 and 1e900, positive), never a warning (warnings are errors here).
    assert orient2d_value([0.0, 0.0], [1e300, 0.0], [0.0, 1e300]).tolist() == [math.inf]
    o, x, y, z = np.zeros(3), np.array([1e300, 0, 0]), np.array([0, 1e300, 0]), np.array([0, 0, 1e300])
    assert _sign(exact3(x, y, z, o)[0]) == 1
    assert orient3d_value(x, y, z, o).tolist() == [math.inf]


# --------------------------------------------------------------------------- sums and means


def test_sum_signs_of_small_polygons_both_ways_and_of_nothing():
    # orient2d_sum_sign with c at the first vertex: the sign of the signed area.  A triangle of
    # area 1/4 (sum of determinants 1/2, below 1), clockwise and counter-clockwise; a triangle of
    # area 2**-61, which the float sum cannot decide; no rows at all: the empty sum, 0.
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.5]])
    assert orient2d_sum_sign(tri, np.roll(tri, -1, axis=0), tri[0]) == 1
    assert orient2d_sum_sign(tri[::-1], np.roll(tri[::-1], -1, axis=0), tri[0]) == -1
    thin = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 2.0**-60]])
    far = np.array([3.7, -1.3])  # each determinant near 1, their sum 2**-60: only the exact sum can tell
    assert orient2d_sum_sign(thin, np.roll(thin, -1, axis=0), far) == 1
    assert orient2d_sum_sign(thin[::-1], np.roll(thin[::-1], -1, axis=0), far) == -1
    assert orient2d_sum_sign(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 2))) == 0
    assert orient3d_sum_sign(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))) == 0
    # A tetrahedron of volume 1/48 (sum of determinants 1/8), both orientations.
    p = np.array([[0.0, 0, 0], [0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]])
    t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert orient3d_sum_sign(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]], p[0]) == 1
    assert orient3d_sum_sign(p[t[:, 0]], p[t[:, 2]], p[t[:, 1]], p[0]) == -1


@pytest.mark.parametrize("scale", [1.0, 2.0**-20, 2.0**-1060, 2.0**1000])
def test_exact_det_sum_against_fractions(scale):
    # Rows of very different magnitudes in one sum (the per-row exponents differ).
    a, b, c, d = (x * scale for x in rows3("jitter", 24))
    a[:8] *= 2.0**-30
    want3 = sum(exact3(a, b, c, d), Fraction(0))
    assert exact_det_sum(3, [a, b, c, d]) == want3
    want2 = sum(exact2(a[:, :2], b[:, :2], d[:, :2]), Fraction(0))
    assert exact_det_sum(2, [a[:, :2], b[:, :2], d[:, :2]]) == want2
    assert exact_det_sum(3, [a[:1], b[:1], c[:1], d[:1]]) == exact3(a[:1], b[:1], c[:1], d[:1])[0]
    assert exact_det_sum(2, [np.zeros((0, 2))] * 3) == 0


@pytest.mark.parametrize("kind", ["jitter", "tilted", "lattice", "tiny"])
def test_float_det_sum_bounds_its_distance_to_the_exact_sum(kind):
    a, b, c, d = rows3(kind, 40)
    total, bound = float_det_sum(3, [a, b, c, d])
    assert abs(Fraction(total) - sum(exact3(a, b, c, d), Fraction(0))) <= Fraction(bound)
    total, bound = float_det_sum(2, [a[:, :2], b[:, :2], c[:, :2]])
    assert abs(Fraction(total) - sum(exact2(a[:, :2], b[:, :2], c[:, :2]), Fraction(0))) <= Fraction(bound)
    assert float_det_sum(3, [np.zeros((0, 3))] * 4) == (0.0, 0.0)


def test_float_det_sum_overflow_says_only_the_exact_sum_can_tell():
    a, b, c, d = rows3("huge", 8)
    total, bound = float_det_sum(3, [a * 2.0**30, b, c, d])
    assert math.isnan(total) and bound == math.inf
    # Mixed magnitudes whose float sum overflows part way.
    total, bound = sum_with_bound(np.array([1e308, 1e308, -1e308]), np.zeros(3))
    assert math.isnan(total) and bound == math.inf


def test_means_exactly_on_the_plane_are_zero_whatever_the_rounding():
    # orient3d_mean(a, b, c, ds): a, b, c on z = 0, so each determinant is -d_z times twice the
    # area of abc; the z values cancel in pairs over 100 points, so the mean is on the plane
    # exactly (0), while each float determinant is rounded (non-dyadic x, y).  Moving one point
    # by 2**-40 decides the side.
    rng = np.random.default_rng(3)
    a, b, c = np.array([0.1, 0.2, 0.0]), np.array([1.3, 0.3, 0.0]), np.array([0.4, 1.7, 0.0])
    zs = rng.random(50) * 3
    ds = [np.array([x, y, z]) for (x, y), z in zip(rng.random((100, 2)) * 5, np.r_[zs, -zs])]
    assert orient3d_mean(a, b, c, ds).tolist() == [0]
    assert _sign(_det3(*_rows_of(a, b, c, np.array([0.0, 0.0, -1.0]))[0])) == 1  # below: +1
    up = ds[:-1] + [ds[-1] + [0.0, 0.0, 2.0**-40]]
    down = ds[:-1] + [ds[-1] - [0.0, 0.0, 2.0**-40]]
    assert orient3d_mean(a, b, c, up).tolist() == [-1] and orient3d_mean(a, b, c, down).tolist() == [1]
    got = orient3d_mean(np.tile(a, (3, 1)), b, c, [np.tile(d, (3, 1)) for d in ds])
    assert got.dtype == np.int8 and got.tolist() == [0, 0, 0]
    # 2D: a, b on y = 0.3 (b to the right), so each determinant is (y - 0.3) (b_x - a_x):
    # heights cancelling in pairs around 0.3 exactly give 0.
    a2, b2 = np.array([0.1, 0.3]), np.array([2.7, 0.3])
    hs = rng.integers(1, 200, 50) * 2.0**-12  # 0.3 + h stays in [1/4, 1/2): exact
    cs = [np.array([x, 0.3 + h]) for x, h in zip(rng.random(100) * 5, np.r_[hs, -hs])]
    assert all(Fraction(cc[1]) - Fraction(0.3) == h for cc, h in zip(cs, np.r_[hs, -hs]))
    got2 = orient2d_mean(a2, b2, cs)
    assert got2.dtype == np.int8 and got2.tolist() == [0]


@pytest.mark.parametrize("m", [1, 2, 5])
def test_means_of_nearly_coplanar_points_against_fractions(m):
    # The mean of m jittered points near the plane of (a, b, c), without rounding the mean.
    a, b, c, _ = rows3("jitter", 40, seed=2)
    rng = np.random.default_rng(m)
    ds = [rows3("jitter", 40, seed=10 + j)[3] for j in range(m)]
    ds = [a + rng.random((40, 1)) * (b - a) + rng.random((40, 1)) * (c - a) for _ in range(m)]
    ds = [_ulps(x, rng.integers(-1, 2, x.shape)) for x in ds]
    want = []
    for k in range(40):
        fa, fb, fc = ([Fraction(v) for v in p[k]] for p in (a, b, c))
        fd = [sum(Fraction(x[k, i]) for x in ds) / m for i in range(3)]
        want.append(_sign(_det3(fa, fb, fc, fd)))
    assert orient3d_mean(a, b, c, ds).tolist() == want
    want2 = []
    for k in range(40):
        fa, fb = ([Fraction(v) for v in p[k, :2]] for p in (a, b))
        fd = [sum(Fraction(x[k, i]) for x in ds) / m for i in range(2)]
        want2.append(_sign(_det2(fa, fb, fd)))
    assert orient2d_mean(a[:, :2], b[:, :2], [x[:, :2] for x in ds]).tolist() == want2


# --------------------------------------------------------------------------- arguments


def test_arguments_that_do_not_broadcast_are_refused():
    with pytest.raises(ValueError, match="broadcast"):
        orient2d(np.zeros((2, 2)), np.zeros((3, 2)), np.zeros(2))
    with pytest.raises(ValueError, match=r"argument 2 must have shape \(k, 3\)"):
        orient3d(np.zeros(3), np.zeros(3), np.zeros((2, 2)), np.zeros(3))
    # One row against k rows broadcasts, in any position.
    rows = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.25, 0.5, 0.0]])
    o, x, y = np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    assert orient3d(o, x, y, rows).tolist() == [-1, 1, 0]
    assert orient3d(rows, o, x, y).tolist() == [1, -1, 0]  # a cyclic shift of four: odd, the opposite sign


def test_collinear3d_against_the_exact_cross_product():
    # Three points are collinear iff (b - a) x (c - a) = 0 exactly.  Exactly collinear lattice
    # triples, rounded points of a segment (almost never exactly on it), and the same at huge
    # coordinates where the filter overflows.
    rng = np.random.default_rng(8)
    a, b = rng.integers(-8, 9, (60, 3)) * 0.25, rng.integers(-8, 9, (60, 3)) * 0.25
    on = a + rng.integers(-3, 4, (60, 1)) * (b - a)
    p, q = rng.random((60, 3)), rng.random((60, 3))
    near = p + rng.random((60, 1)) * (q - p)
    for x, y, z in ((a, b, on), (p, q, near), (p * 1e300, q * 1e300, near * 1e300)):
        want = []
        for ra, rb, rc in _rows_of(x, y, z):
            u = [rb[i] - ra[i] for i in range(3)]
            v = [rc[i] - ra[i] for i in range(3)]
            want.append(u[1] * v[2] - u[2] * v[1] == 0 and u[2] * v[0] - u[0] * v[2] == 0 and u[0] * v[1] - u[1] * v[0] == 0)
        assert collinear3d(x, y, z).tolist() == want
    assert collinear3d(a, b, on).all() and not collinear3d(p, q, near).all()


def test_sum_with_bound_covers_the_exact_sum_of_its_terms():
    # sum_with_bound(det, err): fsum of the terms and a bound on the distance to the exact sum
    # of the values they stand for (each within its err).  Terms that cancel to a tiny sum,
    # each off by its full error, both ways.
    det = np.array([1.0, 1e-17, -1.0, 3.0, -3.0 + 2.0**-51])
    err = np.array([2.0**-50, 2.0**-100, 2.0**-50, 2.0**-49, 2.0**-49])
    total, bound = sum_with_bound(det, err)
    assert total == math.fsum(det.tolist())
    for signs_ in ([1, 1, 1, 1, 1], [-1, -1, -1, -1, -1], [1, -1, 1, -1, 1]):
        exact = sum((Fraction(x) + s * Fraction(e) for x, e, s in zip(det.tolist(), err.tolist(), signs_)), Fraction(0))
        assert abs(Fraction(total) - exact) <= Fraction(bound)
    # The bound is the sum of the errors, slightly widened, plus the rounding of the total.
    assert Fraction(bound) >= sum(Fraction(e) for e in err.tolist())
    assert bound <= 2 * math.fsum(err.tolist()) + 4 * EPS * abs(total)
    # A total that is not finite, or a bound that is not: only the exact sum can tell.
    for d_, e_ in ((np.array([math.inf, 1.0]), np.zeros(2)), (np.array([1.0]), np.array([math.inf])),
                   (np.array([math.nan]), np.zeros(1))):
        t_, b_ = sum_with_bound(d_, e_)
        assert math.isnan(t_) and b_ == math.inf
    # One row is a sum too.
    a, b, c, d = rows3("jitter", 1)
    total, bound = float_det_sum(3, [a, b, c, d])
    assert abs(Fraction(total) - exact3(a, b, c, d)[0]) <= Fraction(bound) and bound > 0


# --------------------------------------------------------------------------- rows built by hand for single stages


def test_the_exactness_check_needs_every_difference_of_a_term_exact(monkeypatch):
    # a, b, d on z = 0 (adz = bdz = 0: the first two terms are exactly 0 whatever their
    # minors), c one above d, so det = cdz (adx bdy - bdx ady) with cdz = 1.  d_x = 2**-60
    # makes adx = 1 - 2**-60 round to 1 (inexact) while bdx = 2**-58 - 2**-60 = 3 * 2**-60,
    # ady = 1 and bdy = 3 * 2**-60 are exact: the float minor is 3 * 2**-60 - 3 * 2**-60 = 0,
    # every product and sum after the differences exact, the exact minor
    # (1 - 2**-60) 3 * 2**-60 - 3 * 2**-60 = -3 * 2**-120.
    a = np.array([[1.0, 1.0, 0.0]])
    b = np.array([[2.0**-58, 3 * 2.0**-60, 0.0]])
    c = np.array([[0.0, 0.0, 1.0]])
    d = np.array([[2.0**-60, 0.0, 0.0]])
    assert exact3(a, b, c, d) == [Fraction(-3, 2**120)]
    with np.errstate(all="ignore"):
        value, ok = P._exact_eval3(*cols(a, b, c, d))
    assert value.tolist() == [0.0] and ok.tolist() == [False]
    for few in (0, FEW_FOR_INTEGERS):
        monkeypatch.setattr(P, "FEW_FOR_INTEGERS", few)
        assert orient3d(a, b, c, d).tolist() == [-1]


def test_a_double_double_value_of_zero_is_no_sign():
    # c = (1024, 1024) and a, b within 2**-44 of the origin: every difference rounds to -1024
    # (its low part is the small coordinate; 2**-44 is a tie, to even), so the hi products
    # cancel and the first-order tails -1024 (a_x + b_y) + 1024 (a_y + b_x) cancel too
    # (a_x + b_y = a_y + b_x = 5 * 2**-46): the double-double value is exactly 0.  The exact
    # determinant keeps the second-order part a_x b_y - a_y b_x = 3 * 2**-91 - 2**-90 = 2**-91 > 0.
    a = np.array([[2.0**-45, 2.0**-46]])
    b = np.array([[2.0**-44, 3 * 2.0**-46]])
    c = np.array([[1024.0, 1024.0]])
    assert exact2(a, b, c) == [Fraction(1, 2**91)]
    with np.errstate(all="ignore"):
        value, decided = P._dd_eval2(*cols(a, b, c))
    assert value.tolist() == [0.0] and decided.tolist() == [False]
    assert orient2d(a, b, c).tolist() == [1]


def test_orient2d_through_the_float_stages_returns_int8(monkeypatch):
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", 0)
    a, b, c = rows2("jitter")
    assert orient2d(a, b, c).dtype == np.int8
    assert orient3d(*rows3("jitter")).dtype == np.int8
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", FEW_FOR_INTEGERS)
    assert orient2d(a[:1], b[:1], c[:1]).dtype == np.int8 and orient3d(*(x[:1] for x in rows3("tilted"))).dtype == np.int8


def test_an_integer_determinant_of_one_unit_is_positive():
    # All six coordinates in [1, 2), so one unit is 2**-52 and the integer images are the
    # coordinates in units: differences x = y = 2**26, z = 2**26 + 1, w = 2**26 - 1 units
    # give x y - z w = 2**52 - (2**52 - 1) = 1 unit**2.  In float the products are exact
    # (2**-52 and (2**52 - 1) 2**-104) but the filter's bound 3 eps (|l| + |r|) is above their
    # difference 2**-104: the row goes to integers, whose value is exactly 1.
    u = 2.0**-52
    a = np.array([[1.0 + 2**26 * u, 1.0 + (2**26 + 1) * u]])
    b = np.array([[1.0 + (2**26 - 1) * u, 1.0 + 2**26 * u]])
    c = np.array([[1.0, 1.0]])
    assert exact2(a, b, c) == [Fraction(1, 2**104)]
    det, bound = filter2(a, b, c)
    assert det.tolist() == [2.0**-104] and not abs(det[0]) > bound[0]
    assert orient2d(a, b, c).tolist() == [1]


def test_the_mean_covers_the_rounding_of_its_float_sum():
    # orient2d((0, 0), (1, 0), (0, y)) = y exactly in float (the left product is 0 * -y), with
    # permanent |y|.  The terms M, 20 times eps M, then -(M + 8 eps M) (M = 2**20, eps = 2**-53):
    # each eps M added to M is a tie and rounds back to M (to even), so the float sum is
    # -8 eps M while the exact sum is +12 eps M: the mean is above the line.  The per-row
    # bounds alone (3 eps times the permanents, about 6 eps M) would call -8 eps M decided;
    # the summation term must cover the lost 20 eps M.
    big = 2.0**20
    ys = [big] + [EPS * big] * 20 + [-(big + 8 * EPS * big)]
    assert sum(Fraction(y) for y in ys) == 12 * Fraction(EPS) * big
    cs = [np.array([0.0, y]) for y in ys]
    assert orient2d_mean(np.zeros(2), np.array([1.0, 0.0]), cs).tolist() == [1]


def test_integer_coordinates_are_taken_as_float64():
    # n = 2**40 + 2**22 is an exact double, and so is n**2 = 2**80 + 2**63 + 2**44 (37
    # significant bits): in float64 orient2d((0, 0), (n, 0), (0, n)) = n**2 > 0 is computed
    # exactly.  In int64, n**2 wraps to 2**63 + 2**44 - 2**64 < 0 and the sign would come out
    # wrong, far beyond the filter's bound.
    n = 2**40 + 2**22
    assert exact2([0, 0], [n, 0], [0, n]) == [Fraction(n * n)]
    assert orient2d([0, 0], [n, 0], [0, n]).tolist() == [1]
    assert orient3d([0, 0, 0], [n, 0, 0], [0, n, 0], [0, 0, -1]).tolist() == [1]  # d below z = 0


#: Products A * B that are not exact doubles (a few found by a random search; their exact
#: rounding errors are checked with Fractions below), with a first factor of few bits.
_INEXACT_PRODUCTS = [
    (float.fromhex("-0x1.2067bf0000000p-23"), float.fromhex("0x1.a947edccbee92p+19")),
    (float.fromhex("-0x1.e8c61c0000000p+4"), float.fromhex("-0x1.a8308b4d44b90p+34")),
    (0.1, 0.3),
]


@pytest.mark.parametrize("A, B", _INEXACT_PRODUCTS)
def test_the_exactness_check_never_claims_a_rounded_product_exact(monkeypatch, A, B):
    # c = 0, a = (A, fl(A B)), b = (1, B): every difference is exact and the right product
    # fl(A B) * 1 too, so the float determinant is A B rounded minus itself, 0, while the
    # exact one is A B - fl(A B), the product's rounding error (not 0).
    a, b, c = np.array([[A, A * B]]), np.array([[1.0, B]]), np.zeros((1, 2))
    error = Fraction(A) * Fraction(B) - Fraction(A * B)
    assert error != 0 and exact2(a, b, c) == [error]
    with np.errstate(all="ignore"):
        value, ok = P._exact_eval2(*cols(a, b, c))
        assert not P._two_prod_exact(np.array([A]), np.array([B]), np.array([A * B]))[0]
    assert value.tolist() == [0.0] and ok.tolist() == [False]
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", 0)
    assert orient2d(a, b, c).tolist() == [_sign(error)]


#: (a, b) with c = (1024, 1024): every difference but b_x - c_x rounds to -1024 (their low
#: parts the small coordinates), b_x - c_x to -(1024 + 2**-42), so |z1 w1| > |x1 y1| by
#: 2**-32, and the first-order tails cancel that to within a few ulps of the small
#: coordinates (found by solving for b_x and searching the others).
_DD_NEAR_ZERO = [
    ("-0x1.8000000002478p-44", "0x1.ffffffffc3650p-46", "-0x1.3ffffffff9591p-43", "-0x1.fffffffffe456p-46"),
    ("-0x1.3ffffffff5f23p-44", "0x1.000000000b64ap-46", "-0x1.3ffffffff60fap-43", "-0x1.ffffffffe6a7fp-45"),
]


@pytest.mark.parametrize("row", _DD_NEAR_ZERO)
def test_a_double_double_value_within_its_error_is_left_open_whatever_the_permanents_order(monkeypatch, row):
    ax, ay, bx, by = (float.fromhex(h) for h in row)
    a, b, c = np.array([[ax, ay]]), np.array([[bx, by]]), np.array([[1024.0, 1024.0]])
    x1, y1, z1, w1 = ax - 1024.0, by - 1024.0, ay - 1024.0, bx - 1024.0
    assert (x1, y1, z1) == (-1024.0, -1024.0, -1024.0) and w1 == -(1024.0 + 2.0**-42)
    exact = exact2(a, b, c)[0]
    # Far below the stage's bound 128 eps**2 P (P about 2**21): the value may be anything
    # within its error, so the row must stay open.
    assert exact != 0 and abs(exact) < 128 * Fraction(EPS) ** 2 * 2**21
    with np.errstate(all="ignore"):
        _, decided = P._dd_eval2(*cols(a, b, c))
    assert decided.tolist() == [False]
    monkeypatch.setattr(P, "FEW_FOR_INTEGERS", 0)
    assert orient2d(a, b, c).tolist() == [_sign(exact)]
