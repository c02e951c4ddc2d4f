"""``hullstress.checker.certify``, pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/certify.py``
that survived the rest of the fast suite (``tools/mutation.sh
'hullstress.checker.certify.*'``, docs/testing.md "Mutation testing").  Every expectation
comes from the documented behaviour (the certificate's fields, docs/design.md's
verdict semantics) worked out by hand on small integer polytopes, never from the
checker's own output.
"""

from __future__ import annotations

import numpy as np
import pytest

from hullstress.checker.certify import certify
from hullstress.contract import normalize_output

TETRA = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
#: Counter-clockwise seen from outside (the outward normals are -z, -y, -x and (1, 1, 1)).
TETRA_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def test_a_tetrahedron_is_certified_by_the_general_checks():
    faces = normalize_output(TETRA_FACES, 4, 3)
    cert = certify(TETRA, faces, batched=False)
    assert (cert.containment, cert.convexity, cert.manifoldness) == (True, True, True)
    assert cert.dim == 3 and cert.n_faces == 4
    assert cert.extreme.tolist() == [0, 1, 2, 3] and cert.boundary_nonextreme.tolist() == []
    assert cert.outside.tolist() == [] and cert.n_nonconvex_edges == 0 and cert.n_degenerate_faces == 0


# The general 2D checks (batched=False skips the one-batch certificate of a convex polygon).
#: A 2x2 square, counter-clockwise, with (1, 0) on its bottom edge as a vertex; (3, 1) lies 1
#: right of the edge x = 2, (1, 1) is the centre.
SQUARE_PTS = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [3.0, 1.0], [1.0, 1.0], [1.0, 0.0]])
SQUARE_POLY = np.array([0, 6, 1, 2, 3])


def test_a_convex_polygon_with_a_point_outside_is_not_contained_and_says_how_far():
    cert = certify(SQUARE_PTS, SQUARE_POLY, batched=False)
    assert (cert.containment, cert.convexity, cert.manifoldness) == (False, True, True)
    assert cert.dim == 2 and cert.n_faces == 5 and cert.hull_vertices.tolist() == [0, 1, 2, 3, 6]
    assert cert.extreme is None and cert.boundary_nonextreme is None  # not certified
    assert cert.outside.tolist() == [4] and cert.offending["containment"].tolist() == [4]
    assert cert.reasons["containment"] == ["1 points outside"]
    assert list(cert.magnitudes) == ["outside"] and cert.magnitudes["outside"] == pytest.approx(1.0, rel=1e-9)
    assert cert.n_nonconvex_edges == 0 and cert.n_degenerate_faces == 0


def test_a_certified_polygon_names_its_corners_and_its_edge_vertex():
    pts = np.delete(SQUARE_PTS, 4, axis=0)  # (1, 1) and (1, 0) are now rows 4 and 5
    cert = certify(pts, np.array([0, 5, 1, 2, 3]), batched=False)
    assert (cert.containment, cert.convexity, cert.manifoldness) == (True, True, True)
    assert cert.extreme.tolist() == [0, 1, 2, 3] and cert.boundary_nonextreme.tolist() == [5]
    assert cert.magnitudes == {} and cert.reasons["containment"] == [] and cert.outside.tolist() == []


def test_a_reflex_vertex_of_a_polygon_is_named_by_its_point_index():
    # 0 -> 1 -> (1, 1) -> 2 -> 3: at (1, 1) the turn from direction (-1, 1) to (1, 1) is clockwise.
    pts = np.delete(SQUARE_PTS, [4, 6], axis=0)  # (1, 1) is row 4
    cert = certify(pts, np.array([0, 1, 4, 2, 3]), batched=False)
    assert cert.convexity is False and cert.manifoldness is True
    assert cert.offending["reflex_vertices"].tolist() == [4] and cert.n_nonconvex_edges == 1
    assert cert.extreme is None and cert.boundary_nonextreme is None


