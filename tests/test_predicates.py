"""Exact predicates against fractions.Fraction: random, degenerate, Kettner, ulp-grid, extreme magnitudes."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from hullstress.checker import (
    affine_rank,
    collinear3d,
    orient2d,
    orient2d_mean,
    orient2d_sum_sign,
    orient3d,
    orient3d_mean,
    orient3d_sum_sign,
)


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def det2(a, b, c) -> Fraction:
    a, b, c = ([Fraction(float(v)) for v in p] for p in (a, b, c))
    return (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])


def det3(a, b, c, d) -> Fraction:
    a, b, c, d = ([Fraction(float(v)) for v in p] for p in (a, b, c, d))
    m = [[a[i] - d[i] for i in range(3)], [b[i] - d[i] for i in range(3)], [c[i] - d[i] for i in range(3)]]
    return (
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    )


def ref2(a, b, c) -> np.ndarray:
    return np.array([_sign(det2(*row)) for row in zip(a, b, c)], dtype=np.int8)


def ref3(a, b, c, d) -> np.ndarray:
    return np.array([_sign(det3(*row)) for row in zip(a, b, c, d)], dtype=np.int8)


# Any finite double, including subnormals, huge values and signed zeros.
any_float = st.floats(allow_nan=False, allow_infinity=False, width=64)
# Small integers scaled by a random power of two: exact degeneracies are common.
def lattice(exp_lo: int, exp_hi: int):
    return st.builds(lambda k, e: float(np.ldexp(k, e)), st.integers(-4, 4), st.integers(exp_lo, exp_hi))


def rows(elements, dim, k=12):
    return hnp.arrays(np.float64, (k, dim), elements=elements)


@given(a=rows(any_float, 2), b=rows(any_float, 2), c=rows(any_float, 2))
def test_orient2d_any_floats(a, b, c):
    assert np.array_equal(orient2d(a, b, c), ref2(a, b, c))


@given(a=rows(any_float, 3), b=rows(any_float, 3), c=rows(any_float, 3), d=rows(any_float, 3))
def test_orient3d_any_floats(a, b, c, d):
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))


@pytest.mark.parametrize("lo,hi", [(-2, 2), (-1074, -1060), (-540, -500), (1000, 1020), (-1074, 1020)])
@given(data=st.data())
def test_orient_on_scaled_lattices(lo, hi, data):
    # Exact zeros abound; subnormal (2**-1074), tiny, huge and mixed magnitudes.
    el = lattice(lo, hi)
    a, b, c, d = (data.draw(rows(el, 3)) for _ in range(4))
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    assert np.array_equal(orient2d(a[:, :2], b[:, :2], c[:, :2]), ref2(a[:, :2], b[:, :2], c[:, :2]))


def test_exactly_collinear_and_coplanar_points():
    rng = np.random.default_rng(1)
    t = rng.integers(-1000, 1000, size=(500, 1)) * 2.0**-10
    p, q = np.array([0.25, -3.0]), np.array([1.5, 7.0])
    on_line = p + t * (q - p)  # exact: dyadic arithmetic without rounding
    assert not orient2d(p, q, on_line).any()
    bumped = on_line.copy()
    bumped[:, 1] = np.nextafter(bumped[:, 1], np.inf)
    assert np.array_equal(orient2d(p, q, bumped), ref2(np.tile(p, (500, 1)), np.tile(q, (500, 1)), bumped))
    a, b, c = np.array([0.0, 0, 1]), np.array([1.0, 0, 1]), np.array([0.0, 1, 1])
    plane = np.c_[rng.random((500, 2)), np.ones(500)]
    assert not orient3d(a, b, c, plane).any()
    plane[:, 2] = np.nextafter(1.0, 2.0)  # one ulp above: strictly above, so negative
    assert (orient3d(a, b, c, plane) == -1).all()


def test_random_general_position_against_fractions():
    rng = np.random.default_rng(7)
    a, b, c, d = (rng.normal(size=(400, 3)) for _ in range(4))
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    assert np.array_equal(orient2d(a[:, :2], b[:, :2], c[:, :2]), ref2(a[:, :2], b[:, :2], c[:, :2]))


def test_nearly_coplanar_rounded_points():
    # d = a + s (b - a) + t (c - a) in float: coplanar up to rounding, the filter's hard case.
    rng = np.random.default_rng(3)
    a, b, c = (rng.random((600, 3)) * 10 for _ in range(3))
    s, t = rng.random((600, 1)), rng.random((600, 1))
    d = a + s * (b - a) + t * (c - a)
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    # A few ulps of jitter: mostly settled by the double-double stage, never wrongly.
    d = d + rng.integers(-3, 4, d.shape) * np.spacing(d)
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    e = a[:, :2] + s * (b[:, :2] - a[:, :2])
    e = e + rng.integers(-3, 4, e.shape) * np.spacing(e)
    assert np.array_equal(orient2d(a[:, :2], b[:, :2], e), ref2(a[:, :2], b[:, :2], e))


# Kettner et al., "Classroom examples of robustness problems", orientation grids:
# p + (i u, j u), u = 2**-53, i, j in 0..255, with q and r fixed.
KETTNER_GRIDS = [
    ((0.5, 0.5), (12.0, 12.0), (24.0, 24.0)),
    ((0.50000000000002531, 0.5000000000000171), (17.300000000000001, 17.300000000000001), (24.00000000000005, 24.000000000000053)),
    ((0.5, 0.5), (8.8000000000000007, 8.8000000000000007), (12.1, 12.1)),
]


@pytest.mark.parametrize("p,q,r", KETTNER_GRIDS)
def test_kettner_orientation_grids(p, q, r):
    u = 2.0**-53
    i, j = np.meshgrid(np.arange(256), np.arange(256), indexing="ij")
    grid = np.stack([p[0] + i.ravel() * u, p[1] + j.ravel() * u], axis=1)
    got = orient2d(grid, np.array(q), np.array(r))
    # The Fraction reference on the same doubles.
    fq = [Fraction(v) for v in q]
    fr = [Fraction(v) for v in r]
    expect = np.empty(len(grid), dtype=np.int8)
    for k, (x, y) in enumerate(grid.tolist()):
        fx, fy = Fraction(x), Fraction(y)
        expect[k] = _sign((fx - fr[0]) * (fq[1] - fr[1]) - (fy - fr[1]) * (fq[0] - fr[0]))
    assert np.array_equal(got, expect)
    # The naive float formula is wrong somewhere on each grid: the test is not vacuous.
    naive = np.sign((q[0] - grid[:, 0]) * (r[1] - grid[:, 1]) - (q[1] - grid[:, 1]) * (r[0] - grid[:, 0]))
    assert (naive != expect).any()


def test_ulp_grid_around_a_plane_point():
    # 3D analogue: d walks an ulp grid around a point of the plane through a, b, c.
    a, b, c = np.array([0.1, 0.2, 0.3]), np.array([1.7, -0.4, 2.2]), np.array([-0.9, 3.1, 0.7])
    base = (a + b + c) / 3
    steps = np.arange(-6, 7)
    i, j, k = np.meshgrid(steps, steps, steps, indexing="ij")
    ulp = np.spacing(np.abs(base))
    d = base + np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) * ulp
    n = len(d)
    got = orient3d(a, b, c, d)
    assert np.array_equal(got, ref3(np.tile(a, (n, 1)), np.tile(b, (n, 1)), np.tile(c, (n, 1)), d))
    assert (got > 0).any() and (got < 0).any()


@pytest.mark.parametrize("scale", [2.0**-1060, 1e-300, 1e300, 2.0**1000])
def test_extreme_magnitudes(scale):
    rng = np.random.default_rng(11)
    a, b, c, d = (rng.normal(size=(200, 3)) * scale for _ in range(4))
    d[:50] = a[:50]  # exact zeros too
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    assert np.array_equal(orient2d(a[:, :2], b[:, :2], d[:, :2]), ref2(a[:, :2], b[:, :2], d[:, :2]))


@given(a=rows(lattice(-3, 3), 3, 6), b=rows(lattice(-3, 3), 3, 6), c=rows(lattice(-3, 3), 3, 6), ds=st.lists(rows(lattice(-3, 3), 3, 6), min_size=1, max_size=4))
def test_mean_forms_are_exact(a, b, c, ds):
    # orient3d(a, b, c, mean(ds)) without rounding the mean: compare with Fractions.
    expect = []
    for k in range(len(a)):
        fa, fb, fc = ([Fraction(float(v)) for v in p[k]] for p in (a, b, c))
        fd = [sum(Fraction(float(d[k][i])) for d in ds) / len(ds) for i in range(3)]
        m = [[fa[i] - fd[i] for i in range(3)], [fb[i] - fd[i] for i in range(3)], [fc[i] - fd[i] for i in range(3)]]
        det = (
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        )
        expect.append(_sign(det))
    assert orient3d_mean(a, b, c, ds).tolist() == expect
    expect2 = []
    for k in range(len(a)):
        fd = [sum(Fraction(float(d[k][i])) for d in ds) / len(ds) for i in range(2)]
        fa, fb = [Fraction(float(v)) for v in a[k][:2]], [Fraction(float(v)) for v in b[k][:2]]
        expect2.append(_sign((fa[0] - fd[0]) * (fb[1] - fd[1]) - (fa[1] - fd[1]) * (fb[0] - fd[0])))
    assert orient2d_mean(a[:, :2], b[:, :2], [d[:, :2] for d in ds]).tolist() == expect2


@given(a=rows(any_float, 3, 5), b=rows(any_float, 3, 5), c=rows(any_float, 3, 5), d=rows(any_float, 3, 1))
def test_sum_signs(a, b, c, d):
    total3 = sum(det3(a[k], b[k], c[k], d[0]) for k in range(len(a)))
    assert orient3d_sum_sign(a, b, c, d[0]) == _sign(total3)
    total2 = sum(det2(a[k, :2], b[k, :2], d[0, :2]) for k in range(len(a)))
    assert orient2d_sum_sign(a[:, :2], b[:, :2], d[0, :2]) == _sign(total2)


def test_collinear3d_and_affine_rank():
    line = np.array([[0.0, 0, 0], [1, 2, 3], [2, 4, 6], [-1, -2, -3]])
    assert collinear3d(line[0], line[1], line[2:]).all()
    assert affine_rank(line) == 1
    assert affine_rank(np.r_[line, [[0.0, 0, np.nextafter(0.0, 1.0)]]]) == 2  # off the line by a subnormal
    flat = np.c_[np.random.default_rng(0).random((50, 2)), np.full(50, 0.3)]
    assert affine_rank(flat) == 2
    flat[7, 2] = np.nextafter(0.3, 1.0)
    assert affine_rank(flat) == 3
    assert affine_rank(np.zeros((5, 2))) == 0
    assert affine_rank(np.zeros((0, 3))) == -1
    with pytest.raises(ValueError, match="shape"):
        affine_rank(np.zeros((3, 4)))
    with pytest.raises(ValueError, match="finite"):
        affine_rank(np.array([[0.0, np.inf]]))


def test_bad_shapes_raise():
    with pytest.raises(ValueError, match="shape"):
        orient2d(np.zeros((3, 3)), np.zeros(2), np.zeros(2))
    with pytest.raises(ValueError, match="at least one"):
        orient3d_mean(np.zeros(3), np.zeros(3), np.zeros(3), [])


@pytest.mark.parametrize("few", [0, 10**9], ids=["float-stages-first", "integers-at-once"])
@pytest.mark.parametrize("kind", ["lattice", "near-coplanar", "coincident", "subnormal"])
def test_every_path_through_the_stages_gives_the_exact_sign(monkeypatch, few, kind):
    # Rows the filter leaves open go through the exactness check and double-double stages
    # before integers, or (a few rows: FEW_FOR_INTEGERS) straight to integers.  Forced each
    # way on the same rows, both give the exact sign whatever the row count.
    import hullstress.checker.predicates as predicates

    monkeypatch.setattr(predicates, "FEW_FOR_INTEGERS", few)
    rng = np.random.default_rng(11)
    k = 40
    a, b, c = (rng.integers(-8, 9, (k, 3)) * 0.125 for _ in range(3))
    if kind == "lattice":  # exact zeros and small integers: the exactness check decides
        d = a + rng.integers(-2, 3, (k, 1)) * (b - a) + rng.integers(-2, 3, (k, 1)) * (c - a)
    elif kind == "near-coplanar":  # a few ulps off the plane: the double-double stage decides
        a, b, c = (rng.random((k, 3)) for _ in range(3))
        d = a + rng.random((k, 1)) * (b - a) + rng.random((k, 1)) * (c - a)
        d = d + rng.integers(-2, 3, d.shape) * np.spacing(d)
    elif kind == "coincident":  # two equal points: zero without any stage
        d = b.copy()
    else:  # subnormal differences: integers decide
        a, b, c = (rng.integers(-8, 9, (k, 3)) * 5e-324 for _ in range(3))
        d = a + rng.integers(-1, 2, (k, 3)) * 5e-324
    assert np.array_equal(orient3d(a, b, c, d), ref3(a, b, c, d))
    assert np.array_equal(orient2d(a[:, :2], b[:, :2], d[:, :2]), ref2(a[:, :2], b[:, :2], d[:, :2]))


def _points_against_few_planes(rng: np.random.Generator, scale: float):
    """Many points against a few planes, most left to the integer stage.

    The planes pass through random float points; the points are on them to
    within a few ulps, or exactly on them (``z = x`` planes), and the whole
    configuration is scaled by a power of two far outside the double-double
    range, so neither the exactness check nor double-double decides.
    """
    n_planes, per_plane = 6, 40
    abc = rng.random((n_planes, 3, 3))
    abc[::2, :, 2] = abc[::2, :, 0]  # every other plane is z = x: exact zeros below
    label = np.repeat(np.arange(n_planes), per_plane)
    a, b, c = (abc[label, i] for i in range(3))
    s, t = rng.random((2, len(label), 1))
    d = a + s * (b - a) + t * (c - a)
    d[label % 2 == 0, 2] = d[label % 2 == 0, 0]  # exactly on z = x
    d = d + rng.integers(-2, 3, d.shape) * np.spacing(d) * (rng.random((len(label), 1)) < 0.5)
    return [x * scale for x in (a, b, c, d)], label


@pytest.mark.parametrize("scale", [1.0, 2.0**700, 2.0**-700, 2.0**-1040])
def test_points_against_labelled_planes_share_one_exact_normal(monkeypatch, scale):
    # The labels only share work: the signs are the exact ones, with and without
    # them, and the shared integer normal is really used (not a silent fallback).
    import hullstress.checker.predicates as predicates

    used = []

    def spy(cols, labels):
        signs = shared(cols, labels)
        used.append(len(labels) if signs is not None else 0)
        return signs

    shared = predicates._int_signs3_by_plane
    monkeypatch.setattr(predicates, "_int_signs3_by_plane", spy)
    row_by_row = []  # the integer stage's rows when each row is evaluated on its own
    exact_eval, dd_eval, int_det = predicates._STAGES3
    monkeypatch.setattr(predicates, "_STAGES3",
                        (exact_eval, dd_eval, lambda *cols: row_by_row.append(len(cols[0])) or int_det(*cols)))
    rng = np.random.default_rng(3)
    (a, b, c, d), label = _points_against_few_planes(rng, scale)
    expected = ref3(a, b, c, d)
    assert {-1, 0, 1} <= set(expected.tolist()), "the input should give every sign"
    assert np.array_equal(orient3d(a, b, c, d, planes=label), expected)
    assert used and used[0] > predicates.FEW_FOR_INTEGERS, "the rows should reach the shared integer normals"
    assert not row_by_row, "with labels, no row should be left to the row-by-row integer stage"
    assert np.array_equal(orient3d(a, b, c, d), expected)
    assert sum(row_by_row) == used[0], "without labels, the same rows take the row-by-row integer stage"


def test_plane_labels_that_break_their_promise_are_ignored():
    rng = np.random.default_rng(4)
    (a, b, c, d), label = _points_against_few_planes(rng, 2.0**700)
    expected = ref3(a, b, c, d)
    wrong = label.copy()
    wrong[::7] = (wrong[::7] + 1) % 6  # some rows claim another plane's points
    assert np.array_equal(orient3d(a, b, c, d, planes=wrong), expected)
    assert np.array_equal(orient3d(a, b, c, d, planes=np.zeros(len(label), dtype=int)), expected)
    with pytest.raises(ValueError, match="planes must have shape"):
        orient3d(a, b, c, d, planes=label[:-1])
