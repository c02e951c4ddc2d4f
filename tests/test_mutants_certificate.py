"""The certificate record and its corners (``hullstress/checker/certificate.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/certificate.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the
docstrings: a vertex with no sharp edge is inside a flat region, one with
exactly two collinear sharp edges on either side is inside an edge, a corner
has at least three; docs/design.md's verdict semantics) or from the geometry worked
out by hand, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.certificate import Certificate, corners3
from hullstress.checker.measure import surface_measure

_CUBE = np.array([[x, y, z] for x in (0.0, 2.0) for y in (0.0, 2.0) for z in (0.0, 2.0)])  # vertex 4x + 2y + z
_CUBE_EDGES = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]


def test_corners_of_a_cube_are_its_eight_vertices():
    # A cube's 12 edges are its sharp ones; each corner meets three.
    assert len(_CUBE_EDGES) == 12
    assert corners3(_CUBE, np.arange(8), np.array(_CUBE_EDGES)).tolist() == list(range(8))


def test_edge_midpoints_and_face_centres_of_a_cube_are_not_corners():
    # Points 8.. split three cube edges at their midpoints (two collinear sharp edges, one
    # on either side: inside an edge) and sit at two face centres (no sharp edge: flat).
    mids = {(0, 1): [0.0, 0, 1], (2, 6): [1.0, 2, 0], (5, 7): [2.0, 1, 2]}
    pts = np.r_[_CUBE, list(mids.values()), [[1.0, 1, 0], [2, 1, 1]]]
    sharp = [e for e in _CUBE_EDGES if e not in mids]
    for k, (a, b) in enumerate(mids):
        sharp += [(a, 8 + k), (b, 8 + k)] if k % 2 else [(8 + k, a), (8 + k, b)]  # either direction
    for order in (np.arange(len(sharp)), np.arange(len(sharp))[::-1]):
        got = corners3(pts, np.arange(13), np.array(sharp)[order])
        assert got.tolist() == list(range(8))
    assert corners3(pts, np.arange(8, 13), np.array(sharp)).tolist() == []  # only the non-corners asked


def test_two_sharp_edges_make_a_corner_unless_they_continue_each_other():
    # A triangle of sharp edges 0-1-2 with point 3 on the segment 0-1 (split there):
    # 0, 1, 2 have two sharp edges at an angle (corners), 3 two collinear ones on either side.
    pts = np.array([[0.0, 0, 0], [4, 0, 0], [0, 4, 4], [1, 0, 0]])
    sharp = np.array([[0, 3], [3, 1], [1, 2], [2, 0]])
    assert corners3(pts, np.arange(4), sharp).tolist() == [0, 1, 2]
    # Collinear on the same side (0 -> 1 and 0 -> 2 point the same way): not between, a corner;
    # 1 and 2 have one sharp edge each (impossible on a convex surface: kept as corners).
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [5, 5, 5]])
    assert corners3(pts, np.arange(4), np.array([[0, 1], [0, 2]])).tolist() == [0, 1, 2]
    # The same directions along every axis pair, and one on either side along y only.
    pts = np.array([[1.0, 1, 1], [2, 3, 4], [3, 5, 7], [1, 0, 1], [1, 2, 1]])
    assert corners3(pts, np.arange(5), np.array([[0, 1], [0, 2]])).tolist() == [0, 1, 2]
    assert corners3(pts, np.arange(5), np.array([[3, 0], [4, 0]])).tolist() == [3, 4]


def test_no_sharp_edge_means_no_corner():
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    got = corners3(pts, np.arange(3), np.zeros((0, 2), dtype=np.int64))
    assert got.tolist() == [] and got.dtype == np.int64


def _cert(**kw) -> Certificate:
    base = dict(
        dim=3, containment=True, convexity=True, manifoldness=True, n_faces=4, hull_vertices=np.arange(4),
        extreme=None, boundary_nonextreme=None, outside=np.zeros(0, np.int64), n_nonconvex_edges=0, n_degenerate_faces=0,
    )
    return Certificate(**{**base, **kw})


def test_certified_needs_all_three_checks_and_structural_means_topology_or_a_wrong_wrap():
    assert _cert().certified
    for failed in ("containment", "convexity", "manifoldness"):
        assert not _cert(**{failed: False}).certified
    assert not _cert().structural and not _cert(wraps=1).structural
    assert _cert(manifoldness=False).structural and _cert(manifoldness=False, wraps=1).structural
    assert _cert(wraps=2).structural and _cert(wraps=0).structural
    assert not _cert(containment=False, convexity=False).structural  # geometric failures only


def test_volume_of_a_certificate():
    assert _cert().volume == 0.0  # no measure: no volume
    sq = np.array([[0.0, 0], [2, 0], [2, 2], [0, 2]])
    assert _cert(dim=2, measure=surface_measure(sq, np.arange(4))).volume == 4.0
    assert _cert(dim=2, measure=surface_measure(sq, np.arange(4)[::-1])).volume == -4.0


def test_a_ring_of_sharp_edges_at_obtuse_angles_and_points_along_it():
    # A hexagon of sharp edges (120 degrees at each corner: the two edges point to opposite
    # sides along one axis, yet are not collinear), each side split by a midpoint (collinear,
    # on either side), all in one call with a same-side collinear pair elsewhere, at
    # negative coordinates (the directions from a vertex, not its position, decide).
    hexagon = np.array([[2.0, 0, 0], [1, 2, 0], [-1, 2, 0], [-2, 0, 0], [-1, -2, 0], [1, -2, 0]]) - [10.0, 10.0, 10.0]
    mids = (hexagon + np.roll(hexagon, -1, axis=0)) / 2
    spike = np.array([[-30.0, -30, -30], [-31, -30, -30], [-32, -30, -30]])  # 12 -> 13 and 12 -> 14: same side
    segment = np.array([[-5.0, 0, 0], [-6, 0, 0], [-4, 0, 0]])  # 15 between 16 and 17
    pts = np.r_[hexagon, mids, spike, segment]
    sharp = [(i, 6 + i) for i in range(6)] + [(6 + i, (i + 1) % 6) for i in range(6)] + [(12, 13), (12, 14), (16, 15), (15, 17)]
    got = corners3(pts, np.arange(18), np.array(sharp))
    assert got.tolist() == [0, 1, 2, 3, 4, 5, 12, 13, 14, 16, 17]
    assert corners3(pts, np.arange(6, 12), np.array(sharp)).tolist() == []
