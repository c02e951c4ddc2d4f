"""Volumes, areas and their comparison (``hullstress/checker/measure.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/measure.py``
that survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: an exact sum, independent of face order) or from an independent exact
computation with Fractions, never from the checker's own output.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from hullstress.checker.measure import surface_measure


def test_area_of_a_square_is_exact_and_signed():
    sq = np.array([[0.0, 0], [3, 0], [3, 3], [0, 3]])
    ccw = surface_measure(sq, np.array([0, 1, 2, 3]))
    assert ccw.value() == 9.0 and ccw.sign == 1 and ccw.exact_sum() == Fraction(18)
    cw = surface_measure(sq, np.array([3, 2, 1, 0]))
    assert cw.value() == -9.0 and cw.sign == -1
