"""The batched certificate (``hullstress/checker/closed_mesh.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/closed_mesh.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: the path concludes "certified" only for a closed convex surface that
wraps once around the vertices' mean, and then with the certificate the general
path builds; anything else declines with None) or from an independent exact
computation in integers or Fractions, never from the checker's own output.

The wrap-number ray is forced where the seeded one would almost never go (through
a vertex, through an edge, onto the mean itself) by replacing the module's
``ray_point``, as tests/test_mutants_wrap.py does for :mod:`.wrap`: the tie-break
must then give the count known from the geometry.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker import closed_mesh
from hullstress.checker.closed_mesh import certify_closed_mesh
from hullstress.contract import FaceSet

#: The octahedron with vertices at +-2 on each axis, faces counter-clockwise seen from outside.
_OCTA = np.array([[2.0, 0, 0], [-2, 0, 0], [0, 2, 0], [0, -2, 0], [0, 0, 2], [0, 0, -2]])
_OCTA_FACES = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]


def _force_ray(monkeypatch, q) -> None:
    monkeypatch.setattr(closed_mesh, "ray_point", lambda origin, extent, seed: np.array(q, dtype=np.float64))


def test_the_octahedron_is_certified_with_the_ray_through_a_vertex(monkeypatch):
    # The mean is the origin; q = (1, 0, 0) puts vertex 0 on the ray: four wrap rows tie.
    _force_ray(monkeypatch, [1.0, 0.0, 0.0])
    cert = certify_closed_mesh(_OCTA, FaceSet.from_triangles(_OCTA_FACES))
    assert cert is not None and cert.wraps == 1
    assert cert.extreme.tolist() == list(range(6))
