"""3D convexity (``hullstress/checker/convexity3d.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/convexity3d.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring, docs/design.md's verdict semantics) or from an independent exact
computation in integers or Fractions, never from the checker's own output.

The interior point of a surface that is not certified by its vertex mean is
"the exact centroid of a non-degenerate simplex of the surface's own
vertices" (module docstring), the witness simplex of :mod:`.rank`: "far points
first", the two ends of the widest axis, the vertex farthest from their line,
then the one farthest from that plane.  ``_far_points_first`` below works that
choice out in integers, on inputs where no two candidates tie.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker.convexity3d import check_convexity3d
from hullstress.checker.topology import half_edges
from hullstress.contract import FaceSet

from _exact import winding_number as _winding

_CUBE = np.array([[2 * (v >> 2) - 1, 2 * ((v >> 1) & 1) - 1, 2 * (v & 1) - 1] for v in range(8)], dtype=np.float64)
#: Vertex v = 4x + 2y + z (bits), each quadrilateral counter-clockwise seen from outside.
_CUBE_QUADS = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def _check(points, faces, *, closed: bool = True):
    pts = np.asarray(points, dtype=np.float64)
    fs = FaceSet.from_polygons([list(f) for f in faces])
    return check_convexity3d(pts, fs, half_edges(fs, len(pts)), closed=closed)


def test_the_cube_of_quadrilaterals_is_convex_with_twelve_sharp_edges():
    faces = FaceSet.from_polygons(_CUBE_QUADS)
    res = check_convexity3d(_CUBE, faces, half_edges(faces, 8), closed=True)
    assert res.ok and res.degree == 1 and res.n_reflex_edges == 0
    assert len(res.sharp_edges) == 12


# --------------------------------------------------------------------------- exact helpers


def _sub(p, q):
    return tuple(a - b for a, b in zip(p, q))


def _cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _dot(u, v):
    return sum(a * b for a, b in zip(u, v))


def _height(points, face, p) -> Fraction:
    """orient3d of the face's first three corners with p: > 0 when p is strictly below the face
    (outward by the right-hand rule), exactly."""
    a, b, c = (points[i] for i in face[:3])
    return -_dot(_cross(_sub(b, a), _sub(c, a)), _sub(p, a))


def _distance(points, face, p) -> float:
    """How far p is above the plane of the face's first three corners (float)."""
    a, b, c = (points[i] for i in face[:3])
    n = _cross(_sub(b, a), _sub(c, a))
    return float(_dot(n, _sub(p, a))) / math.sqrt(float(_dot(n, n)))


def _unique_argmax(values) -> int:
    best = max(values)
    assert values.count(best) == 1, "the far-points-first choice must not tie here"
    return values.index(best)


def _far_points_first(points) -> list[int]:
    """The witness simplex by "far points first", in integers (no ties on these inputs)."""
    spans = [max(p[a] for p in points) - min(p[a] for p in points) for a in range(3)]
    axis = _unique_argmax(spans)
    lo = _unique_argmax([-p[axis] for p in points])
    hi = _unique_argmax([p[axis] for p in points])
    u = _sub(points[hi], points[lo])
    k = _unique_argmax([_dot(c, c) for c in (_cross(_sub(p, points[lo]), u) for p in points)])
    n = _cross(u, _sub(points[k], points[lo]))
    m = _unique_argmax([abs(_dot(n, _sub(p, points[lo]))) for p in points])
    return [lo, hi, k, m]


def _centroid(points, simplex):
    return tuple(Fraction(sum(points[i][a] for i in simplex), len(simplex)) for a in range(3))


def _prism(ring, shift):
    """The prism over a counter-clockwise ring of (x, y) points, its top the ring moved by
    ``shift`` (dz > 0): points (bottom ring, then top ring) and faces (bottom, top, then the
    side over each ring edge i -> i + 1), each counter-clockwise seen from outside.  The rings
    here turn left at their first four corners, so each cap starts at a convex corner (its
    first three corners give its outward plane, as for the triangles)."""
    k = len(ring)
    points = [(x, y, 0) for x, y in ring] + [(x + shift[0], y + shift[1], shift[2]) for x, y in ring]
    faces = [[3, 2, 1, 0] + list(range(k - 1, 3, -1)), list(range(k, 2 * k))]
    faces += [[i, (i + 1) % k, (i + 1) % k + k, i + k] for i in range(k)]
    return points, faces


