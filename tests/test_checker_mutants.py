"""The checker's verdict-deciding helpers, pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/`` that
survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstrings, docs/design.md's verdict semantics) or from an independent exact
computation, never from the checker's own output.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker.convexity3d import _outside_magnitude
from hullstress.checker.extreme import Coordinates, exact_extreme_2d, first_of_each, rows_in
from hullstress.checker.polygon2d import check_polygon2d, self_intersections
from hullstress.checker.rank import affine_rank, witness_simplex
from hullstress.checker.severity import ROUNDOFF_MULTIPLE, relative_magnitudes, severity

# --------------------------------------------------------------------------- severity.py


def test_relative_magnitudes_of_a_zero_unit():
    # DISTround 0 (an input of zeros): a positive distance is infinitely many units,
    # a zero distance (a degenerate face without one) stays 0, never 0/0.
    assert relative_magnitudes({"outside": 1e-300, "degenerate": 0.0}, 0.0) == {"outside": math.inf, "degenerate": 0.0}


def test_relative_magnitudes_of_non_finite_distances():
    # An overflowed distance (inf, or NaN from inf - inf) is an infinite violation, never
    # a NaN that every comparison would let through as "not beyond".
    got = relative_magnitudes({"inf": math.inf, "nan": math.nan, "negative": -1.0}, 1e-16)
    assert got == {"inf": math.inf, "nan": math.inf, "negative": 0.0}


@pytest.mark.parametrize(
    ("relative", "failed", "topological", "want"),
    [
        ({"outside": ROUNDOFF_MULTIPLE}, True, False, "roundoff"),  # "<= ROUNDOFF_MULTIPLE": the bound is roundoff
        ({"outside": math.nextafter(ROUNDOFF_MULTIPLE, math.inf)}, True, False, "gross"),
        ({"outside": 0.5, "reflex": 3.0}, True, False, "roundoff"),
        ({"outside": 0.5}, True, True, "gross"),  # any manifoldness failure is gross
        ({"outside": 50.0}, False, False, "none"),  # no check failed
        ({}, True, False, "roundoff"),  # a failure without a distance: magnitude 0
    ],
)
def test_severity_thresholds(relative, failed, topological, want):
    got, worst = severity(relative, failed=failed, topological=topological)
    assert got == want
    assert worst == max(relative.values(), default=0.0)


# --------------------------------------------------------------------------- rank.py


def test_witness_simplex_of_no_points_is_an_empty_index_array():
    for d in (2, 3):
        empty = witness_simplex(np.zeros((0, d)))
        assert empty.dtype == np.int64 and empty.shape == (0,)


def test_affine_rank_near_the_double_range_is_exact_and_silent():
    # Spans of 3e308 overflow to inf in the float heuristics; the rank is still exact and
    # no overflow warning escapes (warnings are errors in this suite).
    big = 1.5e308
    assert affine_rank(np.array([[-big, 0.0], [big, 0.0], [0.0, 1.0]])) == 2
    assert affine_rank(np.array([[-big, 0.0, 0.0], [big, 0.0, 0.0], [0.0, big, 0.0], [0.0, 0.0, -big]])) == 3
    assert affine_rank(np.array([[-big, -big, 0.0], [big, big, 0.0], [0.0, 0.0, 0.0]])) == 1


def _cross2(u, v) -> int:
    return u[0] * v[1] - u[1] * v[0]


def _sub(p, q):
    return tuple(a - b for a, b in zip(p, q))


@pytest.mark.parametrize("offset", [(0, 0, 0), (1000, -3000, 7000)])
def test_witness_simplex_takes_far_points_first(offset):
    # "Far points first, so the simplex is fat": the widest axis's two ends, then the
    # point farthest from their line, then (3D) the point farthest from that plane.  The
    # candidates' distances differ by large factors, so float rounding cannot reorder them;
    # the expected indices come from integer arithmetic.  The ends are not first in the
    # list, and the offset keeps them away from the origin.
    ints = [(10, 1, 0), (50, 30, 2), (90, 2, 1), (20, -5, 3), (60, 10, 45), (0, 0, 0), (100, 40, 0), (30, 20, -9),
            (70, 60, 5), (95, 37, 0)]
    pts = [tuple(a + b for a, b in zip(p, offset)) for p in ints]
    ends = {5, 6}  # x spans 100, more than y (65) or z (54); their line is oblique
    a, b = pts[5], pts[6]
    ab = _sub(b, a)
    # 2D: the largest |cross| (twice the triangle's area) with the segment between the ends.
    flat = [p[:2] for p in pts]
    area2 = [abs(_cross2(ab[:2], _sub(p, flat[5]))) for p in flat]
    k2 = area2.index(max(area2))
    assert k2 == 2
    got2 = witness_simplex(np.array(flat, dtype=np.float64)).tolist()
    assert set(got2[:2]) == ends and got2[2] == k2
    # 3D: the largest squared distance from the line, then the largest |orient3d|.
    def line2(p):
        c = np.cross(np.array(_sub(p, a), dtype=object), np.array(ab, dtype=object))
        return int(sum(x * x for x in c))

    dist = [line2(p) for p in pts]
    k3 = dist.index(max(dist))
    assert k3 == 4
    normal = np.cross(np.array(ab, dtype=object), np.array(_sub(pts[k3], a), dtype=object))
    height = [abs(int(np.dot(normal, np.array(_sub(p, a), dtype=object)))) for p in pts]
    m3 = height.index(max(height))
    assert m3 == 2
    got3 = witness_simplex(np.array(pts, dtype=np.float64)).tolist()
    assert set(got3[:2]) == ends and got3[2:] == [k3, m3]


# --------------------------------------------------------------------------- extreme.py


def test_rows_in_compares_by_value():
    table = np.array([[0.0, 1.0], [2.0, 3.0]])
    rows = np.array([[-0.0, 1.0], [2.0, 3.0], [2.0, -3.0], [1.0, 0.0]])
    assert rows_in(rows, table).tolist() == [True, True, False, False]  # -0.0 == 0.0
    assert rows_in(table, rows).tolist() == [True, True]
    for got in (rows_in(rows, table[:0]), rows_in(rows[:0], table)):
        assert got.dtype == bool and got.tolist() == [False] * len(got)
    assert rows_in(rows, table[:0]).shape == (4,) and rows_in(rows[:0], table).shape == (0,)


def test_first_of_each_keeps_the_first_index_of_each_coordinate():
    pts = np.array([[1.0, 1.0], [0.0, -0.0], [1.0, 1.0], [-0.0, 0.0], [2.0, 0.0]])
    # The first in the order of idx: (0, 0) first at 3 (-0.0 == 0.0), (1, 1) at 2; sorted.
    assert first_of_each(pts, np.array([3, 2, 1, 0, 4])).tolist() == [2, 3, 4]
    assert first_of_each(pts, np.array([4, 3])).tolist() == [3, 4]
    for none in (np.zeros(0, dtype=np.int64), []):
        empty = first_of_each(pts, none)
        assert empty.dtype == np.int64 and empty.shape == (0,)


def test_coordinates_ids_are_by_value():
    pts = np.array([[0.0, 1.0], [2.0, 3.0], [0.0, 1.0], [-0.0, 1.0], [5.0, 5.0], [2.0, -3.0]])
    ids = Coordinates(pts, np.array([0, 1, 2]), np.array([3, 5]))
    assert ids.count == 3  # (0, 1) three times, (2, 3), (2, -3); point 4 not indexed
    assert ids.distinct(np.array([0, 2, 3])) == 1
    assert ids.distinct(np.array([0, 1, 5])) == 3
    assert ids.first_of_each(np.array([3, 2, 1, 5])).tolist() == [1, 3, 5]  # first in the order given
    groups = ids.groups(np.array([1, 3]))
    assert len(groups) == 2 and groups.tolist() == sorted(groups.tolist())
    assert ids.within(np.array([0, 1, 2, 3, 5]), groups).tolist() == [True, True, True, True, False]
    assert ids.within(np.array([5]), ids.groups(np.array([5]))).tolist() == [True]
    assert ids.first_of_each([]).dtype == np.int64 and ids.first_of_each([]).shape == (0,)
    # Index arrays may be lists, and empty (the checker passes an empty extreme set).
    assert Coordinates(pts, [0, 2], []).count == 1


def test_coordinates_tell_tiny_coordinates_apart():
    # Ids are by exact value at any scale: 1e-20 and 2e-20 are different coordinates.
    pts = np.array([[1e-20, 0.0], [2e-20, 0.0], [1e-20, -0.0], [0.0, 3e-300]])
    ids = Coordinates(pts, np.arange(4))
    assert ids.count == 3
    assert ids.first_of_each(np.arange(4)).tolist() == [0, 1, 3]


@pytest.mark.parametrize("scale", [1.0, 2.0**-1000, 2.0**1000])
def test_exact_extreme_2d_collinear_and_triangle(scale):
    # Three or more distinct collinear points: the two ends; a triangle: all three, ccw
    # from the lexicographically smallest.
    line = np.array([[2.0, 2.0], [0.0, 0.0], [1.0, 1.0], [3.0, 3.0], [1.0, 1.0]]) * scale
    assert exact_extreme_2d(line).tolist() == [1, 3]
    tri = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.5, 0.25]]) * scale
    assert exact_extreme_2d(tri).tolist() == [2, 0, 1]


# --------------------------------------------------------------------------- polygon2d.py

# A square-ish heptagon with a spike that folds back onto itself: up from P3 = (4, 8) to
# P4 = (4, 12), then back down the same line.  Short fold: down to P5 = (4, 10), so edge
# 5 starts on edge 3; long fold: down to (4, 6), past P3, so edge 4 covers edge 3 and
# edge 2 ends on it.
_SPIKE = [(0, 0), (8, 0), (8, 8), (4, 8), (4, 12), None, (0, 8)]
#: Edge positions (edge i runs from vertex i to i + 1) that touch a non-adjacent edge or
#: fold back onto the next one, worked out by hand from the pictures above.
_SPIKE_BAD = {"short": {3, 4, 5}, "long": {2, 3, 4}}


def _spike(kind: str, rotate: int, scale: float, shift: float) -> tuple[np.ndarray, np.ndarray, list[int]]:
    ring = list(_SPIKE)
    ring[5] = (4, 10) if kind == "short" else (4, 6)
    pts = (np.array(ring, dtype=np.float64) + shift) * scale
    k = len(ring)
    poly = np.roll(np.arange(k), -rotate)  # position p holds vertex p + rotate
    return pts, poly, sorted((b - rotate) % k for b in _SPIKE_BAD[kind])


@pytest.mark.parametrize("rotate", range(7))
@pytest.mark.parametrize("kind", ["short", "long"])
@pytest.mark.parametrize(("scale", "shift"), [(1.0, 0.0), (1.0, 100.0), (2.0**1021, -6.0), (2.0**-1060, 3.0)])
def test_self_intersections_positions_of_a_folded_spike(kind, rotate, scale, shift):
    # Every rotation of the ring (the fold and the contacts wrap around the end), offset
    # from the origin, and at scales where coordinate differences overflow (2**1021 * 12
    # exceeds the double range: no warning may escape) or are subnormal.
    pts, poly, want = _spike(kind, rotate, scale, shift)
    assert self_intersections(pts, poly).tolist() == want


@pytest.mark.parametrize("rotate", range(4))
def test_self_intersections_of_a_bow_tie_and_a_straight_vertex(rotate):
    bow = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]]) + 7.0
    poly = np.roll(np.arange(4), -rotate)
    assert self_intersections(bow, poly).tolist() == sorted({(1 - rotate) % 4, (3 - rotate) % 4})
    # A vertex straight on along an edge (the polygon goes on, not back): no contact.
    square = np.array([[0.0, 0.0], [4.0, 0.0], [8.0, 0.0], [8.0, 8.0], [0.0, 8.0]]) - 3.0
    assert self_intersections(square, np.roll(np.arange(5), -rotate)).tolist() == []
    # The same beside an acute corner (where the neighbours lie on one side on both axes).
    tri = np.array([[0.0, 0.0], [4.0, 0.0], [8.0, 0.0], [0.0, 8.0]]) + 1.0
    assert self_intersections(tri, np.roll(np.arange(4), -rotate)).tolist() == []


def test_self_intersections_of_tiny_polygons():
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]])
    # A triangle folded flat: 0 -> 1 -> 2 turns back at 1, and 2 -> 0 -> 1 turns back at 0.
    assert self_intersections(pts, np.array([0, 1, 2])).tolist() == [0, 1, 2]
    for poly in (np.array([0, 1]), np.array([0]), np.zeros(0, dtype=np.int64)):
        got = self_intersections(pts, poly)
        assert got.dtype == np.int64 and got.shape == (0,)


def test_check_polygon2d_of_fewer_than_three_vertices():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    for poly in (np.array([0, 1]), np.array([2])):
        res = check_polygon2d(pts, poly)
        assert not res.manifold_ok and not res.convex_ok
        for reasons in (res.reasons_manifold, res.reasons_convex):
            assert reasons == [f"{len(poly)} vertices: a polygon needs at least 3"]
        assert res.bad_vertices.tolist() == list(range(len(poly)))
        assert res.turn.dtype == np.int8 and res.turn.tolist() == [0] * len(poly)
        assert res.center is None and res.wraps is None


def _strictly_left_of_every_edge(pts: np.ndarray, poly, centre) -> bool:
    """Exactly (Fractions): is ``centre`` strictly left of every edge of the ring?"""
    c = [Fraction(float(x)) for x in centre]
    ring = [[Fraction(float(x)) for x in pts[i]] for i in poly]
    for a, b in zip(ring, ring[1:] + ring[:1]):
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0:
            return False
    return True


@pytest.mark.parametrize(
    "ring",
    [
        [(0, 0), (4, 0), (4, 4), (0, 4)],
        [(0, 0), (2, 0), (4, 0), (4, 4), (0, 4)],  # a vertex straight on an edge
        [(0, 0), (1, 0), (0, 1)],
        [(0.1, 0.1), (0.7, 0.2), (0.3, 0.9)],  # inexact coordinates
    ],
)
@pytest.mark.parametrize("scale", [1.0, 2.0**-1000, 2.0**1000])
def test_check_polygon2d_convex_polygons_get_a_verified_centre(ring, scale):
    # Polygon2D.center: "a float point verified strictly left of every edge" (the
    # containment shortcut projects from it); a convex polygon always has one.
    pts = np.array(ring, dtype=np.float64) * scale
    poly = np.arange(len(ring))
    res = check_polygon2d(pts, poly)
    assert res.manifold_ok and res.convex_ok and res.wraps == 1
    assert res.center is not None and res.center.dtype == np.float64 and res.center.shape == (2,)
    assert _strictly_left_of_every_edge(pts, poly, res.center)
    assert res.flipped.tolist() == [] and res.reflex.tolist() == [] and res.magnitudes == {}


@pytest.mark.parametrize("scale", [1.0, 0.25, 2.0**-1000, 2.0**1000])
def test_check_polygon2d_clockwise_square(scale):
    # Every turn is right and the interior point is right of every edge: all four edges
    # are flipped, by about half the side (the interior point is inside the square).
    pts = np.array([[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]]) * scale
    res = check_polygon2d(pts, np.arange(4))
    assert not res.convex_ok and not res.manifold_ok
    assert res.reflex.tolist() == [0, 1, 2, 3] and res.flipped.tolist() == [0, 1, 2, 3]
    assert res.center is None
    assert "4 reflex vertices" in res.reasons_convex
    assert "4 edges with the interior point not strictly left" in res.reasons_convex
    if scale in (1.0, 0.25):
        # Magnitudes are float distances for the severity, computed on the checker's
        # power-of-two rescaled copy (check() rescales: raw coordinates near the ends of
        # the double range underflow or overflow them to 0).
        assert 0.0 < res.magnitudes["flipped"] < 4.0 * scale
        assert res.magnitudes["reflex"] == pytest.approx(4.0 * scale)  # the next corner, a side right of the edge


def test_check_polygon2d_dart_and_zero_length_edge_magnitudes():
    # A dart (0, 0), (4, 2), (0, 4), (1, 2): reflex at (1, 2), where the polygon turns
    # right; the vertices around it are 4 / sqrt(5) right of the neighbouring edge lines.
    dart = np.array([[0.0, 0.0], [4.0, 2.0], [0.0, 4.0], [1.0, 2.0]])
    res = check_polygon2d(dart, np.arange(4))
    assert res.manifold_ok and not res.convex_ok and res.reflex.tolist() == [3]
    assert res.magnitudes["reflex"] == pytest.approx(4 / math.sqrt(5))
    # Its vertex mean (1.25, 2) is strictly left of every edge: a verified centre even
    # though the polygon is not convex, and no edge is flipped.
    assert res.center is not None and _strictly_left_of_every_edge(dart, np.arange(4), res.center)
    assert res.flipped.tolist() == []
    # A repeated vertex makes a zero-length edge: a degenerate edge of magnitude 0
    # (severity.py: degenerate faces without a distance count as 0).
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [4.0, 0.0]])
    res = check_polygon2d(square, np.array([0, 1, 4, 2, 3]))
    assert res.degenerate_edges.tolist() == [1]
    assert res.flipped.tolist() == []  # a zero-length edge is degenerate, not flipped
    assert res.magnitudes["degenerate"] == 0.0
    assert "1 zero-length edges" in res.reasons_convex


_SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [4.0, 0.0]])  # point 4 is a copy of point 1


def test_check_polygon2d_repeated_index():
    # Index 1 twice (positions 1 and 3 of [0, 1, 2, 1, 3]): a repeated vertex index,
    # reported as such and not also as repeated coordinates.  Not convex (a right turn at
    # position 3), so simplicity is tested pairwise: edge 2 folds back onto edge 1, and
    # edges 0, 1 and 3 all touch at (4, 0) without being consecutive there; edge 4, from
    # (0, 4) to (0, 0), touches nothing.
    res = check_polygon2d(_SQUARE, np.array([0, 1, 2, 1, 3]))
    assert not res.manifold_ok and not res.convex_ok
    assert res.reasons_manifold == ["1 repeated vertex indices", "4 edges touching or crossing another edge"]
    assert res.bad_vertices.tolist() == [0, 1, 2, 3]


def test_check_polygon2d_repeated_coordinates():
    # Points 1 and 4 share coordinates: positions 1 and 2 of [0, 1, 4, 2, 3].  Edge 1 has
    # zero length (not convex), so simplicity is tested pairwise: edge 0 (ending at (4, 0))
    # and edge 2 (starting there) are not consecutive, and meet.
    res = check_polygon2d(_SQUARE, np.array([0, 1, 4, 2, 3]))
    assert not res.manifold_ok and not res.convex_ok
    assert res.degenerate_edges.tolist() == [1]
    assert res.reasons_manifold == ["2 vertices at repeated coordinates", "2 edges touching or crossing another edge"]
    assert res.bad_vertices.tolist() == [0, 1, 2]


# --------------------------------------------------------------------------- convexity3d.py

# A dart D, A, B, C: the vertices C and A lie right of the edge lines D -> A (by 4 / sqrt(2))
# and C -> D (by 4 / sqrt(10)); nothing else is outside an edge line.
_DART = [(1.0, 1.0), (0.0, 0.0), (4.0, 2.0), (0.0, 4.0)]


@pytest.mark.parametrize("scale", [1.0, 0.125])
def test_outside_magnitude_of_a_projected_dart(scale):
    # "Largest distance of a vertex outside an edge line"; edge 0 (D -> A) holds it.
    p2 = np.array(_DART) * scale
    assert _outside_magnitude(p2, 1) == pytest.approx(4 / math.sqrt(2) * scale)
    # The same polygon listed clockwise, with the orientation sign saying so.
    assert _outside_magnitude(p2[::-1].copy(), -1) == pytest.approx(4 / math.sqrt(2) * scale)
    # A repeated vertex (a zero-length edge, no line) adds nothing, and warns of nothing
    # (warnings are errors here).
    doubled = np.array([_DART[0], _DART[1], _DART[1], _DART[2], _DART[3]]) * scale
    assert _outside_magnitude(doubled, 1) == pytest.approx(4 / math.sqrt(2) * scale)


# --------------------------------------------------------------------------- closed_mesh.py

from scipy.spatial import ConvexHull  # noqa: E402

from hullstress.checker import certify as certify_module  # noqa: E402
from hullstress.checker import check  # noqa: E402
from hullstress.checker._geometry import exact_scale  # noqa: E402
from hullstress.checker.closed_mesh import certify_closed_mesh, certify_convex_polygon  # noqa: E402
from hullstress.contract import normalize_output  # noqa: E402


def _outward(points: np.ndarray, simplices: np.ndarray) -> list[list[int]]:
    """Qhull's triangles turned outward (the far-from-degenerate inputs below leave no doubt)."""
    centre = points.mean(axis=0)
    out = []
    for a, b, c in simplices.tolist():
        n = np.cross(points[b] - points[a], points[c] - points[a])
        out.append([a, b, c] if np.dot(n, points[a] - centre) > 0 else [a, c, b])
    return out


