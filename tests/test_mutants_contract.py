"""``hullstress/contract.py`` (output normalisation) pinned where the mutation run found it loose.

Each test here was written against mutants of ``contract.py`` that survived
the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented contract (docs/own-code.md
"Testing your own hull code", docs/design.md "Outputs are canonicalised", the
module's docstrings) or is worked out by hand or by brute force, never from
the module's own output.
"""

from __future__ import annotations

import itertools
import re
from fractions import Fraction

import numpy as np
import pytest

from hullstress.contract import (
    FaceSet,
    canonical_output,
    least_rotation,
    normalize_faces,
    normalize_polygon,
    reverse_orientation,
)
from hullstress.errors import ContractViolation

# --------------------------------------------------------------------------- FaceSet


def test_fan_triangles_of_mixed_faces_by_hand():
    fs = FaceSet.from_polygons([[5, 6, 7, 8, 9], [1, 2, 3], [4, 3, 2, 1]])
    tri, face_of = fs.fan_triangles()
    assert tri.tolist() == [[5, 6, 7], [5, 7, 8], [5, 8, 9], [1, 2, 3], [4, 3, 2], [4, 2, 1]]
    assert face_of.tolist() == [0, 0, 0, 1, 2, 2]
    assert tri.dtype == np.int64 and face_of.dtype == np.int64


def test_fan_triangles_of_one_triangle_and_of_faces_too_small_for_one():
    tri, face_of = FaceSet.from_triangles([[4, 5, 6]]).fan_triangles()
    assert tri.tolist() == [[4, 5, 6]] and face_of.tolist() == [0]
    # Faces of one and two vertices (the lower-dimensional answers) hold no triangle.
    tri, face_of = FaceSet.from_polygons([[0, 1], [7], [2, 3, 4], [5, 6]]).fan_triangles()
    assert tri.tolist() == [[2, 3, 4]] and face_of.tolist() == [2]
    for fs in (FaceSet.from_polygons([]), FaceSet.from_polygons([[0, 1], [2]])):
        tri, face_of = fs.fan_triangles()
        assert tri.shape == (0, 3) and tri.dtype == np.int64
        assert face_of.shape == (0,) and face_of.dtype == np.int64


def test_triangles_refuses_polygons_with_its_documented_message():
    assert FaceSet.from_polygons([[0, 1, 2], [2, 1, 3]]).triangles().tolist() == [[0, 1, 2], [2, 1, 3]]
    with pytest.raises(ValueError, match=re.escape("not every face is a triangle; use fan_triangles()")):
        FaceSet.from_polygons([[0, 1, 2, 3]]).triangles()


# --------------------------------------------------------------------------- normalisation messages


def test_normalize_polygon_names_the_vertex_indices_in_its_messages():
    with pytest.raises(ContractViolation, match="^the algorithm returned None instead of vertex indices$"):
        normalize_polygon(None, 3)
    with pytest.raises(ContractViolation, match="^vertex indices must be integer indices, got "):
        normalize_polygon([0.5, 1.5], 3)
    with pytest.raises(ContractViolation, match="^vertex indices holds index 5, out of range for 3 points$"):
        normalize_polygon([0, 1, 5], 3)


def test_a_face_too_small_names_the_exception_for_flat_inputs():
    want = "face 1 has 2 vertices; a face needs at least 3 (fewer only in the answer for a collinear or one-point input)"
    with pytest.raises(ContractViolation, match=f"^{re.escape(want)}$"):
        normalize_faces([[0, 1, 2], [0, 1]], 3)


def test_face_sets_hold_int64_whatever_integers_they_are_built_from():
    # "indices : ndarray of shape (k,), int64"; "offsets : ndarray of shape (m + 1,), int64".
    tri = FaceSet.from_triangles(np.array([[0, 1, 2], [2, 1, 3]], dtype=np.int32))
    poly = FaceSet.from_polygons([np.array([0, 1, 2, 3], dtype=np.int32), np.array([3, 2, 4], dtype=np.uint8)])
    for fs in (tri, poly):
        assert fs.indices.dtype == np.int64 and fs.offsets.dtype == np.int64
    assert tri.to_python() == [[0, 1, 2], [2, 1, 3]] and tri.offsets.tolist() == [0, 3, 6]
    assert poly.to_python() == [[0, 1, 2, 3], [3, 2, 4]] and poly.offsets.tolist() == [0, 4, 7]


