"""The half-edge pairs the convexity check compares: every ordered pair on one undirected edge, in different faces.

Non-manifold outputs (an edge in three or more faces, common in wrong hulls
of degenerate inputs) give groups larger than two; the pairs are built for
all groups at once and must be exactly the brute-force set.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from hullstress.checker.convexity3d import _edge_pairs


def _brute(src, dst, face):
    return {
        (i, j)
        for i in range(len(src))
        for j in range(len(src))
        if i != j and {src[i], dst[i]} == {src[j], dst[j]} and face[i] != face[j]
    }


def test_edge_pairs_are_every_ordered_pair_on_a_shared_edge_in_other_faces():
    rng = np.random.default_rng(5)
    seen_big = 0
    for _ in range(300):
        n, m = int(rng.integers(2, 6)), int(rng.integers(0, 24))
        src, dst = rng.integers(0, n, m), rng.integers(0, n, m)
        face = rng.integers(0, m // 2 + 1, m)
        he = SimpleNamespace(src=src, dst=dst, face=face, paired=False)
        i, j = _edge_pairs(he, n)
        got = list(zip(i.tolist(), j.tolist()))
        assert len(got) == len(set(got))
        assert set(got) == _brute(src.tolist(), dst.tolist(), face.tolist())
        keys = np.minimum(src, dst) * n + np.maximum(src, dst)
        seen_big += int((np.unique(keys, return_counts=True)[1] > 2).any())
    assert seen_big > 50  # the groups of three or more were exercised