def _convex_hulls():
    """Convex hulls the batch should certify: 3D triangle meshes and 2D polygons, with and
    without interior points, points on the boundary, and enough of them to leave the
    batched containment test (more than 2000 point-face rows) to the general one."""
    rng = np.random.default_rng(21)
    cases = []
    for n_hull, n_inner in ((4, 0), (12, 3), (40, 1), (60, 80)):
        shell = rng.normal(size=(n_hull, 3))
        shell /= np.linalg.norm(shell, axis=1)[:, None]
        inner = rng.uniform(-0.3, 0.3, size=(n_inner, 3))
        pts = np.vstack([shell, inner])
        cases.append((f"3d-{n_hull}-{n_inner}", pts, _outward(pts, ConvexHull(shell).simplices)))
    # A cube's faces split through their centres: the centres are boundary points, not corners.
    corners = np.array([[x, y, z] for x in (0.0, 4.0) for y in (0.0, 4.0) for z in (0.0, 4.0)])
    centres = np.array([[2.0, 2.0, 0.0], [2.0, 2.0, 4.0], [2.0, 0.0, 2.0], [2.0, 4.0, 2.0], [0.0, 2.0, 2.0], [4.0, 2.0, 2.0]])
    pts = np.vstack([corners, centres, [[1.0, 1.0, 1.0]]])
    cases.append(("3d-cube-centres", pts, _outward(pts, ConvexHull(pts[:14]).simplices)))
    for n_hull, n_inner in ((3, 0), (7, 2), (30, 90)):
        ang = 2 * np.pi * (np.arange(n_hull) + rng.uniform(0, 0.3, n_hull)) / n_hull  # round: the inner points are inside
        ring = np.c_[np.cos(ang), np.sin(ang)]
        inner = rng.uniform(-0.2, 0.2, size=(n_inner, 2))
        pts = np.vstack([ring, inner])
        cases.append((f"2d-{n_hull}-{n_inner}", pts, ConvexHull(ring).vertices.tolist()))
    square = np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [1.0, 1.0]])
    cases.append(("2d-square-edge-point", square, [0, 1, 2, 3, 4]))
    # Entirely at non-positive coordinates (the wrap-number ray's length comes from the
    # largest magnitude, here that of the most negative coordinate).
    cases.append(("2d-negative-square", square - 4.0, [0, 1, 2, 3, 4]))
    # The straight vertex first, and a point on an edge that is not a vertex (boundary, allowed).
    on_edge = np.vstack([square, [[4.0, 2.0]]])
    cases.append(("2d-straight-first-edge-point", on_edge, [1, 2, 3, 4, 0]))
    # Interior points before the hull's vertices: the lowest vertex index is not 0.
    ang = 2 * np.pi * (np.arange(9) + rng.uniform(0, 0.3, 9)) / 9
    ring = np.c_[np.cos(ang), np.sin(ang)] * 3.0
    pts = np.vstack([rng.uniform(-0.5, 0.5, size=(4, 2)), ring])
    cases.append(("2d-inner-first", pts, (ConvexHull(ring).vertices + 4).tolist()))
    shell = rng.normal(size=(20, 3))
    shell /= np.linalg.norm(shell, axis=1)[:, None]
    pts = np.vstack([rng.uniform(-0.2, 0.2, size=(5, 3)), shell])
    cases.append(("3d-inner-first", pts, _outward(pts, ConvexHull(shell).simplices + 5)))
    cube = np.vstack([corners, centres, [[1.0, 1.0, 1.0]]]) - 4.0
    cases.append(("3d-negative-cube", cube, _outward(cube, ConvexHull(cube[:14]).simplices)))
    return cases


