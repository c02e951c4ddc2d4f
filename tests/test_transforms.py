"""Tests for the metamorphic transforms: each keeps its claimed exact relation.

Property tests draw point sets from the families (hullstress.strategies) and
check the relation exactly (byte equality, Fraction orientations); a few
example tests compare Qhull's hull of the original and of the transformed set
on generic inputs, which is how the checker's tests use them.
"""

from __future__ import annotations

import zlib
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import generators as G
from generators.transforms import (
    TRANSFORMS,
    Transformed,
    add_interior,
    apply_transform,
    duplicate_all,
    permute_axes,
    permute_rows,
    reflect,
    reverse_rows,
    safe_pow2_range,
    scale_pow2,
)
from hullstress.strategies import point_sets, points_in_general_position, seeds


def orient(rows) -> int:
    p = [[Fraction(float(x)) for x in r] for r in rows]
    m = [[r[j] - p[0][j] for j in range(len(p[0]))] for r in p[1:]]
    if len(m) == 2:
        det = m[0][0] * m[1][1] - m[0][1] * m[1][0]
    else:
        det = (
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        )
    return (det > 0) - (det < 0)


any_points = st.sampled_from([2, 3]).flatmap(lambda d: point_sets(dim=d, min_size=1, max_size=30))


@given(any_points, seeds())
def test_permute_rows_is_the_same_point_set(points, seed):
    t = permute_rows(points, np.random.default_rng(seed))
    assert t.points.tobytes() == points[t.source_rows].tobytes()
    assert sorted(t.source_rows.tolist()) == list(range(len(points)))
    assert t.orientation_preserved


@given(any_points, st.integers(-80, 80))
def test_scale_pow2_is_exact_or_refused(points, k):
    lo, hi = safe_pow2_range(points)
    if lo <= k <= hi:
        t = scale_pow2(points, k)
        assert np.ldexp(t.points, -k).tobytes() == points.tobytes()
        assert t.points.tobytes() == (points * 2.0**k).tobytes()
        assert t.source_rows.tolist() == list(range(len(points)))
    else:
        with pytest.raises(ValueError, match="k must keep the scaling exact"):
            scale_pow2(points, k)


def test_scale_pow2_refuses_overflow_and_subnormal_loss():
    with pytest.raises(ValueError):
        scale_pow2(np.array([[1e308, 0.0]]), 2)
    with pytest.raises(ValueError):
        scale_pow2(np.array([[3 * 5e-324, 1.0]]), -1)  # 3 * 2**-1074 halved is not a double
    t = scale_pow2(np.array([[3 * 5e-324, 1.0]]), 1)  # scaling subnormals up is exact
    assert t.points[0, 0] == 6 * 5e-324


@given(points_in_general_position(dim=3, max_size=8), st.permutations([0, 1, 2]))
def test_permute_axes_relation_and_orientation_parity(points, perm):
    t = permute_axes(points, perm)
    inverse = np.argsort(perm)
    assert t.points[:, inverse].tobytes() == points.tobytes()
    before, after = orient(points[:4]), orient(t.points[:4])
    assert before != 0
    assert (before == after) == t.orientation_preserved


@given(points_in_general_position(dim=2, max_size=8), st.integers(0, 1))
def test_reflect_is_an_involution_that_flips_orientation(points, axis):
    t = reflect(points, axis)
    assert reflect(t.points, axis).points.tobytes() == points.tobytes()
    assert orient(t.points[:3]) == -orient(points[:3]) != 0
    assert not t.orientation_preserved


@given(any_points)
def test_duplicate_all_doubles_every_row_exactly(points):
    t = duplicate_all(points)
    n = len(points)
    assert t.points.shape == (2 * n, points.shape[1])
    assert t.points[:n].tobytes() == points.tobytes() == t.points[n:].tobytes()
    assert t.source_rows.tolist() == list(range(n)) * 2


general_2d_3d = st.sampled_from([2, 3]).flatmap(lambda d: points_in_general_position(dim=d, max_size=12))


@given(general_2d_3d, seeds(), st.integers(1, 6))
def test_add_interior_points_are_strictly_inside_a_witness_simplex(points, seed, m):
    t = add_interior(points, np.random.default_rng(seed), m)
    n, d = points.shape
    assert t.points[:n].tobytes() == points.tobytes()
    assert t.source_rows.tolist() == list(range(n)) + [-1] * m
    for q, simplex in zip(t.points[n:], t.witness):
        verts = points[simplex]
        s = orient(verts)
        assert s != 0
        for i in range(d + 1):
            trial = verts.copy()
            trial[i] = q
            assert orient(trial) == s  # strictly on the inner side of every facet