def test_a_tetrahedron_with_a_point_outside_through_the_general_checks():
    pts = np.vstack([TETRA, [[0.1, 0.1, 0.1], [1.0, 1.0, 1.0]]])
    cert = certify(pts, normalize_output(TETRA_FACES, 6, 3), batched=False)
    assert (cert.containment, cert.convexity, cert.manifoldness) == (False, True, True)
    assert cert.outside.tolist() == [5] and cert.offending["containment"].tolist() == [5]
    assert cert.reasons["containment"] == ["1 points outside"]
    # (1, 1, 1) is (3 - 1) / sqrt(3) beyond the face x + y + z = 1.
    assert cert.magnitudes["outside"] == pytest.approx(2 / 3**0.5, rel=1e-9)
    assert cert.extreme is None and cert.boundary_nonextreme is None and cert.hull_vertices.tolist() == [0, 1, 2, 3]


def test_a_closed_surface_with_a_collinear_face_names_it_as_degenerate():
    # The tetrahedron with vertex 4 the midpoint of edge 0-1: face (0, 2, 1) is split in two
    # at 4, and the sliver (1, 0, 4) of three collinear points closes the surface (every edge
    # is used twice, once each way), so it is a closed manifold with one degenerate face.
    pts = np.vstack([TETRA, [[0.5, 0.0, 0.0]]])
    faces = normalize_output([[0, 2, 4], [4, 2, 1], [1, 0, 4], [0, 1, 3], [0, 3, 2], [1, 2, 3]], 5, 3)
    sliver = [k for k in range(faces.n_faces)
              if sorted(faces.indices[faces.offsets[k]:faces.offsets[k + 1]].tolist()) == [0, 1, 4]]
    cert = certify(pts, faces, batched=False)
    assert cert.convexity is False
    assert cert.offending["degenerate_faces"].tolist() == sliver and cert.n_degenerate_faces == 1
    assert cert.extreme is None and cert.boundary_nonextreme is None


def test_a_polygon_wound_twice_names_point_indices_not_positions():
    # The square 1 -> 2 -> 3 -> 0 twice round: every vertex index is repeated, so every vertex
    # is a manifoldness failure; offending lists point indices (0..3), not positions (0..7).
    pts = np.delete(SQUARE_PTS, [4, 5, 6], axis=0)
    cert = certify(pts, np.array([1, 2, 3, 0, 1, 2, 3, 0]), batched=False)
    assert cert.manifoldness is False
    assert sorted(set(cert.offending["manifold_vertices"].tolist())) == [0, 1, 2, 3]


def test_a_convex_hull_is_certified_in_one_batch_with_a_witness_simplex():
    # By default certify tries the one-batch certificate first (closed_mesh.py), which names
    # dim + 1 affinely independent vertices met on the way (Certificate.witness, reused by
    # qhull_reference); the general checks name none.  The tetrahedron's four vertices and
    # three corners of the square are the only such sets here.
    cert = certify(TETRA, normalize_output(TETRA_FACES, 4, 3))
    assert cert.certified and sorted(cert.witness.tolist()) == [0, 1, 2, 3]
    assert certify(TETRA, normalize_output(TETRA_FACES, 4, 3), batched=False).witness is None
    square = np.delete(SQUARE_PTS, [4, 5, 6], axis=0)
    cert2 = certify(square, np.array([0, 1, 2, 3]))
    assert cert2.certified and len(set(cert2.witness.tolist())) == 3 and set(cert2.witness.tolist()) <= {0, 1, 2, 3}


def test_the_general_checks_compute_the_half_edges_and_the_measure_once(monkeypatch):
    # certify hands its half-edges and its measure on to the checks (which would otherwise
    # build their own): one of each per certificate.
    import hullstress.checker.certify as certify_module
    import hullstress.checker.polygon2d as polygon2d_module
    import hullstress.checker.topology as topology_module

    calls = []

    def counting(module, name):
        real = getattr(module, name)

        def wrapper(*args, **kwargs):
            calls.append(name)
            return real(*args, **kwargs)

        monkeypatch.setattr(module, name, wrapper)

    for module in (certify_module, topology_module, polygon2d_module):
        counting(module, "surface_measure")
    for module in (certify_module, topology_module):
        counting(module, "half_edges")
    cert = certify(TETRA, normalize_output(TETRA_FACES, 4, 3), batched=False)
    assert cert.certified and sorted(calls) == ["half_edges", "surface_measure"]
    calls.clear()
    cert2 = certify(np.delete(SQUARE_PTS, [4, 5, 6], axis=0), np.array([0, 1, 2, 3]), batched=False)
    assert cert2.certified and calls == ["surface_measure"]
