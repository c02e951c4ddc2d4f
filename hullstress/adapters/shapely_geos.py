"""GEOS's convex hull through shapely (2D): ``MultiPoint(points).convex_hull``.

Registered as ``shapely-convex-hull`` (dim 2, no options, no ``eps``).

GEOS returns a geometry, not indices.  The adapter

1. orients the polygon counter-clockwise (GEOS's exterior ring is clockwise
   in practice and its orientation is not documented), using shapely's
   ``orient``, whose ``is_ccw`` test is GEOS's robust orientation predicate;
2. drops the ring's closing vertex (a repeat of the first);
3. maps each ring coordinate back to an input index by exact coordinate
   match: GEOS copies the input doubles.  Rows with identical coordinates map
   to the lowest index (see :mod:`hullstress.adapters._mapping`).

For collinear input GEOS returns a LineString, for a single distinct point a
Point, for no points an empty geometry; none of them is a polygon, so the
adapter raises ``ValueError`` naming what GEOS returned.  The harness records
that as ``rejected`` on degenerate input (and ``error`` otherwise).

Declared contract: ``strict,flat=raise``.  GEOS's ``ConvexHull`` (a port of
JTS's) documents its result as the smallest convex polygon and removes
collinear ring points with its robust orientation test, so only extreme
points are vertices; for collinear input shapely documents a LineString,
which this adapter turns into ``ValueError`` (an exact test: GEOS's
orientation predicate is robust).  See ``docs/contracts.md``.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
>>> shapely_convex_hull(square).tolist()
[0, 1, 2, 3]
>>> shapely_convex_hull(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
Traceback (most recent call last):
...
ValueError: shapely returned a LineString for collinear input, not a Polygon
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import MultiPoint, Polygon
from shapely.geometry.polygon import orient

from .._registry import register_algorithm
from ._mapping import coordinate_table, indices_of

__all__ = ["ALGORITHM_NAMES", "shapely_convex_hull"]

#: The algorithm names this module registers.
ALGORITHM_NAMES: tuple[str, ...] = ("shapely-convex-hull",)

# Why a non-polygon came back, for the error message.
_DEGENERATE_KIND = {
    "LineString": "collinear input",
    "Point": "input with a single distinct point",
}


@register_algorithm("shapely-convex-hull", dim=2, contract="strict,flat=raise")
def shapely_convex_hull(points: np.ndarray, /) -> np.ndarray:
    """GEOS convex hull via shapely.MultiPoint(points).convex_hull (2D).

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64

    Returns
    -------
    ndarray of shape (k,), int64
        Hull vertex indices, counter-clockwise, without a repeated closing vertex.

    Raises
    ------
    ValueError
        When GEOS returns something other than a non-empty Polygon (collinear
        input, one distinct point, no points).
    RuntimeError
        When a returned vertex is not an input point.
    """
    hull = MultiPoint(np.asarray(points, dtype=np.float64)).convex_hull
    if not isinstance(hull, Polygon) or hull.is_empty:
        kind = hull.geom_type
        why = "empty input" if hull.is_empty else _DEGENERATE_KIND.get(kind, "this input")
        article = "an" if kind[0] in "AEIOU" else "a"
        raise ValueError(f"shapely returned {article} {kind} for {why}, not a Polygon")
    ring = orient(hull, sign=1.0).exterior.coords
    coords = list(ring)[:-1]  # the ring repeats its first vertex at the end
    return np.asarray(indices_of(coords, coordinate_table(points), library="shapely"), dtype=np.int64)
