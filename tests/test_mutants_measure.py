"""Volumes, areas and their comparison (``hullstress/checker/measure.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/measure.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: an exact sum, a recorded value that is a function of the face set
only, an exact comparison) or from an independent exact computation with
Fractions (the divergence theorem about the origin, the shoelace formula),
never from the checker's own output.
"""

from __future__ import annotations

import math
from fractions import Fraction
from itertools import permutations

import numpy as np
import pytest

from hullstress.checker.measure import (
    Measure,
    canonical_triangles,
    compare,
    measure_rows,
    rotated_to_lowest,
    surface_area,
    surface_measure,
    to_float,
    triangle_keys,
)
from hullstress.checker.predicates import exact_det_sum
from hullstress.contract import FaceSet

# --------------------------------------------------------------------------- exact references


def _det3(a, b, c) -> Fraction:
    return (
        a[0] * (b[1] * c[2] - b[2] * c[1])
        - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
    )


def exact_volume(points: np.ndarray, faces) -> Fraction:
    """The volume, by the divergence theorem about the origin (each face fanned from its first vertex), in Fractions."""
    p = [[Fraction(x) for x in row] for row in points.tolist()]
    total = Fraction(0)
    for f in faces:
        for k in range(1, len(f) - 1):
            total += _det3(p[f[0]], p[f[k]], p[f[k + 1]])
    return total / 6


def exact_area(points: np.ndarray, poly) -> Fraction:
    """The shoelace formula in Fractions."""
    p = [[Fraction(x) for x in row] for row in points.tolist()]
    n = len(poly)
    return sum((p[poly[i]][0] * p[poly[(i + 1) % n]][1] - p[poly[(i + 1) % n]][0] * p[poly[i]][1] for i in range(n)), Fraction(0)) / 2


def _sign(x) -> int:
    return (x > 0) - (x < 0)


# --------------------------------------------------------------------------- inputs


