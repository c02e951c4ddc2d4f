"""The sphere method's two causes, recorded per sphere=on row: exact on inputs built to show each.

Each constructed input's expected counts are proved here independently of
the code under test, in integer or rational arithmetic: which points the
support mapping returns (every dot product compared exactly), which points
are extreme, and which triangles are faces of the input's hull.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.evaluate import evaluate
from hullstress.records import SphereStructure
from hullstress.sphere import map_back, project_onto_sphere, sphere_centroid, sphere_project

# A wide box whose top edge carries a vertex just above its chord: extreme, yet never the farthest
# point along any direction from the centroid to an input point (the right corner always beats it).
SHOULDER = np.array([[-10.0, 1.0], [10.0, 1.0], [5.0, 1.0078125], [-10.0, -1.0], [10.0, -1.0]])
SHOULDER_VERTEX = 2
# Four integer points and their negatives: every point is strictly the farthest along its own
# direction from the centroid (the origin), so nothing is dropped; their norms differ, and moving
# them radially onto a sphere changes which triples span faces.
HALF = np.array([[5, 5, -1], [1, -4, -3], [-5, 0, -3], [-3, 1, 2]])
SYMMETRIC = np.vstack([HALF, -HALF]).astype(np.float64)


def _exact_support(points: np.ndarray, centroid: list[Fraction]) -> set[int]:
    """Rows that are the unique farthest point along some direction centroid -> input point (rationals)."""
    pts = [[Fraction(x) for x in p] for p in points.tolist()]
    found = set()
    for p in pts:
        d = [a - c for a, c in zip(p, centroid)]
        values = [sum(a * b for a, b in zip(d, q)) for q in pts]
        best = max(values)
        found.update(j for j, v in enumerate(values) if v == best)
    return found


def _orient(a, b, c, d) -> int:
    """Sign of det[b - a, c - a, d - a] for integer (or rational) points."""
    u, v, w = ([q[i] - a[i] for i in range(3)] for q in (b, c, d))
    det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
    return (det > 0) - (det < 0)


def _is_supporting(points: list[list[int]], tri) -> bool:
    """Whether the plane of ``tri`` has every point on one side (a face plane of the hull)."""
    sides = {_orient(*(points[i] for i in tri), p) for p in points} - {0}
    return len(sides) <= 1


def test_the_support_mapping_provably_drops_the_shoulder_vertex():
    centroid = [sum(Fraction(p[j]) for p in SHOULDER.tolist()) / len(SHOULDER) for j in range(2)]
    assert _exact_support(SHOULDER, centroid) == {0, 1, 3, 4}  # the shoulder is never the farthest
    # ... and it is extreme: strictly above the chord from (-10, 1) to (10, 1).
    assert SHOULDER[SHOULDER_VERTEX, 1] > 1.0
    _, rows = sphere_project(SHOULDER)
    assert SHOULDER_VERTEX not in rows.tolist()
    row = evaluate(Case(points=SHOULDER, dim=2, family="test"), AlgorithmConfig("monotone-chain", "on", "scaled"))
    assert (row["sphere_extreme"], row["sphere_lost_extreme"]) == (5, 1)
    assert row["sphere_structure"] == SphereStructure.CHANGED
    # With every true vertex kept, the 2D projection keeps the angular order, so the hull: only loss hurts here.
    assert row["sphere_kept_structure"] == SphereStructure.SAME
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "preprocess", "fail")


def test_a_symmetric_set_keeps_every_vertex_but_changes_faces():
    ints = SYMMETRIC.astype(int).tolist()
    gram = SYMMETRIC.astype(int) @ SYMMETRIC.astype(int).T
    # Each point is strictly its own support from the centroid 0 (exact: integer dot products) ...
    assert all(gram[i, i] > gram[i, j] for i in range(8) for j in range(8) if i != j)
    assert sphere_centroid(SYMMETRIC).tolist() == [0.0, 0.0, 0.0]
    _, rows = sphere_project(SYMMETRIC)
    assert sorted(rows.tolist()) == list(range(8))  # ... so the surface list holds every point.
    # The method's own projection, hulled (scipy), mapped back: some triangle is not a face plane.
    from scipy.spatial import ConvexHull

    projected = project_onto_sphere(SYMMETRIC, np.arange(8), np.zeros(3))
    triangles = map_back(ConvexHull(projected).simplices, np.arange(8))
    assert not all(_is_supporting(ints, tri) for tri in triangles.tolist())
    row = evaluate(Case(points=SYMMETRIC, dim=3, family="test"), AlgorithmConfig("kenwright", "on", "scaled"))
    assert (row["sphere_extreme"], row["sphere_lost_extreme"]) == (8, 0)
    assert row["sphere_structure"] == row["sphere_kept_structure"] == SphereStructure.CHANGED
    assert (row["stage"], row["sphere_method"]) == ("preprocess", "fail")


def test_a_regular_polygon_keeps_its_hull():
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    case = Case(points=np.c_[np.cos(angles), np.sin(angles)] * 3.0, dim=2, family="regular-polygon")
    row = evaluate(case, AlgorithmConfig("monotone-chain", "on", "scaled"))
    assert (row["sphere_extreme"], row["sphere_lost_extreme"]) == (12, 0)
    assert row["sphere_structure"] == row["sphere_kept_structure"] == SphereStructure.SAME
    assert row["sphere_method"] == "pass"


def test_the_causes_do_not_depend_on_the_algorithm():
    rng = np.random.default_rng(5)
    case = Case(points=rng.normal(size=(40, 3)), dim=3, family="test")
    cols = ("sphere_extreme", "sphere_lost_extreme", "sphere_structure", "sphere_kept_structure")
    rows = [evaluate(case, AlgorithmConfig(name, "on", "scaled")) for name in ("kenwright", "henckel", "gift-wrap-3d")]
    assert len({tuple(r[c] for c in cols) for r in rows}) == 1
    # A vertex lost always changes the hull (the invariant the findings rely on).
    assert rows[0]["sphere_lost_extreme"] == 0 or rows[0]["sphere_structure"] == SphereStructure.CHANGED


def test_no_columns_without_a_projection():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(20, 3))
    off = evaluate(Case(points=pts, dim=3, family="test"), AlgorithmConfig("kenwright", "off", "scaled"))
    assert off["sphere_structure"] == off["sphere_kept_structure"] == ""
    assert off["sphere_extreme"] is None and off["sphere_lost_extreme"] is None
    # The projection raises (squares underflow): no projection, so no causes either.
    tiny = evaluate(Case(points=pts * 1e-170, dim=3, family="test"), AlgorithmConfig("kenwright", "on", "scaled"))
    assert (tiny["stage"], tiny["sphere_method"], tiny["sphere_structure"]) == ("preprocess", "error", "")


@pytest.mark.parametrize("dim", [2, 3])
def test_a_projection_of_lower_rank_is_a_changed_structure(dim):
    # A long segment and apexes just off it near its middle: every direction from the centroid to an
    # apex points mostly along +x, so the surface list is the segment's two ends, a flat projection.
    pts = np.zeros((dim + 1, dim))
    pts[0, 0], pts[1, 0] = -1000.0, 1000.0
    for k in range(2, dim + 1):
        pts[k, 0], pts[k, k - 1] = 1.0, 1e-3
    _, rows = sphere_project(pts)
    assert rows.tolist() == [0, 1]
    row = evaluate(Case(points=pts, dim=dim, family="test"),
                   AlgorithmConfig("monotone-chain" if dim == 2 else "kenwright", "on", "scaled"))
    assert (row["sphere_extreme"], row["sphere_lost_extreme"]) == (dim + 1, dim - 1)
    assert row["sphere_structure"] == SphereStructure.CHANGED
    assert (row["stage"], row["sphere_method"]) == ("preprocess", "fail")
