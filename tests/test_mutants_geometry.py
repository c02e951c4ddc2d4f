"""``hullstress/checker/_geometry.py`` pinned where the mutation run found it loose.

Each test here was written against mutants of ``_geometry.py`` that survived
the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the
docstrings, DESIGN.md's verdict semantics) or is worked out by hand in
integers or Fractions, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker._geometry import point_line_distance


def test_point_line_distance_is_the_signed_height_over_the_segment():
    # Line (1, 0) -> (3, 0): (2, 2) is 2 to the left, (2, -3) is 3 to the right.  The
    # direction's length is |b - a| = 2, not |b + a| = 4.
    a = np.array([[1.0, 0.0], [1.0, 0.0]])
    b = np.array([[3.0, 0.0], [3.0, 0.0]])
    p = np.array([[2.0, 2.0], [2.0, -3.0]])
    assert point_line_distance(a, b, p).tolist() == [2.0, -3.0]
