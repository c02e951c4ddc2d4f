"""The batched certificate (``hullstress/checker/closed_mesh.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/closed_mesh.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: the path concludes "certified" only for a closed convex surface that
wraps once around the vertices' mean, and then with the certificate the general
path builds; anything else declines with None) or from an independent exact
computation in integers or Fractions, never from the checker's own output.

The wrap-number ray is forced where the seeded one would almost never go (through
a vertex, through an edge, onto the mean itself) by replacing the module's
``ray_point``, as tests/test_mutants_wrap.py does for :mod:`.wrap`: the tie-break
must then give the count known from the geometry.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from hullstress.checker import closed_mesh
from hullstress.checker.closed_mesh import certify_closed_mesh, certify_convex_polygon
from hullstress.contract import FaceSet

from _exact import orient2d as _orient, winding_number as _winding

# --------------------------------------------------------------------------- inputs

#: The square ring (+-2, 0, 0), (0, +-2, 0) of the octahedron, counter-clockwise seen from +z.
_RING = [(2, 0, 0), (0, 2, 0), (-2, 0, 0), (0, -2, 0)]


def _bipyramid(turns: int) -> tuple[np.ndarray, FaceSet]:
    """Poles (0, 0, +-2) over the square ring run ``turns`` times (its points repeated under
    new indices): a closed surface with V - E + F = 2 whose faces all have the origin, the
    exact vertex mean, strictly below them and no reflex edge; it covers the sphere of
    directions ``turns`` times.  ``turns = 1`` is the octahedron."""
    pts = np.array([(0, 0, 2), (0, 0, -2)] + _RING * turns, dtype=np.float64)
    ring = [2 + j for j in range(4 * turns)]
    faces = []
    for j, a in enumerate(ring):
        b = ring[(j + 1) % len(ring)]
        faces += [(0, a, b), (1, b, a)]
    return pts, FaceSet.from_triangles(faces)


#: Ray points q (the ray runs from the mean, the origin, through q): through a vertex
#: (four wrap rows tie), through the middle of an edge of the ring or of a pole's edge
#: (two rows tie), along the ring's plane between two vertices, onto the mean itself
#: (every row ties), and one in general position.
_RAYS_3D = [
    (1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1),
    (1, 1, 0), (-1, 1, 0), (1, 0, 1), (0, -1, -1),
    (3, 1, 0), (1, -3, 0),
    (0, 0, 0),
    (0.3, 0.2, 0.1),
]

#: Ray points for the polygons below (whose vertex mean is the origin): through each vertex and
#: away from it, onto the mean, and one in general position; added to the vertices' own.
_RAYS_2D = [(0, 0), (0.3, 0.1), (1, 0), (0, 1), (-1, 0), (0, -1)]


def _force_ray(monkeypatch, q) -> None:
    monkeypatch.setattr(closed_mesh, "ray_point", lambda origin, extent, seed: np.array(q, dtype=np.float64))



def _mean(pts):
    return tuple(Fraction(sum(c), len(pts)) for c in zip(*pts))


# --------------------------------------------------------------------------- 3D


@pytest.mark.parametrize("q", _RAYS_3D)
def test_the_octahedron_is_certified_whatever_the_ray(monkeypatch, q):
    _force_ray(monkeypatch, q)
    pts, faces = _bipyramid(1)
    cert = certify_closed_mesh(pts, faces)
    assert cert is not None and cert.wraps == 1
    assert cert.containment and cert.convexity and cert.manifoldness
    assert cert.hull_vertices.tolist() == list(range(6)) and cert.extreme.tolist() == list(range(6))
    assert cert.boundary_nonextreme.tolist() == []


@pytest.mark.parametrize("q", _RAYS_3D)
def test_a_double_cover_is_declined_whatever_the_ray(monkeypatch, q):
    # The ring run twice: every local test passes (paired edges, V - E + F = 2, the mean
    # strictly below every face, no reflex edge) and only the wrap count, 2, tells.
    _force_ray(monkeypatch, q)
    pts, faces = _bipyramid(2)
    assert certify_closed_mesh(pts, faces) is None


@pytest.mark.parametrize("q", _RAYS_3D)
def test_the_octahedron_is_certified_when_point_0_is_inside(monkeypatch, q):
    # An extra input point first, at the mean: the rows that must start from the mean would
    # start from it anyway, so the vertex rows below are the ones that differ.
    _force_ray(monkeypatch, q)
    pts, faces = _bipyramid(1)
    pts = np.r_[[[0.0, 0.0, 0.0]], pts]
    faces = FaceSet.from_triangles(np.asarray(faces.indices).reshape(-1, 3) + 1)
    cert = certify_closed_mesh(pts, faces)
    assert cert is not None and cert.extreme.tolist() == list(range(1, 7))


# --------------------------------------------------------------------------- 2D

#: A convex pentagon with integer corners whose sum is 0: its vertex mean is the origin.
_PENTAGON = [(0, 10), (-10, 3), (-6, -8), (6, -8), (10, 3)]


def _polygon_rays(corners):
    return [tuple(0.5 * c for c in p) for p in corners] + _RAYS_2D


@pytest.mark.parametrize("q", _polygon_rays(_PENTAGON))
def test_a_convex_pentagon_is_certified_whatever_the_ray(monkeypatch, q):
    _force_ray(monkeypatch, q)
    pts = np.array(_PENTAGON, dtype=np.float64)
    cert = certify_convex_polygon(pts, np.arange(5))
    assert cert is not None and cert.wraps == 1 and cert.extreme.tolist() == list(range(5))


@pytest.mark.parametrize("q", _polygon_rays(_PENTAGON))
def test_the_pentagram_around_its_mean_is_declined_whatever_the_ray(monkeypatch, q):
    # Every second corner of the pentagon: all turns left, the mean (the origin) strictly left
    # of every edge, winding twice around it.
    star = [_PENTAGON[i] for i in (0, 2, 4, 1, 3)]
    assert all(_orient(star[i - 1], star[i], star[(i + 1) % 5]) > 0 for i in range(5))
    assert all(_orient(star[i], star[(i + 1) % 5], (0, 0)) > 0 for i in range(5))
    assert _winding(star, (0, 0)) == 2
    _force_ray(monkeypatch, q)
    assert certify_convex_polygon(np.array(_PENTAGON, dtype=np.float64), np.array([0, 2, 4, 1, 3])) is None


#: A convex pentagon (integer corners summing to 0, so the vertex mean is the origin) whose
#: pentagram leaves the origin in one of its five tips: winding once around it, but right of
#: an edge.
_LOPSIDED = [(-9, -8), (4, -10), (6, 7), (5, 7), (-6, 4)]
#: A square with a slit: from the middle of its bottom edge, M = (0, -4), up to S = (0, -2)
#: and back down to M' = (0, -3), then on to the next corner.  Every turn is left or straight
#: (the fold at S is collinear), and the vertex mean (0, -9/7) is on the slit's line x = 0,
#: above its tip, and strictly left of every other edge.
_SLIT = [(-4, -4), (0, -4), (0, -2), (0, -3), (4, -4), (4, 4), (-4, 4)]


@pytest.mark.parametrize("q", _polygon_rays(_SLIT) + [(0, 5), (0, -5), (5, 0)])
def test_a_square_with_a_slit_towards_its_mean_is_declined(monkeypatch, q):
    # The slit's two edges run along one line in opposite directions (the polygon touches
    # itself, it is not simple): the mean is on their line, not strictly left of them.  Seen
    # from the mean, the slit's edges cover no direction, so the wrap count alone is 1.
    k = len(_SLIT)
    assert all(_orient(_SLIT[i - 1], _SLIT[i], _SLIT[(i + 1) % k]) >= 0 for i in range(k))
    mean = _mean(_SLIT)
    assert mean == (0, Fraction(-9, 7))
    left = [_orient(_SLIT[i], _SLIT[(i + 1) % k], mean) for i in range(k)]
    assert [i for i in range(k) if left[i] == 0] == [1, 2] and min(left) == 0
    assert _winding(_SLIT, mean) == 1
    _force_ray(monkeypatch, q)
    assert certify_convex_polygon(np.array(_SLIT, dtype=np.float64), np.arange(k)) is None


#: A square about the origin, counter-clockwise.
_SQUARE = [(2, -2), (2, 2), (-2, 2), (-2, -2)]


@pytest.mark.parametrize("q", _polygon_rays(_SQUARE))
@pytest.mark.parametrize("kind", ["doubled corner", "run twice"])
def test_a_polygon_repeating_a_coordinate_is_declined(monkeypatch, q, kind):
    # Repeated coordinates under distinct indices (not simple, docs/design.md): a corner given
    # twice in a row (an edge of zero length, on whose line the mean lies), or the square run
    # twice (every turn left and the mean strictly left of every edge, but winding twice).
    ring = _SQUARE[:1] + _SQUARE if kind == "doubled corner" else _SQUARE * 2
    pts = np.array(ring, dtype=np.float64)
    if kind == "doubled corner":
        assert _mean(ring) != (0, 0) and _orient(ring[0], ring[1], _mean(ring)) == 0
    else:
        assert _mean(ring) == (0, 0) and min(_orient(ring[i], ring[(i + 1) % 8], (0, 0)) for i in range(8)) > 0
    _force_ray(monkeypatch, q)
    assert certify_convex_polygon(pts, np.arange(len(ring))) is None
