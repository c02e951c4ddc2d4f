"""Exact extreme points and coordinate sets (``hullstress/checker/extreme.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/extreme.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module's
docstrings) or from an independent exact computation in integers or Fractions,
never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.extreme import exact_extreme_2d


def test_a_square_with_points_on_its_edges_has_its_four_corners():
    # Corners (0,0), (4,0), (4,4), (0,4); (2,0) and (4,2) on edges, (1,1) inside.
    pts = np.array([[2.0, 0], [4, 4], [1, 1], [0, 0], [4, 2], [0, 4], [4, 0]])
    assert exact_extreme_2d(pts).tolist() == [3, 6, 1, 5]
