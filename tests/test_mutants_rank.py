"""The exact affine rank and witness simplex (``hullstress/checker/rank.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/rank.py`` that
survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module's
docstrings: the rank is exact, the witness simplex's choice is "far points
first") or from an independent exact computation in integers or Fractions,
never from the checker's own output.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker.rank import affine_rank, witness_simplex


def test_a_point_off_a_line_by_one_unit_in_the_last_place():
    # (1, 1 + 2**-52) is off the line y = x through (0, 0) and (2, 2): rank 2, exactly.
    assert affine_rank(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0 + 2.0**-52]])) == 2
    assert affine_rank(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0]])) == 1


def _cross(o, a, b) -> Fraction:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def test_the_far_point_is_chosen_when_the_float_scores_overflow():
    # The ends span 2e308 on x: the float scores overflow (to inf, or NaN for inf - inf),
    # so the best-scored point is one exactly on the ends' line (point 3).  It fails the
    # exact test; of the points that pass it, "far points first" takes the one farthest
    # from the line: point 4 (4.5 above it), not point 2 (0.5 below it).
    big = 1e308
    pts = [(-big, 0.0), (big, 1.0), (0.0, 0.0), (0.0, 0.5), (0.0, 5.0)]
    exact = [tuple(Fraction(c) for c in p) for p in pts]
    area = [abs(_cross(exact[0], exact[1], p)) for p in exact]  # |cross| = length * distance
    assert area[3] == 0 and area[4] == 9 * area[2] > 0
    assert witness_simplex(np.array(pts)).tolist() == [0, 1, 4]
    assert affine_rank(np.array(pts)) == 2


def test_the_third_point_is_the_farthest_from_the_ends_line_away_from_the_origin():
    # The ends of the widest axis (x: 0 to 20) are (0, -10) and (20, -10); of the others,
    # (5, -4) is 6 from their line y = -10 and (5, -15) only 5: "far points first" takes
    # (5, -4).  The line is away from the origin and horizontal, so a score measured from
    # the origin, or with the line's direction mixed up, would pick the other point.
    pts = [(5.0, -15.0), (0.0, -10.0), (5.0, -4.0), (20.0, -10.0)]
    dist = [abs(Fraction(p[1]) - (-10)) for p in pts]
    assert dist[2] == 6 and dist[0] == 5
    got = witness_simplex(np.array(pts)).tolist()
    assert got == [1, 3, 2]


def test_the_error_for_non_finite_points_says_so():
    for bad in (np.nan, np.inf, -np.inf):
        with pytest.raises(ValueError, match=r"^points must be finite, got NaN or inf coordinates$"):
            affine_rank(np.array([[0.0, 0.0], [1.0, bad], [0.0, 1.0]]))
