"""``hullstress/checker/_geometry.py`` pinned where the mutation run found it loose.

Each test here was written against mutants of ``_geometry.py`` that survived
the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the
docstrings, docs/design.md's verdict semantics) or is worked out by hand in
integers or Fractions, never from the checker's own output.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker._geometry import (
    axis_extents,
    distround,
    exact_scale,
    inner_radius,
    point_line_distance,
    point_plane_distance,
)
from hullstress.checker.predicates import filter3

from _exact import frac_rows, orient_frac

# --------------------------------------------------------------------------- exact_scale


def _assert_exact_scaling(points, scaled, k):
    # "scaled == points * 2**exponent exactly": undoing the power of two gives the input back.
    assert scaled.dtype == np.float64 and scaled.shape == points.shape
    assert np.array_equal(np.ldexp(scaled, -k), points)


@pytest.mark.parametrize(
    "top", [2.0**-100, 2.0**100, 3.0, 1.0, -(2.0**100), -(2.0**-100)],
)
def test_exact_scale_leaves_the_middle_range_alone(top):
    # "Inputs whose largest magnitude is already within [2**-100, 2**100] are returned as
    # they are" (the bounds included; the largest magnitude may be a negative coordinate).
    pts = np.array([[top, 0.0], [top / 4, -top / 8]])
    scaled, k = exact_scale(pts)
    assert k == 0 and scaled is pts


def test_exact_scale_of_nothing_and_of_zeros():
    for pts in (np.zeros((0, 3)), np.zeros((3, 2))):
        scaled, k = exact_scale(pts)
        assert k == 0 and np.array_equal(scaled, pts)


@pytest.mark.parametrize(
    ("pts", "k"),
    [
        ([[1e300, 0.0], [-3e299, 1.0]], -997),  # the docstring's example
        ([[-1e300, 0.5], [2.0, 1.0]], -997),  # the largest magnitude negative
        ([[2.0**-200, 0.0], [0.0, -(2.0**-201)]], 199),  # scaled up: 2**-200 = 0.5 * 2**-199
        ([[2.0**1000, 2.0**-60]], -1001),  # 2**-1061 afterwards: subnormal but exact
    ],
)
def test_exact_scale_brings_the_largest_magnitude_to_half_one(pts, k):
    pts = np.array(pts)
    scaled, got = exact_scale(pts)
    assert got == k
    assert 0.5 <= np.abs(scaled).max() < 1.0
    _assert_exact_scaling(pts, scaled, got)


@pytest.mark.parametrize(
    "pts",
    [
        [[1e300, 1e-300]],  # 2000 binades: 1e-300 * 2**-997 underflows
        [[2.0**1000, (1 + 2.0**-52) * 2.0**-22]],  # lands in [2**-1023, 2**-1022): the last bit is lost
    ],
)
def test_exact_scale_declines_when_a_coordinate_would_round(pts):
    # "When the scaling would round a tiny coordinate ... the points are returned unscaled."
    pts = np.array(pts)
    scaled, k = exact_scale(pts)
    assert k == 0 and np.array_equal(scaled, pts)


# --------------------------------------------------------------------------- distround


def _qhull_distround(maxabs: float, maxsumcoord: float, d: int) -> float:
    # The docstring's formula: eps * (d * min(sqrt(d) * MAXabs, MAXsumcoord) * 1.01 + MAXabs).
    return 2.0**-52 * (d * min(math.sqrt(d) * maxabs, maxsumcoord) * 1.01 + maxabs)


def test_distround_follows_qhulls_formula():
    # min() takes sqrt(d) MAXabs for a centred cube, MAXsumcoord for one axis-aligned point.
    cube = np.array([[0.5, 0.5, 0.5], [-0.5, -0.5, -0.5]])
    assert distround(cube) == pytest.approx(_qhull_distround(0.5, 1.5, 3), rel=1e-12)
    assert f"{distround(cube):.3g}" == "6.94e-16"  # the docstring's example
    axis = np.array([[3.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    assert distround(axis) == pytest.approx(_qhull_distround(3.0, 4.0, 3), rel=1e-12)
    square = np.array([[-2.0, 1.0], [0.5, -4.0]])
    assert distround(square) == pytest.approx(_qhull_distround(4.0, 6.0, 2), rel=1e-12)
    # The caller's extents are taken as given.
    assert distround(square, extents=[2.0, 4.0]) == distround(square)


def test_distround_of_nothing_is_zero():
    assert distround(np.zeros((0, 3))) == 0.0
    assert distround(np.zeros((4, 2))) == 0.0
    assert axis_extents(np.zeros((0, 3))) == []


def test_distround_near_the_top_of_the_double_range_is_finite():
    # Qhull's formula is linear in the magnitude: at MAXabs 1.5e308 the sums overflow, the
    # value does not (about 1.5e308 * 2**-52 * 6.2).
    big = 1.5e308
    pts = np.array([[big, big, big], [-big, 0.0, 0.0]])
    got = distround(pts)
    assert math.isfinite(got)
    unit = math.ldexp(big, -1024)  # the formula on the magnitudes scaled by 2**-1024 (exact), then back
    assert got == pytest.approx(math.ldexp(_qhull_distround(unit, 3 * unit, 3), 1024), rel=1e-12)

# --------------------------------------------------------------------------- reporting distances


def test_point_line_distance_is_the_signed_height_over_the_segment():
    # Line (1, 0) -> (3, 0): (2, 2) is 2 to the left, (2, -3) is 3 to the right.  The
    # direction's length is |b - a| = 2, not |b + a| = 4.
    a = np.array([[1.0, 0.0], [1.0, 0.0]])
    b = np.array([[3.0, 0.0], [3.0, 0.0]])
    p = np.array([[2.0, 2.0], [2.0, -3.0]])
    assert point_line_distance(a, b, p).tolist() == [2.0, -3.0]


def test_point_line_distance_never_lets_inf_or_nan_out():
    # "For reporting": a zero-length line (0 / 0) and a height whose product with the
    # length overflows (2 * 1e308, either side) are reported as 0, never inf or NaN, and
    # silently (warnings are errors in this suite).
    a = np.array([[5.0, 5.0], [0.0, 0.0], [0.0, 0.0]])
    b = np.array([[5.0, 5.0], [2.0, 0.0], [2.0, 0.0]])
    p = np.array([[1.0, 2.0], [1.0, 1e308], [1.0, -1e308]])
    assert point_line_distance(a, b, p).tolist() == [0.0, 0.0, 0.0]


def test_point_plane_distance_is_the_signed_height_on_the_normal_side():
    # Plane of (1, 1, 1), (3, 1, 1), (1, 3, 1): normal (b - a) x (c - a) = (0, 0, 4), up.
    a, b, c = np.array([1.0, 1, 1]), np.array([3.0, 1, 1]), np.array([1.0, 3, 1])
    p = np.array([[7.0, -5.0, 3.0], [0.0, 0.0, -4.0]])
    assert point_plane_distance(a, b, c, p).tolist() == [2.0, -5.0]


def test_point_plane_distance_never_lets_inf_or_nan_out():
    # A degenerate triangle (0 / 0) and heights beyond the double range over a triangle of
    # normal length 4 (4 * 1e308 overflows, either side): 0, silently.
    a = np.array([[1.0, 1, 1], [0.0, 0, 0], [0.0, 0, 0]])
    b = np.array([[2.0, 2, 2], [2.0, 0, 0], [2.0, 0, 0]])
    c = np.array([[3.0, 3, 3], [0.0, 2, 0], [0.0, 2, 0]])
    p = np.array([[0.0, 5, 0], [0.5, 0.5, 1e308], [0.5, 0.5, -1e308]])
    assert point_plane_distance(a, b, c, p).tolist() == [0.0, 0.0, 0.0]


# --------------------------------------------------------------------------- inner_radius


def _exact_orient(rows) -> Fraction:
    """The orientation determinant of (a, b, c[, d]) in Fractions: positive when the last
    point is left of a -> b (2D) or below the plane of a counter-clockwise a, b, c (3D)."""
    *base, d = rows
    return orient_frac(frac_rows(np.asarray([d, *base])))


def _exact_distance_squared(plane, center) -> Fraction:
    """The squared distance of ``center`` from the line/plane through ``plane``'s points."""
    base = [[Fraction(float(x)) for x in r] for r in plane]
    u = [x - y for x, y in zip(base[1], base[0])]
    if len(base) == 2:
        normal = [u[1], -u[0]]
    else:
        v = [x - y for x, y in zip(base[2], base[0])]
        normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    return _exact_orient([*plane, center]) ** 2 / sum(x * x for x in normal)


