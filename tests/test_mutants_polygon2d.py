"""The 2D polygon checks (``hullstress/checker/polygon2d.py``), pinned where the mutation run found them loose.

Each test here was written against mutants of ``hullstress/checker/polygon2d.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring, docs/design.md's verdict semantics) or from an independent exact
computation in integers or Fractions, never from the checker's own output.

The interior point of a polygon that is not certified by its vertex mean is
"the exact centroid of a triangle of the polygon's vertices" (module
docstring), the witness simplex of :mod:`.rank`: "far points first", the two
ends of the widest axis, then the vertex farthest from their line.  The
polygons below make that choice unambiguous (no ties), so the centroid is
worked out by hand.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from hullstress.checker.polygon2d import check_polygon2d

from _exact import orient2d as _orient, winding_number as _winding




def _turns(ring):
    k = len(ring)
    return [_orient(ring[i - 1], ring[i], ring[(i + 1) % k]) for i in range(k)]


def _left(ring, o):
    """orient2d of every edge (i -> i + 1) with o, exactly."""
    k = len(ring)
    return [_orient(ring[i], ring[(i + 1) % k], o) for i in range(k)]


def _mean(ring):
    return tuple(Fraction(sum(c), len(ring)) for c in zip(*ring))


def _strictly_left_of_every_edge(ring, center) -> bool:
    return min(_left(ring, tuple(Fraction(float(c)) for c in center))) > 0


def test_a_unit_square_passes_with_one_wrap():
    pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    res = check_polygon2d(pts, np.arange(4))
    assert res.manifold_ok and res.convex_ok and res.wraps == 1
    assert res.turn.tolist() == [1, 1, 1, 1]


#: A heptagon with a notch at N = (0, 2) between the top corners A = (1, 9) and C = (-1, 8):
#: one reflex vertex (position 5).  Its vertex mean (0, 13/7) is strictly left of every edge;
#: the witness triangle (the x ends L = (-10, 0) and R = (10, 0), then A, the farthest from
#: their line) has its centroid (1/3, 3) above the notch, right of the edge N -> C.
_NOTCH = [(-10, 0), (-6, -3), (6, -3), (10, 0), (1, 9), (0, 2), (-1, 8)]


def test_a_notched_polygon_names_the_edge_its_interior_point_is_right_of():
    ring = _NOTCH
    assert [i for i, t in enumerate(_turns(ring)) if t <= 0] == [5] and _turns(ring)[5] < 0
    mean = _mean(ring)
    assert mean == (0, Fraction(13, 7)) and min(_left(ring, mean)) > 0
    centroid = (Fraction(-10 + 10 + 1, 3), Fraction(0 + 0 + 9, 3))
    assert [i for i, v in enumerate(_left(ring, centroid)) if v <= 0] == [5]
    res = check_polygon2d(np.array(ring, dtype=np.float64), np.arange(7))
    assert not res.convex_ok and res.reflex.tolist() == [5]
    # The polygon failed already (a reflex vertex), so the exact centroid names the edges it
    # is not strictly left of: the edge N -> C, at position 5.
    assert res.flipped.tolist() == [5]
    assert any("interior point not strictly left" in r for r in res.reasons_convex)
    # The vertex mean still qualifies as a centre (strictly left of every edge): it is found.
    assert res.center is not None and _strictly_left_of_every_edge(ring, res.center)


#: A square-ish heptagon with a slit up from its bottom edge along x = 3: M = (3, -6) up to
#: S = (3, -1), then back down to M' = (3, -3).  Every turn is left or straight (the fold at
#: S is collinear).  The witness triangle: the x ends (-6, -6) and (8, -6), then (7, 7), the
#: farthest from their line; its centroid (3, -5/3) is exactly on the slit's line.
_SLIT = [(-6, -6), (3, -6), (3, -1), (3, -3), (8, -6), (7, 7), (-5, 6)]


def test_a_slit_through_the_interior_point_names_both_slit_edges():
    ring = _SLIT
    assert min(_turns(ring)) == 0 and _turns(ring)[2] == 0
    centroid = (Fraction(-6 + 8 + 7, 3), Fraction(-6 - 6 + 7, 3))
    assert centroid == (3, Fraction(-5, 3))
    assert [i for i, v in enumerate(_left(ring, centroid)) if v <= 0] == [1, 2]
    assert [v == 0 for v in _left(ring, centroid)[1:3]] == [True, True]
    assert min(_left(ring, _mean(ring))) < 0  # the mean is strictly right of S -> M'
    res = check_polygon2d(np.array(ring, dtype=np.float64), np.arange(7))
    assert not res.convex_ok and res.reflex.tolist() == []
    # "Strictly left": an edge through the interior point is flipped.
    assert res.flipped.tolist() == [1, 2]
    # No point is strictly left of both slit edges (they run along one line both ways).
    assert res.center is None
    assert not res.manifold_ok  # the slit's edges overlap: not simple


#: The same square with the slit along x = 0 from its bottom edge, for a polygon whose vertex
#: mean (0, -9/7) lies on the slit's line above its tip.
_SLIT_TO_MEAN = [(-4, -4), (0, -4), (0, -2), (0, -3), (4, -4), (4, 4), (-4, 4)]


def test_a_slit_towards_the_vertex_mean_is_neither_convex_nor_simple():
    ring = _SLIT_TO_MEAN
    assert min(_turns(ring)) == 0
    mean = _mean(ring)
    assert mean == (0, Fraction(-9, 7)) and [v == 0 for v in _left(ring, mean)] == [False, True, True] + [False] * 4
    res = check_polygon2d(np.array(ring, dtype=np.float64), np.arange(7))
    assert not res.convex_ok and not res.manifold_ok
    assert res.center is None  # no point is strictly left of both slit edges
    assert set(res.flipped.tolist()) & {1, 2}


#: Nine integer points near a circle of radius 100 (coordinates summing to 0: the vertex mean
#: is the origin), joined every fourth: the star {9/4}.  Every turn is left and the origin is
#: strictly left of every edge, but the star winds four times around it.  The witness triangle
#: (the x ends P4 = (-99, 15) and P0 = (98, 20), then P6 = (-32, -95), the farthest from their
#: line) has its centroid (-11, -20) in a tip of the star, strictly right of two edges.
_CIRCLE9 = [(98, 20), (62, 78), (-3, 100), (-66, 75), (-99, 15), (-85, -52), (-32, -95), (37, -93), (88, -48)]
_STAR94 = [(4 * t) % 9 for t in range(9)]


def test_a_star_winding_four_times_is_counted_around_its_vertex_mean():
    ring = [_CIRCLE9[i] for i in _STAR94]
    assert min(_turns(ring)) > 0
    assert _mean(ring) == (0, 0) and min(_left(ring, (0, 0))) > 0
    assert _winding(ring, (0, 0)) == 4
    # The witness triangle by hand: x spans 197 (-99 to 98), y 195; the point farthest from
    # the line P4 P0 (|cross| with its direction, exact) is P6 alone.
    p4, p0 = _CIRCLE9[4], _CIRCLE9[0]
    cross = [abs(_orient(p4, p0, p)) for p in _CIRCLE9]
    assert max(range(9), key=cross.__getitem__) == 6 and sorted(cross)[-2] < cross[6]
    centroid = tuple(Fraction(p4[c] + p0[c] + _CIRCLE9[6][c], 3) for c in range(2))
    assert centroid == (-11, -20)
    assert [i for i, v in enumerate(_left(ring, centroid)) if v <= 0] == [1, 3]
    assert min(_left(ring, centroid)) < 0
    res = check_polygon2d(np.array(_CIRCLE9, dtype=np.float64), np.array(_STAR94))
    # The polygon passed every local test, so its vertex mean is the centre (tested exactly,
    # and it is strictly left of every edge): the wrap count names the failure, and no edge
    # is flipped (the centroid, in a tip, would flip two).
    assert not res.convex_ok and res.reflex.tolist() == [] and res.degenerate_edges.tolist() == []
    assert res.wraps == 4
    assert res.flipped.tolist() == []
    assert res.center is not None and res.center.tolist() == [0.0, 0.0]
    assert len(res.reasons_convex) == 1 and "winds 4 times" in res.reasons_convex[0]
