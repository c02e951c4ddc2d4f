"""The wrap number (``hullstress/checker/wrap.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/wrap.py`` that
survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: a convex surface wraps once, a surface covering the sphere of
directions k times wraps k times, whatever the ray; a zero orientation is
replaced by the sign of the first nonzero component of the normal) or from an
independent exact computation in integers or Fractions, never from the
checker's own output.

The ray is forced where the seeded one would almost never go (through a
vertex, along an edge's plane, onto the interior point itself) by replacing
``wrap.ray_point``: the count must not change, so every tie the symbolic
perturbation breaks is checked against a count known from the geometry.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker import wrap
from hullstress.checker._geometry import Interior
from hullstress.checker.wrap import break_ties_2d, break_ties_3d, ray_point, wrap_number_2d, wrap_number_3d
from hullstress.contract import FaceSet

# --------------------------------------------------------------------------- inputs


def _polygon(k: int, step: int, radius: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """k points on a circle about the origin and the polygon visiting every ``step``-th one
    (counter-clockwise; it winds ``step`` times around the origin when gcd(k, step) = 1)."""
    t = 2 * np.pi * np.arange(k) / k
    return radius * np.c_[np.cos(t), np.sin(t)], (np.arange(k) * step) % k


def _bipyramid(m: int, turns: int = 1) -> tuple[np.ndarray, FaceSet]:
    """Poles (0, 0, +-2) over a ring of m points of radius 2 about the origin, the ring run
    ``turns`` times (its points repeated under new indices): a closed surface of genus 0 whose
    faces are each strictly above the origin, covering the sphere of directions ``turns`` times."""
    t = 2 * np.pi * np.arange(m) / m
    ring = 2 * np.c_[np.cos(t), np.sin(t), np.zeros(m)]
    pts = np.r_[[[0.0, 0.0, 2.0], [0.0, 0.0, -2.0]], np.tile(ring, (turns, 1))]
    equator = [2 + j for j in range(turns * m)]
    faces = []
    for j in range(turns * m):
        a, b = equator[j], equator[(j + 1) % (turns * m)]
        faces += [(0, a, b), (1, b, a)]
    return pts, FaceSet.from_triangles(faces)


def _cube_and_pyramid() -> tuple[np.ndarray, FaceSet]:
    """A cube [-1, 1]^3 with a square pyramid (apex (0, 0, 3)) on its top: quadrilaterals
    and triangles mixed, so faces of different sizes follow each other in the index array."""
    pts = np.array([[2 * (v >> 2) - 1, 2 * ((v >> 1) & 1) - 1, 2 * (v & 1) - 1] for v in range(8)] + [[0, 0, 3]], dtype=np.float64)
    # Vertex v = 4x + 2y + z (bits), counter-clockwise seen from outside.
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4]]
    faces += [[1, 5, 8], [5, 7, 8], [7, 3, 8], [3, 1, 8]]  # the pyramid over the top z = 1
    return pts, FaceSet.from_polygons(faces)


def _outward_everywhere(points: np.ndarray, faces: FaceSet, o) -> bool:
    """Integer check that every face's first corner turns counter-clockwise seen from outside
    with ``o`` strictly below (the precondition of wrap_number_3d), in Fractions."""
    for f in faces.polygons():
        a, b, c = ([Fraction(x) for x in points[i]] for i in f[:3])
        n = [
            (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
            (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]),
        ]
        if sum(n[k] * (Fraction(o[k]) - a[k]) for k in range(3)) >= 0:
            return False
    return True


#: An interior point given exactly: the centroid of these rows is the origin.
_ZERO_CENTROID_3D = Interior.from_simplex(0.25 * np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]))
_ZERO_CENTROID_2D = Interior.from_simplex(0.25 * np.array([[1.0, 1], [-2, 1], [1, -2]]))


def _force_ray(monkeypatch, q: np.ndarray) -> None:
    monkeypatch.setattr(wrap, "ray_point", lambda origin, extent, seed: np.array(q, dtype=np.float64))


# --------------------------------------------------------------------------- wrap_number_2d


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_a_convex_polygon_wraps_once_and_a_star_as_often_as_its_step(origin):
    center, interior = (np.zeros(2), None) if origin == "center" else (None, _ZERO_CENTROID_2D)
    for k, step in ((7, 1), (7, 2), (7, 3), (5, 2), (4, 1)):
        pts, poly = _polygon(k, step)
        for seed in range(3):  # the count does not depend on the ray
            assert wrap_number_2d(pts, poly, center, interior, seed) == step


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_a_ray_through_vertices_counts_the_same(monkeypatch, origin):
    # The ray from the origin through a vertex (q = half the vertex: exactly on the line),
    # or through the opposite side: orientation zero at that vertex, the others decided.
    center, interior = (np.zeros(2), None) if origin == "center" else (None, _ZERO_CENTROID_2D)
    for k, step in ((7, 1), (7, 2), (7, 3), (4, 1), (8, 3)):
        pts, poly = _polygon(k, step)
        for vertex in range(k):
            for q in (0.5 * pts[vertex], -0.5 * pts[vertex], np.zeros(2)):
                _force_ray(monkeypatch, q)
                assert wrap_number_2d(pts, poly, center, interior) == step, (k, step, vertex, q)


def test_a_square_on_the_axes_with_the_ray_along_each_axis(monkeypatch):
    # Vertices on both axes: with q on an axis two vertices are on the ray's line (one on
    # the ray, one behind it), and a vertex with o_y = a_y is decided by the x order alone.
    pts = np.array([[3.0, 0.0], [0.0, 3.0], [-3.0, 0.0], [0.0, -3.0]])
    for q in ([1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.0, 0.0]):
        _force_ray(monkeypatch, np.array(q))
        assert wrap_number_2d(pts, np.arange(4), np.zeros(2), None) == 1
        twice = np.r_[pts, pts]  # the square run twice (repeated coordinates, new indices)
        assert wrap_number_2d(twice, np.arange(8), np.zeros(2), None) == 2


# --------------------------------------------------------------------------- wrap_number_3d


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_a_bipyramid_wraps_as_often_as_its_ring_runs(origin):
    center, interior = (np.zeros(3), None) if origin == "center" else (None, _ZERO_CENTROID_3D)
    for m, turns in ((4, 1), (5, 1), (5, 2), (4, 3)):
        pts, faces = _bipyramid(m, turns)
        assert _outward_everywhere(pts, faces, [0, 0, 0])
        for seed in range(3):
            assert wrap_number_3d(pts, faces, center, interior, seed) == turns


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_a_ray_through_a_vertex_or_along_an_edge_counts_the_same(monkeypatch, origin):
    # A ray through a pole meets every edge at that pole (zero orientation) but no equator
    # edge; one through a ring point meets the edges at it; one through an edge's midpoint
    # lies in that edge's plane.  The count stays the number of turns.
    center, interior = (np.zeros(3), None) if origin == "center" else (None, _ZERO_CENTROID_3D)
    for m, turns in ((4, 1), (5, 2), (4, 3)):
        pts, faces = _bipyramid(m, turns)
        rays = [0.5 * pts[0], 0.5 * pts[1], np.zeros(3)] + [0.5 * pts[2 + j] for j in range(m)] + [-0.5 * pts[2 + j] for j in range(m)]
        rays += [0.25 * (pts[0] + pts[2]), 0.25 * (pts[2] + pts[3]), 0.25 * (pts[1] + pts[3])]
        for q in rays:
            _force_ray(monkeypatch, q)
            assert wrap_number_3d(pts, faces, center, interior) == turns, (m, turns, q)


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_faces_of_several_sizes_wrap_once(monkeypatch, origin):
    # Quadrilaterals and triangles mixed: each face's edges close on its own first vertex.
    center, interior = (np.zeros(3), None) if origin == "center" else (None, _ZERO_CENTROID_3D)
    pts, faces = _cube_and_pyramid()
    assert _outward_everywhere(pts, faces, [0, 0, 0])
    for seed in range(4):
        assert wrap_number_3d(pts, faces, center, interior, seed) == 1
    # Rays through a corner, an edge, a face's centre, the apex, and the origin itself.
    for q in ([1.0, 1, 1], [1.0, 0, 1], [0.0, 0, -1], [0.0, 0, 1], [-1.0, 0, 0], [0.0, 0, 0], [0.5, 0.5, -0.5]):
        _force_ray(monkeypatch, np.array(q))
        assert wrap_number_3d(pts, faces, center, interior) == 1, q


# --------------------------------------------------------------------------- break_ties_3d


def _normal_sign(o, u, v) -> int:
    """Sign of the first nonzero component of (u - o) x (v - o), in Fractions."""
    a = [Fraction(u[k]) - Fraction(o[k]) for k in range(3)]
    b = [Fraction(v[k]) - Fraction(o[k]) for k in range(3)]
    n = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    for c in n:
        if c:
            return 1 if c > 0 else -1
    return 0


def _tie_rows_3d():
    """Edge end points (u - o, v - o) with components in {-1, 0, 1}: every sign of every
    normal component, the first nonzero one at x, at y and at z; never a zero normal."""
    vals = (-1, 0, 1)
    rows = [
        (a, b)
        for a in ((x, y, z) for x in vals for y in vals for z in vals)
        for b in ((x, y, z) for x in vals for y in vals for z in vals)
    ]
    return [(a, b) for a, b in rows if _normal_sign((0, 0, 0), a, b) != 0]


@pytest.mark.parametrize("origin", ["center", "interior", "indices"])
def test_break_ties_3d_takes_the_first_nonzero_normal_component(origin):
    rows = _tie_rows_3d()
    o = np.array([1.0, 2.0, 3.0]) if origin != "interior" else np.zeros(3)
    u = np.array([a for a, _ in rows], dtype=np.float64) + o
    v = np.array([b for _, b in rows], dtype=np.float64) + o
    want = [_normal_sign(o, a, b) for a, b in zip(u, v)]
    assert {w for w in want} == {-1, 1}
    assert any(a[0] * b[1] - a[1] * b[0] == 0 and a[2] * b[0] - a[0] * b[2] == 0 for a, b in rows)  # z decides some
    # Every other row already decided (+-1, kept as it is); the ties are the zeros.
    s = np.zeros(2 * len(rows), dtype=np.int8)
    s[1::2] = np.where(np.arange(len(rows)) % 2 == 0, 1, -1)
    uu, vv = np.repeat(u, 2, axis=0), np.repeat(v, 2, axis=0)
    if origin == "center":
        break_ties_3d(s, uu, vv, o, None)
    elif origin == "interior":
        break_ties_3d(s, uu, vv, None, _ZERO_CENTROID_3D)
    else:  # u and v as indices into points, as the batched certificate passes them
        points = np.r_[u, v]
        ui = np.repeat(np.arange(len(rows)), 2)
        break_ties_3d(s, ui, ui + len(rows), o, None, points)
    assert s[0::2].tolist() == want
    assert s[1::2].tolist() == np.where(np.arange(len(rows)) % 2 == 0, 1, -1).tolist()


def test_break_ties_3d_with_an_exact_interior_point_that_no_double_reaches():
    # The centroid of these rows is (1/4, 1/4, 1/4 + 2**-62): its float rounding is
    # (1/4, 1/4, 1/4), on the line of the first two edges; the exact point is not.
    simplex = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 2.0**-60], [0, 0, 1]])
    interior = Interior.from_simplex(simplex)
    assert interior.approx.tolist() == [0.25, 0.25, 0.25]
    o = [Fraction(1, 4), Fraction(1, 4), (1 + Fraction(2) ** -60) / 4]
    u = np.array([[0.25, 0.25, 0.25], [0.25, 0.25, 0.25], [0.0, 0.25, 0.25]])
    v = np.array([[0.25, 0.0, 0.25], [0.0, 0.25, 0.25], [0.25, 0.0, 0.25]])
    want = [_normal_sign(o, a, b) for a, b in zip(u, v)]
    assert 0 not in want
    s = np.zeros(3, dtype=np.int8)
    break_ties_3d(s, u, v, None, interior)
    assert s.tolist() == want


def test_break_ties_3d_leaves_a_decided_array_alone_and_refuses_a_zero_normal():
    s = np.array([1, -1, 1], dtype=np.int8)
    u = v = np.zeros((3, 3))  # would be a zero normal, but nothing is tied
    break_ties_3d(s, u, v, np.ones(3), None)
    assert s.tolist() == [1, -1, 1]
    # o on the line of two edges (u, v collinear with o): never counted silently.
    s = np.array([0, 1, 0, 0], dtype=np.int8)
    u = np.array([[2.0, 2, 2], [0, 1, 0], [3, 3, 3], [1, 0, 0]])
    v = np.array([[3.0, 3, 3], [0, 0, 1], [5, 5, 5], [0, 1, 0]])
    with pytest.raises(ValueError, match="undecidable.* 2 edges"):
        break_ties_3d(s, u, v, np.ones(3), None)


# --------------------------------------------------------------------------- break_ties_2d


def _tie_sign_2d(o, a) -> int:
    """``s(q + (e, e**2)) = e (o_y - a_y) + e**2 (a_x - o_x)``: the first nonzero term, in Fractions."""
    first = Fraction(o[1]) - Fraction(a[1])
    if first:
        return 1 if first > 0 else -1
    second = Fraction(a[0]) - Fraction(o[0])
    return (second > 0) - (second < 0)


@pytest.mark.parametrize("origin", ["center", "interior"])
def test_break_ties_2d_is_decided_by_y_then_by_x(origin):
    o = np.array([1.0, 2.0]) if origin == "center" else np.zeros(2)
    offsets = np.array([[1.0, 1], [1, -1], [-1, 1], [-1, -1], [0, 1], [0, -1], [1, 0], [-1, 0], [5, 0], [-0.5, 0]])
    a = np.repeat(offsets + o, 2, axis=0)
    s = np.zeros(len(a), dtype=np.int8)
    s[1::2] = np.where(np.arange(len(offsets)) % 2 == 0, -1, 1)  # decided entries stay
    if origin == "center":
        break_ties_2d(s, a, o, None)
    else:
        break_ties_2d(s, a, None, _ZERO_CENTROID_2D)
    assert s[0::2].tolist() == [_tie_sign_2d(o, p) for p in offsets + o] == [-1, 1, -1, 1, -1, 1, 1, -1, 1, -1]
    assert s[1::2].tolist() == np.where(np.arange(len(offsets)) % 2 == 0, -1, 1).tolist()


def test_break_ties_2d_with_an_exact_interior_point_that_no_double_reaches():
    # The centroid of (0, 0), (1, 0), (0, 1) is (1/3, 1/3); the vertex (1/3 rounded, 1/3 rounded)
    # is below and left of it, (1/3 rounded, 1/3 rounded up) above: y decides, never x.
    third = 1 / 3
    up = float(np.nextafter(third, 1.0))
    interior = Interior.from_simplex(np.array([[0.0, 0], [1, 0], [0, 1]]))
    o = (Fraction(1, 3), Fraction(1, 3))
    a = np.array([[third, third], [third, up], [up, third], [5.0, third]])
    want = [_tie_sign_2d(o, p) for p in a]
    assert want == [1, -1, 1, 1]
    s = np.zeros(4, dtype=np.int8)
    break_ties_2d(s, a, None, interior)
    assert s.tolist() == want


def test_break_ties_2d_at_the_height_of_an_exact_interior_point_off_the_axis():
    # The centroid of (0, 0), (3, 0), (-3, 3) is (0, 1): vertices at y = 1 are decided by
    # x alone, on either side of it.
    interior = Interior.from_simplex(np.array([[0.0, 0], [3, 0], [-3, 3]]))
    a = np.array([[-2.0, 1], [2, 1], [-0.5, 1], [7, 1]])
    s = np.zeros(4, dtype=np.int8)
    break_ties_2d(s, a, None, interior)
    assert s.tolist() == [_tie_sign_2d((0, 1), p) for p in a] == [-1, 1, -1, 1]


def test_break_ties_2d_refuses_an_interior_point_on_a_vertex():
    s = np.array([0, 1], dtype=np.int8)
    a = np.array([[1.0, 2.0], [0.0, 0.0]])
    with pytest.raises(ValueError, match="undecidable.*polygon vertex"):
        break_ties_2d(s, a, np.array([1.0, 2.0]), None)
    s = np.array([1, -1], dtype=np.int8)
    break_ties_2d(s, a, np.array([1.0, 2.0]), None)  # nothing tied: nothing to decide
    assert s.tolist() == [1, -1]


# --------------------------------------------------------------------------- ray_point


def test_ray_point_is_fixed_per_seed_off_the_origin_and_at_the_input_scale():
    origin = np.array([1.0, -2.0, 0.5])
    for seed in range(5):
        q = ray_point(origin, 8.0, seed)
        assert q.shape == (3,) and np.array_equal(q, ray_point(origin, 8.0, seed))
        assert not np.array_equal(q, origin)
        assert np.abs(q - origin).max() <= 8.0  # a sixteenth of the extent per unit of direction
        assert len(set((q - origin).tolist())) == 3  # a random direction, not along a diagonal
        far = ray_point(origin, 2.0**20, seed)  # at the input's scale, not a fixed distance
        assert 2.0**10 <= np.abs(far - origin).max() <= 2.0**20
    assert not np.array_equal(ray_point(origin, 8.0, 0), ray_point(origin, 8.0, 1))
    assert ray_point(np.zeros(2), 1.0, 0).shape == (2,)


def test_ray_point_near_the_double_range_is_finite_and_silent():
    # Warnings are errors here: an overflow inside must be caught, and the answer is
    # finite: q itself where it fits, else the origin (the perturbation gives the direction).
    big = np.finfo(np.float64).max
    hit_origin = 0
    for seed in range(12):
        for origin in (np.full(3, big), np.full(3, -big), np.array([big, -big, 0.0]), np.full(2, big)):
            q = ray_point(origin, big, seed)
            assert np.isfinite(q).all() and q.shape == origin.shape
            hit_origin += bool(np.array_equal(q, origin))
    assert hit_origin  # some direction leaves the double range from a corner of it
    # Just below the guard the plain sum cannot overflow and is the documented point;
    # above it, where the sum still fits, it is that point too (not the origin).
    for extent in (float(np.nextafter(2.0**1000, 0)), 2.0**1010):
        for seed in range(5):
            q = ray_point(np.zeros(3), extent, seed)
            assert np.isfinite(q).all() and extent / 2**10 <= np.abs(q).max() <= extent


def test_wrap_numbers_at_the_top_of_the_double_range():
    # A polygon and a bipyramid about a centre near the largest double: for most seeds the
    # ray point overflows and falls back on the centre, whose every orientation is a tie
    # (for the others it is an ordinary ray); the counts come out right either way.
    o = np.array([1.6e308, 1.6e308, 1.6e308])
    fell_back = 0
    for seed in range(6):
        pts, poly = _polygon(7, 2, radius=1e307)
        pts += o[:2]
        fell_back += bool(np.array_equal(ray_point(o[:2], float(pts.max()), seed), o[:2]))
        assert wrap_number_2d(pts, poly, o[:2], None, seed) == 2
        pts3, faces = _bipyramid(5, 2)
        pts3 = pts3 * 5e306 + o
        assert wrap_number_3d(pts3, faces, o, None, seed) == 2
    assert fell_back
