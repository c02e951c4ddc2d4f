"""Tests for hullstress.sphere: Kenwright's preliminary stage (seed 002).

Pinned to the seed's description (duplicates, centroid, support mapping,
unit-sphere projection), not to hull correctness.  The reference support
mapping here is a plain Python loop, independent of the vectorised code.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hullstress import sphere
from hullstress.sphere import map_back, remove_duplicates, sphere_project, support_indices, surface_points
from hullstress.tolerance import tolerance

CUBE = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
SQUARE = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])


def reference_surface(points: np.ndarray) -> list[int]:
    """Seed's Algorithm 1 lines 2-8 as a Python loop, for duplicate-free input.

    The dot product is summed left to right, like the code under test, so
    ties and near-ties resolve identically.
    """
    pts = points.tolist()
    d = len(pts[0])
    c = np.asarray(points).mean(axis=0).tolist()
    found: list[int] = []
    for p in pts:
        direction = [p[j] - c[j] for j in range(d)]
        if all(x == 0.0 for x in direction):
            continue
        best, best_j = None, -1
        for j, q in enumerate(pts):
            s = direction[0] * q[0]
            for t in range(1, d):
                s = s + direction[t] * q[t]
            if best is None or s > best:
                best, best_j = s, j
        if best_j not in found:
            found.append(best_j)
    return found


def random_cloud(seed: int, n: int, dim: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.standard_normal((n, dim))


# -- duplicates ---------------------------------------------------------------


def test_exact_duplicates_removed_first_occurrence_kept():
    pts = np.array([[1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [5.0, 5.0, 5.0]])
    assert remove_duplicates(pts, 0.0).tolist() == [0, 1, 4]


def test_signed_zero_is_a_duplicate():
    pts = np.array([[0.0, 1.0], [-0.0, 1.0], [3.0, 3.0]])
    assert remove_duplicates(pts, 0.0).tolist() == [0, 2]


def test_duplicates_within_tolerance_removed_outside_kept():
    eps = 1e-9
    pts = np.array([[0.0, 0.0, 0.0], [0.5e-9, 0.0, 0.0], [0.0, 2e-9, 0.0], [1.0, 1.0, 1.0]])
    assert remove_duplicates(pts, eps).tolist() == [0, 2, 3]
    assert remove_duplicates(pts, 0.0).tolist() == [0, 1, 2, 3]


def test_duplicate_greedy_chain_compares_with_kept_points_only():
    # 1 is within eps of 0 (dropped); 2 is within eps of 1 but not of 0: kept.
    pts = np.array([[0.0], [0.6], [1.2]]) @ np.array([[1.0, 0.0]])
    assert remove_duplicates(pts, 1.0).tolist() == [0, 2]


def test_default_eps_is_scaled_tolerance():
    base = np.vstack([CUBE * 4.0, [[2.0, 2.0, 2.0]]])
    eps = tolerance(base, "scaled")
    assert eps > 0.0
    near = base[1] + [eps / 2, 0.0, 0.0]  # within the scaled tolerance of row 1
    pts = np.vstack([base, near])
    assert surface_points(pts).kept.tolist() == list(range(len(base)))
    assert surface_points(pts, eps=0.0).kept.tolist() == list(range(len(pts)))


@pytest.mark.parametrize("power", [-600, -60, 60, 600])
def test_duplicate_removal_is_invariant_under_power_of_two_scaling(power):
    rng = np.random.default_rng(4)
    base = rng.standard_normal((200, 3))
    pts = np.vstack([base, base[:50] + rng.uniform(-1e-9, 1e-9, (50, 3)), base[:20]])
    eps = 1e-9
    expected = remove_duplicates(pts, eps)
    assert 200 <= len(expected) < 270  # some near copies removed, some kept
    np.testing.assert_array_equal(remove_duplicates(np.ldexp(pts, power), np.ldexp(eps, power)), expected)


def test_duplicates_never_come_back_from_projection():
    pts = np.vstack([CUBE, CUBE[::-1], CUBE])
    _, idx = sphere_project(pts)
    assert sorted(idx.tolist()) == list(range(8))


# -- centroid and projection -----------------------------------------------------


def test_centroid_is_mean_of_deduplicated_points():
    # Corner 0 repeated 50 times would drag a mean over all rows towards it.
    pts = np.vstack([np.repeat(CUBE[:1], 50, axis=0), CUBE[1:]])
    surf = surface_points(pts)
    np.testing.assert_array_equal(surf.centroid, CUBE.mean(axis=0))
    q, idx = sphere_project(pts)
    np.testing.assert_allclose(np.linalg.norm(q - CUBE.mean(axis=0), axis=1), 1.0, rtol=0, atol=1e-15)


@pytest.mark.parametrize("dim", [2, 3])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(3, 120), scale=st.sampled_from([1e-6, 1.0, 1e6]))
def test_projection_onto_unit_sphere_along_the_direction(dim, seed, n, scale):
    pts = random_cloud(seed, n, dim) * scale
    q, idx = sphere_project(pts)
    assert q.dtype == np.float64 and q.flags.c_contiguous and q.shape == (len(idx), dim)
    assert idx.dtype == np.int64
    c = pts[remove_duplicates(pts, tolerance(pts, "scaled"))].mean(axis=0)
    rel_q = q - c
    rel_p = pts[idx] - c
    # Storing centroid + unit vector rounds at the centroid's magnitude.
    atol = 8 * np.finfo(float).eps * (1.0 + np.abs(c).max())
    # every point at distance 1 from the centroid ...
    np.testing.assert_allclose(np.linalg.norm(rel_q, axis=1), 1.0, rtol=0, atol=atol)
    # ... along the ray from the centroid through its original point
    unit_p = rel_p / np.linalg.norm(rel_p, axis=1)[:, None]
    np.testing.assert_allclose(rel_q, unit_p, rtol=0, atol=atol)


@pytest.mark.parametrize("dim", [2, 3])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 60))
def test_surface_list_matches_reference_loop(dim, seed, n):
    pts = random_cloud(seed, n, dim)
    assert surface_points(pts, eps=0.0).indices.tolist() == reference_surface(pts)


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 60))
def test_surface_list_matches_reference_loop_with_ties(seed, n):
    # Small integer grid: many exact ties, which go to the lowest row.
    rng = np.random.default_rng(seed)
    grid = rng.integers(-2, 3, size=(n, 3)).astype(np.float64)
    pts = grid[np.sort(np.unique(grid, axis=0, return_index=True)[1])]
    assert surface_points(pts, eps=0.0).indices.tolist() == reference_surface(pts)


def test_support_points_are_scipy_hull_vertices():
    from scipy.spatial import ConvexHull

    pts = random_cloud(7, 500, 3)
    _, idx = sphere_project(pts)
    assert set(idx.tolist()) <= set(ConvexHull(pts).vertices.tolist())


# -- support mapping culls the interior -------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
@given(seed=st.integers(0, 2**32 - 1), n_inner=st.integers(0, 80))
def test_box_corners_survive_interior_points_never(dim, seed, n_inner):
    corners = np.array(list(itertools.product((-1.0, 3.0), repeat=dim)))
    rng = np.random.default_rng(seed)
    inner = rng.uniform(-0.9, 2.9, size=(n_inner, dim))
    order = rng.permutation(len(corners) + n_inner)
    pts = np.vstack([corners, inner])[order]
    _, idx = sphere_project(pts)
    corner_rows = {int(np.flatnonzero(order == i)[0]) for i in range(len(corners))}
    assert set(idx.tolist()) == corner_rows


def test_point_at_centroid_asks_for_no_support_point():
    # Row 0 sits exactly at the centroid; a zero direction ties every dot
    # product at 0, and counting it would add row 0 (the lowest) as a
    # "surface" point.  The reading taken: it contributes nothing.
    pts = np.vstack([[[1.0, 1.0]], SQUARE])
    assert surface_points(pts).indices.tolist() == [1, 2, 3, 4]


def test_first_found_order():
    # Centroid (1, 1).  Row 0 (interior) looks along +x: corners 3 and 4 tie,
    # the lower row (3) wins and is found first; row 5 looks along -x and
    # finds row 1 again, which is not repeated.
    pts = np.array([[1.75, 1.0], [0.0, 0.0], [0.0, 2.0], [2.0, 2.0], [2.0, 0.0], [0.25, 1.0]])
    pts = np.vstack([pts, [[1.75, 1.0]]])  # a duplicate of row 0: removed, no pull on the centroid
    surf = surface_points(pts)
    assert surf.indices.tolist() == [3, 1, 2, 4]
    np.testing.assert_array_equal(surf.centroid, [1.0, 1.0])


def test_support_indices_blocks_match_single_pass(monkeypatch):
    pts = random_cloud(3, 300, 3)
    dirs = random_cloud(4, 97, 3)
    whole = np.argmax(
        dirs[:, 0:1] * pts[:, 0] + dirs[:, 1:2] * pts[:, 1] + dirs[:, 2:3] * pts[:, 2], axis=1
    )
    monkeypatch.setattr(sphere, "_BLOCK_ELEMENTS", 1000)  # 3 directions per block
    np.testing.assert_array_equal(support_indices(pts, dirs), whole)


def test_large_input_is_fast_enough_and_bounded():
    pts = random_cloud(11, 20000, 3)
    q, idx = sphere_project(pts)
    assert 0 < len(idx) < 2000
    assert np.all(np.abs(np.linalg.norm(q - pts.mean(axis=0), axis=1) - 1.0) < 1e-12)


# -- determinism, read-only input, mapping back ----------------------------------------


def test_deterministic_and_input_untouched():
    pts = random_cloud(5, 400, 3)
    pts.setflags(write=False)
    before = pts.copy()
    q1, i1 = sphere_project(pts)
    q2, i2 = sphere_project(pts.copy())
    assert q1.tobytes() == q2.tobytes() and i1.tobytes() == i2.tobytes()
    np.testing.assert_array_equal(pts, before)


def test_indices_map_back_to_original_rows():
    rng = np.random.default_rng(9)
    pts = np.vstack([CUBE, rng.uniform(0.2, 0.8, size=(30, 3))])[rng.permutation(38)]
    q, idx = sphere_project(pts)
    c = pts.mean(axis=0)
    for i, row in enumerate(idx):
        expected = c + (pts[row] - c) / np.linalg.norm(pts[row] - c)
        np.testing.assert_allclose(q[i], expected, rtol=0, atol=1e-15)
        assert pts[row].tolist() in CUBE.tolist()


def test_map_back_shapes():
    orig = np.array([10, 20, 30, 40], dtype=np.int64)
    assert map_back(np.array([3, 0, 1]), orig).tolist() == [40, 10, 20]
    assert map_back([[0, 1, 2], [2, 1, 3]], orig).tolist() == [[10, 20, 30], [30, 20, 40]]
    ragged = map_back([[0, 1, 2, 3], [3, 2, 1]], orig)
    assert [p.tolist() for p in ragged] == [[10, 20, 30, 40], [40, 30, 20]]


# -- degenerate and bad input ------------------------------------------------------------


@pytest.mark.parametrize(
    "pts, expected",
    [
        (np.zeros((0, 3)), []),
        (np.ones((5, 3)), []),  # one distinct point: it is the centroid
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), [0, 2]),  # collinear
        (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), [0, 1]),
    ],
)
def test_degenerate_inputs(pts, expected):
    q, idx = sphere_project(pts)
    assert idx.tolist() == expected
    assert q.shape == (len(expected), pts.shape[1])


@pytest.mark.parametrize(
    "points, kwargs, match",
    [
        (np.zeros((4, 4)), {}, r"points must have shape \(n, 2\) or \(n, 3\), got \(4, 4\)"),
        (np.zeros(6), {}, r"points must have shape \(n, 2\) or \(n, 3\), got \(6,\)"),
        (np.array([[0.0, np.nan, 1.0]]), {}, "points must be finite, got 1 non-finite"),
        (np.zeros((3, 3)), {"eps": -1.0}, "eps must be a finite float >= 0 or None, got -1.0"),
        (np.zeros((3, 3)), {"eps": float("inf")}, "eps must be a finite float"),
    ],
)
def test_bad_calls(points, kwargs, match):
    with pytest.raises(ValueError, match=match):
        sphere_project(points, **kwargs)


@pytest.mark.parametrize("scale", [1e160, 1e200, 1e300, 2.0**1020])
def test_default_duplicate_tolerance_stays_finite_at_huge_scale(scale):
    # Issue 13: the scaled tolerance overflowed to inf above ~1e154, so every point was a
    # "duplicate" of the first (or, passed explicitly, the projection refused eps=inf).
    pts = random_cloud(0, 30, 3) * scale
    eps = tolerance(pts, "scaled")
    assert np.isfinite(eps)
    assert len(surface_points(pts).kept) == 30
    assert len(surface_points(pts, eps=eps).kept) == 30