_HULLS = _convex_hulls()


@pytest.mark.parametrize(("name", "points", "faces"), _HULLS, ids=[c[0] for c in _HULLS])
def test_the_batch_certifies_convex_hulls_as_the_general_checks_do(name, points, faces, monkeypatch):
    # closed_mesh.py: "the common case ... certified in one batch"; it "builds exactly the
    # certificate the general path builds", so the verdicts must be identical field by field.
    scaled, _ = exact_scale(points)
    norm = normalize_output(faces, len(points), points.shape[1])
    batch = (certify_closed_mesh(scaled, norm) if points.shape[1] == 3 else certify_convex_polygon(scaled, norm))
    assert batch is not None and batch.certified
    general = certify_module.certify(scaled, norm, batched=False)
    for name in ("dim", "containment", "convexity", "manifoldness", "n_faces", "n_nonconvex_edges",
                 "n_degenerate_faces", "magnitudes", "reasons", "wraps", "volume"):
        assert getattr(batch, name) == getattr(general, name), name
    for name in ("hull_vertices", "extreme", "boundary_nonextreme", "outside"):
        assert np.array_equal(getattr(batch, name), getattr(general, name)), name
    assert {k: v.tolist() for k, v in batch.offending.items()} == {k: v.tolist() for k, v in general.offending.items()}
    # The witness: dim + 1 affinely independent vertices of the surface.
    w = batch.witness
    assert w.shape == (points.shape[1] + 1,) and set(w.tolist()) <= set(batch.hull_vertices.tolist())
    assert np.linalg.matrix_rank(scaled[w[1:]] - scaled[w[0]]) == points.shape[1]
    fast = check(points, faces)
    assert fast.ok and fast.severity == "none"
    monkeypatch.setattr(certify_module, "certify_closed_mesh", lambda *a, **k: None)
    monkeypatch.setattr(certify_module, "certify_convex_polygon", lambda *a, **k: None)
    full = check(points, faces, reuse_reference=False)
    assert fast == full