# --------------------------------------------------------------------------- the interior point of a failed surface

#: A heptagon with one reflex corner, N = (-4, 3) at position 5.
_NOTCH = [(-10, 0), (-6, -3), (6, -3), (10, 0), (1, 9), (-4, 3), (-6, 4)]
#: The same with N = (-5, 3) and C = (-7, 3): the edge N -> C runs along y = 3.
_LEDGE = [(-10, 0), (-6, -3), (6, -3), (10, 0), (1, 9), (-5, 3), (-7, 3)]
_SHIFT = (1, 0, 2)


def test_a_notched_prism_names_the_side_its_interior_point_is_above():
    # The prism over the notched heptagon (its caps are not convex polygons, and the side
    # edge at N is reflex): the surface failed, so the exact centroid of the witness simplex
    # names the faces it is not strictly below.  That centroid is above the side over the
    # edge N -> C (face 7); the vertex mean is strictly below every face.
    points, faces = _prism(_NOTCH, _SHIFT)
    simplex = _far_points_first(points)
    centroid = _centroid(points, simplex)
    assert [f for f, face in enumerate(faces) if _height(points, face, centroid) <= 0] == [7]
    mean = _centroid(points, range(len(points)))
    assert min(_height(points, face, mean) for face in faces) > 0
    res = _check(points, faces)
    assert not res.ok and res.degenerate.tolist() == [True, True] + [False] * 7  # the caps are not convex
    assert res.flipped.tolist() == [7]
    assert "1 faces with the interior point not strictly below" in res.reasons
    assert res.magnitudes["flipped"] == pytest.approx(_distance(points, faces[7], centroid))
    # The vertex mean qualifies as a centre (strictly below every face) and is reported.
    assert res.center is not None
    assert min(_height(points, face, tuple(Fraction(float(c)) for c in res.center)) for face in faces) > 0


def test_a_face_through_the_interior_point_is_flipped():
    # "Strictly below": the witness centroid (-1, 3, 1) is exactly on the plane y = 3 of the
    # side over the edge N -> C (face 7), and strictly below every other face.
    points, faces = _prism(_LEDGE, _SHIFT)
    centroid = _centroid(points, _far_points_first(points))
    assert centroid == (-1, 3, 1)
    heights = [_height(points, face, centroid) for face in faces]
    assert heights[7] == 0 and min(heights[:7] + heights[8:]) > 0
    res = _check(points, faces)
    assert res.flipped.tolist() == [7]


# --------------------------------------------------------------------------- reflex magnitudes

#: A box-like solid whose roof is an asymmetric valley along the edge 8-9 (x = 1, z = 3): the
#: left half of the roof (4, 8, 9, 7) slopes as z = 4 - x, the right half (8, 5, 6, 9) as
#: z = x + 2.  The left wall is slanted (4x - y + 4 = 0), so the left roof is not a rectangle:
#: its corner 4 = (-1, 0, 5) is twice as far above the right roof's plane as its corner 7.
#: The front and back are each a convex quad and a triangle in one plane.
_VALLEY = [(-1, 0, 0), (2, 0, 0), (2, 4, 0), (0, 4, 0), (-1, 0, 5), (2, 0, 4), (2, 4, 4), (0, 4, 4), (1, 0, 3), (1, 4, 3)]
_VALLEY_FACES = [
    [3, 2, 1, 0],  # bottom
    [0, 4, 7, 3],  # left wall
    [1, 2, 6, 5],  # right wall, x = 2
    [4, 8, 9, 7],  # roof, left half
    [8, 5, 6, 9],  # roof, right half
    [0, 1, 5, 8], [0, 8, 4],  # front, y = 0
    [2, 3, 7, 9], [2, 9, 6],  # back, y = 4
]