def _check_inner_radius(facets, center, *, tight: float | None):
    """inner_radius of ``facets`` around ``center``, against the exact nearest plane distance."""
    facets = [np.asarray(f, dtype=np.float64) for f in facets]
    center = np.asarray(center, dtype=np.float64)
    for f in facets:  # the documented orientation: centre below (left of) every facet
        assert _exact_orient([*f, center]) > 0
    planes = [np.array([f[k] for f in facets]) for k in range(len(facets[0]))]
    r = inner_radius(planes, center)
    assert isinstance(r, float) and r >= 0.0
    nearest = min(_exact_distance_squared(f, center) for f in facets)
    assert Fraction(r) ** 2 <= nearest  # a rigorous lower bound: the ball lies below every plane
    if tight is not None:  # within the documented slack (doubled error bounds, then 1e-9)
        assert Fraction(r) ** 2 >= nearest * Fraction(1 - tight) ** 2
    return r


# The cube [1, 3]^3, one triangle per face, counter-clockwise from outside; centre (2, 2, 2).
_CUBE_FACETS = [
    [[1, 1, 3], [3, 1, 3], [3, 3, 3]],  # z = 3
    [[1, 1, 1], [1, 3, 1], [3, 3, 1]],  # z = 1
    [[3, 1, 1], [3, 3, 1], [3, 3, 3]],  # x = 3
    [[1, 1, 1], [1, 1, 3], [1, 3, 3]],  # x = 1
    [[1, 3, 1], [1, 3, 3], [3, 3, 3]],  # y = 3
    [[1, 1, 1], [3, 1, 1], [3, 1, 3]],  # y = 1
]