def _failed_corpus_entries():
    """Negative-corpus hulls with a defect that the batch applies to (a polygon, or a
    3D surface of triangles that passes the output contract)."""
    import json
    from pathlib import Path

    from hullstress.errors import ContractViolation

    out = []
    for path in sorted((Path(__file__).parent / "data" / "negative").glob("*.json")):
        for e in json.loads(path.read_text()):
            if not e["expect"]["failed"] or e.get("isolate"):
                continue
            points = np.array(e["points"], dtype=np.float64)
            try:
                faces = normalize_output(e["faces"], len(points), points.shape[1])
            except ContractViolation:  # rejected before any certificate
                continue
            if points.shape[1] == 2 or (faces.sizes == 3).all():
                out.append(pytest.param(points, faces, id=e["id"]))
    return out


@pytest.mark.parametrize(("points", "faces"), _failed_corpus_entries())
def test_the_batch_declines_every_wrong_hull_of_the_negative_corpus(points, faces):
    # The batch "only ever concludes certified": on a hull with a defect it must decline.
    scaled, _ = exact_scale(points)
    if points.shape[1] == 2:
        assert certify_convex_polygon(scaled, faces) is None
    else:
        assert certify_closed_mesh(scaled, faces) is None


from hullstress.checker.convexity3d import check_convexity3d  # noqa: E402
from hullstress.checker.topology import half_edges  # noqa: E402


