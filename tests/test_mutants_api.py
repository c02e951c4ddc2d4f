"""``hullstress/checker/api.py`` (the ``check`` entry point) pinned where the mutation run found it loose.

Each test here was written against mutants of ``api.py`` that survived the
rest of the fast suite (``tools/mutation.sh``, README "Mutation testing").
Every expectation comes from the documented behaviour (``check``'s
docstring, DESIGN.md's verdict semantics) or is worked out by hand in
integers or Fractions, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker import check


def test_a_cut_corner_in_2d_by_hand():
    # The square 0..3 with its centre 4: the hull 0 1 4 3 cuts the corner 2 = (2, 2) off
    # (orient2d((2, 0), (1, 1), (2, 2)) = -2: right of the edge 1 -> 4, outside).
    pts = np.array([[0.0, 0], [2, 0], [2, 2], [0, 2], [1, 1]])
    v = check(pts, [0, 1, 4, 3])
    assert not v.ok
    assert v.offending["containment"] == (2,)
    assert v.offending["missing_extreme"] == (2,)
    assert v.n_extreme == 4 and v.n_outside == 1 and v.n_hull_vertices == 4
