"""``hullstress/contract.py`` (output normalisation) pinned where the mutation run found it loose.

Each test here was written against mutants of ``contract.py`` that survived
the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented contract (README
"Testing your own hull code", the module's docstrings) or is worked out by
hand, never from the module's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.contract import FaceSet


def test_fan_triangles_of_mixed_faces_by_hand():
    fs = FaceSet.from_polygons([[5, 6, 7, 8, 9], [1, 2, 3], [4, 3, 2, 1]])
    tri, face_of = fs.fan_triangles()
    assert tri.tolist() == [[5, 6, 7], [5, 7, 8], [5, 8, 9], [1, 2, 3], [4, 3, 2], [4, 2, 1]]
    assert face_of.tolist() == [0, 0, 0, 1, 2, 2]
    assert tri.dtype == np.int64 and face_of.dtype == np.int64
