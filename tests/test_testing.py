"""Tests for hullstress.testing: the public assertion helpers pass on hulls and
fail, showing both sides, on corrupted ones."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from hullstress.errors import UsageError
from hullstress.testing import assert_same_hull, assert_valid_hull


def _ball(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    d = rng.standard_normal((n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * rng.uniform(0.2, 1.0, size=(n, 1))


def _square(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1.0, 1.0, size=(n, 2))


def _outward_triangles(points: np.ndarray) -> np.ndarray:
    """Qhull's triangles, each flipped to face away from the centroid (general position only)."""
    tri = ConvexHull(points).simplices.copy()
    a, b, c = (points[tri[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), points.mean(axis=0) - a) > 0
    tri[inward, 1], tri[inward, 2] = tri[inward, 2], tri[inward, 1].copy()
    return tri


def _message(excinfo: pytest.ExceptionInfo[AssertionError]) -> str:
    return str(excinfo.value)


def _shows_both_sides(message: str) -> None:
    assert "expected:" in message and "got:" in message, message


@pytest.mark.parametrize("seed", [0, 1])
def test_valid_hulls_pass(seed: int) -> None:
    p2 = _square(40, seed)
    assert assert_valid_hull(p2, ConvexHull(p2).vertices).ok
    p3 = _ball(60, seed)
    verdict = assert_valid_hull(p3, _outward_triangles(p3))
    assert verdict.ok and verdict.n_faces == len(ConvexHull(p3).simplices)


def test_flipped_face_fails_with_both_sides() -> None:
    points = _ball(40, 2)
    tri = _outward_triangles(points)
    tri[5] = tri[5, [0, 2, 1]]
    with pytest.raises(AssertionError) as excinfo:
        assert_valid_hull(points, tri)
    message = _message(excinfo)
    assert message.startswith("not a valid convex hull of 40 points in 3D: failed")
    assert "manifoldness" in message.splitlines()[0]
    _shows_both_sides(message)


def test_missing_face_fails_with_counts() -> None:
    points = _ball(40, 3)
    tri = _outward_triangles(points)
    with pytest.raises(AssertionError) as excinfo:
        assert_valid_hull(points, tri[1:])
    message = _message(excinfo)
    assert "manifoldness" in message.splitlines()[0]
    assert f"got:      {len(tri) - 1} faces" in message
    _shows_both_sides(message)


def test_interior_vertex_fails_and_names_the_point_left_outside() -> None:
    points = np.vstack([_ball(40, 4), [[0.0, 0.0, 0.0]]])  # row 40: an interior point
    tri = _outward_triangles(points)
    lost = int(tri[0, 0])  # an extreme point, replaced by the interior one everywhere
    tri[tri == lost] = 40
    with pytest.raises(AssertionError) as excinfo:
        assert_valid_hull(points, tri, max_offending=len(points))
    message = _message(excinfo)
    assert "containment" in message.splitlines()[0]
    coords = "(" + ", ".join(repr(float(x)) for x in points[lost]) + ")"
    assert f"point {lost} {coords}" in message
    _shows_both_sides(message)


def test_clockwise_polygon_fails() -> None:
    points = _square(30, 5)
    with pytest.raises(AssertionError) as excinfo:
        assert_valid_hull(points, ConvexHull(points).vertices[::-1])
    message = _message(excinfo)
    assert message.startswith("not a valid convex hull of 30 points in 2D")
    _shows_both_sides(message)


@pytest.mark.parametrize(
    ("faces", "match"),
    [
        (np.array([[0, 1, 99]]), "faces breaks the output contract: .*out of range"),
        (None, "faces breaks the output contract: .*None"),
        (np.array([[0.0, 1.0, 2.0]]), "faces breaks the output contract: .*integer"),
    ],
)
def test_contract_violations_are_assertion_errors(faces: object, match: str) -> None:
    with pytest.raises(AssertionError, match=match):
        assert_valid_hull(_ball(10, 6), faces)


@pytest.mark.parametrize("points", [np.zeros(5), np.zeros((5, 4)), [[0.0, 1.0], [2.0]]])
def test_bad_points_are_usage_errors(points: object) -> None:
    with pytest.raises(UsageError, match="points must"):
        assert_valid_hull(points, [0, 1, 2])


def test_same_hull_passes_across_triangulations_duplicates_and_rotation() -> None:
    cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    pts = np.vstack([cube, cube[7]])  # row 8 duplicates row 7
    a = _outward_triangles(pts[:8])
    b = a.copy()
    b[b == 7] = 8
    b = np.roll(b, 3, axis=0)
    assert_same_hull(pts, a, b)
    sq = _square(25, 7)
    v = ConvexHull(sq).vertices
    assert_same_hull(sq, v, np.roll(v, 2))


def test_same_hull_allows_boundary_non_extreme_vertices() -> None:
    sq = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 0.0], [1.0, 1.0]])
    assert_same_hull(sq, [0, 1, 2, 3], [0, 4, 1, 2, 3])  # 4 is the midpoint of edge 0-1


def test_different_hulls_fail_showing_both_vertex_sets() -> None:
    points = _ball(30, 8)
    tri = _outward_triangles(points)
    lost = int(tri[0, 0])
    keep = ~(tri == lost).any(axis=1)
    with pytest.raises(AssertionError) as excinfo:
        assert_same_hull(points, tri, tri[keep])
    message = _message(excinfo)
    lines = message.splitlines()
    assert lines[0] == "not the same hull: b is not a valid hull"
    assert lines[1].startswith("  a: valid;")
    assert lines[2].startswith("  b: NOT a valid hull")
    coords = "(" + ", ".join(repr(float(x)) for x in points[lost]) + ")"
    assert lines[3] == f"  vertices only in a: {lost} {coords}"
    assert lines[4] == "  vertices only in b: none"


def test_same_hull_reports_a_contract_violation_by_side() -> None:
    sq = _square(10, 9)
    with pytest.raises(AssertionError, match="^b breaks the output contract"):
        assert_same_hull(sq, ConvexHull(sq).vertices, [0, 1, 10])
