"""The judge: no false alarm on correct hulls, the right alarm for each corruption."""

from __future__ import annotations

import itertools
import json
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hullstress.checker import QhullReference, check, qhull_reference
from hullstress.checker._geometry import distround
from hullstress.checker.extreme import exact_extreme_2d
from hullstress.contract import FaceSet
from hullstress.errors import ContractViolation
from hullstress.verdict import VERDICT_COLUMNS

seeds = st.integers(0, 2**32 - 1)


# --------------------------------------------------------------------------- inputs


def ball(rng, n, dim):
    v = rng.normal(size=(n, dim))
    v /= np.linalg.norm(v, axis=1)[:, None]
    return v * rng.random(n)[:, None] ** (1.0 / dim)


def cube_surface(k: int, rng: np.random.Generator):
    """The k x k x k integer lattice and its cube surface through every boundary lattice point.

    Every grid cell of every face is split by a randomly chosen diagonal: an
    arbitrary triangulation of the coplanar faces, with collinear and coplanar
    boundary vertices that are not extreme.
    """
    pts = np.array(list(itertools.product(range(k), repeat=3)), dtype=float)
    index = {p: i for i, p in enumerate(map(tuple, pts.astype(int).tolist()))}
    tris = []
    for axis in range(3):
        u, w = [a for a in range(3) if a != axis]
        for val, outward in ((0, -1), (k - 1, 1)):
            for i in range(k - 1):
                for j in range(k - 1):
                    def at(di, dj):
                        q = [0, 0, 0]
                        q[axis], q[u], q[w] = val, i + di, j + dj
                        return index[tuple(q)]

                    c = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)]
                    split = [(c[0], c[1], c[2]), (c[0], c[2], c[3])] if rng.random() < 0.5 else [(c[0], c[1], c[3]), (c[1], c[2], c[3])]
                    for a, b, cc in split:
                        n = np.cross(pts[b] - pts[a], pts[cc] - pts[a])
                        tris.append((a, b, cc) if n[axis] * outward > 0 else (a, cc, b))
    return pts, np.array(tris, dtype=np.int64)


def square_polygon(k: int):
    """The k x k integer lattice and its boundary polygon through every boundary point (ccw)."""
    pts = np.array(list(itertools.product(range(k), repeat=2)), dtype=float)
    index = {p: i for i, p in enumerate(map(tuple, pts.astype(int).tolist()))}
    ring = [(x, 0) for x in range(k - 1)] + [(k - 1, y) for y in range(k - 1)]
    ring += [(x, k - 1) for x in range(k - 1, 0, -1)] + [(0, y) for y in range(k - 1, 0, -1)]
    return pts, np.array([index[p] for p in ring], dtype=np.int64)


def qhull_faces(points):
    return qhull_reference(points).faces


def assert_valid(v, context=""):
    assert v.ok, f"false alarm {context}: {v.detail}"
    assert v.severity == "none" and v.max_violation == 0.0
    assert v.n_outside == 0 and v.n_missing_extreme == 0 and not v.offending


# --------------------------------------------------------------------------- no false alarms


@given(seed=seeds, n=st.integers(4, 80))
def test_qhull_hull_of_general_position_3d_is_valid(seed, n):
    pts = np.random.default_rng(seed).normal(size=(n, 3))
    ref = qhull_reference(pts)
    assert ref.qhull_ok, ref.qhull_detail
    v = check(pts, ref.faces, reference=ref)
    assert_valid(v)
    assert v.qhull_agreement == "agree" and v.n_extreme == len(ref.vertices)
    assert v.volume == pytest.approx(ref.volume, rel=1e-12)


@given(seed=seeds, n=st.integers(3, 80))
def test_qhull_hull_of_general_position_2d_is_valid(seed, n):
    pts = np.random.default_rng(seed).normal(size=(n, 2))
    ref = qhull_reference(pts)
    v = check(pts, ref.faces, reference=ref)
    assert_valid(v)
    assert v.qhull_agreement == "agree"
    assert v.volume == pytest.approx(ref.volume, rel=1e-12)