def _violation(call, *args) -> str:
    with pytest.raises(ContractViolation) as info:
        call(*args)
    return str(info.value)


def test_index_conversion_accepts_integers_only():
    # "Convert to int64 without accepting floats, bools, strings or ragged nesting."
    ok = normalize_polygon(np.array([0, 1, 2], dtype=object), 3)  # Python ints held as objects
    assert ok.dtype == np.int64 and ok.tolist() == [0, 1, 2]
    assert normalize_polygon([np.int32(2), 0, np.uint8(1)], 3).tolist() == [2, 0, 1]
    assert _violation(normalize_polygon, [0, 1, Fraction(2)], 3) == "vertex indices must be integer indices, got element Fraction(2, 1)"
    assert _violation(normalize_polygon, np.array([0, True, 2], dtype=object), 3) == (
        "vertex indices must be integer indices, got element True"
    )
    assert _violation(normalize_polygon, np.array([1, 2.5, 0], dtype=object), 3) == (
        "vertex indices must be integer indices, got element 2.5"
    )
    assert _violation(normalize_polygon, [[0, 1], [2]], 3).startswith(
        "vertex indices must be integer indices, got list [[0, 1], [2]]: "
    )
    # Objects keep their nesting: a 2-D object array is no polygon.
    assert _violation(normalize_polygon, np.array([[0, 1], [2, 3]], dtype=object), 4) == (
        "a 2D hull must be a 1-D sequence of vertex indices, got shape (2, 2)"
    )


def test_a_bool_among_python_ints_is_refused():
    # Regression: numpy turns [0, True, 2] into the int64 array [0, 1, 2], so a bool index
    # used to pass as 1 (while an object array or a list of bools was refused).
    assert _violation(normalize_polygon, [0, True, 2], 3) == "vertex indices must be integer indices, got element True"
    assert _violation(normalize_polygon, (2, 0, np.True_), 3) == "vertex indices must be integer indices, got element np.True_"
    assert _violation(normalize_faces, [[0, 1, 2], [2, False, 0]], 3) == "face 1 must be integer indices, got element False"
    # Other refusals keep their own message.
    assert _violation(normalize_polygon, [0.5, True, 2], 3) == "vertex indices must be integer indices, got list [0.5, True, 2]"
    assert _violation(normalize_polygon, np.array([True, False, True]), 3) == (
        "vertex indices must be integer indices, got ndarray of dtype bool and shape (3,)"
    )


def test_indices_beyond_int64_are_a_contract_violation():
    # Regression: a Python int beyond int64 (numpy keeps such a list as objects) raised
    # OverflowError from the conversion instead of a ContractViolation (a crash, not "fail").
    assert _violation(normalize_polygon, [0, 2**70, 1], 3) == (
        f"vertex indices holds an index outside the int64 range: {2**70}"
    )
    assert _violation(normalize_faces, [[0, 1, -(2**63) - 1]], 3) == (
        f"face 0 holds an index outside the int64 range: {-(2**63) - 1}"
    )
    # The int64 bounds themselves fit (and are then out of range), held as objects too.
    for big in (-(2**63), 2**63 - 1):
        assert _violation(normalize_polygon, np.array([0, big], dtype=object), 3) == (
            f"vertex indices holds index {big}, out of range for 3 points"
        )
    # Unsigned arrays: 2**63 does not fit int64; 2**63 - 1 does, and is out of range.
    assert _violation(normalize_polygon, np.array([0, 2**63], dtype=np.uint64), 3) == (
        f"vertex indices holds an index too large for int64: {2**63}"
    )
    assert _violation(normalize_polygon, np.array([0, 2**63 - 1], dtype=np.uint64), 3) == (
        f"vertex indices holds index {2**63 - 1}, out of range for 3 points"
    )


def test_normalize_faces_names_the_faces_in_its_messages():
    assert _violation(normalize_faces, np.array([[0, 1, 2.5]]), 3) == (
        "faces must be integer indices, got ndarray of dtype float64 and shape (1, 3)"
    )
    assert _violation(normalize_faces, np.array([[0, 1, 5]]), 3) == "faces holds index 5, out of range for 3 points"
    assert _violation(normalize_faces, 42, 3) == (
        "faces must be an (m, 3) integer array or a list of polygons, got int 42"
    )
    assert _violation(normalize_faces, [[0, 1, 2], 5], 3) == "face 1 must be a sequence of vertex indices, got int 5"
    assert _violation(normalize_faces, [[[0], [1], [2]]], 3) == (
        "face 0 must be a sequence of vertex indices, got list [[0], [1], [2]]"
    )
    assert _violation(normalize_faces, [[0, 1, 2], [0, 1, 7]], 3) == "face 1 holds index 7, out of range for 3 points"