def _convexity(points, faces):
    pts = np.asarray(points, dtype=np.float64)
    fs = normalize_output(faces, len(pts), 3)
    return check_convexity3d(pts, fs, half_edges(fs, len(pts)), closed=True)


# A box 4 x 4 x 4 whose top is a valley: two planar quads sloping down to the edge
# (2, 0, 3)-(2, 4, 3).  The front and back are each a convex quad and a triangle in one
# plane, so every face is a planar convex polygon and the valley edge is the one reflex edge.
_VALLEY_POINTS = [(0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 0), (0, 0, 4), (4, 0, 4), (4, 4, 4), (0, 4, 4), (2, 0, 3), (2, 4, 3)]
_VALLEY_FACES = [
    [3, 2, 1, 0],  # bottom
    [0, 4, 7, 3],  # left, x = 0
    [1, 2, 6, 5],  # right, x = 4
    [4, 8, 9, 7],  # roof, left half
    [8, 5, 6, 9],  # roof, right half
    [0, 1, 5, 8], [0, 8, 4],  # front, y = 0
    [2, 3, 7, 9], [2, 9, 6],  # back, y = 4
]


@pytest.mark.parametrize("rotate", [0, 1, 2])
def test_a_valley_between_planar_polygon_faces_is_one_reflex_edge(rotate):
    faces = [f[rotate % len(f):] + f[:rotate % len(f)] for f in _VALLEY_FACES]
    conv = _convexity(_VALLEY_POINTS, faces)
    assert not conv.ok
    assert conv.n_reflex_edges == 1 and conv.reflex_faces.tolist() == [3, 4]
    assert not conv.degenerate.any()
    assert "1 reflex edges" in conv.reasons
    # The valley's far side is 2 * 1 / sqrt(1.25) (a corner 2 across and 1 up, against a
    # slope of 1/2) above the other half's plane.
    assert conv.magnitudes["reflex"] == pytest.approx(2 / math.sqrt(1.25))
    # The sharp edges are the box's own edges and the two ridges, not the seams inside the
    # front and back (coplanar faces) and not the valley.
    sharp = {tuple(e) for e in conv.sharp_edges.tolist()}
    assert (0, 8) not in sharp and (2, 9) not in sharp and (8, 9) not in sharp
    assert {(0, 1), (4, 8), (5, 8), (7, 9), (6, 9)} <= sharp


def test_face_planes_and_degenerate_polygon_faces():
    # A pyramid over a quad whose corner (0, 4, 1) is lifted off the plane of the other
    # three: the base is not planar, by 16 / sqrt(272) (corner 0 against the plane of
    # the first fan triple 3, 2, 1); a collinear triangle face has no plane (-1).
    pts = [(0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 1), (2, 2, 4)]
    faces = [[3, 2, 1, 0], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    conv = _convexity(pts, faces)
    assert conv.degenerate.tolist() == [True, False, False, False, False]
    assert conv.plane[0].tolist() == [3, 2, 1] and conv.plane[1].tolist() == [0, 1, 4]
    assert conv.magnitudes["degenerate"] == pytest.approx(16 / math.sqrt(272))
    assert "1 degenerate faces" in conv.reasons
    # Polygon faces (a quad among them) and a collinear one: a tetrahedron's edge 0-1
    # split at its midpoint 4, with the zero-area triangle (0, 4, 1) filling the gap.
    pts = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (0, 0, 4), (2, 0, 0)]
    faces = [[0, 2, 1], [0, 4, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]]
    conv = _convexity(pts, faces)
    assert conv.plane[4].tolist() == [-1, -1, -1]
    assert conv.degenerate.tolist() == [False, False, False, False, True]
    assert conv.magnitudes["degenerate"] == 0.0


def test_the_valley_as_triangles():
    # The same surface fan-triangulated (a paired triangle mesh, the shortcut path): the
    # valley edge is still the one reflex edge, with the same magnitude.
    faces = [[f[0], f[i], f[i + 1]] for f in _VALLEY_FACES for i in range(1, len(f) - 1)]
    conv = _convexity(_VALLEY_POINTS, faces)
    assert conv.n_reflex_edges == 1 and not conv.degenerate.any()
    roof = [i for i, f in enumerate(faces) if set(f) <= {4, 5, 6, 7, 8, 9} and ({8, 9} <= set(f))]
    assert conv.reflex_faces.tolist() == roof
    assert conv.magnitudes["reflex"] == pytest.approx(2 / math.sqrt(1.25))


def test_a_collinear_triangle_has_no_plane():
    # The tetrahedron whose edge 0-1 is split at 4, the gap closed by the flat triangle (0, 1, 4).
    pts = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (0, 0, 4), (2, 0, 0)]
    faces = [[0, 2, 1], [0, 4, 3], [4, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]]
    conv = _convexity(pts, faces)
    assert conv.plane[5].tolist() == [-1, -1, -1] and conv.plane[0].tolist() == [0, 2, 1]
    assert conv.degenerate.tolist() == [False] * 5 + [True]