@pytest.mark.parametrize("scale", [1.0, 0.1, 3.7, 2.0**-1000, 2.0**996])
@given(seed=seeds, k=st.integers(2, 5))
def test_cube_lattices_with_any_triangulation_are_valid(scale, seed, k):
    pts, tri = cube_surface(k, np.random.default_rng(seed))
    pts = pts * scale
    v = check(pts, tri)
    assert v.containment and v.convexity and v.manifoldness, v.detail
    assert v.qhull_agreement in ("agree", "qhull-wrong")  # Qhull itself may fail at 1e300 scale
    assert v.n_extreme == 8
    assert v.n_boundary_nonextreme == 6 * (k - 2) ** 2 + 12 * (k - 2)
    assert v.n_hull_vertices == 8 + v.n_boundary_nonextreme


@pytest.mark.parametrize("scale", [1.0, 2.0**-1000, 2.0**996, 1e-300, 1e300])
def test_general_position_at_extreme_scales(scale):
    rng = np.random.default_rng(42)
    base = rng.normal(size=(300, 3))
    hull = qhull_faces(base)
    # Power-of-two scalings keep the hull exactly; 1e+-300 scalings round the points,
    # so their hull is taken from Qhull on the scaled points when Qhull is certified there.
    pts = base * scale
    faces = hull
    if scale in (1e-300, 1e300):
        ref = qhull_reference(pts)
        if ref.qhull_ok:
            faces = ref.faces
    v = check(pts, faces)
    assert v.containment and v.convexity and v.manifoldness, v.detail
    assert v.qhull_agreement in ("agree", "qhull-wrong")


def test_square_lattice_polygon_with_boundary_points():
    pts, ring = square_polygon(6)
    v = check(pts, ring)
    assert_valid(v)
    assert v.n_extreme == 4 and v.n_boundary_nonextreme == 16 and v.n_hull_vertices == 20


def test_duplicated_input_points_do_not_matter():
    rng = np.random.default_rng(5)
    pts = rng.normal(size=(60, 3))
    pts = np.r_[pts, pts[::3]]  # every third point twice
    v = check(pts, qhull_faces(pts))
    assert_valid(v)