def _largest_reflex_distance(points, faces, edge) -> float:
    """The largest distance of a vertex of one face across ``edge`` above the other's plane."""
    across = [f for f in faces if set(edge) <= set(f)]
    assert len(across) == 2
    return max(_distance(points, f, points[v]) for f, g in (across, across[::-1]) for v in g)


def test_the_valley_is_planar_and_outward():
    inside = (Fraction(1, 2), 2, 1)
    for face in _VALLEY_FACES:
        assert _height(_VALLEY, face, inside) > 0
        assert all(_height(_VALLEY, face, _VALLEY[v]) == 0 for v in face)
    assert _largest_reflex_distance(_VALLEY, _VALLEY_FACES, (8, 9)) == pytest.approx(4 / math.sqrt(2))
    assert _distance(_VALLEY, _VALLEY_FACES[4], _VALLEY[7]) == pytest.approx(2 / math.sqrt(2))


@pytest.mark.parametrize("rotate", [0, 3])
def test_an_asymmetric_valley_of_polygons_reports_its_largest_distance(rotate):
    # "Largest distance per violation kind": corner 4 of the left roof, 4 / sqrt(2) above the
    # right roof's plane; the right roof's far corners are only 2 / sqrt(2) above the left's,
    # and so is the left roof's other far corner 7.  The distances are taken for the corners
    # of the neighbour's plane triple (its first non-collinear fan triple, off the edge):
    # in these two orders of the left roof, (4, 8, 9) and (7, 4, 8), corner 4 is one of them.
    faces = [list(f) for f in _VALLEY_FACES]
    faces[3] = faces[3][rotate:] + faces[3][:rotate]
    res = _check(_VALLEY, faces)
    assert not res.ok and res.n_reflex_edges == 1 and res.reflex_faces.tolist() == [3, 4]
    assert not res.degenerate.any()
    assert res.magnitudes["reflex"] == pytest.approx(_largest_reflex_distance(_VALLEY, _VALLEY_FACES, (8, 9)))


@pytest.mark.parametrize("mirror", [False, True])
def test_an_asymmetric_valley_of_triangles_reports_its_largest_distance(mirror):
    # The same solid fan-triangulated (a closed triangle mesh: one test per edge, and the
    # reverse distance too), and its mirror image x -> 1 - x (faces reversed to stay
    # outward), which triangulates the roof the other way.  Across the valley edge the
    # neighbours are now two triangles, one far corner each.  Unmirrored, the edge's first
    # half-edge (8 -> 9) is in the left triangle (4, 8, 9), so the largest distance, corner
    # 4 above the right roof, is the reverse one.
    points = [(1 - x, y, z) for x, y, z in _VALLEY] if mirror else _VALLEY
    polygons = [f[::-1] for f in _VALLEY_FACES] if mirror else _VALLEY_FACES
    faces = [[f[0], f[i], f[i + 1]] for f in polygons for i in range(1, len(f) - 1)]
    res = _check(points, faces)
    assert res.n_reflex_edges == 1 and not res.degenerate.any()
    assert res.magnitudes["reflex"] == pytest.approx(_largest_reflex_distance(points, faces, (8, 9)))
    if not mirror:
        assert [4, 8, 9] in faces and res.magnitudes["reflex"] == pytest.approx(4 / math.sqrt(2))


# --------------------------------------------------------------------------- degenerate faces


@pytest.mark.parametrize("rotate", range(5))
def test_a_rectangle_visiting_a_corner_twice_is_degenerate(rotate):
    # Points 0 and 4 are the same corner: a polygon face without distinct vertex coordinates
    # (module docstring), though planar and turning once around.  Between the two copies, in
    # every order of the sort, sits a corner sharing two of their coordinates: (4, 0, 0)
    # shares y and z, (0, 3, 0) shares x and z.
    points = [(0, 0, 0), (4, 0, 0), (4, 3, 0), (0, 3, 0), (0, 0, 0)]
    face = [0, 1, 2, 3, 4]
    res = _check(points, [face[rotate:] + face[:rotate]], closed=False)
    assert res.degenerate.tolist() == [True]
    assert "1 degenerate faces" in res.reasons


