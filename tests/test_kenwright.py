"""Tests for hullstress.algorithms.kenwright (seed 002, Algorithm 1 lines 10-17).

With ``sphere=off`` Kenwright's algorithm is a plain incremental hull over all
input rows, so on general position it must give Qhull's vertices, with every
input point on or inside every face (an exact orientation predicate: a float
filter with Shewchuk's orient3d error bound, Fractions for the undecided
cases).  With ``sphere=on`` the harness runs hullstress.sphere.sphere_project
first and this hull on the projected points: that is the seed's full method,
and the tests pin both its hull of the projected points and the support
mapping's culling of true hull vertices (a flaw of the sphere variant).
"""

from __future__ import annotations

import doctest
import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from hullstress import _registry
from hullstress.algorithms import kenwright
from hullstress.algorithms.kenwright import _cross, kenwright_hull
from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.contract import FaceSet, canonical_output
from hullstress.errors import AlgorithmStepLimit, HullstressError
from hullstress.evaluate import call_algorithm
from hullstress.sphere import sphere_project
from hullstress.tolerance import tolerance

from _hull_oracle import orient_sign


def test_orient_sign_convention():
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    face = np.array([[0, 1, 2]])  # counter-clockwise seen from +z
    q = np.array([[0.2, 0.2, 1.0], [0.2, 0.2, -1.0], [5.0, 5.0, 0.0], [0.1, 0.1, 1e-300]])
    assert orient_sign(pts, face, q).tolist() == [[-1, 1, 0, -1]]


def assert_closed_outward_surface(points: np.ndarray, faces: np.ndarray) -> None:
    """Every directed edge once, its reverse once; Euler 2; a centre below every face."""
    assert faces.ndim == 2 and faces.shape[1] == 3 and faces.dtype.kind == "i"
    assert len(faces) >= 4
    edges = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    directed = set(map(tuple, edges.tolist()))
    assert len(directed) == len(edges), "a directed edge is used twice"
    assert all((b, a) in directed for a, b in directed), "an edge without its twin"
    verts = np.unique(faces)
    assert len(verts) - len(edges) // 2 + len(faces) == 2
    centre = points[verts].mean(axis=0)[None, :]
    assert np.all(orient_sign(points, faces, centre) > 0), "a face does not face away from the centre"


def assert_nothing_outside(points: np.ndarray, faces: np.ndarray, rows: np.ndarray) -> None:
    sign = orient_sign(points, faces, points[rows])
    bad = np.argwhere(sign < 0)
    assert len(bad) == 0, f"row {rows[bad[0][1]]} is strictly outside face {faces[bad[0][0]].tolist()}"


def ball(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniform in the unit ball, by rejection from the cube: elementwise arithmetic only, so the
    same generator state gives the same bytes on every machine (no ``**``, no BLAS)."""
    kept = np.zeros((0, 3))
    while len(kept) < n:
        x = rng.random((2 * n + 8, 3)) * 2 - 1
        kept = np.vstack([kept, x[x[:, 0] * x[:, 0] + x[:, 1] * x[:, 1] + x[:, 2] * x[:, 2] <= 1.0]])
    return kept[:n].copy()


CLOUDS = {
    "ball": ball,
    "cube": lambda rng, n: rng.uniform(-1.0, 1.0, (n, 3)),
    "gauss": lambda rng, n: rng.standard_normal((n, 3)) * [3.0, 1.0, 0.5] + [10.0, -2.0, 0.0],
}


def symmetric_sphere(rng: np.random.Generator, n_half: int, n_inner: int) -> np.ndarray:
    """Points v and -v on the unit sphere plus symmetric interior points, shuffled.

    The centroid is the origin up to rounding, so each sphere point is the
    farthest point along its own direction: the support mapping keeps them all.
    """
    v = rng.standard_normal((n_half, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    # Interior points within half the in-radius of the sphere points' hull.
    inradius = -ConvexHull(np.vstack([v, -v])).equations[:, 3].max()
    w = rng.standard_normal((n_inner, 3))
    w *= (0.5 * inradius * rng.random((n_inner, 1))) / np.linalg.norm(w, axis=1)[:, None]
    pts = np.vstack([v, -v, w, -w])
    return pts[rng.permutation(len(pts))]


def assert_qhull_hull(points: np.ndarray, faces: np.ndarray) -> None:
    """Closed, outward, Qhull's vertex set, and no input point strictly outside a face."""
    assert_closed_outward_surface(points, faces)
    assert set(faces.ravel().tolist()) == set(ConvexHull(points).vertices.tolist())
    assert_nothing_outside(points, faces, np.arange(len(points)))


def test_registered():
    spec = _registry.get_algorithm("kenwright")
    assert spec.func is kenwright_hull and spec.dim == 3 and spec.takes_eps


def test_cube_with_interior_points_first():
    # The tetrahedron and the early hulls are made of interior points; the
    # corners, coming last, must swallow them all.
    rng = np.random.default_rng(0)
    cube = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
    pts = np.vstack([rng.uniform(0.1, 0.9, (40, 3)), cube])
    faces = kenwright_hull(pts)
    assert_closed_outward_surface(pts, faces)
    assert set(faces.ravel().tolist()) == set(range(40, 48))
    assert_nothing_outside(pts, faces, np.arange(len(pts)))


# -- sphere off, general position: Qhull's hull -------------------------------------------


@pytest.mark.parametrize("policy", ["scaled", "fixed"])
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(4, 200),
    cloud=st.sampled_from(sorted(CLOUDS)),
)
def test_random_cloud_gives_qhull_hull(policy, seed, n, cloud):
    pts = CLOUDS[cloud](np.random.default_rng(seed), n)
    faces = kenwright_hull(pts, eps=tolerance(pts, policy))
    assert_qhull_hull(pts, faces)