def test_polygon_faces_are_accepted():
    # A cube with square faces; point 8 lies on the edge between corners 0 and 1, and
    # both faces along that edge list it.
    pts = np.array(list(itertools.product((0.0, 1.0), repeat=3)) + [[0.0, 0.0, 0.5]])
    cycles = [[0, 8, 1, 3, 2], [4, 5, 7, 6], [0, 8, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]
    faces = []
    for cyc in cycles:
        ring = pts[cyc]
        normal = np.cross(ring - ring.mean(axis=0), np.roll(ring, -1, axis=0) - ring.mean(axis=0)).sum(axis=0)
        faces.append(cyc if normal @ (ring.mean(axis=0) - 0.5) > 0 else cyc[::-1])
    v = check(pts, faces)
    assert_valid(v, str(faces))
    assert v.n_extreme == 8 and v.n_boundary_nonextreme == 1 and v.n_faces == 6
    # A non-planar pentagon: move point 8 off the edge, outwards in x only.
    bent = pts.copy()
    bent[8, 0] = -0.25
    v = check(bent, faces)
    assert not v.convexity and v.n_degenerate_faces >= 1 and not v.containment


# --------------------------------------------------------------------------- corruptions (3D)


@pytest.fixture(scope="module")
def sphere_case():
    pts = ball(np.random.default_rng(9), 400, 3)
    ref = qhull_reference(pts)
    return pts, ref, ref.faces.triangles().copy()


def test_flipped_facet(sphere_case):
    pts, ref, tri = sphere_case
    bad = tri.copy()
    bad[7] = bad[7][::-1]
    v = check(pts, bad, reference=ref)
    assert not v.manifoldness and not v.convexity
    assert 7 in v.offending["flipped_faces"] and v.severity == "gross"


def test_removed_facet(sphere_case):
    pts, ref, tri = sphere_case
    v = check(pts, np.delete(tri, 11, axis=0), reference=ref)
    assert not v.manifoldness
    assert v.severity == "gross"


def test_duplicated_facet(sphere_case):
    pts, ref, tri = sphere_case
    v = check(pts, np.r_[tri, tri[[3]]], reference=ref)
    assert not v.manifoldness and v.convexity and v.containment
    assert {3, len(tri)} <= set(v.offending["manifold_faces"])


def test_vertex_replaced_by_interior_point(sphere_case):
    pts, ref, tri = sphere_case
    vertex = int(tri[0, 0])
    inner = int(np.argmin(np.linalg.norm(pts, axis=1)))  # the point nearest the centre
    bad = np.where(tri == vertex, inner, tri)
    v = check(pts, bad, reference=ref, max_offending=len(pts))
    assert not v.containment and not v.convexity
    assert vertex in v.offending["containment"] and vertex in v.offending["missing_extreme"]
    assert v.qhull_agreement == "disagree" and v.severity == "gross"


def test_extreme_point_left_out(sphere_case):
    pts, ref, _ = sphere_case
    drop = int(ref.vertices[5])
    keep = np.delete(np.arange(len(pts)), drop)
    sub = qhull_reference(pts[keep]).faces.triangles()
    v = check(pts, keep[sub], reference=ref)
    assert v.convexity and v.manifoldness and not v.containment
    assert v.offending["containment"] == (drop,) and v.offending["missing_extreme"] == (drop,)
    assert v.n_missing_extreme == 1 and v.qhull_agreement == "disagree"


@pytest.mark.parametrize("direction,alarm", [(np.inf, True), (-np.inf, False)])
def test_point_one_ulp_outside_a_facet(direction, alarm):
    cube = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
    tri = qhull_faces(cube)
    extra = np.array([[0.25, 0.5, np.nextafter(1.0, direction)]])  # one ulp above / below the top face
    pts = np.r_[cube, extra]
    v = check(pts, tri)
    assert v.containment is (not alarm)
    if alarm:
        assert v.offending["containment"] == (8,)
        assert v.severity == "roundoff" and 0 < v.max_violation <= 1
        assert v.n_missing_extreme == 1  # the point is a corner of the true hull
    else:
        assert_valid(v)


def test_locally_convex_double_cover_is_caught():
    # A regular 7-gon traversed with step 2 in 2D: every turn is left and the centre is
    # left of every edge, yet it winds twice.
    angles = 2 * np.pi * np.arange(7) / 7
    pts = np.c_[np.cos(angles), np.sin(angles)]
    v = check(pts, [(2 * i) % 7 for i in range(7)])
    assert not v.convexity and not v.manifoldness and not v.containment


def test_flat_input_with_a_surface():
    # Coplanar 3D input: the hull is a flat polygon (docs/lower-dimensional.md).  Qhull's
    # joggled hull of it is a two-sided triangulation of that polygon, a correct answer; with one
    # face less it has a hole; a triangle and its reverse miss most of the polygon.
    pts = np.c_[np.random.default_rng(2).random((30, 2)), np.zeros(30)]
    ref = qhull_reference(pts)
    assert ref.affine_rank == 2 and ref.options == "QJ" and ref.qhull_ok is False
    v = check(pts, ref.faces, reference=ref)
    assert v.ok and v.affine_rank == 2 and v.qhull_agreement is None
    v = check(pts, ref.faces.triangles()[1:], reference=ref)
    assert not v.manifoldness and "hole" in v.detail
    v = check(pts, [[0, 1, 2], [0, 2, 1]])
    assert not v.containment and v.n_missing_extreme == 6


# --------------------------------------------------------------------------- corruptions (2D)


def _exact_left_of_hull(points, hull, q) -> int:
    """Fraction test: min over hull edges of the orientation of q (positive: strictly inside)."""
    fq = [Fraction(float(v)) for v in q]
    worst = 1
    for i in range(len(hull)):
        a = [Fraction(float(v)) for v in points[hull[i]]]
        b = [Fraction(float(v)) for v in points[hull[(i + 1) % len(hull)]]]
        d = (b[0] - a[0]) * (fq[1] - a[1]) - (b[1] - a[1]) * (fq[0] - a[0])
        worst = min(worst, (d > 0) - (d < 0))
    return worst


KETTNER = {
    "A1": [[7.3000000000000194, 7.3000000000000167], [24.000000000000068, 24.000000000000071], [24.00000000000005, 24.000000000000053], [0.50000000000001621, 0.50000000000001243], [8, 4], [4, 9], [15, 27], [26, 25], [19, 11]],
    "A2": [[27.643564356435643, -21.881188118811881], [83.366336633663366, 15.544554455445542], [4.0, 4.0], [73.415841584158414, 8.8613861386138595]],
    "B1": [[200.0, 49.200000000000003], [100.0, 49.600000000000001], [-233.33333333333334, 50.93333333333333], [166.66666666666669, 49.333333333333336]],
    "B2": [[0.50000000000001243, 0.50000000000000189], [0.50000000000001243, 0.50000000000000333], [24.00000000000005, 24.000000000000053], [24.000000000000068, 24.000000000000071], [17.300000000000001, 17.300000000000001]],
    "global_area": [[0.10000000000000001, 0.10000000000000001], [0.20000000000000001, 0.20000000000000004], [0.79999999999999993, 0.80000000000000004], [1.267650600228229e30, 1.2676506002282291e30]],
    "global_nonconvex": [[24.00000000000005, 24.000000000000053], [24, 6], [54.85, 6], [54.850000000000357, 61.000000000000121], [24.000000000000068, 24.000000000000071], [6, 6]],
}


@pytest.mark.parametrize("name", sorted(KETTNER))
def test_kettner_sets(name):
    pts = np.array(KETTNER[name], dtype=float)
    ref = qhull_reference(pts)
    hull = exact_extreme_2d(pts)  # the exact extreme points, counter-clockwise
    v = check(pts, hull, reference=ref)
    assert_valid(v, name)
    # Inserting any non-extreme point into the hull at its nearest edge: the alarm must
    # match the exact (Fraction) position of the point.
    for q in np.setdiff1d(np.arange(len(pts)), hull):
        side = _exact_left_of_hull(pts, hull, pts[q])
        best = None
        for i in range(len(hull)):
            poly = np.insert(hull, i + 1, q)
            w = check(pts, poly, reference=ref)
            if best is None or w.ok:
                best = w
        if side > 0:  # strictly inside: every insertion makes a reflex vertex
            assert not best.convexity and q in best.offending["reflex_vertices"]
        elif side == 0:  # on the boundary: some insertion is a valid hull with q allowed
            assert best.ok and best.n_boundary_nonextreme >= 1


def test_kettner_a2_nonconvex_result():
    pts = np.array(KETTNER["A2"])
    v = check(pts, [0, 3, 1, 2])  # (p1, p4, p2, p3): the incremental algorithm's output
    assert not v.convexity and v.offending["reflex_vertices"] == (3,)
    assert v.severity == "roundoff"


def test_2d_corruptions():
    pts, ring = square_polygon(4)
    assert not check(pts, ring[::-1]).manifoldness  # clockwise
    v = check(pts, np.r_[ring, ring[:1]])  # a repeated vertex
    assert not v.manifoldness and v.offending["manifold_vertices"]
    v = check(pts, np.delete(ring, 3))  # corner (3, 0) left out
    assert not v.containment and v.n_missing_extreme == 1
    corners = ring[[0, 3, 6, 9]]
    v = check(pts, corners[[0, 2, 1, 3]])  # a bow tie
    assert not v.manifoldness and not v.convexity


# --------------------------------------------------------------------------- API and records


def test_verdict_record_and_table_row(sphere_case):
    pts, ref, tri = sphere_case
    v = check(pts, tri, reference=ref)
    row = v.as_row()
    assert tuple(row) == VERDICT_COLUMNS
    assert row["qhull_options"] == "Qt" and row["qhull_ok"] is True and row["affine_rank"] == 3
    assert row["distround"] == distround(pts)
    json.loads(row["offending"])
    assert isinstance(v.containment, bool) and v.qhull_agreement in ("agree", "disagree", "qhull-wrong")


def test_max_offending_limits_the_lists(sphere_case):
    pts, ref, tri = sphere_case
    v = check(pts, tri[:, ::-1], reference=ref, max_offending=3)  # everything flipped
    assert all(len(ix) <= 3 for ix in v.offending.values())
    assert v.n_outside == len(pts)


BAD_CALLS = [
    (np.zeros((4, 4)), [0, 1, 2], ValueError, "shape"),
    (np.array([[0.0, np.nan], [1, 1], [0, 1]]), [0, 1, 2], ValueError, "finite"),
    (np.eye(3), [[0, 1, 5]], ContractViolation, "out of range"),
    (np.eye(2), None, ContractViolation, "None"),
    (np.eye(3), [[0, 1]], ContractViolation, "at least 3"),
]


@pytest.mark.parametrize("points,faces,error,message", BAD_CALLS)
def test_bad_calls(points, faces, error, message):
    with pytest.raises(error, match=message):
        check(points, faces)


def test_reference_must_match_points(sphere_case):
    pts, ref, tri = sphere_case
    with pytest.raises(ValueError, match="reference was computed"):
        check(pts[:-1], tri[tri.max(axis=1) < len(pts) - 1], reference=ref)


def test_faceset_and_no_qhull(sphere_case):
    pts, ref, tri = sphere_case
    v = check(pts, FaceSet.from_triangles(tri), qhull=False)
    assert v.ok and v.qhull_agreement is None and v.qhull_options is None


@pytest.mark.parametrize(
    "points",
    [np.zeros((0, 3)), np.ones((5, 3)), np.array([[0.0, np.nan, 1.0]]), np.zeros((3, 4)), "abc", np.c_[np.arange(5.0), np.arange(5.0)]],
)
def test_qhull_reference_never_raises(points):
    ref = qhull_reference(points)
    assert isinstance(ref, QhullReference)
    if ref.vertices is None:
        assert ref.error
    else:
        assert ref.options is not None and ref.qhull_ok is not None


def test_qhull_reference_records_retried_options():
    pts = np.c_[np.random.default_rng(0).random((20, 2)), np.full(20, 0.5)]
    ref = qhull_reference(pts)
    assert ref.options == "QJ" and ref.attempts and ref.attempts[0].startswith("Qt:")
    assert ref.distround == distround(pts)


@pytest.mark.slow
def test_large_ball_uses_the_fast_path_and_stays_exact():
    pts = ball(np.random.default_rng(0), 100_000, 3)
    ref = qhull_reference(pts)
    v = check(pts, ref.faces, reference=ref)
    assert_valid(v)
    bad = ref.faces.triangles().copy()
    far = int(np.argmax(np.linalg.norm(pts, axis=1)))
    v = check(pts, bad[~np.any(bad == far, axis=1)], reference=ref)
    assert not v.manifoldness


# --------------------------------------------------------------------------- the fast containment path


@given(seed=seeds, drop=st.integers(1, 3), dim=st.sampled_from([2, 3]))
def test_left_out_extreme_points_are_found_by_the_fast_path(seed, drop, dim):
    # The hull of the remaining points is convex and closed, so containment takes the
    # cone (2D: angular) shortcut; exactly the dropped extreme points must be outside.
    rng = np.random.default_rng(seed)
    pts = ball(rng, 3000, dim)
    ref = qhull_reference(pts)
    gone = rng.choice(ref.vertices, size=drop, replace=False)
    keep = np.setdiff1d(np.arange(len(pts)), gone)
    sub = qhull_reference(pts[keep]).faces
    faces = keep[sub] if dim == 2 else keep[sub.triangles()]
    v = check(pts, faces, reference=ref, max_offending=len(pts))
    assert v.convexity and v.manifoldness
    assert set(v.offending["containment"]) == set(gone.tolist())
    assert set(v.offending["missing_extreme"]) == set(gone.tolist())


def test_cone_and_brute_containment_agree():
    from hullstress.checker.containment import check_containment3d
    from hullstress.checker.convexity3d import check_convexity3d
    from hullstress.checker.topology import half_edges

    rng = np.random.default_rng(17)
    inner = ball(rng, 200, 3)
    hull = qhull_faces(inner)
    # Probe points all around the surface: inside, on vertices, just outside, far outside.
    probes = np.r_[inner * 1.0000001, inner * 0.999, ball(rng, 2000, 3) * 1.2, inner[hull.indices[:30]]]
    pts = np.r_[inner, probes]
    he = half_edges(hull, len(pts))
    conv = check_convexity3d(pts, hull, he, closed=True)
    assert conv.ok and conv.center is not None
    fast = check_containment3d(pts, hull, conv.plane, certified=True, center=conv.center, he=he)
    slow = check_containment3d(pts, hull, conv.plane)
    assert fast.method.startswith("cones") and slow.method == "brute"
    assert np.array_equal(fast.outside, slow.outside) and fast.outside.size > 100


@given(seed=seeds, n=st.integers(1, 60), m=st.integers(0, 80))
def test_union_find_components_match_scipy(seed, n, m):
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from hullstress.checker.topology import components

    rng = np.random.default_rng(seed)
    u, v = rng.integers(0, n, m), rng.integers(0, n, m)
    label = components(n, u, v)
    _, expected = connected_components(coo_matrix((np.ones(m), (u, v)), shape=(n, n)), directed=False)
    # Same partition, each labelled by its smallest node.
    assert np.array_equal(label[label], label) and np.all(label <= np.arange(n))
    assert np.array_equal(np.unique(expected[np.arange(n)], return_inverse=True)[1], np.unique(label, return_inverse=True)[1])
