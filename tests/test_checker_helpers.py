"""The checker's fallback helpers, each against the independent exact verdict module.

The negative corpus reaches these only when Qhull's own hull fails (the 2D
exact monotone chain), on flat inputs (affine rank, witness simplex) or on
invalid input (Qhull reference records), so they get direct tests here:
expectations from ``tests/_exact_verdict.py`` (integers), never from the checker.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from _exact_verdict import affine_rank as exact_rank
from _exact_verdict import hull2d, to_integers
from hullstress.checker import affine_rank, qhull_reference, witness_simplex
from hullstress.checker.extreme import exact_extreme_2d
from hullstress.contract import normalize_output
from hullstress.errors import ContractViolation

SCALES = [1.0, 2.0**-1000, 2.0**990, 0.1]  # 0.1 rounds: the float filter meets inexact input


lattice2 = st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=12)


@pytest.mark.parametrize("scale", SCALES)
@given(ints=lattice2)
@example(ints=[(0, 0), (1, 1), (2, 2), (3, 3)])  # collinear: the two ends
@example(ints=[(0, 0), (2, 0), (1, 0), (1, 1), (0, 0)])  # a point on an edge, a duplicate
@example(ints=[(1, 1)])
@example(ints=[(0, 0), (1, 1), (2, 2)])  # three distinct collinear points: the two ends
@example(ints=[(2, 1), (0, 0)])  # two distinct points, given out of order
def test_exact_extreme_2d_is_the_strictly_convex_ring(scale, ints):
    pts = np.array(ints, dtype=np.float64) * scale
    got = exact_extreme_2d(pts).tolist()
    exact, _ = to_integers(pts.tolist())
    assert got == hull2d(exact)  # same indices (first of each coordinate), same ccw order


def test_exact_extreme_2d_edge_cases():
    empty = exact_extreme_2d(np.zeros((0, 2)))
    assert empty.dtype == np.int64 and empty.shape == (0,)
    # -0.0 and 0.0 are one coordinate: the origin appears once (its lowest index).
    pts = np.array([[0.0, 0.0], [4.0, 0.0], [-0.0, -0.0], [0.0, 4.0], [-0.0, 4.0]])
    assert exact_extreme_2d(pts).tolist() == [0, 1, 3]
    assert exact_extreme_2d(np.array([[1.0, 2.0], [1.0, 2.0]])).dtype == np.int64


def _flat_points(draw_ints, rank: int) -> list[tuple[int, int, int]]:
    base, u, v, coeffs = draw_ints
    dirs = [u, v][:rank]
    return [tuple(b + sum(c[i] * d[j] for i, d in enumerate(dirs)) for j, b in enumerate(base)) for c in coeffs]


vec = st.tuples(st.integers(-4, 4), st.integers(-4, 4), st.integers(-4, 4))


@pytest.mark.parametrize("scale", SCALES[:3])
@given(
    rank=st.integers(0, 2),
    data=st.tuples(vec, vec, vec, st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=8)),
    nudge=st.none() | st.tuples(st.integers(0, 7), st.integers(0, 2)),
)
@example(rank=2, data=((1, 2, 3), (1, 1, 0), (0, 1, 1), [(0, 0), (1, 0), (0, 1), (1, 1)]), nudge=None)  # an oblique plane
@example(rank=2, data=((1, 2, 3), (1, 1, 0), (0, 1, 1), [(0, 0), (1, 0), (0, 1), (1, 1)]), nudge=(3, 2))  # one ulp off it
@example(rank=1, data=((1, 2, 3), (1, 2, 3), (0, 0, 0), [(0, 0), (1, 0), (2, 0)]), nudge=None)  # an oblique line
def test_affine_rank_and_witness_simplex_of_flat_sets(scale, rank, data, nudge):
    # Points on a (possibly oblique) line or plane through integer points, optionally one
    # coordinate one ulp off; the rank and the simplex are checked in integers.
    pts = np.array(_flat_points(data, rank), dtype=np.float64) * scale
    if nudge is not None and nudge[0] < len(pts):
        i, axis = nudge
        pts[i, axis] = np.nextafter(pts[i, axis], np.inf)
    exact, _ = to_integers(pts.tolist())
    want = exact_rank(sorted(set(exact)))
    assert affine_rank(pts) == want
    for d in (2, 3):
        flat = pts[:, :d]
        simplex = witness_simplex(flat)
        sub, _ = to_integers(flat.tolist())
        r = exact_rank(sorted(set(sub)))
        assert len(simplex) == r + 1
        assert exact_rank([sub[i] for i in simplex]) == r  # affinely independent


def test_affine_rank_converts_integer_input():
    assert affine_rank([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]) == 3
    with pytest.raises(ValueError, match="finite"):
        affine_rank(np.array([[0.0, np.inf]]))


@pytest.mark.parametrize(
    "points, n, dim, error",
    [
        (np.array([[0.0, np.nan]]), 1, 2, "finite"),
        (np.zeros((0, 3)), 0, 3, "empty"),
        (np.zeros((3, 4)), 0, 0, "shape"),
        ("abc", 0, 0, "numeric"),
    ],
)
def test_qhull_reference_of_invalid_input_is_a_record(points, n, dim, error):
    ref = qhull_reference(points)
    assert error in ref.error
    assert (ref.n_points, ref.dim) == (n, dim)
    assert ref.vertices is None and ref.faces is None and ref.options is None
    assert ref.attempts == () and ref.qhull_ok is None and ref.qhull_detail == ""
    assert ref.distround == 0.0 and ref.extreme is None and ref.affine_rank is None
    assert ref.as_dict() == {
        "qhull_options": None, "qhull_ok": None, "qhull_volume": None,
        "qhull_error": ref.error, "distround": 0.0, "affine_rank": None,
    }


def test_qhull_reference_record_of_a_flat_input():
    ref = qhull_reference(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    assert ref.as_dict()["affine_rank"] == 1 and ref.as_dict()["qhull_options"] == "QJ"
    # "<options>: <exception type>: <first line of Qhull's message>" (Qhull's QHnnnn code).
    assert ref.attempts and ref.attempts[0].startswith("Qt: QhullError: QH")


@pytest.mark.parametrize(
    "output, dim, message",
    [
        ({"faces": [0, 1, 2]}, 3, "got dict {'faces': [0, 1, 2]}"),
        ("0 1 2", 2, "got str '0 1 2'"),
        (np.zeros((2, 4), dtype=int), 3, "got shape (2, 4)"),
        (np.zeros((2, 3)), 3, "got ndarray of dtype float64 and shape (2, 3)"),
        ([list(range(40))], 3, "out of range for 4 points"),
        ([[0.5, 1, 2]], 3, "face 0 must be integer indices, got list [0.5, 1, 2]"),
        (b"x" * 57, 2, "got bytes b'" + "x" * 57 + "'"),  # a repr of 60 characters: whole
        (b"x" * 58, 2, "got bytes b'" + "x" * 58 + "..."),  # of 61: cut at 60
    ],
    ids=["dict", "str", "shape", "float", "range", "float-entry", "bytes-60", "bytes-61"],
)
def test_contract_messages_name_the_offending_value(output, dim, message):
    with pytest.raises(ContractViolation) as info:
        normalize_output(output, 4, dim)
    assert str(info.value).endswith(message)
