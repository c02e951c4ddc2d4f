"""Exact extreme points and coordinate sets (``hullstress/checker/extreme.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/extreme.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module's
docstrings) or from an independent exact computation in integers or Fractions,
never from the checker's own output.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from hullstress.checker.extreme import exact_extreme_2d, rows_in


def test_a_square_with_points_on_its_edges_has_its_four_corners():
    # Corners (0,0), (4,0), (4,4), (0,4); (2,0) and (4,2) on edges, (1,1) inside.
    pts = np.array([[2.0, 0], [4, 4], [1, 1], [0, 0], [4, 2], [0, 4], [4, 0]])
    assert exact_extreme_2d(pts).tolist() == [3, 6, 1, 5]


def _exact_orient(a, b, c) -> int:
    fa = [Fraction(v) for v in (*a, *b, *c)]
    det = (fa[0] - fa[4]) * (fa[3] - fa[5]) - (fa[1] - fa[5]) * (fa[2] - fa[4])
    return (det > 0) - (det < 0)


def test_a_point_the_float_orientation_misplaces_is_not_extreme():
    # b is within a few units in the last place of the segment a-c, and exactly on the same
    # side of it as e: b lies strictly inside the triangle a, c, e, so the extreme points are
    # a, c and e.  The naive float orientation of (a, b, c) says the opposite turn (it is
    # evaluated here in plain Python floats, as a witness that the input is a hard one): only
    # the exact stage gets b right.
    a = (0.8744245391048224, 2.7134700765232402)
    b = (1.008100977785846, 1.0749891821858217)
    c = (1.274660195179873, -2.1922446641004196)
    e = (2.0, 10.0)
    assert _exact_orient(a, c, e) == 1 and _exact_orient(a, c, b) == 1  # b and e on one side of a-c
    assert _exact_orient(c, e, b) == 1 and _exact_orient(e, a, b) == 1  # b inside the triangle
    naive = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])
    assert naive > 0 and _exact_orient(a, b, c) == -1  # (IEEE doubles: the same on every machine)
    pts = np.array([e, b, a, c])
    assert exact_extreme_2d(pts).tolist() == [2, 3, 0]  # a, c, e: counter-clockwise from a


def test_rows_in_compares_values_of_any_float_width():
    # "Exact float equality" by value: float32 rows equal to float64 table rows are in it.
    table = np.array([[1.0, 2.0], [0.5, -3.0]])
    rows = np.array([[0.5, -3.0], [2.0, 1.0], [1.0, 2.0]], dtype=np.float32)
    assert rows_in(rows, table).tolist() == [True, False, True]
    assert rows_in(table, rows).tolist() == [True, True]