def test_a_star_polygon_face_is_not_convex():
    # A pyramid over a heptagon taken with step 2 (a {7/2} star): every turn of the base
    # goes the same way, but its edge directions turn around twice (x-signs change four
    # times), so the base face is not a convex polygon.
    ring = [(16, 0), (28, 6), (32, 18), (24, 30), (8, 30), (0, 18), (4, 6)]
    pts = [(x, y, 0) for x, y in ring] + [(16, 16, 24)]
    star = [(2 * i) % 7 for i in range(7)]
    faces = [star[::-1]] + [[star[i], star[(i + 1) % 7], 7] for i in range(7)]
    conv = _convexity(pts, faces)
    assert conv.degenerate[0] and not conv.degenerate[1:].any()


def _strictly_below_every_face(points, faces, centre) -> bool:
    """Exactly (Fractions): is ``centre`` strictly below the plane of every face's first
    non-collinear fan triple, outward by the right-hand rule?"""
    p = [[Fraction(float(x)) for x in q] for q in points]
    c = [Fraction(float(x)) for x in centre]

    def sub(u, v):
        return [u[0] - v[0], u[1] - v[1], u[2] - v[2]]

    def det(u, v, w):
        return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))

    for f in faces:
        a = p[f[0]]
        for i in range(1, len(f) - 1):
            u, v = sub(p[f[i]], a), sub(p[f[i + 1]], a)
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            if any(n):
                if det(u, v, sub(c, a)) >= 0:
                    return False
                break
    return True


_CUBE_POINTS = [(x, y, z) for x in (0.0, 4.0) for y in (0.0, 4.0) for z in (0.0, 4.0)]
_CUBE_FACES = [[0, 2, 6, 4], [1, 5, 7, 3], [0, 4, 5, 1], [2, 3, 7, 6], [0, 1, 3, 2], [4, 6, 7, 5]]


@pytest.mark.parametrize("triangulate", [False, True])
def test_convexity3d_centre_of_a_convex_surface(triangulate):
    # Convexity3D.center: "a float point verified (exactly) to be strictly below every
    # face"; degree: faces crossed by a ray from it (once around: 1).
    faces = _CUBE_FACES
    if triangulate:
        faces = [[f[0], f[i], f[i + 1]] for f in faces for i in range(1, len(f) - 1)]
    conv = _convexity(_CUBE_POINTS, faces)
    assert conv.ok and conv.degree == 1 and conv.flipped.tolist() == [] and conv.magnitudes == {}
    assert conv.center is not None and conv.center.dtype == np.float64
    assert _strictly_below_every_face(_CUBE_POINTS, faces, conv.center)


def test_convexity3d_centre_of_the_valley():
    # Not convex, but the vertices' mean is still strictly below every face: a verified centre.
    conv = _convexity(_VALLEY_POINTS, _VALLEY_FACES)
    assert conv.center is not None and _strictly_below_every_face(_VALLEY_POINTS, _VALLEY_FACES, conv.center)
    assert conv.flipped.tolist() == []


@pytest.mark.parametrize("size", [0.25, 4.0])
def test_an_inside_out_tetrahedron_has_every_face_flipped(size):
    pts = [(0.0, 0.0, 0.0), (size, 0.0, 0.0), (0.0, size, 0.0), (0.0, 0.0, size)]
    outward = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    conv = _convexity(pts, [f[::-1] for f in outward])
    assert conv.flipped.tolist() == [0, 1, 2, 3] and conv.center is None
    assert "4 faces with the interior point not strictly below" in conv.reasons
    # The interior point is inside the tetrahedron, so above each reversed face by less
    # than the tetrahedron's size.
    assert 0.0 < conv.magnitudes["flipped"] < size


@pytest.mark.parametrize("hole", range(12))
def test_the_batch_declines_a_cube_with_a_missing_triangle(hole):
    # Every one of the twelve triangles left out in turn: an edge without its reverse
    # (whichever end of the sorted edge keys it falls at), so not a closed mesh.
    faces = [[f[0], f[i], f[i + 1]] for f in _CUBE_FACES for i in range(1, len(f) - 1)]
    del faces[hole]
    pts = np.array(_CUBE_POINTS)
    assert certify_closed_mesh(pts, normalize_output(faces, len(pts), 3)) is None


# --------------------------------------------------------------------------- topology.py

from hullstress.checker.topology import check_topology, components  # noqa: E402
from hullstress.contract import FaceSet  # noqa: E402

_TET_POINTS = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
_TET = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def _topology(points, faces):
    fs = FaceSet.from_polygons(faces)
    return check_topology(np.asarray(points, dtype=np.float64), fs)


