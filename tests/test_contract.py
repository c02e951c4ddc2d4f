"""The output contract: good outputs normalise, bad ones raise ContractViolation with a clear reason."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hullstress.contract import FaceSet, canonical_output, least_rotation, normalize_output, require_face_size
from hullstress.errors import ContractViolation


@pytest.mark.parametrize(
    "output, n, dim, expected",
    [
        ([0, 1, 2], 3, 2, [0, 1, 2]),
        (np.array([2, 0, 1], dtype=np.uint8), 3, 2, [2, 0, 1]),
        ((np.int32(1), 0, 2), 3, 2, [1, 0, 2]),
        ([], 3, 2, []),
    ],
)
def test_polygon_outputs_normalise(output, n, dim, expected):
    out = normalize_output(output, n, dim)
    assert out.dtype == np.int64 and out.tolist() == expected


def test_triangles_and_polygons_normalise():
    fs = normalize_output(np.array([[0, 1, 2], [0, 2, 3]]), 4, 3)
    assert isinstance(fs, FaceSet) and fs.is_triangles and fs.triangles().tolist() == [[0, 1, 2], [0, 2, 3]]
    poly = normalize_output([[0, 1, 2, 3], (0, 3, 4)], 5, 3)
    assert poly.sizes.tolist() == [4, 3] and not poly.is_triangles
    tri, face_of = poly.fan_triangles()
    assert tri.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]] and face_of.tolist() == [0, 0, 1]


@pytest.mark.parametrize(
    "output, n, dim, message",
    [
        (None, 4, 3, "returned None"),
        (None, 4, 2, "returned None"),
        (np.array([[0.0, 1.0, 2.0]]), 4, 3, "integer"),
        ([0.0, 1.0, 2.0], 4, 2, "integer"),
        ([True, False, True], 4, 2, "integer"),
        (np.array([[0, 1]]), 4, 3, r"shape \(1, 2\)"),
        ([[0, 1, 2], [0, 1]], 4, 3, "face 1 has 2 vertices"),
        (np.array([[0, 1, 4]]), 4, 3, "index 4, out of range for 4 points"),
        ([0, -1, 2], 4, 2, "index -1, out of range"),
        ([[0, 1], [2, 3]], 4, 2, "1-D sequence"),
        ("012", 4, 2, "integers"),
        ({"faces": 1}, 4, 3, "list of polygons"),
        (5, 4, 3, "list of polygons"),
        ([[0, 1, "2"]], 4, 3, "integer"),
    ],
)
def test_contract_violations(output, n, dim, message):
    with pytest.raises(ContractViolation, match=message):
        normalize_output(output, n, dim)


def test_short_faces_only_when_asked_for():
    # Faces of one or two vertices are the answer for a point or a segment; whoever normalises
    # before the input's rank is known asks for them (min_face_size=1) and checks later.
    fs = normalize_output([[0, 1]], 4, 3, min_face_size=1)
    assert fs.sizes.tolist() == [2]
    with pytest.raises(ContractViolation, match="face 0 has 2 vertices; a face needs at least 3"):
        require_face_size(fs)
    require_face_size(normalize_output([[0, 1, 2]], 4, 3, min_face_size=1))
    with pytest.raises(ContractViolation, match="face 0 has 0 vertices"):
        normalize_output([[]], 4, 3, min_face_size=1)


@given(st.lists(st.integers(0, 3), min_size=0, max_size=9))
def test_least_rotation_is_the_smallest_rotation(seq):
    k = least_rotation(seq)
    assert seq[k:] + seq[:k] == min((seq[i:] + seq[:i] for i in range(len(seq))), default=[])


_faces = st.lists(st.lists(st.integers(0, 7), min_size=1, max_size=5), min_size=0, max_size=6)


@given(_faces, st.randoms(use_true_random=False))
def test_canonical_faces_do_not_depend_on_emission_order(faces, rnd):
    canonical = canonical_output(FaceSet.from_polygons(faces)).to_python()
    assert canonical == sorted(min(f[i:] + f[:i] for i in range(len(f))) for f in faces)
    shuffled = rnd.sample(faces, len(faces))
    rotated = [f[r:] + f[:r] for f in shuffled for r in [rnd.randrange(len(f))]]
    assert canonical_output(FaceSet.from_polygons(rotated)).to_python() == canonical


def test_canonical_output_keeps_orientation_and_triangle_fast_path():
    tri = np.array([[4, 2, 9], [9, 4, 2], [1, 3, 0], [5, 6, 7]])
    out = canonical_output(FaceSet.from_triangles(tri)).triangles().tolist()
    assert out == [[0, 1, 3], [2, 9, 4], [2, 9, 4], [5, 6, 7]]  # same cycles, same directions
    assert canonical_output(np.array([5, 1, 7, 1, 2])).tolist() == [1, 2, 5, 1, 7]
    assert canonical_output(np.array([3, 1, 2])).tolist() == [1, 2, 3]
    assert canonical_output(np.array([3, 2, 1])).tolist() == [1, 3, 2]


def _shuffled_hull(points):
    """Qhull's outward triangles, each rotated and the list shuffled anew on every call (a test algorithm)."""
    import random

    from _hull_oracle import qhull_outward

    rnd = random.SystemRandom()
    out = [list(np.roll(f, rnd.randrange(3))) for f in qhull_outward(points)]
    rnd.shuffle(out)
    return out


def test_rows_do_not_depend_on_the_order_faces_are_emitted():
    from hullstress import register_algorithm
    from hullstress._registry import ALGORITHMS
    from hullstress.case import Case
    from hullstress.config import AlgorithmConfig
    from hullstress.evaluate import evaluate
    from hullstress.results import TIMING_COLUMNS

    rng = np.random.default_rng(4)
    pts = rng.normal(size=(60, 3))
    pts[:, 2] *= 1e-9  # a thin slab: the float volume sum depends on the summation order
    case = Case(points=pts, dim=3, family="slab")
    register_algorithm("test-shuffled-3d", dim=3)(_shuffled_hull)
    try:
        rows = [evaluate(case, AlgorithmConfig("test-shuffled-3d", s)) for s in ("off", "on") for _ in range(4)]
    finally:
        ALGORITHMS.remove("test-shuffled-3d")  # the corpus replay runs every registered algorithm
    for group in (rows[:4], rows[4:]):
        first = {k: v for k, v in group[0].values.items() if k not in TIMING_COLUMNS}
        for other in group[1:]:
            assert {k: v for k, v in other.values.items() if k not in TIMING_COLUMNS} == first
