"""The exact judge of lower-dimensional answers (docs/lower-dimensional.md)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.checker import check
from hullstress.checker.lowdim import full_dimensional, lower_dimensional_hull
from hullstress.config import AlgorithmConfig
from hullstress.errors import ContractViolation
from hullstress.evaluate import evaluate
from hullstress._registry import ALGORITHMS, register_algorithm


def _segment_2d() -> np.ndarray:
    # Points on y = 2x, out of order, with a repeat of an endpoint (row 5 = row 1).
    return np.array([[1.0, 2.0], [3.0, 6.0], [0.0, 0.0], [2.0, 4.0], [0.5, 1.0], [3.0, 6.0]])


def _segment_3d() -> np.ndarray:
    return np.array([[0.5, 1.0, 1.5], [0.0, 0.0, 0.0], [2.0, 4.0, 6.0], [1.0, 2.0, 3.0]])


def _one_point(dim: int) -> np.ndarray:
    return np.full((4, dim), 0.1)


def _tilted_square() -> np.ndarray:
    # A square with an edge midpoint (4) and its centre (5) in the plane z = x + 2y + 1.
    xy = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 0.0], [1.0, 1.0]])
    return np.c_[xy, xy[:, 0] + 2 * xy[:, 1] + 1]


# name -> (points, answer, expected: True for a pass, else the check that fails)
CASES = {
    "segment, endpoints": (_segment_2d(), [2, 1], True),
    "segment, endpoints reversed": (_segment_2d(), [1, 2], True),
    "segment, a duplicate of an endpoint stands for it": (_segment_2d(), [2, 5], True),
    "segment, there and back through inner points": (_segment_2d(), [2, 4, 0, 1, 3], True),
    "segment, inner points out of order": (_segment_2d(), [2, 0, 4, 1], "convexity"),
    "segment, one endpoint missing": (_segment_2d(), [2, 3], "containment"),
    "segment, an endpoint twice": (_segment_2d(), [2, 1, 5], "manifoldness"),
    "segment, as a triangle of collinear points": (_segment_2d(), [2, 1, 0], True),
    "segment, nothing": (_segment_2d(), [], "containment"),
    "one point, one index": (_one_point(2), [3], True),
    "one point, two indices": (_one_point(2), [0, 1], "manifoldness"),
    "3D segment, one face of two vertices": (_segment_3d(), [[1, 2]], True),
    "3D segment, a face and its reverse": (_segment_3d(), [[1, 0, 2], [2, 0, 1]], True),
    "3D segment, two different faces": (_segment_3d(), [[1, 2], [1, 3]], "manifoldness"),
    "3D one point, one face of one vertex": (_one_point(3), [[2]], True),
    "flat square, one polygon": (_tilted_square(), [[0, 4, 1, 2, 3]], True),
    "flat square, the other side": (_tilted_square(), [[3, 2, 1, 0]], True),
    "flat square, two-sided pair": (_tilted_square(), [[0, 1, 2, 3], [3, 2, 1, 0]], True),
    "flat square, triangulated pillow": (_tilted_square(), [[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]], True),
    "flat square, fan from the centre plus the polygon": (
        _tilted_square(), [[5, 0, 4], [5, 4, 1], [5, 1, 2], [5, 2, 3], [5, 3, 0], [3, 2, 1, 0]], True),
    "flat square, overlapping triangles": (_tilted_square(), [[0, 1, 2], [0, 2, 3], [1, 2, 3]], "manifoldness"),
    "flat square, a hole": (_tilted_square(), [[0, 1, 2], [0, 2, 3], [0, 2, 1]], "manifoldness"),
    "flat square, a corner missing": (_tilted_square(), [[0, 1, 2]], "containment"),
    "flat square, a self-crossing face": (_tilted_square(), [[0, 2, 1, 3]], "convexity"),
    "flat square, the midpoint off its edge order": (_tilted_square(), [[0, 1, 4, 2, 3]], "convexity"),
    "flat square, a zero-area face": (_tilted_square(), [[0, 4, 1], [0, 1, 2, 3]], "convexity"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_lower_dimensional_answers(name):
    points, answer, expected = CASES[name]
    verdict = check(points, answer, qhull=False)
    assert verdict.affine_rank < points.shape[1] and verdict.qhull_agreement is None
    if expected is True:
        assert verdict.ok, verdict.detail
        assert verdict.detail.startswith("ok: ") and verdict.severity == "none"
    else:
        assert not verdict.ok and expected in verdict.failed_checks, verdict.detail


def test_reasons_cite_the_exact_answer_not_qhull():
    # The example: a collinear 2D set judged against Qhull's (joggled) vertex count.
    pts = _segment_2d()
    v = check(pts, [2, 3])  # with the Qhull reference computed
    assert "the segment from point 2 (0.0, 0.0) to point 1 (3.0, 6.0)" in v.detail
    assert "extreme point 1 missing" in v.detail and "qhull" not in v.detail.lower()
    assert v.n_extreme == 2 and v.n_missing_extreme == 1 and v.offending["missing_extreme"] == (1,)
    assert v.n_outside == 2 and v.offending["containment"] == (1, 5)
    flat = check(_tilted_square(), [[0, 1, 2]])
    assert "the flat polygon with extreme points 0, 1, 2, 3" in flat.detail


def test_exact_hull_of_lower_dimensional_sets():
    h = lower_dimensional_hull(_segment_2d())
    assert (h.rank, h.extreme.tolist()) == (1, [2, 1])
    assert lower_dimensional_hull(_one_point(3)).extreme.tolist() == [0]
    h = lower_dimensional_hull(_tilted_square())
    assert h.rank == 2 and h.extreme.tolist() == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="full-dimensional"):
        lower_dimensional_hull(np.eye(3)[[0, 1, 2, 0]] + np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 1, 1]]))


def test_a_two_vertex_face_is_a_contract_violation_above_rank_one():
    with pytest.raises(ContractViolation, match="face 0 has 2 vertices; a face needs at least 3"):
        check(_tilted_square(), [[0, 1]])


def test_ulp_close_points_are_not_one_point():
    # Exactness: 1.0 and the next double are two points, so [0] alone misses an endpoint.
    pts = np.array([[1.0, 1.0], [np.nextafter(1.0, 2.0), 1.0]])
    assert not check(pts, [0], qhull=False).containment
    assert check(pts, [1, 0], qhull=False).ok


def _fraction_cover(points_2d, triangles, q) -> int:
    """How many triangles (counter-clockwise) strictly contain q, in rationals."""
    def orient(a, b, c):
        a, b, c = ([Fraction(float(v)) for v in p] for p in (a, b, c))
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    return sum(all(orient(points_2d[t[i]], points_2d[t[(i + 1) % 3]], q) > 0 for i in range(3)) for t in triangles)


@pytest.mark.parametrize("seed", range(4))
def test_random_flat_triangulations_agree_with_a_rational_cover_count(seed):
    """A side passes exactly when it covers every point of the polygon once (checked in rationals)."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(seed)
    xy = rng.integers(-8, 9, size=(14, 2)).astype(float)
    xy = np.unique(xy, axis=0)
    pts = np.c_[xy, 3 * xy[:, 0] - xy[:, 1] + 0.5]  # exactly coplanar, tilted
    tri = Delaunay(xy).simplices
    u, v = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    ccw = np.where((u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0)[:, None], tri, tri[:, ::-1])  # small integers: exact
    surface = np.vstack([ccw, ccw[:, ::-1]])
    assert check(pts, surface, qhull=False).ok
    dropped = np.vstack([ccw[1:], ccw[:, ::-1]])
    probe = xy[ccw[0]].mean(axis=0)  # inside the dropped triangle only
    assert _fraction_cover(xy, ccw[1:], probe) == 0
    assert not check(pts, dropped, qhull=False).ok
    doubled = np.vstack([ccw, ccw[:1]])
    assert _fraction_cover(xy, doubled, probe) == 2 and not check(pts, doubled, qhull=False).ok