@pytest.mark.parametrize("closed", [True, False])
def test_no_reflex_edge_next_to_a_face_without_a_plane(closed):
    # The tetrahedron whose edge 0-1 is split at 4, the gap closed by the collinear triangle
    # (0, 1, 4), which has no plane; and the same without its face (1, 2, 3), an open surface
    # (the general pairing of half-edges).  Every vertex of the collinear triangle lies on the
    # planes y = 0 and z = 0 of its neighbours, so no edge is reflex.  An input point that is
    # no vertex, (1, -5, 1), is above those planes: it must not stand in for the missing
    # plane's vertices.
    points = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (0, 0, 4), (2, 0, 0), (1, -5, 1)]
    faces = [[0, 2, 1], [0, 4, 3], [4, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]]
    if not closed:
        del faces[4]
    res = _check(points, faces, closed=closed)
    assert res.degenerate.tolist() == [False] * (len(faces) - 1) + [True]
    assert res.n_reflex_edges == 0 and res.reflex_faces.tolist() == []
    assert "reflex" not in res.magnitudes


# --------------------------------------------------------------------------- a surface winding more than once

#: Nine integer points near a circle of radius 100 in z = 0 (coordinates summing to 0),
#: joined every fourth: the star {9/4}, every turn left, winding four times around the origin.
_CIRCLE9 = [(98, 20), (62, 78), (-3, 100), (-66, 75), (-99, 15), (-85, -52), (-32, -95), (37, -93), (88, -48)]
_STAR94 = [(4 * t) % 9 for t in range(9)]


def test_a_star_bipyramid_winding_four_times_is_counted_around_its_vertex_mean():
    # Poles N = (0, 0, 50) and S = (0, 0, -40) over the {9/4} star: a closed surface
    # (V - E + F = 11 - 27 + 18 = 2) with no reflex edge and the vertex mean (0, 0, 10/11)
    # strictly below every face, but covering the sphere of directions four times, as its
    # ring winds around the axis.  The surface passed every local test, so the vertex mean
    # is the centre and the wrap count names the failure.  The witness simplex's centroid
    # (-33/4, -15, 25/2) lies in a tip of the star: above the faces from N over star edges
    # 1 and 3, so it would flip them.
    points = [(x, y, 0) for x, y in _CIRCLE9] + [(0, 0, 50), (0, 0, -40)]
    faces = []
    for t in range(9):
        a, b = _STAR94[t], _STAR94[(t + 1) % 9]
        faces += [[9, a, b], [10, b, a]]
    mean = _centroid(points, range(11))
    assert mean == (0, 0, Fraction(10, 11))
    assert min(_height(points, f, mean) for f in faces) > 0
    for f in faces:  # no reflex edge: no vertex of a neighbouring face strictly above a face
        for g in faces:
            if len(set(f) & set(g)) == 2:
                assert min(_height(points, f, points[v]) for v in g) >= 0
    assert _winding([_CIRCLE9[i] for i in _STAR94], (0, 0)) == 4
    simplex = _far_points_first(points)
    assert simplex == [4, 0, 6, 9]
    centroid = _centroid(points, simplex)
    assert centroid == (Fraction(-33, 4), -15, Fraction(25, 2))
    assert [k for k, f in enumerate(faces) if _height(points, f, centroid) <= 0] == [2, 6]
    res = _check(points, faces)
    assert not res.ok and res.n_reflex_edges == 0 and not res.degenerate.any()
    assert res.degree == 4
    assert res.flipped.tolist() == []
    assert res.center is not None and min(_height(points, f, tuple(Fraction(float(c)) for c in res.center)) for f in faces) > 0
    assert len(res.reasons) == 1 and "wraps 4 times" in res.reasons[0]