def test_inner_radius_of_a_cube_is_just_below_the_half_width():
    # Every face is at distance exactly 1; the bound is below 1 (never above, even by the
    # final 1e-9) and above 1 - 1e-6 (the slack is the doubled float error, ~1e-14, the
    # denominator's 1e-12 and the final 1e-9).
    r = _check_inner_radius(_CUBE_FACETS, [2, 2, 2], tight=1e-6)
    assert r < 1.0


def test_inner_radius_of_oblique_planes():
    # A tetrahedron with slanted faces (irrational distances, compared squared and exact),
    # and an axis-aligned face next to them (zero coordinates in its edge vectors).
    facets = [
        [[0, 0, 0], [0, 4, 0], [4, 0, 0]],  # z = 0, seen from below
        [[0, 0, 0], [4, 0, 0], [0, 0, 4]],
        [[0, 0, 0], [0, 0, 4], [0, 4, 0]],
        [[4, 0, 0], [0, 4, 0], [0, 0, 4]],
    ]
    _check_inner_radius(facets, [1, 1, 1], tight=1e-6)
    _check_inner_radius(facets, [0.5, 1.25, 2], tight=1e-6)


def test_inner_radius_of_a_square_in_2d():
    # The square [1, 3]^2, edges counter-clockwise, centre (2, 2): every edge at distance 1;
    # then a slanted triangle.
    square = [[[1, 1], [3, 1]], [[3, 1], [3, 3]], [[3, 3], [1, 3]], [[1, 3], [1, 1]]]
    assert _check_inner_radius(square, [2, 2], tight=1e-6) < 1.0
    triangle = [[[1, 0], [5, 1]], [[5, 1], [2, 6]], [[2, 6], [1, 0]]]
    _check_inner_radius(triangle, [2.5, 2], tight=1e-6)