def test_normalize_faces_array_shapes():
    # An (m, 3) array; m = 0 with any width is no faces (nothing to be wrong), a non-empty
    # array of another width is refused.
    assert normalize_faces(np.zeros((0, 4), dtype=np.int64), 3).n_faces == 0
    assert _violation(normalize_faces, np.zeros((2, 0), dtype=np.int64), 3) == (
        "faces must be an (m, 3) integer array, got shape (2, 0)"
    )
    assert _violation(normalize_faces, np.zeros((2, 4), dtype=np.int64), 3) == (
        "faces must be an (m, 3) integer array, got shape (2, 4)"
    )


# --------------------------------------------------------------------------- canonical order


def _least_rotation_by_brute_force(seq):
    return min(tuple(seq[k:] + seq[:k]) for k in range(len(seq))) if seq else ()


def test_least_rotation_against_brute_force():
    # Every sequence over {0, 1, 2} of length 0 to 6: the returned start gives the least
    # rotation (for a periodic sequence several starts do; any of them).
    for n in range(7):
        for seq in itertools.product(range(3), repeat=n):
            seq = list(seq)
            k = least_rotation(seq)
            assert 0 <= k < max(n, 1)
            assert tuple(seq[k:] + seq[:k]) == _least_rotation_by_brute_force(seq), seq


def test_canonical_polygon_starts_at_its_least_rotation():
    assert canonical_output(np.array([5, 3])).tolist() == [3, 5]
    assert canonical_output(np.array([7])).tolist() == [7]
    assert canonical_output(np.array([], dtype=np.int64)).tolist() == []
    assert canonical_output([4, 9, 2, 6]).tolist() == [2, 6, 4, 9]
    # The smallest index twice: the rotation from the 0 followed by 1 is the least.
    assert canonical_output(np.array([2, 0, 3, 0, 1])).tolist() == [0, 1, 2, 0, 3]
    out = canonical_output(np.array([2, 0, 3, 0, 1]))
    assert out.dtype == np.int64


def test_canonical_faces_are_sorted_lexicographically_and_keep_their_orientation():
    # Two triangles sorted by their first, then second index: (0, 1, 5) before (0, 2, 3)
    # (not by their last index).
    out = canonical_output(FaceSet.from_triangles([[2, 3, 0], [5, 0, 1]]))
    assert out.to_python() == [[0, 1, 5], [0, 2, 3]]
    assert out.offsets.tolist() == [0, 3, 6]
    # Mixed sizes: a shorter prefix first; a face holding its smallest index twice starts
    # at the least of its rotations from there.
    out = canonical_output(FaceSet.from_polygons([[3, 1, 2, 1], [2, 3, 4, 1], [6, 0, 5], [3, 1, 2]]))
    assert out.to_python() == [[0, 5, 6], [1, 2, 1, 3], [1, 2, 3], [1, 2, 3, 4]]
    assert out.offsets.tolist() == [0, 3, 7, 10, 14]
    assert out.indices.dtype == np.int64 and out.offsets.dtype == np.int64


def test_canonical_output_of_no_faces_is_an_empty_face_set():
    out = canonical_output(FaceSet.from_polygons([]))
    assert isinstance(out, FaceSet) and out.n_faces == 0
    assert out.indices.dtype == np.int64 and out.indices.shape == (0,)
    assert out.offsets.tolist() == [0]


def test_reverse_orientation_by_hand():
    assert reverse_orientation(np.array([0, 1, 2, 5])).tolist() == [5, 2, 1, 0]
    fs = FaceSet.from_polygons([[0, 1, 2], [0, 2, 3, 4], [7, 8, 9, 10, 11]])
    rev = reverse_orientation(fs)
    assert rev.to_python() == [[2, 1, 0], [4, 3, 2, 0], [11, 10, 9, 8, 7]]
    assert rev.offsets.tolist() == [0, 3, 7, 12]
    assert fs.to_python() == [[0, 1, 2], [0, 2, 3, 4], [7, 8, 9, 10, 11]]  # the input is kept
