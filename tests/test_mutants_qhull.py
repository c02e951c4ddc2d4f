"""Qhull as a witness (``hullstress/checker/qhull.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/qhull.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
and field docstrings, DESIGN.md's "qhull agreement") or from the geometry
worked out by hand, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.qhull import qhull_reference


def test_reference_of_a_tetrahedron_with_an_inner_point():
    pts = np.array([[0.0, 0, 0], [4, 0, 0], [0, 4, 0], [0, 0, 4], [1, 1, 1]])
    ref = qhull_reference(pts)
    assert ref.error is None and ref.qhull_ok is True and ref.options == "Qt"
    assert sorted(ref.vertices.tolist()) == [0, 1, 2, 3]
    assert ref.extreme.tolist() == [0, 1, 2, 3]
    assert ref.volume == 64 / 6 and ref.affine_rank == 3 and ref.n_points == 5 and ref.dim == 3
