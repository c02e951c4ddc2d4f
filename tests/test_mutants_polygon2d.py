"""The 2D polygon checks (``hullstress/checker/polygon2d.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/polygon2d.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring, DESIGN.md's verdict semantics) or from an independent exact
computation in integers or Fractions, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.polygon2d import check_polygon2d


def test_a_unit_square_passes_with_one_wrap():
    pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    res = check_polygon2d(pts, np.arange(4))
    assert res.manifold_ok and res.convex_ok and res.wraps == 1
    assert res.turn.tolist() == [1, 1, 1, 1]
