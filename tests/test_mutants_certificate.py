"""The certificate record and its corners (``hullstress/checker/certificate.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/certificate.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the
docstrings, DESIGN.md's verdict semantics) or from the geometry worked out by
hand, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.certificate import corners3


def test_corners_of_a_cube_are_its_eight_vertices():
    # A unit cube as 12 triangles: its 12 edges are the sharp ones; each corner meets three.
    pts = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    sharp = np.array([[a, b] for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1])
    assert len(sharp) == 12
    assert corners3(pts, np.arange(8), sharp).tolist() == list(range(8))
