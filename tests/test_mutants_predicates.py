"""The exact orientation predicates, pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/predicates.py``
that survived the rest of the fast suite (``tools/mutation.sh
'hullstress.checker.predicates.*'``, README "Mutation testing").  Every expected
sign is derived by hand from the geometry (points on a known plane or line, whose
determinant is a known multiple of one coordinate) or computed independently with
``fractions.Fraction``; never copied from the predicates' own output.  A row only
reaches the exactness-check and double-double stages when the float filter leaves
more than ``FEW_FOR_INTEGERS`` rows open, so the tests that aim at those stages
either use more rows than that or set it to 0.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.predicates import FEW_FOR_INTEGERS, orient3d


def test_points_off_a_coordinate_plane_by_tiny_heights_through_every_stage():
    # a, b, c span the plane z = 0 with (b - a) x (c - a) = +z, so the determinant of
    # (a, b, c, d) is exactly -d_z whatever d_x, d_y: the sign is -sign(d_z) (docstring:
    # +1 when d is below the plane).  Heights far below the filter's bound leave every row
    # open; lattice abscissas are settled by the exactness check, 0.1-multiples by the
    # double-double stage, heights below its precision by integers.
    k = 3 * (FEW_FOR_INTEGERS + 1)
    rng = np.random.default_rng(5)
    xy = np.r_[rng.integers(-9, 10, (k // 3, 2)) * 1.0, rng.integers(-9, 10, (2 * k // 3, 2)) * 0.1]
    heights = rng.integers(-3, 4, k) * np.r_[np.full(2 * k // 3, 2.0**-60), np.full(k - 2 * k // 3, 2.0**-120)]
    d = np.c_[xy, heights]
    a, b, c = np.zeros(3), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    assert np.array_equal(orient3d(a, b, c, d), -np.sign(heights).astype(np.int8))