def _box(lo, hi) -> tuple[np.ndarray, list[list[int]]]:
    """An axis-parallel box as six quadrilaterals, counter-clockwise seen from outside (vertex 4x + 2y + z)."""
    pts = np.array([[(lo[0], hi[0])[v >> 2], (lo[1], hi[1])[(v >> 1) & 1], (lo[2], hi[2])[v & 1]] for v in range(8)], dtype=np.float64)
    return pts, [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def _triangulated(faces: list[list[int]]) -> list[list[int]]:
    return [[f[0], f[k], f[k + 1]] for f in faces for k in range(1, len(f) - 1)]


def _ball(n: int, seed: int) -> tuple[np.ndarray, list[list[int]]]:
    """Random points on a sphere and their hull, oriented outward by an exact test against the centroid."""
    from scipy.spatial import ConvexHull

    pts = np.random.default_rng(seed).normal(size=(n, 3))
    pts /= np.linalg.norm(pts, axis=1)[:, None]
    pts = pts * 3.0 + np.array([10.0, -20.0, 5.0])
    tri = ConvexHull(pts).simplices.tolist()
    c = [sum(Fraction(x) for x in pts[:, k]) / n for k in range(3)]
    p = [[Fraction(x) for x in row] for row in pts.tolist()]
    out = []
    for a, b, cc in tri:
        u = [p[b][k] - p[a][k] for k in range(3)]
        v = [p[cc][k] - p[a][k] for k in range(3)]
        w = [c[k] - p[a][k] for k in range(3)]
        out.append([a, b, cc] if _det3(u, v, w) < 0 else [a, cc, b])
    return pts, out


# --------------------------------------------------------------------------- the volume


@pytest.mark.parametrize("shape", ["box", "box-triangles", "ball"])
def test_volume_is_exact_and_a_function_of_the_face_set_only(shape):
    if shape == "ball":
        pts, faces = _ball(40, 3)
    else:
        pts, faces = _box((1.0, 2.0, 3.0), (4.0, 7.0, 4.5))
        if shape == "box-triangles":
            faces = _triangulated(faces)
    want = exact_volume(pts, faces)
    m = surface_measure(pts, FaceSet.from_polygons(faces))
    assert m.dim == 3 and m.denominator == 6
    assert m.exact_sum() == 6 * want
    assert m.sign == 1
    assert abs(Fraction(m.estimate) - 6 * want) <= Fraction(m.error)
    assert abs(Fraction(m.value()) - want) <= abs(want) * Fraction(2) ** -40
    if shape != "ball":
        assert m.value() == float(want) and m.estimate == 6 * want  # small integers and halves: every determinant exact
    rng = np.random.default_rng(0)
    for _ in range(3):  # another face order, every face listed from another vertex
        order = rng.permutation(len(faces))
        shuffled = [list(np.roll(faces[i], int(rng.integers(len(faces[i]))))) for i in order]
        other = surface_measure(pts, FaceSet.from_polygons(shuffled))
        assert other.value() == m.value() and other.estimate == m.estimate and other.error == m.error
    inward = surface_measure(pts, FaceSet.from_polygons([f[::-1] for f in faces]))
    assert inward.sign == -1 and inward.exact_sum() == -6 * want and inward.value() == -m.value()


def test_measure_rows_fan_each_face_from_its_lowest_vertex_against_the_lowest_vertex():
    # Module docstring: each face fanned from its lowest index, r the surface's lowest-index
    # vertex, the determinant taken as orient3d(r, b, a, c) = orient3d(a, b, c, r).
    pts, faces = _box((1.0, 2.0, 3.0), (4.0, 7.0, 4.5))
    faces = [f[1:] + f[:1] for f in faces[::-1]]  # each face listed from its second vertex
    fs = FaceSet.from_polygons(faces)
    r, b, a, c = measure_rows(pts, fs)
    assert np.array_equal(r, pts[min(min(f) for f in faces)])
    fans = []
    for f in faces:
        k = f.index(min(f))
        g = f[k:] + f[:k]
        fans += [(g[0], g[i], g[i + 1]) for i in range(1, len(g) - 1)]
    assert sorted(map(tuple, np.stack([a, b, c], axis=1).tolist())) == sorted(tuple(pts[list(t)].tolist()) for t in fans)
    assert exact_det_sum(3, [r, b, a, c]) == 6 * exact_volume(pts, faces)


def test_the_error_bound_scales_with_the_faces_not_with_the_distance_to_the_reference_vertex():
    # Module docstring: a hull of many small faces sums to within ~1e-15 of exact.
    pts, faces = _ball(400, 1)
    m = surface_measure(pts, FaceSet.from_polygons(faces))
    assert m.error <= 1e-13 * abs(m.estimate)


def test_polygon_area_is_exact_and_signed():
    sq = np.array([[0.0, 0], [3, 0], [3, 3], [0, 3]])
    ccw = surface_measure(sq, np.array([0, 1, 2, 3]))
    assert ccw.dim == 2 and ccw.denominator == 2
    assert ccw.value() == 9.0 and ccw.sign == 1 and ccw.exact_sum() == Fraction(18)
    cw = surface_measure(sq, np.array([3, 2, 1, 0]))
    assert cw.value() == -9.0 and cw.sign == -1
    # Listed from another vertex and with the lowest index elsewhere: the same numbers.
    pts = np.array([[5.0, 1.0], [1.5, 0.25], [7, 3], [2, 6], [0.5, 2]])
    for poly in ([1, 0, 2, 3, 4], [2, 3, 4, 1, 0], [4, 1, 0, 2, 3]):
        m = surface_measure(pts, np.array(poly))
        assert m.exact_sum() == 2 * exact_area(pts, poly) and m.value() == float(exact_area(pts, poly))


@pytest.mark.parametrize("dim", [2, 3])
def test_an_empty_surface_measures_zero(dim):
    if dim == 2:
        m = surface_measure(np.array([[0.0, 0], [1, 1]]), np.array([0, 1]))  # fewer than three vertices
    else:
        m = surface_measure(np.zeros((4, 3)), FaceSet(np.zeros(0, np.int64), np.zeros(1, np.int64)))
    assert (m.estimate, m.error) == (0.0, 0.0)
    assert m.sign == 0 and m.exact_sum() == 0 and m.value() == 0.0
    assert m.dim == dim and m.denominator == (6 if dim == 3 else 2)


def _triangle_rows(pts: np.ndarray) -> list:
    """The rows of surface_measure for the triangle 0, 1, 2: orient2d(p0, p_i, p_i+1) summed."""
    return [pts[0], pts[[0, 1, 2]], pts[[1, 2, 0]]]


def test_a_sliver_takes_its_sign_and_value_from_the_exact_sum():
    # Three points a rounding away from collinear, far from the origin: the float
    # determinants are mostly rounding error; sign and exact sum are exact whatever they are,
    # and the recorded value is within 2**-44 of the exact area.
    p = np.array([[1e8 + 0.1, 1e8 + 0.3], [3e8 + 0.7, 3e8 + 0.9], [2e8 + 0.4, 2e8 + 0.6]])
    for poly in ([0, 1, 2], [0, 2, 1]):
        want = exact_area(p, poly)
        assert want != 0
        m = surface_measure(p, np.array(poly))
        assert m.sign == _sign(want)
        assert m.exact_sum() == 2 * want
        assert abs(Fraction(m.estimate) - 2 * want) <= Fraction(m.error)
        assert abs(Fraction(m.value()) - want) <= abs(want) * Fraction(2) ** -43


def test_an_estimate_that_cannot_decide_leaves_sign_and_value_to_the_exact_sum():
    # Float values given (``filtered``): 2 area claimed 0.5 +- 1 (and -0.5 +- 1) where it is
    # exactly 3 (and -3): the bound allows either sign, so the exact sum gives the sign, and
    # the bound is far above 2**-44 |estimate|, so the value is the exact area rounded.
    tri = np.array([[0.0, 0], [3, 0], [0, 1]])
    ccw = Measure(2, _triangle_rows(tri), (np.array([0.0, 0.5, 0.0]), np.array([0.0, 1.0, 0.0])))
    cw = Measure(2, _triangle_rows(tri[[0, 2, 1]]), (np.array([0.0, -0.5, 0.0]), np.array([0.0, 1.0, 0.0])))
    assert (ccw.estimate, cw.estimate) == (0.5, -0.5) and ccw.error >= 1.0
    assert (ccw.sign, ccw.exact_sum(), ccw.value()) == (1, 3, 1.5)
    assert (cw.sign, cw.exact_sum(), cw.value()) == (-1, -3, -1.5)
    # A decided estimate (bound below |estimate|) keeps its own sign, and its value when accurate.
    sure = Measure(2, _triangle_rows(tri), (np.array([0.0, 3.0, 0.0]), np.array([0.0, 2.0**-60, 0.0])))
    assert (sure.sign, sure.value()) == (1, 1.5)


def test_a_volume_beyond_the_double_range_is_infinite_and_its_sign_exact():
    # A box of side 1e200: every determinant overflows (estimate nan, error inf), the exact
    # sum decides the sign, and the volume 1e600 rounds to inf.
    pts, faces = _box((-1e200, -1e200, -1e200), (1e200, 1e200, 1e200))
    m = surface_measure(pts, FaceSet.from_polygons(faces))
    assert math.isnan(m.estimate) and m.error == math.inf
    assert m.sign == 1 and m.value() == math.inf
    inward = surface_measure(pts, FaceSet.from_polygons([f[::-1] for f in faces]))
    assert inward.sign == -1 and inward.value() == -math.inf
    assert m.exact_sum() == 6 * exact_volume(pts, faces)


def test_to_float_rounds_to_nearest_and_saturates():
    assert to_float(Fraction(1, 3)) == 1 / 3
    assert to_float(Fraction(10) ** 400) == math.inf
    assert to_float(-(Fraction(10) ** 400)) == -math.inf
    assert to_float(Fraction(0)) == 0.0


def test_measure_given_its_float_values():
    # ``filtered``: the determinants' float values and bounds are taken as given.
    rows = [np.array([[0.0, 0]]), np.array([[2.0, 0]]), np.array([[0.0, 2]])]
    m = Measure(2, rows, (np.array([4.0]), np.array([0.0])))
    assert (m.estimate, m.value(), m.sign) == (4.0, 2.0, 1)
    assert Measure(2, rows).estimate == 4.0


# --------------------------------------------------------------------------- compare


def _triangle(h: float) -> Measure:
    return surface_measure(np.array([[0.0, 0], [4, 0], [0, h]]), np.array([0, 1, 2]))


def test_compare_within_and_beyond_the_tolerance():
    # Areas 2 h: 8 and 6, a difference of exactly 2.
    a, b = _triangle(4.0), _triangle(3.0)
    assert compare(a, b, 2) == (True, Fraction(2))
    assert compare(a, b, Fraction(3, 2)) == (False, Fraction(2))
    assert compare(b, a, 2.5) == (True, Fraction(2))
    assert compare(a, b, math.nextafter(2.0, 0.0)) == (False, Fraction(2))
    assert compare(a, a, 0) == (True, Fraction(0))
    same, gap = compare(a, b, 1e-300)
    assert not same and gap == 2


def test_compare_is_exact_where_the_floats_cannot_tell():
    # Two slivers whose float areas are rounding noise: the decision is the exact one, and
    # so is the difference returned whenever the floats could not decide.
    p = np.array([[1e8 + 0.1, 1e8 + 0.3], [3e8 + 0.7, 3e8 + 0.9], [2e8 + 0.4, 2e8 + 0.6]])
    one, other = surface_measure(p, np.array([0, 1, 2])), surface_measure(p, np.array([0, 2, 1]))
    gap = abs(exact_area(p, [0, 1, 2]) - exact_area(p, [0, 2, 1]))
    assert gap > 0
    assert compare(one, other, gap)[0] and not compare(one, other, gap * (1 - Fraction(1, 10**6)))[0]
    for tol in (gap, gap * (1 - Fraction(1, 10**6))):
        _, got = compare(one, other, tol)
        assert abs(got - gap) <= Fraction(one.error + other.error) / 2
    assert compare(one, one, 0) == (True, 0)


def test_compare_of_overflowed_volumes_is_exact():
    big = _box((-1e200, -1e200, -1e200), (1e200, 1e200, 1e200))
    bigger = _box((-1e200, -1e200, -1e200), (1e200, 1e200, 2e200))
    a = surface_measure(big[0], FaceSet.from_polygons(big[1]))
    b = surface_measure(bigger[0], FaceSet.from_polygons(bigger[1]))
    gap = exact_volume(*bigger) - exact_volume(*big)
    assert compare(a, b, gap) == (True, gap)
    assert compare(a, b, gap / 2) == (False, gap)
    assert compare(a, a, 0) == (True, 0)


# --------------------------------------------------------------------------- surface_area


def test_surface_area_and_perimeter():
    assert surface_area(np.array([[0.0, 0], [3, 0], [3, 4]]), np.array([0, 1, 2])) == 12.0
    pts, faces = _box((1.0, 2.0, 3.0), (4.0, 7.0, 4.5))  # 3 x 5 x 1.5
    want = 2 * (3 * 5 + 3 * 1.5 + 5 * 1.5)
    assert surface_area(pts, FaceSet.from_polygons(faces)) == want
    assert surface_area(pts, FaceSet.from_polygons(_triangulated(faces))) == want
    assert surface_area(pts, FaceSet.from_polygons([f[::-1] for f in faces])) == want  # unsigned


def test_surface_area_overflows_to_inf_silently():
    pts, faces = _box((-1e200, -1e200, -1e200), (1e200, 1e200, 1e200))
    assert surface_area(pts, FaceSet.from_polygons(faces)) == math.inf
    assert surface_area(np.array([[-1e308, 0], [1e308, 0], [0, 1e308]]), np.array([0, 1, 2])) == math.inf


# --------------------------------------------------------------------------- face keys and rotations


def _smallest_rotation(t):
    return min(tuple(t[k:]) + tuple(t[:k]) for k in range(len(t)))


def test_triangle_keys_and_canonical_triangles():
    n = 10
    tri = np.array([[3, 1, 2], [1, 2, 3], [2, 3, 1], [3, 2, 1], [7, 7, 2], [2, 7, 7], [7, 2, 7], [0, 9, 5], [9, 0, 0]])
    keys = triangle_keys(tri, n)
    want = [_smallest_rotation(t) for t in tri.tolist()]
    assert keys.tolist() == [(a * n + b) * n + c for a, b, c in want]
    out, key2 = canonical_triangles(tri, n)
    assert out.tolist() == [list(t) for t in want] and np.array_equal(key2, keys)
    assert keys[0] == keys[1] == keys[2] != keys[3]  # rotations share a key, the reverse does not


@pytest.mark.parametrize("offset", [0, 2**21, 2**40])
def test_rotated_to_lowest_triangles(offset):
    # Below 2**21 vertices through the integer keys, above by comparisons: the same rotation.
    tri = np.array([[5, 2, 7], [2, 7, 5], [7, 5, 2], [4, 3, 9], [6, 8, 1], [3, 3, 8], [8, 3, 3]]) + offset
    got = rotated_to_lowest(FaceSet.from_triangles(tri)).to_python()
    assert got == [list(_smallest_rotation(t)) for t in tri.tolist()]
    already = FaceSet.from_triangles([[1, 5, 3], [2, 4, 9]])
    assert rotated_to_lowest(already) is already  # already so: returned as it is
    # Every face starts below its second vertex, not every one below its third.
    got = rotated_to_lowest(FaceSet.from_triangles(np.array([[1, 5, 0], [2, 3, 4]]) + offset)).to_python()
    assert got == (np.array([[0, 1, 5], [2, 3, 4]]) + offset).tolist()


@pytest.mark.parametrize("top", [9, 2**21 - 2, 2**21 + 9, 2**40])
def test_rotated_to_lowest_of_a_triangle_repeating_its_lowest_index(top):
    # (X, Y, X) starts at the occurrence giving the smallest sequence, (X, X, Y), whether or
    # not the other faces start at their lowest index already, below 2**21 vertices (through
    # the integer keys) and above (by comparisons).
    base = top - 9
    tri = np.array([[3, 8, 3], [1, 2, 9]]) + base
    got = rotated_to_lowest(FaceSet.from_triangles(tri)).to_python()
    assert got == [[3 + base, 3 + base, 8 + base], [1 + base, 2 + base, 9 + base]]


def test_rotated_to_lowest_polygons():
    faces = FaceSet.from_polygons([[9, 8, 3, 4], [5, 2, 7], [6, 1, 6, 1, 0], [4, 2, 5, 2], [3, 0, 1, 2, 0]])
    # The first occurrence of a repeated lowest index, orientation kept.
    assert rotated_to_lowest(faces).to_python() == [[3, 4, 9, 8], [2, 7, 5], [0, 6, 1, 6, 1], [2, 5, 2, 4], [0, 1, 2, 0, 3]]
    empty = FaceSet(np.zeros(0, np.int64), np.zeros(1, np.int64))
    assert rotated_to_lowest(empty) is empty


def test_volume_is_the_same_for_every_listing_of_a_mixed_surface():
    # Quadrilaterals and triangles: every rotation of every face gives the same exact sum.
    pts, faces = _box((0.5, 0.25, 0.125), (3.5, 2.25, 1.125))
    faces = faces[:3] + _triangulated(faces[3:])
    want = exact_volume(pts, faces)
    for shift in range(4):
        rolled = [f[shift % len(f):] + f[: shift % len(f)] for f in faces]
        for order in list(permutations(range(3)))[:2]:
            listed = [rolled[i] for i in order] + rolled[3:]
            m = surface_measure(pts, FaceSet.from_polygons(listed))
            assert m.exact_sum() == 6 * want and m.value() == float(want)


def test_compare_does_not_trust_equal_estimates_with_wide_bounds():
    # Float values given (``filtered``): a triangle of area 1.5 claimed as 2 +- 1, against one
    # of area 2 whose claim 2 is exact.  The floats agree exactly, the exact areas differ by
    # 0.5; in either order only the exact values may decide.
    wide = Measure(2, _triangle_rows(np.array([[0.0, 0], [3, 0], [0, 1]])), (np.array([0.0, 4.0, 0.0]), np.array([0.0, 1.0, 0.0])))
    exact = Measure(2, _triangle_rows(np.array([[0.0, 0], [4, 0], [0, 1]])), (np.array([0.0, 4.0, 0.0]), np.array([0.0, 0.0, 0.0])))
    assert wide.estimate == exact.estimate == 4.0 and (wide.exact_sum(), exact.exact_sum()) == (3, 4)
    for a, b in ((wide, exact), (exact, wide)):
        assert compare(a, b, Fraction(1, 4)) == (False, Fraction(1, 2))
        assert compare(a, b, Fraction(1, 2)) == (True, Fraction(1, 2))  # the floats show only |gap| <= 1


def test_compare_where_the_float_difference_overflows():
    # A square of area about 5.4e307 and the same square clockwise: each estimate fits
    # (twice the area, 1.1e308), their difference is beyond the doubles (silently: warnings
    # are errors here); the exact values decide.
    side = 1.1 * 2.0**511
    sq = np.array([[0.0, 0], [side, 0], [side, side], [0, side]])
    ccw, cw = surface_measure(sq, np.arange(4)), surface_measure(sq, np.arange(4)[::-1])
    area = Fraction(side) ** 2
    assert compare(ccw, cw, 2 * area) == (True, 2 * area)
    assert compare(ccw, cw, area) == (False, 2 * area)


def test_perimeter_of_a_quadrilateral_is_the_sum_of_its_sides():
    # Sides 5, 5, 5, 5 of a rhombus; its diagonals (8 and 6) must not enter.
    rhombus = np.array([[0.0, 0], [4, 3], [8, 0], [4, -3]])
    assert surface_area(rhombus, np.array([0, 3, 2, 1])) == 20.0


def test_compare_lets_accurate_estimates_decide_and_returns_their_difference():
    # Module docstring: the float estimates decide when their error bounds show the
    # difference within the tolerance, and the difference returned is then theirs.  A
    # triangle with legs 0.1 and 0.3 (not exact in binary: its float determinant is rounded)
    # against an empty surface: a tolerance 10 or 1 + 1e-9 times the difference is decided
    # by the floats, so the returned gap is the estimate's, not the (different) exact one.
    tri = surface_measure(np.array([[0.0, 0], [0.1, 0], [0, 0.3]]), np.array([0, 1, 2]))
    empty = surface_measure(np.array([[0.0, 0], [1, 1]]), np.array([0, 1]))
    float_gap = Fraction(tri.estimate) / 2
    exact_gap = tri.exact_sum() / 2
    assert exact_gap == Fraction(0.1) * Fraction(0.3) / 2 != float_gap
    for tol in (10 * float_gap, float_gap * (1 + Fraction(1, 10**9))):
        assert compare(tri, empty, tol) == (True, float_gap)
        assert compare(empty, tri, tol) == (True, float_gap)
