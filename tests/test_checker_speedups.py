"""The checker's speed-ups give exactly what the plain numpy operations give (issue 33's perf targets)."""

from __future__ import annotations

import numpy as np
import pytest

from hullstress.checker import check
from hullstress.checker._unique import unique_ints
from hullstress.checker.closed_mesh import _sort_with_positions, certify_closed_mesh
from hullstress.contract import FaceSet


@pytest.mark.parametrize("dtype", [np.int64, np.int32, np.uint8, np.bool_])
@pytest.mark.parametrize("shape", [(0,), (1,), (7,), (50, 3)])
def test_unique_ints_is_np_unique(dtype, shape):
    values = np.random.default_rng(sum(shape)).integers(0, 20, size=shape).astype(dtype)
    got, want = unique_ints(values), np.unique(values)
    assert got.dtype == want.dtype
    assert np.array_equal(got, want)


def test_unique_ints_refuses_floats():
    with pytest.raises(TypeError, match="float64"):
        unique_ints(np.array([0.5, 0.5]))


@pytest.mark.parametrize("limit", [10**6, 2**62])  # packed sort, and the argsort fallback
def test_sort_with_positions(limit):
    keys = np.random.default_rng(1).integers(0, min(limit, 10**6), size=1000)
    order, ordered = _sort_with_positions(keys, limit)
    assert np.array_equal(ordered, np.sort(keys))
    assert np.array_equal(keys[order], ordered)
    assert np.array_equal(np.sort(order), np.arange(len(keys)))


TETRA = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TETRA_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def test_closed_mesh_pairs_twins():
    cert = certify_closed_mesh(TETRA, FaceSet.from_triangles(TETRA_FACES))
    assert cert is not None and cert.certified


@pytest.mark.parametrize(
    "faces",
    [
        TETRA_FACES[:3] + [[1, 3, 2]],  # one face reversed: an edge twice in the same direction
        TETRA_FACES + [[0, 2, 1]],  # a face twice: an edge three times
        TETRA_FACES[:3] + [[1, 1, 3]],  # a loop edge 1 -> 1
    ],
)
def test_closed_mesh_declines_unpaired_edges(faces):
    assert certify_closed_mesh(TETRA, FaceSet.from_triangles(faces)) is None
    assert not check(TETRA, faces, qhull=False).ok


def test_sphere_batch_verdict_matches_general_path():
    """A sphere large enough for slabs: the batched path and Qhull's own certificate agree."""
    rng = np.random.default_rng(3)
    p = rng.standard_normal((3000, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    verdict = check(p, _hull_faces(p))
    assert verdict.ok and verdict.n_extreme == 3000
    reversed_verdict = check(p, _hull_faces(p)[:, ::-1])
    assert not reversed_verdict.ok and reversed_verdict.n_outside == 3000


def _hull_faces(p):
    from scipy.spatial import ConvexHull

    hull = ConvexHull(p)
    tri = hull.simplices.copy()
    a, b, c = (p[tri[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    tri[inward] = tri[inward][:, ::-1]
    return tri


@pytest.mark.parametrize("chunk", [997, 4096])
def test_slabs_give_the_same_verdict(monkeypatch, chunk):
    """Rows gathered a slab at a time (slab edges inside the fixed-point blocks) give the one-slab verdict."""
    import hullstress.checker.closed_mesh as closed_mesh

    rng = np.random.default_rng(4)
    p = rng.standard_normal((2000, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    faces = _hull_faces(p)
    whole = check(p, faces, qhull=False)
    monkeypatch.setattr(closed_mesh, "_FILTER_CHUNK", chunk)
    cert = closed_mesh.certify_closed_mesh(p, FaceSet.from_triangles(faces))
    assert cert is not None and len(cert.extreme) == 2000
    sliced = check(p, faces, qhull=False)
    assert (sliced.ok, sliced.detail, sliced.volume) == (whole.ok, whole.detail, whole.volume)
