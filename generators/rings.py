"""Closed rings, as GIS data stores polygons: the first point repeated at the end of every ring.

GeoJSON, WKT, GML/CityGML and shapely/GEOS all store a polygon ring with its
first coordinate repeated as the last, and users hand those coordinate lists
straight to hull code.  The repeated point is an exact duplicate of a hull
vertex (often the lexicographically smallest or the starting point of the
scan), the rows come in boundary order (sorted by angle, not shuffled), a
polygon with holes repeats a point per ring, and digitised parcels have
vertices exactly on the straight edges between corners.

Real reports this imitates:

- JuliaGeometry/DelaunayTriangulation.jl#109: ``convex_hull`` was invalid
  on repeated points, raised because "all geographic polygons must have
  ``polygon[begin] == polygon[end]``" (``shape="convex"``).
- shapely/shapely#541: ``Polygon(...).convex_hull`` of a closed ring (first
  point repeated last) returned an invalid hull (``shape="star"``).
- benbovy/spherely#42: a ring closed by its first point rejected as a
  "degenerate edge (duplicate vertex)"; 3dcitydb/3dcitydb#31 explains why
  every GML ring repeats it (``shape="holes"``: each ring closed).

In 3D the footprint is stored twice, as the floor and the roof ring of an
extruded building (each closed), like the LoD1 solids of CityGML.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import check_choice, check_dim, check_n, check_positive, declare_min_size, finish, sector_polygon

__all__ = ["closed_ring", "RING_SHAPES"]

RING_SHAPES = ("convex", "star", "rectangle", "holes")
#: distinct points a ring needs (before the closing repeat)
_RING_MIN = {"convex": 3, "star": 3, "rectangle": 4, "holes": 3}


def _rectangle_ring(rng: np.random.Generator, m: int) -> np.ndarray:
    """An integer rectangle's 4 corners and m - 4 integer points on its edges, in boundary order."""
    a, b = (int(v) for v in rng.integers(m, 2 * m + 1, 2))
    perimeter = 2 * (a + b)
    corners = np.array([0, a, a + b, 2 * a + b])
    free = np.ones(perimeter, dtype=bool)
    free[corners] = False
    others = np.flatnonzero(free)
    t = np.sort(np.concatenate([corners, rng.choice(others, m - 4, replace=False)]))
    # walk the boundary counter-clockwise from (0, 0): bottom, right, top, left
    x = np.select([t <= a, t <= a + b, t <= 2 * a + b], [t, a, 2 * a + b - t], 0)
    y = np.select([t <= a, t <= a + b, t <= 2 * a + b], [0, t - a, b], perimeter - t)
    return np.column_stack([x, y]).astype(np.float64)


def _footprint(rng: np.random.Generator, m: int, shape: str, scale: float) -> list[np.ndarray]:
    """The rings (each open, counter-clockwise) of a footprint with m distinct points in all."""
    if shape == "rectangle":
        return [_rectangle_ring(rng, m) * scale]
    if shape == "holes":
        inner = max(3, m // 3)
        outer = sector_polygon(rng, m - inner, wobble=False) * scale
        # the hole stays strictly inside the outer ring: within 0.9 of its inradius
        nxt = np.roll(outer, -1, axis=0)
        cross = np.abs(outer[:, 0] * nxt[:, 1] - outer[:, 1] * nxt[:, 0])
        inradius = float(np.min(cross / np.hypot(*(nxt - outer).T)))
        return [outer, sector_polygon(rng, inner, wobble=True) * (0.9 * inradius)]
    return [sector_polygon(rng, m, wobble=shape == "star") * scale]


def _closed(ring: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Reverse a ring at random (GIS rings come in both orientations), keep its start, repeat it last."""
    if rng.random() < 0.5:
        ring = np.concatenate([ring[:1], ring[:0:-1]])
    return np.concatenate([ring, ring[:1]])


@register_generator(
    "closed-ring",
    dims=(2, 3),
    variants=({"shape": "convex"}, {"shape": "star"}, {"shape": "rectangle"}, {"shape": "holes"}),
)
def closed_ring(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    shape: str = "convex",
    scale: float = 1.0,
) -> np.ndarray:
    """Polygon rings in boundary order with the first point repeated at the end (GeoJSON, WKT, GML).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of rows including the closing repeats (see ``min_size``).
    dim : {2, 3}
        2D: the footprint's rings.  3D: the footprint as the floor (z = 0)
        and the roof (z = ``scale``), every ring closed on its own.
    shape : {"convex", "star", "rectangle", "holes"}
        ``convex``: points on a circle of radius ``scale``, one per sector
        (every point extreme).  ``star``: random radii in [0.5, 1] times
        ``scale`` (a simple non-convex ring).  ``rectangle``: a parcel with
        integer corners and integer vertices on its edges (exactly collinear
        runs), times ``scale``.  ``holes``: an outer circle ring and an inner
        star ring strictly inside it (a hole), each closed.
    scale : float
        Size of the footprint (> 0).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Ring after ring, each in boundary order (counter-clockwise or
        clockwise at random) and ending with an exact copy of its first row;
        in 3D the floor's rings, then the roof's (an odd n repeats the roof's
        closing row once more).

    Notes
    -----
    The closing duplicate is a hull vertex for the convex and rectangle
    rings (the first row of a ring is a corner or a circle point), so an
    implementation that does not de-duplicate emits a zero-length edge or a
    repeated vertex; one that de-duplicates by a tolerance must still keep
    exactly one copy.

    Examples
    --------
    >>> pts = closed_ring(np.random.default_rng(0), 6, dim=2)
    >>> bool(np.array_equal(pts[0], pts[-1])), len(np.unique(pts, axis=0))
    (True, 5)
    """
    fam = "closed-ring"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "shape", shape, RING_SHAPES)
    scale = check_positive(fam, "scale", scale)
    n = check_n(fam, n, _min_rows(dim, shape), "every ring needs its points and its closing repeat")
    rings_2d = _footprint(rng, n // (dim - 1) - (2 if shape == "holes" else 1), shape, scale)
    closed = [_closed(r, rng) for r in rings_2d]
    if dim == 2:
        return finish(np.concatenate(closed))
    floor = [np.column_stack([r, np.zeros(len(r))]) for r in closed]
    roof = [np.column_stack([r, np.full(len(r), scale)]) for r in closed]
    pts = np.concatenate(floor + roof)
    if len(pts) < n:  # odd n: the extra row repeats the roof's closing point once more
        pts = np.concatenate([pts, pts[-1:]])
    return finish(pts)


def _min_rows(dim: int, shape: str) -> int:
    rings = 2 if shape == "holes" else 1
    per_storey = (_RING_MIN[shape] * (2 if shape == "holes" else 1)) + rings
    return per_storey * (dim - 1)


declare_min_size("closed-ring", lambda dim, shape="convex", **p: _min_rows(dim, shape))