def test_fixed_large_cloud():
    pts = ball(np.random.default_rng(2000), 2000)
    assert_qhull_hull(pts, kenwright_hull(pts))


def test_fixed_large_symmetric_sphere_with_interior_points():
    pts = symmetric_sphere(np.random.default_rng(7), 1000, 500)  # n = 3000
    faces = kenwright_hull(pts)
    assert_closed_outward_surface(pts, faces)
    assert set(faces.ravel().tolist()) == set(ConvexHull(pts).vertices.tolist())
    a, b, c = (pts[faces[:, j]] for j in range(3))
    normals = np.cross(b - a, c - a)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    heights = normals @ pts.T - np.einsum("ij,ij->i", normals, a)[:, None]
    assert heights.max() <= 1e-12


def test_blocked_scan_equals_one_point_at_a_time(monkeypatch):
    # Runs of invisible points are tested in blocks; with a block of one the
    # loop is the seed's plain "for i" loop, and the faces must be identical.
    pts = np.vstack([ball(np.random.default_rng(5), 1500), CLOUDS["cube"](np.random.default_rng(6), 300)])
    blocked = kenwright_hull(pts)
    monkeypatch.setattr(kenwright, "_BLOCK_ELEMENTS", 1)
    assert np.array_equal(kenwright_hull(pts), blocked)


@pytest.mark.parametrize("few", [0, 10**9], ids=["numpy-horizon", "python-horizon"])
def test_horizon_in_python_or_numpy_gives_the_same_faces(monkeypatch, few):
    # The horizon of a few removed faces is found in plain Python, of many with
    # np.unique: either way the same edges in the same order, so the same faces.
    pts = np.vstack([ball(np.random.default_rng(7), 400), CLOUDS["cube"](np.random.default_rng(8), 200)])
    expected = kenwright_hull(pts)
    monkeypatch.setattr(kenwright, "_FEW_FACES", few)
    assert np.array_equal(kenwright_hull(pts), expected)
    removed = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [4, 5, 6]])  # a cap of three faces and a lone one
    assert kenwright._horizon(removed, 7).tolist() == [[1, 2], [2, 3], [3, 1], [4, 5], [5, 6], [6, 4]]


