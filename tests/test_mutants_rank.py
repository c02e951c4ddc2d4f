"""The exact affine rank and witness simplex (``hullstress/checker/rank.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/rank.py`` that
survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module's
docstrings) or from an independent exact computation in integers or Fractions,
never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.rank import affine_rank


def test_a_point_off_a_line_by_one_unit_in_the_last_place():
    # (1, 1 + 2**-52) is off the line y = x through (0, 0) and (2, 2): rank 2, exactly.
    assert affine_rank(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0 + 2.0**-52]])) == 2
    assert affine_rank(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0]])) == 1
