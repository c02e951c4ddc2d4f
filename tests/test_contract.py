"""The output contract: good outputs normalise, bad ones raise ContractViolation with a clear reason."""

import numpy as np
import pytest

from hullstress.contract import FaceSet, normalize_output
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