def test_insertion_order_is_input_order():
    # A pyramid's square top is split by one diagonal.  The starting
    # tetrahedron is the apex and the first three corners in input order; the
    # fourth corner is coplanar with that top face, so the face is kept and
    # the diagonal joins the first and third corners, whichever they are.
    top = np.array([[0.0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
    for shift in range(4):
        pts = np.vstack([[[0.5, 0.5, -1.0]], np.roll(top, -shift, axis=0)])
        faces = kenwright_hull(pts)
        assert_closed_outward_surface(pts, faces)
        top_faces = [set(f) for f in faces.tolist() if 0 not in f]
        assert len(top_faces) == 2 and {1, 2, 3} in top_faces
        assert top_faces[0] & top_faces[1] == {1, 3}


def test_octahedron_interior_point_first_is_dropped():
    # The interior point is in the starting tetrahedron, then swallowed.
    pts = np.array(
        [[0.5, 0.5, 0.5], [2.0, 0, 0], [-2, 0, 0], [0, 2, 0], [0, -2, 0], [0, 0, 2], [0, 0, -2]]
    )
    faces = kenwright_hull(pts)
    assert_closed_outward_surface(pts, faces)
    assert set(faces.ravel().tolist()) == set(range(1, 7))
    assert len(faces) == 8


def test_duplicates_within_eps_are_one_vertex():
    cube = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
    pts = np.vstack([cube, cube + 1e-13])  # within eps=1e-12 of the originals
    faces = kenwright_hull(pts, eps=1e-12)
    assert set(faces.ravel().tolist()) <= set(range(8))
    assert_closed_outward_surface(pts, faces)


def test_starting_tetrahedron_skips_coplanar_leaders():
    # The first four rows lie in z = 0; the scan takes the next row off that
    # plane, and the hull is still closed and complete.
    pts = np.array(
        [[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    )
    faces = kenwright_hull(pts)
    assert_closed_outward_surface(pts, faces)
    assert len(faces) == 8


def test_input_is_not_written():
    pts = ball(np.random.default_rng(3), 100)
    pts.setflags(write=False)
    kenwright_hull(pts)


def test_step_limit(monkeypatch):
    monkeypatch.setattr(kenwright, "FACE_LIMIT_PER_POINT", 0)
    monkeypatch.setattr(kenwright, "FACE_LIMIT_BASE", 5)
    pts = symmetric_sphere(np.random.default_rng(1), 10, 0)
    match = r"^kenwright: insertion step \d+ .* over the limit 5 for 20 points$"
    with pytest.raises(AlgorithmStepLimit, match=match):
        kenwright_hull(pts)


# -- sphere on: the seed's full method (sphere_project, then this hull) ---------------------------


def sphere_path(points: np.ndarray, policy: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What the harness runs for sphere=on: projected points, their input rows, the faces."""
    projected, rows = sphere_project(points, eps=tolerance(points, policy))
    return projected, rows, kenwright_hull(projected, eps=tolerance(projected, policy))


@pytest.mark.parametrize("policy", ["scaled", "fixed"])
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(4, 200),
    cloud=st.sampled_from(sorted(CLOUDS)),
)
def test_sphere_path_gives_hull_of_projected_points(policy, seed, n, cloud):
    pts = CLOUDS[cloud](np.random.default_rng(seed), n)
    projected, _ = sphere_project(pts, eps=tolerance(pts, policy))
    if len(projected) < 4:
        # The support mapping can leave two or three points of a real tetrahedron.
        match = f"^kenwright: need at least 4 points for a tetrahedron, got {len(projected)}$"
        with pytest.raises(ValueError, match=match):
            sphere_path(pts, policy)
        return
    projected, _, faces = sphere_path(pts, policy)
    assert_qhull_hull(projected, faces)
    # On a sphere every projected point is a vertex.
    assert set(faces.ravel().tolist()) == set(range(len(projected)))


def test_harness_sphere_variant_runs_the_sphere_path():
    pts = ball(np.random.default_rng(11), 300)
    outcome = call_algorithm(Case.from_points(pts), AlgorithmConfig("kenwright", "on", "scaled"))
    assert outcome.kind == "ok", outcome.error
    _, rows, faces = sphere_path(pts, "scaled")
    # The harness records the canonical order (faces sorted, each from its smallest index).
    assert canonical_output(outcome.faces).to_python() == canonical_output(FaceSet.from_triangles(rows[faces])).to_python()


def test_sphere_path_culls_true_hull_vertices_on_random_clouds():
    # The sphere variant's flaw, kept: a vertex of the hull that is not the
    # farthest point along any direction centroid -> p_i never reaches the
    # projected set, so it is missing after mapping back.
    pts = ball(np.random.default_rng(0), 50)
    c = pts.mean(axis=0)
    d = pts - c
    scores = d[:, 0:1] * pts[:, 0] + d[:, 1:2] * pts[:, 1] + d[:, 2:3] * pts[:, 2]  # row i: direction_i . p_j
    top2 = np.sort(scores, axis=1)[:, -2:]
    # Each winner leads by far more than rounding (of the centroid or the
    # products, however a machine orders them) could move a score: geometry.
    assert (top2[:, 1] - top2[:, 0] > 1e-9 * np.abs(top2[:, 1]).max()).all()
    winners = set(np.argmax(scores, axis=1).tolist())
    culled = set(ConvexHull(pts).vertices.tolist()) - winners
    assert culled, "expected the support mapping to miss some vertex of this cloud"
    _, rows, faces = sphere_path(pts, "scaled")
    mapped = rows[faces]
    assert set(mapped.ravel().tolist()) == winners
    assert_closed_outward_surface(pts, mapped)
    culled_rows = np.array(sorted(culled))
    assert np.any(orient_sign(pts, mapped, pts[culled_rows]) < 0), "culled vertices must stick out"
    # The same points with sphere off: nothing is culled.
    assert culled <= set(kenwright_hull(pts).ravel().tolist())


def test_sphere_path_is_complete_on_symmetric_points():
    # Where the support mapping keeps every extreme point, the seed's full
    # method gives the true hull's vertices once mapped back.
    pts = symmetric_sphere(np.random.default_rng(4), 60, 30)
    _, rows, faces = sphere_path(pts, "scaled")
    assert set(rows[faces].ravel().tolist()) == set(ConvexHull(pts).vertices.tolist())


# -- degenerate input: whatever the method gives, but promptly and clearly ----------------------


def _minkowski_cubes() -> np.ndarray:
    cube = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))
    t = 0.3
    rot = np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])
    return (cube[:, None, :] + (cube @ rot.T)[None, :, :]).reshape(-1, 3)


DEGENERATE = {
    "coplanar-grid": np.array([[x, y, 0.0] for x in range(5) for y in range(5)]),
    "collinear": np.array([[t, 2 * t, 3 * t] for t in np.linspace(0.0, 1.0, 9)]),
    "all-duplicates": np.ones((12, 3)),
    "cube-grid": np.array(list(itertools.product(range(4), repeat=3)), dtype=float),
    "minkowski-cubes": _minkowski_cubes(),
    "far-offset-cube": np.array(list(itertools.product((0.0, 1e-6), repeat=3))) + 1e8,
    # Dot products and cross products under- or overflow at these scales.
    "tiny-scale": np.random.default_rng(1).standard_normal((40, 3)) * 1e-200,
    "huge-scale": np.random.default_rng(1).standard_normal((40, 3)) * 1e200,
}


@pytest.mark.parametrize("sphere", ["off", "on"])
@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_degenerate_input_no_hang_and_clear_errors(name, sphere):
    pts = DEGENERATE[name]
    try:
        if sphere == "on":
            pts, _ = sphere_project(pts)
        faces = kenwright_hull(pts)
    except (ValueError, HullstressError) as exc:
        message = str(exc)
        assert message.startswith(("kenwright: ", "points row ")) and "\n" not in message
    else:
        assert faces.ndim == 2 and faces.shape[1] == 3
        assert faces.size == 0 or 0 <= faces.min() <= faces.max() < len(pts)


_TETRA = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])


@pytest.mark.parametrize(
    "points, kwargs, match",
    [
        (np.zeros((5, 2)), {}, r"^points must have shape \(n, 3\), got \(5, 2\)$"),
        (np.zeros(3), {}, r"^points must have shape \(n, 3\), got \(3,\)$"),
        (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.inf]]), {}, "^points must be finite, got 1 "),
        (_TETRA[:3], {}, r"^kenwright: need at least 4 points for a tetrahedron, got 3$"),
        (np.zeros((0, 3)), {}, r"^kenwright: need at least 4 points for a tetrahedron, got 0$"),
        (_TETRA, {"eps": -1.0}, r"^eps must be a finite float >= 0 or None, got -1.0$"),
        (_TETRA, {"eps": float("nan")}, r"^eps must be a finite float >= 0 or None, got nan$"),
        (_TETRA, {"eps": 2.0}, r"^kenwright: all 4 points are within eps=2.0 of one point$"),
    ],
)
def test_bad_calls(points, kwargs, match):
    with pytest.raises(ValueError, match=match):
        kenwright_hull(points, **kwargs)


@pytest.mark.parametrize("module", [kenwright], ids=lambda m: m.__name__.rsplit(".", 1)[-1])
def test_docstring_examples_run_as_printed(module):
    # The examples document the seed's behaviour, weak spots included.
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, verbose=False)
    assert result.attempted > 0 and result.failed == 0


_component = st.one_of(st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
                       st.floats(-1e3, 1e3))


@given(st.lists(st.tuples(*[_component] * 6), min_size=1, max_size=8))
def test_cross_is_two_products_and_one_difference_per_component(rows):
    # IEEE double products and differences, one rounding each: Python floats give the same bits.
    u = np.array([r[:3] for r in rows])
    v = np.array([r[3:] for r in rows])
    with np.errstate(all="ignore"):
        got = _cross(u, v)
    for (a0, a1, a2, b0, b1, b2), row in zip(rows, got.tolist()):
        expected = [a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0]
        assert [x if x == x else "nan" for x in row] == [x if x == x else "nan" for x in expected]
