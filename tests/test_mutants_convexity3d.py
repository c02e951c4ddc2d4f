"""3D convexity (``hullstress/checker/convexity3d.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/convexity3d.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring, DESIGN.md's verdict semantics) or from an independent exact
computation in integers or Fractions, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.convexity3d import check_convexity3d
from hullstress.checker.topology import half_edges
from hullstress.contract import FaceSet

_CUBE = np.array([[2 * (v >> 2) - 1, 2 * ((v >> 1) & 1) - 1, 2 * (v & 1) - 1] for v in range(8)], dtype=np.float64)
#: Vertex v = 4x + 2y + z (bits), each quadrilateral counter-clockwise seen from outside.
_CUBE_QUADS = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def test_the_cube_of_quadrilaterals_is_convex_with_twelve_sharp_edges():
    faces = FaceSet.from_polygons(_CUBE_QUADS)
    res = check_convexity3d(_CUBE, faces, half_edges(faces, 8), closed=True)
    assert res.ok and res.degree == 1 and res.n_reflex_edges == 0
    assert len(res.sharp_edges) == 12