def test_topology_of_a_tetrahedron_both_ways():
    ok = _topology(_TET_POINTS, _TET)
    assert ok.ok and ok.reasons == [] and ok.n_edges == 6
    assert ok.bad_faces.tolist() == [] and ok.bad_vertices.tolist() == []
    inward = _topology(_TET_POINTS, [f[::-1] for f in _TET])
    assert not inward.ok and inward.reasons == ["inward orientation (signed volume negative)"] and inward.n_edges == 6
    # The same as polygon faces (the general path): a quad-free mesh given as a FaceSet of
    # polygons with one face split into a triangle fan is still a triangle mesh, so use a
    # square pyramid instead, both ways.
    pts = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (1, 1, 2)]
    pyramid = [[3, 2, 1, 0], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    ok = _topology(pts, pyramid)
    assert ok.ok and ok.n_edges == 8
    assert ok.bad_faces.dtype == np.int64 and ok.bad_vertices.dtype == np.int64
    # A flat closed surface (a square as one quad above, two triangles below): a sphere
    # by its combinatorics, of zero volume.
    flat = _topology(pts[:4], [[0, 1, 2, 3], [0, 3, 1], [1, 3, 2]])
    assert flat.reasons == ["zero signed volume"]
    inward = _topology(pts, [f[::-1] for f in pyramid])
    assert inward.reasons == ["inward orientation (signed volume negative)"]


def test_topology_of_two_tetrahedra_sharing_a_vertex():
    # Vertex 3 is shared: its link is two cycles; the two pieces meet only there
    # (V - E + F = 7 - 12 + 8 = 3).
    pts = np.vstack([_TET_POINTS, [[0.0, 0, 2], [1, 0, 2], [0, 1, 2]]])
    top = [[3, 4, 5], [3, 5, 6], [3, 6, 4], [4, 6, 5]]
    res = _topology(pts, _TET + top)
    assert not res.ok and res.n_edges == 12
    assert res.reasons == ["1 vertices whose link is not a single cycle", "2 connected pieces",
                           "Euler characteristic 3, expected 2"]
    assert res.bad_vertices.tolist() == [3] and res.bad_faces.tolist() == []
    # The same with every index shifted by 100 (unused points first): vertex 103.
    far = np.vstack([np.zeros((100, 3)), pts])
    res = _topology(far, [[v + 100 for v in f] for f in _TET + top])
    assert res.bad_vertices.tolist() == [103] and res.reasons[0] == "1 vertices whose link is not a single cycle"


def test_topology_of_two_faces_and_of_two_pieces():
    # Two triangles on the same three vertices, opposite ways round (a zero-volume
    # pillow): repeated faces (the module's docstring example), not a sphere.
    assert _topology(_TET_POINTS, [[0, 1, 2], [0, 2, 1]]).reasons == ["2 repeated faces"]
    # A tetrahedron with a hole beside a whole one: two pieces (the border edges join nothing).
    pts = np.vstack([_TET_POINTS, _TET_POINTS + 5.0])
    res = _topology(pts, _TET[:3] + [[v + 4 for v in f] for f in _TET])
    assert "2 connected pieces" in res.reasons


def test_topology_of_a_tetrahedron_with_a_hole_and_with_a_face_twice():
    # Face 3 (1, 2, 3) left out: its three edges have no opposite half-edge, in faces 0, 1, 2.
    res = _topology(_TET_POINTS, _TET[:3])
    assert res.reasons[0] == "3 edges without an opposite half-edge (border or same-direction neighbour)"
    assert res.bad_faces.tolist() == [0, 1, 2] and res.bad_vertices.tolist() == [1, 2, 3]
    assert res.bad_faces.dtype == np.int64 and res.bad_vertices.dtype == np.int64
    assert "Euler characteristic 1, expected 2" in res.reasons and res.n_edges == 6
    # The border vertices' corners still form one fan each: only the border and the
    # Euler characteristic are reported.
    assert res.reasons == ["3 edges without an opposite half-edge (border or same-direction neighbour)",
                           "Euler characteristic 1, expected 2"]
    # Face 0 twice, the same way round: its three directed edges twice (6 half-edges), so
    # their reverses in faces 1, 2 and 3 have no unique opposite, and a repeated face.
    res = _topology(_TET_POINTS, _TET + [_TET[0]])
    assert res.reasons[:3] == ["6 half-edges occur more than once in the same direction",
                               "3 edges without an opposite half-edge (border or same-direction neighbour)",
                               "2 repeated faces"]
    assert res.bad_faces.tolist() == [0, 1, 2, 3, 4] and res.bad_vertices.tolist() == [0, 1, 2]


def test_topology_of_a_face_repeating_a_vertex_and_of_no_faces():
    pts = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (1, 1, 2)]
    pyramid = [[3, 2, 1, 1, 0], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    res = _topology(pts, pyramid)
    assert res.reasons[0] == "1 faces repeat a vertex" and 0 in res.bad_faces.tolist()
    empty = check_topology(np.asarray(pts, dtype=np.float64), FaceSet.from_polygons([]))
    assert empty.ok is False and empty.reasons == ["no faces"] and empty.n_edges == 0
    for found in (empty.bad_faces, empty.bad_vertices):
        assert found.dtype == np.int64 and found.tolist() == []


def test_components_labels_by_smallest_member():
    assert components(6, np.array([5, 1, 3]), np.array([4, 0, 5])).tolist() == [0, 0, 2, 3, 3, 3]
    assert components(3, np.zeros(0, np.int64), np.zeros(0, np.int64)).tolist() == [0, 1, 2]


@pytest.mark.parametrize("n_points", [4, 2**20, 2**40])
def test_repeated_faces_are_all_copies(n_points):
    # The same vertex set in any order and orientation is a repeat; every copy is reported.
    from hullstress.checker.topology import _repeated_faces

    faces = FaceSet.from_polygons(_TET + [[1, 0, 2], [3, 1, 0]])
    assert _repeated_faces(faces, n_points, True).tolist() == [0, 1, 4, 5]
    assert _repeated_faces(FaceSet.from_polygons(_TET), n_points, True).tolist() == []
    quads = FaceSet.from_polygons([[0, 1, 2, 3], [3, 2, 1, 0], [0, 1, 3], [4, 5, 6, 7]])
    assert _repeated_faces(quads, n_points, False).tolist() == [0, 1]
    # Different vertex sets with the same sums or the same two largest vertices are not repeats.
    assert _repeated_faces(FaceSet.from_polygons([[0, 2, 4], [1, 2, 3]]), max(n_points, 5), True).tolist() == []
    mixed = FaceSet.from_polygons([[0, 2, 4], [1, 2, 4], [0, 4, 2]])
    assert _repeated_faces(mixed, max(n_points, 5), True).tolist() == [0, 2]


# --------------------------------------------------------------------------- containment.py

from hullstress.checker.containment import check_containment2d, check_containment3d  # noqa: E402
from hullstress.checker.convexity3d import face_planes  # noqa: E402


def _integer_hull3(seed: int):
    """A convex triangle mesh on integer points (multiples of 6, so edge midpoints and
    face centroids are integer points on the surface) and query points around it."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(150, 3))
    shell = np.unique(np.round(d / np.linalg.norm(d, axis=1)[:, None] * 300).astype(np.int64) * 6, axis=0)
    hull = ConvexHull(shell)
    shell = shell[hull.vertices]
    faces = np.array(_outward(shell.astype(np.float64), ConvexHull(shell).simplices))
    a, b, c = shell[faces[:, 0]], shell[faces[:, 1]], shell[faces[:, 2]]
    queries = [rng.integers(-2100, 2101, size=(3000, 3)), (a + b) // 2, (a + b + c) // 3,
               (a + b + c) // 3 + rng.integers(-1, 2, size=(len(faces), 3))]
    return shell, faces, np.vstack(queries)


def _outside_exactly(points: np.ndarray, facets: list[np.ndarray]) -> list[int]:
    """Indices strictly outside some facet (above its outward plane), in integers."""
    out = np.zeros(len(points), dtype=bool)
    if len(facets) == 3:
        a, b, c = facets
        n = np.cross(b - a, c - a)  # int64, outward
        for i in range(len(a)):
            out |= (points - a[i]) @ n[i] > 0
    else:
        a, b = facets
        for i in range(len(a)):
            e, r = b[i] - a[i], points - a[i]
            out |= e[0] * r[:, 1] - e[1] * r[:, 0] < 0  # strictly right of a ccw edge
    return np.flatnonzero(out).tolist()


@pytest.mark.parametrize("seed", [1, 2])
def test_containment3d_strategies_against_integers(seed):
    shell, faces, queries = _integer_hull3(seed)
    pts_int = np.vstack([shell, queries])
    want = _outside_exactly(pts_int, [shell[faces[:, 0]], shell[faces[:, 1]], shell[faces[:, 2]]])
    pts = pts_int.astype(np.float64)
    fs = normalize_output(faces.tolist(), len(pts), 3)
    plane = face_planes(pts, fs)
    he = half_edges(fs, len(pts))
    centre = shell.mean(axis=0).astype(np.float64)
    assert 0 < len(want) < len(queries)
    for kwargs, methods in (({"certified": True, "center": centre, "he": he}, {"cones", "cones+brute"}),
                            ({"certified": False, "center": centre}, {"brute"}),
                            ({}, {"brute"})):
        res = check_containment3d(pts, fs, plane, **kwargs)
        assert res.outside.tolist() == want, kwargs
        assert not res.ok and res.magnitude > 0 and res.method in methods
    inside = np.vstack([shell, queries[np.isin(np.arange(len(queries)), np.array(want) - len(shell), invert=True)]])
    res = check_containment3d(inside.astype(np.float64), fs, plane, certified=True, center=centre, he=he)
    assert res.ok and res.outside.tolist() == [] and res.magnitude == 0.0


@pytest.mark.parametrize("seed", [1, 2])
def test_containment2d_strategies_against_integers(seed):
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 400))
    ring = np.unique(np.round(np.c_[np.cos(ang), np.sin(ang)] * 500).astype(np.int64) * 2, axis=0)
    ring = ring[ConvexHull(ring).vertices]  # counter-clockwise
    a, b = ring, np.roll(ring, -1, axis=0)
    queries = np.vstack([rng.integers(-1100, 1101, size=(3000, 2)), (a + b) // 2,
                         (a + b) // 2 + rng.integers(-1, 2, size=(len(ring), 2))])
    pts_int = np.vstack([ring, queries])
    want = _outside_exactly(pts_int, [a, b])
    pts = pts_int.astype(np.float64)
    poly = np.arange(len(ring))
    centre = ring.mean(axis=0).astype(np.float64)
    assert 0 < len(want) < len(queries)
    for kwargs, methods in (({"certified": True, "center": centre}, {"cones", "cones+brute"}),
                            ({"certified": False, "center": centre}, {"brute"}), ({}, {"brute"})):
        res = check_containment2d(pts, poly, **kwargs)
        assert res.outside.tolist() == want, kwargs
        assert not res.ok and res.magnitude > 0 and res.method in methods


def test_a_valley_on_an_open_and_on_a_non_manifold_surface():
    # Edges that do not pair up (a face missing, or three faces on one edge) send the
    # reflex test through the sorted edge groups instead of the twins.
    # Without the bottom face: the roof halves are faces 2 and 3, the valley still reflex.
    conv = _convexity(_VALLEY_POINTS, _VALLEY_FACES[1:])
    assert conv.n_reflex_edges == 1 and conv.reflex_faces.tolist() == [2, 3]
    # The same with the valley's ends renumbered 0 and 1 (8 <-> 0, 9 <-> 1): the valley
    # edge is then the first of the sorted edges.
    swap = {0: 8, 8: 0, 1: 9, 9: 1}
    pts = [_VALLEY_POINTS[swap.get(i, i)] for i in range(len(_VALLEY_POINTS))]
    faces = [[swap.get(v, v) for v in f] for f in _VALLEY_FACES[1:]]
    conv = _convexity(pts, faces)
    assert conv.n_reflex_edges == 1 and conv.reflex_faces.tolist() == [2, 3]
    # A fin (8, 9, 10) standing on the valley edge, up to (2, 2, 6): three faces on that
    # edge.  The fin's top is above both roof planes, and the right roof's far corners are
    # on the fin plane's outer side (x > 2); the left roof's are not.  One reflex edge,
    # in the two roof halves and the fin.
    pts = _VALLEY_POINTS + [(2, 2, 6)]
    conv = _convexity(pts, _VALLEY_FACES + [[8, 9, 10]])
    assert conv.n_reflex_edges == 1 and conv.reflex_faces.tolist() == [3, 4, 9]


def _torus(offset: int) -> list[list[int]]:
    """A 3 x 3 grid triangulation of a torus (9 vertices, 27 edges, 18 faces: V - E + F = 0)."""
    def v(i, j):
        return offset + (i % 3) * 3 + (j % 3)

    faces = []
    for i in range(3):
        for j in range(3):
            faces += [[v(i, j), v(i + 1, j), v(i + 1, j + 1)], [v(i, j), v(i + 1, j + 1), v(i, j + 1)]]
    return faces


def _quick(points, faces):
    from hullstress.checker.topology import _closed_triangle_mesh

    pts = np.asarray(points, dtype=np.float64)
    fs = FaceSet.from_polygons(faces)
    return _closed_triangle_mesh(pts, fs, half_edges(fs, len(pts)), None)


def test_the_closed_triangle_mesh_shortcut_concludes_only_on_spheres():
    # "The verdict on a triangle mesh whose edges pair up exactly, when it is a sphere; else None."
    ok = _quick(_TET_POINTS, _TET)
    assert ok is not None and ok.ok and ok.n_edges == 6
    inward = _quick(_TET_POINTS, [f[::-1] for f in _TET])
    assert inward is not None and inward.reasons == ["inward orientation (signed volume negative)"]
    # A single triangle repeating a vertex pairs its own edges and has V - E + F = 2.
    for bad in ([0, 0, 1], [0, 1, 1], [1, 0, 1]):
        assert _quick(_TET_POINTS, [bad]) is None, bad
    # Two spheres (V - E + F = 4), and a sphere beside a torus (2 + 0: one number right,
    # two pieces).
    pts = np.vstack([_TET_POINTS, _TET_POINTS + 5.0, np.zeros((9, 3))])
    assert _quick(pts, _TET + [[v + 4 for v in f] for f in _TET]) is None
    assert _quick(pts, _TET + _torus(8)) is None
    # The general check names the torus's defect.
    res = _topology(pts, _TET + _torus(8))
    assert "2 connected pieces" in res.reasons and not any("Euler" in r for r in res.reasons)


@pytest.mark.parametrize("bad", [[0, 0, 1], [0, 1, 1], [1, 0, 1]])
def test_a_triangle_repeating_a_vertex_is_named(bad):
    res = _topology(_TET_POINTS, _TET + [bad])
    assert res.reasons[0] == "1 faces repeat a vertex" and 4 in res.bad_faces.tolist()