def test_full_rank_certificate_is_exact():
    rng = np.random.default_rng(0)
    assert full_dimensional(rng.random((50, 3)))
    flat = np.c_[rng.random((50, 2)), np.zeros(50)]
    assert not full_dimensional(flat)
    # One point off the plane by one ulp is full-dimensional, and nothing is lost by the quick test.
    flat[7, 2] = 5e-324
    v = check(flat, [[0, 1, 2]], qhull=False)
    assert v.affine_rank == 3


def _endpoints(points):
    """A 2D hull that answers a collinear input with its two extreme endpoints (a test algorithm)."""
    order = np.lexsort(points.T[::-1])
    return [int(order[-1]), int(order[0])]


@pytest.fixture
def endpoints_algorithm():
    register_algorithm("test-endpoints-2d", dim=2)(_endpoints)
    yield AlgorithmConfig("test-endpoints-2d")
    ALGORITHMS.remove("test-endpoints-2d")


def test_the_sweep_passes_a_correct_lower_dimensional_answer(endpoints_algorithm):
    case = Case(points=_segment_2d(), dim=2, family="collinear-line")
    row = evaluate(case, endpoints_algorithm)
    assert (row["status"], row["stage"], row["affine_rank"]) == ("pass", "algorithm", 1)
    wrong = Case(points=np.r_[_segment_2d(), [[1.0, 0.0]]], dim=2, family="x")  # not collinear any more
    assert evaluate(wrong, endpoints_algorithm)["status"] == "fail"
