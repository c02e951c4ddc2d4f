"""Tests for hullstress.strategies: valid arrays, the promised exact properties, small shrinks."""

from __future__ import annotations

import math
from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest
from hypothesis import find, given, settings
from hypothesis import strategies as st
from hypothesis.errors import InvalidArgument

import generators as G
from hullstress.case import Case
from hullstress.strategies import (
    collinear_points,
    coplanar_points,
    family_cases,
    point_sets,
    points_in_general_position,
    seeds,
    transformed,
    ulp_perturbed,
)

from _exact import frac_rows, orient_frac


def det(rows) -> Fraction:
    """The exact orientation determinant of the rows (their doubles as rationals)."""
    return orient_frac(frac_rows(np.asarray(rows)))


@given(family_cases(max_size=30))
def test_family_cases_are_valid_cases(case):
    assert isinstance(case, Case)
    assert case.family in G.family_names()
    assert case.family != "bad-input"
    assert case.points.dtype == np.float64 and case.points.shape[1] == case.dim
    assert np.all(np.isfinite(case.points))
    # reproducible from its provenance
    params = dict(case.params)
    again = G.generate(case.family, case.size, dim=case.dim, seed=case.seed, **params)
    assert again.tobytes() == case.points.tobytes()


@given(family_cases(dim=3, include_bad_input=True, families=["bad-input", "duplicates"], max_size=10))
def test_bad_input_only_when_asked(case):
    assert case.family in ("bad-input", "duplicates")


@given(family_cases(dim=2, max_size=20, transforms=True))
def test_family_cases_with_transforms_record_them(case):
    t = case.params.get("transform")
    assert t is None or t in G.TRANSFORMS


@given(point_sets(dim=2, min_size=5, max_size=25))
def test_point_sets_shape_and_writable(points):
    assert points.ndim == 2 and points.shape[1] == 2 and 5 <= len(points) <= 25
    points[0, 0] = 0.0  # a writable copy, not the case's read-only array


@given(st.sampled_from([2, 3]).flatmap(lambda d: points_in_general_position(dim=d, max_size=10)))
def test_general_position_is_exact(points):
    d = points.shape[1]
    for subset in combinations(range(len(points)), d + 1):
        assert det(points[list(subset)]) != 0


@given(coplanar_points(dim=3, max_size=15))
def test_coplanar_points_are_exactly_coplanar(points):
    for subset in combinations(range(min(len(points), 7)), 4):
        assert det(points[list(subset)]) == 0


@given(collinear_points(dim=2, max_size=15))
def test_collinear_points_are_exactly_collinear(points):
    for subset in combinations(range(min(len(points), 7)), 3):
        assert det(points[list(subset)]) == 0


@given(coplanar_points(dim=3, max_size=10, exact=False))
def test_inexact_coplanar_points_are_nearly_flat(points):
    c = points - points.mean(axis=0)
    s = np.linalg.svd(c, compute_uv=False)
    assert s[-1] <= 1e-12 * max(s[0], 1.0)


@given(st.data())
def test_ulp_perturbed_stays_within_its_ulps(data):
    base = data.draw(collinear_points(dim=3, max_size=8))
    k = data.draw(st.integers(0, 5))
    pts = data.draw(ulp_perturbed(st.just(base), k))
    for a, b in zip(pts.ravel(), base.ravel()):
        x = float(b)
        for _ in range(k):
            if x == a:
                break
            x = math.nextafter(x, a)
        assert x == a


@given(transformed(points_in_general_position(dim=3, max_size=8)))
def test_transformed_pairs_are_consistent(pair):
    orig, t = pair
    assert t.name in G.TRANSFORMS
    kept = t.source_rows >= 0
    if t.name in ("permute-rows", "duplicate-all", "add-interior"):
        assert t.points[kept].tobytes() == orig[t.source_rows[kept]].tobytes()


def test_family_cases_shrink_to_the_simplest_case():
    case = find(family_cases(dim=3, families=["coplanar-grid"], max_size=40), lambda c: c.n_points >= 9)
    assert (case.seed, case.size, case.params) == (0, 9, {})


def test_point_sets_shrink_to_the_smallest_failing_size():
    pts = find(point_sets(dim=2, families=["uniform"], min_size=3, max_size=60), lambda p: len(p) >= 17)
    assert pts.shape == (17, 2)


def test_ulp_perturbation_shrinks_to_a_single_ulp():
    base = np.array([[1.0, 2.0], [3.0, 4.0]])
    pts = find(ulp_perturbed(st.just(base), 8), lambda p: not np.array_equal(p, base))
    assert np.count_nonzero(pts != base) == 1
    changed = float(pts[pts != base][0])
    original = float(base[pts != base][0])
    assert changed in (math.nextafter(original, -math.inf), math.nextafter(original, math.inf))


def test_general_position_shrinks_to_the_moment_curve():
    pts = find(points_in_general_position(dim=3), lambda p: True)
    assert pts.tolist() == [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 4.0, 8.0], [3.0, 9.0, 27.0]]


def test_seeds_shrink_to_zero():
    assert find(seeds(), lambda s: True) == 0


BAD = [
    lambda: family_cases(dim=4),
    lambda: family_cases(min_size=10, max_size=5),
    lambda: family_cases(families=["regular-polyhedron"], max_size=3),
    lambda: family_cases(transforms=["spin"]),
    lambda: points_in_general_position(max_size=10**6),
    lambda: coplanar_points(min_size=0),
    lambda: ulp_perturbed(st.just(np.zeros((1, 2))), -1),
    lambda: transformed(st.just(np.zeros((1, 2))), ["spin"]),
]


@pytest.mark.parametrize("make", BAD, ids=range(len(BAD)))
def test_invalid_strategy_arguments(make):
    with pytest.raises(InvalidArgument):
        make()


@settings(max_examples=5)
@given(family_cases(dim=2, families=["kettner-classroom"]))
def test_fixed_size_families_keep_their_size(case):
    assert case.n_points in (4, 5, 6, 9)