@pytest.mark.parametrize("height", [2.0**-40, 2.0**-30])
def test_inner_radius_next_to_a_plane_stays_below_the_distance(height):
    # The centre just below the plane z = 0 of (0, 0, 0), (1, 0, 0), (0, 1, 0): the float
    # determinant is exact here (dyadic coordinates of few bits), its error bound is
    # ~2**-52, a large part of the determinant 2**-40: the margin subtracted from the
    # determinant (not added) keeps r below the true distance ``height``.
    facets = [[[0, 0, 0], [0, 1, 0], [1, 0, 0]]]
    r = _check_inner_radius(facets, [0.25, 0.25, height], tight=None)
    assert height / 2 < r < height
    # The same in 2D: the line y = 0 from (1, 0) to (0, 0), the centre just above it.
    r2 = _check_inner_radius([[[1, 0], [0, 0]]], [0.25, -height], tight=None)
    assert height / 2 < r2 < height


def test_inner_radius_of_a_sliver_facet_keeps_the_normals_rounding_margin():
    # A facet 6e7 long and about 0.5 wide, the centre near its short edge: the float normal
    # (b - a) x (c - a) loses about 1e-7 of its length to cancellation, far more than the
    # 1e-12 factor covers.  The margin of 8 eps on each component's terms keeps the bound
    # below the exact distance (a bound without it, or with it subtracted, lands 2e-8 above).
    facets = [[[39685897.25, 32056937.9375, 34359407.5], [0.1676, 0.4036, -0.0311], [-0.0184, 0.7114, 0.5381]]]
    _check_inner_radius(facets, [1.783, -3.2304, -0.8544], tight=1e-6)


def _documented_inner_radius_3d(a, b, c, center) -> float:
    """inner_radius of one facet by its docstring: Shewchuk's bound doubled off the float
    determinant (filter3: the value, o3derrboundA x the rows' L1 norms, the underflow
    term), over the float normal's length plus 8 eps (2**-53) of its terms' magnitudes per
    component and 2**-1000, times 1 + 1e-12; the result shrunk by a further 1e-9."""
    a, b, c, center = (np.asarray(x, dtype=np.float64) for x in (a, b, c, center))
    num, num_err, noise = (float(x[0]) for x in filter3(a[None], b[None], c[None], center[None]))
    u, v = b - a, c - a
    n = np.abs(np.cross(u, v))
    terms = [abs(u[1] * v[2]) + abs(u[2] * v[1]), abs(u[2] * v[0]) + abs(u[0] * v[2]), abs(u[0] * v[1]) + abs(u[1] * v[0])]
    up = [float(n[i]) + 8.0 * 2.0**-53 * terms[i] + 2.0**-1000 for i in range(3)]
    den = math.sqrt(up[0] ** 2 + up[1] ** 2 + up[2] ** 2) * (1.0 + 1e-12)
    return max((num - (2.0 * num_err + noise)) / den * (1.0 - 1e-9), 0.0)


@pytest.mark.parametrize(
    "facet, center",
    [
        # Thin: the centre 2**-40 below the plane, the determinant's bound ~2**-11 of it.
        ([[0, 0, 0], [0, 1, 0], [1, 0, 0]], [0.25, 0.25, 2.0**-40]),
        # The sliver above: the normal's margin ~1e-7 of its length.
        ([[39685897.25, 32056937.9375, 34359407.5], [0.1676, 0.4036, -0.0311], [-0.0184, 0.7114, 0.5381]], [1.783, -3.2304, -0.8544]),
    ],
)
def test_inner_radius_is_the_documented_bound(facet, center):
    # The margins are those of the docstring, no more (a tighter shortcut) and no less (a
    # rigorous one): within 1e-13, where one rounding more or less anywhere is ~1e-16 and
    # every margin here is 1e-12 or more of the result.
    want = _documented_inner_radius_3d(*facet, center)
    got = _check_inner_radius([facet], center, tight=None)
    assert want > 0 and got == pytest.approx(want, rel=1e-13, abs=0)


def test_inner_radius_of_planes_beyond_the_double_range_is_zero_silently():
    # Coordinates near 1e300: the float determinant and the normal overflow; the bound is
    # then 0 (no shortcut), never inf or NaN, and no overflow warning escapes.
    big = 1e300
    facets = [[[-big, -big, big], [big, -big, big], [big, big, big]]]
    assert _check_inner_radius(facets, [0.0, 0.0, 0.0], tight=None) == 0.0
    assert _check_inner_radius([[[big, -big], [big, big]]], [-big, 0.0], tight=None) == 0.0
    assert inner_radius([np.zeros((0, 3))] * 3, np.zeros(3)) == 0.0