def test_add_interior_on_every_full_dimensional_family():
    """Runs on the families' own degeneracies (slivers, offsets, huge and tiny scales)."""
    checked = 0
    for name, dim, params in [
        ("sliver-tetrahedron", 3, {"kind": "sliver"}),
        ("sliver-triangle", 2, {"kind": "needle"}),
        ("scaled", 3, {"scale": 1e300}),
        ("scaled", 2, {"scale": 1e-300}),
        ("offset", 3, {"offset": 1e15}),
        ("subnormal", 2, {"units": 1000}),
        ("cube-faces", 3, {"layout": "grid"}),
        ("near-coplanar", 3, {"surface": "cube", "ulps": 1}),
    ]:
        pts = G.generate(name, 40, dim=dim, seed=3, **params)
        t = add_interior(pts, np.random.default_rng(0), 5)
        for q, simplex in zip(t.points[40:], t.witness):
            verts = pts[simplex]
            s = orient(verts)
            for i in range(dim + 1):
                trial = verts.copy()
                trial[i] = q
                assert orient(trial) == s != 0
        checked += 1
    assert checked == 8


@pytest.mark.parametrize(
    "points",
    [
        np.zeros((5, 3)),
        np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]]),
        np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
        np.array([[0.0, 0.0], [1.0, np.nan], [0.0, 1.0]]),
        np.array([[0.0, 0.0], [1.0, 0.0]]),
    ],
    ids=["identical", "collinear", "coplanar", "nan", "too-few"],
)
def test_add_interior_refuses_degenerate_input(points):
    with pytest.raises(ValueError, match="add_interior"):
        add_interior(points, np.random.default_rng(0), 3)


BAD = [
    (lambda: permute_axes(np.zeros((3, 3)), [0, 0, 1]), "perm"),
    (lambda: reflect(np.zeros((3, 2)), 2), "axis"),
    (lambda: scale_pow2(np.zeros((3, 2)), 1.5), "k"),
    (lambda: add_interior(np.eye(3), np.random.default_rng(0), 0), "m"),
    (lambda: duplicate_all(np.zeros((3, 4))), "shape"),
    (lambda: apply_transform("twist", np.zeros((3, 2)), np.random.default_rng(0)), "transform"),
]


@pytest.mark.parametrize("call,word", BAD, ids=[b[1] for b in BAD])
def test_bad_transform_arguments_raise(call, word):
    with pytest.raises(ValueError, match=word):
        call()


@pytest.mark.parametrize("name", sorted(TRANSFORMS))
def test_registry_transforms_keep_the_qhull_hull(name):
    """On generic input the hull after the transform is the hull before, through source_rows."""
    pts = G.generate("uniform", 60, dim=3, seed=11, shape="ball")
    t = apply_transform(name, pts, np.random.default_rng(5))
    assert isinstance(t, Transformed) and t.name == name
    before = set(ConvexHull(pts).vertices.tolist())
    after = {int(t.source_rows[i]) for i in ConvexHull(t.points).vertices}
    assert after == before
    assert -1 not in after


@pytest.mark.parametrize("name", sorted(TRANSFORMS))
def test_generate_with_transform_is_deterministic(name):
    a = G.generate("cube-faces", 20, dim=3, seed=4, transform=name)
    b = G.generate("cube-faces", 20, dim=3, seed=4, transform=name)
    assert a.tobytes() == b.tobytes()
    plain = G.generate("cube-faces", 20, dim=3, seed=4)
    rng = np.random.default_rng([4, zlib.crc32(name.encode()), 0])
    assert a.tobytes() == apply_transform(name, plain, rng).points.tobytes()


def test_generate_chains_transforms():
    pts = G.generate("collinear-edges", 16, dim=2, seed=2, transform=["duplicate-all", "permute-rows", "reflect"])
    assert pts.shape == (32, 2)
    assert len(np.unique(pts, axis=0)) == 16


@given(any_points)
def test_reverse_rows_is_the_same_point_set_backwards(points):
    t = reverse_rows(points)
    assert t.points.tobytes() == points[::-1].tobytes() == points[t.source_rows].tobytes()
    assert reverse_rows(t.points).points.tobytes() == points.tobytes()

